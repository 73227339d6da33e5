//! The dm_control family's registrations.

use carl_env::Runtime;
use carl_env::api::UnknownFeature;
use carl_env::context::{MakeError, OptionKind, OptionSpec};
use carl_env::registration::{AuditProfile, Registration, StepCost};
use carl_env::runtime::AnyEnv;

use crate::finger::{self, Finger};
use crate::fish::{self, Fish};
use crate::point_mass::{self, PointMass};
use crate::quadruped::{self, Quadruped};
use crate::walker::{self, Walker};

/// The environments of this family, in registry order.
pub const REGISTRATIONS: &[Registration] = &[
    Registration {
        id: "dmc_finger",
        build: |v, o| {
            let r = o.get("target_radius");
            let task = if r > 0.0 {
                finger::Task::Turn(r)
            } else {
                finger::Task::Spin
            };
            build("dmc_finger", v, finger::Params::set, |p| Finger::new(p, task))
        },
        runtime_default: |n| finger::Params::default().get(n),
        options: &[OptionSpec {
            name: "target_radius",
            help: "0: dm_control's finger spin task (default); a positive radius (m) is the turn task with a target of that radius: turn_easy 0.07, turn_hard 0.03",
            kind: OptionKind::Number {
                default: 0.0,
                min: 0.0,
                max: 0.2,
            },
        }],
        heuristic: None,
        renders: true,
        cost: StepCost::Heavy,
        // Two physics steps per transition with finger–spinner contacts. State: proximal,
        // distal (±1.92), hinge, then rates.
        audit: AuditProfile {
            trajectory_seeds: 2,
            trajectory_steps: 16,
            random_states: 16,
            reset_seeds: 4,
            state_hint: &[
                (-1.9, 1.9),
                (-1.9, 1.9),
                (-3.1, 3.1),
                (-5.0, 5.0),
                (-5.0, 5.0),
                (-10.0, 10.0),
            ],
        },
        vector_kernel: None,
    },
    Registration {
        id: "dmc_point_mass",
        build: |v, o| {
            let variant = point_mass::Variant {
                hard: o.flag("hard"),
                random_start: o.flag("random_start"),
            };
            build("dmc_point_mass", v, point_mass::Params::set, |p| {
                PointMass::new(p, variant)
            })
        },
        runtime_default: |n| point_mass::Params::default().get(n),
        options: &[
            OptionSpec {
                name: "hard",
                help: "dm_control's point_mass `hard` task: each episode the two motors push along random directions (the second not within |cos| > 0.9 of the first) instead of along x and y",
                kind: OptionKind::Bool { default: false },
            },
            OptionSpec {
                name: "random_start",
                help: "dm_control's reset: each slide uniform over its range (starting_x/y unused); false: the ball starts at starting_x/y (carl-bench)",
                kind: OptionKind::Bool { default: false },
            },
        ],
        heuristic: None,
        renders: true,
        cost: StepCost::Heavy,
        // Two slides within ±0.29 (the limits, where the soft walls act), rates of a few cm/s.
        audit: AuditProfile {
            trajectory_seeds: 3,
            trajectory_steps: 16,
            random_states: 32,
            reset_seeds: 4,
            state_hint: &[(-0.3, 0.3), (-0.3, 0.3), (-0.5, 0.5), (-0.5, 0.5)],
        },
        vector_kernel: None,
    },
    Registration {
        id: "dmc_walker",
        build: |v, o| {
            build("dmc_walker", v, walker::Params::set, |p| {
                Walker::new(p, o.get("move_speed"))
            })
        },
        runtime_default: |n| walker::Params::default().get(n),
        options: &[OptionSpec {
            name: "move_speed",
            help: "the horizontal speed (m/s) above which the move reward is 1: dm_control's walker walk 1 (default), run 8; 0 is stand (the standing reward alone)",
            kind: OptionKind::Number {
                default: walker::WALK_SPEED,
                min: 0.0,
                max: 20.0,
            },
        }],
        heuristic: None,
        renders: true,
        cost: StepCost::Heavy,
        // Ten physics steps per transition with floor contacts. State: rootz rootx rooty, the six
        // leg joints, then rates; heights that put the feet into the floor.
        audit: AuditProfile {
            trajectory_seeds: 2,
            trajectory_steps: 16,
            random_states: 8,
            reset_seeds: 4,
            state_hint: &[(-1.0, 0.2), (0.0, 0.0), (-0.5, 0.5)],
        },
        vector_kernel: None,
    },
    Registration {
        id: "dmc_fish",
        build: |v, o| build("dmc_fish", v, fish::Params::set, |p| Fish::new(p, o.flag("upright"))),
        runtime_default: |n| fish::Params::default().get(n),
        options: &[OptionSpec {
            name: "upright",
            help: "dm_control's fish `upright` task (reward: the torso upright; the target stays at the XML's place) instead of `swim` (reach a random target with the mouth)",
            kind: OptionKind::Bool { default: false },
        }],
        heuristic: None,
        renders: true,
        cost: StepCost::Heavy,
        // Ten physics steps per transition, no contacts. State: root position and quaternion,
        // seven joints, then rates, then the target; a small fish near its start.
        audit: AuditProfile {
            trajectory_seeds: 2,
            trajectory_steps: 16,
            random_states: 8,
            reset_seeds: 4,
            state_hint: &[(-0.2, 0.2), (-0.2, 0.2), (0.0, 0.3)],
        },
        vector_kernel: None,
    },
    Registration {
        id: "dmc_quadruped",
        build: |v, o| {
            build("dmc_quadruped", v, quadruped::Params::set, |p| {
                Quadruped::new(p, o.get("move_speed"))
            })
        },
        runtime_default: |n| quadruped::Params::default().get(n),
        options: &[OptionSpec {
            name: "move_speed",
            help: "the forward speed (m/s) above which the move reward is 1: dm_control's quadruped walk 0.5 (default), run 5",
            kind: OptionKind::Number {
                default: quadruped::WALK_SPEED,
                min: 0.05,
                max: 20.0,
            },
        }],
        heuristic: None,
        renders: true,
        cost: StepCost::Heavy,
        // Four physics steps per transition, 22 degrees of freedom with floor contacts. State:
        // the torso's position, orientation, the hinges, then rates (and activations); torso
        // heights that put the legs into the floor.
        audit: AuditProfile {
            trajectory_seeds: 2,
            trajectory_steps: 12,
            random_states: 8,
            reset_seeds: 4,
            state_hint: &[(0.0, 0.0), (0.0, 0.0), (0.2, 0.8)],
        },
        vector_kernel: None,
    },
];

/// Builds one of the family's environments: the context applied to the domain's defaults
/// (`set` refuses a name the domain does not know), then `new` under the options' task.
fn build<P: Default, E: Runtime>(
    id: &str,
    values: &[(String, f64)],
    set: fn(&mut P, &str, f64) -> Result<(), UnknownFeature>,
    new: impl FnOnce(P) -> Result<E, String>,
) -> Result<AnyEnv, MakeError> {
    let mut p = P::default();
    carl_env::context::apply(id, values, |name, x| set(&mut p, name, x))?;
    new(p).map(AnyEnv::new).map_err(|message| MakeError::Runtime {
        env: id.into(),
        message,
    })
}
