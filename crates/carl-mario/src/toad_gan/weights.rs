//! Loading a converted generator: `manifest.json` (tokens, sizes, noise amplitudes) and
//! `weights.safetensors` (8-byte little-endian header length, JSON header, raw little-endian f32).
//! Every size and offset is checked, so corrupt files give an error, not a panic.

use crate::data::{read, read_json};
use crate::error::{MarioError, Result};
use serde::Deserialize;
use std::collections::{BTreeMap, HashMap};
use std::path::Path;

#[derive(Debug, Deserialize)]
pub(crate) struct RawManifest {
    pub name: String,
    pub tokens: Vec<String>,
    pub num_layer: usize,
    pub original_height: usize,
    pub original_width: usize,
    pub scales: Vec<RawScale>,
}

#[derive(Debug, Deserialize)]
pub(crate) struct RawScale {
    pub noise_amplitude_f32_hex: String,
    pub noise_map_shape: Vec<usize>,
    pub real_shape: Vec<usize>,
}

#[derive(Debug, Deserialize)]
struct RawTensor {
    dtype: String,
    shape: Vec<usize>,
    data_offsets: [usize; 2],
}

/// An f32 tensor with its shape.
#[derive(Debug, Clone)]
pub(crate) struct Tensor {
    pub shape: Vec<usize>,
    pub data: Vec<f32>,
}

/// Reads a safetensors file into named f32 tensors.
pub(crate) fn read_safetensors(path: &Path) -> Result<HashMap<String, Tensor>> {
    let bytes = read(path)?;
    let corrupt = |reason: String| MarioError::CorruptWeights {
        path: path.to_path_buf(),
        reason,
    };
    let head: [u8; 8] = bytes.get(..8).and_then(|b| b.try_into().ok()).ok_or_else(|| {
        corrupt(format!(
            "file is {} bytes, shorter than the 8-byte header length",
            bytes.len()
        ))
    })?;
    let header_len = u64::from_le_bytes(head);
    let data_start = usize::try_from(header_len)
        .ok()
        .and_then(|n| n.checked_add(8))
        .filter(|&end| end <= bytes.len())
        .ok_or_else(|| {
            corrupt(format!(
                "header length {header_len} exceeds the file size {}",
                bytes.len()
            ))
        })?;
    let header: BTreeMap<String, serde_json::Value> = serde_json::from_slice(&bytes[8..data_start])
        .map_err(|e| corrupt(format!("header is not a JSON object: {e}")))?;
    let data = &bytes[data_start..];
    let mut out = HashMap::new();
    for (name, value) in header {
        if name == "__metadata__" {
            continue;
        }
        let t: RawTensor = serde_json::from_value(value).map_err(|e| corrupt(format!("tensor {name}: {e}")))?;
        if t.dtype != "F32" {
            return Err(corrupt(format!("tensor {name}: dtype {} (expected F32)", t.dtype)));
        }
        let [a, b] = t.data_offsets;
        let count = t.shape.iter().try_fold(1usize, |acc, &d| acc.checked_mul(d));
        if a > b || b > data.len() || count.and_then(|c| c.checked_mul(4)) != Some(b - a) {
            return Err(corrupt(format!(
                "tensor {name}: offsets [{a}, {b}] do not fit shape {:?} inside {} data bytes",
                t.shape,
                data.len()
            )));
        }
        let values = data[a..b]
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect::<Vec<_>>();
        if let Some(bad) = values.iter().position(|v| !v.is_finite()) {
            return Err(corrupt(format!("tensor {name}: element {bad} is not finite")));
        }
        out.insert(
            name,
            Tensor {
                shape: t.shape,
                data: values,
            },
        );
    }
    Ok(out)
}

/// Reads `manifest.json`.
pub(crate) fn read_manifest(path: &Path) -> Result<RawManifest> {
    read_json(path)
}

/// Takes tensor `name` out of `tensors`, checking its shape.
pub(crate) fn take(
    tensors: &mut HashMap<String, Tensor>,
    path: &Path,
    name: &str,
    shape: &[usize],
) -> Result<Vec<f32>> {
    let t = tensors.remove(name).ok_or_else(|| MarioError::CorruptWeights {
        path: path.to_path_buf(),
        reason: format!("tensor {name} is missing"),
    })?;
    if t.shape != shape {
        return Err(MarioError::CorruptWeights {
            path: path.to_path_buf(),
            reason: format!("tensor {name} has shape {:?}, expected {shape:?}", t.shape),
        });
    }
    Ok(t.data)
}
