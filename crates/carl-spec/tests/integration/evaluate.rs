//! The evaluation engine and `carl-spec evaluate`: episode outcomes from the environments
//! themselves (scalar and batched), the seed rule shared with Python, the Landing in Space
//! experiment's numbers unchanged on top of the engine, and the CLI's output and bad input.

use std::io::{BufRead, BufReader, Write};
use std::process::{Command, Stdio};

use carl_spec::envs::box2d::{LunarLander, heuristic};
use carl_spec::envs::policy::{FnPolicy, Policy};
use carl_spec::envs::registry::{MakeOptions, make_with};
use carl_spec::envs::vec_env::{AutoresetMode, VecEnv, VecOptions};
use carl_spec::envs::{Action, ContextSource, ContextualEnv, ContextualOptions, Env};
use carl_spec::episode::{EpisodeConfig, EpisodeEnd, EpisodeListener, Flow, StepRecord, run_episode};
use carl_spec::evaluation::{self, Config, Same, Source, Unobserved, episode_seed};
use carl_spec::experiments::landing_in_space::{self as lis, EpisodeEnd as End, Heuristic, reset_seed};
use carl_spec::instances::Store;
use carl_spec::spec::SpecSet;
use carl_spec::spec::model::Value;

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_carl-spec"));
    c.current_dir(std::env::temp_dir());
    c
}

struct Quiet;
impl<E: Env + ?Sized> EpisodeListener<E> for Quiet {
    fn on_step(&mut self, _: &E, _: &StepRecord<'_>) -> Result<Flow, carl_spec::episode::EpisodeError> {
        Ok(Flow::Continue)
    }
}

fn lander_heuristic(obs: &[f32]) -> Action {
    Action::Discrete(heuristic(obs))
}

/// SplitMix64 known answers (the seed rule Python's `carl_spec.evaluate` documents): a change
/// here would make the CLI and Python play different episodes.
#[test]
fn episode_seeds_follow_the_documented_rule() {
    let mix = |x: u64| {
        let mut z = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    };
    // SplitMix64's first output from state 0 (the reference implementation's known answer).
    assert_eq!(mix(0), 0xE220_A839_7B1D_CDAF);
    let h = mix(mix(mix(5) ^ 3) ^ 2) >> 1;
    assert_eq!(episode_seed(5, 3, 2, None), h);
    let s = episode_seed(5, 3, 2, Some(7));
    assert_eq!(s % 7, 3);
    assert_eq!(s, h - h % 7 + 3);
}

/// `reset_some` (the resets between `evaluate`'s steps) resets the listed environments exactly
/// as `reset_each` with a mask does, on CartPole's structure-of-arrays kernel and on a batch of
/// contextual environments playing given instances of a set, and refuses bad input without
/// resetting anything.
#[test]
fn reset_some_equals_a_masked_reset_each() {
    let specs = SpecSet::bundled().unwrap();
    let set = Store::new(&specs)
        .load("lunar_lander/landing_in_space_test_planets")
        .unwrap();
    let lander = specs.get("lunar_lander").unwrap();
    let n = 5;
    let batch = |kind: usize| -> VecEnv {
        if kind == 0 {
            let spec = specs.get("cartpole").unwrap();
            let envs = (0..n)
                .map(|_| make_with(spec, &Default::default(), MakeOptions::default()).unwrap())
                .collect();
            VecEnv::from_envs_with(envs, VecOptions::default(), AutoresetMode::Disabled).unwrap()
        } else {
            let envs = (0..n)
                .map(|_| {
                    ContextualEnv::new(lander, ContextSource::Set(set.clone()), ContextualOptions::default()).unwrap()
                })
                .collect();
            VecEnv::from_contextual(envs, VecOptions::default(), AutoresetMode::Disabled).unwrap()
        }
    };
    for kind in 0..2 {
        let (mut a, mut b) = (batch(kind), batch(kind));
        a.reset(3);
        b.reset(3);
        let rows = [4, 1, 2];
        let seeds = [40, 10, 20];
        let instances = (kind == 1).then_some(&[Some(5), None, Some(0)][..]);
        a.reset_some(&rows, &seeds, instances).unwrap();
        let mut all_seeds = vec![None; n];
        let mut all_instances = vec![None; n];
        let mut mask = vec![false; n];
        for (k, &i) in rows.iter().enumerate() {
            (all_seeds[i], mask[i]) = (Some(seeds[k]), true);
            all_instances[i] = instances.and_then(|v| v[k]);
        }
        let inst = (kind == 1).then_some(&all_instances[..]);
        b.reset_each(&all_seeds, inst, Some(&mask)).unwrap();
        assert_eq!(a.obs(), b.obs(), "batch kind {kind}");
        assert_eq!(a.instance_ids(), b.instance_ids());
        for i in 0..n {
            assert_eq!(a.state(i), b.state(i), "environment {i}");
        }
        // Bad input: an error, and nothing moves.
        let before = a.obs().to_vec();
        assert!(a.reset_some(&[0, 1], &[1], None).is_err());
        assert!(a.reset_some(&[0, n], &[1, 2], None).is_err());
        assert!(a.reset_some(&[0], &[1], Some(&[Some(99)])).is_err());
        if kind == 0 {
            assert!(
                a.reset_some(&[0], &[1], Some(&[Some(0)])).is_err(),
                "a fixed context has no instances"
            );
        }
        assert_eq!(a.obs(), &before[..]);
    }
}

/// LunarLander's outcomes come from the lander: the heuristic crashes on Jupiter and lands on
/// the Moon; the scalar env, the contextual env and the batch agree.
#[test]
fn outcomes_come_from_the_environment() {
    let specs = SpecSet::bundled().unwrap();
    let spec = specs.get("lunar_lander").unwrap();
    let set = Store::new(&specs)
        .load("lunar_lander/landing_in_space_test_planets")
        .unwrap();
    let mut env = ContextualEnv::new(spec, ContextSource::Set(set.clone()), ContextualOptions::default()).unwrap();
    let mut policy = FnPolicy(lander_heuristic);
    let mut seen = std::collections::BTreeMap::new();
    for (i, inst) in set.instances.iter().enumerate() {
        let job = evaluation::Job {
            instance: i,
            episode: 0,
            seed: 11,
        };
        let (r, summary) = evaluation::run_job(&mut env, true, &job, &mut policy, &mut Quiet).unwrap();
        assert!(summary.end == EpisodeEnd::Terminated || summary.end == EpisodeEnd::Truncated);
        let word = r.outcome.clone().expect("LunarLander names every ending");
        if r.truncated {
            assert_eq!(word, "timed_out");
        } else {
            assert!(["landed", "crashed", "out_of_view"].contains(&word.as_str()), "{word}");
            // The lander's own state says the same.
            let ll = env.inner().inner().downcast_ref::<LunarLander>().unwrap();
            assert_eq!(ll.outcome().name(), Some(word.as_str()));
        }
        seen.insert(inst.label(), word);
    }
    assert_eq!(seen["Jupiter"], "crashed");
    assert_eq!(seen["Earth"], "landed");
    assert!(env.outcome().is_some());

    // The same episodes in a batch (autoreset disabled): the same words per environment.
    let n = set.instances.len();
    let envs: Vec<ContextualEnv> = (0..n)
        .map(|_| ContextualEnv::new(spec, ContextSource::Set(set.clone()), ContextualOptions::default()).unwrap())
        .collect();
    let mut venv = VecEnv::from_contextual(envs, VecOptions::default(), AutoresetMode::Disabled).unwrap();
    venv.reset_each(&vec![Some(11); n], Some(&(0..n).map(Some).collect::<Vec<_>>()), None)
        .unwrap();
    let mut words: Vec<Option<String>> = vec![None; n];
    let mut done = vec![false; n];
    let d = venv.obs_dim();
    while done.iter().any(|x| !x) {
        let actions: Vec<i64> = (0..n)
            .map(|i| {
                if done[i] {
                    0
                } else {
                    heuristic(&venv.obs()[i * d..(i + 1) * d])
                }
            })
            .collect();
        if done.iter().any(|&x| x) {
            // Finished envs restart so the batch can step; their words are already kept.
            let mask: Vec<bool> = done.clone();
            venv.reset_each(&vec![Some(11); n], None, Some(&mask)).unwrap();
        }
        venv.step_discrete(&actions).unwrap();
        for i in 0..n {
            if !done[i] && (venv.terminated()[i] || venv.truncated()[i]) {
                done[i] = true;
                words[i] = venv.outcome(i).map(str::to_string);
            }
        }
    }
    let labels: Vec<String> = set.instances.iter().map(|i| i.label()).collect();
    for (i, l) in labels.iter().enumerate() {
        assert_eq!(words[i].as_deref(), Some(seen[l].as_str()), "{l}");
    }
}

/// CartPole fails or times out; MountainCar and Acrobot are solved or time out; Pendulum only
/// times out.
#[test]
fn classic_outcomes() {
    let specs = SpecSet::bundled().unwrap();
    for (id, words) in [
        ("cartpole", &["failed", "timed_out"][..]),
        ("mountain_car", &["solved", "timed_out"][..]),
        ("acrobot", &["solved", "timed_out"][..]),
        ("pendulum", &["timed_out"][..]),
    ] {
        let spec = specs.get(id).unwrap();
        let mut env = make_with(spec, &Default::default(), MakeOptions::default()).unwrap();
        let space = env.action_space();
        let mut p = carl_spec::envs::policy::RandomPolicy::new(space, 3);
        let s = run_episode(&mut env, &mut p, &EpisodeConfig::default(), &mut Quiet).unwrap();
        let word = env
            .outcome()
            .unwrap_or_else(|| panic!("{id}: no outcome after {:?}", s.end));
        assert!(words.contains(&word), "{id}: {word}");
        assert_eq!(word == "timed_out", s.end == EpisodeEnd::Truncated, "{id}");
    }
    // A random CartPole episode fails long before the limit.
    let mut env = make_with(
        specs.get("cartpole").unwrap(),
        &Default::default(),
        MakeOptions::default(),
    )
    .unwrap();
    let mut p = carl_spec::envs::policy::RandomPolicy::new(env.action_space(), 0);
    run_episode(&mut env, &mut p, &EpisodeConfig::default(), &mut Quiet).unwrap();
    assert_eq!(env.outcome(), Some("failed"));
}

/// `run landing_in_space` on the engine gives the numbers of the former implementation: a
/// runtime made per episode with the full context, its crash penalty set, reset with the row's
/// seed, the outcome read from the lander.
#[test]
fn landing_in_space_numbers_are_unchanged() {
    let specs = SpecSet::bundled().unwrap();
    let spec = specs.get("lunar_lander").unwrap();
    let cfg = lis::Config {
        episodes: 3,
        seed: 5,
        crash_penalty: 10000.0,
    };
    let results = lis::evaluate(&specs, &cfg, "heuristic", &mut Heuristic, &mut lis::Unobserved).unwrap();
    let store = Store::new(&specs);
    let test = store.load(lis::TEST_SET).unwrap();
    let train = store.load(lis::TRAIN_SET).unwrap();
    for row in &results.rows {
        let set = if row.body == lis::TRAIN_ROW { &train } else { &test };
        for (k, run) in row.runs.iter().enumerate() {
            let i = run.instance;
            let ctx = set.full_context(spec, i).unwrap();
            let opts = MakeOptions {
                allow_out_of_bounds: set.provenance.definition.allow_out_of_bounds,
            };
            let mut env = make_with(spec, &ctx, opts).unwrap();
            env.inner_mut()
                .downcast_mut::<LunarLander>()
                .unwrap()
                .options_mut()
                .crash_penalty = 10000.0;
            let seed = reset_seed(5, &row.body, k);
            let config = EpisodeConfig {
                seed,
                ..Default::default()
            };
            let s = run_episode(&mut env, &mut Heuristic, &config, &mut Quiet).unwrap();
            let ll = env.inner().downcast_ref::<LunarLander>().unwrap();
            let end = match (s.end, ll.outcome().name()) {
                (EpisodeEnd::Terminated, Some("landed")) => End::Landed,
                (EpisodeEnd::Terminated, Some("out_of_view")) => End::OutOfView,
                (EpisodeEnd::Terminated, _) => End::Crashed,
                _ => End::Timeout,
            };
            assert_eq!(run.seed, seed);
            assert_eq!(run.ret.to_bits(), s.total_reward.to_bits(), "{} episode {k}", row.body);
            assert_eq!(run.length, s.steps);
            assert_eq!(run.end, end, "{} episode {k}", row.body);
        }
    }
}

/// The engine: every instance, the documented seeds, results in (instance, episode) order,
/// reproducible; a heuristic's numbers equal a hand-run of the same jobs.
#[test]
fn engine_plays_every_instance_with_the_documented_seeds() {
    let specs = SpecSet::bundled().unwrap();
    let spec = specs.get("lunar_lander").unwrap();
    let set = Store::new(&specs)
        .load("lunar_lander/landing_in_space_test_planets")
        .unwrap();
    let n = set.instances.len();
    let cfg = Config {
        source: Source::Set { set, episodes: 2 },
        seed: 9,
        env_options: Default::default(),
        policy: "heuristic".into(),
    };
    let run = || evaluation::evaluate(spec, &cfg, &mut Same(FnPolicy(lander_heuristic)), &mut Unobserved).unwrap();
    let a = run();
    let b = run();
    assert_eq!(a.to_json(), b.to_json());
    assert_eq!(a.episodes.len(), 2 * n);
    for (j, e) in a.episodes.iter().enumerate() {
        assert_eq!((e.instance, e.episode), (j / 2, j % 2));
        assert_eq!(e.seed, episode_seed(9, e.instance, e.episode, Some(n)));
        assert!(e.outcome.is_some());
    }
    let doc = a.to_json();
    assert_eq!(doc["format"], evaluation::FORMAT);
    assert_eq!(
        doc["provenance"]["source"]["name"],
        "lunar_lander/landing_in_space_test_planets"
    );
    assert!(
        doc["provenance"]["source"]["content_hash"]
            .as_str()
            .unwrap()
            .starts_with("sha256:")
    );
    assert_eq!(doc["summary"].as_array().unwrap().len(), n);
    assert_eq!(doc["instances"][0]["name"], "Jupiter");
}

fn evaluate_cli(args: &[&str]) -> std::process::Output {
    bin().arg("evaluate").args(args).stdin(Stdio::null()).output().unwrap()
}

#[test]
fn cli_evaluate_prints_tables_and_json() {
    let o = evaluate_cli(&[
        "lunar_lander/landing_in_space_test_planets",
        "--episodes",
        "2",
        "--seed",
        "1",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(
        text.contains("lunar_lander/landing_in_space_test_planets (sha256:"),
        "{text}"
    );
    assert!(text.contains("| Jupiter |"), "{text}");
    assert!(text.contains("crashed"), "{text}");

    let o = evaluate_cli(&[
        "lunar_lander/landing_in_space_test_planets",
        "--episodes",
        "2",
        "--seed",
        "1",
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0));
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(doc["provenance"]["seed"], 1);
    assert!(doc["provenance"]["env_version"].is_u64());
    assert_eq!(doc["episodes"].as_array().unwrap().len(), 12);
    // The JSON is the engine's, episode for episode.
    let specs = SpecSet::bundled().unwrap();
    let set = Store::new(&specs)
        .load("lunar_lander/landing_in_space_test_planets")
        .unwrap();
    let cfg = Config {
        source: Source::Set { set, episodes: 2 },
        seed: 1,
        env_options: Default::default(),
        policy: "x".into(),
    };
    let mine = evaluation::evaluate(
        specs.get("lunar_lander").unwrap(),
        &cfg,
        &mut Same(FnPolicy(lander_heuristic)),
        &mut Unobserved,
    )
    .unwrap();
    assert_eq!(doc["episodes"], mine.to_json()["episodes"]);

    // Random actions: reproducible per seed; a distribution's draws; a fixed context.
    let r1 = evaluate_cli(&["cartpole", "--policy", "random", "--episodes", "3", "--json"]);
    let r2 = evaluate_cli(&["cartpole", "--policy", "random", "--episodes", "3", "--json"]);
    assert_eq!(r1.status.code(), Some(0), "{}", String::from_utf8_lossy(&r1.stderr));
    assert_eq!(r1.stdout, r2.stdout);
    let o = evaluate_cli(&[
        "pendulum",
        "--distribution",
        "q1_g_sigma_0_5",
        "--draws",
        "3",
        "--policy",
        "random",
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(doc["instances"].as_array().unwrap().len(), 3);
    assert!(doc["instances"][0]["context"]["g"].is_number());
    assert!(doc["episodes"][0]["context_seed"].is_u64());
    assert!(
        doc["episodes"]
            .as_array()
            .unwrap()
            .iter()
            .all(|e| e["outcome"] == "timed_out")
    );
}

#[test]
fn cli_evaluate_refuses_bad_input() {
    let cases: &[(&[&str], &str)] = &[
        (&["lunar_lander/no_such_set"], "no_such_set"),
        (&["nosuchenv/x"], "nosuchenv"),
        (
            &["pendulum/q1_g_sigma_0_5", "--env", "lunar_lander"],
            "belongs to pendulum, not to lunar_lander",
        ),
        (&["pendulum", "--distribution", "nope"], "nope"),
        (
            &["pendulum/q1_g_sigma_0_5", "--policy", "heuristic"],
            "no built-in controller",
        ),
        (&["cartpole", "--option", "continuous=true"], "continuous"),
        (&["cartpole", "--context", "gravity=-5"], "outside its bounds"),
    ];
    for (args, want) in cases {
        let o = evaluate_cli(args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(want), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}

/// `--policy stdin`: episodes streamed as JSON lines; an action outside the action space is a
/// clear error and exit 2, never a panic.
#[test]
fn cli_evaluate_stdin_policy() {
    let run = |answer: &str| {
        let mut child = bin()
            .args(["evaluate", "cartpole", "--policy", "stdin", "--episodes", "2", "--json"])
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut stdin = child.stdin.take().unwrap();
        let stdout = BufReader::new(child.stdout.take().unwrap());
        let mut heads = 0;
        for line in stdout.lines() {
            let v: serde_json::Value = serde_json::from_str(&line.unwrap()).unwrap();
            if v.get("episode").is_some() {
                heads += 1;
                continue;
            }
            let done = v.get("t").is_some() && (v["terminated"] == true || v["truncated"] == true);
            if !done && writeln!(stdin, "{answer}").and_then(|()| stdin.flush()).is_err() {
                break;
            }
        }
        drop(stdin);
        (heads, child.wait_with_output().unwrap())
    };
    let (heads, o) = run("1");
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(heads, 2);
    let doc: serde_json::Value = serde_json::from_slice(&o.stderr).unwrap();
    assert_eq!(doc["episodes"].as_array().unwrap().len(), 2);
    assert_eq!(doc["episodes"][0]["outcome"], "failed");
    let (_, o) = run("7");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("instance 0 episode 0") && err.contains('7'), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

/// A crash penalty reaches the runtime through `--option`.
#[test]
fn cli_evaluate_passes_options() {
    let o = evaluate_cli(&[
        "lunar_lander/landing_in_space_test_planets",
        "--episodes",
        "1",
        "--option",
        "crash_penalty=10000",
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let jupiter = &doc["episodes"][0];
    assert_eq!(jupiter["outcome"], "crashed");
    assert!(jupiter["return"].as_f64().unwrap() < -9000.0);
    assert_eq!(
        doc["provenance"]["options"]["crash_penalty"],
        Value::Number(10000.0).as_json()
    );
}

trait AsJson {
    fn as_json(&self) -> serde_json::Value;
}
impl AsJson for Value {
    fn as_json(&self) -> serde_json::Value {
        serde_json::to_value(self).unwrap()
    }
}

#[allow(dead_code)]
fn _policy_is_object_safe(p: &mut dyn Policy) -> &mut dyn Policy {
    p
}
