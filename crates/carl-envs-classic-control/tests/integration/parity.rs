//! Bit-exact parity with Gymnasium 1.4: replays the fixtures written by
//! `scripts/gen_parity_fixtures.py` (real Gymnasium + NumPy) and compares every float32
//! observation bit pattern, every float64 reward exactly, the terminated/truncated flags, and
//! the float64 internal state bit-for-bit at the recorded checkpoints (every 10th step and the
//! last step of each episode).

use std::path::PathBuf;

use carl_env::api::{Action, Env, TimeLimit};
use carl_envs_classic_control::{
    Acrobot, AcrobotParams, CartPole, CartPoleParams, Dynamics, MountainCar, MountainCarContinuous,
    MountainCarContinuousParams, MountainCarParams, Pendulum, PendulumParams,
};
use serde_json::Value;

fn load(name: &str) -> Value {
    let path: PathBuf = [
        env!("CARGO_MANIFEST_DIR"),
        "tests",
        "fixtures",
        "parity",
        &format!("{name}.json"),
    ]
    .iter()
    .collect();
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap()
}

fn context(ep: &Value) -> Vec<(String, f64)> {
    ep["context"]
        .as_object()
        .unwrap()
        .iter()
        .map(|(k, v)| (k.clone(), v.as_f64().unwrap()))
        .collect()
}

fn f64s(v: &Value) -> Vec<f64> {
    v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()
}

fn bits(v: &Value) -> Vec<u32> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_u64().unwrap() as u32)
        .collect()
}

/// Builds the environment for one episode from its context and options.
fn build(name: &str, ep: &Value) -> Box<dyn Env> {
    let ctx = context(ep);
    macro_rules! with_ctx {
        ($params:ty) => {{
            let mut p = <$params>::default();
            for (k, v) in &ctx {
                p.set(k, *v).unwrap();
            }
            p
        }};
    }
    match name {
        "cartpole" => Box::new(CartPole::new(with_ctx!(CartPoleParams))),
        "pendulum" => Box::new(Pendulum::new(with_ctx!(PendulumParams))),
        "mountain_car" => Box::new(MountainCar::new(with_ctx!(MountainCarParams))),
        "mountain_car_continuous" => Box::new(MountainCarContinuous::new(with_ctx!(MountainCarContinuousParams))),
        "acrobot" => {
            let mut p = with_ctx!(AcrobotParams);
            if ep["options"]["dynamics"].as_str() == Some("nips") {
                p.dynamics = Dynamics::Nips;
            }
            Box::new(Acrobot::new(p))
        }
        _ => panic!("unknown env {name}"),
    }
}

fn replay(name: &str) {
    let doc = load(name);
    assert_eq!(doc["env"], name);
    let continuous = matches!(name, "pendulum" | "mountain_car_continuous");
    let mut total_steps = 0;
    for ep in doc["episodes"].as_array().unwrap() {
        let ep_name = ep["name"].as_str().unwrap();
        let max_steps = ep["max_episode_steps"].as_u64().unwrap();
        let mut env = TimeLimit::new(build(name, ep), Some(max_steps));
        // A seeded reset first (as the generator does), then the recorded initial state.
        env.reset(Some(0));
        env.set_state(&f64s(&ep["initial_state"])).unwrap();
        let init: Vec<u32> = env.observe().iter().map(|x| x.to_bits()).collect();
        assert_eq!(init, bits(&ep["initial_obs_bits"]), "{name}/{ep_name}: initial obs");

        let actions = ep["actions"].as_array().unwrap();
        let obs = ep["obs_bits"].as_array().unwrap();
        let rewards = f64s(&ep["rewards"]);
        let terms = ep["terminated"].as_array().unwrap();
        let truncs = ep["truncated"].as_array().unwrap();
        let mut checkpoints = ep["state_checkpoints"].as_array().unwrap().iter().peekable();
        let mut buf = vec![0.0f32; env.obs_dim()];
        for (t, a) in actions.iter().enumerate() {
            let action = if continuous {
                Action::Continuous(vec![f32::from_bits(a.as_u64().unwrap() as u32)])
            } else {
                Action::Discrete(a.as_i64().unwrap())
            };
            let out = env.step_into(&action, &mut buf).unwrap();
            let got: Vec<u32> = buf.iter().map(|x| x.to_bits()).collect();
            let want = bits(&obs[t]);
            assert_eq!(
                got,
                want,
                "{name}/{ep_name} step {t}: obs {:?} != gymnasium {:?} (state {:?})",
                buf,
                want.iter().map(|b| f32::from_bits(*b)).collect::<Vec<_>>(),
                env.state()
            );
            assert_eq!(
                out.reward.to_bits(),
                rewards[t].to_bits(),
                "{name}/{ep_name} step {t}: reward {} != {}",
                out.reward,
                rewards[t]
            );
            assert_eq!(
                out.terminated,
                terms[t].as_bool().unwrap(),
                "{name}/{ep_name} step {t}: terminated"
            );
            assert_eq!(
                out.truncated,
                truncs[t].as_bool().unwrap(),
                "{name}/{ep_name} step {t}: truncated"
            );
            if let Some(cp) = checkpoints.next_if(|cp| cp[0].as_u64() == Some(t as u64)) {
                let want = f64s(&cp[1]);
                let got = env.state();
                assert_eq!(
                    got.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                    want.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                    "{name}/{ep_name} step {t}: float64 state {got:?} != gymnasium {want:?}"
                );
            }
            total_steps += 1;
        }
        assert!(
            checkpoints.next().is_none(),
            "{name}/{ep_name}: unused state checkpoints"
        );
    }
    assert!(total_steps >= 800, "{name}: fixture too small ({total_steps} steps)");
}

#[test]
fn cartpole_matches_gymnasium() {
    replay("cartpole");
}

#[test]
fn pendulum_matches_gymnasium() {
    replay("pendulum");
}

#[test]
fn mountain_car_matches_gymnasium() {
    replay("mountain_car");
}

#[test]
fn mountain_car_continuous_matches_gymnasium() {
    replay("mountain_car_continuous");
}

#[test]
fn acrobot_matches_gymnasium() {
    replay("acrobot");
}

#[test]
fn fixtures_record_versions() {
    for name in [
        "cartpole",
        "pendulum",
        "mountain_car",
        "mountain_car_continuous",
        "acrobot",
    ] {
        let doc = load(name);
        assert!(doc["gymnasium_version"].as_str().unwrap().starts_with("1.4"), "{name}");
        assert!(doc["numpy_version"].as_str().is_some(), "{name}");
    }
}
