//! carl-spec-core's integration tests, one harness (one binary to link): the spec language,
//! the validator and its corpus, sampling golden vectors, split kinds, the schema snapshot.

mod bundled_specs;
mod fragments;
mod paper_tables;
mod sampling_golden;
mod schema_snapshot;
mod split_kinds;
mod validate_corpus;
mod validate_robustness;
