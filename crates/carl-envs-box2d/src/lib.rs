//! Box2D-family environments, simulated with Box2D 2.3's semantics in Rust (no Box2D code).
//!
//! * [`lunar_lander`]: Gymnasium's `LunarLander-v3` (discrete and continuous) with all of
//!   CARL's 16 context features, each instance owning its own physics world: free flight in
//!   closed form, [`carl_physics2d`] near the ground.
//! * [`heuristic`](mod@heuristic): Gymnasium's hand-written landing controller (same control law).
//! * [`bipedal_walker`]: Gymnasium's `BipedalWalker-v3` (and the hardcore terrain) with all of
//!   CARL's 20 context features on [`carl_physics2d`], plus Gymnasium's scripted gait
//!   ([`WalkerHeuristic`]).
//! * [`vehicle_racing`]: Gymnasium's `CarRacing-v3` with CARL's 29 vehicles (pixel observations
//!   drawn in software; its rigid-body physics is plain Rust, see its module docs).
//!
//! The solver follows Box2D 2.3 but computes in `f64` (Box2D: `f32`), so trajectories are not
//! bit-identical to Gymnasium's; the geometry, masses, joints, engine impulses, observation,
//! reward and termination rules are the same, and the deviations that remain are listed in
//! each environment's module docs.

pub mod bipedal_walker;
pub mod heuristic;
pub mod lunar_lander;
mod registry;
pub mod vehicle_racing;

pub use bipedal_walker::{BipedalWalker, BipedalWalkerOptions, BipedalWalkerParams, WalkerHeuristic};
pub use heuristic::{heuristic, heuristic_continuous};
pub use lunar_lander::{LunarLander, LunarLanderOptions, LunarLanderParams, Outcome};
pub use registry::REGISTRATIONS;
pub use vehicle_racing::{VehicleRacing, VehicleRacingOptions, VehicleRacingParams};

/// The physics behind LunarLander and BipedalWalker (VehicleRacing has its own, see its module
/// docs), recorded in results files: changing it can change every trajectory. The solver is part
/// of this crate, so the crate version identifies it.
pub const PHYSICS_ENGINE: &str = concat!(
    "carl-spec ",
    env!("CARGO_PKG_VERSION"),
    " physics2d (Box2D 2.3 semantics: sequential impulses, Step(1/FPS, 6*30, 2*30), continuous ",
    "collision; f64); LunarLander's free flight in closed form"
);
