//! Deterministic per-environment random stream used by `reset` (and Acrobot's torque noise).
//!
//! The stream is **NumPy's**: `EnvRng::from_seed(s)` is bit for bit the generator Gymnasium's
//! `env.np_random` becomes after `reset(seed=s)` (`np.random.Generator(PCG64(SeedSequence(s)))`),
//! and [`uniform`] is `Generator.uniform`'s formula on it. So a classic-control environment reset
//! with the same seed starts from the same state as Gymnasium's (CartPole's
//! `uniform(-0.05, 0.05, size=4)` draws four doubles in a row; `tests/parity.rs` checks the states
//! against Gymnasium's own). [`normal`] is our Box–Muller, not NumPy's ziggurat (no classic
//! environment draws normals under its default context).
//!
//! `SeedSequence` (NumPy's entropy pool: four 32-bit words, the hash/mix constants of O'Neill's
//! `seed_seq_fe`) is written here from NumPy's documented algorithm; `scripts/pcg64_known_answers.py`
//! prints the vectors pinned in the tests below from NumPy itself.

use carl_spec_core::sampling::Pcg64;
use carl_spec_core::sampling::pcg64::MULTIPLIER;

/// NumPy's `SeedSequence` pool size (32-bit words).
const POOL_SIZE: usize = 4;
const INIT_A: u32 = 0x43b0_d7e5;
const MULT_A: u32 = 0x931e_8875;
const INIT_B: u32 = 0x8b51_f9dd;
const MULT_B: u32 = 0x58f3_8ded;
const MIX_MULT_L: u32 = 0xca01_f9dd;
const MIX_MULT_R: u32 = 0x4973_f715;
const XSHIFT: u32 = 16;

fn hashmix(value: u32, hash_const: &mut u32) -> u32 {
    let mut v = value ^ *hash_const;
    *hash_const = hash_const.wrapping_mul(MULT_A);
    v = v.wrapping_mul(*hash_const);
    v ^ (v >> XSHIFT)
}

fn mix(x: u32, y: u32) -> u32 {
    let r = MIX_MULT_L.wrapping_mul(x).wrapping_sub(MIX_MULT_R.wrapping_mul(y));
    r ^ (r >> XSHIFT)
}

/// `np.random.SeedSequence(seed).generate_state(N, np.uint32)` for an integer seed
/// (allocation-free: resets must not allocate).
pub fn seed_sequence_words<const N: usize>(seed: u64) -> [u32; N] {
    // The seed as little-endian 32-bit words (0 is one zero word).
    let entropy = [seed as u32, (seed >> 32) as u32];
    let n_entropy = if seed >> 32 == 0 { 1 } else { 2 };
    let mut pool = [0u32; POOL_SIZE];
    let mut hc = INIT_A;
    for (i, slot) in pool.iter_mut().enumerate() {
        let word = if i < n_entropy { entropy[i] } else { 0 };
        *slot = hashmix(word, &mut hc);
    }
    for src in 0..POOL_SIZE {
        for dst in 0..POOL_SIZE {
            if src != dst {
                let h = hashmix(pool[src], &mut hc);
                pool[dst] = mix(pool[dst], h);
            }
        }
    }
    let mut hc = INIT_B;
    let mut out = [0u32; N];
    for (i, word) in out.iter_mut().enumerate() {
        let mut v = pool[i % POOL_SIZE] ^ hc;
        hc = hc.wrapping_mul(MULT_B);
        v = v.wrapping_mul(hc);
        *word = v ^ (v >> XSHIFT);
    }
    out
}

/// `np.random.PCG64(seed)`: the 128-bit seed and increment come from
/// `SeedSequence(seed).generate_state(4, np.uint64)` (words 0–1 and 2–3, high word first), then
/// PCG's standard `srandom` (NumPy's `pcg64_set_seed`).
pub fn numpy_pcg64(seed: u64) -> Pcg64 {
    let w: [u32; 8] = seed_sequence_words(seed);
    let u = |k: usize| u64::from(w[2 * k]) | (u64::from(w[2 * k + 1]) << 32);
    let initstate = (u128::from(u(0)) << 64) | u128::from(u(1));
    let initseq = (u128::from(u(2)) << 64) | u128::from(u(3));
    let inc = (initseq << 1) | 1;
    let state = inc.wrapping_add(initstate).wrapping_mul(MULTIPLIER).wrapping_add(inc);
    Pcg64::from_raw(state, inc)
}

/// An environment's random stream: NumPy's `Generator(PCG64(SeedSequence(seed)))`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EnvRng {
    pcg: Pcg64,
}

/// Seed used when an environment is reset without ever having been seeded.
pub const DEFAULT_SEED: u64 = 0;

impl EnvRng {
    pub fn from_seed(seed: u64) -> Self {
        EnvRng { pcg: numpy_pcg64(seed) }
    }

    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        self.pcg.next_u64()
    }

    /// Uniform double in `[0, 1)` with 53 random bits (NumPy's `Generator.random()`).
    #[inline]
    pub fn next_f64(&mut self) -> f64 {
        self.pcg.next_f64()
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

    /// From NumPy 2.4 (`scripts/numpy_seed_known_answers.py`).
    #[test]
    fn seed_sequence_and_pcg64_equal_numpy() {
        let words: &[(u64, [u32; 8])] = &[
            (
                0,
                [
                    0xb0f478be, 0xdb2cd7e7, 0x2c71ba49, 0xabf4641a, 0x9d7b8d41, 0x20c6ed6d, 0x223c39d4, 0x2c4099de,
                ],
            ),
            (
                42,
                [
                    0xcd540ab7, 0x9f1e2e6d, 0x79fb94b6, 0xd57873dc, 0x64d420b7, 0x7d282a1b, 0x4692d5ff, 0x33657971,
                ],
            ),
            (
                (1 << 32) + 7,
                [
                    0x16073898, 0x5c15e68f, 0xd1803233, 0x473d7918, 0xc4907c0f, 0xf3e9cae3, 0x099c820f, 0xdd958930,
                ],
            ),
            (
                u64::MAX,
                [
                    0x928cad0d, 0xaebca151, 0x8638dc7a, 0x119c3044, 0x59e642a7, 0x1bbb1556, 0xe8c4a8f6, 0xa76b11e3,
                ],
            ),
        ];
        for (seed, w) in words {
            assert_eq!(seed_sequence_words::<8>(*seed), *w, "seed {seed}");
        }
        let raw: &[(u64, [u64; 2])] = &[
            (0, [0xa30febcfd9c2825f, 0x4510bdf882d9d721]),
            (1, [0x8306bdf37922e4ff, 0xf35196bbc152a866]),
            (42, [0xc621fbcd16d92688, 0x705a5661a791ffc1]),
            (u64::MAX, [0xae163a7a8c47568f, 0xd86659f5f3382359]),
        ];
        for (seed, r) in raw {
            let mut g = numpy_pcg64(*seed);
            assert_eq!([g.next_u64(), g.next_u64()], *r, "seed {seed}");
        }
    }

    /// `np.random.default_rng(s).uniform(-0.05, 0.05, size=4)`: Gymnasium CartPole's reset state.
    #[test]
    fn uniform_equals_numpy_generator() {
        let cases: &[(u64, [f64; 4])] = &[
            (
                0,
                [
                    0.013696168732145436,
                    -0.02302132862361297,
                    -0.045902647606380534,
                    -0.04834723644714709,
                ],
            ),
            (
                42,
                [
                    0.027395604855596334,
                    -0.006112156024794771,
                    0.03585979199113824,
                    0.019736802905936393,
                ],
            ),
        ];
        for (seed, want) in cases {
            let mut rng = EnvRng::from_seed(*seed);
            let got: Vec<f64> = (0..4).map(|_| uniform(&mut rng, -0.05, 0.05)).collect();
            assert_eq!(got, want.to_vec(), "seed {seed}");
        }
    }

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
