//! Smooth dynamics on world-frame spatial vectors (about the world origin, so no frame
//! transforms between bodies): forward kinematics with MuJoCo's joint semantics, the motion
//! subspace of every degree of freedom (`cdof`) and its time derivative (`cdof_dot`, built
//! incrementally along each body's joints as MuJoCo's `mj_comVel`), the composite-rigid-body
//! mass matrix (only ancestor pairs are visited), recursive Newton–Euler bias forces
//! (Coriolis, centrifugal, gravity), passive forces (joint and tendon springs and damping,
//! the medium's drag), actuator forces (MuJoCo's general actuators) and
//! the dense Cholesky factorization of the small joint-space systems.

use crate::data::Data;
use crate::math::{
    IDENTITY, Inertia, QUAT_IDENTITY, ZERO3, add, add6, col, cross, cross_force, cross_motion, dot6, join, mat_mul,
    mat_t_vec, mat_vec, quat_axis_angle, quat_mul, quat_normalize, quat_rotate, quat_to_mat, rotate_diag, scale,
};
use crate::model::{JointKind, Model};

impl Data {
    /// Body and geom poses, centres of mass, spatial inertias and each dof's motion subspace
    /// from `qpos` (nothing to do when they are of the same `qpos` bits already).
    pub(crate) fn kinematics(&mut self) {
        if self.kin_valid && self.kin_qpos.iter().zip(&self.qpos).all(|(b, q)| *b == q.to_bits()) {
            return;
        }
        self.compute_kinematics();
        for (b, q) in self.kin_qpos.iter_mut().zip(&self.qpos) {
            *b = q.to_bits();
        }
        self.kin_valid = true;
        self.vel_valid = false;
    }

    fn compute_kinematics(&mut self) {
        let m = &*self.model;
        self.xpos[0] = ZERO3;
        self.xquat[0] = QUAT_IDENTITY;
        self.xmat[0] = IDENTITY;
        // As MuJoCo's `mj_kinematics`: a body's frame from its parent's, then each joint in turn
        // on the quaternion (axes and anchors rotated by it), which is normalized and turned
        // into the rotation matrix once, after the body's last joint.
        for b in 1..m.bodies.len() {
            let body = &m.bodies[b];
            let p = body.parent;
            let mut pos = add(self.xpos[p], mat_vec(&self.xmat[p], body.pos));
            let mut quat = quat_mul(self.xquat[p], body.quat);
            for j in m.body_joints[b].clone() {
                let jt = &m.joints[j];
                let qa = m.jnt_qposadr[j];
                let da = m.jnt_dofadr[j];
                match jt.kind {
                    JointKind::Free => {
                        pos = [self.qpos[qa], self.qpos[qa + 1], self.qpos[qa + 2]];
                        quat = quat_normalize([
                            self.qpos[qa + 3],
                            self.qpos[qa + 4],
                            self.qpos[qa + 5],
                            self.qpos[qa + 6],
                        ]);
                        let r = quat_to_mat(quat);
                        let anchor = add(pos, quat_rotate(quat, jt.pos));
                        for k in 0..3 {
                            let mut e = ZERO3;
                            e[k] = 1.0;
                            self.cdof[da + k] = join(ZERO3, e);
                            let axis = col(&r, k);
                            self.cdof[da + 3 + k] = join(axis, cross(anchor, axis));
                        }
                    }
                    JointKind::Hinge => {
                        let anchor = add(pos, quat_rotate(quat, jt.pos));
                        let axis = quat_rotate(quat, jt.axis);
                        self.cdof[da] = join(axis, cross(anchor, axis));
                        quat = quat_mul(quat, quat_axis_angle(jt.axis, self.qpos[qa] - jt.qpos0));
                        pos = crate::math::sub(anchor, quat_rotate(quat, jt.pos));
                    }
                    JointKind::Slide => {
                        let axis = quat_rotate(quat, jt.axis);
                        self.cdof[da] = join(ZERO3, axis);
                        pos = add(pos, scale(axis, self.qpos[qa] - jt.qpos0));
                    }
                }
            }
            let quat = quat_normalize(quat);
            let r = quat_to_mat(quat);
            self.xpos[b] = pos;
            self.xquat[b] = quat;
            self.xmat[b] = r;
            self.xipos[b] = add(pos, mat_vec(&r, body.ipos));
            let ri = mat_mul(&r, &m.body_imat[b]);
            self.cinert[b] = Inertia::new(body.mass, self.xipos[b], &rotate_diag(&ri, body.inertia));
        }
        for (g, geom) in m.geoms.iter().enumerate() {
            let b = geom.body;
            self.geom_xpos[g] = add(self.xpos[b], mat_vec(&self.xmat[b], geom.pos));
            self.geom_xmat[g] = mat_mul(&self.xmat[b], &m.geom_mat[g]);
        }
    }

    /// Body velocities and each dof's `cdof_dot` from `qvel` (as MuJoCo's `mj_comVel`: a
    /// joint's `cdof_dot` is the body velocity accumulated before it crossed with its `cdof`;
    /// a free joint's translations have none). Nothing to do when they are of the same poses
    /// and `qvel` bits already.
    pub(crate) fn velocities(&mut self) {
        if self.vel_valid && self.vel_qvel.iter().zip(&self.qvel).all(|(b, v)| *b == v.to_bits()) {
            return;
        }
        self.compute_velocities();
        for (b, v) in self.vel_qvel.iter_mut().zip(&self.qvel) {
            *b = v.to_bits();
        }
        self.vel_valid = true;
    }

    fn compute_velocities(&mut self) {
        let m = &*self.model;
        self.cvel[0] = [0.0; 6];
        for b in 1..m.bodies.len() {
            let mut cv = self.cvel[m.bodies[b].parent];
            for j in m.body_joints[b].clone() {
                let da = m.jnt_dofadr[j];
                match m.joints[j].kind {
                    JointKind::Free => {
                        for k in 0..3 {
                            self.cdof_dot[da + k] = [0.0; 6];
                            add6(&mut cv, &self.cdof[da + k], self.qvel[da + k]);
                        }
                        for k in 3..6 {
                            self.cdof_dot[da + k] = cross_motion(&cv, &self.cdof[da + k]);
                        }
                        for k in 3..6 {
                            add6(&mut cv, &self.cdof[da + k], self.qvel[da + k]);
                        }
                    }
                    _ => {
                        self.cdof_dot[da] = cross_motion(&cv, &self.cdof[da]);
                        add6(&mut cv, &self.cdof[da], self.qvel[da]);
                    }
                }
            }
            self.cvel[b] = cv;
        }
    }

    /// The mass matrix (armature on the diagonal) by composite rigid bodies, row-major `nv × nv`.
    pub(crate) fn mass_matrix(&mut self) {
        let m = &*self.model;
        let nv = m.nv;
        for b in 0..m.bodies.len() {
            self.crb[b] = self.cinert[b];
        }
        for b in (1..m.bodies.len()).rev() {
            let p = m.bodies[b].parent;
            let c = self.crb[b];
            self.crb[p].add(&c);
        }
        // Only ancestor pairs are written; every other entry stays the zero it was allocated
        // with.
        let qm = &mut self.qm[..nv * nv];
        for i in 0..nv {
            let f = self.crb[m.dof_body[i]].mul(&self.cdof[i]);
            for &j in m.dof_path(i) {
                let v = dot6(&self.cdof[j], &f);
                qm[i * nv + j] = v;
                qm[j * nv + i] = v;
            }
            qm[i * nv + i] += m.joints[m.dof_joint[i]].armature;
        }
    }

    /// Bias forces `C(q, v) v − gravity` by recursive Newton–Euler with zero joint
    /// accelerations (gravity as an upward acceleration of the world).
    pub(crate) fn bias_forces(&mut self) {
        let m = &*self.model;
        let g = m.opt.gravity;
        self.cacc[0] = join(ZERO3, scale(g, -1.0));
        for b in 1..m.bodies.len() {
            let mut a = self.cacc[m.bodies[b].parent];
            for j in m.body_joints[b].clone() {
                let da = m.jnt_dofadr[j];
                for d in da..da + m.joints[j].kind.nv() {
                    add6(&mut a, &self.cdof_dot[d], self.qvel[d]);
                }
            }
            self.cacc[b] = a;
            let i = &self.cinert[b];
            let mut f = i.mul(&a);
            let h = i.mul(&self.cvel[b]);
            add6(&mut f, &cross_force(&self.cvel[b], &h), 1.0);
            self.cfrc[b] = f;
        }
        for b in (1..m.bodies.len()).rev() {
            let p = m.bodies[b].parent;
            if p != 0 {
                let f = self.cfrc[b];
                add6(&mut self.cfrc[p], &f, 1.0);
            }
        }
        for d in 0..m.nv {
            self.qfrc_bias[d] = dot6(&self.cdof[d], &self.cfrc[m.dof_body[d]]);
        }
    }

    /// Passive forces: joint springs and damping, and the medium's viscous drag.
    pub(crate) fn passive_forces(&mut self) {
        let m = &*self.model;
        self.qfrc_passive.fill(0.0);
        for (j, jt) in m.joints.iter().enumerate() {
            let da = m.jnt_dofadr[j];
            for d in da..da + jt.kind.nv() {
                self.qfrc_passive[d] -= jt.damping * self.qvel[d];
            }
            if jt.kind != JointKind::Free && jt.stiffness != 0.0 {
                let qa = m.jnt_qposadr[j];
                self.qfrc_passive[da] -= jt.stiffness * (self.qpos[qa] - jt.springref);
            }
        }
        let (mu, rho) = (m.opt.viscosity, m.opt.density);
        if mu > 0.0 || rho > 0.0 {
            for b in 1..m.bodies.len() {
                let body = &m.bodies[b];
                if body.mass <= 0.0 || m.body_last_dof[b] == usize::MAX {
                    continue;
                }
                let wrench = self.fluid_wrench(b);
                for &k in m.dof_path(m.body_last_dof[b]) {
                    self.qfrc_passive[k] += dot6(&self.cdof[k], &wrench);
                }
            }
        }
        self.tendon_forces();
    }

    /// MuJoCo's inertia-box fluid model (`mj_inertiaBoxFluidModel`) on body `b`, as a world
    /// spatial force about the origin: the body is the box of its principal inertia (sides
    /// `sᵢ = √(6 (I_j + I_k − I_i) / m)`), moving with velocity `v − wind` at its centre of mass
    /// and angular velocity `ω`, both in the inertia frame. Viscosity: Stokes drag
    /// `−3π μ d v` and torque `−π μ d³ ω`, `d` the sides' mean; density: quadratic drag
    /// `−½ ρ s_j s_k |vᵢ| vᵢ` on each face pair and torque `−ρ sᵢ (s_j⁴ + s_k⁴) |ωᵢ| ωᵢ / 64`.
    fn fluid_wrench(&self, b: usize) -> [f64; 6] {
        let m = &*self.model;
        let body = &m.bodies[b];
        let (mu, rho) = (m.opt.viscosity, m.opt.density);
        let i = body.inertia;
        let side = |a: f64, b2: f64, c: f64| (6.0 * (a + b2 - c).max(1e-15) / body.mass).sqrt();
        let s = [side(i[1], i[2], i[0]), side(i[0], i[2], i[1]), side(i[0], i[1], i[2])];
        let c = self.xipos[b];
        let r = mat_mul(&self.xmat[b], &m.body_imat[b]);
        let (w, v0) = crate::math::split(&self.cvel[b]);
        let vc = crate::math::sub(add(v0, cross(w, c)), m.opt.wind);
        let lw = mat_t_vec(&r, w);
        let lv = mat_t_vec(&r, vc);
        let mut lt = [0.0; 3];
        let mut lf = [0.0; 3];
        if mu > 0.0 {
            let d = (s[0] + s[1] + s[2]) / 3.0;
            let pi = std::f64::consts::PI;
            lt = scale(lw, -pi * d * d * d * mu);
            lf = scale(lv, -3.0 * pi * d * mu);
        }
        if rho > 0.0 {
            for k in 0..3 {
                let (a, b2) = ((k + 1) % 3, (k + 2) % 3);
                lf[k] -= 0.5 * rho * s[a] * s[b2] * lv[k].abs() * lv[k];
                lt[k] -= rho * s[k] * (s[a].powi(4) + s[b2].powi(4)) * lw[k].abs() * lw[k] / 64.0;
            }
        }
        let f = mat_vec(&r, lf);
        let t = mat_vec(&r, lt);
        join(add(t, cross(c, f)), f)
    }

    /// Length and velocity of tendon `t` (`Σ coef · q`, `Σ coef · q̇`).
    fn tendon_state(&self, t: usize) -> (f64, f64) {
        let m = &*self.model;
        let (mut l, mut v) = (0.0, 0.0);
        for &(j, coef) in &m.tendons[t].joints {
            l += coef * self.qpos[m.jnt_qposadr[j]];
            v += coef * self.qvel[m.jnt_dofadr[j]];
        }
        (l, v)
    }

    /// Tendon lengths and velocities, and the tendons' passive forces (MuJoCo's dead-band
    /// spring on `lengthspring` and damping) added to `qfrc_passive`.
    pub(crate) fn tendon_forces(&mut self) {
        let m = &*self.model;
        for t in 0..m.tendons.len() {
            let (l, v) = self.tendon_state(t);
            self.ten_length[t] = l;
            self.ten_velocity[t] = v;
            let tendon = &m.tendons[t];
            if tendon.stiffness == 0.0 && tendon.damping == 0.0 {
                continue;
            }
            let [lo, hi] = m.tendon_lengthspring[t];
            let spring = if l > hi {
                tendon.stiffness * (hi - l)
            } else if l < lo {
                tendon.stiffness * (lo - l)
            } else {
                0.0
            };
            let f = spring - tendon.damping * v;
            for &(j, coef) in &tendon.joints {
                self.qfrc_passive[m.jnt_dofadr[j]] += coef * f;
            }
        }
    }

    /// Actuator forces (see [`crate::model::Actuator`]): the control clipped to each
    /// actuator's `ctrlrange` (NaN acts as 0), the activations' rates `act_dot`, each
    /// actuator's scalar force `actuator_force` and the generalized forces `qfrc_actuator`.
    pub(crate) fn actuation(&mut self) {
        let m = &*self.model;
        self.qfrc_actuator.fill(0.0);
        for (a, act) in m.actuators.iter().enumerate() {
            let mut u = self.ctrl[a];
            if u.is_nan() {
                u = 0.0;
            }
            if let Some([lo, hi]) = act.ctrlrange {
                u = u.clamp(lo, hi);
            }
            let input = match (act.dynamics, m.actuator_actadr[a]) {
                (crate::model::Dynamics::Filter { tau } | crate::model::Dynamics::FilterExact { tau }, Some(k)) => {
                    self.act_dot[k] = (u - self.act[k]) / tau;
                    self.act[k]
                }
                _ => u,
            };
            let mut force = act.gain * input;
            if act.bias != [0.0; 3] {
                let (len, vel) = match m.actuator_tendon[a] {
                    None => (self.qpos[m.jnt_qposadr[act.joint]], self.qvel[m.jnt_dofadr[act.joint]]),
                    Some(t) => self.tendon_state(t),
                };
                force += act.bias[0] + act.bias[1] * (act.gear * len) + act.bias[2] * (act.gear * vel);
            }
            if let Some([lo, hi]) = act.forcerange {
                force = force.clamp(lo, hi);
            }
            self.actuator_force[a] = force;
            match m.actuator_tendon[a] {
                None => self.qfrc_actuator[m.jnt_dofadr[act.joint]] += act.gear * force,
                Some(t) => {
                    for &(j, coef) in &m.tendons[t].joints {
                        self.qfrc_actuator[m.jnt_dofadr[j]] += coef * act.gear * force;
                    }
                }
            }
        }
    }
}

/// In-place Cholesky factor of the symmetric positive-definite row-major `n × n` matrix `a`:
/// its upper triangle is read (the lower one need not be set) and replaced by `U` with
/// `A = Uᵀ U` (row `j` of `U` is column `j` of the lower factor `L = Uᵀ`); the entries below the
/// diagonal are left as they were. `false` if `a` is not positive definite.
///
/// Row `j` of `U` is `A`'s row `j` (from the diagonal on) minus `U[k][j]` times row `k` of `U`
/// for `k = 0, 1, …, j − 1`; its first entry becomes that entry's square root `d` and the others
/// are multiplied by `1 / d` (one division per row, as MuJoCo's `mju_cholFactor`; the reciprocal is
/// what the solves multiply by too). The row is worked in blocks of 8 entries and one block each
/// of 4, 2 and 1 for the entries left, held in registers while `k` runs (independent lanes the
/// compiler vectorizes; with AVX2 where the processor has it, chosen at run time). Every entry's
/// sum is still taken in the order `k = 0, 1, …, j − 1` with the textbook loop's products and no
/// fused multiply-add, so the factor is the same, bit for bit, as the textbook loop's on every
/// processor.
pub fn cholesky(a: &mut [f64], n: usize) -> bool {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2, checked just above.
        return unsafe { simd::cholesky_avx2(a, n) };
    }
    cholesky_rows(a, n)
}

/// [`cholesky`] of `a`, then [`cholesky_solve`] of `x` (`b` on entry, the solution on return)
/// with the factor; the forward substitution runs inside the factorization, so the two overlap.
/// The same bits as the two calls. `false` (and `x` unspecified) if `a` is not positive definite.
pub fn cholesky_and_solve(a: &mut [f64], n: usize, x: &mut [f64]) -> bool {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2, checked just above.
        return unsafe { simd::cholesky_and_solve_avx2(a, n, x) };
    }
    factor_and_solve_rows(a, n, x)
}

#[inline(always)]
fn factor_and_solve_rows(a: &mut [f64], n: usize, x: &mut [f64]) -> bool {
    if !factor_rows(a, n, Some(&mut x[..n])) {
        return false;
    }
    backward_cols(a, n, x);
    true
}

/// Solve `A x = b` in place with the factor `U` of [`cholesky`]. The forward substitution
/// `Uᵀ y = b` finishes `y[k]` (times `1 / U[k][k]`) and subtracts `y[k]` times row `k` of `U` from
/// the entries after `k` (contiguous, vectorized), so each entry's sum runs over `k = 0, …, i − 1`
/// in order; the backward substitution `U x = y` works by columns the same way, each entry's sum
/// over `k = n − 1, …, i + 1` in order. Both chains are one multiply and one subtraction per
/// entry.
pub fn cholesky_solve(u: &[f64], n: usize, x: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2, checked just above.
        return unsafe { simd::solve_avx2(u, n, x) };
    }
    solve_rows(u, n, x)
}

/// `out = A x` for the symmetric row-major `n × n` matrix `a`, each entry the sum
/// `Σₖ A[i][k] x[k]` in the order `k = 0, 1, …, n − 1` from the neutral element of `f64`'s
/// `Sum` (as `row.iter().zip(x).map(|(a, b)| a * b).sum()`), taken down the columns (`A[k][i]`,
/// the same entry) in register blocks of `out`: the same bits as the row-by-row dot products.
pub fn sym_mat_vec(a: &[f64], n: usize, x: &[f64], out: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2, checked just above.
        return unsafe { simd::sym_mat_vec_avx2(a, n, x, out) };
    }
    sym_mat_vec_cols(a, n, x, out)
}

#[inline(always)]
fn sym_mat_vec_cols(a: &[f64], n: usize, x: &[f64], out: &mut [f64]) {
    let out = &mut out[..n];
    let x = &x[..n];
    let mut c = 0;
    while c + 8 <= n {
        col_block::<8>(a, n, x, c, &mut out[c..c + 8]);
        c += 8;
    }
    if c + 4 <= n {
        col_block::<4>(a, n, x, c, &mut out[c..c + 4]);
        c += 4;
    }
    if c + 2 <= n {
        col_block::<2>(a, n, x, c, &mut out[c..c + 2]);
        c += 2;
    }
    if c < n {
        col_block::<1>(a, n, x, c, &mut out[c..c + 1]);
    }
}

#[inline(always)]
fn col_block<const W: usize>(a: &[f64], n: usize, x: &[f64], c: usize, out: &mut [f64]) {
    let zero: f64 = std::iter::empty::<f64>().sum();
    let mut s = [zero; W];
    for (row, &xk) in a.chunks_exact(n).zip(x) {
        let u = &row[c..c + W];
        for t in 0..W {
            s[t] += u[t] * xk;
        }
    }
    out.copy_from_slice(&s);
}

/// The same functions compiled for AVX2 (the portable bodies, inlined: same operations in the
/// same order, so the same bits).
#[cfg(target_arch = "x86_64")]
mod simd {
    #[target_feature(enable = "avx2")]
    pub(super) unsafe fn cholesky_avx2(a: &mut [f64], n: usize) -> bool {
        super::cholesky_rows(a, n)
    }

    #[target_feature(enable = "avx2")]
    pub(super) unsafe fn cholesky_and_solve_avx2(a: &mut [f64], n: usize, x: &mut [f64]) -> bool {
        super::factor_and_solve_rows(a, n, x)
    }

    #[target_feature(enable = "avx2")]
    pub(super) unsafe fn sym_mat_vec_avx2(a: &[f64], n: usize, x: &[f64], out: &mut [f64]) {
        super::sym_mat_vec_cols(a, n, x, out)
    }

    #[target_feature(enable = "avx2")]
    pub(super) unsafe fn solve_avx2(u: &[f64], n: usize, x: &mut [f64]) {
        super::solve_rows(u, n, x)
    }
}

#[inline(always)]
fn cholesky_rows(a: &mut [f64], n: usize) -> bool {
    factor_rows(a, n, None)
}

/// The factorization of [`cholesky`]; with `rhs`, also the forward substitution `Uᵀ y = b` in
/// place (`b` in `rhs` on entry), entry `j` as soon as row `j` of `U` is done: `b[j]` minus
/// `U[k][j] y[k]` for `k = 0, 1, …, j − 1` in order, times `1 / U[j][j]` (the operations of
/// [`cholesky_solve`]'s forward substitution in the same order, overlapped with the factor's).
#[inline(always)]
fn factor_rows(a: &mut [f64], n: usize, mut rhs: Option<&mut [f64]>) -> bool {
    for j in 0..n {
        let (done, rest) = a.split_at_mut(j * n);
        let row = &mut rest[j..n];
        let len = n - j;
        // The forward substitution's entry `j` rides along the first block (it reads the same
        // `U[k][j]`).
        let mut fwd = rhs.as_deref_mut().map(|y| {
            let (solved, rest) = y.split_at_mut(j);
            (&*solved, &mut rest[0])
        });
        // Blocks of 8 entries, then one of 4, 2 and 1 each where the entries left need it.
        let mut c = 0;
        while c + 8 <= len {
            row_block::<8>(done, n, j, c, &mut row[c..c + 8], fwd.take());
            c += 8;
        }
        if c + 4 <= len {
            row_block::<4>(done, n, j, c, &mut row[c..c + 4], fwd.take());
            c += 4;
        }
        if c + 2 <= len {
            row_block::<2>(done, n, j, c, &mut row[c..c + 2], fwd.take());
            c += 2;
        }
        if c < len {
            row_block::<1>(done, n, j, c, &mut row[c..c + 1], fwd.take());
        }
        let d = row[0];
        if d.is_nan() || d <= 0.0 {
            return false;
        }
        let d = d.sqrt();
        row[0] = d;
        let r = 1.0 / d;
        for x in &mut row[1..] {
            *x *= r;
        }
        if let Some(y) = rhs.as_deref_mut() {
            y[j] *= r;
        }
    }
    true
}

/// Entries `j + c .. j + c + W` of row `j` of the factor before its scaling by `1 / d`: `out` (holding
/// `A`'s entries) minus `Σₖ U[k][j] U[k][j + c + t]` over the finished rows `done`, `k` in order.
/// With `fwd = (y[..j], y[j])`, also `y[j] −= U[k][j] y[k]` in the same loop, `k` in order.
#[inline(always)]
fn row_block<const W: usize>(
    done: &[f64],
    n: usize,
    j: usize,
    c: usize,
    out: &mut [f64],
    fwd: Option<(&[f64], &mut f64)>,
) {
    let out = &mut out[..W];
    let mut s = [0.0; W];
    s.copy_from_slice(out);
    match fwd {
        None => {
            for row in done.chunks_exact(n) {
                let l = row[j];
                let u = &row[j + c..j + c + W];
                for t in 0..W {
                    s[t] -= u[t] * l;
                }
            }
        }
        Some((solved, acc)) => {
            let mut y = *acc;
            for (row, &yk) in done.chunks_exact(n).zip(solved) {
                let l = row[j];
                let u = &row[j + c..j + c + W];
                for t in 0..W {
                    s[t] -= u[t] * l;
                }
                y -= l * yk;
            }
            *acc = y;
        }
    }
    out.copy_from_slice(&s);
}

#[inline(always)]
fn solve_rows(u: &[f64], n: usize, x: &mut [f64]) {
    let x = &mut x[..n];
    for k in 0..n {
        let row = &u[k * n + k..(k + 1) * n];
        let (head, tail) = x.split_at_mut(k + 1);
        let xk = head[k] * (1.0 / row[0]);
        head[k] = xk;
        for (xi, &a) in tail.iter_mut().zip(&row[1..]) {
            *xi -= a * xk;
        }
    }
    backward_cols(u, n, x);
}

/// The backward substitution `U x = y` (`y` in `x` on entry) by columns: `x[i]` is finished
/// (times the reciprocal of `U[i][i]`) for `i = n − 1, …, 0` in turn, and `U[k][i] x[i]` is taken
/// off every `x[k]`, `k < i` (independent entries, so the chain is one multiply and one
/// subtraction per `i`, not a dot product per `i`).
#[inline(always)]
fn backward_cols(u: &[f64], n: usize, x: &mut [f64]) {
    let x = &mut x[..n];
    for i in (0..n).rev() {
        let xi = x[i] * (1.0 / u[i * n + i]);
        x[i] = xi;
        for (k, xk) in x[..i].iter_mut().enumerate() {
            *xk -= u[k * n + i] * xi;
        }
    }
}

/// [`cholesky_solve`] on four right-hand sides at once, interleaved (`x[k]` holds entry `k` of
/// each), all of whose entries before `first` are zero (`+0`, as a Jacobian row's untouched
/// entries; the forward substitution starts there). Each lane's sums run in the order of
/// [`cholesky_solve`]'s, which before a lane's first nonzero entry meets only exact zeros
/// (`+0 − u·0` is `+0`), so every lane's solution is the same, bit for bit, as its own solve's.
pub fn cholesky_solve4(u: &[f64], n: usize, x: &mut [[f64; 4]], first: usize) {
    let x = &mut x[..n];
    for k in first..n {
        let row = &u[k * n + k..(k + 1) * n];
        let (head, tail) = x.split_at_mut(k + 1);
        let r = 1.0 / row[0];
        let xk = head[k].map(|v| v * r);
        head[k] = xk;
        for (xi, &a) in tail.iter_mut().zip(&row[1..]) {
            for t in 0..4 {
                xi[t] -= a * xk[t];
            }
        }
    }
    for i in (0..n).rev() {
        let r = 1.0 / u[i * n + i];
        let xi = x[i].map(|v| v * r);
        x[i] = xi;
        for (k, xk) in x[..i].iter_mut().enumerate() {
            let a = u[k * n + i];
            for t in 0..4 {
                xk[t] -= a * xi[t];
            }
        }
    }
}

/// MuJoCo's "simple, sliders only" bodies (`body_simple` 2): only slide joints with orthogonal
/// axes, the centre of mass at the body frame's origin on its axes, no child body, attached to
/// (a body welded to) the world. MuJoCo gives them `body_invweight0 = [1/mass, 0]` and
/// `dof_invweight0 = 1/mass` (armature left out), not the `J M⁻¹ Jᵀ` means.
fn sliders_only_bodies(model: &Model) -> Vec<bool> {
    let nb = model.bodies.len();
    let mut has_child = vec![false; nb];
    for b in 1..nb {
        has_child[model.bodies[b].parent] = true;
    }
    (0..nb)
        .map(|b| {
            let joints = &model.joints[model.body_joints[b].clone()];
            let body = &model.bodies[b];
            let orthogonal = joints.iter().enumerate().all(|(i, a)| {
                joints[i + 1..]
                    .iter()
                    .all(|c| crate::math::dot(a.axis, c.axis).abs() < 1e-10)
            });
            b != 0
                && !joints.is_empty()
                && joints.iter().all(|j| j.kind == JointKind::Slide)
                && orthogonal
                && !has_child[b]
                && model.body_weld[body.parent] == 0
                && body.ipos == [0.0; 3]
                && body.iquat == crate::math::QUAT_IDENTITY
                && body.mass > 0.0
        })
        .collect()
}

/// MuJoCo's `body_invweight0` and `dof_invweight0` at `qpos0`: the mean diagonal of the
/// translational and rotational blocks of `J M⁻¹ Jᵀ` at each body's centre of mass, and the
/// diagonal of `M⁻¹` (averaged over a free joint's translations and rotations); sliders-only
/// bodies as MuJoCo's ([`sliders_only_bodies`]).
pub(crate) fn set_invweight0(model: &mut Model) {
    let nv = model.nv;
    if nv == 0 {
        return;
    }
    let mut d = Data::new(std::sync::Arc::new(model.clone()));
    d.kinematics();
    d.mass_matrix();
    let mut l = d.qm.clone();
    if !cholesky(&mut l, nv) {
        return;
    }
    let mut minv = vec![0.0; nv * nv];
    let mut e = vec![0.0; nv];
    for i in 0..nv {
        e.fill(0.0);
        e[i] = 1.0;
        cholesky_solve(&l, nv, &mut e);
        for k in 0..nv {
            minv[k * nv + i] = e[k];
        }
    }
    const MINVAL: f64 = 1e-15;
    // Bodies some other body's degrees of freedom hang below (their mass matrix block is not
    // diagonal: MuJoCo's `body_simple` is 0 for them).
    let nb = model.bodies.len();
    let mut carries = vec![false; nb];
    for c in 1..nb {
        if model.body_last_dof[c] == usize::MAX {
            continue;
        }
        let mut a = model.bodies[c].parent;
        while a != usize::MAX && a != 0 {
            carries[a] = true;
            a = model.bodies[a].parent;
        }
    }
    let mut jac = vec![[0.0; 6]; nv];
    for b in 1..model.bodies.len() {
        if model.body_last_dof[b] == usize::MAX {
            continue;
        }
        let c = d.xipos[b];
        jac.iter_mut().for_each(|x| *x = [0.0; 6]);
        for &k in model.dof_path(model.body_last_dof[b]) {
            let (w, v) = crate::math::split(&d.cdof[k]);
            let lin = add(v, cross(w, c));
            jac[k] = join(lin, w);
        }
        // MuJoCo averages the three diagonal entries of each block, except for a body that
        // cannot rotate (slides alone) and carries no other body's degrees of freedom (MuJoCo's
        // `body_simple` 2): its translational weight is the mean of the entries that are not
        // zero (1/mass on one, two or three slides), its rotational weight 0. (A cart with a
        // pole hinged on it averages all three, as any other body.)
        let (mut tr, mut rot, mut ntr) = (0.0, 0.0, 0usize);
        for r in 0..6 {
            let mut s = 0.0;
            for (i, ji) in jac.iter().enumerate() {
                if ji[r] == 0.0 {
                    continue;
                }
                for (j, jj) in jac.iter().enumerate() {
                    s += ji[r] * minv[i * nv + j] * jj[r];
                }
            }
            if r < 3 {
                tr += s;
                ntr += usize::from(s > MINVAL);
            } else {
                rot += s;
            }
        }
        model.body_invweight0[b] = if rot > MINVAL || carries[b] {
            [(tr / 3.0).max(MINVAL), rot / 3.0]
        } else {
            [if ntr > 0 { tr / ntr as f64 } else { MINVAL }, MINVAL]
        };
    }
    for (b, _) in sliders_only_bodies(model).iter().enumerate().filter(|(_, s)| **s) {
        model.body_invweight0[b] = [(1.0 / model.bodies[b].mass).max(MINVAL), 0.0];
    }
    let sliders = sliders_only_bodies(model);
    for (j, jt) in model.joints.iter().enumerate() {
        let da = model.jnt_dofadr[j];
        if sliders[jt.body] {
            model.dof_invweight0[da] = (1.0 / model.bodies[jt.body].mass).max(MINVAL);
            continue;
        }
        match jt.kind {
            JointKind::Free => {
                for (lo, hi) in [(da, da + 3), (da + 3, da + 6)] {
                    let mean = (lo..hi).map(|k| minv[k * nv + k]).sum::<f64>() / 3.0;
                    for k in lo..hi {
                        model.dof_invweight0[k] = mean.max(MINVAL);
                    }
                }
            }
            _ => model.dof_invweight0[da] = minv[da * nv + da].max(MINVAL),
        }
    }
}

/// MuJoCo's `tendon_invweight0`: `J M⁻¹ Jᵀ` of each fixed tendon at `qpos0`.
pub(crate) fn tendon_invweight0(model: &Model) -> Vec<f64> {
    let nv = model.nv;
    if nv == 0 || model.tendons.is_empty() {
        return vec![0.0; model.tendons.len()];
    }
    let mut d = Data::new(std::sync::Arc::new(model.clone()));
    d.kinematics();
    d.mass_matrix();
    let mut l = d.qm.clone();
    if !cholesky(&mut l, nv) {
        return vec![0.0; model.tendons.len()];
    }
    model
        .tendons
        .iter()
        .map(|t| {
            let mut jac = vec![0.0; nv];
            for &(j, c) in &t.joints {
                jac[model.jnt_dofadr[j]] += c;
            }
            let mut x = jac.clone();
            cholesky_solve(&l, nv, &mut x);
            jac.iter().zip(&x).map(|(a, b)| a * b).sum::<f64>().max(1e-15)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::{cholesky, cholesky_solve, cholesky_solve4};

    /// The row-wise factorization, the solves, the four-lane solve and the column-wise product
    /// equal the textbook loops bit for bit
    /// (right-hand sides with leading zeros, as Jacobian rows have).
    #[test]
    fn interleaved_cholesky_and_solves_are_bit_identical() {
        let n = 23;
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut rnd = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let b: Vec<f64> = (0..n * n).map(|_| rnd()).collect();
        let mut a = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                a[i * n + j] =
                    (0..n).map(|k| b[i * n + k] * b[j * n + k]).sum::<f64>() + if i == j { 0.5 } else { 0.0 };
            }
        }
        // The textbook loop.
        let mut reference = a.clone();
        for j in 0..n {
            let mut d = reference[j * n + j];
            for k in 0..j {
                d -= reference[j * n + k] * reference[j * n + k];
            }
            let d = d.sqrt();
            reference[j * n + j] = d;
            let r = 1.0 / d;
            for i in j + 1..n {
                let mut s = reference[i * n + j];
                for k in 0..j {
                    s -= reference[i * n + k] * reference[j * n + k];
                }
                reference[i * n + j] = s * r;
            }
        }
        let mut l = a.clone();
        for i in 0..n {
            for j in 0..i {
                l[i * n + j] = f64::NAN; // only the upper triangle is read
            }
        }
        assert!(cholesky(&mut l, n));
        let mut portable = a.clone();
        assert!(super::cholesky_rows(&mut portable, n));
        for i in 0..n {
            for j in i..n {
                assert_eq!(portable[i * n + j].to_bits(), l[i * n + j].to_bits());
            }
        }
        for i in 0..n {
            for j in 0..=i {
                assert_eq!(l[j * n + i].to_bits(), reference[i * n + j].to_bits());
            }
        }
        // The textbook substitutions on the textbook factor (each sum in the order the solves
        // take it: forward `k = 0, …, i − 1`, backward `k = n − 1, …, i + 1`).
        let b: Vec<f64> = (0..n).map(|_| rnd()).collect();
        let mut y = b.clone();
        for i in 0..n {
            let mut s = y[i];
            for k in 0..i {
                s -= reference[i * n + k] * y[k];
            }
            y[i] = s * (1.0 / reference[i * n + i]);
        }
        for i in (0..n).rev() {
            let mut s = y[i];
            for k in (i + 1..n).rev() {
                s -= reference[k * n + i] * y[k];
            }
            y[i] = s * (1.0 / reference[i * n + i]);
        }
        let mut x = b.clone();
        cholesky_solve(&l, n, &mut x);
        let mut portable = b.clone();
        super::solve_rows(&l, n, &mut portable);
        for k in 0..n {
            assert_eq!(x[k].to_bits(), y[k].to_bits());
            assert_eq!(portable[k].to_bits(), y[k].to_bits());
        }
        let mut fused = b.clone();
        let mut fused_factor = a.clone();
        assert!(super::cholesky_and_solve(&mut fused_factor, n, &mut fused));
        let mut fused_portable = b.clone();
        let mut fused_portable_factor = a.clone();
        assert!(super::factor_and_solve_rows(
            &mut fused_portable_factor,
            n,
            &mut fused_portable
        ));
        for k in 0..n {
            assert_eq!(fused[k].to_bits(), y[k].to_bits());
            assert_eq!(fused_portable[k].to_bits(), y[k].to_bits());
        }
        for i in 0..n {
            for j in i..n {
                assert_eq!(fused_factor[i * n + j].to_bits(), l[i * n + j].to_bits());
            }
        }
        let mut ax = vec![0.0; n];
        super::sym_mat_vec(&a, n, &b, &mut ax);
        let mut ax_portable = vec![0.0; n];
        super::sym_mat_vec_cols(&a, n, &b, &mut ax_portable);
        for i in 0..n {
            let dot: f64 = a[i * n..(i + 1) * n].iter().zip(&b).map(|(p, q)| p * q).sum();
            assert_eq!(ax[i].to_bits(), dot.to_bits());
            assert_eq!(ax_portable[i].to_bits(), dot.to_bits());
        }
        let firsts = [2, 5, 3, 8];
        let mut rhs = vec![[0.0; 4]; n];
        let mut single: Vec<Vec<f64>> = Vec::new();
        for (lane, &f) in firsts.iter().enumerate() {
            let mut x = vec![0.0; n];
            for v in &mut x[f..] {
                *v = rnd();
            }
            for k in 0..n {
                rhs[k][lane] = x[k];
            }
            cholesky_solve(&l, n, &mut x);
            single.push(x);
        }
        cholesky_solve4(&l, n, &mut rhs, 2);
        for (lane, x) in single.iter().enumerate() {
            for k in 0..n {
                assert_eq!(rhs[k][lane].to_bits(), x[k].to_bits());
            }
        }
    }
}
