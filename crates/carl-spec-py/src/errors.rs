//! Library errors as Python exceptions, each with the library's message: unknown names raise
//! `carl_spec.UnknownNameError` (a `KeyError` and a `ValueError`), bad input `ValueError`, misuse of
//! an episode `RuntimeError`.

use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

use carl_spec::envs::EnvError;
use carl_spec::envs::contextual::ContextualError;
use carl_spec::envs::registry::MakeError;
use carl_spec::instances::derive::DeriveError;
use carl_spec::instances::store::StoreError;

/// `carl_spec.UnknownNameError(message)` (defined in Python so it is both a KeyError and a
/// ValueError and prints its message without KeyError's quotes).
pub(crate) fn unknown_name(py: Python<'_>, message: String) -> PyErr {
    match py
        .import("carl_spec._errors")
        .and_then(|m| m.getattr("UnknownNameError"))
        .and_then(|cls| cls.call1((message.clone(),)))
    {
        Ok(exc) => PyErr::from_value(exc),
        Err(_) => PyValueError::new_err(message),
    }
}

/// `carl_spec.InvalidActionError(message)` (a ValueError and a TypeError, as `cs.make` raises).
pub(crate) fn invalid_action(py: Python<'_>, message: String) -> PyErr {
    match py
        .import("carl_spec._errors")
        .and_then(|m| m.getattr("InvalidActionError"))
        .and_then(|cls| cls.call1((message.clone(),)))
    {
        Ok(exc) => PyErr::from_value(exc),
        Err(_) => PyValueError::new_err(message),
    }
}

/// The library's message, with the CLI's flag named as the Python keyword.
pub(crate) fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(
        e.to_string()
            .replace("use --allow-out-of-bounds", "pass allow_out_of_bounds=True"),
    )
}

/// A failed `make`: unknown features, runtimes and options are unknown names, the rest bad input.
pub(crate) fn make_error(py: Python<'_>, e: &MakeError) -> PyErr {
    match e {
        MakeError::UnknownFeature { .. } | MakeError::NoRuntime { .. } | MakeError::UnknownOption { .. } => {
            unknown_name(py, e.to_string())
        }
        _ => value_error(e),
    }
}

/// A contextual env's options refused: unknown names (sets, distributions, features) or bad input.
pub(crate) fn contextual_error(py: Python<'_>, e: &ContextualError) -> PyErr {
    match e {
        ContextualError::UnknownDistribution { .. } | ContextualError::UnknownFeature { .. } => {
            unknown_name(py, e.to_string())
        }
        ContextualError::Make { source, .. }
            if matches!(
                **source,
                MakeError::UnknownFeature { .. } | MakeError::NoRuntime { .. } | MakeError::UnknownOption { .. }
            ) =>
        {
            unknown_name(py, e.to_string())
        }
        ContextualError::Derive(DeriveError::UnknownDistribution { .. } | DeriveError::UnknownFeature { .. }) => {
            unknown_name(py, e.to_string())
        }
        _ => value_error(e),
    }
}

/// Stepping before reset or after an episode's end is misuse (`RuntimeError`); a step that
/// Ctrl-C interrupted is a `KeyboardInterrupt`; a bad action is bad input.
pub(crate) fn env_error(e: &EnvError) -> PyErr {
    match e {
        EnvError::NeedsReset { .. } | EnvError::EpisodeOver { .. } => PyRuntimeError::new_err(e.to_string()),
        EnvError::Interrupted { .. } => pyo3::exceptions::PyKeyboardInterrupt::new_err(e.to_string()),
        _ => value_error(e),
    }
}

/// An unknown or malformed set name is an unknown name; a broken set file is bad input.
pub(crate) fn store_error(py: Python<'_>, e: StoreError) -> PyErr {
    use StoreError as S;
    match e {
        S::Unknown(_) | S::BadName(_) => unknown_name(py, e.to_string()),
        _ => value_error(e),
    }
}
