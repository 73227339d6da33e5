//! Articulated robots from URDF: the MuJoCo family (Ant, HalfCheetah, Humanoid, Hopper,
//! Walker2d, the inverted pendulums, Reacher) on the articulated-body engine with MuJoCo's
//! semantics (crate `carl-articulated`, [`articulated`]), the Brax-2021 manipulation tasks on
//! rapier3d (reduced-coordinate multibody joints).
//!
//! * [`model`]: the embedded robot descriptions: `robots/<name>.urdf` (links, collision
//!   shapes, masses, joints; authored for this project from the published geometry or converted
//!   from Gymnasium's MuJoCo XML) and
//!   `robots/<name>.actuators.json` (motors, control range, time step, contact and solver
//!   settings that URDF cannot express).
//! * [`params`]: the context (Brax's physics parameters as CARL sets them, per-link masses).
//! * [`articulated`]: the loader from URDF + side file + context to a `carl_articulated::Model`
//!   (free, planar and fixed roots, rails and tables, MuJoCo's contact and limit models), and
//!   one instance's world on that engine.
//! * [`physics`]: a task's physics, either engine.
//! * [`world`]: one instance's rapier3d physics world, built from model + context; nothing is shared
//!   between instances.
//! * [`locomotion`]: Gymnasium v5 tasks (Ant, HalfCheetah, Humanoid, Hopper, Walker2d).
//! * [`control`]: Gymnasium v5 control tasks (InvertedPendulum, InvertedDoublePendulum,
//!   Reacher) on the articulated engine.
//! * [`com`]: MuJoCo's centre-of-mass based body quantities (`cinert`, `cvel`, `cfrc_ext`).
//! * [`goal`]: carl-bench's goal-directed variant of the locomotion tasks (the `goal` option).
//! * [`fetch`]: Brax's fetch task (a dog runs to random targets).
//! * [`grasp`]: Brax's claw hand grasping a ball.
//! * [`render`]: software rendering of a world to a [`Frame`](carl_pixels::Frame).

pub mod articulated;
pub mod com;
pub mod control;
pub mod fetch;
pub mod goal;
pub mod grasp;
pub mod locomotion;
pub mod model;
pub mod params;
pub mod physics;
pub mod reach;
mod registry;
pub mod render;
pub mod vec3;
pub mod world;

pub use control::{Control, ControlTask};
pub use fetch::Fetch;
pub use goal::GoalLocomotion;
pub use grasp::Grasp;
pub use locomotion::{ContactCost, ForwardVelocity, Locomotion, StepInfo, TaskConfig, VelocityNoise};
pub use model::RobotModel;
pub use params::RobotParams;
pub use reach::Reach;
pub use registry::REGISTRATIONS;
pub use world::RobotWorld;

/// The physics engine behind the rapier-based environments, pinned exactly in `Cargo.toml`
/// (HalfCheetah runs on [`articulated`] unless its `rapier` option is set).
pub const PHYSICS_ENGINE: &str =
    "rapier3d =0.36.1 + rapier3d-urdf =0.36.1 (features: enhanced-determinism; f32, dim3, multibody joints)";

/// Default context of a robot environment (the spec's defaults, for direct construction).
pub fn default_params(id: &str) -> Option<RobotParams> {
    let model = RobotModel::load(robot_of(id)?).ok()?;
    let mut p = RobotParams::for_model(robot_of(id)?, &model);
    match id {
        "ant" => {
            p.joint_angular_damping = 35.0;
            p.torso_mass = Some(10.0);
            p.actuator_strength = Some(300.0);
        }
        "half_cheetah" => {
            p.joint_stiffness = 15000.0;
            p.torso_mass = Some(9.457333);
        }
        "humanoid" => {
            p.torso_mass = Some(8.907463);
        }
        // carl-bench 1.1.1's CARLBraxHopper / CARLBraxWalker2d defaults (the other links keep
        // the model's masses, which equal carl-bench's).
        "hopper" | "walker2d" => {
            p.friction = 1.0;
            p.torso_mass = Some(10.0);
            let foot = if id == "hopper" { 5.3155746 } else { 3.1667254 };
            let mut masses = vec![("thigh", 4.0578904), ("leg", 2.7813568), ("foot", foot)];
            if id == "walker2d" {
                masses.extend([("thigh_left", 4.0578904), ("leg_left", 2.7813568), ("foot_left", foot)]);
            }
            p.link_masses = masses.into_iter().map(|(l, m)| (l.to_string(), m)).collect();
        }
        // carl-bench 1.1.1's CARLBraxInvertedPendulum / CARLBraxInvertedDoublePendulum /
        // CARLBraxReacher defaults (Brax's masses of the pendulums; Reacher's equal MuJoCo's).
        "inverted_pendulum" | "inverted_double_pendulum" => {
            p.friction = 1.0;
            let mut masses = vec![("cart", 1.0), ("pole", 1.0)];
            if id == "inverted_double_pendulum" {
                masses.push(("pole2", 1.0));
            }
            p.link_masses = masses.into_iter().map(|(l, m)| (l.to_string(), m)).collect();
        }
        "reacher" => {
            p.friction = 1.0;
            p.link_masses = vec![("body0".to_string(), 0.03560472), ("body1".to_string(), 0.03979351)];
        }
        // carl-bench 1.1.1's CARLBraxPusher / CARLBraxHumanoidStandup defaults (Brax's masses,
        // which equal the models' but for Pusher's object and HumanoidStandup's torso).
        "pusher" => {
            p.friction = 1.0;
            p.goal_position = [0.45, 0.05, 0.05];
            p.link_masses = [
                ("r_shoulder_pan_link", 7.2935214),
                // carl-bench's literal (Brax's mass of a capsule at density 300), not π.
                #[allow(clippy::approx_constant)]
                ("r_shoulder_lift_link", 3.1415926535898),
                ("r_upper_arm_roll_link", 1.7140529),
                ("r_elbow_flex_link", 0.40715042),
                ("r_forearm_roll_link", 0.92818356),
                ("r_wrist_flex_link", 0.0050265482),
                ("r_wrist_roll_link", 0.18346901),
                ("object", 0.0018325957),
            ]
            .into_iter()
            .map(|(l, m)| (l.to_string(), m))
            .collect();
        }
        "humanoid_standup" => {
            p.friction = 1.0;
            p.torso_mass = Some(10.0);
            p.link_masses = [
                ("lwaist", 2.2619467),
                ("pelvis", 6.6161942),
                ("right_thigh", 4.751751),
                ("right_shin", 4.522842),
                ("left_thigh", 4.751751),
                ("left_shin", 4.522842),
                ("right_upper_arm", 1.6610805),
                ("right_lower_arm", 1.2295402),
                ("left_upper_arm", 1.6610805),
                ("left_lower_arm", 1.2295402),
            ]
            .into_iter()
            .map(|(l, m)| (l.to_string(), m))
            .collect();
        }
        "ur5e" => {
            p.gravity = -9.81;
            p.joint_angular_damping = 50.0;
            p.joint_stiffness = 40000.0;
            p.actuator_strength = Some(100.0);
            p.torso_mass = Some(1.0);
            p.target_distance = 0.5;
            p.target_radius = 0.02;
        }
        "fetch" => {
            p.joint_angular_damping = 35.0;
            p.actuator_strength = Some(300.0);
            p.torso_mass = Some(1.0);
            p.target_distance = 15.0;
            p.target_radius = 2.0;
        }
        "grasp" => {
            p.joint_angular_damping = 50.0;
            p.actuator_strength = Some(300.0);
            p.target_distance = 10.0;
            p.target_height = 8.0;
            p.target_radius = 1.1;
        }
        _ => return None,
    }
    if has_goal_option(id) {
        // carl-bench 1.1.1's goal features (BraxWalkerGoalWrapper).
        p.target_distance = 100.0;
        p.target_radius = 5.0;
        p.target_direction = 1.0;
    }
    Some(p)
}

/// Whether environment `id` takes the `goal` option (carl-bench's goal-directed walkers).
pub fn has_goal_option(id: &str) -> bool {
    matches!(id, "ant" | "half_cheetah" | "hopper" | "humanoid" | "walker2d")
}

/// Whether `id` is one of the robot environments of this module.
pub fn is_robot(id: &str) -> bool {
    robot_of(id).is_some()
}

/// The robot (URDF and side-file name) of environment `id`; also the environment's id.
fn robot_of(id: &str) -> Option<&'static str> {
    match id {
        "ant" => Some("ant"),
        "half_cheetah" => Some("half_cheetah"),
        "humanoid" => Some("humanoid"),
        "hopper" => Some("hopper"),
        "walker2d" => Some("walker2d"),
        "inverted_pendulum" => Some("inverted_pendulum"),
        "inverted_double_pendulum" => Some("inverted_double_pendulum"),
        "reacher" => Some("reacher"),
        "pusher" => Some("pusher"),
        "humanoid_standup" => Some("humanoid_standup"),
        "ur5e" => Some("ur5e"),
        "fetch" => Some("fetch"),
        "grasp" => Some("grasp"),
        _ => None,
    }
}

/// Build the fetch environment with context `params`.
pub fn make_fetch(params: RobotParams) -> Option<Fetch> {
    Some(Fetch::new(RobotModel::load("fetch").ok()?, params))
}

/// Build Gymnasium's control task `id` (inverted_pendulum, inverted_double_pendulum, reacher,
/// pusher)
/// with context `params`, or `None` if `id` is none of them.
pub fn make_control(id: &str, params: RobotParams) -> Option<Control> {
    let (id, task) = match id {
        "inverted_pendulum" => ("inverted_pendulum", ControlTask::InvertedPendulum),
        "inverted_double_pendulum" => ("inverted_double_pendulum", ControlTask::InvertedDoublePendulum),
        "reacher" => ("reacher", ControlTask::Reacher),
        "pusher" => ("pusher", ControlTask::Pusher),
        _ => return None,
    };
    Control::new(id, RobotModel::load(robot_of(id)?).ok()?, params, task).ok()
}

/// Build the UR5e reach environment with context `params`.
pub fn make_reach(params: RobotParams) -> Option<Reach> {
    Some(Reach::new(RobotModel::load("ur5e").ok()?, params))
}

/// Build Brax's grasp environment with context `params`.
pub fn make_grasp(params: RobotParams) -> Option<Grasp> {
    Some(Grasp::new(RobotModel::load("grasp").ok()?, params))
}

/// Build the environment `id` with context `params`, or `None` if `id` is not a robot.
pub fn make_robot(id: &str, params: RobotParams) -> Option<Locomotion> {
    make_robot_with_model(id, RobotModel::load(robot_of(id)?).ok()?, params)
}

/// [`make_robot`] with Gymnasium's `terminate_when_unhealthy` set (Hopper, Walker2d: `false`
/// keeps an unhealthy robot running, without the healthy reward, until the time limit).
pub fn make_robot_with_termination(
    id: &str,
    params: RobotParams,
    terminate_when_unhealthy: bool,
) -> Option<Locomotion> {
    let model = RobotModel::load(robot_of(id)?).ok()?;
    let (id, mut task) = match id {
        "hopper" => ("hopper", TaskConfig::HOPPER),
        "walker2d" => ("walker2d", TaskConfig::WALKER2D),
        _ => return None,
    };
    task.terminate_when_unhealthy = terminate_when_unhealthy;
    Locomotion::new(id, model, params, task).ok()
}

/// [`make_robot`] on the rapier3d engine whatever the side file's `engine` (HalfCheetah's
/// `--option rapier=true`, for comparison).
pub fn make_robot_on_rapier(id: &str, params: RobotParams) -> Option<Locomotion> {
    let mut model = (*RobotModel::load(robot_of(id)?).ok()?).clone();
    model.side.engine = model::Engine::Rapier;
    make_robot_with_model(id, std::sync::Arc::new(model), params)
}

fn make_robot_with_model(id: &str, model: std::sync::Arc<RobotModel>, params: RobotParams) -> Option<Locomotion> {
    match id {
        "ant" => Locomotion::new("ant", model, params, TaskConfig::ANT).ok(),
        "half_cheetah" => Locomotion::new("half_cheetah", model, params, TaskConfig::HALF_CHEETAH).ok(),
        "humanoid" => Locomotion::new("humanoid", model, params, TaskConfig::HUMANOID).ok(),
        "humanoid_standup" => Locomotion::new("humanoid_standup", model, params, TaskConfig::HUMANOID_STANDUP).ok(),
        "hopper" => Locomotion::new("hopper", model, params, TaskConfig::HOPPER).ok(),
        "walker2d" => Locomotion::new("walker2d", model, params, TaskConfig::WALKER2D).ok(),
        _ => None,
    }
}

/// The empty context of robot `id` (every feature at the model's value) for the registry to
/// fill in, or `None` if `id` is not a robot.
pub fn blank_params(id: &str) -> Option<RobotParams> {
    let model = RobotModel::load(robot_of(id)?).ok()?;
    Some(RobotParams::for_model(robot_of(id)?, &model))
}
