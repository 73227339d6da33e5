//! The patched rapier3d (vendor/rapier3d): its tree-sparse body Jacobians and multibody mass
//! matrices equal upstream's dense `Σ Jᵀ·M·J` (kept in the patch as the reference) up to f32
//! rounding, and its tree-sparse factorizations solve like upstream's dense LU, on random
//! configurations and velocities of every robot model. The pipeline's start-of-step forward
//! kinematics, skipped when nothing changed, changes nothing when it runs, and runs when the
//! user changed the joints.

use carl_env::rng::EnvRng;
use carl_envs_brax::world::{Configuration, RobotWorld};
use carl_envs_brax::{RobotModel, RobotParams, default_params};

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
/// How many root DoFs the robot's multibody has (6 for a free root, 0 for a fixed base).
fn root_dofs(model: &RobotModel, params: &RobotParams) -> usize {
    let q = random_configuration(model, 0, &mut EnvRng::from_seed(0));
    RobotWorld::build(model, params, &q).root_dofs()
}

/// A world in a random configuration, then `steps` steps under random controls (link
/// velocities, contacts and springs as in use).
fn random_state(
    model: &RobotModel,
    params: &RobotParams,
    root_dofs: usize,
    steps: usize,
    rng: &mut EnvRng,
) -> RobotWorld {
    let q = random_configuration(model, root_dofs, rng);
    let mut w = RobotWorld::build(model, params, &q);
    for _ in 0..steps {
        let ctrl: Vec<f32> = (0..model.num_actuators()).map(|_| uniform(rng, 1.0) as f32).collect();
        w.step(&ctrl);
    }
    w
}

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
        let root_dofs = root_dofs(&model, &params);
        let mut rng = EnvRng::from_seed(15);
        let mut worst_all: f64 = 0.0;
        let mut worst_implicit: f64 = 0.0;
        for trial in 0..20 {
            let w = random_state(&model, &params, root_dofs, 1 + trial % 4, &mut rng);
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
            // The implicit gyroscopic and Coriolis terms alone (`dt`-small beside the mass
            // matrix), relative to their own size.
            let implicit_dense = acc_dense - m_dense;
            let implicit_sparse = acc_sparse - m_sparse;
            let implicit = rel_diff(implicit_dense.as_slice(), implicit_sparse.as_slice());
            assert!(
                implicit <= 1e-4,
                "{id} trial {trial}: implicit terms differ by {implicit:e}"
            );
            worst_implicit = worst_implicit.max(implicit);
            // The patch sums some products in another order (3×3 blocks, one pass for the
            // accelerated matrix, a mirrored symmetric mass matrix): f32 rounding, no more.
            assert!(worst <= 2e-6, "{id} trial {trial}: relative difference {worst:e}");
            // The matrices are not trivially equal: nonzero, with the coupling terms present.
            assert!(m_dense.iter().filter(|x| **x != 0.0).count() > dense.ndofs(), "{id}");
            worst_all = worst_all.max(worst);
        }
        eprintln!(
            "{id}: worst relative difference to the dense reference {worst_all:.1e} \
             (implicit terms alone {worst_implicit:.1e})"
        );
    }
}

/// Every link pose and generalized velocity, bit for bit.
fn exact_state(w: &RobotWorld) -> Vec<u32> {
    let mut bits: Vec<u32> = Vec::new();
    for i in 0..w.links.len() {
        let p = w.link_pose(i);
        let (t, r) = (p.translation, p.rotation);
        bits.extend([t.x, t.y, t.z, r.x, r.y, r.z, r.w].map(f32::to_bits));
    }
    bits.extend(w.multibody().generalized_velocity().iter().map(|v| v.to_bits()));
    bits
}

/// The patch skips the pipeline's start-of-step forward kinematics when the multibody and its
/// bodies are as the last substep left them; forcing it (a `&mut` access to a link marks the
/// kinematics stale) must give the same trajectory bit for bit, on every robot.
#[test]
fn skipped_start_of_step_kinematics_changes_nothing() {
    for &(id, robot) in ROBOTS {
        let model = RobotModel::load(robot).unwrap();
        let params = default_params(id).unwrap();
        let root_dofs = root_dofs(&model, &params);
        let mut rng = EnvRng::from_seed(16);
        let q = random_configuration(&model, root_dofs, &mut rng);
        let mut skipping = RobotWorld::build(&model, &params, &q);
        let mut forced = RobotWorld::build(&model, &params, &q);
        for step in 0..40 {
            let ctrl: Vec<f32> = (0..model.num_actuators())
                .map(|_| uniform(&mut rng, 1.0) as f32)
                .collect();
            forced.multibody_mut().link_mut(0).expect("root link");
            skipping.step(&ctrl);
            forced.step(&ctrl);
            assert_eq!(exact_state(&skipping), exact_state(&forced), "{id} step {step}");
        }
    }
}

/// User changes between steps reach the physics as they do upstream (which runs the
/// start-of-step forward kinematics every step; emulated by marking the kinematics stale
/// before every step): joint coordinates moved without forward kinematics
/// (`apply_displacements`), and the root body moved by the user.
#[test]
fn user_changes_rerun_the_skipped_kinematics() {
    for &(id, robot) in ROBOTS {
        let model = RobotModel::load(robot).unwrap();
        let params = default_params(id).unwrap();
        let root_dofs = root_dofs(&model, &params);
        let mut rng = EnvRng::from_seed(17);
        let q = random_configuration(&model, root_dofs, &mut rng);
        let mut skipping = RobotWorld::build(&model, &params, &q);
        let mut forced = RobotWorld::build(&model, &params, &q);
        let ndofs = skipping.multibody().ndofs();
        let disp: Vec<f32> = (0..ndofs).map(|k| if k >= root_dofs { 0.2 } else { 0.0 }).collect();
        for step in 0..12 {
            for w in [&mut skipping, &mut forced] {
                match step {
                    4 => w.multibody_mut().apply_displacements(&disp),
                    8 => {
                        let root = w.links[0];
                        let mut pose = *w.pw.bodies[root].position();
                        pose.translation.z += 0.05;
                        w.pw.bodies[root].set_position(pose, true);
                    }
                    _ => {}
                }
            }
            let ctrl: Vec<f32> = (0..model.num_actuators())
                .map(|_| uniform(&mut rng, 1.0) as f32)
                .collect();
            let before = exact_state(&skipping);
            forced.multibody_mut().link_mut(0).expect("root link");
            skipping.step(&ctrl);
            forced.step(&ctrl);
            assert_eq!(exact_state(&skipping), exact_state(&forced), "{id} step {step}");
            assert_ne!(exact_state(&skipping), before, "{id} step {step}: nothing moved");
        }
    }
}

/// Relative error of `x` against the f64 solution `exact`.
fn rel_err(x: &[f32], exact: &[f64]) -> f64 {
    let scale = exact.iter().map(|v| v.abs()).fold(0.0, f64::max).max(1e-30);
    x.iter()
        .zip(exact)
        .map(|(a, b)| (f64::from(*a) - b).abs())
        .fold(0.0, f64::max)
        / scale
}

/// The patch's tree-sparse factorizations of both augmented mass matrices (the one the joint,
/// contact and limit constraints use, and the accelerated one the free accelerations use) solve
/// like the dense LU they replace: on random states of every robot, against an f64 solve of the
/// same matrix, no worse than upstream's f32 LU beyond a small margin.
#[test]
fn tree_sparse_factorization_solves_like_dense_lu_on_every_robot() {
    use rapier3d::na::{DMatrix, LU};
    for &(id, robot) in ROBOTS {
        let model = RobotModel::load(robot).unwrap();
        let params = default_params(id).unwrap();
        let root_dofs = root_dofs(&model, &params);
        let mut rng = EnvRng::from_seed(16);
        let (mut worst_tree, mut worst_lu): (f64, f64) = (0.0, 0.0);
        for trial in 0..20 {
            let w = random_state(&model, &params, root_dofs, 1 + trial % 4, &mut rng);
            let dt = w.pw.integration_parameters.dt;
            let mut mb = w.multibody().clone();
            mb.update_sparse(dt, &w.pw.bodies);
            let n = mb.ndofs();
            let (m, acc) = mb.augmented_mass_matrices();
            let factors = [(m, mb.inv_augmented_mass()), (acc, mb.acc_inv_augmented_mass())];
            for (which, (a, factor)) in factors.into_iter().enumerate() {
                assert!(
                    factor.is_tree_sparse(),
                    "{id} trial {trial}: matrix {which} fell back to LU"
                );
                let b = DMatrix::<f32>::from_fn(n, 3, |_, _| uniform(&mut rng, 1.0) as f32);
                let mut x_tree = b.clone();
                assert!(factor.solve_mut(&mut x_tree));
                let mut x_lu = b.clone();
                assert!(LU::new(a.clone()).solve_mut(&mut x_lu));
                let exact = LU::new(a.map(f64::from))
                    .solve(&b.map(f64::from))
                    .expect("the mass matrices are invertible");
                for c in 0..3 {
                    let col = exact.column(c);
                    let e_tree = rel_err(x_tree.column(c).as_slice(), col.as_slice());
                    let e_lu = rel_err(x_lu.column(c).as_slice(), col.as_slice());
                    assert!(
                        e_tree <= 1e-5_f64.max(4.0 * e_lu),
                        "{id} trial {trial} matrix {which}: tree error {e_tree:e}, dense LU {e_lu:e}"
                    );
                    worst_tree = worst_tree.max(e_tree);
                    worst_lu = worst_lu.max(e_lu);
                }
            }
        }
        eprintln!("{id}: worst relative error, tree-sparse {worst_tree:.1e}, dense LU {worst_lu:.1e}");
    }
}

/// A random matrix with the branch-induced sparsity of `parent`: `Σₖ vₖ·vₖᵀ + I/2` with `vₖ`
/// supported on DoF `k` and its ancestors (symmetric positive definite), plus a small
/// nonsymmetric part on the same pattern unless `symmetric`.
fn tree_matrix(parent: &[usize], rng: &mut EnvRng, symmetric: bool) -> rapier3d::na::DMatrix<f32> {
    use rapier3d::dynamics::NO_PARENT;
    let n = parent.len();
    let mut a = rapier3d::na::DMatrix::<f32>::zeros(n, n);
    for k in 0..n {
        let mut path = vec![k];
        let mut i = parent[k];
        while i != NO_PARENT {
            path.push(i);
            i = parent[i];
        }
        let v: Vec<f32> = path.iter().map(|_| uniform(rng, 1.0) as f32).collect();
        for (p, &r) in path.iter().enumerate() {
            for (q, &c) in path.iter().enumerate() {
                a[(r, c)] += v[p] * v[q];
                if !symmetric && p != q {
                    a[(r, c)] += 0.05 * uniform(rng, 1.0) as f32;
                }
            }
        }
        a[(k, k)] += 0.5;
    }
    a
}

/// The factorization on synthetic trees (chains, branches, a single DoF; symmetric and not):
/// residual `A·x − b` at f32 level, and no fill-in needed (the tree factor is used).
#[test]
fn tree_factorization_solves_synthetic_trees() {
    use rapier3d::dynamics::{MassMatrixFactor, NO_PARENT};
    use rapier3d::na::DMatrix;
    let trees: [&[usize]; 4] = [
        &[NO_PARENT, 0, 1, 2, 3, 2, 5, 6],
        &[NO_PARENT, 0, 0, 1, 2, 2],
        &[NO_PARENT, 0, 1, 2, 3, 4, 5, 5, 7, 8, 5, 10, 4, 12],
        &[NO_PARENT],
    ];
    let mut rng = EnvRng::from_seed(17);
    for (t, parent) in trees.iter().enumerate() {
        for symmetric in [true, false] {
            let n = parent.len();
            let a = tree_matrix(parent, &mut rng, symmetric);
            let mut factor = MassMatrixFactor::default();
            factor.factorize(&a, n, Some(parent), symmetric);
            assert!(factor.is_tree_sparse(), "tree {t}");
            let b = DMatrix::<f32>::from_fn(n, 2, |_, _| uniform(&mut rng, 1.0) as f32);
            let mut x = b.clone();
            assert!(factor.solve_mut(&mut x));
            let residual = (&a * &x - &b).amax();
            assert!(residual < 1e-4, "tree {t} symmetric {symmetric}: residual {residual}");
        }
    }
}

/// A matrix whose elimination meets a non-positive pivot goes to the dense LU with pivoting.
#[test]
fn tree_factorization_falls_back_to_dense_lu() {
    use rapier3d::dynamics::{MassMatrixFactor, NO_PARENT};
    use rapier3d::na::{DMatrix, DVector};
    let a = DMatrix::<f32>::from_row_slice(2, 2, &[0.0, 1.0, 1.0, 0.0]);
    let mut factor = MassMatrixFactor::default();
    factor.factorize(&a, 2, Some(&[NO_PARENT, 0]), true);
    assert!(!factor.is_tree_sparse());
    let mut x = DVector::<f32>::from_column_slice(&[2.0, 3.0]);
    assert!(factor.solve_mut(&mut x));
    assert_eq!(x.as_slice(), &[3.0, 2.0]);
    // And without a tree (kinematic DoFs reorder the matrix): the dense LU too.
    factor.factorize(&DMatrix::<f32>::identity(2, 2), 2, None, true);
    assert!(!factor.is_tree_sparse());
}
