//! Raw spec files exactly as authors write them (serde + schemars).
//!
//! These types are the source of the committed JSON Schema. They keep what the author wrote
//! (includes, overrides, optional fields); `spec::model` holds the resolved form that the rest of
//! the crate uses. Keep the two apart, as cargo does with its manifest.

use std::collections::BTreeMap;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// Instance sets larger than this are refused (a frozen set is a file people read and diff).
pub const MAX_INSTANCES: u64 = 1_000_000;
/// Most values (instances × varied features) one sampled set may hold: deriving, hashing and
/// printing a set peaks at about 1.5 KB of memory per value (1.5 GB at this limit, measured).
pub const MAX_SET_VALUES: u64 = 1_000_000;

/// One environment's context specification (`specs/<id>.json`).
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema, PartialEq)]
#[serde(deny_unknown_fields)]
#[schemars(title = "carl-spec environment spec")]
pub struct RawEnvSpec {
    /// Path or URL of this schema, for editor completion. Ignored by carl-spec.
    #[serde(rename = "$schema", default, skip_serializing_if = "Option::is_none")]
    pub schema: Option<String>,
    /// Stable snake_case identifier, e.g. `cartpole`. Used on the command line and in instance-set names.
    #[schemars(regex(pattern = r"^[a-z][a-z0-9_]*$"))]
    pub id: String,
    /// Other names users know the environment by, e.g. the paper's class name `CARLCartPoleEnv`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub aliases: Vec<String>,
    /// Environment family, snake_case, e.g. `classic_control`, `box2d`, `brax`.
    #[schemars(regex(pattern = r"^[a-z][a-z0-9_]*$"))]
    pub family: String,
    /// The upstream environment this spec extends with a context.
    pub upstream: Upstream,
    /// The environment's version, bumped whenever its dynamics, observation, reward or
    /// termination change so that published results stay comparable; Gymnasium ids are
    /// `carl_spec/<id>-v<version>`.
    #[serde(default)]
    pub version: u32,
    /// What steps the environment, e.g. `physics2d`, `rapier3d`, `articulated`, `closed-form`;
    /// absent for a spec without a runtime.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(length(min = 1))]
    pub engine: Option<String>,
    /// One or two sentences: what the task is and what the context changes.
    pub description: String,
    pub observation_space: Space,
    pub action_space: Space,
    /// Episode limit in steps (truncation); `null` when the task has none.
    pub max_episode_steps: Option<u64>,
    /// Where the numbers come from (paper table, reference code), for readers and reviewers.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source: Option<String>,
    /// Shared feature blocks (fragments in `specs/shared/`) merged in before `features`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub include: Vec<Include>,
    /// The context features this spec defines itself, in order.
    #[serde(default)]
    pub features: Vec<RawFeature>,
    /// Named distributions over the context space.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub distributions: BTreeMap<String, RawDistribution>,
    /// Named regions of the context space (a box over continuous features) from which `split`
    /// instance sets derive train, interpolation and extrapolation sets.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub regions: BTreeMap<String, Region>,
    /// Named instance sets (train/test splits).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub instance_sets: BTreeMap<String, RawInstanceSet>,
}

/// A reusable block of features shared by several specs (`specs/shared/<name>.json`).
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema, PartialEq)]
#[serde(deny_unknown_fields)]
#[schemars(title = "carl-spec shared feature fragment")]
pub struct RawFragment {
    #[serde(rename = "$schema", default, skip_serializing_if = "Option::is_none")]
    pub schema: Option<String>,
    /// Name other specs use in `include`, snake_case.
    #[schemars(regex(pattern = r"^[a-z][a-z0-9_]*$"))]
    pub fragment: String,
    pub description: String,
    pub features: Vec<RawFeature>,
}

/// Either kind of spec document. Fragments are recognised by their `fragment` key.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema, PartialEq)]
#[serde(untagged)]
#[schemars(title = "carl-spec document")]
pub enum RawDocument {
    Environment(Box<RawEnvSpec>),
    Fragment(RawFragment),
}

#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Upstream {
    /// Library that provides the original environment, e.g. `gymnasium`, `brax`.
    pub library: String,
    /// The original environment's id, e.g. `CartPole-v1`.
    pub id: String,
    /// Version of the library the spec was checked against.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub version: Option<String>,
}

/// Pull a shared fragment's features into this spec.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Include {
    /// Name of the fragment (its `fragment` field).
    pub fragment: String,
    /// Features of the fragment to leave out.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub except: Vec<String>,
    /// Per-feature field overrides, e.g. `{"torso_mass": {"default": 10.0}}`.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub overrides: BTreeMap<String, FeaturePatch>,
}

/// Fields of an included feature that a spec may change.
#[derive(Debug, Clone, Default, Serialize, Deserialize, JsonSchema, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FeaturePatch {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub default: Option<Value>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bounds: Option<Bounds>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub affects: Option<Vec<Effect>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unit: Option<String>,
}

/// A context feature.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RawFeature {
    /// Canonical name (the CARL paper's spelling): letters, digits and underscores, starting with a
    /// letter, at most 64 characters (names become `--context` keys and column headers).
    #[schemars(regex(pattern = r"^[A-Za-z][A-Za-z0-9_]{0,63}$"))]
    pub name: String,
    /// Other names accepted on input, e.g. the newer carl-bench spelling (same pattern as `name`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    #[schemars(inner(regex(pattern = r"^[A-Za-z][A-Za-z0-9_]{0,63}$")))]
    pub aliases: Vec<String>,
    #[serde(rename = "type")]
    pub kind: FeatureType,
    /// Default value. Omit only with `default_from`, for defaults that are computed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub default: Option<Value>,
    /// How a computed default is derived, e.g. `f(dataset)`; only when `default` is absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub default_from: Option<String>,
    /// Inclusive `[lower, upper]`; `null` for an open side (JSON has no infinity).
    /// For `list_int` the bounds apply to every element. Not used by `bool` and `categorical`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bounds: Option<Bounds>,
    /// The allowed values of a `categorical` feature.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub choices: Option<Vec<Scalar>>,
    /// Human-readable names of the choices, same length and order as `choices`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub choice_labels: Option<Vec<String>>,
    /// Physical unit (SI where possible), e.g. `m/s^2`, `kg`, `s`. Omit for dimensionless.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unit: Option<String>,
    /// One line: what the feature is.
    pub description: String,
    /// What changing the feature changes. Verified by `carl-spec audit` where a runtime exists.
    pub affects: Vec<Effect>,
    /// The boolean environment option (e.g. `goal`) without which the feature does not act.
    /// `make` refuses a value other than the default while the option is off (naming it), and
    /// `carl-spec audit` audits the feature with the option set.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(regex(pattern = r"^[a-z][a-z0-9_]{0,63}$"))]
    pub requires_option: Option<String>,
}

/// `[lower, upper]`, each side a number or `null` (unbounded).
pub type Bounds = [Option<f64>; 2];

#[derive(Debug, Clone, Copy, Serialize, Deserialize, JsonSchema, PartialEq, Eq, Hash)]
#[serde(rename_all = "snake_case")]
pub enum FeatureType {
    Float,
    Int,
    Bool,
    Categorical,
    ListInt,
}

#[derive(Debug, Clone, Copy, Serialize, Deserialize, JsonSchema, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[serde(rename_all = "snake_case")]
pub enum Effect {
    Dynamics,
    Reward,
    Termination,
    InitialState,
    Observation,
    TaskGeneration,
}

impl Effect {
    pub const ALL: [Effect; 6] = [
        Effect::Dynamics,
        Effect::Reward,
        Effect::Termination,
        Effect::InitialState,
        Effect::Observation,
        Effect::TaskGeneration,
    ];
    pub fn as_str(self) -> &'static str {
        match self {
            Effect::Dynamics => "dynamics",
            Effect::Reward => "reward",
            Effect::Termination => "termination",
            Effect::InitialState => "initial_state",
            Effect::Observation => "observation",
            Effect::TaskGeneration => "task_generation",
        }
    }
}

/// A scalar value: number, string or bool.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema, PartialEq)]
#[serde(untagged)]
pub enum Scalar {
    Bool(bool),
    Number(f64),
    String(String),
}

/// A feature value: a scalar or a list of integers (`list_int`).
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema, PartialEq)]
#[serde(untagged)]
pub enum Value {
    Bool(bool),
    Number(f64),
    String(String),
    List(Vec<f64>),
}

/// Observation or action space, with Gymnasium's meaning.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema, PartialEq)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum Space {
    /// `Box(low, high, shape, dtype)`; `low`/`high` are one number for every element or one per element,
    /// `null` for unbounded.
    Box {
        shape: Vec<u64>,
        low: BoxLimit,
        high: BoxLimit,
        dtype: Dtype,
    },
    /// `Discrete(n)`: actions `0..n`.
    Discrete { n: u64 },
    /// `MultiDiscrete(nvec)`.
    MultiDiscrete { nvec: Vec<u64> },
    /// A space carl-spec does not model in detail (e.g. a dict of images and text); say what it is.
    Other { description: String },
}

#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema, PartialEq)]
#[serde(untagged)]
pub enum BoxLimit {
    Uniform(Option<f64>),
    PerElement(Vec<Option<f64>>),
}

#[derive(Debug, Clone, Copy, Serialize, Deserialize, JsonSchema, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Dtype {
    Float32,
    Float64,
    Int64,
    Uint8,
}

/// What a sampler does with a draw outside the feature's bounds.
#[derive(Debug, Clone, Copy, Serialize, Deserialize, JsonSchema, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum AtBounds {
    /// Clamp to the nearest bound.
    Clip,
    /// Draw again (up to a fixed number of tries, then fail): the distribution truncated to the bounds.
    Resample,
    /// Fail with an error naming the instance and value.
    Reject,
}

/// A named distribution: each listed feature gets its own sampler; the others stay at their default.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RawDistribution {
    pub description: String,
    /// What happens to a draw outside a feature's bounds. Required: never silently out of bounds.
    pub at_bounds: AtBounds,
    /// Per-feature samplers, keyed by feature name.
    pub features: BTreeMap<String, Sampler>,
}

#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema, PartialEq)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Sampler {
    /// Always the same value.
    Constant { value: Value },
    /// N(mean, std).
    Normal { mean: f64, std: f64 },
    /// The paper's N(default, sigma_rel * |default|); when the default is 0 the std is `fallback_std`.
    RelativeNormal {
        sigma_rel: f64,
        #[serde(default = "default_fallback_std")]
        fallback_std: f64,
    },
    /// N(mean, std) truncated to [low, high] (exact inverse-CDF-free rejection from the normal).
    TruncatedNormal { mean: f64, std: f64, low: f64, high: f64 },
    /// U[low, high).
    Uniform { low: f64, high: f64 },
    /// exp(U[ln low, ln high)); both positive.
    LogUniform { low: f64, high: f64 },
    /// Integers uniform on [low, high], both inclusive.
    IntUniform { low: i64, high: i64 },
    /// One of `choices` (default: the feature's choices), with optional relative weights.
    Categorical {
        #[serde(default, skip_serializing_if = "Option::is_none")]
        choices: Option<Vec<Scalar>>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        weights: Option<Vec<f64>>,
    },
    /// Uniform on a union of intervals; an interval is picked by `weights` (default: equal), or with
    /// `stratified` the first n/k draws come from the first interval, the next n/k from the second, ...
    IntervalMixture {
        intervals: Vec<[f64; 2]>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        weights: Option<Vec<f64>>,
        #[serde(default)]
        stratified: bool,
    },
}

fn default_fallback_std() -> f64 {
    0.1
}

/// A named instance set: sampled from a distribution, listed explicitly, or a regular grid.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RawInstanceSet {
    pub description: String,
    /// `train` or `test` (free text allowed, e.g. `test_ood`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub role: Option<String>,
    /// Permit explicit or grid values outside the features' bounds (deliberate out-of-distribution tests).
    #[serde(default)]
    pub allow_out_of_bounds: bool,
    /// `size` draws from a named distribution with a seed. Exactly one of `sampled`, `explicit`, `grid`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sampled: Option<SampledSet>,
    /// Contexts written out by hand.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub explicit: Option<Vec<ExplicitInstance>>,
    /// `from, from+step, ...` up to `to` (inclusive) for one feature.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grid: Option<GridSet>,
    /// Derived from a named region: its training points, or test points between them
    /// (interpolation) or beyond it (extrapolation), one feature at a time or jointly.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub split: Option<SplitSet>,
}

/// A box over continuous features: the training region of a generalization protocol.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Region {
    pub description: String,
    /// Feature name -> `[low, high]`, inside the feature's bounds, with low < high.
    pub features: BTreeMap<String, [f64; 2]>,
}

/// Which points of a region a `split` set holds.
#[derive(Debug, Clone, Copy, Serialize, Deserialize, JsonSchema, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum SplitKind {
    /// Inside the region: its grid points (edges included) or uniform draws.
    Train,
    /// Inside the region, between the training grid's points (the cell centres, or the midpoints
    /// along each feature when one factor varies), or fresh uniform draws.
    Interpolation,
    /// Beyond the region: each feature `distance × width` below its low or above its high edge.
    Extrapolation,
}

/// Whether the features of a region vary one at a time or jointly.
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize, JsonSchema, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Factors {
    /// Every point moves all the region's features (the grid's product; every side of every corner).
    #[default]
    Combinatorial,
    /// Every point moves one feature; the others keep their defaults (which must lie in the region).
    Single,
}

/// A set derived from a region (Kirk et al.'s evaluation protocols; CARL's TMLR paper).
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SplitSet {
    /// The region's name (under `regions`).
    pub region: String,
    pub kind: SplitKind,
    #[serde(default)]
    pub factors: Factors,
    /// `train` and `interpolation`: points per feature of the training grid (≥ 2).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grid: Option<u32>,
    /// `train` and `interpolation`: uniform draws in the region instead of a grid (per feature
    /// when one factor varies).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sampled: Option<SplitSample>,
    /// `extrapolation`: how far beyond the region, in multiples of each feature's width (> 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub distances: Option<Vec<f64>>,
}

#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SplitSample {
    pub size: u64,
    pub seed: u64,
}

#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SampledSet {
    pub distribution: String,
    pub size: u64,
    pub seed: u64,
}

#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct GridSet {
    pub feature: String,
    pub from: f64,
    pub to: f64,
    pub step: f64,
}

#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ExplicitInstance {
    /// Instance name, e.g. `Mars`.
    pub name: String,
    /// Feature values; unnamed features stay at their default.
    pub context: BTreeMap<String, Value>,
    /// Label relative to the training distribution, as the paper uses it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub split: Option<Split>,
}

#[derive(Debug, Clone, Copy, Serialize, Deserialize, JsonSchema, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Split {
    InDistribution,
    OutOfDistribution,
}
