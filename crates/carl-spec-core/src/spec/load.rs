//! Spec sets: the bundled specs (embedded at build time), authors' directories, and the loaded set.
//!
//! Loading validates everything first; that pipeline lives above this module
//! (the `validate` module, which adds `SpecSet::bundled`, `bundled_with` and `from_inputs`), so the spec
//! language never depends on its checker.

use std::path::{Path, PathBuf};

use super::model::EnvSpec;
use super::raw::GridSet;
use crate::diagnostics::{Input, MAX_FILE_BYTES, Report};
use crate::suggest::did_you_mean;

mod embedded {
    include!(concat!(env!("OUT_DIR"), "/bundled_specs.rs"));
}

/// Folder (under a spec directory) that holds frozen instance sets, not spec documents.
pub const INSTANCES_DIR: &str = "instances";

/// Every bundled file: `(path relative to specs/, contents)`.
pub fn bundled_files() -> &'static [(&'static str, &'static str)] {
    embedded::BUNDLED
}

/// The bundled spec documents (environments and shared fragments), as validator inputs.
pub fn bundled_inputs(library: bool) -> Vec<Input> {
    bundled_files()
        .iter()
        .filter(|(p, _)| !p.starts_with(&format!("{INSTANCES_DIR}/")))
        .map(|(p, text)| Input {
            name: format!("bundled:specs/{p}"),
            bytes: text.as_bytes().to_vec(),
            library,
        })
        .collect()
}

/// Whether `input` is a bundled spec exactly as embedded at build time (name and bytes).
pub(crate) fn is_embedded(input: &Input) -> bool {
    input
        .name
        .strip_prefix("bundled:specs/")
        .and_then(|p| bundled_files().iter().find(|(q, _)| *q == p))
        .is_some_and(|(_, text)| text.as_bytes() == input.bytes.as_slice())
}

/// A validated, resolved set of environment specs.
#[derive(Debug, Clone, Default)]
pub struct SpecSet {
    envs: Vec<EnvSpec>,
}

#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    #[error("cannot read {path}: {source}")]
    Io { path: String, source: std::io::Error },
    #[error("{} error(s) in the specs:\n{report}", report.errors())]
    Invalid { report: Report },
    #[error("no *.json spec files found in {paths}")]
    NoSpecFiles { paths: String },
}

impl SpecSet {
    /// A set of already validated, resolved specs (the loaders are in the `validate` module).
    pub(crate) fn from_validated(envs: Vec<EnvSpec>) -> SpecSet {
        SpecSet { envs }
    }

    /// By id or alias (e.g. `cartpole` or `CARLCartPoleEnv`).
    pub fn get(&self, name: &str) -> Option<&EnvSpec> {
        self.envs
            .iter()
            .find(|e| e.id == name)
            .or_else(|| self.envs.iter().find(|e| e.matches_name(name)))
    }

    /// Like `get`, with a "did you mean" error for unknown names.
    pub fn require(&self, name: &str) -> Result<&EnvSpec, String> {
        self.get(name).ok_or_else(|| {
            let ids = self.envs.iter().map(|e| e.id.as_str());
            match did_you_mean(name, ids.clone()) {
                Some(s) => format!("no environment \"{name}\"; did you mean \"{s}\"?"),
                None => format!(
                    "no environment \"{name}\"; known: {}",
                    ids.collect::<Vec<_>>().join(", ")
                ),
            }
        })
    }

    pub fn envs(&self) -> &[EnvSpec] {
        &self.envs
    }
}

/// What `carl-spec validate PATH…` (and the Python `cs.validate`) checks: with no paths, the
/// bundled specs, named by their path in the repository; else the files at `paths` (none found
/// is an error) plus the bundled shared fragments an author's spec may include.
pub fn validation_inputs(paths: &[PathBuf]) -> Result<Vec<Input>, LoadError> {
    if paths.is_empty() {
        return Ok(bundled_inputs(false)
            .into_iter()
            .map(|mut i| {
                i.name = i.name.trim_start_matches("bundled:").to_string();
                i
            })
            .collect());
    }
    let mut inputs = read_inputs(paths)?;
    if inputs.is_empty() {
        let shown: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
        return Err(LoadError::NoSpecFiles {
            paths: shown.join(", "),
        });
    }
    inputs.extend(bundled_inputs(true).into_iter().filter(|i| i.name.contains("/shared/")));
    Ok(inputs)
}

/// Read spec files: a file is read as is; a directory yields every `*.json` below it, except
/// frozen instance sets under `instances/`. Sorted, so reports are stable.
pub fn read_inputs(paths: &[PathBuf]) -> Result<Vec<Input>, LoadError> {
    let mut files = Vec::new();
    for p in paths {
        let meta = std::fs::metadata(p).map_err(|e| LoadError::Io {
            path: p.display().to_string(),
            source: e,
        })?;
        if meta.is_dir() {
            walk(p, &mut files).map_err(|e| LoadError::Io {
                path: p.display().to_string(),
                source: e,
            })?;
        } else {
            files.push(p.clone());
        }
    }
    files.sort();
    files.dedup();
    files
        .into_iter()
        .map(|f| {
            let bytes = read_limited(&f).map_err(|e| LoadError::Io {
                path: f.display().to_string(),
                source: e,
            })?;
            Ok(Input {
                name: f.display().to_string(),
                bytes,
                library: false,
            })
        })
        .collect()
}

/// Read at most MAX_FILE_BYTES + 1 bytes, so a huge file is refused without reading it all.
fn read_limited(path: &Path) -> std::io::Result<Vec<u8>> {
    use std::io::Read;
    let f = std::fs::File::open(path)?;
    let mut buf = Vec::new();
    f.take(MAX_FILE_BYTES as u64 + 1).read_to_end(&mut buf)?;
    Ok(buf)
}

fn walk(dir: &Path, out: &mut Vec<PathBuf>) -> std::io::Result<()> {
    for entry in std::fs::read_dir(dir)? {
        let entry = entry?;
        let path = entry.path();
        let ty = entry.file_type()?;
        if ty.is_dir() {
            if entry.file_name() != INSTANCES_DIR && !entry.file_name().to_string_lossy().starts_with('.') {
                walk(&path, out)?;
            }
        } else if path.extension().is_some_and(|e| e == "json") {
            out.push(path);
        }
    }
    Ok(())
}

/// The points of a grid: `from + i·step` for i = 0, 1, … while ≤ `to` (with a relative tolerance of
/// 1e-9 steps, so `-25 … -0.5 step 0.5` includes -0.5). Computed by multiplication, not repeated
/// addition, so every point is reproducible bit for bit.
pub fn grid_points(g: &GridSet) -> impl Iterator<Item = f64> + '_ {
    let n = if g.step > 0.0 && g.from <= g.to {
        ((g.to - g.from) / g.step + 1e-9).floor() as u64 + 1
    } else {
        0
    };
    (0..n).map(move |i| g.from + (i as f64) * g.step)
}
