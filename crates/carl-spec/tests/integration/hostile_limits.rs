//! Regression tests for issue 31's Rust and CLI side: no crash, hang or silent non-finite number
//! at any feature's bounds; sizes the runtimes cannot run refused with the feature named;
//! non-finite actions refused naming the component; output files never written through a planted
//! symlink; empty instance sets refused at load; stream input read only up to a named limit;
//! `run --figure` only to an `.svg` file.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use carl_spec::envs::api::{Action, Env, EnvError, Space, check_finite_output};
use carl_spec::envs::registry::{Context, MakeError, MakeOptions, ids, make, make_with};
use carl_spec::instances::Store;
use carl_spec::spec::SpecSet;
use carl_spec::spec::model::{FeatureType, Value};

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_carl-spec"));
    c.current_dir(std::env::temp_dir());
    c
}

fn tempdir(tag: &str) -> PathBuf {
    let p = std::env::temp_dir().join(format!("carl-spec-limits-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&p);
    std::fs::create_dir_all(&p).unwrap();
    p
}

fn ctx(pairs: &[(&str, f64)]) -> Context {
    pairs.iter().map(|(k, v)| (k.to_string(), Value::Number(*v))).collect()
}

/// A fixed in-range action of `space`: its start, or the middle of each finite [low, high].
fn middle_action(space: &Space) -> Action {
    match space {
        Space::Discrete { start, .. } => Action::Discrete(*start),
        Space::Box { low, high, .. } => Action::Continuous(
            low.iter()
                .zip(high)
                .map(|(l, h)| {
                    if l.is_finite() && h.is_finite() {
                        0.5 * (l + h)
                    } else {
                        0.0
                    }
                })
                .collect(),
        ),
    }
}

/// Every runtime at every finite bound of every numeric feature: `make` gives an environment or a
/// clear error, and the environment resets and steps with finite observations and rewards (or
/// refuses the step with an error): never a panic, an abort or a silent ±inf/NaN.
#[test]
fn every_runtime_is_finite_at_every_feature_bound() {
    let specs = SpecSet::bundled().unwrap();
    let mut failures = Vec::new();
    let mut tried = 0;
    for id in ids() {
        let spec = specs.get(id).unwrap();
        for f in &spec.features {
            if !matches!(f.kind, FeatureType::Float | FeatureType::Int) {
                continue;
            }
            for bound in f.bounds.iter().flatten() {
                let context = ctx(&[(f.name.as_str(), *bound)]);
                let mut env = match make(spec, &context) {
                    Ok(env) => env,
                    Err(e) => {
                        // Refusing a bound is allowed only with a message naming the feature.
                        if !e.to_string().contains(&f.name) {
                            failures.push(format!("{id} {}={bound}: make: {e}", f.name));
                        }
                        continue;
                    }
                };
                tried += 1;
                let (obs, _) = env.reset(Some(0));
                if let Err(e) = check_finite_output(id_static(id), &obs, 0.0) {
                    failures.push(format!("{id} {}={bound}: reset: {e}", f.name));
                    continue;
                }
                let action = middle_action(&env.action_space());
                for _ in 0..10 {
                    let Ok(step) = env.step(&action) else { break };
                    if let Err(e) = check_finite_output(id_static(id), &step.obs, step.reward) {
                        failures.push(format!("{id} {}={bound}: step: {e}", f.name));
                        break;
                    }
                    if step.terminated || step.truncated {
                        break;
                    }
                }
            }
        }
    }
    assert!(tried > 100, "only {tried} bounds tried");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

fn id_static(id: &str) -> &'static str {
    carl_spec::envs::registry::lookup(id).unwrap().id
}

/// rna_design's observation is 2·state_radius+1 wide: the spec bounds it (500), and even out of
/// bounds the runtime refuses what it cannot allocate, naming the feature, instead of aborting.
#[test]
fn rna_design_sizes_are_bounded() {
    let specs = SpecSet::bundled().unwrap();
    let spec = specs.get("rna_design").unwrap();
    for r in [2f64.powi(62), 1e9, 1e7, 501.0] {
        let e = make(spec, &ctx(&[("state_radius", r)])).unwrap_err();
        assert!(matches!(e, MakeError::OutOfBounds { .. }), "{r}: {e}");
        assert!(e.to_string().contains("state_radius"), "{e}");
    }
    let oob = MakeOptions {
        allow_out_of_bounds: true,
    };
    for r in [2f64.powi(62), 1e9, 1e7] {
        let e = make_with(spec, &ctx(&[("state_radius", r)]), oob)
            .unwrap_err()
            .to_string();
        assert!(e.contains("state_radius") && e.contains("at most 65536"), "{e}");
    }
    let mut wide = make(spec, &ctx(&[("state_radius", 500.0)])).unwrap();
    let (obs, _) = wide.reset(Some(0));
    assert_eq!(obs.len(), 1001);
    for t in [1000.0, 10.5] {
        let e = make(spec, &ctx(&[("mutation_threshold", t)])).unwrap_err();
        assert!(matches!(e, MakeError::OutOfBounds { .. }), "{t}: {e}");
    }
    assert!(make(spec, &ctx(&[("mutation_threshold", 10.0)])).is_ok());
}

/// BipedalWalker's course is generated and built in linear time; a length beyond what the runtime
/// builds is refused at `make` and in `set_state` instead of hanging.
#[test]
fn bipedal_walker_terrain_length_is_bounded_and_linear() {
    let specs = SpecSet::bundled().unwrap();
    let spec = specs.get("bipedal_walker").unwrap();
    let oob = MakeOptions {
        allow_out_of_bounds: true,
    };
    let e = make_with(spec, &ctx(&[("TERRAIN_LENGTH", 200_000.0)]), oob)
        .unwrap_err()
        .to_string();
    assert!(e.contains("TERRAIN_LENGTH") && e.contains("at most 10000"), "{e}");
    // The longest course resets quickly: the broad phase no longer tests the terrain's edges
    // against each other (it took minutes at this length, O(n²)).
    let start = Instant::now();
    let mut env = make_with(spec, &ctx(&[("TERRAIN_LENGTH", 10_000.0)]), oob).unwrap();
    env.reset(Some(0));
    env.step(&Action::Continuous(vec![0.0; 4])).unwrap();
    assert!(start.elapsed() < Duration::from_secs(20), "{:?}", start.elapsed());

    let mut env = make(spec, &Context::new()).unwrap();
    env.reset(Some(0));
    let mut state = env.state();
    state[21] = 1e12;
    let start = Instant::now();
    let e = env.set_state(&state).unwrap_err().to_string();
    assert!(start.elapsed() < Duration::from_secs(1));
    assert!(e.contains("TERRAIN_LENGTH") && e.contains("at most 10000"), "{e}");
}

/// NaN and ±inf actions (and f32-overflowing ones, which arrive as ±inf) are refused by every
/// runtime with a continuous action space, naming the component.
#[test]
fn non_finite_actions_are_refused_by_every_runtime() {
    let specs = SpecSet::bundled().unwrap();
    let mut checked = 0;
    for id in ids() {
        let Ok(mut env) = make(specs.get(id).unwrap(), &Context::new()) else {
            continue;
        };
        let Space::Box { low, .. } = env.action_space() else {
            continue;
        };
        env.reset(Some(0));
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 1e300f64 as f32] {
            let mut a = vec![0.0f32; low.len()];
            let last = low.len() - 1;
            a[last] = bad;
            let e = env.step(&Action::Continuous(a)).unwrap_err();
            assert!(
                matches!(e, EnvError::ActionNotFinite { index, .. } if index == last),
                "{id} {bad}: {e}"
            );
            assert!(
                e.to_string()
                    .contains(&format!("action component {last} is not finite")),
                "{e}"
            );
        }
        checked += 1;
    }
    assert!(checked >= 8, "{checked}");
}

/// A symlink planted at the temporary name earlier versions used (`.NAME.PID.tmp`) is not
/// followed by any writer: the link's target keeps its bytes, the output is written.
#[cfg(unix)]
#[test]
fn planted_symlinks_at_old_temporary_names_are_not_followed() {
    let dir = tempdir("symlink");
    let victim = dir.join("victim.txt");
    std::fs::write(&victim, "precious").unwrap();
    let plant = |name: &str| {
        std::os::unix::fs::symlink(&victim, dir.join(format!(".{name}.{}.tmp", std::process::id()))).unwrap();
    };

    // render, plot and run write through output::write_file.
    plant("fig.svg");
    carl_spec::output::write_file(&dir.join("fig.svg"), b"<svg/>", false).unwrap();
    assert_eq!(std::fs::read_to_string(dir.join("fig.svg")).unwrap(), "<svg/>");

    // freeze writes through the same rule.
    std::fs::copy(
        concat!(env!("CARGO_MANIFEST_DIR"), "/../../specs/pendulum.json"),
        dir.join("pendulum.json"),
    )
    .unwrap();
    let sets_dir = dir.join("instances/pendulum");
    std::fs::create_dir_all(&sets_dir).unwrap();
    std::os::unix::fs::symlink(
        &victim,
        sets_dir.join(format!(".q1_dt_sigma_0_1.json.{}.tmp", std::process::id())),
    )
    .unwrap();
    let specs = author_specs(&dir);
    Store::new(&specs)
        .freeze(&["pendulum/q1_dt_sigma_0_1".into()], None, false)
        .unwrap();
    assert!(sets_dir.join("q1_dt_sigma_0_1.json").is_file());
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
    let _ = std::fs::remove_dir_all(&dir);
}

fn author_specs(dir: &Path) -> SpecSet {
    use carl_spec::spec::load::read_inputs;
    SpecSet::from_inputs(&read_inputs(&[dir.to_path_buf()]).unwrap()).unwrap()
}

/// An instance file with `"instances": []` and a recomputed hash is refused at load, with the
/// file and the reason named, instead of loading and panicking at reset.
#[test]
fn an_empty_frozen_set_is_refused_at_load() {
    let dir = tempdir("empty");
    std::fs::copy(
        concat!(env!("CARGO_MANIFEST_DIR"), "/../../specs/pendulum.json"),
        dir.join("pendulum.json"),
    )
    .unwrap();
    let specs = author_specs(&dir);
    let store = Store::new(&specs);
    store.freeze(&["pendulum/q1_dt_sigma_0_1".into()], None, false).unwrap();
    let file = dir.join("instances/pendulum/q1_dt_sigma_0_1.json");
    let mut frozen = store.load("pendulum/q1_dt_sigma_0_1").unwrap();
    frozen.instances.clear();
    std::fs::write(&file, frozen.with_hash().to_text()).unwrap();
    let e = store.load("pendulum/q1_dt_sigma_0_1").unwrap_err().to_string();
    assert!(e.contains("no instances") && e.contains("q1_dt_sigma_0_1"), "{e}");
    let o = bin()
        .args(["instances", "verify", "--specs"])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(!o.status.success());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Stream input is read up to a named limit, never whole: `/dev/zero` as input ends in an error
/// naming the limit within seconds (it grew to gigabytes before).
#[test]
fn stream_inputs_are_read_up_to_a_limit() {
    if !Path::new("/dev/zero").exists() {
        eprintln!("no /dev/zero: skipped");
        return;
    }
    let zero = || std::fs::File::open("/dev/zero").unwrap();
    let cases: [(&[&str], bool, &str); 5] = [
        (
            &["fold", "--input", "/dev/zero"],
            false,
            "/dev/zero is longer than the limit of 67108864 bytes",
        ),
        (
            &["fold", "eval", "-i", "-"],
            true,
            "stdin is longer than the limit of 67108864 bytes",
        ),
        (&["fold"], true, "stdin is longer than the limit of 67108864 bytes"),
        (
            &["rollout", "cartpole", "--actions", "-"],
            true,
            "an action line is longer than the limit of 1048576 bytes",
        ),
        (
            &["run", "landing_in_space", "--policy", "stdin", "--episodes", "1"],
            true,
            "an action line is longer than the limit of 1048576 bytes",
        ),
    ];
    for (args, stdin, message) in cases {
        let start = Instant::now();
        let mut cmd = bin();
        cmd.args(args).stdout(Stdio::null()).stderr(Stdio::piped());
        if stdin {
            cmd.stdin(zero());
        }
        let o = cmd.output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{args:?}");
        assert!(err.contains(message), "{args:?}: {err}");
        assert!(
            start.elapsed() < Duration::from_secs(30),
            "{args:?}: {:?}",
            start.elapsed()
        );
    }
    let dir = tempdir("actions");
    let o = bin()
        .args(["rollout", "cartpole", "--actions", "/dev/zero"])
        .output()
        .unwrap();
    assert!(String::from_utf8_lossy(&o.stderr).contains("--actions: /dev/zero is longer than the limit"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// `run --figure` writes SVG, so it takes only a `.svg` file, checked before the evaluation.
#[test]
fn run_figure_refuses_a_non_svg_name() {
    let dir = tempdir("figure");
    let png = dir.join("x.png");
    let o = bin()
        .args(["run", "landing_in_space", "--episodes", "1", "--figure"])
        .arg(&png)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("--figure") && err.contains("x.png") && err.contains(".svg"),
        "{err}"
    );
    assert!(!png.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Context noise too large for a float32 observation is refused when the wrapper is built,
/// naming the feature, instead of observing ±inf.
#[test]
fn huge_context_noise_is_refused_at_construction() {
    let o = bin()
        .args([
            "rollout",
            "cartpole",
            "--obs-context",
            "gravity",
            "--noise",
            "gravity=1e308",
            "--steps",
            "1",
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", String::from_utf8_lossy(&o.stdout));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("gravity") && err.contains("at most") && err.contains("1e30"),
        "{err}"
    );
}

/// Unknown names are quoted escaped and cut in make's messages.
#[test]
fn unknown_names_are_quoted_escaped_and_cut() {
    let specs = SpecSet::bundled().unwrap();
    let spec = specs.get("cartpole").unwrap();
    let long = format!("\u{1b}[2J{}", "x".repeat(100_000));
    let e = make(spec, &ctx(&[(long.as_str(), 1.0)])).unwrap_err().to_string();
    assert!(!e.contains('\u{1b}') && e.contains("\\u{1b}[2J"), "{e}");
    assert!(e.len() < 1000 && e.contains("(100004 bytes)"), "{}", e.len());
}
