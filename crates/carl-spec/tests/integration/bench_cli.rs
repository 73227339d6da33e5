//! `carl-spec bench`: one JSON line on success, exit 2 for unknown envs or envs without runtime.

use std::process::Command;

fn bench(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_carl-spec"))
        .arg("bench")
        .args(args)
        .output()
        .expect("run carl-spec")
}

#[test]
fn prints_one_json_line() {
    let o = bench(&["cartpole", "--num-envs", "40", "--steps", "20000", "--threads", "2"]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8(o.stdout).unwrap();
    assert_eq!(text.lines().count(), 1);
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(v["env"], "cartpole");
    assert_eq!(v["num_envs"], 40);
    assert_eq!(v["threads"], 2);
    assert_eq!(v["steps"], 20000);
    for k in ["single_steps_per_sec", "single_ns_per_step", "vec_steps_per_sec"] {
        assert!(v[k].as_f64().unwrap() > 0.0, "{k}");
    }
    let o = bench(&["pendulum", "--num-envs", "3", "--steps", "3000", "--threads", "1"]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn defaults_fit_the_environment() {
    // A physics environment: 64 worlds (not 1024) and steps calibrated to about a second per
    // run instead of 20 M (hours at a millisecond per step).
    let o = bench(&["ur5e", "--threads", "1"]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["num_envs"], 64);
    let steps = v["steps"].as_u64().unwrap();
    assert!((1000..1_000_000).contains(&steps), "{steps}");
}

#[test]
fn unknown_env_or_missing_runtime_exits_2() {
    let o = bench(&["cartpol"]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("unknown environment") && err.contains("cartpole"), "{err}");
    let o = bench(&["cartpole", "--num-envs", "0"]);
    assert_eq!(o.status.code(), Some(2));
}
