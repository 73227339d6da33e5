//! Deterministic per-environment random stream used by `reset` (and Acrobot's torque noise).
//!
//! This is a deliberately tiny, self-contained generator (SplitMix64) placed behind two
//! functions, [`uniform`] and [`normal`], so it can later be swapped for the crate's portable
//! PCG64 without touching the environments. It is *not* NumPy's generator: initial states
//! drawn by `reset(Some(seed))` are reproducible across runs and platforms of this crate, but
//! they are not the states Gymnasium would draw for the same seed.

/// SplitMix64 stream. Seeding is `state = seed`; the output function is Steele/Lea/Flood's.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EnvRng {
    state: u64,
}

/// Seed used when an environment is reset without ever having been seeded.
pub const DEFAULT_SEED: u64 = 0;

impl EnvRng {
    pub fn from_seed(seed: u64) -> Self {
        EnvRng { state: seed }
    }

    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform double in `[0, 1)` with 53 random bits (same construction as NumPy's `random()`).
    #[inline]
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / 9_007_199_254_740_992.0)
    }
}

impl Default for EnvRng {
    fn default() -> Self {
        EnvRng::from_seed(DEFAULT_SEED)
    }
}

/// `low + (high - low) * U[0,1)`, the formula NumPy's `Generator.uniform` uses.
#[inline]
pub fn uniform(rng: &mut EnvRng, low: f64, high: f64) -> f64 {
    low + (high - low) * rng.next_f64()
}

/// Gaussian sample (Box–Muller, one value per call). `std == 0` returns `mean` exactly.
pub fn normal(rng: &mut EnvRng, mean: f64, std: f64) -> f64 {
    // 1 - U[0,1) is in (0, 1], so the log is finite.
    let u1 = 1.0 - rng.next_f64();
    let u2 = rng.next_f64();
    let z = (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos();
    if std == 0.0 { mean } else { mean + std * z }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reproducible_and_in_range() {
        let mut a = EnvRng::from_seed(42);
        let mut b = EnvRng::from_seed(42);
        for _ in 0..1000 {
            let x = uniform(&mut a, -0.05, 0.05);
            assert_eq!(x.to_bits(), uniform(&mut b, -0.05, 0.05).to_bits());
            assert!((-0.05..0.05).contains(&x));
        }
        assert_ne!(EnvRng::from_seed(1).next_u64(), EnvRng::from_seed(2).next_u64());
    }
}
