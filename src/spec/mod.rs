//! The spec language: raw documents as written (`raw`) and the resolved model (`model`).

pub mod raw;
