//! Gymnasium 1.4 classic-control environments with explicit contexts.
//!
//! Every environment holds its context as a plain `Params` value (Gymnasium defaults via
//! `Default`), reads it at step time and derives dependent quantities from it there, so a
//! changed parameter always takes full effect. The arithmetic follows Gymnasium's Python/NumPy
//! code operation by operation (including where NumPy 2 keeps float32), so trajectories are
//! bit-identical to Gymnasium on the same machine; see the crate's `tests/integration/parity.rs`.

pub mod acrobot;
pub mod cartpole;
pub mod mountain_car;
pub mod mountain_car_continuous;
pub mod pendulum;
mod registry;

pub use acrobot::{Acrobot, AcrobotParams, Dynamics};
pub use cartpole::{CartPole, CartPoleParams};
pub use mountain_car::{MountainCar, MountainCarParams, StartDistribution};
pub use mountain_car_continuous::{MountainCarContinuous, MountainCarContinuousParams};
pub use pendulum::{Pendulum, PendulumParams};
pub use registry::REGISTRATIONS;
