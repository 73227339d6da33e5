//! Environment runtimes.
//!
//! * [`api`]: the Gymnasium-style [`Env`] trait, spaces, actions, errors and [`TimeLimit`].
//! * [`rng`]: the small deterministic stream used by `reset` (swappable).
//! * [`classic`]: CartPole, Pendulum, MountainCar, MountainCarContinuous and Acrobot with
//!   Gymnasium 1.4 dynamics, parameterised by an explicit context (`Params`) value.

pub mod api;
pub mod classic;
pub mod registry;
pub mod rng;

pub use api::{Action, DType, Env, EnvError, Info, Space, Step, StepOutcome, TimeLimit, UnknownFeature};
