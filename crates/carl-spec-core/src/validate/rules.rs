//! Semantic rules the JSON Schema cannot express. Each rule id is stable and listed on the rules page (docs/reference/rules.md).

// `!(x > 0.0)` is deliberate throughout: it also rejects NaN, which `x <= 0.0` would let through.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use std::collections::{BTreeMap, BTreeSet};

use crate::diagnostics::Sink;
use crate::diagnostics::rules as rule;
use crate::json::escape_token;
use crate::sampling::error::SamplerProblem;
use crate::sampling::{FeatureInfo, FeatureSampler, SamplingError};
use crate::spec::model::value_text;
use crate::spec::model::{Feature, InstanceSet};
use crate::spec::raw::{AtBounds, FeatureType, RawFragment, Sampler, Scalar, Space, Value};
use crate::spec::resolve::{FeatureSite, Resolved};
use crate::suggest::did_you_mean;
use crate::text::quote;

pub use crate::spec::raw::{MAX_INSTANCES, MAX_SET_VALUES};

pub fn check_fragment(frag: &RawFragment, file: usize, sink: &mut Sink<'_>) {
    let mut seen = BTreeSet::new();
    for (i, f) in frag.features.iter().enumerate() {
        if !seen.insert(f.name.as_str()) {
            sink.report(
                file,
                &rule::DUPLICATE_FEATURE,
                &format!("/features/{i}/name"),
                format!("feature \"{}\" is defined twice in this fragment", f.name),
                Some("remove or rename one of them".into()),
            );
        }
    }
    if frag.description.trim().is_empty() {
        sink.report(
            file,
            &rule::DESCRIPTION_EMPTY,
            "/description",
            "the description is empty",
            Some("say in one line what this block of features is".into()),
        );
    }
}

pub fn check_env(r: &Resolved, sink: &mut Sink<'_>) {
    let spec = &r.spec;
    let file = r.file;
    if spec.description.trim().is_empty() {
        sink.report(
            file,
            &rule::DESCRIPTION_EMPTY,
            "/description",
            "the description is empty",
            Some("say in one or two sentences what the task is and what the context changes".into()),
        );
    }
    if spec.max_episode_steps == Some(0) {
        sink.report(
            file,
            &rule::EPISODE_LIMIT,
            "/max_episode_steps",
            "an episode limit of 0 steps ends every episode at reset",
            Some("use the upstream limit, or null for none".into()),
        );
    }
    check_space(&spec.observation_space, file, "/observation_space", sink);
    check_space(&spec.action_space, file, "/action_space", sink);

    // Names and aliases must identify exactly one feature.
    let mut names: BTreeMap<&str, usize> = BTreeMap::new();
    for (i, f) in spec.features.iter().enumerate() {
        for (k, n) in std::iter::once(&f.name).chain(f.aliases.iter()).enumerate() {
            if let Some(&prev) = names.get(n.as_str()) {
                let site = &r.sites[i];
                let ptr = if k == 0 {
                    format!("{}/name", site.pointer)
                } else {
                    format!("{}/aliases/{}", site.pointer, k - 1)
                };
                sink.report(
                    site.file,
                    &rule::DUPLICATE_FEATURE,
                    &ptr,
                    format!("\"{n}\" already names feature #{} (\"{}\") of {}", prev + 1, spec.features[prev].name, spec.id),
                    Some("every feature name and alias must be unique within an environment (included fragments count too)".into()),
                );
            } else {
                names.insert(n, i);
            }
        }
    }
    for (f, site) in spec.features.iter().zip(&r.sites) {
        check_feature(f, site, sink);
    }
    for (name, dist) in &spec.distributions {
        let base = format!("/distributions/{}", escape_token(name));
        check_set_name(name, file, &base, "distribution", sink);
        if dist.description.trim().is_empty() {
            sink.report(
                file,
                &rule::DESCRIPTION_EMPTY,
                &format!("{base}/description"),
                "the description is empty",
                Some("say what the distribution models".into()),
            );
        }
        if dist.features.is_empty() {
            sink.report(
                file,
                &rule::DISTRIBUTION_EMPTY,
                &format!("{base}/features"),
                format!("distribution \"{name}\" varies no feature"),
                Some("name at least one feature and its sampler".into()),
            );
        }
        let mut varied: BTreeMap<&str, &str> = BTreeMap::new();
        for (fname, sampler) in &dist.features {
            let ptr = format!("{base}/features/{}", escape_token(fname));
            match spec.feature(fname) {
                None => unknown_feature(spec.feature_names(), fname, file, &ptr, sink),
                Some(f) => {
                    // Both a name and its alias: the two would read the same stream (freeze refuses).
                    if let Some(first) = varied.insert(&f.name, fname) {
                        sink.report(
                            file,
                            &rule::DUPLICATE_FEATURE,
                            &ptr,
                            format!(
                                "{} and {} are the same feature {}",
                                quote(first),
                                quote(fname),
                                quote(&f.name)
                            ),
                            Some("vary each feature once per distribution".into()),
                        );
                    }
                    check_sampler(sampler, f, dist.at_bounds, file, &ptr, sink);
                }
            }
        }
    }
    for name in spec.regions.keys() {
        check_set_name(
            name,
            r.file,
            &format!("/regions/{}", escape_token(name)),
            "region",
            sink,
        );
        if let Err(e) = crate::instances::split::check_region(spec, name) {
            sink.report(
                r.file,
                &rule::SPLIT_DEFINITION,
                &format!("/regions/{}", escape_token(name)),
                e,
                Some(SPLIT_HELP.into()),
            );
        }
    }
    for (name, set) in &spec.instance_sets {
        check_instance_set(r, name, set, sink);
    }
}

const SPLIT_HELP: &str = "a region maps float features to [low, high] inside their bounds; a split set names it \
     with kind train or interpolation (and grid or sampled) or extrapolation (and distances); see the \
     spec-language reference, \"Split kinds\"";

pub fn check_set(resolved: &[Resolved], sink: &mut Sink<'_>) {
    let mut ids: BTreeMap<&str, &Resolved> = BTreeMap::new();
    for r in resolved {
        if let Some(prev) = ids.get(r.spec.id.as_str()) {
            sink.report(
                r.file,
                &rule::DUPLICATE_ID,
                "/id",
                format!("id \"{}\" is already used by {}", r.spec.id, sink.files[prev.file].name),
                Some("ids are unique across the spec set: rename one of them".into()),
            );
        } else {
            ids.insert(&r.spec.id, r);
        }
    }
    let mut names: BTreeMap<&str, &Resolved> = ids.clone();
    for r in resolved {
        for (k, a) in r.spec.aliases.iter().enumerate() {
            match names.get(a.as_str()) {
                Some(prev) if !std::ptr::eq(*prev, r) => sink.report(
                    r.file,
                    &rule::DUPLICATE_ALIAS,
                    &format!("/aliases/{k}"),
                    format!("alias \"{a}\" already names {}", prev.spec.id),
                    Some("an alias must identify one environment".into()),
                ),
                Some(_) => {}
                None => {
                    names.insert(a, r);
                }
            }
        }
    }
}

fn check_space(space: &Space, file: usize, ptr: &str, sink: &mut Sink<'_>) {
    match space {
        Space::Box { shape, low, high, .. } => {
            let n: u64 = shape.iter().product();
            let lims = [("low", low), ("high", high)];
            let mut per: [Option<Vec<Option<f64>>>; 2] = [None, None];
            for (k, (field, lim)) in lims.iter().enumerate() {
                if let crate::spec::raw::BoxLimit::PerElement(v) = lim {
                    if v.len() as u64 != n {
                        sink.report(
                            file,
                            &rule::SPACE_SHAPE,
                            &format!("{ptr}/{field}"),
                            format!("{field} has {} element(s) but the shape {shape:?} has {n}", v.len()),
                            Some("give one value per element, or a single number for all".into()),
                        );
                    }
                    per[k] = Some(v.clone());
                }
            }
            let get = |lim: &crate::spec::raw::BoxLimit, i: usize| match lim {
                crate::spec::raw::BoxLimit::Uniform(x) => *x,
                crate::spec::raw::BoxLimit::PerElement(v) => v.get(i).copied().flatten(),
            };
            for i in 0..(n.min(100_000) as usize) {
                if let (Some(l), Some(h)) = (get(low, i), get(high, i))
                    && l > h
                {
                    sink.report(
                        file,
                        &rule::SPACE_BOUNDS,
                        &format!("{ptr}/low"),
                        format!("element {i}: low {l} is above high {h}"),
                        Some("swap them".into()),
                    );
                    break;
                }
            }
        }
        Space::Discrete { n } if *n == 0 => {
            sink.report(
                file,
                &rule::SPACE_SHAPE,
                &format!("{ptr}/n"),
                "Discrete(0) has no actions",
                Some("n is the number of actions, at least 1".into()),
            );
        }
        Space::MultiDiscrete { nvec } if nvec.is_empty() || nvec.contains(&0) => {
            sink.report(
                file,
                &rule::SPACE_SHAPE,
                &format!("{ptr}/nvec"),
                "MultiDiscrete needs at least one dimension and no zero sizes",
                None,
            );
        }
        _ => {}
    }
}

fn fmt_bounds(b: &[Option<f64>; 2]) -> String {
    let s = |x: Option<f64>, inf: &str| x.map_or(inf.to_string(), |v| v.to_string());
    format!("[{}, {}]", s(b[0], "-inf"), s(b[1], "inf"))
}

/// The largest integer magnitude carl-spec holds exactly: values are 64-bit floats at runtime.
const MAX_EXACT_INT: f64 = 9_007_199_254_740_992.0;

/// An integer feature's value or bound: no fractional part (`int-not-integral`) and within ±2^53
/// (`int-out-of-range`). The number is quoted as written, so 2^63-1 is not shown rounded.
fn check_int(x: f64, what: &str, type_name: &str, name: &str, file: usize, ptr: &str, sink: &mut Sink<'_>) {
    let shown = sink.number_text(file, ptr, x);
    if x.is_finite() && x.fract() != 0.0 {
        sink.report(
            file,
            &rule::INT_NOT_INTEGRAL,
            ptr,
            format!(
                "{what} {shown} of {type_name} feature {} is not an integer",
                quote(name)
            ),
            Some("round it, or make the feature float".into()),
        );
    } else if !is_integral(x) {
        sink.report(
            file,
            &rule::INT_OUT_OF_RANGE,
            ptr,
            format!(
                "{what} {shown} of {type_name} feature {} is beyond ±2^53 = 9007199254740992, the largest integers carl-spec holds exactly (values are 64-bit floats at runtime)",
                quote(name)
            ),
            Some("use an integer within ±9007199254740992, or make the feature float".into()),
        );
    }
}

fn is_integral(x: f64) -> bool {
    x.is_finite() && x.fract() == 0.0 && x.abs() <= MAX_EXACT_INT
}

fn check_feature(f: &Feature, site: &FeatureSite, sink: &mut Sink<'_>) {
    let at = |field: &'static str| site.field(field);
    let name = &f.name;
    if f.description.trim().is_empty() {
        let (file, p) = at("description");
        sink.report(
            file,
            &rule::DESCRIPTION_EMPTY,
            &p,
            format!("feature \"{name}\" has an empty description"),
            Some("say in one line what the feature is".into()),
        );
    }
    let mut seen = BTreeSet::new();
    for (i, e) in f.affects.iter().enumerate() {
        if !seen.insert(*e) {
            let (file, p) = at("affects");
            sink.report(
                file,
                &rule::DUPLICATE_EFFECT,
                &format!("{p}/{i}"),
                format!("\"{}\" is listed twice", e.as_str()),
                Some("list each effect once".into()),
            );
        }
    }
    // Defaults: exactly one of a value or a derivation.
    match (&f.default, &f.default_from) {
        (None, None) => {
            let (file, _) = at("default");
            sink.report(
                file,
                &rule::DEFAULT_MISSING,
                &site.pointer,
                format!("feature \"{name}\" has no default"),
                Some("add \"default\", or \"default_from\" if the default is computed from other features".into()),
            );
        }
        (Some(_), Some(_)) => {
            let (file, p) = at("default_from");
            sink.report(
                file,
                &rule::DEFAULT_CONFLICT,
                &p,
                format!("feature \"{name}\" has both a default and default_from"),
                Some("keep one: a value, or how it is computed".into()),
            );
        }
        _ => {}
    }
    let [lo, hi] = f.bounds;
    let has_bounds = lo.is_some() || hi.is_some();
    if let (Some(l), Some(h)) = (lo, hi)
        && l > h
    {
        let (file, p) = at("bounds");
        sink.report(
            file,
            &rule::BOUNDS_ORDER,
            &p,
            format!("lower bound {l} is above upper bound {h}"),
            Some("bounds are [lower, upper]: swap them".into()),
        );
    }
    let (dfile, dptr) = at("default");
    let bounds_site = at("bounds");
    let type_name = kind_name(f.kind);
    let bounds_ordered = !matches!((lo, hi), (Some(l), Some(h)) if l > h);
    let check_in_bounds = |x: f64, sink: &mut Sink<'_>, what: &str, ptr: &str| {
        if bounds_ordered && !f.in_bounds(x) {
            sink.report(
                dfile,
                &rule::DEFAULT_OUT_OF_BOUNDS,
                ptr,
                format!(
                    "{what} {x} of \"{name}\" is outside its bounds {}",
                    fmt_bounds(&f.bounds)
                ),
                Some("change the default, or widen the bounds".into()),
            );
        }
    };
    if f.kind != FeatureType::Categorical && (f.choices.is_some() || f.choice_labels.is_some()) {
        let (file, p) = (site.file, format!("{}/choices", site.pointer));
        sink.report(
            file,
            &rule::CHOICES_NOT_APPLICABLE,
            &p,
            format!("only categorical features have choices; \"{name}\" is {type_name}"),
            Some("remove choices, or make the feature categorical".into()),
        );
    }
    // Integer kinds need integer bounds (for list_int they bound every element).
    if matches!(f.kind, FeatureType::Int | FeatureType::ListInt) {
        for (k, b) in [lo, hi].iter().enumerate() {
            if let Some(b) = b {
                let at = format!("{}/{k}", bounds_site.1);
                check_int(*b, "bound", type_name, name, bounds_site.0, &at, sink);
            }
        }
    }
    match f.kind {
        FeatureType::Float | FeatureType::Int => match &f.default {
            Some(Value::Number(x)) => {
                if f.kind == FeatureType::Int {
                    check_int(*x, "default", type_name, name, dfile, &dptr, sink);
                }
                check_in_bounds(*x, sink, "default", &dptr);
            }
            Some(other) => type_mismatch(other, type_name, name, dfile, &dptr, sink),
            None => {}
        },
        FeatureType::Bool => {
            if has_bounds {
                sink.report(
                    bounds_site.0,
                    &rule::BOUNDS_NOT_APPLICABLE,
                    &bounds_site.1,
                    format!("bool feature \"{name}\" cannot have bounds"),
                    Some("remove bounds".into()),
                );
            }
            if let Some(d) = &f.default
                && !matches!(d, Value::Bool(_))
            {
                type_mismatch(d, type_name, name, dfile, &dptr, sink);
            }
        }
        FeatureType::Categorical => {
            if has_bounds {
                sink.report(
                    bounds_site.0,
                    &rule::BOUNDS_NOT_APPLICABLE,
                    &bounds_site.1,
                    format!("categorical feature \"{name}\" cannot have bounds; its choices bound it"),
                    Some("remove bounds".into()),
                );
            }
            let cptr = format!("{}/choices", site.pointer);
            match &f.choices {
                None => sink.report(
                    site.file,
                    &rule::CATEGORICAL_CHOICES,
                    &site.pointer,
                    format!("categorical feature \"{name}\" has no choices"),
                    Some("add \"choices\": [...]".into()),
                ),
                Some(c) if c.is_empty() => sink.report(
                    site.file,
                    &rule::CATEGORICAL_CHOICES,
                    &cptr,
                    format!("categorical feature \"{name}\" has an empty list of choices"),
                    Some("list the allowed values".into()),
                ),
                Some(c) => {
                    for (i, x) in c.iter().enumerate() {
                        if c[..i].contains(x) {
                            sink.report(
                                site.file,
                                &rule::CATEGORICAL_CHOICES,
                                &format!("{cptr}/{i}"),
                                format!("choice {} is listed twice", scalar_text(x)),
                                Some("list each choice once".into()),
                            );
                        }
                    }
                    if let Some(labels) = &f.choice_labels
                        && labels.len() != c.len()
                    {
                        sink.report(
                            site.file,
                            &rule::CHOICE_LABELS,
                            &format!("{}/choice_labels", site.pointer),
                            format!("{} labels for {} choices", labels.len(), c.len()),
                            Some("give exactly one label per choice, in the same order".into()),
                        );
                    }
                    if let Some(d) = &f.default
                        && !c.iter().any(|x| scalar_eq_value(x, d))
                    {
                        sink.report(
                            dfile,
                            &rule::CATEGORICAL_DEFAULT,
                            &dptr,
                            format!("default {} of \"{name}\" is not one of its choices", value_text(d)),
                            Some(format!(
                                "use one of {}",
                                c.iter().map(scalar_text).collect::<Vec<_>>().join(", ")
                            )),
                        );
                    }
                }
            }
        }
        FeatureType::ListInt => match &f.default {
            Some(Value::List(items)) => {
                for (i, x) in items.iter().enumerate() {
                    let p = format!("{dptr}/{i}");
                    check_int(*x, "element", type_name, name, dfile, &p, sink);
                    check_in_bounds(*x, sink, "element", &p);
                }
            }
            Some(other) => type_mismatch(other, type_name, name, dfile, &dptr, sink),
            None => {}
        },
    }
}

fn kind_name(k: FeatureType) -> &'static str {
    match k {
        FeatureType::Float => "float",
        FeatureType::Int => "int",
        FeatureType::Bool => "bool",
        FeatureType::Categorical => "categorical",
        FeatureType::ListInt => "list_int",
    }
}

fn type_mismatch(v: &Value, type_name: &str, name: &str, file: usize, ptr: &str, sink: &mut Sink<'_>) {
    let mut help = format!(
        "a {type_name} feature needs a {} value",
        match type_name {
            "float" | "int" => "number",
            "bool" => "true/false",
            "list_int" => "list of integers",
            _ => "matching",
        }
    );
    if let Value::String(s) = v {
        let l = s.to_ascii_lowercase();
        if l.contains("inf") || l == "nan" {
            help = "JSON has no infinity or NaN; values must be finite numbers".into();
        } else if s.trim().parse::<f64>().is_ok() {
            help = format!("write the number without quotes: {}", s.trim());
        }
    }
    sink.report(
        file,
        &rule::TYPE_MISMATCH,
        ptr,
        format!(
            "{} is not a valid value for {type_name} feature \"{name}\"",
            value_text(v)
        ),
        Some(help),
    );
}

pub(crate) fn scalar_eq_value(s: &Scalar, v: &Value) -> bool {
    match (s, v) {
        (Scalar::Bool(a), Value::Bool(b)) => a == b,
        (Scalar::Number(a), Value::Number(b)) => a == b,
        (Scalar::String(a), Value::String(b)) => a == b,
        _ => false,
    }
}

fn scalar_text(s: &Scalar) -> String {
    match s {
        Scalar::Bool(b) => b.to_string(),
        Scalar::Number(x) => x.to_string(),
        Scalar::String(s) => quote(s),
    }
}

fn unknown_feature<'a>(
    known: impl Iterator<Item = &'a str> + Clone,
    name: &str,
    file: usize,
    ptr: &str,
    sink: &mut Sink<'_>,
) {
    let help = match did_you_mean(name, known.clone()) {
        Some(s) => format!("did you mean \"{s}\"?"),
        None => format!("features of this environment: {}", known.collect::<Vec<_>>().join(", ")),
    };
    sink.report(
        file,
        &rule::UNKNOWN_FEATURE,
        ptr,
        format!("no feature named {}", quote(name)),
        Some(help),
    );
}

fn check_set_name(name: &str, file: usize, ptr: &str, what: &str, sink: &mut Sink<'_>) {
    let ok = name.chars().next().is_some_and(|c| c.is_ascii_lowercase())
        && name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
    if !ok {
        sink.report(file, &rule::INVALID_NAME, ptr, format!("{what} name {} is not snake_case", quote(name)), Some("use lowercase letters, digits and underscores, starting with a letter (it becomes part of ENV/SET names and file names)".into()));
    }
}

/// A sampler against its feature: exactly the check `sample` and `freeze` run
/// ([`FeatureSampler::compile`]), reported at the parameter at fault.
fn check_sampler(s: &Sampler, f: &Feature, at_bounds: AtBounds, file: usize, ptr: &str, sink: &mut Sink<'_>) {
    let err = match FeatureSampler::compile(s, FeatureInfo::from_feature(f), at_bounds) {
        Ok(_) => return,
        Err(e) => e,
    };
    let SamplingError::InvalidSampler {
        kind,
        message,
        field,
        problem,
        ..
    } = err
    else {
        // The feature itself cannot be sampled (reversed bounds, or int bounds holding no integer):
        // `bounds-order` / `int-not-integral` / `int-out-of-range` already refuse the feature.
        return;
    };
    let (r, help) = match problem {
        SamplerProblem::Params => (&rule::DISTRIBUTION_PARAMS, params_help(kind)),
        SamplerProblem::Type => (
            &rule::DISTRIBUTION_TYPE,
            match f.kind {
                FeatureType::Int => {
                    "int features take int_uniform, categorical or constant (continuous samplers would produce non-integers)"
                }
                FeatureType::Categorical => {
                    "categorical features take categorical or constant, with values among the feature's choices"
                }
                FeatureType::Bool => "bool features take categorical or constant",
                FeatureType::ListInt => "list_int features take a constant list of integers",
                FeatureType::Float => "use a sampler that produces numbers",
            },
        ),
        SamplerProblem::Support => (
            &rule::DISTRIBUTION_SUPPORT,
            "every draw would be clipped or rejected: move the distribution inside the bounds",
        ),
    };
    let at = if field.is_empty() {
        ptr.to_string()
    } else {
        format!("{ptr}/{field}")
    };
    sink.report(
        file,
        r,
        &at,
        format!("{kind} sampler of {}: {message}", quote(&f.name)),
        Some(help.into()),
    );
}

fn params_help(kind: &str) -> &'static str {
    match kind {
        "normal" => {
            "a normal needs a finite mean and a std > 0, with mean ± 40·std finite; use constant for a fixed value"
        }
        "relative_normal" => {
            "sigma_rel and fallback_std must be > 0 (the paper uses 0.1, 0.25 or 0.5), and the feature needs a numeric default"
        }
        "truncated_normal" => "a truncated normal needs a finite mean, std > 0 and finite low < high",
        "uniform" => "write finite low < high whose width is finite; use constant for a single value",
        "log_uniform" => "log_uniform needs 0 < low < high; use uniform for ranges that include 0 or negatives",
        "int_uniform" => "write low ≤ high, both within ±2^53 (9007199254740992)",
        "categorical" => {
            "list at least one choice; weights are relative, finite and ≥ 0 with a positive sum, one per choice"
        }
        "interval_mixture" => {
            "write [low, high] intervals with finite low < high; give weights (one per interval) or stratified, not both"
        }
        _ => "see the sampler's parameters in the spec-language reference (docs/reference/spec-language.md)",
    }
}

fn check_instance_set(r: &Resolved, name: &str, set: &InstanceSet, sink: &mut Sink<'_>) {
    let spec = &r.spec;
    let file = r.file;
    let base = format!("/instance_sets/{}", escape_token(name));
    check_set_name(name, file, &base, "instance set", sink);
    if set.description.trim().is_empty() {
        sink.report(
            file,
            &rule::DESCRIPTION_EMPTY,
            &format!("{base}/description"),
            "the description is empty",
            Some("say what the set is for (train/test, which experiment)".into()),
        );
    }
    let n_sources = usize::from(set.sampled.is_some())
        + usize::from(set.explicit.is_some())
        + usize::from(set.grid.is_some())
        + usize::from(set.split.is_some());
    if n_sources != 1 {
        sink.report(file, &rule::INSTANCE_SET_SOURCE, &base, format!("instance set \"{name}\" must have exactly one of sampled, explicit, grid, split (has {n_sources})"), Some("sampled: draws from a named distribution; explicit: a list of named contexts; grid: a regular grid over one feature; split: train, interpolation or extrapolation points of a region".into()));
    }
    let mut any_out = false;
    // Reports a value outside its feature's bounds (unless allowed); true when it was outside.
    let out_of_bounds = |fname: &str, x: f64, ptr: &str, sink: &mut Sink<'_>| -> bool {
        let Some(f) = spec.feature(fname) else { return false };
        if f.in_bounds(x) {
            return false;
        }
        {
            if !set.allow_out_of_bounds {
                sink.report(file, &rule::INSTANCE_OUT_OF_BOUNDS, ptr, format!("{x} is outside the bounds {} of \"{}\"", fmt_bounds(&f.bounds), f.name), Some("fix the value, or set \"allow_out_of_bounds\": true on the set if this is a deliberate out-of-distribution test".into()));
            }
        }
        true
    };
    if let Some(s) = &set.sampled {
        let p = format!("{base}/sampled");
        if !spec.distributions.contains_key(&s.distribution) {
            let known = spec.distributions.keys().map(String::as_str);
            let help = match did_you_mean(&s.distribution, known.clone()) {
                Some(k) => format!("did you mean \"{k}\"?"),
                None if spec.distributions.is_empty() => {
                    "this spec defines no distributions; add one under \"distributions\"".into()
                }
                None => format!("distributions of {}: {}", spec.id, known.collect::<Vec<_>>().join(", ")),
            };
            sink.report(
                file,
                &rule::UNKNOWN_DISTRIBUTION,
                &format!("{p}/distribution"),
                format!("no distribution named \"{}\"", s.distribution),
                Some(help),
            );
        }
        if s.size == 0 || s.size > MAX_INSTANCES {
            sink.report(
                file,
                &rule::INSTANCE_SET_SIZE,
                &format!("{p}/size"),
                format!("size {} is not in 1..={MAX_INSTANCES}", s.size),
                Some("an instance set has at least one and at most a million instances".into()),
            );
        }
        let varied = spec
            .distributions
            .get(&s.distribution)
            .map_or(0, |d| d.features.len() as u64);
        if s.size <= MAX_INSTANCES && s.size.saturating_mul(varied) > MAX_SET_VALUES {
            sink.report(
                file,
                &rule::INSTANCE_SET_SIZE,
                &format!("{p}/size"),
                format!(
                    "{} instances × {varied} varied features = {} values, more than {MAX_SET_VALUES} per set",
                    s.size,
                    s.size.saturating_mul(varied)
                ),
                Some("sample fewer instances, or split the set (memory grows by about 1.5 KB per value)".into()),
            );
        }
    }
    if let Some(list) = &set.explicit {
        let p = format!("{base}/explicit");
        if list.is_empty() {
            sink.report(
                file,
                &rule::INSTANCE_SET_SIZE,
                &p,
                "the explicit list is empty",
                Some("list at least one named context".into()),
            );
        }
        let mut names = BTreeSet::new();
        for (i, inst) in list.iter().enumerate() {
            let ip = format!("{p}/{i}");
            if !names.insert(inst.name.as_str()) {
                sink.report(
                    file,
                    &rule::DUPLICATE_INSTANCE,
                    &format!("{ip}/name"),
                    format!("instance name \"{}\" is used twice in this set", inst.name),
                    Some("instance names identify instances in results: make them unique".into()),
                );
            }
            for (fname, v) in &inst.context {
                let fp = format!("{ip}/context/{}", escape_token(fname));
                match spec.feature(fname) {
                    None => unknown_feature(spec.feature_names(), fname, file, &fp, sink),
                    Some(f) => match (f.kind, v) {
                        (FeatureType::Float | FeatureType::Int, Value::Number(x)) => {
                            if f.kind == FeatureType::Int {
                                check_int(*x, "value", "int", &f.name, file, &fp, sink);
                            }
                            any_out |= out_of_bounds(fname, *x, &fp, sink);
                        }
                        (FeatureType::Bool, Value::Bool(_)) => {}
                        (FeatureType::Categorical, v)
                            if f.choices
                                .as_ref()
                                .is_some_and(|c| c.iter().any(|x| scalar_eq_value(x, v))) => {}
                        (FeatureType::ListInt, Value::List(_)) => {}
                        _ => type_mismatch(v, kind_name(f.kind), &f.name, file, &fp, sink),
                    },
                }
            }
        }
    }
    if let Some(g) = &set.grid {
        let p = format!("{base}/grid");
        match spec.feature(&g.feature) {
            None => unknown_feature(spec.feature_names(), &g.feature, file, &format!("{p}/feature"), sink),
            Some(f) if !matches!(f.kind, FeatureType::Float | FeatureType::Int) => {
                sink.report(
                    file,
                    &rule::DISTRIBUTION_TYPE,
                    &format!("{p}/feature"),
                    format!(
                        "a grid needs a numeric feature; \"{}\" is {}",
                        f.name,
                        kind_name(f.kind)
                    ),
                    None,
                );
            }
            Some(_) => {}
        }
        if !(g.step > 0.0) || !(g.from <= g.to) {
            sink.report(
                file,
                &rule::GRID_PARAMS,
                &p,
                format!("grid from {} to {} step {} is empty or reversed", g.from, g.to, g.step),
                Some("use from ≤ to and step > 0".into()),
            );
        } else {
            let count = ((g.to - g.from) / g.step).floor() + 1.0;
            if count > MAX_INSTANCES as f64 {
                sink.report(
                    file,
                    &rule::INSTANCE_SET_SIZE,
                    &p,
                    format!("the grid has {count} points, more than {MAX_INSTANCES}"),
                    Some("use a larger step".into()),
                );
            } else {
                for x in crate::spec::grid_points(g) {
                    if out_of_bounds(&g.feature, x, &p, sink) {
                        any_out = true;
                        break; // one diagnostic per grid is enough
                    }
                }
            }
        }
    }
    if let Some(sp) = &set.split {
        let p = format!("{base}/split");
        // A broken region is reported once, under /regions.
        if !spec.regions.contains_key(&sp.region) || crate::instances::split::check_region(spec, &sp.region).is_ok() {
            match crate::instances::split::split_points(spec, sp) {
                Err(e) => sink.report(file, &rule::SPLIT_DEFINITION, &p, e, Some(SPLIT_HELP.into())),
                Ok(points) => {
                    'points: for pt in &points {
                        for (fname, &x) in &pt.context {
                            if out_of_bounds(fname, x, &p, sink) {
                                any_out = true;
                                break 'points; // one diagnostic per set is enough
                            }
                        }
                    }
                }
            }
        }
    }
    if set.allow_out_of_bounds && !any_out && (set.explicit.is_some() || set.grid.is_some() || set.split.is_some()) {
        sink.report(
            file,
            &rule::NEEDLESS_ALLOW_OUT_OF_BOUNDS,
            &format!("{base}/allow_out_of_bounds"),
            "allow_out_of_bounds is set but every value is inside the bounds",
            Some("remove it, so an accidental out-of-bounds value is caught".into()),
        );
    }
}
