//! `carl_spec._core`: a thin PyO3 layer over the carl-spec library.
//!
//! Everything here converts between Python and the library; behaviour lives in the library
//! (`carl_spec::envs::{contextual, vec_env}`, `instances::Store`, `validate`). Structured data
//! (specs, instance sets, diagnostics, samples) crosses as the same JSON the CLI prints, and the
//! Python package (`python/carl_spec`) turns it into objects. Every library error becomes a Python
//! exception carrying the library's message: unknown names raise `carl_spec.UnknownNameError`
//! (a `KeyError` and a `ValueError`), other bad input `ValueError`, misuse of an episode
//! (stepping before reset) `RuntimeError`.

use std::path::PathBuf;
use std::sync::OnceLock;

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1, PyUntypedArrayMethods};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use carl_spec::envs::contextual::{ContextInfo, ContextSource, ContextualEnv, ContextualError, ContextualOptions};
use carl_spec::envs::registry::{Context, MakeError, MakeOptions, has_runtime, ids, ids_text, make_with};
use carl_spec::envs::vec_env::{AutoresetMode, VecActions, VecEnv as RustVecEnv, VecEnvError, VecOptions};
use carl_spec::envs::{Action, DType, Env as _, EnvError, Features, Selection, Space, Visibility};
use carl_spec::instances::Store;
use carl_spec::instances::derive::{DeriveError, sample_adhoc};
use carl_spec::spec::SpecSet;
use carl_spec::spec::load::{bundled_inputs, read_inputs};
use carl_spec::validate;

mod user_spec;

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

fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
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

/// Where contexts come from, as the Python constructors pass it.
#[derive(Clone)]
struct SourceArgs {
    context_json: Option<String>,
    instances: Option<String>,
    distribution: Option<String>,
    selection: String,
    instance: Option<usize>,
    obs_context: Option<Vec<String>>,
    obs_context_all: bool,
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
        let ctx: Context = match &a.context_json {
            Some(text) => serde_json::from_str(text).map_err(|e| value_error(format!("context: {e}")))?,
            None => Context::new(),
        };
        ContextSource::Fixed(ctx)
    };
    let selection = match (a.selection.as_str(), a.instance) {
        ("round_robin", None) => Selection::RoundRobin,
        ("random", None) => Selection::Random,
        ("static", Some(i)) => Selection::Static(i),
        ("static", None) => return Err(value_error("selection=\"static\" needs instance=<index>")),
        (_, Some(_)) => return Err(value_error("instance= goes with selection=\"static\"")),
        (other, None) => {
            return Err(value_error(format!(
                "selection must be \"round_robin\", \"random\" or \"static\", got \"{other}\""
            )));
        }
    };
    let visibility = if a.obs_context_all {
        Visibility::Visible(Features::All)
    } else {
        match &a.obs_context {
            Some(names) if !names.is_empty() => Visibility::Visible(Features::Only(names.clone())),
            _ => Visibility::Hidden,
        }
    };
    ContextualEnv::new(
        spec,
        source,
        ContextualOptions {
            selection,
            visibility,
            ..ContextualOptions::default()
        },
    )
    .map_err(|e| contextual_error(py, &e))
}

/// The observation as the space declares it: float32, float64 or uint8, in the space's shape.
fn obs_array<'py>(py: Python<'py>, obs: &[f32], shape: &[usize], dtype: DType) -> PyResult<Bound<'py, PyAny>> {
    Ok(match dtype {
        DType::Float32 => PyArray1::from_slice(py, obs).reshape(shape.to_vec())?.into_any(),
        DType::Float64 => PyArray1::from_iter(py, obs.iter().map(|&x| f64::from(x)))
            .reshape(shape.to_vec())?
            .into_any(),
        // Pixel values are whole numbers 0..=255 held in f32.
        DType::UInt8 => PyArray1::from_iter(py, obs.iter().map(|&x| x as u8))
            .reshape(shape.to_vec())?
            .into_any(),
    })
}

fn obs_layout(space: &Space) -> (Vec<usize>, DType) {
    match space {
        Space::Box { shape, dtype, .. } => (shape.clone(), *dtype),
        Space::Discrete { .. } => (vec![], DType::Float32),
    }
}

fn info_dict<'py>(py: Python<'py>, ci: &ContextInfo) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let ctx = PyDict::new(py);
    for (k, v) in &ci.context {
        ctx.set_item(k, v)?;
    }
    // Only what the seed determines (check_env compares infos across equal seeds), so no
    // episode counter.
    d.set_item("context", ctx)?;
    if let Some(id) = ci.instance_id {
        d.set_item("instance_id", id)?;
    }
    if let Some(name) = &ci.instance_name {
        d.set_item("instance_name", name)?;
    }
    if let Some(seed) = ci.context_seed {
        d.set_item("context_seed", seed)?;
    }
    Ok(d)
}

fn env_source_args(
    context_json: Option<String>,
    instances: Option<String>,
    distribution: Option<String>,
    selection: &str,
    instance: Option<usize>,
    obs_context: Option<&Bound<'_, PyAny>>,
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
    })
}

/// One contextual environment (`carl_spec.make` wraps it in a `gymnasium.Env`).
#[pyclass(module = "carl_spec._core")]
struct Env {
    inner: ContextualEnv,
    action: Action,
    obs: Vec<f32>,
    shape: Vec<usize>,
    dtype: DType,
}

#[pymethods]
impl Env {
    #[new]
    #[pyo3(signature = (env, *, context_json=None, instances=None, distribution=None, selection="round_robin", instance=None, obs_context=None, specs_dir=None))]
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
        specs_dir: Option<PathBuf>,
    ) -> PyResult<Self> {
        let args = env_source_args(context_json, instances, distribution, selection, instance, obs_context)?;
        let inner = with_specs(specs_dir, |specs| build_contextual(py, specs, env, &args))?;
        let action = match inner.action_space() {
            Space::Discrete { .. } => Action::Discrete(0),
            s @ Space::Box { .. } => Action::Continuous(vec![0.0; s.flat_dim()]),
        };
        let (shape, dtype) = obs_layout(&inner.observation_space());
        Ok(Env {
            obs: vec![0.0; inner.obs_dim()],
            inner,
            action,
            shape,
            dtype,
        })
    }

    /// `(observation, info)`; `seed=None` continues the current streams.
    #[pyo3(signature = (seed=None))]
    fn reset<'py>(&mut self, py: Python<'py>, seed: Option<u64>) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyDict>)> {
        self.inner.reset_into(seed, &mut self.obs).map_err(|e| env_error(&e))?;
        let obs = obs_array(py, &self.obs, &self.shape, self.dtype)?;
        Ok((obs, info_dict(py, self.inner.context_info())?))
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
        let obs = obs_array(py, &self.obs, &self.shape, self.dtype)?;
        Ok((obs, out.reward, out.terminated, out.truncated))
    }

    /// The current episode's context info (as `reset` returns it).
    fn info<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        info_dict(py, self.inner.context_info())
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
        space_json(&self.inner.observation_space()).to_string()
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

/// `(observations, rewards, terminated, truncated)` of one batch step.
type BatchStep<'py> = (
    Bound<'py, PyAny>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<bool>>,
    Bound<'py, PyArray1<bool>>,
);

/// A batch of environments stepped by one call (`carl_spec.make_vec` wraps it in a
/// `gymnasium.vector.VectorEnv`). The GIL is released while Rust steps.
#[pyclass(module = "carl_spec._core")]
struct VecEnv {
    inner: RustVecEnv,
    shape: Vec<usize>,
    dtype: DType,
    discrete: bool,
    action_dim: usize,
    contextual: bool,
}

impl VecEnv {
    fn batch_obs<'py>(&self, py: Python<'py>, flat: &[f32]) -> PyResult<Bound<'py, PyAny>> {
        let mut shape = vec![self.inner.num_envs()];
        shape.extend(&self.shape);
        obs_array(py, flat, &shape, self.dtype)
    }
}

#[pymethods]
impl VecEnv {
    #[new]
    #[pyo3(signature = (env, num_envs, *, context_json=None, instances=None, distribution=None, selection="round_robin", instance=None, obs_context=None, autoreset_mode="next_step", threads=1, specs_dir=None))]
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
        autoreset_mode: &str,
        threads: usize,
        specs_dir: Option<PathBuf>,
    ) -> PyResult<Self> {
        let mode = self::autoreset_mode(autoreset_mode)?;
        if num_envs == 0 {
            return Err(value_error("num_envs must be at least 1"));
        }
        let args = env_source_args(context_json, instances, distribution, selection, instance, obs_context)?;
        let plain = args.instances.is_none()
            && args.distribution.is_none()
            && args.obs_context.as_ref().is_none_or(Vec::is_empty)
            && !args.obs_context_all;
        let opts = VecOptions {
            threads,
            ..VecOptions::default()
        };
        let vec_err = |e: VecEnvError| match e {
            VecEnvError::Make(m) => make_error(py, &m),
            other => value_error(other),
        };
        let inner = with_specs(specs_dir, |specs| {
            // Validate everything (names, selection) through the contextual path first.
            let proto = build_contextual(py, specs, env, &args)?;
            if plain {
                // One fixed context without visible features: the plain batch (CartPole's
                // structure-of-arrays kernel in same-step mode).
                let spec = require(py, specs, env)?;
                let ctx: Context = match &args.context_json {
                    Some(text) => serde_json::from_str(text).map_err(|e| value_error(format!("context: {e}")))?,
                    None => Context::new(),
                };
                let envs = (0..num_envs)
                    .map(|_| make_with(spec, &ctx, MakeOptions::default()))
                    .collect::<Result<Vec<_>, _>>()
                    .map_err(|e| make_error(py, &e))?;
                RustVecEnv::from_envs_with(envs, opts, mode).map_err(vec_err)
            } else {
                let envs = vec![proto; num_envs];
                RustVecEnv::from_contextual(envs, opts, mode).map_err(vec_err)
            }
        })?;
        let (shape, dtype) = obs_layout(&inner.observation_space());
        let (discrete, action_dim) = match inner.action_space() {
            Space::Discrete { .. } => (true, 1),
            s @ Space::Box { .. } => (false, s.flat_dim()),
        };
        Ok(VecEnv {
            inner,
            shape,
            dtype,
            discrete,
            action_dim,
            contextual: !plain,
        })
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
        self.batch_obs(py, self.inner.obs())
    }

    /// `(observations, rewards, terminated, truncated)` as fresh NumPy arrays. Actions: int64
    /// `(num_envs,)` or float32 `(num_envs, action_dim)`, C-contiguous.
    fn step<'py>(&mut self, py: Python<'py>, actions: &Bound<'py, PyAny>) -> PyResult<BatchStep<'py>> {
        let (n, id) = (self.inner.num_envs(), self.inner.id());
        let inner = &mut self.inner;
        if self.discrete {
            let a: PyReadonlyArray1<'_, i64> = actions.extract()?;
            let a = a.as_slice().map_err(value_error)?;
            py.detach(|| inner.step(VecActions::Discrete(a)).map(|_| ()))
                .map_err(|e| env_error(&e))?;
        } else {
            let a: numpy::PyReadonlyArrayDyn<'_, f32> = actions.extract()?;
            if a.len() != n * self.action_dim {
                return Err(value_error(format!(
                    "{}: expected actions of shape ({}, {}), got {:?}",
                    id,
                    n,
                    self.action_dim,
                    a.shape()
                )));
            }
            let a = a.as_slice().map_err(value_error)?;
            py.detach(|| inner.step(VecActions::Continuous(a)).map(|_| ()))
                .map_err(|e| env_error(&e))?;
        }
        Ok((
            self.batch_obs(py, self.inner.obs())?,
            PyArray1::from_slice(py, self.inner.rewards()),
            PyArray1::from_slice(py, self.inner.terminated()),
            PyArray1::from_slice(py, self.inner.truncated()),
        ))
    }

    /// Last observations of the episodes that ended in the latest step (same-step mode; rows of
    /// other environments are meaningless).
    fn final_obs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.batch_obs(py, self.inner.final_observations())
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
        space_json(&self.inner.observation_space()).to_string()
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
