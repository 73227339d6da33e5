//! `VecEnv`'s next-step and disabled autoreset modes and its contextual batches, against scalar
//! environments stepped by hand with Gymnasium 1.x's rules.

use carl_spec::envs::contextual::{ContextSource, ContextualEnv, ContextualOptions, Selection, Visibility};
use carl_spec::envs::registry::{Context, SpecEnv, make};
use carl_spec::envs::vec_env::{AutoresetMode, VecActions, VecEnv, VecOptions};
use carl_spec::envs::{Action, Env, EnvError};
use carl_spec::instances::Store;
use carl_spec::spec::SpecSet;

const N: usize = 3;

fn cartpoles(specs: &SpecSet) -> Vec<SpecEnv> {
    let spec = specs.get("cartpole").unwrap();
    (0..N).map(|_| make(spec, &Context::new()).unwrap()).collect()
}

/// Next-step: the step after an episode ends resets that environment (its action ignored) and
/// reports reward 0 and no flags; the ending step reports the episode's last observation.
#[test]
fn next_step_mode_follows_gymnasium() {
    let specs = SpecSet::bundled().unwrap();
    let mut scalar = cartpoles(&specs);
    let mut venv = VecEnv::from_envs_with(cartpoles(&specs), VecOptions::default(), AutoresetMode::NextStep).unwrap();
    assert!(
        venv.is_soa(),
        "the CartPole kernel runs next-step mode too (checked here against scalar envs)"
    );
    venv.reset(7);
    let mut pending = [false; N];
    let mut obs = vec![0.0f32; 4];
    for (i, e) in scalar.iter_mut().enumerate() {
        e.reset_into(Some(7 + i as u64), &mut obs).unwrap();
        assert_eq!(&venv.obs()[i * 4..i * 4 + 4], &obs[..]);
    }
    let mut finished = 0;
    for t in 0..400 {
        let actions: Vec<i64> = (0..N).map(|i| ((t + i) % 2) as i64).collect();
        let step = venv.step(VecActions::Discrete(&actions)).unwrap();
        let (o, r, te, tr) = (
            step.obs.to_vec(),
            step.rewards.to_vec(),
            step.terminated.to_vec(),
            step.truncated.to_vec(),
        );
        for i in 0..N {
            if pending[i] {
                scalar[i].reset_into(None, &mut obs).unwrap();
                assert_eq!((r[i], te[i], tr[i]), (0.0, false, false));
                pending[i] = false;
            } else {
                let out = scalar[i].step_into(&Action::Discrete(actions[i]), &mut obs).unwrap();
                assert_eq!((r[i], te[i], tr[i]), (out.reward, out.terminated, out.truncated));
                if out.terminated || out.truncated {
                    pending[i] = true;
                    finished += 1;
                    assert!(venv.final_obs(i).is_none());
                }
            }
            assert_eq!(&o[i * 4..i * 4 + 4], &obs[..], "env {i} step {t}");
        }
        assert_eq!(venv.pending_resets(), &pending[..]);
    }
    assert!(finished > N);
}

/// Disabled: nothing resets by itself, stepping a finished environment is refused before anything
/// moves, and a masked reset resets only the chosen environments (seeded `seed + i`).
#[test]
fn disabled_mode_needs_masked_resets() {
    let specs = SpecSet::bundled().unwrap();
    let mut venv = VecEnv::from_envs_with(cartpoles(&specs), VecOptions::default(), AutoresetMode::Disabled).unwrap();
    venv.reset(0);
    let mut done_at = None;
    for t in 0..500 {
        let step = venv.step(VecActions::Discrete(&[1, 1, 1])).unwrap();
        if step.terminated.iter().any(|&x| x) {
            done_at = Some(t);
            break;
        }
    }
    assert!(done_at.is_some());
    let before = venv.obs().to_vec();
    let err = venv.step(VecActions::Discrete(&[1, 1, 1])).unwrap_err();
    assert!(matches!(err, EnvError::EpisodeOver { index: 0, .. }), "{err}");
    assert_eq!(venv.obs(), &before[..], "a refused step moves nothing");
    let mask = [true, false, true];
    venv.reset_masked(Some(100), Some(&mask));
    let spec = specs.get("cartpole").unwrap();
    let mut e = make(spec, &Context::new()).unwrap();
    let mut obs = vec![0.0f32; 4];
    e.reset_into(Some(102), &mut obs).unwrap();
    assert_eq!(&venv.obs()[8..12], &obs[..]);
    assert_eq!(&venv.obs()[4..8], &before[4..8]);
    assert_eq!(venv.pending_resets(), &[false, false, false]);
    venv.step(VecActions::Discrete(&[0, 0, 0])).unwrap();
}

/// A contextual batch equals its contextual environments stepped one by one (same-step), and
/// re-selects each environment's instance at every automatic reset.
#[test]
fn contextual_batch_equals_scalar_contextual_envs() {
    let specs = SpecSet::bundled().unwrap();
    let spec = specs.get("pendulum").unwrap();
    let set = Store::new(&specs).load("pendulum/q1_g_sigma_0_5").unwrap();
    let opts = ContextualOptions {
        selection: Selection::Random,
        visibility: Visibility::Hidden,
        ..ContextualOptions::default()
    };
    let proto = ContextualEnv::new(spec, ContextSource::Set(set), opts).unwrap();
    let mut scalar = vec![proto.clone(); N];
    let threads = VecOptions {
        threads: 2,
        ..VecOptions::default()
    };
    let mut venv = VecEnv::from_contextual(vec![proto; N], threads, AutoresetMode::SameStep).unwrap();
    venv.reset(5);
    let mut obs = vec![0.0f32; 3];
    for (i, e) in scalar.iter_mut().enumerate() {
        e.reset_into(Some(5 + i as u64), &mut obs).unwrap();
        assert_eq!(&venv.obs()[i * 3..i * 3 + 3], &obs[..]);
        assert_eq!(venv.instance_ids()[i], e.context_info().instance_id.unwrap() as i64);
    }
    let mut seen = std::collections::BTreeSet::new();
    for t in 0..650 {
        let a: Vec<f32> = (0..N).map(|i| ((t * 7 + i * 3) % 5) as f32 - 2.0).collect();
        let step = venv.step(VecActions::Continuous(&a)).unwrap();
        let (o, r, tr) = (step.obs.to_vec(), step.rewards.to_vec(), step.truncated.to_vec());
        for (i, e) in scalar.iter_mut().enumerate() {
            let out = e.step_into(&Action::Continuous(vec![a[i]]), &mut obs).unwrap();
            assert_eq!((r[i], tr[i]), (out.reward, out.truncated));
            if out.truncated {
                assert_eq!(venv.final_obs(i).unwrap(), &obs[..]);
                // The batch already reset: it still reports the finished episode's context.
                let finished = e.context_info().clone();
                assert_eq!(venv.final_context_info(i).as_ref(), Some(&finished));
                e.reset_into(None, &mut obs).unwrap();
                assert_eq!(e.previous_context_info(), Some(finished));
            }
            assert_eq!(&o[i * 3..i * 3 + 3], &obs[..]);
            assert_eq!(venv.instance_ids()[i], e.context_info().instance_id.unwrap() as i64);
            seen.insert(venv.instance_ids()[i]);
        }
    }
    assert!(seen.len() > N, "instances are re-selected at autoreset: {seen:?}");
    assert_eq!(
        venv.context_info(0).unwrap().instance_id,
        scalar[0].context_info().instance_id
    );
}

/// A distribution draws a new context at every reset: the finished episode's draw stays
/// reportable after the automatic reset replaced it.
#[test]
fn final_context_of_a_distribution_is_the_finished_draw() {
    let specs = SpecSet::bundled().unwrap();
    let spec = specs.get("pendulum").unwrap();
    let source = ContextSource::Distribution {
        name: "q1_g_sigma_0_5".into(),
    };
    let proto = ContextualEnv::new(spec, source, ContextualOptions::default()).unwrap();
    let mut venv = VecEnv::from_contextual(vec![proto; 2], VecOptions::default(), AutoresetMode::SameStep).unwrap();
    venv.reset(3);
    let before: Vec<_> = (0..2).map(|i| venv.context_info(i).unwrap().clone()).collect();
    assert!(venv.final_context_info(0).is_none(), "no episode has ended yet");
    for _ in 0..200 {
        venv.step(VecActions::Continuous(&[0.5, -0.5])).unwrap();
    }
    // Pendulum truncates at 200 steps: both reset in this step, each to a fresh draw.
    assert!(venv.truncated().iter().all(|t| *t));
    for (i, old) in before.iter().enumerate() {
        let new = venv.context_info(i).unwrap();
        assert_ne!(new.context_seed, old.context_seed);
        assert_eq!(venv.final_context_info(i).as_ref(), Some(old));
    }
}

/// `step_with`: the caller's closure runs once per step, while the batch is stepped, whether it
/// takes its share of the blocks, leaves them all to the pool (the rest is claimed after it
/// returns) or runs on a single thread; the results are those of `step`, bit for bit. Blocks are
/// left for workers only while a worker could claim them.
#[test]
fn step_with_runs_the_caller_once_and_steps_every_environment() {
    let specs = SpecSet::bundled().unwrap();
    let spec = specs.get("lunar_lander").unwrap();
    let n = 24;
    let batch = |threads: usize| {
        let envs: Vec<SpecEnv> = (0..n).map(|_| make(spec, &Context::new()).unwrap()).collect();
        let mut v = VecEnv::from_envs_with(
            envs,
            VecOptions {
                threads,
                ..VecOptions::default()
            },
            AutoresetMode::SameStep,
        )
        .unwrap();
        v.reset(3);
        v
    };
    let mut plain = batch(2);
    let mut claiming = batch(2);
    let mut leaving = batch(2);
    let mut single = batch(1);
    let (mut calls, mut ended) = (0, 0);
    for t in 0..300 {
        let actions: Vec<i64> = (0..n).map(|i| ((t * 7 + i) % 4) as i64).collect();
        let a = VecActions::Discrete(&actions);
        let want = plain.step(a).unwrap();
        let want = (
            want.obs.to_vec(),
            want.rewards.to_vec(),
            want.terminated.to_vec(),
            want.truncated.to_vec(),
        );
        ended += want.2.iter().chain(&want.3).filter(|&&x| x).count();
        for (venv, claim) in [(&mut claiming, true), (&mut leaving, false), (&mut single, true)] {
            let single_thread = venv.threads() == 1;
            let got = venv
                .step_with(a, |share| {
                    calls += 1;
                    // No worker can take blocks on one thread, nor any after the caller took all.
                    assert!(!single_thread || !share.blocks_left());
                    if claim {
                        share.claim_all();
                        assert!(!share.blocks_left());
                    }
                })
                .unwrap();
            let got = (
                got.obs.to_vec(),
                got.rewards.to_vec(),
                got.terminated.to_vec(),
                got.truncated.to_vec(),
            );
            assert_eq!(got, want, "step {t}");
        }
    }
    assert_eq!(calls, 3 * 300);
    assert!(ended > 0, "episodes ended (autoresets were compared too)");
    // Refused actions: the closure is not called.
    let bad = vec![0i64; n - 1];
    assert!(
        claiming
            .step_with(VecActions::Discrete(&bad), |_| panic!("called"))
            .is_err()
    );
}
