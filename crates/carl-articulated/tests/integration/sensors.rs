//! Parity with MuJoCo on dm_control's quadruped without actuators
//! (`scripts/articulated_quadruped_fixture.py`): the torso's ellipsoid on the floor, the four
//! tendon equalities coupling each leg, and the site sensors (accelerometer, gyro, velocimeter,
//! force, torque, subtree centre of mass). Sensors are compared at MuJoCo's own states (each
//! record restarts from its `qpos`/`qvel`), so the trajectory's divergence does not enter;
//! the trajectory itself is compared over its contact-free start (to rounding) and then on the
//! floor (to the solvers' tolerances).

use std::sync::Arc;

use carl_articulated::{Data, Site};
use serde_json::Value;

use super::fixture::{f, fs, load, model};

fn site(s: &Value) -> Site {
    let p = fs(&s["pos"]);
    let q = fs(&s["quat"]);
    Site {
        body: s["body"].as_u64().unwrap() as usize,
        pos: [p[0], p[1], p[2]],
        mat: carl_articulated::math::quat_to_mat([q[0], q[1], q[2], q[3]]),
    }
}

/// Our reading of each of the fixture's sensors at `d`'s state (after forward and
/// rne_post_constraint), concatenated in MuJoCo's `sensordata` order.
fn readings(d: &Data, sensors: &[Value]) -> Vec<f64> {
    let mut out = Vec::new();
    for s in sensors {
        let v = match s["kind"].as_str().unwrap() {
            "subtreecom" => d.subtree_com(s["body"].as_u64().unwrap() as usize),
            kind => {
                let st = site(&s["site"]);
                match kind {
                    "accelerometer" => d.accelerometer(&st),
                    "gyro" => d.gyro(&st),
                    "velocimeter" => d.velocimeter(&st),
                    "force" => d.force_sensor(&st),
                    "torque" => d.torque_sensor(&st),
                    other => panic!("sensor kind {other}"),
                }
            }
        };
        out.extend_from_slice(&v);
    }
    out
}

#[test]
fn quadruped_constants_match_mujoco() {
    let fx = load("quadruped");
    let m = model(&fx);
    for (a, b) in m.tendon_invweight0.iter().zip(fs(&fx["model"]["tendon_invweight0"])) {
        assert!((a - b).abs() < 1e-6 * b.abs(), "tendon_invweight0 {a} vs MuJoCo {b}");
    }
}

#[test]
fn quadruped_sensors_match_mujoco_at_its_states() {
    let fx = load("quadruped");
    let sensors = fx["sensors"].as_array().unwrap().clone();
    let mut d = Data::new(Arc::new(model(&fx)));
    let mut worst = vec![0.0f64; sensors.len()];
    for rec in fx["trajectory"].as_array().unwrap() {
        d.qpos.copy_from_slice(&fs(&rec["qpos"]));
        d.qvel.copy_from_slice(&fs(&rec["qvel"]));
        // Twice: the second solve starts warm from the first (as MuJoCo's from its last step).
        d.forward();
        d.forward();
        d.rne_post_constraint();
        assert_eq!(
            d.ncon as u64,
            rec["ncon"].as_u64().unwrap(),
            "contacts at step {}",
            rec["step"]
        );
        let ours = readings(&d, &sensors);
        let theirs = fs(&rec["sensordata"]);
        for (k, s) in sensors.iter().enumerate() {
            let a = s["adr"].as_u64().unwrap() as usize;
            for i in a..a + 3 {
                let e = (ours[i] - theirs[i]).abs() / theirs[a..a + 3].iter().fold(1.0f64, |m, x| m.max(x.abs()));
                worst[k] = worst[k].max(e);
            }
        }
    }
    for (s, w) in sensors.iter().zip(&worst) {
        let name = s["name"].as_str().unwrap();
        if std::env::var("ARTICULATED_TRACE").is_ok() {
            eprintln!("{name}: {w:.2e}");
        }
        // Contact forces enter the accelerations through the solver (MuJoCo's Newton and ours,
        // each to its tolerance).
        assert!(*w < 1e-6, "{name}: relative deviation {w:.2e}");
    }
}

#[test]
fn quadruped_trajectory_matches_mujoco() {
    let fx = load("quadruped");
    let mut d = Data::new(Arc::new(model(&fx)));
    d.qpos.copy_from_slice(&fs(&fx["qpos0"]));
    d.qvel.copy_from_slice(&fs(&fx["qvel0"]));
    let mut step = 0;
    for rec in fx["trajectory"].as_array().unwrap() {
        let target = rec["step"].as_u64().unwrap() as usize;
        while step < target {
            d.step();
            step += 1;
        }
        assert!((d.time - f(&rec["time"])).abs() < 1e-9);
        let dq = fs(&rec["qpos"])
            .iter()
            .zip(&d.qpos)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        // Contact-free until step 30: to rounding; then on the floor to the solvers' tolerances
        // (5e-6 observed).
        let tol = if target <= 20 { 1e-9 } else { 5e-5 };
        if std::env::var("ARTICULATED_TRACE").is_ok() {
            eprintln!("step {target}: qpos {dq:.3e} ncon {} vs {}", d.ncon, rec["ncon"]);
        }
        assert!(dq < tol, "step {target}: qpos deviates by {dq:.3e}");
    }
}
