//! Specs, validation, instance sets and samples, crossing as the JSON the CLI prints (the
//! Python package turns it into objects).

use std::path::PathBuf;
use std::sync::OnceLock;

use pyo3::prelude::*;

use carl_spec::envs::registry::{Context, MakeOptions, has_runtime, make_with};
use carl_spec::envs::{DType, Env as _, Space};
use carl_spec::instances::Store;
use carl_spec::instances::derive::{DeriveError, sample_adhoc};
use carl_spec::spec::SpecSet;
use carl_spec::spec::load::validation_inputs;
use carl_spec::validate;

use crate::errors::{make_error, store_error, unknown_name, value_error};

static BUNDLED: OnceLock<Result<SpecSet, String>> = OnceLock::new();

/// The bundled specs (validated once per process, then shared read-only), or bundled + `dir`.
pub(crate) fn with_specs<T>(specs_dir: Option<PathBuf>, f: impl FnOnce(&SpecSet) -> PyResult<T>) -> PyResult<T> {
    match specs_dir {
        None => {
            let specs = BUNDLED.get_or_init(|| SpecSet::bundled().map_err(|e| e.to_string()));
            f(specs.as_ref().map_err(value_error)?)
        }
        Some(dir) => f(&SpecSet::bundled_with(Some(&dir)).map_err(value_error)?),
    }
}

/// The spec of `name` (id or alias), or `UnknownNameError` with suggestions.
pub(crate) fn require<'a>(
    py: Python<'_>,
    specs: &'a SpecSet,
    name: &str,
) -> PyResult<&'a carl_spec::spec::model::EnvSpec> {
    specs.require(name).map_err(|m| unknown_name(py, m))
}

/// Every environment: `[{"id", "aliases", "family", "upstream", "features", "instance_sets", "runtime"}]`.
#[pyfunction]
#[pyo3(signature = (specs_dir=None))]
pub(crate) fn list_envs_json(specs_dir: Option<PathBuf>) -> PyResult<String> {
    with_specs(specs_dir, |specs| {
        let rows: Vec<_> = specs
            .envs()
            .iter()
            .map(|e| {
                let mut row = e.summary_json();
                row["runtime"] = has_runtime(&e.id).into();
                row
            })
            .collect();
        serde_json::to_string(&rows).map_err(value_error)
    })
}

/// The resolved spec as `carl-spec show ID --format json` prints it, plus the runtime's spaces.
#[pyfunction]
#[pyo3(signature = (name, specs_dir=None))]
pub(crate) fn spec_json(py: Python<'_>, name: &str, specs_dir: Option<PathBuf>) -> PyResult<String> {
    with_specs(specs_dir, |specs| {
        let spec = require(py, specs, name)?;
        let mut v = serde_json::to_value(spec).map_err(value_error)?;
        if has_runtime(&spec.id) {
            let env = make_with(spec, &Context::new(), MakeOptions::default()).map_err(|e| make_error(py, &e))?;
            v["runtime_spaces"] = serde_json::json!({
                "observation": space_json(&env.observation_space()),
                "action": space_json(&env.action_space()),
            });
        }
        serde_json::to_string(&v).map_err(value_error)
    })
}

fn dtype_name(d: DType) -> &'static str {
    match d {
        DType::Float32 => "float32",
        DType::Float64 => "float64",
        DType::UInt8 => "uint8",
    }
}

/// Infinite bounds cross as `null` (JSON has no infinity).
fn bound(x: f32) -> serde_json::Value {
    if x.is_finite() {
        serde_json::json!(x)
    } else {
        serde_json::Value::Null
    }
}

/// A Gymnasium space as the Python package rebuilds it (`kind`, `shape`, `dtype`, bounds, `n`).
pub(crate) fn space_json(s: &Space) -> serde_json::Value {
    match s {
        Space::Box {
            low,
            high,
            shape,
            dtype,
        } => serde_json::json!({
            "type": "box", "shape": shape, "dtype": dtype_name(*dtype),
            "low": low.iter().map(|x| bound(*x)).collect::<Vec<_>>(),
            "high": high.iter().map(|x| bound(*x)).collect::<Vec<_>>(),
        }),
        Space::Discrete { n, start } => serde_json::json!({"type": "discrete", "n": n, "start": start}),
    }
}

/// `carl-spec validate PATH… --format json`'s document (no paths: the bundled specs).
#[pyfunction]
#[pyo3(signature = (paths))]
pub(crate) fn validate_json(paths: Vec<PathBuf>) -> PyResult<String> {
    // The same inputs as the CLI (`carl-spec validate PATH…`).
    let inputs = validation_inputs(&paths).map_err(value_error)?;
    let (_resolved, report) = validate::run(&inputs);
    serde_json::to_string(&report.to_json()).map_err(value_error)
}

/// Declared instance sets, `ENV/SET`.
#[pyfunction]
#[pyo3(signature = (specs_dir=None))]
pub(crate) fn instance_sets(specs_dir: Option<PathBuf>) -> PyResult<Vec<String>> {
    with_specs(specs_dir, |specs| {
        Ok(Store::new(specs)
            .declared()
            .into_iter()
            .map(|(e, s)| format!("{}/{s}", e.id))
            .collect())
    })
}

/// A frozen set's file (checked: hash and spec digest), as JSON.
#[pyfunction]
#[pyo3(signature = (name, specs_dir=None))]
pub(crate) fn load_instances_json(py: Python<'_>, name: &str, specs_dir: Option<PathBuf>) -> PyResult<String> {
    with_specs(specs_dir, |specs| {
        let set = Store::new(specs).load(name).map_err(|e| store_error(py, e))?;
        serde_json::to_string(&set).map_err(value_error)
    })
}

/// `carl-spec sample ENV --distribution D -n N --seed S` as a frozen-set JSON document.
#[pyfunction]
#[pyo3(signature = (env, distribution, n, seed, specs_dir=None))]
pub(crate) fn sample_json(
    py: Python<'_>,
    env: &str,
    distribution: &str,
    n: u64,
    seed: u64,
    specs_dir: Option<PathBuf>,
) -> PyResult<String> {
    with_specs(specs_dir, |specs| {
        let spec = require(py, specs, env)?;
        let set = sample_adhoc(spec, distribution, n, seed).map_err(|e| match e {
            DeriveError::UnknownDistribution { .. } => unknown_name(py, e.to_string()),
            _ => value_error(e),
        })?;
        serde_json::to_string(&set).map_err(value_error)
    })
}
