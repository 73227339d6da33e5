//! Soft constraints as MuJoCo defines them, solved by Newton's method on the primal (pyramidal
//! cones, MuJoCo's default solver) or by projected Gauss–Seidel on the dual (elliptic cones).
//!
//! Every constraint row `i` has a Jacobian `Jᵢ`, a violation `rᵢ = posᵢ − marginᵢ`, an
//! impedance `dᵢ = d(|rᵢ|)` from `solimp` (MuJoCo's sigmoid from `dmin` at 0 to `dmax` at
//! `width`), a reference acceleration `arefᵢ = −B (Jᵢ v) − K dᵢ rᵢ` from `solref` (with
//! `timeconst ≥ 2h`: `B = 2 / (dmax·timeconst)`, `K = 1 / (dmax²·timeconst²·dampratio²)`; or
//! `K = −solref₀ / dmax²`, `B = −solref₁ / dmax` for negative `solref`) and a regularizer
//! `Rᵢ = (1 − dᵢ)/dᵢ · Âᵢ`, `Âᵢ` MuJoCo's diagonal approximation of `A = J M⁻¹ Jᵀ` from
//! `body_invweight0`/`dof_invweight0`. The forces `f` minimize
//! `½ fᵀ (A + R) f + fᵀ (J a₀ − aref)` over the cone, `a₀` the unconstrained acceleration, and
//! the acceleration is `a₀ + M⁻¹ Jᵀ f`. The same problem on the primal (MuJoCo's "Computation"
//! chapter; Todorov 2014, *Convex and analytically-invertible dynamics with contacts and
//! constraints*): the acceleration `a` minimizes `½ (a − a₀)ᵀ M (a − a₀) + Σᵢ sᵢ(Jᵢ a − arefᵢ)`,
//! each row's convex piecewise-quadratic `sᵢ` the cost whose derivative is minus the row's force
//! (`fᵢ = −(Jᵢ a − arefᵢ)/Rᵢ` projected on the row's bounds); both have the same unique solution.
//!
//! ## Why Newton replaces projected Gauss–Seidel
//!
//! Until the environments' versions of this change (`dmc_walker-v1`, `ant-v3`, …; every
//! articulated-engine environment with constraints and pyramidal cones), every model was solved
//! by projected Gauss–Seidel on the dual: `A` (rows × rows) built from `nefc` solves with `M`,
//! then sweeps of one-row projections, warm-started from the previous step's forces by row. Its
//! convergence is linear and slow where rows are coupled (a foot's four pyramid edges, a body
//! on two contacts): Walker needed about 80 sweeps per physics step even warm-started, 45 % of
//! its time. Newton on the primal converges quadratically (a piecewise-quadratic cost: once the
//! set of rows in their quadratic zone is the solution's, one step lands on the minimum) in a
//! few iterations per step (Walker under random actions: 2.2 on average), each a Cholesky
//! factor of the `nv × nv` Hessian `M + Jᵀ D J` (Walker nv = 9), never the rows × rows `A`. It
//! is MuJoCo's default solver, so the results also move towards MuJoCo's: the planar robots'
//! local parity improved from 4e-5 to 1e-11 in `qpos`. Elliptic cones (dm_control's Finger,
//! `dmc_finger-v0` unchanged) keep the dual Gauss–Seidel with a contact's three forces as one
//! block: their primal cost has a cone term whose Hessian is not a sum of rows, not written here.
//!
//! Newton (pyramidal cones): each iteration solves `(M + Jᵀ D J) δ = −∇`, `D = 1/R` on the rows
//! in their quadratic zone, and minimizes the cost along `δ` exactly. It starts from the previous
//! solve's acceleration (MuJoCo starts from whichever of it and `a₀` costs less). With that warm
//! start the solve needs neither `a₀` nor `M`'s factor: written as `½ aᵀ M a − aᵀ τ` (`τ` the
//! smooth force `qfrc_smooth`, equal to the cost above up to a constant), the cost's gradient is
//! `M a − τ − Jᵀ f`, and an iteration factors only `M + Jᵀ D J`: a forward pass with constraint rows
//! and a warm start factors the Hessian once per iteration and `M` not at all (Humanoid under
//! random actions: 1.4 factorizations per forward pass, 2.0 when every pass factored `M` for
//! `a₀`). The first solve after a reset, and one without rows, solve for `a₀` as before.
//!
//! Friction cone, as the model's [`Cone`] says:
//! * **pyramidal**, MuJoCo's default (`cone="pyramidal"`): a contact of condim 3 has four rows
//!   `J_n ± μ J_tₖ`, each with `f ≥ 0`, so every row has the same simple bound (on the primal: a
//!   one-sided quadratic cost per row). Pyramid rows get MuJoCo's regularizer
//!   `R = 2μ²/impratio · (1 − d)/d · (1 + μ²) Â_n` (observed in MuJoCo 4.0.0's `efc_R`).
//! * **elliptic** (`cone="elliptic"`): a contact of condim 3 has three rows, the normal `J_n` and
//!   the tangents `J_t₁`, `J_t₂`, the forces in `{f_n ≥ 0, ‖f_t‖ ≤ μ f_n}`. All three share the
//!   normal's impedance; the tangents' violation is 0 (`aref = −B J_t v`) and their regularizer
//!   `R_t = R_n / impratio` (MuJoCo's `efc_R`; equal sliding frictions in both directions).
//!   Gauss–Seidel updates the contact's three forces as a block, by the exact minimizer of their
//!   3×3 quadratic over the cone (`cone_qp`: the unconstrained minimizer if inside, else the
//!   best point of the cone's surface). Updating the normal and the friction forces one after
//!   the other (MuJoCo's PGS) creeps along the cone's surface when a contact slides.
//!
//! MuJoCo solves both cones by Newton on the primal by default; Newton here and Gauss–Seidel
//! converge to the minimizer of the same strictly convex problem, so the results agree up to
//! the solvers' tolerances.
//!
//! Dry friction (MuJoCo's `frictionloss`): one row per coordinate that has it, before the limits
//! and contacts as in MuJoCo, `Jᵢ` the unit row, violation 0, `Â = dof_invweight0`, the force
//! bounded by `±frictionloss` (Gauss–Seidel's projection clamps it, where the other rows are only
//! kept non-negative; on the primal its cost is quadratic within `|Jᵢ a − arefᵢ| ≤ R·frictionloss`
//! and linear outside). A body's dry friction on a table normal to gravity (a carl extension) is two
//! such rows on its centre of mass's velocity, `Â = body_invweight0` (translation).
//!
//! Restitution (a carl extension, 0 in MuJoCo): a contact or limit row with restitution `e`
//! approached at speed `vₙ < 0` gets `aref ← max(aref, −(1 + e) vₙ / h)`.
//!
//! Tendon equalities (MuJoCo's `<equality><tendon>`): one row each, first as in MuJoCo, the
//! residual `l₁ − l₁⁰ − p(l₂ − l₂⁰)` with Jacobian `J₁ − p′ J₂`, `Â` the sum of the tendons'
//! `tendon_invweight0`, the force of either sign (no projection).
//!
//! Joint limits: one row per violated side (`q − lo` or `hi − q` below the joint's margin),
//! `Â = dof_invweight0`. Gauss–Seidel's forces are warm-started from the previous solve (matched
//! by contact pair, contact and row, or by joint and side).

use crate::collision::{Placed, collide};
use crate::data::Data;
use crate::dynamics::{cholesky_and_solve, cholesky_solve, cholesky_solve4, sym_mat_vec};
use crate::math::{V3, add, col, cross, dot, dot6, join, scale, sub};
use crate::model::{Cone, SolImp, SolRef};

/// What a row constrains (for warm starts and contact forces).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RowKind {
    /// Edge `edge` (0–3) of contact `contact`'s pyramid, or its normal (frictionless, `edge` 0).
    Contact {
        contact: usize,
        edge: u8,
        frictionless: bool,
    },
    /// A joint limit of `joint` (`upper`: the upper one).
    Limit { joint: usize, upper: bool },
    /// The dry friction (`frictionloss`) of `joint`'s coordinate.
    Friction { joint: usize },
    /// The dry friction of `body` on its table along the plane's axis `axis` (0 or 1).
    DryFriction { body: usize, axis: u8 },
    /// Tendon equality `eq` (its force of either sign).
    Equality { eq: usize },
    #[default]
    None,
}

/// MuJoCo's impedance `d(x)` of `solimp` at violation `x ≥ 0`.
pub fn impedance(solimp: &SolImp, x: f64) -> f64 {
    const MIN: f64 = 0.0001;
    const MAX: f64 = 0.9999;
    let dmin = solimp[0].clamp(MIN, MAX);
    let dmax = solimp[1].clamp(MIN, MAX);
    let width = solimp[2].max(0.0);
    let mid = solimp[3].clamp(MIN, MAX);
    let power = solimp[4].max(1.0);
    if dmin == dmax || width <= 1e-10 {
        return dmax;
    }
    let x = (x / width).clamp(0.0, 1.0);
    if x >= 1.0 {
        return dmax;
    }
    if x <= 0.0 {
        return dmin;
    }
    let y = if power == 1.0 {
        x
    } else if x <= mid {
        x.powf(power) / mid.powf(power - 1.0)
    } else {
        1.0 - (1.0 - x).powf(power) / (1.0 - mid).powf(power - 1.0)
    };
    dmin + y * (dmax - dmin)
}

/// `(K, B)` of `solref` with impedance limits `solimp` for time step `h`.
pub fn stiffness_damping(solref: &SolRef, solimp: &SolImp, h: f64) -> (f64, f64) {
    let dmax = solimp[1].clamp(0.0001, 0.9999);
    if solref[0] > 0.0 {
        let tc = solref[0].max(2.0 * h);
        let dr = solref[1];
        (1.0 / (dmax * dmax * tc * tc * dr * dr), 2.0 / (dmax * tc))
    } else {
        (-solref[0] / (dmax * dmax), -solref[1] / dmax)
    }
}

impl Data {
    /// Contacts of every candidate pair at the current poses.
    pub(crate) fn collide(&mut self) {
        let m = &*self.model;
        self.ncon = 0;
        for (pi, &(g1, g2, plane, reach, reach2)) in self.pair_reach.iter().enumerate() {
            let d = sub(self.geom_xpos[g2], self.geom_xpos[g1]);
            if plane {
                // The other geom's bounding sphere above the plane by more than the margin (and
                // a slack far above the narrow phase's rounding): no point of it is within reach.
                if dot(d, col(&self.geom_xmat[g1], 2)) > reach + 1e-9 {
                    continue;
                }
            } else {
                // Bounding spheres: `|d| > reach`, decided without the square root when `d · d`
                // exceeds `reach² (1 + 10⁻¹²)` (then `√(d · d)` rounds above `reach` too).
                let d2 = dot(d, d);
                if d2 > reach2 || d2.sqrt() > reach {
                    continue;
                }
            }
            let pair = &m.pairs[pi];
            let (s1, s2) = (m.geoms[g1].shape, m.geoms[g2].shape);
            let a = Placed {
                shape: s1,
                pos: self.geom_xpos[g1],
                mat: self.geom_xmat[g1],
            };
            let b = Placed {
                shape: s2,
                pos: self.geom_xpos[g2],
                mat: self.geom_xmat[g2],
            };
            let start = self.ncon;
            let room = (self.contacts.len() - start).min(pair.max_contacts);
            let k = collide(&a, &b, pair.margin - pair.gap, &mut self.contacts[start..start + room]);
            for c in &mut self.contacts[start..start + k] {
                c.pair = pi;
            }
            self.ncon += k;
        }
    }

    /// `Jᵀ`-row of direction `u` at world point `p` of body `b` (added with sign `s`).
    fn add_point_row(&mut self, r: usize, b: usize, p: V3, u: V3, s: f64) {
        let m = &*self.model;
        let nv = m.nv;
        let f = join(cross(p, u), u);
        let row = &mut self.efc_j[r * nv..(r + 1) * nv];
        for &k in m.dof_path(m.body_last_dof[b]) {
            row[k] += s * dot6(&self.cdof[k], &f);
        }
    }

    /// Build the constraint rows of the current contacts and joint limits.
    pub(crate) fn make_constraints(&mut self) {
        let model = std::sync::Arc::clone(&self.model);
        let m = &*model;
        let nv = m.nv;
        let h = m.opt.timestep;
        self.nefc = 0;
        for (e, eq) in m.tendon_equalities.iter().enumerate() {
            let Some(r) = self.new_row() else { return };
            let len = |t: usize, q: &[f64]| -> f64 {
                m.tendons[t]
                    .joints
                    .iter()
                    .map(|&(j, c)| c * q[m.jnt_qposadr[j]])
                    .sum::<f64>()
                    - m.tendon_length0[t]
            };
            let x1 = len(eq.tendon1, &self.qpos);
            let (pos, deriv) = match eq.tendon2 {
                Some(t2) => {
                    let x2 = len(t2, &self.qpos);
                    let c = &eq.polycoef;
                    let p = c[0] + x2 * (c[1] + x2 * (c[2] + x2 * (c[3] + x2 * c[4])));
                    let dp = c[1] + x2 * (2.0 * c[2] + x2 * (3.0 * c[3] + x2 * 4.0 * c[4]));
                    (x1 - p, dp)
                }
                None => (x1 - eq.polycoef[0], 0.0),
            };
            for &(j, c) in &m.tendons[eq.tendon1].joints {
                self.efc_j[r * nv + m.jnt_dofadr[j]] += c;
            }
            if let Some(t2) = eq.tendon2 {
                for &(j, c) in &m.tendons[t2].joints {
                    self.efc_j[r * nv + m.jnt_dofadr[j]] -= deriv * c;
                }
            }
            let imp = impedance(&eq.solimp, pos.abs());
            let (kk, bb) = stiffness_damping(&eq.solref, &eq.solimp, h);
            self.efc_kind[r] = RowKind::Equality { eq: e };
            let mut diag = m.tendon_invweight0[eq.tendon1];
            if let Some(t2) = eq.tendon2 {
                diag += m.tendon_invweight0[t2];
            }
            self.set_row(r, pos, imp, kk, bb, diag);
        }
        for (j, jt) in m.joints.iter().enumerate() {
            if jt.frictionloss <= 0.0 {
                continue;
            }
            let d = m.jnt_dofadr[j];
            let Some(r) = self.new_row() else { return };
            self.efc_j[r * nv + d] = 1.0;
            let imp = impedance(&jt.solimp_friction, 0.0);
            let (_, bb) = stiffness_damping(&jt.solref_friction, &jt.solimp_friction, h);
            self.efc_kind[r] = RowKind::Friction { joint: j };
            self.set_row(r, 0.0, imp, 0.0, bb, m.dof_invweight0[d]);
            self.efc_bound[r] = jt.frictionloss;
        }
        if m.bodies.iter().any(|b| b.dryfriction > 0.0) {
            let axes = crate::math::plane_axes(m.opt.gravity);
            for (b, body) in m.bodies.iter().enumerate() {
                if body.dryfriction <= 0.0 || m.body_last_dof[b] == usize::MAX {
                    continue;
                }
                for (k, u) in axes.iter().enumerate() {
                    let Some(r) = self.new_row() else { return };
                    self.add_point_row(r, b, self.xipos[b], *u, 1.0);
                    let imp = impedance(&crate::model::SOLIMP_DEFAULT, 0.0);
                    let (_, bb) = stiffness_damping(&crate::model::SOLREF_DEFAULT, &crate::model::SOLIMP_DEFAULT, h);
                    self.efc_kind[r] = RowKind::DryFriction { body: b, axis: k as u8 };
                    self.set_row(r, 0.0, imp, 0.0, bb, m.body_invweight0[b][0]);
                    self.efc_bound[r] = body.dryfriction;
                }
            }
        }
        for ci in 0..self.ncon {
            let c = self.contacts[ci];
            let pair = &m.pairs[c.pair];
            let (b1, b2) = (m.geoms[pair.g1].body, m.geoms[pair.g2].body);
            let tran = m.body_invweight0[b1][0] + m.body_invweight0[b2][0];
            let imargin = pair.margin - pair.gap;
            let r_viol = c.dist - imargin;
            let imp = impedance(&pair.solimp, r_viol.abs());
            let (kk, bb) = stiffness_damping(&pair.solref, &pair.solimp, h);
            let elliptic = m.opt.cone == Cone::Elliptic && pair.condim != 1;
            let rows: &[(f64, usize)] = if pair.condim == 1 {
                &[(0.0, 0)]
            } else if elliptic {
                &[(0.0, 0), (0.0, 1), (0.0, 2)]
            } else {
                &[(1.0, 1), (-1.0, 1), (1.0, 2), (-1.0, 2)]
            };
            let mu = pair.friction;
            // The normal approach speed (restitution only).
            let vn = if pair.restitution > 0.0 {
                let Some(r) = self.new_row() else { return };
                self.add_point_row(r, b2, c.pos, c.frame[0], 1.0);
                self.add_point_row(r, b1, c.pos, c.frame[0], -1.0);
                self.nefc -= 1;
                self.row_velocity(r)
            } else {
                0.0
            };
            for (e, &(sign, t)) in rows.iter().enumerate() {
                let Some(r) = self.new_row() else { return };
                if elliptic {
                    let u = c.frame[t];
                    self.add_point_row(r, b2, c.pos, u, 1.0);
                    self.add_point_row(r, b1, c.pos, u, -1.0);
                    self.efc_kind[r] = RowKind::Contact {
                        contact: ci,
                        edge: e as u8,
                        frictionless: false,
                    };
                    if t == 0 {
                        self.set_row(r, r_viol, imp, kk, bb, tran);
                        self.restitute(r, pair.restitution, vn, h);
                    } else {
                        self.set_row(r, 0.0, imp, 0.0, bb, tran);
                        self.efc_r[r] = self.efc_r[r - t] / m.opt.impratio;
                    }
                    continue;
                }
                let mut u = c.frame[0];
                if t > 0 {
                    u = add(u, scale(c.frame[t], sign * mu));
                }
                self.add_point_row(r, b2, c.pos, u, 1.0);
                self.add_point_row(r, b1, c.pos, u, -1.0);
                let diag = if pair.condim == 1 {
                    tran
                } else {
                    2.0 * mu * mu / m.opt.impratio * (1.0 + mu * mu) * tran
                };
                self.efc_kind[r] = RowKind::Contact {
                    contact: ci,
                    edge: e as u8,
                    frictionless: pair.condim == 1,
                };
                self.set_row(r, r_viol, imp, kk, bb, diag);
                self.restitute(r, pair.restitution, vn, h);
            }
        }
        for (j, jt) in m.joints.iter().enumerate() {
            let Some([lo, hi]) = jt.range else { continue };
            let qa = m.jnt_qposadr[j];
            let d = m.jnt_dofadr[j];
            let q = self.qpos[qa];
            for (dist, sign, upper) in [(q - lo, 1.0, false), (hi - q, -1.0, true)] {
                if dist >= jt.margin {
                    continue;
                }
                let Some(r) = self.new_row() else { return };
                self.efc_j[r * nv + d] = sign;
                let viol = dist - jt.margin;
                let imp = impedance(&jt.solimp_limit, viol.abs());
                let (kk, bb) = stiffness_damping(&jt.solref_limit, &jt.solimp_limit, h);
                self.efc_kind[r] = RowKind::Limit { joint: j, upper };
                self.set_row(r, viol, imp, kk, bb, m.dof_invweight0[d]);
                self.restitute(r, jt.restitution, sign * self.qvel[d], h);
            }
        }
    }

    /// The next row, its Jacobian cleared and unbounded above (`None` when all are in use).
    fn new_row(&mut self) -> Option<usize> {
        let r = self.nefc;
        if r >= self.efc_kind.len() {
            return None;
        }
        self.nefc += 1;
        let nv = self.model.nv;
        self.efc_j[r * nv..(r + 1) * nv].fill(0.0);
        self.efc_bound[r] = f64::INFINITY;
        Some(r)
    }

    /// `Jᵣ v`.
    fn row_velocity(&self, r: usize) -> f64 {
        let nv = self.model.nv;
        self.efc_j[r * nv..(r + 1) * nv]
            .iter()
            .zip(&self.qvel)
            .map(|(a, v)| a * v)
            .sum()
    }

    /// Restitution `e` of row `r` approached at normal speed `vn`.
    fn restitute(&mut self, r: usize, e: f64, vn: f64, h: f64) {
        if e > 0.0 && vn < 0.0 {
            self.efc_aref[r] = self.efc_aref[r].max(-(1.0 + e) * vn / h);
        }
    }

    /// Reference acceleration and regularizer of row `r`.
    fn set_row(&mut self, r: usize, viol: f64, imp: f64, k: f64, b: f64, diag: f64) {
        let vel = self.row_velocity(r);
        self.efc_aref[r] = -b * vel - k * imp * viol;
        self.efc_r[r] = ((1.0 - imp) / imp * diag).max(1e-15);
    }

    /// The constraint forces of the current rows: `qacc` holds the unconstrained acceleration on
    /// entry (with `qld` the factor of `M`) when `smooth_solved` (forward solved for it), and the
    /// constrained one on return, `efc_force` the rows' forces and `qfrc_constraint = Jᵀ f`.
    /// Newton on the primal for pyramidal cones, projected Gauss–Seidel on the dual for elliptic
    /// ones. `false` if a factorization fails.
    pub(crate) fn solve_constraints(&mut self, smooth_solved: bool) -> bool {
        let n = self.nefc;
        self.qfrc_constraint.fill(0.0);
        self.solver_sweeps = 0;
        for r in 0..n {
            self.efc_class[r] = if self.efc_bound[r].is_finite() {
                1
            } else if let RowKind::Equality { .. } = self.efc_kind[r] {
                2
            } else {
                0
            };
        }
        if self.model.solves_dual() {
            if n == 0 {
                self.warm_count = 0;
                return true;
            }
            self.solve_dual();
            true
        } else {
            self.solve_newton(smooth_solved)
        }
    }

    /// Newton's method on the primal (MuJoCo's default solver), started from the previous
    /// solve's acceleration (from `a₀` when forward solved for it: no warm start, or no rows):
    /// minimize over `a` the convex, piecewise-quadratic
    /// `½ aᵀ M a − aᵀ qfrc_smooth + Σᵢ sᵢ(Jᵢ a − arefᵢ)`, each row's `sᵢ(x)` the cost whose
    /// derivative is minus its force: `½ x²/Rᵢ` below 0 and 0 above for rows with `f ≥ 0`,
    /// `½ x²/Rᵢ` for equalities, and for dry friction (`|f| ≤ F`) the quadratic within
    /// `|x| ≤ R F` continued linearly (`F|x| − ½ R F²`) outside. Each iteration solves the
    /// Newton system `(M + Jᵀ D J) δ = −∇` (`D = 1/R` on the rows in their quadratic zone; its
    /// `nv × nv` Cholesky factor is kept while that set does not change) and minimizes the cost
    /// along `δ` exactly (the cost is a piecewise quadratic of the step: safeguarded 1-D Newton).
    /// It stops as MuJoCo does, when the cost's decrease or the gradient's norm, scaled by
    /// `1 / (mean diag M · nv)`, falls below `tolerance`. `false` if a factorization fails (`M`
    /// is not positive definite).
    fn solve_newton(&mut self, smooth_solved: bool) -> bool {
        let model = std::sync::Arc::clone(&self.model);
        let m = &*model;
        let nv = m.nv;
        let n = self.nefc;
        let mut nt = std::mem::take(&mut self.newton);
        let frc = &self.qfrc_smooth;
        let qm = &self.qm;
        let qld = &self.qld;
        let jac = &self.efc_j[..n * nv];
        let aref = &self.efc_aref[..n];
        let reg = &self.efc_r[..n];
        let bound = &self.efc_bound[..n];
        let class = &self.efc_class[..n];
        let mean_inertia = (0..nv).map(|k| qm[k * nv + k]).sum::<f64>() / nv.max(1) as f64;
        let scale = 1.0 / (mean_inertia * nv.max(1) as f64);
        let mat_vec = |x: &[f64], out: &mut [f64]| sym_mat_vec(qm, nv, x, out);
        // The start: a₀ when forward solved it (no warm start), else the warm start. `ma` is
        // the smooth cost's gradient `M a − qfrc_smooth` (0 at a₀).
        if smooth_solved {
            nt.a[..nv].copy_from_slice(&self.qacc_smooth);
            nt.ma[..nv].fill(0.0);
        } else {
            nt.a[..nv].copy_from_slice(&nt.warm[..nv]);
            mat_vec(&nt.a[..nv], &mut nt.ma[..nv]);
            for (g, f) in nt.ma[..nv].iter_mut().zip(frc) {
                *g -= f;
            }
        }
        jac_mul(jac, nv, &nt.a[..nv], &mut nt.jar[..n]);
        for (x, a) in nt.jar[..n].iter_mut().zip(aref) {
            *x -= a;
        }
        // The smooth cost ½ aᵀ M a − aᵀ qfrc_smooth = ½ aᵀ (ma − qfrc_smooth).
        let smooth_cost = |a: &[f64], ma: &[f64]| -> f64 {
            0.5 * a.iter().zip(ma).zip(frc).map(|((a, g), f)| a * (g - f)).sum::<f64>()
        };
        let mut cost = smooth_cost(&nt.a[..nv], &nt.ma[..nv])
            + (0..n)
                .map(|r| row_cost(class[r], reg[r], bound[r], nt.jar[r]))
                .sum::<f64>();
        let mut factored = false;
        for _ in 0..if n == 0 { 0 } else { m.opt.iterations } {
            // Forces, the quadratic zone and the gradient M a − qfrc_smooth − Jᵀ f at a.
            let mut changed = !factored;
            nt.grad[..nv].copy_from_slice(&nt.ma[..nv]);
            for r in 0..n {
                let (f, quad) = row_force(class[r], reg[r], bound[r], nt.jar[r]);
                if quad != nt.active[r] {
                    nt.active[r] = quad;
                    changed = true;
                }
                if f != 0.0 {
                    for (g, j) in nt.grad[..nv].iter_mut().zip(&jac[r * nv..(r + 1) * nv]) {
                        *g -= j * f;
                    }
                }
            }
            if scale * dot_n(&nt.grad[..nv], &nt.grad[..nv]).sqrt() < m.opt.tolerance {
                break;
            }
            for k in 0..nv {
                nt.dir[k] = -nt.grad[k];
            }
            if changed {
                // H = M + Σ (1/Rᵣ) Jᵣᵀ Jᵣ over the quadratic zone, factored: row `q` of H's upper
                // triangle gets `(d jₚ) j_q` for `p = q, …, last` (the row's last nonzero entry;
                // contiguous, vectorized) for every `j_q ≠ 0`. With no row in the quadratic zone
                // H is M, whose factor `qld` is taken as it is.
                if nt.active[..n].iter().any(|&a| a) {
                    nt.h[..nv * nv].copy_from_slice(qm);
                    for r in 0..n {
                        if !nt.active[r] {
                            continue;
                        }
                        let j = &jac[r * nv..(r + 1) * nv];
                        let Some(first) = j.iter().position(|x| *x != 0.0) else {
                            continue;
                        };
                        let last = j.iter().rposition(|x| *x != 0.0).unwrap_or(first);
                        let d = 1.0 / reg[r];
                        for (dj, &jp) in nt.dj[first..=last].iter_mut().zip(&j[first..=last]) {
                            *dj = d * jp;
                        }
                        for q in first..=last {
                            let jq = j[q];
                            if jq == 0.0 {
                                continue;
                            }
                            let hq = &mut nt.h[q * nv + q..q * nv + last + 1];
                            for (h, &djp) in hq.iter_mut().zip(&nt.dj[q..=last]) {
                                *h += djp * jq;
                            }
                        }
                    }
                    if !cholesky_and_solve(&mut nt.h[..nv * nv], nv, &mut nt.dir[..nv]) {
                        self.newton = nt;
                        return false;
                    }
                } else if smooth_solved {
                    nt.h[..nv * nv].copy_from_slice(qld);
                    cholesky_solve(&nt.h[..nv * nv], nv, &mut nt.dir[..nv]);
                } else {
                    nt.h[..nv * nv].copy_from_slice(qm);
                    if !cholesky_and_solve(&mut nt.h[..nv * nv], nv, &mut nt.dir[..nv]) {
                        self.newton = nt;
                        return false;
                    }
                }
                factored = true;
            } else {
                cholesky_solve(&nt.h[..nv * nv], nv, &mut nt.dir[..nv]);
            }
            mat_vec(&nt.dir[..nv], &mut nt.mdir[..nv]);
            jac_mul(jac, nv, &nt.dir[..nv], &mut nt.jdir[..n]);
            let alpha = line_search(&nt, n, nv, class, reg, bound);
            if !(alpha > 0.0) {
                break;
            }
            self.solver_sweeps += 1;
            for k in 0..nv {
                nt.a[k] += alpha * nt.dir[k];
                nt.ma[k] += alpha * nt.mdir[k];
            }
            for r in 0..n {
                nt.jar[r] += alpha * nt.jdir[r];
            }
            let mut new_cost = smooth_cost(&nt.a[..nv], &nt.ma[..nv]);
            for r in 0..n {
                new_cost += row_cost(class[r], reg[r], bound[r], nt.jar[r]);
            }
            let improvement = scale * (cost - new_cost);
            cost = new_cost;
            if improvement < m.opt.tolerance {
                break;
            }
        }
        for r in 0..n {
            let f = row_force(class[r], reg[r], bound[r], nt.jar[r]).0;
            self.efc_force[r] = f;
            if f != 0.0 {
                for (q, j) in self.qfrc_constraint.iter_mut().zip(&jac[r * nv..(r + 1) * nv]) {
                    *q += j * f;
                }
            }
        }
        self.qacc.copy_from_slice(&nt.a[..nv]);
        nt.warm[..nv].copy_from_slice(&nt.a[..nv]);
        nt.warm_valid = true;
        self.newton = nt;
        true
    }

    /// Projected Gauss–Seidel on the dual, warm-started (elliptic cones).
    /// The sweeps run on the Delassus matrix `A = J M⁻¹ Jᵀ` (rows × rows), each row update
    /// `fᵢ ← max(0, fᵢ − (bᵢ + (A f)ᵢ + Rᵢ fᵢ) / (Aᵢᵢ + Rᵢ))` with `b = J a₀ − aref`, a contact's
    /// three forces as one block.
    fn solve_dual(&mut self) {
        let m = &*self.model;
        let nv = m.nv;
        let n = self.nefc;
        // W = M⁻¹ Jᵀ row by row, four rows' solves at a time.
        let mut group = [0usize; 4];
        let mut count = 0;
        let mut first = nv;
        let mut r = 0;
        while r < n || count > 0 {
            if r < n {
                let row = r;
                r += 1;
                let j = &self.efc_j[row * nv..(row + 1) * nv];
                first = first.min(j.iter().position(|x| *x != 0.0).unwrap_or(nv));
                for (t, x) in self.solve4.iter_mut().zip(j) {
                    t[count] = *x;
                }
                group[count] = row;
                count += 1;
                if count < 4 {
                    continue;
                }
            } else {
                // The last group's empty lanes repeat its first row.
                for t in &mut self.solve4[..nv] {
                    for lane in count..4 {
                        t[lane] = t[0];
                    }
                }
            }
            cholesky_solve4(&self.qld, nv, &mut self.solve4, first);
            for (lane, &row) in group[..count].iter().enumerate() {
                for (w, t) in self.efc_w[row * nv..(row + 1) * nv].iter_mut().zip(&self.solve4) {
                    *w = t[lane];
                }
            }
            count = 0;
            first = nv;
        }
        for r in 0..n {
            let j = &self.efc_j[r * nv..(r + 1) * nv];
            // The row's nonzero entries (a kinematic tree's row touches only the dofs on the
            // contact bodies' paths to the root); the products left out are exact zeros.
            let mut nnz = 0;
            for (k, x) in j.iter().enumerate() {
                if *x != 0.0 {
                    self.efc_nz[nnz] = k;
                    nnz += 1;
                }
            }
            let nz = &self.efc_nz[..nnz];
            for c in 0..=r {
                let w = &self.efc_w[c * nv..(c + 1) * nv];
                let a = nz.iter().fold(-0.0, |s, &k| s + j[k] * w[k]);
                self.efc_a[r * n + c] = a;
                self.efc_a[c * n + r] = a;
            }
            let a0: f64 = j.iter().zip(&self.qacc).map(|(x, y)| x * y).sum();
            self.efc_b[r] = a0 - self.efc_aref[r];
            self.efc_inv[r] = 1.0 / (self.efc_a[r * n + r] + self.efc_r[r]);
            // Warm start from the previous solve's force of the same row.
            let key = self.row_key(r);
            self.efc_force[r] = self.warm[..self.warm_count]
                .iter()
                .find(|(k, _)| *k == key)
                .map_or(0.0, |(_, f)| *f);
        }
        // g = b + A f, kept current as forces change (a row whose force does not move costs
        // nothing).
        for r in 0..n {
            let row = &self.efc_a[r * n..(r + 1) * n];
            let af: f64 = row.iter().zip(&self.efc_force[..n]).map(|(a, f)| a * f).sum();
            self.efc_g[r] = self.efc_b[r] + af;
        }
        self.elliptic_sweeps();
        for r in 0..n {
            let f = self.efc_force[r];
            if f == 0.0 {
                continue;
            }
            let (j, w) = (&self.efc_j[r * nv..(r + 1) * nv], &self.efc_w[r * nv..(r + 1) * nv]);
            for k in 0..nv {
                self.qfrc_constraint[k] += j[k] * f;
                self.qacc[k] += w[k] * f;
            }
        }
        self.warm_count = 0;
        for r in 0..n.min(self.warm.len()) {
            self.warm[r] = (self.row_key(r), self.efc_force[r]);
            self.warm_count += 1;
        }
    }

    /// Set row `r`'s force to `new`, keeping `g = b + A f` current; returns the change.
    fn move_force(&mut self, r: usize, new: f64) -> f64 {
        let n = self.nefc;
        let d = new - self.efc_force[r];
        if d != 0.0 {
            self.efc_force[r] = new;
            let col = &self.efc_a[r * n..(r + 1) * n];
            for (g, a) in self.efc_g[..n].iter_mut().zip(col) {
                *g += a * d;
            }
        }
        d
    }

    /// The sweeps of a model with elliptic cones: the rows of a contact with friction (its
    /// normal, then its two tangents) are updated as a block, every other row on its own
    /// (projected on `f ≥ 0`, or on `±bound` for dry friction).
    fn elliptic_sweeps(&mut self) {
        let model = std::sync::Arc::clone(&self.model);
        let m = &*model;
        let n = self.nefc;
        for _ in 0..m.opt.iterations {
            self.solver_sweeps += 1;
            let mut change = 0.0f64;
            let mut scale_f = 0.0f64;
            let mut r = 0;
            while r < n {
                let block = matches!(
                    self.efc_kind[r],
                    RowKind::Contact {
                        edge: 0,
                        frictionless: false,
                        ..
                    }
                );
                if !block {
                    let old = self.efc_force[r];
                    let grad = self.efc_g[r] + self.efc_r[r] * old;
                    let bound = self.efc_bound[r];
                    let new = if bound.is_finite() {
                        (old - grad * self.efc_inv[r]).clamp(-bound, bound)
                    } else {
                        (old - grad * self.efc_inv[r]).max(0.0)
                    };
                    change = change.max(self.move_force(r, new).abs());
                    scale_f = scale_f.max(new.abs());
                    r += 1;
                    continue;
                }
                let RowKind::Contact { contact, .. } = self.efc_kind[r] else {
                    unreachable!()
                };
                let mu = m.pairs[self.contacts[contact].pair].friction;
                // ½ xᵀ H x + cᵀ x over the contact's three forces, the gradient at the current
                // forces x0 the rows' current one.
                let rows = [r, r + 1, r + 2];
                let x0 = rows.map(|i| self.efc_force[i]);
                let mut hm = [[0.0; 3]; 3];
                for (a, &i) in rows.iter().enumerate() {
                    for (b, &j) in rows.iter().enumerate() {
                        hm[a][b] = self.efc_a[i * n + j];
                    }
                    hm[a][a] += self.efc_r[i];
                }
                let mut c = [0.0; 3];
                for a in 0..3 {
                    let g0 = self.efc_g[rows[a]] + self.efc_r[rows[a]] * x0[a];
                    c[a] = g0 - (0..3).map(|b| hm[a][b] * x0[b]).sum::<f64>();
                }
                let x = cone_qp(&hm, &c, mu, x0);
                for (k, &row) in rows.iter().enumerate() {
                    change = change.max(self.move_force(row, x[k]).abs());
                    scale_f = scale_f.max(x[k].abs());
                }
                r += 3;
            }
            if change <= m.opt.tolerance * scale_f.max(1.0) {
                break;
            }
        }
    }

    fn row_key(&self, r: usize) -> u64 {
        match self.efc_kind[r] {
            RowKind::Contact { contact, edge, .. } => {
                let c = &self.contacts[contact];
                ((c.pair as u64) << 8) | ((c.sub as u64) << 3) | edge as u64
            }
            RowKind::Limit { joint, upper } => (1u64 << 63) | ((joint as u64) << 1) | upper as u64,
            RowKind::Friction { joint } => (1u64 << 62) | joint as u64,
            RowKind::DryFriction { body, axis } => (3u64 << 61) | ((body as u64) << 1) | axis as u64,
            RowKind::Equality { eq } => (5u64 << 60) | eq as u64,
            RowKind::None => u64::MAX,
        }
    }

    /// World force on body 2 of each contact of the last solve (normal plus friction).
    pub(crate) fn contact_force(&self, ci: usize) -> V3 {
        let m = &*self.model;
        let c = &self.contacts[ci];
        let mu = m.pairs[c.pair].friction;
        let mut f = [0.0; 3];
        for r in 0..self.nefc {
            if let RowKind::Contact {
                contact,
                edge,
                frictionless,
            } = self.efc_kind[r]
                && contact == ci
            {
                let fr = self.efc_force[r];
                if m.opt.cone == Cone::Elliptic {
                    f = add(f, scale(c.frame[edge as usize], fr));
                    continue;
                }
                f = add(f, scale(c.frame[0], fr));
                if !frictionless {
                    let (t, s) = match edge {
                        0 => (1, 1.0),
                        1 => (1, -1.0),
                        2 => (2, 1.0),
                        _ => (2, -1.0),
                    };
                    f = add(f, scale(c.frame[t], s * mu * fr));
                }
            }
        }
        let _ = dot;
        f
    }
}

/// The Newton solver's warm start and scratch: the acceleration `a`, `M a − qfrc_smooth`, the
/// gradient, the direction `δ` with `M δ`, the factor of `M + Jᵀ D J`, and per row `J a − aref`,
/// `J δ` and whether the row is in its quadratic zone.
#[derive(Debug, Clone, Default)]
pub(crate) struct Newton {
    a: Vec<f64>,
    ma: Vec<f64>,
    grad: Vec<f64>,
    dir: Vec<f64>,
    mdir: Vec<f64>,
    h: Vec<f64>,
    warm: Vec<f64>,
    pub(crate) warm_valid: bool,
    jar: Vec<f64>,
    jdir: Vec<f64>,
    active: Vec<bool>,
    /// A Hessian row's Jacobian entries times `1/R`.
    dj: Vec<f64>,
}

impl Newton {
    pub(crate) fn new(nv: usize, rows: usize) -> Self {
        Newton {
            a: vec![0.0; nv],
            ma: vec![0.0; nv],
            grad: vec![0.0; nv],
            dir: vec![0.0; nv],
            mdir: vec![0.0; nv],
            h: vec![0.0; nv * nv],
            warm: vec![0.0; nv],
            warm_valid: false,
            jar: vec![0.0; rows],
            jdir: vec![0.0; rows],
            active: vec![false; rows],
            dj: vec![0.0; nv],
        }
    }
}

/// `out = J x` for the row-major `J` (`out.len()` rows of `nv`): each row's sum runs over
/// `k = 0, …, nv − 1` in order (the bits of `dot_n` per row), four rows at a time so that their
/// independent sums overlap.
fn jac_mul(jac: &[f64], nv: usize, x: &[f64], out: &mut [f64]) {
    let n = out.len();
    let x = &x[..nv];
    let mut r = 0;
    while r + 4 <= n {
        let rows = &jac[r * nv..(r + 4) * nv];
        let (j0, rest) = rows.split_at(nv);
        let (j1, rest) = rest.split_at(nv);
        let (j2, j3) = rest.split_at(nv);
        let mut acc = [-0.0f64; 4];
        for k in 0..nv {
            let xk = x[k];
            acc[0] += j0[k] * xk;
            acc[1] += j1[k] * xk;
            acc[2] += j2[k] * xk;
            acc[3] += j3[k] * xk;
        }
        out[r..r + 4].copy_from_slice(&acc);
        r += 4;
    }
    for (o, row) in out[r..].iter_mut().zip(jac[r * nv..n * nv].chunks_exact(nv)) {
        *o = dot_n(row, x);
    }
}

fn dot_n(x: &[f64], y: &[f64]) -> f64 {
    x.iter().zip(y).map(|(p, q)| p * q).sum()
}

/// A row's force at `x = J a − aref` and whether `x` is in the row's quadratic zone (class as
/// `efc_class`, regularizer `r`, dry friction's bound `bound`).
#[inline]
fn row_force(class: u8, r: f64, bound: f64, x: f64) -> (f64, bool) {
    match class {
        0 => {
            if x < 0.0 {
                (-x / r, true)
            } else {
                (0.0, false)
            }
        }
        1 => {
            let f = -x / r;
            if f > bound {
                (bound, false)
            } else if f < -bound {
                (-bound, false)
            } else {
                (f, true)
            }
        }
        _ => (-x / r, true),
    }
}

/// A row's cost at `x` (its derivative is minus [`row_force`]'s force).
#[inline]
fn row_cost(class: u8, r: f64, bound: f64, x: f64) -> f64 {
    match class {
        0 => {
            if x < 0.0 {
                0.5 * x * x / r
            } else {
                0.0
            }
        }
        1 => {
            let rf = r * bound;
            if x > rf {
                bound * x - 0.5 * rf * bound
            } else if x < -rf {
                -bound * x - 0.5 * rf * bound
            } else {
                0.5 * x * x / r
            }
        }
        _ => 0.5 * x * x / r,
    }
}

/// The step `α ≥ 0` minimizing the cost along the Newton direction (`nt.dir`, with `nt.mdir` and
/// `nt.jdir`), exactly up to rounding: the cost is convex and piecewise quadratic in `α`, so 1-D
/// Newton on its derivative, kept inside a bracket (bisection when a step leaves it), lands on
/// the minimum once it reaches the minimum's piece. 0 if `δ` is not a descent direction.
fn line_search(nt: &Newton, n: usize, nv: usize, class: &[u8], reg: &[f64], bound: &[f64]) -> f64 {
    let g0 = dot_n(&nt.dir[..nv], &nt.ma[..nv]);
    let q0 = dot_n(&nt.dir[..nv], &nt.mdir[..nv]);
    // The derivative and second derivative of the cost at α.
    let eval = |alpha: f64| -> (f64, f64) {
        let (mut d1, mut d2) = (g0 + alpha * q0, q0);
        for r in 0..n {
            let v = nt.jdir[r];
            if v == 0.0 {
                continue;
            }
            let (f, quad) = row_force(class[r], reg[r], bound[r], nt.jar[r] + alpha * v);
            d1 -= f * v;
            if quad {
                d2 += v * v / reg[r];
            }
        }
        (d1, d2)
    };
    let (d0, _) = eval(0.0);
    if !(d0 < 0.0) {
        return 0.0;
    }
    let (mut lo, mut hi) = (0.0f64, f64::INFINITY);
    let mut alpha = 1.0;
    let mut best = 0.0;
    for _ in 0..60 {
        let (d1, d2) = eval(alpha);
        if d1 < 0.0 {
            lo = alpha;
            best = alpha;
        } else {
            hi = alpha;
        }
        if d1.abs() <= 1e-12 * d0.abs() {
            return alpha;
        }
        let next = alpha - d1 / d2;
        alpha = if next > lo && next < hi {
            next
        } else if hi.is_finite() {
            0.5 * (lo + hi)
        } else {
            2.0 * alpha
        };
        if hi - lo <= 1e-15 * hi {
            break;
        }
    }
    if hi.is_finite() { 0.5 * (lo + hi) } else { best }
}

/// The minimizer of `½ fᵀ H f + cᵀ f` (`H` 3×3 symmetric positive definite) over the cone
/// `{f₀ ≥ 0, ‖(f₁, f₂)‖ ≤ μ f₀}`: the unconstrained minimizer if it lies in the cone; else the
/// best point of the cone's surface, `s·(1, μ cos θ, μ sin θ)` with `s ≥ 0` optimal in closed form
/// for each direction θ, θ found by a scan of the circle (and the current force's direction)
/// refined by golden-section search. A strictly convex problem's minimizer over the cone.
fn cone_qp(h: &[[f64; 3]; 3], c: &[f64; 3], mu: f64, x0: [f64; 3]) -> [f64; 3] {
    if let Some(x) = solve3(h, c)
        && x[0] >= 0.0
        && x[1].hypot(x[2]) <= mu * x[0]
    {
        return x;
    }
    if mu <= 0.0 {
        let s = (-c[0] / h[0][0]).max(0.0);
        return [s, 0.0, 0.0];
    }
    // The best point along direction θ and its value.
    let along = |t: f64| {
        let v = [1.0, mu * t.cos(), mu * t.sin()];
        let cv = c[0] * v[0] + c[1] * v[1] + c[2] * v[2];
        let mut vhv = 0.0;
        for a in 0..3 {
            for b in 0..3 {
                vhv += v[a] * h[a][b] * v[b];
            }
        }
        let s = (-cv / vhv).max(0.0);
        (0.5 * s * s * vhv + s * cv, s, v)
    };
    const SCAN: usize = 32;
    let step = std::f64::consts::TAU / SCAN as f64;
    let mut best = (f64::INFINITY, 0.0);
    for k in 0..SCAN {
        let t = k as f64 * step;
        let (q, ..) = along(t);
        if q < best.0 {
            best = (q, t);
        }
    }
    if x0[1] != 0.0 || x0[2] != 0.0 {
        let t = x0[2].atan2(x0[1]);
        let (q, ..) = along(t);
        if q < best.0 {
            best = (q, t);
        }
    }
    if best.0 >= 0.0 {
        return [0.0; 3];
    }
    let (mut a, mut b) = (best.1 - step, best.1 + step);
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let (mut x1, mut x2) = (b - g * (b - a), a + g * (b - a));
    let (mut f1, mut f2) = (along(x1).0, along(x2).0);
    for _ in 0..80 {
        if f1 < f2 {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = b - g * (b - a);
            f1 = along(x1).0;
        } else {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = a + g * (b - a);
            f2 = along(x2).0;
        }
        if b - a < 1e-13 {
            break;
        }
    }
    let (_, s, v) = along(0.5 * (a + b));
    [s * v[0], s * v[1], s * v[2]]
}

/// `−H⁻¹ c` of a 3×3 `H` (`None` if singular).
fn solve3(h: &[[f64; 3]; 3], c: &[f64; 3]) -> Option<[f64; 3]> {
    let det = h[0][0] * (h[1][1] * h[2][2] - h[1][2] * h[2][1]) - h[0][1] * (h[1][0] * h[2][2] - h[1][2] * h[2][0])
        + h[0][2] * (h[1][0] * h[2][1] - h[1][1] * h[2][0]);
    if !(det.abs() > 1e-300) {
        return None;
    }
    let mut x = [0.0; 3];
    for (k, xk) in x.iter_mut().enumerate() {
        let mut m = *h;
        for row in 0..3 {
            m[row][k] = c[row];
        }
        let d = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
        *xk = -d / det;
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    use super::{cone_qp, solve3};

    /// Inside the cone the unconstrained minimizer; outside, a point of the surface no better
    /// than any other surface point nearby (checked on a fine circle of directions).
    #[test]
    fn cone_qp_is_the_constrained_minimizer() {
        let h = [[2.0, 0.3, 0.1], [0.3, 1.0, 0.2], [0.1, 0.2, 1.5]];
        let q = |f: [f64; 3], c: [f64; 3]| {
            let mut v = 0.0;
            for a in 0..3 {
                v += c[a] * f[a];
                for b in 0..3 {
                    v += 0.5 * f[a] * h[a][b] * f[b];
                }
            }
            v
        };
        let c = [-1.0, 0.1, -0.05];
        let x = cone_qp(&h, &c, 1.0, [0.0; 3]);
        assert_eq!(Some(x), solve3(&h, &c));
        let c = [-1.0, 3.0, -2.0];
        let x = cone_qp(&h, &c, 0.5, [0.0; 3]);
        assert!((x[1].hypot(x[2]) - 0.5 * x[0]).abs() < 1e-12 && x[0] > 0.0);
        for k in 0..3600 {
            let t = k as f64 * std::f64::consts::TAU / 3600.0;
            for s in [0.5 * x[0], x[0], 1.5 * x[0]] {
                let f = [s, 0.5 * s * t.cos(), 0.5 * s * t.sin()];
                assert!(q(f, c) >= q(x, c) - 1e-12);
            }
        }
        assert_eq!(cone_qp(&h, &[1.0, 0.0, 0.0], 0.5, [0.0; 3]), [0.0; 3]);
    }
}
