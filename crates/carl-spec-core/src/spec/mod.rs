//! The spec language: raw documents as written (`raw`), the resolved model (`model`),
//! resolution of includes (`resolve`), loading of spec sets (`load`) and counts over them (`stats`).

pub mod load;
pub mod model;
pub mod raw;
pub mod resolve;
pub mod stats;

pub use load::{LoadError, SpecSet, grid_points};
pub use model::{EnvSpec, Feature};
