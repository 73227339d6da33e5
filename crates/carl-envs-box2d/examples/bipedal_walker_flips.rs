//! Counts BipedalWalker episodes whose hull flips past ±π in the air under random actions
//! (observation 0 leaves the observation space), where Gymnasium's Box2D walker ends the episode
//! on hull contact first (0 of 51 episodes, largest |angle| 2.53).
//!
//!     cargo run --release -p carl-envs-box2d --example bipedal_walker_flips -- [EPISODES] [TRACE_EPISODE]
//!
//! Episode `e` resets with seed `e` and draws its actions uniformly in [-1, 1]^4 from
//! `Pcg64::new(e, 7)`. Measured on the Box2D-semantics engine: 1 of 300 episodes flips (85,
//! largest |angle| 3.21). The former rapier2d engine (removed) flipped 8 of 300 (largest 10.0):
//! its contact warm start threw the walker up at hard landings. `TRACE_EPISODE` prints that
//! episode step by step.
use carl_env::api::{Action, Env};
use carl_envs_box2d::{BipedalWalker, BipedalWalkerParams};
use carl_spec_core::sampling::{Pcg64, dist};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let episodes: u64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(300);
    let trace: Option<u64> = args.get(2).and_then(|s| s.parse().ok());
    let mut env = BipedalWalker::new(BipedalWalkerParams::default());
    let (mut flipped, mut steps_out, mut total, mut largest) = (0, 0, 0usize, 0f32);
    for ep in (0..episodes).filter(|&e| trace.is_none_or(|t| t == e)) {
        let mut rng = Pcg64::new(ep, 7);
        env.reset(Some(ep));
        let mut out = false;
        for t in 0..1600 {
            let a: Vec<f32> = (0..4).map(|_| dist::uniform(&mut rng, -1.0, 1.0) as f32).collect();
            let st = env.step(&Action::Continuous(a)).expect("valid action");
            let o = &st.obs;
            total += 1;
            largest = largest.max(o[0].abs());
            if trace.is_some() {
                let y: Vec<String> = env
                    .body_states()
                    .unwrap()
                    .iter()
                    .map(|b| format!("{:.2}", b.y))
                    .collect();
                let hull = env.body_states().unwrap()[0];
                println!(
                    "{t}: y {y:?} hull vy {:.2} angle {:.3} w {:.2} joints [{:.2} {:.2} {:.2} {:.2}] contacts {} {}",
                    hull.vy,
                    o[0],
                    hull.w,
                    o[4],
                    o[6] - 1.0,
                    o[9],
                    o[11] - 1.0,
                    o[8],
                    o[13]
                );
            }
            if o[0].abs() > std::f32::consts::PI {
                steps_out += 1;
                if !out {
                    println!("episode {ep}: |angle| > π from step {t} ({})", o[0]);
                }
                out = true;
            }
            if st.terminated {
                break;
            }
        }
        flipped += usize::from(out);
    }
    println!(
        "{flipped} of {episodes} episodes flip past ±π ({steps_out} of {total} steps), largest |angle| {largest:.3}"
    );
}
