//! The contextual wrapper's vocabulary: where contexts come from, how a set's instance is chosen,
//! what the agent sees of the context, the noise on it, what is reported per episode, the seed
//! stream names and the errors. Kept apart from [`ContextualEnv`](super::ContextualEnv) so that
//! the per-reset rules ([`super::context_schedule`]) and the wrapper both build on it.

use super::registry::{Context, EnvOptions, MakeError};
use crate::instances::FrozenSet;
use crate::instances::derive::DeriveError;

/// Stream name of the instance-selection generator (see the module docs).
pub const SELECTION_STREAM: &str = "carl-spec/contextual/selection";
/// Stream name of the per-reset distribution-seed generator.
pub const CONTEXT_STREAM: &str = "carl-spec/contextual/context";
/// Stream name of the runtime reset-seed generator.
pub const ENV_STREAM: &str = "carl-spec/contextual/env";
/// Stream name of the context-noise generator.
pub const NOISE_STREAM: &str = "carl-spec/contextual/noise";
/// Info key prefix of the observed (noisy) context values; `context.<feature>` holds the true ones.
pub const OBSERVED_PREFIX: &str = "observed_context.";

/// Where the contexts come from.
// A `FrozenSet` is large, but a source is built once and consumed by `ContextualEnv::new`.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, PartialEq)]
pub enum ContextSource {
    /// A frozen instance set (e.g. from [`Store::load`](crate::instances::Store::load)).
    Set(FrozenSet),
    /// A distribution of the spec, sampled once per reset.
    Distribution { name: String },
    /// One context for every episode (missing features take their defaults).
    Fixed(Context),
}

/// How a set's instance is chosen at reset. Ignored for distributions and fixed contexts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Selection {
    /// Instance `k mod n` at the `k`-th reset since construction.
    #[default]
    RoundRobin,
    /// Seeded uniform choice (see the module docs for the derivation).
    Random,
    /// Always this instance (position in the set, i.e. its id).
    Static(usize),
}

/// Which features are appended to the observation.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Features {
    /// Every feature with a numeric value, in spec order.
    All,
    /// These features (canonical names or aliases), in this order.
    Only(Vec<String>),
}

/// Whether the context is part of the observation.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub enum Visibility {
    #[default]
    Hidden,
    Visible(Features),
}

#[derive(Debug, Clone, PartialEq, Default)]
pub struct ContextualOptions {
    pub selection: Selection,
    pub visibility: Visibility,
    /// Gaussian noise on what the agent observes of visible features (the dynamics always use
    /// the true context).
    pub noise: ContextNoise,
    /// Variant options of the runtime (`continuous`, `hardcore`, …), the same for every instance.
    pub env_options: EnvOptions,
    /// A fixed context may lie outside the spec's bounds (a set's instances follow the set's
    /// own declaration; distribution draws never may).
    pub allow_out_of_bounds: bool,
    /// Features that change within every episode ([`super::schedules`]), by feature name.
    pub schedules: Vec<(String, super::schedules::Schedule)>,
}

/// The paper's "context measured with noise": each listed visible feature is observed as
/// `true value + std · N(0, 1)`, drawn from the wrapper's own noise stream.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ContextNoise {
    /// `(feature, std)`; canonical names or aliases of visible features.
    pub features: Vec<(String, NoiseStd)>,
    pub redraw: NoiseRedraw,
}

impl ContextNoise {
    pub fn is_empty(&self) -> bool {
        self.features.is_empty()
    }
}

/// The noise's standard deviation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NoiseStd {
    /// In the feature's own unit.
    Absolute(f64),
    /// A fraction of `|default|` (e.g. 0.1 for 10 %).
    Relative(f64),
}

/// When a new noise value is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum NoiseRedraw {
    /// Once per episode, at reset: a consistently wrong measurement.
    #[default]
    Episode,
    /// At every step: a noisy sensor.
    Step,
}

/// What the wrapper reports about the current episode's context.
#[derive(Debug, Clone, PartialEq)]
pub struct ContextInfo {
    /// The instance's id in its set (`None` for distributions and fixed contexts).
    pub instance_id: Option<usize>,
    /// The instance's name, if the set names its instances.
    pub instance_name: Option<String>,
    /// Every feature's value (defaults filled in), canonical names in spec order.
    pub context: Vec<(String, f64)>,
    /// Distributions only: the seed this episode's context was drawn with.
    pub context_seed: Option<u64>,
    /// 0-based number of the reset that started this episode (counted since construction).
    pub episode: u64,
}

#[derive(Debug, thiserror::Error)]
pub enum ContextualError {
    #[error("instance set {set} belongs to \"{set_env}\", not to \"{env}\"")]
    WrongEnv { set: String, set_env: String, env: String },
    #[error("instance set {0} has no instances")]
    EmptySet(String),
    #[error("static instance index {index} is out of range: {set} has {len} instance(s)")]
    StaticOutOfRange { index: usize, set: String, len: usize },
    #[error("{env} has no distribution \"{name}\"{hint}")]
    UnknownDistribution { env: String, name: String, hint: String },
    #[error("{env} has no context feature \"{name}\" to show in the observation{hint}; valid names: {valid}")]
    UnknownFeature {
        env: String,
        name: String,
        hint: String,
        valid: String,
    },
    #[error("{env}: context feature \"{name}\" is listed twice for the observation")]
    DuplicateFeature { env: String, name: String },
    #[error("{env}: feature \"{name}\" has no numeric value in {who}, so it cannot be observed")]
    MissingValue { env: String, name: String, who: String },
    #[error("{env}: noise on \"{name}\": {message}")]
    Noise { env: String, name: String, message: String },
    #[error("{env}: the observation space is not a Box, so the context cannot be appended")]
    NotBox { env: String },
    #[error("{who}: {source}")]
    Make {
        who: String,
        #[source]
        source: Box<MakeError>,
    },
    #[error("{0}")]
    Derive(#[from] DeriveError),
    #[error("{0}")]
    Schedule(String),
    #[error("{0}")]
    Curriculum(String),
}
