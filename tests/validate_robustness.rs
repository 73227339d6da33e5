//! No input makes the validator panic or hang: truncations, byte flips, random values spliced into
//! a real spec, huge and deeply nested files, thousands of files.

use carl_spec::validate::{self, Input};
use proptest::prelude::*;

const BASE: &str = include_str!("corpus/base.json");

fn run(bytes: Vec<u8>) -> validate::Report {
    let (_, report) = validate::run(&[Input {
        name: "fuzz.json".into(),
        bytes,
        library: false,
    }]);
    for d in &report.diagnostics {
        // Every diagnostic is located inside the file (when it has a location at all).
        if let Some(loc) = &d.location {
            assert!(loc.line >= 1 && loc.column >= 1);
        }
        let _ = d.render_text(false);
        let _ = d.render_github();
    }
    report
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, .. ProptestConfig::default() })]

    #[test]
    fn truncated_specs_are_errors_not_panics(cut in 0usize..BASE.len()) {
        let report = run(BASE.as_bytes()[..cut].to_vec());
        // Cutting only trailing whitespace leaves a valid spec; any other cut is an error.
        prop_assert_eq!(report.has_errors(), BASE[..cut].trim_end() != BASE.trim_end());
    }

    #[test]
    fn byte_flips_never_panic(pos in 0usize..BASE.len(), byte in any::<u8>()) {
        let mut b = BASE.as_bytes().to_vec();
        b[pos] = byte;
        run(b);
    }

    #[test]
    fn spliced_values_never_panic(
        pos in 0usize..BASE.len(),
        junk in prop_oneof![
            Just("NaN".to_string()), Just("\"inf\"".to_string()), Just("-1e999".to_string()),
            Just("null".to_string()), Just("[]".to_string()), Just("{}".to_string()),
            Just("1e308".to_string()), Just("-0".to_string()), Just("18446744073709551616".to_string()),
            "\\PC{0,8}",
        ],
    ) {
        let mut s = BASE.to_string();
        let mut p = pos;
        while !s.is_char_boundary(p) { p -= 1; }
        s.insert_str(p, &junk);
        run(s.into_bytes());
    }

    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..512)) {
        run(bytes);
    }
}

#[test]
fn huge_file_is_refused_quickly() {
    let mut big = String::from("{\"id\": \"x\", \"pad\": \"");
    big.push_str(&"a".repeat(50 * 1024 * 1024));
    big.push_str("\"}");
    let report = run(big.into_bytes());
    assert_eq!(report.diagnostics[0].rule, "file-too-large");
}

#[test]
fn large_valid_json_that_is_not_a_spec_is_handled() {
    // 2 MB of numbers: parsed and rejected by the schema, no pathological slowness.
    let body: Vec<String> = (0..200_000).map(|i| i.to_string()).collect();
    let text = format!("{{\"features\": [{}]}}", body.join(","));
    let report = run(text.into_bytes());
    assert!(report.has_errors());
}

#[test]
fn deep_nesting_is_an_error() {
    let report = run("[".repeat(1_000_000).into_bytes());
    assert_eq!(report.diagnostics[0].rule, "json-syntax");
}

#[test]
fn thousands_of_specs_in_one_run() {
    let inputs: Vec<Input> = (0..3000)
        .map(|i| Input {
            name: format!("s{i}.json"),
            bytes: BASE
                .replace("\"id\": \"toy\"", &format!("\"id\": \"toy_{i}\""))
                .into_bytes(),
            library: false,
        })
        .collect();
    let (resolved, report) = validate::run(&inputs);
    assert!(!report.has_errors(), "{report}");
    assert_eq!(resolved.len(), 3000);
}
