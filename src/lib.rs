//! carl-spec: the CARL contextual-RL benchmark as declarative, verifiable specs,
//! reproducible instance sets and Rust environments.
//!
//! Layout: `text` (quoting input into messages), `diagnostics` (located diagnostics and the rule
//! registry), `spec` (the spec language and spec sets), `validate` (schema + semantic rules; loads
//! `SpecSet`s), `json` (JSON with source positions), `schema` (the generated JSON Schema),
//! `sampling` (portable generator and samplers), `instances` (derive, freeze, load, verify sets),
//! `envs` (the environment table, runtimes, policies, contextual wrapper, VecEnv), `episode` (one
//! episode loop, the JSON Lines protocol), `bench` (speed measurements), `audit` (checks each
//! feature's `affects` claim against the runtime), `plot` (figures of instance sets), `render`
//! (environment pictures to files), `physics2d` (a 2-D rigid-body engine with Box2D 2.3's
//! semantics: solver, joints, manifolds, GJK distance, time of impact; BipedalWalker runs on
//! it), `experiments` (the paper's experiments end to end), `cli`
//! (argument parsing and printing, one module per subcommand). Two low modules depend on nothing
//! above them: `pixels` (canvas, colours, font, PNG/GIF encoders; used by the environments'
//! renderers and by `plot`) and `output` (the one rule for writing output files).

pub mod audit;
pub mod bench;
pub mod cli;
pub mod diagnostics;
pub mod envs;
pub mod episode;
pub mod experiments;
pub mod instances;
pub mod json;
pub mod output;
pub mod physics2d;
pub mod pixels;
pub mod plot;
pub mod render;
pub mod sampling;
pub mod schema;
pub mod spec;
pub mod suggest;
pub mod text;
pub mod validate;
