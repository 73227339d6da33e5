//! The loaders of [`SpecSet`]: every spec is validated (this module's pipeline) before it is used.
//! They live here, not in `spec`, so that the spec language does not depend on its validator.

use std::path::Path;

use crate::diagnostics::Input;
use crate::spec::load::{LoadError, SpecSet, bundled_inputs, read_inputs};

impl SpecSet {
    /// The specs shipped with carl-spec.
    pub fn bundled() -> Result<SpecSet, LoadError> {
        Self::from_inputs(&bundled_inputs(false))
    }

    /// Bundled specs plus an author's directory of specs (ids must not clash).
    pub fn bundled_with(dir: Option<&Path>) -> Result<SpecSet, LoadError> {
        let mut inputs = bundled_inputs(false);
        if let Some(dir) = dir {
            inputs.extend(read_inputs(&[dir.to_path_buf()])?);
        }
        Self::from_inputs(&inputs)
    }

    /// Validate and resolve; any error fails the whole load.
    pub fn from_inputs(inputs: &[Input]) -> Result<SpecSet, LoadError> {
        let (resolved, report) = super::run(inputs);
        if report.has_errors() {
            return Err(LoadError::Invalid { report });
        }
        Ok(SpecSet::from_validated(resolved.into_iter().map(|r| r.spec).collect()))
    }
}
