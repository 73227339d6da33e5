//! Environment runtimes.
//!
//! * [`api`]: the Gymnasium-style [`Env`] trait, spaces, actions, errors and [`TimeLimit`].
//! * [`rng`]: the small deterministic stream used by `reset` (swappable).
//! * [`vec_env`]: [`VecEnv`](vec_env::VecEnv), N environments with their own contexts stepped as a
//!   batch (auto-reset, structure-of-arrays CartPole kernel, multi-threaded).
//! * [`classic`]: CartPole, Pendulum, MountainCar, MountainCarContinuous and Acrobot with
//!   Gymnasium 1.4 dynamics, parameterised by an explicit context (`Params`) value.
//! * [`registry`]: the environment table (every runtime declared once) and `make`.
//! * [`context`]: a context and variant options checked against the spec and the table.
//! * [`runtime`]: [`AnyEnv`], any runtime behind one type.
//! * [`policy`]: who acts (random, no-op, the table's hand-written controllers).
//! * [`contextual`]: CARL's contextual wrapper (instance selection, context in observation/info).
//!   Its vocabulary (sources, selection, visibility, noise, errors) is [`contextual_options`]; its
//!   per-reset rules (which instance, which seeds) are [`context_schedule`].
//! * [`box2d`]: LunarLander and BipedalWalker on [`crate::physics2d`] (Box2D 2.3's semantics),
//!   CarRacing on its own Box2D-style rigid bodies; each instance owns its physics world.
//! * [`rna_design`]: LEARNA's RNA design task on carl-rna's folding (crates/carl-rna).
//! * [`robots`]: articulated robots from URDF on rapier3d (Ant, HalfCheetah).

pub mod api;
pub mod box2d;
pub mod classic;
pub mod context;
pub mod context_schedule;
pub mod contextual;
pub mod contextual_options;
pub mod mario;
pub mod policy;
mod pool;
pub mod registry;
pub mod rna_design;
pub mod rng;
pub mod robots;
pub mod runtime;
pub mod vec_env;

pub use api::{Action, DType, Env, EnvError, Info, Space, Step, StepOutcome, TimeLimit, UnknownFeature};
pub use contextual::{
    ContextInfo, ContextSource, ContextualEnv, ContextualError, ContextualOptions, Features, Selection, Visibility,
};
pub use policy::{Policy, PolicyKind};
pub use registry::{REGISTRY, Registration};
pub use runtime::{AnyEnv, Runtime};
