//! The `carl-spec` binary as users and CI run it: outputs and exit codes (0 ok, 1 invalid, 2 usage/I-O).

use std::process::{Command, Output};

fn carl(args: &[&str]) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_carl-spec"));
    cmd.args(args).current_dir(std::env::temp_dir()); // bundled specs work from any directory
    // Mario's levels come from the data directory, which a user names with CARL_SPEC_DATA.
    if let Ok(data) = carl_mario::DataDir::discover(std::path::Path::new(env!("CARGO_MANIFEST_DIR"))) {
        cmd.env("CARL_SPEC_DATA", data.root());
    }
    cmd.output().expect("binary runs")
}

fn corpus(p: &str) -> String {
    format!("{}/../carl-spec-core/tests/corpus/{p}", env!("CARGO_MANIFEST_DIR"))
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

#[test]
fn validate_bundled_specs_passes() {
    let o = carl(&["validate"]);
    assert_eq!(o.status.code(), Some(0), "{}", stdout(&o));
    assert!(stdout(&o).starts_with("valid: "));
}

#[test]
fn validate_invalid_exits_1_with_located_errors() {
    let o = carl(&["validate", &corpus("invalid/bounds-order.json")]);
    assert_eq!(o.status.code(), Some(1));
    let text = stdout(&o);
    assert!(text.contains("error[bounds-order]"), "{text}");
    assert!(text.contains("bounds-order.json:15:17"), "{text}");
    assert!(text.contains("^^^^"), "the source line is underlined: {text}");
}

#[test]
fn validate_json_format_is_machine_readable() {
    let o = carl(&["validate", &corpus("invalid"), "--format", "json"]);
    assert_eq!(o.status.code(), Some(1));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["valid"], false);
    let diags = v["diagnostics"].as_array().unwrap();
    assert!(diags.len() >= 27);
    for d in diags {
        assert!(d["rule"].is_string() && d["file"].is_string() && d["message"].is_string());
    }
}

#[test]
fn validate_github_format_emits_annotations() {
    let o = carl(&[
        "validate",
        &corpus("invalid/default-out-of-bounds.json"),
        "--format",
        "github",
    ]);
    assert_eq!(o.status.code(), Some(1));
    let text = stdout(&o);
    let first = text.lines().next().unwrap();
    assert!(first.starts_with("::error file="), "{first}");
    assert!(first.contains(",line=14,col=18,"), "{first}");
    assert!(first.contains("title=carl-spec default-out-of-bounds::"), "{first}");
}

#[test]
fn validate_missing_path_or_empty_dir_is_a_usage_error() {
    let o = carl(&["validate", "/definitely/not/here.json"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("cannot read"));
    let empty = tempdir();
    let o = carl(&["validate", empty.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("no *.json spec files found in") && err.contains(empty.to_str().unwrap()),
        "{err}"
    );
}

#[test]
fn unknown_command_or_flag_is_a_usage_error() {
    assert_eq!(carl(&["frobnicate"]).status.code(), Some(2));
    assert_eq!(carl(&["validate", "--format", "yaml"]).status.code(), Some(2));
}

#[test]
fn show_list_schema_stats() {
    let o = carl(&["show", "CARLCartPoleEnv"]);
    assert_eq!(o.status.code(), Some(0));
    assert!(stdout(&o).contains("masscart"));
    let o = carl(&["show", "cartpole", "--format", "json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["id"], "cartpole");
    assert_eq!(v["features"][1]["name"], "gravity");

    let o = carl(&["show", "cartpol"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("did you mean \"cartpole\""));

    let o = carl(&["list"]);
    assert!(stdout(&o).lines().any(|l| l.starts_with("cartpole ")));

    let o = carl(&["schema"]);
    let committed = std::fs::read_to_string(format!(
        "{}/../../schema/carl-spec.schema.json",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    assert_eq!(stdout(&o), committed);

    let o = carl(&["stats", "--format", "json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(v["features"].as_u64().unwrap() > 0);
}

#[test]
fn author_specs_dir_is_added_to_bundled() {
    let dir = tempdir();
    let base = std::fs::read_to_string(corpus("base.json")).unwrap();
    std::fs::write(dir.join("toy.json"), base).unwrap();
    let o = carl(&["--specs", dir.to_str().unwrap(), "show", "toy"]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let o = carl(&["--specs", dir.to_str().unwrap(), "list"]);
    assert!(stdout(&o).contains("toy"));
}

fn tempdir() -> crate::common::TempDir {
    crate::common::TempDir::new("cli")
}

#[test]
fn audit_exit_codes_and_formats() {
    let o = carl(&["audit", "cartpole"]);
    assert_eq!(o.status.code(), Some(0), "{}", stdout(&o));
    let text = stdout(&o);
    assert!(text.contains("masscart") && text.contains("✓"), "{text}");
    assert!(text.contains("cartpole: ok"), "{text}");

    let o = carl(&["audit", "mountain_car", "--format", "json"]);
    assert_eq!(o.status.code(), Some(0));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["env"], "mountain_car");
    assert_eq!(v["passed"], true);
    let goal = v["features"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["name"] == "goal_position")
        .unwrap();
    let term = goal["effects"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["effect"] == "termination")
        .unwrap();
    assert_eq!(term["verdict"], "ok");
    assert_eq!(term["measured"], "changed");

    // The one full audit of every bundled runtime in the suite (what a benchmark's CI runs):
    // every claim holds, no feature is skipped, task-generation effects are left to the
    // dedicated checks (not applicable to transitions).
    let o = carl(&["audit", "--all", "--format", "json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let reports = v.as_array().unwrap();
    let specs = carl_spec::spec::SpecSet::bundled().unwrap();
    let mut ids: Vec<&str> = reports.iter().map(|r| r["env"].as_str().unwrap()).collect();
    let mut runtimes = carl_spec::envs::registry::ids().collect::<Vec<_>>();
    ids.sort_unstable();
    runtimes.sort_unstable();
    assert_eq!(ids, runtimes);
    for r in reports {
        let id = &r["env"];
        assert_eq!(r["passed"], true, "{id}: {:#}", r["contradictions"]);
        for f in r["features"].as_array().unwrap() {
            // Only a computed default (Mario's `noise`, CARL's sampling; its effect on the level
            // is tested in tests/mario_env.rs) has no value to perturb around.
            // Likewise a string choice (RNA's `dataset`).
            if f["skipped"]
                .as_str()
                .is_some_and(|s| s.contains("computed default") || s.contains("without numeric choices"))
            {
                continue;
            }
            if f.get("skipped").is_some() {
                // Only features acting on task generation alone (rna_design's dataset names and
                // target id list) may be skipped: transitions cannot show that effect anyway.
                let spec = specs.get(id.as_str().unwrap()).unwrap();
                let feature = spec.feature(f["name"].as_str().unwrap()).unwrap();
                assert!(
                    feature
                        .affects
                        .iter()
                        .all(|e| *e == carl_spec::spec::model::Effect::TaskGeneration),
                    "{id}.{} skipped: {}",
                    f["name"],
                    f["skipped"]
                );
                continue;
            }
            assert!(!f["values"].as_array().unwrap().is_empty(), "{id}.{}", f["name"]);
            for e in f["effects"].as_array().unwrap() {
                let verdict = e["verdict"].as_str().unwrap();
                assert!(
                    verdict == "ok" || verdict == "not_applicable",
                    "{id}.{}: {e}",
                    f["name"]
                );
                if e["effect"] == "task_generation" {
                    assert_eq!(verdict, "not_applicable", "{id}.{}", f["name"]);
                }
            }
        }
    }
    assert_eq!(o.status.code(), Some(0));

    // Unknown environment, environment without runtime, nothing named: usage errors listing runtimes.
    for args in [&["audit", "cartpol"][..], &["audit"]] {
        let o = carl(args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        if args.len() == 2 {
            let err = String::from_utf8_lossy(&o.stderr);
            assert!(err.contains("mountain_car_continuous"), "{args:?}: {err}");
        }
    }
}
