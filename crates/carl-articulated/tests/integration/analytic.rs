//! Analytic checks: small-angle pendulum period, RK4 energy conservation, a torque-free
//! tumbling body, a capsule resting on the floor at MuJoCo's soft penetration, a slide joint
//! under gravity, and refusals of bad input.

use std::sync::Arc;

use carl_articulated::model::{Body, Geom, Integrator, Joint, JointKind, Model, ModelError, Options, Shape};
use carl_articulated::{Data, math};

fn opts(h: f64, integrator: Integrator, gravity: f64) -> Options {
    Options {
        timestep: h,
        gravity: [0.0, 0.0, -gravity],
        integrator,
        ..Options::default()
    }
}

fn world() -> Body {
    Body::new("world", 0, [0.0; 3], 0.0, [0.0; 3], [0.0; 3])
}

/// A point-like bob of 1 kg on a massless rod of length `l` hinged about y at the origin.
fn pendulum(l: f64, integrator: Integrator, h: f64) -> Model {
    let bob = Body::new("bob", 0, [0.0; 3], 1.0, [0.0, 0.0, -l], [1e-6; 3]);
    let hinge = Joint::new("hinge", 1, JointKind::Hinge, [0.0, 1.0, 0.0]);
    Model::new(
        opts(h, integrator, 9.81),
        vec![world(), bob],
        vec![hinge],
        vec![],
        vec![],
    )
    .unwrap()
}

#[test]
fn small_angle_pendulum_period() {
    let l = 0.5;
    let mut d = Data::new(Arc::new(pendulum(l, Integrator::Rk4, 1e-3)));
    d.qpos[0] = 0.01;
    // Time between successive upward zero crossings of the angle.
    let mut crossings = Vec::new();
    let mut prev = d.qpos[0];
    for _ in 0..5000 {
        d.step();
        if prev < 0.0 && d.qpos[0] >= 0.0 {
            crossings.push(d.time);
        }
        prev = d.qpos[0];
    }
    let period = crossings[1] - crossings[0];
    let expected = 2.0 * std::f64::consts::PI * (l / 9.81f64).sqrt();
    assert!((period - expected).abs() < 2e-3, "period {period} vs {expected}");
}

#[test]
fn rk4_conserves_energy_without_damping() {
    // A double pendulum swinging wildly: chaotic, yet RK4 at 1 ms holds the energy.
    let b1 = Body::new("a", 0, [0.0; 3], 1.0, [0.2, 0.0, 0.0], [0.01, 0.02, 0.015]);
    let b2 = Body::new("b", 1, [0.4, 0.0, 0.0], 0.7, [0.15, 0.05, 0.0], [0.005, 0.01, 0.008]);
    let j1 = Joint::new("j1", 1, JointKind::Hinge, [0.0, 1.0, 0.0]);
    let j2 = Joint::new("j2", 2, JointKind::Hinge, [0.3, 1.0, 0.2]);
    let m = Model::new(
        opts(1e-3, Integrator::Rk4, 9.81),
        vec![world(), b1, b2],
        vec![j1, j2],
        vec![],
        vec![],
    )
    .unwrap();
    let mut d = Data::new(Arc::new(m));
    d.qvel[0] = 4.0;
    d.qvel[1] = -6.0;
    d.update_kinematics();
    let e0 = d.energy();
    for _ in 0..3000 {
        d.step();
    }
    d.update_kinematics();
    let e1 = d.energy();
    assert!((e1 - e0).abs() < 1e-6 * e0.abs().max(1.0), "energy {e0} -> {e1}");
    // Euler without damping drifts measurably (the test can tell the integrators apart).
    let mut m = d.model().clone();
    m.opt.integrator = Integrator::Euler;
    let mut d = Data::new(Arc::new(m));
    d.qvel[0] = 4.0;
    d.qvel[1] = -6.0;
    for _ in 0..3000 {
        d.step();
    }
    d.update_kinematics();
    assert!((d.energy() - e0).abs() > 1e-4, "Euler unexpectedly conserved energy");
}

#[test]
fn free_tumbling_body_conserves_momentum_and_energy() {
    // An asymmetric body spinning near its intermediate axis (Dzhanibekov), no gravity.
    let mut body = Body::new("b", 0, [0.0; 3], 2.0, [0.05, -0.02, 0.03], [0.1, 0.2, 0.3]);
    body.iquat = math::quat_normalize([0.9, 0.1, 0.3, -0.2]);
    let free = Joint::new("free", 1, JointKind::Free, [0.0, 0.0, 1.0]);
    let m = Model::new(
        opts(1e-3, Integrator::Rk4, 0.0),
        vec![world(), body],
        vec![free],
        vec![],
        vec![],
    )
    .unwrap();
    let mut d = Data::new(Arc::new(m));
    d.qvel.copy_from_slice(&[0.3, -0.1, 0.2, 0.05, 5.0, 0.02]);
    d.update_kinematics();
    d.forward();
    let (l0, p0) = d.momentum();
    let e0 = d.energy();
    for _ in 0..5000 {
        d.step();
    }
    d.forward();
    let (l1, p1) = d.momentum();
    let e1 = d.energy();
    for k in 0..3 {
        assert!((l1[k] - l0[k]).abs() < 5e-5, "angular momentum {l0:?} -> {l1:?}");
        assert!((p1[k] - p0[k]).abs() < 1e-9, "linear momentum {p0:?} -> {p1:?}");
    }
    assert!((e1 - e0).abs() < 1e-6 * e0, "energy {e0} -> {e1}");
    // It did tumble: the body-frame angular velocity changed direction.
    let q = &d.qpos[3..7];
    assert!((q[0].abs() - 1.0).abs() > 1e-3);
}

#[test]
fn capsule_rests_at_radius_minus_soft_penetration() {
    let r = 0.05;
    let mass = 1.0;
    let floor = Geom::new("floor", 0, Shape::Plane, [0.0; 3]);
    // A horizontal capsule (axis along x).
    let mut body = Body::new("cap", 0, [0.0, 0.0, 0.2], mass, [0.0; 3], [0.001, 0.005, 0.005]);
    body.quat = math::quat_axis_angle([0.0, 1.0, 0.0], std::f64::consts::FRAC_PI_2);
    let cap = Geom::new(
        "cap",
        1,
        Shape::Capsule {
            radius: r,
            half_length: 0.1,
        },
        [0.0; 3],
    );
    let free = Joint::new("free", 1, JointKind::Free, [0.0, 0.0, 1.0]);
    let h = 0.002;
    let m = Model::new(
        opts(h, Integrator::Euler, 9.81),
        vec![world(), body],
        vec![free],
        vec![floor, cap],
        vec![],
    )
    .unwrap();
    let mut d = Data::new(Arc::new(m));
    for _ in 0..2000 {
        d.step();
    }
    // MuJoCo's soft constraint gives the row the acceleration d·aref + (1 − d)·a₀ when its
    // regularizer is R = (1 − d)/d·A. At rest (a = 0, v = 0, a₀ = −g along the normal, d = dmax
    // beyond solimp's width, aref = −K·d·r): 0 = d·(−K·d·r) − (1 − d)·g, so the penetration is
    // r = −(1 − d)·g / (K·d²) with K = 1/(dmax²·timeconst²) (≈ 0.2 mm here). MuJoCo's R uses its
    // diagonal approximation of A (and the pyramid's), not A itself: hence the 10 % tolerance.
    let imp = 0.95; // solimp dmax
    let tc: f64 = 0.02;
    let k = 1.0 / (imp * imp * tc * tc);
    let pen = -(1.0 - imp) * 9.81 / (k * imp * imp);
    let z = d.qpos[2];
    let expected = r + pen;
    assert!(
        (z - expected).abs() < 2e-5,
        "rest height {z} vs {expected} (radius {r}, soft penetration {pen})"
    );
    assert!(z < r, "no soft penetration: {z}");
    assert!(d.qvel.iter().all(|v| v.abs() < 1e-6), "not at rest: {:?}", d.qvel);
}

#[test]
fn slide_joint_falls_with_gravity() {
    let body = Body::new("slider", 0, [0.0; 3], 3.0, [0.0; 3], [0.1; 3]);
    let mut slide = Joint::new("z", 1, JointKind::Slide, [0.0, 0.0, 1.0]);
    slide.armature = 0.0;
    let m = Model::new(
        opts(1e-3, Integrator::Euler, 9.81),
        vec![world(), body],
        vec![slide],
        vec![],
        vec![],
    )
    .unwrap();
    let mut d = Data::new(Arc::new(m));
    for _ in 0..1000 {
        d.step();
    }
    // Semi-implicit Euler: v_n = −g n h, q_n = −g h² n(n+1)/2.
    let (n, h, g) = (1000.0, 1e-3, 9.81);
    assert!((d.qvel[0] + g * n * h).abs() < 1e-9);
    assert!((d.qpos[0] + g * h * h * n * (n + 1.0) / 2.0).abs() < 1e-9);
    // With armature the acceleration is g·m/(m + armature).
    let mut m = d.model().clone();
    m.joints[0].armature = 1.0;
    let m = Model::new(m.opt.clone(), m.bodies.clone(), m.joints.clone(), vec![], vec![]).unwrap();
    let mut d = Data::new(Arc::new(m));
    d.forward();
    assert!((d.qacc[0] + g * 3.0 / 4.0).abs() < 1e-12);
}

#[test]
fn bad_input_is_refused_with_a_clear_error() {
    let body = Body::new("b", 0, [0.0; 3], 1.0, [0.0; 3], [0.1; 3]);
    let zero_axis = Joint::new("j", 1, JointKind::Hinge, [0.0; 3]);
    let e = Model::new(
        Options::default(),
        vec![world(), body.clone()],
        vec![zero_axis],
        vec![],
        vec![],
    )
    .unwrap_err();
    assert!(matches!(e, ModelError::Joint { .. }), "{e}");
    assert!(e.to_string().contains("axis"), "{e}");
    let mut bad = body.clone();
    bad.mass = f64::NAN;
    let e = Model::new(Options::default(), vec![world(), bad], vec![], vec![], vec![]).unwrap_err();
    assert!(e.to_string().contains("mass"), "{e}");
    let o = Options {
        timestep: 0.0,
        ..Options::default()
    };
    assert!(Model::new(o, vec![world()], vec![], vec![], vec![]).is_err());
    let mut j = Joint::new("j", 1, JointKind::Hinge, [0.0, 0.0, 1.0]);
    j.range = Some([1.0, -1.0]);
    assert!(Model::new(Options::default(), vec![world(), body.clone()], vec![j], vec![], vec![]).is_err());
    // General actuators: a filter needs a positive time constant; ranges must be ordered;
    // tendon springs non-negative.
    let hinge = Joint::new("j", 1, JointKind::Hinge, [0.0, 0.0, 1.0]);
    let mut a = carl_articulated::Actuator::position("servo", 0, 2.0, 0.0, Some([-1.0, 1.0]));
    a.dynamics = carl_articulated::Dynamics::Filter { tau: 0.0 };
    let e = Model::new(
        Options::default(),
        vec![world(), body.clone()],
        vec![hinge.clone()],
        vec![],
        vec![a],
    )
    .unwrap_err();
    assert!(e.to_string().contains("tau"), "{e}");
    let mut a = carl_articulated::Actuator::motor("m", 0, 1.0, None);
    a.forcerange = Some([1.0, -1.0]);
    let e = Model::new(
        Options::default(),
        vec![world(), body.clone()],
        vec![hinge.clone()],
        vec![],
        vec![a],
    )
    .unwrap_err();
    assert!(e.to_string().contains("forcerange"), "{e}");
    let mut t = carl_articulated::Tendon::fixed("t", vec![(0, 1.0)]);
    t.stiffness = -1.0;
    let e = Model::new(Options::default(), vec![world(), body], vec![hinge], vec![], vec![])
        .and_then(|m| m.with_tendons(vec![t], vec![]))
        .unwrap_err();
    assert!(e.to_string().contains("stiffness"), "{e}");
    // Non-finite state and controls do not panic; the state reports itself insane.
    let m = pendulum(0.5, Integrator::Euler, 1e-3);
    let mut d = Data::new(Arc::new(m));
    d.qvel[0] = f64::NAN;
    d.step();
    assert!(!d.is_sane(1e3));
}
