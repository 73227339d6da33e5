//! Closest points between two convex shapes: the GJK distance algorithm as Box2D 2.3 runs it
//! (`b2Distance`), in `f64`.
//!
//! A shape is a [`DistanceProxy`]: a convex CCW vertex list (1 vertex = a point or circle centre,
//! 2 = an edge, 3..=8 = a polygon) plus a skin `radius` (Box2D's polygon radius). GJK works on the
//! Minkowski difference B − A through support points only, keeping a simplex of at most three
//! support-point pairs and reducing it with barycentric (Voronoi-region) coordinates; it stops when a
//! support point repeats, when the origin is enclosed, or when the search direction degenerates.
//! The simplex can be kept between calls ([`SimplexCache`], warm start) as Box2D does; a cache whose
//! simplex changed size by more than a factor 2 is flushed, so a stale cache never changes the answer,
//! only the work.
//!
//! Algorithm after Erin Catto, "Computing Distance" (GDC 2010) and Box2D 2.3 (© Erin Catto, zlib
//! licence), reimplemented here: same termination rules, the same simplex vertex order (the time of
//! impact code reads it), no global statistics counters (the iteration count is in the output).
//! The functions never allocate: the simplex is a fixed array, proxies own their vertices.

/// Box2D's `b2_maxPolygonVertices`.
pub const MAX_POLYGON_VERTICES: usize = 8;
/// Box2D's `b2_epsilon` (`FLT_EPSILON`). Kept at `f32`'s value although we compute in `f64`: it
/// only decides when a search direction or a normal counts as degenerate, and matching Box2D's
/// cut-off keeps the same decisions.
pub const EPSILON: f64 = f32::EPSILON as f64;
/// Box2D's `k_maxIters` for GJK (support-point evaluations per call).
pub const MAX_GJK_ITERATIONS: usize = 20;

/// A 2-D vector `(x, y)`.
pub type Vec2 = (f64, f64);

/// Small vector helpers shared with the time-of-impact module.
pub(super) mod v2 {
    use super::{EPSILON, Vec2};

    pub fn add(a: Vec2, b: Vec2) -> Vec2 {
        (a.0 + b.0, a.1 + b.1)
    }
    pub fn sub(a: Vec2, b: Vec2) -> Vec2 {
        (a.0 - b.0, a.1 - b.1)
    }
    pub fn scale(s: f64, a: Vec2) -> Vec2 {
        (s * a.0, s * a.1)
    }
    pub fn neg(a: Vec2) -> Vec2 {
        (-a.0, -a.1)
    }
    pub fn dot(a: Vec2, b: Vec2) -> f64 {
        a.0 * b.0 + a.1 * b.1
    }
    /// z of the 3-D cross product.
    pub fn cross(a: Vec2, b: Vec2) -> f64 {
        a.0 * b.1 - a.1 * b.0
    }
    /// `a` turned a quarter clockwise (Box2D's `b2Cross(a, 1)`): the outward normal direction of a
    /// CCW polygon edge `a`.
    pub fn right_perp(a: Vec2) -> Vec2 {
        (a.1, -a.0)
    }
    /// `a` turned a quarter anticlockwise (Box2D's `b2Cross(1, a)`).
    pub fn left_perp(a: Vec2) -> Vec2 {
        (-a.1, a.0)
    }
    pub fn length(a: Vec2) -> f64 {
        a.0.hypot(a.1)
    }
    /// Unit vector along `a` and the length of `a`; a vector shorter than `EPSILON` is returned
    /// unchanged with length 0 (Box2D's `Normalize`), so callers never divide by zero.
    pub fn normalize(a: Vec2) -> (Vec2, f64) {
        let len = length(a);
        if len < EPSILON {
            return (a, 0.0);
        }
        (scale(1.0 / len, a), len)
    }
}

/// A rotation, stored as sine and cosine of the angle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rot {
    pub s: f64,
    pub c: f64,
}

impl Rot {
    pub const IDENTITY: Rot = Rot { s: 0.0, c: 1.0 };

    /// The rotation by `angle` radians (anticlockwise).
    pub fn from_angle(angle: f64) -> Rot {
        let (s, c) = angle.sin_cos();
        Rot { s, c }
    }

    pub fn angle(&self) -> f64 {
        self.s.atan2(self.c)
    }

    /// Rotates `v`.
    pub fn apply(&self, v: Vec2) -> Vec2 {
        (self.c * v.0 - self.s * v.1, self.s * v.0 + self.c * v.1)
    }

    /// Rotates `v` back (the inverse rotation).
    pub fn apply_inv(&self, v: Vec2) -> Vec2 {
        (self.c * v.0 + self.s * v.1, -self.s * v.0 + self.c * v.1)
    }
}

/// A rigid placement: rotate by `q`, then translate by `p` (the body origin in world coordinates).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    pub p: Vec2,
    pub q: Rot,
}

impl Transform {
    pub const IDENTITY: Transform = Transform {
        p: (0.0, 0.0),
        q: Rot::IDENTITY,
    };

    pub fn new(p: Vec2, angle: f64) -> Transform {
        Transform {
            p,
            q: Rot::from_angle(angle),
        }
    }

    /// A body-local point in world coordinates.
    pub fn apply(&self, v: Vec2) -> Vec2 {
        v2::add(self.q.apply(v), self.p)
    }
}

/// Why a vertex list is not a valid [`DistanceProxy`].
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ProxyError {
    #[error("a distance proxy needs 1 to {MAX_POLYGON_VERTICES} vertices, got {0}")]
    VertexCount(usize),
    #[error("vertex {0} of a distance proxy is not finite")]
    NonFinite(usize),
    #[error("a distance proxy's radius must be finite and >= 0, got {0}")]
    Radius(f64),
    #[error("edge {0} of a distance proxy is shorter than {EPSILON}")]
    ShortEdge(usize),
    #[error(
        "distance proxy vertices are not a strictly convex counter-clockwise polygon: vertex {vertex} is not left of edge {edge}"
    )]
    NotConvexCcw { edge: usize, vertex: usize },
}

/// A convex shape for GJK: its vertices in body coordinates and its skin radius.
///
/// Invariants (checked by [`DistanceProxy::new`]; the query functions assume them and may panic
/// on an empty vertex list): 1..=8 finite vertices; for 3 or more, strictly convex and
/// counter-clockwise; `radius` finite and ≥ 0.
#[derive(Clone, Debug, PartialEq)]
pub struct DistanceProxy {
    pub vertices: Vec<Vec2>,
    pub radius: f64,
}

impl DistanceProxy {
    /// A validated proxy.
    pub fn new(vertices: Vec<Vec2>, radius: f64) -> Result<DistanceProxy, ProxyError> {
        let n = vertices.len();
        if n == 0 || n > MAX_POLYGON_VERTICES {
            return Err(ProxyError::VertexCount(n));
        }
        if let Some(i) = vertices.iter().position(|v| !(v.0.is_finite() && v.1.is_finite())) {
            return Err(ProxyError::NonFinite(i));
        }
        if !(radius.is_finite() && radius >= 0.0) {
            return Err(ProxyError::Radius(radius));
        }
        if n >= 2 {
            for i in 0..n {
                if v2::length(v2::sub(vertices[(i + 1) % n], vertices[i])) < EPSILON {
                    return Err(ProxyError::ShortEdge(i));
                }
            }
        }
        if n >= 3 {
            // Every vertex strictly left of every edge: convex, CCW and simple at once.
            for edge in 0..n {
                let (a, b) = (vertices[edge], vertices[(edge + 1) % n]);
                for (vertex, &v) in vertices.iter().enumerate() {
                    if vertex == edge || vertex == (edge + 1) % n {
                        continue;
                    }
                    if v2::cross(v2::sub(b, a), v2::sub(v, a)) <= 0.0 {
                        return Err(ProxyError::NotConvexCcw { edge, vertex });
                    }
                }
            }
        }
        Ok(DistanceProxy { vertices, radius })
    }

    /// Box2D's `SetAsBox(hx, hy)`: a box of half-extents `hx`, `hy` centred on the body origin.
    pub fn boxed(hx: f64, hy: f64, radius: f64) -> Result<DistanceProxy, ProxyError> {
        DistanceProxy::new(vec![(-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy)], radius)
    }

    /// An edge (segment) from `v1` to `v2`.
    pub fn edge(v1: Vec2, v2: Vec2, radius: f64) -> Result<DistanceProxy, ProxyError> {
        DistanceProxy::new(vec![v1, v2], radius)
    }

    /// Index of the vertex furthest along `d` (body coordinates); the first one on ties.
    pub fn support(&self, d: Vec2) -> usize {
        let mut best = 0;
        let mut best_value = v2::dot(self.vertices[0], d);
        for (i, &v) in self.vertices.iter().enumerate().skip(1) {
            let value = v2::dot(v, d);
            if value > best_value {
                best = i;
                best_value = value;
            }
        }
        best
    }

    pub fn vertex(&self, index: usize) -> Vec2 {
        self.vertices[index]
    }
}

/// The simplex of the previous call, to warm-start the next one (Box2D's `b2SimplexCache`).
/// `Default` is the empty cache. Keep one per shape pair; it refers to vertex indices, so it must
/// not be reused with other proxies.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SimplexCache {
    /// Length (2 points) or signed area (3 points) of the cached simplex.
    pub metric: f64,
    /// Number of cached points, 0..=3.
    pub count: usize,
    pub index_a: [usize; 3],
    pub index_b: [usize; 3],
}

/// Input of [`distance`].
#[derive(Clone, Copy, Debug)]
pub struct DistanceInput<'a> {
    pub proxy_a: &'a DistanceProxy,
    pub proxy_b: &'a DistanceProxy,
    pub transform_a: Transform,
    pub transform_b: Transform,
    /// Subtract the radii (distance between the skins) instead of the core shapes' distance.
    pub use_radii: bool,
}

/// Result of [`distance`], in world coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DistanceOutput {
    /// Closest point on A.
    pub point_a: Vec2,
    /// Closest point on B.
    pub point_b: Vec2,
    /// Distance between them; 0 when the shapes overlap.
    pub distance: f64,
    /// Number of support-point evaluations (GJK iterations).
    pub iterations: usize,
}

/// One simplex point: a support point of A, one of B, their difference and its barycentric weight.
#[derive(Clone, Copy, Debug, Default)]
struct SimplexVertex {
    wa: Vec2,
    wb: Vec2,
    /// `wb - wa`, a point of the Minkowski difference B − A.
    w: Vec2,
    /// Barycentric coordinate of the closest point.
    weight: f64,
    index_a: usize,
    index_b: usize,
}

impl SimplexVertex {
    fn at(input: &DistanceInput, index_a: usize, index_b: usize) -> SimplexVertex {
        let wa = input.transform_a.apply(input.proxy_a.vertex(index_a));
        let wb = input.transform_b.apply(input.proxy_b.vertex(index_b));
        SimplexVertex {
            wa,
            wb,
            w: v2::sub(wb, wa),
            weight: 0.0,
            index_a,
            index_b,
        }
    }
}

#[derive(Clone, Copy, Debug)]
struct Simplex {
    v: [SimplexVertex; 3],
    count: usize,
}

impl Simplex {
    /// The cached simplex at the new transforms, or the first vertices of both proxies when the
    /// cache is empty or its shape changed too much to be a useful start.
    fn from_cache(cache: &SimplexCache, input: &DistanceInput) -> Simplex {
        let mut simplex = Simplex {
            v: [SimplexVertex::default(); 3],
            count: cache.count.min(3),
        };
        let (na, nb) = (input.proxy_a.vertices.len(), input.proxy_b.vertices.len());
        for i in 0..simplex.count {
            if cache.index_a[i] >= na || cache.index_b[i] >= nb {
                // A cache from other proxies: ignore it rather than index out of bounds.
                simplex.count = 0;
                break;
            }
            simplex.v[i] = SimplexVertex::at(input, cache.index_a[i], cache.index_b[i]);
        }
        if simplex.count > 1 {
            let (old, new) = (cache.metric, simplex.metric());
            if new < 0.5 * old || 2.0 * old < new || new < EPSILON {
                simplex.count = 0;
            }
        }
        if simplex.count == 0 {
            simplex.v[0] = SimplexVertex::at(input, 0, 0);
            simplex.v[0].weight = 1.0;
            simplex.count = 1;
        }
        simplex
    }

    fn write_cache(&self, cache: &mut SimplexCache) {
        cache.metric = self.metric();
        cache.count = self.count;
        for i in 0..self.count {
            cache.index_a[i] = self.v[i].index_a;
            cache.index_b[i] = self.v[i].index_b;
        }
    }

    fn metric(&self) -> f64 {
        let [v1, v2, v3] = self.v;
        match self.count {
            2 => v2::length(v2::sub(v2.w, v1.w)),
            3 => v2::cross(v2::sub(v2.w, v1.w), v2::sub(v3.w, v1.w)),
            _ => 0.0,
        }
    }

    /// Direction from the simplex towards the origin: the point's negation, or the edge normal on
    /// the origin's side (not normalised).
    fn search_direction(&self) -> Vec2 {
        let (w1, w2) = (self.v[0].w, self.v[1].w);
        if self.count == 1 {
            return v2::neg(w1);
        }
        let e12 = v2::sub(w2, w1);
        if v2::cross(e12, v2::neg(w1)) > 0.0 {
            v2::left_perp(e12)
        } else {
            v2::right_perp(e12)
        }
    }

    /// Closest points on A and on B from the barycentric weights.
    fn witness_points(&self) -> (Vec2, Vec2) {
        if self.count == 1 {
            // A lone point's weight is 1 whatever is stored (a point read from the cache has none).
            return (self.v[0].wa, self.v[0].wb);
        }
        let mut pa = (0.0, 0.0);
        let mut pb = (0.0, 0.0);
        for v in &self.v[..self.count] {
            pa = v2::add(pa, v2::scale(v.weight, v.wa));
            pb = v2::add(pb, v2::scale(v.weight, v.wb));
        }
        if self.count == 3 {
            // The origin is inside the triangle: the shapes overlap, one common point.
            pb = pa;
        }
        (pa, pb)
    }

    /// Reduces a segment simplex to the feature closest to the origin.
    fn solve2(&mut self) {
        let (w1, w2) = (self.v[0].w, self.v[1].w);
        let e12 = v2::sub(w2, w1);
        // Unnormalised barycentric coordinates of the origin's projection on the segment.
        let u2 = -v2::dot(w1, e12);
        if u2 <= 0.0 {
            self.keep_one(0);
            return;
        }
        let u1 = v2::dot(w2, e12);
        if u1 <= 0.0 {
            self.keep_one(1);
            return;
        }
        let inv = 1.0 / (u1 + u2);
        self.v[0].weight = u1 * inv;
        self.v[1].weight = u2 * inv;
        self.count = 2;
    }

    /// Reduces a triangle simplex to the feature (vertex, edge or the whole triangle) whose
    /// Voronoi region holds the origin. Region tests and the resulting vertex order follow Box2D.
    fn solve3(&mut self) {
        let (w1, w2, w3) = (self.v[0].w, self.v[1].w, self.v[2].w);
        let e12 = v2::sub(w2, w1);
        let (u12_1, u12_2) = (v2::dot(w2, e12), -v2::dot(w1, e12));
        let e13 = v2::sub(w3, w1);
        let (u13_1, u13_2) = (v2::dot(w3, e13), -v2::dot(w1, e13));
        let e23 = v2::sub(w3, w2);
        let (u23_1, u23_2) = (v2::dot(w3, e23), -v2::dot(w2, e23));
        // Signed sub-triangle areas (times the whole area's sign): the triangle's barycentrics.
        let n123 = v2::cross(e12, e13);
        let u123_1 = n123 * v2::cross(w2, w3);
        let u123_2 = n123 * v2::cross(w3, w1);
        let u123_3 = n123 * v2::cross(w1, w2);

        if u12_2 <= 0.0 && u13_2 <= 0.0 {
            self.keep_one(0);
        } else if u12_1 > 0.0 && u12_2 > 0.0 && u123_3 <= 0.0 {
            self.keep_two(0, 1, u12_1, u12_2);
        } else if u13_1 > 0.0 && u13_2 > 0.0 && u123_2 <= 0.0 {
            self.keep_two(0, 2, u13_1, u13_2);
        } else if u12_1 <= 0.0 && u23_2 <= 0.0 {
            self.keep_one(1);
        } else if u13_1 <= 0.0 && u23_1 <= 0.0 {
            self.keep_one(2);
        } else if u23_1 > 0.0 && u23_2 > 0.0 && u123_1 <= 0.0 {
            // Box2D keeps this edge as (w3, w2).
            self.keep_two(2, 1, u23_2, u23_1);
        } else {
            let inv = 1.0 / (u123_1 + u123_2 + u123_3);
            self.v[0].weight = u123_1 * inv;
            self.v[1].weight = u123_2 * inv;
            self.v[2].weight = u123_3 * inv;
            self.count = 3;
        }
    }

    fn keep_one(&mut self, i: usize) {
        self.v[0] = self.v[i];
        self.v[0].weight = 1.0;
        self.count = 1;
    }

    /// Keeps vertices `i`, `j` (in that order) with unnormalised weights `ui`, `uj`.
    fn keep_two(&mut self, i: usize, j: usize, ui: f64, uj: f64) {
        let inv = 1.0 / (ui + uj);
        let (mut a, mut b) = (self.v[i], self.v[j]);
        a.weight = ui * inv;
        b.weight = uj * inv;
        self.v[0] = a;
        self.v[1] = b;
        self.count = 2;
    }
}

/// Closest points of two convex proxies (GJK), warm-started from and written back to `cache`.
///
/// With `use_radii` the distance is between the skins (core distance minus both radii, witness
/// points moved onto the skins; 0 with both points at the midpoint when the skins overlap);
/// without, between the core polygons. Does not allocate.
pub fn distance(input: &DistanceInput, cache: &mut SimplexCache) -> DistanceOutput {
    let mut simplex = Simplex::from_cache(cache, input);
    let mut iterations = 0;
    while iterations < MAX_GJK_ITERATIONS {
        // The simplex before this step, to detect a repeated support point (cycling).
        let saved = simplex;
        match simplex.count {
            2 => simplex.solve2(),
            3 => simplex.solve3(),
            _ => {}
        }
        if simplex.count == 3 {
            break; // the origin is enclosed: overlap
        }
        let d = simplex.search_direction();
        if v2::dot(d, d) < EPSILON * EPSILON {
            // The origin lies (numerically) on the simplex: touching or overlapping; the
            // witness points of the current simplex are the answer.
            break;
        }
        let index_a = input.proxy_a.support(input.transform_a.q.apply_inv(v2::neg(d)));
        let index_b = input.proxy_b.support(input.transform_b.q.apply_inv(d));
        iterations += 1;
        let repeated = saved.v[..saved.count]
            .iter()
            .any(|v| v.index_a == index_a && v.index_b == index_b);
        if repeated {
            break; // no progress possible: the current simplex is closest
        }
        simplex.v[simplex.count] = SimplexVertex::at(input, index_a, index_b);
        simplex.count += 1;
    }

    let (mut point_a, mut point_b) = simplex.witness_points();
    let mut dist = v2::length(v2::sub(point_b, point_a));
    simplex.write_cache(cache);

    if input.use_radii {
        let (ra, rb) = (input.proxy_a.radius, input.proxy_b.radius);
        if dist > ra + rb && dist > EPSILON {
            let (normal, _) = v2::normalize(v2::sub(point_b, point_a));
            dist -= ra + rb;
            point_a = v2::add(point_a, v2::scale(ra, normal));
            point_b = v2::sub(point_b, v2::scale(rb, normal));
        } else {
            let mid = v2::scale(0.5, v2::add(point_a, point_b));
            point_a = mid;
            point_b = mid;
            dist = 0.0;
        }
    }
    DistanceOutput {
        point_a,
        point_b,
        distance: dist,
        iterations,
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use proptest::prelude::*;

    const SQRT_HALF: f64 = std::f64::consts::FRAC_1_SQRT_2;

    fn query(a: &DistanceProxy, xa: Transform, b: &DistanceProxy, xb: Transform) -> DistanceOutput {
        let input = DistanceInput {
            proxy_a: a,
            proxy_b: b,
            transform_a: xa,
            transform_b: xb,
            use_radii: false,
        };
        distance(&input, &mut SimplexCache::default())
    }

    fn unit_box() -> DistanceProxy {
        DistanceProxy::boxed(0.5, 0.5, 0.01).unwrap()
    }

    fn point() -> DistanceProxy {
        DistanceProxy::new(vec![(0.0, 0.0)], 0.0).unwrap()
    }

    fn close(a: Vec2, b: Vec2) -> bool {
        v2::length(v2::sub(a, b)) < 1e-12
    }

    #[test]
    fn parallel_boxes_are_face_to_face() {
        let b = unit_box();
        let out = query(&b, Transform::IDENTITY, &b, Transform::new((2.0, 0.3), 0.0));
        assert!((out.distance - 1.0).abs() < 1e-12, "{out:?}");
        assert!((out.point_a.0 - 0.5).abs() < 1e-12 && (out.point_b.0 - 1.5).abs() < 1e-12);
        // The witness points are a closest pair: same height, inside the shared y range.
        assert!((out.point_a.1 - out.point_b.1).abs() < 1e-12);
        assert!((-0.2..=0.5).contains(&out.point_a.1), "{out:?}");
    }

    #[test]
    fn rotated_box_corner_against_face() {
        let b = unit_box();
        let out = query(
            &b,
            Transform::IDENTITY,
            &b,
            Transform::new((2.0, 0.0), std::f64::consts::FRAC_PI_4),
        );
        assert!((out.distance - (2.0 - SQRT_HALF - 0.5)).abs() < 1e-12, "{out:?}");
        assert!(close(out.point_b, (2.0 - SQRT_HALF, 0.0)), "{out:?}");
        assert!(close(out.point_a, (0.5, 0.0)), "{out:?}");
    }

    #[test]
    fn radii_are_subtracted_and_points_moved_onto_the_skins() {
        let b = unit_box();
        let input = DistanceInput {
            proxy_a: &b,
            proxy_b: &b,
            transform_a: Transform::IDENTITY,
            transform_b: Transform::new((2.0, 0.0), 0.0),
            use_radii: true,
        };
        let out = distance(&input, &mut SimplexCache::default());
        assert!((out.distance - 0.98).abs() < 1e-12, "{out:?}");
        assert!((out.point_a.0 - 0.51).abs() < 1e-12 && (out.point_b.0 - 1.49).abs() < 1e-12);
        // Skins overlapping: distance 0, both points at the midpoint.
        let touching = DistanceInput {
            transform_b: Transform::new((1.015, 0.0), 0.0),
            ..input
        };
        let out = distance(&touching, &mut SimplexCache::default());
        assert_eq!(out.distance, 0.0);
        assert!(close(out.point_a, out.point_b) && (out.point_a.0 - 0.5075).abs() < 1e-12);
    }

    #[test]
    fn tilted_box_above_an_edge() {
        let ground = DistanceProxy::edge((-5.0, 0.0), (5.0, 0.0), 0.01).unwrap();
        let angle: f64 = 0.3;
        let out = query(
            &ground,
            Transform::IDENTITY,
            &unit_box(),
            Transform::new((1.0, 2.0), angle),
        );
        let expected = 2.0 - 0.5 * (angle.sin() + angle.cos());
        assert!((out.distance - expected).abs() < 1e-12, "{out:?}");
        assert!(
            out.point_a.1.abs() < 1e-12,
            "closest point of the edge lies on it: {out:?}"
        );
    }

    #[test]
    fn point_against_edge_interior_vertex_and_on_it() {
        let edge = DistanceProxy::edge((0.0, 0.0), (3.0, 0.0), 0.0).unwrap();
        let p = point();
        let cases = [
            ((1.0, 2.0), 2.0, (1.0, 0.0)),
            ((-3.0, 4.0), 5.0, (0.0, 0.0)),
            ((1.5, 0.0), 0.0, (1.5, 0.0)),
        ];
        for (at, expected, closest) in cases {
            let out = query(&p, Transform::new(at, 0.7), &edge, Transform::IDENTITY);
            assert!((out.distance - expected).abs() < 1e-12, "{at:?}: {out:?}");
            assert!(close(out.point_b, closest), "{at:?}: {out:?}");
        }
    }

    #[test]
    fn overlapping_shapes_have_distance_zero() {
        let big = DistanceProxy::boxed(2.0, 2.0, 0.0).unwrap();
        let edge = DistanceProxy::edge((-5.0, 0.0), (5.0, 0.0), 0.0).unwrap();
        let out = query(&big, Transform::new((0.1, 0.2), 0.3), &unit_box(), Transform::IDENTITY);
        assert!(out.distance < 1e-12, "box inside box: {out:?}");
        let out = query(&edge, Transform::IDENTITY, &unit_box(), Transform::new((0.0, 0.1), 0.5));
        assert!(out.distance < 1e-12, "edge through box: {out:?}");
    }

    #[test]
    fn a_cache_from_other_proxies_is_ignored() {
        let octagon = regular(8, 1.0);
        let mut cache = SimplexCache::default();
        let input = DistanceInput {
            proxy_a: &octagon,
            proxy_b: &octagon,
            transform_a: Transform::IDENTITY,
            transform_b: Transform::new((3.0, 0.5), 0.2),
            use_radii: false,
        };
        let expected = distance(&input, &mut cache);
        cache.index_a = [7, 7, 7];
        cache.index_b = [6, 5, 4];
        let p = point();
        let out = distance(
            &DistanceInput {
                proxy_a: &p,
                proxy_b: &p,
                ..input
            },
            &mut cache,
        );
        assert!((out.distance - v2::length((3.0, 0.5))).abs() < 1e-12, "{out:?}");
        assert!(expected.distance > 0.0);
    }

    #[test]
    fn invalid_vertex_lists_are_rejected() {
        assert_eq!(DistanceProxy::new(vec![], 0.0), Err(ProxyError::VertexCount(0)));
        assert_eq!(
            DistanceProxy::new(vec![(0.0, 0.0); 9], 0.0),
            Err(ProxyError::VertexCount(9))
        );
        assert_eq!(
            DistanceProxy::new(vec![(f64::NAN, 0.0)], 0.0),
            Err(ProxyError::NonFinite(0))
        );
        assert_eq!(
            DistanceProxy::new(vec![(0.0, 0.0)], -1.0),
            Err(ProxyError::Radius(-1.0))
        );
        assert_eq!(
            DistanceProxy::edge((1.0, 1.0), (1.0, 1.0), 0.0),
            Err(ProxyError::ShortEdge(0))
        );
        let clockwise = vec![(0.0, 0.0), (0.0, 1.0), (1.0, 0.0)];
        assert!(matches!(
            DistanceProxy::new(clockwise, 0.0),
            Err(ProxyError::NotConvexCcw { .. })
        ));
        let collinear = vec![(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (1.0, 1.0)];
        assert!(matches!(
            DistanceProxy::new(collinear, 0.0),
            Err(ProxyError::NotConvexCcw { .. })
        ));
        let bow_tie = vec![(0.0, 0.0), (1.0, 1.0), (1.0, 0.0), (0.0, 1.0)];
        assert!(DistanceProxy::new(bow_tie, 0.0).is_err());
        let message = DistanceProxy::new(vec![], 0.0).unwrap_err().to_string();
        assert!(message.contains("1 to 8 vertices"), "{message}");
    }

    /// A regular `n`-gon of circumradius `r` (n = 1: a point, n = 2: an edge).
    fn regular(n: usize, r: f64) -> DistanceProxy {
        let vertices = (0..n)
            .map(|k| {
                let a = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
                (r * a.cos(), r * a.sin())
            })
            .collect();
        DistanceProxy::new(vertices, 0.01).unwrap()
    }

    fn point_segment(p: Vec2, a: Vec2, b: Vec2) -> f64 {
        let ab = v2::sub(b, a);
        let len2 = v2::dot(ab, ab);
        let t = if len2 == 0.0 {
            0.0
        } else {
            (v2::dot(v2::sub(p, a), ab) / len2).clamp(0.0, 1.0)
        };
        v2::length(v2::sub(p, v2::add(a, v2::scale(t, ab))))
    }

    fn segments_cross(a: Vec2, b: Vec2, c: Vec2, d: Vec2) -> bool {
        let side = |p: Vec2, q: Vec2, r: Vec2| v2::cross(v2::sub(q, p), v2::sub(r, p));
        let (d1, d2) = (side(c, d, a), side(c, d, b));
        let (d3, d4) = (side(a, b, c), side(a, b, d));
        d1 * d2 < 0.0 && d3 * d4 < 0.0
    }

    /// World vertices and the features (segments; a lone vertex is a zero-length one).
    fn world(p: &DistanceProxy, xf: Transform) -> Vec<(Vec2, Vec2)> {
        let w: Vec<Vec2> = p.vertices.iter().map(|&v| xf.apply(v)).collect();
        match w.len() {
            1 => vec![(w[0], w[0])],
            2 => vec![(w[0], w[1])],
            n => (0..n).map(|i| (w[i], w[(i + 1) % n])).collect(),
        }
    }

    fn inside(p: Vec2, polygon: &[(Vec2, Vec2)]) -> bool {
        polygon.len() >= 3
            && polygon
                .iter()
                .all(|&(a, b)| v2::cross(v2::sub(b, a), v2::sub(p, a)) > 0.0)
    }

    /// Core distance by brute force: 0 when one contains a vertex of the other or edges cross,
    /// else the smallest vertex–segment distance.
    fn brute_force(a: &DistanceProxy, xa: Transform, b: &DistanceProxy, xb: Transform) -> f64 {
        let (fa, fb) = (world(a, xa), world(b, xb));
        if fa.iter().any(|&(p, _)| inside(p, &fb)) || fb.iter().any(|&(p, _)| inside(p, &fa)) {
            return 0.0;
        }
        let mut best = f64::INFINITY;
        for &(p, q) in &fa {
            for &(r, s) in &fb {
                if segments_cross(p, q, r, s) {
                    return 0.0;
                }
                best = best
                    .min(point_segment(p, r, s))
                    .min(point_segment(q, r, s))
                    .min(point_segment(r, p, q))
                    .min(point_segment(s, p, q));
            }
        }
        best
    }

    /// A convex CCW polygon with 1..=8 vertices on a circle at random increasing angles.
    pub(crate) fn arb_proxy() -> impl Strategy<Value = DistanceProxy> {
        (
            1usize..=8,
            0.2f64..2.0,
            proptest::collection::vec(0.2f64..1.0, 8),
            0.0f64..6.3,
        )
            .prop_map(|(n, r, gaps, start)| {
                let total: f64 = gaps[..n].iter().sum();
                let mut angle = start;
                let mut vertices = Vec::with_capacity(n);
                for gap in &gaps[..n] {
                    vertices.push((r * angle.cos(), r * angle.sin()));
                    angle += 2.0 * std::f64::consts::PI * gap / total;
                }
                DistanceProxy::new(vertices, 0.01).unwrap()
            })
    }

    fn arb_transform() -> impl Strategy<Value = Transform> {
        (-4.0f64..4.0, -4.0f64..4.0, -3.2f64..3.2).prop_map(|(x, y, a)| Transform::new((x, y), a))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]

        #[test]
        fn matches_brute_force_and_is_symmetric(
            a in arb_proxy(), xa in arb_transform(), b in arb_proxy(), xb in arb_transform()
        ) {
            let ab = query(&a, xa, &b, xb);
            let ba = query(&b, xb, &a, xa);
            let exact = brute_force(&a, xa, &b, xb);
            prop_assert!((ab.distance - exact).abs() < 1e-9, "A-B {ab:?} vs {exact}");
            prop_assert!((ba.distance - exact).abs() < 1e-9, "B-A {ba:?} vs {exact}");
            prop_assert!(ab.iterations <= MAX_GJK_ITERATIONS);
            // The witness points are a pair realising the distance.
            prop_assert!((v2::length(v2::sub(ab.point_b, ab.point_a)) - ab.distance).abs() < 1e-12);
        }

        #[test]
        fn warm_start_gives_the_cold_result(
            a in arb_proxy(), xa in arb_transform(), b in arb_proxy(), xb in arb_transform(),
            dx in -0.3f64..0.3, dy in -0.3f64..0.3, da in -0.3f64..0.3,
        ) {
            let mut cache = SimplexCache::default();
            let first = DistanceInput { proxy_a: &a, proxy_b: &b, transform_a: xa, transform_b: xb, use_radii: true };
            distance(&first, &mut cache);
            let moved = Transform::new(v2::add(xb.p, (dx, dy)), xb.q.angle() + da);
            let second = DistanceInput { transform_b: moved, ..first };
            let warm = distance(&second, &mut cache);
            let cold = distance(&second, &mut SimplexCache::default());
            prop_assert!((warm.distance - cold.distance).abs() < 1e-9, "warm {warm:?} cold {cold:?}");
            // Same place again from the fresh cache: nothing left to search.
            let again = distance(&second, &mut cache);
            prop_assert!((again.distance - cold.distance).abs() < 1e-9);
            prop_assert!(again.iterations <= cold.iterations.max(1));
        }
    }
}
