//! Resolution: merge included fragments into environment specs, apply overrides, and remember
//! where every resolved field came from so diagnostics can point at the right file and line.

use std::collections::BTreeMap;

use super::model::{EnvSpec, Feature};
use super::raw::{FeaturePatch, RawEnvSpec, RawFeature, RawFragment};
use crate::diagnostics::Sink;
use crate::diagnostics::rules as rule;
use crate::suggest::did_you_mean;

/// Where a resolved feature (and each overridden field) is written: (file index, JSON pointer).
#[derive(Debug, Clone, Default)]
pub struct FeatureSite {
    pub file: usize,
    pub pointer: String,
    pub overrides: BTreeMap<&'static str, (usize, String)>,
}

impl FeatureSite {
    /// The site of one field of the feature (`default`, `bounds`, …).
    pub fn field(&self, field: &'static str) -> (usize, String) {
        match self.overrides.get(field) {
            Some(site) => site.clone(),
            None => (self.file, format!("{}/{field}", self.pointer)),
        }
    }
}

/// An environment spec with the source sites of its parts.
#[derive(Debug, Clone)]
pub struct Resolved {
    pub spec: EnvSpec,
    pub file: usize,
    pub sites: Vec<FeatureSite>,
}

/// A fragment known to the resolver, with the file it came from.
pub struct FragmentEntry<'a> {
    pub fragment: &'a RawFragment,
    pub file: usize,
}

pub fn resolve(
    raw: &RawEnvSpec,
    file: usize,
    origin: &str,
    fragments: &BTreeMap<String, FragmentEntry<'_>>,
    sink: &mut Sink<'_>,
) -> Resolved {
    let mut features: Vec<Feature> = Vec::new();
    let mut sites: Vec<FeatureSite> = Vec::new();

    for (i, inc) in raw.include.iter().enumerate() {
        let inc_ptr = format!("/include/{i}");
        let Some(entry) = fragments.get(&inc.fragment) else {
            let names: Vec<&str> = fragments.keys().map(String::as_str).collect();
            sink.report(
                file,
                &rule::UNKNOWN_FRAGMENT,
                &format!("{inc_ptr}/fragment"),
                format!("no shared fragment named \"{}\"", inc.fragment),
                Some(match did_you_mean(&inc.fragment, names.iter().copied()) {
                    Some(s) => format!("did you mean \"{s}\"?"),
                    None => format!("known fragments: {}", names.join(", ")),
                }),
            );
            continue;
        };
        let frag = entry.fragment;
        let frag_names = || frag.features.iter().map(|f| f.name.as_str());
        for (j, name) in inc.except.iter().enumerate() {
            if !frag.features.iter().any(|f| &f.name == name) {
                sink.report(
                    file,
                    &rule::UNKNOWN_FEATURE,
                    &format!("{inc_ptr}/except/{j}"),
                    format!("fragment \"{}\" has no feature \"{name}\" to leave out", frag.fragment),
                    hint(name, frag_names()),
                );
            }
        }
        for name in inc.overrides.keys() {
            let ptr = format!("{inc_ptr}/overrides/{}", crate::json::escape_token(name));
            if !frag.features.iter().any(|f| &f.name == name) {
                sink.report(
                    file,
                    &rule::UNKNOWN_FEATURE,
                    &ptr,
                    format!("fragment \"{}\" has no feature \"{name}\" to override", frag.fragment),
                    hint(name, frag_names()),
                );
            } else if inc.except.contains(name) {
                sink.report(
                    file,
                    &rule::OVERRIDE_EXCLUDED,
                    &ptr,
                    format!("\"{name}\" is both left out (except) and overridden"),
                    Some("remove it from one of the two lists".into()),
                );
            }
        }
        for (j, f) in frag.features.iter().enumerate() {
            if inc.except.contains(&f.name) {
                continue;
            }
            let mut feature = from_raw(f, Some(&frag.fragment));
            let mut site = FeatureSite {
                file: entry.file,
                pointer: format!("/features/{j}"),
                overrides: BTreeMap::new(),
            };
            if let Some(patch) = inc.overrides.get(&f.name) {
                let base = format!("{inc_ptr}/overrides/{}", crate::json::escape_token(&f.name));
                apply_patch(&mut feature, &mut site, patch, file, &base);
            }
            features.push(feature);
            sites.push(site);
        }
    }

    for (j, f) in raw.features.iter().enumerate() {
        features.push(from_raw(f, None));
        sites.push(FeatureSite {
            file,
            pointer: format!("/features/{j}"),
            overrides: BTreeMap::new(),
        });
    }

    let spec = EnvSpec {
        id: raw.id.clone(),
        aliases: raw.aliases.clone(),
        family: raw.family.clone(),
        upstream: raw.upstream.clone(),
        description: raw.description.clone(),
        observation_space: raw.observation_space.clone(),
        action_space: raw.action_space.clone(),
        max_episode_steps: raw.max_episode_steps,
        version: raw.version,
        engine: raw.engine.clone(),
        source: raw.source.clone(),
        features,
        distributions: raw.distributions.clone(),
        regions: raw.regions.clone(),
        instance_sets: raw.instance_sets.clone(),
        origin: origin.to_string(),
    };
    Resolved { spec, file, sites }
}

fn hint<'a>(name: &str, known: impl Iterator<Item = &'a str> + Clone) -> Option<String> {
    match did_you_mean(name, known.clone()) {
        Some(s) => Some(format!("did you mean \"{s}\"?")),
        None => Some(format!("known names: {}", known.collect::<Vec<_>>().join(", "))),
    }
}

fn from_raw(f: &RawFeature, fragment: Option<&str>) -> Feature {
    Feature {
        name: f.name.clone(),
        aliases: f.aliases.clone(),
        kind: f.kind,
        default: f.default.clone(),
        default_from: f.default_from.clone(),
        bounds: f.bounds.unwrap_or([None, None]),
        choices: f.choices.clone(),
        choice_labels: f.choice_labels.clone(),
        unit: f.unit.clone(),
        description: f.description.clone(),
        affects: f.affects.clone(),
        requires_option: f.requires_option.clone(),
        from_fragment: fragment.map(str::to_string),
    }
}

fn apply_patch(feature: &mut Feature, site: &mut FeatureSite, patch: &FeaturePatch, file: usize, base: &str) {
    let mut mark = |field: &'static str| {
        site.overrides.insert(field, (file, format!("{base}/{field}")));
    };
    if let Some(d) = &patch.default {
        feature.default = Some(d.clone());
        feature.default_from = None;
        mark("default");
    }
    if let Some(b) = patch.bounds {
        feature.bounds = b;
        mark("bounds");
    }
    if let Some(d) = &patch.description {
        feature.description = d.clone();
        mark("description");
    }
    if let Some(a) = &patch.affects {
        feature.affects = a.clone();
        mark("affects");
    }
    if let Some(u) = &patch.unit {
        feature.unit = Some(u.clone());
        mark("unit");
    }
}
