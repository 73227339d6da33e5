//! Figures of instance sets: one histogram panel per varied feature, with the feature's bounds,
//! named instances as labelled markers and other sets' values as rugs (`carl-spec plot`).
//!
//! * [`figure`]: what is shown and the layout (shared by both formats).
//! * [`histogram`]: binning (Freedman–Diaconis, square-root fallback) and axis ticks.
//! * [`svg`] / [`png`]: the two output formats, both written here without system libraries;
//!   PNG pixels, colours and text come from the pixel layer ([`crate::pixels`]).
//!
//! Output is deterministic: the same sets give the same bytes. A figure whose coordinates are
//! not finite (values too far apart to draw) is an error, never a broken file. Files are
//! written by [`crate::output`].

pub mod figure;
pub mod histogram;
pub mod png;
pub mod scene;
pub mod svg;

use std::path::Path;

pub use figure::{Figure, Mark, MarkKind, Panel, Rug, layout};
pub use scene::Scene;

use crate::instances::FrozenSet;
use crate::spec::model::{EnvSpec, FeatureType, Value};
use crate::spec::raw::Split;

/// Output format, chosen from the file extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    Svg,
    Png,
}

impl Format {
    /// `.svg` or `.png` (any case); anything else is an error message.
    pub fn from_path(path: &Path) -> Result<Format, String> {
        match path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .as_deref()
        {
            Some("svg") => Ok(Format::Svg),
            Some("png") => Ok(Format::Png),
            Some(other) => Err(format!(
                "cannot tell the output format from \"{}\": the extension .{other} is neither .svg nor .png",
                path.display()
            )),
            None => Err(format!(
                "cannot tell the output format from \"{}\": give it a .svg or .png extension",
                path.display()
            )),
        }
    }
}

/// How another set is drawn over the histogram.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Overlay {
    /// Named instances as labelled markers (coloured by split); unnamed ones as a rug.
    Mark,
    /// Every value as a rug tick.
    Rug,
}

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum PlotError {
    #[error("{set} has no instances to plot")]
    Empty { set: String },
    #[error("{set} varies no numeric feature (non-numeric: {features}); nothing to plot")]
    NotNumeric { set: String, features: String },
    #[error("cannot overlay {overlay} on {set}: it belongs to environment {other}, not {env}")]
    OtherEnv {
        overlay: String,
        set: String,
        other: String,
        env: String,
    },
    #[error("cannot overlay {overlay} on {set}: it varies {theirs}, the plot shows {ours}")]
    NoSharedFeature {
        overlay: String,
        set: String,
        theirs: String,
        ours: String,
    },
}

fn number(v: &Value) -> Option<f64> {
    match v {
        Value::Number(x) => Some(*x),
        Value::Bool(b) => Some(f64::from(u8::from(*b))),
        _ => None,
    }
}

fn kind_of(split: Option<&Split>) -> MarkKind {
    match split {
        Some(Split::InDistribution) => MarkKind::InDistribution,
        Some(Split::OutOfDistribution) => MarkKind::OutOfDistribution,
        None => MarkKind::Named,
    }
}

/// Add `set`'s values of `feature` to `panel` as marks (named instances) or rug ticks.
fn overlay(panel: &mut Panel, set: &FrozenSet, how: Overlay) {
    let name = set.qualified_name();
    let mut rug = Vec::new();
    for inst in &set.instances {
        let Some(x) = inst.context.get(&panel.feature).and_then(number) else {
            continue;
        };
        match (&inst.name, how) {
            (Some(label), Overlay::Mark) => panel.marks.push(Mark {
                label: label.clone(),
                value: x,
                kind: kind_of(inst.split.as_ref()),
                set: name.clone(),
            }),
            _ => rug.push(x),
        }
    }
    if !rug.is_empty() {
        panel.rugs.push(Rug { set: name, values: rug });
    }
}

/// The figure of `set` (of environment `spec`): one panel per varied numeric feature, the set's
/// own named instances marked, then each overlay. Also returns warnings (skipped features).
pub fn build(
    spec: &EnvSpec,
    set: &FrozenSet,
    overlays: &[(Overlay, &FrozenSet)],
    bins: Option<usize>,
) -> Result<(Figure, Vec<String>), PlotError> {
    let name = set.qualified_name();
    if set.instances.is_empty() {
        return Err(PlotError::Empty { set: name });
    }
    let mut warnings = Vec::new();
    let mut skipped = Vec::new();
    let mut panels = Vec::new();
    for feature in &set.features {
        let values: Vec<f64> = set
            .instances
            .iter()
            .filter_map(|i| i.context.get(feature))
            .filter_map(number)
            .collect();
        if values.is_empty() {
            skipped.push(feature.clone());
            warnings.push(format!("{feature} is not numeric; no panel for it"));
            continue;
        }
        let f = spec.feature(feature);
        let mut panel = Panel {
            feature: feature.clone(),
            unit: f.and_then(|f| f.unit.clone()),
            bounds: f.map_or([None, None], |f| f.bounds),
            integer: f.is_some_and(|f| matches!(f.kind, FeatureType::Int | FeatureType::Bool)),
            values,
            marks: Vec::new(),
            rugs: Vec::new(),
        };
        if set.instances.iter().any(|i| i.name.is_some()) {
            panel.marks.extend(set.instances.iter().filter_map(|i| {
                Some(Mark {
                    label: i.name.clone()?,
                    value: number(i.context.get(feature)?)?,
                    kind: kind_of(i.split.as_ref()),
                    set: name.clone(),
                })
            }));
        }
        panels.push(panel);
    }
    if panels.is_empty() {
        return Err(PlotError::NotNumeric {
            set: name,
            features: skipped.join(", "),
        });
    }
    for (how, other) in overlays {
        if other.env != set.env {
            return Err(PlotError::OtherEnv {
                overlay: other.qualified_name(),
                set: name,
                other: other.env.clone(),
                env: set.env.clone(),
            });
        }
        if !panels.iter().any(|p| other.features.contains(&p.feature)) {
            return Err(PlotError::NoSharedFeature {
                overlay: other.qualified_name(),
                set: name,
                theirs: other.features.join(", "),
                ours: panels.iter().map(|p| p.feature.as_str()).collect::<Vec<_>>().join(", "),
            });
        }
        for panel in &mut panels {
            overlay(panel, other, *how);
        }
    }
    let description = set.description.clone();
    Ok((
        Figure {
            title: name,
            description,
            panels,
            bins,
        },
        warnings,
    ))
}

/// The figure in `format`; an error if any coordinate is not finite.
pub fn render(fig: &Figure, format: Format) -> Result<Vec<u8>, String> {
    let scene = layout(fig);
    scene.check_finite()?;
    match format {
        Format::Svg => Ok(svg::render(&scene).into_bytes()),
        Format::Png => png::render(&scene),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn figure(values: Vec<f64>) -> Figure {
        Figure {
            title: "toy/set".into(),
            description: String::new(),
            panels: vec![Panel {
                feature: "x".into(),
                unit: None,
                bounds: [None, None],
                integer: false,
                values,
                marks: Vec::new(),
                rugs: Vec::new(),
            }],
            bins: None,
        }
    }

    #[test]
    fn subnormal_differences_plot_without_panic() {
        // Regression: explicit values 0 and 1e-323 panicked with "capacity overflow".
        for format in [Format::Svg, Format::Png] {
            let bytes = render(&figure(vec![0.0, 1e-323]), format).unwrap();
            assert!(!bytes.is_empty());
        }
        let svg = String::from_utf8(render(&figure(vec![0.0, 1e-323]), Format::Svg).unwrap()).unwrap();
        assert!(!svg.contains("NaN") && !svg.contains("inf"), "{svg}");
        assert!(svg.contains("too close to tell apart"));
    }

    #[test]
    fn values_too_far_apart_are_an_error_not_a_broken_file() {
        for format in [Format::Svg, Format::Png] {
            let err = render(&figure(vec![-1.7e308, 1.7e308]), format).unwrap_err();
            assert!(err.contains("non-finite"), "{err}");
        }
    }
}
