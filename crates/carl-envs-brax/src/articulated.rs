//! Robots on the articulated-body engine ([`carl_articulated`], MuJoCo's semantics): the
//! loader from a [`RobotModel`] (URDF + side file) and a context to a
//! [`carl_articulated::Model`], kept apart from the engine, and [`ArticulatedWorld`], one
//! instance with the operations the tasks call.
//!
//! The URDF's root link is body 1 (a free joint when the side file's root is `free`, welded to
//! the world otherwise); every other link is a body placed at its joint's origin, hinge or
//! slide along the URDF axis (fixed joints weld). A carrier link (massless, no colliders, one
//! child on a hinge or slide at its own frame: [`super::model::is_carrier`]) and its child are
//! one body with both joints, in order (MuJoCo's several hinges of one body, e.g. Humanoid's
//! hips). Inertials: the URDF tensor's principal axes.
//! Colliders: spheres, capsules, cylinders and boxes; the floor is a plane at the side file's
//! `floor_height`. How the context enters:
//! * `gravity` → the gravity vector's z; `friction` → every geom's sliding friction (MuJoCo
//!   takes the pair's larger, so every contact has it; at 0 every contact is frictionless,
//!   condim 1);
//! * `joint_angular_damping` → MuJoCo's joint damping of every robot joint the side file's
//!   `joint_dampings` does not list (implicit under Euler, explicit under RK4, as MuJoCo); with
//!   a `damping_reference`, the listed dampings scaled by `joint_angular_damping / reference`;
//! * `joint_stiffness` → the joint limits unless the side file gives a `limit_model`: MuJoCo
//!   soft limits with `solref = [−k/I, −2ζ√(k/I)]` (stiffness and damping form), `k` the
//!   feature, `I` the side file's `limit_reference_inertia`, `ζ` its `limit_damping_ratio`
//!   (`k = 2500`, `I = 1`, `ζ = 1` are MuJoCo's default `solreflimit` (0.02, 1));
//! * `actuator_strength` → the motors' gear (`gear · strength / strength_reference`);
//! * `torso_mass`, `mass_<link>` → link masses (the inertia scales with the mass); with the side
//!   file's `welded_masses`, the mass of the link together with the links welded to it, each
//!   scaled by one factor (Brax's links, which carl-bench's features name);
//! * `angular_damping` → after each step every hinge rate and the free root's angular velocity
//!   are scaled by `exp(angular_damping · h)` (Brax's global angular damping; 0 in MuJoCo);
//! * `viscosity` → MuJoCo's medium viscosity;
//! * `elasticity` → the restitution of every contact and of the side file's `bouncing_limits`
//!   (a carl extension; 0 is MuJoCo's);
//! * robots welded to the world: a `rail_joints` slide gets MuJoCo's `frictionloss`
//!   `friction · |gravity| ·` the mass it carries; with `gravity_normal_to_plane` (an arm on a
//!   horizontal table, modelled turned by +90° about x) gravity points along the URDF's y and
//!   each moving body slides on the table with dry friction `friction · |gravity| · m`.
//!
//! Roots: `free` (a free joint, the root link at `root_height`) or `fixed` (welded at the world
//! frame); a planar root's `root_joints` (two slides and a hinge on stand-in links) fold into
//! the torso as MuJoCo's three joints of one body.
//!
//! Contacts use the side file's `contact_model` (`solref`, `solimp`, and the robot–floor pair's
//! `margin`, of which the floor has `floor_margin`, default 0, and each robot geom the rest) or
//! MuJoCo's defaults, the robot geoms' `condim` the side file's `contact_condim` (default 3; the
//! floor's is 3, a pair takes the larger); robot geoms collide with the floor, with
//! each other only under `self_collisions` (MuJoCo's parent–child filter applies; only the side
//! file's `contact_links` when it names any), and only the side file's `ground_links` touch the
//! floor when it names any.
//!
//! Velocities are MuJoCo's: a free root's linear velocity in the world frame, its angular
//! velocity in the root body's frame. [`ArticulatedWorld::com_inertia`] and
//! [`ArticulatedWorld::com_velocity`] give MuJoCo's `cinert` and `cvel` about a point (the
//! robot's centre of mass) from the state the last step ended in.

use std::sync::Arc;

use carl_articulated::math::{self, M3, V3};
use carl_articulated::model::{Actuator, Body, Geom, Integrator, Joint, JointKind, Model, Options, Shape};
use carl_articulated::{Data, model::SOLIMP_DEFAULT};
use rapier3d_urdf::urdf_rs;

use super::model::{RobotModel, RootKind};
use super::params::{RobotParams, finite_or};
use super::world::Configuration;

/// URDF `rpy` as a rotation matrix `Rz(yaw)·Ry(pitch)·Rx(roll)`.
fn rpy_mat(rpy: [f64; 3]) -> M3 {
    let (sr, cr) = rpy[0].sin_cos();
    let (sp, cp) = rpy[1].sin_cos();
    let (sy, cy) = rpy[2].sin_cos();
    [
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ]
}

/// The context-dependent parts of an articulated robot, shared by its instances.
#[derive(Debug)]
pub struct ArticulatedSystem {
    pub model: Arc<Model>,
    /// Body of each URDF link.
    pub link_body: Vec<usize>,
    /// (qpos address, dof address) of each movable URDF joint, URDF order.
    joint_addr: Vec<(usize, usize)>,
    free_root: bool,
    /// Multiplier of hinge rates and the free root's angular velocity after each step.
    angular_decay: f64,
    torso: usize,
}

impl ArticulatedSystem {
    /// The engine model of `robot` under `params`, or why it cannot be built.
    pub fn new(robot: &RobotModel, params: &RobotParams) -> Result<ArticulatedSystem, String> {
        let side = &robot.side;
        let urdf = &robot.urdf;
        let nl = urdf.links.len();
        let link_index = |name: &str| urdf.links.iter().position(|l| l.name == name);
        // Parent joint of each link.
        let mut parent_joint: Vec<Option<usize>> = vec![None; nl];
        for (j, jt) in urdf.joints.iter().enumerate() {
            let (Some(_), Some(c)) = (link_index(&jt.parent.link), link_index(&jt.child.link)) else {
                return Err(format!("joint {} names a link that does not exist", jt.name));
            };
            if parent_joint[c].is_some() {
                return Err(format!("link {} has two parent joints", jt.child.link));
            }
            parent_joint[c] = Some(j);
        }
        let roots: Vec<usize> = (0..nl).filter(|&i| parent_joint[i].is_none()).collect();
        if roots.len() != 1 {
            return Err("the URDF must form one tree".into());
        }
        // Links depth-first, children in URDF joint order (MuJoCo's body order for a converted
        // XML, so coordinates line up with MuJoCo's `qpos`).
        let mut order = Vec::with_capacity(nl);
        let mut stack = vec![roots[0]];
        while let Some(li) = stack.pop() {
            order.push(li);
            let name = &urdf.links[li].name;
            let children: Vec<usize> = urdf
                .joints
                .iter()
                .filter(|j| j.parent.link == *name)
                .filter_map(|j| link_index(&j.child.link))
                .collect();
            if order.len() + stack.len() + children.len() > nl {
                return Err("the URDF's joints form a loop".into());
            }
            stack.extend(children.into_iter().rev());
        }
        if order.len() != nl {
            return Err("the URDF's joints form a loop".into());
        }
        let h = side.timestep;
        let strength = match params.actuator_strength {
            Some(s) => finite_or(s, side.strength_reference) / side.strength_reference,
            None => 1.0,
        };
        let jd = finite_or(params.joint_angular_damping, 0.0).max(0.0);
        let k_lim = finite_or(params.joint_stiffness, 1.0).max(1e-9) / side.limit_reference_inertia;
        let limit_solref = [-k_lim, -2.0 * side.limit_damping_ratio * k_lim.sqrt()];
        let friction = finite_or(params.friction, 0.0).max(0.0);
        let (solref, solimp, margin) = match &side.contact_model {
            Some(c) => (c.solref, c.solimp, c.margin.max(0.0)),
            None => (carl_articulated::model::SOLREF_DEFAULT, SOLIMP_DEFAULT, 0.0),
        };
        let floor_margin = side.floor_margin.clamp(0.0, margin);
        let elasticity = finite_or(params.elasticity, 0.0).max(0.0);
        let g = finite_or(params.gravity, 0.0);
        // At friction 0 every contact is frictionless (condim 1, MuJoCo's frictionless contact;
        // a pyramid of zero friction would be four copies of the normal).
        let condim = if friction > 0.0 {
            side.contact_condim.unwrap_or(3)
        } else {
            1
        };
        // With the side file's `welded_masses`, `mass_<link>` is the mass of the link with the
        // links welded to it (Brax's links, which carl-bench's features name): each link's group
        // head and each head's total URDF mass.
        let group_head: Vec<usize> = (0..nl)
            .map(|li| {
                let mut h = li;
                while side.welded_masses
                    && let Some(j) = parent_joint[h]
                    && urdf.joints[j].joint_type == urdf_rs::JointType::Fixed
                {
                    h = link_index(&urdf.joints[j].parent.link).expect("checked");
                }
                h
            })
            .collect();
        let mut group_mass = vec![0.0; nl];
        for (li, &h) in group_head.iter().enumerate() {
            group_mass[h] += urdf.links[li].inertial.mass.value;
        }
        let mut bodies = vec![Body::new("world", 0, [0.0; 3], 0.0, [0.0; 3], [0.0; 3])];
        let mut joints = Vec::new();
        let mut geoms = Vec::new();
        let mut link_body = vec![0; nl];
        let mut urdf_joint_model: Vec<Option<usize>> = vec![None; urdf.joints.len()];
        // A planar root's slides are carried by stand-in links (their small mass keeps rapier's
        // multibody well posed): MuJoCo puts all three root joints on the torso, so do we.
        let root_joint = |j: Option<usize>| j.is_some_and(|j| side.root_joints.contains(&urdf.joints[j].name));
        let carrier: Vec<bool> = (0..nl)
            .map(|i| {
                let children: Vec<usize> = (0..urdf.joints.len())
                    .filter(|&j| urdf.joints[j].parent.link == urdf.links[i].name)
                    .collect();
                let root_carrier = root_joint(parent_joint[i])
                    && urdf.links[i].collision.is_empty()
                    && matches!(children[..], [c] if root_joint(Some(c))
                        && urdf.joints[c].origin.xyz.0 == [0.0; 3]
                        && urdf.joints[c].origin.rpy.0 == [0.0; 3]);
                super::model::is_carrier(urdf, i) || root_carrier
            })
            .collect();
        for &li in &order {
            let l = &urdf.links[li];
            // The child of a carrier shares the carrier's body (one body, several joints).
            let merged = parent_joint[li]
                .and_then(|j| link_index(&urdf.joints[j].parent.link))
                .filter(|&p| carrier[p]);
            let b = merged.map_or(bodies.len(), |p| link_body[p]);
            link_body[li] = b;
            let (parent, pos, quat) = match parent_joint[li] {
                // A free root starts at `root_height`; a fixed one is the world's frame (a planar
                // root's joints place the torso).
                None if side.root == RootKind::Free => (0, [0.0, 0.0, side.root_height], math::QUAT_IDENTITY),
                None => (0, [0.0; 3], math::QUAT_IDENTITY),
                Some(j) => {
                    let jt = &urdf.joints[j];
                    let p = link_body[link_index(&jt.parent.link).expect("checked")];
                    (p, jt.origin.xyz.0, math::mat_to_quat(&rpy_mat(jt.origin.rpy.0)))
                }
            };
            // Mass with the context's overrides; the inertia scales with it.
            let base = l.inertial.mass.value;
            let head = group_head[li];
            let mut target = None;
            if head == robot.torso {
                target = params.torso_mass;
            }
            if let Some((_, v)) = params.link_masses.iter().find(|(n, _)| *n == urdf.links[head].name) {
                target = Some(*v);
            }
            // A welded group (`welded_masses`): the override is the group's mass, every member
            // scaled by one factor.
            let m = match target {
                Some(t) if group_mass[head] != base => base * t / group_mass[head],
                Some(t) => t,
                None => base,
            };
            let ine = &l.inertial.inertia;
            let tensor = [
                [ine.ixx, ine.ixy, ine.ixz],
                [ine.ixy, ine.iyy, ine.iyz],
                [ine.ixz, ine.iyz, ine.izz],
            ];
            let (moments, axes) = math::principal_axes(&tensor);
            let frame = math::mat_to_quat(&rpy_mat(l.inertial.origin.rpy.0));
            if carrier[li] {
                // Filled in by the carried link (a carrier carried by a carrier adds nothing).
                if merged.is_none() {
                    let mut body = Body::new(&l.name, parent, pos, 0.0, [0.0; 3], [0.0; 3]);
                    body.quat = quat;
                    bodies.push(body);
                }
            } else {
                let m = finite_or(m, base).max(1e-6);
                let moments = math::scale(moments, m / base);
                match merged {
                    Some(_) => {
                        let body = &mut bodies[b];
                        body.name.clone_from(&l.name);
                        body.mass = m;
                        body.ipos = l.inertial.origin.xyz.0;
                        body.inertia = moments;
                        body.iquat = math::quat_mul(frame, axes);
                    }
                    None => {
                        let mut body = Body::new(&l.name, parent, pos, m, l.inertial.origin.xyz.0, moments);
                        body.quat = quat;
                        body.iquat = math::quat_mul(frame, axes);
                        bodies.push(body);
                    }
                }
            }
            // A fixed joint welds the link: its body has no joint (MuJoCo's weld), its colliders stay.
            let welded = parent_joint[li].is_some_and(|j| urdf.joints[j].joint_type == urdf_rs::JointType::Fixed);
            match parent_joint[li] {
                _ if welded => {}
                None if side.root == RootKind::Free => {
                    joints.push(Joint::new("root", b, JointKind::Free, [0.0, 0.0, 1.0]));
                }
                None => {}
                Some(j) => {
                    let jt = &urdf.joints[j];
                    let kind = match jt.joint_type {
                        urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous => JointKind::Hinge,
                        urdf_rs::JointType::Prismatic => JointKind::Slide,
                        ref other => return Err(format!("joint {} is a {other:?} joint", jt.name)),
                    };
                    let name = &jt.name;
                    let root = side.root_joints.contains(name);
                    let mut joint = Joint::new(name, b, kind, jt.axis.xyz.0);
                    joint.armature = if root {
                        0.0
                    } else {
                        side.joint_armatures
                            .iter()
                            .find(|a| a.joint == *name)
                            .map_or(side.joint_armature, |a| a.armature)
                    };
                    joint.damping = match side.joint_dampings.iter().find(|d| d.joint == *name) {
                        Some(d) => match side.damping_reference {
                            Some(r) => d.damping.max(0.0) * jd / r,
                            None => d.damping.max(0.0),
                        },
                        None if !root => jd,
                        None => 0.0,
                    };
                    joint.stiffness = side
                        .joint_springs
                        .iter()
                        .find(|s| s.joint == *name)
                        .map_or(0.0, |s| s.stiffness);
                    if !root
                        && !matches!(jt.joint_type, urdf_rs::JointType::Continuous)
                        && jt.limit.lower < jt.limit.upper
                    {
                        joint.range = Some([jt.limit.lower, jt.limit.upper]);
                    }
                    if side.bouncing_limits.contains(name) {
                        joint.restitution = elasticity;
                    }
                    match &side.limit_model {
                        Some(lm) => {
                            joint.solref_limit = lm.solref;
                            joint.solimp_limit = lm.solimp;
                            joint.margin = lm.margin;
                        }
                        None => {
                            joint.solref_limit = limit_solref;
                            if let Some(si) = side.limit_solimp {
                                joint.solimp_limit = si;
                            }
                        }
                    }
                    urdf_joint_model[j] = Some(joints.len());
                    joints.push(joint);
                }
            }
            let ground = side.ground_contacts && (side.ground_links.is_empty() || side.ground_links.contains(&l.name));
            for c in &l.collision {
                let shape = match c.geometry {
                    urdf_rs::Geometry::Sphere { radius } => Shape::Sphere { radius },
                    urdf_rs::Geometry::Capsule { radius, length } => Shape::Capsule {
                        radius,
                        half_length: length / 2.0,
                    },
                    urdf_rs::Geometry::Cylinder { radius, length } => Shape::Cylinder {
                        radius,
                        half_length: length / 2.0,
                    },
                    urdf_rs::Geometry::Box { size } => Shape::Box {
                        half: math::scale(size.0, 0.5),
                    },
                    ref g => return Err(format!("a collider of link {} is a {g:?}", l.name)),
                };
                let mut g = Geom::new(&l.name, b, shape, c.origin.xyz.0);
                g.quat = math::mat_to_quat(&rpy_mat(c.origin.rpy.0));
                g.friction[0] = friction;
                g.solref = solref;
                g.solimp = solimp;
                g.margin = margin - floor_margin;
                g.condim = condim;
                g.restitution = elasticity;
                // Bit 1: the floor (contype = conaffinity = 1); bit 2: other robot geoms.
                let contact = side.contact_links.is_empty() || side.contact_links.contains(&l.name);
                let selfc = if side.self_collisions && contact { 2 } else { 0 };
                g.contype = u32::from(ground) | selfc;
                g.conaffinity = selfc;
                geoms.push(g);
            }
        }
        if side.ground_contacts {
            let mut floor = Geom::new("floor", 0, Shape::Plane, [0.0, 0.0, side.floor_height]);
            floor.friction[0] = friction;
            floor.condim = condim.max(if friction > 0.0 { 3 } else { 1 });
            floor.solref = solref;
            floor.solimp = solimp;
            floor.margin = floor_margin;
            floor.restitution = elasticity;
            floor.contype = 1;
            floor.conaffinity = 1;
            geoms.push(floor);
        }
        // Joints must be listed in body order (they are: bodies were made parent-first).
        let mut actuators = Vec::new();
        for a in &side.actuators {
            let j = urdf.joints.iter().position(|j| j.name == a.joint);
            let Some(mj) = j.and_then(|j| urdf_joint_model[j]) else {
                return Err(format!("actuator joint {} is not a movable joint", a.joint));
            };
            actuators.push(Actuator::motor(&a.joint, mj, a.gear * strength, Some(side.ctrl_range)));
        }
        // Dry friction of the rails and tables that carry a robot welded to the world: a rail
        // joint's `frictionloss` is `friction · |g| ·` the mass it carries (its body's subtree);
        // on a table normal to gravity each moving body slides with `friction · |g| · m`.
        let mut subtree: Vec<f64> = bodies.iter().map(|b| b.mass).collect();
        for b in (1..bodies.len()).rev() {
            let p = bodies[b].parent;
            if p != 0 {
                subtree[p] += subtree[b];
            }
        }
        for name in &side.rail_joints {
            let joint = joints
                .iter_mut()
                .find(|j| j.name == *name)
                .ok_or_else(|| format!("rail joint {name} is not a movable joint"))?;
            if joint.kind != JointKind::Slide {
                return Err(format!("rail joint {name} is a hinge, not a slide"));
            }
            joint.frictionloss = friction * g.abs() * subtree[joint.body];
        }
        for name in &side.bouncing_limits {
            if !joints.iter().any(|j| j.name == *name) {
                return Err(format!("bouncing limit {name} is not a movable joint"));
            }
        }
        if side.gravity_normal_to_plane {
            // A body moves if it or an ancestor has a joint (bodies are parent-first).
            let mut moves = vec![false; bodies.len()];
            for b in 1..bodies.len() {
                moves[b] = moves[bodies[b].parent] || joints.iter().any(|j| j.body == b);
                if moves[b] {
                    bodies[b].dryfriction = friction * g.abs() * bodies[b].mass;
                }
            }
        }
        let opt = Options {
            timestep: h,
            // A robot moving in a horizontal plane is modelled turned by +90° about x (MuJoCo's
            // (x, y, z) is the URDF's (x, −z, y)): gravity is along the URDF's y.
            gravity: if side.gravity_normal_to_plane {
                [0.0, -g, 0.0]
            } else {
                [0.0, 0.0, g]
            },
            integrator: match side.integrator {
                super::model::Integrator::Euler => Integrator::Euler,
                super::model::Integrator::Rk4 => Integrator::Rk4,
            },
            viscosity: finite_or(params.viscosity, 0.0).max(0.0),
            ..Options::default()
        };
        let model = Model::new(opt, bodies, joints, geoms, actuators).map_err(|e| e.to_string())?;
        let joint_addr = robot
            .joint_names
            .iter()
            .map(|n| {
                let j = model.joint_index(n).expect("every movable URDF joint is a model joint");
                (model.jnt_qposadr[j], model.jnt_dofadr[j])
            })
            .collect();
        Ok(ArticulatedSystem {
            free_root: side.root == RootKind::Free,
            angular_decay: (finite_or(params.angular_damping, 0.0) * h).exp(),
            torso: link_body[robot.torso],
            link_body,
            joint_addr,
            model: Arc::new(model),
        })
    }
}

/// One robot instance on the articulated engine. `Clone` copies the state exactly.
#[derive(Debug, Clone)]
pub struct ArticulatedWorld {
    sys: Arc<ArticulatedSystem>,
    data: Data,
    /// Contact wrench of each body over the last step.
    wrench: Vec<[f64; 6]>,
}

fn coord(x: f64) -> f64 {
    finite_or(x, 0.0).clamp(-1e6, 1e6)
}

impl ArticulatedWorld {
    /// The world of `sys` in configuration `c` (root pose, joints in URDF order, rates).
    pub fn new(sys: Arc<ArticulatedSystem>, c: &Configuration) -> ArticulatedWorld {
        let mut data = Data::new(Arc::clone(&sys.model));
        if sys.free_root {
            for (k, x) in c.root.iter().take(7).enumerate() {
                data.qpos[k] = coord(*x);
            }
            let q = math::quat_normalize([data.qpos[3], data.qpos[4], data.qpos[5], data.qpos[6]]);
            data.qpos[3..7].copy_from_slice(&q);
            for (k, v) in c.vel.iter().take(6).enumerate() {
                data.qvel[k] = coord(*v);
            }
        }
        let off = if sys.free_root { 6 } else { 0 };
        for (i, &(qa, da)) in sys.joint_addr.iter().enumerate() {
            if let Some(x) = c.joints.get(i) {
                data.qpos[qa] = coord(*x);
            }
            if let Some(v) = c.vel.get(off + i) {
                data.qvel[da] = coord(*v);
            }
        }
        data.update_kinematics();
        let nb = sys.model.bodies.len();
        ArticulatedWorld {
            data,
            wrench: vec![[0.0; 6]; nb],
            sys,
        }
    }

    pub fn data(&self) -> &Data {
        &self.data
    }

    pub fn system(&self) -> &ArticulatedSystem {
        &self.sys
    }

    /// Root pose (free root), joints in URDF order and rates (root first).
    pub fn configuration(&self) -> Configuration {
        let d = &self.data;
        let off = if self.sys.free_root { 6 } else { 0 };
        let mut vel = d.qvel[..off].to_vec();
        vel.extend(self.sys.joint_addr.iter().map(|&(_, da)| d.qvel[da]));
        Configuration {
            root: if self.sys.free_root {
                d.qpos[..7].to_vec()
            } else {
                Vec::new()
            },
            joints: self.sys.joint_addr.iter().map(|&(qa, _)| d.qpos[qa]).collect(),
            vel,
        }
    }

    /// One physics step with motor controls `ctrl` (clipped to the control range).
    pub fn step(&mut self, ctrl: &[f32]) {
        self.steps(ctrl, 1);
    }

    /// `n` physics steps with motor controls `ctrl` (an environment step's frame skip); the
    /// contact wrenches are the last step's, positions and velocities the final state's (one
    /// kinematics pass at the end: each step's forward pass makes its own).
    pub fn steps(&mut self, ctrl: &[f32], n: usize) {
        for (c, u) in self.data.ctrl.iter_mut().zip(ctrl) {
            *c = f64::from(*u);
        }
        for _ in 0..n {
            self.physics_step();
        }
        self.data.contact_wrenches(&mut self.wrench);
        self.data.update_kinematics();
    }

    fn physics_step(&mut self) {
        self.data.step();
        let decay = self.sys.angular_decay;
        if decay != 1.0 {
            let m = &*self.sys.model;
            for (j, jt) in m.joints.iter().enumerate() {
                let da = m.jnt_dofadr[j];
                match jt.kind {
                    JointKind::Hinge => self.data.qvel[da] *= decay,
                    JointKind::Free => self.data.qvel[da + 3..da + 6].iter_mut().for_each(|v| *v *= decay),
                    JointKind::Slide => {}
                }
            }
        }
    }

    /// Whether every coordinate and rate is finite and no rate exceeds `max_speed`.
    pub fn is_sane(&self, max_speed: f64) -> bool {
        self.data.is_sane(max_speed)
    }

    /// Generalized constraint forces of the last step (MuJoCo's `qfrc_constraint`), one per
    /// velocity coordinate (a free root's six first).
    pub fn constraint_forces(&self, out: &mut [f64]) {
        out.fill(0.0);
        for (o, f) in out.iter_mut().zip(&self.data.qfrc_constraint) {
            *o = *f;
        }
    }

    /// World position of the point `local` (link frame) of URDF link `i`.
    pub fn link_point(&self, i: usize, local: [f64; 3]) -> [f64; 3] {
        let b = self.sys.link_body[i];
        carl_articulated::math::add(
            self.data.xpos[b],
            carl_articulated::math::mat_vec(&self.data.xmat[b], local),
        )
    }

    /// Contact wrench on each URDF link over the last step, `[torque, force]` (world frame,
    /// torque about the link's centre of mass), 6 per link.
    pub fn contact_wrenches(&self, out: &mut [f64]) {
        for (li, &b) in self.sys.link_body.iter().enumerate() {
            if let Some(o) = out.get_mut(6 * li..6 * li + 6) {
                o.copy_from_slice(&self.wrench[b]);
            }
        }
    }

    /// Link wrenches (as [`ArticulatedWorld::contact_wrenches`]) of `bodies` with the torque
    /// moved to `c` (MuJoCo's com-based `cfrc_ext`).
    pub fn com_wrenches(&self, bodies: &[usize], c: [f64; 3], link_wrenches: &[f64], out: &mut [f64]) {
        for (k, &i) in bodies.iter().enumerate() {
            let p = self.data.xipos[self.sys.link_body[i]];
            let w = &link_wrenches[6 * i..6 * i + 6];
            let f = [w[3], w[4], w[5]];
            let t = math::cross(math::sub(p, c), f);
            let o = &mut out[6 * k..6 * k + 6];
            for j in 0..3 {
                o[j] = w[j] + t[j];
                o[3 + j] = f[j];
            }
        }
    }

    /// MuJoCo's `cinert` of the links `bodies` about `c`, 10 values per body:
    /// `[Ixx Iyy Izz Ixy Ixz Iyz, m·d, m]`, `d` = the link's centre of mass − `c`.
    pub fn com_inertia(&self, bodies: &[usize], c: [f64; 3], out: &mut [f64]) {
        let m = &*self.sys.model;
        for (k, &i) in bodies.iter().enumerate() {
            let bi = self.sys.link_body[i];
            let body = &m.bodies[bi];
            let r = math::mat_mul(&self.data.xmat[bi], &math::quat_to_mat(body.iquat));
            let iw = math::rotate_diag(&r, body.inertia);
            let mass = body.mass;
            let d = math::sub(self.data.xipos[bi], c);
            let o = &mut out[10 * k..10 * k + 10];
            o[0] = iw[0][0] + mass * (d[1] * d[1] + d[2] * d[2]);
            o[1] = iw[1][1] + mass * (d[0] * d[0] + d[2] * d[2]);
            o[2] = iw[2][2] + mass * (d[0] * d[0] + d[1] * d[1]);
            o[3] = iw[0][1] - mass * d[0] * d[1];
            o[4] = iw[0][2] - mass * d[0] * d[2];
            o[5] = iw[1][2] - mass * d[1] * d[2];
            for j in 0..3 {
                o[6 + j] = mass * d[j];
            }
            o[9] = mass;
        }
    }

    /// MuJoCo's `cvel` of the links `bodies` at `c`, 6 values per body: `[ω, v]`, the angular
    /// velocity and the velocity of the body's point (rigidly extended) at `c`, world axes.
    pub fn com_velocity(&self, bodies: &[usize], c: [f64; 3], out: &mut [f64]) {
        for (k, &i) in bodies.iter().enumerate() {
            let (w, v0) = math::split(&self.data.cvel[self.sys.link_body[i]]);
            let v = math::add(v0, math::cross(w, c));
            let o = &mut out[6 * k..6 * k + 6];
            o[..3].copy_from_slice(&w);
            o[3..].copy_from_slice(&v);
        }
    }

    /// Generalized actuator forces under controls `ctrl`, one per movable URDF joint.
    pub fn actuator_forces(&self, ctrl: &[f32], out: &mut [f64]) {
        out.fill(0.0);
        let m = &*self.sys.model;
        for (a, &u) in m.actuators.iter().zip(ctrl) {
            let mut u = if u.is_nan() { 0.0 } else { f64::from(u) };
            if let Some([lo, hi]) = a.ctrlrange {
                u = u.clamp(lo, hi);
            }
            let da = m.jnt_dofadr[a.joint];
            if let Some(i) = self.sys.joint_addr.iter().position(|&(_, d)| d == da)
                && let Some(o) = out.get_mut(i)
            {
                *o += a.gear * u;
            }
        }
    }

    /// Mass-weighted centre of mass of the robot.
    pub fn center_of_mass(&self) -> [f64; 3] {
        self.data.center_of_mass()
    }

    /// World position of the torso link's frame.
    pub fn torso_position(&self) -> V3 {
        self.data.xpos[self.sys.torso]
    }

    /// Every geom of the robot in the world: (link-colour index, shape, position, rotation).
    pub fn geoms(&self) -> impl Iterator<Item = (usize, Shape, V3, M3)> + '_ {
        let m = &*self.sys.model;
        m.geoms
            .iter()
            .enumerate()
            .filter(|(_, g)| g.body != 0)
            .map(|(i, g)| (g.body, g.shape, self.data.geom_xpos[i], self.data.geom_xmat[i]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::RobotModel;

    /// The context that reproduces Gymnasium's ant.xml (the spec's `mujoco_v5` instance set).
    fn mujoco_ant_params(model: &RobotModel) -> RobotParams {
        let mut p = RobotParams::for_model("ant", model);
        for (name, v) in [
            ("gravity", -9.81),
            ("friction", 1.0),
            ("angular_damping", 0.0),
            ("joint_angular_damping", 1.0),
            ("joint_stiffness", 2500.0),
            ("actuator_strength", 150.0),
            ("torso_mass", 0.327249235),
        ] {
            p.set(name, v).unwrap();
        }
        p
    }

    /// robots/ant (converted from ant.xml) at MuJoCo's values is MuJoCo's Ant: its compiled
    /// constants and every 5-step interval of carl-articulated's MuJoCo fixture agree.
    #[test]
    fn ant_at_mujoco_values_matches_the_mujoco_fixture() {
        let robot = RobotModel::load("ant").unwrap();
        let sys = ArticulatedSystem::new(&robot, &mujoco_ant_params(&robot)).unwrap();
        let m = &*sys.model;
        let fx = fixture("ant");
        check_dof_invweight0(m, &fx);
        assert_eq!(m.nq, 15);
        let devs = interval_deviations(&sys, &fx);
        let dq = devs.iter().map(|d| d.0).fold(0.0, f64::max);
        let dv = devs.iter().map(|d| d.1).fold(0.0, f64::max);
        assert!(
            dq < 1e-5 && dv < 2e-4,
            "ant from the URDF: qpos off by {dq}, qvel by {dv}"
        );
    }

    /// robots/humanoid (converted from humanoid.xml: carrier links folded into multi-hinge
    /// bodies, per-joint damping, springs, gears, condim 1, self-collisions) at MuJoCo's values
    /// is MuJoCo's Humanoid: its bodies, compiled constants and every 5-step interval of
    /// carl-articulated's MuJoCo fixture agree (as carl-articulated's own parity test: 75 of
    /// 80 intervals within 2e-7 / 2e-5, contact onsets within 5e-5 / 5e-3).
    #[test]
    fn humanoid_at_mujoco_values_matches_the_mujoco_fixture() {
        let robot = RobotModel::load("humanoid").unwrap();
        let mut p = RobotParams::for_model("humanoid", &robot);
        for (name, v) in [
            ("gravity", -9.81),
            ("friction", 1.0),
            ("angular_damping", 0.0),
            ("joint_angular_damping", 5.0),
        ] {
            p.set(name, v).unwrap();
        }
        let sys = ArticulatedSystem::new(&robot, &p).unwrap();
        let m = &*sys.model;
        assert_eq!((m.bodies.len(), m.nq, m.nv), (14, 24, 23));
        let fx = fixture("humanoid");
        check_dof_invweight0(m, &fx);
        for (j, fj) in m.joints.iter().zip(fx["model"]["joints"].as_array().unwrap()) {
            assert_eq!(j.body, fj["body"].as_u64().unwrap() as usize, "joint {} body", j.name);
            assert!(
                (j.damping - fj["damping"].as_f64().unwrap()).abs() < 1e-12,
                "joint {} damping",
                j.name
            );
            assert!(
                (j.stiffness - fj["stiffness"].as_f64().unwrap()).abs() < 1e-12,
                "joint {} stiffness",
                j.name
            );
        }
        let devs = interval_deviations(&sys, &fx);
        let dq = devs.iter().map(|d| d.0).fold(0.0, f64::max);
        let dv = devs.iter().map(|d| d.1).fold(0.0, f64::max);
        let loose = devs.iter().filter(|(q, v)| *q > 2e-7 || *v > 2e-5).count();
        assert!(
            dq < 5e-5 && dv < 5e-3 && loose <= 6,
            "humanoid from the URDF: qpos off by {dq}, qvel by {dv}, {loose} loose intervals"
        );
    }

    /// The robot's context at its spec's `mujoco_v5` instance set (MuJoCo v5's own values).
    fn mujoco_v5_params(env: &'static str, robot: &RobotModel) -> RobotParams {
        if env == "half_cheetah" {
            // No instance set: half_cheetah.xml's values where a feature exists (the torso's
            // exact mass; the dampings' mean; solreflimit (0.02, 1) as a stiffness).
            let mut p = RobotParams::for_model(env, robot);
            for (name, v) in [
                ("gravity", -9.81),
                ("friction", 0.4),
                ("angular_damping", 0.0),
                ("joint_angular_damping", 3.75),
                ("joint_stiffness", 2500.0),
                ("torso_mass", 6.25020921),
            ] {
                p.set(name, v).unwrap();
            }
            return p;
        }
        let path = format!(
            "{}/../../specs/instances/{env}/mujoco_v5.json",
            env!("CARGO_MANIFEST_DIR")
        );
        let set: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        let mut p = RobotParams::for_model(env, robot);
        for (name, v) in set["instances"][0]["context"].as_object().unwrap() {
            p.set(name, v.as_f64().unwrap()).unwrap();
        }
        p
    }

    /// carl-articulated's MuJoCo fixture of `env`.
    fn fixture(env: &str) -> serde_json::Value {
        let path = format!(
            "{}/../carl-articulated/tests/fixtures/mujoco_{env}.json",
            env!("CARGO_MANIFEST_DIR")
        );
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
    }

    fn nums(v: &serde_json::Value) -> Vec<f64> {
        v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()
    }

    /// The compiled `dof_invweight0` equals the fixture's (relative 1e-6).
    fn check_dof_invweight0(m: &carl_articulated::Model, fx: &serde_json::Value) {
        let dw = nums(&fx["model"]["dof_invweight0"]);
        for (a, b) in m.dof_invweight0.iter().zip(&dw) {
            assert!(
                (a - b).abs() < 1e-6 * b,
                "dof_invweight0 {:?} vs {dw:?}",
                m.dof_invweight0
            );
        }
    }

    /// The deviation of `qpos` and `qvel` at the end of every 5-step interval of fixture `fx`,
    /// each interval started from MuJoCo's state under the fixtures' control.
    fn interval_deviations(sys: &ArticulatedSystem, fx: &serde_json::Value) -> Vec<(f64, f64)> {
        let m = &*sys.model;
        // Robots of hinges and slides: (MuJoCo's coordinate, ours) of every joint, matched by name
        // (Reacher's target is task state). A free root (Ant, Humanoid): MuJoCo's own order.
        let by_name = !m.joints.iter().any(|j| j.kind == JointKind::Free);
        let map: Vec<(usize, usize)> = if by_name {
            let names = fx["model"]["joint_names"].as_array().unwrap();
            let map: Vec<(usize, usize)> = names
                .iter()
                .enumerate()
                .filter_map(|(k, n)| m.joint_index(n.as_str().unwrap()).map(|j| (k, m.jnt_qposadr[j])))
                .collect();
            assert_eq!(map.len(), m.nq, "every joint of the model is MuJoCo's");
            map
        } else {
            Vec::new()
        };
        let mut d = Data::new(Arc::clone(&sys.model));
        let mut out = Vec::new();
        for w in fx["trajectory"].as_array().unwrap().windows(2) {
            let (q0, v0) = (nums(&w[0]["qpos"]), nums(&w[0]["qvel"]));
            if by_name {
                for &(k, a) in &map {
                    d.qpos[a] = q0[k];
                    d.qvel[a] = v0[k];
                }
            } else {
                d.qpos.copy_from_slice(&q0);
                d.qvel.copy_from_slice(&v0);
            }
            d.time = w[0]["time"].as_f64().unwrap();
            for _ in 0..5 {
                let t = d.time;
                for (a, u) in d.ctrl.iter_mut().enumerate() {
                    *u = (2.0 * std::f64::consts::PI * 1.3 * t + 0.7 * a as f64).sin() * (0.6 + 0.1 * a as f64);
                }
                d.step();
            }
            let (q1, v1) = (nums(&w[1]["qpos"]), nums(&w[1]["qvel"]));
            let max_dev = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
            out.push(if by_name {
                map.iter().fold((0.0f64, 0.0f64), |(eq, ev), &(k, a)| {
                    (eq.max((d.qpos[a] - q1[k]).abs()), ev.max((d.qvel[a] - v1[k]).abs()))
                })
            } else {
                (max_dev(&d.qpos, &q1), max_dev(&d.qvel, &v1))
            });
        }
        out
    }

    /// [`interval_deviations`] of `env` loaded from its URDF and side file at its `mujoco_v5`
    /// context.
    fn local_deviations_from_mujoco(env: &'static str) -> Vec<(f64, f64)> {
        let robot = RobotModel::load(env).unwrap();
        let sys = ArticulatedSystem::new(&robot, &mujoco_v5_params(env, &robot)).unwrap();
        interval_deviations(&sys, &fixture(env))
    }

    /// The planar robots and control tasks from their URDFs at `mujoco_v5` are MuJoCo's models:
    /// every 5-step interval of their fixtures agrees (planar roots, RK4, limits, Hopper's
    /// self-collisions, Reacher's turned plane with gravity along the hinges). Walker2d's
    /// intervals where a shin touches the floor are looser: MuJoCo's friction there is the
    /// floor's 1.0, one context feature (its foot's 1.9) here.
    #[test]
    fn planar_robots_at_mujoco_values_match_the_mujoco_fixtures() {
        // (env, tight qpos / qvel bounds, intervals allowed beyond them, bounds for those)
        // Observed: half_cheetah 3e-8 / 3e-6 (Euler, contacts; its context holds the dampings'
        // mean, the per-joint pattern comes from the side file); hopper 1.1e-10 / 1.9e-8; walker2d 9e-10 / 1.3e-7 except 8 intervals with
        // a shin on the floor (8e-4 / 0.22); the control tasks 2e-9 / 3e-8 (the URDF's rounded
        // masses).
        for (env, tq, tv, loose, lq, lv) in [
            ("half_cheetah", 1e-4, 5e-3, 0, 0.0, 0.0),
            ("hopper", 1e-8, 1e-6, 0, 0.0, 0.0),
            ("walker2d", 1e-8, 1e-6, 8, 2e-3, 0.5),
            ("inverted_pendulum", 1e-8, 1e-7, 0, 0.0, 0.0),
            // The XML's gravity has an x component of 1e-5 m/s² (the context's gravity is z):
            // 5e-7 m/s per interval.
            ("inverted_double_pendulum", 5e-8, 2e-6, 0, 0.0, 0.0),
            ("reacher", 1e-8, 1e-7, 0, 0.0, 0.0),
        ] {
            let devs = local_deviations_from_mujoco(env);
            if std::env::var("ARTICULATED_TRACE").is_ok() {
                eprintln!("{env}: {devs:?}");
            }
            let beyond: Vec<&(f64, f64)> = devs.iter().filter(|(q, v)| *q > tq || *v > tv).collect();
            assert!(
                beyond.len() <= loose && beyond.iter().all(|(q, v)| *q <= lq && *v <= lv),
                "{env} from the URDF: {} intervals beyond {tq} / {tv}: {beyond:?}",
                beyond.len()
            );
        }
    }

    #[test]
    fn rpy_matrix_is_urdf_order() {
        // yaw 90° turns x into y; roll 90° turns y into z.
        let m = rpy_mat([0.0, 0.0, std::f64::consts::FRAC_PI_2]);
        assert!((m[1][0] - 1.0).abs() < 1e-12);
        let m = rpy_mat([std::f64::consts::FRAC_PI_2, 0.0, 0.0]);
        assert!((m[2][1] - 1.0).abs() < 1e-12);
    }
}
