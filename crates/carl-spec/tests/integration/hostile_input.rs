//! Regression tests for what hostile input found (issue 11): every command reports failure
//! clearly with a non-zero exit, never a truncated or `null`-filled result, never a panic.

use std::io::Write;
use std::process::{Command, Output, Stdio};

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_carl-spec"));
    c.current_dir(std::env::temp_dir());
    c
}

fn run(args: &[&str]) -> Output {
    bin().args(args).output().unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn a_failed_write_to_stdout_is_an_error_in_every_command() {
    let Ok(full) = std::fs::OpenOptions::new().write(true).open("/dev/full") else {
        eprintln!("no /dev/full on this system: skipped");
        return;
    };
    for args in [
        &["list"][..],
        &["show", "cartpole"],
        &["schema"],
        &["stats"],
        &["validate", "--format", "json"],
        &["instances", "list"],
        &["instances", "show", "lunar_lander/landing_in_space_train"],
        &[
            "sample",
            "pendulum",
            "--distribution",
            "q1_g_sigma_0_5",
            "-n",
            "5",
            "--seed",
            "0",
        ],
        &["rollout", "cartpole", "--steps", "5"],
        &["audit", "cartpole"],
        &["bench", "cartpole", "--steps", "1000", "--num-envs", "16"],
    ] {
        let o = bin().args(args).stdout(full.try_clone().unwrap()).output().unwrap();
        assert!(!o.status.success(), "{args:?} exited 0 with stdout on a full disk");
        assert!(
            o.status.code().is_some_and(|c| c == 1 || c == 2),
            "{args:?}: {:?} {}",
            o.status,
            stderr(&o)
        );
        assert!(stderr(&o).contains("No space left"), "{args:?}: {}", stderr(&o));
    }
}

#[test]
fn a_closed_pipe_is_still_a_quiet_success() {
    let mut child = bin()
        .args(["rollout", "pendulum"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}

#[test]
fn non_finite_steps_are_errors_not_nulls() {
    for args in [
        &["rollout", "cartpole", "--context", "gravity=1e30"][..],
        &["rollout", "pendulum", "--context", "max_speed=-1e300"],
        &["rollout", "fetch", "--context", "target_radius=1e20", "--steps", "3"],
    ] {
        let o = run(args);
        let out = String::from_utf8_lossy(&o.stdout);
        assert!(!out.contains("null"), "{args:?} printed null: {out}");
        if o.status.success() {
            // A runtime may also refuse such a context up front or end the episode with an
            // info flag; what it may not do is print a non-finite number.
            continue;
        }
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains("non-finite"), "{args:?}: {}", stderr(&o));
    }
    // The cartpole case must fail (its pole accelerates to infinity within two steps).
    assert!(
        !run(&["rollout", "cartpole", "--context", "gravity=1e30"])
            .status
            .success()
    );
}

#[test]
fn a_sets_out_of_bounds_permission_does_not_cover_overrides() {
    let o = run(&[
        "rollout",
        "lunar_lander",
        "--instance-set",
        "lunar_lander/landing_in_space_test_planets",
        "--instance",
        "3",
        "--context",
        "GRAVITY_X=100",
        "--steps",
        "1",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("outside its bounds"), "{}", stderr(&o));
    // The set's own out-of-bounds instance (Jupiter) still runs, and an explicit flag still works.
    let jupiter = [
        "rollout",
        "lunar_lander",
        "--instance-set",
        "lunar_lander/landing_in_space_test_planets",
    ];
    let o = bin()
        .args(jupiter)
        .args(["--instance", "0", "--steps", "1"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let o = bin()
        .args(jupiter)
        .args([
            "--instance",
            "3",
            "--context",
            "GRAVITY_X=100",
            "--allow-out-of-bounds",
            "--steps",
            "1",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn categorical_labels_work_on_the_command_line() {
    let o = run(&["rollout", "vehicle_racing", "--context", "VEHICLE=Bus", "--steps", "1"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = run(&[
        "rollout",
        "vehicle_racing",
        "--context",
        "VEHICLE=Spaceship",
        "--steps",
        "1",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("Spaceship"), "{}", stderr(&o));
}

#[test]
fn long_bad_input_is_quoted_short() {
    let mut child = bin()
        .args(["rollout", "cartpole", "--actions", "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Below the 1 MiB action-line limit (hostile_limits tests a longer one).
    let line = format!("[{}\n", "9".repeat(900_000));
    let _ = child.stdin.as_mut().unwrap().write_all(line.as_bytes());
    drop(child.stdin.take());
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(err.len() < 1000, "{} bytes of error", err.len());
    assert!(err.contains("900001 bytes"), "{err}");
}

#[test]
fn bench_refuses_absurd_sizes_quickly() {
    for args in [
        &["bench", "cartpole", "--num-envs", "1000000000"][..],
        &["bench", "cartpole", "--steps", "18446744073709551615"],
        &["bench", "humanoid", "--num-envs", "100000"],
        &["bench", "cartpole", "--threads", "100000"],
        &["bench", "cartpole", "--num-envs", "0"],
    ] {
        let t = std::time::Instant::now();
        let o = run(args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains("--"), "{args:?}: {}", stderr(&o));
        // Refused before any work (not a timing assertion on speed: a refusal does no work).
        assert!(t.elapsed().as_secs() < 60, "{args:?}");
    }
}

#[test]
fn every_command_offers_the_same_policies() {
    // rollout drives the lander with its heuristic, as render does; environments without one
    // are refused with the list of those that have one.
    let o = run(&["rollout", "lunar_lander", "--policy", "heuristic", "--seed", "1"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let last: serde_json::Value =
        serde_json::from_str(String::from_utf8_lossy(&o.stdout).lines().last().unwrap()).unwrap();
    assert_eq!(last["terminated"], true, "the heuristic lands within the time limit");
    let o = run(&["rollout", "cartpole", "--policy", "heuristic"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("lunar_lander, bipedal_walker"), "{}", stderr(&o));
    let o = run(&["rollout", "bipedal_walker", "--policy", "heuristic", "--steps", "50"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = run(&["rollout", "pendulum", "--policy", "noop", "--steps", "3"]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.lines().skip(1).all(|l| l.contains("\"action\":[0.0]")), "{text}");
}

#[test]
fn variant_options_select_the_environment_variant() {
    let o = run(&["rollout", "lunar_lander", "--option", "continuous=true", "--steps", "1"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let step: serde_json::Value =
        serde_json::from_str(String::from_utf8_lossy(&o.stdout).lines().nth(1).unwrap()).unwrap();
    assert_eq!(step["action"].as_array().map(Vec::len), Some(2));
    let o = run(&["rollout", "bipedal_walker", "--option", "hardcore=true", "--steps", "1"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = run(&["rollout", "lunar_lander", "--option", "continous=true"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("did you mean \"continuous\""), "{}", stderr(&o));
    let o = run(&["rollout", "cartpole", "--option", "hardcore=true"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("takes no options"), "{}", stderr(&o));
    // The removed rapier2d walker engine: its old option is refused like any unknown one.
    for old in ["rapier=true", "box2d_contacts=true"] {
        let o = run(&["rollout", "bipedal_walker", "--option", old, "--steps", "1"]);
        assert_eq!(o.status.code(), Some(2), "{old}");
        let err = stderr(&o);
        let name = old.split('=').next().unwrap();
        assert!(
            err.contains(&format!("bipedal_walker has no option \"{name}\"")),
            "{err}"
        );
        assert!(err.contains("valid options: hardcore"), "{err}");
        assert!(
            o.stdout.is_empty(),
            "nothing runs: {}",
            String::from_utf8_lossy(&o.stdout)
        );
    }
    let o = run(&["rollout", "lunar_lander", "--option", "continuous=maybe"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("true or false"), "{}", stderr(&o));
}

#[test]
fn the_data_directory_can_be_named_on_the_command_line() {
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data");
    if !data.join("mario").is_dir() {
        eprintln!("no ../shared/data/mario beside the checkout: skipped");
        return;
    }
    let o = bin()
        .env_remove("CARL_SPEC_DATA")
        .arg("--data-dir")
        .arg(&data)
        .args(["rollout", "mario", "--steps", "1"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let o = bin()
        .env_remove("CARL_SPEC_DATA")
        .args(["--data-dir", "/no/such/dir", "rollout", "mario"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("not a directory"), "{}", stderr(&o));
}
