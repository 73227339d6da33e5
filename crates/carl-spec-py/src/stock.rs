//! Fresh NumPy arrays and info dicts made ahead of need. `make_vec`'s step is Python work that
//! only the calling thread can do (it holds the GIL) around a native step that all threads
//! share, so the objects it needs are made while the worker threads still step the batch
//! (`VecEnv::step_with`): `restock` there, `filled` / `nested` / `nones` after the step. What a
//! step hands out is as fresh as before: an object leaves the stock at most once, and no Python
//! code sees it before it is filled.

use std::any::TypeId;
use std::sync::Mutex;

use numpy::ndarray::IxDyn;
use numpy::{PyArray1, PyArrayDyn, PyArrayMethods};
use pyo3::prelude::*;

use crate::info_keys::{Columns, Nested};

/// Most objects one shelf keeps ready.
const MAX_PER_SHELF: usize = 64;

/// Ready objects of one kind: arrays of one element type and shape, or nested info dicts of
/// one set of columns.
struct Shelf {
    kind: Kind,
    ready: Vec<Ready>,
    /// Taken since the last restock.
    taken: usize,
    /// Kept ready: the most one step took so far (capped).
    want: usize,
}

enum Kind {
    Array {
        element: TypeId,
        dims: Vec<usize>,
        make: for<'py> fn(Python<'py>, &[usize]) -> Bound<'py, PyAny>,
    },
    /// Object arrays of `n` Nones.
    Nones { n: usize },
    /// [`Nested`] dicts of the [`Columns`] whose template is at this address, `n` rows.
    Nested { columns: usize, n: usize },
}

enum Ready {
    Object(Py<PyAny>),
    Nested(Nested),
}

impl Kind {
    fn is_array<T: 'static>(&self, d: &[usize]) -> bool {
        matches!(self, Kind::Array { element, dims, .. } if *element == TypeId::of::<T>() && dims == d)
    }

    /// A new object of this kind; `nested`: the columns that `Nested` kinds may name.
    fn make(&self, py: Python<'_>, nested: &[&Columns]) -> PyResult<Option<Ready>> {
        Ok(Some(match self {
            Kind::Array { dims, make, .. } => Ready::Object(make(py, dims).unbind()),
            Kind::Nones { n } => Ready::Object(nones(py, *n).into_any().unbind()),
            Kind::Nested { columns, n } => match nested.iter().find(|c| c.id() == *columns) {
                Some(c) => Ready::Nested(c.make_nested(py, *n)?),
                None => return Ok(None),
            },
        }))
    }
}

/// (A `Mutex` only because a `#[pyclass]` must be `Sync`: the GIL serialises every use.)
#[derive(Default)]
pub(crate) struct Stock {
    shelves: Mutex<Vec<Shelf>>,
}

fn uninit<'py, T: numpy::Element>(py: Python<'py>, dims: &[usize]) -> Bound<'py, PyAny> {
    // SAFETY: uninitialised until `Stock::filled` writes every element, before Python sees it.
    unsafe { PyArrayDyn::<T>::new(py, IxDyn(dims), false) }.into_any()
}

fn nones(py: Python<'_>, n: usize) -> Bound<'_, PyArray1<Py<PyAny>>> {
    PyArray1::from_vec(py, (0..n).map(|_| py.None()).collect())
}

impl Stock {
    /// Take a ready object from the shelf that `is_kind` finds (a shelf of `kind()` is added
    /// when there is none), or `None` when it has none ready.
    fn take(&self, is_kind: impl Fn(&Kind) -> bool, kind: impl FnOnce() -> Kind) -> Option<Ready> {
        let mut shelves = self.shelves.lock().unwrap_or_else(|e| e.into_inner());
        let i = match shelves.iter().position(|s| is_kind(&s.kind)) {
            Some(i) => i,
            None => {
                shelves.push(Shelf {
                    kind: kind(),
                    ready: Vec::new(),
                    taken: 0,
                    want: 0,
                });
                shelves.len() - 1
            }
        };
        let shelf = &mut shelves[i];
        shelf.taken += 1;
        shelf.ready.pop()
    }

    fn take_object(&self, is_kind: impl Fn(&Kind) -> bool, kind: impl FnOnce() -> Kind) -> Option<Py<PyAny>> {
        match self.take(is_kind, kind) {
            Some(Ready::Object(obj)) => Some(obj),
            _ => None,
        }
    }

    /// A C-contiguous array of `dims`, every element written by `fill` (as [`crate::arrays::filled`]).
    pub fn filled<'py, T: numpy::Element + 'static>(
        &self,
        py: Python<'py>,
        dims: &[usize],
        fill: impl FnOnce(&mut [T]),
    ) -> Bound<'py, PyAny> {
        let kind = || Kind::Array {
            element: TypeId::of::<T>(),
            dims: dims.to_vec(),
            make: uninit::<T>,
        };
        let Some(obj) = self.take_object(|k| k.is_array::<T>(dims), kind) else {
            return crate::arrays::filled(py, dims, fill);
        };
        // SAFETY: made by `uninit::<T>` with these dims (the shelf's kind says so), and held by
        // the stock alone until now: no Python code has seen it and nothing borrows it.
        let arr = unsafe { obj.into_bound(py).cast_into_unchecked::<PyArrayDyn<T>>() };
        fill(unsafe { arr.as_slice_mut() }.expect("a fresh array is contiguous"));
        arr.into_any()
    }

    /// A writeable object array of `n` Nones.
    pub fn nones<'py>(&self, py: Python<'py>, n: usize) -> Bound<'py, PyArray1<Py<PyAny>>> {
        match self.take_object(|k| matches!(k, Kind::Nones { n: m } if *m == n), || Kind::Nones { n }) {
            // SAFETY: a `Nones` shelf holds only arrays made by `nones`.
            Some(obj) => unsafe { obj.into_bound(py).cast_into_unchecked() },
            None => nones(py, n),
        }
    }

    /// A nested info dict of `columns` for `n` environments, its columns zero and its mask false.
    pub fn nested(&self, py: Python<'_>, columns: &Columns, n: usize) -> PyResult<Nested> {
        let id = columns.id();
        let kind = || Kind::Nested { columns: id, n };
        match self.take(
            |k| matches!(k, Kind::Nested { columns: c, n: m } if *c == id && *m == n),
            kind,
        ) {
            Some(Ready::Nested(kit)) => Ok(kit),
            _ => columns.make_nested(py, n),
        }
    }

    /// Make the shelves hold as many objects as the most that one step took from each, for as
    /// long as `go()` says (checked before each object): what is left is made when it is needed.
    /// `nested`: the columns of the nested info dicts (the ones `nested` was called with).
    pub fn restock(&self, py: Python<'_>, nested: &[&Columns], go: impl Fn() -> bool) -> PyResult<()> {
        let mut shelves = self.shelves.lock().unwrap_or_else(|e| e.into_inner());
        for shelf in shelves.iter_mut() {
            shelf.want = shelf.want.max(shelf.taken).min(MAX_PER_SHELF);
            shelf.taken = 0;
        }
        for shelf in shelves.iter_mut() {
            while shelf.ready.len() < shelf.want {
                if !go() {
                    return Ok(());
                }
                match shelf.kind.make(py, nested)? {
                    Some(ready) => shelf.ready.push(ready),
                    None => break,
                }
            }
        }
        Ok(())
    }
}
