//! TOAD-GAN level generation: what CARL's `generate_level(width, 16, level_index, seed)`
//! computes, from the converted generators (`toad_gan/<name>/{manifest.json,weights.safetensors}`)
//! and without an ML framework.
//!
//! A level is a pure function of (generator, width, seed): scale 0's noise is
//! `torch.randn` seeded with the seed, scales 1 and 2 always use seed 0 (CARL's behaviour).
//!
//! **Widths CARL crashes on.** CARL sizes scale 0's noise twice with two rounding orders; for
//! 303 of the 14,775 (generator, width) pairs they disagree and CARL raises a tensor-size error.
//! There is no reference level for those pairs, so [`WidthMismatch::Reject`] (the default) reports
//! a [`MarioError::WidthCrashesInCarl`] naming the nearest widths that work; callers that want a
//! level anyway choose [`WidthMismatch::UseScale0Width`] (noise drawn at the scale-0 width, the
//! only size the network can consume).

pub mod network;
pub mod noise;
mod weights;

use crate::data::{DataDir, read_json};
use crate::error::{MarioError, Result};
use network::{BatchNormLeaky, Conv3x3, Map, argmax_channels, softmax_channels};
use serde::Deserialize;
use std::path::Path;

/// Level height of every CARL level.
pub const LEVEL_HEIGHT: usize = 16;
/// Narrowest and widest levels CARL's `level_width` allows.
pub const MIN_WIDTH: usize = 16;
pub const MAX_WIDTH: usize = 1000;

/// What to do for the (generator, width) pairs on which CARL crashes (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum WidthMismatch {
    /// Report [`MarioError::WidthCrashesInCarl`] (faithful: CARL has no level there).
    #[default]
    Reject,
    /// Draw scale 0's noise at the network's scale-0 width and generate a level.
    UseScale0Width,
}

/// One generator's conv → BN → LeakyReLU layers, tail conv, noise amplitude and sizes.
#[derive(Debug, Clone)]
struct Scale {
    /// Training noise map rows/cols (only used to size the sample).
    noise_rows: usize,
    noise_cols: usize,
    /// Size of the training image at this scale (scale 0's starting image is zeros of it).
    real_rows: usize,
    real_cols: usize,
    amplitude: f32,
    blocks: Vec<(Conv3x3, BatchNormLeaky)>,
    tail: Conv3x3,
}

/// A loaded TOAD-GAN generator.
#[derive(Debug, Clone)]
pub struct Generator {
    name: String,
    tokens: Vec<char>,
    num_layer: usize,
    original_height: usize,
    original_width: usize,
    scales: Vec<Scale>,
}

#[derive(Debug, Deserialize)]
struct Index {
    generators: Vec<IndexEntry>,
}

#[derive(Debug, Deserialize)]
struct IndexEntry {
    name: String,
}

/// Generator names in CARL's `level_index` order (`toad_gan/index.json`). Every name must be a
/// plain folder name ([`is_plain_name`]), so a generator is always read from inside `toad_gan/`.
pub fn generator_names(data: &DataDir) -> Result<Vec<String>> {
    let index_path = data.toad_gan().join("index.json");
    let index: Index = read_json(&index_path)?;
    let names: Vec<String> = index.generators.into_iter().map(|g| g.name).collect();
    if let Some((position, bad)) = names.iter().enumerate().find(|(_, n)| !is_plain_name(n)) {
        return Err(MarioError::BadGeneratorName {
            index: index_path,
            position,
            name: shown_name(bad),
        });
    }
    Ok(names)
}

/// Whether `name` names an entry directly inside a directory: not empty, not `.` or `..`, no
/// `/`, `\` or `:` (a Windows drive or stream), no control characters, at most 255 bytes.
pub fn is_plain_name(name: &str) -> bool {
    !name.is_empty()
        && name.len() <= 255
        && name != "."
        && name != ".."
        && !name.chars().any(|c| matches!(c, '/' | '\\' | ':') || c.is_control())
}

/// `name` quoted for a message: escaped (Rust's debug form) and cut to 80 characters.
fn shown_name(name: &str) -> String {
    let cut: String = name.chars().take(80).collect();
    if cut.len() < name.len() {
        format!("{:?}… ({} bytes)", cut, name.len())
    } else {
        format!("{cut:?}")
    }
}

impl Generator {
    /// Loads generator `level_index` (CARL's order) from the data directory.
    pub fn load_index(data: &DataDir, level_index: usize) -> Result<Self> {
        let names = generator_names(data)?;
        let name = names.get(level_index).ok_or(MarioError::UnknownGenerator {
            index: level_index,
            available: names.len(),
        })?;
        Self::load(&data.toad_gan().join(name))
    }

    /// Loads a generator folder (`manifest.json` + `weights.safetensors`).
    pub fn load(dir: &Path) -> Result<Self> {
        let manifest_path = dir.join("manifest.json");
        let man = weights::read_manifest(&manifest_path)?;
        let bad = |reason: String| MarioError::BadManifest {
            path: manifest_path.clone(),
            reason,
        };
        let tokens = man
            .tokens
            .iter()
            .map(|t| {
                let mut chars = t.chars();
                match (chars.next(), chars.next()) {
                    (Some(c), None) if c.is_ascii_graphic() => Ok(c),
                    _ => Err(bad(format!("token {t:?} is not one ASCII tile character"))),
                }
            })
            .collect::<Result<Vec<char>>>()?;
        let c = tokens.len();
        let nl = man.num_layer;
        if c == 0 || nl < 2 || man.scales.is_empty() || man.original_height == 0 || man.original_width == 0 {
            return Err(bad("empty tokens, scales or sizes, or num_layer < 2".into()));
        }
        let weights_path = dir.join("weights.safetensors");
        let mut tensors = weights::read_safetensors(&weights_path)?;
        let mut scales = Vec::with_capacity(man.scales.len());
        for (s, raw) in man.scales.iter().enumerate() {
            let (&[_, zc, zh, zw], &[_, rc, rh, rw]) = (raw.noise_map_shape.as_slice(), raw.real_shape.as_slice())
            else {
                return Err(bad(format!(
                    "scale {s}: noise_map_shape and real_shape must have 4 entries"
                )));
            };
            if zc != c || rc != c || zh <= 2 * nl || zw <= 2 * nl || rh == 0 || rw == 0 {
                return Err(bad(format!(
                    "scale {s}: shapes {:?} / {:?} do not fit {c} tokens",
                    raw.noise_map_shape, raw.real_shape
                )));
            }
            let amplitude = u32::from_str_radix(&raw.noise_amplitude_f32_hex, 16)
                .map(f32::from_bits)
                .ok()
                .filter(|a| a.is_finite())
                .ok_or_else(|| {
                    bad(format!(
                        "scale {s}: noise_amplitude_f32_hex {:?}",
                        raw.noise_amplitude_f32_hex
                    ))
                })?;
            // The feature width (nfc) is read from the head conv's bias.
            let nfc = tensors
                .get(&format!("scale{s}.head.conv.bias"))
                .map(|t| t.data.len())
                .ok_or_else(|| MarioError::CorruptWeights {
                    path: weights_path.clone(),
                    reason: format!("tensor scale{s}.head.conv.bias is missing"),
                })?;
            let mut blocks = Vec::new();
            for i in 0..nl - 1 {
                let prefix = if i == 0 {
                    format!("scale{s}.head")
                } else {
                    format!("scale{s}.body.block{i}")
                };
                let cin = if i == 0 { c } else { nfc };
                let conv_layer = Conv3x3 {
                    cin,
                    cout: nfc,
                    weight: weights::take(
                        &mut tensors,
                        &weights_path,
                        &format!("{prefix}.conv.weight"),
                        &[nfc, cin, 3, 3],
                    )?,
                    bias: weights::take(&mut tensors, &weights_path, &format!("{prefix}.conv.bias"), &[nfc])?,
                };
                let mut norm =
                    |p: &str| weights::take(&mut tensors, &weights_path, &format!("{prefix}.norm.{p}"), &[nfc]);
                let bn = BatchNormLeaky::new(
                    norm("running_mean")?,
                    norm("running_var")?,
                    norm("weight")?,
                    norm("bias")?,
                );
                if bn.std.iter().any(|s| s.is_nan() || *s <= 0.0) {
                    return Err(MarioError::CorruptWeights {
                        path: weights_path.clone(),
                        reason: format!("{prefix}.norm.running_var has a negative entry"),
                    });
                }
                blocks.push((conv_layer, bn));
            }
            let tail = Conv3x3 {
                cin: nfc,
                cout: c,
                weight: weights::take(
                    &mut tensors,
                    &weights_path,
                    &format!("scale{s}.tail.0.weight"),
                    &[c, nfc, 3, 3],
                )?,
                bias: weights::take(&mut tensors, &weights_path, &format!("scale{s}.tail.0.bias"), &[c])?,
            };
            scales.push(Scale {
                noise_rows: zh,
                noise_cols: zw,
                real_rows: rh,
                real_cols: rw,
                amplitude,
                blocks,
                tail,
            });
        }
        Ok(Generator {
            name: man.name,
            tokens,
            num_layer: nl,
            original_height: man.original_height,
            original_width: man.original_width,
            scales,
        })
    }

    pub fn name(&self) -> &str {
        &self.name
    }

    /// Tile characters in channel order.
    pub fn tokens(&self) -> &[char] {
        &self.tokens
    }

    /// `(rows, cols)` of every scale for a level `width` wide, as CARL sizes them:
    /// `round((Z - 2·nl)·(16/oh))` in f64 with the division first, Python's half-to-even round.
    pub fn scale_sizes(&self, width: usize) -> Vec<(usize, usize)> {
        let nl2 = 2 * self.num_layer;
        let fy = LEVEL_HEIGHT as f64 / self.original_height as f64;
        let fx = width as f64 / self.original_width as f64;
        self.scales
            .iter()
            .map(|s| {
                (
                    ((s.noise_rows - nl2) as f64 * fy).round_ties_even() as usize,
                    ((s.noise_cols - nl2) as f64 * fx).round_ties_even() as usize,
                )
            })
            .collect()
    }

    /// The width CARL gives scale 0's initial noise: `round((Z - 2·nl)·W/ow)`, multiplication first.
    pub fn initial_noise_width(&self, width: usize) -> usize {
        let z = (self.scales[0].noise_cols - 2 * self.num_layer) * width;
        (z as f64 / self.original_width as f64).round_ties_even() as usize
    }

    /// Whether CARL can generate a level of this width with this generator.
    pub fn carl_accepts_width(&self, width: usize) -> bool {
        self.initial_noise_width(width) == self.scale_sizes(width)[0].1
    }

    fn check_width(&self, width: usize, policy: WidthMismatch) -> Result<()> {
        if !(MIN_WIDTH..=MAX_WIDTH).contains(&width) {
            return Err(MarioError::WidthOutOfRange {
                width,
                min: MIN_WIDTH,
                max: MAX_WIDTH,
            });
        }
        if policy == WidthMismatch::Reject && !self.carl_accepts_width(width) {
            let ok = |w: &usize| self.carl_accepts_width(*w);
            return Err(MarioError::WidthCrashesInCarl {
                generator: self.name.clone(),
                width,
                initial_noise_width: self.initial_noise_width(width),
                scale0_width: self.scale_sizes(width)[0].1,
                below: (MIN_WIDTH..width).rev().find(ok),
                above: (width + 1..=MAX_WIDTH).find(ok),
            });
        }
        Ok(())
    }

    /// Generates the level (16 rows joined by `\n`, no trailing newline: the string CARL passes
    /// to the engine).
    pub fn generate(&self, width: usize, seed: u32, policy: WidthMismatch) -> Result<String> {
        self.generate_scaled(width, seed, 1.0, policy)
    }

    /// [`Generator::generate`] with scale 0's noise multiplied by `noise_scale` (σ; the paper's
    /// explicit noise map, σ-scaled). σ = 1 is CARL's sampling exactly (the product is exact);
    /// σ = 0 gives the generator's noise-free level.
    pub fn generate_scaled(&self, width: usize, seed: u32, noise_scale: f32, policy: WidthMismatch) -> Result<String> {
        self.check_width(width, policy)?;
        if !noise_scale.is_finite() {
            return Err(MarioError::BadLevel {
                origin: self.name.clone(),
                reason: format!("noise scale {noise_scale} is not finite"),
            });
        }
        let c = self.tokens.len();
        let nl = self.num_layer;
        let sizes = self.scale_sizes(width);
        let mut prev: Option<Map> = None;
        for (s, (scale, &(h, w))) in self.scales.iter().zip(&sizes).enumerate() {
            let noise_seed = if s == 0 { u64::from(seed) } else { 0 };
            let mut data = noise::randn(c * h * w, noise_seed);
            if s == 0 && noise_scale != 1.0 {
                data.iter_mut().for_each(|v| *v *= noise_scale);
            }
            let z = Map { c, h, w, data }.pad(nl);
            let base = prev
                .take()
                .unwrap_or_else(|| Map::zeros(c, scale.real_rows, scale.real_cols));
            let resized = base.resize_bilinear(h, w);
            let i_prev = resized.pad(nl);
            let mut x = z;
            for (xv, iv) in x.data.iter_mut().zip(&i_prev.data) {
                *xv = scale.amplitude * *xv + iv;
            }
            for (conv, bn) in &scale.blocks {
                x = conv.forward(&x);
                bn.apply(&mut x);
            }
            let mut out = scale.tail.forward(&x);
            softmax_channels(&mut out);
            for (ov, rv) in out.data.iter_mut().zip(&resized.data) {
                *ov += rv;
            }
            prev = Some(out);
        }
        let img = prev.expect("at least one scale");
        let idx = argmax_channels(&img);
        let rows: Vec<String> = idx
            .chunks(img.w)
            .map(|row| row.iter().map(|&k| self.tokens[k]).collect())
            .collect();
        Ok(rows.join("\n"))
    }
}
