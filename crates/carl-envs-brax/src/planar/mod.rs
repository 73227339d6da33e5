//! A reduced-coordinate engine for planar robots (HalfCheetah, Hopper, Walker2d,
//! InvertedPendulum, InvertedDoublePendulum, Reacher): every link moves in the x-z plane (Reacher's
//! horizontal plane is turned into it, see `gravity_normal_to_plane`), so the state is the joint
//! coordinates `q` and rates `v` alone and one physics step is a handful of small dense
//! operations in f64.
//!
//! * [`tree`]: the planar kinematic tree read from the same URDF and side file as the rapier
//!   world, with a clear error for a robot that is not planar;
//! * [`kinematics`]: link poses, velocities and bias accelerations, Jacobian columns;
//! * [`dynamics`]: mass matrix and bias forces (Newton–Euler), Cholesky;
//! * [`contacts`]: ground contacts with Coulomb friction and joint limits as soft
//!   velocity-level constraints, projected Gauss–Seidel.
//!
//! One step of length `h` (the side file's `timestep`), semi-implicit Euler as MuJoCo's
//! default integrator, with the joint damping implicit:
//! `(M + A + hD)(v⁺ − v) = h(τ − b − Dv − Kq) + Jᵀλ`, `q⁺ = q + h v⁺`, where `A` is the
//! armature, `D` the side file's per-joint damping (`joint_dampings`, MuJoCo's joint
//! `damping`) or else the context's `joint_angular_damping` on every robot hinge, `K` the side
//! file's passive springs (explicit, as MuJoCo's), `b` gravity and velocity-product forces,
//! `τ` the motors and `λ` the constraint impulses. How each context feature enters:
//! * `gravity` → `b`; `friction` → the Coulomb coefficient of every ground contact;
//! * `angular_damping` → after each step every hinge rate (root pitch included) is scaled by
//!   `exp(angular_damping · h)`, as in the rapier world;
//! * `joint_angular_damping` → `D`; `actuator_strength` → the motor torques;
//! * `joint_stiffness` → the joint limits: soft rows of angular frequency
//!   `√(joint_stiffness / limit_reference_inertia)` and damping ratio `limit_damping_ratio`
//!   (the rapier world's semantics);
//! * `torso_mass`, `mass_<link>` → link masses (inertia scaled with them);
//! * `elasticity` → an approaching contact's normal row targets at least `elasticity` times
//!   the approach speed as separation speed (0: MuJoCo's inelastic soft contact);
//! * `viscosity` → MuJoCo's medium viscosity (inertia-box model): each link's Stokes drag
//!   `−3πμd·v` at its centre of mass and `−πμd³·ω`, `d` the mean side of its inertia box,
//!   implicit like the joint damping (`h·Dᵥ` joins the matrix).
//!
//! Robots welded to the world without ground contacts (the inverted pendulums' cart on its
//! rail, Reacher's arm on its table) use three side-file properties:
//! * `rail_joints`: a slide carrying the weight of everything it moves has dry friction
//!   `friction · |gravity| · carried mass` (a bounded row on its rate, MuJoCo's `frictionloss`);
//! * `bouncing_limits`: these joints' limit rows restitute with `elasticity` (an approaching
//!   limit row targets at least `elasticity` times the approach speed as separation speed);
//! * `gravity_normal_to_plane`: the plane of motion is horizontal (Reacher): gravity exerts no
//!   force in it; each moving link's weight presses it onto the table, where it slides with
//!   Coulomb friction `friction · m · |gravity|` at its centre of mass (two bounded rows, along
//!   the plane's axes, on the centre of mass's velocity).
//!
//! With the side file's `"integrator": "rk4"` (the contact-free models whose XML asks for
//! MuJoCo's RK4: the inverted pendulums, Reacher) a step is classic fourth-order Runge–Kutta as
//! MuJoCo's `mj_RungeKutta`: each of the four stages computes the acceleration at its state,
//! constraint rows included (the row impulses of a step of length `h` from that state, over
//! `h`), with the joint damping explicit; `ang_damping` acts after the whole step. A step that
//! starts with an impact on a bouncing limit (elasticity > 0) is one semi-implicit Euler step:
//! RK4's averaged stages would blur the restitution impulse.
//!
//! Ground contact normals are soft as MuJoCo's: by default its default `solref` and `solimp`
//! (time constant 0.02 s, damping ratio 1, impedance 0.9–0.95 as a linear ramp); with the side
//! file's `contact_model` its `solref`, `solimp` (MuJoCo's sigmoid) and `margin` as MuJoCo
//! mixes them for the robot–floor pair. Friction is Coulomb's, stiff. With the side file's
//! `limit_model` the joint limits are MuJoCo's soft limits (rows active once the limit is
//! passed, reference acceleration and regularizer from `solreflimit`/`solimplimit`) instead of
//! the `joint_stiffness` spring.

pub mod contacts;
pub mod dynamics;
pub mod kinematics;
pub mod tree;

use std::sync::Arc;

use rapier3d::prelude::{Pose, Rotation, Vector};

use super::model::RobotModel;
use super::params::{RobotParams, finite_or};
use super::world::Configuration;
use contacts::{Impedance, RowKind, Rows, Softness};
use kinematics::{DofAxis, LinkState, point_velocity, positions, velocities};
pub use tree::PlanarTree;

/// The context-dependent constants of a planar world (shared by its clones).
#[derive(Debug)]
pub struct PlanarSystem {
    pub tree: PlanarTree,
    pub h: f64,
    /// Gravity in the plane of motion (0 when it is normal to the plane).
    pub gravity: f64,
    pub friction: f64,
    /// Dry-friction bound (N) of each coordinate's rate: the rail joints' (0 elsewhere).
    rail_friction: Vec<f64>,
    /// Coulomb friction bound (N) of each link's centre of mass sliding on its table
    /// (`gravity_normal_to_plane`; empty otherwise).
    table_friction: Vec<f64>,
    /// Per coordinate: its limits restitute with `elasticity`.
    bouncing: Vec<bool>,
    /// Implicit damping per coordinate.
    damping: Vec<f64>,
    /// Multiplier of the hinge rates after each step.
    angular_decay: f64,
    limit_soft: Softness,
    /// MuJoCo's soft joint limits and their margin (the side file's `limit_model`), instead of
    /// `limit_soft`.
    limit_mujoco: Option<(Impedance, f64)>,
    contact: Impedance,
    /// Contacts activate this far above the floor (MuJoCo's `margin`).
    contact_margin: f64,
    /// Restitution of ground contacts.
    elasticity: f64,
    /// Medium viscosity (MuJoCo's inertia-box Stokes drag on every link).
    viscosity: f64,
    /// (coordinate, torque per unit control) of each actuator.
    motors: Vec<(usize, f64)>,
    ctrl_range: [f64; 2],
    torso: usize,
    rk4: bool,
}

impl PlanarSystem {
    /// The system of `model` (which must have passed [`PlanarTree::from_model`]) under `params`.
    pub fn new(model: &RobotModel, params: &RobotParams) -> Result<PlanarSystem, String> {
        let side = &model.side;
        let tree = PlanarTree::from_model(model)?.with_masses(model, params);
        let h = side.timestep;
        let jd = finite_or(params.joint_angular_damping, 0.0).max(0.0);
        let damping = tree
            .dofs
            .iter()
            .zip(&model.joint_names)
            .map(
                |(d, name)| match side.joint_dampings.iter().find(|j| j.joint == *name) {
                    Some(j) => j.damping.max(0.0),
                    None if d.hinge && !d.root => jd,
                    None => 0.0,
                },
            )
            .collect();
        let k = finite_or(params.joint_stiffness, 1.0).max(1e-9);
        let limit_omega = (k / side.limit_reference_inertia).sqrt();
        let strength = match params.actuator_strength {
            Some(s) => finite_or(s, side.strength_reference) / side.strength_reference,
            None => 1.0,
        };
        let mut motors = Vec::new();
        for a in &side.actuators {
            let j = model
                .joint_names
                .iter()
                .position(|n| *n == a.joint)
                .ok_or_else(|| format!("actuator joint {} is not movable", a.joint))?;
            motors.push((j, a.gear * strength));
        }
        let g = finite_or(params.gravity, 0.0);
        let friction = finite_or(params.friction, 0.0).max(0.0);
        let dof_of = |name: &String| model.joint_names.iter().position(|n| n == name);
        let mut rail_friction = vec![0.0; tree.dofs.len()];
        for name in &side.rail_joints {
            let d = dof_of(name).ok_or_else(|| format!("rail joint {name} is not movable"))?;
            if tree.dofs[d].hinge {
                return Err(format!("rail joint {name} is a hinge, not a slide"));
            }
            let carried: f64 = tree
                .links
                .iter()
                .filter(|l| l.ancestors.contains(&d))
                .map(|l| l.mass)
                .sum();
            rail_friction[d] = friction * g.abs() * carried;
        }
        let table_friction = if side.gravity_normal_to_plane {
            tree.links
                .iter()
                .map(|l| {
                    if l.ancestors.is_empty() {
                        0.0
                    } else {
                        friction * g.abs() * l.mass
                    }
                })
                .collect()
        } else {
            Vec::new()
        };
        let mut bouncing = vec![false; tree.dofs.len()];
        for name in &side.bouncing_limits {
            let d = dof_of(name).ok_or_else(|| format!("bouncing limit {name} is not a movable joint"))?;
            if side.limit_model.is_none() {
                return Err(format!("bouncing limit {name} needs the side file's limit_model"));
            }
            bouncing[d] = true;
        }
        Ok(PlanarSystem {
            h,
            gravity: if side.gravity_normal_to_plane { 0.0 } else { g },
            friction,
            rail_friction,
            table_friction,
            bouncing,
            damping,
            angular_decay: (finite_or(params.angular_damping, 0.0) * h).exp(),
            limit_soft: Softness::new(limit_omega, side.limit_damping_ratio, h),
            limit_mujoco: side
                .limit_model
                .as_ref()
                .map(|l| (Impedance::mujoco(l.solref, l.solimp, h), l.margin)),
            contact: side
                .contact_model
                .as_ref()
                .map_or(Impedance::MUJOCO_DEFAULT, |c| Impedance::mujoco(c.solref, c.solimp, h)),
            contact_margin: side.contact_model.as_ref().map_or(0.0, |c| c.margin.max(0.0)),
            elasticity: finite_or(params.elasticity, 0.0).max(0.0),
            viscosity: finite_or(params.viscosity, 0.0).max(0.0),
            motors,
            ctrl_range: side.ctrl_range,
            torso: model.torso,
            rk4: side.integrator == super::model::Integrator::Rk4,
            tree,
        })
    }

    pub fn num_dofs(&self) -> usize {
        self.tree.dofs.len()
    }
}

/// One planar robot instance: coordinates, rates and preallocated work buffers. `Clone`
/// copies the state exactly.
#[derive(Debug, Clone)]
pub struct PlanarWorld {
    sys: Arc<PlanarSystem>,
    q: Vec<f64>,
    v: Vec<f64>,
    links: Vec<LinkState>,
    axes: Vec<DofAxis>,
    mass: Vec<f64>,
    bias: Vec<f64>,
    force: Vec<f64>,
    /// The rates at the start of the step (MuJoCo's limit rows use them).
    v_start: Vec<f64>,
    rows: Rows,
    /// Contact force and torque about the centre of mass of each link over the last step:
    /// `[f_x, f_z, τ_y]`.
    wrench: Vec<[f64; 3]>,
    /// What each row stands for.
    row_site: Vec<RowSite>,
}

/// What a constraint row stands for.
#[derive(Debug, Clone, Copy)]
enum RowSite {
    /// The normal of a contact of `link` at world point `p`.
    Normal {
        link: usize,
        p: [f64; 2],
    },
    /// The friction of a contact of `link` at world point `p`.
    Friction {
        link: usize,
        p: [f64; 2],
    },
    Limit,
    /// Dry friction of a rail or a table.
    Friction0,
}

/// Clamp a state coordinate to a finite value (as the rapier world does).
fn coord(x: f64) -> f64 {
    finite_or(x, 0.0).clamp(-1e6, 1e6)
}

impl PlanarWorld {
    /// The world of `sys` in configuration `c` (joint coordinates and rates in URDF order).
    pub fn new(sys: Arc<PlanarSystem>, c: &Configuration) -> PlanarWorld {
        let n = sys.num_dofs();
        let nl = sys.tree.links.len();
        let mut q = vec![0.0; n];
        let mut v = vec![0.0; n];
        for (d, x) in q.iter_mut().zip(&c.joints) {
            *d = coord(*x);
        }
        for (d, x) in v.iter_mut().zip(&c.vel) {
            *d = coord(*x);
        }
        let capacity = 2 * 2 * sys.tree.capsules.len() + 3 * n + 2 * nl;
        let mut w = PlanarWorld {
            q,
            v,
            links: vec![LinkState::default(); nl],
            axes: vec![DofAxis::default(); n],
            mass: vec![0.0; n * n],
            bias: vec![0.0; n],
            force: vec![0.0; n],
            v_start: vec![0.0; n],
            rows: Rows::new(n, capacity),
            wrench: vec![[0.0; 3]; nl],
            row_site: vec![RowSite::Limit; capacity],
            sys,
        };
        positions(&w.sys.tree, &w.q, &mut w.links, &mut w.axes);
        w
    }

    pub fn system(&self) -> &PlanarSystem {
        &self.sys
    }

    /// Joint coordinates and rates in URDF order.
    pub fn configuration(&self) -> Configuration {
        Configuration {
            root: Vec::new(),
            joints: self.q.clone(),
            vel: self.v.clone(),
        }
    }

    pub fn q(&self) -> &[f64] {
        &self.q
    }
    pub fn v(&self) -> &[f64] {
        &self.v
    }

    /// The mass matrix `M(q)` without armature (row-major `n × n`) and the bias forces at the
    /// current state.
    pub fn mass_matrix_and_bias(&self) -> (Vec<f64>, Vec<f64>) {
        let n = self.sys.num_dofs();
        let mut links = self.links.clone();
        velocities(&self.sys.tree, &self.v, &mut links, &self.axes);
        let mut m = vec![0.0; n * n];
        let mut b = vec![0.0; n];
        dynamics::mass_matrix_and_bias(&self.sys.tree, &links, &self.axes, self.sys.gravity, &mut m, &mut b);
        (m, b)
    }

    /// Mechanical energy (J): the links' kinetic and gravitational energy, the armature's
    /// kinetic energy and the passive springs' energy.
    pub fn energy(&self) -> f64 {
        let tree = &self.sys.tree;
        let mut links = self.links.clone();
        velocities(tree, &self.v, &mut links, &self.axes);
        let joints: f64 = tree
            .dofs
            .iter()
            .zip(self.q.iter().zip(&self.v))
            .map(|(d, (q, v))| 0.5 * (d.armature * v * v + d.spring * q * q))
            .sum();
        dynamics::kinetic_energy(tree, &links) + dynamics::potential_energy(tree, &links, self.sys.gravity) + joints
    }

    fn clipped(&self, u: f32) -> f64 {
        let [lo, hi] = self.sys.ctrl_range;
        if u.is_nan() { 0.0 } else { f64::from(u).clamp(lo, hi) }
    }

    /// The acceleration at the current state (links placed at `q`) into `out`, the constraint
    /// rows included (solved for a step of length `h` from this state); damping explicit. The
    /// state is unchanged. `false` if the mass matrix is not positive definite.
    fn acceleration(&mut self, ctrl: &[f32], out: &mut [f64]) -> bool {
        let sys = Arc::clone(&self.sys);
        let tree = &sys.tree;
        let n = sys.num_dofs();
        let h = sys.h;
        velocities(tree, &self.v, &mut self.links, &self.axes);
        dynamics::mass_matrix_and_bias(
            tree,
            &self.links,
            &self.axes,
            sys.gravity,
            &mut self.mass,
            &mut self.bias,
        );
        for (d, dof) in tree.dofs.iter().enumerate() {
            self.mass[d * n + d] += dof.armature;
            self.force[d] = -self.bias[d] - sys.damping[d] * self.v[d] - dof.spring * self.q[d];
        }
        for (&(d, gear), &u) in sys.motors.iter().zip(ctrl) {
            self.force[d] += gear * self.clipped(u);
        }
        if sys.viscosity > 0.0 {
            self.add_viscosity();
        }
        self.v_start.copy_from_slice(&self.v);
        if !dynamics::cholesky(&mut self.mass, n) {
            return false;
        }
        dynamics::cholesky_solve(&self.mass, n, &mut self.force);
        for (v, a) in self.v.iter_mut().zip(&self.force) {
            *v += h * a;
        }
        self.build_rows();
        self.rows.solve(&self.mass, &mut self.v);
        self.collect_wrenches();
        for ((o, v), v0) in out.iter_mut().zip(&mut self.v).zip(&self.v_start) {
            *o = (*v - v0) / h;
            *v = *v0;
        }
        true
    }

    /// Whether a bouncing limit (`bouncing_limits`, with `elasticity` > 0) is passed and
    /// approached at the current state: an impact with restitution, which an RK4 model
    /// integrates with one semi-implicit Euler step (RK4's averaged stages would blur the
    /// impulse).
    fn impact(&self) -> bool {
        let sys = &*self.sys;
        if sys.elasticity <= 0.0 {
            return false;
        }
        let margin = sys.limit_mujoco.map_or(0.0, |(_, m)| m);
        sys.tree.dofs.iter().enumerate().any(|(d, dof)| {
            let Some((lo, hi)) = dof.limits else { return false };
            sys.bouncing[d]
                && ((self.q[d] - lo < margin && self.v[d] < 0.0) || (hi - self.q[d] < margin && self.v[d] > 0.0))
        })
    }

    /// One RK4 step (MuJoCo's `mj_RungeKutta` with the classic tableau).
    fn step_rk4(&mut self, ctrl: &[f32]) {
        let sys = Arc::clone(&self.sys);
        let n = sys.num_dofs();
        let h = sys.h;
        let (q0, v0) = (self.q.clone(), self.v.clone());
        let mut acc = vec![0.0; 4 * n];
        let mut vel = vec![0.0; 4 * n];
        for k in 0..4 {
            if k > 0 {
                let c = if k == 3 { h } else { h / 2.0 };
                for d in 0..n {
                    self.q[d] = q0[d] + c * vel[(k - 1) * n + d];
                    self.v[d] = v0[d] + c * acc[(k - 1) * n + d];
                }
                positions(&sys.tree, &self.q, &mut self.links, &mut self.axes);
            }
            vel[k * n..(k + 1) * n].copy_from_slice(&self.v);
            if !self.acceleration(ctrl, &mut acc[k * n..(k + 1) * n]) {
                self.v.fill(f64::NAN);
                return;
            }
        }
        let w = [1.0, 2.0, 2.0, 1.0];
        for d in 0..n {
            let (mut a, mut v) = (0.0, 0.0);
            for k in 0..4 {
                a += w[k] * acc[k * n + d];
                v += w[k] * vel[k * n + d];
            }
            self.v[d] = v0[d] + h / 6.0 * a;
            self.q[d] = q0[d] + h / 6.0 * v;
        }
        if sys.angular_decay != 1.0 {
            for (v, dof) in self.v.iter_mut().zip(&sys.tree.dofs) {
                if dof.hinge {
                    *v *= sys.angular_decay;
                }
            }
        }
        positions(&sys.tree, &self.q, &mut self.links, &mut self.axes);
    }

    /// One physics step with motor controls `ctrl` (clipped to the control range).
    pub fn step(&mut self, ctrl: &[f32]) {
        if self.sys.rk4 && !self.impact() {
            self.step_rk4(ctrl);
            return;
        }
        let sys = Arc::clone(&self.sys);
        let tree = &sys.tree;
        let n = sys.num_dofs();
        let h = sys.h;
        velocities(tree, &self.v, &mut self.links, &self.axes);
        dynamics::mass_matrix_and_bias(
            tree,
            &self.links,
            &self.axes,
            sys.gravity,
            &mut self.mass,
            &mut self.bias,
        );
        for (d, dof) in tree.dofs.iter().enumerate() {
            self.mass[d * n + d] += dof.armature + h * sys.damping[d];
            self.force[d] = -self.bias[d] - sys.damping[d] * self.v[d] - dof.spring * self.q[d];
        }
        for (&(d, gear), &u) in sys.motors.iter().zip(ctrl) {
            self.force[d] += gear * self.clipped(u);
        }
        if sys.viscosity > 0.0 {
            self.add_viscosity();
        }
        self.v_start.copy_from_slice(&self.v);
        if !dynamics::cholesky(&mut self.mass, n) {
            self.v.fill(f64::NAN);
            return;
        }
        dynamics::cholesky_solve(&self.mass, n, &mut self.force);
        for (v, a) in self.v.iter_mut().zip(&self.force) {
            *v += h * a;
        }
        self.build_rows();
        self.rows.solve(&self.mass, &mut self.v);
        self.collect_wrenches();
        if sys.angular_decay != 1.0 {
            for (v, dof) in self.v.iter_mut().zip(&tree.dofs) {
                if dof.hinge {
                    *v *= sys.angular_decay;
                }
            }
        }
        for (q, v) in self.q.iter_mut().zip(&self.v) {
            *q += h * v;
        }
        positions(tree, &self.q, &mut self.links, &mut self.axes);
    }

    /// MuJoCo's viscous drag of the medium on every link (its inertia-box model with density
    /// 0): force `−3π μ d v` at the centre of mass and torque `−π μ d³ ω`, `d` the link's box
    /// diameter; linear in the rates, so it enters implicitly: `h·Dᵥ` joins the mass matrix and
    /// `−Dᵥ v` the forces.
    fn add_viscosity(&mut self) {
        let sys = &*self.sys;
        let n = sys.num_dofs();
        let h = sys.h;
        let mu = sys.viscosity;
        for (l, s) in sys.tree.links.iter().zip(&self.links) {
            if l.ancestors.is_empty() {
                continue;
            }
            let d = l.box_diameter;
            let (cl, ca) = (
                3.0 * std::f64::consts::PI * mu * d,
                std::f64::consts::PI * mu * d * d * d,
            );
            let vc = point_velocity(s, s.com);
            for &da in &l.ancestors {
                let (ja, wa) = self.axes[da].point_column(s.com);
                self.force[da] -= cl * kinematics::dot(ja, vc) + ca * wa * s.omega;
                for &db in &l.ancestors {
                    let (jb, wb) = self.axes[db].point_column(s.com);
                    self.mass[da * n + db] += h * (cl * kinematics::dot(ja, jb) + ca * wa * wb);
                }
            }
        }
    }

    /// Contact rows (end spheres of the capsules near the ground) and joint-limit rows.
    fn build_rows(&mut self) {
        let sys = &*self.sys;
        let tree = &sys.tree;
        let h = sys.h;
        self.rows.clear();
        for cap in tree.capsules.iter().filter(|c| c.ground) {
            let s = &self.links[cap.link];
            let ends = if cap.a == cap.b { 1 } else { 2 };
            for &e in [cap.a, cap.b].iter().take(ends) {
                let centre = kinematics::add(s.pos, tree::rotate(s.cs, e));
                // Contacts within the margin (MuJoCo's; HalfCheetah's is zero), the
                // penetration measured from it.
                let gap = centre[1] - cap.radius - sys.contact_margin;
                if gap >= 0.0 {
                    continue;
                }
                let p = [centre[0], centre[1] - cap.radius];
                let anc = &tree.links[cap.link].ancestors;
                let v0 = point_velocity(s, p);
                // The normal: MuJoCo's soft contact (and a bounce of `elasticity` times the
                // approach speed); friction: Coulomb's box, stiff (a resting contact does not
                // creep).
                let r = self.rows.count;
                let (mut target, ratio) = sys.contact.row(v0[1], gap, h);
                if sys.elasticity > 0.0 && v0[1] < 0.0 {
                    target = target.max(-sys.elasticity * v0[1]);
                }
                let Some(row) = self.rows.push(RowKind::Unilateral, target, ratio) else {
                    return;
                };
                for &d in anc {
                    row[d] = self.axes[d].point_column(p).0[1];
                }
                self.row_site[r] = RowSite::Normal { link: cap.link, p };
                let friction = RowKind::Friction {
                    normal: r,
                    mu: sys.friction,
                };
                let Some(row) = self.rows.push(friction, 0.0, 0.0) else {
                    return;
                };
                for &d in anc {
                    row[d] = self.axes[d].point_column(p).0[0];
                }
                self.row_site[r + 1] = RowSite::Friction { link: cap.link, p };
            }
        }
        let first_limit = self.rows.count;
        for (d, dof) in tree.dofs.iter().enumerate() {
            let Some((lo, hi)) = dof.limits else { continue };
            if let Some((imp, margin)) = sys.limit_mujoco {
                // MuJoCo's soft limit: active within the margin, penetration from it.
                for (dist, sign) in [(self.q[d] - lo, 1.0), (hi - self.q[d], -1.0)] {
                    let r = dist - margin;
                    if r >= 0.0 {
                        continue;
                    }
                    let approach = sign * self.v_start[d];
                    let (mut target, ratio) = imp.row(approach, r, h);
                    if sys.bouncing[d] && sys.elasticity > 0.0 && approach < 0.0 {
                        target = target.max(-sys.elasticity * approach);
                    }
                    let Some(row) = self.rows.push(RowKind::Unilateral, target, ratio) else {
                        return;
                    };
                    row[d] = sign;
                }
                continue;
            }
            // Rows for limits within reach of this step's motion (and a margin).
            let reach = 1e-2 + h * self.v[d].abs();
            for (gap, sign) in [(self.q[d] - lo, 1.0), (hi - self.q[d], -1.0)] {
                if gap > reach {
                    continue;
                }
                let Some(row) = self.rows.push_gap(gap, sys.limit_soft, h) else {
                    return;
                };
                row[d] = sign;
            }
        }
        for site in &mut self.row_site[first_limit..self.rows.count] {
            *site = RowSite::Limit;
        }
        let first_friction = self.rows.count;
        for (d, &f) in sys.rail_friction.iter().enumerate() {
            if f > 0.0 {
                let Some(row) = self.rows.push(RowKind::Bounded { limit: f * h }, 0.0, 0.0) else {
                    return;
                };
                row[d] = 1.0;
            }
        }
        for (l, &f) in sys.table_friction.iter().enumerate() {
            if f <= 0.0 {
                continue;
            }
            let com = self.links[l].com;
            for axis in 0..2 {
                let Some(row) = self.rows.push(RowKind::Bounded { limit: f * h }, 0.0, 0.0) else {
                    return;
                };
                for &d in &tree.links[l].ancestors {
                    row[d] = self.axes[d].point_column(com).0[axis];
                }
            }
        }
        for site in &mut self.row_site[first_friction..self.rows.count] {
            *site = RowSite::Friction0;
        }
    }

    /// Generalized constraint forces of the last step (MuJoCo's `qfrc_constraint`): every
    /// row's impulse over the step, one per coordinate.
    pub fn constraint_forces(&self, out: &mut [f64]) {
        let n = self.sys.num_dofs();
        out.fill(0.0);
        for r in 0..self.rows.count {
            let f = self.rows.lambda[r] / self.sys.h;
            for (o, j) in out.iter_mut().zip(&self.rows.jac[r * n..(r + 1) * n]) {
                *o += j * f;
            }
        }
    }

    /// World position `[x, 0, z]` of the point `local` (`[x, y, z]`, y ignored) of link `i`.
    pub fn link_point(&self, i: usize, local: [f64; 3]) -> [f64; 3] {
        let s = &self.links[i];
        let p = kinematics::add(s.pos, tree::rotate(s.cs, [local[0], local[2]]));
        [p[0], 0.0, p[1]]
    }

    /// Per-link contact force and torque of the last step from the contact impulses.
    fn collect_wrenches(&mut self) {
        let h = self.sys.h;
        self.wrench.iter_mut().for_each(|w| *w = [0.0; 3]);
        for r in 0..self.rows.count {
            let f = self.rows.lambda[r] / h;
            let (link, p, force) = match self.row_site[r] {
                RowSite::Normal { link, p } => (link, p, [0.0, f]),
                RowSite::Friction { link, p } => (link, p, [f, 0.0]),
                RowSite::Limit | RowSite::Friction0 => continue,
            };
            let c = self.links[link].com;
            let rr = kinematics::sub(p, c);
            let w = &mut self.wrench[link];
            w[0] += force[0];
            w[1] += force[1];
            w[2] += rr[1] * force[0] - rr[0] * force[1];
        }
    }

    /// External contact wrench on each link over the last step, MuJoCo `cfrc_ext` order
    /// `[torque, force]` (world frame, torque about the link's centre of mass); normal and
    /// friction forces.
    pub fn contact_wrenches(&self, out: &mut [f64]) {
        for (li, w) in self.wrench.iter().enumerate() {
            let o = 6 * li;
            if o + 6 <= out.len() {
                out[o..o + 6].copy_from_slice(&[0.0, w[2], 0.0, w[0], 0.0, w[1]]);
            }
        }
    }

    /// Whether every coordinate and rate is finite and no rate exceeds `max_speed`.
    pub fn is_sane(&self, max_speed: f64) -> bool {
        self.q.iter().all(|x| x.is_finite()) && self.v.iter().all(|v| v.is_finite() && v.abs() <= max_speed)
    }

    /// World pose of link `i` (its frame's origin and pitch).
    pub fn link_pose(&self, i: usize) -> Pose {
        let s = &self.links[i];
        Pose::from_parts(
            Vector::new(s.pos[0] as f32, 0.0, s.pos[1] as f32),
            Rotation::from_rotation_y(s.angle as f32),
        )
    }

    /// The torso link's index.
    pub fn torso(&self) -> usize {
        self.sys.torso
    }

    /// Generalized actuator forces under controls `ctrl`, one per coordinate.
    pub fn actuator_forces(&self, ctrl: &[f32], out: &mut [f64]) {
        out.fill(0.0);
        for (&(d, gear), &u) in self.sys.motors.iter().zip(ctrl) {
            if let Some(o) = out.get_mut(d) {
                *o += gear * self.clipped(u);
            }
        }
    }

    /// Mass (kg) of link `i`.
    pub fn link_mass(&self, i: usize) -> f64 {
        self.sys.tree.links[i].mass
    }

    /// Mass-weighted centre of mass of the moving links.
    pub fn center_of_mass(&self) -> [f64; 3] {
        let (mut m, mut c) = (0.0, [0.0; 2]);
        for (l, s) in self.sys.tree.links.iter().zip(&self.links) {
            if l.parent.is_some() {
                m += l.mass;
                c[0] += l.mass * s.com[0];
                c[1] += l.mass * s.com[1];
            }
        }
        if m > 0.0 { [c[0] / m, 0.0, c[1] / m] } else { [0.0; 3] }
    }

    /// The world pose of every link's centre of mass `[x, z]` (for tests and diagnostics).
    pub fn link_com(&self, i: usize) -> [f64; 2] {
        self.links[i].com
    }

    /// The capsules of the robot in world coordinates: (link, end a, end b, radius).
    pub fn capsules(&self) -> impl Iterator<Item = (usize, [f64; 3], [f64; 3], f64)> + '_ {
        self.sys.tree.capsules.iter().map(|c| {
            let s = &self.links[c.link];
            let a = kinematics::add(s.pos, tree::rotate(s.cs, c.a));
            let b = kinematics::add(s.pos, tree::rotate(s.cs, c.b));
            (c.link, [a[0], 0.0, a[1]], [b[0], 0.0, b[1]], c.radius)
        })
    }
}

#[cfg(test)]
mod tests;
