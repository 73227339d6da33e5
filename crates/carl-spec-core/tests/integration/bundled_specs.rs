//! The bundled specs pass the whole validator, JSON Schema and duplicate keys included. This is
//! the guarantee behind `SpecSet::bundled` skipping those syntactic checks for the copies embedded
//! at build time (they are these very bytes): a spec that breaks the schema fails this test.

use carl_spec_core::spec::SpecSet;
use carl_spec_core::spec::load::{bundled_files, bundled_inputs};
use carl_spec_core::validate;

#[test]
fn bundled_specs_pass_the_whole_validator() {
    let inputs = bundled_inputs(false);
    let documents = bundled_files().iter().filter(|(p, _)| !p.starts_with("instances/"));
    assert_eq!(
        inputs.len(),
        documents.count(),
        "every bundled spec document is checked"
    );
    assert!(inputs.len() >= 17);
    let (resolved, report) = validate::run(&inputs);
    assert!(
        report.diagnostics.is_empty(),
        "bundled specs must be clean (errors and warnings):\n{}",
        report
            .diagnostics
            .iter()
            .map(|d| format!("{d:?}"))
            .collect::<Vec<_>>()
            .join("\n")
    );
    assert_eq!(resolved.len(), SpecSet::bundled().unwrap().envs().len());
}

#[test]
fn trusted_load_equals_the_fully_validated_one() {
    let full = SpecSet::from_inputs(&bundled_inputs(false)).unwrap();
    let trusted = SpecSet::bundled().unwrap();
    assert_eq!(full.envs(), trusted.envs());
    let with_empty_dir = SpecSet::bundled_with(None).unwrap();
    assert_eq!(full.envs(), with_empty_dir.envs());
}
