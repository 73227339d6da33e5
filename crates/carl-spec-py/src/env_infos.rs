//! The info dicts of one environment: its context, what the agent observes of it, and what a
//! runtime reports at an episode's end.

use pyo3::prelude::*;
use pyo3::types::PyDict;

use carl_spec::envs::AnyEnv;
use carl_spec::envs::brax::GoalLocomotion;
use carl_spec::envs::contextual::{ContextInfo, ContextualEnv};
use carl_spec::envs::rna_design::RnaDesign;

/// The info dict of the context `ci` (see [`context_info_dict`]).
pub(crate) fn info_dict<'py>(py: Python<'py>, ci: &ContextInfo) -> PyResult<Bound<'py, PyDict>> {
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
pub(crate) fn episode_end_info<'py>(py: Python<'py>, runtime: &AnyEnv) -> PyResult<Option<Bound<'py, PyDict>>> {
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

/// The goal of a locomotion robot built with the `goal` option after its last reset or step:
/// `goal_direction` (the name of its compass code), `goal_distance` (m), `success` (0/1), and
/// `goal_position` / `torso_position` relative to the torso's start.
/// None for other runtimes.
pub(crate) fn goal_info<'py>(py: Python<'py>, runtime: &AnyEnv) -> PyResult<Option<Bound<'py, PyDict>>> {
    let Some(g) = runtime.downcast_ref::<GoalLocomotion>() else {
        return Ok(None);
    };
    let info = carl_spec::envs::Env::info(g);
    let d = PyDict::new(py);
    d.set_item("goal_direction", g.direction().name)?;
    d.set_item("goal_distance", info.get("goal_distance").copied().unwrap_or(f64::NAN))?;
    d.set_item("success", info.get("success").map_or(0, |s| i64::from(*s != 0.0)))?;
    // Relative to the torso's start (m, x east, y north).
    let (s, g, t) = (g.start(), g.goal(), g.torso_position());
    d.set_item("goal_position", [g[0] - s[0], g[1] - s[1]])?;
    d.set_item("torso_position", [t[0] - s[0], t[1] - s[1]])?;
    Ok(Some(d))
}

/// Whether the runtime reports [`episode_end_info`].
pub(crate) fn has_episode_end_info(runtime: &AnyEnv) -> bool {
    runtime.downcast_ref::<RnaDesign>().is_some()
}

/// `{feature: observed value}` of the visible features (what the agent sees, noise included).
pub(crate) fn observed_dict<'py>(py: Python<'py>, env: &ContextualEnv) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (k, v) in env.visible_features().iter().zip(env.observed_context()) {
        d.set_item(k, f64::from(*v))?;
    }
    Ok(d)
}
