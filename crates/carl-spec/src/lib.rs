//! carl-spec: the CARL contextual-RL benchmark as declarative, verifiable specs, reproducible
//! instance sets and Rust environments. This crate is the CARL layer over the workspace's
//! lower crates and the `carl-spec` command.
//!
//! Below it (re-exported under their module names so `carl_spec::spec`, `carl_spec::envs::api`,
//! … name each concept once): the spec core [`carl_spec_core`] (`text`, `suggest`,
//! `diagnostics`, `json`, `spec`, `schema`, `validate`, `sampling`, `instances`, `input`, `output`), the
//! drawing layer [`pixels`], the 2-D engine [`physics2d`], the environment API and the
//! families ([`envs`]).
//!
//! Without the default `envs` feature, only the spec tooling is built (no physics).
//!
//! Here: [`envs`] (the registry of every family, CARL's contextual wrapper, `VecEnv`),
//! [`episode`] (one episode loop, the JSON Lines protocol), [`evaluation`] (a policy on every
//! instance of a set, the engine of `carl-spec evaluate`), [`bench`] (speed measurements),
//! [`audit`] (checks each feature's `affects` claim against the runtime), [`plot`] (figures of
//! instance sets), [`render`] (environment pictures to files), [`experiments`] (the paper's
//! experiments end to end), [`cli`] (argument parsing and printing, one module per subcommand).

#[cfg(feature = "envs")]
pub use carl_physics2d as physics2d;
pub use carl_pixels as pixels;
pub use carl_spec_core::{
    diagnostics, input, instances, json, output, sampling, schema, spec, suggest, text, validate,
};

pub mod cli;
pub mod plot;

#[cfg(feature = "envs")]
pub mod audit;
#[cfg(feature = "envs")]
pub mod bench;
#[cfg(feature = "envs")]
pub mod envs;
#[cfg(feature = "envs")]
pub mod episode;
#[cfg(feature = "envs")]
pub mod evaluation;
#[cfg(feature = "envs")]
pub mod experiments;
#[cfg(feature = "envs")]
pub mod render;
