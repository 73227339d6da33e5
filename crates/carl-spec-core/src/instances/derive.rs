//! Computing instance sets from their definitions: the single source of instance values.

use std::collections::BTreeMap;

use super::frozen::{FORMAT, FrozenSet, Instance, Provenance, set_distribution, set_region, spec_digest};
use crate::sampling::{self, FeatureInfo, SamplingError};
use crate::spec::model::{Distribution, EnvSpec, Feature, Value};
use crate::spec::raw::{MAX_INSTANCES, MAX_SET_VALUES};
use crate::suggest::did_you_mean;

#[derive(Debug, thiserror::Error)]
pub enum DeriveError {
    #[error("{env} has no instance set \"{set}\"{hint}")]
    UnknownSet { env: String, set: String, hint: String },
    #[error("{env} has no distribution \"{name}\"{hint}")]
    UnknownDistribution { env: String, name: String, hint: String },
    #[error("{env}: no feature \"{name}\"{hint}")]
    UnknownFeature { env: String, name: String, hint: String },
    #[error("{context}: {source}")]
    Sampling { context: String, source: SamplingError },
    #[error("size {0} is not in 1..={MAX_INSTANCES}")]
    Size(u64),
    #[error(
        "{n} instances × {features} varied feature(s) = {} values, more than the limit of {MAX_SET_VALUES} per set \
         (about 1.5 KB of memory per value); sample fewer instances",
        n.saturating_mul(*features)
    )]
    TooManyValues { n: u64, features: u64 },
    #[error("{0}")]
    Invalid(String),
}

fn hint<'a>(name: &str, known: impl Iterator<Item = &'a str> + Clone) -> String {
    match did_you_mean(name, known.clone()) {
        Some(s) => format!("; did you mean \"{s}\"?"),
        None => {
            let all: Vec<&str> = known.collect();
            if all.is_empty() {
                String::new()
            } else {
                format!("; known: {}", all.join(", "))
            }
        }
    }
}

/// Draw `n` contexts from a named distribution. Columns are the distribution's features by canonical
/// name; each feature has its own stream (seed, feature name), so values don't depend on which other
/// features the distribution varies.
pub fn sample_distribution(
    spec: &EnvSpec,
    dist_name: &str,
    dist: &Distribution,
    n: u64,
    seed: u64,
) -> Result<(Vec<String>, Vec<Vec<Value>>), DeriveError> {
    if n == 0 || n > MAX_INSTANCES {
        return Err(DeriveError::Size(n));
    }
    let features = dist.features.len() as u64;
    if n.saturating_mul(features) > MAX_SET_VALUES {
        return Err(DeriveError::TooManyValues { n, features });
    }
    let mut cols = Vec::new();
    for (name, sampler) in &dist.features {
        let f = spec.feature(name).ok_or_else(|| DeriveError::UnknownFeature {
            env: spec.id.clone(),
            name: name.clone(),
            hint: hint(name, spec.feature_names()),
        })?;
        cols.push((FeatureInfo::from_feature(f), sampler));
    }
    let names = cols.iter().map(|(i, _)| i.name.clone()).collect();
    let rows =
        sampling::sample_contexts(seed, n as usize, &cols, dist.at_bounds).map_err(|source| DeriveError::Sampling {
            context: format!("{}/{dist_name}", spec.id),
            source,
        })?;
    Ok((names, rows))
}

/// Ad-hoc sampling (`carl-spec sample`): a set that is not declared in the spec.
pub fn sample_adhoc(spec: &EnvSpec, dist_name: &str, n: u64, seed: u64) -> Result<FrozenSet, DeriveError> {
    spec.distributions
        .get(dist_name)
        .ok_or_else(|| DeriveError::UnknownDistribution {
            env: spec.id.clone(),
            name: dist_name.to_string(),
            hint: hint(dist_name, spec.distributions.keys().map(String::as_str)),
        })?;
    let set = crate::spec::model::InstanceSet {
        description: format!("ad-hoc sample of {dist_name}"),
        role: None,
        allow_out_of_bounds: false,
        sampled: Some(crate::spec::raw::SampledSet {
            distribution: dist_name.to_string(),
            size: n,
            seed,
        }),
        explicit: None,
        grid: None,
        split: None,
    };
    build(spec, &format!("{dist_name}_n{n}_seed{seed}"), &set)
}

/// Derive a declared set by name.
pub fn derive_set(spec: &EnvSpec, set_name: &str) -> Result<FrozenSet, DeriveError> {
    let set = spec
        .instance_sets
        .get(set_name)
        .ok_or_else(|| DeriveError::UnknownSet {
            env: spec.id.clone(),
            set: set_name.to_string(),
            hint: hint(set_name, spec.instance_sets.keys().map(String::as_str)),
        })?;
    build(spec, set_name, set)
}

fn build(spec: &EnvSpec, set_name: &str, set: &crate::spec::model::InstanceSet) -> Result<FrozenSet, DeriveError> {
    let (features, instances): (Vec<String>, Vec<Instance>) = if let Some(s) = &set.sampled {
        let d = spec
            .distributions
            .get(&s.distribution)
            .ok_or_else(|| DeriveError::UnknownDistribution {
                env: spec.id.clone(),
                name: s.distribution.clone(),
                hint: hint(&s.distribution, spec.distributions.keys().map(String::as_str)),
            })?;
        let (names, rows) = sample_distribution(spec, &s.distribution, d, s.size, s.seed)?;
        let instances = rows
            .into_iter()
            .enumerate()
            .map(|(id, row)| Instance {
                id,
                name: None,
                split: None,
                context: names.iter().cloned().zip(row).collect(),
            })
            .collect();
        (names, instances)
    } else if let Some(list) = &set.explicit {
        let mut names: Vec<String> = Vec::new();
        let mut instances = Vec::new();
        for (id, inst) in list.iter().enumerate() {
            let mut context = BTreeMap::new();
            for (k, v) in &inst.context {
                let f = spec.feature(k).ok_or_else(|| DeriveError::UnknownFeature {
                    env: spec.id.clone(),
                    name: k.clone(),
                    hint: hint(k, spec.feature_names()),
                })?;
                check_value(spec, f, v, set.allow_out_of_bounds, &inst.name)?;
                if !names.contains(&f.name) {
                    names.push(f.name.clone());
                }
                context.insert(f.name.clone(), v.clone());
            }
            instances.push(Instance {
                id,
                name: Some(inst.name.clone()),
                split: inst.split,
                context,
            });
        }
        (names, instances)
    } else if let Some(g) = &set.grid {
        let f = spec.feature(&g.feature).ok_or_else(|| DeriveError::UnknownFeature {
            env: spec.id.clone(),
            name: g.feature.clone(),
            hint: hint(&g.feature, spec.feature_names()),
        })?;
        let points: Vec<f64> = crate::spec::grid_points(g).take(MAX_INSTANCES as usize + 1).collect();
        if points.is_empty() || points.len() as u64 > MAX_INSTANCES {
            return Err(DeriveError::Size(points.len() as u64));
        }
        let mut instances = Vec::with_capacity(points.len());
        for (id, x) in points.into_iter().enumerate() {
            let v = Value::Number(x);
            check_value(spec, f, &v, set.allow_out_of_bounds, &format!("#{id}"))?;
            instances.push(Instance {
                id,
                name: None,
                split: None,
                context: BTreeMap::from([(f.name.clone(), v)]),
            });
        }
        (vec![f.name.clone()], instances)
    } else if let Some(sp) = &set.split {
        let points = super::split::split_points(spec, sp)
            .map_err(|e| DeriveError::Invalid(format!("{}/{set_name}: {e}", spec.id)))?;
        let mut names: Vec<String> = Vec::new();
        let mut instances = Vec::with_capacity(points.len());
        for (id, p) in points.into_iter().enumerate() {
            let mut context = BTreeMap::new();
            for (k, x) in p.context {
                let f = spec.feature(&k).expect("split points name resolved features");
                let v = Value::Number(x);
                let who = p.name.clone().unwrap_or_else(|| format!("#{id}"));
                check_value(spec, f, &v, set.allow_out_of_bounds, &who)?;
                if !names.contains(&k) {
                    names.push(k.clone());
                }
                context.insert(k, v);
            }
            instances.push(Instance {
                id,
                name: p.name,
                split: p.split,
                context,
            });
        }
        (names, instances)
    } else {
        return Err(DeriveError::Invalid(format!(
            "{}/{set_name} has no sampled, explicit, grid or split definition",
            spec.id
        )));
    };
    Ok(FrozenSet {
        format: FORMAT.to_string(),
        env: spec.id.clone(),
        set: set_name.to_string(),
        description: set.description.clone(),
        role: set.role.clone(),
        provenance: Provenance {
            generator: format!("carl-spec {}", env!("CARGO_PKG_VERSION")),
            rng: sampling::GENERATOR.to_string(),
            sampler_version: sampling::SAMPLER_VERSION.to_string(),
            spec_digest: spec_digest(spec, set),
            definition: set.clone(),
            distribution: set_distribution(spec, set),
            region: set_region(spec, set).cloned(),
        },
        features,
        instances,
        content_hash: String::new(),
    }
    .with_hash())
}

fn check_value(spec: &EnvSpec, f: &Feature, v: &Value, allow_oob: bool, who: &str) -> Result<(), DeriveError> {
    if let Value::Number(x) = v
        && !allow_oob
        && !f.in_bounds(*x)
    {
        return Err(DeriveError::Invalid(format!(
            "{}: instance {who}: {} = {x} is outside its bounds (set allow_out_of_bounds on the set if deliberate)",
            spec.id, f.name
        )));
    }
    Ok(())
}
