//! `carl-spec run landing_in_space` end to end: reproducibility, the heuristic's qualitative
//! behaviour across planets, the crash penalty, output-file safety and the stdin policy.

use std::io::{BufRead, BufReader, Write};
use std::process::{Command, Stdio};

use carl_spec::experiments::landing_in_space::{Config, Heuristic, Results, Unobserved, evaluate, reset_seed};
use carl_spec::spec::SpecSet;

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_carl-spec"));
    c.current_dir(std::env::temp_dir());
    c
}

fn tmpdir(tag: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("carl-lis-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn heuristic(episodes: usize, seed: u64) -> Results {
    let specs = SpecSet::bundled().unwrap();
    let cfg = Config {
        episodes,
        seed,
        crash_penalty: 100.0,
    };
    evaluate(&specs, &cfg, "heuristic", &mut Heuristic, &mut Unobserved).unwrap()
}

fn row<'a>(r: &'a Results, body: &str) -> &'a carl_spec::experiments::landing_in_space::Row {
    r.rows.iter().find(|x| x.body == body).unwrap()
}

#[test]
fn reset_seeds_are_distinct_and_stable() {
    assert_eq!(reset_seed(0, "Earth", 0), reset_seed(0, "Earth", 0));
    assert_ne!(reset_seed(0, "Earth", 0), reset_seed(0, "Earth", 1));
    assert_ne!(reset_seed(0, "Earth", 0), reset_seed(0, "Mars", 0));
    assert_ne!(reset_seed(0, "Earth", 0), reset_seed(1, "Earth", 0));
}

/// Same seed, same numbers; at the documented configuration (seed 0, 20 episodes per row) the
/// heuristic crashes on Jupiter, lands ≥ 85 % on Earth and Mars and keeps Earth, Mars and the
/// Moon at a crash rate (crashes plus out of view) ≤ 0.2 (Gymnasium: 100 % crashes on Jupiter, ≤ 8 % crash-or-out-of-view on Earth and
/// Mars, 22 % out of view on the Moon).
#[test]
fn heuristic_is_reproducible_and_crashes_only_on_jupiter() {
    let a = heuristic(20, 0);
    let b = heuristic(20, 0);
    let key = |r: &Results| serde_json::to_string(&r.rows).unwrap();
    assert_eq!(key(&a), key(&b));
    assert_eq!(a.rows.len(), 7);
    assert_eq!(a.rows[6].body, "train");
    assert_eq!(
        a.rows[6].runs.iter().map(|r| r.instance).collect::<Vec<_>>(),
        (0..20).collect::<Vec<_>>()
    );
    assert_eq!(row(&a, "Mars").split, "in_distribution");
    assert_eq!(row(&a, "Jupiter").split, "out_of_distribution");
    let jupiter = row(&a, "Jupiter").crash_rate;
    assert!(jupiter >= 0.9, "Jupiter crash rate {jupiter}");
    for body in ["Earth", "Mars", "Moon"] {
        let c = row(&a, body).crash_rate;
        assert!(c <= 0.2, "{body}: crash rate {c}");
    }
    // Gymnasium's heuristic lands 92 % on Earth and 96 % on Mars; so does ours.
    for body in ["Earth", "Mars"] {
        let l = row(&a, body).landed_rate;
        assert!(l >= 0.85, "{body}: landed rate {l}");
    }
    for r in &a.rows {
        let total = r.landed_rate + r.crash_rate + r.timeout_rate;
        assert!((total - 1.0).abs() < 1e-9, "{}: rates sum to {total}", r.body);
    }
}

/// Under another seed the Moon's out-of-view share varies (15–50 % over seeds 0–7, drifting out
/// sideways in low gravity); body-on-ground crashes stay rare on Earth, Mars and the Moon.
#[test]
fn heuristic_rarely_crashes_into_the_ground_on_earth_mars_moon() {
    let a = heuristic(10, 7);
    assert!(row(&a, "Jupiter").crash_rate >= 0.9);
    for body in ["Earth", "Mars", "Moon"] {
        let r = row(&a, body);
        let ground = r.crash_rate - r.out_of_view_rate;
        assert!(ground <= 0.2, "{body}: ground-crash rate {ground}");
    }
}

#[test]
fn paper_crash_penalty_sinks_jupiter_and_outputs_are_written() {
    let d = tmpdir("penalty");
    let (out, fig) = (d.join("results.json"), d.join("returns.svg"));
    let o = bin()
        .args([
            "run",
            "landing_in_space",
            "--episodes",
            "3",
            "--seed",
            "1",
            "--crash-penalty",
            "10000",
        ])
        .arg("--out")
        .arg(&out)
        .arg("--figure")
        .arg(&fig)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let table = String::from_utf8_lossy(&o.stdout);
    assert!(table.contains("Jupiter") && table.contains("train"), "{table}");
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(v["crash_penalty"], 10000.0);
    // The physics is recorded with the results: the in-crate Box2D-semantics solver, by version.
    let engine = carl_spec::envs::box2d::PHYSICS_ENGINE;
    assert_eq!(v["physics_engine"], engine);
    assert!(
        engine.starts_with(&format!("carl-spec {} physics2d (Box2D 2.3", env!("CARGO_PKG_VERSION"))),
        "{engine}"
    );
    let jup = v["rows"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["body"] == "Jupiter")
        .unwrap();
    let mean = jup["mean_return"].as_f64().unwrap();
    assert!(mean <= -9000.0, "Jupiter mean return {mean}");
    let svg = std::fs::read_to_string(&fig).unwrap();
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let bars = doc
        .descendants()
        .filter(|n| n.has_tag_name("rect") && n.children().any(|c| c.has_tag_name("title")))
        .count();
    assert_eq!(bars, 7);
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn bad_policy_and_existing_outputs_exit_2_and_write_nothing() {
    let d = tmpdir("refuse");
    let (out, fig) = (d.join("results.json"), d.join("returns.svg"));
    let o = bin()
        .args(["run", "landing_in_space", "--policy", "random", "--episodes", "1"])
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(!out.exists());
    std::fs::write(&out, "old").unwrap();
    let o = bin()
        .args(["run", "landing_in_space", "--episodes", "1"])
        .arg("--out")
        .arg(&out)
        .arg("--figure")
        .arg(&fig)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--force"));
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "old");
    assert!(!fig.exists());
    let leftovers = std::fs::read_dir(&d).unwrap().count();
    assert_eq!(leftovers, 1);
    let _ = std::fs::remove_dir_all(&d);
}

/// An external agent through a pipe: always action 0 (free fall), one episode per row.
#[test]
fn stdin_policy_streams_episodes_and_reads_actions() {
    let mut child = bin()
        .args([
            "run",
            "landing_in_space",
            "--policy",
            "stdin",
            "--episodes",
            "1",
            "--seed",
            "3",
        ])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let stdout = BufReader::new(child.stdout.take().unwrap());
    let mut episodes = Vec::new();
    let mut steps = 0;
    for line in stdout.lines() {
        let v: serde_json::Value = serde_json::from_str(&line.unwrap()).unwrap();
        if let Some(ep) = v.get("episode") {
            episodes.push(ep.clone());
            continue;
        }
        let done = v.get("t").is_some() && (v["terminated"].as_bool().unwrap() || v["truncated"].as_bool().unwrap());
        if v.get("t").is_some() {
            steps += 1;
            assert_eq!(v["action"], 0);
        } else {
            assert_eq!(v["reset"]["obs"].as_array().unwrap().len(), 8);
        }
        if !done {
            writeln!(stdin, "0").unwrap();
            stdin.flush().unwrap();
        }
    }
    drop(stdin);
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(episodes.len(), 7);
    assert_eq!(episodes[0]["body"], "Jupiter");
    assert_eq!(episodes[6]["body"], "train");
    assert_eq!(episodes[0]["seed"], reset_seed(3, "Jupiter", 0));
    assert!(episodes.iter().all(|e| e["gravity"].as_f64().unwrap() < 0.0));
    assert!(steps >= 7);
    // The table goes to stderr in this mode.
    assert!(String::from_utf8_lossy(&o.stderr).contains("Jupiter"));
}

fn run_lis(args: &[&str]) -> std::process::Output {
    bin()
        .args(["run", "landing_in_space"])
        .args(args)
        .stdin(Stdio::null())
        .output()
        .unwrap()
}

/// Regression: `--out missing/dir/r.json` created the directories (render and plot refuse).
#[test]
fn missing_output_directories_are_refused_like_everywhere() {
    let d = tmpdir("missing");
    for (flag, name) in [("--out", "r.json"), ("--figure", "r.svg")] {
        let p = d.join("missing/dir").join(name);
        let o = run_lis(&["--episodes", "1", flag, p.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{flag}");
        assert!(String::from_utf8_lossy(&o.stderr).contains("does not exist"), "{flag}");
        assert!(!d.join("missing").exists(), "{flag}: no directory created");
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// Regression: a bad `--out` (here a directory, with --force) was found only after the whole
/// evaluation. With the streaming policy the evaluation would print episodes first.
#[test]
fn a_bad_out_is_refused_before_the_evaluation() {
    let d = tmpdir("early");
    let o = run_lis(&[
        "--policy",
        "stdin",
        "--episodes",
        "1",
        "--force",
        "--out",
        d.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        o.stdout.is_empty(),
        "no episode started: {}",
        String::from_utf8_lossy(&o.stdout)
    );
    assert!(String::from_utf8_lossy(&o.stderr).contains("is a directory"));
    let f = d.join("same.json");
    let o = run_lis(&[
        "--episodes",
        "1",
        "--out",
        f.to_str().unwrap(),
        "--figure",
        f.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(!f.exists());
    let _ = std::fs::remove_dir_all(&d);
}

/// Regression: `--crash-penalty 1e308` wrote NaN into the SVG and null into the JSON.
#[test]
fn absurd_crash_penalties_are_refused_up_front() {
    let d = tmpdir("absurd");
    let (out, fig) = (d.join("r.json"), d.join("f.svg"));
    for p in ["1e308", "inf", "NaN", "-5", "1e10"] {
        let o = run_lis(&[
            "--policy",
            "stdin",
            "--episodes",
            "1",
            "--crash-penalty",
            p,
            "--out",
            out.to_str().unwrap(),
            "--figure",
            fig.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(2), "{p}");
        assert!(o.stdout.is_empty(), "{p}: refused before the evaluation");
        assert!(String::from_utf8_lossy(&o.stderr).contains("crash"), "{p}");
    }
    assert!(!out.exists() && !fig.exists());
    let _ = std::fs::remove_dir_all(&d);
}
