//! Contexts that change within an episode: each schedule kind moves its feature as declared, the
//! dynamics follow (equal to the runtime with its parameters changed by hand), values return to
//! the instance's own at reset, random walks repeat with the seed, the batch equals the scalar
//! wrapper, and schedules that would leave the bounds (or cannot act) are refused up front.

use carl_spec::envs::classic_control::{Pendulum, PendulumParams};
use carl_spec::envs::schedules::{Schedule, parse_schedules};
use carl_spec::envs::vec_env::{AutoresetMode, VecActions, VecEnv, VecOptions};
use carl_spec::envs::{Action, ContextSource, ContextualEnv, ContextualOptions, Env, Features, Visibility};
use carl_spec::instances::Store;
use carl_spec::spec::SpecSet;
use carl_spec::spec::model::Value;

fn pendulum(source: ContextSource, schedules: &str, visible: bool) -> Result<ContextualEnv, String> {
    let specs = SpecSet::bundled().unwrap();
    let spec = specs.get("pendulum").unwrap();
    let opts = ContextualOptions {
        schedules: parse_schedules(schedules)?,
        visibility: if visible {
            Visibility::Visible(Features::Only(vec!["g".into()]))
        } else {
            Visibility::Hidden
        },
        ..ContextualOptions::default()
    };
    ContextualEnv::new(spec, source, opts).map_err(|e| e.to_string())
}

fn fixed(g: f64) -> ContextSource {
    ContextSource::Fixed([("g".to_string(), Value::Number(g))].into())
}

fn g_of(env: &ContextualEnv) -> f64 {
    env.context_info().context.iter().find(|(k, _)| k == "g").unwrap().1
}

#[test]
fn each_kind_moves_the_feature_as_declared_in_info_and_observation() {
    let cases: &[(&str, &[f64])] = &[
        (r#"{"g": {"kind": "step", "at": 2, "to": 4}}"#, &[10.0, 10.0, 4.0, 4.0]),
        (
            r#"{"g": {"kind": "linear", "to": 14, "over": 2}}"#,
            &[10.0, 12.0, 14.0, 14.0],
        ),
        (
            r#"{"g": {"kind": "sine", "amplitude": 2, "period": 4}}"#,
            &[10.0, 12.0, 10.0, 8.0],
        ),
    ];
    for (json, want) in cases {
        let mut env = pendulum(fixed(10.0), json, true).unwrap();
        let mut obs = vec![0.0f32; 4];
        env.reset_into(Some(1), &mut obs).unwrap();
        let mut got = vec![g_of(&env)];
        assert_eq!(obs[3] as f64, got[0]);
        for _ in 0..3 {
            env.step_into(&Action::Continuous(vec![0.5]), &mut obs).unwrap();
            got.push(g_of(&env));
            assert_eq!(
                obs[3],
                *got.last().unwrap() as f32,
                "{json}: the visible value is the current one"
            );
        }
        for (a, b) in got.iter().zip(*want) {
            assert!((a - b).abs() < 1e-9, "{json}: {got:?} vs {want:?}");
        }
        // The next episode starts from the context's own value again.
        env.reset_into(Some(2), &mut obs).unwrap();
        assert_eq!(g_of(&env), want[0]);
        assert_eq!(env.scheduled_values().collect::<Vec<_>>(), [("g", want[0])]);
    }
}

#[test]
fn the_dynamics_follow_the_schedule() {
    // A linear drift of g, against the runtime with its g changed by hand before each step.
    let mut env = pendulum(fixed(10.0), r#"{"g": {"kind": "linear", "to": 20, "over": 50}}"#, false).unwrap();
    let mut manual = Pendulum::new(PendulumParams::default());
    let (mut a, mut b) = (vec![0.0f32; 3], vec![0.0f32; 3]);
    env.reset_into(Some(7), &mut a).unwrap();
    let s = env.state();
    manual.reset_into(Some(0), &mut b).unwrap();
    manual.set_state(&s).unwrap();
    for t in 0..60u32 {
        manual.params_mut().g = 10.0 + 10.0 * (f64::from(t.min(50)) / 50.0);
        let u = Action::Continuous(vec![(t as f32 * 0.37).sin() * 2.0]);
        env.step_into(&u, &mut a).unwrap();
        manual.step_into(&u, &mut b).unwrap();
        assert_eq!(a, b, "step {t}");
    }
    // and it differs from the unscheduled pendulum
    let mut plain = pendulum(fixed(10.0), "{}", false).unwrap();
    plain.reset_into(Some(7), &mut b).unwrap();
    for _ in 0..60 {
        plain.step_into(&Action::Continuous(vec![0.0]), &mut b).unwrap();
    }
    assert_ne!(a, b);
}

#[test]
fn random_walks_repeat_with_the_seed_and_stay_in_range() {
    let json = r#"{"g": {"kind": "random_walk", "std": 0.5, "low": 8, "high": 12}}"#;
    let walk = |seed: u64| {
        let mut env = pendulum(fixed(10.0), json, false).unwrap();
        let mut obs = vec![0.0f32; 3];
        env.reset_into(Some(seed), &mut obs).unwrap();
        (0..200)
            .map(|_| {
                env.step_into(&Action::Continuous(vec![0.0]), &mut obs).unwrap();
                g_of(&env)
            })
            .collect::<Vec<f64>>()
    };
    let (a, b, c) = (walk(3), walk(3), walk(4));
    assert_eq!(a, b);
    assert_ne!(a, c);
    assert!(a.iter().all(|g| (8.0..=12.0).contains(g)));
    assert!(a.iter().any(|g| (g - 10.0).abs() > 1.0), "the walk moves");
}

#[test]
fn the_batch_equals_the_scalar_wrapper() {
    let specs = SpecSet::bundled().unwrap();
    let set = Store::new(&specs).load("pendulum/g_l_train").unwrap();
    let json = r#"{"g": {"kind": "sine", "amplitude": 1.5, "period": 37}, "l": {"kind": "random_walk", "std": 0.01, "low": 0.5, "high": 1.5}}"#;
    let proto = pendulum(ContextSource::Set(set), json, true).unwrap();
    const N: usize = 5;
    let mut scalar = vec![proto.clone(); N];
    let opts = VecOptions {
        threads: 2,
        ..VecOptions::default()
    };
    let mut venv = VecEnv::from_contextual(vec![proto; N], opts, AutoresetMode::SameStep).unwrap();
    venv.reset(11);
    let mut obs = vec![0.0f32; 4];
    for (i, e) in scalar.iter_mut().enumerate() {
        e.reset_into(Some(11 + i as u64), &mut obs).unwrap();
    }
    for t in 0..450 {
        let a: Vec<f32> = (0..N).map(|i| ((t * 5 + i) % 5) as f32 - 2.0).collect();
        let step = venv.step(VecActions::Continuous(&a)).unwrap();
        let o = step.obs.to_vec();
        for (i, e) in scalar.iter_mut().enumerate() {
            let out = e.step_into(&Action::Continuous(vec![a[i]]), &mut obs).unwrap();
            if out.truncated {
                e.reset_into(None, &mut obs).unwrap();
            }
            assert_eq!(&o[i * 4..i * 4 + 4], &obs[..], "env {i} step {t}");
            assert_eq!(venv.context_info(i), Some(e.context_info()));
        }
    }
}

#[test]
fn schedules_that_leave_the_bounds_or_cannot_act_are_refused() {
    let specs = SpecSet::bundled().unwrap();
    let set = Store::new(&specs).load("pendulum/g_l_train").unwrap();
    let cases: Vec<(ContextSource, &str, &str)> = vec![
        (
            fixed(10.0),
            r#"{"g": {"kind": "linear", "to": -1, "over": 5}}"#,
            "outside the bounds",
        ),
        (
            ContextSource::Set(set),
            r#"{"g": {"kind": "sine", "amplitude": 8, "period": 10}}"#,
            "pendulum/g_l_train instance #0",
        ),
        (
            fixed(10.0),
            r#"{"gg": {"kind": "step", "at": 1, "to": 2}}"#,
            "did you mean \"g\"",
        ),
        (
            fixed(10.0),
            r#"{"g": {"kind": "random_walk", "std": 1, "low": -5, "high": 5}}"#,
            "outside the feature's bounds",
        ),
        (
            fixed(10.0),
            r#"{"g": {"kind": "sine", "amplitude": 1, "period": -3}}"#,
            "period",
        ),
    ];
    for (source, json, want) in cases {
        let e = pendulum(source, json, false).unwrap_err();
        assert!(e.contains(want), "{json}: {e}");
    }
    // With noise on the same visible feature.
    let specs = SpecSet::bundled().unwrap();
    let opts = ContextualOptions {
        schedules: vec![("g".into(), Schedule::Step { at: 1, to: 5.0 })],
        visibility: Visibility::Visible(Features::Only(vec!["g".into()])),
        noise: carl_spec::envs::contextual::ContextNoise {
            features: vec![("g".into(), carl_spec::envs::contextual::NoiseStd::Absolute(0.1))],
            ..Default::default()
        },
        ..ContextualOptions::default()
    };
    let e = ContextualEnv::new(specs.get("pendulum").unwrap(), fixed(10.0), opts).unwrap_err();
    assert!(e.to_string().contains("both scheduled and observed with noise"), "{e}");
    // A runtime that fixes its context when built (LunarLander's Box2D world).
    let opts = ContextualOptions {
        schedules: vec![("GRAVITY_Y".into(), Schedule::Step { at: 1, to: -5.0 })],
        ..ContextualOptions::default()
    };
    let ll = ContextualEnv::new(
        specs.get("lunar_lander").unwrap(),
        ContextSource::Fixed(Default::default()),
        opts,
    );
    assert!(ll.unwrap_err().to_string().contains("fixes the context"));
}
