//! Rigid bodies: static or dynamic, their sweep over a step and their mass.

use super::math::{V2, Xf};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BodyKind {
    /// Never moves; infinite mass.
    Static,
    Dynamic,
}

/// The motion of a body's centre of mass over a step (Box2D's `b2Sweep`): from `c0`, `a0` at
/// time fraction `alpha0` to `c`, `a` at the end.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sweep {
    pub local_center: V2,
    pub c0: V2,
    pub c: V2,
    pub a0: f64,
    pub a: f64,
    pub alpha0: f64,
}

impl Sweep {
    /// The transform at fraction `beta` of the remaining sweep.
    pub fn transform_at(&self, beta: f64) -> Xf {
        let c = (1.0 - beta) * self.c0 + beta * self.c;
        let a = (1.0 - beta) * self.a0 + beta * self.a;
        Xf::from_center(c, a, self.local_center)
    }
    /// Move the start of the sweep to step fraction `alpha`.
    pub fn advance(&mut self, alpha: f64) {
        let beta = (alpha - self.alpha0) / (1.0 - self.alpha0);
        self.c0 += beta * (self.c - self.c0);
        self.a0 += beta * (self.a - self.a0);
        self.alpha0 = alpha;
    }
}

/// A rigid body. Positions are of the body origin unless a name says centre.
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    pub kind: BodyKind,
    pub sweep: Sweep,
    /// Transform at the end of the sweep.
    pub xf: Xf,
    /// Velocity of the centre of mass and angular velocity.
    pub v: V2,
    pub w: f64,
    /// Force and torque accumulated for the next step (cleared after it).
    pub force: V2,
    pub torque: f64,
    pub mass: f64,
    pub inv_mass: f64,
    /// Rotational inertia about the centre of mass.
    pub inertia: f64,
    pub inv_inertia: f64,
}

impl Body {
    pub fn new(kind: BodyKind, position: V2, angle: f64) -> Body {
        Body {
            kind,
            sweep: Sweep {
                local_center: V2::ZERO,
                c0: position,
                c: position,
                a0: angle,
                a: angle,
                alpha0: 0.0,
            },
            xf: Xf::new(position, angle),
            v: V2::ZERO,
            w: 0.0,
            force: V2::ZERO,
            torque: 0.0,
            mass: 0.0,
            inv_mass: 0.0,
            inertia: 0.0,
            inv_inertia: 0.0,
        }
    }

    pub fn is_dynamic(&self) -> bool {
        self.kind == BodyKind::Dynamic
    }
    pub fn position(&self) -> V2 {
        self.xf.p
    }
    pub fn angle(&self) -> f64 {
        self.sweep.a
    }
    /// World centre of mass.
    pub fn center(&self) -> V2 {
        self.sweep.c
    }

    /// Recompute `xf` from the end of the sweep.
    pub fn synchronize_transform(&mut self) {
        self.xf = Xf::from_center(self.sweep.c, self.sweep.a, self.sweep.local_center);
    }

    /// Advance the sweep's start to `alpha` and put the body there (Box2D's `b2Body::Advance`).
    pub fn advance(&mut self, alpha: f64) {
        self.sweep.advance(alpha);
        self.sweep.c = self.sweep.c0;
        self.sweep.a = self.sweep.a0;
        self.synchronize_transform();
    }

    /// Place the body (origin and angle), keeping its velocities.
    pub fn set_transform(&mut self, position: V2, angle: f64) {
        self.xf = Xf::new(position, angle);
        let c = self.xf.apply(self.sweep.local_center);
        self.sweep.c = c;
        self.sweep.c0 = c;
        self.sweep.a = angle;
        self.sweep.a0 = angle;
    }

    /// Set mass properties (from the fixtures): `center` in body coordinates, `inertia` about it.
    /// Keeps the origin in place and the velocity of the origin's material point, as Box2D does.
    pub(crate) fn set_mass(&mut self, mass: f64, center: V2, inertia: f64) {
        if self.kind != BodyKind::Dynamic {
            return;
        }
        let (mass, center) = if mass > 0.0 { (mass, center) } else { (1.0, center) };
        self.mass = mass;
        self.inv_mass = 1.0 / mass;
        self.inertia = inertia;
        self.inv_inertia = if inertia > 0.0 { 1.0 / inertia } else { 0.0 };
        let old_c = self.sweep.c;
        self.sweep.local_center = center;
        let c = self.xf.apply(center);
        self.sweep.c0 = c;
        self.sweep.c = c;
        self.v += super::math::cross_sv(self.w, c - old_c);
    }
}
