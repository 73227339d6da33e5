//! `carl-spec rollout` end to end: the documented JSON Lines, Gymnasium parity through the CLI,
//! closed-loop driving through a pipe, and bad input.

use std::io::{BufRead, BufReader, Write};
use std::process::{Command, Stdio};

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_carl-spec"));
    c.current_dir(std::env::temp_dir());
    c
}

fn lines(out: &[u8]) -> Vec<serde_json::Value> {
    String::from_utf8_lossy(out)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

/// Replay every parity fixture episode through the CLI (context, initial state, actions) and compare
/// the float32 observations bit for bit with Gymnasium's.
#[test]
fn cli_rollouts_reproduce_gymnasium_fixtures() {
    let dir = std::env::temp_dir().join(format!("carl-rollout-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let specs = carl_spec::spec::SpecSet::bundled().unwrap();
    let mut replayed = 0;
    for env in [
        "cartpole",
        "pendulum",
        "mountain_car",
        "mountain_car_continuous",
        "acrobot",
    ] {
        let spec = specs.get(env).unwrap();
        let path = format!(
            "{}/../carl-envs-classic-control/tests/fixtures/parity/{env}.json",
            env!("CARGO_MANIFEST_DIR")
        );
        let fx: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        for ep in fx["episodes"].as_array().unwrap() {
            // Runtime-only options (e.g. Acrobot's "nips" dynamics) are not context features.
            // Contexts using runtime parameters that are not spec features (e.g. Pendulum's max_torque) too.
            if !ep["options"].as_object().unwrap().is_empty()
                || ep["context"]
                    .as_object()
                    .unwrap()
                    .keys()
                    .any(|k| spec.feature(k).is_none())
            {
                continue;
            }
            replayed += 1;
            let mut cmd = bin();
            cmd.arg("rollout").arg(env).arg("--allow-out-of-bounds");
            for (k, v) in ep["context"].as_object().unwrap() {
                cmd.arg("--context").arg(format!("{k}={v}"));
            }
            let state: Vec<String> = ep["initial_state"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.to_string())
                .collect();
            cmd.arg("--initial-state").arg(state.join(","));
            let actions = if fx["action_encoding"].as_str().unwrap_or("").contains("bit patterns") {
                // Continuous (1-D) actions are stored as float32 bits: decode to JSON numbers.
                let acts: Vec<Vec<f32>> = ep["actions"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|b| vec![f32::from_bits(b.as_u64().unwrap() as u32)])
                    .collect();
                serde_json::to_string(&acts).unwrap()
            } else {
                ep["actions"].to_string()
            };
            let afile = dir.join(format!("{env}-{}.json", ep["name"].as_str().unwrap().replace('#', "_")));
            std::fs::write(&afile, actions).unwrap();
            cmd.arg("--actions").arg(&afile);
            let out = cmd.output().unwrap();
            assert!(
                out.status.success(),
                "{env} {}: {}",
                ep["name"],
                String::from_utf8_lossy(&out.stderr)
            );
            let ls = lines(&out.stdout);
            let obs_bits = ep["obs_bits"].as_array().unwrap();
            let n = obs_bits.len().min(ls.len() - 1);
            assert!(n > 0);
            for (t, expected) in obs_bits.iter().take(n).enumerate() {
                let got: Vec<u32> = ls[t + 1]["obs"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|x| (x.as_f64().unwrap() as f32).to_bits())
                    .collect();
                let want: Vec<u32> = expected
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|b| b.as_u64().unwrap() as u32)
                    .collect();
                assert_eq!(got, want, "{env} {} step {}", ep["name"], t + 1);
                assert_eq!(
                    ls[t + 1]["reward"].as_f64(),
                    ep["rewards"][t].as_f64(),
                    "{env} reward step {}",
                    t + 1
                );
            }
        }
    }
    assert!(replayed >= 30, "only {replayed} episodes replayed");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn output_follows_the_documented_format() {
    let out = bin()
        .args(["rollout", "cartpole", "--seed", "3", "--context", "masscart=2.5"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    let first = text.lines().next().unwrap();
    assert!(first.starts_with("{\"reset\":{\"obs\":["), "{first}");
    let ls = lines(&out.stdout);
    assert_eq!(ls[0]["reset"]["context"]["masscart"], 2.5);
    assert_eq!(ls[0]["reset"]["context"]["gravity"], 9.8);
    let second = text.lines().nth(1).unwrap();
    assert!(second.starts_with("{\"t\":1,\"action\":"), "{second}");
    let last = ls.last().unwrap();
    assert!(last["terminated"].as_bool().unwrap() || last["truncated"].as_bool().unwrap());
    // Same seed, same run.
    let again = bin()
        .args(["rollout", "cartpole", "--seed", "3", "--context", "masscart=2.5"])
        .output()
        .unwrap();
    assert_eq!(again.stdout, out.stdout);
    // --steps caps the run; instance sets provide contexts.
    let out = bin()
        .args([
            "rollout",
            "pendulum",
            "--instance-set",
            "pendulum/q1_l_sigma_0_5",
            "--instance",
            "7",
            "--steps",
            "4",
        ])
        .output()
        .unwrap();
    let ls = lines(&out.stdout);
    assert_eq!(ls.len(), 5);
    assert_ne!(ls[0]["reset"]["context"]["l"], 1.0);
}

/// A program drives the environment step by step: each line must arrive before the next action
/// is sent (the process is never given more than one action ahead).
#[test]
fn closed_loop_through_a_pipe() {
    let mut child = bin()
        .args(["rollout", "mountain_car", "--actions", "-", "--initial-state", "-0.5,0"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let mut reader = BufReader::new(child.stdout.take().unwrap());
    let mut line = String::new();
    reader.read_line(&mut line).unwrap();
    let reset: serde_json::Value = serde_json::from_str(&line).unwrap();
    let mut velocity = reset["reset"]["obs"][1].as_f64().unwrap();
    for t in 1..=5 {
        // Bang-bang controller on the observed velocity.
        let action = if velocity >= 0.0 { 2 } else { 0 };
        writeln!(stdin, "{action}").unwrap();
        stdin.flush().unwrap();
        line.clear();
        reader.read_line(&mut line).unwrap();
        let step: serde_json::Value = serde_json::from_str(&line).unwrap();
        assert_eq!(step["t"], t);
        assert_eq!(step["action"], action);
        velocity = step["obs"][1].as_f64().unwrap();
    }
    drop(stdin);
    assert!(child.wait().unwrap().success());
}

#[test]
fn bad_input_is_refused_with_exit_2() {
    for (args, needle) in [
        (
            &["rollout", "cartpole", "--context", "gravty=1"][..],
            "did you mean \"gravity\"",
        ),
        (
            &["rollout", "cartpole", "--context", "masscart=100"],
            "outside its bounds",
        ),
        (&["rollout", "cartpole", "--context", "masscart"], "NAME=VALUE"),
        (&["rollout", "cartpole", "--initial-state", "1,2"], "--initial-state"),
        (
            &["rollout", "cartpole", "--instance-set", "pendulum/q1_g_sigma_0_1"],
            "belongs to pendulum",
        ),
        (
            &[
                "rollout",
                "pendulum",
                "--instance-set",
                "pendulum/q1_g_sigma_0_1",
                "--instance",
                "100",
            ],
            "no instance 100",
        ),
    ] {
        let o = bin().args(args).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
    let mut child = bin()
        .args(["rollout", "cartpole", "--actions", "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    writeln!(child.stdin.as_mut().unwrap(), "5").unwrap();
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("out of range")
            || String::from_utf8_lossy(&out.stderr).contains("step 1")
    );
}
