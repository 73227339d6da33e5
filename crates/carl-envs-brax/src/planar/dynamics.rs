//! Joint-space dynamics of the planar tree: the mass matrix `M(q)` as `Σ Jᵢᵀ Mᵢ Jᵢ` over the
//! links' centre-of-mass Jacobians (only a link's ancestor coordinates have non-zero
//! columns), the bias forces `C(q, q̇)q̇ − τ_gravity` by recursive Newton–Euler with zero joint
//! accelerations; the dense Cholesky factorization of the small symmetric positive definite
//! systems (n ≤ a dozen coordinates) is the articulated engine's.

use super::kinematics::{DofAxis, LinkState, dot, point_bias_acceleration};
use super::tree::PlanarTree;

/// `M(q)` (row-major `n × n`, without armature) and the bias forces `b = C(q, q̇)q̇ − Σ Jᵢᵀ mᵢ g`
/// from the link states of [`super::kinematics`].
pub fn mass_matrix_and_bias(
    tree: &PlanarTree,
    links: &[LinkState],
    axes: &[DofAxis],
    gravity: f64,
    m_out: &mut [f64],
    bias: &mut [f64],
) {
    let n = tree.dofs.len();
    m_out.fill(0.0);
    bias.fill(0.0);
    for (l, s) in tree.links.iter().zip(links) {
        if l.ancestors.is_empty() {
            continue;
        }
        let c = s.com;
        // Newton–Euler force of the link with zero joint accelerations, gravity moved to the
        // acceleration side: f = m (a_c − g), torque = I α.
        let a = point_bias_acceleration(s, c);
        let f = [l.mass * a[0], l.mass * (a[1] - gravity)];
        let t = l.inertia * s.alpha;
        for (k, &da) in l.ancestors.iter().enumerate() {
            let (ja, wa) = axes[da].point_column(c);
            bias[da] += dot(ja, f) + wa * t;
            for &db in &l.ancestors[..=k] {
                let (jb, wb) = axes[db].point_column(c);
                let e = l.mass * dot(ja, jb) + l.inertia * wa * wb;
                m_out[da * n + db] += e;
            }
        }
    }
    // Mirror the accumulated lower triangle (ancestors are root-first, so `db` ≤ `da` in
    // visiting order but not necessarily in index order: symmetrize both ways).
    for i in 0..n {
        for j in 0..i {
            let s = m_out[i * n + j] + m_out[j * n + i];
            m_out[i * n + j] = s;
            m_out[j * n + i] = s;
        }
    }
}

/// Kinetic energy `½ Σ (mᵢ |v_cᵢ|² + Iᵢ ωᵢ²)` of the links.
pub fn kinetic_energy(tree: &PlanarTree, links: &[LinkState]) -> f64 {
    tree.links
        .iter()
        .zip(links)
        .map(|(l, s)| {
            let v = super::kinematics::point_velocity(s, s.com);
            0.5 * (l.mass * dot(v, v) + l.inertia * s.omega * s.omega)
        })
        .sum()
}

/// Potential energy `−Σ mᵢ g z_cᵢ` of the links (gravity `g` along z, negative = down).
pub fn potential_energy(tree: &PlanarTree, links: &[LinkState], gravity: f64) -> f64 {
    tree.links
        .iter()
        .zip(links)
        .filter(|(l, _)| l.parent.is_some())
        .map(|(l, s)| -l.mass * gravity * s.com[1])
        .sum()
}

/// The dense Cholesky factorization and solve of the small symmetric positive definite systems
/// (n ≤ a dozen coordinates): the articulated engine's, the same arithmetic.
pub use carl_articulated::dynamics::{cholesky, cholesky_solve};

/// `J_p` of world point `p` on the link with ancestors `ancestors`: its velocity per unit rate
/// of each coordinate (one row per axis, row-major `2 × n`, zero outside the ancestors).
pub fn point_jacobian(ancestors: &[usize], axes: &[DofAxis], p: [f64; 2], jx: &mut [f64], jz: &mut [f64]) {
    jx.fill(0.0);
    jz.fill(0.0);
    for &d in ancestors {
        let (col, _) = axes[d].point_column(p);
        jx[d] = col[0];
        jz[d] = col[1];
    }
}
