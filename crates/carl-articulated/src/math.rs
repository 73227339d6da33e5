//! Small fixed-size linear algebra in f64: 3-vectors, row-major 3×3 matrices, unit quaternions
//! `[w, x, y, z]` (MuJoCo's order), spatial motion and force vectors `[angular; linear]`
//! expressed in the world frame about the world origin, and spatial inertias in that frame.

pub type V3 = [f64; 3];
pub type M3 = [[f64; 3]; 3];
pub type Quat = [f64; 4];
/// A spatial vector: motion `[ω; v_O]` (v_O the velocity of the point at the world origin) or
/// force `[n_O; f]` (n_O the moment about the world origin).
pub type V6 = [f64; 6];

pub const ZERO3: V3 = [0.0; 3];
pub const IDENTITY: M3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
pub const QUAT_IDENTITY: Quat = [1.0, 0.0, 0.0, 0.0];

#[inline]
pub fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
#[inline]
pub fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
#[inline]
pub fn scale(a: V3, s: f64) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}
#[inline]
pub fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
#[inline]
pub fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
#[inline]
pub fn norm(a: V3) -> f64 {
    dot(a, a).sqrt()
}
/// Two orthonormal axes of the plane normal to `g` (x and y when `g` is zero or along z).
pub fn plane_axes(g: V3) -> [V3; 2] {
    let Some(n) = normalize(g) else {
        return [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    };
    // Start from the world axis least aligned with the normal.
    let k = (0..3).min_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs())).unwrap_or(0);
    let mut e = [0.0; 3];
    e[k] = 1.0;
    let u = normalize(sub(e, scale(n, dot(e, n)))).unwrap_or([1.0, 0.0, 0.0]);
    [u, cross(n, u)]
}

/// `a / |a|`, or `None` for a (near) zero vector.
pub fn normalize(a: V3) -> Option<V3> {
    let n = norm(a);
    (n > 1e-15 && n.is_finite()).then(|| scale(a, 1.0 / n))
}

#[inline]
pub fn mat_vec(m: &M3, v: V3) -> V3 {
    [dot(m[0], v), dot(m[1], v), dot(m[2], v)]
}
/// `mᵀ v`.
#[inline]
pub fn mat_t_vec(m: &M3, v: V3) -> V3 {
    [
        m[0][0] * v[0] + m[1][0] * v[1] + m[2][0] * v[2],
        m[0][1] * v[0] + m[1][1] * v[1] + m[2][1] * v[2],
        m[0][2] * v[0] + m[1][2] * v[1] + m[2][2] * v[2],
    ]
}
pub fn mat_mul(a: &M3, b: &M3) -> M3 {
    let mut r = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            r[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        }
    }
    r
}
/// `r · diag(d) · rᵀ`.
pub fn rotate_diag(r: &M3, d: V3) -> M3 {
    let mut m = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            m[i][j] = r[i][0] * d[0] * r[j][0] + r[i][1] * d[1] * r[j][1] + r[i][2] * d[2] * r[j][2];
        }
    }
    m
}
/// Column `j` of `m`.
#[inline]
pub fn col(m: &M3, j: usize) -> V3 {
    [m[0][j], m[1][j], m[2][j]]
}

pub fn quat_mul(a: Quat, b: Quat) -> Quat {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}
/// The unit quaternion of `q` (identity for a zero or non-finite one), as MuJoCo's
/// `mju_normalize4`: left as it is when its norm is within 1e-15 of 1, else multiplied by the
/// reciprocal of its norm.
pub fn quat_normalize(q: Quat) -> Quat {
    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    if !(n > 1e-15 && n.is_finite()) {
        QUAT_IDENTITY
    } else if (n - 1.0).abs() > 1e-15 {
        let r = 1.0 / n;
        [q[0] * r, q[1] * r, q[2] * r, q[3] * r]
    } else {
        q
    }
}
/// `v` rotated by the unit quaternion `q`: `v + 2 u × (w v + u × v)` (`q = [w, u]`), as MuJoCo's
/// `mju_rotVecQuat` rotates joint axes and anchors (the same bits in about half of random cases,
/// the rest within rounding); `v` itself when `q` is the identity, zero when `v` is.
#[inline]
pub fn quat_rotate(q: Quat, v: V3) -> V3 {
    if v == ZERO3 {
        return ZERO3;
    }
    if q == QUAT_IDENTITY {
        return v;
    }
    let u = [q[1], q[2], q[3]];
    let t = add(scale(v, q[0]), cross(u, v));
    let c = cross(u, t);
    [v[0] + 2.0 * c[0], v[1] + 2.0 * c[1], v[2] + 2.0 * c[2]]
}
/// Rotation by `angle` about the unit `axis`.
pub fn quat_axis_angle(axis: V3, angle: f64) -> Quat {
    let (s, c) = (0.5 * angle).sin_cos();
    [c, axis[0] * s, axis[1] * s, axis[2] * s]
}
/// The rotation matrix of a unit quaternion.
pub fn quat_to_mat(q: Quat) -> M3 {
    let [w, x, y, z] = q;
    [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ]
}
/// MuJoCo's quaternion integration: `q ← q ⊗ exp(ω h / 2)`, `ω` in the local frame, then
/// normalized.
pub fn quat_integrate(q: Quat, omega_local: V3, h: f64) -> Quat {
    let w = norm(omega_local);
    if w * h < 1e-300 || !w.is_finite() {
        return quat_normalize(q);
    }
    let axis = scale(omega_local, 1.0 / w);
    quat_normalize(quat_mul(q, quat_axis_angle(axis, w * h)))
}

/// Motion cross product `a ×ₘ b` of spatial motion vectors.
#[inline]
pub fn cross_motion(a: &V6, b: &V6) -> V6 {
    let (wa, va) = ([a[0], a[1], a[2]], [a[3], a[4], a[5]]);
    let (wb, vb) = ([b[0], b[1], b[2]], [b[3], b[4], b[5]]);
    let w = cross(wa, wb);
    let v = add(cross(wa, vb), cross(va, wb));
    [w[0], w[1], w[2], v[0], v[1], v[2]]
}
/// Force cross product `a ×* f` (motion `a`, force `f`).
#[inline]
pub fn cross_force(a: &V6, f: &V6) -> V6 {
    let (wa, va) = ([a[0], a[1], a[2]], [a[3], a[4], a[5]]);
    let (n, ff) = ([f[0], f[1], f[2]], [f[3], f[4], f[5]]);
    let m = add(cross(wa, n), cross(va, ff));
    let l = cross(wa, ff);
    [m[0], m[1], m[2], l[0], l[1], l[2]]
}
#[inline]
pub fn dot6(a: &V6, b: &V6) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}
#[inline]
pub fn add6(a: &mut V6, b: &V6, s: f64) {
    for (x, y) in a.iter_mut().zip(b) {
        *x += s * y;
    }
}
/// Angular and linear halves of a spatial vector.
#[inline]
pub fn split(a: &V6) -> (V3, V3) {
    ([a[0], a[1], a[2]], [a[3], a[4], a[5]])
}
#[inline]
pub fn join(a: V3, b: V3) -> V6 {
    [a[0], a[1], a[2], b[0], b[1], b[2]]
}

/// A spatial inertia about the world origin: rotational inertia about the origin `rot`
/// (`I_c − m [c]×²`), first moment `h = m c` and mass `m`. Additive, so composite inertias are
/// sums.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Inertia {
    pub rot: M3,
    pub h: V3,
    pub m: f64,
}

impl Inertia {
    /// The inertia of mass `m` at `c` with rotational inertia `ic` about `c` (world frame).
    pub fn new(m: f64, c: V3, ic: &M3) -> Inertia {
        // −m [c]×² = m (|c|² 1 − c cᵀ)
        let cc = dot(c, c);
        let mut rot = *ic;
        for i in 0..3 {
            for j in 0..3 {
                rot[i][j] += m * (if i == j { cc } else { 0.0 } - c[i] * c[j]);
            }
        }
        Inertia { rot, h: scale(c, m), m }
    }
    pub fn add(&mut self, o: &Inertia) {
        for i in 0..3 {
            for j in 0..3 {
                self.rot[i][j] += o.rot[i][j];
            }
        }
        self.h = add(self.h, o.h);
        self.m += o.m;
    }
    /// Momentum `I v` of motion `v`: `[rot ω + h × v; m v − h × ω]`.
    pub fn mul(&self, v: &V6) -> V6 {
        let (w, lin) = split(v);
        let n = add(mat_vec(&self.rot, w), cross(self.h, lin));
        let f = sub(scale(lin, self.m), cross(self.h, w));
        join(n, f)
    }
}

/// The unit quaternion of a rotation matrix (Shepperd's method).
pub fn mat_to_quat(m: &M3) -> Quat {
    let tr = m[0][0] + m[1][1] + m[2][2];
    let q = if tr > 0.0 {
        let s = (tr + 1.0).sqrt() * 2.0;
        [
            0.25 * s,
            (m[2][1] - m[1][2]) / s,
            (m[0][2] - m[2][0]) / s,
            (m[1][0] - m[0][1]) / s,
        ]
    } else if m[0][0] > m[1][1] && m[0][0] > m[2][2] {
        let s = (1.0 + m[0][0] - m[1][1] - m[2][2]).sqrt() * 2.0;
        [
            (m[2][1] - m[1][2]) / s,
            0.25 * s,
            (m[0][1] + m[1][0]) / s,
            (m[0][2] + m[2][0]) / s,
        ]
    } else if m[1][1] > m[2][2] {
        let s = (1.0 + m[1][1] - m[0][0] - m[2][2]).sqrt() * 2.0;
        [
            (m[0][2] - m[2][0]) / s,
            (m[0][1] + m[1][0]) / s,
            0.25 * s,
            (m[1][2] + m[2][1]) / s,
        ]
    } else {
        let s = (1.0 + m[2][2] - m[0][0] - m[1][1]).sqrt() * 2.0;
        [
            (m[1][0] - m[0][1]) / s,
            (m[0][2] + m[2][0]) / s,
            (m[1][2] + m[2][1]) / s,
            0.25 * s,
        ]
    };
    quat_normalize(q)
}

/// Principal moments and axes of a symmetric inertia tensor (cyclic Jacobi rotations):
/// `(moments, q)` with `i = R(q) · diag(moments) · R(q)ᵀ`, `R(q)` a proper rotation.
pub fn principal_axes(i: &M3) -> (V3, Quat) {
    let mut a = *i;
    let mut v = IDENTITY;
    for _ in 0..50 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        if off < 1e-18 * (a[0][0].abs() + a[1][1].abs() + a[2][2].abs()).max(1e-300) {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q].abs() < 1e-300 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            // a ← Jᵀ a J, v ← v J with the rotation J in the (p, q) plane.
            for row in a.iter_mut() {
                let (akp, akq) = (row[p], row[q]);
                row[p] = c * akp - s * akq;
                row[q] = s * akp + c * akq;
            }
            let (rp, rq) = (a[p], a[q]);
            for k in 0..3 {
                a[p][k] = c * rp[k] - s * rq[k];
                a[q][k] = s * rp[k] + c * rq[k];
            }
            for row in v.iter_mut() {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    // A proper rotation: flip the last axis if needed.
    let det = dot(col(&v, 0), cross(col(&v, 1), col(&v, 2)));
    if det < 0.0 {
        for row in v.iter_mut() {
            row[2] = -row[2];
        }
    }
    ([a[0][0], a[1][1], a[2][2]], mat_to_quat(&v))
}

#[cfg(test)]
mod tests {
    #[test]
    fn principal_axes_reconstruct_the_tensor() {
        let i = [[0.02, -0.006, 0.001], [-0.006, 0.03, 0.002], [0.001, 0.002, 0.015]];
        let (d, q) = principal_axes(&i);
        let r = rotate_diag(&quat_to_mat(q), d);
        for a in 0..3 {
            for b in 0..3 {
                assert!((r[a][b] - i[a][b]).abs() < 1e-14, "{r:?} vs {i:?}");
            }
        }
        let (d, q) = principal_axes(&[[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 3.0]]);
        assert_eq!(d, [1.0, 2.0, 3.0]);
        assert!((q[0] - 1.0).abs() < 1e-15);
    }

    use super::*;

    #[test]
    fn quaternion_matrix_and_integration_agree() {
        let q = quat_normalize([0.3, -0.2, 0.5, 0.7]);
        let r = quat_to_mat(q);
        let rt_r = mat_mul(&[col(&r, 0), col(&r, 1), col(&r, 2)], &r);
        for (i, row) in rt_r.iter().enumerate() {
            for (j, x) in row.iter().enumerate() {
                assert!((x - if i == j { 1.0 } else { 0.0 }).abs() < 1e-12);
            }
        }
        // Integrating ω = (0, 0, π/2) for 1 s from identity turns x into y.
        let q = quat_integrate(QUAT_IDENTITY, [0.0, 0.0, std::f64::consts::FRAC_PI_2], 1.0);
        let x = mat_vec(&quat_to_mat(q), [1.0, 0.0, 0.0]);
        assert!((x[1] - 1.0).abs() < 1e-12 && x[0].abs() < 1e-12);
    }

    #[test]
    fn inertia_momentum_matches_point_mass() {
        // A point mass 2 kg at c moving with ω about the origin: p = m ω × c.
        let c = [1.0, 2.0, 0.5];
        let i = Inertia::new(2.0, c, &[[0.0; 3]; 3]);
        let w = [0.1, -0.3, 0.2];
        let h = i.mul(&join(w, ZERO3));
        let p = scale(cross(w, c), 2.0);
        for k in 0..3 {
            assert!((h[3 + k] - p[k]).abs() < 1e-12);
        }
        let l = cross(c, p);
        for k in 0..3 {
            assert!((h[k] - l[k]).abs() < 1e-12);
        }
    }
}
