//! JSON Schema validation (the pinned `jsonschema` crate), wrapped so its errors become located
//! diagnostics with stable rule ids (`schema/<keyword>`) and messages that say how to fix them.

use jsonschema::error::{TypeKind, ValidationErrorKind};
use jsonschema::{ValidationError, Validator};

use crate::json::escape_token;

/// At most this many schema errors are reported per file; the first ones are the useful ones.
pub const MAX_SCHEMA_ERRORS: usize = 50;

/// Compiled validators for both document kinds, built once per process (immutable after that).
pub fn shared() -> Result<&'static SchemaChecker, String> {
    static CHECKER: std::sync::OnceLock<Result<SchemaChecker, String>> = std::sync::OnceLock::new();
    CHECKER.get_or_init(SchemaChecker::new).as_ref().map_err(Clone::clone)
}

/// Compiled validators for both document kinds.
pub struct SchemaChecker {
    env: Validator,
    fragment: Validator,
}

/// A schema problem before it is located in a file.
#[derive(Debug, Clone, PartialEq)]
pub struct SchemaProblem {
    pub keyword: String,
    pub pointer: String,
    pub message: String,
    pub help: Option<String>,
}

impl SchemaChecker {
    pub fn new() -> Result<Self, String> {
        let build = |def: &str| {
            jsonschema::draft202012::new(&crate::schema::schema_for_definition(def))
                .map_err(|e| format!("internal error: the generated schema does not compile: {e}"))
        };
        Ok(SchemaChecker {
            env: build("RawEnvSpec")?,
            fragment: build("RawFragment")?,
        })
    }

    /// Every schema problem of one document (empty when valid).
    pub fn check(&self, doc: &serde_json::Value) -> Vec<SchemaProblem> {
        let is_fragment = doc.get("fragment").is_some() && doc.get("id").is_none();
        let validator = if is_fragment { &self.fragment } else { &self.env };
        let mut out = Vec::new();
        // Lazily evaluated: a hostile document with millions of errors costs only the first few.
        for e in validator.iter_errors(doc).take(MAX_SCHEMA_ERRORS) {
            explain(&e, &mut out);
        }
        out.sort_by(|a, b| a.pointer.cmp(&b.pointer));
        out.dedup();
        out
    }
}

fn explain(e: &ValidationError<'_>, out: &mut Vec<SchemaProblem>) {
    let pointer = e.instance_path().as_str().to_string();
    let keyword = keyword_of(e.kind());
    let found = describe(e.instance());
    let (message, help) = match e.kind() {
        ValidationErrorKind::AdditionalProperties { unexpected } => {
            for name in unexpected {
                out.push(SchemaProblem {
                    keyword: "additionalProperties".into(),
                    pointer: format!("{pointer}/{}", escape_token(name)),
                    message: format!("unknown property \"{name}\""),
                    help: Some(known_properties_hint(e)),
                });
            }
            return;
        }
        ValidationErrorKind::Required { property } => (
            format!("missing required property {property}"),
            Some(format!("add {property} to this object")),
        ),
        ValidationErrorKind::Type { kind } => {
            let expected = match kind {
                TypeKind::Single(t) => t.to_string(),
                TypeKind::Multiple(ts) => ts.into_iter().map(|t| t.to_string()).collect::<Vec<_>>().join(" or "),
            };
            let mut help = None;
            if let serde_json::Value::String(s) = e.instance().as_ref() {
                let l = s.trim().to_ascii_lowercase();
                if ["inf", "+inf", "-inf", "infinity", "-infinity", "nan"].contains(&l.as_str()) {
                    help = Some("JSON has no infinity or NaN: write null for an open bound".into());
                } else if s.trim().parse::<f64>().is_ok() && expected.contains("number") {
                    help = Some(format!("write the number without quotes: {}", s.trim()));
                }
            }
            (
                format!("expected {expected}, found {found}"),
                help.or(Some(format!("change this value to a {expected}"))),
            )
        }
        ValidationErrorKind::Enum { options } => (
            format!("{found} is not one of the allowed values {options}"),
            Some(format!("use one of {options}")),
        ),
        ValidationErrorKind::Constant { expected_value } => (format!("expected {expected_value}, found {found}"), None),
        ValidationErrorKind::Pattern { pattern } => (
            format!("{found} does not match the pattern {pattern}"),
            Some(
                "ids are snake_case (lowercase letters, digits, underscores, starting with a letter); feature names may also use capitals"
                    .into(),
            ),
        ),
        ValidationErrorKind::MinItems { limit } | ValidationErrorKind::MaxItems { limit } => {
            (format!("{e}"), Some(format!("this array needs {limit} item(s) here")))
        }
        ValidationErrorKind::Minimum { limit } => (format!("{found} is less than the minimum {limit}"), None),
        ValidationErrorKind::AnyOf { context } | ValidationErrorKind::OneOfNotValid { context } => {
            // Report the branch that matched best (e.g. the sampler whose `kind` matched) instead of
            // "not valid under any of the schemas".
            if let Some(best) = best_branch(context, &pointer) {
                for sub in best {
                    explain(sub, out);
                }
                return;
            }
            if let Some((tag, found_tag, options)) = unmatched_tag(context) {
                let help = match crate::suggest::did_you_mean(&found_tag, options.iter().map(String::as_str)) {
                    Some(s) => format!("did you mean \"{s}\"? accepted: {}", options.join(", ")),
                    None => format!("accepted: {}", options.join(", ")),
                };
                out.push(SchemaProblem {
                    keyword: "enum".into(),
                    pointer: format!("{pointer}/{tag}"),
                    message: format!("unknown {tag} \"{found_tag}\""),
                    help: Some(help),
                });
                return;
            }
            (
                format!("{found} does not have any of the accepted shapes"),
                Some("compare with the schema (carl-spec schema) or an existing spec".into()),
            )
        }
        _ => (e.to_string(), None),
    };
    out.push(SchemaProblem {
        keyword: keyword.to_string(),
        pointer,
        message,
        help,
    });
}

/// Of several failing alternatives, the one whose discriminator (`kind`/`type` const) matched, or the
/// one with the fewest errors; `None` when they all fail at the top (plain type mismatch).
fn best_branch<'a>(
    context: &'a [Vec<ValidationError<'static>>],
    at: &str,
) -> Option<&'a Vec<ValidationError<'static>>> {
    let tag_failed = |errs: &Vec<ValidationError<'static>>| {
        errs.iter().any(|e| {
            matches!(
                e.kind(),
                ValidationErrorKind::Constant { .. } | ValidationErrorKind::Enum { .. }
            ) && matches!(e.instance_path().as_str().rsplit('/').next(), Some("kind" | "type"))
        })
    };
    // The value itself has the wrong type for this branch (not one of its fields).
    let top_type_failed = |errs: &Vec<ValidationError<'static>>| {
        errs.iter()
            .any(|e| matches!(e.kind(), ValidationErrorKind::Type { .. }) && e.instance_path().as_str() == at)
    };
    let candidates: Vec<_> = context
        .iter()
        .filter(|b| !tag_failed(b) && !top_type_failed(b))
        .collect();
    candidates.into_iter().min_by_key(|b| b.len())
}

/// When every branch failed on its discriminator (`kind`/`type`), the discriminator's name, the
/// value found, and the accepted values.
fn unmatched_tag(context: &[Vec<ValidationError<'static>>]) -> Option<(String, String, Vec<String>)> {
    let mut options = Vec::new();
    let mut tag = None;
    let mut found = None;
    for branch in context {
        let e = branch
            .iter()
            .find(|e| matches!(e.kind(), ValidationErrorKind::Constant { .. }))?;
        let path = e.instance_path().as_str();
        let name = path.rsplit('/').next()?.to_string();
        if name != "kind" && name != "type" {
            return None;
        }
        if let ValidationErrorKind::Constant { expected_value } = e.kind() {
            options.push(expected_value.as_str().unwrap_or_default().to_string());
        }
        found = Some(match e.instance().as_ref() {
            serde_json::Value::String(s) => s.clone(),
            other => other.to_string(),
        });
        tag = Some(name);
    }
    Some((tag?, found?, options))
}

fn known_properties_hint(e: &ValidationError<'_>) -> String {
    let _ = e;
    "remove it, or check its spelling against the schema (carl-spec schema)".to_string()
}

fn keyword_of(kind: &ValidationErrorKind) -> &'static str {
    match kind {
        ValidationErrorKind::Type { .. } => "type",
        ValidationErrorKind::Required { .. } => "required",
        ValidationErrorKind::Enum { .. } => "enum",
        ValidationErrorKind::Constant { .. } => "const",
        ValidationErrorKind::Pattern { .. } => "pattern",
        ValidationErrorKind::MinItems { .. } => "minItems",
        ValidationErrorKind::MaxItems { .. } => "maxItems",
        ValidationErrorKind::Minimum { .. } => "minimum",
        ValidationErrorKind::Maximum { .. } => "maximum",
        ValidationErrorKind::AnyOf { .. } => "anyOf",
        ValidationErrorKind::OneOfNotValid { .. } => "oneOf",
        ValidationErrorKind::OneOfMultipleValid { .. } => "oneOf",
        _ => "other",
    }
}

/// A short description of a JSON value for messages: `string "inf"`, `number 3`, `an object`.
pub fn describe(v: &serde_json::Value) -> String {
    match v {
        serde_json::Value::Null => "null".into(),
        serde_json::Value::Bool(b) => format!("boolean {b}"),
        serde_json::Value::Number(n) => format!("number {}", crate::text::escape(&n.to_string())),
        serde_json::Value::String(s) => format!("string {}", crate::text::quote(s)),
        serde_json::Value::Array(a) => format!("an array of {} item(s)", a.len()),
        serde_json::Value::Object(_) => "an object".into(),
    }
}
