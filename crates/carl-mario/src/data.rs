//! The user-supplied data directory (`CARL_SPEC_DATA`, layout in the data guide
//! docs/guides/data.md): `mario/levels/original/lvl-N.txt`, `mario/toad_gan/index.json`,
//! `mario/toad_gan/<generator>/{manifest.json,weights.safetensors}`. Tests find the project's
//! test data in a `shared/data` folder beside the checkout.

use crate::error::{MarioError, Result};
use std::path::{Path, PathBuf};

/// Environment variable naming the data directory.
pub const DATA_ENV_VAR: &str = "CARL_SPEC_DATA";

/// A data directory that has a `mario/` folder.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DataDir {
    root: PathBuf,
}

impl DataDir {
    /// Uses `root` (a folder containing `mario/`); errors when it has no `mario/` folder.
    pub fn new(root: impl Into<PathBuf>) -> Result<Self> {
        let root = root.into();
        if !root.join("mario").is_dir() {
            return Err(MarioError::DataDirMissing {
                reason: format!("{} has no mario/ folder", root.display()),
            });
        }
        Ok(DataDir { root })
    }

    /// `explicit` if given (a CLI option), else `$CARL_SPEC_DATA`.
    pub fn resolve(explicit: Option<&Path>) -> Result<Self> {
        if let Some(p) = explicit {
            return Self::new(p);
        }
        match std::env::var_os(DATA_ENV_VAR) {
            Some(v) if !v.is_empty() => Self::new(PathBuf::from(v)),
            _ => Err(MarioError::DataDirMissing {
                reason: format!("{DATA_ENV_VAR} is not set and no data directory was given"),
            }),
        }
    }

    /// `$CARL_SPEC_DATA`, else the first `shared/data` beside `start` or one of its ancestors
    /// (a checkout with `../shared` next to it, as CI has). For tests and benchmarks.
    pub fn discover(start: &Path) -> Result<Self> {
        if std::env::var_os(DATA_ENV_VAR).is_some_and(|v| !v.is_empty()) {
            return Self::resolve(None);
        }
        for dir in start.ancestors() {
            let candidate = dir.join("shared").join("data");
            if candidate.join("mario").is_dir() {
                return Self::new(candidate);
            }
        }
        Err(MarioError::DataDirMissing {
            reason: format!(
                "{DATA_ENV_VAR} is not set and no shared/data/mario beside {} or its parents",
                start.display()
            ),
        })
    }

    pub fn root(&self) -> &Path {
        &self.root
    }

    pub fn mario(&self) -> PathBuf {
        self.root.join("mario")
    }

    pub fn toad_gan(&self) -> PathBuf {
        self.mario().join("toad_gan")
    }

    /// `mario/levels/original/lvl-{n}.txt` (n = 1..=15).
    pub fn original_level(&self, n: usize) -> PathBuf {
        self.mario()
            .join("levels")
            .join("original")
            .join(format!("lvl-{n}.txt"))
    }
}

/// Reads a file, mapping failures to [`MarioError::Io`] with the path.
pub(crate) fn read(path: &Path) -> Result<Vec<u8>> {
    std::fs::read(path).map_err(|source| MarioError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Reads and parses a JSON file.
pub(crate) fn read_json<T: serde::de::DeserializeOwned>(path: &Path) -> Result<T> {
    let bytes = read(path)?;
    serde_json::from_slice(&bytes).map_err(|source| MarioError::Json {
        path: path.to_path_buf(),
        source,
    })
}
