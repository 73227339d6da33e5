//! Environments: the environment API and the families, joined in one registry, with CARL's
//! contextual wrapper and the vector environment on top.
//!
//! * [`api`], [`runtime`], [`context`], [`policy`], [`rng`]: the environment API
//!   ([`carl_env`]), re-exported here.
//! * The families, one crate each, each registering its own environments:
//!   [`classic_control`], [`box2d`], [`brax`], [`dmc`], [`rna_design`], [`mario`].
//! * [`registry`]: the families' registrations in one table, and `make`.
//! * [`contextual`]: CARL's contextual wrapper (instance selection, context in observation/info).
//!   Its vocabulary (sources, selection, visibility, noise, errors) is [`contextual_options`]; its
//!   per-reset rules (which instance, which seeds) are [`context_schedule`]; features that change
//!   within an episode are [`schedules`].
//! * [`vec_env`]: [`VecEnv`](vec_env::VecEnv), N environments with their own contexts stepped as a
//!   batch (auto-reset, structure-of-arrays CartPole kernel, multi-threaded).

pub use carl_env::{api, cancel, context, policy, rng, runtime};
pub use carl_envs_box2d as box2d;
pub use carl_envs_brax as brax;
pub use carl_envs_classic_control as classic_control;
pub use carl_envs_dmc as dmc;
pub use carl_envs_mario as mario;
pub use carl_envs_rna_design as rna_design;

pub mod context_schedule;
pub mod contextual;
pub mod contextual_options;
mod pool;
pub mod registry;
pub mod schedules;
pub mod vec_env;

pub use api::{Action, DType, Env, EnvError, Info, Space, Step, StepOutcome, TimeLimit, UnknownFeature};
pub use contextual::{
    ContextInfo, ContextSource, ContextualEnv, ContextualError, ContextualOptions, Features, Selection, Visibility,
};
pub use policy::{Policy, PolicyKind};
pub use registry::{REGISTRY, Registration};
pub use runtime::{AnyEnv, Runtime};
