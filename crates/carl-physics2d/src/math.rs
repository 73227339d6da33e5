//! 2-D vectors, rotations and rigid transforms (Box2D's `b2Vec2`, `b2Rot`, `b2Transform`).

use std::ops::{Add, AddAssign, Mul, Neg, Sub, SubAssign};

#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct V2 {
    pub x: f64,
    pub y: f64,
}

pub const fn v2(x: f64, y: f64) -> V2 {
    V2 { x, y }
}

impl V2 {
    pub const ZERO: V2 = v2(0.0, 0.0);
    pub fn dot(self, o: V2) -> f64 {
        self.x * o.x + self.y * o.y
    }
    /// z of the 3-D cross product.
    pub fn cross(self, o: V2) -> f64 {
        self.x * o.y - self.y * o.x
    }
    pub fn length_squared(self) -> f64 {
        self.dot(self)
    }
    pub fn length(self) -> f64 {
        self.length_squared().sqrt()
    }
    /// Unit vector (the zero vector for lengths below `EPSILON`, as Box2D's `Normalize`).
    pub fn normalized(self) -> V2 {
        let l = self.length();
        if l < super::settings::EPSILON {
            V2::ZERO
        } else {
            self * (1.0 / l)
        }
    }
    /// `cross(v, s)`: `(s·y, −s·x)`.
    pub fn cross_s(self, s: f64) -> V2 {
        v2(s * self.y, -s * self.x)
    }
    pub fn min(self, o: V2) -> V2 {
        v2(self.x.min(o.x), self.y.min(o.y))
    }
    pub fn max(self, o: V2) -> V2 {
        v2(self.x.max(o.x), self.y.max(o.y))
    }
    pub fn tuple(self) -> (f64, f64) {
        (self.x, self.y)
    }
}

/// `cross(s, v)`: `(−s·y, s·x)` (the velocity of a point at `v` rotating at `s`).
pub fn cross_sv(s: f64, v: V2) -> V2 {
    v2(-s * v.y, s * v.x)
}

impl From<(f64, f64)> for V2 {
    fn from((x, y): (f64, f64)) -> V2 {
        v2(x, y)
    }
}
impl Add for V2 {
    type Output = V2;
    fn add(self, o: V2) -> V2 {
        v2(self.x + o.x, self.y + o.y)
    }
}
impl Sub for V2 {
    type Output = V2;
    fn sub(self, o: V2) -> V2 {
        v2(self.x - o.x, self.y - o.y)
    }
}
impl Neg for V2 {
    type Output = V2;
    fn neg(self) -> V2 {
        v2(-self.x, -self.y)
    }
}
impl Mul<f64> for V2 {
    type Output = V2;
    fn mul(self, s: f64) -> V2 {
        v2(self.x * s, self.y * s)
    }
}
impl Mul<V2> for f64 {
    type Output = V2;
    fn mul(self, v: V2) -> V2 {
        v * self
    }
}
impl AddAssign for V2 {
    fn add_assign(&mut self, o: V2) {
        self.x += o.x;
        self.y += o.y;
    }
}
impl SubAssign for V2 {
    fn sub_assign(&mut self, o: V2) {
        self.x -= o.x;
        self.y -= o.y;
    }
}

/// A rotation as sine and cosine.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rot {
    pub s: f64,
    pub c: f64,
}

impl Rot {
    pub fn new(angle: f64) -> Rot {
        let (s, c) = angle.sin_cos();
        Rot { s, c }
    }
    pub fn apply(self, v: V2) -> V2 {
        v2(self.c * v.x - self.s * v.y, self.s * v.x + self.c * v.y)
    }
    pub fn apply_inv(self, v: V2) -> V2 {
        v2(self.c * v.x + self.s * v.y, -self.s * v.x + self.c * v.y)
    }
}

/// A rigid transform: rotation then translation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Xf {
    pub p: V2,
    pub q: Rot,
}

impl Xf {
    pub fn new(p: V2, angle: f64) -> Xf {
        Xf { p, q: Rot::new(angle) }
    }
    /// The transform of a body whose centre of mass `c` (local `local_center`) has angle `a`.
    pub fn from_center(c: V2, a: f64, local_center: V2) -> Xf {
        let q = Rot::new(a);
        Xf {
            p: c - q.apply(local_center),
            q,
        }
    }
    pub fn apply(&self, v: V2) -> V2 {
        self.q.apply(v) + self.p
    }
    pub fn apply_inv(&self, v: V2) -> V2 {
        self.q.apply_inv(v - self.p)
    }
}
