//! A sampler compiled against one feature: parameters checked once, then cheap draws that always
//! respect the feature's type and bounds.

use super::dist;
use super::error::{SamplerProblem, SamplingError};
use super::pcg64::Pcg64;
use crate::spec::model::Feature;
use crate::spec::raw::{AtBounds, Bounds, FeatureType, RawFeature, Sampler, Scalar, Value};

/// Redraws allowed by `at_bounds = resample` before giving up (fixed: part of the output contract).
pub const MAX_RESAMPLE_TRIES: u32 = 10_000;
/// Proposals allowed inside one truncated-normal draw.
pub const MAX_TRUNCATION_TRIES: u32 = 10_000;
/// Integers are carried as f64; beyond 2^53 they stop being exact.
const MAX_EXACT_INT: f64 = 9_007_199_254_740_992.0;
/// Standardised truncation limits beyond this many std are treated as infinite (the normal has
/// no representable mass there) and keep a*a finite in the tail sampler.
const FAR_TAIL: f64 = 1e100;

/// What the sampler needs to know about a feature.
#[derive(Debug, Clone, PartialEq)]
pub struct FeatureInfo {
    pub name: String,
    pub kind: FeatureType,
    pub default: Option<Value>,
    /// `[None, None]` when the feature has no bounds.
    pub bounds: Bounds,
    pub choices: Option<Vec<Scalar>>,
}

impl FeatureInfo {
    pub fn from_raw(f: &RawFeature) -> Self {
        FeatureInfo {
            name: f.name.clone(),
            kind: f.kind,
            default: f.default.clone(),
            bounds: f.bounds.unwrap_or([None, None]),
            choices: f.choices.clone(),
        }
    }

    /// What the sampler needs of a resolved feature (the one conversion `freeze`, `sample` and
    /// `validate` all use).
    pub fn from_feature(f: &Feature) -> Self {
        FeatureInfo {
            name: f.name.clone(),
            kind: f.kind,
            default: f.default.clone(),
            bounds: f.bounds,
            choices: f.choices.clone(),
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
enum Draw {
    /// Non-numeric or list value, or a number already checked against the bounds.
    Fixed(Value),
    Normal {
        mean: f64,
        std: f64,
    },
    /// Standardised limits `a`, `b`; `low`, `high` re-clamp after rounding.
    Truncated {
        mean: f64,
        std: f64,
        a: f64,
        b: f64,
        low: f64,
        high: f64,
    },
    Uniform {
        low: f64,
        high: f64,
    },
    LogUniform {
        ln_low: f64,
        ln_high: f64,
        low: f64,
        high: f64,
    },
    IntUniform {
        low: i64,
        range: u64,
    },
    Choice {
        values: Vec<Value>,
        cum: Vec<f64>,
    },
    Mixture {
        intervals: Vec<(f64, f64)>,
        pick: Pick,
    },
}

#[derive(Debug, Clone, PartialEq)]
enum Pick {
    Equal,
    Weighted(Vec<f64>),
    Stratified,
}

/// A [`Sampler`] bound to one feature and an [`AtBounds`] policy.
#[derive(Debug, Clone, PartialEq)]
pub struct FeatureSampler {
    name: String,
    draw: Draw,
    at_bounds: AtBounds,
    /// Effective inclusive bounds (rounded inwards to integers for int features).
    lo: f64,
    hi: f64,
}

fn kind_name(s: &Sampler) -> &'static str {
    match s {
        Sampler::Constant { .. } => "constant",
        Sampler::Normal { .. } => "normal",
        Sampler::RelativeNormal { .. } => "relative_normal",
        Sampler::TruncatedNormal { .. } => "truncated_normal",
        Sampler::Uniform { .. } => "uniform",
        Sampler::LogUniform { .. } => "log_uniform",
        Sampler::IntUniform { .. } => "int_uniform",
        Sampler::Categorical { .. } => "categorical",
        Sampler::IntervalMixture { .. } => "interval_mixture",
    }
}

fn type_name(t: FeatureType) -> &'static str {
    match t {
        FeatureType::Float => "float",
        FeatureType::Int => "int",
        FeatureType::Bool => "bool",
        FeatureType::Categorical => "categorical",
        FeatureType::ListInt => "list_int",
    }
}

fn fmt_bound(b: Option<f64>) -> String {
    b.map_or_else(|| "null".to_string(), |x| x.to_string())
}

fn scalar_to_value(s: &Scalar) -> Value {
    match s {
        Scalar::Bool(b) => Value::Bool(*b),
        Scalar::Number(x) => Value::Number(*x),
        Scalar::String(t) => Value::String(t.clone()),
    }
}

fn is_int(x: f64) -> bool {
    x.is_finite() && x.trunc() == x && x.abs() <= MAX_EXACT_INT
}

/// Cumulative weights after checking them: one per entry, finite, >= 0, finite positive sum.
fn cumulative(weights: &[f64], n: usize) -> Result<Vec<f64>, String> {
    if weights.len() != n {
        return Err(format!("{} weights for {n} entries", weights.len()));
    }
    let mut cum = Vec::with_capacity(n);
    let mut total = 0.0;
    for (i, &w) in weights.iter().enumerate() {
        if !w.is_finite() || w < 0.0 {
            return Err(format!("weight {i} is {w}; weights must be finite and >= 0"));
        }
        total += w;
        cum.push(total);
    }
    if !(total > 0.0 && total.is_finite()) {
        return Err(format!("weights sum to {total}; need a finite positive sum"));
    }
    Ok(cum)
}

impl FeatureSampler {
    /// Check `sampler` against `feature` and precompute what the draws need.
    pub fn compile(sampler: &Sampler, feature: FeatureInfo, at_bounds: AtBounds) -> Result<Self, SamplingError> {
        let kind = kind_name(sampler);
        let name = feature.name.clone();
        // Refusals name the parameter at fault and the kind of problem, so the validator can
        // point at it; `bad` is a parameter problem of the sampler as a whole.
        let refuse = |problem: SamplerProblem, field: &str, message: String| SamplingError::InvalidSampler {
            feature: name.clone(),
            kind,
            message,
            field: field.to_string(),
            problem,
        };
        let bad_at = |field: &str, message: String| refuse(SamplerProblem::Params, field, message);
        let wrong_type = |field: &str, message: String| refuse(SamplerProblem::Type, field, message);
        let no_support = |message: String| refuse(SamplerProblem::Support, "", message);
        let bad_feature = |message: String| SamplingError::InvalidFeature {
            feature: name.clone(),
            message,
        };

        let numeric = matches!(
            feature.kind,
            FeatureType::Float | FeatureType::Int | FeatureType::ListInt
        );
        let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
        if numeric {
            let [l, h] = feature.bounds;
            lo = l.unwrap_or(f64::NEG_INFINITY);
            hi = h.unwrap_or(f64::INFINITY);
            if lo.is_nan() || hi.is_nan() || lo > hi || lo == f64::INFINITY || hi == f64::NEG_INFINITY {
                return Err(bad_feature(format!(
                    "bounds [{}, {}] are not an interval",
                    fmt_bound(l),
                    fmt_bound(h)
                )));
            }
            if feature.kind != FeatureType::Float {
                lo = lo.ceil();
                hi = hi.floor();
                if lo > hi {
                    return Err(bad_feature(format!(
                        "bounds [{}, {}] contain no integer",
                        fmt_bound(l),
                        fmt_bound(h)
                    )));
                }
            }
        }
        let in_bounds = |x: f64| lo <= x && x <= hi;
        let bounds_text = format!("[{}, {}]", fmt_bound(feature.bounds[0]), fmt_bound(feature.bounds[1]));
        // Draws reach about 40 std (the polar method's limit); those must stay finite.
        let check_no_overflow = |mean: f64, std: f64| {
            if (mean.abs() + 40.0 * std).is_finite() {
                Ok(())
            } else {
                Err(bad_at(
                    "std",
                    format!("mean {mean} with std {std} would overflow to infinity"),
                ))
            }
        };
        let check_positive_std = |what: &str, s: f64| {
            if s.is_finite() && s > 0.0 {
                Ok(())
            } else {
                Err(bad_at(what, format!("{what} must be finite and > 0, got {s}")))
            }
        };
        // Continuous samplers need a float feature; int/bool/categorical/list features would get
        // non-integral or wrongly typed values.
        let need_float = || {
            if feature.kind == FeatureType::Float {
                Ok(())
            } else {
                Err(wrong_type(
                    "kind",
                    format!(
                        "{} feature needs {}, not a continuous sampler",
                        type_name(feature.kind),
                        match feature.kind {
                            FeatureType::Int => "an integer-valued sampler (int_uniform, categorical or constant)",
                            FeatureType::ListInt => "a constant list",
                            _ => "a categorical or constant sampler",
                        }
                    ),
                ))
            }
        };
        // Support [s_lo, s_hi] must meet the bounds, else every policy fails or silently pins.
        let overlap = |s_lo: f64, s_hi: f64| {
            if s_hi < lo || s_lo > hi {
                Err(no_support(format!(
                    "support [{s_lo}, {s_hi}] lies entirely outside the bounds {bounds_text}"
                )))
            } else {
                Ok(())
            }
        };

        let draw = match sampler {
            Sampler::Constant { value } => {
                check_value_type(value, &feature).map_err(|m| wrong_type("value", m))?;
                check_value(value, &feature, lo, hi).map_err(no_support)?;
                Draw::Fixed(value.clone())
            }
            Sampler::Normal { mean, std } => {
                need_float()?;
                if !mean.is_finite() {
                    return Err(bad_at("mean", format!("mean must be finite, got {mean}")));
                }
                check_positive_std("std", *std)?;
                check_no_overflow(*mean, *std)?;
                Draw::Normal { mean: *mean, std: *std }
            }
            Sampler::RelativeNormal {
                sigma_rel,
                fallback_std,
            } => {
                need_float()?;
                check_positive_std("sigma_rel", *sigma_rel)?;
                check_positive_std("fallback_std", *fallback_std)?;
                let mean = match &feature.default {
                    Some(Value::Number(d)) if d.is_finite() => *d,
                    Some(other) => {
                        return Err(bad_at(
                            "kind",
                            format!("needs a finite numeric default, the feature's is {other:?}"),
                        ));
                    }
                    None => {
                        return Err(bad_at("kind", "needs the feature's default, which is not set".into()));
                    }
                };
                // The CARL paper's rule: std relative to |default|, absolute fallback at 0.
                let std = if mean == 0.0 {
                    *fallback_std
                } else {
                    sigma_rel * mean.abs()
                };
                if !(std.is_finite() && std > 0.0) {
                    return Err(bad_at(
                        "sigma_rel",
                        format!("sigma_rel * |default| = {std} is not a usable std (overflow or underflow)"),
                    ));
                }
                check_no_overflow(mean, std)?;
                Draw::Normal { mean, std }
            }
            Sampler::TruncatedNormal { mean, std, low, high } => {
                need_float()?;
                if !mean.is_finite() {
                    return Err(bad_at("mean", format!("mean must be finite, got {mean}")));
                }
                check_positive_std("std", *std)?;
                check_interval(*low, *high).map_err(|m| bad_at("low", m))?;
                overlap(*low, *high)?;
                let mut a = (low - mean) / std;
                let mut b = (high - mean) / std;
                if a > FAR_TAIL || b < -FAR_TAIL {
                    return Err(no_support(format!(
                        "[{low}, {high}] is more than {FAR_TAIL:e} std from the mean {mean}; no representable mass"
                    )));
                }
                if a < -FAR_TAIL {
                    a = f64::NEG_INFINITY;
                }
                if b > FAR_TAIL {
                    b = f64::INFINITY;
                }
                if a >= b {
                    return Err(bad_at(
                        "low",
                        format!("[{low}, {high}] is narrower than the float resolution at std {std}"),
                    ));
                }
                Draw::Truncated {
                    mean: *mean,
                    std: *std,
                    a,
                    b,
                    low: *low,
                    high: *high,
                }
            }
            Sampler::Uniform { low, high } => {
                need_float()?;
                check_interval(*low, *high).map_err(|m| bad_at("low", m))?;
                overlap(*low, *high)?;
                Draw::Uniform { low: *low, high: *high }
            }
            Sampler::LogUniform { low, high } => {
                need_float()?;
                check_interval(*low, *high).map_err(|m| bad_at("low", m))?;
                if *low <= 0.0 {
                    return Err(bad_at("low", format!("low must be > 0, got {low}")));
                }
                overlap(*low, *high)?;
                Draw::LogUniform {
                    ln_low: libm::log(*low),
                    ln_high: libm::log(*high),
                    low: *low,
                    high: *high,
                }
            }
            Sampler::IntUniform { low, high } => {
                if !matches!(feature.kind, FeatureType::Float | FeatureType::Int) {
                    return Err(wrong_type(
                        "kind",
                        format!("not usable for a {} feature", type_name(feature.kind)),
                    ));
                }
                if low > high {
                    return Err(bad_at("low", format!("low {low} > high {high}")));
                }
                let limit = MAX_EXACT_INT as i64;
                if low.unsigned_abs() > limit as u64 || high.unsigned_abs() > limit as u64 {
                    return Err(bad_at(
                        "low",
                        format!("low and high must lie within +-2^53 ({limit}) to stay exact"),
                    ));
                }
                overlap(*low as f64, *high as f64)?;
                // Fits: both within 2^53, so the span is at most 2^54 + 1.
                let range = (high - low) as u64 + 1;
                Draw::IntUniform { low: *low, range }
            }
            Sampler::Categorical { choices, weights } => {
                let own;
                let choices: &[Scalar] = match (choices, &feature.choices) {
                    (Some(c), _) => c,
                    (None, Some(c)) => c,
                    (None, None) if feature.kind == FeatureType::Bool => {
                        own = [Scalar::Bool(false), Scalar::Bool(true)];
                        &own
                    }
                    (None, None) => {
                        return Err(bad_at("kind", "no choices given and the feature has none".into()));
                    }
                };
                if choices.is_empty() {
                    return Err(bad_at("choices", "choices are empty".into()));
                }
                let values: Vec<Value> = choices.iter().map(scalar_to_value).collect();
                for (i, v) in values.iter().enumerate() {
                    check_value_type(v, &feature).map_err(|m| wrong_type(&format!("choices/{i}"), m))?;
                }
                if !values.iter().any(|v| match v {
                    Value::Number(x) => in_bounds(*x),
                    _ => true,
                }) {
                    return Err(no_support(format!(
                        "every choice lies outside the bounds {bounds_text}"
                    )));
                }
                let cum = match weights {
                    Some(w) => cumulative(w, values.len()).map_err(|m| bad_at("weights", m))?,
                    None => (1..=values.len()).map(|i| i as f64).collect(),
                };
                Draw::Choice { values, cum }
            }
            Sampler::IntervalMixture {
                intervals,
                weights,
                stratified,
            } => {
                need_float()?;
                if intervals.is_empty() {
                    return Err(bad_at("intervals", "intervals are empty".into()));
                }
                for (i, [l, h]) in intervals.iter().enumerate() {
                    check_interval(*l, *h).map_err(|m| bad_at(&format!("intervals/{i}"), m))?;
                }
                if !intervals.iter().any(|[l, h]| *h >= lo && *l <= hi) {
                    return Err(no_support(format!(
                        "every interval lies outside the bounds {bounds_text}"
                    )));
                }
                let pick = match (weights, stratified) {
                    (Some(_), true) => {
                        return Err(bad_at(
                            "stratified",
                            "`weights` and `stratified` exclude each other".into(),
                        ));
                    }
                    (Some(w), false) => {
                        Pick::Weighted(cumulative(w, intervals.len()).map_err(|m| bad_at("weights", m))?)
                    }
                    (None, true) => Pick::Stratified,
                    (None, false) => Pick::Equal,
                };
                Draw::Mixture {
                    intervals: intervals.iter().map(|[l, h]| (*l, *h)).collect(),
                    pick,
                }
            }
        };
        Ok(FeatureSampler {
            name,
            draw,
            at_bounds,
            lo,
            hi,
        })
    }

    pub fn feature_name(&self) -> &str {
        &self.name
    }

    /// Draw for instance `index` of a set of `set_size` (the size matters only to stratified
    /// mixtures). Numbers outside the bounds are handled by the `at_bounds` policy, never
    /// returned.
    pub fn sample(&self, rng: &mut Pcg64, index: usize, set_size: usize) -> Result<Value, SamplingError> {
        if index >= set_size {
            return Err(SamplingError::IndexOutOfRange {
                feature: self.name.clone(),
                index,
                set_size,
            });
        }
        if let Draw::Fixed(v) = &self.draw {
            // Checked against type and bounds at compile time; costs no randomness.
            return Ok(v.clone());
        }
        match self.at_bounds {
            AtBounds::Clip => {
                let v = self.raw(rng, index, set_size)?;
                Ok(self.map_number(v, |x| x.clamp(self.lo, self.hi)))
            }
            AtBounds::Resample => {
                for _ in 0..MAX_RESAMPLE_TRIES {
                    let v = self.raw(rng, index, set_size)?;
                    match v {
                        Value::Number(x) if !(self.lo <= x && x <= self.hi) => continue,
                        v => return Ok(v),
                    }
                }
                Err(SamplingError::ResampleExhausted {
                    feature: self.name.clone(),
                    bounds: format!("[{}, {}]", self.lo, self.hi),
                    tries: MAX_RESAMPLE_TRIES,
                })
            }
            AtBounds::Reject => {
                let v = self.raw(rng, index, set_size)?;
                if let Value::Number(x) = v {
                    // `raw` never returns NaN, so plain comparisons are complete.
                    if x < self.lo {
                        return Err(self.out_of_bounds(index, x, "below the lower", self.lo));
                    }
                    if x > self.hi {
                        return Err(self.out_of_bounds(index, x, "above the upper", self.hi));
                    }
                }
                Ok(v)
            }
        }
    }

    fn out_of_bounds(&self, index: usize, value: f64, side: &'static str, bound: f64) -> SamplingError {
        SamplingError::OutOfBounds {
            feature: self.name.clone(),
            index,
            value,
            side,
            bound,
        }
    }

    fn map_number(&self, v: Value, f: impl Fn(f64) -> f64) -> Value {
        match v {
            Value::Number(x) => Value::Number(f(x)),
            other => other,
        }
    }

    /// One draw before the bounds policy.
    #[inline]
    fn raw(&self, rng: &mut Pcg64, index: usize, set_size: usize) -> Result<Value, SamplingError> {
        let x = match &self.draw {
            Draw::Fixed(v) => return Ok(v.clone()),
            Draw::Normal { mean, std } => mean + std * dist::std_normal(rng),
            Draw::Truncated {
                mean,
                std,
                a,
                b,
                low,
                high,
            } => {
                let z = dist::std_truncated_normal(rng, *a, *b, MAX_TRUNCATION_TRIES).ok_or_else(|| {
                    SamplingError::TruncationExhausted {
                        feature: self.name.clone(),
                        tries: MAX_TRUNCATION_TRIES,
                    }
                })?;
                // mean + std*z is inside [low, high] up to rounding; clamp only that rounding.
                (mean + std * z).clamp(*low, *high)
            }
            Draw::Uniform { low, high } => dist::uniform(rng, *low, *high),
            Draw::LogUniform {
                ln_low,
                ln_high,
                low,
                high,
            } => {
                let x = libm::exp(ln_low + (ln_high - ln_low) * rng.next_f64());
                if x >= *high {
                    dist::next_down(*high).max(*low)
                } else {
                    x.max(*low)
                }
            }
            Draw::IntUniform { low, range } => (*low + dist::below(rng, *range) as i64) as f64,
            Draw::Choice { values, cum } => {
                return Ok(values[dist::weighted_index(rng, cum)].clone());
            }
            Draw::Mixture { intervals, pick } => {
                let k = intervals.len();
                let i = match pick {
                    Pick::Equal => dist::below(rng, k as u64) as usize,
                    Pick::Weighted(cum) => dist::weighted_index(rng, cum),
                    // Draw i of n goes to interval floor(i*k/n): contiguous, near-equal blocks.
                    Pick::Stratified => ((index as u128 * k as u128) / set_size as u128) as usize,
                };
                let (l, h) = intervals[i.min(k - 1)];
                dist::uniform(rng, l, h)
            }
        };
        if !x.is_finite() {
            // Unreachable with compiled parameters; an error beats a silent infinity.
            return Err(SamplingError::NonFiniteDraw {
                feature: self.name.clone(),
                value: x,
            });
        }
        Ok(Value::Number(x))
    }
}

/// Finite `low < high` with a finite width.
fn check_interval(low: f64, high: f64) -> Result<(), String> {
    if !(low.is_finite() && high.is_finite()) {
        return Err(format!("low {low} and high {high} must be finite"));
    }
    if low >= high {
        return Err(format!("low {low} must be < high {high}"));
    }
    if !(high - low).is_finite() {
        return Err(format!("the width of [{low}, {high}] overflows"));
    }
    Ok(())
}

/// A value of `f` as an instance holds it: the right type (among the choices, for features that
/// have them) and, unless `allow_out_of_bounds`, inside the bounds (every element, for lists).
/// Loading a frozen set runs this on every value, so a tampered file cannot smuggle values in.
pub fn check_instance_value(v: &Value, f: &FeatureInfo, allow_out_of_bounds: bool) -> Result<(), String> {
    if allow_out_of_bounds {
        return check_value_type(v, f);
    }
    let lo = f.bounds[0].unwrap_or(f64::NEG_INFINITY);
    let hi = f.bounds[1].unwrap_or(f64::INFINITY);
    check_value(v, f, lo, hi)
}

/// A value for messages: strings quoted, escaped and cut.
fn shown(v: &Value) -> String {
    match v {
        Value::Bool(b) => b.to_string(),
        Value::Number(x) => x.to_string(),
        Value::String(s) => crate::text::quote(s),
        Value::List(l) => crate::text::escape(&format!("{l:?}")),
    }
}

/// A value's type fits the feature (and for categorical features, is one of its choices).
fn check_value_type(v: &Value, f: &FeatureInfo) -> Result<(), String> {
    let ok = match (f.kind, v) {
        (FeatureType::Float, Value::Number(x)) => x.is_finite(),
        (FeatureType::Int, Value::Number(x)) => is_int(*x),
        (FeatureType::Bool, Value::Bool(_)) => true,
        (FeatureType::Categorical, Value::Number(x)) => x.is_finite(),
        (FeatureType::Categorical, Value::Bool(_) | Value::String(_)) => true,
        (FeatureType::ListInt, Value::List(xs)) => xs.iter().all(|x| is_int(*x)),
        _ => false,
    };
    if !ok {
        return Err(format!(
            "value {} does not fit a {} feature{}",
            shown(v),
            type_name(f.kind),
            if f.kind == FeatureType::Int {
                " (integers within +-2^53)"
            } else {
                ""
            }
        ));
    }
    if let Some(choices) = &f.choices {
        let in_choices = choices.iter().any(|c| scalar_to_value(c) == *v);
        if !in_choices && !choices.is_empty() {
            return Err(format!("value {} is not among the feature's choices", shown(v)));
        }
    }
    Ok(())
}

/// A constant: right type and inside the bounds (every element, for lists).
fn check_value(v: &Value, f: &FeatureInfo, lo: f64, hi: f64) -> Result<(), String> {
    check_value_type(v, f)?;
    let outside = |x: f64| !(lo <= x && x <= hi);
    match v {
        Value::Number(x) if outside(*x) => Err(format!("value {x} lies outside the bounds [{lo}, {hi}]")),
        Value::List(xs) => match xs.iter().find(|x| outside(**x)) {
            Some(x) => Err(format!("list element {x} lies outside the bounds [{lo}, {hi}]")),
            None => Ok(()),
        },
        _ => Ok(()),
    }
}

#[cfg(test)]
#[path = "feature_tests.rs"]
mod tests;
