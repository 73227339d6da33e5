//! Sampling a whole instance set: one independent stream per feature.

use super::error::SamplingError;
use super::feature::{FeatureInfo, FeatureSampler};
use super::pcg64::Pcg64;
use crate::spec::raw::{AtBounds, Sampler, Value};

/// FNV-1a 64 (offset basis 0xcbf29ce484222325, prime 0x100000001b3), fed bytes in pieces.
#[derive(Debug, Clone, Copy)]
pub struct Fnv1a64(u64);

impl Default for Fnv1a64 {
    fn default() -> Self {
        Fnv1a64(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv1a64 {
    pub fn new() -> Self {
        Self::default()
    }

    pub fn update(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    pub fn finish(self) -> u64 {
        self.0
    }
}

/// Stream of a feature: [`Fnv1a64`] of its canonical name's UTF-8 bytes. Keyed by name, not
/// position, so adding or reordering features never changes the other features' values.
pub fn stream_id(feature_name: &str) -> u64 {
    let mut h = Fnv1a64::new();
    h.update(feature_name.as_bytes());
    h.finish()
}

/// The generator feature `feature_name` draws from in a set with `seed`.
pub fn feature_rng(seed: u64, feature_name: &str) -> Pcg64 {
    Pcg64::new(seed, stream_id(feature_name))
}

impl FeatureSampler {
    /// All `n` values of this feature for a set with `seed`, in instance order.
    pub fn sample_column(&self, seed: u64, n: usize) -> Result<Vec<Value>, SamplingError> {
        let mut rng = feature_rng(seed, self.feature_name());
        (0..n).map(|i| self.sample(&mut rng, i, n)).collect()
    }
}

/// `n` contexts: row `i` holds instance `i`'s values, in the order of `features`. Every sampler
/// is compiled (and so checked) before anything is drawn; a feature listed twice is an error.
pub fn sample_contexts(
    seed: u64,
    n: usize,
    features: &[(FeatureInfo, &Sampler)],
    at_bounds: AtBounds,
) -> Result<Vec<Vec<Value>>, SamplingError> {
    let mut compiled = Vec::with_capacity(features.len());
    for (k, (info, sampler)) in features.iter().enumerate() {
        if features[..k].iter().any(|(other, _)| other.name == info.name) {
            return Err(SamplingError::DuplicateFeature {
                feature: info.name.clone(),
            });
        }
        compiled.push(FeatureSampler::compile(sampler, info.clone(), at_bounds)?);
    }
    let mut rows: Vec<Vec<Value>> = (0..n).map(|_| Vec::with_capacity(compiled.len())).collect();
    for fs in &compiled {
        for (row, v) in rows.iter_mut().zip(fs.sample_column(seed, n)?) {
            row.push(v);
        }
    }
    Ok(rows)
}
