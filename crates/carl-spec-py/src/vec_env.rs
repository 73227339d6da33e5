//! `_core.VecEnv`: a batch of environments stepped by one call (`carl_spec.make_vec` wraps it in
//! a `gymnasium.vector.VectorEnv`); the GIL is released while Rust steps.

use std::borrow::Cow;
use std::path::PathBuf;

use numpy::{
    IntoPyArray, PyArray1, PyArrayDescrMethods, PyArrayDyn, PyArrayMethods, PyReadonlyArray1, PyUntypedArray,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use pyo3::{PyTraverseError, PyVisit};

use carl_spec::envs::contextual::ContextInfo;
use carl_spec::envs::registry::{Context, MakeOptions, make_env};
use carl_spec::envs::vec_env::{AutoresetMode, VecActions, VecEnv as RustVecEnv, VecEnvError, VecOptions};
use carl_spec::envs::{Env as _, Space, cancel};

use crate::actions::{BoxBounds, check_obs};
use crate::context_args::{ContextArgs, build_contextual, source_of};
use crate::env_infos::{episode_end_info, has_episode_end_info, info_dict};
use crate::errors::{env_error, invalid_action, make_error, value_error};
use crate::info_keys::{Columns, keyed};
use crate::obs_layout::ObsLayout;
use crate::specs::{require, space_json, with_specs};
use crate::stock::Stock;
use crate::vec_infos::{mask, read_only_any, set_column, set_nested};

/// Largest `threads` (as `carl-spec bench --threads`).
const MAX_THREADS: usize = 256;

/// A batch is stepped by one call at a time: a second thread gets this instead of PyO3's
/// "Already borrowed".
fn busy() -> PyErr {
    pyo3::exceptions::PyRuntimeError::new_err(
        "this vector env is being used by another thread (one call at a time: give each thread its own make_vec)",
    )
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
pub(crate) struct VecEnv {
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
    /// Continuous actions: the space's bounds (finite actions are clipped to them).
    bounds: Option<BoxBounds>,
    /// Batch steps since construction (named when an output is not finite).
    steps: u64,
    /// Every env's context infos (see `cached_context_infos`), until a context may change.
    context_cache: Option<Py<PyDict>>,
    /// Some feature changes within episodes (a schedule): the context infos change every step.
    scheduled: bool,
    /// Whether an episode ended in the last step (its env resets in the next, next-step mode).
    last_any_done: bool,
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
        let value = |k: usize, j: usize| f64::from(obs[rows[k] * w + base + j]);
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

    /// Copy the batch's actions out of NumPy (the GIL is held), checked as `cs.make` checks one
    /// action: discrete actions are integers (bools, floats and strings refused) of shape
    /// `(num_envs,)`; continuous ones are numbers of shape `(num_envs, *action_shape)` (or
    /// `(num_envs,)` for one component), finite, clipped to the space.
    fn take_actions<'py>(&mut self, actions: &Bound<'py, PyAny>) -> PyResult<()> {
        let py = actions.py();
        let (n, id) = (self.inner.num_envs(), self.inner.id());
        // NumPy is looked up only off the fast path (an int64 / float32 C-contiguous array).
        let numpy = || py.import(pyo3::intern!(py, "numpy"));
        let convert = |x: &Bound<'py, PyAny>, dtype: &str| -> PyResult<Bound<'py, PyAny>> {
            let kwargs = PyDict::new(py);
            kwargs.set_item(pyo3::intern!(py, "dtype"), dtype)?;
            numpy()?
                .getattr(pyo3::intern!(py, "ascontiguousarray"))?
                .call((x,), Some(&kwargs))
        };
        let given;
        let a = match actions.cast::<PyUntypedArray>() {
            Ok(a) => a,
            Err(_) => {
                given = numpy()?.getattr(pyo3::intern!(py, "asarray"))?.call1((actions,))?;
                given.cast::<PyUntypedArray>()?
            }
        };
        let kind = a.dtype().kind();
        let shape = a.shape();
        let describe = || format!("{} array of shape {:?}", a.dtype(), shape);
        if self.discrete {
            if !matches!(kind, b'i' | b'u') || shape != [n] {
                return Err(invalid_action(
                    py,
                    format!(
                        "{id}: discrete actions are integers of shape ({n},), got a {}",
                        describe()
                    ),
                ));
            }
            let owned;
            let a = match a.as_any().cast::<PyArrayDyn<i64>>() {
                Ok(a) if a.is_c_contiguous() => a,
                _ => {
                    owned = convert(a.as_any(), "int64")?;
                    owned.cast::<PyArrayDyn<i64>>()?
                }
            };
            // SAFETY: C-contiguous (checked or made so), and read while the GIL is held: no
            // Python code runs until the copy is done.
            self.discrete_actions
                .copy_from_slice(unsafe { a.as_slice() }.map_err(value_error)?);
        } else {
            let dim = self.action_dim;
            let rows_ok = shape.first() == Some(&n) && shape[1..].iter().product::<usize>() == dim;
            if !matches!(kind, b'i' | b'u' | b'f') || !rows_ok {
                return Err(invalid_action(
                    py,
                    format!(
                        "{id}: continuous actions are numbers of shape ({n}, {dim}), got a {}",
                        describe()
                    ),
                ));
            }
            let bounds = self.bounds.as_ref().expect("a Box action space has bounds");
            let out = &mut self.continuous_actions;
            match a.as_any().cast::<PyArrayDyn<f32>>() {
                Ok(f) if f.is_c_contiguous() => {
                    // SAFETY: as below.
                    let src = unsafe { f.as_slice() }.map_err(value_error)?;
                    let mut row = vec![0.0f64; dim];
                    for i in 0..n {
                        for (r, x) in row.iter_mut().zip(&src[i * dim..(i + 1) * dim]) {
                            *r = f64::from(*x);
                        }
                        bounds.take(id, Some(i), &row, &mut out[i * dim..(i + 1) * dim])?;
                    }
                }
                _ => {
                    let owned = convert(a.as_any(), "float64")?;
                    let f = owned.cast::<PyArrayDyn<f64>>()?;
                    // SAFETY: C-contiguous (made so), read while the GIL is held.
                    let src = unsafe { f.as_slice() }.map_err(value_error)?;
                    for i in 0..n {
                        bounds.take(
                            id,
                            Some(i),
                            &src[i * dim..(i + 1) * dim],
                            &mut out[i * dim..(i + 1) * dim],
                        )?;
                    }
                }
            }
        }
        Ok(())
    }

    /// A non-finite observation or reward after a step or reset, naming the environment.
    fn check_outputs(&self, what: impl Fn() -> String) -> PyResult<()> {
        let (obs, d) = (self.inner.obs(), self.inner.obs_dim());
        let rewards = self.inner.rewards();
        let wide = self.inner.obs_f64();
        // Branch-free folds (vectorized): outputs are nearly always finite.
        let fine = match wide {
            Some(w) => w.iter().fold(true, |ok, x| ok & x.is_finite()),
            None => obs.iter().fold(true, |ok, x| ok & x.is_finite()),
        } & rewards.iter().fold(true, |ok, r| ok & r.is_finite());
        if fine {
            return Ok(());
        }
        for i in 0..self.inner.num_envs() {
            let what = what();
            let reward = if what == "reset" { 0.0 } else { rewards[i] };
            let w = wide.map_or(&[][..], |w| &w[i * d..(i + 1) * d]);
            check_obs(
                || format!("{} environment {i}, {what}", self.inner.id()),
                &obs[i * d..(i + 1) * d],
                w,
                reward,
            )?;
        }
        Ok(())
    }

    /// After a reset of the envs `rows` (the others unchanged since they were checked): a
    /// non-finite first observation, naming the environment.
    fn check_reset(&self, rows: &[usize]) -> PyResult<()> {
        let (obs, d) = (self.inner.obs(), self.inner.obs_dim());
        let wide = self.inner.obs_f64();
        for &i in rows {
            let w = wide.map_or(&[][..], |w| &w[i * d..(i + 1) * d]);
            check_obs(
                || format!("{} environment {i}, reset", self.inner.id()),
                &obs[i * d..(i + 1) * d],
                w,
                0.0,
            )?;
        }
        Ok(())
    }

    /// A fresh infos dict holding every env's context infos (`context_infos` of all envs), from
    /// a cache kept while no context changes: the outer dict and the nested `context` dict are
    /// fresh copies, the arrays in them read-only and shared with later steps' infos.
    fn cached_context_infos<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        if self.context_cache.is_none() {
            let d = PyDict::new(py);
            let all: Vec<usize> = (0..self.inner.num_envs()).collect();
            let infos: Vec<(usize, &ContextInfo)> = all.iter().map(|&i| (i, self.current_info(i))).collect();
            self.set_context_infos(&d, &infos)?;
            for (_, v) in d.iter() {
                match v.cast::<PyDict>() {
                    Ok(nested) => nested.iter().for_each(|(_, a)| read_only_any(&a)),
                    Err(_) => read_only_any(&v),
                }
            }
            self.context_cache = Some(d.unbind());
        }
        let cached = self.context_cache.as_ref().expect("made above").bind(py);
        let out = cached.copy()?;
        let key = pyo3::intern!(py, "context");
        if let Some(ctx) = cached.get_item(key)? {
            out.set_item(key, ctx.cast::<PyDict>()?.copy()?)?;
        }
        Ok(out)
    }

    /// Environment `i`'s current context info (a plain batch: the one fixed context).
    fn current_info(&self, i: usize) -> &ContextInfo {
        self.inner.context_info(i).unwrap_or(&self.fixed_info)
    }

    /// What every step's (and reset's) infos carry for the envs `rows`, as `cs.make`'s info
    /// (`context`, `instance_id` / `instance_name` from a set, `context_seed` from a
    /// distribution, `observed_context` with noise) in Gymnasium's vector layout.
    fn context_infos(&self, d: &Bound<'_, PyDict>, rows: &[usize]) -> PyResult<()> {
        let infos: Vec<(usize, &ContextInfo)> = rows.iter().map(|&i| (i, self.current_info(i))).collect();
        self.set_context_infos(d, &infos)?;
        if self.noisy {
            self.set_observed(d, self.inner.obs(), rows)?;
        }
        Ok(())
    }

    /// `context`, `instance_id`, `instance_name` and `context_seed` of `infos` (env, its
    /// context info) into `d`, each with its mask, as `SyncVectorEnv._add_info` lays them out.
    fn set_context_infos(&self, d: &Bound<'_, PyDict>, infos: &[(usize, &ContextInfo)]) -> PyResult<()> {
        let py = d.py();
        let n = self.inner.num_envs();
        let rows: Vec<usize> = infos.iter().map(|(i, _)| *i).collect();
        let value = |k: usize, j: usize| infos[k].1.context.get(j).map_or(0.0, |(_, v)| *v);
        set_nested(
            &self.stock,
            d,
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
            set_column(&self.stock, d, &keyed!(py, "instance_id"), n, &ids)?;
        }
        if infos.iter().any(|(_, ci)| ci.instance_name.is_some()) {
            let mut names: Vec<Py<PyAny>> = (0..n).map(|_| py.None()).collect();
            let mut has = Vec::new();
            for (i, ci) in infos {
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
            set_column(&self.stock, d, &keyed!(py, "context_seed"), n, &seeds)?;
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

    /// `outcome` (the environment's word for how each finished episode ended, `Env::outcome`:
    /// `landed`, `solved`, `timed_out`, ...; None where it defines none) with its mask `_outcome`,
    /// for the environments `ended`.
    fn set_outcomes(&self, d: &Bound<'_, PyDict>, ended: &[usize]) -> PyResult<()> {
        let py = d.py();
        let n = self.inner.num_envs();
        let mut words: Vec<Py<PyAny>> = (0..n).map(|_| py.None()).collect();
        let mut has = Vec::with_capacity(ended.len());
        for &i in ended {
            if let Some(word) = self.inner.outcome(i) {
                words[i] = pyo3::types::PyString::intern(py, word).into_any().unbind();
                has.push(i);
            }
        }
        d.set_item(pyo3::intern!(py, "outcome"), PyArray1::from_vec(py, words))?;
        d.set_item(pyo3::intern!(py, "_outcome"), mask(&self.stock, py, n, &has))
    }

    fn final_obs_objects<'py>(&self, py: Python<'py>, ended: &[usize]) -> PyResult<Bound<'py, PyAny>> {
        let n = self.inner.num_envs();
        let d = self.inner.obs_dim();
        let (flat, wide) = (self.inner.final_observations(), self.inner.final_observations_f64());
        let objects = self.stock.nones(py, n);
        // SAFETY: a fresh object array (from the stock, not yet seen by Python code), contiguous;
        // assigning drops the None it held.
        let slots = unsafe { objects.as_slice_mut() }.map_err(value_error)?;
        // One fresh observation per finished env, from the stock: made while the workers stepped.
        for &i in ended {
            slots[i] = self
                .layout
                .value(
                    py,
                    &flat[i * d..(i + 1) * d],
                    wide.map(|w| &w[i * d..(i + 1) * d]),
                    None,
                    Some(&self.stock),
                )?
                .unbind();
        }
        Ok(objects.into_any())
    }

    /// `final_info`: the finished episodes' infos (`cs.make`'s step info: `context`,
    /// `instance_id`, `instance_name`, `context_seed`, `observed_context`) in the vector info
    /// layout, masked to the finished envs.
    fn final_info<'py>(&self, py: Python<'py>, ended: &[usize]) -> PyResult<Bound<'py, PyDict>> {
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
        let refs: Vec<(usize, &ContextInfo)> = infos.iter().map(|(i, ci)| (*i, &**ci)).collect();
        self.set_context_infos(&d, &refs)?;
        if self.noisy {
            self.set_observed(&d, self.inner.final_observations(), ended)?;
        }
        Ok(d)
    }
}

/// `carl_spec.evaluate`'s reset seeds of the episodes `(instances[j], episodes[j])`
/// (`carl_spec::evaluation::episode_seed`, the rule the CLI's `evaluate` follows), as uint64.
/// Negative numbers, or columns of different lengths, are a ValueError.
#[pyfunction]
#[pyo3(signature = (seed, instances, episodes, n_instances=None))]
pub(crate) fn episode_seeds<'py>(
    py: Python<'py>,
    seed: u64,
    instances: PyReadonlyArray1<'py, i64>,
    episodes: PyReadonlyArray1<'py, i64>,
    n_instances: Option<usize>,
) -> PyResult<Bound<'py, PyArray1<u64>>> {
    let (inst, eps) = (
        instances.as_slice().map_err(value_error)?,
        episodes.as_slice().map_err(value_error)?,
    );
    if inst.len() != eps.len() {
        return Err(value_error(format!(
            "{} instances for {} episodes",
            inst.len(),
            eps.len()
        )));
    }
    let index = |x: i64, what: &str| usize::try_from(x).map_err(|_| value_error(format!("{what} {x} is negative")));
    let seeds = inst
        .iter()
        .zip(eps)
        .map(|(&k, &e)| {
            Ok(carl_spec::evaluation::episode_seed(
                seed,
                index(k, "instance")?,
                index(e, "episode")?,
                n_instances,
            ))
        })
        .collect::<PyResult<Vec<u64>>>()?;
    Ok(seeds.into_pyarray(py))
}

/// The context an episode played and its draw's seed (`VecEnv.play`'s `contexts`).
type DrawnContext = (Vec<(String, f64)>, Option<u64>);

/// `order` as indices into `total` jobs: each job exactly once, else a ValueError.
fn permutation(order: &[i64], total: usize) -> PyResult<Vec<usize>> {
    if order.len() != total {
        return Err(value_error(format!(
            "order lists {} jobs, not the {total} given",
            order.len()
        )));
    }
    let mut seen = vec![false; total];
    order
        .iter()
        .map(|&j| match usize::try_from(j) {
            Ok(j) if j < total && !std::mem::replace(&mut seen[j], true) => Ok(j),
            _ => Err(value_error(format!(
                "order must list each of the {total} jobs once, got {j} (out of range or repeated)"
            ))),
        })
        .collect()
}

#[pymethods]
impl VecEnv {
    /// `args`: the context source (`carl_spec._args.context_args`; None: the default context).
    /// `num_envs` and `threads` are bounded as `carl-spec bench` bounds them.
    #[new]
    #[pyo3(signature = (env, num_envs, args=None, *, autoreset_mode="next_step", threads=1, specs_dir=None))]
    fn new(
        py: Python<'_>,
        env: &str,
        num_envs: usize,
        args: Option<&Bound<'_, ContextArgs>>,
        autoreset_mode: &str,
        threads: usize,
        specs_dir: Option<PathBuf>,
    ) -> PyResult<Self> {
        let mode = self::autoreset_mode(autoreset_mode)?;
        if threads == 0 || threads > MAX_THREADS {
            return Err(value_error(format!("threads={threads} is outside 1..={MAX_THREADS}")));
        }
        let args = source_of(args);
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
            let max = carl_spec::bench::max_num_envs(require(py, specs, env)?);
            if num_envs == 0 || num_envs > max {
                return Err(value_error(format!(
                    "num_envs={num_envs} is outside 1..={max} for {env} (the limit of `carl-spec bench`: \
                     {} for closed-form environments, {} for physics and pixel ones)",
                    carl_spec::bench::MAX_NUM_ENVS_LIGHT,
                    carl_spec::bench::MAX_NUM_ENVS_HEAVY
                )));
            }
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
            // The contextual space (the same for every source), also for a plain batch, whose
            // runtimes report their own (`cs.make`'s space, whatever the batch's kernel).
            obs_space: proto.observation_space(),
            discrete_actions: vec![0; if discrete { num_envs } else { 0 }],
            continuous_actions: vec![0.0; if discrete { 0 } else { num_envs * action_dim }],
            same_step: mode == AutoresetMode::SameStep,
            feature_keys: Columns::new(py, fixed_info.context.iter().map(|(k, _)| k.as_str()))?,
            visible_keys: Columns::new(py, proto.visible_features().iter().map(String::as_str))?,
            bounds: BoxBounds::of(&inner.action_space()),
            steps: 0,
            context_cache: None,
            scheduled: proto.has_schedules(),
            last_any_done: false,
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
        slf: &Bound<'py, Self>,
        seed: Option<u64>,
        mask: Option<PyReadonlyArray1<'py, bool>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let mut guard = slf.try_borrow_mut().map_err(|_| busy())?;
        let this = &mut *guard;
        let py = slf.py();
        let mask_slice = match &mask {
            Some(m) => {
                let s = m.as_slice().map_err(value_error)?;
                if s.len() != this.inner.num_envs() {
                    return Err(value_error(format!(
                        "reset_mask must have {} entries, got {}",
                        this.inner.num_envs(),
                        s.len()
                    )));
                }
                Some(s)
            }
            None => None,
        };
        let inner = &mut this.inner;
        py.detach(|| {
            inner.reset_masked(seed, mask_slice);
        });
        this.context_cache = None;
        this.last_any_done = false;
        this.check_outputs(|| "reset".to_string())?;
        this.batch_obs(py)
    }

    /// `carl_spec.evaluate`'s loop, run here: play one episode per job (`seeds[j]`, and for a
    /// set `instances[j]`), environment `i` starting job `i` and each finished environment the
    /// next job, until every job has ended. Per batch step Python only runs `act(obs)` (and, on
    /// the first, `check(actions)`, which returns the actions to take); returns, lengths,
    /// termination flags and outcomes are kept here, and the environments whose episodes ended
    /// are reset in one native call per step that touches only them (`VecEnv::reset_some`).
    /// Once the jobs run out, finished environments replay their last seed so the batch can go
    /// on stepping (not recorded). Returns `(returns, lengths, terminated, truncated, outcomes,
    /// contexts)` per job, `contexts[j]` = `(context, context_seed)` of its episode when
    /// `record_contexts` (distributions), else None; with `order` (a permutation of the jobs)
    /// entry `k` is job `order[k]`'s. Needs autoreset "disabled". `seeds` (uint64), `instances`
    /// and `order` (int64) are NumPy arrays, and the returns, lengths and flags come back as
    /// NumPy arrays (float64, uint64, bool); the outcomes are one Python string per distinct word:
    /// no Python object is made per job.
    #[pyo3(signature = (act, check, seeds, instances=None, record_contexts=false, order=None))]
    #[allow(clippy::too_many_arguments)]
    fn play<'py>(
        slf: &Bound<'py, Self>,
        act: &Bound<'py, PyAny>,
        check: &Bound<'py, PyAny>,
        seeds: PyReadonlyArray1<'py, u64>,
        instances: Option<PyReadonlyArray1<'py, i64>>,
        record_contexts: bool,
        order: Option<PyReadonlyArray1<'py, i64>>,
    ) -> PyResult<Bound<'py, PyTuple>> {
        let seeds = seeds.as_slice().map_err(value_error)?.to_vec();
        let instances = match &instances {
            Some(a) => Some(
                a.as_slice()
                    .map_err(value_error)?
                    .iter()
                    .map(|&k| usize::try_from(k).map_err(|_| value_error(format!("instance {k} is negative"))))
                    .collect::<PyResult<Vec<usize>>>()?,
            ),
            None => None,
        };
        let total = seeds.len();
        let order = match &order {
            Some(a) => Some(permutation(a.as_slice().map_err(value_error)?, total)?),
            None => None,
        };
        let mut guard = slf.try_borrow_mut().map_err(|_| busy())?;
        let this = &mut *guard;
        let py = slf.py();
        let n = this.inner.num_envs();
        if this.inner.autoreset_mode() != AutoresetMode::Disabled {
            return Err(value_error("play needs a batch with autoreset_mode='disabled'"));
        }
        if total < n {
            return Err(value_error(format!(
                "play needs at least num_envs={n} jobs, got {total}"
            )));
        }
        if let Some(inst) = &instances
            && inst.len() != total
        {
            return Err(value_error(format!("{} instances for {total} seeds", inst.len())));
        }
        let instance_of = |j: usize| instances.as_ref().map(|v| v[j]);
        let mut job_of: Vec<Option<usize>> = (0..n).map(Some).collect();
        let mut last_seed: Vec<u64> = seeds[..n].to_vec();
        let mut next = n;
        let mut ret = vec![0.0f64; n];
        let mut len = vec![0u64; n];
        let mut out_ret = vec![0.0f64; total];
        let mut out_len = vec![0u64; total];
        let mut out_term = vec![false; total];
        let mut out_trunc = vec![false; total];
        let mut out_word: Vec<Option<&'static str>> = vec![None; total];
        let mut out_ctx: Vec<Option<DrawnContext>> = vec![None; total];
        // The environments to reset between two steps, with their seeds and instances.
        let mut rows: Vec<usize> = (0..n).collect();
        let mut row_seeds: Vec<u64> = seeds[..n].to_vec();
        let mut row_inst: Vec<Option<usize>> = (0..n).map(instance_of).collect();
        let reset = |this: &mut Self, rows: &[usize], seeds: &[u64], inst: &[Option<usize>]| {
            let inner = &mut this.inner;
            let with_inst = inst.iter().any(Option::is_some).then_some(inst);
            py.detach(|| inner.reset_some(rows, seeds, with_inst))
                .map_err(|e| env_error(&e))?;
            this.context_cache = None;
            this.last_any_done = false;
            this.check_reset(rows)
        };
        reset(this, &rows, &row_seeds, &row_inst)?;
        if record_contexts {
            for (i, slot) in out_ctx.iter_mut().enumerate().take(n) {
                let ci = this.current_info(i);
                *slot = Some((ci.context.clone(), ci.context_seed));
            }
        }
        let mut remaining = total;
        let mut first = true;
        let mut started = Vec::new();
        while remaining > 0 {
            py.check_signals()?;
            let obs = this.batch_obs(py)?;
            let mut actions = act.call1((obs,))?;
            if first {
                actions = check.call1((actions,))?;
                first = false;
            }
            this.take_actions(&actions)?;
            let (inner, discrete, continuous) = (&mut this.inner, &this.discrete_actions, &this.continuous_actions);
            let acts = if this.discrete {
                VecActions::Discrete(discrete)
            } else {
                VecActions::Continuous(continuous)
            };
            py.detach(|| inner.step(acts).map(drop)).map_err(|e| env_error(&e))?;
            this.steps += 1;
            let t = this.steps;
            this.check_outputs(|| format!("step {t}"))?;
            let (rewards, term, trunc) = (this.inner.rewards(), this.inner.terminated(), this.inner.truncated());
            // One branch-free pass (zipped: no bounds checks) tells whether an episode ended.
            let mut any = false;
            for (((r, l), &x), (&a, &b)) in ret
                .iter_mut()
                .zip(len.iter_mut())
                .zip(rewards)
                .zip(term.iter().zip(trunc))
            {
                *r += x;
                *l += 1;
                any |= a | b;
            }
            if !any {
                continue;
            }
            rows.clear();
            row_seeds.clear();
            row_inst.clear();
            started.clear();
            for i in (0..n).filter(|&i| term[i] | trunc[i]) {
                if let Some(j) = job_of[i] {
                    (out_ret[j], out_len[j], out_term[j], out_trunc[j]) = (ret[i], len[i], term[i], trunc[i]);
                    out_word[j] = this.inner.outcome(i);
                    remaining -= 1;
                }
                let inst = if next < total {
                    job_of[i] = Some(next);
                    last_seed[i] = seeds[next];
                    started.push(i);
                    next += 1;
                    instance_of(next - 1)
                } else {
                    job_of[i] = None;
                    None
                };
                rows.push(i);
                row_seeds.push(last_seed[i]);
                row_inst.push(inst);
                (ret[i], len[i]) = (0.0, 0);
            }
            if remaining == 0 {
                break;
            }
            reset(this, &rows, &row_seeds, &row_inst)?;
            if record_contexts {
                for &i in &started {
                    let ci = this.current_info(i);
                    if let Some(j) = job_of[i] {
                        out_ctx[j] = Some((ci.context.clone(), ci.context_seed));
                    }
                }
            }
        }
        if let Some(order) = &order {
            out_ret = order.iter().map(|&j| out_ret[j]).collect();
            out_len = order.iter().map(|&j| out_len[j]).collect();
            out_term = order.iter().map(|&j| out_term[j]).collect();
            out_trunc = order.iter().map(|&j| out_trunc[j]).collect();
            out_word = order.iter().map(|&j| out_word[j]).collect();
            out_ctx = order.iter().map(|&j| out_ctx[j].take()).collect();
        }
        // One Python string per distinct word (a handful), shared by the jobs.
        let mut made: Vec<(&'static str, Bound<'py, PyAny>)> = Vec::new();
        let mut words = Vec::with_capacity(total);
        for w in out_word {
            let obj = match w {
                None => py.None().into_bound(py),
                Some(w) => match made.iter().find(|(m, _)| *m == w) {
                    Some((_, o)) => o.clone(),
                    None => {
                        let o = pyo3::types::PyString::new(py, w).into_any();
                        made.push((w, o.clone()));
                        o
                    }
                },
            };
            words.push(obj);
        }
        let contexts: Vec<Py<PyAny>> = out_ctx
            .into_iter()
            .map(|c| match c {
                None => Ok(py.None()),
                Some((ctx, seed)) => {
                    let d = PyDict::new(py);
                    for (k, v) in ctx {
                        d.set_item(k, v)?;
                    }
                    Ok((d, seed).into_pyobject(py)?.into_any().unbind())
                }
            })
            .collect::<PyResult<_>>()?;
        PyTuple::new(
            py,
            [
                out_ret.into_pyarray(py).into_any(),
                out_len.into_pyarray(py).into_any(),
                out_term.into_pyarray(py).into_any(),
                out_trunc.into_pyarray(py).into_any(),
                pyo3::types::PyList::new(py, words)?.into_any(),
                contexts.into_pyobject(py)?.into_any(),
            ],
        )
    }

    /// Reset the envs where `mask` is true (all for None) in one call, env `i` with its own seed
    /// `seeds[i]` (None: it continues its streams; no `+ i`) and, where `instances[i]` is not
    /// None, playing that instance of its set. A bad length or instance raises ValueError and
    /// resets nothing.
    #[pyo3(signature = (seeds, instances=None, mask=None))]
    fn reset_each<'py>(
        slf: &Bound<'py, Self>,
        seeds: Vec<Option<u64>>,
        instances: Option<Vec<Option<usize>>>,
        mask: Option<PyReadonlyArray1<'py, bool>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let mut guard = slf.try_borrow_mut().map_err(|_| busy())?;
        let this = &mut *guard;
        let py = slf.py();
        let mask_slice = match &mask {
            Some(m) => Some(m.as_slice().map_err(value_error)?),
            None => None,
        };
        let inner = &mut this.inner;
        py.detach(|| inner.reset_each(&seeds, instances.as_deref(), mask_slice).map(drop))
            .map_err(|e| env_error(&e))?;
        this.context_cache = None;
        this.last_any_done = false;
        this.check_outputs(|| "reset".to_string())?;
        this.batch_obs(py)
    }

    /// `(observations, rewards, terminated, truncated, infos)`: fresh NumPy arrays and the step's
    /// infos in Gymnasium's vector layout (same-step `final_obs` / `final_info`, `instance_id`,
    /// `observed_context`), all built here in one call. Actions: int64 `(num_envs,)` or float32
    /// `(num_envs, action_dim)` (other dtypes and layouts are converted as NumPy converts them).
    /// The GIL is released while this thread steps its share of the batch.
    ///
    /// Only this thread can do the Python work of a step, while all threads share the stepping,
    /// so the Python work that does not need the step's results is done while the worker threads
    /// step (`VecEnv::step_with`). First the tuple returned two steps ago is released (in a loop
    /// `obs, ... = venv.step(a)` the caller's own references to it are gone by then; a step's
    /// objects thus live two steps longer), and the arrays in it that nobody else holds go back
    /// to the stock (`Stock::reclaim`: refilled later instead of freed and made anew). Then, for
    /// as long as blocks of the batch are left for the workers, the stock makes what the step's
    /// outputs will need; then this thread steps the blocks left with the GIL released, and
    /// restocks while a worker still steps its last block. What is not ready is made when needed
    /// (with one thread: all of it).
    fn step<'py>(slf: &Bound<'py, Self>, actions: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyTuple>> {
        let mut guard = slf.try_borrow_mut().map_err(|_| busy())?;
        let this = &mut *guard;
        let py = slf.py();
        this.take_actions(actions)?;
        let acts = if this.discrete {
            VecActions::Discrete(&this.discrete_actions)
        } else {
            VecActions::Continuous(&this.continuous_actions)
        };
        let oldest = this.returned[0].take();
        let (stock, n) = (&this.stock, this.inner.num_envs());
        let nested = [&this.feature_keys, &this.visible_keys];
        let mut restocked = Ok(());
        let inner = &mut this.inner;
        // Long steps (rna_design's folds) poll for Ctrl-C, on the worker threads too (the pool
        // relays this thread's check to them).
        cancel::with_check(
            || Python::attach(|py| py.check_signals().is_err()),
            || {
                inner
                    .step_with(acts, |share| {
                        if let Some(t) = oldest {
                            stock.reclaim(t.into_bound(py).into_any(), &nested, n);
                        }
                        restocked = stock.restock(py, &nested, || share.blocks_left()).and_then(|()| {
                            py.detach(|| share.claim_all());
                            stock.restock(py, &nested, || share.workers_busy())
                        });
                    })
                    .map(|_| ())
            },
        )
        .map_err(|e| env_error(&e))?;
        restocked?;
        this.steps += 1;
        let t = this.steps;
        this.check_outputs(|| format!("step {t}"))?;
        let (term, trunc) = (this.inner.terminated(), this.inner.truncated());
        // Most batch steps end no episode: one branch-free pass tells (a filter over all envs
        // cost ~450 instructions per step).
        let any_done = term.iter().zip(trunc).fold(false, |any, (&a, &b)| any | a | b);
        let ended: Vec<usize> = if this.same_step && any_done {
            (0..n).filter(|&i| term[i] | trunc[i]).collect()
        } else {
            Vec::new()
        };
        // Contexts change only where an env resets: in this step (same-step) or the next
        // (next-step), or at every step under a schedule; a plain batch has one fixed context.
        if this.contextual && (any_done || this.last_any_done || this.scheduled) {
            this.context_cache = None;
        }
        this.last_any_done = any_done;
        let infos = this.cached_context_infos(py)?;
        if !ended.is_empty() {
            this.final_infos(&infos, &ended)?;
            // How the finished episodes ended, beside their other final infos.
            if let Some(fin) = infos.get_item(pyo3::intern!(py, "final_info"))? {
                this.set_outcomes(fin.cast::<PyDict>()?, &ended)?;
            }
        } else if any_done {
            // Next-step and disabled modes: this step's infos are the finished episodes' last.
            let (term, trunc) = (this.inner.terminated(), this.inner.truncated());
            let done: Vec<usize> = (0..n).filter(|&i| term[i] | trunc[i]).collect();
            this.set_outcomes(&infos, &done)?;
        }
        if this.noisy {
            let all: Vec<usize> = (0..n).collect();
            this.set_observed(&infos, this.inner.obs(), &all)?;
        }
        let (term, trunc) = (this.inner.terminated(), this.inner.truncated());
        let out = PyTuple::new(
            py,
            [
                this.batch_obs(py)?,
                this.stock
                    .filled(py, &[n], |o: &mut [f64]| o.copy_from_slice(this.inner.rewards())),
                this.stock.filled(py, &[n], |o: &mut [bool]| o.copy_from_slice(term)),
                this.stock.filled(py, &[n], |o: &mut [bool]| o.copy_from_slice(trunc)),
                infos.into_any(),
            ],
        )?;
        this.returned = [this.returned[1].take(), Some(out.clone().unbind())];
        Ok(out)
    }

    /// Benchmark anchor, not for training: `steps` batch steps of `actions` (a list of action
    /// batches, cycled from the first) stepped by the Rust `VecEnv` in one native loop, the GIL
    /// released, no outputs made for Python. `python/bench/bench_python_api.py` times it in the
    /// same process as `step`, alternating with it, over the same window of the same episodes:
    /// the native rate under the same machine conditions as the Python-driven one.
    fn native_steps(slf: &Bound<'_, Self>, actions: Vec<Bound<'_, PyAny>>, steps: usize) -> PyResult<()> {
        let mut guard = slf.try_borrow_mut().map_err(|_| busy())?;
        let this = &mut *guard;
        let py = slf.py();
        if actions.is_empty() {
            return Err(value_error("native_steps needs at least one action batch"));
        }
        let (mut discrete, mut continuous) = (Vec::new(), Vec::new());
        for a in &actions {
            this.take_actions(a)?;
            if this.discrete {
                discrete.push(this.discrete_actions.clone());
            } else {
                continuous.push(this.continuous_actions.clone());
            }
        }
        // In slices of ~50 ms with the GIL released, checking for Ctrl-C between them.
        let inner = &mut this.inner;
        let mut k = 0;
        while k < steps {
            py.check_signals()?;
            k = py
                .detach(|| -> Result<usize, carl_spec::envs::EnvError> {
                    let t0 = std::time::Instant::now();
                    let mut k = k;
                    while k < steps {
                        let acts = if discrete.is_empty() {
                            VecActions::Continuous(&continuous[k % continuous.len()])
                        } else {
                            VecActions::Discrete(&discrete[k % discrete.len()])
                        };
                        inner.step(acts)?;
                        k += 1;
                        if t0.elapsed() > std::time::Duration::from_millis(50) {
                            break;
                        }
                    }
                    Ok(k)
                })
                .map_err(|e| env_error(&e))?;
        }
        Ok(())
    }

    /// The infos of a reset of the envs where `mask` is true (all for None): `cs.make`'s reset
    /// info (`context`, ...) of each, in Gymnasium's vector layout.
    #[pyo3(signature = (mask=None))]
    fn infos<'py>(slf: &Bound<'py, Self>, mask: Option<PyReadonlyArray1<'py, bool>>) -> PyResult<Bound<'py, PyDict>> {
        let this = slf.try_borrow().map_err(|_| busy())?;
        let py = slf.py();
        let n = this.inner.num_envs();
        let rows: Vec<usize> = match &mask {
            Some(m) => {
                let s = m.as_slice().map_err(value_error)?;
                (0..n).filter(|&i| s.get(i).copied().unwrap_or(false)).collect()
            }
            None => (0..n).collect(),
        };
        let d = PyDict::new(py);
        this.context_infos(&d, &rows)?;
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

    /// Environment `i`'s next episode plays `context` (a JSON object; a curriculum's choice).
    fn set_next_context(&mut self, i: usize, context: &str) -> PyResult<()> {
        let ctx: Context = serde_json::from_str(context).map_err(|e| value_error(format!("context: {e}")))?;
        self.inner.set_next_context(i, &ctx).map_err(value_error)
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
