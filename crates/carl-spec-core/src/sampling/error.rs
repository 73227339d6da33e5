//! Errors of the sampling core. Every message names the feature so spec authors can find it.

use thiserror::Error;

/// Why a sampler was refused; the validator reports each as its own rule.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SamplerProblem {
    /// A parameter is unusable (non-positive std, reversed interval, overflow, bad weights, …).
    Params,
    /// The sampler cannot produce the feature's type.
    Type,
    /// Nothing the sampler can draw lies inside the feature's bounds.
    Support,
}

#[derive(Debug, Clone, PartialEq, Error)]
pub enum SamplingError {
    /// The sampler's parameters are unusable for this feature (found by `FeatureSampler::compile`).
    #[error("feature `{feature}`: {kind} sampler: {message}")]
    InvalidSampler {
        feature: String,
        kind: &'static str,
        message: String,
        /// The parameter at fault, as a JSON pointer below the sampler (`std`, `intervals/1`);
        /// empty for the sampler as a whole.
        field: String,
        problem: SamplerProblem,
    },
    /// The feature itself cannot be sampled (bad bounds, missing default, ...).
    #[error("feature `{feature}`: {message}")]
    InvalidFeature { feature: String, message: String },
    /// `at_bounds = resample` gave up: the sampler puts (almost) no mass inside the bounds.
    #[error(
        "feature `{feature}`: no draw inside bounds {bounds} after {tries} tries (at_bounds = resample); \
         the sampler puts almost no probability inside the bounds"
    )]
    ResampleExhausted {
        feature: String,
        bounds: String,
        tries: u32,
    },
    /// `at_bounds = reject` and a draw fell outside the bounds.
    #[error("feature `{feature}`: instance {index}: drawn value {value} is {side} bound {bound} (at_bounds = reject)")]
    OutOfBounds {
        feature: String,
        index: usize,
        value: f64,
        side: &'static str,
        bound: f64,
    },
    /// The truncated-normal rejection loop hit its cap (should not happen with valid parameters).
    #[error("feature `{feature}`: truncated normal found no accepted draw in {tries} tries")]
    TruncationExhausted { feature: String, tries: u32 },
    /// A draw came out infinite or NaN (guard; compile-time checks should prevent it).
    #[error("feature `{feature}`: the draw {value} is not finite")]
    NonFiniteDraw { feature: String, value: f64 },
    /// A draw index outside `0..set_size`.
    #[error("feature `{feature}`: draw index {index} is not below the set size {set_size}")]
    IndexOutOfRange {
        feature: String,
        index: usize,
        set_size: usize,
    },
    /// The same feature twice in one set: both would read the same stream.
    #[error("feature `{feature}` is listed twice; each feature draws from its own stream")]
    DuplicateFeature { feature: String },
}
