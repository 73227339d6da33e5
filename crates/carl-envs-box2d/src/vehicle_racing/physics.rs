//! A minimal Box2D-style rigid-body stepper for the vehicles: compound rigid bodies (a hull or
//! trailer together with the wheels pinned to it), revolute joints between them (point
//! constraint, optional angle limit, optional motor at speed 0 as hinge friction), soft distance
//! joints (Box2D's spring formulation), symplectic
//! Euler integration with Box2D's per-step motion caps, and Box2D 2.3's position correction.
//! See the parent module's docs for why this replaces a rapier world.

/// 2-D vector.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct V2 {
    pub x: f64,
    pub y: f64,
}

impl V2 {
    pub const ZERO: V2 = V2 { x: 0.0, y: 0.0 };
    #[inline]
    pub const fn new(x: f64, y: f64) -> V2 {
        V2 { x, y }
    }
    #[inline]
    pub fn dot(self, o: V2) -> f64 {
        self.x * o.x + self.y * o.y
    }
    #[inline]
    pub fn cross(self, o: V2) -> f64 {
        self.x * o.y - self.y * o.x
    }
    #[inline]
    pub fn len(self) -> f64 {
        self.dot(self).sqrt()
    }
    /// Rotate by `(sin, cos)`.
    #[inline]
    pub fn rot(self, s: f64, c: f64) -> V2 {
        V2::new(c * self.x - s * self.y, s * self.x + c * self.y)
    }
    /// `w × self` for a scalar angular velocity `w`.
    #[inline]
    pub fn perp_scaled(self, w: f64) -> V2 {
        V2::new(-w * self.y, w * self.x)
    }
}

impl std::ops::Add for V2 {
    type Output = V2;
    #[inline]
    fn add(self, o: V2) -> V2 {
        V2::new(self.x + o.x, self.y + o.y)
    }
}
impl std::ops::Sub for V2 {
    type Output = V2;
    #[inline]
    fn sub(self, o: V2) -> V2 {
        V2::new(self.x - o.x, self.y - o.y)
    }
}
impl std::ops::Mul<f64> for V2 {
    type Output = V2;
    #[inline]
    fn mul(self, k: f64) -> V2 {
        V2::new(self.x * k, self.y * k)
    }
}
impl std::ops::Neg for V2 {
    type Output = V2;
    #[inline]
    fn neg(self) -> V2 {
        V2::new(-self.x, -self.y)
    }
}

/// Convex hull (counter-clockwise, Andrew's monotone chain), as Box2D's `b2PolygonShape::Set`
/// takes of the vertices it is given.
pub fn convex_hull(points: &[V2]) -> Vec<V2> {
    let mut p: Vec<V2> = points.to_vec();
    p.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let mut hull: Vec<V2> = Vec::with_capacity(2 * p.len());
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &V2>> = if pass == 0 {
            Box::new(p.iter())
        } else {
            Box::new(p.iter().rev())
        };
        for &q in iter {
            while hull.len() >= start + 2 {
                let a = hull[hull.len() - 2];
                let b = hull[hull.len() - 1];
                if (b - a).cross(q - a) <= 0.0 {
                    hull.pop();
                } else {
                    break;
                }
            }
            hull.push(q);
        }
        hull.pop();
    }
    hull
}

/// Mass, centroid and rotational inertia about the *origin* of a convex polygon of uniform
/// `density` (Box2D's `b2PolygonShape::ComputeMass`).
pub fn polygon_mass(hull: &[V2], density: f64) -> (f64, V2, f64) {
    let n = hull.len();
    if n < 3 {
        return (0.0, V2::ZERO, 0.0);
    }
    let s = hull[0];
    let (mut area, mut center, mut inertia) = (0.0, V2::ZERO, 0.0);
    for i in 0..n {
        let e1 = hull[i] - s;
        let e2 = hull[(i + 1) % n] - s;
        let d = e1.cross(e2);
        let tri = 0.5 * d;
        area += tri;
        center = center + (e1 + e2) * (tri / 3.0);
        let intx2 = e1.x * e1.x + e2.x * e1.x + e2.x * e2.x;
        let inty2 = e1.y * e1.y + e2.y * e1.y + e2.y * e2.y;
        inertia += (0.25 / 3.0 * d) * (intx2 + inty2);
    }
    let mass = density * area;
    let c = center * (1.0 / area);
    let centroid = c + s;
    // Inertia about the centroid, then about the origin.
    let i_c = density * inertia - mass * c.dot(c);
    (mass, centroid, i_c + mass * centroid.dot(centroid))
}

/// Mass properties of a compound body: total mass, centre of mass (body frame) and rotational
/// inertia about the centre of mass.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MassProps {
    pub mass: f64,
    pub com: V2,
    pub inertia: f64,
}

impl MassProps {
    /// Sum of parts given as (mass, centroid, inertia about the body origin).
    pub fn from_parts(parts: &[(f64, V2, f64)]) -> MassProps {
        let mass: f64 = parts.iter().map(|p| p.0).sum();
        let mut c = V2::ZERO;
        let mut i_origin = 0.0;
        for &(m, pc, i) in parts {
            c = c + pc * m;
            i_origin += i;
        }
        let com = if mass > 0.0 { c * (1.0 / mass) } else { V2::ZERO };
        MassProps {
            mass,
            com,
            inertia: i_origin - mass * com.dot(com),
        }
    }
}

/// Kinematic state of one compound body: origin position, angle, velocity of the centre of mass
/// and angular velocity (Box2D's `position`, `angle`, `linearVelocity`, `angularVelocity`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BodyState {
    pub pos: V2,
    pub angle: f64,
    pub vel: V2,
    pub w: f64,
}

/// A body of the simulation: mass properties, state and the force/torque accumulated this step.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Body {
    pub props: MassProps,
    pub s: BodyState,
    pub force: V2,
    pub torque: f64,
}

impl Body {
    #[inline]
    pub fn sin_cos(&self) -> (f64, f64) {
        self.s.angle.sin_cos()
    }
    /// World position of a body-frame point.
    #[inline]
    pub fn world_point(&self, local: V2) -> V2 {
        let (s, c) = self.sin_cos();
        self.s.pos + local.rot(s, c)
    }
    #[inline]
    pub fn com_world(&self) -> V2 {
        self.world_point(self.props.com)
    }
    /// Velocity of the material point at world position `p`.
    #[inline]
    pub fn velocity_at(&self, p: V2) -> V2 {
        self.s.vel + (p - self.com_world()).perp_scaled(self.s.w)
    }
    /// `ApplyForce(f, p)`.
    #[inline]
    pub fn apply_force(&mut self, f: V2, p: V2) {
        self.force = self.force + f;
        self.torque += (p - self.com_world()).cross(f);
    }
    fn inv_mass(&self) -> f64 {
        if self.props.mass > 0.0 {
            1.0 / self.props.mass
        } else {
            0.0
        }
    }
    fn inv_inertia(&self) -> f64 {
        if self.props.inertia > 0.0 {
            1.0 / self.props.inertia
        } else {
            0.0
        }
    }
}

/// A revolute joint between bodies `a` and `b` (anchors in the bodies' frames, reference angle 0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Revolute {
    pub a: usize,
    pub b: usize,
    pub anchor_a: V2,
    pub anchor_b: V2,
    /// Symmetric angle limit `[-limit, +limit]`.
    pub limit: Option<f64>,
    /// Motor at speed 0 with this maximal torque (acts as hinge friction).
    pub motor_torque: Option<f64>,
}

/// A soft distance joint (Box2D 2.3 `b2DistanceJoint` with `frequencyHz > 0`): a spring of
/// `length` between the anchors, solved at velocity level with Box2D's soft-constraint bias and
/// no position correction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Distance {
    pub a: usize,
    pub b: usize,
    pub anchor_a: V2,
    pub anchor_b: V2,
    pub length: f64,
    pub frequency_hz: f64,
    pub damping_ratio: f64,
}

/// Box2D 2.3 constants (b2Settings.h).
pub const LINEAR_SLOP: f64 = 0.005;
pub const ANGULAR_SLOP: f64 = 2.0 / 180.0 * std::f64::consts::PI;
pub const MAX_ANGULAR_CORRECTION: f64 = 8.0 / 180.0 * std::f64::consts::PI;
pub const MAX_TRANSLATION: f64 = 2.0;
pub const MAX_ROTATION: f64 = 0.5 * std::f64::consts::PI;

/// Solver iteration counts (Box2D in CarRacing: 180 velocity, 60 position iterations, with warm
/// starting; here no impulses are carried between steps, so the state is just the bodies).
pub const VELOCITY_ITERATIONS: usize = 60;
pub const POSITION_ITERATIONS: usize = 60;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum LimitState {
    Inactive,
    AtLower,
    AtUpper,
}

/// Box2D's revolute joint angle: `angle_b - angle_a` (reference angle 0).
pub fn joint_angle(bodies: &[Body], j: &Revolute) -> f64 {
    bodies[j.b].s.angle - bodies[j.a].s.angle
}

fn solve_k(k11: f64, k12: f64, k22: f64, b: V2) -> V2 {
    let det = k11 * k22 - k12 * k12;
    let det = if det != 0.0 { 1.0 / det } else { 0.0 };
    V2::new(det * (k22 * b.x - k12 * b.y), det * (k11 * b.y - k12 * b.x))
}

/// Per-step data of a distance joint (`InitVelocityConstraints`).
struct RodRow {
    u: V2,
    ra: V2,
    rb: V2,
    mass: f64,
    gamma: f64,
    bias: f64,
    acc: f64,
}

fn rod_row(bodies: &[Body], j: &Distance, dt: f64) -> RodRow {
    let (ba, bb) = (&bodies[j.a], &bodies[j.b]);
    let (sa, ca) = ba.sin_cos();
    let (sb, cb) = bb.sin_cos();
    let ra = (j.anchor_a - ba.props.com).rot(sa, ca);
    let rb = (j.anchor_b - bb.props.com).rot(sb, cb);
    let mut u = bb.com_world() + rb - ba.com_world() - ra;
    let length = u.len();
    u = if length > LINEAR_SLOP {
        u * (1.0 / length)
    } else {
        V2::ZERO
    };
    let (ma, mb) = (ba.inv_mass(), bb.inv_mass());
    let (ia, ib) = (ba.inv_inertia(), bb.inv_inertia());
    let cra = ra.cross(u);
    let crb = rb.cross(u);
    let mut inv_mass = ma + ia * cra * cra + mb + ib * crb * crb;
    let mut mass = if inv_mass != 0.0 { 1.0 / inv_mass } else { 0.0 };
    let (mut gamma, mut bias) = (0.0, 0.0);
    if j.frequency_hz > 0.0 {
        let c = length - j.length;
        let omega = 2.0 * std::f64::consts::PI * j.frequency_hz;
        let d = 2.0 * mass * j.damping_ratio * omega;
        let k = mass * omega * omega;
        gamma = dt * (d + dt * k);
        gamma = if gamma != 0.0 { 1.0 / gamma } else { 0.0 };
        bias = c * dt * k * gamma;
        inv_mass += gamma;
        mass = if inv_mass != 0.0 { 1.0 / inv_mass } else { 0.0 };
    }
    RodRow {
        u,
        ra,
        rb,
        mass,
        gamma,
        bias,
        acc: 0.0,
    }
}

/// Advance `bodies` by `dt` under their accumulated forces, the revolute `joints` and the soft
/// distance joints `rods`; clears the forces.
pub fn step(bodies: &mut [Body], joints: &[Revolute], rods: &[Distance], dt: f64) {
    // Integrate velocities.
    for b in bodies.iter_mut() {
        let (im, ii) = (b.inv_mass(), b.inv_inertia());
        b.s.vel = b.s.vel + b.force * (dt * im);
        b.s.w += dt * ii * b.torque;
        b.force = V2::ZERO;
        b.torque = 0.0;
    }

    // Velocity constraints.
    let states: Vec<LimitState> = joints
        .iter()
        .map(|j| match j.limit {
            Some(l) => {
                let a = joint_angle(bodies, j);
                if a <= -l {
                    LimitState::AtLower
                } else if a >= l {
                    LimitState::AtUpper
                } else {
                    LimitState::Inactive
                }
            }
            None => LimitState::Inactive,
        })
        .collect();
    let mut rod_rows: Vec<RodRow> = rods.iter().map(|j| rod_row(bodies, j, dt)).collect();
    if !joints.is_empty() || !rods.is_empty() {
        let mut motor_acc = vec![0.0f64; joints.len()];
        let mut limit_acc = vec![0.0f64; joints.len()];
        for _ in 0..VELOCITY_ITERATIONS {
            for (k, j) in joints.iter().enumerate() {
                let (ba, bb) = (bodies[j.a], bodies[j.b]);
                let (ma, mb) = (ba.inv_mass(), bb.inv_mass());
                let (ia, ib) = (ba.inv_inertia(), bb.inv_inertia());
                let (mut va, mut wa, mut vb, mut wb) = (ba.s.vel, ba.s.w, bb.s.vel, bb.s.w);
                let axial = if ia + ib > 0.0 { 1.0 / (ia + ib) } else { 0.0 };
                if let Some(t) = j.motor_torque {
                    let cdot = wb - wa;
                    let max = dt * t;
                    let old = motor_acc[k];
                    motor_acc[k] = (old - axial * cdot).clamp(-max, max);
                    let imp = motor_acc[k] - old;
                    wa -= ia * imp;
                    wb += ib * imp;
                }
                if states[k] != LimitState::Inactive {
                    let cdot = wb - wa;
                    let old = limit_acc[k];
                    let new = old - axial * cdot;
                    limit_acc[k] = if states[k] == LimitState::AtLower {
                        new.max(0.0)
                    } else {
                        new.min(0.0)
                    };
                    let imp = limit_acc[k] - old;
                    wa -= ia * imp;
                    wb += ib * imp;
                }
                let (sa, ca) = ba.sin_cos();
                let (sb, cb) = bb.sin_cos();
                let ra = (j.anchor_a - ba.props.com).rot(sa, ca);
                let rb = (j.anchor_b - bb.props.com).rot(sb, cb);
                let cdot = vb + rb.perp_scaled(wb) - va - ra.perp_scaled(wa);
                let k11 = ma + mb + ia * ra.y * ra.y + ib * rb.y * rb.y;
                let k12 = -ia * ra.x * ra.y - ib * rb.x * rb.y;
                let k22 = ma + mb + ia * ra.x * ra.x + ib * rb.x * rb.x;
                let p = solve_k(k11, k12, k22, -cdot);
                va = va - p * ma;
                wa -= ia * ra.cross(p);
                vb = vb + p * mb;
                wb += ib * rb.cross(p);
                bodies[j.a].s.vel = va;
                bodies[j.a].s.w = wa;
                bodies[j.b].s.vel = vb;
                bodies[j.b].s.w = wb;
            }
            for (j, r) in rods.iter().zip(rod_rows.iter_mut()) {
                let (ba, bb) = (bodies[j.a], bodies[j.b]);
                let vpa = ba.s.vel + r.ra.perp_scaled(ba.s.w);
                let vpb = bb.s.vel + r.rb.perp_scaled(bb.s.w);
                let cdot = r.u.dot(vpb - vpa);
                let imp = -r.mass * (cdot + r.bias + r.gamma * r.acc);
                r.acc += imp;
                let p = r.u * imp;
                bodies[j.a].s.vel = ba.s.vel - p * ba.inv_mass();
                bodies[j.a].s.w = ba.s.w - ba.inv_inertia() * r.ra.cross(p);
                bodies[j.b].s.vel = bb.s.vel + p * bb.inv_mass();
                bodies[j.b].s.w = bb.s.w + bb.inv_inertia() * r.rb.cross(p);
            }
        }
    }

    // Integrate positions (centre of mass), with Box2D's per-step caps.
    for b in bodies.iter_mut() {
        let t = b.s.vel * dt;
        if t.dot(t) > MAX_TRANSLATION * MAX_TRANSLATION {
            b.s.vel = b.s.vel * (MAX_TRANSLATION / t.len());
        }
        let r = dt * b.s.w;
        if r * r > MAX_ROTATION * MAX_ROTATION {
            b.s.w *= MAX_ROTATION / r.abs();
        }
        let c = b.com_world() + b.s.vel * dt;
        b.s.angle += dt * b.s.w;
        let (s, co) = b.sin_cos();
        b.s.pos = c - b.props.com.rot(s, co);
    }

    // Position correction (Box2D 2.3 `b2RevoluteJoint::SolvePositionConstraints`).
    for _ in 0..POSITION_ITERATIONS {
        let mut ok = true;
        for (k, j) in joints.iter().enumerate() {
            let (ia, ib) = (bodies[j.a].inv_inertia(), bodies[j.b].inv_inertia());
            let axial = if ia + ib > 0.0 { 1.0 / (ia + ib) } else { 0.0 };
            let mut angular_error = 0.0;
            if let Some(l) = j.limit {
                let angle = joint_angle(bodies, j);
                let imp = match states[k] {
                    LimitState::AtLower => {
                        let c = angle + l;
                        angular_error = -c;
                        -axial * (c + ANGULAR_SLOP).clamp(-MAX_ANGULAR_CORRECTION, 0.0)
                    }
                    LimitState::AtUpper => {
                        let c = angle - l;
                        angular_error = c;
                        -axial * (c - ANGULAR_SLOP).clamp(0.0, MAX_ANGULAR_CORRECTION)
                    }
                    LimitState::Inactive => 0.0,
                };
                rotate_about_com(&mut bodies[j.a], -ia * imp);
                rotate_about_com(&mut bodies[j.b], ib * imp);
            }
            let (ba, bb) = (bodies[j.a], bodies[j.b]);
            let (ma, mb) = (ba.inv_mass(), bb.inv_mass());
            let (sa, ca) = ba.sin_cos();
            let (sb, cb) = bb.sin_cos();
            let ra = (j.anchor_a - ba.props.com).rot(sa, ca);
            let rb = (j.anchor_b - bb.props.com).rot(sb, cb);
            let c = bb.com_world() + rb - ba.com_world() - ra;
            let position_error = c.len();
            let k11 = ma + mb + ia * ra.y * ra.y + ib * rb.y * rb.y;
            let k12 = -ia * ra.x * ra.y - ib * rb.x * rb.y;
            let k22 = ma + mb + ia * ra.x * ra.x + ib * rb.x * rb.x;
            let imp = -solve_k(k11, k12, k22, c);
            translate_com(&mut bodies[j.a], -imp * ma, -ia * ra.cross(imp));
            translate_com(&mut bodies[j.b], imp * mb, ib * rb.cross(imp));
            ok &= position_error <= LINEAR_SLOP && angular_error <= ANGULAR_SLOP;
        }
        if ok {
            break;
        }
    }
}

/// Rotate a body by `da` about its centre of mass.
fn rotate_about_com(b: &mut Body, da: f64) {
    translate_com(b, V2::ZERO, da);
}

/// Move a body's centre of mass by `dc` and rotate it by `da` about it.
fn translate_com(b: &mut Body, dc: V2, da: f64) {
    let c = b.com_world() + dc;
    b.s.angle += da;
    let (s, co) = b.sin_cos();
    b.s.pos = c - b.props.com.rot(s, co);
}
