//! Primitive draws on top of [`Pcg64`]. Maths through `libm` only (and IEEE-exact `sqrt`), so the
//! bits are the same on every platform and build.

use super::pcg64::Pcg64;

/// sqrt(2*pi): below this width a uniform proposal beats drawing from the whole normal.
const SQRT_2PI: f64 = 2.506_628_274_631_000_5;

/// Largest float strictly below `x` (`x` finite). `f64::next_down` needs a newer Rust than our MSRV.
pub fn next_down(x: f64) -> f64 {
    if x == 0.0 {
        -f64::from_bits(1)
    } else if x > 0.0 {
        f64::from_bits(x.to_bits() - 1)
    } else {
        f64::from_bits(x.to_bits() + 1)
    }
}

/// U[low, high) for finite `low < high` with finite `high - low`.
#[inline]
pub fn uniform(rng: &mut Pcg64, low: f64, high: f64) -> f64 {
    let x = low + (high - low) * rng.next_f64();
    // Rounding can land on `high`; keep the interval half-open as documented.
    if x >= high { next_down(high).max(low) } else { x }
}

/// Standard normal, Marsaglia's polar method; the second value of each pair is dropped so that
/// draw `i` depends only on the stream position, not on hidden state. Terminates with
/// probability 1 (acceptance pi/4 per pair).
#[inline]
pub fn std_normal(rng: &mut Pcg64) -> f64 {
    loop {
        let x = 2.0 * rng.next_f64() - 1.0;
        let y = 2.0 * rng.next_f64() - 1.0;
        let s = x * x + y * y;
        if s < 1.0 && s > 0.0 {
            return x * (-2.0 * libm::log(s) / s).sqrt();
        }
    }
}

/// Standard normal truncated to [a, b] (a < b; either side may be infinite, |finite side| must
/// keep a*a finite). `None` after `max_tries` rejected proposals; every branch accepts with
/// probability above about 0.3, so that means a broken caller, not bad luck.
///
/// Branches: interval straddling 0 -> uniform proposal when narrow, plain normal otherwise;
/// interval in one tail -> uniform proposal when b^2 - a^2 <= 2 (acceptance >= 1/e), otherwise
/// Robert (1995)'s exponential proposal with the optimal rate.
pub fn std_truncated_normal(rng: &mut Pcg64, a: f64, b: f64, max_tries: u32) -> Option<f64> {
    if a >= 0.0 {
        tail(rng, a, b, max_tries)
    } else if b <= 0.0 {
        tail(rng, -b, -a, max_tries).map(|z| -z)
    } else if b - a < SQRT_2PI {
        for _ in 0..max_tries {
            let z = uniform(rng, a, b);
            if rng.next_f64() < libm::exp(-0.5 * z * z) {
                return Some(z);
            }
        }
        None
    } else {
        for _ in 0..max_tries {
            let z = std_normal(rng);
            if a <= z && z <= b {
                return Some(z);
            }
        }
        None
    }
}

/// [a, b] with 0 <= a < b.
fn tail(rng: &mut Pcg64, a: f64, b: f64, max_tries: u32) -> Option<f64> {
    if (b - a) * (b + a) <= 2.0 {
        for _ in 0..max_tries {
            let z = uniform(rng, a, b);
            // exp((a^2 - z^2) / 2), factored to keep precision far out in the tail.
            if rng.next_f64() < libm::exp(-0.5 * (z - a) * (z + a)) {
                return Some(z);
            }
        }
        return None;
    }
    let alpha = 0.5 * (a + (a * a + 4.0).sqrt());
    for _ in 0..max_tries {
        let z = a - libm::log(rng.next_f64_nonzero()) / alpha;
        if z > b {
            continue;
        }
        let d = z - alpha;
        if rng.next_f64() < libm::exp(-0.5 * d * d) {
            return Some(z);
        }
    }
    None
}

/// Uniform integer in [0, range), range > 0, without modulo bias (Lemire's multiply-shift with
/// rejection of the short leftover band).
#[inline]
pub fn below(rng: &mut Pcg64, range: u64) -> u64 {
    let mut m = u128::from(rng.next_u64()) * u128::from(range);
    if (m as u64) < range {
        let threshold = range.wrapping_neg() % range;
        while (m as u64) < threshold {
            m = u128::from(rng.next_u64()) * u128::from(range);
        }
    }
    (m >> 64) as u64
}

/// Index picked by cumulative weights `cum` (non-decreasing, last > 0). Zero-weight entries are
/// never picked: the first `i` with `target < cum[i]` skips them.
#[inline]
pub fn weighted_index(rng: &mut Pcg64, cum: &[f64]) -> usize {
    let total = cum.last().copied().unwrap_or(0.0);
    let target = rng.next_f64() * total;
    let i = cum.partition_point(|&c| c <= target);
    if i < cum.len() {
        i
    } else {
        // Rounding put `target` at the total: take the last entry with positive weight.
        let mut j = cum.len().saturating_sub(1);
        while j > 0 && cum[j - 1] == cum[j] {
            j -= 1;
        }
        j
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mean_std(xs: &[f64]) -> (f64, f64) {
        let n = xs.len() as f64;
        let m = xs.iter().sum::<f64>() / n;
        let v = xs.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0);
        (m, v.sqrt())
    }

    #[test]
    fn normal_moments() {
        let mut r = Pcg64::new(1, 1);
        let xs: Vec<f64> = (0..100_000).map(|_| std_normal(&mut r)).collect();
        let (m, s) = mean_std(&xs);
        assert!(m.abs() < 0.015, "mean {m}");
        assert!((s - 1.0).abs() < 0.015, "std {s}");
    }

    #[test]
    fn uniform_range_and_mean() {
        let mut r = Pcg64::new(2, 1);
        let xs: Vec<f64> = (0..100_000).map(|_| uniform(&mut r, -3.0, 5.0)).collect();
        assert!(xs.iter().all(|&x| (-3.0..5.0).contains(&x)));
        let (m, s) = mean_std(&xs);
        assert!((m - 1.0).abs() < 0.03, "mean {m}");
        assert!((s - 8.0 / 12f64.sqrt()).abs() < 0.03, "std {s}");
    }

    #[test]
    fn uniform_never_hits_high() {
        let mut r = Pcg64::new(3, 1);
        let (lo, hi) = (1.0, next_up(1.0));
        for _ in 0..1000 {
            assert_eq!(uniform(&mut r, lo, hi), lo);
        }
    }

    fn next_up(x: f64) -> f64 {
        f64::from_bits(x.to_bits() + 1)
    }

    #[test]
    fn next_down_values() {
        assert_eq!(next_down(1.0), 1.0 - f64::EPSILON / 2.0);
        assert!(next_down(0.0) < 0.0);
        assert!(next_down(-1.0) < -1.0);
    }

    /// Truncated-normal means against closed forms: E[Z | a<=Z<=b] = (phi(a)-phi(b)) / (Phi(b)-Phi(a)).
    #[test]
    fn truncated_normal_means() {
        let phi = |x: f64| libm::exp(-0.5 * x * x) / SQRT_2PI;
        let cdf = |x: f64| 0.5 * libm::erfc(-x / std::f64::consts::SQRT_2);
        let cases = [
            (-1.0, 1.0),
            (-3.0, 4.0),
            (0.5, f64::INFINITY),
            (3.0, 3.5),
            (5.0, f64::INFINITY),
            (8.0, 30.0),
            (f64::NEG_INFINITY, -6.0),
            (1.0, 1.2),
        ];
        for (k, (a, b)) in cases.into_iter().enumerate() {
            let mut r = Pcg64::new(10, k as u64);
            let xs: Vec<f64> = (0..50_000)
                .map(|_| std_truncated_normal(&mut r, a, b, 10_000).expect("accepts"))
                .collect();
            assert!(xs.iter().all(|&z| a <= z && z <= b));
            let (m, s) = mean_std(&xs);
            // Mills-ratio form in the far tails where Phi differences underflow.
            let want = if a > 4.0 || b < -4.0 {
                let (pa, pb) = (phi(a), if b.is_finite() { phi(b) } else { 0.0 });
                let mass = 0.5 * (libm::erfc(a / std::f64::consts::SQRT_2) - libm::erfc(b / std::f64::consts::SQRT_2));
                if b < -4.0 {
                    let (pa, pb) = (phi(-b), if a.is_finite() { phi(-a) } else { 0.0 });
                    let mass =
                        0.5 * (libm::erfc(-b / std::f64::consts::SQRT_2) - libm::erfc(-a / std::f64::consts::SQRT_2));
                    -(pa - pb) / mass
                } else {
                    (pa - pb) / mass
                }
            } else {
                let pb = if b.is_finite() { phi(b) } else { 0.0 };
                let pa = if a.is_finite() { phi(a) } else { 0.0 };
                (pa - pb) / (cdf(b) - cdf(a))
            };
            assert!(
                (m - want).abs() < 4.0 * s / (xs.len() as f64).sqrt() + 1e-9,
                "[{a},{b}] mean {m} want {want}"
            );
        }
    }

    #[test]
    fn below_is_unbiased_and_in_range() {
        let mut r = Pcg64::new(4, 1);
        let mut counts = [0u32; 7];
        for _ in 0..70_000 {
            counts[below(&mut r, 7) as usize] += 1;
        }
        for c in counts {
            assert!((9_600..10_400).contains(&c), "{counts:?}");
        }
        assert_eq!(below(&mut r, 1), 0);
    }

    #[test]
    fn weighted_index_skips_zero_weights() {
        let mut r = Pcg64::new(5, 1);
        let cum = [0.0, 1.0, 1.0, 4.0, 4.0];
        let mut counts = [0u32; 5];
        for _ in 0..40_000 {
            counts[weighted_index(&mut r, &cum)] += 1;
        }
        assert_eq!(counts[0], 0);
        assert_eq!(counts[2], 0);
        assert_eq!(counts[4], 0);
        assert!((9_500..10_500).contains(&counts[1]), "{counts:?}");
    }
}
