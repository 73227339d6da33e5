//! Each file in tests/corpus/invalid/ breaks exactly one rule; the validator must name that rule
//! and point at the right line and column. The base spec must be valid.

use std::path::PathBuf;

use carl_spec::spec::load::read_inputs;
use carl_spec::validate;

fn corpus(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/corpus")
        .join(name)
}

/// (file stem, rule id, line, column)
const EXPECTED: &[(&str, &str, usize, usize)] = &[
    ("bounds-not-applicable", "bounds-not-applicable", 33, 17),
    ("bounds-order", "bounds-order", 15, 17),
    ("categorical-choices", "categorical-choices", 32, 24),
    ("categorical-default", "categorical-default", 31, 18),
    ("default-missing", "default-missing", 11, 5),
    ("default-out-of-bounds", "default-out-of-bounds", 14, 18),
    ("distribution-params", "distribution-params", 41, 69),
    ("distribution-support", "distribution-support", 41, 29),
    ("distribution-type", "distribution-type", 41, 40),
    ("duplicate-feature", "duplicate-feature", 21, 15),
    ("duplicate-key", "duplicate-key", 5, 3),
    ("episode-limit", "episode-limit", 9, 24),
    ("instance-out-of-bounds", "instance-out-of-bounds", 45, 101),
    ("instance-set-size", "instance-set-size", 45, 93),
    ("instance-set-source", "instance-set-source", 45, 14),
    ("int-not-integral", "int-not-integral", 23, 18),
    ("invalid-name", "invalid-name", 45, 5),
    ("json-syntax", "json-syntax", 9, 28),
    ("schema-additionalProperties", "schema/additionalProperties", 17, 7),
    ("schema-enum", "schema/enum", 41, 39),
    ("schema-pattern", "schema/pattern", 3, 9),
    ("schema-required", "schema/required", 1, 1),
    ("schema-type", "schema/type", 15, 23),
    ("space-shape", "space-shape", 7, 62),
    ("type-mismatch", "type-mismatch", 14, 18),
    ("unknown-distribution", "unknown-distribution", 45, 77),
    ("unknown-feature", "unknown-feature", 41, 21),
];

#[test]
fn base_spec_is_valid() {
    let inputs = read_inputs(&[corpus("base.json")]).unwrap();
    let (resolved, report) = validate::run(&inputs);
    assert!(report.diagnostics.is_empty(), "{report}");
    assert_eq!(resolved.len(), 1);
}

#[test]
fn every_broken_spec_fails_with_its_rule_at_its_location() {
    for (stem, rule, line, col) in EXPECTED {
        let inputs = read_inputs(&[corpus(&format!("invalid/{stem}.json"))]).unwrap();
        let (_, report) = validate::run(&inputs);
        assert!(report.has_errors(), "{stem}: expected an error");
        let d = report
            .diagnostics
            .iter()
            .find(|d| d.rule == *rule)
            .unwrap_or_else(|| panic!("{stem}: no {rule} diagnostic in\n{report}"));
        let loc = d.location.as_ref().unwrap_or_else(|| panic!("{stem}: no location"));
        assert_eq!(
            (loc.line, loc.column),
            (*line, *col),
            "{stem}: {}",
            d.render_text(false)
        );
        assert!(d.help.is_some(), "{stem}: every diagnostic says how to fix it");
        assert_eq!(
            report.diagnostics.len(),
            1,
            "{stem}: exactly one problem expected\n{report}"
        );
    }
}

#[test]
fn corpus_and_expectations_match() {
    let mut files: Vec<String> = std::fs::read_dir(corpus("invalid"))
        .unwrap()
        .map(|e| e.unwrap().path().file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    files.sort();
    let mut expected: Vec<&str> = EXPECTED.iter().map(|e| e.0).collect();
    expected.sort();
    assert_eq!(files, expected);
}

#[test]
fn all_problems_of_all_files_are_reported_in_one_run() {
    let inputs = read_inputs(&[corpus("invalid")]).unwrap();
    let (_, report) = validate::run(&inputs);
    let files: std::collections::BTreeSet<_> = report.diagnostics.iter().map(|d| d.file.clone()).collect();
    // Every file in the corpus is reported, plus duplicate-id errors (they all use id "toy").
    assert_eq!(files.len(), EXPECTED.len());
    assert!(report.diagnostics.iter().any(|d| d.rule == "duplicate-id"));
}
