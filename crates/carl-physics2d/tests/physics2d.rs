//! Analytic checks of the Box2D-semantics solver (src/physics2d).

use carl_physics2d::settings::{ANGULAR_SLOP, LINEAR_SLOP, POLYGON_RADIUS};
use carl_physics2d::*;

const DT: f64 = 1.0 / 60.0;

fn ground(w: &mut World) -> usize {
    let g = w.add_body(BodyKind::Static, v2(0.0, 0.0), 0.0);
    w.add_fixture(
        g,
        FixtureDef {
            shape: Shape::Edge(v2(-20.0, 0.0), v2(20.0, 0.0)),
            density: 0.0,
            friction: 0.6,
            restitution: 0.0,
            filter: Filter::default(),
        },
    );
    g
}

fn boxed(w: &mut World, pos: V2, angle: f64, hx: f64, hy: f64) -> usize {
    let b = w.add_body(BodyKind::Dynamic, pos, angle);
    w.add_fixture(
        b,
        FixtureDef {
            shape: Shape::Polygon(Polygon::new_box(hx, hy)),
            density: 1.0,
            friction: 0.6,
            restitution: 0.0,
            filter: Filter::default(),
        },
    );
    b
}

#[test]
fn box_rests_on_an_edge_without_drift_or_sinking() {
    let mut w = World::new(v2(0.0, -10.0));
    ground(&mut w);
    let b = boxed(&mut w, v2(1.0, 0.6), 0.0, 0.5, 0.5);
    for _ in 0..600 {
        w.step(DT, 8, 3);
    }
    let body = &w.bodies[b];
    // Rests on the two skins minus the allowed slop.
    let gap = body.position().y - 0.5;
    assert!(
        (gap - (2.0 * POLYGON_RADIUS - LINEAR_SLOP)).abs() < 0.5 * LINEAR_SLOP,
        "gap {gap}"
    );
    assert!((body.position().x - 1.0).abs() < 1e-6, "drift {}", body.position().x);
    assert!(body.angle().abs() < 1e-6);
    assert!(body.v.length() < 1e-6);
    assert!(w.touching_fixtures().count() == 1);
}

fn pendulum(w: &mut World, motor: Option<(f64, f64)>, limit: Option<(f64, f64)>) -> (usize, usize) {
    let anchor = w.add_body(BodyKind::Static, v2(0.0, 10.0), 0.0);
    let bob = boxed(w, v2(1.0, 10.0), 0.0, 0.5, 0.05);
    let j = w.add_revolute(RevoluteDef {
        body_a: anchor,
        body_b: bob,
        local_anchor_a: v2(0.0, 0.0),
        local_anchor_b: v2(-1.0, 0.0),
        reference_angle: 0.0,
        enable_limit: limit.is_some(),
        lower: limit.map_or(0.0, |l| l.0),
        upper: limit.map_or(0.0, |l| l.1),
        enable_motor: motor.is_some(),
        motor_speed: motor.map_or(0.0, |m| m.0),
        max_motor_torque: motor.map_or(0.0, |m| m.1),
    });
    (bob, j)
}

#[test]
fn pendulum_conserves_energy() {
    let mut w = World::new(v2(0.0, -10.0));
    let (bob, _) = pendulum(&mut w, None, None);
    let energy = |w: &World| {
        let b = &w.bodies[bob];
        0.5 * b.mass * b.v.length_squared() + 0.5 * b.inertia * b.w * b.w + b.mass * 10.0 * b.center().y
    };
    let e0 = energy(&w);
    let mut worst: f64 = 0.0;
    // Velocity-level constraints lose energy at O(dt²) per step (the projected velocity drops
    // the centripetal part), so a fine step over two swings.
    let dt = 1.0 / 960.0;
    for _ in 0..1920 {
        w.step(dt, 8, 3);
        worst = worst.max((energy(&w) - e0).abs());
    }
    let swing = w.bodies[bob].mass * 10.0 * 1.0;
    assert!(worst < 0.03 * swing, "energy error {worst} of {swing}");
    // The pin holds.
    let b = &w.bodies[bob];
    let pin = b.xf.apply(v2(-1.0, 0.0));
    assert!((pin - v2(0.0, 10.0)).length() < LINEAR_SLOP);
}

#[test]
fn motor_reaches_its_speed_unless_torque_saturates() {
    // Strong motor: the bob turns at the motor speed against gravity.
    let mut w = World::new(v2(0.0, -10.0));
    let (bob, j) = pendulum(&mut w, Some((2.0, 1000.0)), None);
    for _ in 0..30 {
        w.step(DT, 8, 3);
    }
    let s = w.joints[j].speed(&w.bodies);
    assert!((s - 2.0).abs() < 1e-2, "speed {s}");
    // Weak motor in zero gravity: angular acceleration = torque / inertia about the pin.
    let mut w = World::new(v2(0.0, 0.0));
    let (bob2, j2) = pendulum(&mut w, Some((100.0, 0.5)), None);
    let b = &w.bodies[bob2];
    let i_pin = b.inertia + b.mass * 1.0;
    w.step(DT, 8, 3);
    let expected = 0.5 / i_pin * DT;
    let got = w.joints[j2].speed(&w.bodies);
    assert!(
        (got - expected).abs() < 1e-3 * expected.abs() + 1e-9,
        "{got} vs {expected}"
    );
    let _ = bob;
}

#[test]
fn limit_holds_within_two_degrees() {
    let mut w = World::new(v2(0.0, -10.0));
    // Falling from horizontal, stopped at -0.5 rad.
    let (_, j) = pendulum(&mut w, None, Some((-0.5, 0.5)));
    let mut lowest: f64 = 0.0;
    for _ in 0..300 {
        w.step(DT, 8, 3);
        lowest = lowest.min(w.joints[j].angle(&w.bodies));
    }
    let a = w.joints[j].angle(&w.bodies);
    assert!(a >= -0.5 - ANGULAR_SLOP - 1e-3, "rest angle {a}");
    // One step of overshoot at most before the limit engages.
    assert!(lowest > -0.5 - 0.15, "overshoot {lowest}");
}

#[test]
fn two_worlds_stepped_alternately_equal_each_alone() {
    let build = |x: f64| {
        let mut w = World::new(v2(0.0, -10.0));
        ground(&mut w);
        boxed(&mut w, v2(x, 2.0), 0.3, 0.5, 0.2);
        pendulum(&mut w, Some((1.0, 5.0)), Some((-0.4, 0.4)));
        w
    };
    let (mut a, mut b) = (build(0.0), build(3.0));
    let (mut a2, mut b2) = (a.clone(), b.clone());
    for _ in 0..200 {
        a.step(DT, 8, 3);
        b.step(DT, 8, 3);
    }
    for _ in 0..200 {
        a2.step(DT, 8, 3);
    }
    for _ in 0..200 {
        b2.step(DT, 8, 3);
    }
    for (x, y) in a.bodies.iter().zip(&a2.bodies).chain(b.bodies.iter().zip(&b2.bodies)) {
        assert_eq!(x, y);
    }
}

#[test]
fn fast_box_hits_the_ground_through_continuous_collision() {
    // A 0.2 m box thrown down at 100 m/s covers 1.67 m per step: without continuous collision it
    // passes through the edge between two steps; with it, it stops on the ground.
    let run = |continuous: bool| {
        let mut w = World::new(v2(0.0, -10.0));
        w.continuous = continuous;
        ground(&mut w);
        let b = boxed(&mut w, v2(0.0, 1.0), 0.0, 0.1, 0.1);
        w.bodies[b].v = v2(0.0, -100.0);
        for _ in 0..60 {
            w.step(DT, 8, 3);
        }
        w.bodies[b].position().y
    };
    let y = run(true);
    assert!((y - 0.1).abs() < 2.0 * POLYGON_RADIUS, "box at {y}");
    let tunnelled = run(false);
    assert!(
        tunnelled < -1.0,
        "without continuous collision the box tunnels: {tunnelled}"
    );
}
