//! Contacts and joint limits as velocity-level constraints in joint space, solved by projected
//! Gauss–Seidel on the rows' effective masses (`J M̃⁻¹ Jᵀ`).
//!
//! Each capsule meets the ground plane `z = 0` at its end spheres (the lowest point of a
//! segment over a plane is always one of its ends) once they penetrate it: a normal row
//! (unilateral, soft as MuJoCo's contacts) and a friction row along x (Coulomb,
//! `|λ_t| ≤ μ λ_n`, stiff: MuJoCo's regularized pyramid let a resting HalfCheetah creep here
//! and moved the random-policy return 29 % from MuJoCo's, the stiff box 5 %). A joint limit is
//! a unilateral row on its coordinate. Every row is regularized (`J v⁺ + R λ = target`): contacts as MuJoCo's default
//! soft contacts ([`Impedance`]), joint limits as a spring–damper of given natural frequency
//! and damping ratio on the row's effective mass ([`Softness`]). A limit row whose gap is still
//! open is speculative: it lets the gap close by the end of the step (softly: the limit's
//! regularizer applies as in rapier's soft joint limits).

use super::dynamics::cholesky_solve;

/// Constraint softness of one row for time step `h`, as a target velocity and a regularizer:
/// a row's impulse `λ` solves `J v⁺ + R λ = target` (projected on its bounds), with
/// `R = ratio · (J M̃⁻¹ Jᵀ)`. A stiff row has `ratio` 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Softness {
    /// Target velocity per unit of constraint violation (1/s; the violation is negative).
    pub bias_rate: f64,
    /// `R` relative to the row's inverse effective mass.
    pub ratio: f64,
}

impl Softness {
    /// A spring–damper of angular frequency `omega` (rad/s) and damping ratio `zeta` (Catto's
    /// soft step: bias rate `ω / (2ζ + hω)`, regularizer `1 / (hω(2ζ + hω))`).
    pub fn new(omega: f64, zeta: f64, h: f64) -> Softness {
        let a1 = 2.0 * zeta + h * omega;
        let a2 = h * omega * a1;
        if !(omega > 0.0 && a1 > 0.0 && a2.is_finite() && a2 > 0.0) {
            return Softness::rigid(h);
        }
        Softness {
            bias_rate: omega / a1,
            ratio: 1.0 / a2,
        }
    }

    /// No softness: the full error is removed within one step.
    pub fn rigid(h: f64) -> Softness {
        Softness {
            bias_rate: 1.0 / h,
            ratio: 0.0,
        }
    }
}

/// MuJoCo's soft contact for time constant `tc` and damping ratio `zeta` (its `solref`) and
/// impedance from `d0` at zero penetration to `d_width` at `width` and beyond (its `solimp`,
/// a linear ramp, or MuJoCo's sigmoid of given midpoint and power, [`ImpedanceShape`]): the
/// row's reference acceleration is `−b·v₀ − k·r` with
/// `b = 2 / (d_width·tc)`, `k = d / (d_width²·tc²·ζ²)`, `v₀` the row velocity at the start of
/// the step and `r` the (negative) penetration; the regularizer is `(1 − d) / d`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Impedance {
    pub tc: f64,
    pub zeta: f64,
    pub d0: f64,
    pub d_width: f64,
    pub width: f64,
    pub shape: ImpedanceShape,
}

/// How the impedance goes from `d0` to `d_width` over the width.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ImpedanceShape {
    /// A linear ramp (HalfCheetah's contacts).
    Linear,
    /// MuJoCo's `solimp` sigmoid: two power curves of the given `power` meeting at `mid`.
    Sigmoid { mid: f64, power: f64 },
}

impl Impedance {
    /// MuJoCo's defaults: `solref = (0.02, 1)`, `solimp = (0.9, 0.95, 0.001)`.
    pub const MUJOCO_DEFAULT: Impedance = Impedance {
        tc: 0.02,
        zeta: 1.0,
        d0: 0.9,
        d_width: 0.95,
        width: 0.001,
        shape: ImpedanceShape::Linear,
    };

    /// MuJoCo's soft constraint of `solref` and `solimp` (positive `solref` form) for a time
    /// step `h`: the time constant is at least `2h` (MuJoCo's `refsafe`).
    pub fn mujoco(solref: [f64; 2], solimp: [f64; 5], h: f64) -> Impedance {
        let clamp = |d: f64| d.clamp(1e-4, 0.9999);
        Impedance {
            tc: solref[0].max(2.0 * h),
            zeta: solref[1],
            d0: clamp(solimp[0]),
            d_width: clamp(solimp[1]),
            width: solimp[2].max(1e-10),
            shape: ImpedanceShape::Sigmoid {
                mid: solimp[3].clamp(1e-4, 1.0 - 1e-4),
                power: solimp[4].max(1.0),
            },
        }
    }

    fn d(&self, r: f64) -> f64 {
        let x = (r.abs() / self.width).min(1.0);
        let y = match self.shape {
            ImpedanceShape::Linear => x,
            ImpedanceShape::Sigmoid { .. } if x >= 1.0 => 1.0,
            ImpedanceShape::Sigmoid { power: 1.0, .. } => x,
            ImpedanceShape::Sigmoid { mid, power } => {
                if x <= mid {
                    x.powf(power) / mid.powf(power - 1.0)
                } else {
                    1.0 - (1.0 - x).powf(power) / (1.0 - mid).powf(power - 1.0)
                }
            }
        };
        self.d0 + (self.d_width - self.d0) * y
    }

    /// (target velocity, regularizer ratio) of a row of a contact with start velocity `v0`
    /// along the row and penetration `r` (< 0) over a step `h`.
    pub fn row(&self, v0: f64, r: f64, h: f64) -> (f64, f64) {
        let d = self.d(r);
        let b = 2.0 / (self.d_width * self.tc);
        let k = d / (self.d_width * self.d_width * self.tc * self.tc * self.zeta * self.zeta);
        (v0 - h * (b * v0 + k * r), (1.0 - d) / d)
    }
}

/// What a row constrains.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RowKind {
    /// A joint limit or a contact normal: `λ ≥ 0`.
    Unilateral,
    /// Friction bounded by `mu` times the impulse of row `normal`.
    Friction { normal: usize, mu: f64 },
    /// Dry friction of a known normal load: `|λ| ≤ limit` (MuJoCo's joint `frictionloss`
    /// times the step).
    Bounded { limit: f64 },
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
    /// Target velocity of each row.
    target: Vec<f64>,
    /// Regularizer ratio of each row (see [`Softness`]); `R` itself after [`Rows::solve`]
    /// starts.
    reg: Vec<f64>,
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
            target: vec![0.0; capacity],
            reg: vec![0.0; capacity],
            kind: vec![RowKind::Unilateral; capacity],
            lambda: vec![0.0; capacity],
        }
    }

    pub fn clear(&mut self) {
        self.count = 0;
    }

    /// Start a new row with its target velocity and regularizer ratio and return its
    /// Jacobian for the caller to fill (zeroed), or `None` if the buffers are full.
    pub fn push(&mut self, kind: RowKind, target: f64, ratio: f64) -> Option<&mut [f64]> {
        let r = self.count;
        if r >= self.inv_mass.len() {
            return None;
        }
        self.count += 1;
        self.kind[r] = kind;
        self.target[r] = target;
        self.reg[r] = ratio;
        let n = self.n;
        let row = &mut self.jac[r * n..(r + 1) * n];
        row.fill(0.0);
        Some(row)
    }

    /// A unilateral row at signed gap `gap` with softness `soft`: an open gap may close within
    /// the step (speculative) but not more, up to the row's softness; a closed one is pushed
    /// open at the soft rate.
    pub fn push_gap(&mut self, gap: f64, soft: Softness, h: f64) -> Option<&mut [f64]> {
        if gap >= 0.0 {
            self.push(RowKind::Unilateral, -gap / h, soft.ratio)
        } else {
            self.push(RowKind::Unilateral, -soft.bias_rate * gap, soft.ratio)
        }
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
            // From here on `reg` holds R itself and `inv_mass` 1 / (A + R).
            self.reg[r] *= a;
            self.inv_mass[r] = if a > 1e-12 { 1.0 / (a + self.reg[r]) } else { 0.0 };
            self.lambda[r] = 0.0;
        }
        for _ in 0..MAX_SWEEPS {
            let mut change = 0.0f64;
            for r in 0..self.count {
                let j = &self.jac[r * n..(r + 1) * n];
                let cdot: f64 = j.iter().zip(v.iter()).map(|(a, b)| a * b).sum();
                let old = self.lambda[r];
                let free = old - self.inv_mass[r] * (cdot + self.reg[r] * old - self.target[r]);
                let new = match self.kind[r] {
                    RowKind::Unilateral => free.max(0.0),
                    RowKind::Friction { normal, mu } => {
                        let lim = mu * self.lambda[normal];
                        free.clamp(-lim, lim)
                    }
                    RowKind::Bounded { limit } => free.clamp(-limit, limit),
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
