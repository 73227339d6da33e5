//! A context checked against its spec: every name known, every value of the right type, finite
//! and (unless explicitly allowed) inside its bounds; defaults filled in. Also the runtime options
//! (`continuous`, `hardcore`, …) that select an environment's variant, checked against the
//! registry's declarations.
//!
//! A context is a plain value (`Context`: feature name → value). Nothing here builds an
//! environment: [`registry::make`](super::registry::make) does, from what this module resolves.

use std::collections::BTreeMap;

use carl_spec_core::spec::model::{EnvSpec, FeatureType, Scalar, Value};
use carl_spec_core::suggest::did_you_mean;
use carl_spec_core::text::quote;

/// Feature values by name (canonical names or aliases); missing features take their defaults.
pub type Context = BTreeMap<String, Value>;

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MakeError {
    #[error(
        "{env}: the context gives feature {feature} twice, as {} and {}; give it once",
        quote(first),
        quote(second)
    )]
    FeatureTwice {
        env: String,
        feature: String,
        first: String,
        second: String,
    },
    #[error("environment \"{env}\" has a spec but no runtime yet; runtimes exist for: {available}")]
    NoRuntime { env: String, available: String },
    #[error("{env} has no option {}; {valid}", quote(name))]
    UnknownOption { env: String, name: String, valid: String },
    #[error("{env}: option {name} needs {expected}, got {got}")]
    BadOption {
        env: String,
        name: String,
        expected: String,
        got: String,
    },
    #[error("{env} has no context feature {}{hint}; valid names: {valid}", quote(name))]
    UnknownFeature {
        env: String,
        name: String,
        hint: String,
        valid: String,
    },
    #[error("{env}: {name} = {value} is outside its bounds {bounds} (use --allow-out-of-bounds to run it anyway)")]
    OutOfBounds {
        env: String,
        name: String,
        value: f64,
        bounds: String,
    },
    #[error("{env}: {name} needs a {expected} value, got {got}")]
    BadValue {
        env: String,
        name: String,
        expected: &'static str,
        got: String,
    },
    #[error(
        "{env}: {name} is a list, and a context holds numbers only; give it as an option instead \
         (Python: options={{\"{name}\": [1, 2]}}; CLI: --option {name}=1,2)"
    )]
    ListFeature { env: String, name: String },
    #[error(
        "{env}: {name} = {value} acts only with option {option}, which is off (its default {default} is used without it); \
         set the option (Python: options={{\"{option}\": True}}; CLI: --option {option}=true) or leave {name} out"
    )]
    NeedsOption {
        env: String,
        name: String,
        value: f64,
        default: String,
        option: String,
    },
    #[error("{env}: {name} = {value} is not finite")]
    NotFinite { env: String, name: String, value: f64 },
    /// The runtime could not be built from a valid context: its data is missing or corrupt, or
    /// the context is one the runtime cannot run (e.g. a Mario level width CARL crashes on).
    #[error("{env}: {message}")]
    Runtime { env: String, message: String },
}

/// Options for [`make_with`](super::registry::make_with).
#[derive(Debug, Clone, Copy, Default)]
pub struct MakeOptions {
    /// Accept values outside the spec's bounds (deliberate out-of-distribution runs).
    pub allow_out_of_bounds: bool,
}

/// Check a context against the spec and return every feature's numeric value (defaults filled in),
/// keyed by canonical name, in spec order.
pub fn resolve_context(spec: &EnvSpec, context: &Context, opts: MakeOptions) -> Result<Vec<(String, f64)>, MakeError> {
    let env = spec.id.clone();
    for name in context.keys() {
        if spec.feature(name).is_none() {
            let names = spec.feature_names();
            let hint = did_you_mean(name, names.clone())
                .map(|s| format!(" (did you mean \"{s}\"?)"))
                .unwrap_or_default();
            return Err(MakeError::UnknownFeature {
                env,
                name: name.clone(),
                hint,
                valid: names.collect::<Vec<_>>().join(", "),
            });
        }
    }
    // One feature named twice (an alias and its canonical name, or two aliases) would silently
    // take one of the values.
    let mut seen: Vec<(usize, &str)> = Vec::new();
    for name in context.keys() {
        let Some(i) = spec.feature_index(name) else { continue };
        if let Some((_, first)) = seen.iter().find(|(j, _)| *j == i) {
            return Err(MakeError::FeatureTwice {
                env,
                feature: spec.features[i].name.clone(),
                first: (*first).to_string(),
                second: name.clone(),
            });
        }
        seen.push((i, name));
    }
    let mut out = Vec::with_capacity(spec.features.len());
    for f in &spec.features {
        let given = context.iter().find(|(k, _)| f.matches_name(k)).map(|(_, v)| v);
        if f.kind == FeatureType::ListInt && given.is_some() {
            return Err(MakeError::ListFeature {
                env,
                name: f.name.clone(),
            });
        }
        let value = given.or(f.default.as_ref());
        let Some(value) = value else { continue };
        let x = match (f.kind, value) {
            (FeatureType::Float | FeatureType::Int, Value::Number(x)) => *x,
            (FeatureType::Bool, Value::Bool(b)) => f64::from(u8::from(*b)),
            // A categorical feature takes one of its numeric choices, or the label of one.
            (FeatureType::Categorical, Value::Number(x)) => *x,
            (FeatureType::Categorical, Value::String(label)) => {
                let idx = f
                    .choice_labels
                    .as_ref()
                    .and_then(|labels| labels.iter().position(|l| l == label));
                // String choices (e.g. rna_design's dataset) resolve to the index of the choice
                // named by `label` or by its choice label.
                let string_choice = f.choices.as_ref().and_then(|choices| {
                    choices
                        .iter()
                        .position(|c| matches!(c, Scalar::String(s) if s == label))
                        .or(idx.filter(|&i| matches!(choices.get(i), Some(Scalar::String(_)))))
                });
                match idx.and_then(|i| f.choices.as_ref()?.get(i)) {
                    Some(Scalar::Number(x)) => *x,
                    _ if string_choice.is_some() => string_choice.unwrap_or_default() as f64,
                    _ => {
                        return Err(MakeError::BadValue {
                            env,
                            name: f.name.clone(),
                            expected: "choice or choice label",
                            got: label.clone(),
                        });
                    }
                }
            }
            (_, v) => {
                return Err(MakeError::BadValue {
                    env,
                    name: f.name.clone(),
                    expected: "numeric",
                    got: carl_spec_core::validate::value_text(v),
                });
            }
        };
        if !x.is_finite() {
            return Err(MakeError::NotFinite {
                env,
                name: f.name.clone(),
                value: x,
            });
        }
        if f.kind == FeatureType::Int && x.fract() != 0.0 {
            return Err(MakeError::BadValue {
                env,
                name: f.name.clone(),
                expected: "integer",
                got: x.to_string(),
            });
        }
        if f.kind == FeatureType::Categorical && given.is_some() && !opts.allow_out_of_bounds {
            let choices = f.choices.as_deref().unwrap_or_default();
            let numeric = choices.iter().any(|c| matches!(c, Scalar::Number(_)));
            if numeric && !choices.iter().any(|c| matches!(c, Scalar::Number(v) if *v == x)) {
                return Err(MakeError::OutOfBounds {
                    env,
                    name: f.name.clone(),
                    value: x,
                    bounds: format!(
                        "choices {}",
                        carl_spec_core::validate::value_text(&Value::List(
                            choices
                                .iter()
                                .filter_map(|c| match c {
                                    Scalar::Number(v) => Some(*v),
                                    _ => None,
                                })
                                .collect()
                        ))
                    ),
                });
            }
        }
        if given.is_some() && !opts.allow_out_of_bounds && !f.in_bounds(x) {
            let b = |v: Option<f64>, inf: &str| v.map_or(inf.to_string(), |v| v.to_string());
            return Err(MakeError::OutOfBounds {
                env,
                name: f.name.clone(),
                value: x,
                bounds: format!("[{}, {}]", b(f.bounds[0], "-inf"), b(f.bounds[1], "inf")),
            });
        }
        out.push((f.name.clone(), x));
    }
    Ok(out)
}

/// Refuse a feature that acts only with an option (its spec's `requires_option`) at a value other
/// than its default while that option is off: the value would be silently dead. `values` are
/// [`resolve_context`]'s.
pub fn check_option_features(
    spec: &EnvSpec,
    values: &[(String, f64)],
    options: &OptionValues,
) -> Result<(), MakeError> {
    for f in &spec.features {
        let Some(option) = &f.requires_option else { continue };
        if options.flag(option) {
            continue;
        }
        let Some((_, x)) = values.iter().find(|(n, _)| *n == f.name) else {
            continue;
        };
        let default = f.default_f64();
        if default != Some(*x) {
            return Err(MakeError::NeedsOption {
                env: spec.id.clone(),
                name: f.name.clone(),
                value: *x,
                default: default.map_or_else(|| "(none)".to_string(), |d| d.to_string()),
                option: option.clone(),
            });
        }
    }
    Ok(())
}

/// Write every `(feature, value)` into a runtime's parameters with `set`; a name the runtime does
/// not know means the spec and the runtime disagree.
pub fn apply(
    id: &str,
    values: &[(String, f64)],
    mut set: impl FnMut(&str, f64) -> Result<(), super::api::UnknownFeature>,
) -> Result<(), MakeError> {
    for (name, x) in values {
        set(name, *x).map_err(|e| MakeError::UnknownFeature {
            env: id.to_string(),
            name: name.clone(),
            hint: " (the spec names a feature the runtime does not know)".into(),
            valid: e.known,
        })?;
    }
    Ok(())
}

/// Runtime options by name (e.g. `continuous = true`): which variant of an environment to build.
/// Unlike context features they are not sampled or frozen in instance sets; they pick e.g.
/// `LunarLanderContinuous` over `LunarLander`.
pub type EnvOptions = BTreeMap<String, Value>;

/// An option an environment declares in the registry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OptionSpec {
    pub name: &'static str,
    pub help: &'static str,
    pub kind: OptionKind,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum OptionKind {
    /// `true` / `false`.
    Bool { default: bool },
    /// A finite number in `[min, max]`.
    Number { default: f64, min: f64, max: f64 },
    /// A non-empty list of integer ids in `0..=u32::MAX` (default: none given). Given as a list
    /// (JSON / Python), one number, or comma-separated text (`--option NAME=1,2,3`).
    Ids,
}

/// Every declared option's value (given or default), as numbers (`bool`: 0 or 1), and the
/// id lists that were given.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct OptionValues {
    numbers: Vec<(&'static str, f64)>,
    ids: Vec<(&'static str, Vec<u32>)>,
}

impl OptionValues {
    /// The value of a declared option (0 for a name that was not declared).
    pub fn get(&self, name: &str) -> f64 {
        self.numbers.iter().find(|(n, _)| *n == name).map_or(0.0, |(_, v)| *v)
    }
    pub fn flag(&self, name: &str) -> bool {
        self.get(name) != 0.0
    }
    /// The ids given for an [`OptionKind::Ids`] option (`None`: not given).
    pub fn ids(&self, name: &str) -> Option<&[u32]> {
        self.ids.iter().find(|(n, _)| *n == name).map(|(_, v)| v.as_slice())
    }
    /// `(name, value)` of every declared number or bool option, in declaration order.
    pub fn pairs(&self) -> &[(&'static str, f64)] {
        &self.numbers
    }
}

/// An [`OptionKind::Ids`] value: a list of whole numbers, one number, or text "1,2,3".
fn parse_ids(value: &Value) -> Option<Vec<u32>> {
    let id = |x: f64| (x.fract() == 0.0 && (0.0..=f64::from(u32::MAX)).contains(&x)).then_some(x as u32);
    let ids: Option<Vec<u32>> = match value {
        Value::List(xs) => xs.iter().map(|x| id(*x)).collect(),
        Value::Number(x) => id(*x).map(|i| vec![i]),
        Value::String(text) => text
            .split(',')
            .map(|part| part.trim().parse::<f64>().ok().and_then(id))
            .collect(),
        Value::Bool(_) => None,
    };
    ids.filter(|v| !v.is_empty())
}

/// Check `given` against the declared options of environment `env` and fill in defaults.
pub fn resolve_options(env: &str, declared: &[OptionSpec], given: &EnvOptions) -> Result<OptionValues, MakeError> {
    for name in given.keys() {
        if !declared.iter().any(|o| o.name == name) {
            let valid = if declared.is_empty() {
                "it takes no options".to_string()
            } else {
                let names: Vec<&str> = declared.iter().map(|o| o.name).collect();
                let hint = did_you_mean(name, names.iter().copied())
                    .map(|s| format!("did you mean \"{s}\"? "))
                    .unwrap_or_default();
                format!("{hint}valid options: {}", names.join(", "))
            };
            return Err(MakeError::UnknownOption {
                env: env.to_string(),
                name: name.clone(),
                valid,
            });
        }
    }
    let bad = |o: &OptionSpec, expected: String, got: &Value| MakeError::BadOption {
        env: env.to_string(),
        name: o.name.to_string(),
        expected,
        got: carl_spec_core::validate::value_text(got),
    };
    let mut out = Vec::with_capacity(declared.len());
    let mut ids = Vec::new();
    for o in declared {
        let v = given.get(o.name);
        let x = match (o.kind, v) {
            (OptionKind::Ids, None) => continue,
            (OptionKind::Ids, Some(got)) => {
                let list = parse_ids(got).ok_or_else(|| {
                    bad(
                        o,
                        "a non-empty list of whole numbers >= 0 (Python: a list; CLI: NAME=1,2,3)".into(),
                        got,
                    )
                })?;
                ids.push((o.name, list));
                continue;
            }
            (OptionKind::Bool { default }, None) => f64::from(u8::from(default)),
            (OptionKind::Number { default, .. }, None) => default,
            (OptionKind::Bool { .. }, Some(Value::Bool(b))) => f64::from(u8::from(*b)),
            (OptionKind::Bool { .. }, Some(got)) => return Err(bad(o, "true or false".into(), got)),
            (OptionKind::Number { min, max, .. }, Some(Value::Number(x)))
                if x.is_finite() && (min..=max).contains(x) =>
            {
                *x
            }
            (OptionKind::Number { min, max, .. }, Some(got)) => {
                return Err(bad(o, format!("a number in [{min}, {max}]"), got));
            }
        };
        out.push((o.name, x));
    }
    Ok(OptionValues { numbers: out, ids })
}
