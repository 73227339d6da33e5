//! Binning and axis ticks.
//!
//! Bin count: the Freedman–Diaconis rule, bin width `h = 2 · IQR · n^(-1/3)` (IQR from linearly
//! interpolated quartiles), number of bins `ceil(range / h)`. When the IQR is zero (or there are
//! fewer than 4 values) the square-root rule `ceil(sqrt(n))` is used instead. The count is clamped
//! to 1..=200. Integer features get integer-wide bins centred on whole numbers. Bins span
//! `[min, max]` exactly, the last one closed, so every value lands in exactly one bin.

/// A histogram: `counts[i]` values lie in `[start + i·width, start + (i+1)·width)`.
#[derive(Debug, Clone, PartialEq)]
pub struct Bins {
    pub start: f64,
    pub width: f64,
    pub counts: Vec<u64>,
    /// Which rule chose the width: `freedman-diaconis`, `sqrt`, `fixed` or `single value`.
    pub rule: &'static str,
}

impl Bins {
    pub fn edge(&self, i: usize) -> f64 {
        self.start + self.width * i as f64
    }
    pub fn end(&self) -> f64 {
        self.edge(self.counts.len())
    }
    pub fn max_count(&self) -> u64 {
        self.counts.iter().copied().max().unwrap_or(0)
    }
}

const MAX_BINS: usize = 200;

/// The `q`-quantile (0..=1) of sorted values, linear interpolation between order statistics.
pub fn quantile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let pos = q * (sorted.len() - 1) as f64;
    let lo = pos.floor() as usize;
    let hi = (lo + 1).min(sorted.len() - 1);
    sorted[lo] + (sorted[hi] - sorted[lo]) * (pos - lo as f64)
}

/// Bin finite `values`; `fixed` forces the number of bins.
pub fn bin(values: &[f64], integer: bool, fixed: Option<usize>) -> Bins {
    let mut sorted: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    sorted.sort_by(f64::total_cmp);
    let (Some(&min), Some(&max)) = (sorted.first(), sorted.last()) else {
        return Bins {
            start: 0.0,
            width: 1.0,
            counts: Vec::new(),
            rule: "empty",
        };
    };
    let n = sorted.len();
    // Values closer than a normal number per bin (e.g. 0 and 1e-323) cannot be told apart on an
    // axis, nor can a range that overflows (±1.8e308): one bin, as for a single value.
    let range = max - min;
    let separable = (range / MAX_BINS as f64).is_normal();
    let rule_one = if range == 0.0 { "single value" } else { "inseparable" };
    let range = if separable { range } else { 0.0 };
    let (mut k, rule) = if let Some(k) = fixed {
        (k.clamp(1, MAX_BINS), "fixed")
    } else if range == 0.0 {
        (1, rule_one)
    } else {
        let iqr = quantile(&sorted, 0.75) - quantile(&sorted, 0.25);
        if n >= 4 && iqr > 0.0 {
            let h = 2.0 * iqr / (n as f64).cbrt();
            ((range / h).ceil() as usize, "freedman-diaconis")
        } else {
            ((n as f64).sqrt().ceil() as usize, "sqrt")
        }
    };
    k = k.clamp(1, MAX_BINS);
    let (start, width) = if integer {
        let width = if range == 0.0 {
            1.0
        } else {
            (range / k as f64).round().max(1.0)
        };
        let start = min.round() - 0.5;
        k = (((max - start) / width).floor() as usize + 1).clamp(1, MAX_BINS.max(1));
        (start, width)
    } else if range == 0.0 {
        let half = (min.abs() * 0.05).max(0.5);
        (min - half, 2.0 * half)
    } else {
        (min, range / k as f64)
    };
    let mut counts = vec![0u64; k];
    for &x in &sorted {
        let i = (((x - start) / width).floor().max(0.0) as usize).min(k - 1);
        counts[i] += 1;
    }
    Bins {
        start,
        width,
        counts,
        rule,
    }
}

/// "Nice" tick positions (steps of 1, 2 or 5 × 10^k) covering `[lo, hi]` with about `target`
/// ticks, and the number of decimals needed to print them.
pub fn ticks(lo: f64, hi: f64, target: usize) -> (Vec<f64>, usize) {
    if hi.partial_cmp(&lo) != Some(std::cmp::Ordering::Greater) || !lo.is_finite() || !hi.is_finite() {
        return (vec![lo], 0);
    }
    let raw = (hi - lo) / target.max(1) as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 2.5, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let first = (lo / step).ceil();
    let last = (hi / step).floor();
    // A range too small for a representable step (subnormal) or too wide for one (overflow).
    if !(step.is_finite() && step > 0.0 && first.is_finite() && last.is_finite())
        || last - first > 10.0 * target as f64 + 10.0
    {
        return (vec![lo], 0);
    }
    let (first, last) = (first as i64, last as i64);
    let ticks: Vec<f64> = (first..=last)
        .map(|i| {
            let t = i as f64 * step;
            if t == 0.0 { 0.0 } else { t }
        })
        .collect();
    let mut decimals = 0;
    while decimals < 8
        && ((step * 10f64.powi(decimals as i32)).round() - step * 10f64.powi(decimals as i32)).abs() > 1e-6
    {
        decimals += 1;
    }
    (ticks, decimals)
}

/// A number for axis labels and notes: at most `decimals` places.
pub fn fmt_num(x: f64, decimals: usize) -> String {
    let s = format!("{x:.decimals$}");
    if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
        s[1..].to_string()
    } else {
        s
    }
}

/// A number with 4 significant digits, for notes such as bounds and bin widths.
pub fn fmt_sig(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let mag = x.abs().log10().floor() as i32;
    if !(-4..=6).contains(&mag) {
        return format!("{x:.3e}");
    }
    let decimals = (3 - mag).max(0) as usize;
    let s = format!("{x:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_sum_to_n_and_cover_extremes() {
        let v: Vec<f64> = (0..100).map(|i| (i as f64 * 0.37).sin() * 3.0 - 4.0).collect();
        let b = bin(&v, false, None);
        assert_eq!(b.counts.iter().sum::<u64>(), 100);
        assert_eq!(b.rule, "freedman-diaconis");
        let min = v.iter().copied().fold(f64::INFINITY, f64::min);
        let max = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        assert_eq!(b.start, min);
        assert!((b.end() - max).abs() < 1e-9);
    }

    #[test]
    fn degenerate_inputs() {
        assert_eq!(bin(&[], false, None).counts.len(), 0);
        let b = bin(&[2.0, 2.0, 2.0], false, None);
        assert_eq!(b.counts, vec![3]);
        let b = bin(&[1.0, 1.0, 1.0, 1.0, 5.0], false, None);
        assert_eq!(b.rule, "sqrt");
        assert_eq!(b.counts.iter().sum::<u64>(), 5);
        let b = bin(&[1.0, 2.0, 2.0, 3.0, 7.0], true, None);
        assert_eq!(b.width.fract(), 0.0);
        assert_eq!(b.counts.iter().sum::<u64>(), 5);
        assert_eq!(bin(&[1.0, 2.0, 3.0], false, Some(7)).counts.len(), 7);
    }

    #[test]
    fn subnormal_and_overflowing_ranges_give_one_bin_and_few_ticks() {
        // Regression: 0 and 1e-323 made `ticks` allocate ~2^63 ticks (capacity overflow).
        let b = bin(&[0.0, 1e-323], false, None);
        assert_eq!((b.counts.clone(), b.rule), (vec![2], "inseparable"));
        assert!(b.width.is_normal());
        assert!(ticks(0.0, 1e-323, 10).0.len() <= 1);
        let b = bin(&[-1e308, 1e308], false, None);
        assert_eq!(b.counts.iter().sum::<u64>(), 2);
        assert!(ticks(-1e308, 1e308, 10).0.len() <= 21);
        assert!(ticks(-f64::MAX, f64::MAX, 10).0.len() <= 21);
    }

    #[test]
    fn nice_ticks() {
        let (t, d) = ticks(-24.0, 0.5, 8);
        assert_eq!(t, vec![-20.0, -15.0, -10.0, -5.0, 0.0]);
        assert_eq!(d, 0);
        let (t, d) = ticks(0.0, 1.0, 4);
        assert_eq!(t, vec![0.0, 0.25, 0.5, 0.75, 1.0]);
        assert_eq!(d, 2);
        assert_eq!(fmt_num(-0.0001, 2), "0.00");
        assert_eq!(fmt_sig(-0.01), "-0.01");
        assert_eq!(fmt_sig(-20.0), "-20");
        assert_eq!(fmt_sig(0.5234567), "0.5235");
    }
}
