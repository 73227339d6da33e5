//! The frozen instance-set file: values plus everything needed to re-derive and check them.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::spec::model::{Distribution, EnvSpec, InstanceSet, Region, Value};
use crate::spec::raw::Split;

/// Format tag of frozen files; bump on incompatible changes.
pub const FORMAT: &str = "carl-spec-instances/1";

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FrozenSet {
    pub format: String,
    pub env: String,
    pub set: String,
    pub description: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub role: Option<String>,
    pub provenance: Provenance,
    /// The features this set varies (all other features stay at their defaults).
    pub features: Vec<String>,
    pub instances: Vec<Instance>,
    /// `sha256:<hex>` of this file's canonical JSON with `content_hash` set to "".
    pub content_hash: String,
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Provenance {
    /// carl-spec version that wrote the file.
    pub generator: String,
    /// Bit generator and seeding scheme (sampled sets), e.g. `pcg64-…`.
    pub rng: String,
    pub sampler_version: String,
    /// `sha256:<hex>` over what determines the values: the features' names, types, defaults and
    /// bounds, this set's definition and its distribution.
    pub spec_digest: String,
    /// The set definition as written in the spec.
    pub definition: InstanceSet,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub distribution: Option<Distribution>,
    /// The region a `split` set derives from.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub region: Option<Region>,
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Instance {
    /// Position in the set (0-based); stable, used as the instance id.
    pub id: usize,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub split: Option<Split>,
    /// Values of the varied features, by canonical name.
    pub context: BTreeMap<String, Value>,
}

impl Instance {
    /// `name` if it has one, else `#id`.
    pub fn label(&self) -> String {
        self.name.clone().unwrap_or_else(|| format!("#{}", self.id))
    }
}

impl FrozenSet {
    /// `env/set`.
    pub fn qualified_name(&self) -> String {
        format!("{}/{}", self.env, self.set)
    }

    /// The hash this file should carry.
    pub fn compute_hash(&self) -> String {
        let mut copy = self.clone();
        copy.content_hash = String::new();
        let bytes = serde_json::to_vec(&copy).unwrap_or_default();
        format!("sha256:{}", hex(&Sha256::digest(&bytes)))
    }

    pub fn with_hash(mut self) -> Self {
        self.content_hash = self.compute_hash();
        self
    }

    /// The file's text: pretty JSON, one instance per line for readable diffs.
    pub fn to_text(&self) -> String {
        let mut head = self.clone();
        head.instances = Vec::new();
        let mut text = serde_json::to_string_pretty(&head).unwrap_or_default();
        let lines: Vec<String> = self
            .instances
            .iter()
            .map(|i| format!("    {}", serde_json::to_string(i).unwrap_or_default()))
            .collect();
        let body = if lines.is_empty() {
            "[]".to_string()
        } else {
            format!("[\n{}\n  ]", lines.join(",\n"))
        };
        text = text.replacen("\"instances\": []", &format!("\"instances\": {body}"), 1);
        text.push('\n');
        text
    }

    /// The full context of instance `i`: the spec's defaults overlaid with the instance's values.
    pub fn full_context(&self, spec: &EnvSpec, i: usize) -> Option<BTreeMap<String, Value>> {
        let inst = self.instances.get(i)?;
        let mut ctx = spec.default_context();
        for (k, v) in &inst.context {
            ctx.insert(k.clone(), v.clone());
        }
        Some(ctx)
    }
}

/// The digest of everything that determines a set's values.
/// (name, type, default, bounds): the parts of a feature that determine sampled values.
type FeatureBasis<'a> = (
    &'a str,
    &'a crate::spec::raw::FeatureType,
    &'a Option<Value>,
    &'a [Option<f64>; 2],
);

pub fn spec_digest(spec: &EnvSpec, set: &InstanceSet) -> String {
    #[derive(Serialize)]
    struct Basis<'a> {
        env: &'a str,
        features: Vec<FeatureBasis<'a>>,
        set: &'a InstanceSet,
        distribution: Option<&'a Distribution>,
        #[serde(skip_serializing_if = "Option::is_none")]
        region: Option<&'a Region>,
    }
    let dist = set_distribution(spec, set);
    let basis = Basis {
        env: &spec.id,
        features: spec
            .features
            .iter()
            .map(|f| (f.name.as_str(), &f.kind, &f.default, &f.bounds))
            .collect(),
        set,
        distribution: dist.as_ref(),
        region: set_region(spec, set),
    };
    let bytes = serde_json::to_vec(&basis).unwrap_or_default();
    format!("sha256:{}", hex(&Sha256::digest(&bytes)))
}

/// The distribution a set's values are drawn from: its named distribution, or uniform over the
/// region of a sampled split.
pub fn set_distribution(spec: &EnvSpec, set: &InstanceSet) -> Option<Distribution> {
    if let Some(s) = &set.sampled {
        return spec.distributions.get(&s.distribution).cloned();
    }
    set.split
        .as_ref()
        .filter(|s| s.sampled.is_some())
        .and_then(|s| super::split::region_distribution(spec, s))
}

/// The region a `split` set derives from.
pub fn set_region<'a>(spec: &'a EnvSpec, set: &InstanceSet) -> Option<&'a Region> {
    set.split.as_ref().and_then(|s| spec.regions.get(&s.region))
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Write `text` to `path` atomically: a temporary file in the same directory (the rule of
/// [`crate::output::write_temp`]: unpredictable name, `O_EXCL|O_NOFOLLOW`), flushed to disk, then
/// renamed over the target. An interrupted write leaves the old file (or none), never half a file.
pub fn write_atomic(path: &Path, text: &str) -> std::io::Result<()> {
    let tmp = write_temp(path, text)?;
    std::fs::rename(&tmp, path).inspect_err(|_| {
        let _ = std::fs::remove_file(&tmp);
    })
}

/// Write `text` to a temporary file beside `path` ([`crate::output::write_temp`]) and return
/// its path; the caller renames it into place. Creates the directory.
pub fn write_temp(path: &Path, text: &str) -> std::io::Result<PathBuf> {
    let dir = crate::output::parent_dir(path);
    std::fs::create_dir_all(dir)?;
    crate::output::write_temp(dir, text.as_bytes())
}

/// Remove the temporary files left in `dir` by a killed `freeze`: carl-spec's own
/// ([`crate::output::remove_stale_temp_files`], older than [`crate::output::STALE_TEMP_AGE`]) and
/// those of older versions, which named them `.NAME.json.PID.tmp`, when their process no longer
/// runs (checked in /proc) or, where /proc is absent, they are older than a day. Only regular
/// files are removed, never symlinks. Returns the files removed.
pub fn remove_stale_temp_files(dir: &Path) -> Vec<PathBuf> {
    let mut removed = crate::output::remove_stale_temp_files(dir, crate::output::STALE_TEMP_AGE);
    let Ok(entries) = std::fs::read_dir(dir) else {
        return removed;
    };
    let proc_fs = Path::new("/proc/self").exists();
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(pid) = temp_file_pid(&name) else { continue };
        let Ok(meta) = std::fs::symlink_metadata(e.path()) else {
            continue;
        };
        let stale = if proc_fs {
            pid != std::process::id() && !Path::new(&format!("/proc/{pid}")).exists()
        } else {
            meta.modified()
                .is_ok_and(|t| t.elapsed().is_ok_and(|age| age.as_secs() > 86_400))
        };
        if stale && meta.file_type().is_file() && std::fs::remove_file(e.path()).is_ok() {
            removed.push(e.path());
        }
    }
    removed
}

/// The process id in an older version's temporary file name `.NAME.json.PID.tmp`.
fn temp_file_pid(name: &str) -> Option<u32> {
    let rest = name.strip_prefix('.')?.strip_suffix(".tmp")?;
    let (file, pid) = rest.rsplit_once('.')?;
    file.ends_with(".json").then(|| pid.parse().ok())?
}

#[cfg(test)]
mod tests {
    #[test]
    fn temp_file_names_give_their_pid() {
        assert_eq!(super::temp_file_pid(".train.json.1234.tmp"), Some(1234));
        assert_eq!(super::temp_file_pid("train.json"), None);
        assert_eq!(super::temp_file_pid(".notes.txt.12.tmp"), None);
    }
}
