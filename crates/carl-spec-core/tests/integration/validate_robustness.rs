//! No input makes the validator panic or hang: truncations, byte flips, random values spliced into
//! a real spec, huge and deeply nested files, thousands of files.

use carl_spec_core::validate::{self, Input};
use proptest::prelude::*;

const BASE: &str = include_str!("../corpus/base.json");

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

/// Numbers that sit on the edges of what the samplers can handle.
fn edge_number() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("0".to_string()),
        Just("-1".to_string()),
        Just("0.5".to_string()),
        Just("1".to_string()),
        Just("5".to_string()),
        Just("20".to_string()),
        Just("1e-320".to_string()),
        Just("1e300".to_string()),
        Just("1e308".to_string()),
        Just("1.7e308".to_string()),
        Just("-1.7e308".to_string()),
        (-30.0f64..30.0).prop_map(|x| format!("{x}")),
    ]
}

fn edge_int() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("0".to_string()),
        Just("3".to_string()),
        Just("-5".to_string()),
        Just("20".to_string()),
        Just("9007199254740992".to_string()),
        Just("9007199254740993".to_string()),
        Just("-9007199254740993".to_string()),
        Just("9223372036854775807".to_string()),
        (-30i64..30).prop_map(|x| x.to_string()),
    ]
}

/// A sampler for one of the base spec's features, as JSON.
fn sampler_json() -> impl Strategy<Value = String> {
    let n = edge_number;
    prop_oneof![
        (n(), n()).prop_map(|(m, s)| format!(r#"{{ "kind": "normal", "mean": {m}, "std": {s} }}"#)),
        (n(), n())
            .prop_map(|(a, b)| format!(r#"{{ "kind": "relative_normal", "sigma_rel": {a}, "fallback_std": {b} }}"#)),
        (n(), n(), n(), n()).prop_map(|(m, s, l, h)| format!(
            r#"{{ "kind": "truncated_normal", "mean": {m}, "std": {s}, "low": {l}, "high": {h} }}"#
        )),
        (n(), n()).prop_map(|(l, h)| format!(r#"{{ "kind": "uniform", "low": {l}, "high": {h} }}"#)),
        (n(), n()).prop_map(|(l, h)| format!(r#"{{ "kind": "log_uniform", "low": {l}, "high": {h} }}"#)),
        (edge_int(), edge_int()).prop_map(|(l, h)| format!(r#"{{ "kind": "int_uniform", "low": {l}, "high": {h} }}"#)),
        (n(), n(), n(), n(), any::<bool>()).prop_map(|(a, b, c, d, s)| format!(
            r#"{{ "kind": "interval_mixture", "intervals": [[{a}, {b}], [{c}, {d}]], "stratified": {s} }}"#
        )),
        (n(), n()).prop_map(|(w1, w2)| format!(r#"{{ "kind": "categorical", "weights": [{w1}, {w2}] }}"#)),
        n().prop_map(|v| format!(r#"{{ "kind": "constant", "value": {v} }}"#)),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, .. ProptestConfig::default() })]

    /// The sampler is the one authority on its parameters: a distribution `validate` accepts can
    /// be frozen, and one it refuses for its parameters is refused by `freeze` too.
    #[test]
    fn validate_accepts_exactly_what_freeze_can_sample(
        feature in prop_oneof![Just("mass"), Just("steps"), Just("mode")],
        sampler in sampler_json(),
        at_bounds in prop_oneof![Just("clip"), Just("resample"), Just("reject")],
    ) {
        let text = BASE
            .replace(
                r#""features": { "mass": { "kind": "normal", "mean": 1.0, "std": 0.5 } }"#,
                &format!(r#""features": {{ "{feature}": {sampler} }}"#),
            )
            .replace(r#""at_bounds": "resample""#, &format!(r#""at_bounds": "{at_bounds}""#));
        let (resolved, report) = validate::run(&[Input { name: "p.json".into(), bytes: text.into_bytes(), library: false }]);
        // Shapes the schema refuses (e.g. a fraction for int_uniform) never reach the sampler.
        prop_assume!(!report.diagnostics.iter().any(|d| d.rule.starts_with("schema/")));
        let refused = report.diagnostics.iter().any(|d| d.rule.starts_with("distribution-"));
        prop_assert_eq!(refused, report.has_errors(), "only the sampler was changed:\n{}", report);
        let spec = &resolved[0].spec;
        match carl_spec_core::instances::derive_set(spec, "train") {
            Ok(set) => {
                prop_assert!(!refused, "validate refused what freeze samples:\n{}", report);
                prop_assert_eq!(set.instances.len(), 10);
            }
            Err(carl_spec_core::instances::DeriveError::Sampling { source, .. }) => {
                use carl_spec_core::sampling::SamplingError as E;
                match source {
                    // Draw-time outcomes of a valid sampler under `reject`/`resample`.
                    E::OutOfBounds { .. } | E::ResampleExhausted { .. } => {
                        prop_assert!(!refused);
                        prop_assert_ne!(at_bounds, "clip");
                    }
                    other => prop_assert!(refused, "validate accepted what freeze refuses: {}", other),
                }
            }
            Err(e) => prop_assert!(false, "unexpected: {}", e),
        }
    }
}

#[test]
fn the_issues_examples_are_refused_by_validate() {
    for (feature, sampler) in [
        ("mass", r#"{ "kind": "uniform", "low": -1.7e308, "high": 1.7e308 }"#),
        ("mass", r#"{ "kind": "normal", "mean": 1e308, "std": 1e308 }"#),
        (
            "steps",
            r#"{ "kind": "int_uniform", "low": -9007199254740993, "high": 5 }"#,
        ),
    ] {
        let text = BASE.replace(
            r#""features": { "mass": { "kind": "normal", "mean": 1.0, "std": 0.5 } }"#,
            &format!(r#""features": {{ "{feature}": {sampler} }}"#),
        );
        let report = run(text.into_bytes());
        assert_eq!(report.diagnostics.len(), 1, "{sampler}: {report}");
        assert_eq!(report.diagnostics[0].rule, "distribution-params", "{report}");
        assert_eq!(report.diagnostics[0].location.as_ref().unwrap().line, 41);
    }
}

#[test]
fn names_with_terminal_escapes_are_refused_and_never_printed_raw() {
    let text = BASE.replacen(r#""name": "mass""#, r#""name": "ma\u001b[2Jss""#, 1);
    let report = run(text.into_bytes());
    assert!(
        report.diagnostics.iter().any(|d| d.rule == "schema/pattern"),
        "{report}"
    );
    // An unknown name in a distribution is quoted back: escaped, never raw.
    let text = BASE.replace(r#""features": { "mass":"#, r#""features": { "m\u001b]0;pwned\u0007":"#);
    let report = run(text.into_bytes());
    let all = format!(
        "{report}{}",
        report.diagnostics.iter().map(|d| d.render_github()).collect::<String>()
    );
    assert!(
        report.diagnostics.iter().any(|d| d.rule == "unknown-feature"),
        "{report}"
    );
    assert!(!all.contains('\u{1b}') && !all.contains('\u{7}'), "{all:?}");
    assert!(all.contains("\\u{1b}"), "{all}");
}

#[test]
fn a_huge_number_in_a_message_is_cut() {
    let digits = "7".repeat(100_000);
    let text = BASE.replace(r#""default": "a""#, &format!(r#""default": {digits}"#));
    let report = run(text.into_bytes());
    assert!(report.has_errors());
    for d in &report.diagnostics {
        assert!(
            d.message.len() < 2_000,
            "{} bytes: {}",
            d.message.len(),
            &d.message[..200]
        );
    }
}
