//! The spec language: raw documents as written (`raw`), the resolved model (`model`),
//! resolution of includes (`resolve`) and loading of spec sets (`load`).

pub mod load;
pub mod model;
pub mod raw;
pub mod resolve;

pub use load::{LoadError, SpecSet, grid_points};
pub use model::{EnvSpec, Feature};
