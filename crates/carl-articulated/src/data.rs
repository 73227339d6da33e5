//! The simulation state of one model instance and its preallocated work buffers (MuJoCo's
//! `mjData`): `qpos`, `qvel`, `act` (the stateful actuators' activations), `ctrl` and `time`
//! are the state; [`Data::forward`] computes the acceleration (and the activations' rates),
//! [`Data::step`] advances one time step with the model's integrator (activations with it, as
//! MuJoCo's `mj_advance`). No step allocates; `Clone` copies the state exactly.
//!
//! Semi-implicit Euler (MuJoCo's `Euler`): after the constraint solve, the acceleration is
//! recomputed as `(M + h D)⁻¹ (f_smooth + Jᵀ f)` when any joint has damping (`D` the diagonal
//! joint damping; `f_smooth` already holds `−D v`), then `v ← v + h a`, `q ← q ⊕ h v` (free
//! joints: position plus `h v`, quaternion rotated by `h ω` in the body frame). RK4: MuJoCo's
//! classic four-stage scheme, each stage a full forward pass (contacts included), damping
//! explicit; a free joint's quaternion advances by its stage derivatives `½ q ⊗ ω` and is
//! normalized (what MuJoCo 4.0.0's RK4 does: its result differs from rotating by the averaged
//! angular velocity by ~1e-7 per step, and matches this to ~1e-11).

use std::sync::Arc;

use crate::collision::Contact;
use crate::constraint::RowKind;
use crate::dynamics::cholesky_and_solve;
use crate::math::{
    IDENTITY, Inertia, M3, QUAT_IDENTITY, Quat, V3, V6, ZERO3, add, cross, dot, quat_integrate, quat_mul,
    quat_normalize, scale, split,
};
use crate::model::{Integrator, JointKind, Model};

/// One instance of a [`Model`].
#[derive(Debug, Clone)]
pub struct Data {
    pub(crate) model: Arc<Model>,
    pub qpos: Vec<f64>,
    pub qvel: Vec<f64>,
    pub ctrl: Vec<f64>,
    /// Activations of the stateful actuators (MuJoCo's `act`, `Model::na` entries at
    /// `Model::actuator_actadr`): part of the state with `qpos` and `qvel` (save and restore
    /// it with them; [`Data::reset`] zeroes it).
    pub act: Vec<f64>,
    /// Their rates of the last forward pass.
    pub act_dot: Vec<f64>,
    /// Each actuator's scalar force of the last forward pass (MuJoCo's `actuator_force`).
    pub actuator_force: Vec<f64>,
    /// Each tendon's length and velocity of the last forward pass.
    pub ten_length: Vec<f64>,
    pub ten_velocity: Vec<f64>,
    pub qacc: Vec<f64>,
    pub time: f64,
    pub xpos: Vec<V3>,
    pub xquat: Vec<Quat>,
    pub xmat: Vec<M3>,
    /// Centre of mass of each body.
    pub xipos: Vec<V3>,
    pub geom_xpos: Vec<V3>,
    pub geom_xmat: Vec<M3>,
    pub(crate) cinert: Vec<Inertia>,
    pub(crate) crb: Vec<Inertia>,
    pub(crate) cdof: Vec<V6>,
    pub(crate) cdof_dot: Vec<V6>,
    /// Spatial velocity of each body (world frame, about the world origin).
    pub cvel: Vec<V6>,
    pub(crate) cacc: Vec<V6>,
    pub(crate) cfrc: Vec<V6>,
    /// MuJoCo's `cacc` and `cfrc_int` after the constraint solve ([`Data::rne_post_constraint`]:
    /// world frame, about the world origin).
    pub(crate) post_cacc: Vec<V6>,
    pub(crate) cfrc_int: Vec<V6>,
    /// Mass matrix (armature included), row-major; the entries of dof pairs neither of which is
    /// an ancestor of the other are zero and never written.
    pub qm: Vec<f64>,
    pub(crate) qld: Vec<f64>,
    pub qfrc_bias: Vec<f64>,
    pub qfrc_passive: Vec<f64>,
    pub qfrc_actuator: Vec<f64>,
    pub qfrc_smooth: Vec<f64>,
    /// The unconstrained acceleration `M⁻¹ qfrc_smooth` where the last forward pass solved for it
    /// (no constraint rows, no Newton warm start, or the dual solver); NaN where Newton, warm
    /// started, did not need it.
    pub qacc_smooth: Vec<f64>,
    pub qfrc_constraint: Vec<f64>,
    pub(crate) contacts: Vec<Contact>,
    pub ncon: usize,
    pub(crate) nefc: usize,
    pub(crate) efc_j: Vec<f64>,
    pub(crate) efc_w: Vec<f64>,
    pub(crate) efc_inv: Vec<f64>,
    /// Delassus matrix `J M⁻¹ Jᵀ` (rows × rows, row-major with stride `nefc`) and `J a₀ − aref`.
    pub(crate) efc_a: Vec<f64>,
    pub(crate) efc_b: Vec<f64>,
    /// `b + A f` during the solve.
    pub(crate) efc_g: Vec<f64>,
    pub(crate) efc_r: Vec<f64>,
    pub(crate) efc_aref: Vec<f64>,
    pub(crate) efc_force: Vec<f64>,
    /// `|f| ≤ bound` for dry-friction rows; infinite (`f ≥ 0`) for the others.
    pub(crate) efc_bound: Vec<f64>,
    pub(crate) efc_kind: Vec<RowKind>,
    /// Each row's cost (Newton's rows): 0 its force non-negative, 1 within `±efc_bound`, 2 free
    /// (a tendon equality's).
    pub(crate) efc_class: Vec<u8>,
    /// Four right-hand sides of `M x = Jᵀ` interleaved (`nv` entries of four).
    pub(crate) solve4: Vec<[f64; 4]>,
    /// The Newton solver's state and scratch (pyramidal-cone models).
    pub(crate) newton: crate::constraint::Newton,
    /// The nonzero entries of a Jacobian row (indices).
    pub(crate) efc_nz: Vec<usize>,
    /// Each candidate pair's geoms, whether the first is a plane, and its reach: the sum of the
    /// geoms' bounding radii and the pair's margin (the broad phase's bounding-sphere test), with
    /// `reach² (1 + 10⁻¹²)`; for a plane, the other geom's bounding radius and the margin (its
    /// height above the plane is tested). The broad phase reads only this.
    pub(crate) pair_reach: Vec<(usize, usize, bool, f64, f64)>,
    /// The previous projected Gauss–Seidel solve's forces by row key (elliptic-cone models).
    pub(crate) warm: Vec<(u64, f64)>,
    pub(crate) warm_count: usize,
    /// Newton iterations (pyramidal cones) or Gauss–Seidel sweeps (elliptic cones) of the last
    /// constraint solve (a diagnostic).
    pub solver_sweeps: usize,
    /// The bits of the `qpos` the poses (`xpos` … `cinert`, `cdof`) were last computed from,
    /// and of the `qvel` the velocities (`cvel`, `cdof_dot`) were, while `kin_valid` /
    /// `vel_valid` hold: `kinematics` and `velocities` return at once on the same bits (both
    /// are functions of them alone), so the forward pass after [`Data::update_kinematics`] (an
    /// environment's observation at the end of a step) does not repeat it.
    pub(crate) kin_qpos: Vec<u64>,
    pub(crate) kin_valid: bool,
    pub(crate) vel_qvel: Vec<u64>,
    pub(crate) vel_valid: bool,
    /// RK4 scratch: start state and stage rates.
    rk_q: [Vec<f64>; 4],
    rk_v0: Vec<f64>,
    rk_vel: [Vec<f64>; 4],
    rk_acc: [Vec<f64>; 4],
    rk_act0: Vec<f64>,
    rk_act_dot: [Vec<f64>; 4],
}

impl Data {
    /// A new instance at `qpos0` with zero velocity and controls.
    pub fn new(model: Arc<Model>) -> Data {
        let (nb, nv, nq, ng) = (model.bodies.len(), model.nv, model.nq, model.geoms.len());
        let rows = model.max_rows;
        // The dual's buffers (W = M⁻¹ Jᵀ, the Delassus matrix, the sweeps' state, the forces'
        // warm start): only elliptic-cone models are solved on the dual.
        let dual = if model.solves_dual() { rows } else { 0 };
        Data {
            qpos: model.qpos0.clone(),
            qvel: vec![0.0; nv],
            ctrl: vec![0.0; model.actuators.len()],
            act: vec![0.0; model.na],
            act_dot: vec![0.0; model.na],
            actuator_force: vec![0.0; model.actuators.len()],
            ten_length: vec![0.0; model.tendons.len()],
            ten_velocity: vec![0.0; model.tendons.len()],
            qacc: vec![0.0; nv],
            time: 0.0,
            xpos: vec![ZERO3; nb],
            xquat: vec![QUAT_IDENTITY; nb],
            xmat: vec![IDENTITY; nb],
            xipos: vec![ZERO3; nb],
            geom_xpos: vec![ZERO3; ng],
            geom_xmat: vec![IDENTITY; ng],
            cinert: vec![Inertia::default(); nb],
            crb: vec![Inertia::default(); nb],
            cdof: vec![[0.0; 6]; nv],
            cdof_dot: vec![[0.0; 6]; nv],
            cvel: vec![[0.0; 6]; nb],
            cacc: vec![[0.0; 6]; nb],
            cfrc: vec![[0.0; 6]; nb],
            post_cacc: vec![[0.0; 6]; nb],
            cfrc_int: vec![[0.0; 6]; nb],
            qm: vec![0.0; nv * nv],
            qld: vec![0.0; nv * nv],
            qfrc_bias: vec![0.0; nv],
            qfrc_passive: vec![0.0; nv],
            qfrc_actuator: vec![0.0; nv],
            qfrc_smooth: vec![0.0; nv],
            qacc_smooth: vec![0.0; nv],
            qfrc_constraint: vec![0.0; nv],
            contacts: vec![Contact::default(); model.max_contacts],
            ncon: 0,
            nefc: 0,
            efc_j: vec![0.0; rows * nv],
            efc_w: vec![0.0; dual * nv],
            efc_inv: vec![0.0; dual],
            efc_a: vec![0.0; dual * dual],
            efc_b: vec![0.0; dual],
            efc_g: vec![0.0; dual],
            efc_r: vec![0.0; rows],
            efc_aref: vec![0.0; rows],
            efc_force: vec![0.0; rows],
            efc_bound: vec![f64::INFINITY; rows],
            efc_kind: vec![RowKind::None; rows],
            efc_class: vec![0; rows],
            solve4: vec![[0.0; 4]; if dual > 0 { nv } else { 0 }],
            newton: crate::constraint::Newton::new(nv, rows),
            efc_nz: vec![0; if dual > 0 { nv } else { 0 }],
            pair_reach: model
                .pairs
                .iter()
                .map(|p| {
                    // A plane (first in MuJoCo's type order) reaches the other geom's bounding
                    // sphere plus the margin along its normal.
                    let plane = model.geoms[p.g1].shape == crate::model::Shape::Plane;
                    let r1 = if plane {
                        0.0
                    } else {
                        model.geoms[p.g1].shape.bounding_radius()
                    };
                    let reach = r1 + model.geoms[p.g2].shape.bounding_radius() + p.margin;
                    (p.g1, p.g2, plane, reach, reach * reach * (1.0 + 1e-12))
                })
                .collect(),
            warm: vec![(0, 0.0); dual],
            warm_count: 0,
            solver_sweeps: 0,
            kin_qpos: vec![0; nq],
            kin_valid: false,
            vel_qvel: vec![0; nv],
            vel_valid: false,
            rk_q: std::array::from_fn(|_| vec![0.0; nq]),
            rk_v0: vec![0.0; nv],
            rk_vel: std::array::from_fn(|_| vec![0.0; nv]),
            rk_acc: std::array::from_fn(|_| vec![0.0; nv]),
            rk_act0: vec![0.0; model.na],
            rk_act_dot: std::array::from_fn(|_| vec![0.0; model.na]),
            model,
        }
    }

    pub fn model(&self) -> &Model {
        &self.model
    }

    /// Back to `qpos0` at rest: zero velocities, activations and controls, time 0.
    pub fn reset(&mut self) {
        self.qpos.copy_from_slice(&self.model.qpos0);
        self.qvel.fill(0.0);
        self.act.fill(0.0);
        self.ctrl.fill(0.0);
        self.time = 0.0;
        self.forget_warm_start();
    }

    /// Start the next constraint solve cold: the solver's warm start (the previous solve's
    /// acceleration for Newton, its forces for Gauss–Seidel) is dropped, so what follows depends
    /// on the state alone. An environment's reset calls it (directly or through [`Data::reset`]):
    /// without it the first solve of an episode starts from the last episode's solution and lands
    /// within the solver's tolerance of, but not on, the same result.
    pub fn forget_warm_start(&mut self) {
        self.warm_count = 0;
        self.newton.warm_valid = false;
    }

    /// MuJoCo's activation update (`mj_advance`) with rates `act_dot` (RK4: its stages' weighted rates) over a step `h`:
    /// `act += h · act_dot` (filter), `act += act_dot · tau · (1 − e^(−h/tau))` (filterexact),
    /// then clipped to `actrange`.
    fn advance_act(&mut self, h: f64, rk4: bool) {
        let m = &*self.model;
        for (a, act) in m.actuators.iter().enumerate() {
            let Some(k) = m.actuator_actadr[a] else { continue };
            let rate = if rk4 {
                const B: [f64; 4] = [1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0];
                (0..4).map(|s| B[s] * self.rk_act_dot[s][k]).sum()
            } else {
                self.act_dot[k]
            };
            let mut x = self.act[k];
            x += match act.dynamics {
                crate::model::Dynamics::FilterExact { tau } => rate * tau * (1.0 - (-h / tau).exp()),
                _ => rate * h,
            };
            if let Some([lo, hi]) = act.actrange {
                x = x.clamp(lo, hi);
            }
            self.act[k] = x;
        }
    }

    /// Positions, velocities, forces and the constrained acceleration `qacc` of the current
    /// state. Returns `false` (and leaves `qacc` NaN) if the mass matrix is not positive
    /// definite (or, Newton warm started, the Hessian `M + Jᵀ D J` is not).
    pub fn forward(&mut self) -> bool {
        self.kinematics();
        self.velocities();
        self.mass_matrix();
        self.bias_forces();
        self.passive_forces();
        self.actuation();
        let nv = self.model.nv;
        for d in 0..nv {
            self.qfrc_smooth[d] = self.qfrc_passive[d] + self.qfrc_actuator[d] - self.qfrc_bias[d];
        }
        self.collide();
        self.make_constraints();
        // Newton warm-started from the previous solve needs neither M's factor nor a₀
        // (`constraint`'s module doc).
        let smooth_solved = self.model.solves_dual() || self.nefc == 0 || !self.newton.warm_valid;
        if smooth_solved {
            self.qld.copy_from_slice(&self.qm);
            self.qacc_smooth.copy_from_slice(&self.qfrc_smooth);
            if !cholesky_and_solve(&mut self.qld, nv, &mut self.qacc_smooth) {
                self.qacc.fill(f64::NAN);
                return false;
            }
            self.qacc.copy_from_slice(&self.qacc_smooth);
        } else {
            self.qacc_smooth.fill(f64::NAN);
        }
        if !self.solve_constraints(smooth_solved) {
            self.qacc.fill(f64::NAN);
            return false;
        }
        true
    }

    /// One time step with the model's integrator.
    pub fn step(&mut self) {
        let ok = self.forward();
        if !ok {
            self.qvel.fill(f64::NAN);
            return;
        }
        self.integrate();
    }

    /// One time step that lets `read` see the state before integration with its accelerations
    /// and interaction forces ([`Data::rne_post_constraint`]): MuJoCo's acceleration sensors
    /// (accelerometer, force, torque), which `mj_step` computes before it integrates.
    pub fn step_observed(&mut self, read: impl FnOnce(&Data)) {
        let ok = self.forward();
        if !ok {
            self.qvel.fill(f64::NAN);
            return;
        }
        self.rne_post_constraint();
        read(self);
        self.integrate();
    }

    /// How many contacts the current `qpos` makes (poses and collision only).
    pub fn count_contacts(&mut self) -> usize {
        self.kinematics();
        self.collide();
        self.ncon
    }

    fn integrate(&mut self) {
        match self.model.opt.integrator {
            Integrator::Euler => self.euler(),
            Integrator::Rk4 => self.rk4(),
        }
    }

    fn euler(&mut self) {
        let model = Arc::clone(&self.model);
        let m = &*model;
        let nv = m.nv;
        let h = m.opt.timestep;
        let damped = m.joints.iter().any(|j| j.damping > 0.0);
        if damped {
            // (M + h D) a = f_smooth + Jᵀ f
            self.qld.copy_from_slice(&self.qm);
            for d in 0..nv {
                self.qld[d * nv + d] += h * m.joints[m.dof_joint[d]].damping;
                self.qacc[d] = self.qfrc_smooth[d] + self.qfrc_constraint[d];
            }
            if !cholesky_and_solve(&mut self.qld, nv, &mut self.qacc) {
                self.qvel.fill(f64::NAN);
                return;
            }
        }
        for d in 0..nv {
            self.qvel[d] += h * self.qacc[d];
        }
        let mut q = std::mem::take(&mut self.qpos);
        integrate_pos(m, &mut q, &self.qvel, h);
        self.qpos = q;
        if m.na > 0 {
            self.advance_act(h, false);
        }
        self.time += h;
    }

    fn rk4(&mut self) {
        const A: [f64; 3] = [0.5, 0.5, 1.0];
        const B: [f64; 4] = [1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0];
        let model = Arc::clone(&self.model);
        let m = &*model;
        let h = m.opt.timestep;
        let t0 = self.time;
        self.rk_q[0].copy_from_slice(&self.qpos);
        self.rk_v0.copy_from_slice(&self.qvel);
        self.rk_vel[0].copy_from_slice(&self.qvel);
        self.rk_acc[0].copy_from_slice(&self.qacc);
        self.rk_act0.copy_from_slice(&self.act);
        self.rk_act_dot[0].copy_from_slice(&self.act_dot);
        for i in 1..4 {
            // Stage i: X₀ + h·A[i]·F[i−1] (the Butcher tableau of classic RK4 is diagonal).
            let mut w = [0.0; 4];
            w[i - 1] = A[i - 1];
            let mut q = std::mem::take(&mut self.qpos);
            self.rk_position(&w, h, &mut q);
            self.qpos = q;
            let acc_prev = &self.rk_acc[i - 1];
            for ((v, v0), a) in self.qvel.iter_mut().zip(&self.rk_v0).zip(acc_prev) {
                *v = v0 + h * A[i - 1] * a;
            }
            for k in 0..m.na {
                self.act[k] = self.rk_act0[k] + h * A[i - 1] * self.rk_act_dot[i - 1][k];
            }
            self.time = t0 + h * A[i - 1];
            if !self.forward() {
                self.qvel.fill(f64::NAN);
                return;
            }
            self.rk_q[i].copy_from_slice(&self.qpos);
            self.rk_vel[i].copy_from_slice(&self.qvel);
            self.rk_acc[i].copy_from_slice(&self.qacc);
            self.rk_act_dot[i].copy_from_slice(&self.act_dot);
        }
        let mut q = std::mem::take(&mut self.qpos);
        self.rk_position(&B, h, &mut q);
        self.qpos = q;
        for d in 0..m.nv {
            let da: f64 = (0..4).map(|k| B[k] * self.rk_acc[k][d]).sum();
            self.qvel[d] = self.rk_v0[d] + h * da;
        }
        if m.na > 0 {
            self.act.copy_from_slice(&self.rk_act0);
            self.advance_act(h, true);
        }
        self.time = t0 + h;
    }

    /// `q = q₀ + h Σₖ wₖ q̇ₖ` over the RK4 stages, as MuJoCo 4's RK4 does it: coordinates
    /// advance with the stage velocities; a free joint's quaternion advances with its stage
    /// derivatives `½ qₖ ⊗ (0, ωₖ)` (ω in the body frame) and is normalized.
    fn rk_position(&self, w: &[f64; 4], h: f64, q: &mut [f64]) {
        let m = &*self.model;
        let q0 = &self.rk_q[0];
        for (j, jt) in m.joints.iter().enumerate() {
            let (qa, da) = (m.jnt_qposadr[j], m.jnt_dofadr[j]);
            let lin = if jt.kind == JointKind::Free { 3 } else { 1 };
            for k in 0..lin {
                let v: f64 = (0..4)
                    .filter(|&s| w[s] != 0.0)
                    .map(|s| w[s] * self.rk_vel[s][da + k])
                    .sum();
                q[qa + k] = q0[qa + k] + h * v;
            }
            if jt.kind == JointKind::Free {
                let mut acc = [q0[qa + 3], q0[qa + 4], q0[qa + 5], q0[qa + 6]];
                for s in (0..4).filter(|&s| w[s] != 0.0) {
                    let qs = &self.rk_q[s];
                    let quat = [qs[qa + 3], qs[qa + 4], qs[qa + 5], qs[qa + 6]];
                    let om = &self.rk_vel[s];
                    let dq = quat_mul(quat, [0.0, om[da + 3], om[da + 4], om[da + 5]]);
                    for k in 0..4 {
                        acc[k] += h * w[s] * 0.5 * dq[k];
                    }
                }
                q[qa + 3..qa + 7].copy_from_slice(&quat_normalize(acc));
            }
        }
    }

    /// Kinetic plus gravitational potential energy plus joint-spring energy (after
    /// [`Data::forward`] or [`Data::update_kinematics`]).
    pub fn energy(&self) -> f64 {
        let m = &*self.model;
        let mut e = 0.0;
        for b in 1..m.bodies.len() {
            let body = &m.bodies[b];
            let (w, v0) = split(&self.cvel[b]);
            let c = self.xipos[b];
            let vc = add(v0, cross(w, c));
            let ri = crate::math::mat_mul(&self.xmat[b], &crate::math::quat_to_mat(body.iquat));
            let wl = crate::math::mat_t_vec(&ri, w);
            let rot: f64 = (0..3).map(|k| body.inertia[k] * wl[k] * wl[k]).sum();
            e += 0.5 * (body.mass * dot(vc, vc) + rot) - body.mass * dot(m.opt.gravity, c);
        }
        for (j, jt) in m.joints.iter().enumerate() {
            let da = m.jnt_dofadr[j];
            for d in da..da + jt.kind.nv() {
                e += 0.5 * jt.armature * self.qvel[d] * self.qvel[d];
            }
            if jt.kind != JointKind::Free {
                let x = self.qpos[m.jnt_qposadr[j]] - jt.springref;
                e += 0.5 * jt.stiffness * x * x;
            }
        }
        e
    }

    /// Poses and velocities of the current `qpos`/`qvel` without dynamics.
    pub fn update_kinematics(&mut self) {
        self.kinematics();
        self.velocities();
    }

    /// Total linear momentum and angular momentum about the world origin.
    pub fn momentum(&self) -> (V3, V3) {
        let m = &*self.model;
        let (mut l, mut p) = (ZERO3, ZERO3);
        for b in 1..m.bodies.len() {
            let h = self.cinert[b].mul(&self.cvel[b]);
            let (hl, hp) = split(&h);
            l = add(l, hl);
            p = add(p, hp);
        }
        (l, p)
    }

    /// Mass-weighted centre of mass of all moving bodies.
    pub fn center_of_mass(&self) -> V3 {
        let m = &*self.model;
        let (mut c, mut mass) = (ZERO3, 0.0);
        for b in 1..m.bodies.len() {
            c = add(c, scale(self.xipos[b], m.bodies[b].mass));
            mass += m.bodies[b].mass;
        }
        if mass > 0.0 { scale(c, 1.0 / mass) } else { ZERO3 }
    }

    /// The contacts of the last forward pass.
    pub fn contacts(&self) -> &[Contact] {
        &self.contacts[..self.ncon]
    }

    /// The normal force of contact `ci` in the last forward pass (MuJoCo's `mj_contactForce`'s
    /// first component).
    pub fn contact_normal_force(&self, ci: usize) -> f64 {
        if ci >= self.ncon {
            return 0.0;
        }
        crate::math::dot(self.contact_force(ci), self.contacts[ci].frame[0])
    }

    /// External contact wrench on each body from the last forward pass, `[torque, force]` in
    /// the world frame, the torque about the body's centre of mass (the force on geom 2's body,
    /// its opposite on geom 1's).
    pub fn contact_wrenches(&self, out: &mut [[f64; 6]]) {
        let m = &*self.model;
        out.iter_mut().for_each(|w| *w = [0.0; 6]);
        for ci in 0..self.ncon {
            let c = &self.contacts[ci];
            let f = self.contact_force(ci);
            let pair = &m.pairs[c.pair];
            for (g, s) in [(pair.g2, 1.0), (pair.g1, -1.0)] {
                let b = m.geoms[g].body;
                if b == 0 || b >= out.len() {
                    continue;
                }
                let fs = scale(f, s);
                let t = cross(crate::math::sub(c.pos, self.xipos[b]), fs);
                for k in 0..3 {
                    out[b][k] += t[k];
                    out[b][3 + k] += fs[k];
                }
            }
        }
    }

    /// Whether every coordinate and rate is finite and no rate exceeds `max_speed`.
    pub fn is_sane(&self, max_speed: f64) -> bool {
        self.qpos.iter().all(|x| x.is_finite()) && self.qvel.iter().all(|v| v.is_finite() && v.abs() <= max_speed)
    }
}

/// `q ← q ⊕ h v` joint by joint (free joints: quaternion integration in the body frame).
pub fn integrate_pos(m: &Model, q: &mut [f64], v: &[f64], h: f64) {
    for (j, jt) in m.joints.iter().enumerate() {
        let (qa, da) = (m.jnt_qposadr[j], m.jnt_dofadr[j]);
        match jt.kind {
            JointKind::Free => {
                for k in 0..3 {
                    q[qa + k] += h * v[da + k];
                }
                let quat = [q[qa + 3], q[qa + 4], q[qa + 5], q[qa + 6]];
                let r = quat_integrate(quat, [v[da + 3], v[da + 4], v[da + 5]], h);
                q[qa + 3..qa + 7].copy_from_slice(&r);
            }
            _ => q[qa] += h * v[da],
        }
    }
}
