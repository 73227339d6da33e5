//! The CARL spec language and everything a benchmark author's CI needs, without physics.
//!
//! * [`spec`]: the spec language (raw serde types, the resolved model, shared fragments, spec
//!   sets, the bundled specs).
//! * [`schema`]: the JSON Schema of spec files, generated from the Rust types.
//! * [`validate`]: schema and semantic rules; loads [`spec::SpecSet`]s with located diagnostics.
//! * [`diagnostics`]: the rule registry and located diagnostics with their text, JSON and GitHub
//!   renderings.
//! * [`json`]: a JSON parser that keeps source positions, JSON pointers, line/column mapping.
//! * [`sampling`]: the portable generator (PCG64) and samplers (libm only).
//! * [`instances`]: derive, freeze, load and verify instance sets.
//! * [`output`]: the one rule for writing output files; [`input`]: reading input with a size
//!   limit.
//! * [`text`] (quoting input into messages) and [`suggest`] ("did you mean").

pub mod diagnostics;
pub mod input;
pub mod instances;
pub mod json;
pub mod output;
pub mod sampling;
pub mod schema;
pub mod spec;
pub mod suggest;
pub mod text;
pub mod validate;
