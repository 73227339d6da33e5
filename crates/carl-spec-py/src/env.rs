//! `_core.Env`: one contextual environment (`carl_spec.make` wraps it in a `gymnasium.Env`).

use std::path::PathBuf;

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use carl_spec::envs::cancel;
use carl_spec::envs::contextual::{ContextualEnv, NoiseRedraw};
use carl_spec::envs::registry::Context;
use carl_spec::envs::{Action, Env as _, Space};

use crate::actions::{BoxBounds, check_obs};
use crate::context_args::{ContextArgs, build_contextual, source_of};
use crate::env_infos::{episode_end_info, goal_info, info_dict, observed_dict};
use crate::errors::{contextual_error, env_error, value_error};
use crate::obs_layout::ObsLayout;
use crate::specs::{space_json, with_specs};

/// One contextual environment (`carl_spec.make` wraps it in a `gymnasium.Env`).
#[pyclass(module = "carl_spec._core")]
pub(crate) struct Env {
    inner: ContextualEnv,
    action: Action,
    obs: Vec<f32>,
    /// The float64 observation (float64 spaces only, else empty).
    obs64: Vec<f64>,
    layout: ObsLayout,
    /// Continuous actions: the space's bounds (finite actions are clipped to them).
    bounds: Option<BoxBounds>,
    /// Steps since the last reset (named when an output is not finite).
    t: u64,
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
    /// `args`: the context source (`carl_spec._args.context_args`; None: the default context).
    #[new]
    #[pyo3(signature = (env, args=None, *, specs_dir=None))]
    fn new(
        py: Python<'_>,
        env: &str,
        args: Option<&Bound<'_, ContextArgs>>,
        specs_dir: Option<PathBuf>,
    ) -> PyResult<Self> {
        let args = source_of(args);
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
            bounds: BoxBounds::of(&inner.action_space()),
            t: 0,
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

    /// `(observation, info)`; `seed=None` continues the current streams; `instance`: play that
    /// instance of the set (a ValueError for an index outside it or a source that is no set).
    #[pyo3(signature = (seed=None, instance=None))]
    fn reset<'py>(
        &mut self,
        py: Python<'py>,
        seed: Option<u64>,
        instance: Option<usize>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyDict>)> {
        match instance {
            Some(i) => self.inner.reset_instance_into(seed, i, &mut self.obs),
            None => self.inner.reset_into(seed, &mut self.obs),
        }
        .map_err(|e| env_error(&e))?;
        self.t = 0;
        let obs = self.observation(py)?;
        check_obs(|| format!("{} reset", self.inner.id()), &self.obs, &self.obs64, 0.0)?;
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
                // float64 from `CarlEnv.step` (float32 is read as well): checked finite and
                // clipped to the space before the cast to float32.
                let id = self.inner.id();
                let bounds = self.bounds.as_ref().expect("a Box action space has bounds");
                if let Ok(arr) = action.extract::<PyReadonlyArray1<'_, f64>>() {
                    bounds.take(id, None, arr.as_slice().map_err(value_error)?, v)?;
                } else {
                    let arr: PyReadonlyArray1<'_, f32> = action.extract()?;
                    let wide: Vec<f64> = arr
                        .as_slice()
                        .map_err(value_error)?
                        .iter()
                        .map(|&x| f64::from(x))
                        .collect();
                    bounds.take(id, None, &wide, v)?;
                }
            }
        }
        // Long steps (rna_design's local improvement: up to 4^9 folds) poll for Ctrl-C.
        let (inner, action, obs) = (&mut self.inner, &self.action, &mut self.obs);
        let out = cancel::with_check(
            || Python::attach(|py| py.check_signals().is_err()),
            || inner.step_into(action, obs),
        )
        .map_err(|e| env_error(&e))?;
        self.t += 1;
        let obs = self.observation(py)?;
        check_obs(
            || format!("{} step {}", self.inner.id(), self.t),
            &self.obs,
            &self.obs64,
            out.reward,
        )?;
        Ok((obs, out.reward, out.terminated, out.truncated))
    }

    /// How the episode ended after the step that ended it (`Env::outcome`: `landed`, `solved`,
    /// `timed_out`, ...), else None.
    fn outcome(&self) -> Option<&'static str> {
        self.inner.outcome()
    }

    /// The current episode's context info (as `reset` returns it).
    fn info<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        info_dict(py, self.inner.context_info())
    }

    /// The next episode plays `context` (a JSON object; a curriculum's choice).
    fn set_next_context(&mut self, py: Python<'_>, context: &str) -> PyResult<()> {
        let ctx: Context = serde_json::from_str(context).map_err(|e| value_error(format!("context: {e}")))?;
        self.inner.set_next_context(&ctx).map_err(|e| contextual_error(py, &e))
    }

    /// The scheduled features' current values (empty without schedules): what changes in the
    /// context info from step to step.
    fn scheduled_context<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (k, x) in self.inner.scheduled_values() {
            d.set_item(k, x)?;
        }
        Ok(d)
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

    /// After a reset or step of a robot built with the `goal` option: `goal_direction` (name),
    /// `goal_distance` and `success`; else None.
    fn goal_info<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        goal_info(py, self.inner.inner().inner())
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
