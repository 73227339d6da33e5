//! VehicleRacing (pixel observations): `cargo bench -p carl-envs-box2d`. A full step (physics +
//! 96×96 picture), the picture alone (`observe_into`), and the 600×400 `render()`.

use carl_env::api::{Action, Env};
use carl_env::rng::EnvRng;
use carl_envs_box2d::{VehicleRacing, VehicleRacingOptions, VehicleRacingParams};
use divan::{Bencher, black_box};

fn main() {
    divan::main();
}

const TABLE: usize = 4096;

fn racer() -> (VehicleRacing, Vec<Action>) {
    let mut e = VehicleRacing::with_options(VehicleRacingParams::default(), VehicleRacingOptions::default())
        .expect("the default vehicle");
    let mut rng = EnvRng::from_seed(7);
    let acts = (0..TABLE)
        .map(|_| {
            let steer = (2.0 * rng.next_f64() - 1.0) as f32;
            let gas = rng.next_f64() as f32;
            let brake = (0.2 * rng.next_f64()) as f32;
            Action::Continuous(vec![steer, gas, brake])
        })
        .collect();
    let mut obs = vec![0.0f32; e.obs_dim()];
    let _ = e.reset_into(Some(0), &mut obs);
    (e, acts)
}

#[divan::bench]
fn step(bencher: Bencher) {
    let (mut e, acts) = racer();
    let mut obs = vec![0.0f32; e.obs_dim()];
    let mut t = 0usize;
    bencher.bench_local(move || {
        t = (t + 1) % TABLE;
        if let Ok(out) = e.step_into(black_box(&acts[t]), &mut obs)
            && (out.terminated || out.truncated)
        {
            let _ = e.reset_into(None, &mut obs);
        }
        black_box(&obs);
    });
}

/// The observation picture of a car 60 steps into an episode (full zoom).
#[divan::bench]
fn observe(bencher: Bencher) {
    let (mut e, acts) = racer();
    let mut obs = vec![0.0f32; e.obs_dim()];
    for a in acts.iter().take(60) {
        let _ = e.step_into(a, &mut obs);
    }
    bencher.bench_local(move || {
        let _ = e.observe_into(&mut obs);
        black_box(&obs);
    });
}

#[divan::bench]
fn render_600x400(bencher: Bencher) {
    let (mut e, acts) = racer();
    let mut obs = vec![0.0f32; e.obs_dim()];
    for a in acts.iter().take(60) {
        let _ = e.step_into(a, &mut obs);
    }
    bencher.bench_local(move || black_box(e.render()));
}
