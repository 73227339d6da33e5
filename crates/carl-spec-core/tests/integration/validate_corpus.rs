//! Each case in tests/corpus/invalid/ (a file, or a folder of files for rules about several files)
//! breaks exactly one rule; the validator must name that rule and point at the right file, line and
//! column. The registry walk makes a new rule without a case fail the suite, and the rules page's
//! table must be the registry's. The base spec must be valid.

use std::path::PathBuf;

use carl_spec_core::diagnostics::rules::{self, ALL};
use carl_spec_core::spec::load::read_inputs;
use carl_spec_core::validate::{self, Input};

fn corpus(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/corpus")
        .join(name)
}

/// (case under invalid/, rule id, file of the diagnostic within the case, line, column).
/// Line 0 = a diagnostic about the file as a whole (no location).
const EXPECTED: &[(&str, &str, &str, usize, usize)] = &[
    ("bounds-not-applicable.json", "bounds-not-applicable", "", 33, 17),
    ("bounds-order.json", "bounds-order", "", 15, 17),
    ("categorical-choices.json", "categorical-choices", "", 32, 24),
    ("categorical-default.json", "categorical-default", "", 31, 18),
    ("choice-labels.json", "choice-labels", "", 32, 47),
    ("choices-not-applicable.json", "choices-not-applicable", "", 15, 39),
    ("default-conflict.json", "default-conflict", "", 14, 39),
    ("default-missing.json", "default-missing", "", 11, 5),
    ("default-out-of-bounds.json", "default-out-of-bounds", "", 14, 18),
    ("description-empty.json", "description-empty", "", 17, 22),
    ("distribution-empty.json", "distribution-empty", "", 41, 19),
    ("distribution-params.json", "distribution-params", "", 41, 69),
    ("distribution-support.json", "distribution-support", "", 41, 29),
    ("distribution-type.json", "distribution-type", "", 41, 40),
    ("duplicate-alias", "duplicate-alias", "b.json", 3, 32),
    ("duplicate-effect.json", "duplicate-effect", "", 18, 31),
    ("duplicate-feature.json", "duplicate-feature", "", 21, 15),
    ("duplicate-fragment", "duplicate-fragment", "b.json", 2, 15),
    ("duplicate-id", "duplicate-id", "b.json", 3, 9),
    ("duplicate-instance.json", "duplicate-instance", "", 45, 114),
    ("duplicate-key.json", "duplicate-key", "", 5, 3),
    ("episode-limit.json", "episode-limit", "", 9, 24),
    ("grid-params.json", "grid-params", "", 45, 56),
    ("instance-out-of-bounds.json", "instance-out-of-bounds", "", 45, 101),
    ("instance-set-size.json", "instance-set-size", "", 45, 93),
    ("instance-set-source.json", "instance-set-source", "", 45, 14),
    ("int-not-integral.json", "int-not-integral", "", 23, 18),
    ("int-out-of-range.json", "int-out-of-range", "", 23, 18),
    ("invalid-name.json", "invalid-name", "", 45, 5),
    ("json-syntax.json", "json-syntax", "", 9, 28),
    (
        "needless-allow-out-of-bounds.json",
        "needless-allow-out-of-bounds",
        "",
        45,
        71,
    ),
    ("not-utf8.json", "not-utf8", "", 17, 41),
    ("override-excluded", "override-excluded", "spec.json", 10, 93),
    (
        "schema-additionalProperties.json",
        "schema/additionalProperties",
        "",
        17,
        7,
    ),
    ("schema-enum.json", "schema/enum", "", 41, 39),
    ("schema-pattern.json", "schema/pattern", "", 3, 9),
    ("schema-required.json", "schema/required", "", 1, 1),
    ("schema-type.json", "schema/type", "", 15, 23),
    ("space-bounds.json", "space-bounds", "", 7, 62),
    ("space-shape.json", "space-shape", "", 7, 62),
    ("split-definition.json", "split-definition", "", 46, 57),
    ("too-many-problems.json", "too-many-problems", "", 0, 0),
    ("type-mismatch.json", "type-mismatch", "", 14, 18),
    ("unknown-distribution.json", "unknown-distribution", "", 45, 77),
    ("unknown-feature.json", "unknown-feature", "", 41, 21),
    ("unknown-fragment.json", "unknown-fragment", "", 10, 29),
];

/// Rules no spec file can trigger, each with the reason and where it is tested instead.
const NO_CORPUS_CASE: &[(&str, &str)] = &[
    (
        "file-too-large",
        "a 16 MiB file does not belong in the repository: generated in file_too_large_is_refused",
    ),
    (
        "internal",
        "carl-spec's own schema failing to compile is a bug, not an input",
    ),
];

fn run_case(case: &str) -> validate::Report {
    let inputs = read_inputs(&[corpus(&format!("invalid/{case}"))]).unwrap();
    validate::run(&inputs).1
}

#[test]
fn base_spec_is_valid() {
    let inputs = read_inputs(&[corpus("base.json")]).unwrap();
    let (resolved, report) = validate::run(&inputs);
    assert!(report.diagnostics.is_empty(), "{report}");
    assert_eq!(resolved.len(), 1);
}

#[test]
fn every_broken_spec_fails_with_its_rule_at_its_location() {
    for (case, rule, file, line, col) in EXPECTED {
        let report = run_case(case);
        let d = report
            .diagnostics
            .iter()
            .find(|d| d.rule == *rule)
            .unwrap_or_else(|| panic!("{case}: no {rule} diagnostic in\n{report}"));
        let registered = rules::lookup(rule).unwrap_or_else(|| panic!("{rule} is not in the registry"));
        assert_eq!(d.severity, registered.severity, "{case}");
        let want_file = if file.is_empty() {
            case.to_string()
        } else {
            format!("{case}/{file}")
        };
        assert!(d.file.ends_with(&want_file), "{case}: reported in {}", d.file);
        match &d.location {
            None => assert_eq!((*line, *col), (0, 0), "{case}: no location\n{report}"),
            Some(loc) => assert_eq!(
                (loc.line, loc.column),
                (*line, *col),
                "{case}: {}",
                d.render_text(false)
            ),
        }
        assert!(d.help.is_some(), "{case}: every diagnostic says how to fix it");
        let others: Vec<_> = report.diagnostics.iter().filter(|o| o.rule != *rule).collect();
        let expected_others = if *rule == "too-many-problems" {
            report.diagnostics.len() - 1
        } else {
            0
        };
        assert_eq!(
            others.len(),
            expected_others,
            "{case}: exactly one rule broken\n{report}"
        );
        if *rule != "too-many-problems" {
            assert_eq!(
                report.diagnostics.len(),
                1,
                "{case}: exactly one problem expected\n{report}"
            );
        }
    }
}

#[test]
fn every_registered_rule_has_a_broken_spec() {
    for r in ALL {
        let covered = EXPECTED
            .iter()
            .any(|e| rules::lookup(e.1).is_some_and(|x| std::ptr::eq(x, *r)));
        let exempt = NO_CORPUS_CASE.iter().any(|(id, _)| *id == r.id);
        assert!(
            covered || exempt,
            "rule {} has no case in tests/corpus/invalid/ (add a spec breaking only it, and a line in EXPECTED)",
            r.id
        );
        assert!(!(covered && exempt), "{} is both covered and exempt", r.id);
    }
}

#[test]
fn file_too_large_is_refused() {
    let bytes = vec![b' '; carl_spec_core::validate::MAX_FILE_BYTES + 1];
    let (_, report) = validate::run(&[Input {
        name: "big.json".into(),
        bytes,
        library: false,
    }]);
    assert_eq!(report.diagnostics.len(), 1, "{report}");
    assert_eq!(report.diagnostics[0].rule, rules::FILE_TOO_LARGE.id);
}

#[test]
fn the_int_beyond_2_pow_53_is_quoted_as_written() {
    let report = run_case("int-out-of-range.json");
    let msg = &report.diagnostics[0].message;
    assert!(msg.contains("9223372036854775807"), "{msg}");
    assert!(!msg.contains("9223372036854776000"), "{msg}");
    assert!(!msg.contains("is not an integer"), "{msg}");
}

#[test]
fn corpus_and_expectations_match() {
    let mut cases: Vec<String> = std::fs::read_dir(corpus("invalid"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    cases.sort();
    let mut expected: Vec<&str> = EXPECTED.iter().map(|e| e.0).collect();
    expected.sort();
    assert_eq!(cases, expected);
}

#[test]
fn rules_page_lists_exactly_the_registry() {
    let page = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../docs/reference/rules.md");
    let text = std::fs::read_to_string(&page).unwrap();
    let table = rules::markdown_table();
    assert!(
        text.contains(&table),
        "docs/reference/rules.md's rule table differs from the registry; paste this between the rule markers:\n{table}"
    );
}

#[test]
fn all_problems_of_all_files_are_reported_in_one_run() {
    let inputs = read_inputs(&[corpus("invalid")]).unwrap();
    let n_files = inputs.len();
    let (_, report) = validate::run(&inputs);
    let files: std::collections::BTreeSet<_> = report.diagnostics.iter().map(|d| d.file.clone()).collect();
    // Every file is reported (the fragment files only by duplicate-fragment, once), plus
    // duplicate-id errors (they all use id "toy").
    assert!(
        files.len() >= n_files - 3,
        "{} of {n_files} files reported",
        files.len()
    );
    assert!(report.diagnostics.iter().any(|d| d.rule == "duplicate-id"));
}
