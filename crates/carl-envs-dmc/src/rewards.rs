//! dm_control's `rewards.tolerance` (`dm_control/utils/rewards.py`), reimplemented from its
//! documented behaviour: 1 inside `[lower, upper]`, falling off outside with a sigmoid of the
//! distance to the nearest bound in units of `margin`, equal to `value_at_margin` at one margin.

/// The sigmoid shapes of `tolerance`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sigmoid {
    Gaussian,
    Hyperbolic,
    LongTail,
    Reciprocal,
    Cosine,
    Linear,
    Quadratic,
    TanhSquared,
}

/// 1 at `x = 0`, `value_at_1` at `x = 1` (`x ≥ 0`).
pub fn sigmoid(x: f64, value_at_1: f64, kind: Sigmoid) -> f64 {
    match kind {
        Sigmoid::Gaussian => {
            let scale = (-2.0 * value_at_1.ln()).sqrt();
            (-0.5 * (x * scale).powi(2)).exp()
        }
        Sigmoid::Hyperbolic => {
            let scale = (1.0 / value_at_1).acosh();
            1.0 / (x * scale).cosh()
        }
        Sigmoid::LongTail => {
            let scale = (1.0 / value_at_1 - 1.0).sqrt();
            1.0 / ((x * scale).powi(2) + 1.0)
        }
        Sigmoid::Reciprocal => {
            let scale = 1.0 / value_at_1 - 1.0;
            1.0 / (x.abs() * scale + 1.0)
        }
        Sigmoid::Cosine => {
            let scaled = x * (2.0 * value_at_1 - 1.0).acos() / std::f64::consts::PI;
            if scaled.abs() < 1.0 {
                (1.0 + (std::f64::consts::PI * scaled).cos()) / 2.0
            } else {
                0.0
            }
        }
        Sigmoid::Linear => {
            let scaled = x * (1.0 - value_at_1);
            if scaled.abs() < 1.0 { 1.0 - scaled } else { 0.0 }
        }
        Sigmoid::Quadratic => {
            let scaled = x * (1.0 - value_at_1).sqrt();
            if scaled.abs() < 1.0 { 1.0 - scaled * scaled } else { 0.0 }
        }
        Sigmoid::TanhSquared => {
            let scale = (1.0 - value_at_1).sqrt().atanh();
            1.0 - (x * scale).tanh().powi(2)
        }
    }
}

/// `tolerance(x, bounds, margin, sigmoid, value_at_margin)`: 1 for `lower ≤ x ≤ upper`; outside,
/// 0 when `margin` is 0, else `sigmoid(d / margin)` with `d` the distance to the nearer bound.
pub fn tolerance(x: f64, bounds: (f64, f64), margin: f64, kind: Sigmoid, value_at_margin: f64) -> f64 {
    let (lower, upper) = bounds;
    if lower <= x && x <= upper {
        return 1.0;
    }
    if margin == 0.0 {
        return 0.0;
    }
    let d = if x < lower { lower - x } else { x - upper } / margin;
    sigmoid(d, value_at_margin, kind)
}

/// dm_control's default `value_at_margin`.
pub const DEFAULT_VALUE_AT_MARGIN: f64 = 0.1;

#[cfg(test)]
mod tests {
    use super::*;

    /// Values of dm_control 1.0.50's `rewards.tolerance` (computed with it).
    #[test]
    fn matches_dm_control() {
        let g = tolerance(0.03, (0.0, 0.015), 0.015, Sigmoid::Gaussian, 0.1);
        assert!((g - 0.1).abs() < 1e-12, "{g}");
        assert_eq!(tolerance(0.01, (0.0, 0.015), 0.015, Sigmoid::Gaussian, 0.1), 1.0);
        let q = tolerance(0.5, (0.0, 0.0), 1.0, Sigmoid::Quadratic, 0.0);
        assert!((q - 0.75).abs() < 1e-12);
        assert_eq!(tolerance(1.5, (0.0, 0.0), 1.0, Sigmoid::Quadratic, 0.0), 0.0);
        let l = tolerance(-2.0, (0.0, 1.0), 4.0, Sigmoid::Linear, 0.1);
        assert!((l - (1.0 - 0.5 * 0.9)).abs() < 1e-12);
        for kind in [
            Sigmoid::Gaussian,
            Sigmoid::Hyperbolic,
            Sigmoid::LongTail,
            Sigmoid::Reciprocal,
            Sigmoid::Cosine,
            Sigmoid::Linear,
            Sigmoid::Quadratic,
            Sigmoid::TanhSquared,
        ] {
            let at_margin = tolerance(3.0, (0.0, 2.0), 1.0, kind, 0.3);
            assert!((at_margin - 0.3).abs() < 1e-9, "{kind:?}: {at_margin}");
        }
    }
}
