//! The Brax family's registrations.

use carl_env::context::{MakeError, OptionKind, OptionSpec, OptionValues};
use carl_env::registration::{AuditProfile, Registration, StepCost};
use carl_env::runtime::AnyEnv;

use crate::{self as robots, RobotParams};

/// Articulated robots: each transition is five 3-D multibody physics steps.
const ROBOT: AuditProfile = AuditProfile {
    trajectory_seeds: 3,
    trajectory_steps: 8,
    random_states: 8,
    reset_seeds: 4,
    state_hint: &[],
};

/// The control tasks (a few joints, cheap steps): longer trajectories, more random states.
const CONTROL_AUDIT: AuditProfile = AuditProfile {
    trajectory_seeds: 3,
    trajectory_steps: 16,
    random_states: 32,
    reset_seeds: 4,
    state_hint: &[],
};

/// Humanoid: transitions cost ~5x an Ant's (20 links, 23 DoFs): fewer base states, one
/// trajectory long enough for the feet to land (~10 steps); root heights down to 0.9 m put the
/// feet in contact, where friction acts.
const HUMANOID_AUDIT: AuditProfile = AuditProfile {
    trajectory_seeds: 1,
    trajectory_steps: 12,
    random_states: 4,
    reset_seeds: 3,
    state_hint: &[(-0.5, 0.5), (-0.5, 0.5), (0.9, 1.45)],
};

/// Gymnasium's `terminate_when_unhealthy` of Hopper-v5 and Walker2d-v5.
const TERMINATE_WHEN_UNHEALTHY: OptionSpec = OptionSpec {
    name: "terminate_when_unhealthy",
    help: "end the episode when the robot leaves its healthy range (Gymnasium's default); false: keep running without the healthy reward",
    kind: OptionKind::Bool { default: true },
};

/// carl-bench's goal-directed variant ([`crate::goal`]): reward for approaching a goal placed by
/// target_distance / target_direction, success within target_radius.
const GOAL: OptionSpec = OptionSpec {
    name: "goal",
    help: "carl-bench's goal-directed variant: reward is the decrease of the torso's distance to a goal target_distance m away on the bearing of target_direction, success (termination) within target_radius",
    kind: OptionKind::Bool { default: false },
};

/// The environments of this family, in registry order.
pub const REGISTRATIONS: &[Registration] = &[
    Registration {
        id: "ant",
        build: |v, o| with_goal(locomotion("ant", v)?, o),
        runtime_default: |n| robot_default("ant", n),
        options: &[GOAL],
        heuristic: None,
        renders: true,
        cost: StepCost::Heavy,
        audit: ROBOT,
        vector_kernel: None,
    },
    Registration {
        id: "half_cheetah",
        build: |v, o| {
            if o.flag("rapier") {
                let p = robot_params("half_cheetah", v)?;
                let task =
                    robots::make_robot_on_rapier("half_cheetah", p).ok_or_else(|| missing_model("half_cheetah"))?;
                return with_goal(task, o);
            }
            with_goal(locomotion("half_cheetah", v)?, o)
        },
        runtime_default: |n| robot_default("half_cheetah", n),
        options: &[
            OptionSpec {
                name: "rapier",
                help: "the rapier3d multibody engine instead of the articulated engine (crates/carl-articulated), for comparison",
                kind: OptionKind::Bool { default: false },
            },
            GOAL,
        ],
        heuristic: None,
        renders: true,
        cost: StepCost::Heavy,
        audit: ROBOT,
        vector_kernel: None,
    },
    Registration {
        id: "hopper",
        build: |v, o| planar_walker("hopper", v, o),
        runtime_default: |n| robot_default("hopper", n),
        options: &[TERMINATE_WHEN_UNHEALTHY, GOAL],
        heuristic: None,
        renders: true,
        cost: StepCost::Heavy,
        // Long enough for the foot (4 cm up at reset) to land (~11 steps); root heights down to
        // 1.05 m put the foot into the floor, where friction and elasticity act; joint angles
        // beyond the limits. State: rootx rootz rooty thigh leg foot, then rates.
        audit: AuditProfile {
            trajectory_seeds: 2,
            trajectory_steps: 16,
            random_states: 8,
            reset_seeds: 4,
            state_hint: &[
                (0.0, 0.0),
                (1.05, 1.3),
                (-0.3, 0.3),
                (-2.8, 0.2),
                (-2.8, 0.2),
                (-1.0, 1.0),
            ],
        },
        vector_kernel: None,
    },
    Registration {
        id: "walker2d",
        build: |v, o| planar_walker("walker2d", v, o),
        runtime_default: |n| robot_default("walker2d", n),
        options: &[TERMINATE_WHEN_UNHEALTHY, GOAL],
        heuristic: None,
        renders: true,
        cost: StepCost::Heavy,
        // As Hopper's, with the left leg after the right.
        audit: AuditProfile {
            trajectory_seeds: 2,
            trajectory_steps: 16,
            random_states: 8,
            reset_seeds: 4,
            state_hint: &[
                (0.0, 0.0),
                (1.05, 1.3),
                (-0.3, 0.3),
                (-2.8, 0.2),
                (-2.8, 0.2),
                (-1.0, 1.0),
                (-2.8, 0.2),
                (-2.8, 0.2),
                (-1.0, 1.0),
            ],
        },
        vector_kernel: None,
    },
    Registration {
        id: "inverted_pendulum",
        build: |v, _| control("inverted_pendulum", v),
        runtime_default: |n| robot_default("inverted_pendulum", n),
        options: &[],
        heuristic: None,
        renders: true,
        cost: StepCost::Heavy,
        // Two coordinates; cart positions beyond the rail's ends (±1, where elasticity acts),
        // pole angles up to its ±90° limits. State: slider hinge, then rates.
        audit: AuditProfile {
            state_hint: &[(-1.1, 1.1), (-1.7, 1.7), (-2.0, 2.0), (-2.0, 2.0)],
            ..CONTROL_AUDIT
        },
        vector_kernel: None,
    },
    Registration {
        id: "inverted_double_pendulum",
        build: |v, _| control("inverted_double_pendulum", v),
        runtime_default: |n| robot_default("inverted_double_pendulum", n),
        options: &[],
        heuristic: None,
        renders: true,
        cost: StepCost::Heavy,
        // As InvertedPendulum's; State: slider hinge hinge2, rates, the slider's constraint force.
        audit: AuditProfile {
            state_hint: &[
                (-1.1, 1.1),
                (-1.0, 1.0),
                (-1.0, 1.0),
                (-2.0, 2.0),
                (-2.0, 2.0),
                (-2.0, 2.0),
            ],
            ..CONTROL_AUDIT
        },
        vector_kernel: None,
    },
    Registration {
        id: "reacher",
        build: |v, _| control("reacher", v),
        runtime_default: |n| robot_default("reacher", n),
        options: &[],
        heuristic: None,
        renders: true,
        cost: StepCost::Heavy,
        // Elbow angles beyond its ±3 rad limit (where elasticity acts), targets in the disc.
        // State: joint0 joint1 target_x target_y, then the arm's rates.
        audit: AuditProfile {
            state_hint: &[
                (-3.2, 3.2),
                (-3.2, 3.2),
                (-0.2, 0.2),
                (-0.2, 0.2),
                (-5.0, 5.0),
                (-5.0, 5.0),
            ],
            ..CONTROL_AUDIT
        },
        vector_kernel: None,
    },
    Registration {
        id: "pusher",
        build: |v, _| control("pusher", v),
        runtime_default: |n| robot_default("pusher", n),
        options: &[],
        heuristic: None,
        renders: true,
        cost: StepCost::Heavy,
        // Arm angles up to and beyond their limits (where the wrist meets the table and the
        // object), the object's slides around the goal. State: the seven arm joints, obj_slidey,
        // obj_slidex, then rates.
        audit: AuditProfile {
            trajectory_seeds: 2,
            trajectory_steps: 12,
            random_states: 12,
            reset_seeds: 4,
            state_hint: &[
                (-2.3, 1.8),
                (-0.6, 1.45),
                (-1.6, 1.8),
                (-2.4, 0.1),
                (-1.6, 1.6),
                (-1.2, 0.1),
                (-1.6, 1.6),
                (-0.3, 0.1),
                (-0.2, 0.2),
                (-2.0, 2.0),
                (-2.0, 2.0),
                (-2.0, 2.0),
                (-2.0, 2.0),
                (-2.0, 2.0),
                (-2.0, 2.0),
                (-2.0, 2.0),
                (-0.5, 0.5),
                (-0.5, 0.5),
            ],
        },
        vector_kernel: None,
    },
    Registration {
        id: "ur5e",
        build: |v, _| {
            let p = robot_params("ur5e", v)?;
            robots::make_reach(p)
                .map(AnyEnv::new)
                .ok_or_else(|| missing_model("ur5e"))
        },
        runtime_default: |n| robot_default("ur5e", n),
        options: &[],
        heuristic: None,
        renders: true,
        cost: StepCost::Heavy,
        // Joint angles beyond the ±2π joint limits (where joint_stiffness acts).
        audit: AuditProfile {
            state_hint: &[(-8.0, 8.0); 6],
            ..ROBOT
        },
        vector_kernel: None,
    },
    Registration {
        id: "fetch",
        build: |v, _| {
            let p = robot_params("fetch", v)?;
            robots::make_fetch(p)
                .map(AnyEnv::new)
                .ok_or_else(|| missing_model("fetch"))
        },
        runtime_default: |n| robot_default("fetch", n),
        options: &[],
        heuristic: None,
        renders: true,
        cost: StepCost::Heavy,
        // Eleven bodies and 21 probe actions per state; one trajectory suffices (the random
        // states reach beyond the joint limits, the goal states hit targets). The root at its
        // standing pose (x y z qw qx qy qz), hinge angles beyond the ±60° limits.
        audit: AuditProfile {
            trajectory_seeds: 1,
            trajectory_steps: 8,
            random_states: 8,
            reset_seeds: 4,
            state_hint: &[
                (0.0, 0.0),
                (0.0, 0.0),
                (1.38, 1.38),
                (1.0, 1.0),
                (0.0, 0.0),
                (0.0, 0.0),
                (0.0, 0.0),
                (-1.6, 1.6),
                (-1.6, 1.6),
                (-1.6, 1.6),
                (-1.6, 1.6),
                (-1.6, 1.6),
                (-1.6, 1.6),
                (-1.6, 1.6),
                (-1.6, 1.6),
                (-1.6, 1.6),
                (-1.6, 1.6),
            ],
        },
        vector_kernel: None,
    },
    Registration {
        id: "humanoid",
        build: |v, o| with_goal(locomotion("humanoid", v)?, o),
        runtime_default: |n| robot_default("humanoid", n),
        options: &[GOAL],
        heuristic: None,
        renders: true,
        cost: StepCost::Heavy,
        audit: HUMANOID_AUDIT,
        vector_kernel: None,
    },
    Registration {
        id: "humanoid_standup",
        build: |v, _| locomotion("humanoid_standup", v).map(AnyEnv::new),
        runtime_default: |n| robot_default("humanoid_standup", n),
        options: &[],
        heuristic: None,
        renders: true,
        cost: StepCost::Heavy,
        // As Humanoid's; the body lies on the floor at reset (torso at 0.105 m), so every step
        // has contacts: root heights from lying to sitting.
        audit: AuditProfile {
            state_hint: &[(-0.5, 0.5), (-0.5, 0.5), (0.09, 0.6)],
            ..HUMANOID_AUDIT
        },
        vector_kernel: None,
    },
    Registration {
        id: "grasp",
        build: |v, _| {
            let p = robot_params("grasp", v)?;
            robots::make_grasp(p)
                .map(AnyEnv::new)
                .ok_or_else(|| missing_model("grasp"))
        },
        runtime_default: |n| robot_default("grasp", n),
        options: &[],
        heuristic: None,
        renders: true,
        cost: StepCost::Heavy,
        // A 19-DoF hand and 39 probe actions; each transition rebuilds the world and takes four
        // physics steps. Palm slides, then the 16 finger joints beyond their limits.
        audit: AuditProfile {
            trajectory_seeds: 1,
            trajectory_steps: 2,
            random_states: 3,
            reset_seeds: 2,
            state_hint: &[
                (-3.0, 3.0),
                (-3.0, 3.0),
                (3.0, 6.0),
                (-2.0, 2.0),
                (-2.0, 2.0),
                (-2.5, 2.5),
                (-2.5, 2.5),
                (-2.0, 2.0),
                (-2.0, 2.0),
                (-2.5, 2.5),
                (-2.5, 2.5),
                (-2.0, 2.0),
                (-2.0, 2.0),
                (-2.5, 2.5),
                (-2.5, 2.5),
                (-2.0, 2.0),
                (-2.0, 2.0),
                (-2.5, 2.5),
                (-2.5, 2.5),
            ],
        },
        vector_kernel: None,
    },
];

fn robot_params(id: &str, values: &[(String, f64)]) -> Result<RobotParams, MakeError> {
    let mut p = robots::blank_params(id).ok_or_else(|| missing_model(id))?;
    carl_env::context::apply(id, values, |name, x| p.set(name, x))?;
    Ok(p)
}

fn locomotion(id: &str, values: &[(String, f64)]) -> Result<robots::Locomotion, MakeError> {
    let p = robot_params(id, values)?;
    robots::make_robot(id, p).ok_or_else(|| missing_model(id))
}

fn control(id: &str, values: &[(String, f64)]) -> Result<AnyEnv, MakeError> {
    let p = robot_params(id, values)?;
    robots::make_control(id, p)
        .map(AnyEnv::new)
        .ok_or_else(|| missing_model(id))
}

/// Hopper or Walker2d with Gymnasium's `terminate_when_unhealthy` and the `goal` option.
fn planar_walker(id: &'static str, values: &[(String, f64)], o: &OptionValues) -> Result<AnyEnv, MakeError> {
    let p = robot_params(id, values)?;
    let task = robots::make_robot_with_termination(id, p, o.flag("terminate_when_unhealthy"))
        .ok_or_else(|| missing_model(id))?;
    with_goal(task, o)
}

/// `task`, or with the `goal` option its goal-directed variant ([`crate::goal`]).
fn with_goal(task: robots::Locomotion, o: &OptionValues) -> Result<AnyEnv, MakeError> {
    if !o.flag("goal") {
        return Ok(AnyEnv::new(task));
    }
    let id = carl_env::api::Env::id(&task);
    let code = task.params().target_direction;
    robots::GoalLocomotion::new(task)
        .map(AnyEnv::new)
        .ok_or_else(|| MakeError::Runtime {
            env: id.into(),
            message: format!(
                "target_direction = {code} is not one of carl-bench's 16 compass codes (1 north, 2 east, 3 south, 4 west, 12, 32, 14, 34, 112, 332, 114, 334, 212, 232, 414, 434)"
            ),
        })
}

/// The embedded robot description failed to load (a build defect, reported, never a panic).
fn missing_model(id: &str) -> MakeError {
    MakeError::Runtime {
        env: id.into(),
        message: "its embedded robot model failed to load (a build defect)".into(),
    }
}

/// The robot's own default of feature `name` (its default `RobotParams`).
fn robot_default(id: &str, name: &str) -> Option<f64> {
    robots::default_params(id)?.get(name).ok()
}
