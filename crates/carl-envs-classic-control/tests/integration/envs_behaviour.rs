//! Behaviour of the classic-control environments that the benchmark relies on.

use carl_env::api::{Action, Env, EnvError, Space, TimeLimit};
use carl_envs_classic_control::{
    Acrobot, AcrobotParams, CartPole, CartPoleParams, MountainCar, MountainCarContinuous, MountainCarParams, Pendulum,
    PendulumParams,
};

fn rollout(env: &mut dyn Env, seed: u64, actions: &[Action]) -> Vec<(Vec<u32>, u64, bool, bool)> {
    env.reset(Some(seed));
    actions
        .iter()
        .map(|a| {
            let s = env.step(a).unwrap();
            (
                s.obs.iter().map(|x| x.to_bits()).collect(),
                s.reward.to_bits(),
                s.terminated,
                s.truncated,
            )
        })
        .collect()
}

fn cartpole_actions(n: usize) -> Vec<Action> {
    (0..n).map(|i| Action::Discrete(((i * 7) % 3 == 0) as i64)).collect()
}

#[test]
fn contexts_are_isolated_when_interleaved() {
    let ctx_a = CartPoleParams::default();
    let mut ctx_b = CartPoleParams::default();
    ctx_b.set("masscart", 3.0).unwrap();
    ctx_b.set("length", 0.9).unwrap();
    let actions = cartpole_actions(60);

    let alone_a = rollout(&mut CartPole::new(ctx_a), 7, &actions);
    let alone_b = rollout(&mut CartPole::new(ctx_b), 7, &actions);

    let (mut a, mut b) = (CartPole::new(ctx_a), CartPole::new(ctx_b));
    a.reset(Some(7));
    b.reset(Some(7));
    let mut inter_a = Vec::new();
    let mut inter_b = Vec::new();
    for act in &actions {
        for (env, out) in [(&mut a, &mut inter_a), (&mut b, &mut inter_b)] {
            let s = env.step(act).unwrap();
            out.push((
                s.obs.iter().map(|x| x.to_bits()).collect(),
                s.reward.to_bits(),
                s.terminated,
                s.truncated,
            ));
        }
    }
    assert_eq!(alone_a, inter_a);
    assert_eq!(alone_b, inter_b);
    assert_ne!(alone_a, alone_b);
}

#[test]
fn masscart_changes_the_cartpole_trajectory() {
    // carl-bench 1.1.1 never recomputes total_mass, so masscart has no effect there.
    let actions = cartpole_actions(20);
    let base = rollout(&mut CartPole::default(), 3, &actions);
    for m in [0.5, 2.0, 9.0] {
        let mut p = CartPoleParams::default();
        p.set("masscart", m).unwrap();
        assert_eq!(p.total_mass(), 0.1 + m);
        let other = rollout(&mut CartPole::new(p), 3, &actions);
        assert_ne!(base, other, "masscart={m} had no effect");
    }
    // Changing the context of a live env takes effect immediately, derived values included.
    let mut env = CartPole::default();
    env.set_state(&[0.0, 0.0, 0.05, 0.0]).unwrap();
    let s1 = env.step(&Action::Discrete(1)).unwrap();
    env.set_state(&[0.0, 0.0, 0.05, 0.0]).unwrap();
    env.params_mut().masscart = 5.0;
    let s2 = env.step(&Action::Discrete(1)).unwrap();
    assert_ne!(s1.obs, s2.obs);
}

#[test]
fn seeded_reset_is_reproducible_and_unseeded_continues_the_stream() {
    let envs: Vec<Box<dyn Fn() -> Box<dyn Env>>> = vec![
        Box::new(|| Box::new(CartPole::default())),
        Box::new(|| Box::new(Pendulum::default())),
        Box::new(|| Box::new(MountainCar::default())),
        Box::new(|| Box::new(MountainCarContinuous::default())),
        Box::new(|| Box::new(Acrobot::default())),
    ];
    for make in envs {
        let mut e1 = make();
        let mut e2 = make();
        let (o1, _) = e1.reset(Some(123));
        let (o2, _) = e2.reset(Some(123));
        assert_eq!(o1, o2, "{}", e1.id());
        let (n1, _) = e1.reset(None);
        let (n2, _) = e2.reset(None);
        assert_eq!(n1, n2, "{}: unseeded resets continue identical streams", e1.id());
        assert_ne!(o1, n1, "{}: unseeded reset repeated the seeded state", e1.id());
        let (r, _) = e1.reset(Some(123));
        assert_eq!(r, o1, "{}: reseeding restarts the stream", e1.id());
        let (other, _) = e1.reset(Some(124));
        assert_ne!(other, o1, "{}", e1.id());
    }
}

#[test]
fn reset_distributions_follow_the_context() {
    let mut env = CartPole::default();
    for seed in 0..200 {
        let (obs, _) = env.reset(Some(seed));
        assert!(obs.iter().all(|x| (-0.05..=0.05).contains(x)), "{obs:?}");
    }
    let mut p = MountainCarParams::default();
    p.set("start_position", -0.3).unwrap();
    p.set("start_position_std", 0.05).unwrap();
    p.set("start_velocity", 0.01).unwrap();
    let mut mc = MountainCar::new(p);
    for seed in 0..200 {
        mc.reset(Some(seed));
        let s = mc.state();
        assert!((-0.35..-0.25).contains(&s[0]) && s[1] == 0.01, "{s:?}");
    }
    // Defaults reproduce Gymnasium's U(-0.6, -0.4), velocity 0.
    let mut mc = MountainCar::default();
    for seed in 0..200 {
        mc.reset(Some(seed));
        let s = mc.state();
        assert!((-0.6..-0.4).contains(&s[0]) && s[1] == 0.0, "{s:?}");
    }
    // Acrobot, like Gymnasium, rounds its initial state to float32.
    let mut ac = Acrobot::default();
    ac.reset(Some(5));
    assert!(ac.state().iter().all(|x| (*x as f32) as f64 == *x));
}

#[test]
fn bad_actions_are_errors_not_panics() {
    let mut cp = CartPole::default();
    assert_eq!(
        cp.step(&Action::Discrete(0)).unwrap_err(),
        EnvError::NeedsReset { env: "cartpole" }
    );
    cp.reset(Some(0));
    for a in [2, 3, -1, i64::MAX, i64::MIN] {
        assert!(
            matches!(cp.step(&Action::Discrete(a)), Err(EnvError::ActionOutOfRange { .. })),
            "{a}"
        );
    }
    assert!(matches!(
        cp.step(&Action::Continuous(vec![0.0])),
        Err(EnvError::ActionKind { .. })
    ));
    let mut ac = Acrobot::default();
    ac.reset(None);
    assert!(matches!(
        ac.step(&Action::Discrete(3)),
        Err(EnvError::ActionOutOfRange { n: 3, .. })
    ));
    let mut mc = MountainCar::default();
    mc.reset(None);
    assert!(mc.step(&Action::Discrete(3)).is_err());

    let mut pe = Pendulum::default();
    pe.reset(None);
    assert!(matches!(
        pe.step(&Action::Continuous(vec![])),
        Err(EnvError::ActionLength { .. })
    ));
    assert!(matches!(
        pe.step(&Action::Continuous(vec![1.0, 2.0])),
        Err(EnvError::ActionLength { .. })
    ));
    assert!(matches!(
        pe.step(&Action::Discrete(1)),
        Err(EnvError::ActionKind { .. })
    ));
    // Out-of-range torques are clipped like Gymnasium does, not rejected.
    pe.set_state(&[0.5, 0.0]).unwrap();
    let big = pe.step(&Action::Continuous(vec![100.0])).unwrap();
    pe.set_state(&[0.5, 0.0]).unwrap();
    let max = pe.step(&Action::Continuous(vec![2.0])).unwrap();
    assert_eq!(big.obs, max.obs);

    let mut mcc = MountainCarContinuous::default();
    mcc.reset(None);
    assert!(matches!(
        mcc.step(&Action::Continuous(vec![f32::NAN])),
        Err(EnvError::ActionNotFinite { index: 0, .. })
    ));
    let err = mcc
        .step(&Action::Continuous(vec![f32::INFINITY]))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("mountain_car_continuous: action component 0 is not finite"),
        "{err}"
    );
    let mut buf = [0.0f32; 5];
    assert!(matches!(
        mcc.step_into(&Action::Continuous(vec![0.0]), &mut buf),
        Err(EnvError::ObsBufferLength { .. })
    ));
}

#[test]
fn bad_states_and_features_are_errors() {
    let mut cp = CartPole::default();
    assert!(matches!(
        cp.set_state(&[0.0; 3]),
        Err(EnvError::StateLength {
            expected: 4,
            got: 3,
            ..
        })
    ));
    assert!(matches!(
        cp.set_state(&[0.0, f64::NAN, 0.0, 0.0]),
        Err(EnvError::StateNotFinite { index: 1, .. })
    ));
    let mut p = CartPoleParams::default();
    let err = p.set("mass_cart", 1.0).unwrap_err();
    assert_eq!(err.name, "mass_cart");
    assert!(err.to_string().contains("masscart"));
    let mut a = AcrobotParams::default();
    a.set("LINK_MASS_2", 2.0).unwrap();
    assert_eq!(a.get("link_mass_2").unwrap(), 2.0);
    assert!(PendulumParams::default().get("gravity").is_err());
}

#[test]
fn feature_tables_are_consistent() {
    fn check(features: &[&str], aliases: &[(&str, &str)], get: &dyn Fn(&str) -> Option<f64>) {
        for f in features {
            assert!(get(f).is_some(), "{f}");
        }
        for (alias, canon) in aliases {
            assert!(features.contains(canon));
            assert_eq!(get(alias), get(canon));
        }
    }
    let cp = CartPoleParams::default();
    check(CartPoleParams::FEATURES, CartPoleParams::ALIASES, &|n| cp.get(n).ok());
    assert_eq!(
        CartPoleParams::FEATURES,
        &[
            "gravity",
            "masscart",
            "masspole",
            "pole_length",
            "force_magnifier",
            "update_interval",
            "initial_state_lower",
            "initial_state_upper"
        ]
    );
    let ac = AcrobotParams::default();
    check(AcrobotParams::FEATURES, AcrobotParams::ALIASES, &|n| ac.get(n).ok());
    assert_eq!(ac.get("MAX_VEL_1").unwrap(), 4.0 * std::f64::consts::PI);
    let pe = PendulumParams::default();
    check(PendulumParams::FEATURES, PendulumParams::ALIASES, &|n| pe.get(n).ok());
    let mc = MountainCarParams::default();
    check(MountainCarParams::FEATURES, MountainCarParams::ALIASES, &|n| {
        mc.get(n).ok()
    });
    assert_eq!(mc.start_position - mc.start_position_std, -0.6);
    assert_eq!(mc.start_position + mc.start_position_std, -0.4);
}

#[test]
fn time_limit_truncates_and_resets_its_counter() {
    let mut env = TimeLimit::new(Pendulum::default(), Some(3));
    env.reset(Some(1));
    let flags: Vec<bool> = (0..4)
        .map(|_| env.step(&Action::Continuous(vec![0.0])).unwrap().truncated)
        .collect();
    assert_eq!(flags, [false, false, true, true]);
    env.reset(None);
    assert!(!env.step(&Action::Continuous(vec![0.0])).unwrap().truncated);
    assert_eq!(env.elapsed_steps(), 1);
}

#[test]
fn spaces_reflect_the_context() {
    let mut p = PendulumParams::default();
    p.set("max_torque", 3.0).unwrap();
    let env = Pendulum::new(p);
    assert_eq!(
        env.action_space(),
        Space::Box {
            low: vec![-3.0],
            high: vec![3.0],
            shape: vec![1],
            dtype: carl_env::api::DType::Float32
        }
    );
    assert!(env.action_space().contains(&Action::Continuous(vec![2.5])));
    assert!(!env.action_space().contains(&Action::Continuous(vec![3.5])));
    assert_eq!(CartPole::default().action_space(), Space::Discrete { n: 2, start: 0 });
    assert_eq!(Acrobot::default().observation_space().flat_dim(), 6);
}

#[test]
fn cartpole_reward_after_termination_is_zero() {
    let mut env = CartPole::default();
    env.set_state(&[2.39, 1.0, 0.0, 0.0]).unwrap();
    let first = env.step(&Action::Discrete(1)).unwrap();
    assert!(first.terminated);
    assert_eq!(first.reward, 1.0);
    let after = env.step(&Action::Discrete(1)).unwrap();
    assert!(after.terminated);
    assert_eq!(after.reward, 0.0);
}
