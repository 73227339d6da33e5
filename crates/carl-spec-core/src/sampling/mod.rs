//! Portable, reproducible sampling of context features.
//!
//! * [`pcg64`]: the generator (NumPy's PCG64 bit stream, our documented seeding).
//! * [`dist`]: primitive draws (normal, truncated normal, uniform, integers, weighted index),
//!   maths through `libm` only so the bits do not depend on platform or build.
//! * [`feature`]: a spec [`Sampler`](crate::spec::raw::Sampler) compiled against one feature,
//!   enforcing type and bounds.
//! * [`set`]: whole instance sets, one stream per feature keyed by the feature's name.
//!
//! Anything that changes output bits must bump [`SAMPLER_VERSION`]; frozen instance files record
//! it together with [`GENERATOR`].

pub mod dist;
pub mod error;
pub mod feature;
pub mod pcg64;
pub mod set;

pub use error::SamplingError;
pub use feature::{FeatureInfo, FeatureSampler, MAX_RESAMPLE_TRIES, MAX_TRUNCATION_TRIES};
pub use pcg64::Pcg64;
pub use set::{Fnv1a64, feature_rng, sample_contexts, stream_id};

/// Version of the sampling algorithms; bump whenever any sampler's output bits change.
pub const SAMPLER_VERSION: &str = "carl-spec-sampling/1";
/// The bit generator and its seeding, as recorded in frozen files.
pub const GENERATOR: &str = "pcg64-xslrr128/64+splitmix64-seed+fnv1a64-stream";
