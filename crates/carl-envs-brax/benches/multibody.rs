//! The patched rapier3d's per-substep multibody work: `cargo bench -p carl-envs-brax`.
//!
//! On a robot at rest after a few steps: the tree-sparse Jacobians, mass matrices and
//! factorizations (`sparse`), beside upstream's dense assembly with the same factorizations
//! (`dense_reference`), and one `M⁻¹·b` solve (`solve`). See vendor/rapier3d/README.md.

use divan::{Bencher, black_box};

fn main() {
    divan::main();
}
use carl_envs_brax::world::{Configuration, RobotWorld};
use carl_envs_brax::{RobotModel, default_params};
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
