//! carl-spec's column of the dm_control comparison (`scripts/dmc_compare.py`, the Fidelity
//! section of each page `crates/carl-envs-dmc/docs/<id>.md`): the deterministic metrics computed
//! here through the environment with the script's definitions, at dm_control's values (the
//! `dm_control` instance set), and pinned to dm_control 1.0.50's numbers. A model change re-runs
//! the script and updates the pins with the page.

use carl_env::api::{Action, Env};
use carl_envs_dmc::point_mass::{Params, PointMass, Variant};
use carl_envs_dmc::walker::{self, Walker};

/// The ball's coordinate `axis` after `steps` control steps of `ctrl` from rest at the centre.
fn push(p: Params, ctrl: [f32; 2], steps: usize, axis: usize) -> f64 {
    let mut e = PointMass::new(p, Variant::default()).unwrap();
    e.reset(Some(0));
    e.set_state(&[0.0; 4]).unwrap();
    for _ in 0..steps {
        e.step(&Action::Continuous(ctrl.to_vec())).unwrap();
    }
    e.state()[axis]
}

/// dm_control's values (specs/instances/dmc_point_mass/dm_control.json).
fn dm_control() -> Params {
    Params {
        starting_x: 0.0,
        starting_y: 0.0,
        ..Params::default()
    }
}

#[test]
fn point_mass_pushes_as_dm_control() {
    // (metric, carl-spec, dm_control 1.0.50) as the script printed them.
    let mut medium = dm_control();
    medium.common.viscosity = 2.0;
    medium.common.density = 1000.0;
    medium.common.wind_x = 0.05;
    let rows = [
        ("push_x_0.2s", push(dm_control(), [1.0, 0.0], 10, 0), 0.0057338),
        ("push_x_1s", push(dm_control(), [1.0, 0.0], 50, 0), 0.07119),
        ("push_y_1s", push(dm_control(), [0.3, -1.0], 50, 1), -0.07119),
        ("medium_push_x_1s", push(medium, [1.0, 0.0], 50, 0), 0.06878),
    ];
    for (name, ours, theirs) in rows {
        assert!(
            (ours / theirs - 1.0).abs() < 1e-4,
            "{name}: carl-spec {ours}, dm_control {theirs}"
        );
    }
}

#[test]
fn walker_falls_as_dm_control() {
    // Standing straight at rest (every joint at 0), zero action: (step, height, torso xz).
    let fall = |p: walker::Params, steps: usize| {
        let mut e = Walker::new(p, walker::WALK_SPEED).unwrap();
        e.reset(Some(0));
        e.set_state(&[0.0; 18]).unwrap();
        let mut obs = Vec::new();
        for _ in 0..steps {
            obs = e.step(&Action::Continuous(vec![0.0; 6])).unwrap().obs;
        }
        (f64::from(obs[14]), f64::from(obs[1]))
    };
    let dm = walker::Params::default();
    let mut medium = dm;
    medium.common.viscosity = 2.0;
    medium.common.density = 1000.0;
    medium.common.wind_x = 0.05;
    // (metric, carl-spec, dm_control 1.0.50); float32 observations.
    let rows = [
        ("fall_height_1s", fall(dm, 40).0, 1.0463),
        ("fall_torso_zz_1s", fall(dm, 40).1, 0.24289),
        ("fall_height_2s", fall(dm, 80).0, 0.18239),
        ("fall_torso_zz_2s", fall(dm, 80).1, -0.92714),
        ("medium_fall_height_1s", fall(medium, 40).0, 0.609),
    ];
    for (name, ours, theirs) in rows {
        assert!(
            (ours / theirs - 1.0).abs() < 1e-3,
            "{name}: carl-spec {ours}, dm_control {theirs}"
        );
    }
}

#[test]
fn fish_coasts_sinks_and_servoes_as_dm_control() {
    use carl_envs_dmc::fish::{self, Fish};
    // Level, joints at 0, 0.4 m/s forward (y), 3 rad/s yaw; the target where dm_control's
    // script leaves it (the metrics do not read it). Returns the observation after `steps`.
    let run = |p: fish::Params, ctrl: [f32; 5], steps: usize| {
        let mut e = Fish::new(p, false).unwrap();
        e.reset(Some(0));
        let mut s = vec![0.0; 30];
        s[2] = 0.1;
        s[3] = 1.0;
        s[15] = 0.4;
        s[19] = 3.0;
        s[28] = 0.4;
        s[29] = 0.1;
        e.set_state(&s).unwrap();
        let mut obs = Vec::new();
        for _ in 0..steps {
            obs = e.step(&Action::Continuous(ctrl.to_vec())).unwrap().obs;
        }
        obs.iter().map(|x| f64::from(*x)).collect::<Vec<f64>>()
    };
    let dm = fish::Params::default();
    let mut gravity = dm;
    gravity.common.gravity = 9.81;
    let zero = [0.0; 5];
    // (metric, carl-spec, dm_control 1.0.50) as the script printed them; float32 observations.
    let rows = [
        ("coast_speed_0.2s", run(dm, zero, 5)[12], 0.10681),
        ("coast_speed_1s", run(dm, zero, 25)[12], 0.027674),
        ("coast_yaw_rate_0.2s", run(dm, zero, 5)[16], 0.0066625),
        ("gravity_sink_speed_1s", -run(gravity, zero, 25)[13], 0.48612),
        ("gravity_sink_speed_2s", -run(gravity, zero, 50)[13], 0.50334),
        ("tail_angle_0.2s", run(dm, [1.0, 0.0, 0.0, 0.0, 0.0], 5)[0], 0.76544),
        ("fins_flap_angle_1s", run(dm, [0.0, 0.0, 1.0, 0.0, 0.0], 25)[3], 1.0045),
        (
            "finleft_pitch_angle_1s",
            run(dm, [0.0, 0.0, 0.0, 0.6, 0.0], 25)[6],
            0.58794,
        ),
        ("tail_yaw_rate_1s", run(dm, [1.0, 0.0, 0.0, 0.0, 0.0], 25)[16], -0.13977),
    ];
    for (name, ours, theirs) in rows {
        assert!(
            (ours / theirs - 1.0).abs() < 1e-3,
            "{name}: carl-spec {ours}, dm_control {theirs}"
        );
    }
}

/// The finger's metrics of `scripts/dmc_compare.py` (`finger_metrics`) at dm_control's values:
/// (name, value).
fn finger_metrics() -> Vec<(&'static str, f64)> {
    use carl_envs_dmc::finger::{Finger, Params, Task};
    use std::f64::consts::PI;
    let f64_obs = |e: &Finger| {
        let mut o = vec![0.0; 9];
        e.observe_f64_into(&mut o).unwrap();
        o
    };
    let run = |qvel: f64, action: [f32; 2], steps: usize| {
        let mut e = Finger::new(Params::default(), Task::Spin).unwrap();
        e.reset(Some(0));
        e.set_state(&[-PI / 2.0, 0.0, 0.0, 0.0, 0.0, qvel]).unwrap();
        let mut obs = vec![f64_obs(&e)];
        for _ in 0..steps {
            e.step(&Action::Continuous(action.to_vec())).unwrap();
            obs.push(f64_obs(&e));
        }
        obs
    };
    let turned = |obs: &[Vec<f64>]| {
        let mut out = vec![0.0];
        let (mut total, mut prev) = (0.0, obs[0][2].atan2(obs[0][3]));
        for o in &obs[1..] {
            let a = o[2].atan2(o[3]);
            total += (a - prev + PI).rem_euclid(2.0 * PI) - PI;
            prev = a;
            out.push(total);
        }
        out
    };
    let coast = run(10.0, [0.0, 0.0], 150);
    let ang = turned(&coast);
    let stop = coast.iter().position(|o| o[6].abs() < 0.05).unwrap_or(coast.len() - 1);
    let push = run(0.0, [1.0, 0.5], 100);
    let pang = turned(&push);
    vec![
        ("coast_speed_0.5s", coast[25][6]),
        ("coast_turned_0.5s", ang[25].abs()),
        ("coast_turned_1s", ang[50].abs()),
        ("coast_stop_time", 0.02 * stop as f64),
        ("push_proximal_0.2s", push[10][0]),
        ("push_touch_0.2s", push[10][7] + push[10][8]),
        ("push_turned_0.2s", pang[10].abs()),
        ("push_proximal_0.5s", push[25][0]),
        ("push_touch_0.5s", push[25][7] + push[25][8]),
        ("push_turned_0.5s", pang[25].abs()),
        ("push_proximal_2s", push[100][0]),
        ("push_turned_2s", pang[100].abs()),
    ]
}

#[test]
fn finger_coasts_and_pushes_as_dm_control() {
    // (metric, dm_control 1.0.50) as the script printed them.
    let dm = [
        ("coast_speed_0.5s", 0.8174056340331062),
        ("coast_turned_0.5s", 2.221937253706825),
        ("coast_turned_1s", 2.254984881400471),
        ("coast_stop_time", 0.6),
        ("push_proximal_0.2s", -0.20326419612097316),
        ("push_touch_0.2s", 4.412084006596887),
        ("push_turned_0.2s", 0.6770206693666876),
        ("push_proximal_0.5s", 0.2371301679264433),
        ("push_touch_0.5s", 4.670808331858963),
        ("push_turned_0.5s", 0.33216941136785705),
        ("push_proximal_2s", 1.9672410483653677),
        ("push_turned_2s", 4.208948179870141),
    ];
    for ((name, ours), (dname, theirs)) in finger_metrics().into_iter().zip(dm) {
        assert_eq!(name, dname);
        // Observed: every metric within 1e-10 of dm_control's.
        assert!(
            (ours - theirs).abs() <= 1e-7 * theirs.abs().max(1.0),
            "{name}: carl-spec {ours}, dm_control {theirs}"
        );
    }
}

/// dm_control's reset pose of seed 0 for walk (its orientation and non-contacting height, joints
/// at 0; `scripts/dmc_compare.py`'s `quadruped_start`), at rest, as carl-spec's state.
const QUADRUPED_DROP_QPOS: [f64; 7] = [
    0.0,
    0.0,
    0.89,
    0.5799686609772982,
    0.13155995106814494,
    0.3217803368403166,
    0.7367399448801994,
];
/// The non-contacting height of the upright (identity) orientation in dm_control.
const QUADRUPED_STAND_HEIGHT: f64 = 0.52;

fn quadruped_run(qpos_root: [f64; 7], action: [f32; 12], steps: usize) -> Vec<Vec<f64>> {
    use carl_envs_dmc::quadruped::{self, Quadruped};
    let mut e = Quadruped::new(quadruped::Params::default(), quadruped::WALK_SPEED).unwrap();
    e.reset(Some(0));
    let mut s = vec![0.0; e.state_dim()];
    s[..7].copy_from_slice(&qpos_root);
    e.set_state(&s).unwrap();
    let observe = |e: &Quadruped| {
        let mut o = vec![0.0; e.obs_dim()];
        e.observe_f64_into(&mut o).unwrap();
        o
    };
    let mut obs = vec![observe(&e)];
    for _ in 0..steps {
        e.step(&Action::Continuous(action.to_vec())).unwrap();
        obs.push(observe(&e));
    }
    obs
}

#[test]
fn quadruped_drops_and_servos_as_dm_control() {
    let drop = quadruped_run(QUADRUPED_DROP_QPOS, [0.0; 12], 150);
    let moving: Vec<bool> = drop
        .iter()
        .map(|o| {
            let hinge = o[16..32].iter().fold(0.0f64, |m, v| m.max(v.abs()));
            hinge.max((o[44] * o[44] + o[45] * o[45] + o[46] * o[46]).sqrt()) >= 0.05
        })
        .collect();
    let last = moving.iter().rposition(|m| *m).unwrap_or(0);
    let toe_force: f64 = (0..4)
        .map(|k| {
            drop[150][54 + 3 * k..57 + 3 * k]
                .iter()
                .map(|x| x.sinh().powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .sum();
    let servo = quadruped_run(
        [0.0, 0.0, QUADRUPED_STAND_HEIGHT, 1.0, 0.0, 0.0, 0.0],
        [0.0, 0.5, 0.3, 0.0, 0.5, 0.3, 0.0, 0.5, 0.3, 0.0, 0.5, 0.3],
        50,
    );
    // (metric, carl-spec, dm_control 1.0.50, tolerance)
    let rows = [
        ("drop_upright_0.5s", drop[25][47], 0.93468, 1e-4),
        ("drop_upright_3s", drop[150][47], 1.0, 1e-4),
        ("drop_time_to_rest", 0.02 * (last + 1) as f64, 1.5, 1e-9),
        ("drop_toe_force_3s", toe_force, 1008.8, 1e-4),
        ("servo_knee_1s", servo[50][2], -0.39173, 1e-4),
        ("servo_upright_1s", servo[50][47], 1.0, 1e-4),
    ];
    for (name, ours, theirs, _) in rows {
        eprintln!("{name}: carl-spec {ours:.6}, dm_control {theirs}");
    }
    for (name, ours, theirs, tol) in rows {
        assert!(
            (ours / theirs - 1.0).abs() < tol,
            "{name}: carl-spec {ours}, dm_control {theirs}"
        );
    }
}
