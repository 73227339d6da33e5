//! Narrow-phase collision as MuJoCo's: a contact has a position midway between the two
//! surfaces, a frame whose first row is the normal (from the first geom to the second) and a
//! signed distance (negative when penetrating); it is kept while the distance is below the
//! pair's margin. Pairs: plane–sphere, plane–capsule (one contact per end, tangent along the
//! capsule), plane–box (the deepest corners, at most four), sphere–sphere, sphere–capsule and
//! capsule–capsule (two contacts for parallel overlapping capsules), sphere–cylinder and
//! capsule–cylinder (one contact at the closest points, as MuJoCo's convex collider gives; the
//! plane–cylinder pair has no routine), plane–ellipsoid (one contact at the ellipsoid's support
//! point, as MuJoCo's plane–convex collider; the ellipsoid's other pairs have no routine).

use crate::math::{M3, V3, add, col, cross, dot, mat_vec, norm, normalize, scale, sub};
use crate::model::Shape;

/// One contact point.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Contact {
    pub pos: V3,
    /// Normal, first tangent, second tangent.
    pub frame: [V3; 3],
    pub dist: f64,
    /// Index into [`crate::Model::pairs`].
    pub pair: usize,
    /// Which contact of its pair (for warm starts).
    pub sub: usize,
}

/// MuJoCo's default tangent frame of normal `n`: `t₁ = n × x̂` (or `n × ŷ` when `n` is close to
/// x̂) normalized, `t₂ = n × t₁`.
pub fn make_frame(n: V3) -> [V3; 3] {
    let t = if n[0].abs() < 0.5 {
        cross(n, [1.0, 0.0, 0.0])
    } else {
        cross(n, [0.0, 1.0, 0.0])
    };
    let t1 = normalize(t).unwrap_or([0.0, 1.0, 0.0]);
    [n, t1, cross(n, t1)]
}

/// A frame with normal `n` and first tangent along `dir` projected off the normal (default
/// frame if `dir` is parallel to `n`).
fn frame_along(n: V3, dir: V3) -> [V3; 3] {
    match normalize(sub(dir, scale(n, dot(dir, n)))) {
        Some(t1) => [n, t1, cross(n, t1)],
        None => make_frame(n),
    }
}

/// A geom placed in the world.
#[derive(Debug, Clone, Copy)]
pub struct Placed {
    pub shape: Shape,
    pub pos: V3,
    pub mat: M3,
}

impl Placed {
    /// End points of a capsule's segment (a sphere's centre twice).
    fn segment(&self) -> (V3, V3, f64) {
        match self.shape {
            Shape::Capsule { radius, half_length } => {
                let a = scale(col(&self.mat, 2), half_length);
                (sub(self.pos, a), add(self.pos, a), radius)
            }
            Shape::Sphere { radius } => (self.pos, self.pos, radius),
            _ => (self.pos, self.pos, 0.0),
        }
    }
}

/// Contacts between `a` and `b` (in MuJoCo's type order) closer than `margin`, written to
/// `out`; returns how many.
pub fn collide(a: &Placed, b: &Placed, margin: f64, out: &mut [Contact]) -> usize {
    match (a.shape, b.shape) {
        (Shape::Plane, Shape::Sphere { radius }) => {
            let n = col(&a.mat, 2);
            let d = dot(sub(b.pos, a.pos), n) - radius;
            push_plane_point(n, b.pos, radius, d, margin, || make_frame(n), out, 0)
        }
        (Shape::Plane, Shape::Capsule { radius, .. }) => {
            let n = col(&a.mat, 2);
            let (p0, p1, _) = b.segment();
            let frame = || frame_along(n, col(&b.mat, 2));
            let mut k = 0;
            for p in [p0, p1] {
                let d = dot(sub(p, a.pos), n) - radius;
                k += push_plane_point(n, p, radius, d, margin, frame, out, k);
            }
            k
        }
        (Shape::Plane, Shape::Box { half }) => {
            let n = col(&a.mat, 2);
            // Corners below the margin, deepest first, at most four (as many as `out` holds).
            let mut corners = [(0.0f64, [0.0; 3]); 8];
            let mut m = 0;
            for i in 0..8 {
                let s = [
                    if i & 1 == 0 { -1.0 } else { 1.0 },
                    if i & 2 == 0 { -1.0 } else { 1.0 },
                    if i & 4 == 0 { -1.0 } else { 1.0 },
                ];
                let local = [s[0] * half[0], s[1] * half[1], s[2] * half[2]];
                let p = add(b.pos, mat_vec(&b.mat, local));
                let d = dot(sub(p, a.pos), n);
                if d < margin {
                    corners[m] = (d, p);
                    m += 1;
                }
            }
            corners[..m].sort_by(|x, y| x.0.total_cmp(&y.0));
            let frame = || make_frame(n);
            let mut k = 0;
            for &(d, p) in corners[..m].iter().take(4) {
                k += push_plane_point(n, p, 0.0, d, margin, frame, out, k);
            }
            k
        }
        (Shape::Plane, Shape::Ellipsoid { radii }) => {
            // The ellipsoid's support point against the normal: `p = −R (r² ∘ n') / |r ∘ n'|`,
            // `n'` the normal in the ellipsoid's frame; one contact there (MuJoCo's
            // plane–convex collider).
            let n = col(&a.mat, 2);
            let nl = [dot(col(&b.mat, 0), n), dot(col(&b.mat, 1), n), dot(col(&b.mat, 2), n)];
            let rn = [radii[0] * nl[0], radii[1] * nl[1], radii[2] * nl[2]];
            let len = norm(rn);
            if len < 1e-15 {
                return 0;
            }
            let local = [
                -radii[0] * rn[0] / len,
                -radii[1] * rn[1] / len,
                -radii[2] * rn[2] / len,
            ];
            let p = add(b.pos, mat_vec(&b.mat, local));
            let d = dot(sub(p, a.pos), n);
            push_plane_point(n, p, 0.0, d, margin, || make_frame(n), out, 0)
        }
        (Shape::Sphere { .. } | Shape::Capsule { .. }, Shape::Sphere { .. } | Shape::Capsule { .. }) => {
            let (a0, a1, ra) = a.segment();
            let (b0, b1, rb) = b.segment();
            segments(a0, a1, ra, b0, b1, rb, margin, out)
        }
        (Shape::Sphere { .. } | Shape::Capsule { .. }, Shape::Cylinder { radius, half_length }) => {
            let (a0, a1, ra) = a.segment();
            segment_cylinder(a0, a1, ra, b, radius, half_length, margin, out)
        }
        _ => 0,
    }
}

/// A contact of a sphere of `radius` centred at `c` at distance `d` above a plane of normal `n`
/// (its frame computed only when there is a contact).
#[allow(clippy::too_many_arguments)]
fn push_plane_point(
    n: V3,
    c: V3,
    radius: f64,
    d: f64,
    margin: f64,
    frame: impl Fn() -> [V3; 3],
    out: &mut [Contact],
    k: usize,
) -> usize {
    if d >= margin || k >= out.len() {
        return 0;
    }
    out[k] = Contact {
        pos: sub(c, scale(n, radius + 0.5 * d)),
        frame: frame(),
        dist: d,
        pair: 0,
        sub: k,
    };
    1
}

/// The contact of spheres of radius `ra` at `pa` and `rb` at `pb` (normal from a to b).
fn spheres(pa: V3, ra: f64, pb: V3, rb: f64, margin: f64, out: &mut [Contact], k: usize) -> usize {
    let dv = sub(pb, pa);
    let len = norm(dv);
    let d = len - ra - rb;
    if d >= margin || k >= out.len() {
        return 0;
    }
    let n = if len > 1e-12 {
        scale(dv, 1.0 / len)
    } else {
        [1.0, 0.0, 0.0]
    };
    out[k] = Contact {
        pos: add(pa, scale(n, ra + 0.5 * d)),
        frame: make_frame(n),
        dist: d,
        pair: 0,
        sub: k,
    };
    1
}

/// The point of segment `p0`–`p1` closest to `x`, as a parameter in [0, 1].
fn closest_on_segment(p0: V3, p1: V3, x: V3) -> f64 {
    let d = sub(p1, p0);
    let l2 = dot(d, d);
    if l2 < 1e-24 {
        0.0
    } else {
        (dot(sub(x, p0), d) / l2).clamp(0.0, 1.0)
    }
}

fn lerp(a: V3, b: V3, t: f64) -> V3 {
    add(a, scale(sub(b, a), t))
}

/// Contacts of two swept spheres (capsules; a sphere is a zero-length segment).
#[allow(clippy::too_many_arguments)]
fn segments(a0: V3, a1: V3, ra: f64, b0: V3, b1: V3, rb: f64, margin: f64, out: &mut [Contact]) -> usize {
    let da = sub(a1, a0);
    let db = sub(b1, b0);
    let (la, lb) = (dot(da, da), dot(db, db));
    if la > 1e-24 && lb > 1e-24 {
        let c = cross(da, db);
        if dot(c, c) < 1e-12 * la * lb {
            // Parallel: contacts at the two ends of the overlap (one if it is a point).
            let param = |x: V3| dot(sub(x, a0), da) / la;
            let (u0, u1) = (param(b0), param(b1));
            let (lo, hi) = (u0.min(u1).max(0.0), u0.max(u1).min(1.0));
            if lo <= hi {
                let mut k = 0;
                let ends = if (hi - lo) * la.sqrt() < 1e-9 { 1 } else { 2 };
                for &t in [lo, hi].iter().take(ends) {
                    let pa = lerp(a0, a1, t);
                    let pb = lerp(b0, b1, closest_on_segment(b0, b1, pa));
                    k += spheres(pa, ra, pb, rb, margin, out, k);
                }
                return k;
            }
        }
    }
    let (pa, pb) = closest_points(a0, a1, b0, b1);
    spheres(pa, ra, pb, rb, margin, out, 0)
}

/// Closest points of segments `a0`–`a1` and `b0`–`b1` (Ericson's clamped solution).
fn closest_points(a0: V3, a1: V3, b0: V3, b1: V3) -> (V3, V3) {
    let d1 = sub(a1, a0);
    let d2 = sub(b1, b0);
    let r = sub(a0, b0);
    let (a, e, f) = (dot(d1, d1), dot(d2, d2), dot(d2, r));
    let (s, t);
    if a < 1e-24 && e < 1e-24 {
        return (a0, b0);
    }
    if a < 1e-24 {
        s = 0.0;
        t = (f / e).clamp(0.0, 1.0);
    } else {
        let c = dot(d1, r);
        if e < 1e-24 {
            t = 0.0;
            s = (-c / a).clamp(0.0, 1.0);
        } else {
            let b = dot(d1, d2);
            let denom = a * e - b * b;
            let s0 = if denom > 1e-24 {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let t0 = (b * s0 + f) / e;
            if t0 < 0.0 {
                t = 0.0;
                s = (-c / a).clamp(0.0, 1.0);
            } else if t0 > 1.0 {
                t = 1.0;
                s = ((b - c) / a).clamp(0.0, 1.0);
            } else {
                t = t0;
                s = s0;
            }
        }
    }
    (lerp(a0, a1, s), lerp(b0, b1, t))
}

/// Signed distance from local point `q` to the cylinder of radius `r` and half-height `h` along
/// z (negative inside), and the outward unit normal of its nearest surface point.
fn cylinder_distance(q: V3, r: f64, h: f64) -> (f64, V3) {
    let rho = q[0].hypot(q[1]);
    let radial = if rho > 0.0 {
        [q[0] / rho, q[1] / rho, 0.0]
    } else {
        [1.0, 0.0, 0.0]
    };
    let axial = [0.0, 0.0, if q[2] < 0.0 { -1.0 } else { 1.0 }];
    let (dr, dz) = (rho - r, q[2].abs() - h);
    if dr > 0.0 && dz > 0.0 {
        let d = dr.hypot(dz);
        (d, add(scale(radial, dr / d), scale(axial, dz / d)))
    } else if dr > dz {
        (dr, radial)
    } else {
        (dz, axial)
    }
}

/// A sphere or capsule (segment `p0`–`p1` inflated by `rc`) against the cylinder `cyl`: one
/// contact at the segment point nearest the cylinder (the signed distance is convex along the
/// segment; golden-section search), normal from the capsule to the cylinder, the position
/// midway between the two surfaces.
#[allow(clippy::too_many_arguments)]
fn segment_cylinder(p0: V3, p1: V3, rc: f64, cyl: &Placed, r: f64, h: f64, margin: f64, out: &mut [Contact]) -> usize {
    let local = |p: V3| {
        let d = sub(p, cyl.pos);
        [
            dot(col(&cyl.mat, 0), d),
            dot(col(&cyl.mat, 1), d),
            dot(col(&cyl.mat, 2), d),
        ]
    };
    let (q0, q1) = (local(p0), local(p1));
    let at = |t: f64| lerp(q0, q1, t);
    let f = |t: f64| cylinder_distance(at(t), r, h).0;
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    if q0 != q1 {
        const G: f64 = 0.618_033_988_749_894_8;
        let (mut x1, mut x2) = (hi - G * (hi - lo), lo + G * (hi - lo));
        let (mut f1, mut f2) = (f(x1), f(x2));
        for _ in 0..80 {
            if f1 <= f2 {
                hi = x2;
                x2 = x1;
                f2 = f1;
                x1 = hi - G * (hi - lo);
                f1 = f(x1);
            } else {
                lo = x1;
                x1 = x2;
                f1 = f2;
                x2 = lo + G * (hi - lo);
                f2 = f(x2);
            }
        }
    }
    let mut t = 0.5 * (lo + hi);
    for end in [0.0, 1.0] {
        if f(end) < f(t) {
            t = end;
        }
    }
    let q = at(t);
    let (sd, n_out) = cylinder_distance(q, r, h);
    let dist = sd - rc;
    if dist >= margin || out.is_empty() {
        return 0;
    }
    let mid = sub(q, scale(n_out, 0.5 * (rc + sd)));
    let n = scale(mat_vec(&cyl.mat, n_out), -1.0);
    out[0] = Contact {
        pos: add(cyl.pos, mat_vec(&cyl.mat, mid)),
        frame: make_frame(n),
        dist,
        pair: 0,
        sub: 0,
    };
    1
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::IDENTITY;

    fn placed(shape: Shape, pos: V3) -> Placed {
        Placed {
            shape,
            pos,
            mat: IDENTITY,
        }
    }

    #[test]
    fn sphere_on_plane_contact_is_midway() {
        let mut out = [Contact::default(); 4];
        let n = collide(
            &placed(Shape::Plane, [0.0; 3]),
            &placed(Shape::Sphere { radius: 0.1 }, [0.0, 0.0, 0.09]),
            0.0,
            &mut out,
        );
        assert_eq!(n, 1);
        assert!((out[0].dist + 0.01).abs() < 1e-12);
        assert!((out[0].pos[2] + 0.005).abs() < 1e-12);
    }

    #[test]
    fn crossing_and_parallel_capsules() {
        let mut out = [Contact::default(); 4];
        let cap = Shape::Capsule {
            radius: 0.1,
            half_length: 0.1,
        };
        // Parallel capsules side by side along z: two contacts.
        let a = placed(cap, [0.0; 3]);
        let b = placed(cap, [0.15, 0.0, 0.0]);
        let n = collide(&a, &b, 0.0, &mut out);
        assert_eq!(n, 2);
        assert!(
            out[..2]
                .iter()
                .all(|c| (c.dist + 0.05).abs() < 1e-12 && (c.frame[0][0] - 1.0).abs() < 1e-12)
        );
        // Crossed capsules: one contact on the common perpendicular.
        let mut b = placed(cap, [0.15, 0.0, 0.0]);
        b.mat = [[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]];
        let n = collide(&a, &b, 0.0, &mut out);
        assert_eq!(n, 1);
        assert!((out[0].dist + 0.05).abs() < 1e-12);
    }
}
