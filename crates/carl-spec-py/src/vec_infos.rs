//! Gymnasium's vector info layout (what `VectorEnv._add_info` builds env by env in Python), built
//! in Rust for `make_vec`'s batch step. The keys are Python strings made once per batch: a
//! same-step LunarLander batch builds 16 masked feature columns at every step where an episode
//! ends, so every allocation per feature counts.

use numpy::npyffi::{_PyArray_GET_ITEM_DATA, NPY_ARRAY_WRITEABLE};
use numpy::{PyArrayDyn, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::info_keys::{Columns, Keyed};
use crate::stock::Stock;

/// A fresh bool array of `n` entries, true at `rows`.
pub(crate) fn mask<'py>(stock: &Stock, py: Python<'py>, n: usize, rows: &[usize]) -> Bound<'py, PyAny> {
    stock.filled(py, &[n], |o: &mut [bool]| {
        o.fill(false);
        for &i in rows {
            o[i] = true;
        }
    })
}

/// `array` made read-only: an array shared by several keys (or steps) must not let a reader
/// change one key's value through another's.
pub(crate) fn read_only(array: Bound<'_, PyAny>) -> Bound<'_, PyAny> {
    let a = array.cast::<PyArrayDyn<bool>>().expect("a bool mask made by `mask`");
    // SAFETY: a fresh array that no Rust borrow and no Python code has seen yet; clearing the
    // flag is what `ndarray.setflags(write=False)` does.
    unsafe { (*_PyArray_GET_ITEM_DATA(a.as_array_ptr())).flags &= !NPY_ARRAY_WRITEABLE };
    array
}

/// `obj` made read-only if it is a NumPy array (what a cache shares between steps' infos).
pub(crate) fn read_only_any(obj: &Bound<'_, PyAny>) {
    if let Ok(a) = obj.cast::<PyUntypedArray>() {
        // SAFETY: clearing the flag is what `ndarray.setflags(write=False)` does; no Rust borrow
        // of the array is alive.
        unsafe { (*_PyArray_GET_ITEM_DATA(a.as_array_ptr())).flags &= !NPY_ARRAY_WRITEABLE };
    }
}

/// A column of numbers: `key` holds each listed env's value (zero elsewhere), `_key` the mask of
/// the envs that have one.
pub(crate) fn set_column<T: numpy::Element + Copy + Default + 'static>(
    stock: &Stock,
    d: &Bound<'_, PyDict>,
    key: &Keyed,
    n: usize,
    rows: &[(usize, T)],
) -> PyResult<()> {
    let py = d.py();
    let col = stock.filled(py, &[n], |o: &mut [T]| {
        o.fill(T::default());
        for &(i, v) in rows {
            o[i] = v;
        }
    });
    let at: Vec<usize> = rows.iter().map(|(i, _)| *i).collect();
    d.set_item(key.key.bind(py), col)?;
    d.set_item(key.mask.bind(py), mask(stock, py, n, &at))
}

/// A nested info dict (`{feature: value}` per env): one masked column per feature under `key`,
/// and `_key`, the mask of the envs that have the dict. `value(k, j)`: the value of `names[j]`
/// of env `rows[k]`.
pub(crate) fn set_nested(
    stock: &Stock,
    d: &Bound<'_, PyDict>,
    key: &Keyed,
    n: usize,
    names: &Columns,
    rows: &[usize],
    value: impl Fn(usize, usize) -> f64,
) -> PyResult<()> {
    let py = d.py();
    let kit = stock.nested(py, names, n)?;
    // SAFETY: the kit's arrays are fresh (made by `make_nested`, held by the kit alone, not yet
    // seen by Python code), contiguous float64 / bool arrays of `n` entries.
    for (j, col) in kit.columns.iter().enumerate() {
        let col = unsafe { col.bind(py).cast_unchecked::<PyArrayDyn<f64>>() };
        let o = unsafe { col.as_slice_mut() }.expect("a fresh array is contiguous");
        for (k, &i) in rows.iter().enumerate() {
            o[i] = value(k, j);
        }
    }
    let shared = kit.mask.into_bound(py);
    let o = unsafe { shared.cast_unchecked::<PyArrayDyn<bool>>().as_slice_mut() }.expect("a fresh array is contiguous");
    for &i in rows {
        o[i] = true;
    }
    // Every feature has the same mask: one read-only array serves them all.
    read_only(shared);
    d.set_item(key.key.bind(py), kit.dict.bind(py))?;
    d.set_item(key.mask.bind(py), mask(stock, py, n, rows))
}
