//! Revolute joint (Box2D 2.3's `b2RevoluteJoint`): a point constraint, a velocity motor whose
//! impulse per step is bounded by `max_motor_torque · dt`, and angle limits with Box2D 2.3's
//! limit states — a limit acts only if the joint is at or past it when the step starts (no
//! speculative limit), its accumulated impulse is one-sided, and position correction leaves
//! `ANGULAR_SLOP` of overshoot.

use super::body::Body;
use super::math::{V2, cross_sv};
use super::settings::{ANGULAR_SLOP, LINEAR_SLOP, MAX_ANGULAR_CORRECTION};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LimitState {
    #[default]
    Inactive,
    AtLower,
    AtUpper,
    /// Lower and upper closer than two angular slops: the angle is locked.
    Equal,
}

/// What a revolute joint is made of (Box2D's `b2RevoluteJointDef`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RevoluteDef {
    pub body_a: usize,
    pub body_b: usize,
    /// Anchor in each body's frame (origin-relative).
    pub local_anchor_a: V2,
    pub local_anchor_b: V2,
    /// `angle_b − angle_a` at which the joint angle is 0.
    pub reference_angle: f64,
    pub enable_limit: bool,
    pub lower: f64,
    pub upper: f64,
    pub enable_motor: bool,
    pub motor_speed: f64,
    pub max_motor_torque: f64,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RevoluteJoint {
    pub def: RevoluteDef,
    /// Accumulated point (x, y) and limit (z) impulses.
    pub impulse: [f64; 3],
    pub motor_impulse: f64,
    pub limit_state: LimitState,
    // Per-step solver data.
    ra: V2,
    rb: V2,
    /// Rows of the symmetric 3×3 effective mass matrix.
    k: [[f64; 3]; 3],
    /// Inverses of `k` and of its upper-left 2×2 block, fixed for the step (the velocity
    /// iterations then multiply instead of solving: Box2D's `Solve33` / `Solve22` by Cramer's
    /// rule, computed once).
    k_inv: [[f64; 3]; 3],
    k_inv22: [[f64; 2]; 2],
    motor_mass: f64,
}

fn inverse22(k: &[[f64; 3]; 3]) -> [[f64; 2]; 2] {
    let c0 = solve22(k, V2 { x: 1.0, y: 0.0 });
    let c1 = solve22(k, V2 { x: 0.0, y: 1.0 });
    [[c0.x, c1.x], [c0.y, c1.y]]
}

fn inverse33(k: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let c: [[f64; 3]; 3] = std::array::from_fn(|i| {
        let mut e = [0.0; 3];
        e[i] = 1.0;
        solve33(k, e)
    });
    std::array::from_fn(|r| std::array::from_fn(|col| c[col][r]))
}

fn mul22(m: &[[f64; 2]; 2], b: V2) -> V2 {
    V2 {
        x: m[0][0] * b.x + m[0][1] * b.y,
        y: m[1][0] * b.x + m[1][1] * b.y,
    }
}

fn mul33(m: &[[f64; 3]; 3], b: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|r| m[r][0] * b[0] + m[r][1] * b[1] + m[r][2] * b[2])
}

fn solve22(k: &[[f64; 3]; 3], b: V2) -> V2 {
    let (a11, a12, a21, a22) = (k[0][0], k[0][1], k[1][0], k[1][1]);
    let mut det = a11 * a22 - a12 * a21;
    if det != 0.0 {
        det = 1.0 / det;
    }
    V2 {
        x: det * (a22 * b.x - a12 * b.y),
        y: det * (a11 * b.y - a21 * b.x),
    }
}

fn cross3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn dot3(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn solve33(k: &[[f64; 3]; 3], b: [f64; 3]) -> [f64; 3] {
    // Columns of the (symmetric) matrix.
    let (ex, ey, ez) = (
        [k[0][0], k[1][0], k[2][0]],
        [k[0][1], k[1][1], k[2][1]],
        [k[0][2], k[1][2], k[2][2]],
    );
    let mut det = dot3(ex, cross3(ey, ez));
    if det != 0.0 {
        det = 1.0 / det;
    }
    [
        det * dot3(b, cross3(ey, ez)),
        det * dot3(ex, cross3(b, ez)),
        det * dot3(ex, cross3(ey, b)),
    ]
}

impl RevoluteJoint {
    pub fn new(def: RevoluteDef) -> RevoluteJoint {
        RevoluteJoint {
            def,
            impulse: [0.0; 3],
            motor_impulse: 0.0,
            limit_state: LimitState::Inactive,
            ra: V2::ZERO,
            rb: V2::ZERO,
            k: [[0.0; 3]; 3],
            k_inv: [[0.0; 3]; 3],
            k_inv22: [[0.0; 2]; 2],
            motor_mass: 0.0,
        }
    }

    /// `angle_b − angle_a − reference`.
    pub fn angle(&self, bodies: &[Body]) -> f64 {
        bodies[self.def.body_b].sweep.a - bodies[self.def.body_a].sweep.a - self.def.reference_angle
    }
    /// `ω_b − ω_a`.
    pub fn speed(&self, bodies: &[Body]) -> f64 {
        bodies[self.def.body_b].w - bodies[self.def.body_a].w
    }

    fn masses(&self, bodies: &[Body]) -> (f64, f64, f64, f64) {
        let (a, b) = (&bodies[self.def.body_a], &bodies[self.def.body_b]);
        (a.inv_mass, a.inv_inertia, b.inv_mass, b.inv_inertia)
    }

    /// Anchors, effective masses and the limit state for this step; then the warm start
    /// (impulses scaled by `dt_ratio`) or, without it, cleared impulses.
    pub fn init_velocity(&mut self, bodies: &mut [Body], dt_ratio: f64, warm_start: bool) {
        let (ia_, ib_) = (self.def.body_a, self.def.body_b);
        let (ma, ia, mb, ib) = self.masses(bodies);
        let (ba, bb) = (&bodies[ia_], &bodies[ib_]);
        self.ra = super::math::Rot::new(ba.sweep.a).apply(self.def.local_anchor_a - ba.sweep.local_center);
        self.rb = super::math::Rot::new(bb.sweep.a).apply(self.def.local_anchor_b - bb.sweep.local_center);
        let (ra, rb) = (self.ra, self.rb);
        let fixed_rotation = ia + ib == 0.0;
        let k00 = ma + mb + ra.y * ra.y * ia + rb.y * rb.y * ib;
        let k01 = -ra.y * ra.x * ia - rb.y * rb.x * ib;
        let k02 = -ra.y * ia - rb.y * ib;
        let k11 = ma + mb + ra.x * ra.x * ia + rb.x * rb.x * ib;
        let k12 = ra.x * ia + rb.x * ib;
        let k22 = ia + ib;
        self.k = [[k00, k01, k02], [k01, k11, k12], [k02, k12, k22]];
        self.k_inv22 = inverse22(&self.k);
        self.motor_mass = if k22 > 0.0 { 1.0 / k22 } else { 0.0 };
        if !self.def.enable_motor || fixed_rotation {
            self.motor_impulse = 0.0;
        }
        if self.def.enable_limit && !fixed_rotation {
            let angle = bb.sweep.a - ba.sweep.a - self.def.reference_angle;
            let (lo, hi) = (self.def.lower, self.def.upper);
            if (hi - lo).abs() < 2.0 * ANGULAR_SLOP {
                self.limit_state = LimitState::Equal;
            } else if angle <= lo {
                if self.limit_state != LimitState::AtLower {
                    self.impulse[2] = 0.0;
                }
                self.limit_state = LimitState::AtLower;
            } else if angle >= hi {
                if self.limit_state != LimitState::AtUpper {
                    self.impulse[2] = 0.0;
                }
                self.limit_state = LimitState::AtUpper;
            } else {
                self.limit_state = LimitState::Inactive;
                self.impulse[2] = 0.0;
            }
        } else {
            self.limit_state = LimitState::Inactive;
        }
        if self.limit_state != LimitState::Inactive {
            self.k_inv = inverse33(&self.k);
        }
        if warm_start {
            for i in &mut self.impulse {
                *i *= dt_ratio;
            }
            self.motor_impulse *= dt_ratio;
            let p = V2 {
                x: self.impulse[0],
                y: self.impulse[1],
            };
            let l = self.motor_impulse + self.impulse[2];
            let ba = &mut bodies[ia_];
            ba.v -= ma * p;
            ba.w -= ia * (ra.cross(p) + l);
            let bb = &mut bodies[ib_];
            bb.v += mb * p;
            bb.w += ib * (rb.cross(p) + l);
        } else {
            self.impulse = [0.0; 3];
            self.motor_impulse = 0.0;
        }
    }

    pub fn solve_velocity(&mut self, bodies: &mut [Body], dt: f64) {
        let (a, b) = (self.def.body_a, self.def.body_b);
        let (ma, ia, mb, ib) = self.masses(bodies);
        let fixed_rotation = ia + ib == 0.0;
        let (ra, rb) = (self.ra, self.rb);
        let (mut va, mut wa, mut vb, mut wb) = (bodies[a].v, bodies[a].w, bodies[b].v, bodies[b].w);

        if self.def.enable_motor && self.limit_state != LimitState::Equal && !fixed_rotation {
            let cdot = wb - wa - self.def.motor_speed;
            let old = self.motor_impulse;
            let max = dt * self.def.max_motor_torque;
            self.motor_impulse = (old - self.motor_mass * cdot).clamp(-max, max);
            let imp = self.motor_impulse - old;
            wa -= ia * imp;
            wb += ib * imp;
        }

        if self.def.enable_limit && self.limit_state != LimitState::Inactive && !fixed_rotation {
            let cdot1 = vb + cross_sv(wb, rb) - va - cross_sv(wa, ra);
            let cdot2 = wb - wa;
            let s = mul33(&self.k_inv, [cdot1.x, cdot1.y, cdot2]);
            let mut imp = [-s[0], -s[1], -s[2]];
            let reduced = |acc: &[f64; 3]| {
                let rhs = -cdot1
                    + acc[2]
                        * V2 {
                            x: self.k[2][0],
                            y: self.k[2][1],
                        };
                mul22(&self.k_inv22, rhs)
            };
            match self.limit_state {
                LimitState::Equal => {
                    for (acc, d) in self.impulse.iter_mut().zip(imp) {
                        *acc += d;
                    }
                }
                LimitState::AtLower | LimitState::AtUpper => {
                    let new_z = self.impulse[2] + imp[2];
                    let violates = if self.limit_state == LimitState::AtLower {
                        new_z < 0.0
                    } else {
                        new_z > 0.0
                    };
                    if violates {
                        let r = reduced(&self.impulse);
                        imp = [r.x, r.y, -self.impulse[2]];
                        self.impulse[0] += r.x;
                        self.impulse[1] += r.y;
                        self.impulse[2] = 0.0;
                    } else {
                        for (acc, d) in self.impulse.iter_mut().zip(imp) {
                            *acc += d;
                        }
                    }
                }
                LimitState::Inactive => unreachable!(),
            }
            let p = V2 { x: imp[0], y: imp[1] };
            va -= ma * p;
            wa -= ia * (ra.cross(p) + imp[2]);
            vb += mb * p;
            wb += ib * (rb.cross(p) + imp[2]);
        } else {
            let cdot = vb + cross_sv(wb, rb) - va - cross_sv(wa, ra);
            let imp = mul22(&self.k_inv22, -cdot);
            self.impulse[0] += imp.x;
            self.impulse[1] += imp.y;
            va -= ma * imp;
            wa -= ia * ra.cross(imp);
            vb += mb * imp;
            wb += ib * rb.cross(imp);
        }
        bodies[a].v = va;
        bodies[a].w = wa;
        bodies[b].v = vb;
        bodies[b].w = wb;
    }

    /// One NGS pass; true when the anchors are within `LINEAR_SLOP` and the limit within
    /// `ANGULAR_SLOP`.
    pub fn solve_position(&self, bodies: &mut [Body]) -> bool {
        let (a, b) = (self.def.body_a, self.def.body_b);
        let (ma, ia, mb, ib) = self.masses(bodies);
        let fixed_rotation = ia + ib == 0.0;
        let mut angular_error = 0.0;
        if self.def.enable_limit && self.limit_state != LimitState::Inactive && !fixed_rotation {
            let angle = bodies[b].sweep.a - bodies[a].sweep.a - self.def.reference_angle;
            let c = match self.limit_state {
                LimitState::Equal => {
                    let c = (angle - self.def.lower).clamp(-MAX_ANGULAR_CORRECTION, MAX_ANGULAR_CORRECTION);
                    angular_error = c.abs();
                    c
                }
                LimitState::AtLower => {
                    let c = angle - self.def.lower;
                    angular_error = -c;
                    (c + ANGULAR_SLOP).clamp(-MAX_ANGULAR_CORRECTION, 0.0)
                }
                LimitState::AtUpper => {
                    let c = angle - self.def.upper;
                    angular_error = c;
                    (c - ANGULAR_SLOP).clamp(0.0, MAX_ANGULAR_CORRECTION)
                }
                LimitState::Inactive => 0.0,
            };
            let limit_impulse = -self.motor_mass * c;
            bodies[a].sweep.a -= ia * limit_impulse;
            bodies[b].sweep.a += ib * limit_impulse;
        }
        let (ba, bb) = (&bodies[a], &bodies[b]);
        let ra = super::math::Rot::new(ba.sweep.a).apply(self.def.local_anchor_a - ba.sweep.local_center);
        let rb = super::math::Rot::new(bb.sweep.a).apply(self.def.local_anchor_b - bb.sweep.local_center);
        let c = bb.sweep.c + rb - ba.sweep.c - ra;
        let position_error = c.length();
        let k01 = -ia * ra.x * ra.y - ib * rb.x * rb.y;
        let k = [
            [ma + mb + ia * ra.y * ra.y + ib * rb.y * rb.y, k01, 0.0],
            [k01, ma + mb + ia * ra.x * ra.x + ib * rb.x * rb.x, 0.0],
            [0.0; 3],
        ];
        let imp = -solve22(&k, c);
        let ba = &mut bodies[a];
        ba.sweep.c -= ma * imp;
        ba.sweep.a -= ia * ra.cross(imp);
        let bb = &mut bodies[b];
        bb.sweep.c += mb * imp;
        bb.sweep.a += ib * rb.cross(imp);
        position_error <= LINEAR_SLOP && angular_error <= ANGULAR_SLOP
    }
}
