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
//! * **Temporary files cannot be hijacked.** A temporary file has an unpredictable name
//!   ([`TEMP_PREFIX`] and 64 random bits, e.g. `.carl-spec-3f9c0e41d2a7b615.tmp`) and is
//!   created with `O_CREAT|O_EXCL` (and `O_NOFOLLOW` on Unix): a file or symlink planted at that
//!   name makes the creation fail (another name is tried) instead of writing through the link.
//!   Temporary files of carl-spec older than [`STALE_TEMP_AGE`] (left by a killed run) are removed
//!   from the directory before writing; nothing else there is touched.
//!
//! `freeze` ([`crate::instances`]) writes its files through [`write_temp`] too. This module
//! depends on nothing else in the crate.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Duration;

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

/// The prefix of every temporary file carl-spec writes beside an output file.
pub const TEMP_PREFIX: &str = ".carl-spec-";

/// The suffix of every temporary file carl-spec writes.
pub const TEMP_SUFFIX: &str = ".tmp";

/// A temporary file of carl-spec older than this was left by a killed run (no write takes an
/// hour: the bytes are computed before the file is created) and is removed.
pub const STALE_TEMP_AGE: Duration = Duration::from_secs(3600);

/// 64 bits no other process can predict: std's `RandomState` keys come from the operating
/// system's random source; the process id, the time and a counter make each call differ.
fn random_bits() -> u64 {
    use std::hash::{BuildHasher, Hasher};
    use std::sync::atomic::{AtomicU64, Ordering};
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let mut h = std::collections::hash_map::RandomState::new().build_hasher();
    h.write_u64(COUNTER.fetch_add(1, Ordering::Relaxed));
    h.write_u32(std::process::id());
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    h.write_u128(nanos);
    h.finish()
}

/// Whether `name` is the name of a carl-spec temporary file.
pub fn is_temp_name(name: &str) -> bool {
    name.strip_prefix(TEMP_PREFIX)
        .and_then(|r| r.strip_suffix(TEMP_SUFFIX))
        .is_some_and(|hex| hex.len() == 16 && hex.bytes().all(|b| b.is_ascii_hexdigit()))
}

/// Open a new file at `path` for writing, failing if anything (a file, a directory, a symlink,
/// dangling or not) is already there: `O_CREAT|O_EXCL`, plus `O_NOFOLLOW` on Unix. `O_EXCL`
/// alone already refuses a symlink as the last component (POSIX: "if O_EXCL and O_CREAT are
/// set, and path names a symbolic link, open() shall fail with EEXIST"); `O_NOFOLLOW` says so
/// twice.
fn create_exclusive(path: &Path) -> std::io::Result<std::fs::File> {
    let mut options = std::fs::OpenOptions::new();
    options.write(true).create_new(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NOFOLLOW);
    }
    options.open(path)
}

/// Create a temporary file with an unpredictable name in `dir` (see the module docs), write
/// `bytes` to it, sync it and return its path; the caller moves it into place (or removes it).
/// Stale temporary files of carl-spec in `dir` are removed first.
pub fn write_temp(dir: &Path, bytes: &[u8]) -> std::io::Result<PathBuf> {
    remove_stale_temp_files(dir, STALE_TEMP_AGE);
    let mut last = None;
    for _ in 0..16 {
        let tmp = dir.join(format!("{TEMP_PREFIX}{:016x}{TEMP_SUFFIX}", random_bits()));
        match create_exclusive(&tmp) {
            Ok(mut f) => {
                let written = f.write_all(bytes).and_then(|()| f.sync_all());
                drop(f);
                return match written {
                    Ok(()) => Ok(tmp),
                    Err(e) => {
                        let _ = std::fs::remove_file(&tmp);
                        Err(e)
                    }
                };
            }
            // Something sits at that name (64 random bits: planted, not chance): another name.
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => last = Some(e),
            Err(e) => return Err(e),
        }
    }
    Err(last.unwrap_or_else(|| std::io::Error::other("no temporary file could be created")))
}

/// Remove carl-spec's temporary files ([`is_temp_name`]: its prefix, 16 hex digits, `.tmp`) in
/// `dir` that are regular files last modified more than `older_than` ago. Nothing else is
/// touched: not other programs' files, not symlinks, not carl-spec's fresh files (another
/// carl-spec may be writing them). Returns the files removed.
pub fn remove_stale_temp_files(dir: &Path, older_than: Duration) -> Vec<PathBuf> {
    let mut removed = Vec::new();
    let Ok(entries) = std::fs::read_dir(dir) else {
        return removed;
    };
    for e in entries.flatten() {
        if !is_temp_name(&e.file_name().to_string_lossy()) {
            continue;
        }
        let Ok(meta) = std::fs::symlink_metadata(e.path()) else {
            continue;
        };
        let old = meta
            .modified()
            .is_ok_and(|t| t.elapsed().is_ok_and(|age| age > older_than));
        if meta.file_type().is_file() && old && std::fs::remove_file(e.path()).is_ok() {
            removed.push(e.path());
        }
    }
    removed
}

/// Write `bytes` to `path` atomically (a temporary file in the same directory, created by
/// [`write_temp`], then moved into place), after [`check_file`]. Without `force` an existing
/// file is never replaced, even one created meanwhile: the temporary file is hard-linked to the
/// target, which fails if it exists. With `force` the rename replaces a symlink at `path`
/// itself, never the file it points to.
pub fn write_file(path: &Path, bytes: &[u8], force: bool) -> Result<(), OutputError> {
    check_file(path, force)?;
    let shown = path.display().to_string();
    let tmp = write_temp(parent_dir(path), bytes).map_err(|source| OutputError::Io {
        path: shown.clone(),
        source,
    })?;
    let result = if force {
        std::fs::rename(&tmp, path)
    } else {
        match std::fs::hard_link(&tmp, path) {
            Ok(()) => std::fs::remove_file(&tmp),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => Err(e),
            // File systems without hard links: checked above, rename.
            Err(_) => std::fs::rename(&tmp, path),
        }
    };
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

    #[test]
    fn temporary_names_are_unpredictable_and_recognised() {
        let d = tmpdir("names");
        let a = write_temp(&d, b"a").unwrap();
        let b = write_temp(&d, b"b").unwrap();
        assert_ne!(a, b);
        for t in [&a, &b] {
            let name = t.file_name().unwrap().to_string_lossy().into_owned();
            assert!(is_temp_name(&name), "{name}");
            assert!(!name.contains(&std::process::id().to_string()), "{name}");
        }
        assert!(!is_temp_name(".a.json.123.tmp"));
        assert!(!is_temp_name(".carl-spec-zzzzzzzzzzzzzzzz.tmp"));
        let _ = std::fs::remove_dir_all(&d);
    }

    #[cfg(unix)]
    #[test]
    fn exclusive_creation_refuses_planted_symlinks() {
        let d = tmpdir("exclusive");
        let victim = d.join("victim");
        std::fs::write(&victim, "keep").unwrap();
        let link = d.join("link");
        std::os::unix::fs::symlink(&victim, &link).unwrap();
        let e = create_exclusive(&link).unwrap_err();
        assert_eq!(e.kind(), std::io::ErrorKind::AlreadyExists, "{e}");
        let dangling = d.join("dangling");
        std::os::unix::fs::symlink(d.join("nowhere"), &dangling).unwrap();
        assert!(create_exclusive(&dangling).is_err());
        assert!(!d.join("nowhere").exists(), "a dangling link's target was created");
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "keep");

        // The name earlier versions used (`.NAME.PID.tmp`) is not followed either, and writing
        // with force replaces a symlink at the target itself, not the file it points to.
        let out = d.join("out.svg");
        std::os::unix::fs::symlink(&victim, d.join(format!(".out.svg.{}.tmp", std::process::id()))).unwrap();
        write_file(&out, b"new", false).unwrap();
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "keep");
        let target_link = d.join("t.svg");
        std::os::unix::fs::symlink(&victim, &target_link).unwrap();
        write_file(&target_link, b"new", true).unwrap();
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "keep");
        assert!(!target_link.symlink_metadata().unwrap().file_type().is_symlink());
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn only_stale_temporary_files_of_carl_spec_are_removed() {
        let d = tmpdir("stale");
        let old = d.join(".carl-spec-00112233445566ff.tmp");
        let fresh = d.join(".carl-spec-ffeeddccbbaa9988.tmp");
        let other = d.join(".other-00112233445566ff.tmp");
        for p in [&old, &fresh, &other] {
            std::fs::write(p, "x").unwrap();
        }
        let two_hours_ago = std::time::SystemTime::now() - Duration::from_secs(7200);
        for p in [&old, &other] {
            std::fs::File::options()
                .write(true)
                .open(p)
                .unwrap()
                .set_modified(two_hours_ago)
                .unwrap();
        }
        assert_eq!(remove_stale_temp_files(&d, STALE_TEMP_AGE), vec![old.clone()]);
        assert!(!old.exists() && fresh.exists() && other.exists());
        // Writing a file cleans the directory the same way.
        std::fs::File::options()
            .write(true)
            .open(&fresh)
            .unwrap()
            .set_modified(two_hours_ago)
            .unwrap();
        write_file(&d.join("f.txt"), b"1", false).unwrap();
        assert!(!fresh.exists());
        assert_eq!(names(&d), [".other-00112233445566ff.tmp", "f.txt"]);
        let _ = std::fs::remove_dir_all(&d);
    }
}
