//! The keys of Gymnasium's vector infos (`name` and its mask `_name`, made once as Python
//! strings) and the nested info dicts built from them (`{feature: column, _feature: mask}`):
//! what both the info builder (`vec_infos`) and the stock of objects made ahead (`stock`) name.

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

/// An info key and Gymnasium's mask key beside it (`name`, `_name`).
pub(crate) struct Keyed {
    pub key: Py<PyString>,
    pub mask: Py<PyString>,
}

impl Keyed {
    pub fn new(py: Python<'_>, name: &str) -> Self {
        Keyed {
            key: PyString::intern(py, name).unbind(),
            mask: PyString::intern(py, &format!("_{name}")).unbind(),
        }
    }
}

/// A [`Keyed`] of a literal name, its strings interned once per process.
macro_rules! keyed {
    ($py:expr, $name:literal) => {
        $crate::info_keys::Keyed {
            key: pyo3::intern!($py, $name).clone().unbind(),
            mask: pyo3::intern!($py, concat!("_", $name)).clone().unbind(),
        }
    };
}
pub(crate) use keyed;

/// The keys of a nested info dict (`{feature: column, _feature: mask}`), and that dict's layout
/// made once: copying it (same key order, table already sized) and filling in the values costs
/// less than growing a fresh dict key by key at every step.
pub(crate) struct Columns {
    keys: Vec<Keyed>,
    template: Py<PyDict>,
}

impl Columns {
    pub fn new<'a>(py: Python<'_>, names: impl IntoIterator<Item = &'a str>) -> PyResult<Self> {
        let keys: Vec<Keyed> = names.into_iter().map(|n| Keyed::new(py, n)).collect();
        let template = PyDict::new(py);
        for k in &keys {
            template.set_item(k.key.bind(py), py.None())?;
            template.set_item(k.mask.bind(py), py.None())?;
        }
        Ok(Columns {
            keys,
            template: template.unbind(),
        })
    }
}

/// A nested info dict made before it is filled: `{feature: column, _feature: mask}` with every
/// column zero and the one mask (shared by all features) false, and those arrays.
pub(crate) struct Nested {
    pub dict: Py<PyDict>,
    pub columns: Vec<Py<PyAny>>,
    pub mask: Py<PyAny>,
}

impl Columns {
    /// The feature keys, in the nested dict's order.
    pub fn keys(&self) -> &[Keyed] {
        &self.keys
    }

    /// Identifies these columns (and their [`Nested`] dicts in a [`Stock`]).
    pub fn id(&self) -> usize {
        self.template.as_ptr() as usize
    }

    /// A fresh [`Nested`] dict of these columns: `mask` (all false) under every `_feature` key
    /// and a column from `zeros` (an all-zero float64 array) under each feature.
    pub fn make_nested<'py>(
        &self,
        py: Python<'py>,
        mask: Bound<'py, PyAny>,
        mut zeros: impl FnMut() -> Bound<'py, PyAny>,
    ) -> PyResult<Nested> {
        let dict = self.template.bind(py).copy()?;
        let mut columns = Vec::with_capacity(self.keys.len());
        for name in &self.keys {
            let col = zeros();
            dict.set_item(name.key.bind(py), &col)?;
            dict.set_item(name.mask.bind(py), &mask)?;
            columns.push(col.unbind());
        }
        Ok(Nested {
            dict: dict.unbind(),
            columns,
            mask: mask.unbind(),
        })
    }
}
