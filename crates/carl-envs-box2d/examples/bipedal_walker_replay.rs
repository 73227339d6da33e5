//! Replays Gymnasium's BipedalWalker one step at a time: every recorded Box2D state is loaded
//! here (`set_state`, on Gymnasium's own course), stepped with Box2D's action, and compared with
//! Box2D's next state. Prints one line per step (hull velocity error, joint speed errors, contact
//! flags, ground impulse of both engines) and the mean hull velocity error.
//!
//!     python3 scripts/bipedal_walker_record_box2d.py --seed 0 --steps 400 > rec.json
//!     cargo run --release -p carl-envs-box2d --example bipedal_walker_replay -- rec.json

use carl_env::api::{Action, Env};
use carl_envs_box2d::bipedal_walker::{Terrain, TerrainSpec};
use carl_envs_box2d::{BipedalWalker, BipedalWalkerParams};
use serde_json::Value;

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .map_or(Vec::new(), |a| a.iter().filter_map(Value::as_f64).collect())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let usage = "usage: bipedal_walker_replay RECORDING.json";
    let (Some(path), 2) = (args.get(1), args.len()) else {
        return Err(usage.into());
    };
    let rec: Value = serde_json::from_str(&std::fs::read_to_string(path)?)?;
    let p = BipedalWalkerParams {
        terrain_height: 400.0 / 30.0 / 4.0, // Gymnasium's TERRAIN_HEIGHT
        ..BipedalWalkerParams::default()
    };
    let mut env = BipedalWalker::new(p);
    env.reset(Some(0));
    let (x, y) = (floats(&rec["terrain_x"]), floats(&rec["terrain_y"]));
    let spec = TerrainSpec {
        seed: 0,
        step: 14.0 / 30.0,
        length: x.len(),
        height: p.terrain_height,
        grass: 10,
        startpad: 20,
        scale: 30.0,
        hardcore: false,
    };
    env.set_course(Terrain {
        spec,
        x,
        y,
        quads: Vec::new(),
        kinds: Vec::new(),
    });
    let base = env.state();
    eprintln!("hull mass here {:?} (Box2D 5.4222226)", env.hull_mass());
    // Box2D's masses (hull, upper 0, lower 0, upper 1, lower 1) for the ground impulse.
    let masses = [5.4222226, 0.3022222, 0.2417778, 0.3022222, 0.2417778];
    let total: f64 = masses.iter().sum();
    let momentum = |bodies: &[Vec<f64>]| -> (f64, f64) {
        (0..5).fold((0.0, 0.0), |(px, py), k| {
            (px + masses[k] * bodies[k][3], py + masses[k] * bodies[k][4])
        })
    };
    let steps = rec["steps"].as_array().ok_or("recording without steps")?;
    let (mut sum_dv, mut n) = (0.0, 0usize);
    for r in steps {
        let (before, after) = (&r["before"], &r["after"]);
        let mut s = base.clone();
        s[..6].copy_from_slice(&floats(&before["hull"]));
        s[6..10].copy_from_slice(&floats(&before["q"]));
        s[10..14].copy_from_slice(&floats(&before["dq"]));
        s[14..16].copy_from_slice(&floats(&before["contact"]));
        env.set_state(&s)?;
        let a: Vec<f32> = floats(&r["action"]).iter().map(|v| *v as f32).collect();
        env.step(&Action::Continuous(a))?;
        let h = env.state();
        let here: Vec<Vec<f64>> = env
            .body_states()
            .ok_or("no world")?
            .iter()
            .map(|b| vec![b.x, b.y, b.angle, b.vx, b.vy, b.w])
            .collect();
        let b0: Vec<Vec<f64>> = before["bodies"]
            .as_array()
            .ok_or("bodies")?
            .iter()
            .map(floats)
            .collect();
        let b1: Vec<Vec<f64>> = after["bodies"].as_array().ok_or("bodies")?.iter().map(floats).collect();
        let (p0, p1, ph) = (momentum(&b0), momentum(&b1), momentum(&here));
        let (hull, dq, contact) = (floats(&after["hull"]), floats(&after["dq"]), floats(&after["contact"]));
        let dv = (h[3] - hull[3]).hypot(h[4] - hull[4]);
        sum_dv += dv;
        n += 1;
        let ddq: Vec<String> = (0..4).map(|j| format!("{:+.2}", h[10 + j] - dq[j])).collect();
        println!(
            "{:4} dv {dv:.3} dw {:.3} ddq [{}] flags box2d {:?} here [{}, {}] ground impulse y box2d {:.2} here {:.2}",
            r["t"],
            (h[5] - hull[5]).abs(),
            ddq.join(" "),
            contact,
            h[14],
            h[15],
            p1.1 - p0.1 + total * 10.0 / 50.0,
            ph.1 - p0.1 + total * 10.0 / 50.0,
        );
    }
    println!(
        "mean hull velocity error over {n} steps: {:.4} m/s",
        sum_dv / n.max(1) as f64
    );
    Ok(())
}
