//! Contacts and joint limits as velocity-level constraints in joint space, solved by projected
//! Gauss–Seidel on the rows' effective masses (`J M̃⁻¹ Jᵀ`).
//!
//! Each capsule meets the ground plane `z = 0` at its end spheres (the lowest point of a
//! segment over a plane is always one of its ends): a normal row (unilateral, soft) and a
//! friction row along x (Coulomb, `|λ_t| ≤ μ λ_n`). A joint limit is a unilateral row on its
//! coordinate. A soft row behaves as an implicit spring–damper of natural frequency `ω` and
//! damping ratio `ζ` on the row's effective mass (Catto's "soft step": bias rate
//! `ω / (2ζ + hω)`, mass scale `hω(2ζ + hω) / (1 + hω(2ζ + hω))`); a row whose gap is still
//! open is speculative: rigid, with the gap closed by the end of the step at the most.

use super::dynamics::cholesky_solve;

/// Constraint softness of one row for time step `h`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Softness {
    pub bias_rate: f64,
    pub mass_scale: f64,
    pub impulse_scale: f64,
}

impl Softness {
    /// A spring–damper of angular frequency `omega` (rad/s) and damping ratio `zeta`.
    pub fn new(omega: f64, zeta: f64, h: f64) -> Softness {
        let a1 = 2.0 * zeta + h * omega;
        let a2 = h * omega * a1;
        let a3 = 1.0 / (1.0 + a2);
        if !(omega > 0.0 && a1 > 0.0 && a2.is_finite()) {
            return Softness::rigid(h);
        }
        Softness {
            bias_rate: omega / a1,
            mass_scale: a2 * a3,
            impulse_scale: a3,
        }
    }

    /// No softness: the full error is removed within one step.
    pub fn rigid(h: f64) -> Softness {
        Softness {
            bias_rate: 1.0 / h,
            mass_scale: 1.0,
            impulse_scale: 0.0,
        }
    }
}

/// What a row constrains.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RowKind {
    /// Contact normal or joint limit: `λ ≥ 0`.
    Unilateral,
    /// Friction bounded by `mu` times the impulse of row `normal`.
    Friction { normal: usize, mu: f64 },
}

/// The constraint rows of one step, in preallocated buffers.
#[derive(Debug, Clone)]
pub struct Rows {
    n: usize,
    pub count: usize,
    /// Jacobian rows (`count × n`).
    pub jac: Vec<f64>,
    /// `M̃⁻¹ Jᵀ` per row.
    w: Vec<f64>,
    inv_mass: Vec<f64>,
    /// Velocity bias (`bias_rate · gap`, or `gap / h` for an open gap).
    bias: Vec<f64>,
    soft: Vec<Softness>,
    pub kind: Vec<RowKind>,
    /// Impulse of each row after [`Rows::solve`].
    pub lambda: Vec<f64>,
}

/// Projected Gauss–Seidel sweeps at most; they stop earlier once no impulse changes by more
/// than [`TOLERANCE`].
pub const MAX_SWEEPS: usize = 50;
pub const TOLERANCE: f64 = 1e-10;

impl Rows {
    pub fn new(n: usize, capacity: usize) -> Rows {
        Rows {
            n,
            count: 0,
            jac: vec![0.0; n * capacity],
            w: vec![0.0; n * capacity],
            inv_mass: vec![0.0; capacity],
            bias: vec![0.0; capacity],
            soft: vec![Softness::rigid(1.0); capacity],
            kind: vec![RowKind::Unilateral; capacity],
            lambda: vec![0.0; capacity],
        }
    }

    pub fn clear(&mut self) {
        self.count = 0;
    }

    /// Start a new row and return its Jacobian for the caller to fill (zeroed), or `None` if the
    /// buffers are full.
    pub fn push(&mut self, kind: RowKind, gap: f64, soft: Softness, h: f64) -> Option<&mut [f64]> {
        let r = self.count;
        if r >= self.inv_mass.len() {
            return None;
        }
        self.count += 1;
        self.kind[r] = kind;
        if let RowKind::Friction { .. } = kind {
            // Friction is regularized like the contact's normal (damping only, no position).
            self.soft[r] = soft;
            self.bias[r] = 0.0;
        } else if gap >= 0.0 {
            self.soft[r] = Softness::rigid(h);
            self.bias[r] = gap / h;
        } else {
            self.soft[r] = soft;
            self.bias[r] = soft.bias_rate * gap;
        }
        let n = self.n;
        let row = &mut self.jac[r * n..(r + 1) * n];
        row.fill(0.0);
        Some(row)
    }

    /// Solve for the impulses given the factor `chol` of `M̃` and update `v` (the velocity
    /// without constraints on entry, with them on return).
    pub fn solve(&mut self, chol: &[f64], v: &mut [f64]) {
        let n = self.n;
        for r in 0..self.count {
            let w = &mut self.w[r * n..(r + 1) * n];
            w.copy_from_slice(&self.jac[r * n..(r + 1) * n]);
            cholesky_solve(chol, n, w);
            let a: f64 = w.iter().zip(&self.jac[r * n..(r + 1) * n]).map(|(x, y)| x * y).sum();
            self.inv_mass[r] = if a > 1e-12 { 1.0 / a } else { 0.0 };
            self.lambda[r] = 0.0;
        }
        for _ in 0..MAX_SWEEPS {
            let mut change = 0.0f64;
            for r in 0..self.count {
                let j = &self.jac[r * n..(r + 1) * n];
                let cdot: f64 = j.iter().zip(v.iter()).map(|(a, b)| a * b).sum();
                let old = self.lambda[r];
                let new = match self.kind[r] {
                    RowKind::Unilateral => {
                        let s = self.soft[r];
                        let imp = -self.inv_mass[r] * s.mass_scale * (cdot + self.bias[r]) - s.impulse_scale * old;
                        (old + imp).max(0.0)
                    }
                    RowKind::Friction { normal, mu } => {
                        let s = self.soft[r];
                        let lim = mu * self.lambda[normal];
                        let imp = -self.inv_mass[r] * s.mass_scale * cdot - s.impulse_scale * old;
                        (old + imp).clamp(-lim, lim)
                    }
                };
                let d = new - old;
                if d != 0.0 {
                    self.lambda[r] = new;
                    for (x, w) in v.iter_mut().zip(&self.w[r * n..(r + 1) * n]) {
                        *x += w * d;
                    }
                    change = change.max(d.abs());
                }
            }
            if change < TOLERANCE {
                break;
            }
        }
    }
}
