//! carl-spec: the CARL contextual-RL benchmark as declarative, verifiable specs,
//! reproducible instance sets and Rust environments.
//!
//! Layout: `spec` (the spec language and loading), `validate` (schema + semantic rules +
//! diagnostics), `json` (JSON with source positions), `schema` (the generated JSON Schema),
//! `sampling` (portable generator and samplers), `envs` (environment runtimes), `audit` (checks
//! that each feature's `affects` claim matches the runtime), `cli`.
//! `sampling` (portable generator and samplers), `envs` (environment runtimes), `plot` (figures of
//! instance sets), `cli`.

pub mod audit;
pub mod cli;
pub mod envs;
pub mod experiments;
pub mod instances;
pub mod json;
pub mod plot;
pub mod sampling;
pub mod schema;
pub mod spec;
pub mod suggest;
pub mod validate;
