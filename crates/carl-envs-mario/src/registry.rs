//! The Mario environment's registration.

use carl_env::context::{MakeError, OptionKind, OptionSpec};
use carl_env::registration::{AuditProfile, Registration, StepCost};
use carl_env::runtime::AnyEnv;

/// The environments of this family, in registry order.
pub const REGISTRATIONS: &[Registration] = &[Registration {
    id: "mario",
    build: |v, o| {
        let options = crate::MarioOptions {
            frame_dim: o.get("frame_dim") as usize,
            sticky_action_probability: o.get("sticky_action_probability"),
            sparse_rewards: o.flag("sparse_rewards"),
            ..crate::MarioOptions::default()
        };
        let env = crate::Mario::from_context_with(v, options).map_err(|e| MakeError::Runtime {
            env: "mario".into(),
            message: e.to_string(),
        })?;
        Ok(AnyEnv::new(env))
    },
    runtime_default: |n| crate::MarioParams::default().get(n).ok(),
    options: &[
        OptionSpec {
            name: "frame_dim",
            help: "side of the grayscale observation frames: 64 (the paper, CARL 2021) or 84 (carl-bench 1.1.1)",
            kind: OptionKind::Number {
                default: 64.0,
                min: 16.0,
                max: 256.0,
            },
        },
        OptionSpec {
            name: "sticky_action_probability",
            help: "probability of repeating the previous action (CARL's default 0.1, unseeded there; seeded by reset here)",
            kind: OptionKind::Number {
                default: 0.0,
                min: 0.0,
                max: 1.0,
            },
        },
        OptionSpec {
            name: "sparse_rewards",
            help: "reward 1 only on completing the level (CARL's sparse_rewards)",
            kind: OptionKind::Bool { default: false },
        },
    ],
    heuristic: None,
    renders: true,
    cost: StepCost::Heavy,
    // Every transition re-runs the reset tick and draws the observation; a new level per
    // perturbed generator feature.
    audit: AuditProfile {
        trajectory_seeds: 2,
        trajectory_steps: 24,
        random_states: 16,
        reset_seeds: 2,
        state_hint: &[],
    },
    vector_kernel: None,
}];
