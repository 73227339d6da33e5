//! The resolved spec model: includes merged, overrides applied, names indexed.
//!
//! Everything downstream (sampling, instance sets, runtimes, audit) reads these types, never the
//! raw documents.

use std::collections::BTreeMap;

use serde::Serialize;

pub use super::raw::{
    AtBounds, Bounds, Effect, FeatureType, RawDistribution as Distribution, RawInstanceSet as InstanceSet, Region,
    Sampler, Scalar, Space, SplitSet, Upstream, Value,
};

/// A context feature after resolution.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Feature {
    pub name: String,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub aliases: Vec<String>,
    #[serde(rename = "type")]
    pub kind: FeatureType,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub default: Option<Value>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub default_from: Option<String>,
    /// `[lower, upper]`, `None` = unbounded side.
    pub bounds: Bounds,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub choices: Option<Vec<Scalar>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub choice_labels: Option<Vec<String>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unit: Option<String>,
    pub description: String,
    pub affects: Vec<Effect>,
    /// The boolean environment option without which the feature does not act (see
    /// [`RawFeature::requires_option`](super::raw::RawFeature::requires_option)).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub requires_option: Option<String>,
    /// The shared fragment this feature came from, if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub from_fragment: Option<String>,
}

impl Feature {
    pub fn affects(&self, effect: Effect) -> bool {
        self.affects.contains(&effect)
    }

    /// The default as a number, for float/int/bool features.
    pub fn default_f64(&self) -> Option<f64> {
        match &self.default {
            Some(Value::Number(x)) => Some(*x),
            Some(Value::Bool(b)) => Some(f64::from(u8::from(*b))),
            _ => None,
        }
    }

    /// Is `x` within the inclusive bounds?
    pub fn in_bounds(&self, x: f64) -> bool {
        self.bounds[0].is_none_or(|lo| x >= lo) && self.bounds[1].is_none_or(|hi| x <= hi)
    }

    /// Is the feature continuous (float)?
    pub fn is_continuous(&self) -> bool {
        self.kind == FeatureType::Float
    }

    pub fn matches_name(&self, name: &str) -> bool {
        self.name == name || self.aliases.iter().any(|a| a == name)
    }
}

/// One environment's resolved spec.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct EnvSpec {
    pub id: String,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub aliases: Vec<String>,
    pub family: String,
    pub upstream: Upstream,
    /// See [`RawEnvSpec::version`](super::raw::RawEnvSpec::version).
    pub version: u32,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub engine: Option<String>,
    pub description: String,
    pub observation_space: Space,
    pub action_space: Space,
    pub max_episode_steps: Option<u64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub source: Option<String>,
    pub features: Vec<Feature>,
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub distributions: BTreeMap<String, Distribution>,
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub regions: BTreeMap<String, Region>,
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub instance_sets: BTreeMap<String, InstanceSet>,
    /// Where the spec was loaded from (file path or `bundled:<path>`).
    #[serde(skip)]
    pub origin: String,
}

impl EnvSpec {
    /// The row `carl-spec list --format json` prints for this environment (the Python
    /// `list_envs` adds whether it has a runtime).
    pub fn summary_json(&self) -> serde_json::Value {
        serde_json::json!({
            "id": self.id, "aliases": self.aliases, "family": self.family,
            "upstream": format!("{} {}", self.upstream.library, self.upstream.id),
            "version": self.version, "engine": self.engine,
            "features": self.features.len(),
            "instance_sets": self.instance_sets.keys().collect::<Vec<_>>(),
        })
    }

    /// `<id>-v<version>`, the versioned name results are reported under (Gymnasium's form).
    pub fn versioned_id(&self) -> String {
        format!("{}-v{}", self.id, self.version)
    }

    /// Look a feature up by canonical name or alias.
    pub fn feature(&self, name: &str) -> Option<&Feature> {
        self.features
            .iter()
            .find(|f| f.name == name)
            .or_else(|| self.features.iter().find(|f| f.matches_name(name)))
    }

    pub fn feature_index(&self, name: &str) -> Option<usize> {
        self.features.iter().position(|f| f.matches_name(name))
    }

    pub fn feature_names(&self) -> impl Iterator<Item = &str> + Clone {
        self.features.iter().map(|f| f.name.as_str())
    }

    /// The default context: every feature at its default (computed defaults are absent).
    pub fn default_context(&self) -> BTreeMap<String, Value> {
        self.features
            .iter()
            .filter_map(|f| f.default.clone().map(|d| (f.name.clone(), d)))
            .collect()
    }

    pub fn matches_name(&self, name: &str) -> bool {
        self.id == name || self.aliases.iter().any(|a| a == name)
    }
}

/// A value for messages: strings quoted (escaped and cut, see `text::quote`), lists cut.
pub fn value_text(v: &Value) -> String {
    match v {
        Value::Bool(b) => b.to_string(),
        Value::Number(x) => x.to_string(),
        Value::String(s) => crate::text::quote(s),
        Value::List(l) => crate::text::escape(&format!("{l:?}")),
    }
}
