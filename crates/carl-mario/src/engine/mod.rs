//! The clean-room platformer engine (engine_behaviour.md): level parsing, the world and its tick.

pub mod level;
pub mod world;

pub use level::Level;
pub use world::{Buttons, Event, Status, World};
