//! One robot instance's physics world: the URDF loaded into rapier3d multibody (reduced
//! coordinate) joints on a ground plane, with the context applied when the world is built.
//!
//! How each context feature reaches the physics (all per instance, at build time):
//! * `gravity` → the world's gravity vector `(0, 0, gravity)`;
//! * `friction` → the friction coefficient of every collider (robot and ground);
//! * `angular_damping` → Brax's global angular damping: after every physics step every angular
//!   generalized velocity (the root's angular velocity and every hinge rate) is multiplied by
//!   `exp(angular_damping · dt)`, which scales every link's angular velocity by that factor;
//! * `joint_angular_damping` → implicit viscous damping (N·m·s/rad) on every hinge DoF: damps
//!   the relative angular velocity of parent and child, as Brax's joint damping does;
//! * `joint_stiffness` → the stiffness of each joint's limit constraint (a reduced-coordinate
//!   joint has no other compliant constraint): natural frequency `√(k / I_ref) / 2π`;
//! * `actuator_strength` → scales every motor's torque;
//! * `torso_mass`, `mass_<link>` → the link's mass (its inertia tensor is scaled with it).
//!
//! A side file's `ground_links` (Brax's `collide_include`) leaves every other link without
//! contacts.

use rapier3d::prelude::*;
use rapier3d_urdf::{UrdfLoaderOptions, UrdfMultibodyOptions, UrdfRobot, urdf_rs};

use super::model::{RobotModel, RootKind, is_movable};
use super::params::{RobotParams, finite_or};

/// Position state of the robot: root pose (free root only) and joint coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct Configuration {
    /// `[x, y, z, qw, qx, qy, qz]` of the root link (free root), empty for a fixed root.
    pub root: Vec<f64>,
    /// Joint coordinates in URDF joint order (rad or m).
    pub joints: Vec<f64>,
    /// Generalized velocities: root `[vx, vy, vz, wx, wy, wz]` (free root; world frame), then
    /// one per joint.
    pub vel: Vec<f64>,
}

/// Per movable joint: where its DoF sits and which bodies it connects.
#[derive(Debug, Clone, Copy)]
struct JointDof {
    link_id: usize,
    dof: usize,
    parent: RigidBodyHandle,
    child: RigidBodyHandle,
    prismatic: bool,
    /// Joint axis in the parent body's frame.
    axis_parent: Vector,
}

pub struct RobotWorld {
    pub pw: PhysicsWorld,
    /// Rigid body of each URDF link, in URDF order.
    pub links: Vec<RigidBodyHandle>,
    /// Colliders of each URDF link.
    pub link_colliders: Vec<Vec<ColliderHandle>>,
    pub ground: ColliderHandle,
    /// Index of the torso link.
    pub torso: usize,
    mb: MultibodyIndex,
    joints: Vec<JointDof>,
    root_dofs: usize,
    /// Indices (into the generalized velocity) scaled by the global angular damping.
    angular_dofs: Vec<usize>,
    angular_decay: f32,
    /// Torque per unit control of each actuator and its joint index.
    motors: Vec<(usize, f32)>,
    ctrl_range: [f32; 2],
}

impl std::fmt::Debug for RobotWorld {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RobotWorld").finish_non_exhaustive()
    }
}

/// A state coordinate as `f32`: non-finite values become 0 and magnitudes are capped at 1e6, so
/// that no state handed to `set_state` can put infinities into the physics engine.
fn coord(x: f64) -> f32 {
    finite_or(x, 0.0).clamp(-1e6, 1e6) as f32
}

impl RobotWorld {
    /// Build the world for `model` under `params`, in configuration `q`.
    pub fn build(model: &RobotModel, params: &RobotParams, q: &Configuration) -> RobotWorld {
        let side = &model.side;
        let mut robot: urdf_rs::Robot = model.urdf.clone();
        // Masses: torso (the first link) and per-link overrides; inertia scales with mass.
        for (i, link) in robot.links.iter_mut().enumerate() {
            let base = link.inertial.mass.value;
            let mut m = base;
            if i == model.torso
                && let Some(t) = params.torso_mass
            {
                m = t;
            }
            if let Some((_, v)) = params.link_masses.iter().find(|(n, _)| *n == link.name) {
                m = *v;
            }
            let m = finite_or(m, base).max(1e-6);
            let k = m / base;
            link.inertial.mass.value = m;
            let ine = &mut link.inertial.inertia;
            for v in [
                &mut ine.ixx,
                &mut ine.ixy,
                &mut ine.ixz,
                &mut ine.iyy,
                &mut ine.iyz,
                &mut ine.izz,
            ] {
                *v *= k;
            }
        }

        let friction = finite_or(params.friction, 0.0).max(0.0) as f32;
        let restitution = side.restitution as f32;
        let root_pose = if side.root == RootKind::Free && q.root.len() == 7 {
            let r = &q.root;
            let mut rot = Rotation::from_xyzw(coord(r[4]), coord(r[5]), coord(r[6]), coord(r[3]));
            let n = rot.length();
            rot = if n.is_finite() && n > 1e-6 {
                rot / n
            } else {
                Rotation::IDENTITY
            };
            Pose::from_parts(Vector::new(coord(r[0]), coord(r[1]), coord(r[2])), rot)
        } else {
            Pose::IDENTITY
        };
        let options = UrdfLoaderOptions {
            create_colliders_from_collision_shapes: true,
            create_colliders_from_visual_shapes: false,
            apply_imported_mass_props: true,
            enable_joint_collisions: false,
            make_roots_fixed: side.root == RootKind::Fixed,
            shift: root_pose,
            collider_blueprint: ColliderBuilder::default()
                .density(0.0)
                .friction(friction)
                .restitution(restitution)
                .friction_combine_rule(CoefficientCombineRule::Average),
            rigid_body_blueprint: RigidBodyBuilder::dynamic().can_sleep(false),
            squeeze_empty_fixed_links: false,
            ..UrdfLoaderOptions::default()
        };
        let mut urdf_robot = UrdfRobot::from_robot(&robot, options, std::path::Path::new("."));
        // Joint limits are springs of stiffness `joint_stiffness` on the reference inertia.
        let k = finite_or(params.joint_stiffness, 1.0).max(1e-9);
        let omega = (k / side.limit_reference_inertia).sqrt();
        let softness = SpringCoefficients::new((omega / std::f64::consts::TAU) as f32, side.limit_damping_ratio as f32);
        for j in &mut urdf_robot.joints {
            j.joint.softness = softness;
        }

        let mut pw = PhysicsWorld::new();
        pw.gravity = Vector::new(0.0, 0.0, finite_or(params.gravity, 0.0) as f32);
        let ip = &mut pw.integration_parameters;
        ip.dt = side.timestep as f32;
        ip.num_solver_iterations = side.solver_iterations;
        if let Some(w) = side.warmstart_coefficient {
            ip.warmstart_coefficient = w as f32;
        }

        let flags = if side.self_collisions {
            UrdfMultibodyOptions::empty()
        } else {
            UrdfMultibodyOptions::DISABLE_SELF_CONTACTS
        };
        let handles = urdf_robot.insert_using_multibody_joints(
            &mut pw.bodies,
            &mut pw.colliders,
            &mut pw.multibody_joints,
            flags,
        );
        let links: Vec<RigidBodyHandle> = handles.links.iter().map(|l| l.body).collect();
        let link_colliders: Vec<Vec<ColliderHandle>> = handles
            .links
            .iter()
            .map(|l| l.colliders.iter().map(|c| c.handle).collect())
            .collect();

        // Ground: a large box whose top face is z = 0.
        let (_, ground) = pw.insert(
            RigidBodyBuilder::fixed(),
            ColliderBuilder::cuboid(1000.0, 1000.0, 1.0)
                .translation(Vector::new(0.0, 0.0, -1.0))
                .friction(friction)
                .restitution(restitution)
                .friction_combine_rule(CoefficientCombineRule::Average)
                .collision_groups(if side.ground_contacts {
                    InteractionGroups::default()
                } else {
                    InteractionGroups::none()
                }),
        );

        if !side.ground_links.is_empty() {
            for (name, cols) in model.link_names.iter().zip(&link_colliders) {
                if !side.ground_links.contains(name) {
                    for &c in cols {
                        pw.colliders[c].set_collision_groups(InteractionGroups::none());
                    }
                }
            }
        }
        for &h in &links {
            pw.bodies[h].recompute_mass_properties_from_colliders(&pw.colliders);
        }
        let root_link = pw
            .multibody_joints
            .rigid_body_link(links[0])
            .copied()
            .expect("the root link belongs to the multibody");
        let mb_index = root_link.multibody;
        let mb = pw
            .multibody_joints
            .get_multibody_mut(mb_index)
            .expect("multibody exists");
        // Settle the root type (a fixed root has no DoFs) before reading DoF indices.
        mb.forward_kinematics(&pw.bodies, true);
        let root_dofs = mb.root().joint().ndofs();

        // Movable joints in URDF order.
        let mut joints = Vec::new();
        for (k, uj) in robot.joints.iter().enumerate() {
            if !is_movable(&uj.joint_type) {
                continue;
            }
            let h = &handles.joints[k];
            let child_link = pw
                .multibody_joints
                .rigid_body_link(h.link2)
                .copied()
                .expect("every joint child is a multibody link");
            let mb = pw.multibody_joints.get_multibody(mb_index).expect("multibody");
            let link = mb.link(child_link.id).expect("link");
            let data = &link.joint().data;
            let prismatic = matches!(uj.joint_type, urdf_rs::JointType::Prismatic);
            joints.push(JointDof {
                link_id: child_link.id,
                dof: link.assembly_id(),
                parent: h.link1,
                child: h.link2,
                prismatic,
                axis_parent: data.local_frame1.rotation * Vector::X,
            });
        }

        let dt = side.timestep;
        let angular_decay = (finite_or(params.angular_damping, 0.0) * dt).exp();
        let mut angular_dofs: Vec<usize> = if side.root == RootKind::Free {
            vec![3, 4, 5]
        } else {
            vec![]
        };
        angular_dofs.extend(joints.iter().filter(|j| !j.prismatic).map(|j| j.dof));

        let mb = pw.multibody_joints.get_multibody_mut(mb_index).expect("multibody");
        // Damping: none on the root; `joint_angular_damping` on every robot hinge.
        let jd = finite_or(params.joint_angular_damping, 0.0).max(0.0) as f32;
        mb.damping_mut().fill(0.0);
        for (j, name) in joints.iter().zip(&model.joint_names) {
            if side.root_joints.contains(name) {
                continue;
            }
            if !j.prismatic {
                mb.damping_mut()[j.dof] = jd;
            }
            let armature = side
                .joint_armatures
                .iter()
                .find(|a| a.joint == *name)
                .map_or(side.joint_armature, |a| a.armature);
            mb.armature_mut()[j.dof] = armature as f32;
            if let Some(s) = side.joint_springs.iter().find(|s| s.joint == *name) {
                let axis = if j.prismatic { 0 } else { 3 };
                if let Some(link) = mb.link_mut(j.link_id) {
                    link.joint.set_spring(axis, s.stiffness as f32, 0.0);
                }
            }
        }
        // Configuration: joint coordinates as displacements from the loader's zero pose.
        let ndofs = mb.ndofs();
        let mut disp = vec![0.0f32; ndofs];
        for (j, x) in joints.iter().zip(&q.joints) {
            disp[j.dof] = coord(*x);
        }
        mb.apply_displacements(&disp);
        mb.forward_kinematics(&pw.bodies, true);
        mb.update_rigid_bodies(&mut pw.bodies, true);
        {
            let mut v = mb.generalized_velocity_mut();
            for i in 0..root_dofs.min(q.vel.len()) {
                v[i] = coord(q.vel[i]);
            }
            for (k, j) in joints.iter().enumerate() {
                if let Some(x) = q.vel.get(root_dofs + k) {
                    v[j.dof] = coord(*x);
                }
            }
        }

        let strength = match params.actuator_strength {
            Some(s) => finite_or(s, side.strength_reference) / side.strength_reference,
            None => 1.0,
        };
        let motors = side
            .actuators
            .iter()
            .map(|a| {
                let j = model
                    .joint_names
                    .iter()
                    .position(|n| *n == a.joint)
                    .expect("checked at load");
                (j, (a.gear * strength) as f32)
            })
            .collect();
        RobotWorld {
            pw,
            links,
            link_colliders,
            ground,
            torso: model.torso,
            mb: mb_index,
            joints,
            root_dofs,
            angular_dofs,
            angular_decay: angular_decay as f32,
            motors,
            ctrl_range: [side.ctrl_range[0] as f32, side.ctrl_range[1] as f32],
        }
    }

    pub fn multibody(&self) -> &Multibody {
        self.pw.multibody_joints.get_multibody(self.mb).expect("multibody")
    }

    /// The robot's multibody, mutably (generalized velocities, damping, armature).
    pub fn multibody_mut(&mut self) -> &mut Multibody {
        self.pw.multibody_joints.get_multibody_mut(self.mb).expect("multibody")
    }

    /// Index of movable joint `k`'s degree of freedom in the generalized velocity.
    pub fn joint_dof(&self, k: usize) -> usize {
        self.joints[k].dof
    }

    /// Put an implicit spring `−stiffness·(q − rest)` on movable joint `k` (N/m or N·m/rad): a
    /// position servo that stays stable at high stiffness.
    pub fn set_joint_spring(&mut self, k: usize, stiffness: f32, rest: f32) {
        let j = self.joints[k];
        let axis = if j.prismatic { 0 } else { 3 };
        if let Some(link) = self.multibody_mut().link_mut(j.link_id) {
            link.joint.set_spring(axis, stiffness, rest);
        }
    }

    /// Current configuration (root pose from the root body, joint coordinates and generalized
    /// velocities from the multibody).
    pub fn configuration(&self) -> Configuration {
        let mb = self.multibody();
        let root = if self.root_dofs == 6 {
            let p = self.pw.bodies[self.links[0]].position();
            let t = p.translation;
            let r = p.rotation;
            vec![t.x, t.y, t.z, r.w, r.x, r.y, r.z]
                .into_iter()
                .map(f64::from)
                .collect()
        } else {
            Vec::new()
        };
        let joints = self
            .joints
            .iter()
            .map(|j| {
                let c = mb.link(j.link_id).expect("link").joint().coords();
                f64::from(if j.prismatic { c[0] } else { c[3] })
            })
            .collect();
        let gv = mb.generalized_velocity();
        let mut vel: Vec<f64> = (0..self.root_dofs).map(|i| f64::from(gv[i])).collect();
        vel.extend(self.joints.iter().map(|j| f64::from(gv[j.dof])));
        Configuration { root, joints, vel }
    }

    /// One physics step with motor controls `ctrl` (clipped to the control range).
    pub fn step(&mut self, ctrl: &[f32]) {
        for &h in &self.links {
            let b = &mut self.pw.bodies[h];
            b.reset_forces(false);
            b.reset_torques(false);
        }
        for (&(j, gear), &u) in self.motors.iter().zip(ctrl) {
            let u = if u.is_nan() {
                0.0
            } else {
                u.clamp(self.ctrl_range[0], self.ctrl_range[1])
            };
            let jd = self.joints[j];
            let axis = self.pw.bodies[jd.parent].rotation() * jd.axis_parent;
            let w = axis * (u * gear);
            if jd.prismatic {
                self.pw.bodies[jd.child].add_force(w, false);
                self.pw.bodies[jd.parent].add_force(-w, false);
            } else {
                self.pw.bodies[jd.child].add_torque(w, false);
                self.pw.bodies[jd.parent].add_torque(-w, false);
            }
        }
        self.pw.step();
        if self.angular_decay != 1.0 {
            let decay = self.angular_decay;
            let dofs = &self.angular_dofs;
            let mb = self.pw.multibody_joints.get_multibody_mut(self.mb).expect("multibody");
            let mut v = mb.generalized_velocity_mut();
            for &i in dofs {
                v[i] *= decay;
            }
        }
    }

    /// External contact wrench on each link, MuJoCo `cfrc_ext` order `[torque, force]` (world
    /// frame, torque about the link's centre of mass), from the last physics step's contact
    /// impulses (normal impulses; friction impulses are not included).
    pub fn contact_wrenches(&self, out: &mut [f64]) {
        let dt = self.pw.integration_parameters.dt;
        for (li, cols) in self.link_colliders.iter().enumerate() {
            let com = self.pw.bodies[self.links[li]].center_of_mass();
            let mut f_sum = Vector::ZERO;
            let mut t_sum = Vector::ZERO;
            for &c in cols {
                for pair in self.pw.contact_pairs_with(c) {
                    let first = pair.collider1 == c;
                    let sign = if first { -1.0 } else { 1.0 };
                    let pose = self.pw.colliders[c].position();
                    for m in pair.solver_manifolds() {
                        let n = m.data.normal;
                        for pt in &m.points {
                            if pt.data.impulse == 0.0 {
                                continue;
                            }
                            let f = n * (sign * pt.data.impulse / dt);
                            let local = if first { pt.local_p1 } else { pt.local_p2 };
                            let p = pose * local;
                            f_sum += f;
                            t_sum += (p - com).cross(f);
                        }
                    }
                }
            }
            let o = 6 * li;
            if o + 6 <= out.len() {
                for k in 0..3 {
                    out[o + k] = f64::from(t_sum[k]);
                    out[o + 3 + k] = f64::from(f_sum[k]);
                }
            }
        }
    }

    /// Whether every link pose and velocity is finite and no link is faster than `max_speed`.
    pub fn is_sane(&self, max_speed: f64) -> bool {
        let lim = max_speed as f32;
        self.links.iter().all(|&h| {
            let b = &self.pw.bodies[h];
            let p = b.position();
            p.translation.is_finite()
                && p.rotation.is_finite()
                && b.linvel().is_finite()
                && b.angvel().is_finite()
                && b.linvel().length() <= lim
                && b.angvel().length() <= lim
        }) && self
            .multibody()
            .generalized_velocity()
            .iter()
            .all(|v| v.is_finite() && v.abs() <= lim)
    }

    /// World pose of link `i`.
    pub fn link_pose(&self, i: usize) -> Pose {
        *self.pw.bodies[self.links[i]].position()
    }

    /// Number of generalized velocities of the root (6 free, 0 fixed).
    pub fn root_dofs(&self) -> usize {
        self.root_dofs
    }

    /// Joint axis of movable joint `k` in world coordinates.
    pub fn joint_axis_world(&self, k: usize) -> Vector {
        let j = self.joints[k];
        self.pw.bodies[j.parent].rotation() * j.axis_parent
    }

    /// Generalized actuator forces (MuJoCo's `qfrc_actuator` of the robot joints): torque (or
    /// force) of the motors under controls `ctrl`, clipped as in [`RobotWorld::step`], one per
    /// movable joint in URDF order.
    pub fn actuator_forces(&self, ctrl: &[f32], out: &mut [f64]) {
        out.fill(0.0);
        for (&(j, gear), &u) in self.motors.iter().zip(ctrl) {
            let u = if u.is_nan() {
                0.0
            } else {
                u.clamp(self.ctrl_range[0], self.ctrl_range[1])
            };
            if let Some(o) = out.get_mut(j) {
                *o += f64::from(u * gear);
            }
        }
    }

    /// Mass (kg) of link `i` as the physics engine sees it.
    pub fn link_mass(&self, i: usize) -> f64 {
        f64::from(self.pw.bodies[self.links[i]].mass())
    }
}
