//! VehicleRacing (CarRacing-v3 with CARL's 29 vehicles): every vehicle builds and steps, tracks
//! are seeded, the controls act in the right direction, heavier vehicles are slower, tiles pay,
//! the picture shows road under the car and grass beside it, instances do not interfere, and
//! leaving the playfield ends the episode.

use carl_spec::envs::box2d::vehicle_racing::vehicles::VEHICLES;
use carl_spec::envs::box2d::vehicle_racing::{STATE_DIM, VehicleRacing, VehicleRacingOptions, VehicleRacingParams};
use carl_spec::envs::registry::{Context, MakeError, MakeOptions, make, make_with};
use carl_spec::envs::{Action, DType, Env, Space};
use carl_spec::spec::SpecSet;
use carl_spec::spec::model::Value;

fn racer(vehicle: usize) -> VehicleRacing {
    VehicleRacing::new(VehicleRacingParams {
        vehicle: vehicle as f64,
    })
    .unwrap()
}

fn act(steer: f32, gas: f32, brake: f32) -> Action {
    Action::Continuous(vec![steer, gas, brake])
}

fn speed_after_gas(env: &mut VehicleRacing, seed: u64, steps: usize) -> f64 {
    env.reset(Some(seed));
    for _ in 0..steps {
        env.step(&act(0.0, 1.0, 0.0)).unwrap();
    }
    env.hull_speed()
}

#[test]
fn the_table_is_carl_benchs_parking_garage_and_the_spec_agrees() {
    assert_eq!(VEHICLES.len(), 29);
    let specs = SpecSet::bundled().unwrap();
    let spec = specs.get("vehicle_racing").unwrap();
    let f = spec.feature("VEHICLE").unwrap();
    let labels = f.choice_labels.as_ref().unwrap();
    let names: Vec<&str> = VEHICLES.iter().map(|v| v.name).collect();
    assert_eq!(labels.iter().map(String::as_str).collect::<Vec<_>>(), names);
    assert_eq!(VEHICLES[0].name, "RaceCar");
    assert_eq!(VEHICLES[28].name, "TukTukSmallTrailer");
}

#[test]
fn all_29_vehicles_build_and_step_with_finite_state() {
    let specs = SpecSet::bundled().unwrap();
    let spec = specs.get("vehicle_racing").unwrap();
    for (i, v) in VEHICLES.iter().enumerate() {
        let ctx = Context::from([("VEHICLE".to_string(), Value::Number(i as f64))]);
        let mut env = make(spec, &ctx).unwrap();
        let (obs, _) = env.reset(Some(7));
        assert_eq!(obs.len(), 96 * 96 * 3);
        for k in 0..60 {
            let a = act(((k as f32) * 0.3).sin(), 0.8, if k % 10 == 9 { 0.5 } else { 0.0 });
            let st = env.step(&a).unwrap();
            assert!(st.reward.is_finite(), "{}", v.name);
            assert!(
                st.obs.iter().all(|x| (0.0..=255.0).contains(x) && x.fract() == 0.0),
                "{}",
                v.name
            );
        }
        let s = env.state();
        assert_eq!(s.len(), STATE_DIM);
        assert!(s.iter().all(|x| x.is_finite()), "{}: {s:?}", v.name);
        let inner = env.inner();
        let speed = inner.downcast_ref::<VehicleRacing>().unwrap().hull_speed();
        assert!(speed > 1.0, "{} did not move (speed {speed})", v.name);
    }
}

#[test]
fn vehicle_out_of_range_is_a_clear_error() {
    let specs = SpecSet::bundled().unwrap();
    let spec = specs.get("vehicle_racing").unwrap();
    let ctx = Context::from([("VEHICLE".to_string(), Value::Number(29.0))]);
    let err = make(spec, &ctx).unwrap_err();
    assert!(matches!(err, MakeError::OutOfBounds { .. }), "{err}");
    let opts = MakeOptions {
        allow_out_of_bounds: true,
    };
    let err = make_with(spec, &ctx, opts).unwrap_err();
    assert!(err.to_string().contains("not a vehicle index"), "{err}");
    assert!(VehicleRacing::new(VehicleRacingParams { vehicle: 2.5 }).is_err());
    assert!(VehicleRacing::new(VehicleRacingParams { vehicle: -1.0 }).is_err());
    // A label selects the vehicle too.
    let ctx = Context::from([("VEHICLE".to_string(), Value::String("Bus".into()))]);
    let env = make(spec, &ctx).unwrap();
    assert_eq!(
        env.inner().downcast_ref::<VehicleRacing>().unwrap().vehicle().name,
        "Bus"
    );
}

#[test]
fn spaces_are_carracings() {
    let env = racer(0);
    match env.observation_space() {
        Space::Box {
            shape,
            dtype,
            low,
            high,
        } => {
            assert_eq!(shape, vec![96, 96, 3]);
            assert_eq!(dtype, DType::UInt8);
            assert!(low.iter().all(|x| *x == 0.0) && high.iter().all(|x| *x == 255.0));
        }
        s => panic!("{s:?}"),
    }
    assert_eq!(
        env.action_space(),
        Space::Box {
            low: vec![-1.0, 0.0, 0.0],
            high: vec![1.0, 1.0, 1.0],
            shape: vec![3],
            dtype: DType::Float32
        }
    );
    let d = VehicleRacing::with_options(
        VehicleRacingParams::default(),
        VehicleRacingOptions {
            continuous: false,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(d.action_space(), Space::Discrete { n: 5, start: 0 });
}

#[test]
fn track_is_reproducible_per_seed_and_differs_across_seeds() {
    let mut a = racer(0);
    let mut b = racer(9);
    let (oa, _) = a.reset(Some(3));
    b.reset(Some(3));
    assert_eq!(a.track(), b.track());
    assert_eq!(a.reset(Some(3)).0, oa);
    let t3 = a.track().unwrap().clone();
    assert!(t3.tiles.len() > 100, "{} tiles", t3.tiles.len());
    a.reset(Some(4));
    assert_ne!(a.track().unwrap().points, t3.points);
    // reset(None) continues the stream: a new track.
    a.reset(Some(3));
    a.reset(None);
    assert_ne!(a.track().unwrap().points, t3.points);
}

#[test]
fn gas_accelerates_and_brake_decelerates() {
    let mut env = racer(0);
    env.reset(Some(1));
    let mut last = env.hull_speed();
    assert!(last < 1e-9);
    for _ in 0..25 {
        env.step(&act(0.0, 1.0, 0.0)).unwrap();
        let v = env.hull_speed();
        assert!(v > last, "speed {v} after {last}");
        last = v;
    }
    let state = env.state();
    // Coasting vs braking from the same state.
    let mut coast = racer(0);
    coast.set_state(&state).unwrap();
    let mut brake = racer(0);
    brake.set_state(&state).unwrap();
    for _ in 0..20 {
        coast.step(&act(0.0, 0.0, 0.0)).unwrap();
        brake.step(&act(0.0, 0.0, 1.0)).unwrap();
    }
    assert!(brake.hull_speed() < last, "braking did not slow down");
    assert!(brake.hull_speed() < coast.hull_speed() - 1.0);
}

#[test]
fn steering_turns_the_car_the_way_gymnasium_says() {
    // action[0] = -1 is "full left": the car turns counter-clockwise (its angle grows).
    for (steer, sign) in [(-1.0f32, 1.0), (1.0, -1.0)] {
        let mut env = racer(0);
        env.reset(Some(2));
        for _ in 0..20 {
            env.step(&act(0.0, 0.5, 0.0)).unwrap();
        }
        let a0 = env.hull().2;
        for _ in 0..15 {
            env.step(&act(steer, 0.0, 0.0)).unwrap();
        }
        let turned = env.hull().2 - a0;
        assert!(turned * sign > 0.05, "steer {steer}: turned {turned}");
        assert!(env.steering_angle() * sign > 0.3);
    }
}

#[test]
fn a_bus_accelerates_slower_than_the_race_car() {
    let race = speed_after_gas(&mut racer(0), 5, 30);
    let bus = speed_after_gas(&mut racer(18), 5, 30);
    let street = speed_after_gas(&mut racer(9), 5, 30);
    assert!(bus < 0.8 * race, "bus {bus} race car {race}");
    assert!(street < race, "street {street} race car {race}");
    // A trailer slows the race car down.
    let trailer = speed_after_gas(&mut racer(6), 5, 30);
    assert!(trailer < race, "large trailer {trailer} race car {race}");
}

#[test]
fn the_race_car_accelerates_like_gymnasiums() {
    // Gymnasium 1.4 CarRacing-v3, full gas on a straight from rest (seed 0): hull speed
    // 20.1437 m/s after 21 steps, 37.6531 after 41 (the tyre model does not depend on the track
    // while all wheels stay on the road).
    let mut env = racer(0);
    env.reset(Some(0));
    let mut speeds = Vec::new();
    for _ in 0..41 {
        env.step(&act(0.0, 1.0, 0.0)).unwrap();
        speeds.push(env.hull_speed());
    }
    assert!((speeds[20] - 20.1437).abs() < 2e-3, "{}", speeds[20]);
    assert!((speeds[40] - 37.6531).abs() < 2e-3, "{}", speeds[40]);
}

#[test]
fn every_kind_of_vehicle_accelerates_like_carl_benchs() {
    // carl-bench's parking-garage classes (automl/CARL 14c8fee4) in Gymnasium 1.4 CarRacing-v3,
    // Box2D 2.3.10: full gas from rest for 41 steps (seed 0, straight start), hull speed after 11,
    // 21, 41 steps; then the speed after 10 steps of full brake.
    let reference: [(usize, [f64; 3], f64, f64); 12] = [
        (1, [11.389, 20.1437, 37.6531], 27.1038, 2e-3),
        (3, [5.9707, 10.5309, 19.6514], 5.7529, 2e-3),
        (6, [3.514, 6.6619, 12.9451], 1.6777, 0.03),
        (9, [8.3726, 15.212, 23.6684], 10.5028, 2e-3),
        (11, [14.9692, 23.6625, 35.173], 21.9486, 2e-3),
        (16, [3.5668, 7.432, 14.5337], 0.2301, 0.03),
        (18, [7.678, 14.0338, 26.72], 3.5897, 2e-3),
        (21, [3.8809, 7.0406, 13.3493], 1.234, 2e-3),
        (24, [1.6618, 3.208, 6.296], 1.604, 0.03),
        (26, [3.6441, 7.1906, 14.2653], 7.7306, 0.03),
        (27, [16.9578, 27.9586, 42.4462], 25.993, 2e-3),
        (28, [8.672, 16.5222, 29.1316], 9.0497, 2e-3),
    ];
    for (v, speeds, braked, tol) in reference {
        let mut env = racer(v);
        env.reset(Some(0));
        let mut got = Vec::new();
        for i in 0..41 {
            env.step(&act(0.0, 1.0, 0.0)).unwrap();
            if [10, 20, 40].contains(&i) {
                got.push(env.hull_speed());
            }
        }
        for _ in 0..10 {
            env.step(&act(0.0, 0.0, 1.0)).unwrap();
        }
        let name = VEHICLES[v].name;
        for (g, r) in got.iter().zip(speeds) {
            assert!((g - r).abs() <= tol * r.max(1.0), "{name}: {got:?} vs {speeds:?}");
        }
        assert!(
            (env.hull_speed() - braked).abs() <= tol * braked.max(1.0),
            "{name}: braked {}",
            env.hull_speed()
        );
    }
}

#[test]
fn visiting_tiles_pays_and_the_step_costs() {
    let mut env = racer(0);
    env.reset(Some(11));
    let n = env.track().unwrap().tiles.len() as f64;
    // reset's step(None) already touched the start tiles; they are paid with the first step.
    let at_reset = env.tiles_visited();
    assert!(at_reset >= 1);
    let st = env.step(&act(0.0, 0.0, 0.0)).unwrap();
    assert!(
        (st.reward - (at_reset as f64 * 1000.0 / n - 0.1)).abs() < 1e-9,
        "{}",
        st.reward
    );
    let st = env.step(&act(0.0, 0.0, 0.0)).unwrap();
    assert!((st.reward + 0.1).abs() < 1e-9);
    let mut paid = 0.0;
    let before = env.tiles_visited();
    for _ in 0..40 {
        let st = env.step(&act(0.0, 0.6, 0.0)).unwrap();
        if st.reward > 0.0 {
            paid += st.reward + 0.1;
        }
    }
    let gained = env.tiles_visited() - before;
    assert!(gained >= 3, "visited {gained} new tiles");
    assert!((paid - gained as f64 * 1000.0 / n).abs() < 1e-6);
}

#[test]
fn pixels_show_road_under_the_car_and_grass_beside() {
    let mut env = racer(0);
    env.reset(Some(1));
    // Stand still until the zoom animation ends (t = 1 s).
    for _ in 0..55 {
        env.step(&act(0.0, 0.0, 0.0)).unwrap();
    }
    let obs = env.observe();
    let px = |x: usize, y: usize| {
        let i = 3 * (y * 96 + x);
        [obs[i] as u8, obs[i + 1] as u8, obs[i + 2] as u8]
    };
    // The car sits at (48, 72); ahead of and beside it along its row: road grey.
    let is_road = |p: [u8; 3]| p[0] == p[1] && p[1] == p[2] && (102..=107).contains(&p[0]);
    let is_grass = |p: [u8; 3]| p == [102, 204, 102] || p == [102, 230, 102];
    assert!(is_road(px(48, 62)), "{:?}", px(48, 62));
    assert!(is_road(px(40, 72)), "{:?}", px(40, 72));
    assert!(is_road(px(56, 72)), "{:?}", px(56, 72));
    // The hull is red.
    assert_eq!(px(48, 72)[0], 204);
    // Far to the side of the car: grass.
    assert!(is_grass(px(4, 72)), "{:?}", px(4, 72));
    assert!(is_grass(px(92, 72)), "{:?}", px(92, 72));
    // The indicator bar at the bottom is black where nothing is drawn.
    assert_eq!(px(60, 95), [0, 0, 0]);
    // A bus looks different from the race car in the same state.
    let mut bus = racer(18);
    bus.set_state(&env.state()).unwrap();
    assert_ne!(bus.observe(), obs);
    let frame = env.render().unwrap();
    assert_eq!((frame.width, frame.height), (600, 400));
}

#[test]
fn two_instances_alternating_equal_each_alone() {
    let actions: Vec<Action> = (0..80)
        .map(|k| act((k as f32 * 0.17).sin(), 0.7, if k % 13 == 0 { 0.4 } else { 0.0 }))
        .collect();
    let run_alone = |v: usize, seed: u64| {
        let mut e = racer(v);
        let mut trace = vec![e.reset(Some(seed)).0];
        let mut rewards = Vec::new();
        for a in &actions {
            let st = e.step(a).unwrap();
            trace.push(st.obs);
            rewards.push(st.reward);
        }
        (trace, rewards, e.state())
    };
    let alone_a = run_alone(0, 21);
    let alone_b = run_alone(24, 22);
    let (mut a, mut b) = (racer(0), racer(24));
    let mut ta = vec![a.reset(Some(21)).0];
    let mut tb = vec![b.reset(Some(22)).0];
    let (mut ra, mut rb) = (Vec::new(), Vec::new());
    for act in &actions {
        let s = a.step(act).unwrap();
        ta.push(s.obs);
        ra.push(s.reward);
        let s = b.step(act).unwrap();
        tb.push(s.obs);
        rb.push(s.reward);
    }
    assert!(ta == alone_a.0 && ra == alone_a.1 && a.state() == alone_a.2);
    assert!(tb == alone_b.0 && rb == alone_b.1 && b.state() == alone_b.2);
}

#[test]
fn state_round_trips_and_replays() {
    let mut a = racer(5);
    a.reset(Some(8));
    for k in 0..30 {
        a.step(&act(0.2 * (k as f32).cos(), 0.9, 0.0)).unwrap();
    }
    let s = a.state();
    let mut b = racer(5);
    b.set_state(&s).unwrap();
    assert_eq!(b.state(), s);
    assert_eq!(b.observe(), a.observe());
    for _ in 0..20 {
        let x = a.step(&act(0.5, 0.5, 0.1)).unwrap();
        let y = b.step(&act(0.5, 0.5, 0.1)).unwrap();
        assert_eq!(x, y);
    }
    assert!(b.set_state(&s[..10]).is_err());
    let mut bad = s.clone();
    bad[7] = f64::NAN;
    assert!(b.set_state(&bad).is_err());
}

#[test]
fn leaving_the_playfield_terminates_with_minus_100() {
    let mut env = racer(0);
    env.reset(Some(3));
    let mut s = env.state();
    // Hull body row: x, y, angle, vx, vy, w after the header and visited words.
    let base = 5 + 12;
    s[base] = 333.0;
    s[base + 1] = 0.0;
    s[base + 3] = 50.0;
    env.set_state(&s).unwrap();
    let st = env.step(&act(0.0, 0.0, 0.0)).unwrap();
    assert!(st.terminated);
    assert_eq!(st.reward, -100.0);
}

#[test]
fn bad_actions_are_errors() {
    let mut env = racer(0);
    assert!(env.step(&act(0.0, 0.0, 0.0)).is_err(), "step before reset");
    env.reset(Some(0));
    assert!(env.step(&Action::Continuous(vec![0.0, 1.0])).is_err());
    assert!(env.step(&Action::Discrete(1)).is_err());
    assert!(env.step(&act(f32::NAN, 0.0, 0.0)).is_err());
    let mut d = VehicleRacing::with_options(
        VehicleRacingParams::default(),
        VehicleRacingOptions {
            continuous: false,
            ..Default::default()
        },
    )
    .unwrap();
    d.reset(Some(0));
    assert!(d.step(&Action::Discrete(5)).is_err());
    for _ in 0..20 {
        d.step(&Action::Discrete(3)).unwrap();
    }
    assert!(d.hull_speed() > 1.0, "discrete gas");
}
