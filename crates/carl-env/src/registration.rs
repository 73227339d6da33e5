//! What an environment family declares for each environment it registers.
//!
//! A [`Registration`] says how to build the runtime from a resolved context, which variant
//! options it takes, whether it has a hand-written controller and a renderer, how the
//! sensitivity audit probes it, how `bench` and the vector environment treat it, and whether it
//! has a vector kernel. Each family crate exports its registrations as one constant slice
//! (`REGISTRATIONS`); the carl-spec crate joins the families' slices into its registry, which
//! everything that runs environments reads (the CLI, the contextual wrapper, `VecEnv`, the
//! Python package). Adding an environment is one module in its family (its `Env`, `Params`,
//! `impl Runtime`), one entry in the family's slice and one spec.

use crate::api::Space;
use crate::context::{MakeError, OptionSpec, OptionValues};
use crate::policy::Policy;
use crate::runtime::AnyEnv;

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
    /// The runtime's own value of feature `name` when no context sets it (its `Params`'
    /// default), `None` for a name it does not know or a feature the spec alone decides (a
    /// choice). The tests hold it equal to the spec's default.
    pub runtime_default: fn(&str) -> Option<f64>,
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

/// Batched kernels (structure-of-arrays stepping) that carl-spec's `VecEnv` has.
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
}

impl Default for AuditProfile {
    fn default() -> Self {
        AuditProfile::STANDARD
    }
}

/// A `Params` value with every feature written in (a name the runtime does not know means
/// the spec and the runtime disagree).
pub fn params<P: Default>(
    id: &str,
    values: &[(String, f64)],
    set: fn(&mut P, &str, f64) -> Result<(), crate::api::UnknownFeature>,
) -> Result<P, MakeError> {
    let mut p = P::default();
    crate::context::apply(id, values, |name, x| set(&mut p, name, x))?;
    Ok(p)
}
