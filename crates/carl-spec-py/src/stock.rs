//! Fresh NumPy arrays and info dicts made ahead of need, and taken back when nobody else holds
//! them. `make_vec`'s step is Python work that only the calling thread can do (it holds the GIL)
//! around a native step that all threads share, so the objects it needs are made while the
//! worker threads step the batch (`VecEnv::step_with`): `restock` there, `filled` / `nested` /
//! `nones` after the step.
//!
//! Making and freeing those objects is most of that Python work, so a step's outputs that the
//! caller has let go of come back to the shelves (`reclaim`) instead of being freed: an array is
//! taken back only when the stock holds the one reference to it (no variable, container, view
//! or weak reference anywhere else), so no Python code can see it change. What a step hands out
//! is as fresh as before: every element is written before it leaves the stock again.

use std::any::TypeId;
use std::sync::{Mutex, MutexGuard};

use numpy::ndarray::IxDyn;
use numpy::npyffi::{
    _PyArray_GET_ITEM_DATA, NPY_ARRAY_ALIGNED, NPY_ARRAY_C_CONTIGUOUS, NPY_ARRAY_OWNDATA, NPY_ARRAY_WRITEABLE,
    PyArray_CheckExact, PyArray_Descr, PyArrayObject, PyArrayObject_fields, npy_intp,
};
use numpy::{Element, PyArray1, PyArrayDescr, PyArrayDyn, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::info_keys::{Columns, Nested};

/// Most objects one shelf keeps ready.
const MAX_PER_SHELF: usize = 64;

/// How deep `reclaim` looks into what a step returned: the tuple, its infos dict, `final_info`,
/// the nested dicts in that, and their arrays.
const RECLAIM_DEPTH: usize = 4;

/// Ready objects of one kind: arrays of one element type and shape, or nested info dicts of
/// one set of columns.
struct Shelf {
    kind: Kind,
    ready: Vec<Ready>,
    /// Taken since the last restock.
    taken: usize,
    /// Kept ready: the most taken between two restocks so far (capped).
    want: usize,
}

enum Kind {
    Array {
        element: TypeId,
        dims: Vec<usize>,
        make: for<'py> fn(Python<'py>, &[usize]) -> Bound<'py, PyAny>,
        /// NumPy's descriptor of the element type (its built-in ones are singletons: an array
        /// of this element type made by NumPy points to this very one).
        descr: Py<PyArrayDescr>,
    },
    /// Object arrays of `n` Nones (`descr`: NumPy's object descriptor).
    Nones { n: usize, descr: Py<PyArrayDescr> },
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

    /// Whether an array of `descr` and `dims` (exact, self-owned, contiguous: see
    /// `own_array`) belongs on this shelf.
    fn holds(&self, descr: *mut PyArray_Descr, dims: &[npy_intp]) -> bool {
        let same_dims = |d: &[usize]| d.len() == dims.len() && d.iter().zip(dims).all(|(&a, &b)| a as npy_intp == b);
        match self {
            Kind::Array { dims: d, descr: e, .. } => e.as_ptr().cast() == descr && same_dims(d),
            Kind::Nones { n, descr: e } => e.as_ptr().cast() == descr && same_dims(&[*n]),
            Kind::Nested { .. } => false,
        }
    }
}

fn uninit<'py, T: numpy::Element>(py: Python<'py>, dims: &[usize]) -> Bound<'py, PyAny> {
    // SAFETY: uninitialised until `Stock::filled` writes every element, before Python sees it.
    unsafe { PyArrayDyn::<T>::new(py, IxDyn(dims), false) }.into_any()
}

/// An object array of `n` Nones that owns its data (so that it can be reclaimed).
fn nones(py: Python<'_>, n: usize) -> Bound<'_, PyArray1<Py<PyAny>>> {
    let a = PyArray1::<Py<PyAny>>::zeros(py, n, false);
    // SAFETY: fresh and contiguous; assigning drops the zeros `zeros` put there.
    for slot in unsafe { a.as_slice_mut() }.expect("a fresh array is contiguous") {
        *slot = py.None();
    }
    a
}

/// The fields of `obj` if it is an exact `ndarray` that owns its C-contiguous, aligned data
/// and has no weak references: an array that the stock may refill in place once it holds the
/// only reference to it.
fn own_array<'a>(obj: &'a Bound<'_, PyAny>) -> Option<&'a PyArrayObject_fields> {
    // SAFETY: `obj` is a live object; its fields are read only after the exact type check.
    if unsafe { PyArray_CheckExact(obj.py(), obj.as_ptr()) } == 0 {
        return None;
    }
    let f = fields(obj);
    let need = NPY_ARRAY_OWNDATA | NPY_ARRAY_C_CONTIGUOUS | NPY_ARRAY_ALIGNED;
    (f.flags & need == need && f.base.is_null() && f.weakreflist.is_null()).then_some(f)
}

/// The fields of an exact `ndarray` (checked by `own_array`), alive as long as it is.
fn fields<'a>(array: &'a Bound<'_, PyAny>) -> &'a PyArrayObject_fields {
    // SAFETY: callers pass arrays that `own_array` accepted.
    unsafe { &*_PyArray_GET_ITEM_DATA(array.as_ptr() as *const PyArrayObject) }
}

/// The dims of an array's fields.
fn dims(f: &PyArrayObject_fields) -> &[npy_intp] {
    // SAFETY: NumPy keeps `nd` dims at `dimensions` (none: a null pointer is allowed then).
    match usize::try_from(f.nd) {
        Ok(nd) if nd > 0 => unsafe { std::slice::from_raw_parts(f.dimensions, nd) },
        _ => &[],
    }
}

/// Whether the caller's reference to `obj` is the only one.
fn only_ours(obj: &Bound<'_, PyAny>) -> bool {
    // SAFETY: a live object.
    unsafe { pyo3::ffi::Py_REFCNT(obj.as_ptr()) == 1 }
}

/// What `reclaim` takes back from a step's outputs.
struct Reclaimed<'a, 'py> {
    /// NumPy's object, float64 and bool descriptors.
    object: *mut PyArray_Descr,
    float: *mut PyArray_Descr,
    boolean: *mut PyArray_Descr,
    /// The columns of the nested dicts handed out, and their rows.
    nested: &'a [&'a Columns],
    n: usize,
    arrays: Vec<Bound<'py, PyAny>>,
    kits: Vec<(usize, Nested)>,
}

impl<'py> Reclaimed<'_, 'py> {
    /// Take apart what only the caller holds: a nested dict that is still exactly as made goes
    /// to `kits` whole; the items of other tuples and dicts are released (and looked into), and
    /// the arrays among them (`own_array`) go to `arrays`, object arrays emptied to Nones.
    /// Anything else is released as it would have been.
    fn take_apart(&mut self, obj: Bound<'py, PyAny>, depth: usize) {
        if !only_ours(&obj) {
            return;
        }
        let py = obj.py();
        let items: Vec<Bound<'py, PyAny>> = if let Ok(t) = obj.cast_exact::<PyTuple>() {
            t.iter().collect()
        } else if let Ok(d) = obj.cast_exact::<PyDict>() {
            if let Some(kit) = self.nested.iter().find_map(|c| self.as_kit(d, c)) {
                self.kits.push(kit);
                return;
            }
            d.iter().map(|(_, v)| v).collect()
        } else if let Some(f) = own_array(&obj) {
            let mut inner = Vec::new();
            if f.descr == self.object {
                // SAFETY: an object array, contiguous (`own_array`) and held by the caller alone.
                let objects = unsafe { obj.cast_unchecked::<PyArrayDyn<Py<PyAny>>>() };
                for slot in unsafe { objects.as_slice_mut() }.expect("checked contiguous") {
                    if !slot.is_none(py) {
                        inner.push(std::mem::replace(slot, py.None()).into_bound(py));
                    }
                }
            }
            self.arrays.push(obj.clone());
            inner
        } else {
            return;
        };
        // Released first, so that the items it held are held by `items` alone.
        drop(obj);
        if depth < RECLAIM_DEPTH {
            for item in items {
                self.take_apart(item, depth + 1);
            }
        }
    }

    /// `dict` (held by the caller alone) as a nested dict of `columns` again, its columns zero
    /// and its mask false, if it still is exactly as `Columns::make_nested` made it: the same
    /// keys in the same order, a float64 column of `n` rows under each feature and one bool mask
    /// under every `_feature`, none of them held by anything else.
    fn as_kit(&self, dict: &Bound<'py, PyDict>, columns: &Columns) -> Option<(usize, Nested)> {
        let keys = columns.keys();
        if dict.len() != 2 * keys.len() {
            return None;
        }
        let features = keys.len() as isize;
        let own = |v: &Bound<'_, PyAny>, descr: *mut PyArray_Descr, refs: isize| {
            // SAFETY: a live object.
            own_array(v).is_some_and(|f| f.descr == descr && dims(f) == [self.n as npy_intp])
                && unsafe { pyo3::ffi::Py_REFCNT(v.as_ptr()) } == refs
        };
        let mut cols = Vec::with_capacity(keys.len());
        let mut mask: Option<Bound<'py, PyAny>> = None;
        let mut entries = dict.iter();
        for k in keys {
            // Each value: the dict's reference and the iterator's.
            let (key, col) = entries.next()?;
            if !key.is(k.key.bind(dict.py())) || !own(&col, self.float, 2) {
                return None;
            }
            let (key, m) = entries.next()?;
            let same_mask = match &mask {
                Some(first) => first.is(&m),
                // The dict's `features` references and the iterator's.
                None => own(&m, self.boolean, features + 1),
            };
            if !key.is(k.mask.bind(dict.py())) || !same_mask {
                return None;
            }
            mask.get_or_insert(m);
            cols.push(col);
        }
        let mask = mask?;
        // SAFETY: float64 / bool arrays of `n` rows (checked), contiguous, held by this dict alone.
        for col in &cols {
            unsafe { col.cast_unchecked::<PyArrayDyn<f64>>().as_slice_mut() }
                .ok()?
                .fill(0.0);
        }
        unsafe { mask.cast_unchecked::<PyArrayDyn<bool>>().as_slice_mut() }
            .ok()?
            .fill(false);
        writeable(&mask);
        Some((
            columns.id(),
            Nested {
                dict: dict.clone().unbind(),
                columns: cols.into_iter().map(Bound::unbind).collect(),
                mask: mask.unbind(),
            },
        ))
    }
}

/// Make an array that only the stock holds writeable again (a mask made read-only by
/// `vec_infos::read_only`, before its next fill).
fn writeable(array: &Bound<'_, PyAny>) {
    // SAFETY: an exact ndarray (`own_array`) held by the stock alone.
    unsafe { (*_PyArray_GET_ITEM_DATA(array.as_ptr() as *const PyArrayObject)).flags |= NPY_ARRAY_WRITEABLE };
}

impl Shelf {
    /// Take a ready object (counted as taken), or `None` when none is ready.
    fn take(&mut self) -> Option<Ready> {
        self.taken += 1;
        self.ready.pop()
    }

    /// Whether a reclaimed object may join the ready ones: up to twice the most taken between
    /// two restocks (what a step hands out comes back two steps later, and steps that take
    /// more, such as those where episodes end, come in runs).
    fn has_room(&self) -> bool {
        self.ready.len() < (2 * self.want.max(self.taken).max(1)).min(MAX_PER_SHELF)
    }
}

#[derive(Default)]
struct Shelves(Vec<Shelf>);

impl Shelves {
    /// The shelf that `is_kind` finds (a shelf of `kind()` is added when there is none).
    fn shelf(&mut self, is_kind: impl Fn(&Kind) -> bool, kind: impl FnOnce() -> Kind) -> &mut Shelf {
        let i = match self.0.iter().position(|s| is_kind(&s.kind)) {
            Some(i) => i,
            None => {
                self.0.push(Shelf {
                    kind: kind(),
                    ready: Vec::new(),
                    taken: 0,
                    want: 0,
                });
                self.0.len() - 1
            }
        };
        &mut self.0[i]
    }

    /// The shelf of nested dicts of the columns `id` for `n` environments.
    fn nested_shelf(&mut self, id: usize, n: usize) -> &mut Shelf {
        self.shelf(
            |k| matches!(k, Kind::Nested { columns: c, n: m } if *c == id && *m == n),
            || Kind::Nested { columns: id, n },
        )
    }

    /// Take a ready object, or `None` when the shelf has none ready.
    fn take(&mut self, is_kind: impl Fn(&Kind) -> bool, kind: impl FnOnce() -> Kind) -> Option<Ready> {
        self.shelf(is_kind, kind).take()
    }

    fn filled<'py, T: numpy::Element + 'static>(
        &mut self,
        py: Python<'py>,
        dims: &[usize],
        fill: impl FnOnce(&mut [T]),
    ) -> Bound<'py, PyAny> {
        let kind = || Kind::Array {
            element: TypeId::of::<T>(),
            dims: dims.to_vec(),
            make: uninit::<T>,
            descr: T::get_dtype(py).unbind(),
        };
        let Some(Ready::Object(obj)) = self.take(|k| k.is_array::<T>(dims), kind) else {
            return crate::arrays::filled(py, dims, fill);
        };
        // SAFETY: made by `uninit::<T>` or reclaimed (`Kind::holds`: T's descriptor and these
        // dims, self-owned and contiguous), and held by the stock alone: no Python code can see
        // it and nothing borrows it.
        let arr = unsafe { obj.into_bound(py).cast_into_unchecked::<PyArrayDyn<T>>() };
        fill(unsafe { arr.as_slice_mut() }.expect("a fresh array is contiguous"));
        arr.into_any()
    }

    /// A nested dict of `columns`, its columns zero and its mask false (arrays from the shelves).
    fn make_nested(&mut self, py: Python<'_>, columns: &Columns, n: usize) -> PyResult<Nested> {
        let mask = self.filled(py, &[n], |o: &mut [bool]| o.fill(false));
        columns.make_nested(py, mask, || self.filled(py, &[n], |o: &mut [f64]| o.fill(0.0)))
    }

    /// Put a reclaimed array (one that `own_array` accepted) on its shelf if the shelf has room.
    fn put_back(&mut self, array: Bound<'_, PyAny>) {
        let f = fields(&array);
        let (descr, dims) = (f.descr, dims(f));
        let Some(shelf) = self.0.iter_mut().find(|s| s.kind.holds(descr, dims)) else {
            return;
        };
        if shelf.has_room() {
            writeable(&array);
            shelf.ready.push(Ready::Object(array.unbind()));
        }
    }
}

/// (A `Mutex` only because a `#[pyclass]` must be `Sync`: the GIL serialises every use.)
#[derive(Default)]
pub(crate) struct Stock {
    shelves: Mutex<Shelves>,
}

impl Stock {
    fn lock(&self) -> MutexGuard<'_, Shelves> {
        self.shelves.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// A C-contiguous array of `dims`, every element written by `fill` (as [`crate::arrays::filled`]).
    pub fn filled<'py, T: numpy::Element + 'static>(
        &self,
        py: Python<'py>,
        dims: &[usize],
        fill: impl FnOnce(&mut [T]),
    ) -> Bound<'py, PyAny> {
        self.lock().filled(py, dims, fill)
    }

    /// A writeable object array of `n` Nones.
    pub fn nones<'py>(&self, py: Python<'py>, n: usize) -> Bound<'py, PyArray1<Py<PyAny>>> {
        match self.lock().take(
            |k| matches!(k, Kind::Nones { n: m, .. } if *m == n),
            || Kind::Nones {
                n,
                descr: PyArrayDescr::object(py).unbind(),
            },
        ) {
            // SAFETY: a `Nones` shelf holds only object arrays of `n` Nones (made by `nones`, or
            // reclaimed and emptied by `take_apart`).
            Some(Ready::Object(obj)) => unsafe { obj.into_bound(py).cast_into_unchecked() },
            _ => nones(py, n),
        }
    }

    /// A nested info dict of `columns` for `n` environments, its columns zero and its mask false.
    pub fn nested(&self, py: Python<'_>, columns: &Columns, n: usize) -> PyResult<Nested> {
        let mut shelves = self.lock();
        match shelves.nested_shelf(columns.id(), n).take() {
            Some(Ready::Nested(kit)) => Ok(kit),
            _ => shelves.make_nested(py, columns, n),
        }
    }

    /// Make the shelves hold as many objects as the most taken between two restocks, for as long
    /// as `go()` says (checked before each object): what is left is made when it is needed.
    /// Nested dicts come first (their arrays come from the array shelves, which are then
    /// refilled). `nested`: the columns of the nested info dicts (the ones `nested` was called
    /// with).
    pub fn restock(&self, py: Python<'_>, nested: &[&Columns], go: impl Fn() -> bool) -> PyResult<()> {
        let mut shelves = self.lock();
        for shelf in shelves.0.iter_mut() {
            shelf.want = shelf.want.max(shelf.taken).min(MAX_PER_SHELF);
            shelf.taken = 0;
        }
        for i in 0..shelves.0.len() {
            let Kind::Nested { columns, n } = shelves.0[i].kind else {
                continue;
            };
            let Some(columns) = nested.iter().find(|c| c.id() == columns) else {
                continue;
            };
            while shelves.0[i].ready.len() < shelves.0[i].want {
                if !go() {
                    return Ok(());
                }
                let kit = shelves.make_nested(py, columns, n)?;
                shelves.0[i].ready.push(Ready::Nested(kit));
            }
        }
        for shelf in shelves.0.iter_mut() {
            while shelf.ready.len() < shelf.want {
                if !go() {
                    return Ok(());
                }
                shelf.ready.push(Ready::Object(match &shelf.kind {
                    Kind::Array { dims, make, .. } => make(py, dims).unbind(),
                    Kind::Nones { n, .. } => nones(py, *n).into_any().unbind(),
                    Kind::Nested { .. } => break,
                }));
            }
        }
        Ok(())
    }

    /// Release what a step returned (`obj`, the stock's own reference to it), taking back the
    /// arrays and nested dicts (of `nested`, for `n` environments) in it that nobody else holds:
    /// they are refilled instead of made anew.
    pub fn reclaim(&self, obj: Bound<'_, PyAny>, nested: &[&Columns], n: usize) {
        let py = obj.py();
        let descr = |d: Bound<'_, PyArrayDescr>| d.as_ptr().cast();
        let mut found = Reclaimed {
            object: descr(PyArrayDescr::object(py)),
            float: descr(f64::get_dtype(py)),
            boolean: descr(bool::get_dtype(py)),
            nested,
            n,
            arrays: Vec::new(),
            kits: Vec::new(),
        };
        found.take_apart(obj, 0);
        if found.arrays.is_empty() && found.kits.is_empty() {
            return;
        }
        let mut shelves = self.lock();
        for array in found.arrays {
            shelves.put_back(array);
        }
        for (id, kit) in found.kits {
            let shelf = shelves.nested_shelf(id, n);
            if shelf.has_room() {
                shelf.ready.push(Ready::Nested(kit));
            }
        }
    }
}
