//! Counts BipedalWalker episodes whose hull flips past ±π in the air under random actions
//! (observation 0 leaves the observation space), where Gymnasium's Box2D walker ends the episode
//! on hull contact first (0 of 51 episodes, largest |angle| 2.53).
//!
//!     cargo run --release --example bipedal_walker_flips -- [EPISODES] [WARMSTART|box2d] [TRACE_EPISODE]
//!
//! Without `WARMSTART` (or with `box2d`) the default Box2D-semantics engine runs: 1 of 300
//! episodes flips (85, largest |angle| 3.21). A number runs the former rapier engine with that
//! contact warm-start factor; the measurements below are rapier's.
//!
//! Episode `e` resets with seed `e` and draws its actions uniformly in [-1, 1]^4 from
//! `Pcg64::new(e, 7)`. Measured (rapier2d 0.36.1, default options): 8 of 300 episodes flip
//! (65, 70, 128, 141, 152, 161, 196, 254), largest |angle| 10.0; with `WARMSTART` 0 none flips
//! (largest 2.78); 0.5 and 0.25 still flip 2, 0.1 and 0.05 none (largest 2.94). But as the default
//! 0.1 halves the replayed Box2D push-off's lift (vy 0.108 vs 0.210) and shortens the scripted
//! gait's episodes (seeds 0-9: 3686 steps vs 5844); 0 keeps the lift but vx drifts (2.219 vs
//! 2.249) and the episodes shorten less (5698). Turning off joint warm start alone
//! (`warmstart_joints`) changes nothing and holding Box2D's joint limits always on still flips 7:
//! the contact warm start is what throws the walker. In episode 65 the walker lands after a
//! jump and step 31 sends the hull from vy −3.9 to +8.1 m/s (ω +4 rad/s); the hull then turns
//! over in the air. `TRACE_EPISODE` prints that episode step by step.
use carl_spec::envs::box2d::{BipedalWalker, BipedalWalkerOptions, BipedalWalkerParams, WalkerEngine};
use carl_spec::envs::{Action, Env};
use carl_spec::sampling::{Pcg64, dist};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let episodes: u64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(300);
    let warmstart: Option<f64> = args.get(2).and_then(|s| s.parse().ok());
    let trace: Option<u64> = args.get(3).and_then(|s| s.parse().ok());
    let opts = match warmstart {
        Some(w) => BipedalWalkerOptions {
            engine: WalkerEngine::Rapier,
            warmstart_coefficient: w,
            ..Default::default()
        },
        None => BipedalWalkerOptions::default(),
    };
    let mut env = BipedalWalker::with_options(BipedalWalkerParams::default(), opts);
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
        "{}: {flipped} of {episodes} episodes flip past ±π ({steps_out} of {total} steps), largest |angle| {largest:.3}",
        warmstart.map_or("Box2D engine".to_string(), |w| format!("rapier, warm start {w}"))
    );
}
