//! Environment stepping speed: `cargo bench --bench envs`.
//!
//! * `single::*`: one environment's `step_into` (default context, random actions drawn
//!   beforehand, auto-reset when an episode ends); divan reports time per step.
//! * `vec::*`: one `VecEnv::step` over `num_envs` environments with 1 or 2 threads; divan reports
//!   environment steps per second (items/s).
//!
//! Both step through `carl_spec::bench`'s runners, the same loops `carl-spec bench` times.
//! * `multibody::*`: the patched rapier3d's per-substep multibody work on a robot at rest after
//!   a few steps: the tree-sparse Jacobians, mass matrices and factorizations (`sparse`), beside
//!   upstream's dense assembly with the same factorizations (`dense_reference`), and one
//!   `M⁻¹·b` solve (`solve`). See vendor/rapier3d/README.md.

use carl_spec::bench::{SingleRunner, VecRunner};
use carl_spec::envs::registry::{Context, SpecEnv, make};
use carl_spec::envs::rng::EnvRng;
use carl_spec::envs::{Action, Env};
use carl_spec::spec::SpecSet;
use divan::counter::ItemsCount;
use divan::{Bencher, black_box};

fn main() {
    divan::main();
}

const TABLE: usize = 4096;

fn env(id: &str) -> SpecEnv {
    let specs = SpecSet::bundled().expect("bundled specs");
    make(specs.get(id).expect("spec"), &Context::new()).expect("make")
}

mod single {
    use super::*;

    fn run(bencher: Bencher, id: &str) {
        let specs = SpecSet::bundled().expect("bundled specs");
        let mut r = SingleRunner::new(specs.get(id).expect("spec")).expect("runner");
        bencher.bench_local(move || r.step());
    }

    #[divan::bench]
    fn cartpole(b: Bencher) {
        run(b, "cartpole");
    }
    #[divan::bench]
    fn pendulum(b: Bencher) {
        run(b, "pendulum");
    }
    #[divan::bench]
    fn mountain_car(b: Bencher) {
        run(b, "mountain_car");
    }
    #[divan::bench]
    fn mountain_car_continuous(b: Bencher) {
        run(b, "mountain_car_continuous");
    }
    #[divan::bench]
    fn acrobot(b: Bencher) {
        run(b, "acrobot");
    }
    /// Closed-form free flight, src/physics2d near the ground (one world per instance); random
    /// actions, so episodes (and resets) are short.
    #[divan::bench]
    fn lunar_lander(b: Bencher) {
        run(b, "lunar_lander");
    }
    #[divan::bench]
    fn bipedal_walker(b: Bencher) {
        run(b, "bipedal_walker");
    }
    /// 3-D multibody robot on rapier3d (5 physics steps per env step).
    #[divan::bench(sample_count = 20, sample_size = 20)]
    fn ant(b: Bencher) {
        run(b, "ant");
    }
    /// The planar reduced-coordinate engine (5 physics steps per env step).
    #[divan::bench(sample_count = 20, sample_size = 20)]
    fn half_cheetah(b: Bencher) {
        run(b, "half_cheetah");
    }
    /// Fixed-base arm, no contacts (4 physics steps per env step).
    #[divan::bench(sample_count = 20, sample_size = 20)]
    fn ur5e(b: Bencher) {
        run(b, "ur5e");
    }
    /// Brax's fetch dog (eleven boxes, 4 physics steps per env step).
    #[divan::bench(sample_count = 20, sample_size = 20)]
    fn fetch(b: Bencher) {
        run(b, "fetch");
    }
    /// Humanoid: 20 links (13 bodies), 23 DoFs, 2 solver iterations; MuJoCo's Humanoid-v5 runs
    /// ~1.2 k steps/s (single env, Gymnasium) on the reference machine.
    #[divan::bench(sample_count = 20, sample_size = 20)]
    fn humanoid(b: Bencher) {
        run(b, "humanoid");
    }
    /// Brax's claw hand and a free ball (21 links, 19 DoFs, 4 physics steps per env step).
    #[divan::bench(sample_count = 10, sample_size = 10)]
    fn grasp(b: Bencher) {
        run(b, "grasp");
    }
}

mod vec {
    use super::*;

    const NUM_ENVS: &[usize] = &[1, 64, 1024];

    fn run(bencher: Bencher, id: &str, n: usize, threads: usize) {
        let specs = SpecSet::bundled().expect("bundled specs");
        let mut r = VecRunner::new(specs.get(id).expect("spec"), n, threads).expect("VecRunner");
        bencher.counter(ItemsCount::new(n)).bench_local(move || r.step());
    }

    #[divan::bench(args = NUM_ENVS)]
    fn cartpole_1t(b: Bencher, n: usize) {
        run(b, "cartpole", n, 1);
    }
    #[divan::bench(args = NUM_ENVS)]
    fn cartpole_2t(b: Bencher, n: usize) {
        run(b, "cartpole", n, 2);
    }
    #[divan::bench(args = NUM_ENVS)]
    fn pendulum_1t(b: Bencher, n: usize) {
        run(b, "pendulum", n, 1);
    }
    #[divan::bench(args = NUM_ENVS)]
    fn pendulum_2t(b: Bencher, n: usize) {
        run(b, "pendulum", n, 2);
    }
    /// envpool's reference point: 64 landers on 2 threads.
    #[divan::bench(args = [64])]
    fn lunar_lander_2t(b: Bencher, n: usize) {
        run(b, "lunar_lander", n, 2);
    }
    /// A physics world per environment: 64 walkers only (1024 take minutes per sample).
    #[divan::bench(args = [64])]
    fn bipedal_walker_2t(b: Bencher, n: usize) {
        run(b, "bipedal_walker", n, 2);
    }
    const ROBOT_ENVS: &[usize] = &[16];

    #[divan::bench(args = ROBOT_ENVS, sample_count = 10, sample_size = 2)]
    fn ant_1t(b: Bencher, n: usize) {
        run(b, "ant", n, 1);
    }
    #[divan::bench(args = ROBOT_ENVS, sample_count = 10, sample_size = 2)]
    fn ant_2t(b: Bencher, n: usize) {
        run(b, "ant", n, 2);
    }
    #[divan::bench(args = ROBOT_ENVS, sample_count = 10, sample_size = 2)]
    fn half_cheetah_1t(b: Bencher, n: usize) {
        run(b, "half_cheetah", n, 1);
    }
    #[divan::bench(args = ROBOT_ENVS, sample_count = 10, sample_size = 2)]
    fn half_cheetah_2t(b: Bencher, n: usize) {
        run(b, "half_cheetah", n, 2);
    }
    #[divan::bench(args = ROBOT_ENVS, sample_count = 10, sample_size = 2)]
    fn ur5e_2t(b: Bencher, n: usize) {
        run(b, "ur5e", n, 2);
    }
}

/// VehicleRacing (pixel observations): a full step (physics + 96×96 picture), the picture alone
/// (`observe_into`), and the 600×400 `render()`.
mod vehicle_racing {
    use super::*;

    fn racer() -> (SpecEnv, Vec<Action>) {
        let mut e = env("vehicle_racing");
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
            if let Ok(out) = e.step_into(black_box(&acts[t]), &mut obs) {
                if out.terminated || out.truncated {
                    let _ = e.reset_into(None, &mut obs);
                }
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
}

mod multibody {
    use super::*;
    use carl_spec::envs::brax::world::{Configuration, RobotWorld};
    use carl_spec::envs::brax::{RobotModel, default_params};
    use rapier3d::na::DVector;

    const ROBOTS: &[&str] = &["ant", "half_cheetah", "humanoid"];

    /// The robot in its default pose after 5 physics steps with a constant control.
    fn world(id: &str) -> RobotWorld {
        let model = RobotModel::load(id).expect("robot model");
        let params = default_params(id).expect("params");
        let n = model.joint_names.len();
        let at_rest = Configuration {
            root: vec![],
            joints: vec![0.0; n],
            vel: vec![0.0; n],
        };
        let probe = RobotWorld::build(&model, &params, &at_rest);
        let root = if probe.root_dofs() == 6 {
            vec![0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0]
        } else {
            vec![]
        };
        let q = Configuration {
            root,
            joints: vec![0.1; n],
            vel: vec![0.5; probe.root_dofs() + n],
        };
        let mut w = RobotWorld::build(&model, &params, &q);
        let ctrl = vec![0.3f32; model.num_actuators()];
        for _ in 0..5 {
            w.step(&ctrl);
        }
        w
    }

    #[divan::bench(args = ROBOTS)]
    fn sparse(b: Bencher, id: &str) {
        let w = world(id);
        let dt = w.pw.integration_parameters.dt;
        let mut mb = w.multibody().clone();
        b.bench_local(|| mb.update_sparse(dt, black_box(&w.pw.bodies)));
    }

    #[divan::bench(args = ROBOTS)]
    fn dense_reference(b: Bencher, id: &str) {
        let w = world(id);
        let dt = w.pw.integration_parameters.dt;
        let mut mb = w.multibody().clone();
        b.bench_local(|| mb.update_dense_reference(dt, black_box(&w.pw.bodies)));
    }

    #[divan::bench(args = ROBOTS)]
    fn solve(b: Bencher, id: &str) {
        let w = world(id);
        let dt = w.pw.integration_parameters.dt;
        let mut mb = w.multibody().clone();
        mb.update_sparse(dt, &w.pw.bodies);
        let rhs = DVector::<f32>::from_fn(mb.ndofs(), |i, _| 1.0 + i as f32);
        b.bench_local(|| {
            let mut x = rhs.clone();
            mb.inv_augmented_mass().solve_mut(&mut x);
            black_box(x)
        });
    }
}
