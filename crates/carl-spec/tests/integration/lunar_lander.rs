//! LunarLander (closed-form flight, physics2d near the ground): physics sanity, determinism, termination rules, context sensitivity,
//! bad input, and the heuristic's qualitative behaviour across planets.

use carl_spec::envs::box2d::{LunarLander, LunarLanderOptions, LunarLanderParams, Outcome, heuristic};
use carl_spec::envs::registry::{Context, MakeOptions, make_with};
use carl_spec::envs::{Action, Env, EnvError};
use carl_spec::instances::Store;
use carl_spec::spec::SpecSet;
use carl_spec::spec::model::Value;

fn planets() -> Vec<(String, f64)> {
    let specs = SpecSet::bundled().unwrap();
    let set = Store::new(&specs)
        .load("lunar_lander/landing_in_space_test_planets")
        .unwrap();
    set.instances
        .iter()
        .map(|i| {
            let g = match &i.context["GRAVITY_Y"] {
                Value::Number(x) => *x,
                v => panic!("{v:?}"),
            };
            (i.label(), g)
        })
        .collect()
}

fn lander(g: f64) -> LunarLander {
    LunarLander::new(LunarLanderParams {
        gravity_y: g,
        ..Default::default()
    })
}

/// Run the heuristic for one episode (≤ 1000 steps): (return, outcome, observations).
fn heuristic_episode(env: &mut LunarLander, seed: u64) -> (f64, Outcome, Vec<Vec<f32>>) {
    let (mut obs, _) = env.reset(Some(seed));
    let mut trace = vec![obs.clone()];
    let mut ret = 0.0;
    for _ in 0..1000 {
        let st = env.step(&Action::Discrete(heuristic(&obs))).unwrap();
        ret += st.reward;
        obs = st.obs;
        trace.push(obs.clone());
        if st.terminated {
            break;
        }
    }
    (ret, env.outcome(), trace)
}

/// Free fall once the legs have swung in (Box2D's first step snaps them out wide, the motors swing
/// them in at 0.3 rad/s over ~24 steps, moving the lander a little against them): from then on
/// the lander falls as `y0 + v0·τ + ½gτ²` up to the semi-implicit Euler term.
#[test]
fn free_fall_matches_half_g_t_squared() {
    for (name, g) in planets() {
        let p = LunarLanderParams {
            gravity_y: g,
            initial_random: 0.0,
            ..Default::default()
        };
        let mut env = LunarLander::new(p);
        env.reset(Some(0));
        let dt = 1.0 / p.fps;
        let deployed = |env: &LunarLander| {
            let [l, a, b] = env.body_poses().unwrap();
            a.2 - l.2 <= 0.35 && b.2 - l.2 >= -0.35
        };
        let mut swing = 1; // reset takes one step
        while !deployed(&env) {
            env.step(&Action::Discrete(0)).unwrap();
            swing += 1;
        }
        assert!((22..=26).contains(&swing), "{name}: legs swung in after {swing} steps");
        // One more step for the legs' last turn to stop (its momentum goes to the lander).
        env.step(&Action::Discrete(0)).unwrap();
        swing += 1;
        let (_, y0, _) = env.lander_pose().unwrap();
        let (_, v0, _) = env.lander_velocity().unwrap();
        // Fall at most 4.5 m in all (the terrain is at most H/2 = 6.7 m high, the lander starts at
        // 13.3 m and its legs reach 1.2 m below it).
        let n_max = ((2.0 * 4.5 / -g).sqrt() / dt).floor().min(200.0) as u64;
        let mut n = 0;
        let mut worst: f64 = 0.0;
        while swing + n < n_max {
            env.step(&Action::Discrete(0)).unwrap();
            n += 1;
            let (x, y, angle) = env.lander_pose().unwrap();
            let t = n as f64 * dt;
            let exact = y0 + v0 * t + 0.5 * g * t * t;
            // Semi-implicit Euler: y_n = y0 + v0 t + g dt² n(n+1)/2, i.e. ½ g t² + ½ g dt t.
            let euler = 0.5 * g * dt * t;
            let err = (y - exact - euler).abs();
            worst = worst.max(err);
            assert!(
                err <= 1e-4,
                "{name}: step {n}: y {y} vs {} (error {err})",
                exact + euler
            );
            assert!(
                (x - p.world_w() / 2.0).abs() < 1e-4,
                "{name}: drifted sideways to x = {x}"
            );
            assert!(angle.abs() < 2e-3, "{name}: rotated to {angle}");
            assert_eq!(env.outcome(), Outcome::Running);
        }
        assert!(n >= 5, "{name}: only {n} steps of free fall");
        eprintln!("{name}: {n} steps of free fall after the swing, worst error {worst:.1e} m");
    }
}

#[test]
fn alternating_two_worlds_equals_each_alone() {
    let (_, _, alone_a) = heuristic_episode(&mut lander(-9.80665), 3);
    let (_, _, alone_b) = heuristic_episode(&mut lander(-1.6279039), 3);
    let (mut a, mut b) = (lander(-9.80665), lander(-1.6279039));
    let (mut oa, _) = a.reset(Some(3));
    let (mut ob, _) = b.reset(Some(3));
    let (mut ta, mut tb) = (vec![oa.clone()], vec![ob.clone()]);
    let (mut done_a, mut done_b) = (false, false);
    for _ in 0..1000 {
        if !done_a {
            let st = a.step(&Action::Discrete(heuristic(&oa))).unwrap();
            done_a = st.terminated;
            oa = st.obs;
            ta.push(oa.clone());
        }
        if !done_b {
            let st = b.step(&Action::Discrete(heuristic(&ob))).unwrap();
            done_b = st.terminated;
            ob = st.obs;
            tb.push(ob.clone());
        }
    }
    assert_eq!(ta, alone_a);
    assert_eq!(tb, alone_b);
    assert_ne!(ta, tb);
}

#[test]
fn reset_is_reproducible_from_the_seed() {
    let mut env = lander(-10.0);
    let (r1, o1, t1) = heuristic_episode(&mut env, 11);
    let (r2, o2, t2) = heuristic_episode(&mut env, 11);
    assert_eq!((r1.to_bits(), o1), (r2.to_bits(), o2));
    assert_eq!(t1, t2);
    let terrain11 = *env.terrain();
    env.reset(Some(12));
    assert_ne!(&terrain11, env.terrain());
    let (_, _, t3) = heuristic_episode(&mut env, 12);
    assert_ne!(t1[0], t3[0]);
}

#[test]
fn out_of_view_terminates_with_crash_reward() {
    let p = LunarLanderParams {
        gravity_x: 20.0,
        gravity_y: -0.5,
        ..Default::default()
    };
    let mut env = LunarLander::new(p);
    let (mut obs, _) = env.reset(Some(0));
    let mut last = None;
    for _ in 0..1000 {
        let st = env.step(&Action::Discrete(0)).unwrap();
        obs = st.obs;
        if st.terminated {
            last = Some(st.reward);
            break;
        }
    }
    assert_eq!(env.outcome(), Outcome::OutOfView);
    assert!(obs[0] >= 1.0, "x = {}", obs[0]);
    assert_eq!(last, Some(-100.0));
}

#[test]
fn crash_detection_and_crash_penalty_option() {
    for penalty in [100.0, 10000.0] {
        let p = LunarLanderParams {
            gravity_y: -23.143694,
            ..Default::default()
        };
        let mut env = LunarLander::with_options(
            p,
            LunarLanderOptions {
                crash_penalty: penalty,
                ..Default::default()
            },
        );
        env.reset(Some(1));
        let mut reward = None;
        for _ in 0..1000 {
            let st = env.step(&Action::Discrete(0)).unwrap();
            if st.terminated {
                reward = Some(st.reward);
                break;
            }
        }
        assert_eq!(env.outcome(), Outcome::Crashed);
        assert_eq!(reward, Some(-penalty));
    }
}

#[test]
fn every_context_feature_changes_the_episode() {
    let base = LunarLanderParams::default();
    let (_, _, reference) = heuristic_episode(&mut LunarLander::new(base), 5);
    for name in LunarLanderParams::FEATURES {
        let mut p = base;
        let v = p.get(name).unwrap();
        let changed = match *name {
            "GRAVITY_X" => 1.0,
            "INITIAL_RANDOM" => 500.0,
            "VIEWPORT_W" => 700.0,
            "VIEWPORT_H" => 500.0,
            _ => v * 1.25,
        };
        p.set(name, changed).unwrap();
        let (_, _, trace) = heuristic_episode(&mut LunarLander::new(p), 5);
        assert_ne!(trace, reference, "{name} = {changed} changed nothing");
    }
}

#[test]
fn bad_actions_are_errors_not_panics() {
    let mut env = lander(-10.0);
    assert!(matches!(
        env.step(&Action::Discrete(0)),
        Err(EnvError::NeedsReset { .. })
    ));
    env.reset(Some(0));
    for a in [
        Action::Discrete(4),
        Action::Discrete(-1),
        Action::Continuous(vec![0.0, 0.0]),
    ] {
        assert!(env.step(&a).is_err(), "{a:?}");
    }
    let mut buf = [0.0f32; 3];
    assert!(env.step_into(&Action::Discrete(0), &mut buf).is_err());
    assert!(env.set_state(&[1.0, 2.0]).is_err());
    let mut nan = env.state();
    nan[12] = f64::NAN;
    assert!(env.set_state(&nan).is_err());

    let mut cont = LunarLander::with_options(
        LunarLanderParams::default(),
        LunarLanderOptions {
            continuous: true,
            ..Default::default()
        },
    );
    cont.reset(Some(0));
    assert!(cont.step(&Action::Discrete(1)).is_err());
    assert!(cont.step(&Action::Continuous(vec![1.0])).is_err());
    // Non-finite actions are refused naming the component; huge finite ones are clipped.
    for a in [[f32::NAN, f32::NAN], [f32::INFINITY, -f32::INFINITY]] {
        let e = cont.step(&Action::Continuous(a.to_vec())).unwrap_err();
        assert!(matches!(e, EnvError::ActionNotFinite { index: 0, .. }), "{a:?} -> {e}");
    }
    for a in [[1e30, -1e30], [0.7, -0.8]] {
        let st = cont.step(&Action::Continuous(a.to_vec())).unwrap();
        assert!(st.obs.iter().all(|x| x.is_finite()), "{a:?} -> {:?}", st.obs);
    }
}

#[test]
fn state_round_trip_and_clone() {
    let mut env = lander(-3.7);
    env.reset(Some(4));
    for _ in 0..20 {
        env.step(&Action::Discrete(2)).unwrap();
    }
    let s = env.state();
    let mut c = env.clone();
    assert_eq!(c.state(), s);
    assert_eq!(c.observe(), env.observe());
    c.set_state(&s).unwrap();
    assert_eq!(c.observe(), env.observe());
}

#[test]
fn registry_builds_lunar_lander_from_spec_and_instance_sets() {
    let specs = SpecSet::bundled().unwrap();
    let spec = specs.get("lunar_lander").unwrap();
    let ctx = Context::from([("GRAVITY_Y".to_string(), Value::Number(-23.143694))]);
    assert!(
        make_with(spec, &ctx, MakeOptions::default()).is_err(),
        "Jupiter is out of bounds"
    );
    let mut env = make_with(
        spec,
        &ctx,
        MakeOptions {
            allow_out_of_bounds: true,
        },
    )
    .unwrap();
    let (obs, _) = env.reset(Some(0));
    assert_eq!(obs.len(), 8);
    let mut steps = 0;
    loop {
        let st = env.step(&Action::Discrete(0)).unwrap();
        steps += 1;
        if st.terminated || st.truncated {
            break;
        }
    }
    assert!(steps < 1000);
}

/// The issue's bar: "a controller that lands reliably in Gymnasium at Earth and Mars gravity
/// should land reliably here, and fail where it fails there". Gymnasium's own numbers come from
/// `scripts/lunar_lander_heuristic_check.py` (tests/fixtures/lunar_lander_heuristic_gymnasium.json,
/// 50 seeds per body). Seeds give Gymnasium's own terrains and initial pushes (NumPy's generator),
/// so only the physics differs: landing and crash rates within 0.10 of Gymnasium's on every body
/// (measured: Neptune, the hardest, landed 0.74 and crashed 0.18; Gymnasium 0.80 and 0.12).
#[test]
fn heuristic_lands_where_gymnasium_lands_and_crashes_where_it_crashes() {
    let fixture: serde_json::Value =
        serde_json::from_str(include_str!("fixtures/lunar_lander_heuristic_gymnasium.json")).unwrap();
    let n = 50u64;
    for (body, gym) in fixture["planets"].as_object().unwrap() {
        let g = gym["gravity_y"].as_f64().unwrap();
        let mut env = lander(g);
        let outcomes: Vec<Outcome> = (0..n).map(|s| heuristic_episode(&mut env, s).1).collect();
        let rate = |o: Outcome| outcomes.iter().filter(|x| **x == o).count() as f64 / n as f64;
        let (landed, crashed) = (rate(Outcome::Landed), rate(Outcome::Crashed));
        let (gym_landed, gym_crashed) = (
            gym["landed_rate"].as_f64().unwrap(),
            gym["crashed_rate"].as_f64().unwrap(),
        );
        eprintln!("{body}: landed {landed} (Gymnasium {gym_landed}), crashed {crashed} (Gymnasium {gym_crashed})");
        assert!(
            (landed - gym_landed).abs() <= 0.10,
            "{body}: landed {landed} vs Gymnasium {gym_landed}"
        );
        assert!(
            (crashed - gym_crashed).abs() <= 0.10,
            "{body}: crashed {crashed} vs Gymnasium {gym_crashed}"
        );
    }
    // Reliable where Gymnasium is reliable, failing where it fails.
    for (g, min) in [(-9.80665, 0.85), (-3.6971070499999996, 0.85)] {
        let mut env = lander(g);
        let landed = (0..n)
            .filter(|s| heuristic_episode(&mut env, *s).1 == Outcome::Landed)
            .count() as f64
            / n as f64;
        assert!(landed >= min, "g = {g}: landed {landed}");
    }
    let mut env = lander(-23.143693999999996);
    assert!((0..n).all(|s| heuristic_episode(&mut env, s).1 == Outcome::Crashed));
}

/// Box2D's own touchdowns replayed here: `scripts/lunar_lander_touchdown_box2d.py` records, for
/// each planet and seed, Gymnasium's full state 10 steps before the first leg contact (its
/// terrain, lander and legs) and the episode's outcome in Box2D. Loaded into our lander, the
/// same heuristic finishes the episode; the flight before touchdown and the terrain generator are
/// taken out of the comparison, so this measures contact and leg dynamics alone.
fn replay_box2d_touchdowns(planet: &str) -> Vec<(u64, String, Outcome, f64, f64)> {
    let fixture: serde_json::Value =
        serde_json::from_str(include_str!("fixtures/lunar_lander_touchdowns_box2d.json")).unwrap();
    let p = &fixture["planets"][planet];
    let g = p["gravity_y"].as_f64().unwrap();
    let mut out = vec![];
    for run in p["runs"].as_array().unwrap() {
        let Some(state) = run.get("state") else { continue };
        let state: Vec<f64> = state.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
        let seed = run["seed"].as_u64().unwrap();
        let mut env = lander(g);
        env.reset(Some(seed));
        // Same seed, same terrain as Gymnasium's (NumPy's generator, Gymnasium's draw order).
        for (ours, box2d) in env.terrain().iter().zip(&state[..11]) {
            // The fixture keeps 9 significant digits.
            assert!(
                (ours - box2d).abs() < 1e-7,
                "{planet} seed {seed}: terrain {ours} vs {box2d}"
            );
        }
        env.set_state(&state).unwrap();
        let mut obs = env.observe();
        let mut max_deflection: f64 = 0.0;
        let mut touched = false;
        for _ in run["state_step"].as_u64().unwrap()..1000 {
            let st = env.step(&Action::Discrete(heuristic(&obs))).unwrap();
            obs = st.obs;
            touched |= env.leg_contacts().iter().any(|c| *c);
            if touched {
                let [l, a, b] = env.body_poses().unwrap();
                max_deflection = max_deflection.max(a.2 - l.2 - 0.4).max(-(b.2 - l.2) - 0.4);
            }
            if st.terminated {
                break;
            }
        }
        out.push((
            seed,
            run["outcome"].as_str().unwrap().to_string(),
            env.outcome(),
            max_deflection,
            run["max_leg_deflection"].as_f64().unwrap(),
        ));
    }
    out
}

#[test]
fn box2d_touchdowns_end_as_in_box2d() {
    let (mut replay_agree, mut replay_total, mut whole_agree, mut whole_total) = (0, 0, 0, 0);
    for planet in ["Jupiter", "Neptune", "Earth", "Mars", "Moon", "Pluto"] {
        let runs = replay_box2d_touchdowns(planet);
        let name = |o: Outcome| match o {
            Outcome::Landed => "landed",
            Outcome::Crashed => "crashed",
            Outcome::OutOfView => "out_of_view",
            Outcome::Running => "timeout",
        };
        let n = runs.len() as f64;
        let rate = |k: &str, ours: bool| {
            runs.iter()
                .filter(|r| if ours { name(r.2) == k } else { r.1 == k })
                .count() as f64
                / n
        };
        for r in &runs {
            eprintln!(
                "{planet} seed {:2}: box2d {:12} here {:12} deflection here {:.3} box2d {:.3}",
                r.0,
                r.1,
                name(r.2),
                r.3,
                r.4
            );
        }
        // The whole episode from the same seed (same terrain and push as Box2D's).
        let fixture: serde_json::Value =
            serde_json::from_str(include_str!("fixtures/lunar_lander_touchdowns_box2d.json")).unwrap();
        let p = &fixture["planets"][planet];
        let mut env = lander(p["gravity_y"].as_f64().unwrap());
        let whole: Vec<(u64, String, Outcome)> = p["runs"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| {
                let seed = r["seed"].as_u64().unwrap();
                let (_, outcome, _) = heuristic_episode(&mut env, seed);
                (seed, r["outcome"].as_str().unwrap().to_string(), outcome)
            })
            .collect();
        let differ: Vec<String> = whole
            .iter()
            .filter(|w| name(w.2) != w.1)
            .map(|w| format!("{}:{}->{}", w.0, w.1, name(w.2)))
            .collect();
        eprintln!(
            "{planet}: whole episodes, {} of {} differ: {}",
            differ.len(),
            whole.len(),
            differ.join(" ")
        );
        whole_agree += whole.len() - differ.len();
        whole_total += whole.len();
        let agree = runs.iter().filter(|r| name(r.2) == r.1).count();
        replay_agree += agree;
        replay_total += runs.len();
        eprintln!(
            "{planet}: {} touchdowns, same outcome {agree}; landed {:.2} (box2d {:.2}) crashed {:.2} (box2d {:.2})",
            runs.len(),
            rate("landed", true),
            rate("landed", false),
            rate("crashed", true),
            rate("crashed", false)
        );
        // Touchdown and leg dynamics: from Box2D's own states, Neptune's hard touchdowns crash
        // as often as in Box2D.
        if planet == "Neptune" {
            assert!(
                (rate("crashed", true) - rate("crashed", false)).abs() <= 0.10,
                "Neptune replays: crashed {} vs Box2D {}",
                rate("crashed", true),
                rate("crashed", false)
            );
        }
    }
    // Measured: 0.952 of the replays and 289 of 300 whole episodes end as in Box2D (with rapier
    // near the ground: 244 of 270 and 275 of 300).
    let (replay, whole) = (
        replay_agree as f64 / replay_total as f64,
        whole_agree as f64 / whole_total as f64,
    );
    eprintln!("same outcome as Box2D: replays {replay:.3}, whole episodes {whole:.3}");
    assert!(
        replay >= 0.92 && whole >= 0.93,
        "replays {replay}, whole episodes {whole}"
    );
}

/// The flight is Box2D's: `scripts/lunar_lander_flight_box2d.py` records Gymnasium's heuristic in
/// Box2D (every planet, seeds 0–4, until the first leg contact or 200 steps): its actions and the
/// lander's state. The same actions from the same seeds here (same terrain, push and engine
/// dispersion) give the same trajectory, from the first step (Box2D assembles the legs in it and
/// the push spins the lander, see `src/envs/box2d/lunar_lander/rigid.rs`) through the legs'
/// swing-in to the last steps before touchdown (where the solver takes over).
#[test]
fn flight_follows_box2d_step_by_step() {
    let fixture: serde_json::Value =
        serde_json::from_str(include_str!("fixtures/lunar_lander_flight_box2d.json")).unwrap();
    let mut worst = [0.0f64; 8];
    let mut worst_end = [0.0f64; 8];
    let mut compared = 0;
    for (planet, p) in fixture["planets"].as_object().unwrap() {
        let mut env = lander(p["gravity_y"].as_f64().unwrap());
        for run in p["runs"].as_array().unwrap() {
            let seed = run["seed"].as_u64().unwrap();
            env.reset(Some(seed));
            let actions: Vec<i64> = run["actions"]
                .as_array()
                .unwrap()
                .iter()
                .map(|a| a.as_i64().unwrap())
                .collect();
            let mut states = run["states"].as_array().unwrap().iter().peekable();
            for (t, a) in actions.iter().enumerate() {
                env.step(&Action::Discrete(*a)).unwrap();
                let Some(want) = states.next_if(|s| s[0].as_u64().unwrap() == t as u64 + 1) else {
                    continue;
                };
                let want: Vec<f64> = want.as_array().unwrap()[1..]
                    .iter()
                    .map(|x| x.as_f64().unwrap())
                    .collect();
                let [l, a0, a1] = env.body_poses().unwrap();
                let (vx, vy, w) = env.lander_velocity().unwrap();
                let got = [l.0, l.1, l.2, vx, vy, w, a0.2 - l.2, a1.2 - l.2];
                // Free flight is Box2D's to the float32 rounding of Box2D's own state: positions
                // and angles to 3 mm / 3 mrad, velocities to 0.02, leg angles to 6 mrad (a swing
                // ends up to one step's turn past the limit). In the last steps before touchdown
                // the solver steps (within two steps' travel of the ground; a slowly hovering
                // lander can stay there for ~20 steps): measured 3.1 mm and 5e-3 m/s at worst.
                let end_phase = actions.len() - t <= 20;
                for k in 0..8 {
                    let err = (got[k] - want[k]).abs();
                    let tol = match (k, end_phase) {
                        (3..=5, false) => 0.02,
                        (6..=7, false) => 6e-3,
                        (_, false) => 3e-3,
                        (3..=5, true) => 0.01,
                        (_, true) => 5e-3,
                    };
                    if !end_phase {
                        worst[k] = worst[k].max(err);
                    } else {
                        worst_end[k] = worst_end[k].max(err);
                    }
                    assert!(
                        err <= tol,
                        "{planet} seed {seed} step {} of {}: value {k} is {} here, {} in Box2D",
                        t + 1,
                        actions.len(),
                        got[k],
                        want[k]
                    );
                }
                compared += 1;
            }
        }
    }
    eprintln!(
        "{compared} states compared; in flight, worst |error| (x, y, angle, vx, vy, ω, legs): {:?}",
        worst.map(|e| format!("{e:.1e}"))
    );
    eprintln!(
        "last steps before touchdown, worst |error|: {:?}",
        worst_end.map(|e| format!("{e:.1e}"))
    );
    assert!(compared > 500);
}

/// Gymnasium's lander never turns past ±2π (its observation space's bound): a lander rolling
/// over ends the episode on body contact. 20,000 random-action steps (Gymnasium 1.4 from seed
/// 0: largest |angle| well inside). On rapier the lander rolled on the ground spinning (58.8 rad).
#[test]
fn random_actions_never_spin_the_lander_past_two_pi() {
    let mut env = LunarLander::default();
    env.reset(Some(0));
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    let (mut largest, mut episodes) = (0.0f32, 1);
    for _ in 0..20_000 {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        let st = env.step(&Action::Discrete((x % 4) as i64)).unwrap();
        largest = largest.max(st.obs[4].abs());
        if st.terminated || st.truncated {
            env.reset(None);
            episodes += 1;
        }
    }
    eprintln!("{episodes} episodes, largest |angle| {largest}");
    assert!(largest < std::f32::consts::TAU, "largest |angle| {largest}");
}
