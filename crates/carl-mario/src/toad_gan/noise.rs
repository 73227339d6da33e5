//! `torch.randn(shape, generator=torch.Generator().manual_seed(seed))` on CPU, bit for bit as
//! torch 2.4.1 computes it on x86-64 with AVX2/AVX512: MT19937, 24-bit uniforms, Box–Muller over
//! blocks of 16 with Cephes-style f32 `log`/`sincos` polynomials and fused multiply-adds
//! (observed behaviour of CARL's TOAD-GAN sampling; `mul_add` exactly where torch fuses).
//! Constants are written with the Cephes decimals so that they round exactly as torch's do.
#![allow(clippy::excessive_precision)]

/// MT19937 (the standard 624-word Mersenne twister) seeded like torch's `manual_seed`.
pub struct Mt19937 {
    mt: [u32; 624],
    idx: usize,
}

impl Mt19937 {
    pub fn new(seed: u64) -> Self {
        let mut mt = [0u32; 624];
        mt[0] = seed as u32; // torch keeps seed mod 2^32
        for i in 1..624 {
            mt[i] = 1_812_433_253u32
                .wrapping_mul(mt[i - 1] ^ (mt[i - 1] >> 30))
                .wrapping_add(i as u32);
        }
        Mt19937 { mt, idx: 624 }
    }

    fn twist(&mut self) {
        for i in 0..624 {
            let y = (self.mt[i] & 0x8000_0000) | (self.mt[(i + 1) % 624] & 0x7fff_ffff);
            let mag = if y & 1 == 1 { 0x9908_b0df } else { 0 };
            self.mt[i] = self.mt[(i + 397) % 624] ^ (y >> 1) ^ mag;
        }
        self.idx = 0;
    }

    pub fn next_u32(&mut self) -> u32 {
        if self.idx >= 624 {
            self.twist();
        }
        let mut y = self.mt[self.idx];
        self.idx += 1;
        y ^= y >> 11;
        y ^= (y << 7) & 0x9d2c_5680;
        y ^= (y << 15) & 0xefc6_0000;
        y ^ (y >> 18)
    }

    /// torch's `uniform_real_distribution<float>(0, 1)`: the low 24 bits times 2^-24.
    pub fn uniform_f32(&mut self) -> f32 {
        (self.next_u32() & 0x00ff_ffff) as f32 * (1.0 / 16_777_216.0)
    }
}

// Constants are the Cephes decimals, rounded decimal → f64 → f32 like the reference does.
const LOG_P: [f64; 9] = [
    7.0376836292E-2,
    -1.1514610310E-1,
    1.1676998740E-1,
    -1.2420140846E-1,
    1.4249322787E-1,
    -1.6668057665E-1,
    2.0000714765E-1,
    -2.4999993993E-1,
    3.3333331174E-1,
];

/// Cephes-style f32 natural logarithm of `x` in (0, 1], as torch's vectorised normal fill.
fn log_cephes(x: f32) -> f32 {
    let x = x.max(f32::from_bits(0x0080_0000));
    let bits = x.to_bits();
    let mut e = ((bits >> 23) as i32 - 127) as f32 + 1.0;
    let mut x = f32::from_bits((bits & 0x807f_ffff) | 0x3f00_0000); // mantissa in [0.5, 1)
    let small = x < std::f64::consts::FRAC_1_SQRT_2 as f32;
    let tmp = if small { x } else { 0.0 };
    x -= 1.0;
    if small {
        e -= 1.0;
    }
    x += tmp; // 2x - 1 when small, else x - 1
    let z = x * x;
    let mut y = LOG_P[0] as f32;
    for p in &LOG_P[1..] {
        y = y.mul_add(x, *p as f32);
    }
    y *= x;
    y = y.mul_add(z, e * (-2.12194440e-4f64 as f32));
    y -= z * 0.5;
    (x + y) + e * 0.693_359_375
}

/// Cephes-style f32 `(sin x, cos x)` for `x ≥ 0`, as torch's vectorised normal fill.
fn sincos_cephes(x: f32) -> (f32, f32) {
    let mut x = x.abs();
    let mut j = (x * (1.27323954473516f64 as f32)) as i32;
    j = (j + 1) & !1;
    let y = j as f32;
    let swap_sign_sin = j & 4 != 0;
    let sine_poly_for_sin = j & 2 == 0;
    for dp in [-0.78515625f64, -2.4187564849853515625e-4, -3.77489497744594108e-8] {
        x = y.mul_add(dp as f32, x);
    }
    let sign_cos = (!(j - 2)) & 4 != 0;
    let z = x * x;
    let mut yc = (2.443315711809948E-005f64 as f32).mul_add(z, -1.388731625493765E-003f64 as f32);
    yc = yc.mul_add(z, 4.166664568298827E-002f64 as f32);
    yc *= z;
    yc = yc.mul_add(z, -(z * 0.5));
    yc += 1.0;
    let mut ys = (-1.9515295891E-4f64 as f32).mul_add(z, 8.3321608736E-3f64 as f32);
    ys = ys.mul_add(z, -1.6666654611E-1f64 as f32);
    ys *= z;
    ys = ys.mul_add(x, x);
    let (mut s, mut c) = if sine_poly_for_sin { (ys, yc) } else { (yc, ys) };
    if swap_sign_sin {
        s = -s;
    }
    if sign_cos {
        c = -c;
    }
    (s, c)
}

/// Box–Muller over one block of 16 uniforms, in place.
fn box_muller16(d: &mut [f32]) {
    debug_assert_eq!(d.len(), 16);
    for j in 0..8 {
        let u1 = 1.0 - d[j];
        let u2 = d[j + 8];
        let r = (-2.0 * log_cephes(u1)).sqrt();
        let theta = std::f64::consts::TAU as f32 * u2;
        let (s, c) = sincos_cephes(theta);
        d[j] = r * c;
        d[j + 8] = r * s;
    }
}

/// `n` standard normals (row-major), `n ≥ 16` (always true for TOAD-GAN noise maps).
pub fn randn(n: usize, seed: u64) -> Vec<f32> {
    assert!(n >= 16, "torch uses another path for n < 16");
    let mut g = Mt19937::new(seed);
    let mut d: Vec<f32> = (0..n).map(|_| g.uniform_f32()).collect();
    let mut b = 0;
    while b + 16 <= n {
        box_muller16(&mut d[b..b + 16]);
        b += 16;
    }
    if !n.is_multiple_of(16) {
        // torch draws 16 fresh uniforms and recomputes the last 16 positions.
        let mut blk = [0f32; 16];
        for v in &mut blk {
            *v = g.uniform_f32();
        }
        box_muller16(&mut blk);
        d[n - 16..].copy_from_slice(&blk);
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mt19937_matches_the_reference_sequence() {
        // First outputs of the reference MT19937 (mt19937ar) for seed 5489.
        let mut g = Mt19937::new(5489);
        let first: Vec<u32> = (0..3).map(|_| g.next_u32()).collect();
        assert_eq!(first, [3_499_211_612, 581_869_302, 3_890_346_734]);
    }

    #[test]
    fn log_and_sincos_are_close_to_libm() {
        for i in 1..1000 {
            let u = i as f32 / 1000.0;
            assert!((log_cephes(u) - u.ln()).abs() < 1e-6 * (1.0 + u.ln().abs()));
            let t = u * 6.283_185_5;
            let (s, c) = sincos_cephes(t);
            assert!((s - t.sin()).abs() < 1e-6 && (c - t.cos()).abs() < 1e-6, "{t}");
        }
    }
}
