//! The spec language: raw documents as written (`raw`), the resolved model (`model`),
//! and loading/resolution of a set of spec files (`load`).

pub mod model;
pub mod raw;

pub use model::{EnvSpec, Feature};
