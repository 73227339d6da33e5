//! Where frozen sets live, and loading, freezing and verifying them.
//!
//! Bundled specs have their frozen sets embedded in the binary (`specs/instances/<env>/<set>.json`
//! at build time); an author's spec `DIR/<env>.json` keeps them in `DIR/instances/<env>/<set>.json`.

use std::path::{Path, PathBuf};

use super::derive::{DeriveError, derive_set};
use super::frozen::{FORMAT, FrozenSet, remove_stale_temp_files, spec_digest, write_temp};
use crate::spec::SpecSet;
use crate::spec::load::{INSTANCES_DIR, bundled_files};
use crate::spec::model::EnvSpec;
use crate::suggest::did_you_mean;

#[derive(Debug, thiserror::Error)]
pub enum StoreError {
    #[error("\"{0}\" is not ENV/SET; e.g. lunar_lander/landing_in_space_train")]
    BadName(String),
    #[error("{0}")]
    Unknown(String),
    #[error("{name} is declared but not frozen ({where_}); run `carl-spec freeze {name}`")]
    NotFrozen { name: String, where_: String },
    #[error("{name}: the frozen file {where_} is corrupt: {reason}")]
    Corrupt {
        name: String,
        where_: String,
        reason: String,
    },
    #[error(
        "{name}: the spec changed since {where_} was frozen (spec digest differs); re-freeze it with `carl-spec freeze {name} --force` if the change is intended"
    )]
    Stale { name: String, where_: String },
    #[error("cannot write {path}: {source}")]
    Write { path: String, source: std::io::Error },
    #[error("cannot read {path}: {source}")]
    Read { path: String, source: std::io::Error },
    #[error("{0}")]
    Derive(#[from] DeriveError),
    #[error("{0}")]
    Refused(String),
}

/// Where one frozen set is stored.
#[derive(Debug, Clone, PartialEq)]
pub enum Location {
    /// Embedded in the binary; the path is relative to `specs/`.
    Bundled(String),
    File(PathBuf),
}

impl Location {
    pub fn describe(&self) -> String {
        match self {
            Location::Bundled(p) => format!("specs/{p} (bundled)"),
            Location::File(p) => p.display().to_string(),
        }
    }

    /// The text, or None when there is no such file.
    fn read(&self) -> Result<Option<String>, StoreError> {
        match self {
            Location::Bundled(p) => Ok(bundled_files().iter().find(|(q, _)| q == p).map(|(_, t)| t.to_string())),
            Location::File(p) => match std::fs::read(p) {
                Ok(bytes) => Ok(Some(String::from_utf8(bytes).map_err(|_| StoreError::Corrupt {
                    name: p.display().to_string(),
                    where_: p.display().to_string(),
                    reason: "not UTF-8".into(),
                })?)),
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
                Err(e) => Err(StoreError::Read {
                    path: p.display().to_string(),
                    source: e,
                }),
            },
        }
    }
}

/// One problem found by `verify`.
#[derive(Debug, Clone, serde::Serialize)]
pub struct VerifyProblem {
    pub set: String,
    pub file: String,
    pub problem: String,
}

/// What `freeze` did with one set.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct FreezeOutcome {
    pub set: String,
    pub file: String,
    /// `written`, `unchanged` or `replaced`.
    pub action: String,
}

pub struct Store<'a> {
    specs: &'a SpecSet,
    /// A checkout's `specs/` folder: the bundled specs' frozen files are read from (and checked
    /// in) its `instances/`, the copies a user can edit, instead of those built into the binary.
    checkout: Option<PathBuf>,
}

impl<'a> Store<'a> {
    /// Frozen files of bundled specs are read from the copies built into the binary.
    pub fn new(specs: &'a SpecSet) -> Self {
        Store { specs, checkout: None }
    }

    /// Read (and verify) the bundled specs' frozen files in `specs_dir/instances/` (a checkout).
    pub fn with_checkout(mut self, specs_dir: PathBuf) -> Self {
        self.checkout = Some(specs_dir);
        self
    }

    /// `dir/specs` when it is a carl-spec checkout's spec folder (it holds the bundled specs and
    /// an `instances/` folder), e.g. when a command runs from the repository root.
    pub fn find_checkout(dir: &Path) -> Option<PathBuf> {
        let specs = dir.join("specs");
        let has_bundled_spec = bundled_files()
            .iter()
            .any(|(p, _)| !p.contains('/') && specs.join(p).is_file());
        (has_bundled_spec && specs.join(INSTANCES_DIR).is_dir()).then_some(specs)
    }

    /// Where the bundled specs' frozen files are read from, for messages.
    pub fn bundled_source(&self) -> String {
        match &self.checkout {
            Some(d) => format!("{} (checkout)", d.join(INSTANCES_DIR).display()),
            None => "the copies built into this binary (no specs/ checkout here)".into(),
        }
    }

    /// Every declared set: (env spec, set name).
    pub fn declared(&self) -> Vec<(&'a EnvSpec, &'a str)> {
        self.specs
            .envs()
            .iter()
            .flat_map(|e| e.instance_sets.keys().map(move |s| (e, s.as_str())))
            .collect()
    }

    /// Resolve `env/set` to its spec and set name, with "did you mean" errors.
    pub fn resolve(&self, name: &str) -> Result<(&'a EnvSpec, String), StoreError> {
        let (env, set) = name
            .split_once('/')
            .ok_or_else(|| StoreError::BadName(name.to_string()))?;
        let spec = self.specs.require(env).map_err(StoreError::Unknown)?;
        if !spec.instance_sets.contains_key(set) {
            let known = spec.instance_sets.keys().map(String::as_str);
            let hint = match did_you_mean(set, known.clone()) {
                Some(s) => format!("did you mean \"{}/{s}\"?", spec.id),
                None if spec.instance_sets.is_empty() => format!("{} declares no instance sets", spec.id),
                None => format!("sets of {}: {}", spec.id, known.collect::<Vec<_>>().join(", ")),
            };
            return Err(StoreError::Unknown(format!(
                "no instance set \"{set}\" in {}; {hint}",
                spec.id
            )));
        }
        Ok((spec, set.to_string()))
    }

    /// Where the frozen file of `spec`'s `set` is read from.
    pub fn location(&self, spec: &EnvSpec, set: &str) -> Location {
        let rel = format!("{INSTANCES_DIR}/{}/{set}.json", spec.id);
        if spec.origin.starts_with("bundled:") {
            match &self.checkout {
                Some(dir) => Location::File(dir.join(rel)),
                None => Location::Bundled(rel),
            }
        } else {
            let dir = Path::new(&spec.origin)
                .parent()
                .map(Path::to_path_buf)
                .unwrap_or_default();
            Location::File(dir.join(rel))
        }
    }

    /// Load a frozen set by name, checking its hash and that the spec has not changed since.
    pub fn load(&self, name: &str) -> Result<FrozenSet, StoreError> {
        let (spec, set) = self.resolve(name)?;
        let loc = self.location(spec, &set);
        let qualified = format!("{}/{set}", spec.id);
        let text = loc.read()?.ok_or_else(|| StoreError::NotFrozen {
            name: qualified.clone(),
            where_: loc.describe(),
        })?;
        let frozen = parse_frozen(&text).map_err(|reason| StoreError::Corrupt {
            name: qualified.clone(),
            where_: loc.describe(),
            reason,
        })?;
        let def = &spec.instance_sets[&set];
        if frozen.provenance.spec_digest != spec_digest(spec, def) {
            return Err(StoreError::Stale {
                name: qualified,
                where_: loc.describe(),
            });
        }
        // The hash only proves the file is consistent with itself (anyone can recompute it):
        // every name and value is checked against the spec before it is used.
        check_against_spec(&frozen, spec, &set, def.allow_out_of_bounds).map_err(|reason| StoreError::Corrupt {
            name: qualified.clone(),
            where_: loc.describe(),
            reason,
        })?;
        Ok(frozen)
    }

    /// The frozen files `verify` reads: one per declared set (existing or not).
    pub fn checked_files(&self) -> Vec<String> {
        self.declared()
            .into_iter()
            .map(|(spec, set)| self.location(spec, set).describe())
            .collect()
    }

    /// Re-derive every declared set and compare with its frozen file; also flag files that belong
    /// to no declared set.
    pub fn verify(&self) -> Vec<VerifyProblem> {
        let mut problems = Vec::new();
        for (spec, set) in self.declared() {
            let qualified = format!("{}/{set}", spec.id);
            let loc = self.location(spec, set);
            let mut push = |problem: String| {
                problems.push(VerifyProblem {
                    set: qualified.clone(),
                    file: loc.describe(),
                    problem,
                })
            };
            let text = match loc.read() {
                Ok(Some(t)) => t,
                Ok(None) => {
                    push(format!("not frozen; run `carl-spec freeze {qualified}`"));
                    continue;
                }
                Err(e) => {
                    push(e.to_string());
                    continue;
                }
            };
            let frozen = match parse_frozen(&text) {
                Ok(f) => f,
                Err(reason) => {
                    push(reason);
                    continue;
                }
            };
            match derive_set(spec, set) {
                Ok(derived) => {
                    for d in diff(&frozen, &derived) {
                        push(d);
                    }
                }
                Err(e) => push(format!("cannot re-derive: {e}")),
            }
        }
        // A checkout's spec files must be the ones this binary was built with, or the frozen files
        // would be checked against other specs than the user sees.
        if let Some(dir) = &self.checkout {
            for (path, text) in bundled_files()
                .iter()
                .filter(|(p, _)| !p.starts_with(&format!("{INSTANCES_DIR}/")))
            {
                let file = dir.join(path);
                if std::fs::read_to_string(&file).is_ok_and(|t| t != *text) {
                    problems.push(VerifyProblem {
                        set: "-".into(),
                        file: file.display().to_string(),
                        problem: "differs from the copy built into this binary: rebuild (cargo build --release) so verify checks the spec you edited".into(),
                    });
                }
            }
        }
        // Orphans: frozen files without a declared set (when the bundled specs are loaded).
        let has_bundled = self.specs.envs().iter().any(|e| e.origin.starts_with("bundled:"));
        let frozen_files: Vec<(String, String)> = match &self.checkout {
            _ if !has_bundled => Vec::new(),
            Some(dir) => list_frozen(&dir.join(INSTANCES_DIR)),
            None => bundled_files()
                .iter()
                .filter(|(p, _)| p.starts_with(&format!("{INSTANCES_DIR}/")))
                .map(|(p, _)| (p.to_string(), format!("specs/{p}")))
                .collect(),
        };
        for (path, shown) in frozen_files {
            let parts: Vec<&str> = path.trim_end_matches(".json").split('/').collect();
            if let [_, env, set] = parts[..]
                && self.specs.get(env).is_none_or(|s| !s.instance_sets.contains_key(set))
            {
                problems.push(VerifyProblem {
                    set: format!("{env}/{set}"),
                    file: shown,
                    problem:
                        "frozen file of a set no spec declares (renamed or removed?); delete it or declare the set"
                            .into(),
                });
            }
        }
        problems
    }

    /// Freeze the named sets (all when `names` is empty). `out` is the spec directory to write into
    /// for bundled specs (default `./specs`, which must be the repository's). An existing file with
    /// different content is only replaced with `force`.
    pub fn freeze(&self, names: &[String], out: Option<&Path>, force: bool) -> Result<Vec<FreezeOutcome>, StoreError> {
        let targets: Vec<(&EnvSpec, String)> = if names.is_empty() {
            self.declared().into_iter().map(|(e, s)| (e, s.to_string())).collect()
        } else {
            let mut t = Vec::new();
            for n in names {
                if n.contains('/') {
                    t.push(self.resolve(n)?);
                } else {
                    let spec = self.specs.require(n).map_err(StoreError::Unknown)?;
                    t.extend(spec.instance_sets.keys().map(|s| (spec, s.clone())));
                }
            }
            t
        };
        // Derive everything first: a failure leaves every file untouched.
        let mut planned = Vec::new();
        for (spec, set) in targets {
            let frozen = derive_set(spec, &set)?;
            let path = self.write_path(spec, &set, out)?;
            planned.push((frozen, path));
        }
        let mut outcomes = Vec::new();
        let mut refused = Vec::new();
        for (frozen, path) in &planned {
            let text = frozen.to_text();
            let existing = std::fs::read_to_string(path).ok();
            let action = match &existing {
                Some(old) if *old == text => "unchanged",
                Some(old) if !force => {
                    let what = describe_difference(old, frozen);
                    refused.push(format!("{} exists and differs ({what})", path.display()));
                    continue;
                }
                Some(_) => "replaced",
                None => "written",
            };
            outcomes.push(FreezeOutcome {
                set: frozen.qualified_name(),
                file: path.display().to_string(),
                action: action.into(),
            });
        }
        if !refused.is_empty() {
            return Err(StoreError::Refused(format!(
                "nothing written: {}\nre-run with --force to replace (the old values are lost)",
                refused.join("\n")
            )));
        }
        let writes: Vec<(&Path, String)> = planned
            .iter()
            .zip(&outcomes)
            .filter(|(_, o)| o.action != "unchanged")
            .map(|((frozen, path), _)| (path.as_path(), frozen.to_text()))
            .collect();
        write_all_or_nothing(&writes)?;
        Ok(outcomes)
    }

    fn write_path(&self, spec: &EnvSpec, set: &str, out: Option<&Path>) -> Result<PathBuf, StoreError> {
        let rel = Path::new(INSTANCES_DIR).join(&spec.id).join(format!("{set}.json"));
        match (self.location(spec, set), out) {
            (_, Some(dir)) => Ok(dir.join(rel)),
            (Location::File(p), None) => Ok(p),
            (Location::Bundled(_), None) => {
                let dir = Path::new("specs");
                if dir.join(format!("{}.json", spec.id)).is_file() {
                    Ok(dir.join(rel))
                } else {
                    Err(StoreError::Refused(format!(
                        "{} is a bundled spec: run freeze from the carl-spec repository root (where specs/{}.json is), or pass --out DIR",
                        spec.id, spec.id
                    )))
                }
            }
        }
    }
}

/// Write every file or none: all temporary files are written (and synced) first; only when all
/// succeeded are they renamed over their targets. A rename failing midway (rare: the temporary
/// files sit beside their targets) is reported with the files already replaced. Temporary files
/// left by killed runs are removed first.
fn write_all_or_nothing(writes: &[(&Path, String)]) -> Result<(), StoreError> {
    let mut temps: Vec<(PathBuf, &Path)> = Vec::new();
    let undo = |temps: &[(PathBuf, &Path)]| {
        for (t, _) in temps {
            let _ = std::fs::remove_file(t);
        }
    };
    for (path, text) in writes {
        if let Some(dir) = path.parent() {
            remove_stale_temp_files(dir);
        }
        match write_temp(path, text) {
            Ok(t) => temps.push((t, path)),
            Err(e) => {
                undo(&temps);
                return Err(StoreError::Write {
                    path: format!("{} (nothing written)", path.display()),
                    source: e,
                });
            }
        }
    }
    for (k, (tmp, path)) in temps.iter().enumerate() {
        if let Err(e) = std::fs::rename(tmp, path) {
            undo(&temps[k..]);
            let done: Vec<String> = temps[..k].iter().map(|(_, p)| p.display().to_string()).collect();
            return Err(StoreError::Write {
                path: format!(
                    "{} (already replaced: {})",
                    path.display(),
                    if done.is_empty() {
                        "none".into()
                    } else {
                        done.join(", ")
                    }
                ),
                source: e,
            });
        }
    }
    Ok(())
}

/// Every name and value of a frozen set against its spec: the set is the one asked for, it varies
/// only features of the spec (by canonical name), and every value has its feature's type (among
/// its choices) and lies inside its bounds unless the set allows out-of-bounds values.
pub fn check_against_spec(
    frozen: &FrozenSet,
    spec: &EnvSpec,
    set: &str,
    allow_out_of_bounds: bool,
) -> Result<(), String> {
    use crate::sampling::FeatureInfo;
    use crate::sampling::feature::check_instance_value;
    use crate::text::quote;
    if frozen.env != spec.id || frozen.set != set {
        return Err(format!(
            "the file holds {}/{}, not {}/{set}",
            quote(&frozen.env),
            quote(&frozen.set),
            spec.id
        ));
    }
    let infos: Vec<(&str, FeatureInfo)> = frozen
        .features
        .iter()
        .map(|name| match spec.features.iter().find(|f| f.name == *name) {
            Some(f) => Ok((name.as_str(), FeatureInfo::from_feature(f))),
            None => Err(format!(
                "it varies {}, which is not a feature of {}",
                quote(name),
                spec.id
            )),
        })
        .collect::<Result<_, _>>()?;
    for (i, inst) in frozen.instances.iter().enumerate() {
        if inst.id != i {
            return Err(format!("instance {i} has id {}", inst.id));
        }
        for (name, value) in &inst.context {
            let (_, info) = infos.iter().find(|(n, _)| n == name).ok_or_else(|| {
                format!(
                    "instance {}: {} is not among the set's features ({})",
                    inst.label(),
                    quote(name),
                    frozen.features.join(", ")
                )
            })?;
            check_instance_value(value, info, allow_out_of_bounds)
                .map_err(|e| format!("instance {}: {name}: {e}", quote(&inst.label())))?;
        }
    }
    Ok(())
}

/// Frozen files under `dir` (`instances/`): (path relative to the spec folder, path to show).
fn list_frozen(dir: &Path) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let Ok(envs) = std::fs::read_dir(dir) else { return out };
    for env in envs.flatten() {
        let Ok(sets) = std::fs::read_dir(env.path()) else {
            continue;
        };
        for set in sets.flatten() {
            let name = set.file_name().to_string_lossy().into_owned();
            if name.ends_with(".json") && !name.starts_with('.') {
                let env_name = env.file_name().to_string_lossy().into_owned();
                out.push((
                    format!("{INSTANCES_DIR}/{env_name}/{name}"),
                    set.path().display().to_string(),
                ));
            }
        }
    }
    out.sort();
    out
}

/// Parse a frozen file and check its format tag, that it holds instances (no derivation gives
/// an empty set, and an environment cannot be reset from one) and its content hash.
pub fn parse_frozen(text: &str) -> Result<FrozenSet, String> {
    let frozen: FrozenSet = serde_json::from_str(text).map_err(|e| format!("not a frozen instance set: {e}"))?;
    if frozen.format != FORMAT {
        return Err(format!(
            "format {} is not \"{FORMAT}\"",
            crate::text::quote(&frozen.format)
        ));
    }
    if frozen.instances.is_empty() {
        return Err("it holds no instances (\"instances\": []); a set needs at least one".into());
    }
    let expected = frozen.compute_hash();
    if frozen.content_hash != expected {
        return Err(format!(
            "content hash mismatch (file says {}, content hashes to {expected}): the file was edited by hand or corrupted",
            frozen.content_hash
        ));
    }
    Ok(frozen)
}

/// Human-readable differences between a frozen file and a fresh derivation.
pub fn diff(frozen: &FrozenSet, derived: &FrozenSet) -> Vec<String> {
    let mut out = Vec::new();
    let text = |s: &str| crate::text::quote(s);
    if frozen.env != derived.env || frozen.set != derived.set {
        out.push(format!(
            "the file holds {}/{}, not {}",
            text(&frozen.env),
            text(&frozen.set),
            derived.qualified_name()
        ));
    }
    if frozen.provenance.generator != derived.provenance.generator {
        out.push(format!(
            "written by {}, this is {}",
            text(&frozen.provenance.generator),
            derived.provenance.generator
        ));
    }
    if frozen.description != derived.description || frozen.role != derived.role {
        out.push("the set's description or role changed".into());
    }
    if frozen.provenance.definition != derived.provenance.definition
        || frozen.provenance.distribution != derived.provenance.distribution
    {
        out.push("the set's definition or distribution changed".into());
    }
    if frozen.features != derived.features {
        out.push(format!(
            "varies [{}] in the file, [{}] derived",
            frozen.features.join(", "),
            derived.features.join(", ")
        ));
    }
    if frozen.provenance.spec_digest != derived.provenance.spec_digest {
        out.push("the spec changed since the set was frozen (spec digest differs)".into());
    }
    if frozen.provenance.sampler_version != derived.provenance.sampler_version
        || frozen.provenance.rng != derived.provenance.rng
    {
        out.push(format!(
            "frozen with {} / {}, this build has {} / {}",
            frozen.provenance.rng,
            frozen.provenance.sampler_version,
            derived.provenance.rng,
            derived.provenance.sampler_version
        ));
    }
    if frozen.instances.len() != derived.instances.len() {
        out.push(format!(
            "{} instances in the file, {} derived",
            frozen.instances.len(),
            derived.instances.len()
        ));
    }
    let mut shown = 0;
    for (a, b) in frozen.instances.iter().zip(&derived.instances) {
        if a != b && shown < 5 {
            shown += 1;
            let keys: std::collections::BTreeSet<&String> = a.context.keys().chain(b.context.keys()).collect();
            for k in keys {
                if a.context.get(k) != b.context.get(k) {
                    out.push(format!(
                        "instance {}: {k} is {} in the file, {} derived",
                        a.label(),
                        a.context
                            .get(k)
                            .map_or("missing".into(), crate::spec::model::value_text),
                        b.context
                            .get(k)
                            .map_or("missing".into(), crate::spec::model::value_text),
                    ));
                }
            }
            if a.name != b.name || a.split != b.split {
                out.push(format!("instance {}: name or split differs", a.label()));
            }
        }
    }
    if out.is_empty() && frozen.content_hash != derived.content_hash {
        out.push(format!(
            "content hash {} in the file, {} derived",
            frozen.content_hash, derived.content_hash
        ));
    }
    out
}

/// What differs between an existing file's text and the one `freeze` would write; never empty
/// when the texts differ.
fn describe_difference(old: &str, new: &FrozenSet) -> String {
    let found = match parse_frozen(old) {
        Ok(old) => diff(&old, new),
        Err(e) => vec![e],
    };
    if found.is_empty() {
        "same values and metadata, different text (formatting edited by hand?)".into()
    } else {
        let n = found.len();
        let mut shown: Vec<String> = found.into_iter().take(3).collect();
        if n > 3 {
            shown.push(format!("{} more", n - 3));
        }
        shown.join("; ")
    }
}
