//! Output files: one rule for every command that writes a file the user named (`render`,
//! `plot`, `run … --out/--figure`).
//!
//! * **Checked before the work.** [`check_file`] is called before any long computation, so a
//!   typo in `--out` costs nothing; [`write_file`] checks again when writing.
//! * **No directories are created.** The parent directory must exist: a mistyped path is an
//!   error, not a new directory tree.
//! * **Nothing is replaced without `force`.** An existing file (or symlink) is kept unless the
//!   caller passes `force`, even one that appears between the check and the write.
//! * **A directory is not a file.** A path that is a directory, or ends in `/`, is refused.
//! * **Atomic writes.** Bytes go to a temporary file beside the target, are synced, then moved
//!   into place: readers see the old file or the new one, never half of one.
//!
//! This module depends on nothing else in the crate.

use std::io::Write;
use std::path::{Path, PathBuf};

/// Why an output file cannot or must not be written.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    #[error("{0} exists; pass --force to replace it")]
    Exists(String),
    #[error("cannot write {path}: the directory {dir} does not exist")]
    NoDir { path: String, dir: String },
    #[error("cannot write {0}: it is a directory, not a file")]
    IsDir(String),
    #[error("cannot write {0}: a path ending in / names a directory, not a file")]
    TrailingSlash(String),
    #[error("cannot use {0} as a directory: it exists and is not a directory")]
    NotDir(String),
    #[error("{dir} holds {count} file(s) of an earlier run (e.g. {example}); pass --force to replace them")]
    EarlierRun { dir: String, count: usize, example: String },
    #[error("cannot write {path}: {source}")]
    Io { path: String, source: std::io::Error },
}

/// The directory a file `path` goes into (`.` for a bare file name).
pub fn parent_dir(path: &Path) -> &Path {
    path.parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
}

/// Whether `path` is spelled with a trailing separator (`out/`), i.e. names a directory.
pub fn ends_with_separator(path: &Path) -> bool {
    let text = path.as_os_str().to_string_lossy();
    text.ends_with('/') || text.ends_with(std::path::MAIN_SEPARATOR)
}

/// Can `path` be written as a file (with `force`: replacing an existing one)? See the module
/// docs for the rule.
pub fn check_file(path: &Path, force: bool) -> Result<(), OutputError> {
    let shown = path.display().to_string();
    if ends_with_separator(path) {
        return Err(OutputError::TrailingSlash(shown));
    }
    let dir = parent_dir(path);
    if !dir.is_dir() {
        return Err(OutputError::NoDir {
            path: shown,
            dir: dir.display().to_string(),
        });
    }
    if path.is_dir() {
        return Err(OutputError::IsDir(shown));
    }
    if !force && path.symlink_metadata().is_ok() {
        return Err(OutputError::Exists(shown));
    }
    Ok(())
}

/// Can `dir` be used as an output directory: an existing directory, or a new one whose parent
/// exists (only that last level is created, by [`create_dir`])?
pub fn check_dir(dir: &Path) -> Result<(), OutputError> {
    if dir.is_dir() {
        return Ok(());
    }
    let shown = dir.display().to_string();
    if dir.symlink_metadata().is_ok() {
        return Err(OutputError::NotDir(shown));
    }
    let trimmed = PathBuf::from(shown.trim_end_matches(['/', std::path::MAIN_SEPARATOR]));
    let parent = parent_dir(&trimmed);
    if !parent.is_dir() {
        return Err(OutputError::NoDir {
            dir: parent.display().to_string(),
            path: shown,
        });
    }
    Ok(())
}

/// Create output directory `dir` if it does not exist (its parent must; see [`check_dir`]).
pub fn create_dir(dir: &Path) -> Result<(), OutputError> {
    check_dir(dir)?;
    if dir.is_dir() {
        return Ok(());
    }
    std::fs::create_dir(dir).map_err(|source| OutputError::Io {
        path: dir.display().to_string(),
        source,
    })
}

/// The temporary file `bytes` are written to before they are moved to `path`.
fn temp_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    parent_dir(path).join(format!(".{name}.{}.tmp", std::process::id()))
}

/// Write `bytes` to `path` atomically (a temporary file in the same directory, synced, then
/// moved into place), after [`check_file`]. Without `force` an existing file is never
/// replaced, even one created meanwhile: the temporary file is hard-linked to the target,
/// which fails if it exists.
pub fn write_file(path: &Path, bytes: &[u8], force: bool) -> Result<(), OutputError> {
    check_file(path, force)?;
    let shown = path.display().to_string();
    let tmp = temp_path(path);
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        drop(f);
        if force {
            std::fs::rename(&tmp, path)
        } else {
            match std::fs::hard_link(&tmp, path) {
                Ok(()) => std::fs::remove_file(&tmp),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => Err(e),
                // File systems without hard links: checked above, rename.
                Err(_) => std::fs::rename(&tmp, path),
            }
        }
    })();
    match result {
        Ok(()) => Ok(()),
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            if e.kind() == std::io::ErrorKind::AlreadyExists {
                Err(OutputError::Exists(shown))
            } else {
                Err(OutputError::Io { path: shown, source: e })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tmpdir(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("carl-output-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn one_rule_for_files() {
        let d = tmpdir("files");
        let f = d.join("a.json");
        // Missing parent: refused, nothing created.
        let missing = d.join("no/such/dir/a.json");
        assert!(matches!(check_file(&missing, true), Err(OutputError::NoDir { .. })));
        assert!(matches!(
            write_file(&missing, b"x", true),
            Err(OutputError::NoDir { .. })
        ));
        assert!(!d.join("no").exists());
        // A directory, or a path spelled as one, is not a file.
        assert!(matches!(check_file(&d, true), Err(OutputError::IsDir(_))));
        let slash = PathBuf::from(format!("{}/", f.display()));
        assert!(matches!(check_file(&slash, true), Err(OutputError::TrailingSlash(_))));
        // New file, then no replacement without force, then replacement with it.
        write_file(&f, b"one", false).unwrap();
        assert!(matches!(write_file(&f, b"two", false), Err(OutputError::Exists(_))));
        assert_eq!(std::fs::read(&f).unwrap(), b"one");
        write_file(&f, b"two", true).unwrap();
        assert_eq!(std::fs::read(&f).unwrap(), b"two");
        assert_eq!(names(&d), ["a.json"], "no temporary files left");
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn directories_are_created_one_level_only() {
        let d = tmpdir("dirs");
        let sub = d.join("frames");
        check_dir(&sub).unwrap();
        create_dir(&sub).unwrap();
        assert!(sub.is_dir());
        create_dir(&sub).unwrap();
        assert!(matches!(create_dir(&d.join("x/y")), Err(OutputError::NoDir { .. })));
        std::fs::write(d.join("file"), "").unwrap();
        assert!(matches!(check_dir(&d.join("file")), Err(OutputError::NotDir(_))));
        let _ = std::fs::remove_dir_all(&d);
    }
}
