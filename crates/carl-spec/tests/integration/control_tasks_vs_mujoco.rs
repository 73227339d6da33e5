//! carl-spec's side of the InvertedPendulum, InvertedDoublePendulum, Reacher and Pusher rows of
//! the robots-versus-MuJoCo table (`scripts/robot_mujoco_compare.py --robots
//! inverted_pendulum,inverted_double_pendulum,reacher,pusher --episodes 100`), at each spec's frozen
//! instance set `mujoco_v5` (MuJoCo v5's own model values): the script's metrics (`CONTROL`
//! there) computed through the library with the same initial states, actions and seeds, and
//! pinned. The MuJoCo column beside each pin is the script's measurement of Gymnasium 1.4
//! (mujoco 4.0.0); the test also checks that every pinned metric the docs report as within
//! ±15 % of MuJoCo's still is. A legitimate model change re-runs the script and updates both.

use crate::common;
use carl_spec::envs::registry::{Context, EnvOptions, MakeOptions, SpecEnv, make_env};
use carl_spec::envs::{Action, Env};
use carl_spec::instances::Store;
use carl_spec::spec::SpecSet;

/// How a step response is read from the observation.
#[derive(Clone, Copy)]
enum Read {
    Obs(usize),
    /// `atan2(obs[sin], obs[cos])`.
    Angle(usize, usize),
}

/// What the script knows about each task (`CONTROL` there).
struct Task {
    id: &'static str,
    na: usize,
    dt: f64,
    /// Rest state (carl-spec's layout) and the index of the tilted coordinate.
    rest: &'static [f64],
    tilt: Option<usize>,
    tilts: &'static [f64],
    /// (actuator, control, how to read).
    steps: &'static [(usize, f32, Read)],
    at: [usize; 2],
    /// Coasting joints (Pusher): (observation index of the angle, state index of its rate,
    /// which starts at 1 rad/s).
    coast: &'static [(usize, usize)],
}

const IP: Task = Task {
    id: "inverted_pendulum",
    na: 1,
    dt: 0.04,
    rest: &[0.0; 4],
    tilt: Some(1),
    tilts: &[0.02, 0.05],
    steps: &[(0, 0.2, Read::Obs(0)), (0, 0.2, Read::Obs(1))],
    at: [3, 6],
    coast: &[],
};
const IDP: Task = Task {
    id: "inverted_double_pendulum",
    na: 1,
    dt: 0.05,
    rest: &[0.0; 7],
    tilt: Some(1),
    tilts: &[0.02, 0.05],
    steps: &[
        (0, 0.1, Read::Obs(0)),
        (0, 0.1, Read::Angle(1, 3)),
        (0, 0.1, Read::Angle(2, 4)),
    ],
    at: [2, 5],
    coast: &[],
};
const REACHER: Task = Task {
    id: "reacher",
    na: 2,
    dt: 0.02,
    rest: &[0.0, 0.0, 0.1, 0.1, 0.0, 0.0],
    tilt: None,
    tilts: &[],
    steps: &[(0, 1.0, Read::Angle(2, 0)), (1, 1.0, Read::Angle(3, 1))],
    at: [5, 12],
    coast: &[],
};
/// The arm at 0, the object's slides (y, x) at (-0.3, 0.2), out of the arm's way; every motor at
/// full scale towards the inside of its range; the shoulder pan and the elbow coasting.
const PUSHER: Task = Task {
    id: "pusher",
    na: 7,
    dt: 0.05,
    rest: &[
        0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -0.3, 0.2, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
    ],
    tilt: None,
    tilts: &[],
    steps: &[
        (0, 2.0, Read::Obs(0)),
        (1, 2.0, Read::Obs(1)),
        (2, 2.0, Read::Obs(2)),
        (3, -2.0, Read::Obs(3)),
        (4, 2.0, Read::Obs(4)),
        (5, -2.0, Read::Obs(5)),
        (6, 2.0, Read::Obs(6)),
    ],
    at: [2, 5],
    coast: &[(0, 9), (3, 12)],
};

fn env(id: &str) -> SpecEnv {
    let specs = SpecSet::bundled().unwrap();
    let set = Store::new(&specs).load(&format!("{id}/mujoco_v5")).unwrap();
    let ctx: Context = set.instances[0].context.clone().into_iter().collect();
    // MuJoCo's values, Pusher's partly outside carl-bench's bounds (the set allows it).
    let opts = MakeOptions {
        allow_out_of_bounds: true,
    };
    make_env(specs.get(id).unwrap(), &ctx, opts, &EnvOptions::new()).unwrap()
}

/// Observations (from the state `init`) under `actions`, stopping when the episode ends.
fn run(e: &SpecEnv, init: &[f64], actions: &[Vec<f32>]) -> Vec<Vec<f32>> {
    let mut e = e.clone();
    e.reset(Some(0));
    e.set_state(init).unwrap();
    let mut all = vec![e.observe()];
    for a in actions {
        let s = e.step(&Action::Continuous(a.clone())).unwrap();
        all.push(s.obs);
        if s.terminated || s.truncated {
            break;
        }
    }
    all
}

/// The coordinate at observation `n`; an angle unwrapped along the run (as the script's
/// `read`).
fn read(obs: &[Vec<f32>], n: usize, how: Read) -> f64 {
    use std::f64::consts::PI;
    match how {
        Read::Obs(i) => f64::from(obs[n][i]),
        Read::Angle(s, c) => {
            let mut total = 0.0;
            let mut prev: Option<f64> = None;
            for o in &obs[..=n] {
                let a = f64::from(o[s]).atan2(f64::from(o[c]));
                total = match prev {
                    Some(p) => total + (a - p + PI).rem_euclid(2.0 * PI) - PI,
                    None => a,
                };
                prev = Some(a);
            }
            total
        }
    }
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

/// The fall times, step responses, random-policy mean length and mean return.
fn measure(t: &Task) -> Vec<(String, f64)> {
    let e = env(t.id);
    let zero = vec![0.0f32; t.na];
    let mut out = Vec::new();
    for &tilt in t.tilts {
        let mut s = t.rest.to_vec();
        s[t.tilt.unwrap()] = tilt;
        let n = run(&e, &s, &vec![zero.clone(); 1000]).len() - 1;
        out.push((format!("fall_time_{tilt}"), n as f64 * t.dt));
    }
    let horizon = t.at[1];
    for (k, &(obs_index, rate)) in t.coast.iter().enumerate() {
        let mut s = t.rest.to_vec();
        s[rate] = 1.0;
        let obs = run(&e, &s, &vec![zero.clone(); horizon]);
        for &n in &t.at {
            out.push((format!("coast_{k}_{n}"), f64::from(obs[n][obs_index])));
        }
    }
    let base = run(&e, t.rest, &vec![zero.clone(); horizon]);
    for (k, &(act, u, how)) in t.steps.iter().enumerate() {
        let mut a = zero.clone();
        a[act] = u;
        let obs = run(&e, t.rest, &vec![a; horizon]);
        for &n in &t.at {
            if n < obs.len() {
                out.push((format!("step_{k}_{n}"), read(&obs, n, how) - read(&base, n, how)));
            }
        }
    }
    let (lens, rets) = common::random_episodes(0..100, || e.clone());
    out.push(("random_length".to_string(), mean(&lens)));
    out.push(("random_return".to_string(), mean(&rets)));
    out
}

/// `(metric, pinned carl-spec value, tolerance of the pin, MuJoCo's value, whether the docs
/// report it within ±15 % of MuJoCo's)`.
type Pin = (&'static str, f64, f64, f64, bool);

fn check(t: &Task, pins: &[Pin]) {
    let got = measure(t);
    if std::env::var_os("CARL_SPEC_PRINT_PINS").is_some() {
        for (n, v) in &got {
            eprintln!("{} {n} {v:.4}", t.id);
        }
    }
    let names: Vec<&str> = got.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        pins.iter().map(|p| p.0).collect::<Vec<_>>(),
        "{}: metric list",
        t.id
    );
    let mut misses = Vec::new();
    for ((name, value), &(_, pin, tol, mujoco, within)) in got.iter().zip(pins) {
        if (value - pin).abs() > tol {
            misses.push(format!("{} {name}: {value} (pinned {pin} ± {tol})", t.id));
        }
        if within && (value / mujoco - 1.0).abs() > 0.15 {
            misses.push(format!("{} {name}: {value} vs MuJoCo's {mujoco}: beyond ±15 %", t.id));
        }
    }
    assert!(misses.is_empty(), "{}", misses.join("\n"));
}

#[test]
fn inverted_pendulum_side_of_the_mujoco_table() {
    check(&IP, PIN_IP);
}

#[test]
fn inverted_double_pendulum_side_of_the_mujoco_table() {
    check(&IDP, PIN_IDP);
}

#[test]
fn reacher_side_of_the_mujoco_table() {
    check(&REACHER, PIN_REACHER);
}

#[test]
fn pusher_side_of_the_mujoco_table() {
    check(&PUSHER, PIN_PUSHER);
}

// Reacher's random episodes all last 50 steps (no termination).
const PIN_IP: &[Pin] = &[
    ("fall_time_0.02", 0.6400, 0.0410, 0.6400, true),
    ("fall_time_0.05", 0.4400, 0.0410, 0.4400, true),
    ("step_0_3", 0.0119, 0.0005, 0.0119, true),
    ("step_0_6", 0.0476, 0.0014, 0.0476, true),
    ("step_1_3", -0.0270, 0.0008, -0.0270, true),
    ("step_1_6", -0.1104, 0.0033, -0.1104, true),
    ("random_length", 6.3800, 1.2760, 6.6300, true),
    ("random_return", 5.3800, 1.0760, 5.6300, true),
];

const PIN_IDP: &[Pin] = &[
    ("fall_time_0.02", 0.6500, 0.0410, 0.6500, true),
    ("fall_time_0.05", 0.5500, 0.0410, 0.5500, true),
    ("step_0_2", 0.0214, 0.0006, 0.0214, true),
    ("step_0_5", 0.1390, 0.0042, 0.1390, true),
    ("step_1_2", -0.0450, 0.0013, -0.0450, true),
    ("step_1_5", -0.3336, 0.0100, -0.3336, true),
    ("step_2_2", 0.0584, 0.0018, 0.0584, true),
    ("step_2_5", 0.4745, 0.0142, 0.4745, true),
    ("random_length", 6.4400, 1.2880, 6.6000, true),
    ("random_return", 48.6701, 9.7340, 50.0978, true),
];

const PIN_REACHER: &[Pin] = &[
    ("step_0_5", 0.9664, 0.0290, 0.9664, true),
    ("step_0_12", 5.3199, 0.1596, 5.3199, true),
    ("step_1_5", 0.9673, 0.0290, 0.9673, true),
    ("step_1_12", 3.0943, 0.0928, 3.0943, true),
    ("random_length", 50.0000, 0.5000, 50.0000, true),
    ("random_return", -43.1030, 8.6206, -42.8759, true),
];

// Pusher's random episodes all last 100 steps (no termination).
const PIN_PUSHER: &[Pin] = &[
    ("coast_0_2", 0.0944, 0.0028, 0.0944, true),
    ("coast_0_5", 0.2188, 0.0066, 0.2188, true),
    ("coast_1_2", -0.0062, 0.0005, -0.0062, true),
    ("coast_1_5", -0.0182, 0.0005, -0.0182, true),
    ("step_0_2", 0.0111, 0.0005, 0.0111, true),
    ("step_0_5", 0.0625, 0.0019, 0.0625, true),
    ("step_1_2", 0.0233, 0.0007, 0.0233, true),
    ("step_1_5", 0.1216, 0.0036, 0.1216, true),
    ("step_2_2", 0.2198, 0.0066, 0.2198, true),
    ("step_2_5", 1.1739, 0.0352, 1.1739, true),
    ("step_3_2", -0.1560, 0.0047, -0.1560, true),
    ("step_3_5", -0.8198, 0.0246, -0.8198, true),
    ("step_4_2", 0.2375, 0.0071, 0.2375, true),
    ("step_4_5", 1.2579, 0.0377, 1.2579, true),
    ("step_5_2", -0.2474, 0.0074, -0.2474, true),
    ("step_5_5", -1.1132, 0.0334, -1.1132, true),
    ("step_6_2", 0.2424, 0.0073, 0.2424, true),
    ("step_6_5", 1.2815, 0.0384, 1.2815, true),
    ("random_length", 100.0000, 0.5000, 100.0000, true),
    ("random_return", -149.1301, 29.8260, -148.4548, true),
];
