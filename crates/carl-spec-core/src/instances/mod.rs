//! Instance sets: derived from a spec (sampled, explicit, grid or split from a region), frozen to files with their
//! provenance and a content hash, loaded by name (`env/set`) and verified.
//!
//! * [`derive`](mod@derive): compute a set from its definition (the only place values are produced).
//! * [`split`]: the points of a set derived from a region (train, interpolation, extrapolation).
//! * [`frozen`]: the frozen file format, hashing and atomic writes.
//! * [`store`]: where frozen files live (bundled in the binary or an author's directory), loading
//!   by name, freezing and verification.

pub mod derive;
pub mod frozen;
pub mod split;
pub mod store;

pub use derive::{DeriveError, derive_set, sample_adhoc};
pub use frozen::{FORMAT, FrozenSet, Instance, Provenance};
pub use store::{Store, StoreError, VerifyProblem};
