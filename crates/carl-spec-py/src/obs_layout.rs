//! How a runtime's flat float32 observation buffer becomes what Python sees (arrays of the
//! declared dtype and shape, dicts, tuples).

use pyo3::prelude::*;
use pyo3::types::PyDict;

use carl_spec::envs::{DType, Space};

use crate::specs::space_json;
use crate::stock::Stock;

/// How the runtime's flat float32 buffer becomes what Python sees.
#[derive(Clone, Debug)]
pub(crate) enum ObsLayout {
    /// One array of the space's shape and dtype.
    Array { shape: Vec<usize>, dtype: DType },
    /// Pixels with the context appended: `{"obs": uint8 array of `shape`, "context": float32 (k,)}`
    /// (numbers cannot be appended to a uint8 picture without losing them).
    Split { shape: Vec<usize>, base: usize, k: usize },
}

impl ObsLayout {
    /// The layout of an environment whose base (runtime) observation space is `base` and whose
    /// observation has `visible` context features appended.
    pub(crate) fn new(base: &Space, full: &Space, visible: usize) -> Self {
        match (base, full) {
            (
                Space::Box {
                    shape,
                    dtype: DType::UInt8,
                    ..
                },
                _,
            ) if visible > 0 => ObsLayout::Split {
                base: shape.iter().product(),
                shape: shape.clone(),
                k: visible,
            },
            (_, Space::Box { shape, dtype, .. }) => ObsLayout::Array {
                shape: shape.clone(),
                dtype: *dtype,
            },
            (_, Space::Discrete { .. }) => ObsLayout::Array {
                shape: vec![],
                dtype: DType::Float32,
            },
        }
    }

    pub(crate) fn wide(&self) -> bool {
        matches!(
            self,
            ObsLayout::Array {
                dtype: DType::Float64,
                ..
            }
        )
    }

    /// `{"type": "dict", ...}` for split observations, else the space itself.
    pub(crate) fn space_json(&self, full: &Space) -> serde_json::Value {
        match (self, full) {
            (ObsLayout::Split { shape, base, .. }, Space::Box { low, high, .. }) => serde_json::json!({
                "type": "dict",
                "spaces": {
                    "obs": space_json(&Space::Box {
                        low: low[..*base].to_vec(), high: high[..*base].to_vec(),
                        shape: shape.clone(), dtype: DType::UInt8,
                    }),
                    "context": space_json(&Space::Box {
                        low: low[*base..].to_vec(), high: high[*base..].to_vec(),
                        shape: vec![low.len() - base], dtype: DType::Float32,
                    }),
                },
            }),
            _ => space_json(full),
        }
    }

    /// `n` observations (`batch = Some(n)`: with a leading batch axis) from the float32 rows,
    /// or from the float64 rows for float64 spaces.
    /// Arrays come from `stock` if given.
    pub(crate) fn value<'py>(
        &self,
        py: Python<'py>,
        flat: &[f32],
        wide: Option<&[f64]>,
        batch: Option<usize>,
        stock: Option<&Stock>,
    ) -> PyResult<Bound<'py, PyAny>> {
        // The batch axis and the shape, on the stack: a heap `Vec` here cost ~400 instructions
        // per call, and a same-step batch calls this once per finished episode.
        let dims = |shape: &[usize]| Dims::new(batch, shape);
        fn filled<'py, T: numpy::Element + 'static>(
            stock: Option<&Stock>,
            py: Python<'py>,
            dims: &[usize],
            fill: impl FnOnce(&mut [T]),
        ) -> Bound<'py, PyAny> {
            match stock {
                Some(s) => s.filled(py, dims, fill),
                None => crate::arrays::filled(py, dims, fill),
            }
        }
        Ok(match self {
            ObsLayout::Array { shape, dtype } => match (dtype, wide) {
                (DType::Float32, _) => filled(stock, py, dims(shape).as_slice(), |out: &mut [f32]| {
                    out.copy_from_slice(flat)
                }),
                (DType::Float64, Some(w)) => filled(stock, py, dims(shape).as_slice(), |out: &mut [f64]| {
                    out.copy_from_slice(w)
                }),
                (DType::Float64, None) => filled(stock, py, dims(shape).as_slice(), |out: &mut [f64]| {
                    for (o, x) in out.iter_mut().zip(flat) {
                        *o = f64::from(*x);
                    }
                }),
                // Pixel values are whole numbers 0..=255 held in f32.
                (DType::UInt8, _) => filled(stock, py, dims(shape).as_slice(), |out: &mut [u8]| {
                    for (o, x) in out.iter_mut().zip(flat) {
                        *o = *x as u8;
                    }
                }),
            },
            ObsLayout::Split { shape, base, k } => {
                let row = base + k;
                let pixels = filled(stock, py, dims(shape).as_slice(), |out: &mut [u8]| {
                    for (o, r) in out.chunks_exact_mut(*base).zip(flat.chunks_exact(row)) {
                        for (p, x) in o.iter_mut().zip(&r[..*base]) {
                            *p = *x as u8;
                        }
                    }
                });
                let context = filled(stock, py, dims(&[*k]).as_slice(), |out: &mut [f32]| {
                    for (o, r) in out.chunks_exact_mut(*k).zip(flat.chunks_exact(row)) {
                        o.copy_from_slice(&r[*base..]);
                    }
                });
                let d = PyDict::new(py);
                d.set_item("obs", pixels)?;
                d.set_item("context", context)?;
                d.into_any()
            }
        })
    }
}

/// An array's dims (an optional leading batch axis, then a space's shape): up to [`Dims::MAX`] on the
/// stack, more in a `Vec`.
enum Dims {
    Inline([usize; Dims::MAX], usize),
    Heap(Vec<usize>),
}

impl Dims {
    const MAX: usize = 6;

    fn new(batch: Option<usize>, shape: &[usize]) -> Self {
        let all = batch.into_iter().chain(shape.iter().copied());
        let len = usize::from(batch.is_some()) + shape.len();
        if len > Self::MAX {
            return Dims::Heap(all.collect());
        }
        let mut dims = [0; Self::MAX];
        for (d, v) in dims.iter_mut().zip(all) {
            *d = v;
        }
        Dims::Inline(dims, len)
    }

    fn as_slice(&self) -> &[usize] {
        match self {
            Dims::Inline(dims, len) => &dims[..*len],
            Dims::Heap(dims) => dims,
        }
    }
}
