//! carl-spec: the CARL contextual-RL benchmark as declarative, verifiable specs,
//! reproducible instance sets and Rust environments.
//!
//! Layout: `spec` (the spec language), `validate` (schema + semantic rules + diagnostics),
//! `sampling` (portable RNG and samplers), `instances` (instance sets, freeze/load),
//! `envs` (runtimes), `cli` (the `carl-spec` command).

pub mod sampling;
pub mod spec;
