//! `carl_spec._core`: a thin PyO3 layer over the carl-spec library.
//!
//! Everything here converts between Python and the library; behaviour lives in the library
//! (`carl_spec::envs::{contextual, vec_env}`, `instances::Store`, `validate`). Structured data
//! (specs, instance sets, diagnostics, samples) crosses as the same JSON the CLI prints, and the
//! Python package (`python/carl_spec`) turns it into objects. Every library error becomes a Python
//! exception carrying the library's message: unknown names raise `carl_spec.UnknownNameError`
//! (a `KeyError` and a `ValueError`), other bad input `ValueError`, misuse of an episode
//! (stepping before reset) `RuntimeError`.

use std::borrow::Cow;
use std::path::PathBuf;
use std::sync::OnceLock;

use numpy::ndarray::IxDyn;
use numpy::{PyArray1, PyArrayDyn, PyArrayMethods, PyReadonlyArray1, PyUntypedArrayMethods};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use pyo3::{PyTraverseError, PyVisit};

use carl_spec::envs::contextual::{
    ContextInfo, ContextNoise, ContextSource, ContextualEnv, ContextualError, ContextualOptions, NoiseRedraw, NoiseStd,
};
use carl_spec::envs::registry::{
    Context, EnvOptions, MakeError, MakeOptions, has_runtime, ids, ids_text, make_env, make_with,
};
use carl_spec::envs::rna_design::RnaDesign;
use carl_spec::envs::vec_env::{AutoresetMode, VecActions, VecEnv as RustVecEnv, VecEnvError, VecOptions};
use carl_spec::envs::{Action, AnyEnv, DType, Env as _, EnvError, Features, Space, Visibility};
use carl_spec::instances::Store;
use carl_spec::instances::derive::{DeriveError, sample_adhoc};
use carl_spec::spec::SpecSet;
use carl_spec::spec::load::{bundled_inputs, read_inputs};
use carl_spec::validate;

mod info_keys;
mod stock;
mod user_spec;
mod vec_infos;

use info_keys::{Columns, keyed};
use stock::Stock;
use vec_infos::{mask, read_only, set_column, set_nested};

// ---------------------------------------------------------------------------------------
// Errors

/// `carl_spec.UnknownNameError(message)` (defined in Python so it is both a KeyError and a
/// ValueError and prints its message without KeyError's quotes).
fn unknown_name(py: Python<'_>, message: String) -> PyErr {
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
fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(
        e.to_string()
            .replace("use --allow-out-of-bounds", "pass allow_out_of_bounds=True"),
    )
}

fn make_error(py: Python<'_>, e: &MakeError) -> PyErr {
    match e {
        MakeError::UnknownFeature { .. } | MakeError::NoRuntime { .. } | MakeError::UnknownOption { .. } => {
            unknown_name(py, e.to_string())
        }
        _ => value_error(e),
    }
}

fn contextual_error(py: Python<'_>, e: &ContextualError) -> PyErr {
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

fn env_error(e: &EnvError) -> PyErr {
    match e {
        EnvError::NeedsReset { .. } | EnvError::EpisodeOver { .. } => PyRuntimeError::new_err(e.to_string()),
        _ => value_error(e),
    }
}

// ---------------------------------------------------------------------------------------
// Specs

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

fn require<'a>(py: Python<'_>, specs: &'a SpecSet, name: &str) -> PyResult<&'a carl_spec::spec::model::EnvSpec> {
    specs.require(name).map_err(|m| unknown_name(py, m))
}

/// Every environment: `[{"id", "aliases", "family", "upstream", "features", "instance_sets", "runtime"}]`.
#[pyfunction]
#[pyo3(signature = (specs_dir=None))]
fn list_envs_json(specs_dir: Option<PathBuf>) -> PyResult<String> {
    with_specs(specs_dir, |specs| {
        let rows: Vec<_> = specs
            .envs()
            .iter()
            .map(|e| {
                serde_json::json!({
                    "id": e.id, "aliases": e.aliases, "family": e.family,
                    "upstream": format!("{} {}", e.upstream.library, e.upstream.id),
                    "features": e.features.len(),
                    "instance_sets": e.instance_sets.keys().collect::<Vec<_>>(),
                    "runtime": has_runtime(&e.id),
                })
            })
            .collect();
        serde_json::to_string(&rows).map_err(value_error)
    })
}

/// The resolved spec as `carl-spec show ID --format json` prints it, plus the runtime's spaces.
#[pyfunction]
#[pyo3(signature = (name, specs_dir=None))]
fn spec_json(py: Python<'_>, name: &str, specs_dir: Option<PathBuf>) -> PyResult<String> {
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

fn space_json(s: &Space) -> serde_json::Value {
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
fn validate_json(paths: Vec<PathBuf>) -> PyResult<String> {
    // The same inputs as the CLI: bundled files by repository path, or the given files plus the
    // bundled shared fragments an author's spec may include.
    let inputs: Vec<validate::Input> = if paths.is_empty() {
        bundled_inputs(false)
            .into_iter()
            .map(|mut i| {
                i.name = i.name.trim_start_matches("bundled:").to_string();
                i
            })
            .collect()
    } else {
        let mut inputs = read_inputs(&paths).map_err(value_error)?;
        if inputs.is_empty() {
            let shown: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
            return Err(value_error(format!(
                "no *.json spec files found in {}",
                shown.join(", ")
            )));
        }
        inputs.extend(bundled_inputs(true).into_iter().filter(|i| i.name.contains("/shared/")));
        inputs
    };
    let (_resolved, report) = validate::run(&inputs);
    let v = serde_json::json!({
        "valid": !report.has_errors(),
        "files": report.files_checked,
        "environments": report.environments,
        "errors": report.errors(),
        "warnings": report.warnings(),
        "diagnostics": report.diagnostics,
    });
    serde_json::to_string(&v).map_err(value_error)
}

/// Declared instance sets, `ENV/SET`.
#[pyfunction]
#[pyo3(signature = (specs_dir=None))]
fn instance_sets(specs_dir: Option<PathBuf>) -> PyResult<Vec<String>> {
    with_specs(specs_dir, |specs| {
        Ok(Store::new(specs)
            .declared()
            .into_iter()
            .map(|(e, s)| format!("{}/{s}", e.id))
            .collect())
    })
}

fn store_error(py: Python<'_>, e: carl_spec::instances::store::StoreError) -> PyErr {
    use carl_spec::instances::store::StoreError as S;
    match e {
        S::Unknown(_) | S::BadName(_) => unknown_name(py, e.to_string()),
        _ => value_error(e),
    }
}

/// A frozen set's file (checked: hash and spec digest), as JSON.
#[pyfunction]
#[pyo3(signature = (name, specs_dir=None))]
fn load_instances_json(py: Python<'_>, name: &str, specs_dir: Option<PathBuf>) -> PyResult<String> {
    with_specs(specs_dir, |specs| {
        let set = Store::new(specs).load(name).map_err(|e| store_error(py, e))?;
        serde_json::to_string(&set).map_err(value_error)
    })
}

/// `carl-spec sample ENV --distribution D -n N --seed S` as a frozen-set JSON document.
#[pyfunction]
#[pyo3(signature = (env, distribution, n, seed, specs_dir=None))]
fn sample_json(
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

// ---------------------------------------------------------------------------------------
// Environments

/// Everything `make` / `make_vec` pass about contexts, as the Python constructors hand it over.
#[derive(Clone)]
struct SourceArgs {
    context_json: Option<String>,
    instances: Option<String>,
    distribution: Option<String>,
    selection: String,
    instance: Option<usize>,
    obs_context: Option<Vec<String>>,
    obs_context_all: bool,
    /// Variant options (`{"continuous": true}`), as a JSON object.
    options_json: Option<String>,
    noise: ContextNoise,
    allow_out_of_bounds: bool,
}

impl SourceArgs {
    fn context(&self) -> PyResult<Context> {
        match &self.context_json {
            Some(text) => serde_json::from_str(text).map_err(|e| value_error(format!("context: {e}"))),
            None => Ok(Context::new()),
        }
    }

    fn env_options(&self) -> PyResult<EnvOptions> {
        match &self.options_json {
            Some(text) => serde_json::from_str(text).map_err(|e| {
                value_error(format!(
                    "options: {e} (values are true/false, numbers or lists of numbers)"
                ))
            }),
            None => Ok(EnvOptions::new()),
        }
    }

    /// A fixed context without visible features: the plain batch (no contextual wrapper).
    fn is_plain(&self) -> bool {
        self.instances.is_none()
            && self.distribution.is_none()
            && self.obs_context.as_ref().is_none_or(Vec::is_empty)
            && !self.obs_context_all
            && self.noise.is_empty()
    }
}

fn build_contextual(py: Python<'_>, specs: &SpecSet, env: &str, a: &SourceArgs) -> PyResult<ContextualEnv> {
    let spec = require(py, specs, env)?;
    if !has_runtime(&spec.id) {
        return Err(unknown_name(
            py,
            MakeError::NoRuntime {
                env: spec.id.clone(),
                available: ids_text(),
            }
            .to_string(),
        ));
    }
    let given = [
        a.context_json.is_some(),
        a.instances.is_some(),
        a.distribution.is_some(),
    ];
    if given.iter().filter(|g| **g).count() > 1 {
        return Err(value_error(
            "give at most one of context=, instances= and distribution=",
        ));
    }
    if a.allow_out_of_bounds && (a.instances.is_some() || a.distribution.is_some()) {
        return Err(value_error(
            "allow_out_of_bounds=True applies to a fixed context= (an instance set declares its own \
             out-of-bounds policy; distribution draws are always inside the bounds)",
        ));
    }
    let source = if let Some(name) = &a.instances {
        let name = if name.contains('/') {
            name.clone()
        } else {
            format!("{}/{name}", spec.id)
        };
        ContextSource::Set(Store::new(specs).load(&name).map_err(|e| store_error(py, e))?)
    } else if let Some(name) = &a.distribution {
        ContextSource::Distribution { name: name.clone() }
    } else {
        ContextSource::Fixed(a.context()?)
    };
    let selection = user_spec::parse_selection(&a.selection, a.instance)?;
    let visibility = if a.obs_context_all {
        Visibility::Visible(Features::All)
    } else {
        match &a.obs_context {
            Some(names) if !names.is_empty() => Visibility::Visible(Features::Only(names.clone())),
            _ => Visibility::Hidden,
        }
    };
    if !a.noise.is_empty() && visibility == Visibility::Hidden {
        return Err(value_error(NOISE_NEEDS_OBS_CONTEXT));
    }
    ContextualEnv::new(
        spec,
        source,
        ContextualOptions {
            selection,
            visibility,
            noise: a.noise.clone(),
            env_options: a.env_options()?,
            allow_out_of_bounds: a.allow_out_of_bounds,
        },
    )
    .map_err(|e| contextual_error(py, &e))
}

/// How the runtime's flat float32 buffer becomes what Python sees.
#[derive(Clone, Debug)]
enum ObsLayout {
    /// One array of the space's shape and dtype.
    Array { shape: Vec<usize>, dtype: DType },
    /// Pixels with the context appended: `{"obs": uint8 array of `shape`, "context": float32 (k,)}`
    /// (numbers cannot be appended to a uint8 picture without losing them).
    Split { shape: Vec<usize>, base: usize, k: usize },
}

impl ObsLayout {
    /// The layout of an environment whose base (runtime) observation space is `base` and whose
    /// observation has `visible` context features appended.
    fn new(base: &Space, full: &Space, visible: usize) -> Self {
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

    fn wide(&self) -> bool {
        matches!(
            self,
            ObsLayout::Array {
                dtype: DType::Float64,
                ..
            }
        )
    }

    /// `{"type": "dict", ...}` for split observations, else the space itself.
    fn space_json(&self, full: &Space) -> serde_json::Value {
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
    fn value<'py>(
        &self,
        py: Python<'py>,
        flat: &[f32],
        wide: Option<&[f64]>,
        batch: Option<usize>,
        stock: Option<&Stock>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let dims = |shape: &[usize]| -> Vec<usize> { batch.into_iter().chain(shape.iter().copied()).collect() };
        fn filled<'py, T: numpy::Element + 'static>(
            stock: Option<&Stock>,
            py: Python<'py>,
            dims: &[usize],
            fill: impl FnOnce(&mut [T]),
        ) -> Bound<'py, PyAny> {
            match stock {
                Some(s) => s.filled(py, dims, fill),
                None => crate::filled(py, dims, fill),
            }
        }
        Ok(match self {
            ObsLayout::Array { shape, dtype } => match (dtype, wide) {
                (DType::Float32, _) => filled(stock, py, &dims(shape), |out: &mut [f32]| out.copy_from_slice(flat)),
                (DType::Float64, Some(w)) => filled(stock, py, &dims(shape), |out: &mut [f64]| out.copy_from_slice(w)),
                (DType::Float64, None) => filled(stock, py, &dims(shape), |out: &mut [f64]| {
                    for (o, x) in out.iter_mut().zip(flat) {
                        *o = f64::from(*x);
                    }
                }),
                // Pixel values are whole numbers 0..=255 held in f32.
                (DType::UInt8, _) => filled(stock, py, &dims(shape), |out: &mut [u8]| {
                    for (o, x) in out.iter_mut().zip(flat) {
                        *o = *x as u8;
                    }
                }),
            },
            ObsLayout::Split { shape, base, k } => {
                let row = base + k;
                let pixels = filled(stock, py, &dims(shape), |out: &mut [u8]| {
                    for (o, r) in out.chunks_exact_mut(*base).zip(flat.chunks_exact(row)) {
                        for (p, x) in o.iter_mut().zip(&r[..*base]) {
                            *p = *x as u8;
                        }
                    }
                });
                let context = filled(stock, py, &dims(&[*k]), |out: &mut [f32]| {
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

fn info_dict<'py>(py: Python<'py>, ci: &ContextInfo) -> PyResult<Bound<'py, PyDict>> {
    context_info_dict(
        py,
        &ci.context,
        ci.instance_id,
        ci.instance_name.as_deref(),
        ci.context_seed,
    )
}

/// The info dict of an episode's context, shared by `Env`, `VecEnv` and users' `ContextChooser`.
/// Only what the seed determines (check_env compares infos across equal seeds), so no episode
/// counter.
pub(crate) fn context_info_dict<'py>(
    py: Python<'py>,
    context: &[(String, f64)],
    instance_id: Option<usize>,
    instance_name: Option<&str>,
    context_seed: Option<u64>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let ctx = PyDict::new(py);
    for (k, v) in context {
        ctx.set_item(k, v)?;
    }
    d.set_item("context", ctx)?;
    if let Some(id) = instance_id {
        d.set_item("instance_id", id)?;
    }
    if let Some(name) = instance_name {
        d.set_item("instance_name", name)?;
    }
    if let Some(seed) = context_seed {
        d.set_item("context_seed", seed)?;
    }
    Ok(d)
}

/// What a runtime knows of an episode that just terminated and its numeric info cannot hold:
/// for `rna_design`, the target, the designed sequence and its fold (`RnaDesign::last_outcome`,
/// which the next reset keeps). None for other runtimes.
fn episode_end_info<'py>(py: Python<'py>, runtime: &AnyEnv) -> PyResult<Option<Bound<'py, PyDict>>> {
    let Some(o) = runtime.downcast_ref::<RnaDesign>().and_then(RnaDesign::last_outcome) else {
        return Ok(None);
    };
    let d = PyDict::new(py);
    d.set_item("target_id", o.target_id)?;
    d.set_item("target_structure", &o.target_structure)?;
    d.set_item("sequence", &o.design)?;
    d.set_item("folded_structure", &o.folded)?;
    d.set_item("hamming_distance", o.distance)?;
    d.set_item("hamming_distance_folded", o.distance_folded)?;
    d.set_item(
        "normalized_hamming_distance",
        o.distance as f64 / o.target_structure.len() as f64,
    )?;
    d.set_item("improvement_folds", o.improvement_folds)?;
    Ok(Some(d))
}

/// Whether the runtime reports [`episode_end_info`].
fn has_episode_end_info(runtime: &AnyEnv) -> bool {
    runtime.downcast_ref::<RnaDesign>().is_some()
}

/// `{feature: observed value}` of the visible features (what the agent sees, noise included).
fn observed_dict<'py>(py: Python<'py>, env: &ContextualEnv) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (k, v) in env.visible_features().iter().zip(env.observed_context()) {
        d.set_item(k, f64::from(*v))?;
    }
    Ok(d)
}

#[allow(clippy::too_many_arguments)]
fn env_source_args(
    context_json: Option<String>,
    instances: Option<String>,
    distribution: Option<String>,
    selection: &str,
    instance: Option<usize>,
    obs_context: Option<&Bound<'_, PyAny>>,
    options_json: Option<String>,
    noise: Option<Vec<(String, String, f64)>>,
    noise_redraw: &str,
    allow_out_of_bounds: bool,
) -> PyResult<SourceArgs> {
    let (obs_context, obs_context_all) = match obs_context {
        None => (None, false),
        Some(v) if v.is_none() => (None, false),
        Some(v) => match v.extract::<bool>() {
            Ok(all) => (None, all),
            Err(_) => (Some(v.extract::<Vec<String>>()?), false),
        },
    };
    Ok(SourceArgs {
        context_json,
        instances,
        distribution,
        selection: selection.to_string(),
        instance,
        obs_context,
        obs_context_all,
        options_json,
        noise: context_noise_arg(noise, noise_redraw)?,
        allow_out_of_bounds,
    })
}

pub(crate) const NOISE_NEEDS_OBS_CONTEXT: &str =
    "context_noise applies to observed context features: name them in obs_context= (or obs_context=True)";

/// `context_noise=` as the Python package passes it (`(feature, "absolute" | "relative", std)`
/// triples) and `context_noise_redraw=`.
pub(crate) fn context_noise_arg(noise: Option<Vec<(String, String, f64)>>, redraw: &str) -> PyResult<ContextNoise> {
    let redraw = match redraw {
        "episode" => NoiseRedraw::Episode,
        "step" => NoiseRedraw::Step,
        other => {
            return Err(value_error(format!(
                "context_noise_redraw must be \"episode\" or \"step\", got \"{other}\""
            )));
        }
    };
    let mut features = Vec::new();
    for (name, kind, std) in noise.unwrap_or_default() {
        let std = match kind.as_str() {
            "absolute" => NoiseStd::Absolute(std),
            "relative" => NoiseStd::Relative(std),
            other => {
                return Err(value_error(format!(
                    "context_noise[{name:?}]: kind must be \"absolute\" or \"relative\", got \"{other}\""
                )));
            }
        };
        features.push((name, std));
    }
    Ok(ContextNoise { features, redraw })
}

/// One contextual environment (`carl_spec.make` wraps it in a `gymnasium.Env`).
#[pyclass(module = "carl_spec._core")]
struct Env {
    inner: ContextualEnv,
    action: Action,
    obs: Vec<f32>,
    /// The float64 observation (float64 spaces only, else empty).
    obs64: Vec<f64>,
    layout: ObsLayout,
}

impl Env {
    fn observation<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let wide = if self.obs64.is_empty() {
            None
        } else {
            self.inner
                .observe_f64_into(&mut self.obs64)
                .map_err(|e| env_error(&e))?;
            Some(&self.obs64[..])
        };
        self.layout.value(py, &self.obs, wide, None, None)
    }
}

#[pymethods]
impl Env {
    #[new]
    #[pyo3(signature = (env, *, context_json=None, instances=None, distribution=None, selection="round_robin", instance=None, obs_context=None, options_json=None, noise=None, noise_redraw="episode", allow_out_of_bounds=false, specs_dir=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        env: &str,
        context_json: Option<String>,
        instances: Option<String>,
        distribution: Option<String>,
        selection: &str,
        instance: Option<usize>,
        obs_context: Option<&Bound<'_, PyAny>>,
        options_json: Option<String>,
        noise: Option<Vec<(String, String, f64)>>,
        noise_redraw: &str,
        allow_out_of_bounds: bool,
        specs_dir: Option<PathBuf>,
    ) -> PyResult<Self> {
        let args = env_source_args(
            context_json,
            instances,
            distribution,
            selection,
            instance,
            obs_context,
            options_json,
            noise,
            noise_redraw,
            allow_out_of_bounds,
        )?;
        let inner = with_specs(specs_dir, |specs| build_contextual(py, specs, env, &args))?;
        let action = match inner.action_space() {
            Space::Discrete { .. } => Action::Discrete(0),
            s @ Space::Box { .. } => Action::Continuous(vec![0.0; s.flat_dim()]),
        };
        let layout = ObsLayout::new(
            &inner.inner().observation_space(),
            &inner.observation_space(),
            inner.visible_features().len(),
        );
        Ok(Env {
            obs: vec![0.0; inner.obs_dim()],
            obs64: if layout.wide() {
                vec![0.0; inner.obs_dim()]
            } else {
                Vec::new()
            },
            inner,
            action,
            layout,
        })
    }

    /// `(observation, info)`; `seed=None` continues the current streams.
    #[pyo3(signature = (seed=None))]
    fn reset<'py>(&mut self, py: Python<'py>, seed: Option<u64>) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyDict>)> {
        self.inner.reset_into(seed, &mut self.obs).map_err(|e| env_error(&e))?;
        let obs = self.observation(py)?;
        let info = info_dict(py, self.inner.context_info())?;
        if self.inner.noise().is_some() {
            info.set_item("observed_context", observed_dict(py, &self.inner)?)?;
        }
        Ok((obs, info))
    }

    /// `(observation, reward, terminated, truncated)`; the action is an int (discrete) or a
    /// float32 vector.
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        action: &Bound<'py, PyAny>,
    ) -> PyResult<(Bound<'py, PyAny>, f64, bool, bool)> {
        match &mut self.action {
            Action::Discrete(a) => *a = action.extract::<i64>()?,
            Action::Continuous(v) => {
                let arr: PyReadonlyArray1<'_, f32> = action.extract()?;
                let s = arr.as_slice().map_err(value_error)?;
                if s.len() != v.len() {
                    return Err(value_error(format!(
                        "{}: continuous action must have {} component(s), got {}",
                        self.inner.id(),
                        v.len(),
                        s.len()
                    )));
                }
                v.copy_from_slice(s);
            }
        }
        let out = self
            .inner
            .step_into(&self.action, &mut self.obs)
            .map_err(|e| env_error(&e))?;
        let obs = self.observation(py)?;
        Ok((obs, out.reward, out.terminated, out.truncated))
    }

    /// The current episode's context info (as `reset` returns it).
    fn info<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        info_dict(py, self.inner.context_info())
    }

    /// What the agent observes of the visible features now (noise included).
    fn observed_context<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        observed_dict(py, &self.inner)
    }

    /// Right after a step that terminated the episode: what the runtime knows of it beyond
    /// numbers (`rna_design`: `sequence`, `folded_structure`, `target_structure`, `target_id`,
    /// distances), else None.
    fn episode_end_info<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        episode_end_info(py, self.inner.inner().inner())
    }

    /// When noise on the observed context is redrawn: "episode", "step", or None (no noise).
    fn noise_redraw(&self) -> Option<&'static str> {
        self.inner.noise().map(|r| match r {
            NoiseRedraw::Episode => "episode",
            NoiseRedraw::Step => "step",
        })
    }

    /// An RGB picture `(height, width, 3)` uint8 of the current state, or None.
    fn render<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        match self.inner.render() {
            None => Ok(None),
            Some(f) => Ok(Some(
                PyArray1::from_vec(py, f.rgb)
                    .reshape(vec![f.height as usize, f.width as usize, 3])?
                    .into_any(),
            )),
        }
    }

    /// Whether the runtime draws pictures (probed on a reset copy; this env is untouched).
    fn has_renderer(&self) -> bool {
        let mut probe = self.inner.clone();
        let mut obs = vec![0.0; probe.obs_dim()];
        probe.reset_into(Some(0), &mut obs).is_ok() && probe.render().is_some()
    }

    /// JSON description of the observation space.
    fn observation_space_json(&self) -> String {
        self.layout.space_json(&self.inner.observation_space()).to_string()
    }

    fn action_space_json(&self) -> String {
        space_json(&self.inner.action_space()).to_string()
    }

    /// The runtime's internal float64 state.
    fn state(&self) -> Vec<f64> {
        self.inner.state()
    }

    fn set_state(&mut self, state: Vec<f64>) -> PyResult<()> {
        self.inner.set_state(&state).map_err(|e| env_error(&e))
    }

    #[getter]
    fn id(&self) -> &'static str {
        self.inner.id()
    }

    #[getter]
    fn num_instances(&self) -> usize {
        self.inner.num_instances()
    }

    #[getter]
    fn visible_features(&self) -> Vec<String> {
        self.inner.visible_features().to_vec()
    }

    #[getter]
    fn max_episode_steps(&self) -> Option<u64> {
        self.inner.inner().max_episode_steps()
    }
}

fn autoreset_mode(name: &str) -> PyResult<AutoresetMode> {
    match name {
        "next_step" => Ok(AutoresetMode::NextStep),
        "same_step" => Ok(AutoresetMode::SameStep),
        "disabled" => Ok(AutoresetMode::Disabled),
        other => Err(value_error(format!(
            "autoreset_mode must be \"next_step\", \"same_step\" or \"disabled\", got \"{other}\""
        ))),
    }
}

/// A batch of environments stepped by one call (`carl_spec.make_vec` wraps it in a
/// `gymnasium.vector.VectorEnv`). The GIL is released while Rust steps.
#[pyclass(module = "carl_spec._core")]
struct VecEnv {
    inner: RustVecEnv,
    layout: ObsLayout,
    obs_space: Space,
    discrete: bool,
    action_dim: usize,
    contextual: bool,
    /// Where the visible features start in an observation row, and whether they are observed
    /// with noise (then the infos carry `observed_context`).
    base_dim: usize,
    noisy: bool,
    /// The context of a plain batch (one fixed context: every episode's).
    fixed_info: ContextInfo,
    /// The actions of the step in progress, copied out of NumPy before the GIL is released.
    discrete_actions: Vec<i64>,
    continuous_actions: Vec<f32>,
    same_step: bool,
    /// Info keys made once: every context feature (spec order; every episode's context lists
    /// them all) and the visible ones.
    feature_keys: Columns,
    visible_keys: Columns,
    /// `_instance_id` of a contextual batch (every env has an instance id): one read-only
    /// all-true mask shared by every step's infos.
    all_envs: Py<PyAny>,
    /// The tuples the last two steps returned, released while the workers step a later batch
    /// (see `step`).
    returned: [Option<Py<PyTuple>>; 2],
    /// Arrays and dicts of the step's outputs, made while the workers step (see `step`).
    stock: Stock,
}

impl VecEnv {
    fn batch_obs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.layout.value(
            py,
            self.inner.obs(),
            self.inner.obs_f64(),
            Some(self.inner.num_envs()),
            Some(&self.stock),
        )
    }

    /// `observed_context` of the envs `rows` in the vector layout: the visible features' values
    /// are the tail of each observation row, as `cs.make`'s `info["observed_context"]`
    /// (float32 widened).
    fn set_observed(&self, d: &Bound<'_, PyDict>, obs: &[f32], rows: &[usize]) -> PyResult<()> {
        let (w, base) = (self.inner.obs_dim(), self.base_dim);
        let value = |i: usize, j: usize| f64::from(obs[i * w + base + j]);
        set_nested(
            &self.stock,
            d,
            &keyed!(d.py(), "observed_context"),
            self.inner.num_envs(),
            &self.visible_keys,
            rows,
            value,
        )
    }

    /// Copy the batch's actions out of NumPy (the GIL is held). An int64 (discrete) or float32
    /// C-contiguous array is read as it is; anything else goes through
    /// `numpy.ascontiguousarray(actions, dtype)` first, as `CarlVectorEnv.step` always did.
    fn take_actions(&mut self, actions: &Bound<'_, PyAny>) -> PyResult<()> {
        let py = actions.py();
        let (n, id) = (self.inner.num_envs(), self.inner.id());
        let convert = |dtype: &str| -> PyResult<Bound<'_, PyAny>> {
            let numpy = py.import(pyo3::intern!(py, "numpy"))?;
            let kwargs = PyDict::new(py);
            kwargs.set_item(pyo3::intern!(py, "dtype"), dtype)?;
            numpy
                .getattr(pyo3::intern!(py, "ascontiguousarray"))?
                .call((actions,), Some(&kwargs))
        };
        if self.discrete {
            let owned;
            let a = match actions.cast::<PyArrayDyn<i64>>() {
                Ok(a) if a.is_c_contiguous() => a,
                _ => {
                    owned = convert("int64")?;
                    owned.cast::<PyArrayDyn<i64>>()?
                }
            };
            if a.len() != n {
                return Err(value_error(format!("{id}: expected {n} actions, got {}", a.len())));
            }
            // SAFETY: C-contiguous (checked or made so), and read while the GIL is held: no
            // Python code runs until the copy is done.
            self.discrete_actions
                .copy_from_slice(unsafe { a.as_slice() }.map_err(value_error)?);
        } else {
            let owned;
            let a = match actions.cast::<PyArrayDyn<f32>>() {
                Ok(a) if a.is_c_contiguous() => a,
                _ => {
                    owned = convert("float32")?;
                    owned.cast::<PyArrayDyn<f32>>()?
                }
            };
            if a.len() != n * self.action_dim {
                return Err(value_error(format!(
                    "{}: expected actions of shape ({}, {}), got {:?}",
                    id,
                    n,
                    self.action_dim,
                    a.shape()
                )));
            }
            // SAFETY: as above.
            self.continuous_actions
                .copy_from_slice(unsafe { a.as_slice() }.map_err(value_error)?);
        }
        Ok(())
    }

    /// What every step's (and reset's) infos carry: `instance_id` (contextual batches) and
    /// `observed_context` (with context noise), in Gymnasium's vector layout.
    fn context_infos<'py>(&self, d: &Bound<'py, PyDict>) -> PyResult<()> {
        let py = d.py();
        if self.contextual {
            d.set_item(
                pyo3::intern!(py, "instance_id"),
                PyArray1::from_slice(py, self.inner.instance_ids()),
            )?;
            d.set_item(pyo3::intern!(py, "_instance_id"), self.all_envs.bind(py))?;
        }
        if self.noisy {
            let all: Vec<usize> = (0..self.inner.num_envs()).collect();
            self.set_observed(d, self.inner.obs(), &all)?;
        }
        Ok(())
    }

    /// Same-step mode, after a step where the episodes `ended` ended: `final_obs` and
    /// `final_info` as Gymnasium's vector envs lay them out (an object array holding each
    /// finished environment's last observation and None elsewhere; the finished episodes' infos
    /// in the vector layout), with their masks.
    fn final_infos(&self, d: &Bound<'_, PyDict>, ended: &[usize]) -> PyResult<()> {
        let py = d.py();
        let n = self.inner.num_envs();
        d.set_item(pyo3::intern!(py, "final_obs"), self.final_obs_objects(py, ended)?)?;
        d.set_item(pyo3::intern!(py, "_final_obs"), mask(&self.stock, py, n, ended))?;
        d.set_item(pyo3::intern!(py, "final_info"), self.final_info(py, ended)?)?;
        d.set_item(pyo3::intern!(py, "_final_info"), mask(&self.stock, py, n, ended))
    }

    fn final_obs_objects<'py>(&self, py: Python<'py>, ended: &[usize]) -> PyResult<Bound<'py, PyAny>> {
        let n = self.inner.num_envs();
        let d = self.inner.obs_dim();
        let (flat, wide) = (self.inner.final_observations(), self.inner.final_observations_f64());
        let objects = self.stock.nones(py, n);
        // SAFETY: a fresh object array (from the stock, not yet seen by Python code), contiguous;
        // assigning drops the None it held.
        let slots = unsafe { objects.as_slice_mut() }.map_err(value_error)?;
        if let ObsLayout::Array { .. } = &self.layout {
            // One array of the finished rows, handed out as row views (NumPy's own iteration:
            // the cheapest way to make one Python object per row).
            let gather32: Vec<f32> = ended.iter().flat_map(|&i| &flat[i * d..(i + 1) * d]).copied().collect();
            let gather64: Option<Vec<f64>> =
                wide.map(|w| ended.iter().flat_map(|&i| &w[i * d..(i + 1) * d]).copied().collect());
            let block = self
                .layout
                .value(py, &gather32, gather64.as_deref(), Some(ended.len()), None)?;
            for (&i, row) in ended.iter().zip(block.try_iter()?) {
                slots[i] = row?.unbind();
            }
        } else {
            for &i in ended {
                slots[i] = self
                    .layout
                    .value(
                        py,
                        &flat[i * d..(i + 1) * d],
                        wide.map(|w| &w[i * d..(i + 1) * d]),
                        None,
                        None,
                    )?
                    .unbind();
            }
        }
        Ok(objects.into_any())
    }

    /// `final_info`: the finished episodes' infos (`cs.make`'s step info: `context`,
    /// `instance_id`, `instance_name`, `context_seed`, `observed_context`) in the vector info
    /// layout, masked to the finished envs.
    fn final_info<'py>(&self, py: Python<'py>, ended: &[usize]) -> PyResult<Bound<'py, PyDict>> {
        let n = self.inner.num_envs();
        // Plain batches: every episode has the one fixed context (borrowed, not copied).
        let infos: Vec<(usize, Cow<'_, ContextInfo>)> = ended
            .iter()
            .filter_map(|&i| {
                let info = if self.contextual {
                    self.inner.final_context_info(i).map(Cow::Owned)
                } else {
                    Some(Cow::Borrowed(&self.fixed_info))
                };
                info.map(|ci| (i, ci))
            })
            .collect();
        let d = PyDict::new(py);
        let mut at = vec![0; n];
        for (k, (i, _)) in infos.iter().enumerate() {
            at[*i] = k;
        }
        let rows: Vec<usize> = infos.iter().map(|(i, _)| *i).collect();
        let value = |i: usize, j: usize| infos[at[i]].1.context.get(j).map_or(0.0, |(_, v)| *v);
        set_nested(
            &self.stock,
            &d,
            &keyed!(py, "context"),
            n,
            &self.feature_keys,
            &rows,
            value,
        )?;
        let ids: Vec<(usize, i64)> = infos
            .iter()
            .filter_map(|(i, ci)| Some((*i, ci.instance_id? as i64)))
            .collect();
        if !ids.is_empty() {
            set_column(&self.stock, &d, &keyed!(py, "instance_id"), n, &ids)?;
        }
        if infos.iter().any(|(_, ci)| ci.instance_name.is_some()) {
            let mut names: Vec<Py<PyAny>> = (0..n).map(|_| py.None()).collect();
            let mut has = Vec::new();
            for (i, ci) in &infos {
                if let Some(name) = &ci.instance_name {
                    names[*i] = name.into_pyobject(py)?.into_any().unbind();
                    has.push(*i);
                }
            }
            d.set_item(pyo3::intern!(py, "instance_name"), PyArray1::from_vec(py, names))?;
            d.set_item(pyo3::intern!(py, "_instance_name"), mask(&self.stock, py, n, &has))?;
        }
        let seeds: Vec<(usize, u64)> = infos
            .iter()
            .filter_map(|(i, ci)| Some((*i, ci.context_seed?)))
            .collect();
        if !seeds.is_empty() {
            set_column(&self.stock, &d, &keyed!(py, "context_seed"), n, &seeds)?;
        }
        if self.noisy {
            self.set_observed(&d, self.inner.final_observations(), ended)?;
        }
        Ok(d)
    }
}

#[pymethods]
impl VecEnv {
    #[new]
    #[pyo3(signature = (env, num_envs, *, context_json=None, instances=None, distribution=None, selection="round_robin", instance=None, obs_context=None, options_json=None, noise=None, noise_redraw="episode", allow_out_of_bounds=false, autoreset_mode="next_step", threads=1, specs_dir=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        env: &str,
        num_envs: usize,
        context_json: Option<String>,
        instances: Option<String>,
        distribution: Option<String>,
        selection: &str,
        instance: Option<usize>,
        obs_context: Option<&Bound<'_, PyAny>>,
        options_json: Option<String>,
        noise: Option<Vec<(String, String, f64)>>,
        noise_redraw: &str,
        allow_out_of_bounds: bool,
        autoreset_mode: &str,
        threads: usize,
        specs_dir: Option<PathBuf>,
    ) -> PyResult<Self> {
        let mode = self::autoreset_mode(autoreset_mode)?;
        if num_envs == 0 {
            return Err(value_error("num_envs must be at least 1"));
        }
        let args = env_source_args(
            context_json,
            instances,
            distribution,
            selection,
            instance,
            obs_context,
            options_json,
            noise,
            noise_redraw,
            allow_out_of_bounds,
        )?;
        let plain = args.is_plain();
        let opts = VecOptions {
            threads,
            ..VecOptions::default()
        };
        let vec_err = |e: VecEnvError| match e {
            VecEnvError::Make(m) => make_error(py, &m),
            other => value_error(other),
        };
        let (inner, layout, proto) = with_specs(specs_dir, |specs| {
            // Validate everything (names, selection, options, bounds) through the contextual
            // path first.
            let proto = build_contextual(py, specs, env, &args)?;
            let layout = ObsLayout::new(
                &proto.inner().observation_space(),
                &proto.observation_space(),
                proto.visible_features().len(),
            );
            let inner = if plain {
                // One fixed context without visible features: the plain batch (CartPole's
                // structure-of-arrays kernel).
                let spec = require(py, specs, env)?;
                let ctx = args.context()?;
                let make = MakeOptions {
                    allow_out_of_bounds: args.allow_out_of_bounds,
                };
                let env_options = args.env_options()?;
                let envs = (0..num_envs)
                    .map(|_| make_env(spec, &ctx, make, &env_options))
                    .collect::<Result<Vec<_>, _>>()
                    .map_err(|e| make_error(py, &e))?;
                RustVecEnv::from_envs_with(envs, opts, mode).map_err(vec_err)?
            } else {
                RustVecEnv::from_contextual(vec![proto.clone(); num_envs], opts, mode).map_err(vec_err)?
            };
            Ok((inner, layout, proto))
        })?;
        let (discrete, action_dim) = match inner.action_space() {
            Space::Discrete { .. } => (true, 1),
            s @ Space::Box { .. } => (false, s.flat_dim()),
        };
        let fixed_info = proto.context_info().clone();
        Ok(VecEnv {
            obs_space: inner.observation_space(),
            discrete_actions: vec![0; if discrete { num_envs } else { 0 }],
            continuous_actions: vec![0.0; if discrete { 0 } else { num_envs * action_dim }],
            same_step: mode == AutoresetMode::SameStep,
            feature_keys: Columns::new(py, fixed_info.context.iter().map(|(k, _)| k.as_str()))?,
            visible_keys: Columns::new(py, proto.visible_features().iter().map(String::as_str))?,
            all_envs: read_only(mask(
                &Stock::default(),
                py,
                num_envs,
                &(0..num_envs).collect::<Vec<_>>(),
            ))
            .unbind(),
            inner,
            layout,
            discrete,
            action_dim,
            contextual: !plain,
            base_dim: proto.base_obs_dim(),
            noisy: proto.noise().is_some(),
            fixed_info,
            returned: [None, None],
            stock: Stock::default(),
        })
    }

    fn __traverse__(&self, visit: PyVisit<'_>) -> Result<(), PyTraverseError> {
        // The returned tuples hold what the user may have put into the infos (even this object).
        for t in self.returned.iter().flatten() {
            visit.call(t)?;
        }
        Ok(())
    }

    fn __clear__(&mut self) {
        self.returned = [None, None];
    }

    /// Reset the environments where `mask` is true (all for None); env `i` gets `seed + i`
    /// (None: continue its stream). Returns the observations.
    #[pyo3(signature = (seed=None, mask=None))]
    fn reset<'py>(
        &mut self,
        py: Python<'py>,
        seed: Option<u64>,
        mask: Option<PyReadonlyArray1<'py, bool>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let mask_slice = match &mask {
            Some(m) => {
                let s = m.as_slice().map_err(value_error)?;
                if s.len() != self.inner.num_envs() {
                    return Err(value_error(format!(
                        "reset_mask must have {} entries, got {}",
                        self.inner.num_envs(),
                        s.len()
                    )));
                }
                Some(s)
            }
            None => None,
        };
        let inner = &mut self.inner;
        py.detach(|| {
            inner.reset_masked(seed, mask_slice);
        });
        self.batch_obs(py)
    }

    /// `(observations, rewards, terminated, truncated, infos)`: fresh NumPy arrays and the step's
    /// infos in Gymnasium's vector layout (same-step `final_obs` / `final_info`, `instance_id`,
    /// `observed_context`), all built here in one call. Actions: int64 `(num_envs,)` or float32
    /// `(num_envs, action_dim)` (other dtypes and layouts are converted as NumPy converts them).
    /// The GIL is released while this thread steps its share of the batch.
    ///
    /// Only this thread can do the Python work of a step, while all threads share the stepping,
    /// so the Python work that does not need the step's results is done while the worker threads
    /// step (`VecEnv::step_with`): before this thread takes its share of the batch, the tuple
    /// returned two steps ago is released (in a loop `obs, ... = venv.step(a)` the caller's own
    /// references to it are gone by then, so freeing its arrays and dicts happens here rather
    /// than after this call returns; a step's objects thus live two steps longer); after it, for
    /// as long as a worker still steps its last environments, the arrays and dicts of the step's
    /// outputs are made (`stock`; what is not ready is made when needed, as with one thread).
    fn step<'py>(&mut self, py: Python<'py>, actions: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyTuple>> {
        self.take_actions(actions)?;
        let acts = if self.discrete {
            VecActions::Discrete(&self.discrete_actions)
        } else {
            VecActions::Continuous(&self.continuous_actions)
        };
        let oldest = self.returned[0].take();
        let (stock, n) = (&self.stock, self.inner.num_envs());
        let nested = [&self.feature_keys, &self.visible_keys];
        let mut restocked = Ok(());
        self.inner
            .step_with(acts, |share| {
                drop(oldest);
                py.detach(|| share.claim_all());
                restocked = stock.restock(py, &nested, || share.workers_busy());
            })
            .map(|_| ())
            .map_err(|e| env_error(&e))?;
        restocked?;
        let (term, trunc) = (self.inner.terminated(), self.inner.truncated());
        let infos = PyDict::new(py);
        if self.same_step {
            let ended: Vec<usize> = (0..n).filter(|&i| term[i] | trunc[i]).collect();
            if !ended.is_empty() {
                self.final_infos(&infos, &ended)?;
            }
        }
        self.context_infos(&infos)?;
        let out = PyTuple::new(
            py,
            [
                self.batch_obs(py)?,
                self.stock
                    .filled(py, &[n], |o: &mut [f64]| o.copy_from_slice(self.inner.rewards())),
                self.stock.filled(py, &[n], |o: &mut [bool]| o.copy_from_slice(term)),
                self.stock.filled(py, &[n], |o: &mut [bool]| o.copy_from_slice(trunc)),
                infos.into_any(),
            ],
        )?;
        self.returned = [self.returned[1].take(), Some(out.clone().unbind())];
        Ok(out)
    }

    /// The infos every step and reset carry (`instance_id`, `observed_context`), for `reset`.
    fn infos<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        self.context_infos(&d)?;
        Ok(d)
    }

    /// Last observations of the episodes that ended in the latest step (same-step mode; rows of
    /// other environments are meaningless).
    fn final_obs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.layout.value(
            py,
            self.inner.final_observations(),
            self.inner.final_observations_f64(),
            Some(self.inner.num_envs()),
            None,
        )
    }

    /// Right after a step where environment `i` terminated (before it is stepped again): what its
    /// runtime knows of that episode beyond numbers (see `Env.episode_end_info`), else None.
    fn episode_end_info<'py>(&self, py: Python<'py>, i: usize) -> PyResult<Option<Bound<'py, PyDict>>> {
        match self.inner.runtime(i) {
            Some(runtime) => episode_end_info(py, runtime),
            None => Ok(None),
        }
    }

    /// Whether the runtime reports `episode_end_info`.
    #[getter]
    fn has_episode_end_info(&self) -> bool {
        self.inner.runtime(0).is_some_and(has_episode_end_info)
    }

    /// Each environment's instance id in its set (-1: not from a set).
    fn instance_ids<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        PyArray1::from_slice(py, self.inner.instance_ids())
    }

    /// Environment `i`'s context info (contextual batches), else None.
    fn context_info<'py>(&self, py: Python<'py>, i: usize) -> PyResult<Option<Bound<'py, PyDict>>> {
        self.inner.context_info(i).map(|ci| info_dict(py, ci)).transpose()
    }

    fn state(&self, i: usize) -> Option<Vec<f64>> {
        self.inner.state(i)
    }

    fn observation_space_json(&self) -> String {
        self.layout.space_json(&self.obs_space).to_string()
    }

    fn action_space_json(&self) -> String {
        space_json(&self.inner.action_space()).to_string()
    }

    #[getter]
    fn num_envs(&self) -> usize {
        self.inner.num_envs()
    }

    #[getter]
    fn threads(&self) -> usize {
        self.inner.threads()
    }

    #[getter]
    fn contextual(&self) -> bool {
        self.contextual
    }

    /// Whether the visible context is observed with noise (infos carry `observed_context`).
    #[getter]
    fn noisy(&self) -> bool {
        self.noisy
    }

    #[getter]
    fn is_soa(&self) -> bool {
        self.inner.is_soa()
    }
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(list_envs_json, m)?)?;
    m.add_function(wrap_pyfunction!(spec_json, m)?)?;
    m.add_function(wrap_pyfunction!(validate_json, m)?)?;
    m.add_function(wrap_pyfunction!(instance_sets, m)?)?;
    m.add_function(wrap_pyfunction!(load_instances_json, m)?)?;
    m.add_function(wrap_pyfunction!(sample_json, m)?)?;
    m.add_class::<Env>()?;
    m.add_class::<VecEnv>()?;
    user_spec::register(m)?;
    m.add("RUNTIMES", PyList::new(m.py(), ids().collect::<Vec<_>>())?)?;
    m.add("VERSION", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
