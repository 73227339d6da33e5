//! Environment pictures to files: what `carl-spec render --out PATH` writes, as a library.
//!
//! The renderers themselves live with their environments (`Env::render` returns a
//! [`Frame`]); this module decides what `PATH` means and writes the frames, following the
//! crate's one rule for output files ([`crate::output`]):
//!
//! * `*.png`: one frame; `*.gif`: an animation. Such a path that is an existing directory is
//!   an error (it never silently becomes a frame directory).
//! * A directory (an existing one, or a path ending in `/`): one `frame_00000.png`, … per
//!   frame. Its parent must exist; only the last level is created. If it already holds frame
//!   files (`frame_<digits>.png`) of an earlier run, nothing is written without `force`; with
//!   `force` the old frame files are replaced or removed, so afterwards the frame files are
//!   exactly this run's. Other files in the directory are never touched.
//!
//! [`RenderOutput::check`] is meant to run before the episode is simulated, so a bad path
//! costs nothing; [`RenderOutput::write`] checks again.

use std::path::{Path, PathBuf};

use crate::output::{self, OutputError};
use crate::pixels::Frame;
use crate::pixels::encode::{gif_bytes, png_bytes};

/// Where and how `render` writes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum RenderOutput {
    Png(PathBuf),
    Gif(PathBuf),
    Frames(PathBuf),
}

#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The path names no format.
    #[error("{0}")]
    Path(String),
    #[error(transparent)]
    Output(#[from] OutputError),
    #[error("{0}")]
    Encode(String),
}

/// What was written.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Written {
    pub frames: usize,
    /// Stale frame files of an earlier run removed from a frame directory (with `force`).
    pub removed: Vec<PathBuf>,
}

fn frame_name(i: usize) -> String {
    format!("frame_{i:05}.png")
}

/// Is `name` a frame file name (`frame_` + digits + `.png`)?
fn is_frame_name(name: &str) -> bool {
    name.strip_prefix("frame_")
        .and_then(|r| r.strip_suffix(".png"))
        .is_some_and(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()))
}

/// The frame files in `dir` (sorted), or none if it does not exist.
pub fn frame_files(dir: &Path) -> Result<Vec<PathBuf>, OutputError> {
    if !dir.is_dir() {
        return Ok(Vec::new());
    }
    let io = |source| OutputError::Io {
        path: dir.display().to_string(),
        source,
    };
    let mut v = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(io)? {
        let entry = entry.map_err(io)?;
        if entry.file_name().to_str().is_some_and(is_frame_name) {
            v.push(entry.path());
        }
    }
    v.sort();
    Ok(v)
}

impl RenderOutput {
    /// The meaning of `--out PATH` (see the module docs).
    pub fn parse(path: &Path) -> Result<RenderOutput, RenderError> {
        let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        let file_ext = matches!(ext.as_deref(), Some("png" | "gif"));
        if output::ends_with_separator(path) {
            return Ok(RenderOutput::Frames(path.to_path_buf()));
        }
        if path.is_dir() {
            if file_ext {
                return Err(RenderError::Path(format!(
                    "--out {}: this .{} path is a directory; give a file that is not a directory, or write frames into the directory with --out {}/",
                    path.display(),
                    ext.unwrap_or_default(),
                    path.display()
                )));
            }
            return Ok(RenderOutput::Frames(path.to_path_buf()));
        }
        match ext.as_deref() {
            Some("png") => Ok(RenderOutput::Png(path.to_path_buf())),
            Some("gif") => Ok(RenderOutput::Gif(path.to_path_buf())),
            _ => Err(RenderError::Path(format!(
                "--out {}: use a .png file (one frame), a .gif file (animation) or a directory ending in / (PNG frames)",
                path.display()
            ))),
        }
    }

    /// Several frames (GIF, frame directory) or just the last state (PNG)?
    pub fn is_animation(&self) -> bool {
        !matches!(self, RenderOutput::Png(_))
    }

    pub fn path(&self) -> &Path {
        match self {
            RenderOutput::Png(p) | RenderOutput::Gif(p) | RenderOutput::Frames(p) => p,
        }
    }

    /// Would [`Self::write`] be allowed? Run it before the (possibly long) episode.
    pub fn check(&self, force: bool) -> Result<(), OutputError> {
        match self {
            RenderOutput::Png(p) | RenderOutput::Gif(p) => output::check_file(p, force),
            RenderOutput::Frames(dir) => {
                output::check_dir(dir)?;
                let old = frame_files(dir)?;
                match old.first() {
                    Some(first) if !force => Err(OutputError::EarlierRun {
                        dir: dir.display().to_string(),
                        count: old.len(),
                        example: first.display().to_string(),
                    }),
                    _ => Ok(()),
                }
            }
        }
    }

    /// Write `frames` (a PNG gets the last one), PNG files titled `title`, GIF frames
    /// `delay_cs` hundredths of a second apart.
    pub fn write(&self, frames: &[Frame], title: &str, delay_cs: u16, force: bool) -> Result<Written, RenderError> {
        self.check(force)?;
        let Some(last) = frames.last() else {
            return Err(RenderError::Encode("no frames to write".into()));
        };
        let software = format!("carl-spec {}", env!("CARGO_PKG_VERSION"));
        let png = |f: &Frame| png_bytes(f, &[("Title", title), ("Software", &software)]).map_err(RenderError::Encode);
        let mut removed = Vec::new();
        match self {
            RenderOutput::Png(p) => output::write_file(p, &png(last)?, force)?,
            RenderOutput::Gif(p) => {
                let bytes = gif_bytes(frames, delay_cs).map_err(RenderError::Encode)?;
                output::write_file(p, &bytes, force)?;
            }
            RenderOutput::Frames(dir) => {
                output::create_dir(dir)?;
                let old = frame_files(dir)?;
                let paths: Vec<PathBuf> = (0..frames.len()).map(|i| dir.join(frame_name(i))).collect();
                for (f, p) in frames.iter().zip(&paths) {
                    output::write_file(p, &png(f)?, force)?;
                }
                // Only after every new frame is in place: the directory then holds this run.
                for p in old.into_iter().filter(|p| !paths.contains(p)) {
                    std::fs::remove_file(&p).map_err(|source| OutputError::Io {
                        path: p.display().to_string(),
                        source,
                    })?;
                    removed.push(p);
                }
            }
        }
        Ok(Written {
            frames: if self.is_animation() { frames.len() } else { 1 },
            removed,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spec::SpecSet;

    /// The table's `renders` flag says what the runtimes do (so `render`'s messages, which read
    /// the table, can never disagree with the renderers).
    #[test]
    fn the_tables_renderer_flags_match_the_runtimes() {
        use crate::envs::Env;
        use crate::envs::registry::{Context, REGISTRY, make};
        let specs = SpecSet::bundled_with(None).unwrap();
        for reg in REGISTRY {
            let mut env = make(specs.get(reg.id).unwrap(), &Context::new()).unwrap();
            env.reset(Some(0));
            assert_eq!(env.render().is_some(), reg.renders, "{}", reg.id);
        }
    }

    #[test]
    fn frame_names() {
        assert!(is_frame_name("frame_00000.png"));
        assert!(is_frame_name("frame_123456.png"));
        assert!(!is_frame_name("frame_.png"));
        assert!(!is_frame_name("frame_0a.png"));
        assert!(!is_frame_name("notes.txt"));
        assert!(!is_frame_name("frame_00001.png.tmp"));
        assert_eq!(frame_name(7), "frame_00007.png");
    }
}
