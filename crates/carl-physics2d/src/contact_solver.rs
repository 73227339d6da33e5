//! Sequential impulses for contacts (Box2D's `b2ContactSolver`): per point a normal impulse
//! (non-negative, with restitution above `VELOCITY_THRESHOLD`) and a friction impulse bounded by
//! `friction · normal impulse`; two-point manifolds solve their normal impulses together (the
//! block solver's four cases of the 2×2 LCP); positions are corrected non-linearly (NGS), one
//! point at a time, with Baumgarte factor and `LINEAR_SLOP` of allowed overlap.

use super::body::Body;
use super::collide::{Manifold, ManifoldKind, world_manifold};
use super::math::{V2, Xf, cross_sv};
use super::settings::{LINEAR_SLOP, MAX_CONDITION_NUMBER, MAX_LINEAR_CORRECTION, VELOCITY_THRESHOLD};

#[derive(Debug, Clone, Copy, Default)]
pub struct VelocityPoint {
    pub ra: V2,
    pub rb: V2,
    pub normal_impulse: f64,
    pub tangent_impulse: f64,
    pub normal_mass: f64,
    pub tangent_mass: f64,
    pub velocity_bias: f64,
}

/// One contact's constraint for a solve (velocity and position parts).
#[derive(Debug, Clone, Copy, Default)]
pub struct ContactConstraint {
    pub contact: usize,
    pub body_a: usize,
    pub body_b: usize,
    pub points: [VelocityPoint; 2],
    pub normal: V2,
    /// Inverse of `k` for the block solver.
    pub normal_mass: [[f64; 2]; 2],
    pub k: [[f64; 2]; 2],
    pub friction: f64,
    pub restitution: f64,
    /// Points in the velocity solve: a badly conditioned pair solves (and warm-starts and
    /// stores) only its first, as Box2D does.
    pub count: usize,
    pub manifold: Manifold,
    pub radius_a: f64,
    pub radius_b: f64,
}

impl ContactConstraint {
    /// Copy the manifold; impulses scaled by `dt_ratio` (warm start) or zeroed.
    pub fn new(
        contact: usize,
        bodies: (usize, usize),
        manifold: &Manifold,
        friction: f64,
        restitution: f64,
        radii: (f64, f64),
        warm: Option<f64>,
    ) -> ContactConstraint {
        let mut c = ContactConstraint {
            contact,
            body_a: bodies.0,
            body_b: bodies.1,
            friction,
            restitution,
            count: manifold.count,
            manifold: *manifold,
            radius_a: radii.0,
            radius_b: radii.1,
            ..Default::default()
        };
        for (vp, mp) in c.points.iter_mut().zip(&manifold.points).take(manifold.count) {
            if let Some(r) = warm {
                vp.normal_impulse = r * mp.normal_impulse;
                vp.tangent_impulse = r * mp.tangent_impulse;
            }
        }
        c
    }
}

fn xf_of(b: &Body) -> Xf {
    Xf::from_center(b.sweep.c, b.sweep.a, b.sweep.local_center)
}

/// Anchors, effective masses, restitution bias and the block solver's matrix.
pub fn init_velocity(cs: &mut [ContactConstraint], bodies: &[Body]) {
    for c in cs {
        let (ba, bb) = (&bodies[c.body_a], &bodies[c.body_b]);
        let (ma, ia, mb, ib) = (ba.inv_mass, ba.inv_inertia, bb.inv_mass, bb.inv_inertia);
        let (normal, pts, _) = world_manifold(&c.manifold, &xf_of(ba), c.radius_a, &xf_of(bb), c.radius_b);
        c.normal = normal;
        let tangent = normal.cross_s(1.0);
        for (vp, &pt) in c.points.iter_mut().zip(&pts).take(c.manifold.count) {
            vp.ra = pt - ba.sweep.c;
            vp.rb = pt - bb.sweep.c;
            let rna = vp.ra.cross(normal);
            let rnb = vp.rb.cross(normal);
            let kn = ma + mb + ia * rna * rna + ib * rnb * rnb;
            vp.normal_mass = if kn > 0.0 { 1.0 / kn } else { 0.0 };
            let rta = vp.ra.cross(tangent);
            let rtb = vp.rb.cross(tangent);
            let kt = ma + mb + ia * rta * rta + ib * rtb * rtb;
            vp.tangent_mass = if kt > 0.0 { 1.0 / kt } else { 0.0 };
            vp.velocity_bias = 0.0;
            let vrel = normal.dot(bb.v + cross_sv(bb.w, vp.rb) - ba.v - cross_sv(ba.w, vp.ra));
            if vrel < -VELOCITY_THRESHOLD {
                vp.velocity_bias = -c.restitution * vrel;
            }
        }
        c.count = c.manifold.count;
        if c.count == 2 {
            let (p1, p2) = (&c.points[0], &c.points[1]);
            let (rn1a, rn1b) = (p1.ra.cross(normal), p1.rb.cross(normal));
            let (rn2a, rn2b) = (p2.ra.cross(normal), p2.rb.cross(normal));
            let k11 = ma + mb + ia * rn1a * rn1a + ib * rn1b * rn1b;
            let k22 = ma + mb + ia * rn2a * rn2a + ib * rn2b * rn2b;
            let k12 = ma + mb + ia * rn1a * rn2a + ib * rn1b * rn2b;
            let det = k11 * k22 - k12 * k12;
            if k11 * k11 < MAX_CONDITION_NUMBER * det {
                c.k = [[k11, k12], [k12, k22]];
                let inv = if det != 0.0 { 1.0 / det } else { 0.0 };
                c.normal_mass = [[inv * k22, -inv * k12], [-inv * k12, inv * k11]];
            } else {
                // Redundant points: solve one.
                c.count = 1;
            }
        }
    }
}

fn apply(bodies: &mut [Body], a: usize, b: usize, ra: V2, rb: V2, p: V2) {
    let ba = &mut bodies[a];
    ba.v -= ba.inv_mass * p;
    ba.w -= ba.inv_inertia * ra.cross(p);
    let bb = &mut bodies[b];
    bb.v += bb.inv_mass * p;
    bb.w += bb.inv_inertia * rb.cross(p);
}

pub fn warm_start(cs: &[ContactConstraint], bodies: &mut [Body]) {
    for c in cs {
        let tangent = c.normal.cross_s(1.0);
        for vp in &c.points[..c.count] {
            let p = vp.normal_impulse * c.normal + vp.tangent_impulse * tangent;
            apply(bodies, c.body_a, c.body_b, vp.ra, vp.rb, p);
        }
    }
}

fn rel_vel(bodies: &[Body], a: usize, b: usize, ra: V2, rb: V2) -> V2 {
    let (ba, bb) = (&bodies[a], &bodies[b]);
    bb.v + cross_sv(bb.w, rb) - ba.v - cross_sv(ba.w, ra)
}

pub fn solve_velocity(cs: &mut [ContactConstraint], bodies: &mut [Body]) {
    for c in cs {
        let (a, b, normal) = (c.body_a, c.body_b, c.normal);
        let tangent = normal.cross_s(1.0);
        // Friction first: the normal impulse matters more, so it is solved last.
        for vp in &mut c.points[..c.count] {
            let vt = rel_vel(bodies, a, b, vp.ra, vp.rb).dot(tangent);
            let max_f = c.friction * vp.normal_impulse;
            let new = (vp.tangent_impulse - vp.tangent_mass * vt).clamp(-max_f, max_f);
            let lambda = new - vp.tangent_impulse;
            vp.tangent_impulse = new;
            apply(bodies, a, b, vp.ra, vp.rb, lambda * tangent);
        }
        if c.count == 1 {
            let vp = &mut c.points[0];
            let vn = rel_vel(bodies, a, b, vp.ra, vp.rb).dot(normal);
            let new = (vp.normal_impulse - vp.normal_mass * (vn - vp.velocity_bias)).max(0.0);
            let lambda = new - vp.normal_impulse;
            vp.normal_impulse = new;
            apply(bodies, a, b, vp.ra, vp.rb, lambda * normal);
            continue;
        }
        solve_block(c, bodies);
    }
}

/// The two normal impulses of a two-point manifold as a 2×2 LCP: `vn = K·x + b`, `x ≥ 0`,
/// `vn ≥ 0`, `x·vn = 0`, trying the four cases in Box2D's order.
fn solve_block(c: &mut ContactConstraint, bodies: &mut [Body]) {
    let (a, b, normal) = (c.body_a, c.body_b, c.normal);
    let (p1, p2) = (c.points[0], c.points[1]);
    let old = [p1.normal_impulse, p2.normal_impulse];
    let vn1 = rel_vel(bodies, a, b, p1.ra, p1.rb).dot(normal);
    let vn2 = rel_vel(bodies, a, b, p2.ra, p2.rb).dot(normal);
    let k = c.k;
    let bx = vn1 - p1.velocity_bias - (k[0][0] * old[0] + k[0][1] * old[1]);
    let by = vn2 - p2.velocity_bias - (k[1][0] * old[0] + k[1][1] * old[1]);
    let nm = c.normal_mass;
    let candidates = || {
        // Case 1: both points active.
        let x = [-(nm[0][0] * bx + nm[0][1] * by), -(nm[1][0] * bx + nm[1][1] * by)];
        if x[0] >= 0.0 && x[1] >= 0.0 {
            return Some(x);
        }
        // Case 2: only point 1.
        let x1 = -p1.normal_mass * bx;
        let v2n = k[0][1] * x1 + by;
        if x1 >= 0.0 && v2n >= 0.0 {
            return Some([x1, 0.0]);
        }
        // Case 3: only point 2.
        let x2 = -p2.normal_mass * by;
        let v1n = k[1][0] * x2 + bx;
        if x2 >= 0.0 && v1n >= 0.0 {
            return Some([0.0, x2]);
        }
        // Case 4: neither.
        if bx >= 0.0 && by >= 0.0 {
            return Some([0.0, 0.0]);
        }
        None
    };
    if let Some(x) = candidates() {
        let d = [x[0] - old[0], x[1] - old[1]];
        let (q1, q2) = (d[0] * normal, d[1] * normal);
        let ba = &mut bodies[a];
        ba.v -= ba.inv_mass * (q1 + q2);
        ba.w -= ba.inv_inertia * (p1.ra.cross(q1) + p2.ra.cross(q2));
        let bb = &mut bodies[b];
        bb.v += bb.inv_mass * (q1 + q2);
        bb.w += bb.inv_inertia * (p1.rb.cross(q1) + p2.rb.cross(q2));
        c.points[0].normal_impulse = x[0];
        c.points[1].normal_impulse = x[1];
    }
}

/// Normal, point and separation of manifold point `j` at the current positions.
fn position_point(m: &Manifold, j: usize, xfa: &Xf, xfb: &Xf, ra: f64, rb: f64) -> (V2, V2, f64) {
    match m.kind {
        ManifoldKind::FaceA => {
            let normal = xfa.q.apply(m.local_normal);
            let plane = xfa.apply(m.local_point);
            let clip = xfb.apply(m.points[j].local_point);
            (normal, clip, (clip - plane).dot(normal) - ra - rb)
        }
        ManifoldKind::FaceB => {
            let normal = xfb.q.apply(m.local_normal);
            let plane = xfb.apply(m.local_point);
            let clip = xfa.apply(m.points[j].local_point);
            (-normal, clip, (clip - plane).dot(normal) - ra - rb)
        }
    }
}

/// One NGS pass over the contacts; true when no overlap exceeds `done_below · LINEAR_SLOP`.
/// `movable` restricts the correction to the listed bodies (continuous collision moves only
/// the two bodies of the impact); `None` moves every dynamic body.
pub fn solve_position(
    cs: &[ContactConstraint],
    bodies: &mut [Body],
    baumgarte: f64,
    movable: Option<(usize, usize)>,
    done_below: f64,
) -> bool {
    let mut min_sep: f64 = 0.0;
    for c in cs {
        let (a, b) = (c.body_a, c.body_b);
        let mass = |k: usize, bodies: &[Body]| match movable {
            Some((p, q)) if k != p && k != q => (0.0, 0.0),
            _ => (bodies[k].inv_mass, bodies[k].inv_inertia),
        };
        let (ma, ia) = mass(a, bodies);
        let (mb, ib) = mass(b, bodies);
        for j in 0..c.manifold.count {
            let xfa = xf_of(&bodies[a]);
            let xfb = xf_of(&bodies[b]);
            let (normal, point, sep) = position_point(&c.manifold, j, &xfa, &xfb, c.radius_a, c.radius_b);
            let ra = point - bodies[a].sweep.c;
            let rb = point - bodies[b].sweep.c;
            min_sep = min_sep.min(sep);
            let cc = (baumgarte * (sep + LINEAR_SLOP)).clamp(-MAX_LINEAR_CORRECTION, 0.0);
            let rna = ra.cross(normal);
            let rnb = rb.cross(normal);
            let k = ma + mb + ia * rna * rna + ib * rnb * rnb;
            let impulse = if k > 0.0 { -cc / k } else { 0.0 };
            let p = impulse * normal;
            bodies[a].sweep.c -= ma * p;
            bodies[a].sweep.a -= ia * ra.cross(p);
            bodies[b].sweep.c += mb * p;
            bodies[b].sweep.a += ib * rb.cross(p);
        }
    }
    min_sep >= -done_below * LINEAR_SLOP
}
