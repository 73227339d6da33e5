//! UR5e reach task on rapier3d: target placement, joint torque direction, gravity sag,
//! independence of instances, robustness at the spec bounds, Brax's reward, audit, rendering.

use crate::common;

use carl_spec::envs::brax::reach::{HOME, TARGET_HEIGHT};
use carl_spec::envs::registry::{Context, SpecEnv, make};
use carl_spec::envs::rng::EnvRng;
use carl_spec::envs::{Action, Env};
use carl_spec::spec::SpecSet;
use carl_spec::spec::model::{EnvSpec, Value};

fn spec() -> EnvSpec {
    SpecSet::bundled().unwrap().get("ur5e").unwrap().clone()
}

fn env_with(ctx: &[(&str, f64)]) -> SpecEnv {
    let ctx: Context = ctx.iter().map(|(k, v)| (k.to_string(), Value::Number(*v))).collect();
    make(&spec(), &ctx).unwrap()
}

fn random_actions(steps: usize, seed: u64) -> Vec<Action> {
    let mut rng = EnvRng::from_seed(seed);
    (0..steps)
        .map(|_| Action::Continuous((0..6).map(|_| (rng.next_f64() * 2.0 - 1.0) as f32).collect()))
        .collect()
}

fn action(a: [f32; 6]) -> Action {
    Action::Continuous(a.to_vec())
}

/// State: joints (6), joint velocities (6), target (3).
fn state(joints: [f64; 6], target: [f64; 3]) -> Vec<f64> {
    let mut s = joints.to_vec();
    s.extend([0.0; 6]);
    s.extend(target);
    s
}

fn ee(obs: &[f32]) -> [f64; 3] {
    [f64::from(obs[18]), f64::from(obs[19]), f64::from(obs[20])]
}
fn target(obs: &[f32]) -> [f64; 3] {
    [f64::from(obs[21]), f64::from(obs[22]), f64::from(obs[23])]
}

#[test]
fn targets_are_placed_at_the_configured_distance() {
    for (dist, radius) in [(0.5, 0.02), (0.3, 0.1), (0.8, 0.05)] {
        let mut e = env_with(&[("target_distance", dist), ("target_radius", radius)]);
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        let mut quadrants = [false; 4];
        for seed in 0..64 {
            let (obs, _) = e.reset(Some(seed));
            assert_eq!(obs.len(), 24);
            let t = target(&obs);
            let r = t[0].hypot(t[1]);
            assert!(r >= radius - 1e-6 && r <= radius + dist + 1e-6, "r {r}");
            assert!((t[2] - TARGET_HEIGHT).abs() < 1e-6);
            lo = lo.min(r);
            hi = hi.max(r);
            quadrants[usize::from(t[0] > 0.0) * 2 + usize::from(t[1] > 0.0)] = true;
        }
        // Spread over the whole annulus and every direction.
        assert!(lo < radius + 0.2 * dist && hi > radius + 0.8 * dist, "{lo} {hi}");
        assert!(quadrants.iter().all(|q| *q));
    }
    // Seeded.
    let mut e = env_with(&[]);
    assert_eq!(e.reset(Some(7)).0, e.reset(Some(7)).0);
    assert_ne!(e.reset(Some(7)).0, e.reset(Some(8)).0);
    // The arm starts at rest in the home pose.
    let (obs, _) = e.reset(Some(7));
    for j in 0..6 {
        assert!((f64::from(obs[2 * j]) - HOME[j].sin()).abs() < 1e-5);
        assert!((f64::from(obs[2 * j + 1]) - HOME[j].cos()).abs() < 1e-5);
        assert_eq!(obs[12 + j], 0.0);
    }
    // Upright: the flange sits above the shoulder, about d1 + a2 + a3 + d5 high.
    let h = ee(&obs)[2];
    assert!((h - (0.1625 + 0.425 + 0.3922 + 0.0997)).abs() < 1e-3, "{h}");
}

#[test]
fn positive_torque_on_joint_1_rotates_it_positively() {
    let mut e = env_with(&[]);
    e.reset(Some(0));
    // Horizontal arm (DH zero pose), the base joint alone driven.
    e.set_state(&state([0.0; 6], [0.3, 0.0, 0.5])).unwrap();
    let mut obs = Vec::new();
    let start = {
        let mut o = vec![0.0f32; 24];
        e.inner().observe_into(&mut o).unwrap();
        ee(&o)
    };
    for _ in 0..5 {
        obs = e.step(&action([1.0, 0.0, 0.0, 0.0, 0.0, 0.0])).unwrap().obs;
    }
    let s = e.state();
    assert!(s[0] > 0.01 && s[6] > 0.1, "angle {} rate {}", s[0], s[6]);
    // The flange turns counter-clockwise about +z.
    let end = ee(&obs);
    let turn = end[1].atan2(end[0]) - start[1].atan2(start[0]);
    assert!(turn > 0.01, "{turn}");
    // And the other way with a negative torque.
    e.set_state(&state([0.0; 6], [0.3, 0.0, 0.5])).unwrap();
    for _ in 0..5 {
        e.step(&action([-1.0, 0.0, 0.0, 0.0, 0.0, 0.0])).unwrap();
    }
    assert!(e.state()[0] < -0.01);
}

/// Flange height after `steps` zero-action steps from the horizontal pose, under `gravity`.
fn sag(gravity: f64, steps: usize) -> (f64, f64) {
    let mut e = env_with(&[("gravity", gravity)]);
    e.reset(Some(0));
    e.set_state(&state([0.0; 6], [0.3, 0.0, 0.5])).unwrap();
    let mut o = vec![0.0f32; 24];
    e.inner().observe_into(&mut o).unwrap();
    let z0 = ee(&o)[2];
    let mut obs = o;
    for _ in 0..steps {
        obs = e.step(&action([0.0; 6])).unwrap().obs;
    }
    (z0, ee(&obs)[2])
}

#[test]
fn the_arm_sags_under_gravity_with_zero_action() {
    let (z0, z_earth) = sag(-9.81, 25);
    let (_, z_weak) = sag(-2.0, 25);
    assert!(z_earth < z0 - 0.01, "{z0} -> {z_earth}");
    assert!(z_weak < z0 && z_weak > z_earth, "weak {z_weak} earth {z_earth}");
}

#[test]
fn two_instances_with_different_gravity_interleaved_equal_each_alone() {
    let actions = random_actions(60, 5);
    let alone = |g: f64| {
        let mut e = env_with(&[("gravity", g)]);
        let mut out = vec![e.reset(Some(3)).0];
        for a in &actions {
            out.push(e.step(a).unwrap().obs);
        }
        out
    };
    let (a_alone, b_alone) = (alone(-9.81), alone(-3.0));
    assert_ne!(a_alone, b_alone);
    let mut a = env_with(&[("gravity", -9.81)]);
    let mut b = env_with(&[("gravity", -3.0)]);
    let mut a_mix = vec![a.reset(Some(3)).0];
    let mut b_mix = vec![b.reset(Some(3)).0];
    for act in &actions {
        a_mix.push(a.step(act).unwrap().obs);
        b_mix.push(b.step(act).unwrap().obs);
    }
    assert_eq!(a_mix, a_alone);
    assert_eq!(b_mix, b_alone);
}

#[test]
fn finite_at_the_spec_bounds() {
    common::finite_at_the_spec_bounds_for_a_task_without_termination(&spec(), &random_actions(100, 9));
}

#[test]
fn reward_is_brax_s_move_towards_target_plus_hit_bonus() {
    let mut e = env_with(&[]);
    e.reset(Some(0));
    // Far target: reward = 0.1 · displacement towards the target, no bonus, target stays.
    let far = [0.4, -0.3, 0.5];
    e.set_state(&state([0.0, -1.2, 0.8, -1.0, 0.3, 0.0], far)).unwrap();
    let mut before = vec![0.0f32; 24];
    e.inner().observe_into(&mut before).unwrap();
    let mut saw_positive = false;
    for a in random_actions(20, 2) {
        let out = e.step(&a).unwrap();
        let (p, q) = (ee(&before), ee(&out.obs));
        let rel = [far[0] - q[0], far[1] - q[1], far[2] - q[2]];
        let d = (rel[0] * rel[0] + rel[1] * rel[1] + rel[2] * rel[2]).sqrt();
        let along = ((q[0] - p[0]) * rel[0] + (q[1] - p[1]) * rel[1] + (q[2] - p[2]) * rel[2]) / (1e-6 + d);
        assert!(d > 0.02);
        assert!(
            (out.reward - 0.1 * along).abs() < 1e-5,
            "{} vs {}",
            out.reward,
            0.1 * along
        );
        assert_eq!(target(&out.obs), far.map(|v| f64::from(v as f32)));
        assert_eq!(e.info()["hit"], 0.0);
        saw_positive |= out.reward > 0.0;
        before = out.obs;
    }
    assert!(saw_positive);
    // Target 15 mm above the flange: a hit inside the default 20 mm radius (bonus 1, new
    // target), none inside a 10 mm radius.
    for (radius, hit) in [(0.02, true), (0.01, false)] {
        let mut e = env_with(&[("target_radius", radius)]);
        e.reset(Some(0));
        let joints = [0.0, -1.2, 0.8, -1.0, 0.3, 0.0];
        e.set_state(&state(joints, [0.0; 3])).unwrap();
        let mut o = vec![0.0f32; 24];
        e.inner().observe_into(&mut o).unwrap();
        let p = ee(&o);
        let t = [p[0], p[1], p[2] + 0.015];
        e.set_state(&state(joints, t)).unwrap();
        let out = e.step(&action([0.0; 6])).unwrap();
        assert_eq!(e.info()["hit"] == 1.0, hit, "radius {radius}");
        let moved = e.state()[12..].to_vec();
        if hit {
            assert!(out.reward > 0.9 && out.reward < 1.1, "{}", out.reward);
            assert!((moved[2] - TARGET_HEIGHT).abs() < 1e-9);
            let r = moved[0].hypot(moved[1]);
            assert!((radius..=radius + 0.5).contains(&r));
        } else {
            assert!(out.reward.abs() < 0.1);
            assert_eq!(moved, t.to_vec());
        }
        assert!(!out.terminated);
    }
}

#[test]
fn render_draws_the_arm_and_the_target() {
    let mut e = env_with(&[]);
    assert!(e.render().is_none(), "nothing to draw before reset");
    e.reset(Some(0));
    let f = e.render().unwrap();
    assert_eq!(f.rgb.len(), (f.width * f.height * 3) as usize);
    let red = (0..f.height)
        .flat_map(|y| (0..f.width).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let p = f.pixel(x, y);
            p[0] > 150 && p[1] < 110 && p[2] < 100
        })
        .count();
    assert!(red > 4, "target pixels {red}");
    // The picture follows the state: another arm pose, another target.
    let mut s = e.state();
    s[1] = 0.0;
    e.set_state(&s).unwrap();
    let g = e.render().unwrap();
    assert_ne!(g, f);
    s[12] = -s[12];
    s[13] = -s[13] + 0.2;
    e.set_state(&s).unwrap();
    assert_ne!(e.render().unwrap(), g);
    assert_eq!(e.render().unwrap(), e.render().unwrap());
}
