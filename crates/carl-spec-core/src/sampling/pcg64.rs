//! PCG64 (PCG-XSL-RR 128/64), bit-for-bit the generator NumPy calls `PCG64`.
//!
//! State transition: `state = state * MULTIPLIER + inc (mod 2^128)`; output:
//! `rotr64(hi64(state) ^ lo64(state), state >> 122)`. Like NumPy, each draw advances first and
//! then outputs from the *new* state. `scripts/pcg64_known_answers.py` produces the known-answer
//! vectors pinned in the tests below from NumPy itself.
//!
//! Seeding is ours (NumPy seeds through `SeedSequence`, which we do not reproduce); see
//! [`Pcg64::new`] for the exact recipe.

/// The 128-bit LCG multiplier of PCG64 (and NumPy's `PCG64`).
pub const MULTIPLIER: u128 = 0x2360_ed05_1fc6_5da4_4385_df64_9fcc_f645;

/// SplitMix64 increment (the golden-ratio constant).
const SPLITMIX_GAMMA: u64 = 0x9e37_79b9_7f4a_7c15;

/// One step of SplitMix64: advances `x` and returns the mixed output.
pub fn splitmix64(x: &mut u64) -> u64 {
    *x = x.wrapping_add(SPLITMIX_GAMMA);
    let mut z = *x;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

fn join(hi: u64, lo: u64) -> u128 {
    (u128::from(hi) << 64) | u128::from(lo)
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Pcg64 {
    state: u128,
    inc: u128,
}

impl Pcg64 {
    /// Generator for `(seed, stream)`. Exact recipe (part of the frozen-file format):
    ///
    /// 1. SplitMix64 started at `seed` gives `s0, s1`; SplitMix64 started at `stream` gives
    ///    `t0, t1, t2, t3` (each value is one `splitmix64` call, in that order).
    /// 2. `initstate = (s0 << 64 | s1) ^ (t2 << 64 | t3)`, `initseq = t0 << 64 | t1`.
    /// 3. PCG's standard `srandom`: `inc = initseq << 1 | 1`, `state = 0`, step,
    ///    `state += initstate`, step (this is also what NumPy's `pcg64_set_seed` does).
    ///
    /// The stream enters both the increment and the state, so two streams of one seed share
    /// neither; hashing it first avoids PCG's weakness for increments differing in few bits.
    pub fn new(seed: u64, stream: u64) -> Self {
        let mut s = seed;
        let s0 = splitmix64(&mut s);
        let s1 = splitmix64(&mut s);
        let mut t = stream;
        let t0 = splitmix64(&mut t);
        let t1 = splitmix64(&mut t);
        let t2 = splitmix64(&mut t);
        let t3 = splitmix64(&mut t);
        let initstate = join(s0, s1) ^ join(t2, t3);
        let initseq = join(t0, t1);
        let mut rng = Pcg64 {
            state: 0,
            inc: (initseq << 1) | 1,
        };
        rng.step();
        rng.state = rng.state.wrapping_add(initstate);
        rng.step();
        rng
    }

    /// Generator with exactly this raw state, as in NumPy's `bit_generator.state["state"]`.
    /// PCG needs an odd increment, so the lowest bit of `inc` is forced to 1.
    pub fn from_raw(state: u128, inc: u128) -> Self {
        Pcg64 { state, inc: inc | 1 }
    }

    /// The raw `(state, inc)` pair, e.g. to hand to NumPy.
    pub fn raw(&self) -> (u128, u128) {
        (self.state, self.inc)
    }

    #[inline(always)]
    fn step(&mut self) {
        self.state = self.state.wrapping_mul(MULTIPLIER).wrapping_add(self.inc);
    }

    /// Next 64 random bits (NumPy: `bit_generator.random_raw()`).
    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        self.step();
        let s = self.state;
        ((s >> 64) as u64 ^ s as u64).rotate_right((s >> 122) as u32)
    }

    /// Uniform on [0, 1) with 53 random bits: `(next_u64() >> 11) * 2^-53`
    /// (NumPy: `Generator(PCG64).random()`).
    #[inline]
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / 9_007_199_254_740_992.0)
    }

    /// Uniform on (0, 1]: never 0, so safe to take a logarithm of.
    #[inline]
    pub fn next_f64_nonzero(&mut self) -> f64 {
        ((self.next_u64() >> 11) + 1) as f64 * (1.0 / 9_007_199_254_740_992.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splitmix_reference_values() {
        // Reference output of SplitMix64 seeded with 0 (Vigna's splitmix64.c).
        let mut x = 0u64;
        assert_eq!(splitmix64(&mut x), 0xe220_a839_7b1d_cdaf);
        assert_eq!(splitmix64(&mut x), 0x6e78_9e6a_a1b9_65f4);
    }

    #[test]
    fn next_f64_in_unit_interval() {
        let mut r = Pcg64::new(1, 2);
        for _ in 0..10_000 {
            let u = r.next_f64();
            assert!((0.0..1.0).contains(&u));
            let v = r.next_f64_nonzero();
            assert!(v > 0.0 && v <= 1.0);
        }
    }

    #[test]
    fn streams_differ() {
        let a: Vec<u64> = {
            let mut r = Pcg64::new(7, 1);
            (0..4).map(|_| r.next_u64()).collect()
        };
        let b: Vec<u64> = {
            let mut r = Pcg64::new(7, 2);
            (0..4).map(|_| r.next_u64()).collect()
        };
        assert_ne!(a, b);
    }

    // Known answers from NumPy 2.4.6 (`scripts/pcg64_known_answers.py`): raw state -> random_raw().
    #[test]
    fn numpy_known_answers_raw_state() {
        let cases: [(u128, u128, [u64; 6]); 3] = [
            (
                0,
                1,
                [
                    0x0000000000000001,
                    0xe260e53261800aab,
                    0xd4feb4e5a4bcfe09,
                    0xe85a7fe071b026e6,
                    0x3a5b9037fe928c11,
                    0x7b044380d100f216,
                ],
            ),
            (
                0x0123456789abcdeffedcba9876543210,
                0xdeadbeefcafebabe0123456789abcdef,
                [
                    0x158ee7928a5efac9,
                    0x7b8fb62bb38c6d13,
                    0x0d367f74b37922a4,
                    0x726458e8cb0bf6be,
                    0x351c035bd9035b6a,
                    0x7e6348f1d015e3a2,
                ],
            ),
            (
                u128::MAX,
                u128::MAX,
                [
                    0xca64c3001557c2c1,
                    0xb4979fc13a9f569c,
                    0x4dcdd0b4f1c0e360,
                    0x946089d2dcc1bff4,
                    0x0b3d8221f0688079,
                    0xe3c28531b6c1f350,
                ],
            ),
        ];
        for (state, inc, want) in cases {
            let mut r = Pcg64::from_raw(state, inc);
            let got: Vec<u64> = (0..6).map(|_| r.next_u64()).collect();
            assert_eq!(got, want, "state {state:#x} inc {inc:#x}");
        }
    }

    // Same script: our seeding recipe re-implemented in Python, outputs and doubles from NumPy.
    #[test]
    fn numpy_known_answers_seeded() {
        // (seed, stream, state, inc, random_raw, random() bits)
        type Case = (u64, u64, u128, u128, [u64; 4], [u64; 3]);
        let cases: [Case; 3] = [
            (
                0,
                0,
                0xc67fe18e5a199e966eab87730b97322e,
                0xc4415072f63b9b5edcf13cd54372cbe9,
                [
                    0x1e11ed222cc2e2e9,
                    0x7a42dda4d2ec92fe,
                    0xd42a594ab9fb5106,
                    0xfaad6c6903510005,
                ],
                [0x3fbe11ed222cc2e0, 0x3fde90b76934bb24, 0x3fea854b29573f6a],
            ),
            (
                42,
                7,
                0xbaf6107abd5de171714284b8a2553b7e,
                0xc797c3c8b2641bae089879afe878cc39,
                [
                    0xc0d8a7425da0c749,
                    0x77f63dbc13897909,
                    0x12477792d37d766f,
                    0xa3f374de68055c87,
                ],
                [0x3fe81b14e84bb418, 0x3fddfd8f6f04e25e, 0x3fb2477792d37d70],
            ),
            (
                u64::MAX,
                0xcbf29ce484222325,
                0x90c7522b1ce0c34a25d441b9900128b5,
                0x8702f802d749fe602019b5598179262d,
                [
                    0xe661ef7c61339600,
                    0x345f310d43434f97,
                    0x15ac595999ebaec2,
                    0xa590b692ab1feb75,
                ],
                [0x3feccc3def8c2672, 0x3fca2f9886a1a1a4, 0x3fb5ac595999eba8],
            ),
        ];
        for (seed, stream, state, inc, raw, doubles) in cases {
            let r = Pcg64::new(seed, stream);
            assert_eq!(r.raw(), (state, inc), "seed {seed} stream {stream}");
            let mut a = r.clone();
            let got: Vec<u64> = (0..4).map(|_| a.next_u64()).collect();
            assert_eq!(got, raw);
            let mut b = r.clone();
            let got: Vec<u64> = (0..3).map(|_| b.next_f64().to_bits()).collect();
            assert_eq!(got, doubles);
        }
    }
}
