//! Box2D-family environments, simulated with rapier2d instead of Box2D.
//!
//! * [`lunar_lander`]: Gymnasium's `LunarLander-v3` (discrete and continuous) with all of
//!   CARL's 16 context features, each instance owning its own physics world.
//! * [`heuristic`]: Gymnasium's hand-written landing controller (same control law).
//! * [`bipedal_walker`]: Gymnasium's `BipedalWalker-v3` (and the hardcore terrain) with all of
//!   CARL's 20 context features, plus Gymnasium's scripted gait ([`WalkerHeuristic`]).
//! * [`vehicle_racing`]: Gymnasium's `CarRacing-v3` with CARL's 29 vehicles (pixel observations
//!   drawn in software; its rigid-body physics is plain Rust, see its module docs).
//!
//! Physics is not Box2D, so trajectories are not bit-identical to Gymnasium; the geometry,
//! masses, joints, engine impulses, observation, reward and termination rules are the same,
//! and the deviations that remain are listed in [`lunar_lander`]'s module docs.

pub mod bipedal_walker;
pub mod heuristic;
pub mod lunar_lander;
pub mod vehicle_racing;

pub use bipedal_walker::{BipedalWalker, BipedalWalkerOptions, BipedalWalkerParams, WalkerHeuristic};
pub use heuristic::{heuristic, heuristic_continuous};
pub use lunar_lander::{LunarLander, LunarLanderOptions, LunarLanderParams, Outcome};
pub use vehicle_racing::{VehicleRacing, VehicleRacingOptions, VehicleRacingParams};

/// The physics engine behind these environments, pinned exactly in `Cargo.toml`. Recorded in
/// results files: changing it can change every trajectory.
pub const PHYSICS_ENGINE: &str = "rapier2d =0.36.1 (features: enhanced-determinism; f32, dim2)";
