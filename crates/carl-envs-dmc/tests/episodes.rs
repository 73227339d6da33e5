//! What every environment of the family shares through [`carl_envs_dmc::physics::Physics`]:
//! a seeded reset replays its episode whatever came before it (each reset starts from
//! `Data::reset`, the constraint solver cold), and a step before the first reset is an error.

use carl_env::api::{Action, Env, EnvError, Space};
use carl_env::context::{EnvOptions, resolve_options};
use carl_env::runtime::AnyEnv;
use carl_envs_dmc::REGISTRATIONS;

fn make(id: &str) -> AnyEnv {
    let reg = REGISTRATIONS.iter().find(|r| r.id == id).unwrap();
    let options = resolve_options(id, reg.options, &EnvOptions::new()).unwrap();
    (reg.build)(&[], &options).unwrap_or_else(|e| panic!("{id}: {e}"))
}

/// A constant action inside the action space, off its centre.
fn action(env: &AnyEnv) -> Action {
    let Space::Box { low, high, .. } = env.action_space() else {
        panic!("{}: not a box action space", env.id())
    };
    Action::Continuous(low.iter().zip(&high).map(|(l, h)| l + 0.65 * (h - l)).collect())
}

/// The states, `f64` observations and rewards of `steps` steps after a reset with `seed`.
fn episode(env: &mut AnyEnv, seed: u64, steps: usize) -> Vec<(Vec<f64>, Vec<f64>, f64)> {
    let a = action(env);
    env.reset(Some(seed));
    let mut out = Vec::with_capacity(steps + 1);
    let mut record = |env: &AnyEnv, reward: f64| {
        let mut obs = vec![0.0; env.obs_dim()];
        env.observe_f64_into(&mut obs).unwrap();
        out.push((env.state(), obs, reward));
    };
    record(env, 0.0);
    for _ in 0..steps {
        let r = env.step(&a).unwrap().reward;
        record(env, r);
    }
    out
}

/// Long enough for the falling bodies (walker, quadruped) to land: contacts and their solves.
const STEPS: usize = 60;

#[test]
fn a_seeded_reset_replays_its_episode_after_another() {
    for reg in REGISTRATIONS {
        let mut fresh = make(reg.id);
        let expected = episode(&mut fresh, 123, STEPS);
        let mut used = make(reg.id);
        episode(&mut used, 7, STEPS);
        let replayed = episode(&mut used, 123, STEPS);
        assert!(
            expected == replayed,
            "{}: the seeded episode changed after another",
            reg.id
        );
        // And once more after the same episode.
        let again = episode(&mut used, 123, STEPS);
        assert!(expected == again, "{}: the seeded episode changed after itself", reg.id);
    }
}

#[test]
fn a_step_before_the_first_reset_is_an_error() {
    for reg in REGISTRATIONS {
        let mut env = make(reg.id);
        let a = action(&env);
        let e = env.step(&a).unwrap_err();
        assert!(matches!(e, EnvError::NeedsReset { .. }), "{}: {e:?}", reg.id);
        // A wrong state length is an error too, never a panic.
        let n = env.state_dim();
        assert!(
            matches!(env.set_state(&vec![0.0; n + 1]), Err(EnvError::StateLength { .. })),
            "{}",
            reg.id
        );
    }
}
