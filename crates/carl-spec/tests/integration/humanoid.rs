//! The Humanoid (Gymnasium Humanoid-v5 on humanoid.xml, the articulated engine): the model's
//! bodies and masses, standing height at reset, falling under zero control (and how gravity
//! changes it), motor directions, the v5 reward and observation layout, robustness at the spec
//! bounds, independence of instances and rendering (tests/audit.rs audits every runtime).

use crate::common;

use carl_spec::envs::brax::RobotModel;
use carl_spec::envs::registry::{Context, MakeOptions, SpecEnv, make, make_with};
use carl_spec::envs::rng::EnvRng;
use carl_spec::envs::{Action, Env};
use carl_spec::spec::SpecSet;
use carl_spec::spec::model::{EnvSpec, Value};

const NA: usize = 17;
const NQ: usize = 24;
const NV: usize = 23;
const NB: usize = 13;

fn spec() -> EnvSpec {
    SpecSet::bundled().unwrap().get("humanoid").unwrap().clone()
}

fn env_with(ctx: &[(&str, f64)]) -> SpecEnv {
    let ctx: Context = ctx.iter().map(|(k, v)| (k.to_string(), Value::Number(*v))).collect();
    make(&spec(), &ctx).unwrap()
}

fn zeros() -> Action {
    Action::Continuous(vec![0.0; NA])
}

fn random_actions(steps: usize, seed: u64) -> Vec<Action> {
    let mut rng = EnvRng::from_seed(seed);
    (0..steps)
        .map(|_| Action::Continuous((0..NA).map(|_| (rng.next_f64() * 0.8 - 0.4) as f32).collect()))
        .collect()
}

/// Steps until the episode terminates under zero control (`None` if it lasts `max` steps).
fn fall_steps(ctx: &[(&str, f64)], max: usize) -> Option<usize> {
    let mut e = env_with(ctx);
    e.reset(Some(0));
    (1..=max).find(|_| e.step(&zeros()).unwrap().terminated)
}

#[test]
fn model_has_the_mujoco_bodies_joints_and_masses() {
    let m = RobotModel::load("humanoid").unwrap();
    // 13 MuJoCo bodies plus 7 massless carriers of the multi-hinge joints (the engine folds
    // them into their bodies).
    assert_eq!(m.link_names.len(), 20);
    assert_eq!(m.bodies.len(), NB);
    let bodies: Vec<&str> = m.bodies.iter().map(|&i| m.link_names[i].as_str()).collect();
    assert_eq!(bodies[..3], ["torso", "lwaist", "pelvis"]);
    assert_eq!(bodies[12], "left_lower_arm");
    // Joints in MuJoCo's qpos order, actuators in its actuator order.
    assert_eq!(m.joint_names.len(), NA);
    assert_eq!(
        m.joint_names[..4],
        ["abdomen_z", "abdomen_y", "abdomen_x", "right_hip_x"]
    );
    assert_eq!(m.side.actuators[0].joint, "abdomen_y");
    assert_eq!(m.side.actuators[5].gear, 300.0);
    // Masses from MuJoCo's default density: the torso is Brax's/CARL's 8.907463 kg.
    assert!((m.link_mass("torso").unwrap() - 8.907463).abs() < 1e-5);
    let total: f64 = m.bodies.iter().map(|&i| m.link_mass(&m.link_names[i]).unwrap()).sum();
    assert!((total - 42.116).abs() < 1e-2, "total mass {total}");
    assert_eq!(m.side.timestep, 0.003);
    assert_eq!(m.side.frame_skip, 5);
}

#[test]
fn stands_at_reset_then_falls_and_terminates_under_zero_control() {
    let mut e = env_with(&[]);
    let (obs, _) = e.reset(Some(0));
    assert_eq!(obs.len(), 348);
    // qpos[2] (the first observation) is the torso height 1.4 ± the reset noise 0.01.
    assert!((f64::from(obs[0]) - 1.4).abs() <= 0.01, "reset height {}", obs[0]);
    // The feet start 0.107 m above the ground (as in MuJoCo); the body drops and stays healthy
    // for a while, then collapses: terminated once qpos[2] < 1.
    let mut z = Vec::new();
    let mut end = None;
    for t in 1..=400 {
        let s = e.step(&zeros()).unwrap();
        z.push(e.state()[2]);
        if s.terminated {
            assert_eq!(s.info["reward_survive"], 0.0);
            assert_eq!(s.info["diverged"], 0.0);
            end = Some(t);
            break;
        }
        assert_eq!(s.info["reward_survive"], 5.0);
    }
    let end = end.expect("a passive humanoid falls within 6 s");
    // Not instantly: at least 0.15 s (10 steps of 15 ms) of healthy standing.
    assert!(end >= 10, "terminated after {end} steps");
    assert!(*z.last().unwrap() < 1.0);
    assert!(z[..end - 1].iter().all(|h| *h >= 1.0));
}

#[test]
fn stronger_gravity_makes_it_fall_sooner() {
    let steps: Vec<usize> = [-3.0, -9.8, -20.0]
        .iter()
        .map(|g| fall_steps(&[("gravity", *g)], 1000).unwrap_or(1000))
        .collect();
    assert!(steps[0] > steps[1] && steps[1] > steps[2], "fall steps {steps:?}");
}

#[test]
fn each_motor_turns_its_joint_in_the_positive_direction() {
    let m = RobotModel::load("humanoid").unwrap();
    let mut e = env_with(&[]);
    e.reset(Some(0));
    // High in the air at rest, every joint in the middle of its range (no limit acting).
    let mut s = vec![0.0; e.state_dim()];
    s[2] = 5.0;
    s[3] = 1.0;
    for (k, j) in m
        .urdf
        .joints
        .iter()
        .filter(|j| j.limit.upper > j.limit.lower)
        .enumerate()
    {
        s[7 + k] = 0.5 * (j.limit.lower + j.limit.upper);
    }
    let step_from = |act: Vec<f32>| {
        let mut e = env_with(&[]);
        e.reset(Some(0));
        e.set_state(&s).unwrap();
        e.step(&Action::Continuous(act)).unwrap();
        e.state()
    };
    let passive = step_from(vec![0.0; NA]);
    for (k, a) in m.side.actuators.iter().enumerate() {
        let j = m.joint_names.iter().position(|n| *n == a.joint).unwrap();
        for sign in [1.0f32, -1.0] {
            let mut act = vec![0.0; NA];
            act[k] = 0.4 * sign;
            let q = step_from(act)[7 + j];
            let moved = (q - passive[7 + j]) * f64::from(sign);
            assert!(moved > 1e-3, "{}: control {sign} moved the joint by {moved}", a.joint);
        }
    }
    // In the world: +right_hip_y turns the thigh about +y, moving the knee backwards (-x in the
    // pelvis frame).
    let knee_x = |act: Vec<f32>| {
        let mut e = env_with(&[]);
        e.reset(Some(0));
        e.set_state(&s).unwrap();
        e.step(&Action::Continuous(act)).unwrap();
        let r = e.inner().downcast_ref::<carl_spec::envs::brax::Locomotion>().unwrap();
        let w = r.physics().and_then(|p| p.articulated()).unwrap();
        let body = |name: &str| w.system().link_body[m.link_names.iter().position(|n| n == name).unwrap()];
        let d = w.data();
        let (knee, pelvis) = (d.xpos[body("right_shin")], d.xpos[body("pelvis")]);
        let rel = [0, 1, 2].map(|k| knee[k] - pelvis[k]);
        // x of the knee in the pelvis frame (first column of the pelvis rotation · rel).
        let r0 = &d.xmat[body("pelvis")];
        r0[0][0] * rel[0] + r0[1][0] * rel[1] + r0[2][0] * rel[2]
    };
    let mut act = vec![0.0; NA];
    act[5] = 0.4;
    assert!(knee_x(act) < knee_x(vec![0.0; NA]) - 1e-3);
}

#[test]
fn humanoid_v5_reward_and_observation_layout() {
    let m = RobotModel::load("humanoid").unwrap();
    let mut e = env_with(&[("torso_mass", 12.0)]);
    e.reset(Some(0));
    let a: Vec<f32> = (0..NA).map(|i| 0.05 * (i as f32) - 0.4).collect();
    let s = e.step(&Action::Continuous(a.clone())).unwrap();
    let i = &s.info;
    let ctrl: f64 = a.iter().map(|x| f64::from(*x).powi(2)).sum::<f64>() * 0.1;
    assert!((i["reward_ctrl"] + ctrl).abs() < 1e-6);
    assert_eq!(i["reward_survive"], 5.0);
    assert!(i["reward_contact"] <= 0.0 && i["reward_contact"] >= -10.0);
    assert!((i["reward_forward"] - 1.25 * i["x_velocity"]).abs() < 1e-12);
    let total = i["reward_forward"] + i["reward_ctrl"] + i["reward_contact"] + i["reward_survive"];
    assert!((s.reward - total).abs() < 1e-12);
    // Layout: qpos[2:] 22, qvel 23, cinert 13×10, cvel 13×6, qfrc_actuator 17, cfrc_ext 13×6.
    let o = &s.obs;
    let st = e.state();
    for k in 0..NQ - 2 {
        assert_eq!(o[k], st[2 + k] as f32);
    }
    let cinert = NQ - 2 + NV;
    // cinert's last entry of each body is its mass; the torso's is the context's.
    assert!((f64::from(o[cinert + 9]) - 12.0).abs() < 1e-4);
    for (b, &l) in m.bodies.iter().enumerate().skip(1) {
        let mass = m.link_mass(&m.link_names[l]).unwrap();
        assert!((f64::from(o[cinert + 10 * b + 9]) - mass).abs() < 1e-4);
    }
    // Σ m·d over the bodies is ~0: d is taken from the centre of mass (the carriers weigh 1e-4).
    for axis in 0..3 {
        let md: f64 = (0..NB).map(|b| f64::from(o[cinert + 10 * b + 6 + axis])).sum();
        assert!(md.abs() < 1e-2, "Σ m·d[{axis}] = {md}");
    }
    // qfrc_actuator: gear × control, in joint order.
    let qfrc = cinert + 16 * NB;
    for (k, act) in m.side.actuators.iter().enumerate() {
        let j = m.joint_names.iter().position(|n| *n == act.joint).unwrap();
        assert!((f64::from(o[qfrc + j]) - act.gear * f64::from(a[k])).abs() < 1e-3);
    }
    assert_eq!(o.len(), qfrc + NA + 6 * NB);
    // Standing on the feet a while later: the contact block has upward forces on the feet only.
    for _ in 0..12 {
        e.step(&zeros()).unwrap();
    }
    let o = e.observe();
    let cfrc = qfrc + NA;
    let up = |b: usize| f64::from(o[cfrc + 6 * b + 5]);
    let (rf, lf) = (5, 8);
    assert!(up(rf) + up(lf) > 100.0, "foot forces {} {}", up(rf), up(lf));
    for b in (0..NB).filter(|b| *b != rf && *b != lf) {
        assert_eq!(up(b), 0.0, "body {b} touches the ground");
    }

    // Above the healthy range (z > 2): terminated, no survival reward.
    let mut st = e.state();
    st[2] = 2.5;
    e.set_state(&st).unwrap();
    let s = e.step(&zeros()).unwrap();
    assert!(s.terminated);
    assert_eq!(s.info["reward_survive"], 0.0);
}

#[test]
fn torso_mass_enters_the_centre_of_mass_velocity() {
    // The same motion of the bodies weighs the torso differently: the forward reward uses the
    // mass-weighted centre of mass (Humanoid-v5), so it changes with torso_mass at equal root
    // velocity when the torso moves relative to the other bodies.
    let run = |mass: f64| {
        let mut e = env_with(&[("torso_mass", mass)]);
        e.reset(Some(0));
        let mut s = e.state();
        s[7 + 1] = -0.5; // abdomen_y bent
        s[NQ + 3 + 1] = 2.0; // spin about y
        e.set_state(&s).unwrap();
        e.step(&zeros()).unwrap().info["x_velocity"]
    };
    let (a, b) = (run(8.907463), run(30.0));
    assert!((a - b).abs() > 1e-3, "x velocity {a} vs {b}");
}

/// Extreme but allowed values per feature: the finite spec bounds, and far values on open sides.
fn extremes() -> Vec<(String, f64)> {
    let mut out = Vec::new();
    // Features acting only with an option are checked with it (goal_option.rs).
    for f in spec().features.iter().filter(|f| f.requires_option.is_none()) {
        let d = f.default_f64().unwrap();
        let [lo, hi] = f.bounds;
        out.push((f.name.clone(), lo.unwrap_or(if d > 0.0 { 0.0 } else { d * 20.0 - 1.0 })));
        out.push((f.name.clone(), hi.unwrap_or(if d > 0.0 { d * 20.0 } else { 1.0 })));
    }
    out
}

#[test]
fn stays_finite_at_the_spec_bounds_and_flags_divergence() {
    let actions = random_actions(30, 3);
    for (name, value) in extremes() {
        let ctx = Context::from([(name.clone(), Value::Number(value))]);
        let mut e = make_with(
            &spec(),
            &ctx,
            MakeOptions {
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
            assert!(s.reward.is_finite(), "{name} = {value}");
            assert!(e.state().iter().all(|x| x.is_finite()), "{name} = {value}");
            if s.info["diverged"] != 0.0 {
                assert!(s.terminated, "{name} = {value}: a diverged step terminates");
            }
            if s.terminated {
                e.reset(None);
            }
        }
    }
    // A runaway instance (huge anti-damping) is rolled back and flagged, never NaN.
    common::runaway_is_flagged(
        &spec(),
        &[("angular_damping", 1e4), ("joint_angular_damping", 0.0)],
        &random_actions(50, 2),
    );
}

#[test]
fn two_instances_interleaved_equal_each_alone() {
    let actions = random_actions(25, 11);
    let ctx = |g: f64, m: f64| vec![("gravity", g), ("torso_mass", m), ("friction", 1.0)];
    let alone = |g: f64, m: f64| {
        let mut e = env_with(&ctx(g, m));
        let mut out = vec![e.reset(Some(3)).0];
        for a in &actions {
            out.push(e.step(a).unwrap().obs);
        }
        out
    };
    let (a_alone, b_alone) = (alone(-9.8, 8.907463), alone(-4.0, 15.0));
    assert_ne!(a_alone, b_alone);
    let mut a = env_with(&ctx(-9.8, 8.907463));
    let mut b = env_with(&ctx(-4.0, 15.0));
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
fn render_draws_the_humanoid() {
    let mut e = env_with(&[]);
    assert!(e.render().is_none(), "nothing to draw before reset");
    e.reset(Some(0));
    let f = e.render().unwrap();
    assert_eq!(f.rgb.len(), (f.width * f.height * 3) as usize);
    let sky = [214u8, 228, 240];
    let ground = [[196u8, 206, 186], [178, 190, 168]];
    let near = |p: [u8; 3], q: [u8; 3]| p.iter().zip(q).all(|(a, b)| (i32::from(*a) - i32::from(b)).abs() < 12);
    let robot = (0..f.height)
        .flat_map(|y| (0..f.width).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let p = f.pixel(x, y);
            !near(p, sky) && !ground.iter().any(|g| near(p, *g))
        })
        .count();
    let total = (f.width * f.height) as usize;
    assert!(robot > total / 200, "robot pixels {robot}");
    let mut s = e.state();
    s[2] = 1.9;
    e.set_state(&s).unwrap();
    assert_ne!(e.render().unwrap(), f);
}
