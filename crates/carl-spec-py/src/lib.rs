//! `carl_spec._core`: a thin PyO3 layer over the carl-spec library.
//!
//! Everything here converts between Python and the library; behaviour lives in the library
//! (`carl_spec::envs::{contextual, vec_env}`, `instances::Store`, `validate`). Structured data
//! (specs, instance sets, diagnostics, samples) crosses as the same JSON the CLI prints, and the
//! Python package (`python/carl_spec`) turns it into objects. Every library error becomes a Python
//! exception carrying the library's message: unknown names raise `carl_spec.UnknownNameError`
//! (a `KeyError` and a `ValueError`), other bad input `ValueError`, misuse of an episode
//! (stepping before reset) `RuntimeError`.
//!
//! Where things are: `specs` (list, show, validate, instance sets, samples), `env` and `vec_env`
//! (the two environment classes), `context_args` (what their constructors take about contexts),
//! `obs_layout` (observations as Python sees them), `env_infos` / `vec_infos` / `info_keys`
//! (the info dicts, single and batched), `stock` (objects made ahead while workers step),
//! `arrays` (fresh NumPy arrays), `user_spec` (`cs.wrap` / `cs.audit` on users' own envs),
//! `errors` (library errors as Python exceptions), `cli` (the `carl-spec` command of the
//! package).

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use carl_spec::envs::registry::{has_runtime, ids};

mod actions;
mod arrays;
mod cli;
mod context_args;
mod env;
mod env_infos;
mod errors;
mod info_keys;
mod obs_layout;
mod specs;
mod stock;
mod user_spec;
mod vec_env;
mod vec_infos;

/// `{id: version}` of every runtime, from the bundled specs' `version` fields alone (read at
/// import for the Gymnasium ids `carl_spec/<id>-v<version>`; the full specs load on first use).
fn runtime_versions(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    #[derive(serde::Deserialize)]
    struct Versioned {
        id: Option<String>,
        #[serde(default)]
        version: u32,
    }
    let out = PyDict::new(py);
    for (path, text) in carl_spec::spec::load::bundled_files() {
        if path.contains('/') {
            continue; // fragments and frozen sets
        }
        let v: Versioned = serde_json::from_str(text)
            .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(format!("bundled spec {path}: {e}")))?;
        if let Some(id) = v.id.filter(|id| has_runtime(id)) {
            out.set_item(id, v.version)?;
        }
    }
    Ok(out)
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(cli::cli_main, m)?)?;
    m.add_function(wrap_pyfunction!(specs::list_envs_json, m)?)?;
    m.add_function(wrap_pyfunction!(specs::spec_json, m)?)?;
    m.add_function(wrap_pyfunction!(specs::validate_json, m)?)?;
    m.add_function(wrap_pyfunction!(specs::instance_sets, m)?)?;
    m.add_function(wrap_pyfunction!(specs::load_instances_json, m)?)?;
    m.add_function(wrap_pyfunction!(specs::sample_json, m)?)?;
    m.add_class::<context_args::ContextArgs>()?;
    m.add_class::<env::Env>()?;
    m.add_class::<vec_env::VecEnv>()?;
    m.add_function(wrap_pyfunction!(vec_env::episode_seeds, m)?)?;
    user_spec::register(m)?;
    m.add("RUNTIMES", PyList::new(m.py(), ids().collect::<Vec<_>>())?)?;
    m.add("VERSIONS", runtime_versions(m.py())?)?;
    m.add("VERSION", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
