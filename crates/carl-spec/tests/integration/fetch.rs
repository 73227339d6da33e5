//! Brax's fetch task on rapier3d: target placement and its reproducibility, Brax's reward on
//! constructed states, standing at rest, joint torque direction, friction and gravity, bounds and
//! divergence, independence of instances, observation layout, audit, rendering.

use crate::common;

use carl_spec::envs::brax::fetch::{OBS_DIM, TARGET_HEIGHT};
use carl_spec::envs::registry::{Context, MakeOptions, SpecEnv, make, make_with};
use carl_spec::envs::rng::EnvRng;
use carl_spec::envs::{Action, Env};
use carl_spec::spec::SpecSet;
use carl_spec::spec::model::{EnvSpec, Value};

/// State layout: root pose 0..7, joint angles 7..17, root velocities 17..23, joint rates
/// 23..33, target 33..36, contact flags 36..47.
const J: usize = 7;
const V: usize = 17;
const JV: usize = 23;
const T: usize = 33;
const C: usize = 36;
/// Environment step (s), Brax's dt.
const DT: f64 = 0.02;

fn spec() -> EnvSpec {
    SpecSet::bundled().unwrap().get("fetch").unwrap().clone()
}

fn env_with(ctx: &[(&str, f64)]) -> SpecEnv {
    let ctx: Context = ctx.iter().map(|(k, v)| (k.to_string(), Value::Number(*v))).collect();
    make_with(
        &spec(),
        &ctx,
        MakeOptions {
            allow_out_of_bounds: true,
        },
    )
    .unwrap()
}

fn random_actions(steps: usize, seed: u64) -> Vec<Action> {
    let mut rng = EnvRng::from_seed(seed);
    (0..steps)
        .map(|_| Action::Continuous((0..10).map(|_| (rng.next_f64() * 2.0 - 1.0) as f32).collect()))
        .collect()
}

fn zeros() -> Action {
    Action::Continuous(vec![0.0; 10])
}

fn one_joint(j: usize, u: f32) -> Action {
    let mut a = vec![0.0; 10];
    a[j] = u;
    Action::Continuous(a)
}

/// The state after `steps` zero-control steps from the reset of `seed`.
fn settled(e: &mut SpecEnv, seed: u64, steps: usize) -> Vec<f64> {
    e.reset(Some(seed));
    for _ in 0..steps {
        e.step(&zeros()).unwrap();
    }
    e.state()
}

/// Rotate `v` by the unit quaternion `(w, x, y, z)`.
fn rotate(q: &[f64], v: [f64; 3]) -> [f64; 3] {
    let (w, x, y, z) = (q[0], q[1], q[2], q[3]);
    let u = [x, y, z];
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let t = cross(u, v).map(|c| 2.0 * c);
    let ut = cross(u, t);
    [0, 1, 2].map(|i| v[i] + w * t[i] + ut[i])
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn pos(s: &[f64]) -> [f64; 3] {
    [s[0], s[1], s[2]]
}

/// Brax's fetch reward, written out from `brax/envs/fetch.py` for states `a` -> `b` (the target
/// of `b`'s step is `target`).
fn brax_reward(a: &[f64], b: &[f64], target: [f64; 3], radius: f64) -> (f64, bool) {
    let (p0, p1) = (pos(a), pos(b));
    let rel = [0, 1, 2].map(|i| target[i] - p1[i]);
    let dist = dot(rel, rel).sqrt();
    let dir = rel.map(|x| x / (1e-6 + dist));
    let moving = 0.1 * dot([0, 1, 2].map(|i| p1[i] - p0[i]), dir);
    let up = rotate(&b[3..7], [0.0, 0.0, 1.0]);
    let fwd = rotate(&b[3..7], [1.0, 0.0, 0.0]);
    let is_up = 0.1 * DT * up[2];
    let height = 0.1 * DT * p1[2];
    let hit = dist < radius;
    let weighted = if hit { dot(dir, fwd) } else { 0.0 };
    (height + moving + is_up + weighted, hit)
}

#[test]
fn targets_lie_in_the_configured_annulus_and_follow_the_seed() {
    for (dist, radius) in [(15.0, 2.0), (3.0, 0.5), (0.1, 5.0)] {
        let mut e = env_with(&[("target_distance", dist), ("target_radius", radius)]);
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        let mut quadrants = [false; 4];
        for seed in 0..64 {
            let (obs, _) = e.reset(Some(seed));
            assert_eq!(obs.len(), OBS_DIM);
            let t = &e.state()[T..T + 3];
            let r = t[0].hypot(t[1]);
            assert!(r >= radius - 1e-9 && r <= radius + dist + 1e-9, "r {r}");
            assert_eq!(t[2], TARGET_HEIGHT);
            lo = lo.min(r);
            hi = hi.max(r);
            quadrants[usize::from(t[0] > 0.0) * 2 + usize::from(t[1] > 0.0)] = true;
        }
        assert!(lo < radius + 0.2 * dist && hi > radius + 0.8 * dist, "{lo} {hi}");
        assert!(quadrants.iter().all(|q| *q));
    }
    // The whole target sequence of a seeded instance is reproducible: put each target 0.3 m
    // ahead of the torso centre, step, and read the replacement.
    let sequence = |seed: u64, d: f64, rad: f64| {
        let mut e = env_with(&[("target_distance", d), ("target_radius", rad)]);
        e.reset(Some(seed));
        let mut out = vec![e.state()[T..T + 3].to_vec()];
        for _ in 0..6 {
            let mut s = e.state();
            let t = [s[0] + 0.3, s[1], s[2]];
            s[T..T + 3].copy_from_slice(&t);
            e.set_state(&s).unwrap();
            let step = e.step(&zeros()).unwrap();
            assert_eq!(step.info["hit"], 1.0);
            let t = e.state()[T..T + 3].to_vec();
            let r = t[0].hypot(t[1]);
            assert!((rad..=rad + d).contains(&r), "{r}");
            out.push(t);
        }
        out
    };
    let a = sequence(7, 15.0, 2.0);
    assert_eq!(a, sequence(7, 15.0, 2.0));
    assert_ne!(a, sequence(8, 15.0, 2.0));
    // Same random numbers, other annulus: the directions agree, the distances follow the context.
    let b = sequence(7, 5.0, 1.0);
    for (p, q) in a.iter().zip(&b) {
        let (ra, rb) = (p[0].hypot(p[1]), q[0].hypot(q[1]));
        assert!(((ra - 2.0) / 15.0 - (rb - 1.0) / 5.0).abs() < 1e-9);
        assert!((p[1].atan2(p[0]) - q[1].atan2(q[0])).abs() < 1e-9);
    }
}

#[test]
fn reward_is_brax_s_fetch_reward() {
    let mut e = env_with(&[]);
    let mut s = settled(&mut e, 0, 10);
    // A far target: no hit, the target stays; reward = height + upright + moving terms.
    let far = [9.0, -4.0, TARGET_HEIGHT];
    s[T..T + 3].copy_from_slice(&far);
    e.set_state(&s).unwrap();
    let mut moved = 0.0f64;
    for a in random_actions(15, 4) {
        let before = e.state();
        let out = e.step(&a).unwrap();
        let after = e.state();
        let (want, hit) = brax_reward(&before, &after, far, 2.0);
        assert!(!hit);
        assert!((out.reward - want).abs() < 1e-6, "{} vs {want}", out.reward);
        assert_eq!(out.info["hit"], 0.0);
        assert_eq!(after[T..T + 3], far);
        moved += out.info["moving_to_target"].abs();
        assert!(!out.terminated);
    }
    assert!(moved > 1e-4, "the moving term never acted: {moved}");
    // Standing still: 0.1·dt·(up_z + z) per step.
    let s0 = settled(&mut e, 0, 30);
    let out = e.step(&zeros()).unwrap();
    let z = e.state()[2];
    assert!((out.reward - 0.1 * DT * (1.0 + z)).abs() < 2e-4, "{} {z}", out.reward);

    // A target 1.5 m ahead of the torso (about 1.55 m away): a hit for the default radius 2,
    // weighted by facing it (+1 ahead, -1 behind); none for radius 1; then a new target.
    for (radius, ahead, hit) in [(2.0, 1.5, true), (2.0, -1.5, true), (1.0, 1.5, false)] {
        let mut e = env_with(&[("target_radius", radius)]);
        e.reset(Some(0));
        let mut s = s0.clone();
        let t = [s[0] + ahead, s[1], TARGET_HEIGHT];
        s[T..T + 3].copy_from_slice(&t);
        e.set_state(&s).unwrap();
        let out = e.step(&zeros()).unwrap();
        let after = e.state();
        let (want, brax_hit) = brax_reward(&s, &after, t, radius);
        assert_eq!(brax_hit, hit);
        assert_eq!(out.info["hit"] == 1.0, hit, "radius {radius}");
        assert!((out.reward - want).abs() < 1e-6, "{} vs {want}", out.reward);
        if hit {
            let weighted = out.info["weighted_hit"];
            assert!((weighted - ahead.signum() * 0.97).abs() < 0.03, "{weighted}");
            assert_eq!(out.info["hits"], 1.0);
            let new = &after[T..T + 3];
            assert!((2.0..=17.0).contains(&new[0].hypot(new[1])));
            assert_eq!(new[2], TARGET_HEIGHT);
        } else {
            assert_eq!(after[T..T + 3], t);
            assert!(out.reward.abs() < 0.01);
        }
    }
}

#[test]
fn the_dog_stands_and_settles_with_zero_control() {
    let mut e = env_with(&[]);
    let (obs, _) = e.reset(Some(3));
    // Brax's default pose: level torso 1.375 m up (5 mm margin), all joints at 0, at rest.
    assert_eq!(obs[0..6], [1.0, 0.0, 0.0, 0.0, 0.0, 1.0]);
    let s0 = e.state();
    assert!((s0[2] - 1.38).abs() < 1e-6);
    assert!(s0[J..T].iter().all(|x| *x == 0.0));
    for _ in 0..100 {
        e.step(&zeros()).unwrap();
    }
    let s = e.state();
    assert!((1.3..1.4).contains(&s[2]), "torso height {}", s[2]);
    assert!(s[0].abs() < 0.02 && s[1].abs() < 0.02, "drifted to {} {}", s[0], s[1]);
    let up = rotate(&s[3..7], [0.0, 0.0, 1.0]);
    assert!(up[2] > 0.999, "{up:?}");
    assert!(s[V..T].iter().all(|v| v.abs() < 0.05), "not at rest: {:?}", &s[V..T]);
    assert!(s[J..V].iter().all(|q| q.abs() < 0.05), "joints {:?}", &s[J..V]);
    // Only the four lower legs touch the ground (Brax's collide_include).
    let lower = [4, 6, 8, 10];
    for (i, f) in s[C..].iter().enumerate() {
        assert_eq!(*f, f64::from(u8::from(lower.contains(&i))), "link {i}");
    }
    // Observation: the lower legs' and the Ground's contact flags.
    let mut o = vec![0.0f32; OBS_DIM];
    e.inner().observe_into(&mut o).unwrap();
    let flags = &o[OBS_DIM - 13..];
    assert_eq!(flags, [0., 0., 0., 0., 1., 0., 1., 0., 1., 0., 1., 1., 0.]);
}

#[test]
fn positive_hip_torque_turns_the_hip_positively_about_its_axis() {
    // In the air (no ground reaction), the front right hip driven alone.
    for (u, sign) in [(1.0f32, 1.0), (-1.0, -1.0)] {
        let mut e = env_with(&[("gravity", -0.1)]);
        e.reset(Some(0));
        let mut s = e.state();
        s[2] = 4.0;
        e.set_state(&s).unwrap();
        let mut o0 = vec![0.0f32; OBS_DIM];
        e.inner().observe_into(&mut o0).unwrap();
        let mut last = Vec::new();
        for _ in 0..5 {
            last = e.step(&one_joint(2, u)).unwrap().obs;
        }
        let s = e.state();
        assert!(
            sign * s[J + 2] > 0.02 && sign * s[JV + 2] > 0.1,
            "u {u}: angle {} rate {}",
            s[J + 2],
            s[JV + 2]
        );
        // The other hinges barely move (reaction only).
        assert!(s[J + 2].abs() > 5.0 * s[J + 4].abs());
        // About +y: a positive turn swings the upper leg's centre (below the hip) backwards
        // (−x in the torso frame); body 3's local position is at obs[10 + 9..].
        let dx = f64::from(last[19] - o0[19]);
        assert!(sign * dx < -0.003, "u {u}: dx {dx}");
    }
}

/// Torso x after 25 zero-control steps of the settled dog pushed forward at 3 m/s.
fn slide(friction: f64) -> f64 {
    let mut e = env_with(&[("friction", friction)]);
    let mut s = settled(&mut e, 0, 10);
    let x0 = s[0];
    s[V] = 3.0;
    e.set_state(&s).unwrap();
    for _ in 0..25 {
        e.step(&zeros()).unwrap();
    }
    e.state()[0] - x0
}

/// Torso drop over 10 zero-control steps from 0.5 m above the standing pose.
fn drop(gravity: f64) -> f64 {
    let mut e = env_with(&[("gravity", gravity)]);
    e.reset(Some(0));
    let mut s = e.state();
    s[2] += 0.5;
    let z0 = s[2];
    e.set_state(&s).unwrap();
    for _ in 0..10 {
        e.step(&zeros()).unwrap();
    }
    z0 - e.state()[2]
}

#[test]
fn friction_and_gravity_change_the_motion() {
    let (slippery, grippy) = (slide(0.1), slide(1.2));
    assert!(slippery > grippy + 0.1, "slid {slippery} vs {grippy}");
    assert!(slippery > 0.5, "{slippery}");
    // Free fall for 0.2 s: ½ g t².
    for g in [9.8, 3.0] {
        let d = drop(-g);
        let want = 0.5 * g * 0.2 * 0.2;
        assert!((d - want).abs() < 0.15 * want, "g {g}: fell {d}, free fall {want}");
    }
}

#[test]
fn finite_at_the_spec_bounds_and_divergence_is_flagged() {
    common::finite_at_the_spec_bounds_for_a_task_without_termination(&spec(), &random_actions(60, 9));
    // A runaway instance (huge torques, no joint damping, angular anti-damping) is rolled back,
    // flagged and terminated.
    let out = common::runaway_is_flagged(
        &spec(),
        &[
            ("actuator_strength", 1e9),
            ("joint_angular_damping", 0.0),
            ("angular_damping", 50.0),
        ],
        &random_actions(50, 2),
    );
    assert_eq!(out.info["hit"], 0.0);
}

#[test]
fn instances_with_different_contexts_do_not_interfere() {
    let actions = random_actions(40, 5);
    let ctx_a: &[(&str, f64)] = &[("gravity", -9.8), ("target_distance", 15.0)];
    let ctx_b: &[(&str, f64)] = &[("gravity", -3.0), ("target_distance", 4.0), ("torso_mass", 3.0)];
    let alone = |ctx: &[(&str, f64)]| {
        let mut e = env_with(ctx);
        let mut out = vec![e.reset(Some(3)).0];
        for a in &actions {
            out.push(e.step(a).unwrap().obs);
        }
        (out, e.state())
    };
    let (a_alone, b_alone) = (alone(ctx_a), alone(ctx_b));
    assert_ne!(a_alone.0, b_alone.0);
    let mut a = env_with(ctx_a);
    let mut b = env_with(ctx_b);
    let mut a_mix = vec![a.reset(Some(3)).0];
    let mut b_mix = vec![b.reset(Some(3)).0];
    for act in &actions {
        a_mix.push(a.step(act).unwrap().obs);
        b_mix.push(b.step(act).unwrap().obs);
    }
    assert_eq!(a_mix, a_alone.0);
    assert_eq!(b_mix, b_alone.0);
    assert_eq!(a.state(), a_alone.1);
    assert_eq!(b.state(), b_alone.1);
    // A clone has the same state and continues like its original (its world is rebuilt from
    // the state; rapier's warm-start caches start empty, so not to the last bit).
    let mut c = a.clone();
    assert!(c.state().iter().zip(a.state()).all(|(x, y)| (x - y).abs() < 1e-5));
    let (x, y) = (a.step(&actions[0]).unwrap(), c.step(&actions[0]).unwrap());
    assert!((x.reward - y.reward).abs() < 1e-4, "{} {}", x.reward, y.reward);
}

#[test]
fn observation_is_brax_s_egocentric_layout() {
    let mut e = env_with(&[]);
    let mut s = settled(&mut e, 2, 5);
    // Turn the dog 90° about z and give it a world +x velocity.
    let h = std::f64::consts::FRAC_PI_4;
    s[3..7].copy_from_slice(&[h.cos(), 0.0, 0.0, h.sin()]);
    s[V] = 1.0;
    let t = [s[0], s[1] + 5.0, TARGET_HEIGHT];
    s[T..T + 3].copy_from_slice(&t);
    e.set_state(&s).unwrap();
    let mut o = vec![0.0f32; OBS_DIM];
    e.inner().observe_into(&mut o).unwrap();
    let near = |a: &[f32], b: [f64; 3]| a.iter().zip(b).all(|(x, y)| (f64::from(*x) - y).abs() < 1e-4);
    assert!(near(&o[0..3], [0.0, 1.0, 0.0]), "fwd {:?}", &o[0..3]);
    assert!(near(&o[3..6], [0.0, 0.0, 1.0]), "up {:?}", &o[3..6]);
    // The target is 5 m straight ahead (in the torso frame +x), lower by z − 1.
    let dz = TARGET_HEIGHT - s[2];
    let d = (25.0 + dz * dz).sqrt();
    assert!((f64::from(o[6]) - d).abs() < 1e-4);
    assert!(near(&o[7..10], [5.0 / d, 0.0, dz / d]));
    // Body centres in the torso frame: Torso at 0, Shoulders 1 m ahead, Ground, Target.
    let p = |b: usize| &o[10 + 3 * b..13 + 3 * b];
    assert!(near(p(0), [0.0; 3]));
    assert!(near(p(1), [1.0, 0.0, 0.0]));
    assert!(near(p(11), [0.0, 0.0, -s[2]]));
    assert!(near(p(12), [5.0, 0.0, dz]));
    // Velocities in the torso frame: world +x is the torso's −y; Ground and Target at rest.
    let v = |b: usize| &o[49 + 3 * b..52 + 3 * b];
    assert!(near(v(0), [0.0, -1.0, 0.0]), "{:?}", v(0));
    assert!(near(v(11), [0.0; 3]) && near(v(12), [0.0; 3]));
    // While moving, the body velocities agree with rapier's own body velocities (which lag
    // by the last physics step: rapier refreshes them before its solver runs).
    for a in random_actions(8, 6) {
        e.step(&a).unwrap();
    }
    let mut o = vec![0.0f32; OBS_DIM];
    e.inner().observe_into(&mut o).unwrap();
    let v = |b: usize| &o[49 + 3 * b..52 + 3 * b];
    let f = e
        .inner()
        .downcast_ref::<carl_spec::envs::brax::Fetch>()
        .expect("fetch runs as Fetch");
    let w = f.world().unwrap();
    let inv = w.link_pose(0).rotation.inverse();
    let rapier: Vec<_> = w.links.iter().map(|&h| inv * w.pw.bodies[h].linvel()).collect();
    let fast = rapier.iter().map(|r| r.length()).fold(0.0f32, f32::max);
    assert!(fast > 0.2, "{fast}");
    for (b, rv) in rapier.iter().enumerate() {
        let ov = v(b);
        let err = (rv.x - ov[0]).abs() + (rv.y - ov[1]).abs() + (rv.z - ov[2]).abs();
        assert!(err < 0.1 * fast + 0.02, "body {b}: {rv:?} vs {ov:?}");
    }
}

#[test]
fn bad_input_is_an_error() {
    let mut e = env_with(&[]);
    assert!(e.step(&zeros()).is_err(), "step before reset");
    e.reset(Some(0));
    assert!(e.step(&Action::Continuous(vec![0.0; 9])).is_err());
    assert!(e.step(&Action::Discrete(1)).is_err());
    assert!(e.set_state(&[0.0; 5]).is_err());
    // Non-finite state values and actions are refused.
    let mut s = e.state();
    s[0] = f64::NAN;
    assert!(e.set_state(&s).is_err());
    let err = e.step(&Action::Continuous(vec![f32::NAN; 10])).unwrap_err().to_string();
    assert!(err.contains("action component 0 is not finite"), "{err}");
    let ctx = Context::from([("target_radius".to_string(), Value::Number(0.0))]);
    assert!(make(&spec(), &ctx).is_err(), "below the bound");
}

#[test]
fn render_draws_the_dog_and_the_target() {
    let mut e = env_with(&[]);
    assert!(e.render().is_none(), "nothing to draw before reset");
    e.reset(Some(0));
    let f = e.render().unwrap();
    assert_eq!(f.rgb.len(), (f.width * f.height * 3) as usize);
    let pixels = |f: &carl_spec::pixels::Frame, pred: &dyn Fn([u8; 3]) -> bool| {
        (0..f.height)
            .flat_map(|y| (0..f.width).map(move |x| (x, y)))
            .filter(|&(x, y)| pred(f.pixel(x, y)))
            .count()
    };
    let red = pixels(&f, &|p| p[0] > 150 && p[1] < 110 && p[2] < 100);
    assert!(red > 20, "target pixels {red}");
    let sky = [214u8, 228, 240];
    let ground = [[196u8, 206, 186], [178, 190, 168]];
    let near = |p: [u8; 3], q: [u8; 3]| p.iter().zip(q).all(|(a, b)| (i32::from(*a) - i32::from(b)).abs() < 12);
    let other = pixels(&f, &|p| !near(p, sky) && !ground.iter().any(|g| near(p, *g)));
    assert!(other > red + 200, "dog pixels {}", other - red);
    // The picture follows the state: another pose, another target.
    let mut s = e.state();
    s[J + 2] = 0.8;
    e.set_state(&s).unwrap();
    let g = e.render().unwrap();
    assert_ne!(g, f);
    s[T] = -s[T];
    e.set_state(&s).unwrap();
    assert_ne!(e.render().unwrap(), g);
    assert_eq!(e.render().unwrap(), e.render().unwrap());
}
