//! Mario runtime speed: `cargo bench -p carl-mario --bench mario` (needs the data directory:
//! `CARL_SPEC_DATA`, else `shared/data` beside the checkout).
//!
//! * `engine_ticks`: engine ticks per second, scripted play (random CARL actions, fixed table) on
//!   original level 1 and a generated level; an episode restarts when it ends.
//! * `env_steps`: agent steps (2 ticks + reward) per second, without pixels and with the 64×64
//!   and 84×84 grayscale observation.
//! * `generate_level`: TOAD-GAN level generation (widths 100 and 1000).

use carl_mario::DataDir;
use carl_mario::engine::Level;
use carl_mario::game::{ACTIONS, Game};
use carl_mario::render::observe_gray;
use carl_mario::toad_gan::{Generator, WidthMismatch};
use divan::counter::ItemsCount;
use divan::{Bencher, black_box};
use std::path::Path;

fn main() {
    divan::main();
}

fn data() -> DataDir {
    DataDir::discover(Path::new(env!("CARGO_MANIFEST_DIR"))).expect("Mario data directory")
}

fn level(which: &str) -> Level {
    let data = data();
    let text = match which {
        "lvl-1" => std::fs::read_to_string(data.original_level(1)).unwrap(),
        _ => Generator::load_index(&data, 0)
            .unwrap()
            .generate(100, 0, WidthMismatch::Reject)
            .unwrap(),
    };
    Level::parse(&text, which).unwrap()
}

/// A fixed pseudo-random action table biased to the right (mostly actions 2–5).
fn actions() -> Vec<usize> {
    let mut x = 0x2545_f491_4f6c_dd1du64;
    (0..4096)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            [2, 3, 3, 4, 5, 5, 5, 0, 9, 6][(x % 10) as usize]
        })
        .collect()
}

const TICKS: usize = 10_000;

#[divan::bench(args = ["lvl-1", "generated"])]
fn engine_ticks(bencher: Bencher, which: &str) {
    let lvl = level(which);
    let acts = actions();
    bencher.counter(ItemsCount::new(TICKS)).bench_local(|| {
        let mut g = Game::reset(lvl.clone(), 0.89, 0);
        for t in 0..TICKS {
            if g.world.status != carl_mario::engine::Status::Running {
                g = Game::reset(lvl.clone(), 0.89, 0);
            }
            g.world.tick(ACTIONS[acts[(t / 2) % acts.len()]]);
        }
        black_box(g.world.mario().x)
    });
}

const STEPS: usize = 2_000;

#[divan::bench(args = [0, 64, 84])]
fn env_steps(bencher: Bencher, frame_dim: usize) {
    let lvl = level("generated");
    let acts = actions();
    let mut obs = vec![0u8; frame_dim * frame_dim];
    bencher.counter(ItemsCount::new(STEPS)).bench_local(|| {
        let mut g = Game::reset(lvl.clone(), 0.89, 0);
        for k in 0..STEPS {
            let r = g.step(acts[k % acts.len()]);
            if frame_dim > 0 {
                observe_gray(&g.world, frame_dim, &mut obs);
            }
            if r.terminated || r.truncated {
                g = Game::reset(lvl.clone(), 0.89, 0);
            }
        }
        black_box(obs.first().copied())
    });
}

#[divan::bench(args = [100, 1000], sample_count = 10)]
fn generate_level(bencher: Bencher, width: usize) {
    let g = Generator::load_index(&data(), 0).unwrap();
    bencher.bench_local(|| black_box(g.generate(width, 0, WidthMismatch::Reject).unwrap()));
}

#[divan::bench(sample_count = 10)]
fn load_generator(bencher: Bencher) {
    let data = data();
    bencher.bench_local(|| black_box(Generator::load_index(&data, 0).unwrap()));
}
