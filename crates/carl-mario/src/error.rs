//! Typed errors: every bad input (missing data, corrupt weights, impossible sizes, unknown tiles)
//! ends up here with a message that says what to do, never as a panic.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum MarioError {
    #[error(
        "Mario data directory not found: {reason}.\n\
         Set CARL_SPEC_DATA (or pass --data-dir) to a folder with \
         mario/levels/original/lvl-1.txt … and mario/toad_gan/index.json + <generator>/{{manifest.json,weights.safetensors}}.\n\
         The levels and TOAD-GAN generators are CARL's (github.com/automl/CARL, carl/envs/mario/pcg_smb_env); \
         convert the generators with scripts/mario/gen_toad_gan_weights.py (numpy only) as the data guide \
         (docs/guides/data.md) describes."
    )]
    DataDirMissing { reason: String },

    #[error("cannot read {path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },

    #[error("{path}: invalid JSON: {source}")]
    Json {
        path: PathBuf,
        #[source]
        source: serde_json::Error,
    },

    #[error("{path}: corrupt generator weights: {reason}")]
    CorruptWeights { path: PathBuf, reason: String },

    #[error("{path}: invalid generator manifest: {reason}")]
    BadManifest { path: PathBuf, reason: String },

    #[error("level_index {index} out of range: the data directory has {available} generators (0..={last})", last = available.saturating_sub(1))]
    UnknownGenerator { index: usize, available: usize },

    /// A generator name in `toad_gan/index.json` that is not a plain folder name inside
    /// `toad_gan/` (a path separator, `.`, `..`, an absolute path, a control character).
    #[error(
        "{index}: generator {position} is named {name}, which is not a plain folder name inside toad_gan/ \
         (no path separators, `.`, `..` or control characters)"
    )]
    BadGeneratorName {
        index: PathBuf,
        position: usize,
        /// The name, escaped and cut for the message.
        name: String,
    },

    #[error("level width {width} out of range: TOAD-GAN levels are {min}..={max} tiles wide")]
    WidthOutOfRange { width: usize, min: usize, max: usize },

    #[error(
        "generator {generator} cannot make a level {width} tiles wide: CARL computes the initial noise width \
         as {initial_noise_width} but scale 0 as {scale0_width} and crashes (tensor size mismatch). \
         Nearest widths that work: {below:?} and {above:?} (or allow the scale-0 width explicitly)"
    )]
    WidthCrashesInCarl {
        generator: String,
        width: usize,
        initial_noise_width: usize,
        scale0_width: usize,
        below: Option<usize>,
        above: Option<usize>,
    },

    #[error("{origin}: line {line}, column {column}: unknown tile character {ch:?}")]
    UnknownTile {
        origin: String,
        line: usize,
        column: usize,
        ch: char,
    },

    #[error("{origin}: {reason}")]
    BadLevel { origin: String, reason: String },
}

pub type Result<T> = std::result::Result<T, MarioError>;
