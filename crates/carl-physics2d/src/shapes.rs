//! Convex polygons and edges with Box2D's skin (`POLYGON_RADIUS`), their mass and bounding boxes.

use super::math::{V2, Xf, v2};
use super::settings::{LINEAR_SLOP, POLYGON_RADIUS};

/// Most vertices of a polygon (`b2_maxPolygonVertices`).
pub const MAX_VERTICES: usize = 8;

/// A convex polygon, counter-clockwise, in body coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Polygon {
    pub count: usize,
    pub vertices: [V2; MAX_VERTICES],
    /// Outward unit normal of edge `i` (from vertex `i` to `i + 1`).
    pub normals: [V2; MAX_VERTICES],
    pub centroid: V2,
}

/// Why a polygon could not be built.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PolygonError {
    /// Fewer than 3 distinct points, or collinear points, or more than `MAX_VERTICES`.
    Degenerate,
}

impl Polygon {
    /// Box2D's `SetAsBox(hx, hy)`: corners from the lower left, counter-clockwise.
    pub fn new_box(hx: f64, hy: f64) -> Polygon {
        let mut p = Polygon {
            count: 4,
            vertices: [V2::ZERO; MAX_VERTICES],
            normals: [V2::ZERO; MAX_VERTICES],
            centroid: V2::ZERO,
        };
        p.vertices[..4].copy_from_slice(&[v2(-hx, -hy), v2(hx, -hy), v2(hx, hy), v2(-hx, hy)]);
        p.normals[..4].copy_from_slice(&[v2(0.0, -1.0), v2(1.0, 0.0), v2(0.0, 1.0), v2(-1.0, 0.0)]);
        p
    }

    /// Box2D's `b2PolygonShape::Set`: welds points closer than `LINEAR_SLOP / 2`, then wraps the
    /// convex hull counter-clockwise from the rightmost (then lowest) point, as Box2D orders it
    /// (the order decides feature ids and ties in the collision routines).
    pub fn from_points(points: &[V2]) -> Result<Polygon, PolygonError> {
        if points.len() < 3 || points.len() > MAX_VERTICES {
            return Err(PolygonError::Degenerate);
        }
        let mut ps = [V2::ZERO; MAX_VERTICES];
        let mut n = 0;
        for &p in points {
            if !(p.x.is_finite() && p.y.is_finite()) {
                return Err(PolygonError::Degenerate);
            }
            let weld = 0.5 * LINEAR_SLOP;
            if ps[..n].iter().all(|q| (p - *q).length_squared() > weld * weld) {
                ps[n] = p;
                n += 1;
            }
        }
        if n < 3 {
            return Err(PolygonError::Degenerate);
        }
        let mut i0 = 0;
        for i in 1..n {
            if ps[i].x > ps[i0].x || (ps[i].x == ps[i0].x && ps[i].y < ps[i0].y) {
                i0 = i;
            }
        }
        let mut hull = [0usize; MAX_VERTICES];
        let mut m = 0;
        let mut ih = i0;
        loop {
            if m == MAX_VERTICES {
                return Err(PolygonError::Degenerate);
            }
            hull[m] = ih;
            let mut ie = 0;
            for j in 1..n {
                if ie == ih {
                    ie = j;
                    continue;
                }
                let r = ps[ie] - ps[hull[m]];
                let v = ps[j] - ps[hull[m]];
                let c = r.cross(v);
                if c < 0.0 || (c == 0.0 && v.length_squared() > r.length_squared()) {
                    ie = j;
                }
            }
            m += 1;
            ih = ie;
            if ie == i0 {
                break;
            }
        }
        if m < 3 {
            return Err(PolygonError::Degenerate);
        }
        let mut poly = Polygon {
            count: m,
            vertices: [V2::ZERO; MAX_VERTICES],
            normals: [V2::ZERO; MAX_VERTICES],
            centroid: V2::ZERO,
        };
        for i in 0..m {
            poly.vertices[i] = ps[hull[i]];
        }
        for i in 0..m {
            let edge = poly.vertices[(i + 1) % m] - poly.vertices[i];
            if edge.length_squared() <= f64::EPSILON * f64::EPSILON {
                return Err(PolygonError::Degenerate);
            }
            poly.normals[i] = edge.cross_s(1.0).normalized();
        }
        let (area, centroid, _) = poly.area_moments();
        if area <= 0.0 {
            return Err(PolygonError::Degenerate);
        }
        poly.centroid = centroid;
        Ok(poly)
    }

    pub fn vertices(&self) -> &[V2] {
        &self.vertices[..self.count]
    }

    /// Area, centroid and the second moment about the centroid per unit density.
    fn area_moments(&self) -> (f64, V2, f64) {
        let s = self.vertices[0];
        let (mut area, mut c, mut i) = (0.0, V2::ZERO, 0.0);
        for k in 0..self.count {
            let e1 = self.vertices[k] - s;
            let e2 = self.vertices[(k + 1) % self.count] - s;
            let d = e1.cross(e2);
            let a = 0.5 * d;
            area += a;
            c += (a / 3.0) * (e1 + e2);
            let intx2 = e1.x * e1.x + e2.x * e1.x + e2.x * e2.x;
            let inty2 = e1.y * e1.y + e2.y * e1.y + e2.y * e2.y;
            i += (0.25 / 3.0 * d) * (intx2 + inty2);
        }
        if area <= 0.0 {
            return (area, s, 0.0);
        }
        let lc = c * (1.0 / area);
        // `i` is about `s`; move it to the centroid.
        let i_center = i - area * lc.length_squared();
        (area, lc + s, i_center)
    }
}

/// A shape of a fixture, in body coordinates. Stored inline (one per fixture): the collision
/// routines read it every step, so it is not boxed.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape {
    Polygon(Polygon),
    /// A two-sided segment.
    Edge(V2, V2),
}

/// Mass, centre of mass (body coordinates) and rotational inertia about the centre of mass.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MassData {
    pub mass: f64,
    pub center: V2,
    pub inertia_center: f64,
}

/// An axis-aligned box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    pub lo: V2,
    pub hi: V2,
}

impl Aabb {
    pub fn overlaps(&self, o: &Aabb) -> bool {
        !(o.lo.x > self.hi.x || o.lo.y > self.hi.y || self.lo.x > o.hi.x || self.lo.y > o.hi.y)
    }
    pub fn contains(&self, o: &Aabb) -> bool {
        self.lo.x <= o.lo.x && self.lo.y <= o.lo.y && o.hi.x <= self.hi.x && o.hi.y <= self.hi.y
    }
    pub fn union(&self, o: &Aabb) -> Aabb {
        Aabb {
            lo: self.lo.min(o.lo),
            hi: self.hi.max(o.hi),
        }
    }
}

impl Shape {
    /// Every shape carries Box2D's polygon skin.
    pub fn radius(&self) -> f64 {
        POLYGON_RADIUS
    }

    pub fn mass(&self, density: f64) -> MassData {
        match self {
            Shape::Polygon(p) => {
                let (area, c, i) = p.area_moments();
                MassData {
                    mass: density * area,
                    center: c,
                    inertia_center: density * i,
                }
            }
            Shape::Edge(a, b) => MassData {
                mass: 0.0,
                center: 0.5 * (*a + *b),
                inertia_center: 0.0,
            },
        }
    }

    /// Bounding box at `xf`, skin included.
    pub fn aabb(&self, xf: &Xf) -> Aabb {
        let (lo, hi) = match self {
            Shape::Polygon(p) => {
                let first = xf.apply(p.vertices[0]);
                p.vertices()[1..].iter().fold((first, first), |(lo, hi), v| {
                    let w = xf.apply(*v);
                    (lo.min(w), hi.max(w))
                })
            }
            Shape::Edge(a, b) => {
                let (a, b) = (xf.apply(*a), xf.apply(*b));
                (a.min(b), a.max(b))
            }
        };
        let r = v2(self.radius(), self.radius());
        Aabb { lo: lo - r, hi: hi + r }
    }

    /// Core vertices (without the skin) for the distance routines.
    pub fn core_vertices(&self) -> Vec<V2> {
        match self {
            Shape::Polygon(p) => p.vertices().to_vec(),
            Shape::Edge(a, b) => vec![*a, *b],
        }
    }
}
