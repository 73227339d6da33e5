//! BipedalWalker on the Box2D-semantics engine (src/physics2d): observation layout and
//! normalisation, determinism across instances and seeds, falling, lidar against flat ground and stumps, the scripted gait,
//! context sensitivity, bad input and rendering.

use carl_spec::envs::box2d::bipedal_walker::{HIP_LIMITS, HIP_REFERENCE, Obstacle, STATE_DIM};
use carl_spec::envs::box2d::{BipedalWalker, BipedalWalkerOptions, BipedalWalkerParams, WalkerHeuristic};
use carl_spec::envs::registry::{Context, make};
use carl_spec::envs::{Action, Env, EnvError};
use carl_spec::physics2d::settings::ANGULAR_SLOP;
use carl_spec::spec::SpecSet;
use carl_spec::spec::model::Value;

fn walker(p: BipedalWalkerParams) -> BipedalWalker {
    BipedalWalker::new(p)
}

fn act(a: [f32; 4]) -> Action {
    Action::Continuous(a.to_vec())
}

/// Run the scripted gait for at most `n` steps: (observations, rewards, terminated).
fn gait(env: &mut BipedalWalker, seed: u64, n: usize) -> (Vec<Vec<f32>>, Vec<f64>, bool) {
    let mut h = WalkerHeuristic::default();
    let (mut obs, _) = env.reset(Some(seed));
    let mut trace = vec![obs.clone()];
    let mut rewards = Vec::new();
    for _ in 0..n {
        let st = env.step(&act(h.act(&obs))).unwrap();
        obs = st.obs;
        trace.push(obs.clone());
        rewards.push(st.reward);
        if st.terminated {
            return (trace, rewards, true);
        }
    }
    (trace, rewards, false)
}

/// Lidar fraction of ray `i` from height `h` above flat ground (Gymnasium's ray directions).
fn flat_fraction(i: usize, h: f64, range: f64) -> f64 {
    let a = 1.5 * i as f64 / 10.0;
    (h / (a.cos() * range)).min(1.0)
}

#[test]
fn observation_layout_and_normalisation_at_reset() {
    let p = BipedalWalkerParams::default();
    let mut env = walker(p);
    let (obs, _) = env.reset(Some(0));
    assert_eq!(obs.len(), 24);
    assert!(env.observation_space().flat_dim() == 24 && env.action_space().flat_dim() == 4);
    let b = env.body_states().unwrap();
    let hull = b[0];
    // Hull: angle, 2ω/FPS, 0.3·v·(VIEWPORT/SCALE)/FPS.
    assert_eq!(obs[0], hull.angle as f32);
    assert_eq!(obs[1], (2.0 * hull.w / p.fps) as f32);
    assert_eq!(obs[2], (0.3 * hull.vx * (p.viewport_w / p.scale) / p.fps) as f32);
    assert_eq!(obs[3], (0.3 * hull.vy * (p.viewport_h / p.scale) / p.fps) as f32);
    // One step of free fall onto the pad: vy ≈ g·dt = -0.2 m/s, as in Gymnasium (obs[3] = -0.016).
    assert!((obs[3] + 0.016).abs() < 0.002, "{}", obs[3]);
    // Joints: hip angle, hip speed / SPEED_HIP, knee angle + 1, knee speed / SPEED_KNEE.
    for leg in 0..2 {
        let o = 4 + 5 * leg;
        let (hull_b, upper, lower) = (b[0], b[1 + 2 * leg], b[2 + 2 * leg]);
        // Box2D's joint angle: relative angle minus the reference angle pybox2d recorded.
        let hip = upper.angle - hull_b.angle - HIP_REFERENCE[leg];
        let knee = lower.angle - upper.angle;
        assert!((obs[o] as f64 - hip).abs() < 1e-5, "leg {leg}: {} vs {hip}", obs[o]);
        // Gymnasium 1.4, seed 0, reset observation (after its first step, in which Box2D's
        // position solver starts reassembling the legs created apart): hips 0.0918 / 0.0322,
        // knees + 1 = 0.8604 / 0.8539.
        let (hip_want, knee_want) = ([0.0918, 0.0322][leg], [0.8604, 0.8539][leg]);
        assert!((obs[o] as f64 - hip_want).abs() < 0.01, "hip {leg}: {}", obs[o]);
        assert!(
            (obs[o + 2] as f64 - knee_want).abs() < 0.01,
            "knee {leg}: {}",
            obs[o + 2]
        );
        assert!((obs[o + 1] as f64 - (upper.w - hull_b.w) / p.speed_hip).abs() < 1e-5);
        assert!((obs[o + 2] as f64 - (knee + 1.0)).abs() < 1e-5);
        assert!((obs[o + 3] as f64 - (lower.w - upper.w) / p.speed_knee).abs() < 1e-5);
        // The walker starts with both feet on the pad.
        assert_eq!(obs[o + 4], 1.0, "leg {leg} contact");
    }
    // Lidar over the flat start pad: fraction = min(1, h / (cos(angle)·LIDAR_RANGE)).
    let h = hull.y - p.terrain_height;
    assert!((h - 2.351).abs() < 0.005, "hull {h} m above the pad (Gymnasium: 2.351)");
    for i in 0..10 {
        let want = flat_fraction(i, h, p.lidar_range);
        assert!(
            (obs[14 + i] as f64 - want).abs() < 1e-5,
            "ray {i}: {} vs {want}",
            obs[14 + i]
        );
    }
    assert!(env.observation_space().contains_obs(&obs));
}

trait ContainsObs {
    fn contains_obs(&self, obs: &[f32]) -> bool;
}
impl ContainsObs for carl_spec::envs::Space {
    fn contains_obs(&self, obs: &[f32]) -> bool {
        self.contains(&Action::Continuous(obs.to_vec()))
    }
}

#[test]
fn normalisations_follow_the_context() {
    let base = BipedalWalkerParams::default();
    let mut a = walker(base);
    a.reset(Some(5));
    for _ in 0..20 {
        a.step(&act([0.5, -0.5, 0.3, 0.8])).unwrap();
    }
    let s = a.state();
    let oa = a.observe();
    let scaled = BipedalWalkerParams {
        viewport_w: 2.0 * base.viewport_w,
        viewport_h: 3.0 * base.viewport_h,
        speed_hip: 2.0 * base.speed_hip,
        speed_knee: 4.0 * base.speed_knee,
        lidar_range: 2.0 * base.lidar_range,
        ..base
    };
    let mut b = walker(scaled);
    b.reset(Some(5));
    b.set_state(&s).unwrap();
    let ob = b.observe();
    let close = |x: f32, y: f32| (x - y).abs() <= 1e-5 * (1.0 + x.abs());
    assert!(close(ob[2], 2.0 * oa[2]) && close(ob[3], 3.0 * oa[3]), "{oa:?} {ob:?}");
    for leg in 0..2 {
        let o = 4 + 5 * leg;
        assert!(close(ob[o + 1], oa[o + 1] / 2.0) && close(ob[o + 3], oa[o + 3] / 4.0));
        assert_eq!((ob[o], ob[o + 2], ob[o + 4]), (oa[o], oa[o + 2], oa[o + 4]));
    }
    // Doubling the lidar range halves every fraction that hit something.
    for i in 14..24 {
        if oa[i] < 0.45 {
            assert!(close(ob[i], oa[i] / 2.0), "ray {}: {} vs {}", i - 14, ob[i], oa[i]);
        }
    }
}

#[test]
fn alternating_two_walkers_equals_each_alone() {
    let pa = BipedalWalkerParams::default();
    let pb = BipedalWalkerParams {
        gravity_y: -4.0,
        motors_torque: 150.0,
        ..Default::default()
    };
    let n = 300;
    let (alone_a, ra, _) = gait(&mut walker(pa), 7, n);
    let (alone_b, rb, _) = gait(&mut walker(pb), 7, n);
    let (mut a, mut b) = (walker(pa), walker(pb));
    let (mut ha, mut hb) = (WalkerHeuristic::default(), WalkerHeuristic::default());
    let (mut oa, _) = a.reset(Some(7));
    let (mut ob, _) = b.reset(Some(7));
    let (mut ta, mut tb) = (vec![oa.clone()], vec![ob.clone()]);
    let (mut rwa, mut rwb) = (Vec::new(), Vec::new());
    let (mut done_a, mut done_b) = (false, false);
    for _ in 0..n {
        if !done_a {
            let st = a.step(&act(ha.act(&oa))).unwrap();
            done_a = st.terminated;
            oa = st.obs;
            ta.push(oa.clone());
            rwa.push(st.reward);
        }
        if !done_b {
            let st = b.step(&act(hb.act(&ob))).unwrap();
            done_b = st.terminated;
            ob = st.obs;
            tb.push(ob.clone());
            rwb.push(st.reward);
        }
    }
    assert_eq!(ta, alone_a);
    assert_eq!(tb, alone_b);
    assert_eq!((rwa, rwb), (ra, rb));
    assert_ne!(ta, tb);
}

#[test]
fn seeds_reproduce_runs_and_change_the_terrain() {
    let mut env = walker(BipedalWalkerParams::default());
    let (t1, r1, _) = gait(&mut env, 11, 200);
    let terrain11 = env.terrain().unwrap().clone();
    let (t2, r2, _) = gait(&mut env, 11, 200);
    assert_eq!((t1, r1), (t2, r2));
    assert_eq!(&terrain11, env.terrain().unwrap());
    env.reset(Some(12));
    let terrain12 = env.terrain().unwrap();
    assert_ne!(terrain11.y, terrain12.y);
    // The start pad is the same flat stretch for every seed; the course after it differs.
    assert_eq!(terrain11.y[..=20], terrain12.y[..=20]);
    // Hardcore courses differ in their obstacles too.
    let hc = BipedalWalkerOptions {
        hardcore: true,
        ..Default::default()
    };
    let mut h = BipedalWalker::with_options(BipedalWalkerParams::default(), hc);
    h.reset(Some(1));
    let q1 = h.terrain().unwrap().quads.clone();
    h.reset(Some(2));
    assert!(!q1.is_empty());
    assert_ne!(&q1, &h.terrain().unwrap().quads);
}

#[test]
fn zero_action_falls_with_minus_100_and_stays_finite() {
    let mut env = walker(BipedalWalkerParams::default());
    env.reset(Some(0));
    let mut last = None;
    for k in 0..500 {
        let st = env.step(&act([0.0; 4])).unwrap();
        assert!(st.obs.iter().all(|x| x.is_finite()));
        if st.terminated {
            last = Some((k, st.reward));
            break;
        }
    }
    // Gymnasium's walker, limp, folds at the knees and tips over onto its hull (~60 steps).
    let (k, r) = last.expect("the limp walker never fell");
    assert_eq!(r, -100.0);
    assert!(env.game_over());
    assert!((20..400).contains(&k), "fell after {k} steps");
}

#[test]
fn extreme_contexts_stay_finite() {
    let specs = SpecSet::bundled().unwrap();
    let spec = specs.get("bipedal_walker").unwrap();
    for f in &spec.features {
        for bound in f.bounds.iter().flatten() {
            let ctx = Context::from([(f.name.clone(), Value::Number(*bound))]);
            let mut env = make(spec, &ctx).unwrap();
            let (obs, _) = env.reset(Some(3));
            assert!(obs.iter().all(|x| x.is_finite()), "{} = {bound}: {obs:?}", f.name);
            let mut h = WalkerHeuristic::default();
            let mut obs = obs;
            for k in 0..200 {
                let a = if k % 2 == 0 {
                    h.act(&obs)
                } else {
                    [1.0, -1.0, -1.0, 1.0]
                };
                let st = env.step(&act(a)).unwrap();
                assert!(
                    st.obs.iter().all(|x| x.is_finite()) && st.reward.is_finite(),
                    "{} = {bound}, step {k}: {:?}",
                    f.name,
                    st.obs
                );
                obs = st.obs;
                if st.terminated {
                    break;
                }
            }
        }
    }
}

#[test]
fn leaving_the_course_to_the_left_terminates_with_minus_100() {
    let mut env = walker(BipedalWalkerParams::default());
    env.reset(Some(0));
    let mut s = env.state();
    s[0] = 0.02; // hull x
    s[3] = -5.0; // moving left at 5 m/s
    env.set_state(&s).unwrap();
    let st = env.step(&act([0.0; 4])).unwrap();
    assert!(st.terminated);
    assert_eq!(st.reward, -100.0);
    assert!(!env.game_over(), "terminated by x < 0, not by a hull contact");
}

#[test]
fn crossing_the_finish_line_terminates_without_penalty() {
    let p = BipedalWalkerParams::default();
    let mut env = walker(p);
    env.reset(Some(0));
    let mut s = env.state();
    let terrain = env.terrain().unwrap().clone();
    let x = p.finish_x() + 0.05;
    let dy = terrain.height_at(x) - terrain.height_at(s[0]);
    s[0] = x;
    s[1] += dy + 0.3;
    s[17] = 0.0; // no previous shaping: the first reward is 0 minus the (zero) torque cost
    env.set_state(&s).unwrap();
    let st = env.step(&act([0.0; 4])).unwrap();
    assert!(st.terminated);
    assert_eq!(st.reward, 0.0);
    // A shorter course ends earlier.
    let mut short = walker(BipedalWalkerParams {
        terrain_length: 100.0,
        ..p
    });
    short.reset(Some(0));
    let mut s = short.state();
    s[0] = (100.0 - 10.0) * p.terrain_step + 0.05;
    short.set_state(&s).unwrap();
    assert!(short.step(&act([0.0; 4])).unwrap().terminated);
}

#[test]
fn lidar_sees_a_stump_closer_than_the_ground() {
    let p = BipedalWalkerParams::default();
    let opts = BipedalWalkerOptions {
        hardcore: true,
        ..Default::default()
    };
    let mut env = BipedalWalker::with_options(p, opts);
    let mut found = false;
    for seed in 0..20 {
        env.reset(Some(seed));
        let terrain = env.terrain().unwrap().clone();
        let Some(k) = terrain.kinds.iter().position(|k| *k == Obstacle::Stump) else {
            continue;
        };
        let q = terrain.quads[k];
        let (x0, y0) = q[0];
        // Hull 1.5 m before the stump's left face, 2 m above its base.
        let mut s = env.state();
        let dy = y0 + 2.0 - s[1];
        s[0] = x0 - 1.5;
        s[1] += dy;
        env.set_state(&s).unwrap();
        let obs = env.observe();
        let pos = env.body_states().unwrap()[0];
        let mut flat = terrain.clone();
        flat.quads.clear();
        let mut shorter = 0;
        for i in 0..10 {
            let a = 1.5 * i as f64 / 10.0;
            let p1 = (pos.x, pos.y);
            let p2 = (pos.x + a.sin() * p.lidar_range, pos.y - a.cos() * p.lidar_range);
            let with = terrain.ray_fraction(p1, p2);
            let without = flat.ray_fraction(p1, p2);
            assert_eq!(obs[14 + i], with as f32);
            assert!(with <= without);
            if with < without - 0.01 {
                shorter += 1;
            }
        }
        assert!(shorter >= 2, "seed {seed}: only {shorter} rays see the stump");
        found = true;
        break;
    }
    assert!(found, "no stump in 20 hardcore courses");
}

/// Gymnasium's protocol (`bipedal_walker.py`'s `__main__`): reset, one zero action, then the
/// scripted gait; at most 1600 steps. Returns (return, length, final hull x).
fn gymnasium_protocol(seed: u64) -> (f64, usize, f64) {
    let mut env = walker(BipedalWalkerParams::default());
    env.reset(Some(seed));
    let mut h = WalkerHeuristic::default();
    let (mut a, mut ret, mut len) = ([0.0f32; 4], 0.0, 0);
    loop {
        let st = env.step(&act(a)).unwrap();
        ret += st.reward;
        len += 1;
        if st.terminated || len >= 1600 {
            return (ret, len, env.body_states().unwrap()[0].x);
        }
        a = h.act(&st.obs);
    }
}

#[test]
fn scripted_gait_row_is_pinned() {
    // carl-spec's side of the README's gait table (seeds 0-9 of its 30), deterministic:
    // changing the walker's physics changes these numbers on purpose only. Gymnasium 1.4 on its
    // own seeds 0-9: 6 positive returns, 6 past 40 m (the README table).
    let rows: Vec<(f64, usize, f64)> = (0..10).map(gymnasium_protocol).collect();
    let positive = rows.iter().filter(|r| r.0 > 0.0).count();
    let past_40 = rows.iter().filter(|r| r.2 > 40.0).count();
    let lengths: usize = rows.iter().map(|r| r.1).sum();
    assert_eq!((positive, past_40, lengths), PINNED_GAIT_ROW, "{rows:?}");
    // Every episode leaves the start: the gait takes at least one stride.
    for (seed, r) in rows.iter().enumerate() {
        assert!(
            r.2 > BipedalWalkerParams::default().init_x() + 0.5,
            "seed {seed}: x {}",
            r.2
        );
    }
}

/// (positive returns, past 40 m, total length) of [`scripted_gait_row_is_pinned`].
const PINNED_GAIT_ROW: (usize, usize, usize) = (8, 7, 9265);

/// A Gymnasium walker state (seed 0, scripted gait, flat start pad) loaded here: hull (origin x,
/// y, angle, vx, vy, ω), joint angles from the reference angles, joint speeds, contact flags.
/// Box2D rests its polygons 0.015 m off the ground (two 0.01 m skins minus 0.005 m slop), and so
/// does the Box2D-semantics engine: the state loads as recorded.
fn load_box2d_state(hull: [f64; 6], q: [f64; 4], dq: [f64; 4], contact: [f64; 2]) -> BipedalWalker {
    let p = BipedalWalkerParams {
        terrain_height: 400.0 / 30.0 / 4.0, // Gymnasium's TERRAIN_HEIGHT: the same flat start pad
        ..BipedalWalkerParams::default()
    };
    let mut env = BipedalWalker::new(p);
    env.reset(Some(0));
    let mut s = env.state();
    s[..6].copy_from_slice(&hull);
    s[6..10].copy_from_slice(&q);
    s[10..14].copy_from_slice(&dq);
    s[14..16].copy_from_slice(&contact);
    env.set_state(&s).unwrap();
    env
}

/// Box2D's first push-off, replayed: Gymnasium 1.4's walker (seed 0, scripted gait) at step 98,
/// standing on both feet, gets action 99 (supporting knee at full torque). Box2D lifts the hull
/// (vy −0.27 → +0.21 m/s).
#[test]
fn push_off_lifts_the_hull_as_in_box2d() {
    let mut env = load_box2d_state(
        [
            5.576474666595459,
            5.485766887664795,
            0.05302462726831436,
            1.9589295387268066,
            -0.2699141204357147,
            0.825517475605011,
        ],
        [
            -0.1143953949213028,
            -0.8405235409736633,
            0.7254852652549744,
            -1.1512845754623413,
        ],
        [
            -2.6789698600769043,
            1.7487534284591675,
            -1.0069942474365234,
            -1.6326321363449097,
        ],
        [1.0, 1.0],
    );
    let a = [0.0486266054213047f64, 1.0, -0.20137318968772888, 0.19596163928508759].map(|x| x as f32);
    env.step(&act(a)).unwrap();
    let h = env.state();
    // Box2D after the step: vx 2.249, vy +0.210, ω 1.214.
    for (name, got, want) in [
        ("vx", h[3], 2.249178171157837),
        ("vy", h[4], 0.21010462939739227),
        ("w", h[5], 1.214494228363037),
    ] {
        assert!((got - want).abs() < 0.03, "{name}: {got} here, {want} in Box2D");
    }
}

/// A foot landing, replayed: Gymnasium 1.4's walker (seed 0, scripted gait) at step 126 swings
/// leg 1 down (knee at +6 rad/s, lower leg falling at 3.6 m/s) and lands it within the step.
/// Box2D's continuous collision stops the lower leg inside that step (knee speed 6.0 → −0.95,
/// lower leg vy −0.14) and the leg's contact flag is set, so the scripted gait ends the swing at
/// once (the former rapier2d engine's contact acted one step later, through the whole leg).
#[test]
fn foot_landing_stops_the_lower_leg_inside_the_step_as_in_box2d() {
    let hull = [
        7.177334308624268,
        5.487006187438965,
        -0.05940749868750572,
        3.2069270610809326,
        -0.5723114609718323,
        0.8598585724830627,
    ];
    let q = [
        -0.07580478489398956,
        -0.7507901191711426,
        0.9089997410774231,
        -1.2020463943481445,
    ];
    let dq = [
        -3.7876927852630615,
        2.7450220584869385,
        -2.8770084381103516,
        6.000000953674316,
    ];
    let a = [
        -0.0009376164525747299,
        -0.01222085952758789,
        -0.27508094906806946,
        0.8224796652793884,
    ]
    .map(|x| x as f32);
    let mut env = load_box2d_state(hull, q, dq, [0.0, 0.0]);
    let obs = env.step(&act(a)).unwrap().obs;
    let (s, bodies) = (env.state(), env.body_states().unwrap());
    // Box2D after the step: leg 1 touches (observation 13), knee 1 at −0.95 rad/s, lower leg 1
    // (vx, vy, ω) = (2.20, −0.14, −3.77), hull (vx, vy, ω) = (3.250, −0.758, 1.110). Tolerances
    // are about three times this engine's error (measured: knee 0.10, lower leg 0.03 / 0.001 /
    // 0.05, hull within 0.017); the loaded state starts without Box2D's warm-start impulses.
    assert_eq!((obs[8], obs[13]), (0.0, 1.0), "contact flags");
    let lower = bodies[4];
    for (name, got, want, tol) in [
        ("knee 1 speed", s[13], -0.9526867866516113, 0.2),
        ("lower vx", lower.vx, 2.1961007118225098, 0.1),
        ("lower vy", lower.vy, -0.14476870000362396, 0.02),
        ("lower w", lower.w, -3.7684550285339355, 0.15),
        ("hull vx", s[3], 3.2498252391815186, 0.02),
        ("hull vy", s[4], -0.7578383684158325, 0.02),
        ("hull w", s[5], 1.1098676919937134, 0.02),
    ] {
        assert!((got - want).abs() < tol, "{name}: {got} here, {want} in Box2D");
    }
}

#[test]
fn context_changes_the_dynamics() {
    let run = |p: BipedalWalkerParams| gait(&mut walker(p), 2, 60).0;
    let base = run(BipedalWalkerParams::default());
    for p in [
        BipedalWalkerParams {
            friction: 0.05,
            ..Default::default()
        },
        BipedalWalkerParams {
            motors_torque: 20.0,
            ..Default::default()
        },
        BipedalWalkerParams {
            leg_h: 1.5,
            ..Default::default()
        },
        BipedalWalkerParams {
            speed_knee: 2.0,
            ..Default::default()
        },
        BipedalWalkerParams {
            gravity_x: 3.0,
            ..Default::default()
        },
    ] {
        assert_ne!(run(p), base, "{p:?}");
    }
}

#[test]
fn state_round_trip_and_bad_input() {
    let mut env = walker(BipedalWalkerParams::default());
    let mut obs = vec![0.0; 24];
    assert_eq!(
        env.step_into(&act([0.0; 4]), &mut obs),
        Err(EnvError::NeedsReset { env: "bipedal_walker" })
    );
    env.reset(Some(4));
    for _ in 0..30 {
        env.step(&act([0.3, -0.2, -0.4, 0.9])).unwrap();
    }
    let s = env.state();
    assert_eq!(s.len(), STATE_DIM);
    let o = env.observe();
    let mut c = walker(BipedalWalkerParams::default());
    c.set_state(&s).unwrap();
    let s2 = c.state();
    for (i, (x, y)) in s.iter().zip(&s2).enumerate() {
        assert!((x - y).abs() <= 1e-4 * (1.0 + x.abs()), "component {i}: {x} vs {y}");
    }
    for (x, y) in o.iter().zip(c.observe()) {
        assert!((x - y).abs() < 1e-4);
    }
    // Clones continue like each other: the clone's world is rebuilt from joint angles measured
    // from the hips' reference angles, which can move an f32 body angle by its last bit.
    let mut d = c.clone();
    let (sc, sd) = (c.step(&act([1.0; 4])).unwrap(), d.step(&act([1.0; 4])).unwrap());
    assert_eq!((sc.terminated, sc.truncated), (sd.terminated, sd.truncated));
    assert!((sc.reward - sd.reward).abs() < 1e-5, "{} vs {}", sc.reward, sd.reward);
    for (x, y) in sc.obs.iter().zip(&sd.obs) {
        assert!((x - y).abs() < 1e-5, "{:?} vs {:?}", sc.obs, sd.obs);
    }

    assert!(matches!(
        env.step(&Action::Continuous(vec![0.0; 3])),
        Err(EnvError::ActionLength {
            expected: 4,
            got: 3,
            ..
        })
    ));
    assert!(matches!(
        env.step(&Action::Discrete(1)),
        Err(EnvError::ActionKind { .. })
    ));
    assert!(matches!(env.set_state(&s[..5]), Err(EnvError::StateLength { .. })));
    let mut bad = s.clone();
    bad[1] = f64::NAN;
    assert!(matches!(
        env.set_state(&bad),
        Err(EnvError::StateNotFinite { index: 1, .. })
    ));
    assert!(matches!(
        env.observe_into(&mut [0.0; 3]),
        Err(EnvError::ObsBufferLength { .. })
    ));
    // Out-of-range actions are clipped as in Gymnasium (torque ≤ MOTORS_TORQUE); NaN and ±inf
    // are refused, naming the component.
    let st = env.step(&act([7.0, -7.0, 0.5, 0.0])).unwrap();
    assert!(st.obs.iter().all(|x| x.is_finite()));
    assert!(matches!(
        env.step(&act([7.0, -7.0, f32::NAN, 0.0])),
        Err(EnvError::ActionNotFinite { index: 2, .. })
    ));
}

#[test]
fn render_draws_sky_ground_and_hull() {
    let p = BipedalWalkerParams::default();
    let mut env = walker(p);
    env.reset(Some(0));
    let f = env.render().unwrap();
    assert_eq!((f.width, f.height), (600, 400));
    let hull = env.body_states().unwrap()[0];
    let left = (hull.x - p.viewport_w / p.scale / 5.0).max(0.0);
    let px = |x: f64, y: f64| (((x - left) * p.scale) as u32, (p.viewport_h - y * p.scale) as u32);
    // Hull body (a point inside the polygon, right of the hip anchors' lidar origin).
    let (hx, hy) = px(hull.x - 0.5, hull.y + 0.1);
    assert_eq!(f.pixel(hx, hy), [127, 51, 229]);
    // Ground under the start pad, sky above the walker.
    let (gx, gy) = px(hull.x + 2.0, p.terrain_height - 1.0);
    assert_eq!(f.pixel(gx, gy), [102, 153, 76]);
    assert_eq!(f.pixel(590, 5), [215, 215, 255]);
    // A lidar ray (red) between the hull and the ground: ray 5 (0.75 rad from straight down),
    // 1 m from the hull origin, clear of the legs.
    let (lx, ly) = px(hull.x + 0.75f64.sin(), hull.y - 0.75f64.cos());
    let red = (lx.saturating_sub(1)..=lx + 1).any(|x| {
        let c = f.pixel(x, ly);
        c[0] > 200 && c[1] < 120
    });
    assert!(red, "no lidar ray at ({lx}, {ly})");
    // Rendering never changes the simulation.
    let s = env.state();
    env.render();
    assert_eq!(s, env.state());
}

#[test]
fn hip_limits_act_on_the_joint_angle_from_box2ds_reference_angle() {
    // Hips driven into their upper limit: both joint angles (observations) stop near 1.1, and the
    // upper legs stand at 1.1 + HIP_REFERENCE relative to the hull (1.05 and 1.15), as in
    // Gymnasium where pybox2d records the legs' creation angles (∓0.05) as reference angles.
    let mut env = walker(BipedalWalkerParams::default());
    env.reset(Some(3));
    let mut obs = Vec::new();
    for _ in 0..40 {
        obs = env.step(&act([1.0, 0.0, 1.0, 0.0])).unwrap().obs;
    }
    let b = env.body_states().unwrap();
    for leg in 0..2 {
        let joint = obs[4 + 5 * leg] as f64;
        // Box2D holds a joint driven into its limit up to b2_angularSlop past it (Gymnasium 1.4,
        // seed 3, 40 steps of [1, 0, 1, 0]: 1.134 and 1.128).
        assert!(
            joint > HIP_LIMITS[1] && joint < HIP_LIMITS[1] + ANGULAR_SLOP + 0.005,
            "leg {leg}: joint angle {joint}"
        );
        let rel = b[1 + 2 * leg].angle - b[0].angle;
        assert!(
            (rel - joint - HIP_REFERENCE[leg]).abs() < 1e-5,
            "leg {leg}: {rel} vs {joint}"
        );
    }
}

/// Random actions (uniform in [-1, 1]^4 from `Pcg64::new(seed, 7)`) from `reset(seed)` until
/// the episode ends: the largest |hull angle| observed.
fn largest_random_action_angle(seed: u64) -> f32 {
    use carl_spec::sampling::{Pcg64, dist};
    let mut env = walker(BipedalWalkerParams::default());
    let mut rng = Pcg64::new(seed, 7);
    env.reset(Some(seed));
    let mut largest = 0f32;
    for _ in 0..1600 {
        let a: Vec<f32> = (0..4).map(|_| dist::uniform(&mut rng, -1.0, 1.0) as f32).collect();
        let st = env.step(&Action::Continuous(a)).unwrap();
        largest = largest.max(st.obs[0].abs());
        if st.terminated {
            break;
        }
    }
    largest
}

/// The former rapier2d engine's walker flipped past ±π here (8 of 300 random-action episodes);
/// the Box2D-semantics engine does not.
#[test]
fn random_action_episode_65_stays_within_pi() {
    let largest = largest_random_action_angle(65);
    assert!(largest < std::f32::consts::PI, "{largest}");
}
