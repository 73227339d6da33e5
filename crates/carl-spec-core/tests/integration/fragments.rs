//! Shared fragments: includes, exclusions, overrides, and the errors an author can make with them.

use std::path::PathBuf;

use carl_spec_core::spec::load::read_inputs;
use carl_spec_core::validate;

fn dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/corpus/fragments")
}

#[test]
fn include_mistakes_are_located_in_the_including_file() {
    let (_, report) = validate::run(&read_inputs(&[dir()]).unwrap());
    let got: Vec<(String, usize)> = report
        .diagnostics
        .iter()
        .map(|d| (d.rule.clone(), d.location.as_ref().map_or(0, |l| l.line)))
        .collect();
    let expected = [
        ("unknown-feature", 13),   // except: "frction"
        ("override-excluded", 16), // friction both excluded and overridden
        ("unknown-feature", 17),   // override of "mass"
        ("unknown-fragment", 20),  // "toy_physic" → did you mean "toy_physics"
        ("duplicate-feature", 23), // local "gravity" clashes with the included one
    ];
    assert_eq!(got.len(), expected.len(), "{report}");
    for (rule, line) in expected.iter() {
        assert!(
            got.contains(&(rule.to_string(), *line)),
            "missing {rule} at line {line}; got {got:?}\n{report}"
        );
    }
    let unknown = report
        .diagnostics
        .iter()
        .find(|d| d.rule == "unknown-fragment")
        .unwrap();
    assert!(
        unknown
            .help
            .as_deref()
            .unwrap()
            .contains("did you mean \"toy_physics\"")
    );
    assert!(
        report.diagnostics.iter().all(|d| d.file.ends_with("robot.json")),
        "{report}"
    );
}

#[test]
fn bundled_brax_specs_share_one_fragment_with_overrides() {
    let specs = carl_spec_core::spec::SpecSet::bundled().unwrap();
    let ant = specs.get("ant").unwrap();
    let humanoid = specs.get("humanoid").unwrap();
    assert_eq!(ant.feature("torso_mass").unwrap().default_f64(), Some(10.0));
    assert_eq!(
        ant.feature("gravity").unwrap().from_fragment.as_deref(),
        Some("brax_physics")
    );
    assert!(
        humanoid.feature("actuator_strength").is_none(),
        "humanoid excludes actuator_strength"
    );
    assert_eq!(
        specs.get("ur5e").unwrap().feature("gravity").unwrap().default_f64(),
        Some(-9.81)
    );
}

#[test]
fn an_override_out_of_bounds_points_at_the_override() {
    let text = std::fs::read_to_string(dir().join("robot.json"))
        .unwrap()
        .replace("\"default\": -30.0", "\"default\": 5.0")
        .replace(", \"frction\"", "")
        .replace("        \"friction\": { \"default\": 1.0 },\n", "")
        .replace(",\n        \"mass\": { \"default\": 1.0 }", "")
        .replace(",\n    { \"fragment\": \"toy_physic\" }", "")
        .replace(
            "\"name\": \"gravity\", \"type\": \"float\", \"default\": 1.0",
            "\"name\": \"local\", \"type\": \"float\", \"default\": 1.0",
        );
    let frag = std::fs::read(dir().join("physics.json")).unwrap();
    let inputs = vec![
        validate::Input {
            name: "robot.json".into(),
            bytes: text.into_bytes(),
            library: false,
        },
        validate::Input {
            name: "physics.json".into(),
            bytes: frag,
            library: false,
        },
    ];
    let (_, report) = validate::run(&inputs);
    assert_eq!(report.diagnostics.len(), 1, "{report}");
    let d = &report.diagnostics[0];
    assert_eq!(
        (d.rule.as_str(), d.file.as_str()),
        ("default-out-of-bounds", "robot.json")
    );
    assert!(d.pointer.ends_with("/overrides/gravity/default"), "{}", d.pointer);
}
