//! Environment runtimes.
//!
//! * [`api`]: the Gymnasium-style [`Env`] trait, spaces, actions, errors and [`TimeLimit`].
//! * [`rng`]: the small deterministic stream used by `reset` (swappable).
//! * [`classic`]: CartPole, Pendulum, MountainCar, MountainCarContinuous and Acrobot with
//!   Gymnasium 1.4 dynamics, parameterised by an explicit context (`Params`) value.
//! * [`box2d`]: LunarLander on rapier2d (each instance owns its physics world).

pub mod api;
pub mod box2d;
pub mod classic;
pub mod registry;
pub mod rng;

pub use api::{Action, DType, Env, EnvError, Info, Space, Step, StepOutcome, TimeLimit, UnknownFeature};
