//! Analytic checks of the planar engine on HalfCheetah's tree.

use std::sync::Arc;

use super::{PlanarSystem, PlanarWorld};
use crate::model::RobotModel;
use crate::params::RobotParams;
use crate::world::Configuration;
use crate::{blank_params, default_params};

fn cheetah() -> RobotModel {
    (*RobotModel::load("half_cheetah").unwrap()).clone()
}

/// A system of HalfCheetah under `params` with the model's time step replaced by `h`.
fn system(params: &RobotParams, h: f64) -> Arc<PlanarSystem> {
    let mut m = cheetah();
    m.side.timestep = h;
    Arc::new(PlanarSystem::new(&m, params).unwrap())
}

fn world(sys: &Arc<PlanarSystem>, q: &[f64], v: &[f64]) -> PlanarWorld {
    PlanarWorld::new(
        sys.clone(),
        &Configuration {
            root: vec![],
            joints: q.to_vec(),
            vel: v.to_vec(),
        },
    )
}

/// A deterministic pseudo-random sequence in [-1, 1).
fn noise(seed: u64, n: usize) -> Vec<f64> {
    let mut x = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    (0..n)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        })
        .collect()
}

/// Context without damping of any kind (energy checks).
fn undamped() -> RobotParams {
    let mut p = blank_params("half_cheetah").unwrap();
    p.joint_angular_damping = 0.0;
    p.angular_damping = 0.0;
    p
}

#[test]
fn the_whole_robot_falls_freely() {
    let p = default_params("half_cheetah").unwrap();
    let sys = system(&p, 0.01);
    let mut w = world(&sys, &[0.0, 20.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0], &[0.0; 9]);
    let n = 100;
    for _ in 0..n {
        w.step(&[0.0; 6]);
    }
    // Semi-implicit Euler: z_n = z_0 + g h² n(n+1)/2 exactly; nothing else moves.
    let h = 0.01;
    let expect = 20.0 + p.gravity * h * h * (n * (n + 1)) as f64 / 2.0;
    assert!((w.q()[1] - expect).abs() < 1e-9, "{} vs {expect}", w.q()[1]);
    assert!((w.v()[1] - p.gravity * h * n as f64).abs() < 1e-9);
    for (k, (q, v)) in w.q().iter().zip(w.v()).enumerate() {
        if k != 1 {
            assert!(q.abs() < 1e-12 && v.abs() < 1e-12, "coordinate {k}: {q} {v}");
        }
    }
}

#[test]
fn an_undamped_unactuated_swing_keeps_its_energy() {
    // High above the ground (no contacts), joints swinging against the springs and gravity.
    let sys = system(&undamped(), 1e-4);
    let v0 = [0.3, 0.2, 0.5, 1.0, -1.0, 1.5, -1.0, 1.0, -1.5];
    let mut w = world(&sys, &[0.0, 30.0, 0.1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0], &v0);
    let e0 = w.energy();
    let mut worst = 0.0f64;
    for _ in 0..10_000 {
        w.step(&[0.0; 6]);
        worst = worst.max((w.energy() - e0).abs());
    }
    // One second of motion: the joints swung (they are not at rest) and the energy stayed.
    assert!(w.v()[3..].iter().any(|v| v.abs() > 0.1));
    assert!(
        w.q()[3..].iter().all(|q| q.abs() < 0.4),
        "stayed off the limits: {:?}",
        w.q()
    );
    assert!(worst < 1e-3 * e0.abs().max(1.0), "energy drift {worst} of {e0}");
}

#[test]
fn the_mass_matrix_is_symmetric_positive_definite_and_gives_the_kinetic_energy() {
    let sys = system(&undamped(), 0.01);
    for seed in 0..20 {
        let q: Vec<f64> = noise(seed, 9).iter().map(|x| x * 0.5).collect();
        let v = noise(seed + 100, 9);
        let w = world(&sys, &q, &v);
        let (m, _) = w.mass_matrix_and_bias();
        for i in 0..9 {
            for j in 0..9 {
                assert_eq!(m[i * 9 + j], m[j * 9 + i]);
            }
        }
        let mut l = m.clone();
        assert!(super::dynamics::cholesky(&mut l, 9));
        let vmv: f64 = (0..9)
            .map(|i| (0..9).map(|j| v[i] * m[i * 9 + j] * v[j]).sum::<f64>())
            .sum();
        let mut still = world(&sys, &q, &[0.0; 9]);
        let pot = still.energy();
        let w_energy = world(&sys, &q, &v).energy();
        still = world(&sys, &q, &v);
        let armature_and_springs: f64 = sys
            .tree
            .dofs
            .iter()
            .zip(&v)
            .map(|(d, v)| 0.5 * d.armature * v * v)
            .sum();
        let kinetic = w_energy - pot - armature_and_springs;
        assert!(
            (0.5 * vmv - kinetic).abs() < 1e-10 * kinetic.max(1.0),
            "{} vs {kinetic}",
            0.5 * vmv
        );
        let _ = still;
    }
}

#[test]
fn the_bias_forces_are_lagranges_by_finite_differences() {
    // b(q, v) = Ṁv − ½ ∂(vᵀMv)/∂q + ∂V/∂q.
    let sys = system(&undamped(), 0.01);
    let n = 9;
    let eps = 1e-6;
    for seed in 0..5 {
        let q: Vec<f64> = noise(seed, n).iter().map(|x| x * 0.5).collect();
        let v = noise(seed + 50, n);
        let (_, b) = world(&sys, &q, &v).mass_matrix_and_bias();
        let at = |k: usize, d: f64| {
            let mut qq = q.clone();
            qq[k] += d;
            let w = world(&sys, &qq, &[0.0; 9]);
            let pot = super::dynamics::potential_energy(&sys.tree, &w.links, sys.gravity);
            (w.mass_matrix_and_bias().0, pot)
        };
        let mut expect = vec![0.0; n];
        for k in 0..n {
            let ((mp, vp), (mm, vm)) = (at(k, eps), at(k, -eps));
            let dm: Vec<f64> = mp.iter().zip(&mm).map(|(a, b)| (a - b) / (2.0 * eps)).collect();
            // Ṁv contribution of ∂M/∂q_k · v_k, and −½ vᵀ ∂M/∂q_k v.
            for i in 0..n {
                expect[i] += v[k] * (0..n).map(|j| dm[i * n + j] * v[j]).sum::<f64>();
            }
            let quad: f64 = (0..n)
                .map(|i| (0..n).map(|j| v[i] * dm[i * n + j] * v[j]).sum::<f64>())
                .sum();
            expect[k] += -0.5 * quad + (vp - vm) / (2.0 * eps);
        }
        for i in 0..n {
            assert!(
                (b[i] - expect[i]).abs() < 1e-5 * (1.0 + expect[i].abs()),
                "seed {seed} coordinate {i}: {} vs {}",
                b[i],
                expect[i]
            );
        }
    }
}

#[test]
fn it_rests_on_the_floor_without_drift() {
    let p = default_params("half_cheetah").unwrap();
    let sys = system(&p, 0.01);
    let mut w = world(&sys, &[0.0; 9], &[0.0; 9]);
    // The drop and the settling (soft friction lets the feet creep apart at a rate that
    // decays by e every second or so).
    for _ in 0..1000 {
        w.step(&[0.0; 6]);
    }
    let (x0, z0) = (w.q()[0], w.q()[1]);
    for _ in 0..500 {
        w.step(&[0.0; 6]);
    }
    assert!((w.q()[0] - x0).abs() < 1e-4, "slid {} m in 5 s", w.q()[0] - x0);
    assert!((w.q()[1] - z0).abs() < 1e-4, "sank {} m in 5 s", w.q()[1] - z0);
    assert!(w.v().iter().all(|v| v.abs() < 1e-3), "{:?}", w.v());
    // Resting on its feet: every link above the ground within the contacts' softness.
    for (_, a, b, r) in w.capsules() {
        assert!(a[2] - r > -0.01 && b[2] - r > -0.01);
    }
    let mut wrench = vec![0.0; 60];
    w.contact_wrenches(&mut wrench);
    let support: f64 = wrench.chunks(6).map(|c| c[5]).sum();
    let weight: f64 = sys.tree.links[1..].iter().map(|l| l.mass).sum::<f64>() * -p.gravity;
    assert!(
        (support - weight).abs() < 1e-3 * weight,
        "contacts carry {support} N of {weight} N"
    );
}

#[test]
fn two_worlds_stepped_alternately_equal_each_alone() {
    let p = default_params("half_cheetah").unwrap();
    let mut q = p.clone();
    q.gravity = -3.0;
    q.friction = 1.2;
    let (sa, sb) = (system(&p, 0.01), system(&q, 0.01));
    let start = |s: &Arc<PlanarSystem>| world(s, &[0.0, 0.05, 0.1, 0.2, -0.1, 0.0, 0.3, 0.0, -0.2], &[0.5; 9]);
    let ctrl = |k: usize| -> Vec<f32> { noise(k as u64, 6).iter().map(|x| *x as f32).collect() };
    let (mut a, mut b) = (start(&sa), start(&sb));
    for k in 0..300 {
        a.step(&ctrl(k));
        b.step(&ctrl(k));
    }
    let (mut a1, mut b1) = (start(&sa), start(&sb));
    for k in 0..300 {
        a1.step(&ctrl(k));
    }
    for k in 0..300 {
        b1.step(&ctrl(k));
    }
    assert_eq!(a.q(), a1.q());
    assert_eq!(b.v(), b1.v());
    assert_ne!(a.q(), b.q());
    // A clone continues exactly as the original.
    let mut c = a.clone();
    a.step(&ctrl(0));
    c.step(&ctrl(0));
    assert_eq!(a.q(), c.q());
}

#[test]
fn a_robot_that_is_not_planar_is_refused_with_a_reason() {
    let (_, urdf, side) = crate::model::ROBOT_FILES
        .iter()
        .find(|f| f.0 == "ant")
        .copied()
        .unwrap();
    let side = side.replacen("\"engine\": \"articulated\"", "\"engine\": \"planar\"", 1);
    assert!(side.contains("\"engine\": \"planar\""));
    let model = RobotModel::parse("ant", urdf, &side).unwrap();
    let params = blank_params("ant").unwrap();
    let err = crate::physics::PhysicsBuilder::for_model(&model, &params, true)
        .unwrap_err()
        .to_string();
    assert!(err.contains("\"engine\": \"planar\" needs a planar robot"), "{err}");
    assert!(err.contains("root"), "{err}");
}

/// MuJoCo's `solimp` sigmoid (midpoint 0.5, power 2) and `solref` reference acceleration, at
/// points worked by hand: x = |r| / width = 0.25 gives y = 2x² = 0.125, x = 0.75 gives
/// y = 1 − 2(1 − x)² = 0.875, beyond the width y = 1.
#[test]
fn mujoco_impedance_follows_its_sigmoid() {
    use super::contacts::Impedance;
    let h = 0.002;
    let imp = Impedance::mujoco([0.02, 1.0], [0.9, 0.95, 0.001, 0.5, 2.0], h);
    for (r, y) in [(-0.00025, 0.125), (-0.00075, 0.875), (-0.01, 1.0)] {
        let d: f64 = 0.9 + 0.05 * y;
        let (target, ratio) = imp.row(0.0, r, h);
        assert!((ratio - (1.0 - d) / d).abs() < 1e-12, "r {r}: ratio {ratio}");
        let k = d / (0.95f64 * 0.95 * 0.02 * 0.02);
        assert!((target - (-h * k * r)).abs() < 1e-12, "r {r}: target {target}");
    }
    // MuJoCo's refsafe: the time constant is at least two steps.
    assert_eq!(
        Impedance::mujoco([0.001, 1.0], [0.9, 0.95, 0.001, 0.5, 2.0], h).tc,
        2.0 * h
    );
}

/// A system of robot `name` at the context `params`.
fn system_of(name: &str, params: &RobotParams) -> Arc<PlanarSystem> {
    Arc::new(PlanarSystem::new(&RobotModel::load(name).unwrap(), params).unwrap())
}

/// The rail's dry friction holds the cart (and the pole, hanging straight up at rest) against a
/// push below `friction · |g| · carried mass` and yields to one above it.
#[test]
fn rail_friction_holds_below_its_bound_and_slides_above() {
    let mut p = blank_params("inverted_pendulum").unwrap();
    p.friction = 0.5;
    p.link_masses = vec![("cart".into(), 2.0), ("pole".into(), 1.0)];
    let sys = system_of("inverted_pendulum", &p);
    let bound = 0.5 * 9.8 * 3.0; // N; gear 100
    let run = |force: f64| {
        let mut w = world(&sys, &[0.0, 0.0], &[0.0, 0.0]);
        for _ in 0..10 {
            w.step(&[(force / 100.0) as f32]);
        }
        w.q()[0]
    };
    assert!(run(0.8 * bound).abs() < 1e-6, "{}", run(0.8 * bound));
    assert!(run(1.5 * bound) > 1e-3, "{}", run(1.5 * bound));
    // No friction: the same small push moves the cart.
    p.friction = 0.0;
    let free = system_of("inverted_pendulum", &p);
    let mut w = world(&free, &[0.0, 0.0], &[0.0, 0.0]);
    w.step(&[0.01]);
    assert!(w.v()[0] > 0.0);
}

/// A cart hitting the rail's end stop bounces back faster with elasticity than without it
/// (MuJoCo's soft limit alone returns part of the speed from its penetration spring).
#[test]
fn rail_end_stops_restitute_with_elasticity() {
    let bounce = |e: f64| {
        let mut p = blank_params("inverted_pendulum").unwrap();
        p.elasticity = e;
        p.gravity = 0.0;
        let sys = system_of("inverted_pendulum", &p);
        let mut w = world(&sys, &[0.95, 0.0], &[1.0, 0.0]);
        for _ in 0..20 {
            w.step(&[0.0]);
        }
        w.v()[0]
    };
    let (inelastic, elastic) = (bounce(0.0), bounce(0.8));
    assert!(inelastic > -0.5, "{inelastic}");
    assert!(elastic < inelastic - 0.15, "{elastic} vs {inelastic}");
}

/// Reacher's plane is horizontal: gravity exerts no torque on the arm (its energy stays
/// constant without damping), and only presses it onto the table, where friction stops a
/// spinning arm that would otherwise keep turning.
#[test]
fn horizontal_arm_feels_gravity_only_through_table_friction() {
    let mut p = blank_params("reacher").unwrap();
    p.friction = 0.0;
    p.gravity = -1000.0;
    let sys = system_of("reacher", &p);
    assert_eq!(sys.gravity, 0.0);
    let mut w = world(&sys, &[0.3, 0.5], &[0.0, 0.0]);
    for _ in 0..50 {
        w.step(&[0.0, 0.0]);
    }
    assert_eq!(w.q(), &[0.3, 0.5]);
    let spin = |friction: f64| {
        let mut p = blank_params("reacher").unwrap();
        p.friction = friction;
        let sys = system_of("reacher", &p);
        let mut w = world(&sys, &[0.0, 0.0], &[5.0, 0.0]);
        for _ in 0..20 {
            w.step(&[0.0, 0.0]);
        }
        w.v()[0]
    };
    assert!(spin(100.0) < spin(0.0) - 0.1, "{} {}", spin(100.0), spin(0.0));
}

/// RK4 (the side file's `integrator`) conserves the energy of the undamped double pendulum on
/// its cart swinging through large angles far better than semi-implicit Euler, and its error
/// falls as the fourth power of the step.
#[test]
fn rk4_conserves_the_energy_of_an_undamped_double_pendulum() {
    use crate::model::Integrator;
    let drift = |integrator: Integrator, h: f64| {
        let mut m = (*RobotModel::load("inverted_double_pendulum").unwrap()).clone();
        m.side.joint_dampings.iter_mut().for_each(|d| d.damping = 0.0);
        m.side.integrator = integrator;
        m.side.timestep = h;
        let mut p = blank_params("inverted_double_pendulum").unwrap();
        p.angular_damping = 0.0;
        p.friction = 0.0;
        p.gravity = -9.81;
        // A heavy cart: the swing does not carry it to the rail's ends.
        p.link_masses = vec![("cart".into(), 1000.0)];
        let sys = Arc::new(PlanarSystem::new(&m, &p).unwrap());
        let mut w = world(&sys, &[0.0, 1.0, -0.5], &[0.0, 0.0, 0.0]);
        let e0 = w.energy();
        let steps = (2.0 / h).round() as usize;
        let mut worst: f64 = 0.0;
        for _ in 0..steps {
            w.step(&[0.0]);
            worst = worst.max((w.energy() - e0).abs());
        }
        assert!(w.q()[0].abs() < 0.5, "the cart reached {}", w.q()[0]);
        worst
    };
    let (rk, rk_half, euler) = (
        drift(Integrator::Rk4, 0.01),
        drift(Integrator::Rk4, 0.005),
        drift(Integrator::Euler, 0.01),
    );
    // The poles' potential energy swings by tens of joules.
    assert!(rk < 1e-2, "RK4 drift {rk} J");
    assert!(rk < euler / 100.0, "RK4 {rk} J vs Euler {euler} J");
    assert!(rk_half < rk / 8.0, "RK4 at h/2: {rk_half} J vs {rk} J");
}
