//! Instance sets: derived from a spec (sampled, explicit or grid), frozen to files with their
//! provenance and a content hash, loaded by name (`env/set`) and verified.
//!
//! * [`derive`](mod@derive): compute a set from its definition (the only place values are produced).
//! * [`frozen`]: the frozen file format, hashing and atomic writes.
//! * [`store`]: where frozen files live (bundled in the binary or an author's directory), loading
//!   by name, freezing and verification.

pub mod derive;
pub mod frozen;
pub mod store;

pub use derive::{DeriveError, derive_set, sample_adhoc};
pub use frozen::{FORMAT, FrozenSet, Instance, Provenance};
pub use store::{Store, StoreError, VerifyProblem};
