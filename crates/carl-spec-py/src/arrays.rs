//! Fresh NumPy arrays written from Rust in one pass.

use numpy::ndarray::IxDyn;
use numpy::{PyArrayDyn, PyArrayMethods};
use pyo3::prelude::*;

/// A fresh C-contiguous array of `dims`, written by `fill` (one allocation, no reshape).
pub(crate) fn filled<'py, T: numpy::Element>(
    py: Python<'py>,
    dims: &[usize],
    fill: impl FnOnce(&mut [T]),
) -> Bound<'py, PyAny> {
    // SAFETY: `fill` writes every element before Python can see the array (all callers copy
    // exactly `dims.product()` values), and a fresh array is contiguous.
    let arr = unsafe { PyArrayDyn::<T>::new(py, IxDyn(dims), false) };
    fill(unsafe { arr.as_slice_mut() }.expect("a fresh array is contiguous"));
    arr.into_any()
}
