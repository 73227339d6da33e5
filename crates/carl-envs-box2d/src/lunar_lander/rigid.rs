//! Box2D's lander where it moves as one rigid body: its first step, which assembles the legs, and
//! free flight. Both in closed form on plain numbers; [`super::World`] writes the results into
//! the Box2D-semantics solver ([`carl_physics2d`]), which takes over near the ground.
//!
//! **First step.** Gymnasium's `reset` creates the legs *unassembled*: each at the lander's
//! height, `LEG_AWAY` to the side and turned `±0.05` rad, its joint anchor `LEG_DOWN` above the
//! lander's (the joints' reference angle is that creation angle, so they start at their limits).
//! Box2D's first step then does two things, measured in Gymnasium 1.4 (unit tests below):
//! * Velocities: the velocity solver sees each leg locked to the lander (the limit blocks one
//!   direction, the motor pushing into it the other) at the joint's *creation* geometry, so lander
//!   and legs move as one rigid body whose legs hang straight below the anchors. The random
//!   initial push acts at the lander's centre of mass, which is not that composite's centre, and
//!   spins the whole: `ω = (c_lander - c) × F·dt / I` (about −0.113 rad/s per m/s of sideways
//!   push at the defaults; an assembled lander with splayed legs gets two thirds of that).
//! * Positions: the position solver (non-linear Gauss–Seidel, up to 60 iterations) moves the legs
//!   onto their anchors without changing any velocity; they end ~0.14 rad wider than their rest
//!   angle, from where the motor swings them in at 0.3 rad/s.
//!
//! The first step is always free flight: the lander starts at the top of the view, `VIEWPORT_H /
//! 2` above the highest terrain, far more than the legs reach within the spec's bounds.
//!
//! **Free flight.** Away from the ground Box2D's 180 velocity iterations hold each leg exactly at
//! its motor's speed relative to the lander (0.3 rad/s inwards while it swings in, 0 pressed into
//! its limit) as long as that takes less than `LEG_SPRING_TORQUE`: lander and legs are one body
//! whose legs turn at a prescribed rate. [`flight_step`] solves that: engine impulses and gravity
//! change the momenta, the joints only exchange them, so the lander's new velocity is the one that
//! keeps total linear and angular momentum with the legs moving as prescribed. When a motor could
//! not supply the torque (tiny `LEG_SPRING_TORQUE` contexts) it declines and the solver steps instead;
//! in the first step such a leg turns freely under the motor's full torque, as in Box2D (below
//! ~20 N·m at the defaults the push swings a leg out: unit tests against Gymnasium).

/// Box2D's `b2_linearSlop`: position error the position solver accepts.
const LINEAR_SLOP: f64 = 0.005;
/// Box2D's `b2_angularSlop` (2°).
const ANGULAR_SLOP: f64 = 2.0 / 180.0 * std::f64::consts::PI;
/// Box2D's `b2_maxAngularCorrection` (8°): the largest limit correction per iteration.
const MAX_ANGULAR_CORRECTION: f64 = 8.0 / 180.0 * std::f64::consts::PI;
/// Gymnasium's `world.Step(1/FPS, 6*30, 2*30)`: position iterations.
const POSITION_ITERATIONS: usize = 60;

/// One rigid body: centre of mass (world), angle, mass, inertia about the centre of mass,
/// centre of mass in body coordinates, and its velocities (of the centre of mass).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Body {
    pub com: [f64; 2],
    pub angle: f64,
    pub mass: f64,
    pub inertia: f64,
    pub local_com: [f64; 2],
    pub vel: [f64; 2],
    pub w: f64,
}

/// A leg's revolute joint: the anchor on the lander and on the leg (body coordinates) and the
/// limits of the leg's angle relative to the lander's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct LegJoint {
    pub anchor_lander: [f64; 2],
    pub anchor_leg: [f64; 2],
    pub limits: (f64, f64),
}

fn rot(a: f64, v: [f64; 2]) -> [f64; 2] {
    let (s, c) = a.sin_cos();
    [c * v[0] - s * v[1], s * v[0] + c * v[1]]
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// Vector from a body's centre of mass to a point given in its body coordinates.
fn arm(b: &Body, local: [f64; 2]) -> [f64; 2] {
    rot(b.angle, sub(local, b.local_com))
}

/// Perpendicular: `ω × d` for an angular velocity of 1.
fn perp(d: [f64; 2]) -> [f64; 2] {
    [-d[1], d[0]]
}

/// Box2D's first step of the freshly built lander (`bodies`: lander, leg 0, leg 1, all at
/// rest, legs where Gymnasium creates them): `force` acts on the lander's centre of mass for
/// `dt`, gravity on all; `drive` gives the legs' limits and motor torque. Updates positions and
/// velocities in place.
pub(super) fn first_step(
    bodies: &mut [Body; 3],
    joints: &[LegJoint; 2],
    drive: &LegDrive,
    force: [f64; 2],
    gravity: [f64; 2],
    dt: f64,
) {
    // Velocity phase at the joints' creation geometry: each leg where its joint would put it.
    let mut seen = *bodies;
    let anchors = [anchor_world(&seen[0], &joints[0]), anchor_world(&seen[0], &joints[1])];
    for k in 0..2 {
        seen[1 + k].com = sub(anchors[k], arm(&seen[1 + k], joints[k].anchor_leg));
    }
    seen[0].vel = [force[0] * dt / seen[0].mass, force[1] * dt / seen[0].mass];
    for b in seen.iter_mut() {
        b.vel = [b.vel[0] + gravity[0] * dt, b.vel[1] + gravity[1] * dt];
    }
    // The legs start inside their limits (the limit pushes them out, the motor pulls them in):
    // held, unless the motor is too weak.
    if let Some((vels, _)) = solve_velocities(&seen, anchors, [0.0; 2], drive, dt, true) {
        for (b, (v, w)) in bodies.iter_mut().zip(vels) {
            b.vel = v;
            b.w = w;
        }
    }
    for b in bodies.iter_mut() {
        // Box2D integrates the bodies where they are, not where the velocity phase saw them.
        b.com = [b.com[0] + dt * b.vel[0], b.com[1] + dt * b.vel[1]];
        b.angle += dt * b.w;
    }
    solve_positions(bodies, joints);
}

/// Velocity (of the centre of mass) and angular velocity of lander, leg 0 and leg 1.
type Velocities = [([f64; 2], f64); 3];

/// Box2D's converged velocity solution for the lander and its two legs (`b`: velocities before
/// the joints act, centres of mass where the solver sees them; `anchors`: the joints' anchors in
/// world coordinates): every joint's anchors move together and each leg turns at `speed`
/// relative to the lander, unless that takes more joint torque than its motor and limit give
/// (see [`LegDrive`]); then, if `allow_saturation`, that leg turns freely under the motor's full
/// torque, else `None`. Returns the velocities (centre of mass, angular) and which legs saturated.
fn solve_velocities(
    b: &[Body; 3],
    anchors: [[f64; 2]; 2],
    speed: [f64; 2],
    drive: &LegDrive,
    dt: f64,
    allow_saturation: bool,
) -> Option<(Velocities, [bool; 2])> {
    let max_impulse = drive.max_torque * dt;
    // Unknowns z = (lander vx, vy, ω, leg 0 ω, leg 1 ω); the joints' force and torque impulses
    // follow from them. Residuals: the lander's momentum balance (3), per leg its turning rate
    // or, when saturated, its joint torque.
    let residuals = |z: [f64; 5], saturated: [Option<f64>; 2]| -> ([f64; 5], [f64; 2]) {
        let mut r = [0.0; 5];
        let mut torques = [0.0; 2];
        let l = &b[0];
        r[0] = l.mass * (z[0] - l.vel[0]);
        r[1] = l.mass * (z[1] - l.vel[1]);
        r[2] = l.inertia * (z[2] - l.w);
        for k in 0..2 {
            let leg = &b[1 + k];
            let (rl, rk) = (sub(anchors[k], l.com), sub(anchors[k], leg.com));
            let (pl, pk) = (perp(rl), perp(rk));
            let wk = z[3 + k];
            let v = [z[0] + z[2] * pl[0] - wk * pk[0], z[1] + z[2] * pl[1] - wk * pk[1]];
            let f = [leg.mass * (v[0] - leg.vel[0]), leg.mass * (v[1] - leg.vel[1])];
            let t = leg.inertia * (wk - leg.w) - cross(rk, f);
            torques[k] = t;
            r[0] += f[0];
            r[1] += f[1];
            r[2] += t + cross(rl, f);
            r[3 + k] = match saturated[k] {
                Some(t_sat) => t - t_sat,
                None => wk - z[2] - speed[k],
            };
        }
        (r, torques)
    };
    let mut saturated = [None; 2];
    for _ in 0..3 {
        let (r0, _) = residuals([0.0; 5], saturated);
        let mut m = [[0.0; 6]; 5];
        for i in 0..5 {
            let mut e = [0.0; 5];
            e[i] = 1.0;
            let (ri, _) = residuals(e, saturated);
            for row in 0..5 {
                m[row][i] = ri[row] - r0[row];
            }
        }
        for row in 0..5 {
            m[row][5] = -r0[row];
        }
        let z = solve_linear(m)?;
        let (_, torques) = residuals(z, saturated);
        // A leg at (or inside) its limit: the limit pushes it out without bound, the motor pulls
        // it in with at most `max_torque`. A swinging leg: at most `max_torque` either way.
        let mut changed = false;
        for k in 0..2 {
            if saturated[k].is_some() {
                continue;
            }
            let out = drive.limit[k].signum();
            let inward = -out * torques[k];
            let bound = if inward > max_impulse {
                Some(-out * max_impulse)
            } else if speed[k] != 0.0 && inward < -max_impulse {
                Some(out * max_impulse)
            } else {
                None
            };
            if bound.is_some() {
                if !allow_saturation {
                    return None;
                }
                saturated[k] = bound;
                changed = true;
            }
        }
        if !changed {
            let mut out = [([z[0], z[1]], z[2]); 3];
            for k in 0..2 {
                let pk = perp(sub(anchors[k], b[1 + k].com));
                let pl = perp(sub(anchors[k], b[0].com));
                let wk = z[3 + k];
                out[1 + k] = ([z[0] + z[2] * pl[0] - wk * pk[0], z[1] + z[2] * pl[1] - wk * pk[1]], wk);
            }
            return Some((out, saturated.map(|s| s.is_some())));
        }
    }
    None
}

/// Gaussian elimination with partial pivoting on an augmented 5×6 matrix; `None` if singular.
fn solve_linear(mut m: [[f64; 6]; 5]) -> Option<[f64; 5]> {
    for col in 0..5 {
        let pivot = (col..5).max_by(|&a, &b| m[a][col].abs().total_cmp(&m[b][col].abs()))?;
        if m[pivot][col] == 0.0 || !m[pivot][col].is_finite() {
            return None;
        }
        m.swap(col, pivot);
        let pivot_row = m[col];
        for row in m.iter_mut().skip(col + 1) {
            let f = row[col] / pivot_row[col];
            for (x, p) in row.iter_mut().zip(pivot_row).skip(col) {
                *x -= f * p;
            }
        }
    }
    let mut x = [0.0; 5];
    for row in (0..5).rev() {
        let s: f64 = (row + 1..5).map(|c| m[row][c] * x[c]).sum();
        x[row] = (m[row][5] - s) / m[row][row];
    }
    Some(x)
}

/// Which side of its limits a joint started the step on (Box2D decides once per step).
#[derive(Debug, Clone, Copy, PartialEq)]
enum LimitState {
    Lower,
    Upper,
    Inactive,
}

/// Box2D's position phase for the two leg joints: sequential non-linear Gauss–Seidel, the angular
/// limit (with slop, at most 8° per iteration) and then the point constraint per joint, until
/// every joint is within slop or the iterations run out. Velocities are not changed.
fn solve_positions(bodies: &mut [Body; 3], joints: &[LegJoint; 2]) {
    let states = [0, 1].map(|k| {
        let rel = bodies[1 + k].angle - bodies[0].angle;
        let (lo, hi) = joints[k].limits;
        if rel <= lo {
            LimitState::Lower
        } else if rel >= hi {
            LimitState::Upper
        } else {
            LimitState::Inactive
        }
    });
    for _ in 0..POSITION_ITERATIONS {
        let mut solved = true;
        for k in 0..2 {
            let (head, tail) = bodies.split_at_mut(1 + k);
            let (a, b) = (&mut head[0], &mut tail[0]);
            let j = &joints[k];
            let (ima, imb) = (1.0 / a.mass, 1.0 / b.mass);
            let (iia, iib) = (1.0 / a.inertia, 1.0 / b.inertia);
            let rel = b.angle - a.angle;
            let (lo, hi) = j.limits;
            let (correction, angular_error) = match states[k] {
                LimitState::Lower => ((rel - lo + ANGULAR_SLOP).clamp(-MAX_ANGULAR_CORRECTION, 0.0), lo - rel),
                LimitState::Upper => ((rel - hi - ANGULAR_SLOP).clamp(0.0, MAX_ANGULAR_CORRECTION), rel - hi),
                LimitState::Inactive => (0.0, 0.0),
            };
            let limit_impulse = -correction / (iia + iib);
            a.angle -= iia * limit_impulse;
            b.angle += iib * limit_impulse;

            let (ra, rb) = (arm(a, j.anchor_lander), arm(b, j.anchor_leg));
            let c = [b.com[0] + rb[0] - a.com[0] - ra[0], b.com[1] + rb[1] - a.com[1] - ra[1]];
            let position_error = (c[0] * c[0] + c[1] * c[1]).sqrt();
            let k11 = ima + imb + iia * ra[1] * ra[1] + iib * rb[1] * rb[1];
            let k12 = -iia * ra[0] * ra[1] - iib * rb[0] * rb[1];
            let k22 = ima + imb + iia * ra[0] * ra[0] + iib * rb[0] * rb[0];
            let det = k11 * k22 - k12 * k12;
            let det = if det != 0.0 { 1.0 / det } else { 0.0 };
            // impulse = -K⁻¹ C
            let p = [-det * (k22 * c[0] - k12 * c[1]), -det * (k11 * c[1] - k12 * c[0])];
            a.com = [a.com[0] - ima * p[0], a.com[1] - ima * p[1]];
            a.angle -= iia * cross(ra, p);
            b.com = [b.com[0] + imb * p[0], b.com[1] + imb * p[1]];
            b.angle += iib * cross(rb, p);
            solved &= position_error <= LINEAR_SLOP && angular_error <= ANGULAR_SLOP;
        }
        if solved {
            break;
        }
    }
}

/// Where a joint's anchor on the lander is, in world coordinates.
fn anchor_world(lander: &Body, joint: &LegJoint) -> [f64; 2] {
    let r = arm(lander, joint.anchor_lander);
    [lander.com[0] + r[0], lander.com[1] + r[1]]
}

/// How the legs move in free flight (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct LegDrive {
    /// Each leg's inner joint limit as its angle relative to the lander (signed: `-i · 0.35`
    /// for leg `i`): a leg wider than this swings in, one at or inside it stays.
    pub limit: [f64; 2],
    /// The motor's speed while a leg swings in (rad/s).
    pub swing_speed: f64,
    /// The motor's torque limit (N·m).
    pub max_torque: f64,
}

/// One step of free flight for the assembled lander (`bodies`: lander, leg 0, leg 1; the lander's
/// velocity already includes this step's engine impulses). Returns `false`, changing nothing,
/// when a leg motor could not hold the prescribed motion with `max_torque`.
pub(super) fn flight_step(
    bodies: &mut [Body; 3],
    joints: &[LegJoint; 2],
    drive: &LegDrive,
    gravity: [f64; 2],
    dt: f64,
) -> bool {
    if dt.is_nan() || dt <= 0.0 {
        return false;
    }
    let mut b = *bodies;
    for x in b.iter_mut() {
        x.vel = [x.vel[0] + gravity[0] * dt, x.vel[1] + gravity[1] * dt];
    }
    // Each leg's speed relative to the lander: inwards at the motor's speed while wider than its
    // limit, none once at or past it. As in Box2D, which decides at the start of a step whether
    // the limit is active, the last step of a swing overshoots the limit by up to one step's turn
    // and the leg stays there (Box2D corrects limit errors only beyond its 2° slop): the rest
    // angle is 0.344–0.35 rad.
    let mut speed = [0.0; 2];
    for k in 0..2 {
        let rel = b[1 + k].angle - b[0].angle;
        let inward = -drive.limit[k].signum();
        if (rel - drive.limit[k]) * -inward > 0.0 {
            speed[k] = inward * drive.swing_speed;
        }
    }
    let anchors = [anchor_world(&b[0], &joints[0]), anchor_world(&b[0], &joints[1])];
    // A motor too weak to hold its leg: the solver's step instead.
    let Some((new, _)) = solve_velocities(&b, anchors, speed, drive, dt, false) else {
        return false;
    };
    // Integrate: the lander as Box2D does, the legs kept on their joints at their new angles.
    let (v, w) = new[0];
    b[0].vel = v;
    b[0].w = w;
    b[0].com = [b[0].com[0] + dt * v[0], b[0].com[1] + dt * v[1]];
    b[0].angle += dt * w;
    for k in 0..2 {
        let rel = b[1 + k].angle - bodies[0].angle + dt * speed[k];
        (b[1 + k].vel, b[1 + k].w) = new[1 + k];
        b[1 + k].angle = b[0].angle + rel;
        let a = anchor_world(&b[0], &joints[k]);
        let r = arm(&b[1 + k], joints[k].anchor_leg);
        b[1 + k].com = sub(a, r);
    }
    *bodies = b;
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    const DRIVE: LegDrive = LegDrive {
        limit: [0.35, -0.35],
        swing_speed: 0.3,
        max_torque: 40.0,
    };

    /// Gymnasium 1.4's lander at the defaults, as Box2D builds it (masses, inertias about the
    /// centre of mass and centres of mass read from Box2D).
    fn gymnasium_lander() -> ([Body; 3], [LegJoint; 2]) {
        let s = 30.0;
        let (x0, y0) = (10.0, 400.0 / s);
        let body = |com: [f64; 2], angle, mass, inertia, local_com| Body {
            com,
            angle,
            mass,
            inertia,
            local_com,
            vel: [0.0; 2],
            w: 0.0,
        };
        let lc = 0.10130719095468521;
        let lander = body([x0, y0 + lc], 0.0, 4.816666603088379, 0.7838807385255911, [0.0, lc]);
        let legs = [-1.0f64, 1.0].map(|i| {
            body(
                [x0 - i * 20.0 / s, y0],
                i * 0.05,
                0.07111112028360367,
                0.0017909470479935408,
                [0.0; 2],
            )
        });
        let joints = [-1.0f64, 1.0].map(|i| LegJoint {
            anchor_lander: [0.0, 0.0],
            anchor_leg: [i * 20.0 / s, 18.0 / s],
            limits: if i < 0.0 { (0.35, 0.85) } else { (-0.85, -0.35) },
        });
        ([lander, legs[0], legs[1]], joints)
    }

    /// Box2D's first step in Gymnasium 1.4 (gravity −10, seeds 0 and 1, the push as NumPy
    /// draws it): lander ω and velocity, lander origin and angle, legs' angles relative to the
    /// lander, legs' ω (read from Box2D after `reset(seed)`).
    #[test]
    fn first_step_is_box2ds() {
        #[allow(clippy::type_complexity)]
        let cases: [([f64; 2], f64, [f64; 2], [f64; 2], f64, [f64; 2]); 2] = [
            (
                [714.8085531751387, -932.8288493890713],
                -0.32729414105415344,
                [2.889826536178589, -3.962247848510742],
                [10.057061195373535, 13.260224342346191],
                -0.006605303846299648,
                [0.48991051968187094, -0.4941127533093095],
            ),
            (
                [-340.5365670018157, 576.8574068568087],
                0.15592393279075623,
                [-1.376720666885376, 2.126559257507324],
                [9.972817420959473, 13.381998062133789],
                0.00315655255690217,
                [0.492821057792753, -0.4912231364287436],
            ),
        ];
        for (force, w, v, origin, angle, rel) in cases {
            let (mut b, j) = gymnasium_lander();
            first_step(&mut b, &j, &DRIVE, force, [0.0, -10.0], 0.02);
            // Box2D computes in float32: velocities agree to ~1e-6 relative.
            assert!((b[0].w - w).abs() < 1e-5, "ω {} vs {w}", b[0].w);
            for k in 0..2 {
                assert!((b[0].vel[k] - v[k]).abs() < 1e-5, "v {:?} vs {v:?}", b[0].vel);
                assert!((b[1 + k].w - w).abs() < 1e-5, "legs turn with the lander");
            }
            let o = sub(b[0].com, rot(b[0].angle, b[0].local_com));
            assert!(
                (o[0] - origin[0]).abs() < 5e-5 && (o[1] - origin[1]).abs() < 5e-5,
                "origin {o:?} vs {origin:?}"
            );
            assert!((b[0].angle - angle).abs() < 5e-5, "angle {} vs {angle}", b[0].angle);
            for k in 0..2 {
                let r = b[1 + k].angle - b[0].angle;
                assert!((r - rel[k]).abs() < 1e-3, "leg {k}: {r} vs {}", rel[k]);
            }
        }
    }

    /// A weak leg motor (`LEG_SPRING_TORQUE` 0 and 5) cannot hold leg 1 against the push in
    /// Box2D's first step: it swings out and the lander spins less (Gymnasium 1.4, seed 0).
    #[test]
    fn weak_motors_let_a_leg_swing_out_as_in_box2d() {
        for (torque, w, rel) in [(0.0, -0.02779, [0.5119, -0.6235]), (5.0, -0.10081, [0.492, -0.5786])] {
            let (mut b, j) = gymnasium_lander();
            let drive = LegDrive {
                max_torque: torque,
                ..DRIVE
            };
            first_step(
                &mut b,
                &j,
                &drive,
                [714.8085531751387, -932.8288493890713],
                [0.0, -10.0],
                0.02,
            );
            assert!((b[0].w - w).abs() < 1e-4, "torque {torque}: ω {} vs {w}", b[0].w);
            for k in 0..2 {
                let r = b[1 + k].angle - b[0].angle;
                assert!((r - rel[k]).abs() < 2e-3, "torque {torque}, leg {k}: {r} vs {}", rel[k]);
            }
        }
    }

    #[test]
    fn no_push_no_spin_and_legs_snap_out_wide() {
        let (mut b, j) = gymnasium_lander();
        first_step(&mut b, &j, &DRIVE, [0.0, 0.0], [0.0, -10.0], 0.02);
        // Gauss–Seidel solves leg 0 before leg 1: the snap is not exactly mirror-symmetric
        // (Box2D's neither), but no velocity comes of it.
        assert!(
            b.iter()
                .all(|x| x.w.abs() < 1e-12 && x.vel[0].abs() < 1e-12 && (x.vel[1] + 0.2).abs() < 1e-12),
            "{b:?}"
        );
        let (r0, r1) = (b[1].angle - b[0].angle, b[2].angle - b[0].angle);
        assert!(
            b[0].angle.abs() < 2e-3 && (r0 + r1).abs() < 1e-2,
            "{} {r0} {r1}",
            b[0].angle
        );
        assert!(r0 > 0.48 && r0 < 0.5, "{r0}");
    }

    #[test]
    fn flight_keeps_momentum_and_swings_the_legs_in() {
        let (mut b, j) = gymnasium_lander();
        first_step(&mut b, &j, &DRIVE, [300.0, 0.0], [0.0, -10.0], 0.02);
        let drive = DRIVE;
        let momentum = |b: &[Body; 3]| {
            let m: f64 = b.iter().map(|x| x.mass).sum();
            let c = [0, 1].map(|j| b.iter().map(|x| x.mass * x.com[j]).sum::<f64>() / m);
            let p = [0, 1].map(|j| b.iter().map(|x| x.mass * x.vel[j]).sum::<f64>());
            let l: f64 = b
                .iter()
                .map(|x| x.inertia * x.w + x.mass * cross(sub(x.com, c), x.vel))
                .sum();
            (p, l)
        };
        let (p0, l0) = momentum(&b);
        let mut steps = 0;
        while b[1].angle - b[0].angle > 0.35 {
            let before = b;
            assert!(flight_step(&mut b, &j, &drive, [0.0, 0.0], 0.02));
            let (p, l) = momentum(&b);
            assert!(
                (p[0] - p0[0]).abs() < 1e-9 && (p[1] - p0[1]).abs() < 1e-9 && (l - l0).abs() < 1e-3,
                "{p:?} {l}"
            );
            let turned = (b[1].angle - b[0].angle) - (before[1].angle - before[0].angle);
            assert!((turned + 0.3 * 0.02).abs() < 1e-12, "{turned}");
            steps += 1;
        }
        // 0.49 → 0.35 at 0.3 rad/s.
        assert!((22..=25).contains(&steps), "{steps}");
        // A motor with no torque cannot hold a swinging leg: the solver's turn.
        let weak = LegDrive {
            max_torque: 0.0,
            ..drive
        };
        let (mut c, _) = gymnasium_lander();
        first_step(&mut c, &j, &DRIVE, [300.0, 0.0], [0.0, -10.0], 0.02);
        let before = c;
        assert!(!flight_step(&mut c, &j, &weak, [0.0, -10.0], 0.02));
        assert_eq!(c, before);
    }
}
