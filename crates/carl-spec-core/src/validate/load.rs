//! The loaders of [`SpecSet`]: every spec is validated (this module's pipeline) before it is used.
//! They live here, not in `spec`, so that the spec language does not depend on its validator.

use std::path::Path;

use super::Syntax;
use crate::diagnostics::Input;
use crate::spec::load::{LoadError, SpecSet, bundled_inputs, read_inputs};

impl SpecSet {
    /// The specs shipped with carl-spec (their JSON Schema and duplicate-key checks ran at test
    /// time on the same embedded bytes: `Syntax::TrustEmbedded`).
    pub fn bundled() -> Result<SpecSet, LoadError> {
        Self::from_checked(&bundled_inputs(false), Syntax::TrustEmbedded)
    }

    /// Bundled specs plus an author's directory of specs (ids must not clash; the author's are
    /// validated in full).
    pub fn bundled_with(dir: Option<&Path>) -> Result<SpecSet, LoadError> {
        let mut inputs = bundled_inputs(false);
        if let Some(dir) = dir {
            inputs.extend(read_inputs(&[dir.to_path_buf()])?);
        }
        Self::from_checked(&inputs, Syntax::TrustEmbedded)
    }

    /// Validate and resolve; any error fails the whole load.
    pub fn from_inputs(inputs: &[Input]) -> Result<SpecSet, LoadError> {
        Self::from_checked(inputs, Syntax::CheckAll)
    }

    fn from_checked(inputs: &[Input], syntax: Syntax) -> Result<SpecSet, LoadError> {
        let (resolved, report) = super::run_with(inputs, syntax);
        if report.has_errors() {
            return Err(LoadError::Invalid { report });
        }
        Ok(SpecSet::from_validated(resolved.into_iter().map(|r| r.spec).collect()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Only the embedded bytes are trusted: a bundled name with other contents gets every check.
    #[test]
    fn a_changed_bundled_spec_is_checked_in_full() {
        let mut inputs = bundled_inputs(false);
        let cartpole = inputs
            .iter_mut()
            .find(|i| i.name == "bundled:specs/cartpole.json")
            .unwrap();
        let text = String::from_utf8(cartpole.bytes.clone()).unwrap();
        // A property the schema does not allow, and a duplicate key.
        let changed = text.replacen('{', "{\"not_a_field\": 1, \"not_a_field\": 2, ", 1);
        cartpole.bytes = changed.into_bytes();
        let Err(LoadError::Invalid { report }) = SpecSet::from_checked(&inputs, Syntax::TrustEmbedded) else {
            panic!("a changed bundled spec must not be trusted");
        };
        let rules: Vec<&str> = report.diagnostics.iter().map(|d| d.rule.as_str()).collect();
        assert!(rules.iter().any(|r| r.starts_with("schema")), "{rules:?}");
        assert!(rules.contains(&"duplicate-key"), "{rules:?}");
    }
}
