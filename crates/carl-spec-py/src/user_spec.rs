//! Users' own spec files for `carl_spec.wrap` and `carl_spec.audit` (environments carl-spec does
//! not ship): loading them through the same validator, choosing a context per reset by the
//! library's own rules (`carl_spec::envs::context_schedule`, which `ContextualEnv` uses too), and
//! the audit's probe values.
//!
//! The environment itself is the user's Python object, so no runtime is built here: a
//! [`ContextChooser`] only answers "which context does this reset use, with which seed does the
//! user's env reset, and what does the agent observe of the visible features".

use std::collections::BTreeMap;
use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::types::PyDict;

use carl_spec::audit::probes::{perturbed_values, unauditable_reason};
use carl_spec::envs::Selection;
use carl_spec::envs::context_schedule::{ContextSchedule, ObservationNoise, Pick, ScheduleKind, drawn_context};
use carl_spec::envs::contextual::NoiseRedraw;
use carl_spec::envs::registry::{Context, MakeError, MakeOptions};
use carl_spec::instances::Store;
use carl_spec::instances::derive::DeriveError;
use carl_spec::spec::SpecSet;
use carl_spec::spec::load::{bundled_inputs, read_inputs};
use carl_spec::spec::model::{Distribution, EnvSpec};

use crate::context_args::{ContextArgs, SourceArgs, parse_selection, source_of};
use crate::errors::{unknown_name, value_error};

/// The user's spec file(s) (a file or a directory), validated like `carl-spec validate PATH`
/// (bundled shared fragments may be included), and the one environment they describe (`env`
/// chooses when there are several).
fn load_set(py: Python<'_>, path: &PathBuf, env: Option<&str>) -> PyResult<(SpecSet, String)> {
    let mut inputs = read_inputs(std::slice::from_ref(path)).map_err(value_error)?;
    if inputs.is_empty() {
        return Err(value_error(format!("no *.json spec files found in {}", path.display())));
    }
    inputs.extend(bundled_inputs(true).into_iter().filter(|i| i.name.contains("/shared/")));
    let specs = SpecSet::from_inputs(&inputs).map_err(value_error)?;
    let envs = specs.envs();
    let id = match env {
        Some(name) => specs.require(name).map_err(|m| unknown_name(py, m))?.id.clone(),
        None if envs.len() == 1 => envs[0].id.clone(),
        None => Err(value_error(format!(
            "{} describes {} environments ({}); choose one with env_id=",
            path.display(),
            envs.len(),
            envs.iter().map(|e| e.id.as_str()).collect::<Vec<_>>().join(", ")
        )))?,
    };
    Ok((specs, id))
}

fn load(py: Python<'_>, path: &PathBuf, env: Option<&str>) -> PyResult<EnvSpec> {
    let (specs, id) = load_set(py, path, env)?;
    specs
        .get(&id)
        .cloned()
        .ok_or_else(|| value_error(format!("no environment \"{id}\"")))
}

/// The resolved spec of a user's file, as `carl_spec.spec` returns a bundled one.
#[pyfunction]
#[pyo3(signature = (path, env=None))]
pub fn user_spec_json(py: Python<'_>, path: PathBuf, env: Option<&str>) -> PyResult<String> {
    let spec = load(py, &path, env)?;
    serde_json::to_string(&spec).map_err(value_error)
}

/// Per feature: the values the sensitivity audit perturbs it to (the Rust audit's rule), or why
/// it cannot be perturbed. `[{"name", "values", "skipped"}]`.
#[pyfunction]
#[pyo3(signature = (path, env=None))]
pub fn audit_values_json(py: Python<'_>, path: PathBuf, env: Option<&str>) -> PyResult<String> {
    let spec = load(py, &path, env)?;
    let rows: Vec<_> = spec
        .features
        .iter()
        .map(|f| {
            let values = perturbed_values(f);
            let skipped = unauditable_reason(f).or_else(|| {
                values
                    .is_empty()
                    .then(|| "no value inside the bounds differs from the default".to_string())
            });
            serde_json::json!({"name": f.name, "values": values, "skipped": skipped})
        })
        .collect();
    serde_json::to_string(&rows).map_err(value_error)
}

fn make_error(py: Python<'_>, e: MakeError) -> PyErr {
    match e {
        MakeError::UnknownFeature { .. } => unknown_name(py, e.to_string()),
        other => value_error(other),
    }
}

/// One resolved context (every feature, canonical names, spec order) and its set labels.
#[derive(Clone)]
struct Chosen {
    context: Vec<(String, f64)>,
    instance_id: Option<usize>,
    instance_name: Option<String>,
    context_seed: Option<u64>,
}

enum Mode {
    Fixed(Chosen),
    Set(Vec<Chosen>),
    Distribution { name: String, dist: Distribution },
}

/// Chooses each episode's context for a wrapped user environment by the library's
/// [`ContextSchedule`] (the rules and streams of `carl_spec::envs::contextual`, see its module
/// docs), and measures the visible features with the library's [`ObservationNoise`], so a wrapped
/// env and `cs.make` make the same choices and draws from the same seed.
#[pyclass(module = "carl_spec._core")]
pub struct ContextChooser {
    spec: EnvSpec,
    mode: Mode,
    schedule: ContextSchedule,
    /// Canonical names of the features the wrapper appends to the observation.
    visible: Vec<String>,
    noise: ObservationNoise,
    /// What the agent observes of `visible` now (true values + noise).
    observed: Vec<f32>,
    current: Option<Chosen>,
}

impl ContextChooser {
    /// The spec's default context, resolved.
    fn defaults(&self, py: Python<'_>) -> PyResult<Vec<(String, f64)>> {
        carl_spec::envs::context::resolve_context(&self.spec, &Context::new(), MakeOptions::default())
            .map_err(|e| make_error(py, e))
    }

    /// The visible features' true values in `context`, in observation order.
    fn truth(&self, context: &[(String, f64)]) -> Vec<f32> {
        self.visible
            .iter()
            .map(|name| context.iter().find(|(k, _)| k == name).map_or(0.0, |(_, v)| *v as f32))
            .collect()
    }

    fn draw(&self, py: Python<'_>, name: &str, dist: &Distribution, context_seed: u64) -> PyResult<Chosen> {
        let ctx = drawn_context(&self.spec, name, dist, context_seed).map_err(value_error)?;
        let context = carl_spec::envs::context::resolve_context(&self.spec, &ctx, MakeOptions::default())
            .map_err(|e| make_error(py, e))?;
        Ok(Chosen {
            context,
            instance_id: None,
            instance_name: None,
            context_seed: Some(context_seed),
        })
    }
}

#[pymethods]
impl ContextChooser {
    /// `path`: the user's spec file or directory (`env` picks one of its environments); None: the
    /// bundled spec of `env`. `args`: the context source as `cs.wrap` takes it
    /// (`carl_spec._args.context_args`; its `obs_context` are the features the wrapper shows the
    /// agent, in order; `allow_out_of_bounds` is refused: a user's spec states its bounds).
    /// `contexts_json`: an inline list of contexts used like an instance set (ids are positions;
    /// `carl_spec.compat`'s `contexts` dict), selected by `args`' selection.
    #[new]
    #[pyo3(signature = (path, args=None, *, env=None, contexts_json=None))]
    fn new(
        py: Python<'_>,
        path: Option<PathBuf>,
        args: Option<&Bound<'_, ContextArgs>>,
        env: Option<&str>,
        contexts_json: Option<String>,
    ) -> PyResult<Self> {
        let a = source_of(args);
        if a.allow_out_of_bounds {
            return Err(value_error(
                "allow_out_of_bounds applies to carl_spec.make; a user's spec states its own bounds",
            ));
        }
        if a.options_json.is_some() {
            return Err(value_error(
                "options apply to carl_spec.make's runtimes, not to a wrapped env",
            ));
        }
        if a.obs_context_all {
            return Err(value_error(
                "ContextChooser takes obs_context as a list of feature names",
            ));
        }
        let SourceArgs {
            context_json,
            instances,
            distribution,
            selection,
            instance,
            obs_context,
            noise,
            ..
        } = a;
        let selection = selection.as_str();
        let (specs, id) = match &path {
            Some(path) => load_set(py, path, env)?,
            None => {
                let name = env.ok_or_else(|| value_error("ContextChooser needs a spec path or a bundled env id"))?;
                crate::specs::with_specs(None, |specs| {
                    let spec = specs.require(name).map_err(|m| unknown_name(py, m))?;
                    Ok((specs.clone(), spec.id.clone()))
                })?
            }
        };
        let spec = specs
            .get(&id)
            .cloned()
            .ok_or_else(|| value_error(format!("no environment \"{id}\"")))?;
        let given = [
            context_json.is_some(),
            contexts_json.is_some(),
            instances.is_some(),
            distribution.is_some(),
        ];
        if given.iter().filter(|g| **g).count() > 1 {
            return Err(value_error(
                "give at most one of context=, instances= and distribution=",
            ));
        }
        let selection = parse_selection(selection, instance)?;
        if instances.is_none() && contexts_json.is_none() && !matches!(selection, Selection::RoundRobin) {
            return Err(value_error(
                "selection= applies to instances= (or a list of contexts) only",
            ));
        }
        let resolve = |ctx: &Context, allow_out_of_bounds: bool| {
            carl_spec::envs::context::resolve_context(&spec, ctx, MakeOptions { allow_out_of_bounds })
                .map_err(|e| make_error(py, e))
        };
        let check_static = |n: usize, what: &str| match selection {
            Selection::Static(i) if i >= n => Err(value_error(format!(
                "instance={i} is out of range: {what} has {n} instances (0..{n})"
            ))),
            _ => Ok(()),
        };
        let mode = if let Some(text) = contexts_json {
            let list: Vec<Context> = serde_json::from_str(&text).map_err(|e| value_error(format!("contexts: {e}")))?;
            if list.is_empty() {
                return Err(value_error("contexts must hold at least one context"));
            }
            check_static(list.len(), "contexts")?;
            let instances = list
                .iter()
                .enumerate()
                .map(|(i, ctx)| {
                    Ok(Chosen {
                        context: resolve(ctx, false)?,
                        instance_id: Some(i),
                        instance_name: None,
                        context_seed: None,
                    })
                })
                .collect::<PyResult<Vec<_>>>()?;
            Mode::Set(instances)
        } else if let Some(set_name) = instances {
            let qualified = if set_name.contains('/') {
                set_name
            } else {
                format!("{}/{set_name}", spec.id)
            };
            // The user's frozen files live in `<spec dir>/instances/<id>/<set>.json`.
            let store = Store::new(&specs);
            let set = store.load(&qualified).map_err(|e| {
                use carl_spec::instances::store::StoreError as S;
                match e {
                    S::Unknown(_) | S::BadName(_) => unknown_name(py, e.to_string()),
                    // A user's set is frozen beside the user's spec: name that directory.
                    S::NotFrozen { .. } if path.is_some() => {
                        let dir = path
                            .as_deref()
                            .map(|p| if p.is_dir() { p } else { p.parent().unwrap_or(p) })
                            .map(|d| d.display().to_string())
                            .filter(|d| !d.is_empty())
                            .unwrap_or_else(|| ".".into());
                        value_error(format!(
                            "{qualified} is declared but not frozen; freeze it beside the spec with \
                             `carl-spec --specs {dir} freeze {qualified}`"
                        ))
                    }
                    _ => value_error(e),
                }
            })?;
            let allow = spec.instance_sets.get(&set.set).is_some_and(|d| d.allow_out_of_bounds);
            check_static(set.instances.len(), &set.qualified_name())?;
            let instances = set
                .instances
                .iter()
                .map(|i| {
                    let ctx: Context = i.context.clone().into_iter().collect::<BTreeMap<_, _>>();
                    Ok(Chosen {
                        context: resolve(&ctx, allow)?,
                        instance_id: Some(i.id),
                        instance_name: i.name.clone(),
                        context_seed: None,
                    })
                })
                .collect::<PyResult<Vec<_>>>()?;
            Mode::Set(instances)
        } else if let Some(name) = distribution {
            let dist = spec.distributions.get(&name).cloned().ok_or_else(|| {
                let known: Vec<&str> = spec.distributions.keys().map(String::as_str).collect();
                unknown_name(
                    py,
                    DeriveError::UnknownDistribution {
                        env: spec.id.clone(),
                        name: name.clone(),
                        hint: if known.is_empty() {
                            format!("; {} declares no distributions", spec.id)
                        } else {
                            format!("; known: {}", known.join(", "))
                        },
                    }
                    .to_string(),
                )
            })?;
            Mode::Distribution { name, dist }
        } else {
            let ctx: Context = match &context_json {
                Some(text) => serde_json::from_str(text).map_err(|e| value_error(format!("context: {e}")))?,
                None => Context::new(),
            };
            Mode::Fixed(Chosen {
                context: resolve(&ctx, false)?,
                instance_id: None,
                instance_name: None,
                context_seed: None,
            })
        };
        let kind = match &mode {
            Mode::Set(instances) => ScheduleKind::Set {
                n: instances.len(),
                selection,
            },
            Mode::Fixed(_) => ScheduleKind::Fixed,
            Mode::Distribution { .. } => ScheduleKind::Distribution,
        };
        let visible = obs_context
            .unwrap_or_default()
            .iter()
            .map(|name| {
                spec.feature(name).map(|f| f.name.clone()).ok_or_else(|| {
                    unknown_name(
                        py,
                        format!(
                            "{} has no context feature \"{name}\"; features: {}",
                            spec.id,
                            spec.feature_names().collect::<Vec<_>>().join(", ")
                        ),
                    )
                })
            })
            .collect::<PyResult<Vec<_>>>()?;
        if !noise.is_empty() && visible.is_empty() {
            return Err(value_error(crate::context_args::NOISE_NEEDS_OBS_CONTEXT));
        }
        let noise = ObservationNoise::new(&spec, &visible, &noise).map_err(value_error)?;
        let mut chooser = ContextChooser {
            spec,
            mode,
            schedule: ContextSchedule::new(kind),
            visible,
            noise,
            observed: Vec::new(),
            current: None,
        };
        let defaults = chooser.defaults(py)?;
        if let Some(name) = chooser.visible.iter().find(|n| !defaults.iter().any(|(k, _)| k == *n)) {
            return Err(value_error(format!(
                "{}: feature \"{name}\" has no numeric value, so it cannot be observed",
                chooser.spec.id
            )));
        }
        chooser.observed = chooser.truth(&defaults);
        Ok(chooser)
    }

    /// Choose the next episode's context. Returns `(info, env_seed)`: the info dict (`context`,
    /// `instance_id`/`instance_name` for sets, `context_seed` for distributions, and with noise
    /// `observed_context`, as `cs.make`'s) and the seed the user's env resets with (None: continue
    /// its own stream).
    #[pyo3(signature = (seed=None))]
    fn reset<'py>(&mut self, py: Python<'py>, seed: Option<u64>) -> PyResult<(Bound<'py, PyDict>, Option<u64>)> {
        if let Some(s) = seed {
            self.noise.seed(s);
        }
        let plan = self.schedule.next(seed);
        let chosen = match (&self.mode, plan.pick) {
            (Mode::Set(instances), Pick::Instance(i)) => instances[i].clone(),
            (Mode::Distribution { name, dist }, Pick::Draw { context_seed }) => {
                self.draw(py, name, dist, context_seed)?
            }
            (Mode::Fixed(c), _) => c.clone(),
            // The schedule's kind is built from the mode, so they always agree.
            _ => {
                return Err(value_error(
                    "internal error: the context schedule disagrees with the source",
                ));
            }
        };
        let truth = self.truth(&chosen.context);
        self.noise.observe(&truth, &mut self.observed);
        self.current = Some(chosen);
        Ok((self.info(py)?, plan.runtime_seed))
    }

    /// After a step of the user's env: with per-step noise, a fresh measurement of the visible
    /// features (`{feature: observed}`); else None (the episode's measurement stands).
    fn after_step<'py>(&mut self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        if self.noise.redraw() != Some(NoiseRedraw::Step) {
            return Ok(None);
        }
        let truth = match &self.current {
            Some(c) => self.truth(&c.context),
            None => self.truth(&self.defaults(py)?),
        };
        self.noise.after_step(&truth, &mut self.observed);
        self.observed_context(py).map(Some)
    }

    /// `{feature: value}` of the visible features as the agent observes them now (noise
    /// included; the true values without noise).
    fn observed_context<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (k, v) in self.visible.iter().zip(&self.observed) {
            d.set_item(k, f64::from(*v))?;
        }
        Ok(d)
    }

    /// When the noise is redrawn: "episode", "step", or None (no noise).
    fn noise_redraw(&self) -> Option<&'static str> {
        self.noise.redraw().map(|r| match r {
            NoiseRedraw::Episode => "episode",
            NoiseRedraw::Step => "step",
        })
    }

    /// The current episode's info (the default context before the first reset).
    fn info<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = match &self.current {
            Some(c) => crate::env_infos::context_info_dict(
                py,
                &c.context,
                c.instance_id,
                c.instance_name.as_deref(),
                c.context_seed,
            )?,
            None => crate::env_infos::context_info_dict(py, &self.defaults(py)?, None, None, None)?,
        };
        if self.noise.redraw().is_some() {
            d.set_item("observed_context", self.observed_context(py)?)?;
        }
        Ok(d)
    }

    /// Switch to instance `i` now (carl-bench's `context_id` setter): the current info becomes
    /// instance `i`'s; round robin continues with `i + 1` at the next unseeded reset, static
    /// selection stays on `i`. The switch takes effect in the user's env at the next reset.
    fn set_instance(&mut self, i: usize) -> PyResult<()> {
        let Mode::Set(instances) = &self.mode else {
            return Err(value_error("context_id can be set only for a set of contexts"));
        };
        let n = instances.len();
        if i >= n {
            return Err(value_error(format!(
                "context id {i} is out of range: the set has {n} contexts (0..{n})"
            )));
        }
        self.current = Some(instances[i].clone());
        self.schedule.continue_after(i);
        Ok(())
    }

    /// Every instance's resolved context, canonical names, spec order: a set's or a context
    /// list's instances, a fixed context, or nothing for a distribution (drawn per reset).
    fn instance_contexts<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        let dict = |c: &[(String, f64)]| -> PyResult<Bound<'py, PyDict>> {
            let d = PyDict::new(py);
            for (k, v) in c {
                d.set_item(k, v)?;
            }
            Ok(d)
        };
        match &self.mode {
            Mode::Set(instances) => instances.iter().map(|c| dict(&c.context)).collect(),
            Mode::Fixed(c) => Ok(vec![dict(&c.context)?]),
            Mode::Distribution { .. } => Ok(Vec::new()),
        }
    }

    #[getter]
    fn env_id(&self) -> String {
        self.spec.id.clone()
    }

    #[getter]
    fn num_instances(&self) -> usize {
        match &self.mode {
            Mode::Set(instances) => instances.len(),
            _ => 1,
        }
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(user_spec_json, m)?)?;
    m.add_function(wrap_pyfunction!(audit_values_json, m)?)?;
    m.add_class::<ContextChooser>()?;
    Ok(())
}
