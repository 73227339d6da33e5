//! Library errors as Python exceptions, each with the library's message: unknown names raise
//! `carl_spec.UnknownNameError` (a `KeyError` and a `ValueError`), bad input `ValueError`, misuse of
//! an episode `RuntimeError`.

use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

use carl_spec::envs::EnvError;
use carl_spec::envs::contextual::ContextualError;
use carl_spec::envs::registry::MakeError;
use carl_spec::instances::derive::DeriveError;

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

/// The library's message, with the CLI's flag named as the Python keyword.
pub(crate) fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(
        e.to_string()
            .replace("use --allow-out-of-bounds", "pass allow_out_of_bounds=True"),
    )
}

pub(crate) fn make_error(py: Python<'_>, e: &MakeError) -> PyErr {
    match e {
        MakeError::UnknownFeature { .. } | MakeError::NoRuntime { .. } | MakeError::UnknownOption { .. } => {
            unknown_name(py, e.to_string())
        }
        _ => value_error(e),
    }
}

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

pub(crate) fn env_error(e: &EnvError) -> PyErr {
    match e {
        EnvError::NeedsReset { .. } | EnvError::EpisodeOver { .. } => PyRuntimeError::new_err(e.to_string()),
        _ => value_error(e),
    }
}
