//! Split kinds: instance sets derived from a region of the context space.
//!
//! A region is a box over continuous features (`regions` in a spec). A `split` set takes one of
//! its kinds, after the evaluation protocols of Kirk et al.'s survey of zero-shot generalization
//! and CARL's TMLR paper:
//!
//! | kind | combinatorial (default) | single (one feature at a time, the others at their defaults) |
//! |---|---|---|
//! | `train` | the grid's product over the box (edges included), or uniform draws in it | each feature's grid line or draws |
//! | `interpolation` | the centres of the grid's cells, or fresh draws | the midpoints between each line's points, or draws |
//! | `extrapolation` | every corner beyond the box, each feature `d × width` past its edge | each feature alone, `d × width` below or above |
//!
//! Train points carry no split label, interpolation points are `in_distribution`, extrapolation
//! points `out_of_distribution`. Extrapolation points are named (`g+0.5` is g half the region's
//! width above its high edge; `g-0.5,l+0.5` moves both). The one function here,
//! [`split_points`], serves both the derivation of a set and the validator.

use std::collections::BTreeMap;

use crate::sampling::{self, FeatureInfo};
use crate::spec::model::{EnvSpec, FeatureType, Sampler, Value};
use crate::spec::raw::{AtBounds, Factors, MAX_INSTANCES, MAX_SET_VALUES, RawDistribution, Split, SplitKind, SplitSet};

/// One point of a split set.
#[derive(Debug, Clone, PartialEq)]
pub struct SplitPoint {
    pub name: Option<String>,
    pub split: Option<Split>,
    /// The values of the features this point moves (by canonical name); the rest keep their defaults.
    pub context: BTreeMap<String, f64>,
}

/// A region's feature resolved: its canonical name and range.
struct Axis {
    name: String,
    low: f64,
    high: f64,
}

impl Axis {
    fn width(&self) -> f64 {
        self.high - self.low
    }
}

/// The points of a split set, in a stable order (features in the region's order, which is by
/// canonical name), or what is wrong with its definition.
pub fn split_points(spec: &EnvSpec, split: &SplitSet) -> Result<Vec<SplitPoint>, String> {
    let axes = axes(spec, &split.region, split.factors)?;
    let n_axes = axes.len() as u64;
    let points = match (split.kind, split.grid, &split.sampled, &split.distances) {
        (SplitKind::Extrapolation, None, None, Some(d)) => extrapolation(&axes, split.factors, d)?,
        (SplitKind::Extrapolation, ..) => {
            return Err(
                "an extrapolation set takes `distances` (multiples of each feature's width beyond the region) \
                        and neither `grid` nor `sampled`"
                    .into(),
            );
        }
        (kind, Some(n), None, None) => grid(&axes, split.factors, kind, n)?,
        (kind, None, Some(s), None) => {
            let per = if split.factors == Factors::Single { n_axes } else { 1 };
            if s.size == 0 || s.size.saturating_mul(per) > MAX_INSTANCES {
                return Err(format!(
                    "size {} × {per} is not in 1..={MAX_INSTANCES} instances",
                    s.size
                ));
            }
            sampled(spec, &axes, split.factors, kind, s.size, s.seed)?
        }
        (kind, ..) => {
            let k = if kind == SplitKind::Train {
                "a train"
            } else {
                "an interpolation"
            };
            return Err(format!(
                "{k} set takes exactly one of `grid` (points per feature, ≥ 2) or `sampled` ({{size, seed}}), \
                 and no `distances`"
            ));
        }
    };
    let values: u64 = points.iter().map(|p| p.context.len() as u64).sum();
    if values > MAX_SET_VALUES {
        return Err(format!(
            "{values} values, more than the limit of {MAX_SET_VALUES} per set; use fewer points"
        ));
    }
    Ok(points)
}

/// What is wrong with a declared region, if anything.
pub fn check_region(spec: &EnvSpec, region: &str) -> Result<(), String> {
    axes(spec, region, Factors::Combinatorial).map(drop)
}

fn axes(spec: &EnvSpec, region_name: &str, factors: Factors) -> Result<Vec<Axis>, String> {
    let region = spec.regions.get(region_name).ok_or_else(|| {
        let known: Vec<&str> = spec.regions.keys().map(String::as_str).collect();
        match crate::suggest::did_you_mean(region_name, known.iter().copied()) {
            Some(s) => format!("no region \"{}\"; did you mean \"{s}\"?", region_name),
            None if known.is_empty() => format!("no region \"{}\": this spec declares no `regions`", region_name),
            None => format!("no region \"{}\"; regions: {}", region_name, known.join(", ")),
        }
    })?;
    if region.features.is_empty() {
        return Err(format!("region \"{}\" names no feature", region_name));
    }
    if region.features.len() > 16 {
        return Err(format!(
            "region \"{}\" spans {} features; at most 16",
            region_name,
            region.features.len()
        ));
    }
    let mut axes: Vec<Axis> = Vec::new();
    for (name, &[low, high]) in &region.features {
        let f = spec
            .feature(name)
            .ok_or_else(|| format!("region \"{}\": no feature \"{name}\"", region_name))?;
        if f.kind != FeatureType::Float {
            return Err(format!(
                "region \"{}\": \"{}\" is not a float feature",
                region_name, f.name
            ));
        }
        if !(low.is_finite() && high.is_finite() && low < high) {
            return Err(format!(
                "region \"{}\": \"{}\" needs finite low < high, not [{low}, {high}]",
                region_name, f.name
            ));
        }
        if !(f.in_bounds(low) && f.in_bounds(high)) {
            return Err(format!(
                "region \"{}\": [{low}, {high}] of \"{}\" leaves the feature's bounds; a region is where training happens",
                region_name, f.name
            ));
        }
        if axes.iter().any(|a| a.name == f.name) {
            return Err(format!(
                "region \"{}\" names \"{}\" twice (an alias?)",
                region_name, f.name
            ));
        }
        let default = match &f.default {
            Some(Value::Number(x)) => Some(*x),
            _ => None,
        };
        if factors == Factors::Single && !default.is_some_and(|d| low <= d && d <= high) {
            return Err(format!(
                "one factor at a time keeps the other features at their defaults, so each must lie in the region: \
                 the default of \"{}\" is not in [{low}, {high}]",
                f.name
            ));
        }
        axes.push(Axis {
            name: f.name.clone(),
            low,
            high,
        });
    }
    Ok(axes)
}

/// The grid lines: `n` points per feature (train), or the `n - 1` midpoints between them (interpolation).
fn lines(axes: &[Axis], kind: SplitKind, n: u32) -> Result<Vec<Vec<f64>>, String> {
    if n < 2 {
        return Err(format!("grid {n}: a grid needs at least 2 points per feature"));
    }
    let n = f64::from(n);
    Ok(axes
        .iter()
        .map(|a| {
            let step = a.width() / (n - 1.0);
            match kind {
                SplitKind::Train => (0..n as u32).map(|i| a.low + f64::from(i) * step).collect(),
                _ => (0..n as u32 - 1).map(|i| a.low + (f64::from(i) + 0.5) * step).collect(),
            }
        })
        .collect())
}

fn split_label(kind: SplitKind) -> Option<Split> {
    match kind {
        SplitKind::Train => None,
        SplitKind::Interpolation => Some(Split::InDistribution),
        SplitKind::Extrapolation => Some(Split::OutOfDistribution),
    }
}

fn grid(axes: &[Axis], factors: Factors, kind: SplitKind, n: u32) -> Result<Vec<SplitPoint>, String> {
    let lines = lines(axes, kind, n)?;
    let label = split_label(kind);
    match factors {
        Factors::Single => Ok(axes
            .iter()
            .zip(&lines)
            .flat_map(|(a, line)| {
                line.iter().map(|&x| SplitPoint {
                    name: None,
                    split: label,
                    context: BTreeMap::from([(a.name.clone(), x)]),
                })
            })
            .collect()),
        Factors::Combinatorial => {
            let count = lines.iter().try_fold(1u64, |acc, l| acc.checked_mul(l.len() as u64));
            if count.is_none_or(|c| c > MAX_INSTANCES) {
                return Err(format!(
                    "a grid of {n} points per feature over {} features is more than {MAX_INSTANCES} instances",
                    axes.len()
                ));
            }
            let mut points = vec![BTreeMap::new()];
            for (a, line) in axes.iter().zip(&lines) {
                points = points
                    .into_iter()
                    .flat_map(|p| {
                        line.iter().map(move |&x| {
                            let mut p = p.clone();
                            p.insert(a.name.clone(), x);
                            p
                        })
                    })
                    .collect();
            }
            Ok(points
                .into_iter()
                .map(|context| SplitPoint {
                    name: None,
                    split: label,
                    context,
                })
                .collect())
        }
    }
}

/// Uniform draws in the region through the spec's sampling chain (one stream per feature and seed).
fn sampled(
    spec: &EnvSpec,
    axes: &[Axis],
    factors: Factors,
    kind: SplitKind,
    size: u64,
    seed: u64,
) -> Result<Vec<SplitPoint>, String> {
    let draw = |axes: &[&Axis]| -> Result<Vec<BTreeMap<String, f64>>, String> {
        let samplers: Vec<(FeatureInfo, Sampler)> = axes
            .iter()
            .map(|a| {
                let f = spec.feature(&a.name).expect("axes are resolved features");
                (
                    FeatureInfo::from_feature(f),
                    Sampler::Uniform {
                        low: a.low,
                        high: a.high,
                    },
                )
            })
            .collect();
        let cols: Vec<(FeatureInfo, &Sampler)> = samplers.iter().map(|(i, s)| (i.clone(), s)).collect();
        let rows =
            sampling::sample_contexts(seed, size as usize, &cols, AtBounds::Reject).map_err(|e| e.to_string())?;
        Ok(rows
            .into_iter()
            .map(|row| {
                axes.iter()
                    .zip(row)
                    .map(|(a, v)| match v {
                        Value::Number(x) => (a.name.clone(), x),
                        _ => unreachable!("uniform draws are numbers"),
                    })
                    .collect()
            })
            .collect())
    };
    let label = split_label(kind);
    let contexts = match factors {
        Factors::Combinatorial => draw(&axes.iter().collect::<Vec<_>>())?,
        Factors::Single => {
            let mut all = Vec::new();
            for a in axes {
                all.extend(draw(&[a])?);
            }
            all
        }
    };
    Ok(contexts
        .into_iter()
        .map(|context| SplitPoint {
            name: None,
            split: label,
            context,
        })
        .collect())
}

fn extrapolation(axes: &[Axis], factors: Factors, distances: &[f64]) -> Result<Vec<SplitPoint>, String> {
    if distances.is_empty() {
        return Err("`distances` is empty: list how far beyond the region to test, e.g. [0.25, 0.5]".into());
    }
    if let Some(d) = distances.iter().find(|d| !(d.is_finite() && **d > 0.0)) {
        return Err(format!(
            "distance {d} is not finite and > 0 (a multiple of each feature's width)"
        ));
    }
    for (i, d) in distances.iter().enumerate() {
        if distances[..i].contains(d) {
            return Err(format!("distance {d} is listed twice"));
        }
    }
    let side = |a: &Axis, d: f64, up: bool| -> (String, f64) {
        if up {
            (format!("{}+{d}", a.name), a.high + d * a.width())
        } else {
            (format!("{}-{d}", a.name), a.low - d * a.width())
        }
    };
    let label = Some(Split::OutOfDistribution);
    let mut points = Vec::new();
    match factors {
        Factors::Single => {
            for a in axes {
                for &d in distances {
                    for up in [false, true] {
                        let (name, x) = side(a, d, up);
                        points.push(SplitPoint {
                            name: Some(name),
                            split: label,
                            context: BTreeMap::from([(a.name.clone(), x)]),
                        });
                    }
                }
            }
        }
        Factors::Combinatorial => {
            for &d in distances {
                for mask in 0u32..(1 << axes.len()) {
                    let mut names = Vec::new();
                    let mut context = BTreeMap::new();
                    for (i, a) in axes.iter().enumerate() {
                        let (name, x) = side(a, d, mask & (1 << i) != 0);
                        names.push(name);
                        context.insert(a.name.clone(), x);
                    }
                    points.push(SplitPoint {
                        name: Some(names.join(",")),
                        split: label,
                        context,
                    });
                }
            }
        }
    }
    if points.len() as u64 > MAX_INSTANCES {
        return Err(format!("{} points, more than {MAX_INSTANCES}", points.len()));
    }
    Ok(points)
}

/// The distribution a `sampled` split draws from, for provenance: uniform over the region.
pub fn region_distribution(spec: &EnvSpec, split: &SplitSet) -> Option<RawDistribution> {
    let region = spec.regions.get(&split.region)?;
    Some(RawDistribution {
        description: format!("uniform over region {}", split.region),
        at_bounds: AtBounds::Reject,
        features: region
            .features
            .iter()
            .map(|(k, &[low, high])| (k.clone(), Sampler::Uniform { low, high }))
            .collect(),
    })
}
