//! Contact manifolds (Box2D's `b2CollidePolygons` and `b2CollideEdgeAndPolygon`): up to two
//! points, each tagged with the features (vertex or face of each shape) that produced it, so
//! that the solver can carry a point's impulses over to the next step (warm starting).

use super::math::{V2, Xf, v2};
use super::settings::{ANGULAR_SLOP, LINEAR_SLOP};
use super::shapes::{MAX_VERTICES, Polygon};

/// The manifold's reference face belongs to shape A or B.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ManifoldKind {
    #[default]
    FaceA,
    FaceB,
}

const VERTEX: u8 = 0;
const FACE: u8 = 1;

/// Which features of A and B met (Box2D's `b2ContactFeature`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Feature {
    pub index_a: u8,
    pub index_b: u8,
    pub type_a: u8,
    pub type_b: u8,
}

impl Feature {
    fn swapped(self) -> Feature {
        Feature {
            index_a: self.index_b,
            index_b: self.index_a,
            type_a: self.type_b,
            type_b: self.type_a,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ManifoldPoint {
    /// For `FaceA`, the clip point on B in B's frame; for `FaceB`, on A in A's frame.
    pub local_point: V2,
    pub normal_impulse: f64,
    pub tangent_impulse: f64,
    pub id: Feature,
}

#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Manifold {
    pub kind: ManifoldKind,
    /// Reference face normal and a point on it, in the reference shape's frame.
    pub local_normal: V2,
    pub local_point: V2,
    pub points: [ManifoldPoint; 2],
    pub count: usize,
}

#[derive(Debug, Clone, Copy)]
struct ClipVertex {
    v: V2,
    id: Feature,
}

/// Keep the part of segment `vin` with `dot(normal, v) <= offset`; a cut point takes vertex
/// `index_a` of the reference shape as its feature.
fn clip_segment(vin: &[ClipVertex; 2], normal: V2, offset: f64, index_a: usize) -> ([ClipVertex; 2], usize) {
    let mut out = *vin;
    let mut n = 0;
    let d0 = normal.dot(vin[0].v) - offset;
    let d1 = normal.dot(vin[1].v) - offset;
    if d0 <= 0.0 {
        out[n] = vin[0];
        n += 1;
    }
    if d1 <= 0.0 {
        out[n] = vin[1];
        n += 1;
    }
    if d0 * d1 < 0.0 {
        let t = d0 / (d0 - d1);
        out[n] = ClipVertex {
            v: vin[0].v + t * (vin[1].v - vin[0].v),
            id: Feature {
                index_a: index_a as u8,
                index_b: vin[0].id.index_b,
                type_a: VERTEX,
                type_b: FACE,
            },
        };
        n += 1;
    }
    (out, n)
}

/// Largest separation of `p2` from the edges of `p1` and the edge that gives it.
fn max_separation(p1: &Polygon, xf1: &Xf, p2: &Polygon, xf2: &Xf) -> (usize, f64) {
    let mut best = (0, f64::MIN);
    for i in 0..p1.count {
        // Edge i of p1 in p2's frame.
        let n = xf2.q.apply_inv(xf1.q.apply(p1.normals[i]));
        let v1 = xf2.apply_inv(xf1.apply(p1.vertices[i]));
        let si = p2.vertices().iter().map(|v| n.dot(*v - v1)).fold(f64::MAX, f64::min);
        if si > best.1 {
            best = (i, si);
        }
    }
    best
}

/// Box2D's `b2CollidePolygons`.
pub fn collide_polygons(m: &mut Manifold, pa: &Polygon, xfa: &Xf, pb: &Polygon, xfb: &Xf, total_radius: f64) {
    m.count = 0;
    let (edge_a, sep_a) = max_separation(pa, xfa, pb, xfb);
    if sep_a > total_radius {
        return;
    }
    let (edge_b, sep_b) = max_separation(pb, xfb, pa, xfa);
    if sep_b > total_radius {
        return;
    }
    let (p1, xf1, p2, xf2, edge1, flip) = if sep_b > sep_a + 0.1 * LINEAR_SLOP {
        m.kind = ManifoldKind::FaceB;
        (pb, xfb, pa, xfa, edge_b, true)
    } else {
        m.kind = ManifoldKind::FaceA;
        (pa, xfa, pb, xfb, edge_a, false)
    };
    // Incident edge: the edge of p2 most anti-parallel to the reference normal.
    let n1 = xf2.q.apply_inv(xf1.q.apply(p1.normals[edge1]));
    let mut i1 = 0;
    let mut min_dot = f64::MAX;
    for i in 0..p2.count {
        let d = n1.dot(p2.normals[i]);
        if d < min_dot {
            min_dot = d;
            i1 = i;
        }
    }
    let i2 = if i1 + 1 < p2.count { i1 + 1 } else { 0 };
    let incident = [
        ClipVertex {
            v: xf2.apply(p2.vertices[i1]),
            id: Feature {
                index_a: edge1 as u8,
                index_b: i1 as u8,
                type_a: FACE,
                type_b: VERTEX,
            },
        },
        ClipVertex {
            v: xf2.apply(p2.vertices[i2]),
            id: Feature {
                index_a: edge1 as u8,
                index_b: i2 as u8,
                type_a: FACE,
                type_b: VERTEX,
            },
        },
    ];
    let iv1 = edge1;
    let iv2 = if edge1 + 1 < p1.count { edge1 + 1 } else { 0 };
    let (v11, v12) = (p1.vertices[iv1], p1.vertices[iv2]);
    let local_tangent = (v12 - v11).normalized();
    let local_normal = local_tangent.cross_s(1.0);
    let plane_point = 0.5 * (v11 + v12);
    let tangent = xf1.q.apply(local_tangent);
    let normal = tangent.cross_s(1.0);
    let (v11, v12) = (xf1.apply(v11), xf1.apply(v12));
    let front_offset = normal.dot(v11);
    let side1 = -tangent.dot(v11) + total_radius;
    let side2 = tangent.dot(v12) + total_radius;
    let (c1, n) = clip_segment(&incident, -tangent, side1, iv1);
    if n < 2 {
        return;
    }
    let (c2, n) = clip_segment(&c1, tangent, side2, iv2);
    if n < 2 {
        return;
    }
    m.local_normal = local_normal;
    m.local_point = plane_point;
    for cv in &c2 {
        if normal.dot(cv.v) - front_offset <= total_radius {
            let mp = &mut m.points[m.count];
            mp.local_point = xf2.apply_inv(cv.v);
            mp.id = if flip { cv.id.swapped() } else { cv.id };
            m.count += 1;
        }
    }
}

/// Box2D's `b2CollideEdgeAndPolygon` for a lone edge (no neighbour vertices, two-sided): the
/// edge is shape A, the polygon B.
pub fn collide_edge_polygon(m: &mut Manifold, e1: V2, e2: V2, xfa: &Xf, poly: &Polygon, xfb: &Xf, total_radius: f64) {
    m.count = 0;
    // Work in A's frame.
    let xf = Xf {
        q: rot_mul_t(xfa, xfb),
        p: xfa.q.apply_inv(xfb.p - xfa.p),
    };
    let centroid_b = xf.apply(poly.centroid);
    let nb = poly.count;
    let mut verts = [V2::ZERO; MAX_VERTICES];
    let mut norms = [V2::ZERO; MAX_VERTICES];
    for i in 0..nb {
        verts[i] = xf.apply(poly.vertices[i]);
        norms[i] = xf.q.apply(poly.normals[i]);
    }
    let edge = (e2 - e1).normalized();
    let normal1 = v2(edge.y, -edge.x);
    let front = normal1.dot(centroid_b - e1) >= 0.0;
    let (normal, limit) = if front {
        (normal1, -normal1)
    } else {
        (-normal1, normal1)
    };

    // Edge axis.
    let edge_sep = verts[..nb].iter().map(|v| normal.dot(*v - e1)).fold(f64::MAX, f64::min);
    if edge_sep > total_radius {
        return;
    }
    // Polygon axes.
    let mut poly_axis: Option<(usize, f64)> = None;
    for i in 0..nb {
        let n = -norms[i];
        let s = n.dot(verts[i] - e1).min(n.dot(verts[i] - e2));
        if s > total_radius {
            // No collision.
            return;
        }
        // Adjacency: only normals within the admissible cone.
        // Box2D tests the normal against the upper or lower adjacency limit depending on its
        // side of `perp`; a lone edge has one limit for both.
        let admissible = (n - limit).dot(normal) >= -ANGULAR_SLOP;
        if !admissible {
            continue;
        }
        if poly_axis.is_none_or(|(_, best)| s > best) {
            poly_axis = Some((i, s));
        }
    }
    let use_edge = match poly_axis {
        None => true,
        Some((_, s)) => s <= 0.98 * edge_sep + 0.001,
    };
    let (ie, rf_i1, rf_i2, rf_v1, rf_v2, rf_normal);
    if use_edge {
        m.kind = ManifoldKind::FaceA;
        let mut best = 0;
        let mut best_value = normal.dot(norms[0]);
        for (i, n) in norms.iter().enumerate().take(nb).skip(1) {
            let value = normal.dot(*n);
            if value < best_value {
                best_value = value;
                best = i;
            }
        }
        let i1 = best;
        let i2 = if i1 + 1 < nb { i1 + 1 } else { 0 };
        ie = [
            ClipVertex {
                v: verts[i1],
                id: Feature {
                    index_a: 0,
                    index_b: i1 as u8,
                    type_a: FACE,
                    type_b: VERTEX,
                },
            },
            ClipVertex {
                v: verts[i2],
                id: Feature {
                    index_a: 0,
                    index_b: i2 as u8,
                    type_a: FACE,
                    type_b: VERTEX,
                },
            },
        ];
        if front {
            (rf_i1, rf_i2, rf_v1, rf_v2, rf_normal) = (0, 1, e1, e2, normal1);
        } else {
            (rf_i1, rf_i2, rf_v1, rf_v2, rf_normal) = (1, 0, e2, e1, -normal1);
        }
    } else {
        m.kind = ManifoldKind::FaceB;
        let (k, _) = poly_axis.expect("polygon axis");
        ie = [
            ClipVertex {
                v: e1,
                id: Feature {
                    index_a: 0,
                    index_b: k as u8,
                    type_a: VERTEX,
                    type_b: FACE,
                },
            },
            ClipVertex {
                v: e2,
                id: Feature {
                    index_a: 0,
                    index_b: k as u8,
                    type_a: VERTEX,
                    type_b: FACE,
                },
            },
        ];
        rf_i1 = k;
        rf_i2 = if k + 1 < nb { k + 1 } else { 0 };
        rf_v1 = verts[rf_i1];
        rf_v2 = verts[rf_i2];
        rf_normal = norms[rf_i1];
    }
    let side_normal1 = v2(rf_normal.y, -rf_normal.x);
    let side_normal2 = -side_normal1;
    let (c1, n) = clip_segment(&ie, side_normal1, side_normal1.dot(rf_v1), rf_i1);
    if n < 2 {
        return;
    }
    let (c2, n) = clip_segment(&c1, side_normal2, side_normal2.dot(rf_v2), rf_i2);
    if n < 2 {
        return;
    }
    if use_edge {
        m.local_normal = rf_normal;
        m.local_point = rf_v1;
    } else {
        m.local_normal = poly.normals[rf_i1];
        m.local_point = poly.vertices[rf_i1];
    }
    for cv in &c2 {
        if rf_normal.dot(cv.v - rf_v1) <= total_radius {
            let mp = &mut m.points[m.count];
            if use_edge {
                mp.local_point = xf.apply_inv(cv.v);
                mp.id = cv.id;
            } else {
                mp.local_point = cv.v;
                mp.id = cv.id.swapped();
            }
            m.count += 1;
        }
    }
}

/// Rotation of B relative to A.
fn rot_mul_t(a: &Xf, b: &Xf) -> super::math::Rot {
    super::math::Rot {
        s: a.q.c * b.q.s - a.q.s * b.q.c,
        c: a.q.c * b.q.c + a.q.s * b.q.s,
    }
}

/// World normal, contact points (midway between the skins) and separations of a manifold.
pub fn world_manifold(m: &Manifold, xfa: &Xf, ra: f64, xfb: &Xf, rb: f64) -> (V2, [V2; 2], [f64; 2]) {
    let mut pts = [V2::ZERO; 2];
    let mut seps = [0.0; 2];
    match m.kind {
        ManifoldKind::FaceA => {
            let normal = xfa.q.apply(m.local_normal);
            let plane = xfa.apply(m.local_point);
            for i in 0..m.count {
                let clip = xfb.apply(m.points[i].local_point);
                let ca = clip + (ra - (clip - plane).dot(normal)) * normal;
                let cb = clip - rb * normal;
                pts[i] = 0.5 * (ca + cb);
                seps[i] = (cb - ca).dot(normal);
            }
            (normal, pts, seps)
        }
        ManifoldKind::FaceB => {
            let normal = xfb.q.apply(m.local_normal);
            let plane = xfb.apply(m.local_point);
            for i in 0..m.count {
                let clip = xfa.apply(m.points[i].local_point);
                let cb = clip + (rb - (clip - plane).dot(normal)) * normal;
                let ca = clip - ra * normal;
                pts[i] = 0.5 * (ca + cb);
                seps[i] = (ca - cb).dot(normal);
            }
            (-normal, pts, seps)
        }
    }
}
