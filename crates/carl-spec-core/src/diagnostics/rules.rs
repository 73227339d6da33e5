//! The rule registry: every rule the validator can report, declared once (like cargo's lint
//! table). Diagnostics are made from these entries, never from free strings; the rules page's
//! table (docs/reference/rules.md) and the corpus of broken specs (`tests/corpus/invalid/`) are
//! checked against [`ALL`].

use super::Severity;

/// One validation rule.
#[derive(Debug, PartialEq, Eq)]
pub struct Rule {
    /// Stable id, shown as `error[id]` and in JSON output. `schema` stands for the family
    /// `schema/<keyword>` (the JSON Schema keyword that failed).
    pub id: &'static str,
    pub severity: Severity,
    /// Underline the key (a name) rather than its value.
    pub on_key: bool,
    /// What the rule checks, in one line (the rules page's table).
    pub summary: &'static str,
}

impl Rule {
    /// The id written in a diagnostic: the rule's own, or `schema/<keyword>` for the schema family.
    pub fn id_for(&self, keyword: Option<&str>) -> String {
        match keyword {
            Some(k) if self.id == SCHEMA.id => format!("{}/{k}", self.id),
            _ => self.id.to_string(),
        }
    }
}

macro_rules! registry {
    ($($name:ident = $id:literal, $sev:ident, $on_key:literal, $summary:literal;)*) => {
        $(
            #[doc = $summary]
            pub static $name: Rule = Rule { id: $id, severity: Severity::$sev, on_key: $on_key, summary: $summary };
        )*
        /// Every rule, in the order the rules page lists them.
        pub static ALL: &[&Rule] = &[$(&$name),*];
    };
}

registry! {
    JSON_SYNTAX = "json-syntax", Error, false, "the file is not well-formed JSON";
    NOT_UTF8 = "not-utf8", Error, false, "the file is not UTF-8";
    FILE_TOO_LARGE = "file-too-large", Error, false, "the file is larger than the 16 MiB limit";
    DUPLICATE_KEY = "duplicate-key", Error, true, "a property appears twice in one object";
    SCHEMA = "schema", Error, false, "the document breaks the JSON Schema (`schema/<keyword>`: type, required, additionalProperties, enum, pattern, …)";
    DESCRIPTION_EMPTY = "description-empty", Error, false, "a description is empty";
    EPISODE_LIMIT = "episode-limit", Error, false, "max_episode_steps is 0";
    SPACE_SHAPE = "space-shape", Error, false, "a space's limits do not match its shape, or it has no elements";
    SPACE_BOUNDS = "space-bounds", Error, false, "a box space has low above high";
    DUPLICATE_FEATURE = "duplicate-feature", Error, false, "two features (or aliases) share a name, or a distribution varies one feature twice";
    DUPLICATE_EFFECT = "duplicate-effect", Error, false, "an effect is listed twice in `affects`";
    DEFAULT_MISSING = "default-missing", Error, false, "a feature has neither default nor default_from";
    DEFAULT_CONFLICT = "default-conflict", Error, false, "a feature has both default and default_from";
    BOUNDS_ORDER = "bounds-order", Error, false, "a lower bound is above the upper bound";
    DEFAULT_OUT_OF_BOUNDS = "default-out-of-bounds", Error, false, "a default lies outside its feature's bounds";
    INT_NOT_INTEGRAL = "int-not-integral", Error, false, "an int value or bound has a fractional part";
    INT_OUT_OF_RANGE = "int-out-of-range", Error, false, "an int value or bound lies beyond ±2^53, where integers stop being exact";
    TYPE_MISMATCH = "type-mismatch", Error, false, "a value does not have its feature's type";
    CHOICES_NOT_APPLICABLE = "choices-not-applicable", Error, false, "a non-categorical feature lists choices";
    BOUNDS_NOT_APPLICABLE = "bounds-not-applicable", Error, false, "a bool or categorical feature has bounds";
    CATEGORICAL_CHOICES = "categorical-choices", Error, false, "a categorical feature has no, empty or repeated choices";
    CHOICE_LABELS = "choice-labels", Error, false, "choice_labels and choices differ in length";
    CATEGORICAL_DEFAULT = "categorical-default", Error, false, "a categorical default is not one of the choices";
    UNKNOWN_FEATURE = "unknown-feature", Error, true, "a name refers to no feature";
    UNKNOWN_FRAGMENT = "unknown-fragment", Error, false, "an include names no known fragment";
    OVERRIDE_EXCLUDED = "override-excluded", Error, false, "an included feature is both left out and overridden";
    DUPLICATE_FRAGMENT = "duplicate-fragment", Error, false, "two files define the same fragment";
    DUPLICATE_ID = "duplicate-id", Error, false, "two specs share an id";
    DUPLICATE_ALIAS = "duplicate-alias", Error, false, "an environment alias names another environment";
    INVALID_NAME = "invalid-name", Error, true, "a distribution or instance-set name is not snake_case";
    DISTRIBUTION_EMPTY = "distribution-empty", Error, false, "a distribution varies no feature";
    DISTRIBUTION_PARAMS = "distribution-params", Error, false, "a sampler's parameters are unusable (the sampler's own check, as `freeze` runs it)";
    DISTRIBUTION_TYPE = "distribution-type", Error, false, "a sampler cannot produce values of its feature's type";
    DISTRIBUTION_SUPPORT = "distribution-support", Error, false, "a sampler can draw nothing inside its feature's bounds";
    UNKNOWN_DISTRIBUTION = "unknown-distribution", Error, false, "a sampled set names no distribution of its spec";
    INSTANCE_SET_SOURCE = "instance-set-source", Error, false, "an instance set has not exactly one of sampled, explicit, grid";
    INSTANCE_SET_SIZE = "instance-set-size", Error, false, "an instance set is empty or larger than 1,000,000";
    INSTANCE_OUT_OF_BOUNDS = "instance-out-of-bounds", Error, false, "an explicit or grid value lies outside its bounds (without allow_out_of_bounds)";
    DUPLICATE_INSTANCE = "duplicate-instance", Error, false, "two explicit instances share a name";
    GRID_PARAMS = "grid-params", Error, false, "a grid is empty or reversed";
    SPLIT_DEFINITION = "split-definition", Error, false, "a region or a split set derived from it is malformed (unknown region or feature, a range outside the bounds, the wrong parameters for its kind, too many points)";
    NEEDLESS_ALLOW_OUT_OF_BOUNDS = "needless-allow-out-of-bounds", Warning, false, "allow_out_of_bounds is set but every value is inside the bounds";
    TOO_MANY_PROBLEMS = "too-many-problems", Error, false, "more than 200 problems in one file; the rest are not shown";
    INTERNAL = "internal", Error, false, "carl-spec's own schema does not compile (a bug, never the spec's fault)";
}

/// The registry entry of a rule id as it appears in a diagnostic (`schema/type` → [`SCHEMA`]).
pub fn lookup(id: &str) -> Option<&'static Rule> {
    let family = id.split('/').next().unwrap_or(id);
    ALL.iter()
        .copied()
        .find(|r| r.id == id || (r.id == SCHEMA.id && family == SCHEMA.id))
}

/// The README's rule table (a test keeps the README equal to this).
pub fn markdown_table() -> String {
    let mut out = String::from("| rule | severity | what it refuses |\n|---|---|---|\n");
    for r in ALL {
        let id = if r.id == SCHEMA.id { "schema/<keyword>" } else { r.id };
        let sev = match r.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        };
        out.push_str(&format!("| `{id}` | {sev} | {} |\n", r.summary));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_are_unique_kebab_case() {
        let mut seen = std::collections::BTreeSet::new();
        for r in ALL {
            assert!(seen.insert(r.id), "{} declared twice", r.id);
            assert!(
                r.id.chars()
                    .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-'),
                "{}",
                r.id
            );
            assert!(!r.summary.is_empty());
        }
    }

    #[test]
    fn lookup_finds_schema_keywords() {
        assert_eq!(lookup("schema/type"), Some(&SCHEMA));
        assert_eq!(lookup("bounds-order"), Some(&BOUNDS_ORDER));
        assert_eq!(lookup("nope"), None);
    }
}
