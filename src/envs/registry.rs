//! The environment table: every runtime declared once.
//!
//! An entry says how to build the runtime from a resolved context, which variant options it
//! takes, whether it has a hand-written controller and a renderer, how the sensitivity audit
//! probes it, how `bench` and [`VecEnv`](super::vec_env::VecEnv) treat it, and whether it has a
//! vector kernel. Everything that runs environments (the CLI's `rollout`, `render`, `bench`,
//! `audit`, the contextual wrapper, `VecEnv`, the Python package) reads this table, so adding an
//! environment is one module (its `Env`, `Params`, `impl Runtime`) plus one entry here.
//!
//! [`make`] checks every context name and value against the environment's spec (unknown names
//! and out-of-bounds values are errors unless explicitly allowed), writes them into the runtime's
//! `Params`, and wraps the result in the spec's episode limit. Nothing is shared between
//! environments: each owns its `Params`.

use super::api::{Action, Space, TimeLimit};
use super::box2d::{
    BipedalWalker, BipedalWalkerOptions, BipedalWalkerParams, LunarLander, LunarLanderOptions, LunarLanderParams,
    VehicleRacing, VehicleRacingOptions, VehicleRacingParams, WalkerHeuristic,
};
use super::classic::{
    Acrobot, AcrobotParams, CartPole, CartPoleParams, MountainCar, MountainCarContinuous, MountainCarContinuousParams,
    MountainCarParams, Pendulum, PendulumParams,
};
use super::policy::{FnPolicy, Policy, PolicyError};
use super::rna_design::{Dataset, RnaDesign, RnaDesignParams, TargetError};
use super::robots::{self, RobotParams};
use super::runtime::AnyEnv;
use crate::spec::model::EnvSpec;

pub use super::context::{
    Context, EnvOptions, MakeError, MakeOptions, OptionKind, OptionSpec, OptionValues, resolve_context, resolve_options,
};

/// Builds a runtime from every feature's value (canonical names, spec order) and the resolved
/// variant options.
pub type BuildFn = fn(&[(String, f64)], &OptionValues) -> Result<AnyEnv, MakeError>;

/// The hand-written controller for a runtime with this action space.
pub type HeuristicFn = fn(&Space) -> Box<dyn Policy>;

/// One runtime's declaration.
#[derive(Debug, Clone, Copy)]
pub struct Registration {
    /// The spec's environment id.
    pub id: &'static str,
    /// Build the runtime from every feature's value (canonical names, spec order) and the
    /// resolved options.
    pub build: BuildFn,
    /// Variant options (`continuous`, `hardcore`, …).
    pub options: &'static [OptionSpec],
    /// The environment's hand-written controller, for the runtime built (its action space says
    /// e.g. discrete or continuous).
    pub heuristic: Option<HeuristicFn>,
    /// Whether `Env::render` draws pictures.
    pub renders: bool,
    /// How one step costs: sets thread work-sharing and `bench` defaults.
    pub cost: StepCost,
    /// How the sensitivity audit probes this runtime.
    pub audit: AuditProfile,
    /// A batched kernel `VecEnv` uses instead of an array of environments.
    pub vector_kernel: Option<VectorKernel>,
}

/// What one step costs, roughly.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepCost {
    /// Nanoseconds (closed-form dynamics): `VecEnv` shares work in blocks of 16 environments,
    /// `bench` defaults to 1024 environments.
    Light,
    /// Microseconds or more (a physics world, a rendered picture): blocks of 1, 64 environments.
    Heavy,
}

impl StepCost {
    /// Environments per `bench` VecEnv run unless told otherwise.
    pub fn bench_num_envs(self) -> usize {
        match self {
            StepCost::Light => 1024,
            StepCost::Heavy => 64,
        }
    }
    /// Smallest block of environments one `VecEnv` thread claims.
    pub fn min_block(self) -> usize {
        match self {
            StepCost::Light => 16,
            StepCost::Heavy => 1,
        }
    }
}

/// Batched kernels (structure-of-arrays stepping) that [`VecEnv`](super::vec_env::VecEnv) has.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VectorKernel {
    /// CartPole's state and constants in contiguous arrays; the same step function as the
    /// scalar environment.
    CartPole,
}

/// How much the audit probes a runtime, and where its state space lies.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct AuditProfile {
    /// Trajectories (one per reset seed `0..n`) whose states become base states.
    pub trajectory_seeds: u64,
    /// Random-action steps per trajectory.
    pub trajectory_steps: usize,
    /// Extra base states drawn uniformly from a box over the state space.
    pub random_states: usize,
    /// Seeds `0..n` used to compare initial states.
    pub reset_seeds: u64,
    /// Ranges of leading state components that the box must cover beyond what trajectories
    /// reach (angles seen through cos/sin, joint limits, goal regions).
    #[serde(skip)]
    pub state_hint: &'static [(f64, f64)],
}

impl AuditProfile {
    /// The default probes: all five classic-control runtimes in well under a second.
    pub const STANDARD: AuditProfile = AuditProfile {
        trajectory_seeds: 8,
        trajectory_steps: 24,
        random_states: 256,
        reset_seeds: 16,
        state_hint: &[],
    };
    /// Articulated robots: each transition is five 3-D multibody physics steps.
    const ROBOT: AuditProfile = AuditProfile {
        trajectory_seeds: 3,
        trajectory_steps: 8,
        random_states: 8,
        reset_seeds: 4,
        state_hint: &[],
    };
}

impl Default for AuditProfile {
    fn default() -> Self {
        AuditProfile::STANDARD
    }
}

/// A runtime environment as `make` returns it: the spec's episode limit around the dynamics.
pub type SpecEnv = TimeLimit<AnyEnv>;

const PI: f64 = std::f64::consts::PI;

/// Every runtime of this crate.
pub static REGISTRY: &[Registration] = &[
    Registration {
        id: "cartpole",
        build: |v, _| {
            Ok(AnyEnv::new(CartPole::new(params::<CartPoleParams>(
                "cartpole",
                v,
                CartPoleParams::set,
            )?)))
        },
        options: &[],
        heuristic: None,
        renders: false,
        cost: StepCost::Light,
        audit: AuditProfile::STANDARD,
        vector_kernel: Some(VectorKernel::CartPole),
    },
    Registration {
        id: "pendulum",
        build: |v, _| {
            Ok(AnyEnv::new(Pendulum::new(params::<PendulumParams>(
                "pendulum",
                v,
                PendulumParams::set,
            )?)))
        },
        options: &[],
        heuristic: None,
        renders: false,
        cost: StepCost::Light,
        audit: AuditProfile {
            state_hint: &[(-PI, PI), (-8.0, 8.0)],
            ..AuditProfile::STANDARD
        },
        vector_kernel: None,
    },
    Registration {
        id: "mountain_car",
        build: |v, _| {
            let p = params::<MountainCarParams>("mountain_car", v, MountainCarParams::set)?;
            Ok(AnyEnv::new(MountainCar::new(p)))
        },
        options: &[],
        heuristic: None,
        renders: false,
        cost: StepCost::Light,
        audit: AuditProfile::STANDARD,
        vector_kernel: None,
    },
    Registration {
        id: "mountain_car_continuous",
        build: |v, _| {
            let p =
                params::<MountainCarContinuousParams>("mountain_car_continuous", v, MountainCarContinuousParams::set)?;
            Ok(AnyEnv::new(MountainCarContinuous::new(p)))
        },
        options: &[],
        heuristic: None,
        renders: false,
        cost: StepCost::Light,
        audit: AuditProfile::STANDARD,
        vector_kernel: None,
    },
    Registration {
        id: "acrobot",
        build: |v, _| {
            Ok(AnyEnv::new(Acrobot::new(params::<AcrobotParams>(
                "acrobot",
                v,
                AcrobotParams::set,
            )?)))
        },
        options: &[],
        heuristic: None,
        renders: false,
        cost: StepCost::Light,
        audit: AuditProfile {
            state_hint: &[(-PI, PI), (-PI, PI), (-4.0 * PI, 4.0 * PI), (-9.0 * PI, 9.0 * PI)],
            ..AuditProfile::STANDARD
        },
        vector_kernel: None,
    },
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
            let opts = BipedalWalkerOptions {
                hardcore: o.flag("hardcore"),
                ..BipedalWalkerOptions::default()
            };
            Ok(AnyEnv::new(BipedalWalker::with_options(p, opts)))
        },
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
    Registration {
        id: "ant",
        build: |v, _| Ok(AnyEnv::new(locomotion("ant", v)?)),
        options: &[],
        heuristic: None,
        renders: true,
        cost: StepCost::Heavy,
        audit: AuditProfile::ROBOT,
        vector_kernel: None,
    },
    Registration {
        id: "half_cheetah",
        build: |v, o| {
            if o.flag("rapier") {
                let p = robot_params("half_cheetah", v)?;
                return robots::make_robot_on_rapier("half_cheetah", p)
                    .map(AnyEnv::new)
                    .ok_or_else(|| missing_model("half_cheetah"));
            }
            Ok(AnyEnv::new(locomotion("half_cheetah", v)?))
        },
        options: &[OptionSpec {
            name: "rapier",
            help: "the rapier3d multibody engine instead of the planar reduced-coordinate engine (src/envs/robots/planar)",
            kind: OptionKind::Bool { default: false },
        }],
        heuristic: None,
        renders: true,
        cost: StepCost::Heavy,
        audit: AuditProfile::ROBOT,
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
        options: &[],
        heuristic: None,
        renders: true,
        cost: StepCost::Heavy,
        // Joint angles beyond the ±2π joint limits (where joint_stiffness acts).
        audit: AuditProfile {
            state_hint: &[(-8.0, 8.0); 6],
            ..AuditProfile::ROBOT
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
        build: |v, _| Ok(AnyEnv::new(locomotion("humanoid", v)?)),
        options: &[],
        heuristic: None,
        renders: true,
        cost: StepCost::Heavy,
        // Transitions cost ~5x an Ant's (20 links, 23 DoFs): fewer base states, one trajectory
        // long enough for the feet to land (~10 steps); root heights down to 0.9 m put the feet
        // in contact, where friction acts.
        audit: AuditProfile {
            trajectory_seeds: 1,
            trajectory_steps: 12,
            random_states: 4,
            reset_seeds: 3,
            state_hint: &[(-0.5, 0.5), (-0.5, 0.5), (0.9, 1.45)],
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
    Registration {
        id: "rna_design",
        build: |v, o| {
            let p = rna_design_params(v, o)?;
            let env = RnaDesign::new(p).map_err(|e| match e {
                TargetError::UnknownId { .. } | TargetError::NoTargets { .. } => MakeError::Runtime {
                    env: "rna_design".into(),
                    message: format!("option target_structure_ids: {e}"),
                },
                other => MakeError::BadValue {
                    env: "rna_design".into(),
                    name: "dataset".into(),
                    expected: "loadable",
                    got: other.to_string(),
                },
            })?;
            Ok(AnyEnv::new(env))
        },
        options: &[
            OptionSpec {
                name: "max_improvement_folds",
                help: "cap on the folds of LEARNA's local improvement per episode (it costs up to 4^d folds); 0: no cap, as LEARNA",
                kind: OptionKind::Number {
                    default: 0.0,
                    min: 0.0,
                    max: 1e12,
                },
            },
            OptionSpec {
                name: "target_structure_ids",
                help: "ids of the dataset's targets to design for (Eterna100: puzzle numbers 1-100; Rfam-Taneda: 1-29), e.g. 1,5,17; default: all",
                kind: OptionKind::Ids,
            },
        ],
        heuristic: None,
        renders: false,
        cost: StepCost::Heavy,
        // A step is a table write; the last one of an episode folds (up to 400 nt for Eterna100).
        audit: AuditProfile {
            trajectory_seeds: 4,
            trajectory_steps: 24,
            random_states: 0,
            reset_seeds: 8,
            state_hint: &[],
        },
        vector_kernel: None,
    },
    Registration {
        id: "mario",
        build: |v, o| {
            let options = super::mario::MarioOptions {
                frame_dim: o.get("frame_dim") as usize,
                sticky_action_probability: o.get("sticky_action_probability"),
                sparse_rewards: o.flag("sparse_rewards"),
                ..super::mario::MarioOptions::default()
            };
            let env = super::mario::Mario::from_context_with(v, options).map_err(|e| MakeError::Runtime {
                env: "mario".into(),
                message: e.to_string(),
            })?;
            Ok(AnyEnv::new(env))
        },
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
    },
];

/// The registration of environment `id` (a spec id, not an alias).
pub fn lookup(id: &str) -> Option<&'static Registration> {
    REGISTRY.iter().find(|r| r.id == id)
}

/// Whether `id` has a runtime.
pub fn has_runtime(id: &str) -> bool {
    lookup(id).is_some()
}

/// Ids of every runtime, in table order.
pub fn ids() -> impl Iterator<Item = &'static str> {
    REGISTRY.iter().map(|r| r.id)
}

/// `"cartpole, pendulum, …"`: for messages.
pub fn ids_text() -> String {
    ids().collect::<Vec<_>>().join(", ")
}

/// Ids of the runtimes that satisfy `pred`, comma-separated (e.g. those with a renderer).
pub fn ids_where(pred: impl Fn(&Registration) -> bool) -> String {
    REGISTRY
        .iter()
        .filter(|r| pred(r))
        .map(|r| r.id)
        .collect::<Vec<_>>()
        .join(", ")
}

/// Build `spec`'s environment under `context` (bounds enforced, default options).
pub fn make(spec: &EnvSpec, context: &Context) -> Result<SpecEnv, MakeError> {
    make_env(spec, context, MakeOptions::default(), &EnvOptions::new())
}

/// [`make`] with a bounds policy.
pub fn make_with(spec: &EnvSpec, context: &Context, opts: MakeOptions) -> Result<SpecEnv, MakeError> {
    make_env(spec, context, opts, &EnvOptions::new())
}

/// [`make`] with a bounds policy and variant options (`continuous = true`, …).
pub fn make_env(
    spec: &EnvSpec,
    context: &Context,
    opts: MakeOptions,
    options: &EnvOptions,
) -> Result<SpecEnv, MakeError> {
    // "No runtime" first: a spec-only environment may have features (strings, lists) that no
    // runtime could take, and the missing runtime is what the user needs to hear.
    let reg = lookup(&spec.id).ok_or_else(|| MakeError::NoRuntime {
        env: spec.id.clone(),
        available: ids_text(),
    })?;
    let values = resolve_context(spec, context, opts)?;
    let options = resolve_options(reg.id, reg.options, options)?;
    let env = (reg.build)(&values, &options)?;
    Ok(TimeLimit::new(env, spec.max_episode_steps))
}

/// A `Params` value with every feature written in (a name the runtime does not know means
/// the spec and the runtime disagree).
fn params<P: Default>(
    id: &str,
    values: &[(String, f64)],
    set: fn(&mut P, &str, f64) -> Result<(), super::api::UnknownFeature>,
) -> Result<P, MakeError> {
    let mut p = P::default();
    super::context::apply(id, values, |name, x| set(&mut p, name, x))?;
    Ok(p)
}

/// rna_design's context: the spec's `dataset` choice index (eterna, rfam_learn, rfam_taneda)
/// becomes a [`Dataset`]; Rfam-Learn is read from `$CARL_SPEC_DATA`.
fn rna_design_params(values: &[(String, f64)], options: &OptionValues) -> Result<RnaDesignParams, MakeError> {
    let mut p = RnaDesignParams::default();
    for (name, x) in values {
        match name.as_str() {
            "mutation_threshold" => p.mutation_threshold = *x,
            "reward_exponent" => p.reward_exponent = *x,
            "state_radius" => p.state_radius = *x as usize,
            "dataset" => {
                p.dataset = match *x as usize {
                    0 => Dataset::Eterna,
                    1 => Dataset::RfamLearn(super::rna_design::RfamLearnSplit::Train),
                    _ => Dataset::RfamTaneda,
                }
            }
            other => {
                return Err(MakeError::UnknownFeature {
                    env: "rna_design".into(),
                    name: other.into(),
                    hint: " (the spec names a feature the runtime does not know)".into(),
                    valid: "mutation_threshold, reward_exponent, state_radius, dataset".into(),
                });
            }
        }
    }
    let cap = options.get("max_improvement_folds");
    p.max_improvement_folds = (cap > 0.0).then_some(cap as u64);
    p.target_structure_ids = options.ids("target_structure_ids").map(<[u32]>::to_vec);
    Ok(p)
}

fn robot_params(id: &str, values: &[(String, f64)]) -> Result<RobotParams, MakeError> {
    let mut p = robots::blank_params(id).ok_or_else(|| missing_model(id))?;
    super::context::apply(id, values, |name, x| p.set(name, x))?;
    Ok(p)
}

fn locomotion(id: &str, values: &[(String, f64)]) -> Result<robots::Locomotion, MakeError> {
    let p = robot_params(id, values)?;
    robots::make_robot(id, p).ok_or_else(|| missing_model(id))
}

/// The embedded robot description failed to load (a build defect, reported, never a panic).
fn missing_model(id: &str) -> MakeError {
    MakeError::NoRuntime {
        env: format!("{id} (its embedded robot model failed to load)"),
        available: ids_text(),
    }
}

/// Gymnasium's lander heuristic, discrete or continuous after the action space.
fn lander_heuristic(space: &Space) -> Box<dyn Policy> {
    match space {
        Space::Discrete { .. } => Box::new(FnPolicy(|obs| Action::Discrete(super::box2d::heuristic(obs)))),
        Space::Box { .. } => Box::new(FnPolicy(|obs| {
            Action::Continuous(super::box2d::heuristic_continuous(obs).to_vec())
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
