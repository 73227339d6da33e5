//! `VecEnv` against scalar environments: same contexts, seeds and actions give bit-identical
//! observations, rewards and flags (including automatic resets), for every runtime, kernel and
//! thread count. Plus autoreset details, isolation between batches and bad input.

use carl_spec::envs::registry::{Context, REGISTRY, SpecEnv, StepCost, make};
use carl_spec::envs::rng::EnvRng;
use carl_spec::envs::vec_env::{Kernel, VecActions, VecEnv, VecEnvError, VecOptions};
use carl_spec::envs::{Action, Env, EnvError, Space};
use carl_spec::spec::SpecSet;
use carl_spec::spec::model::{EnvSpec, FeatureType, Value};

/// Context `i`: the first few float features moved away from their defaults (inside bounds).
fn context(spec: &EnvSpec, i: usize) -> Context {
    let mut c = Context::new();
    let mut changed = 0;
    for f in &spec.features {
        if changed == 3 || f.kind != FeatureType::Float || f.requires_option.is_some() {
            continue;
        }
        let Some(d) = f.default_f64() else { continue };
        let x = if d == 0.0 {
            0.01 * i as f64
        } else {
            d * (1.0 + 0.04 * (i % 5) as f64)
        };
        if f.in_bounds(x) && !f.name.contains("initial") {
            c.insert(f.name.clone(), Value::Number(x));
            changed += 1;
        }
    }
    c
}

enum Acts {
    Discrete(Vec<i64>),
    Continuous(Vec<f32>),
}

fn random_actions(space: &Space, n: usize, rng: &mut EnvRng) -> Acts {
    match space {
        Space::Discrete { n: k, .. } => Acts::Discrete((0..n).map(|_| (rng.next_u64() % *k as u64) as i64).collect()),
        // Beyond the bounds on purpose: the environments clip.
        Space::Box { .. } => Acts::Continuous(
            (0..n * space.flat_dim())
                .map(|_| (rng.next_f64() * 5.0 - 2.5) as f32)
                .collect(),
        ),
    }
}

fn bits(v: &[f32]) -> Vec<u32> {
    v.iter().map(|x| x.to_bits()).collect()
}

fn compare(id: &str, n: usize, steps: usize, opts: VecOptions) {
    let specs = SpecSet::bundled().unwrap();
    let spec = specs.get(id).unwrap();
    let contexts: Vec<Context> = (0..n).map(|i| context(spec, i)).collect();
    let mut scalar: Vec<SpecEnv> = contexts.iter().map(|c| make(spec, c).unwrap()).collect();
    let mut venv = VecEnv::new(spec, &contexts, opts).unwrap();
    let d = venv.obs_dim();
    let seed = 1234;
    let first = venv.reset(seed).to_vec();
    for (i, e) in scalar.iter_mut().enumerate() {
        let (o, _) = e.reset(Some(seed + i as u64));
        assert_eq!(bits(&o), bits(&first[i * d..(i + 1) * d]), "{id} reset env {i}");
    }
    let space = venv.action_space();
    let adim = space.flat_dim();
    let mut rng = EnvRng::from_seed(99);
    let mut obs = vec![0.0f32; d];
    let mut episodes = 0;
    for t in 0..steps {
        let acts = random_actions(&space, n, &mut rng);
        let step = match &acts {
            Acts::Discrete(a) => venv.step(VecActions::Discrete(a)),
            Acts::Continuous(a) => venv.step(VecActions::Continuous(a)),
        }
        .unwrap();
        let (vobs, vrew, vterm, vtrunc) = (
            step.obs.to_vec(),
            step.rewards.to_vec(),
            step.terminated.to_vec(),
            step.truncated.to_vec(),
        );
        for (i, e) in scalar.iter_mut().enumerate() {
            let action = match &acts {
                Acts::Discrete(a) => Action::Discrete(a[i]),
                Acts::Continuous(a) => Action::Continuous(a[i * adim..(i + 1) * adim].to_vec()),
            };
            let out = e.step_into(&action, &mut obs).unwrap();
            let ctx = format!("{id} threads={} step {t} env {i}", venv.threads());
            assert_eq!(out.reward.to_bits(), vrew[i].to_bits(), "{ctx}: reward");
            assert_eq!(out.terminated, vterm[i], "{ctx}: terminated");
            assert_eq!(out.truncated, vtrunc[i], "{ctx}: truncated");
            if out.terminated || out.truncated {
                episodes += 1;
                assert_eq!(bits(&obs), bits(venv.final_obs(i).unwrap()), "{ctx}: final obs");
                e.reset_into(None, &mut obs).unwrap();
            } else {
                assert!(venv.final_obs(i).is_none(), "{ctx}");
            }
            assert_eq!(bits(&obs), bits(&vobs[i * d..(i + 1) * d]), "{ctx}: obs");
            assert_eq!(
                e.state().iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                venv.state(i).unwrap().iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                "{ctx}: state"
            );
        }
    }
    assert!(episodes > 0, "{id}: the rollout must cover automatic resets");
}

#[test]
fn vec_env_equals_scalar_envs_for_every_runtime() {
    let specs = SpecSet::bundled().unwrap();
    for reg in REGISTRY {
        let spec = specs.get(reg.id).unwrap();
        // Long enough for the time limit to truncate (tasks without one: several episodes).
        let steps = spec.max_episode_steps.map_or(520, |m| m as usize + 10);
        // Light environments: enough of them for several work-sharing blocks across threads;
        // heavy ones (a physics world or a fold per step): a few.
        let (alone, shared) = match reg.cost {
            StepCost::Light => (5, 2 * reg.cost.min_block() + 5),
            StepCost::Heavy => (2, 3),
        };
        compare(reg.id, alone, steps, VecOptions::default());
        compare(
            reg.id,
            shared,
            steps,
            VecOptions {
                threads: 2,
                ..Default::default()
            },
        );
    }
    compare(
        "cartpole",
        50,
        600,
        VecOptions {
            threads: 3,
            kernel: Kernel::ArrayOfEnvs,
        },
    );
}

fn cartpole() -> EnvSpec {
    SpecSet::bundled().unwrap().get("cartpole").unwrap().clone()
}

#[test]
fn cartpole_uses_the_soa_kernel() {
    let spec = cartpole();
    let v = VecEnv::new(&spec, &[Context::new()], VecOptions::default()).unwrap();
    assert!(v.is_soa());
    let opts = VecOptions {
        threads: 1,
        kernel: Kernel::ArrayOfEnvs,
    };
    assert!(!VecEnv::new(&spec, &[Context::new()], opts).unwrap().is_soa());
}

#[test]
fn autoreset_is_same_step_and_keeps_the_final_observation() {
    let spec = cartpole();
    let mut v = VecEnv::new(&spec, &[Context::new(), Context::new()], VecOptions::default()).unwrap();
    v.reset(5);
    let mut scalar = make(&spec, &Context::new()).unwrap();
    scalar.reset(Some(5));
    let mut obs = [0.0f32; 4];
    // Push env 0 right until it falls over; env 1 alternates and survives.
    for t in 0.. {
        let s = v.step_discrete(&[1, t % 2]).unwrap();
        let (term, trunc, next) = (s.terminated[0], s.truncated[0], s.obs[..4].to_vec());
        assert!(!s.terminated[1]);
        let out = scalar.step_into(&Action::Discrete(1), &mut obs).unwrap();
        assert_eq!(out.terminated, term);
        if term {
            assert!(!trunc);
            assert_eq!(v.final_obs(0).unwrap(), &obs, "final obs is the terminal observation");
            assert!(v.final_obs(1).is_none());
            assert!(
                obs[2].abs() > 0.2 || obs[0].abs() > 2.4,
                "terminal state is out of bounds"
            );
            // The returned observation is already the next episode's first one.
            scalar.reset_into(None, &mut obs).unwrap();
            assert_eq!(next, obs);
            assert_eq!(v.elapsed_steps(0), Some(0));
            assert_eq!(v.rewards()[0], 1.0);
            break;
        }
        assert!(t < 500);
    }
    // The next step continues the new episode.
    let s = v.step_discrete(&[0, 0]).unwrap();
    assert!(!s.terminated[0]);
    assert!(v.final_obs(0).is_none());
    assert_eq!(v.elapsed_steps(0), Some(1));
}

#[test]
fn truncation_autoresets_too() {
    let specs = SpecSet::bundled().unwrap();
    let spec = specs.get("mountain_car").unwrap();
    let limit = spec.max_episode_steps.unwrap();
    let mut v = VecEnv::new(spec, &[Context::new()], VecOptions::default()).unwrap();
    let first = v.reset(0).to_vec();
    for t in 1..=limit {
        let s = v.step_discrete(&[1]).unwrap();
        assert_eq!(s.truncated[0], t == limit, "step {t}");
        assert!(!s.terminated[0]);
    }
    let fin = v.final_obs(0).unwrap().to_vec();
    assert_ne!(fin, v.obs());
    assert_ne!(first, v.obs(), "the new episode continues the env's random stream");
    assert_eq!(v.elapsed_steps(0), Some(0));
}

#[test]
fn batches_with_different_contexts_do_not_interfere() {
    let spec = cartpole();
    let light = vec![Context::from([("gravity".to_string(), Value::Number(5.0))]); 8];
    let heavy = vec![Context::from([("gravity".to_string(), Value::Number(15.0))]); 8];
    let run_alone = |ctx: &[Context]| {
        let mut v = VecEnv::new(&spec, ctx, VecOptions::default()).unwrap();
        v.reset(3);
        (0..100)
            .map(|t| v.step_discrete(&[t % 2; 8]).unwrap().obs.to_vec())
            .collect::<Vec<_>>()
    };
    let (alone_a, alone_b) = (run_alone(&light), run_alone(&heavy));
    assert_ne!(alone_a, alone_b);
    let opts = VecOptions {
        threads: 2,
        ..Default::default()
    };
    let mut a = VecEnv::new(&spec, &light, opts).unwrap();
    let mut b = VecEnv::new(&spec, &heavy, VecOptions::default()).unwrap();
    a.reset(3);
    b.reset(3);
    for t in 0..100 {
        assert_eq!(a.step_discrete(&[t % 2; 8]).unwrap().obs, &alone_a[t as usize][..]);
        assert_eq!(b.step_discrete(&[t % 2; 8]).unwrap().obs, &alone_b[t as usize][..]);
    }
}

#[test]
fn bad_input_is_an_error_and_moves_nothing() {
    let spec = cartpole();
    let mut v = VecEnv::new(&spec, &[Context::new(), Context::new()], VecOptions::default()).unwrap();
    assert!(matches!(v.step_discrete(&[0, 1]), Err(EnvError::NeedsReset { .. })));
    v.reset(0);
    let before = (v.state(0), v.state(1));
    assert!(matches!(
        v.step_discrete(&[0]),
        Err(EnvError::BatchLength {
            expected: 2,
            got: 1,
            ..
        })
    ));
    assert!(matches!(
        v.step_discrete(&[0, 2]),
        Err(EnvError::ActionOutOfRange { action: 2, .. })
    ));
    assert!(matches!(
        v.step_discrete(&[-1, 0]),
        Err(EnvError::ActionOutOfRange { action: -1, .. })
    ));
    assert!(matches!(
        v.step_continuous(&[0.0, 0.0]),
        Err(EnvError::ActionKind { .. })
    ));
    assert_eq!(before, (v.state(0), v.state(1)));
    assert!(v.step_discrete(&[0, 1]).is_ok());

    let specs = SpecSet::bundled().unwrap();
    let pendulum = specs.get("pendulum").unwrap();
    let mut p = VecEnv::new(pendulum, &vec![Context::new(); 3], VecOptions::default()).unwrap();
    p.reset(0);
    assert!(matches!(
        p.step_continuous(&[0.0; 2]),
        Err(EnvError::BatchLength { .. })
    ));
    assert!(matches!(p.step_discrete(&[0; 3]), Err(EnvError::ActionKind { .. })));
    assert!(p.step_continuous(&[0.0; 3]).is_ok());

    assert!(matches!(
        VecEnv::from_envs(vec![], VecOptions::default()),
        Err(VecEnvError::Empty)
    ));
    let mixed = vec![
        make(&spec, &Context::new()).unwrap(),
        make(pendulum, &Context::new()).unwrap(),
    ];
    assert!(matches!(
        VecEnv::from_envs(mixed, VecOptions::default()),
        Err(VecEnvError::Mixed { .. })
    ));
    let bad_ctx = [Context::from([("gravty".to_string(), Value::Number(1.0))])];
    assert!(matches!(
        VecEnv::new(&spec, &bad_ctx, VecOptions::default()),
        Err(VecEnvError::Make(_))
    ));
}

/// The CartPole kernel in next-step and disabled modes equals the array of environments (the
/// reference semantics) bit for bit, resets included.
#[test]
fn cartpole_kernel_runs_every_autoreset_mode_like_the_array_of_envs() {
    use carl_spec::envs::vec_env::AutoresetMode;
    let spec = cartpole();
    for mode in [
        AutoresetMode::NextStep,
        AutoresetMode::Disabled,
        AutoresetMode::SameStep,
    ] {
        let contexts: Vec<Context> = (0..40).map(|i| context(&spec, i)).collect();
        let build = |kernel| {
            let envs = contexts.iter().map(|c| make(&spec, c).unwrap()).collect();
            VecEnv::from_envs_with(envs, VecOptions { threads: 2, kernel }, mode).unwrap()
        };
        let (mut soa, mut array) = (build(Kernel::Auto), build(Kernel::ArrayOfEnvs));
        assert!(soa.is_soa() && !array.is_soa());
        assert_eq!(bits(soa.reset(7)), bits(array.reset(7)));
        let mut rng = EnvRng::from_seed(3);
        let mut ends = 0;
        for t in 0..400 {
            let a: Vec<i64> = (0..40).map(|_| (rng.next_u64() % 2) as i64).collect();
            let s = soa.step(VecActions::Discrete(&a)).unwrap();
            let (obs, rew, term, trunc) = (
                s.obs.to_vec(),
                s.rewards.to_vec(),
                s.terminated.to_vec(),
                s.truncated.to_vec(),
            );
            let r = array.step(VecActions::Discrete(&a)).unwrap();
            assert_eq!(bits(&obs), bits(r.obs), "{mode:?} step {t}: obs");
            assert_eq!(rew, r.rewards, "{mode:?} step {t}: rewards");
            assert_eq!(
                (&term[..], &trunc[..]),
                (r.terminated, r.truncated),
                "{mode:?} step {t}: flags"
            );
            assert_eq!(
                soa.pending_resets(),
                array.pending_resets(),
                "{mode:?} step {t}: pending"
            );
            let done: Vec<bool> = term.iter().zip(&trunc).map(|(a, b)| *a || *b).collect();
            ends += done.iter().filter(|d| **d).count();
            if mode == AutoresetMode::Disabled && done.iter().any(|d| *d) {
                let (x, y) = (
                    soa.reset_masked(None, Some(&done)).to_vec(),
                    array.reset_masked(None, Some(&done)),
                );
                assert_eq!(bits(&x), bits(y), "{mode:?} step {t}: masked reset");
            }
        }
        assert!(ends > 20, "{mode:?}: the rollout must cover resets ({ends})");
    }
}

/// Float64 spaces (the robots) carry float64 values through the batch, and the float32 buffer
/// is their rounding. (Humanoid: its centre-of-mass terms are computed in float64; positions and
/// velocities come from rapier's float32 world.)
#[test]
fn float64_observations_reach_the_batch_unrounded() {
    use carl_spec::envs::DType;
    use carl_spec::envs::vec_env::AutoresetMode;
    let specs = SpecSet::bundled().unwrap();
    let spec = specs.get("humanoid").unwrap();
    assert!(matches!(
        make(spec, &Context::new()).unwrap().observation_space(),
        Space::Box {
            dtype: DType::Float64,
            ..
        }
    ));
    let envs = (0..3).map(|_| make(spec, &Context::new()).unwrap()).collect();
    let mut v = VecEnv::from_envs_with(envs, VecOptions::default(), AutoresetMode::SameStep).unwrap();
    let mut scalar = make(spec, &Context::new()).unwrap();
    v.reset(11);
    scalar.reset(Some(11));
    let d = v.obs_dim();
    let mut wide = vec![0.0f64; d];
    let adim = v.action_space().flat_dim();
    let mut rng = EnvRng::from_seed(5);
    let mut unrounded = 0;
    for t in 0..5 {
        let a: Vec<f32> = (0..3 * adim).map(|_| (rng.next_f64() * 0.8 - 0.4) as f32).collect();
        v.step(VecActions::Continuous(&a)).unwrap();
        let mut o32 = vec![0.0f32; d];
        scalar
            .step_into(&Action::Continuous(a[..adim].to_vec()), &mut o32)
            .unwrap();
        scalar.observe_f64_into(&mut wide).unwrap();
        let row = &v.obs_f64().unwrap()[..d];
        assert_eq!(row, &wide[..], "step {t}: float64 row of env 0");
        assert_eq!(bits(&v.obs()[..d]), bits(&o32), "step {t}: float32 row of env 0");
        for (w, n) in row.iter().zip(&v.obs()[..d]) {
            assert_eq!(*w as f32, *n, "step {t}: float32 is the rounding of float64");
            unrounded += usize::from(f64::from(*n) != *w);
        }
    }
    assert!(unrounded > 0, "some components must need more than float32 precision");
    let cartpole = VecEnv::new(&cartpole(), &[Context::new()], VecOptions::default()).unwrap();
    assert!(cartpole.obs_f64().is_none(), "float32 spaces keep one buffer");
}
