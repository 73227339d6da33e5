//! The Box2D family's registrations.

use carl_env::api::{Action, Space};
use carl_env::context::{MakeError, OptionKind, OptionSpec};
use carl_env::policy::{FnPolicy, Policy, PolicyError};
use carl_env::registration::{AuditProfile, Registration, StepCost, params};
use carl_env::runtime::AnyEnv;

use crate::{
    BipedalWalker, BipedalWalkerOptions, BipedalWalkerParams, LunarLander, LunarLanderOptions, LunarLanderParams,
    VehicleRacing, VehicleRacingOptions, VehicleRacingParams, WalkerHeuristic,
};

/// The environments of this family, in registry order.
pub const REGISTRATIONS: &[Registration] = &[
    Registration {
        id: "lunar_lander",
        build: |v, o| {
            let p = params::<LunarLanderParams>("lunar_lander", v, LunarLanderParams::set)?;
            let opts = LunarLanderOptions {
                continuous: o.flag("continuous"),
                crash_penalty: o.get("crash_penalty"),
            };
            Ok(AnyEnv::new(LunarLander::with_options(p, opts)))
        },
        runtime_default: |n| LunarLanderParams::default().get(n).ok(),
        options: &[
            OptionSpec {
                name: "continuous",
                help: "LunarLanderContinuous: actions [main, lateral] in [-1, 1]",
                kind: OptionKind::Bool { default: false },
            },
            OptionSpec {
                name: "crash_penalty",
                help: "reward on crash or leaving the view is -crash_penalty (Gymnasium 100, the paper's evaluation 10000)",
                kind: OptionKind::Number {
                    default: 100.0,
                    min: 0.0,
                    max: 1e9,
                },
            },
        ],
        heuristic: Some(lander_heuristic),
        renders: true,
        cost: StepCost::Heavy,
        audit: AuditProfile::STANDARD,
        vector_kernel: None,
    },
    Registration {
        id: "bipedal_walker",
        build: |v, o| {
            let p = params::<BipedalWalkerParams>("bipedal_walker", v, BipedalWalkerParams::set)?;
            let max = crate::bipedal_walker::MAX_TERRAIN_LENGTH;
            if p.terrain_length > max as f64 {
                return Err(MakeError::Runtime {
                    env: "bipedal_walker".into(),
                    message: format!(
                        "TERRAIN_LENGTH = {} is more than this runtime builds (at most {max} steps, even out of bounds: every step is a static edge the walker is tested against)",
                        p.terrain_length
                    ),
                });
            }
            let opts = BipedalWalkerOptions {
                hardcore: o.flag("hardcore"),
                ..BipedalWalkerOptions::default()
            };
            Ok(AnyEnv::new(BipedalWalker::with_options(p, opts)))
        },
        runtime_default: |n| BipedalWalkerParams::default().get(n).ok(),
        options: &[OptionSpec {
            name: "hardcore",
            help: "BipedalWalkerHardcore: stumps, stairs and pits between grass stretches",
            kind: OptionKind::Bool { default: false },
        }],
        heuristic: Some(|_| Box::new(WalkerPolicy(WalkerHeuristic::default()))),
        renders: true,
        cost: StepCost::Heavy,
        // Each probe rebuilds a physics world and the 4-D action grid is larger (a probe costs
        // ~40 µs against well under 1 µs for classic control). Hull x over the whole default
        // course (200 steps of 14/30 m = 93.3 m) and a little beyond both ends, so states reach
        // `x < 0` and the finish line.
        audit: AuditProfile {
            trajectory_seeds: 4,
            trajectory_steps: 24,
            random_states: 128,
            reset_seeds: 8,
            state_hint: &[(-1.0, 95.0)],
        },
        vector_kernel: None,
    },
    Registration {
        id: "vehicle_racing",
        build: |v, o| {
            let p = params::<VehicleRacingParams>("vehicle_racing", v, VehicleRacingParams::set)?;
            let opts = VehicleRacingOptions {
                continuous: o.flag("continuous"),
                ..VehicleRacingOptions::default()
            };
            let env = VehicleRacing::with_options(p, opts).map_err(|message| MakeError::BadValue {
                env: "vehicle_racing".into(),
                name: "VEHICLE".into(),
                expected: "vehicle index in 0..=28",
                got: message,
            })?;
            Ok(AnyEnv::new(env))
        },
        runtime_default: |n| VehicleRacingParams::default().get(n).ok(),
        options: &[OptionSpec {
            name: "continuous",
            help: "actions [steer, gas, brake] (CarRacing-v3's default); false: 5 discrete actions",
            kind: OptionKind::Bool { default: true },
        }],
        heuristic: None,
        renders: true,
        cost: StepCost::Heavy,
        audit: AuditProfile::STANDARD,
        vector_kernel: None,
    },
];

/// Gymnasium's lander heuristic, discrete or continuous after the action space.
fn lander_heuristic(space: &Space) -> Box<dyn Policy> {
    match space {
        Space::Discrete { .. } => Box::new(FnPolicy(|obs| Action::Discrete(crate::heuristic(obs)))),
        Space::Box { .. } => Box::new(FnPolicy(|obs| {
            Action::Continuous(crate::heuristic_continuous(obs).to_vec())
        })),
    }
}

/// Gymnasium's scripted walker gait (it remembers its phase between steps).
struct WalkerPolicy(WalkerHeuristic);

impl Policy for WalkerPolicy {
    fn reset(&mut self) {
        self.0 = WalkerHeuristic::default();
    }
    fn act(&mut self, obs: &[f32]) -> Result<Option<Action>, PolicyError> {
        Ok(Some(Action::Continuous(self.0.act(obs).to_vec())))
    }
}
