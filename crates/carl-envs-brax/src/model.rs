//! Robot descriptions: a URDF file (links, shapes, masses, joints) plus a small JSON side file
//! for what URDF cannot express (actuators, control range, time step, root joint, contact and
//! solver settings). Both are embedded at build time from `robots/`.

use std::sync::{Arc, OnceLock};

use rapier3d_urdf::urdf_rs;
use serde::Deserialize;

/// How the root link is attached to the world.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RootKind {
    /// A free-floating base (6 DoF), e.g. Ant and Humanoid.
    Free,
    /// The URDF's root link is welded to the world (planar robots carry their own slide and
    /// hinge joints in the URDF, arms are bolted down).
    Fixed,
}

/// The physics engine of a robot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Engine {
    /// rapier3d multibodies ([`super::world::RobotWorld`]).
    #[default]
    Rapier,
    /// The 3-D articulated-body engine with MuJoCo's semantics ([`super::articulated`],
    /// crate `carl-articulated`).
    Articulated,
}

/// Time integration (MuJoCo's `integrator`) of the articulated engine.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Integrator {
    /// Semi-implicit Euler with implicit joint damping (MuJoCo's default `Euler`).
    #[default]
    Euler,
    /// Fourth-order Runge–Kutta (MuJoCo's `RK4`): every stage's acceleration with its
    /// constraint forces (contacts in every stage), damping explicit.
    Rk4,
}

/// One motor: a URDF joint and its gear (torque per unit control, before the strength factor).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ActuatorSpec {
    pub joint: String,
    pub gear: f64,
}

/// A passive spring on one joint.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointSpring {
    pub joint: String,
    pub stiffness: f64,
}

/// Reflected rotor inertia of one joint (MuJoCo's per-joint `armature`), kg·m².
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointArmature {
    pub joint: String,
    pub armature: f64,
}

/// Viscous damping of one joint (MuJoCo's per-joint `damping`), N·m·s/rad.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointDamping {
    pub joint: String,
    pub damping: f64,
}

/// The reset value of one joint coordinate (MuJoCo's `qpos0`, e.g. a slide's `ref`).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialJoint {
    pub joint: String,
    pub value: f64,
}

/// MuJoCo's soft-constraint parameters of a class of constraint rows (contacts or joint
/// limits): `solref = [timeconst, dampratio]`, `solimp = [dmin, dmax, width, midpoint, power]`,
/// and the margin (distance at which the row activates; the penetration is measured from it).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SoftConstraint {
    pub solref: [f64; 2],
    pub solimp: [f64; 5],
    #[serde(default)]
    pub margin: f64,
}

/// A named point fixed on a link (MuJoCo's sites, and its joint-less bodies welded into their
/// parent), in the link frame.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Site {
    pub name: String,
    pub link: String,
    pub pos: [f64; 3],
}

/// The side file `robots/<name>.actuators.json`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SideFile {
    pub robot: String,
    pub source: String,
    /// The physics engine (default rapier).
    #[serde(default)]
    pub engine: Engine,
    /// Physics time step (s).
    pub timestep: f64,
    /// Time integration of the articulated engine (default semi-implicit Euler).
    #[serde(default)]
    pub integrator: Integrator,
    /// Physics steps per environment step.
    pub frame_skip: usize,
    /// rapier solver iterations (substeps) per physics step.
    pub solver_iterations: usize,
    /// rapier's warm-start coefficient (default: rapier's 1; 0 switches warm starting off, which
    /// a robot with light legs may need: stale contact and limit impulses can blow them up
    /// within one substep).
    #[serde(default)]
    pub warmstart_coefficient: Option<f64>,
    pub root: RootKind,
    /// The link `torso_mass` sets and the camera follows (default: the first URDF link).
    #[serde(default)]
    pub torso_link: Option<String>,
    /// Reflected rotor inertia (kg·m²) added to every robot joint (MuJoCo's `armature`).
    #[serde(default)]
    pub joint_armature: f64,
    /// Per-joint armature overriding `joint_armature`.
    #[serde(default)]
    pub joint_armatures: Vec<JointArmature>,
    /// The links that are bodies of the modelled robot, for per-body observations (default:
    /// every link). Massless carrier links of multi-hinge joints are left out.
    #[serde(default)]
    pub bodies: Vec<String>,
    /// Per-joint viscous damping from the model (MuJoCo's joint `damping`); a joint listed here
    /// is not damped by the context's `joint_angular_damping`, unless `damping_reference` is
    /// given.
    #[serde(default)]
    pub joint_dampings: Vec<JointDamping>,
    /// With `joint_dampings`, the articulated engine scales them by the context's
    /// `joint_angular_damping / damping_reference` (the model's pattern of dampings, its level
    /// from the context).
    #[serde(default)]
    pub damping_reference: Option<f64>,
    /// MuJoCo's `condim` of the robot's geoms (1 or 3, default 3; the floor's is 3 and a pair
    /// takes the larger), articulated engine.
    #[serde(default)]
    pub contact_condim: Option<u8>,
    /// The floor's share of `contact_model.margin` (default 0): robot geoms get the rest, so a
    /// pair of robot geoms has twice the rest (MuJoCo adds the two geoms' margins).
    #[serde(default)]
    pub floor_margin: f64,
    /// Reset values of joint coordinates (default 0): MuJoCo's `qpos0`, around which the reset
    /// noise is drawn.
    #[serde(default)]
    pub initial_joints: Vec<InitialJoint>,
    /// MuJoCo's contact parameters of every robot geom, the margin being the robot–floor
    /// pair's (default MuJoCo's: `solref` 0.02/1, `solimp` 0.9–0.95 over 1 mm, no margin).
    #[serde(default)]
    pub contact_model: Option<SoftConstraint>,
    /// Joint limits as MuJoCo's soft limits with these parameters; default: a MuJoCo limit of
    /// the context's `joint_stiffness` (`limit_reference_inertia`, `limit_damping_ratio`).
    #[serde(default)]
    pub limit_model: Option<SoftConstraint>,
    /// Passive joint springs towards 0 (MuJoCo's joint `stiffness`), N·m/rad.
    #[serde(default)]
    pub joint_springs: Vec<JointSpring>,
    /// Joints of the URDF that stand for the root's degrees of freedom (a planar robot's
    /// slides and pitch hinge): not damped like robot joints.
    #[serde(default)]
    pub root_joints: Vec<String>,
    /// Height of the root link's origin at reset (m).
    pub root_height: f64,
    pub ctrl_range: [f64; 2],
    /// Torque = control × gear × actuator_strength / strength_reference (robots without an
    /// `actuator_strength` feature use the gear alone).
    pub strength_reference: f64,
    pub actuators: Vec<ActuatorSpec>,
    /// Joint-limit springs: `joint_stiffness` (N·m/rad) acting on this reference inertia
    /// (kg·m²) gives the limit constraint's natural frequency.
    pub limit_reference_inertia: f64,
    pub limit_damping_ratio: f64,
    /// The impedance (`solimplimit`) of the `joint_stiffness` limits on the articulated engine
    /// (default MuJoCo's `[0.9, 0.95, 0.001, 0.5, 2]`).
    #[serde(default)]
    pub limit_solimp: Option<[f64; 5]>,
    pub restitution: f64,
    /// Whether links of the robot collide with each other.
    pub self_collisions: bool,
    /// Whether the robot's links collide with the ground (default true; Brax's ur5e has no
    /// contacts at all).
    #[serde(default = "yes")]
    pub ground_contacts: bool,
    /// If non-empty, only these links touch the ground (Brax's `collide_include` pairs); the
    /// other links pass through it.
    #[serde(default)]
    pub ground_links: Vec<String>,
    /// If non-empty, only these links' geoms collide with other robot geoms (MuJoCo's
    /// contype/conaffinity of Pusher: the wrist and the object); the others are drawn only
    /// (articulated engine).
    #[serde(default)]
    pub contact_links: Vec<String>,
    /// Articulated engine: `mass_<link>` (and `torso_mass`) is the mass of the link with the links
    /// welded to it by fixed joints, each scaled by one factor (Brax fuses joint-less bodies into
    /// their parent: carl-bench's HumanoidStandup `mass_right_shin` is shin and foot).
    #[serde(default)]
    pub welded_masses: bool,
    /// Height of the floor plane (m; Pusher's table, 0.325 m below the shoulder), articulated
    /// engine.
    #[serde(default)]
    pub floor_height: f64,
    /// Any link faster than this (m/s or rad/s) counts as a diverged simulation.
    pub max_speed: f64,
    /// Gravity is normal to the plane of motion (an arm moving on a horizontal table, Reacher,
    /// modelled turned by +90° about x): gravity points along the URDF's y; each link's weight
    /// presses it onto the table, where it slides with the context's friction (default: gravity
    /// along −z).
    #[serde(default)]
    pub gravity_normal_to_plane: bool,
    /// Slides running on a rail that carries the weight of everything they move;
    /// their dry friction is the context's friction times that weight (MuJoCo's joint
    /// `frictionloss`).
    #[serde(default)]
    pub rail_joints: Vec<String>,
    /// Joints whose limits restitute with the context's elasticity (end stops).
    #[serde(default)]
    pub bouncing_limits: Vec<String>,
    /// Named points on links (MuJoCo's sites).
    #[serde(default)]
    pub sites: Vec<Site>,
}

fn yes() -> bool {
    true
}

/// Whether URDF link `li` is a carrier of a multi-hinge body: no inertia of its own, no
/// colliders, moved by a hinge or slide and carrying exactly one link on a hinge or slide at
/// its own frame. The articulated engine folds a carrier and its child into one body with
/// both joints (MuJoCo's several joints of one body, in order).
pub fn is_carrier(urdf: &urdf_rs::Robot, li: usize) -> bool {
    let l = &urdf.links[li];
    let i = &l.inertial.inertia;
    let massless = l.inertial.mass.value == 0.0 && [i.ixx, i.ixy, i.ixz, i.iyy, i.iyz, i.izz].iter().all(|x| *x == 0.0);
    let moved = urdf
        .joints
        .iter()
        .any(|j| j.child.link == l.name && is_movable(&j.joint_type));
    let children: Vec<_> = urdf.joints.iter().filter(|j| j.parent.link == l.name).collect();
    massless
        && l.collision.is_empty()
        && moved
        && children.len() == 1
        && is_movable(&children[0].joint_type)
        && children[0].origin.xyz.0 == [0.0; 3]
        && children[0].origin.rpy.0 == [0.0; 3]
}

/// A parsed robot description, shared read-only by all instances of one environment.
#[derive(Debug, Clone)]
pub struct RobotModel {
    pub name: &'static str,
    pub urdf: urdf_rs::Robot,
    pub side: SideFile,
    /// URDF link names in file order.
    pub link_names: Vec<String>,
    /// Movable (revolute/prismatic/continuous) joint names in file order: the generalized
    /// coordinates after the root's.
    pub joint_names: Vec<String>,
    /// Index of the torso link (see [`SideFile::torso_link`]).
    pub torso: usize,
    /// Link indices of the robot's bodies (see [`SideFile::bodies`]), in URDF order.
    pub bodies: Vec<usize>,
}

/// Why a robot description could not be loaded (only possible if an embedded file is broken;
/// the tests load every robot).
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    #[error("{robot}.urdf: {message}")]
    Urdf { robot: &'static str, message: String },
    #[error("{robot}.actuators.json: {message}")]
    Side { robot: &'static str, message: String },
    /// Either of the above, as the first parse of `robot` in this process reported it.
    #[error("{message}")]
    Embedded { robot: &'static str, message: String },
}

/// The embedded robot files: (name, URDF text, side-file text).
pub const ROBOT_FILES: &[(&str, &str, &str)] = &[
    (
        "ant",
        include_str!("../robots/ant.urdf"),
        include_str!("../robots/ant.actuators.json"),
    ),
    (
        "half_cheetah",
        include_str!("../robots/half_cheetah.urdf"),
        include_str!("../robots/half_cheetah.actuators.json"),
    ),
    (
        "humanoid",
        include_str!("../robots/humanoid.urdf"),
        include_str!("../robots/humanoid.actuators.json"),
    ),
    (
        "hopper",
        include_str!("../robots/hopper.urdf"),
        include_str!("../robots/hopper.actuators.json"),
    ),
    (
        "walker2d",
        include_str!("../robots/walker2d.urdf"),
        include_str!("../robots/walker2d.actuators.json"),
    ),
    (
        "inverted_pendulum",
        include_str!("../robots/inverted_pendulum.urdf"),
        include_str!("../robots/inverted_pendulum.actuators.json"),
    ),
    (
        "inverted_double_pendulum",
        include_str!("../robots/inverted_double_pendulum.urdf"),
        include_str!("../robots/inverted_double_pendulum.actuators.json"),
    ),
    (
        "reacher",
        include_str!("../robots/reacher.urdf"),
        include_str!("../robots/reacher.actuators.json"),
    ),
    (
        "pusher",
        include_str!("../robots/pusher.urdf"),
        include_str!("../robots/pusher.actuators.json"),
    ),
    (
        "humanoid_standup",
        include_str!("../robots/humanoid_standup.urdf"),
        include_str!("../robots/humanoid_standup.actuators.json"),
    ),
    (
        "ur5e",
        include_str!("../robots/ur5e.urdf"),
        include_str!("../robots/ur5e.actuators.json"),
    ),
    (
        "fetch",
        include_str!("../robots/fetch.urdf"),
        include_str!("../robots/fetch.actuators.json"),
    ),
    (
        "grasp",
        include_str!("../robots/grasp.urdf"),
        include_str!("../robots/grasp.actuators.json"),
    ),
];

pub fn is_movable(kind: &urdf_rs::JointType) -> bool {
    matches!(
        kind,
        urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous | urdf_rs::JointType::Prismatic
    )
}

impl RobotModel {
    /// The embedded description of `name`, parsed once per process: the files are constants and
    /// the model is immutable, so every environment of a robot shares one `Arc` (parsing a URDF
    /// took most of a Humanoid's construction, ~70 ms).
    pub fn load(name: &str) -> Result<Arc<RobotModel>, ModelError> {
        static PARSED: [OnceLock<Result<Arc<RobotModel>, String>>; ROBOT_FILES.len()] =
            [const { OnceLock::new() }; ROBOT_FILES.len()];
        let i = ROBOT_FILES
            .iter()
            .position(|(n, _, _)| *n == name)
            .ok_or_else(|| ModelError::Urdf {
                robot: "?",
                message: format!("no embedded robot named {name}"),
            })?;
        let (robot, urdf_text, side_text) = ROBOT_FILES[i];
        PARSED[i]
            .get_or_init(|| {
                Self::parse(robot, urdf_text, side_text)
                    .map(Arc::new)
                    .map_err(|e| e.to_string())
            })
            .clone()
            .map_err(|message| ModelError::Embedded { robot, message })
    }

    pub fn parse(robot: &'static str, urdf_text: &str, side_text: &str) -> Result<RobotModel, ModelError> {
        let urdf = urdf_rs::read_from_string(urdf_text).map_err(|e| ModelError::Urdf {
            robot,
            message: e.to_string(),
        })?;
        let side: SideFile = serde_json::from_str(side_text).map_err(|e| ModelError::Side {
            robot,
            message: e.to_string(),
        })?;
        let link_names: Vec<String> = urdf.links.iter().map(|l| l.name.clone()).collect();
        let joint_names: Vec<String> = urdf
            .joints
            .iter()
            .filter(|j| is_movable(&j.joint_type))
            .map(|j| j.name.clone())
            .collect();
        for a in &side.actuators {
            if !joint_names.contains(&a.joint) {
                return Err(ModelError::Side {
                    robot,
                    message: format!("actuator joint {} is not a movable joint of the URDF", a.joint),
                });
            }
        }
        let armature_joints = side.joint_armatures.iter().map(|a| &a.joint);
        let damping_joints = side.joint_dampings.iter().map(|a| &a.joint);
        let initial_joints = side.initial_joints.iter().map(|a| &a.joint);
        for name in side
            .joint_springs
            .iter()
            .map(|s| &s.joint)
            .chain(&side.root_joints)
            .chain(armature_joints)
            .chain(damping_joints)
            .chain(initial_joints)
            .chain(&side.rail_joints)
            .chain(&side.bouncing_limits)
        {
            if !joint_names.contains(name) {
                return Err(ModelError::Side {
                    robot,
                    message: format!("joint {name} is not a movable joint of the URDF"),
                });
            }
        }
        for l in side
            .ground_links
            .iter()
            .chain(&side.contact_links)
            .chain(side.sites.iter().map(|s| &s.link))
        {
            if !link_names.contains(l) {
                return Err(ModelError::Side {
                    robot,
                    message: format!("ground, contact or site link {l} is not a link of the URDF"),
                });
            }
        }
        let mut bodies = Vec::new();
        for b in &side.bodies {
            match link_names.iter().position(|l| l == b) {
                Some(i) => bodies.push(i),
                None => {
                    return Err(ModelError::Side {
                        robot,
                        message: format!("body {b} is not a link of the URDF"),
                    });
                }
            }
        }
        if bodies.is_empty() {
            bodies = (0..link_names.len()).collect();
        }
        let torso = side.torso_link.clone().unwrap_or_else(|| link_names[0].clone());
        let Some(torso) = link_names.iter().position(|l| *l == torso) else {
            return Err(ModelError::Side {
                robot,
                message: format!("torso link {torso} is not a link of the URDF"),
            });
        };
        for (i, l) in urdf.links.iter().enumerate() {
            let carrier = side.engine == Engine::Articulated && is_carrier(&urdf, i);
            if !(l.inertial.mass.value > 0.0 || carrier && l.inertial.mass.value == 0.0) {
                return Err(ModelError::Urdf {
                    robot,
                    message: format!("link {} has no mass", l.name),
                });
            }
        }
        if side.damping_reference.is_some_and(|d| !(d > 0.0 && d.is_finite()))
            || side.contact_condim.is_some_and(|c| c != 1 && c != 3)
            || !side.floor_height.is_finite()
            || !(side.floor_margin >= 0.0 && side.floor_margin <= side.contact_model.as_ref().map_or(0.0, |c| c.margin))
        {
            return Err(ModelError::Side {
                robot,
                message: "damping_reference must be positive, contact_condim 1 or 3, floor_height finite, \
                          floor_margin within the contact margin"
                    .into(),
            });
        }
        if side.timestep <= 0.0 || side.frame_skip == 0 || side.solver_iterations == 0 {
            return Err(ModelError::Side {
                robot,
                message: "timestep, frame_skip and solver_iterations must be positive".into(),
            });
        }
        let model = RobotModel {
            torso,
            bodies,
            name: robot,
            urdf,
            side,
            link_names,
            joint_names,
        };
        Ok(model)
    }

    pub fn num_actuators(&self) -> usize {
        self.side.actuators.len()
    }

    /// One control per actuator in the side file's control range.
    pub fn action_space(&self) -> carl_env::api::Space {
        let n = self.num_actuators();
        let [lo, hi] = self.side.ctrl_range;
        carl_env::api::Space::Box {
            low: vec![lo as f32; n],
            high: vec![hi as f32; n],
            shape: vec![n],
            dtype: carl_env::api::DType::Float32,
        }
    }

    /// The link index and link-frame position of site `name`.
    pub fn site(&self, name: &str) -> Option<(usize, [f64; 3])> {
        let s = self.side.sites.iter().find(|s| s.name == name)?;
        Some((self.link_names.iter().position(|l| *l == s.link)?, s.pos))
    }

    /// The URDF mass of a link (kg).
    pub fn link_mass(&self, link: &str) -> Option<f64> {
        self.urdf
            .links
            .iter()
            .find(|l| l.name == link)
            .map(|l| l.inertial.mass.value)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every embedded robot parses, once: a second load is the same model.
    #[test]
    fn every_robot_parses_once() {
        for (name, _, _) in ROBOT_FILES {
            let a = RobotModel::load(name).unwrap();
            let b = RobotModel::load(name).unwrap();
            assert!(Arc::ptr_eq(&a, &b), "{name}");
            assert!(!a.joint_names.is_empty() || !a.link_names.is_empty(), "{name}");
        }
        assert!(RobotModel::load("no_such_robot").is_err());
    }
}
