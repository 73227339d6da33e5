//! The environment API every carl-spec environment family implements.
//!
//! * [`api`]: the Gymnasium-style [`Env`] trait, spaces, actions, errors and [`TimeLimit`].
//! * [`runtime`]: [`Runtime`] and [`AnyEnv`], any environment behind one type.
//! * [`registration`]: what a family declares for each environment it registers (constructor,
//!   options, controller, cost, audit probes).
//! * [`context`]: a context and variant options checked against the environment's spec.
//! * [`policy`]: who acts (random, no-op, the registrations' hand-written controllers).
//! * [`rng`]: the small deterministic stream used by `reset`.
//! * [`cancel`]: a check installed around a call (Ctrl-C in Python) that long native loops poll.

pub mod api;
pub mod cancel;
pub mod context;
pub mod policy;
pub mod registration;
pub mod rng;
pub mod runtime;

pub use api::{Action, DType, Env, EnvError, Info, Space, Step, StepOutcome, TIMED_OUT, TimeLimit, UnknownFeature};
pub use registration::{AuditProfile, Registration, StepCost, VectorKernel};
pub use runtime::{AnyEnv, Runtime};
