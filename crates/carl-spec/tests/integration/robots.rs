//! Articulated robots (Ant, HalfCheetah and Humanoid on the articulated-body engine):
//! physics checks (free fall, rest, joint torque direction,
//! friction), every context feature acting on the physics, robustness at the spec bounds,
//! independence of instances, the Gymnasium v5 task rules, and rendering.

use crate::common;

use carl_spec::envs::brax::world::{Configuration, RobotWorld};
use carl_spec::envs::brax::{RobotModel, default_params};
use carl_spec::envs::registry::{Context, SpecEnv, make, make_with};
use carl_spec::envs::rng::EnvRng;
use carl_spec::envs::{Action, Env, EnvError};
use carl_spec::spec::SpecSet;
use carl_spec::spec::model::{EnvSpec, Value};

fn spec(id: &str) -> EnvSpec {
    SpecSet::bundled().unwrap().get(id).unwrap().clone()
}

fn env_with(id: &str, ctx: &[(&str, f64)]) -> SpecEnv {
    let ctx: Context = ctx.iter().map(|(k, v)| (k.to_string(), Value::Number(*v))).collect();
    make(&spec(id), &ctx).unwrap()
}

fn random_actions(n: usize, steps: usize, seed: u64) -> Vec<Action> {
    let mut rng = EnvRng::from_seed(seed);
    (0..steps)
        .map(|_| Action::Continuous((0..n).map(|_| (rng.next_f64() * 2.0 - 1.0) as f32).collect()))
        .collect()
}

fn zeros(n: usize) -> Action {
    Action::Continuous(vec![0.0; n])
}

/// Ant standing configuration in the air: torso at `z`, ankles inside their ranges.
fn ant_in_air(z: f64) -> Configuration {
    Configuration {
        root: vec![0.0, 0.0, z, 1.0, 0.0, 0.0, 0.0],
        // hip_1, ankle_1, hip_2, ankle_2, hip_3, ankle_3, hip_4, ankle_4 (URDF order)
        joints: vec![0.0, 0.8, 0.0, -0.8, 0.0, -0.8, 0.0, 0.8],
        vel: vec![0.0; 14],
    }
}

#[test]
fn robots_load_from_urdf() {
    let ant = RobotModel::load("ant").unwrap();
    // ant.xml's 13 bodies: torso, then per leg its hip connector, thigh and shin.
    assert_eq!(ant.link_names.len(), 13);
    assert_eq!(ant.joint_names.len(), 8);
    assert_eq!(ant.num_actuators(), 8);
    // MuJoCo's masses from the geoms at density 5 (a 0.08 m capsule 0.28 m long: 0.0392 kg).
    assert!((ant.link_mass("aux_1").unwrap() - 0.0391578).abs() < 1e-6);
    // Context masses reach the physics engine, per link.
    let mut p = default_params("ant").unwrap();
    p.torso_mass = Some(4.0);
    p.set("mass_ankle_3_link", 2.5).unwrap();
    assert!(p.set("mass_nose", 1.0).is_err());
    let sys = carl_spec::envs::brax::articulated::ArticulatedSystem::new(&ant, &p).unwrap();
    let mass = |link: &str| {
        let li = ant.link_names.iter().position(|n| n == link).unwrap();
        sys.model.bodies[sys.link_body[li]].mass
    };
    assert!((mass("torso") - 4.0).abs() < 1e-12);
    assert!((mass("ankle_3_link") - 2.5).abs() < 1e-12);
    assert!((mass("aux_1") - 0.0391578).abs() < 1e-6);
    // rapier3d still builds the same URDF (the manipulation tasks' engine).
    let w = RobotWorld::build(&ant, &p, &ant_in_air(2.0));
    assert!((w.link_mass(0) - 4.0).abs() < 1e-5);
    let cheetah = RobotModel::load("half_cheetah").unwrap();
    // world, two slide carriers, torso, three segments per leg.
    assert_eq!(cheetah.link_names.len(), 10);
    assert_eq!(cheetah.joint_names[..3], ["rootx", "rootz", "rooty"]);
    assert_eq!(cheetah.num_actuators(), 6);
    // MuJoCo's settotalmass=14 split by capsule volume (torso 6.25 kg, back thigh 1.54 kg).
    assert!((cheetah.link_mass("torso").unwrap() - 6.2502).abs() < 1e-3);
    assert!((cheetah.link_mass("bthigh").unwrap() - 1.5435).abs() < 1e-3);
}

#[test]
fn dropped_body_falls_in_sqrt_2h_over_g() {
    let ant = RobotModel::load("ant").unwrap();
    for g in [-9.8, -3.7, -1.6, -20.0] {
        let mut p = default_params("ant").unwrap();
        p.gravity = g;
        let mut w = RobotWorld::build(&ant, &p, &ant_in_air(6.0));
        let dt = ant.side.timestep;
        let h = 3.0;
        let (mut t, mut z_prev) = (0.0, 6.0);
        let crossed = loop {
            w.step(&[0.0; 8]);
            t += dt;
            let z = f64::from(w.link_pose(0).translation.z);
            if z <= 6.0 - h {
                // Interpolate the crossing inside the last step.
                break t - dt * (6.0 - h - z) / (z_prev - z);
            }
            z_prev = z;
            assert!(t < 10.0, "g = {g}: never fell {h} m");
        };
        let expected = (2.0 * h / -g).sqrt();
        // Semi-implicit Euler lands within one step of the analytic time.
        assert!(
            (crossed - expected).abs() <= dt,
            "g = {g}: fell {h} m in {crossed:.4} s, expected {expected:.4} s"
        );
    }
}

#[test]
fn ant_at_rest_settles_at_a_stable_height() {
    let mut e = env_with("ant", &[]);
    e.reset(Some(0));
    let mut heights = Vec::new();
    for _ in 0..200 {
        let s = e.step(&zeros(8)).unwrap();
        assert!(!s.terminated, "the resting ant stays healthy");
        heights.push(e.state()[2]);
    }
    // After 5 s the height no longer drifts: two later windows agree on the mean within 2 mm,
    // and rapier's contact jitter stays below 1 cm.
    let mean = |w: &[f64]| w.iter().sum::<f64>() / w.len() as f64;
    let (m1, m2) = (mean(&heights[100..150]), mean(&heights[150..200]));
    assert!((m1 - m2).abs() < 2e-3, "torso height drifts: {m1} -> {m2}");
    let last = &heights[100..];
    let (lo, hi) = last
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), z| (l.min(*z), h.max(*z)));
    assert!(hi - lo < 1e-2, "torso height jitters: {lo}..{hi}");
    // Resting on its legs: above the torso radius, below the start height.
    assert!(lo > 0.25 && hi < 0.75, "rest height {lo}..{hi}");
    // The torso does not move away.
    let s = e.state();
    assert!(s[0].hypot(s[1]) < 0.2, "the resting ant wandered to {:?}", &s[..2]);
}

/// Extreme but allowed values per feature: the finite spec bounds, and far values on open sides.
fn extremes(id: &str) -> Vec<(String, f64)> {
    let spec = spec(id);
    let mut out = Vec::new();
    // Features acting only with an option are checked with it (goal_option.rs).
    for f in spec.features.iter().filter(|f| f.requires_option.is_none()) {
        let d = f.default_f64().unwrap();
        let [lo, hi] = f.bounds;
        out.push((f.name.clone(), lo.unwrap_or(if d > 0.0 { 0.0 } else { d * 20.0 - 1.0 })));
        out.push((f.name.clone(), hi.unwrap_or(if d > 0.0 { d * 20.0 } else { 1.0 })));
    }
    out
}

#[test]
fn ant_stays_finite_at_the_spec_bounds() {
    let spec = spec("ant");
    let actions = random_actions(8, 60, 3);
    for (name, value) in extremes("ant") {
        let ctx = Context::from([(name.clone(), Value::Number(value))]);
        let mut e = make_with(
            &spec,
            &ctx,
            carl_spec::envs::registry::MakeOptions {
                allow_out_of_bounds: true,
            },
        )
        .unwrap();
        let (obs, _) = e.reset(Some(1));
        assert!(obs.iter().all(|x| x.is_finite()));
        for a in &actions {
            let s = e.step(a).unwrap();
            assert!(
                s.obs.iter().all(|x| x.is_finite()),
                "{name} = {value}: non-finite observation"
            );
            assert!(e.state().iter().all(|x| x.is_finite()), "{name} = {value}");
            if s.info["diverged"] != 0.0 {
                assert!(s.terminated, "{name} = {value}: a diverged step terminates");
            }
            if s.terminated {
                e.reset(None);
            }
        }
    }
}

#[test]
fn positive_hip_torque_rotates_the_leg_in_the_joints_positive_direction() {
    let model = RobotModel::load("ant").unwrap();
    let nq = 15;
    for (k, a) in model.side.actuators.iter().enumerate() {
        let j = model.joint_names.iter().position(|n| *n == a.joint).unwrap();
        for sign in [1.0f32, -1.0] {
            let mut e = env_with("ant", &[]);
            e.reset(Some(0));
            // High in the air: no contact, only the motor acts on the joint.
            let mut s = e.state();
            let mut q = ant_in_air(3.0);
            q.joints[j] = if a.joint.starts_with("ankle") { q.joints[j] } else { 0.0 };
            s[..7].copy_from_slice(&q.root);
            s[7..nq].copy_from_slice(&q.joints);
            for v in &mut s[nq..] {
                *v = 0.0;
            }
            e.set_state(&s).unwrap();
            let before = e.state()[7 + j];
            let mut act = vec![0.0f32; 8];
            act[k] = 0.5 * sign;
            e.step(&Action::Continuous(act)).unwrap();
            let after = e.state()[7 + j];
            assert!(
                (after - before) * f64::from(sign) > 0.01,
                "{}: control {sign} moved the joint from {before} to {after}",
                a.joint
            );
        }
    }
    // In the world: +torque on hip_1 (z axis) turns leg 1 counter-clockwise seen from above,
    // relative to the torso.
    let mut e = env_with("ant", &[]);
    e.reset(Some(0));
    let mut s = e.state();
    let q = ant_in_air(3.0);
    s[..7].copy_from_slice(&q.root);
    s[7..nq].copy_from_slice(&q.joints);
    for v in &mut s[nq..] {
        *v = 0.0;
    }
    e.set_state(&s).unwrap();
    let shin_angle = |e: &SpecEnv| {
        let r = e.inner().downcast_ref::<carl_spec::envs::brax::Locomotion>().unwrap();
        let w = r.physics().and_then(|p| p.articulated()).unwrap();
        let model = r.model();
        let body = |link: &str| w.system().link_body[model.link_names.iter().position(|n| n == link).unwrap()];
        let d = w.data();
        let (torso, shin) = (body("torso"), body("ankle_1_link")); // shin_1 origin = ankle point
        let rel = [0, 1, 2].map(|k| d.xpos[shin][k] - d.xpos[torso][k]);
        let m = &d.xmat[torso];
        // The shin's origin in the torso frame (Rᵀ · rel); the hip sits at (0.2, 0.2).
        let p = [0, 1].map(|c| m[0][c] * rel[0] + m[1][c] * rel[1] + m[2][c] * rel[2]);
        (p[1] - 0.2).atan2(p[0] - 0.2)
    };
    let a0 = shin_angle(&e);
    let mut act = vec![0.0f32; 8];
    act[2] = 1.0; // hip_1
    e.step(&Action::Continuous(act)).unwrap();
    assert!(shin_angle(&e) > a0 + 0.01, "{a0} -> {}", shin_angle(&e));
}

/// The ant settled on the ground (default context), as a state vector.
fn settled_ant() -> Vec<f64> {
    let mut e = env_with("ant", &[]);
    e.reset(Some(0));
    for _ in 0..60 {
        e.step(&zeros(8)).unwrap();
    }
    e.state()
}

#[test]
fn higher_friction_shortens_a_sliding_distance() {
    let start = settled_ant();
    let slide = |friction: f64| {
        let mut e = env_with("ant", &[("friction", friction)]);
        e.reset(Some(0));
        let mut s = start.clone();
        s[15] = 3.0; // root x velocity
        e.set_state(&s).unwrap();
        for _ in 0..20 {
            e.step(&zeros(8)).unwrap();
        }
        e.state()[0] - start[0]
    };
    let d: Vec<f64> = [0.2, 0.6, 1.2].iter().map(|f| slide(*f)).collect();
    assert!(d[0] > d[1] && d[1] > d[2], "slide distances {d:?}");
    assert!(d[2] > 0.0);
}

#[test]
fn every_feature_changes_the_physics_per_instance() {
    let start = settled_ant();
    let actions = random_actions(8, 10, 5);
    let run = |ctx: &[(&str, f64)]| {
        let mut e = env_with("ant", ctx);
        e.reset(Some(0));
        e.set_state(&start).unwrap();
        for a in &actions {
            e.step(a).unwrap();
        }
        e.state()
    };
    let base = run(&[]);
    for (name, value) in [
        ("gravity", -5.0),
        ("friction", 1.2),
        ("angular_damping", -2.0),
        ("joint_angular_damping", 5.0),
        ("joint_stiffness", 50.0),
        ("actuator_strength", 150.0),
        ("torso_mass", 20.0),
    ] {
        let other = run(&[(name, value)]);
        let diff = base.iter().zip(&other).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(diff > 1e-3, "{name} = {value} barely changes the trajectory ({diff})");
    }
    // Building other instances in between changes nothing (no shared state).
    assert_eq!(run(&[]), base);
}

#[test]
fn two_instances_interleaved_equal_each_alone() {
    let actions = random_actions(8, 40, 11);
    let alone = |g: f64| {
        let mut e = env_with("ant", &[("gravity", g)]);
        let mut out = vec![e.reset(Some(3)).0];
        for a in &actions {
            out.push(e.step(a).unwrap().obs);
        }
        out
    };
    let (a_alone, b_alone) = (alone(-9.8), alone(-4.0));
    assert_ne!(a_alone, b_alone);
    let mut a = env_with("ant", &[("gravity", -9.8)]);
    let mut b = env_with("ant", &[("gravity", -4.0)]);
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
fn seeds_reproduce_and_differ() {
    let mut e = env_with("ant", &[]);
    let (a, _) = e.reset(Some(42));
    let (b, _) = e.reset(Some(42));
    let (c, _) = e.reset(Some(43));
    assert_eq!(a, b);
    assert_ne!(a, c);
    // Gymnasium v5 layout: qpos[2:] (13) + qvel (14) + clipped cfrc_ext (13 bodies × 6).
    assert_eq!(a.len(), 13 + 14 + 78);
    // Reset noise: ±0.1 around the initial pose, height 0.75.
    assert!((f64::from(a[0]) - 0.75).abs() <= 0.1);
}

#[test]
fn bad_input_is_an_error() {
    let mut e = env_with("ant", &[]);
    assert!(matches!(e.step(&zeros(8)), Err(EnvError::NeedsReset { .. })));
    e.reset(Some(0));
    assert!(matches!(
        e.step(&zeros(7)),
        Err(EnvError::ActionLength {
            expected: 8,
            got: 7,
            ..
        })
    ));
    assert!(matches!(e.step(&Action::Discrete(1)), Err(EnvError::ActionKind { .. })));
    let n = e.state_dim();
    assert!(matches!(
        e.set_state(&vec![0.0; n - 1]),
        Err(EnvError::StateLength { .. })
    ));
    let mut s = e.state();
    s[3] = f64::NAN;
    assert!(matches!(
        e.set_state(&s),
        Err(EnvError::StateNotFinite { index: 3, .. })
    ));
    // Out-of-range controls are clipped like MuJoCo's ctrlrange, not refused.
    assert!(e.step(&Action::Continuous(vec![5.0; 8])).is_ok());
    // Absurd but finite states neither panic nor leak non-finite numbers.
    let mut s = e.state();
    for (i, v) in s.iter_mut().enumerate() {
        *v = if i % 2 == 0 { 1e12 } else { -1e30 };
    }
    e.set_state(&s).unwrap();
    let out = e.step(&zeros(8)).unwrap();
    assert!(out.obs.iter().all(|x| x.is_finite()));
    assert!(out.terminated);
}

#[test]
fn ant_v5_reward_and_termination() {
    let mut e = env_with("ant", &[]);
    e.reset(Some(0));
    let a = Action::Continuous(vec![0.5, -0.5, 0.2, 0.0, 0.0, 0.1, -1.0, 0.3]);
    let s = e.step(&a).unwrap();
    let i = &s.info;
    let ctrl: f64 = [0.5f64, -0.5, 0.2, 0.0, 0.0, 0.1, -1.0, 0.3]
        .iter()
        .map(|x| x * x)
        .sum::<f64>()
        * 0.5;
    assert!((i["reward_ctrl"] + ctrl).abs() < 1e-6);
    assert_eq!(i["reward_survive"], 1.0);
    assert!(i["reward_contact"] <= 0.0);
    let total = i["reward_forward"] + i["reward_ctrl"] + i["reward_contact"] + i["reward_survive"];
    assert!((s.reward - total).abs() < 1e-12);
    assert!((i["reward_forward"] - i["x_velocity"]).abs() < 1e-12);

    // Above the healthy range (z > 1): terminated, no survival reward.
    let mut st = e.state();
    st[2] = 2.0;
    e.set_state(&st).unwrap();
    let s = e.step(&zeros(8)).unwrap();
    assert!(s.terminated);
    assert_eq!(s.info["reward_survive"], 0.0);
    assert_eq!(s.info["diverged"], 0.0);
}

#[test]
fn diverging_instance_terminates_with_a_flag() {
    // A huge actuator strength with no damping and anti-damping drives the simulation past any
    // physical speed: the step is rolled back, flagged and terminated, observations stay finite.
    common::runaway_is_flagged(
        &spec("ant"),
        &[
            ("actuator_strength", 1e9),
            ("joint_angular_damping", 0.0),
            ("angular_damping", 50.0),
        ],
        &random_actions(8, 50, 2),
    );
}

#[test]
fn render_draws_the_robot_over_the_ground() {
    for id in ["ant", "half_cheetah"] {
        render_checks(id);
    }
}

fn render_checks(id: &str) {
    let mut e = env_with(id, &[]);
    assert!(e.render().is_none(), "nothing to draw before reset");
    e.reset(Some(0));
    let f = e.render().unwrap();
    assert_eq!(f.rgb.len(), (f.width * f.height * 3) as usize);
    let sky = [214u8, 228, 240];
    let ground = [[196u8, 206, 186], [178, 190, 168]];
    let near = |p: [u8; 3], q: [u8; 3]| p.iter().zip(q).all(|(a, b)| (i32::from(*a) - i32::from(b)).abs() < 12);
    let mut robot = 0;
    let mut sky_px = 0;
    let mut ground_px = 0;
    for y in 0..f.height {
        for x in 0..f.width {
            let p = f.pixel(x, y);
            if near(p, sky) {
                sky_px += 1;
            } else if ground.iter().any(|g| near(p, *g)) {
                ground_px += 1;
            } else {
                robot += 1;
            }
        }
    }
    let total = f.width * f.height;
    assert!(robot > total / 100, "{id}: robot pixels {robot}");
    assert!(
        sky_px > total / 10 && ground_px > total / 10,
        "{id}: sky {sky_px} ground {ground_px}"
    );
    // The picture follows the state (the torso height: qpos[2] of a free root, rootz of a
    // planar root).
    let mut s = e.state();
    s[if id == "ant" { 2 } else { 1 }] = 2.0;
    e.set_state(&s).unwrap();
    assert_ne!(e.render().unwrap(), f);
    // Same state, same bytes.
    assert_eq!(e.render().unwrap(), e.render().unwrap());
}

#[test]
fn half_cheetah_rests_and_stays_finite_at_the_spec_bounds() {
    let mut e = env_with("half_cheetah", &[]);
    let (obs, _) = e.reset(Some(0));
    // Gymnasium v5 layout: qpos[1:] (rootz, rooty, 6 joints) + qvel (9).
    assert_eq!(obs.len(), 17);
    let mut heights = Vec::new();
    for _ in 0..120 {
        let s = e.step(&zeros(6)).unwrap();
        assert!(!s.terminated, "HalfCheetah never terminates");
        heights.push(e.state()[1]);
    }
    let mean = |w: &[f64]| w.iter().sum::<f64>() / w.len() as f64;
    let (m1, m2) = (mean(&heights[60..90]), mean(&heights[90..120]));
    assert!((m1 - m2).abs() < 2e-3, "torso height drifts: {m1} -> {m2}");
    // Standing on its legs: the torso (0.7 m at rootz = 0) is lower but well above the ground.
    assert!(m2 > -0.6 && m2 < 0.0, "rootz at rest {m2}");

    let spec = spec("half_cheetah");
    let actions = random_actions(6, 40, 3);
    for (name, value) in extremes("half_cheetah") {
        let ctx = Context::from([(name.clone(), Value::Number(value))]);
        let mut e = make_with(
            &spec,
            &ctx,
            carl_spec::envs::registry::MakeOptions {
                allow_out_of_bounds: true,
            },
        )
        .unwrap();
        e.reset(Some(1));
        for a in &actions {
            let s = e.step(a).unwrap();
            assert!(s.obs.iter().all(|x| x.is_finite()), "{name} = {value}");
            if s.info["diverged"] != 0.0 {
                assert!(s.terminated, "{name} = {value}: a diverged step terminates");
                e.reset(None);
            }
        }
    }
}

#[test]
fn half_cheetah_motors_features_and_reward() {
    let model = RobotModel::load("half_cheetah").unwrap();
    // Each motor turns its joint in the positive direction (torso held high above the ground).
    for (k, a) in model.side.actuators.iter().enumerate() {
        let j = model.joint_names.iter().position(|n| *n == a.joint).unwrap();
        let mut e = env_with("half_cheetah", &[]);
        e.reset(Some(0));
        let mut s = vec![0.0; e.state_dim()];
        s[1] = 3.0; // rootz
        e.set_state(&s).unwrap();
        let mut act = vec![0.0f32; 6];
        act[k] = 1.0;
        e.step(&Action::Continuous(act)).unwrap();
        let q = e.state()[j];
        assert!(q > 0.01, "{}: +1 moved the joint to {q}", a.joint);
    }
    // Every context feature changes the trajectory. The passive springs keep the joints inside
    // their ranges, so the back foot starts beyond its lower limit (-0.4 rad), where the limit
    // spring (`joint_stiffness`) acts.
    let actions = random_actions(6, 10, 5);
    let run = |ctx: &[(&str, f64)]| {
        let mut e = env_with("half_cheetah", ctx);
        e.reset(Some(0));
        let mut s = e.state();
        s[5] = -0.6;
        e.set_state(&s).unwrap();
        for a in &actions {
            e.step(a).unwrap();
        }
        e.state()
    };
    let base = run(&[]);
    for (name, value) in [
        ("gravity", -5.0),
        ("friction", 1.2),
        ("angular_damping", -2.0),
        ("joint_angular_damping", 5.0),
        ("joint_stiffness", 50.0),
        ("torso_mass", 20.0),
    ] {
        let other = run(&[(name, value)]);
        let diff = base.iter().zip(&other).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(diff > 1e-3, "{name} = {value} barely changes the trajectory ({diff})");
    }
    // HalfCheetah-v5 reward: forward velocity minus 0.1·Σa².
    let mut e = env_with("half_cheetah", &[]);
    e.reset(Some(0));
    let a = [0.5f32, -0.5, 1.0, 0.0, 0.25, -1.0];
    let x0 = e.state()[0];
    let s = e.step(&Action::Continuous(a.to_vec())).unwrap();
    let ctrl: f64 = a.iter().map(|x| f64::from(*x).powi(2)).sum::<f64>() * 0.1;
    let v = (e.state()[0] - x0) / 0.05;
    assert!((s.reward - (v - ctrl)).abs() < 1e-9, "{} vs {}", s.reward, v - ctrl);
    assert!((s.info["x_velocity"] - v).abs() < 1e-9);
}

/// HalfCheetah runs on the articulated engine by default and on rapier3d with `rapier = true`;
/// both start from the same reset state and their states round-trip through `set_state` (the
/// articulated one's replay to the constraint solver's tolerance).
#[test]
fn half_cheetah_engines_and_state_round_trip() {
    use carl_spec::envs::brax::Locomotion;
    use carl_spec::envs::registry::{EnvOptions, MakeOptions, make_env};
    let mut on_rapier = EnvOptions::new();
    on_rapier.insert("rapier".into(), Value::Bool(true));
    let s = spec("half_cheetah");
    let mut articulated = env_with("half_cheetah", &[]);
    let mut rapier = make_env(&s, &Context::new(), MakeOptions::default(), &on_rapier).unwrap();
    articulated.reset(Some(4));
    rapier.reset(Some(4));
    // The same reset (rapier keeps f32 coordinates).
    for (a, b) in articulated.state().iter().zip(rapier.state()) {
        assert!((a - b).abs() < 1e-6, "{a} vs {b}");
    }
    let loco = |e: &SpecEnv| {
        e.inner()
            .downcast_ref::<Locomotion>()
            .unwrap()
            .articulated_world()
            .is_some()
    };
    assert!(loco(&articulated) && !loco(&rapier));
    for e in [&mut articulated, &mut rapier] {
        let actions = random_actions(6, 60, 9);
        for a in &actions[..30] {
            e.step(a).unwrap();
        }
        let saved = e.state();
        let rest: Vec<_> = actions[30..].iter().map(|a| e.step(a).unwrap().obs).collect();
        e.set_state(&saved).unwrap();
        assert_eq!(e.state(), saved);
        let again: Vec<_> = actions[30..].iter().map(|a| e.step(a).unwrap().obs).collect();
        if loco(e) {
            // The articulated state is the whole state but for the constraint solver's warm
            // start (its tolerance, 1e-8 relative): the replay agrees to that.
            for (x, y) in rest.iter().zip(&again) {
                for (a, b) in x.iter().zip(y) {
                    assert!((a - b).abs() <= 1e-4 * (1.0 + a.abs()), "replay: {a} vs {b}");
                }
            }
        } else {
            // rapier's warm-start caches are not part of the state.
            assert_eq!(rest[0].len(), again[0].len());
        }
    }
    // The engines differ (the articulated engine is not rapier under another name).
    assert_ne!(articulated.state(), rapier.state());
}
