//! The patched rapier3d (vendor/rapier3d): its tree-sparse body Jacobians and multibody mass
//! matrices equal upstream's dense `Σ Jᵀ·M·J` (kept in the patch as the reference) on random
//! configurations and velocities of every robot model.

use carl_spec::envs::rng::EnvRng;
use carl_spec::envs::robots::world::{Configuration, RobotWorld};
use carl_spec::envs::robots::{RobotModel, default_params};

const ROBOTS: &[(&str, &str)] = &[
    ("ant", "ant"),
    ("half_cheetah", "half_cheetah"),
    ("humanoid", "humanoid"),
    ("ur5e", "ur5e"),
    ("fetch", "fetch"),
    ("grasp", "grasp"),
];

fn uniform(rng: &mut EnvRng, a: f64) -> f64 {
    (rng.next_f64() * 2.0 - 1.0) * a
}

/// A random configuration: any root orientation, joints within ±1.5 rad (or m), velocities
/// up to 3 rad/s (m/s).
fn random_configuration(model: &RobotModel, root_dofs: usize, rng: &mut EnvRng) -> Configuration {
    let root = if root_dofs == 6 {
        let q: Vec<f64> = (0..4).map(|_| uniform(rng, 1.0)).collect();
        let n = q.iter().map(|x| x * x).sum::<f64>().sqrt().max(1e-3);
        vec![
            uniform(rng, 1.0),
            uniform(rng, 1.0),
            1.0 + rng.next_f64(),
            q[0] / n,
            q[1] / n,
            q[2] / n,
            q[3] / n,
        ]
    } else {
        Vec::new()
    };
    let n = model.joint_names.len();
    Configuration {
        root,
        joints: (0..n).map(|_| uniform(rng, 1.5)).collect(),
        vel: (0..root_dofs + n).map(|_| uniform(rng, 3.0)).collect(),
    }
}

/// Largest entry difference relative to the largest entry.
fn rel_diff(a: &[f32], b: &[f32]) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = a.iter().map(|x| f64::from(x.abs())).fold(0.0, f64::max).max(1e-30);
    let diff = a
        .iter()
        .zip(b)
        .map(|(x, y)| f64::from((x - y).abs()))
        .fold(0.0, f64::max);
    diff / scale
}

#[test]
fn sparse_mass_matrix_equals_dense_reference_on_every_robot() {
    for &(id, robot) in ROBOTS {
        let model = RobotModel::load(robot).unwrap();
        let params = default_params(id).unwrap();
        let probe = RobotWorld::build(
            &model,
            &params,
            &random_configuration(&model, 0, &mut EnvRng::from_seed(0)),
        );
        let root_dofs = probe.root_dofs();
        let mut rng = EnvRng::from_seed(15);
        let mut exact = 0;
        for trial in 0..20 {
            let q = random_configuration(&model, root_dofs, &mut rng);
            let mut w = RobotWorld::build(&model, &params, &q);
            // A few steps with random controls: link velocities, contacts and springs as in use.
            for _ in 0..1 + trial % 4 {
                let ctrl: Vec<f32> = (0..model.num_actuators())
                    .map(|_| uniform(&mut rng, 1.0) as f32)
                    .collect();
                w.step(&ctrl);
            }
            let dt = w.pw.integration_parameters.dt;
            let mut dense = w.multibody().clone();
            dense.update_dense_reference(dt, &w.pw.bodies);
            let mut sparse = w.multibody().clone();
            sparse.update_sparse(dt, &w.pw.bodies);
            assert!(dense.ndofs() > 0, "{id}");
            let mut worst: f64 = 0.0;
            for l in 0..dense.num_links() {
                worst = worst.max(rel_diff(
                    dense.body_jacobian(l).as_slice(),
                    sparse.body_jacobian(l).as_slice(),
                ));
            }
            let (m_dense, acc_dense) = dense.augmented_mass_matrices();
            let (m_sparse, acc_sparse) = sparse.augmented_mass_matrices();
            assert_eq!(m_dense.shape(), m_sparse.shape(), "{id}");
            worst = worst.max(rel_diff(m_dense.as_slice(), m_sparse.as_slice()));
            worst = worst.max(rel_diff(acc_dense.as_slice(), acc_sparse.as_slice()));
            assert!(worst <= 1e-9, "{id} trial {trial}: relative difference {worst:e}");
            // The matrices are not trivially equal: nonzero, with the coupling terms present.
            assert!(m_dense.iter().filter(|x| **x != 0.0).count() > dense.ndofs(), "{id}");
            if worst == 0.0 {
                exact += 1;
            }
        }
        eprintln!("{id}: {exact}/20 configurations bit-identical");
    }
}
