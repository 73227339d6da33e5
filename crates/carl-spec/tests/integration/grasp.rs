//! Brax's grasp on rapier3d: target placement, Brax's reward, free fall of the object, a
//! scripted grasp that lifts the ball only with friction, joint torque direction, robustness at
//! the spec bounds, independence of instances, audit, rendering.

use crate::common;

use carl_spec::envs::brax::grasp::{BRAX_DT, Grasp, HIT_BONUS, OBJECT_RADIUS, RewardInput, TARGET_START, grasp_reward};
use carl_spec::envs::brax::world::{Configuration, RobotWorld};
use carl_spec::envs::brax::{RobotModel, default_params, make_grasp};
use carl_spec::envs::registry::{Context, SpecEnv, make};
use carl_spec::envs::rng::EnvRng;
use carl_spec::envs::{Action, Env};
use carl_spec::spec::SpecSet;
use carl_spec::spec::model::{EnvSpec, Value};

fn spec() -> EnvSpec {
    SpecSet::bundled().unwrap().get("grasp").unwrap().clone()
}

fn env_with(ctx: &[(&str, f64)]) -> SpecEnv {
    let ctx: Context = ctx.iter().map(|(k, v)| (k.to_string(), Value::Number(*v))).collect();
    make(&spec(), &ctx).unwrap()
}

fn grasp_with(ctx: &[(&str, f64)]) -> Grasp {
    let mut p = default_params("grasp").unwrap();
    for (k, v) in ctx {
        p.set(k, *v).unwrap();
    }
    make_grasp(p).unwrap()
}

fn random_actions(steps: usize, seed: u64) -> Vec<Action> {
    let mut rng = EnvRng::from_seed(seed);
    (0..steps)
        .map(|_| Action::Continuous((0..19).map(|_| (rng.next_f64() * 2.0 - 1.0) as f32).collect()))
        .collect()
}

/// Finger curls (degrees, positive = towards the palm's underside: proximal, middle, distal)
/// and a palm goal, as a Brax action.
fn grip(c1: f64, c2: f64, c3: f64, palm: [f64; 3]) -> Action {
    let mut a = Vec::new();
    for f in 0..4 {
        if f == 0 {
            // The first finger's hinges curl with negative angles (limits [-90, 0]).
            a.extend([1.0 - c3 / 45.0, 1.0 - c2 / 45.0, -c1 / 45.0, 0.0]);
        } else {
            a.extend([c3 / 45.0 - 1.0, c2 / 45.0 - 1.0, c1 / 45.0, 0.0]);
        }
    }
    a.extend([
        (palm[0] + 10.0) / 10.0 - 1.0,
        (palm[1] + 10.0) / 10.0 - 1.0,
        (palm[2] - 3.5) / 5.0 - 1.0,
    ]);
    Action::Continuous(a.into_iter().map(|x| (x as f32).clamp(-1.0, 1.0)).collect())
}

const OBJ: usize = 38;
const TGT: usize = 51;

#[test]
fn targets_are_placed_within_bounds_and_reproducible_per_seed() {
    for (dist, height, radius) in [(10.0, 8.0, 1.1), (2.0, 0.5, 0.3), (20.0, 3.0, 2.5)] {
        let ctx = [
            ("target_distance", dist),
            ("target_height", height),
            ("target_radius", radius),
        ];
        let sequence = |seed: u64| {
            let mut e = grasp_with(&ctx);
            let mut obs = vec![0.0; 132];
            e.reset_into(Some(seed), &mut obs).unwrap();
            assert_eq!(e.target(), TARGET_START, "reset keeps Brax's config target");
            let mut targets = Vec::new();
            for _ in 0..4 {
                // Put the object onto the target: the step scores a hit and draws a new one.
                let mut s = e.state();
                let t = e.target();
                s[OBJ..OBJ + 3].copy_from_slice(&t);
                s[OBJ + 7..OBJ + 13].fill(0.0);
                e.set_state(&s).unwrap();
                let out = e.step_into(&grip(0.0, 0.0, 0.0, [0.0, 0.0, 8.0]), &mut obs).unwrap();
                assert!(e.last_info().hit, "object on the target scores a hit");
                assert!(out.reward >= HIT_BONUS - 1.0);
                let t = e.target();
                assert_eq!(&e.state()[TGT..TGT + 3], &t, "the new target is part of the state");
                targets.push(t);
            }
            targets
        };
        let mut all = Vec::new();
        for seed in 0..12 {
            let a = sequence(seed);
            assert_eq!(a, sequence(seed), "same seed, same targets");
            for t in &a {
                let r = t[0].hypot(t[1]);
                assert!(r >= radius - 1e-9 && r <= radius + dist + 1e-9, "r {r}");
                assert!(t[2] >= 0.0 && t[2] <= height, "z {}", t[2]);
            }
            all.extend(a);
        }
        let distinct = all.iter().filter(|t| **t != all[0]).count();
        assert!(distinct >= all.len() - 1, "targets vary");
        let spread = all.iter().map(|t| t[0].hypot(t[1])).fold(0.0f64, f64::max);
        assert!(spread > radius + 0.6 * dist, "targets use the distance range: {spread}");
    }
}

#[test]
fn reward_is_brax_s_formula() {
    let mut contacts = [false; 16];
    contacts[3] = true; // first fingertip: counts
    contacts[8] = true; // second fingertip: not in Brax's index list
    let input = RewardInput {
        palm: [0.0, 0.0, 5.0],
        object: [3.0, 4.0, 1.0],
        object_vel: [0.0, 2.0, 0.0],
        hand_vel: [0.6, 0.8, 0.0],
        target: [3.0, 10.0, 1.0],
        contacts,
        target_radius: 1.1,
    };
    let (info, total) = grasp_reward(&input);
    let d = (9.0f64 + 16.0 + 16.0).sqrt();
    let to_object = 0.1 * BRAX_DT * (0.6 * 3.0 + 0.8 * 4.0) / (1e-6 + d);
    let close = 0.1 * BRAX_DT / (1.0 + 5.0);
    let to_target = 1.5 * BRAX_DT * 2.0 * 6.0 / (1e-6 + 6.0);
    let touching = 0.2 * BRAX_DT;
    assert!((info.moving_to_object - to_object).abs() < 1e-12);
    assert!((info.close_to_object - close).abs() < 1e-12);
    assert!((info.moving_to_target - to_target).abs() < 1e-12);
    assert!((info.touching_object - touching).abs() < 1e-12);
    assert!(!info.hit);
    assert!((total - (to_object + close + to_target + touching)).abs() < 1e-12);
    // Within the radius: the hit bonus.
    let (hit, total_hit) = grasp_reward(&RewardInput {
        target: [3.0, 4.9, 1.0],
        ..input
    });
    assert!(hit.hit);
    assert!(
        (total_hit
            - HIT_BONUS
            - hit.moving_to_object
            - hit.close_to_object
            - hit.touching_object
            - hit.moving_to_target)
            .abs()
            < 1e-12
    );

    // A step's reward is the formula on the state after the step (the first step hits the
    // config target next to the object).
    let mut e = grasp_with(&[]);
    let mut obs = vec![0.0; 132];
    e.reset_into(Some(3), &mut obs).unwrap();
    let out = e.step_into(&grip(0.0, 0.0, 0.0, [0.0, 0.0, 6.0]), &mut obs).unwrap();
    let i = e.last_info();
    assert!(i.hit);
    let sum = i.moving_to_object + i.close_to_object + i.touching_object + i.moving_to_target + HIT_BONUS;
    assert!((out.reward - sum).abs() < 1e-9);
    assert_eq!(e.info()["hits"], 1.0);
}

/// Steps until the object, released at rest `h` above the ground, touches it.
fn fall_steps(gravity: f64, h: f64) -> (usize, f64) {
    let mut e = grasp_with(&[("gravity", gravity)]);
    let mut obs = vec![0.0; 132];
    e.reset_into(Some(0), &mut obs).unwrap();
    let mut s = e.state();
    s[OBJ..OBJ + 3].copy_from_slice(&[9.0, 9.0, OBJECT_RADIUS + h]);
    e.set_state(&s).unwrap();
    let a = grip(0.0, 0.0, 0.0, [0.0, 0.0, 8.0]);
    let mut z_at_half = f64::NAN;
    for k in 1..1000 {
        e.step_into(&a, &mut obs).unwrap();
        let z = e.object_position()[2];
        if k == 25 {
            z_at_half = z;
        }
        if z - OBJECT_RADIUS < 0.02 {
            return (k, z_at_half);
        }
    }
    (usize::MAX, z_at_half)
}

#[test]
fn released_object_falls_in_sqrt_2h_over_g() {
    for (g, h) in [(-9.8, 20.0), (-3.0, 12.0)] {
        let (steps, z_half) = fall_steps(g, h);
        let dt = 0.02;
        let expected = (2.0 * h / -g).sqrt() / dt;
        assert!(
            (steps as f64 - expected).abs() <= 2.0,
            "g {g}: {steps} steps, expected {expected:.1}"
        );
        let t = 25.0 * dt;
        let z = OBJECT_RADIUS + h + 0.5 * g * t * t;
        assert!((z_half - z).abs() < 0.05, "z(0.5 s) {z_half} vs {z}");
    }
}

/// Open the hand over the ball, close the fingers, then raise the palm: returns (highest
/// object position while lifting, steps the object was off the ground, fingertip contacts).
fn scripted_grasp(friction: f64) -> (f64, usize, usize) {
    let mut e = grasp_with(&[("friction", friction)]);
    let mut obs = vec![0.0; 132];
    e.reset_into(Some(0), &mut obs).unwrap();
    let (mut top, mut lifted, mut touches) = (0.0f64, 0, 0);
    for k in 0..100 {
        let palm = e.palm_position();
        let a = if k < 25 {
            grip(-45.0, 0.0, 0.0, [0.0, 0.0, 4.5])
        } else if k < 50 {
            grip(40.0, 90.0, 62.0, [0.0, 0.0, 4.5])
        } else {
            grip(40.0, 90.0, 62.0, [0.0, 0.0, palm[2] + 0.3])
        };
        e.step_into(&a, &mut obs).unwrap();
        assert!(!e.last_info().diverged);
        let z = e.object_position()[2];
        if k >= 50 {
            top = top.max(z);
            lifted += usize::from(z > OBJECT_RADIUS + 0.5);
        }
        touches += [3, 8, 11, 14].iter().filter(|&&i| e.contacts()[i]).count();
        assert_eq!(
            obs[116..132].iter().map(|&x| x as usize).collect::<Vec<_>>(),
            e.contacts().map(usize::from)
        );
    }
    (top, lifted, touches)
}

#[test]
fn closed_fingers_lift_the_ball_with_friction_and_lose_it_without() {
    let (top, lifted, touches) = scripted_grasp(0.6);
    assert!(touches > 20, "fingertips touch the ball: {touches}");
    assert!(
        top > 3.0 && lifted >= 30,
        "default friction lifts the ball: top {top}, {lifted} steps"
    );
    let (top0, lifted0, touches0) = scripted_grasp(0.01);
    assert!(touches0 > 0, "the fingers still reach the ball");
    assert!(
        top0 < 1.6 && lifted0 == 0,
        "without friction it slips: top {top0}, {lifted0} steps"
    );
}

#[test]
fn a_positive_joint_torque_rotates_each_finger_joint_positively() {
    let model = RobotModel::load("grasp").unwrap();
    let params = default_params("grasp").unwrap();
    let e = make_grasp(params.clone()).unwrap();
    let q = Configuration {
        root: Vec::new(),
        joints: e.home().to_vec(),
        vel: vec![0.0; 19],
    };
    let run = |ctrl: &[f32]| {
        let mut w = RobotWorld::build(&model, &params, &q);
        for _ in 0..20 {
            w.step(ctrl);
        }
        w.configuration().joints
    };
    let rest = run(&[0.0; 16]);
    for i in 0..16 {
        let mut ctrl = [0.0f32; 16];
        ctrl[i] = 0.2;
        let moved = run(&ctrl);
        let (j, _) = e.actuator(i).unwrap();
        assert!(moved[j] > rest[j] + 1e-3, "actuator {i}: {} vs {}", moved[j], rest[j]);
    }
    // The angle servo: commanding the upper limit moves a joint up, the lower limit down.
    for (i, hi) in [(2usize, true), (2, false), (5, true), (5, false)] {
        let mut g = grasp_with(&[("gravity", -0.1)]);
        let mut obs = vec![0.0; 132];
        g.reset_into(Some(0), &mut obs).unwrap();
        let (j, [lo, up]) = g.actuator(i).unwrap();
        let mut a = vec![0.0f32; 19];
        a[i] = if hi { 1.0 } else { -1.0 };
        a[18] = -0.5;
        for _ in 0..40 {
            g.step_into(&Action::Continuous(a.clone()), &mut obs).unwrap();
        }
        let x = g.state()[j];
        let want = if hi { up } else { lo };
        assert!((x - want).abs() < 0.1, "actuator {i} -> {x}, commanded {want}");
    }
}

#[test]
fn finite_at_the_spec_bounds() {
    common::finite_at_the_spec_bounds_for_a_task_without_termination(&spec(), &random_actions(40, 9));
}

#[test]
fn two_instances_with_different_contexts_interleaved_equal_each_alone() {
    let ctx_a = [("gravity", -9.8), ("friction", 0.6)];
    let ctx_b = [("gravity", -3.0), ("friction", 1.5), ("actuator_strength", 800.0)];
    let actions = random_actions(30, 4);
    let alone = |ctx: &[(&str, f64)]| {
        let mut e = env_with(ctx);
        e.reset(Some(2));
        actions.iter().map(|a| e.step(a).unwrap().obs).collect::<Vec<_>>()
    };
    let (ra, rb) = (alone(&ctx_a), alone(&ctx_b));
    assert_ne!(ra, rb);
    let mut a = env_with(&ctx_a);
    let mut b = env_with(&ctx_b);
    a.reset(Some(2));
    b.reset(Some(2));
    for (k, act) in actions.iter().enumerate() {
        assert_eq!(a.step(act).unwrap().obs, ra[k]);
        assert_eq!(b.step(act).unwrap().obs, rb[k]);
    }
}

#[test]
fn render_draws_the_hand_the_ball_and_the_target() {
    let mut e = env_with(&[]);
    assert!(e.render().is_none(), "nothing to draw before reset");
    e.reset(Some(0));
    let f = e.render().unwrap();
    assert_eq!(f.rgb.len(), (f.width * f.height * 3) as usize);
    let count = |f: &carl_spec::pixels::Frame, pred: &dyn Fn([u8; 3]) -> bool| {
        (0..f.height)
            .flat_map(|y| (0..f.width).map(move |x| (x, y)))
            .filter(|&(x, y)| pred(f.pixel(x, y)))
            .count()
    };
    let red = count(&f, &|p| p[0] > 150 && p[1] < 110 && p[2] < 100);
    assert!(red > 20, "target pixels {red}");
    // Brax's initial target surrounds the object: move it away to see the ball.
    let mut s = e.state();
    s[TGT..TGT + 3].copy_from_slice(&[6.0, 0.0, 4.0]);
    e.set_state(&s).unwrap();
    let g = e.render().unwrap();
    let yellow = count(&g, &|p| p[0] > 180 && p[1] > 150 && p[2] < 100);
    assert!(yellow > 20, "ball pixels {yellow}");
    let red = count(&g, &|p| p[0] > 150 && p[1] < 110 && p[2] < 100);
    assert!(red > 20, "target pixels {red}");
    assert_ne!(g, f);
    assert_eq!(e.render().unwrap(), g);
}
