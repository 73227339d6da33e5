//! What crosses the binding per step and is checked there, as the CLI checks it: continuous
//! actions (finite, clipped to the action space as Gymnasium's own environments clip them) and
//! the environment's outputs (a non-finite observation or reward is an error, as in
//! `carl-spec rollout`).

use pyo3::prelude::*;

use carl_spec::envs::Space;

use crate::errors::value_error;

/// The bounds of a Box action space.
pub(crate) struct BoxBounds {
    low: Vec<f64>,
    high: Vec<f64>,
}

impl BoxBounds {
    /// The bounds of `space` if it is a Box.
    pub(crate) fn of(space: &Space) -> Option<Self> {
        match space {
            Space::Box { low, high, .. } => Some(BoxBounds {
                low: low.iter().map(|&x| f64::from(x)).collect(),
                high: high.iter().map(|&x| f64::from(x)).collect(),
            }),
            Space::Discrete { .. } => None,
        }
    }

    /// Copy one action `src` into `dst`: every component finite (NaN and ±inf refused, naming
    /// the component), clipped to `[low, high]`, then cast to float32. `env`: the environment's
    /// index in a batch.
    pub(crate) fn take(&self, id: &str, env: Option<usize>, src: &[f64], dst: &mut [f32]) -> PyResult<()> {
        let at = || env.map_or_else(String::new, |i| format!(" of environment {i}"));
        if src.len() != dst.len() {
            return Err(value_error(format!(
                "{id}: the continuous action{} must have {} component(s), got {}",
                at(),
                dst.len(),
                src.len()
            )));
        }
        for (j, (x, o)) in src.iter().zip(dst.iter_mut()).enumerate() {
            let clipped = x.clamp(self.low[j], self.high[j]);
            let y = clipped as f32;
            if !x.is_finite() || !y.is_finite() {
                return Err(value_error(format!(
                    "{id}: action{} component {j} is {x}; actions must be finite numbers (within float32 range)",
                    at()
                )));
            }
            *o = y;
        }
        Ok(())
    }
}

/// A non-finite observation component or reward as the CLI reports it (`where_`: which
/// environment and step).
pub(crate) fn check_obs(where_: impl FnOnce() -> String, obs: &[f32], wide: &[f64], reward: f64) -> PyResult<()> {
    if wide.is_empty() {
        return carl_spec::episode::check_finite(where_, obs, reward).map_err(value_error);
    }
    // A float64 observation: its float32 copy may overflow where the float64 one is finite.
    match wide.iter().position(|x| !x.is_finite()) {
        Some(j) => Err(value_error(carl_spec::episode::EpisodeError::NonFinite {
            where_: where_(),
            what: format!("observation component {j}"),
            value: wide[j],
        })),
        None => carl_spec::episode::check_finite(where_, &[], reward).map_err(value_error),
    }
}
