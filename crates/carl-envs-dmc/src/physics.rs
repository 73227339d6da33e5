//! [`Physics`]: the simulation a dm_control environment steps (dm_control's name), with the
//! episode plumbing the family's environments share: the `started` check, the control step's
//! physics substeps, the divergence check and its rollback, the state layout (`qpos`, `qvel`,
//! `act`, then the environment's own entries) and its length checks, and resets through
//! [`Data::reset`]. Each environment keeps its reward, observation, reset distribution,
//! options and drawing; [`observation_space`], [`observe_into`] and [`observe_f64_into`] are
//! the `Env` methods they all write from one `f64` observation.

use std::sync::Arc;

use carl_articulated::{Data, Model};
use carl_env::api::{DType, EnvError, Space, check_obs_len, check_state_len};

/// One environment's simulation: the engine's data, the control step's substeps and the
/// episode's bookkeeping.
#[derive(Debug, Clone)]
pub struct Physics {
    id: &'static str,
    /// The engine's state (public: each environment reads its own sensors from it and sets its
    /// initial state in it).
    pub data: Data,
    substeps: usize,
    /// A step whose speeds exceed this is rolled back ([`Data::is_sane`]); `None`: no check.
    max_speed: Option<f64>,
    started: bool,
}

impl Physics {
    /// The simulation of `model` at `qpos0`, its poses computed; `substeps` physics steps per
    /// control step.
    pub fn new(id: &'static str, model: Arc<Model>, substeps: usize, max_speed: Option<f64>) -> Physics {
        let mut data = Data::new(model);
        data.update_kinematics();
        Physics {
            id,
            data,
            substeps,
            max_speed,
            started: false,
        }
    }

    /// A new model for the next episode (its data at `qpos0`).
    pub fn replace_model(&mut self, model: Arc<Model>) {
        self.data = Data::new(model);
    }

    /// The start of an episode's reset: [`Data::reset`] (`qpos0`, zero velocities, activations
    /// and controls, time 0, the solver's warm start forgotten). The environment then sets its
    /// random initial state and calls [`Physics::start`].
    pub fn reset(&mut self) {
        self.data.reset();
    }

    /// The episode has begun: [`Physics::step`] may run.
    pub fn start(&mut self) {
        self.started = true;
    }

    /// One control step: the action into `ctrl`, the substeps (the last one through
    /// [`Data::step_observed`] with `observe_last` when given), then the divergence check: a
    /// diverged step is rolled back to the state before it (`qpos`, `qvel`, `act`). Returns
    /// whether it diverged (the environment then refreshes what it derives from the state, as
    /// after a set state); [`EnvError::NeedsReset`] before the first reset.
    pub fn step(&mut self, action: &[f32], observe_last: Option<&mut dyn FnMut(&Data)>) -> Result<bool, EnvError> {
        if !self.started {
            return Err(EnvError::NeedsReset { env: self.id });
        }
        let before = self.max_speed.map(|_| self.dynamic_state());
        for (c, x) in self.data.ctrl.iter_mut().zip(action) {
            *c = f64::from(*x);
        }
        match observe_last {
            None => {
                for _ in 0..self.substeps {
                    self.data.step();
                }
            }
            Some(read) => {
                for _ in 1..self.substeps {
                    self.data.step();
                }
                self.data.step_observed(read);
            }
        }
        let diverged = match self.max_speed {
            Some(max_speed) => !self.data.is_sane(max_speed),
            None => false,
        };
        if diverged && let Some(before) = before {
            self.write_dynamic_state(&before);
        }
        Ok(diverged)
    }

    /// The length of `qpos`, `qvel` and `act` together.
    pub fn dynamic_len(&self) -> usize {
        let m = self.data.model();
        m.nq + m.nv + m.na
    }

    /// The state's length with `extra` entries of the environment's own.
    pub fn state_dim(&self, extra: usize) -> usize {
        self.dynamic_len() + extra
    }

    fn dynamic_state(&self) -> Vec<f64> {
        let d = &self.data;
        d.qpos.iter().chain(&d.qvel).chain(&d.act).copied().collect()
    }

    fn write_dynamic_state(&mut self, s: &[f64]) {
        let d = &mut self.data;
        let (nq, nv) = (d.qpos.len(), d.qvel.len());
        d.qpos.copy_from_slice(&s[..nq]);
        d.qvel.copy_from_slice(&s[nq..nq + nv]);
        let na = d.act.len();
        d.act.copy_from_slice(&s[nq + nv..nq + nv + na]);
    }

    /// The state: `qpos`, `qvel`, `act` (empty without activations), then `extra`.
    pub fn state(&self, extra: &[f64]) -> Vec<f64> {
        let d = &self.data;
        d.qpos
            .iter()
            .chain(&d.qvel)
            .chain(&d.act)
            .chain(extra)
            .copied()
            .collect()
    }

    /// Sets the state laid out as [`Physics::state`] (with `extra.len()` entries of the
    /// environment's own, copied into `extra`) and starts the episode; the length and
    /// finiteness errors of [`check_state_len`]. The environment then refreshes what it derives
    /// from the state.
    pub fn set_state(&mut self, state: &[f64], extra: &mut [f64]) -> Result<(), EnvError> {
        let n = self.dynamic_len();
        check_state_len(self.id, state, n + extra.len())?;
        self.write_dynamic_state(&state[..n]);
        extra.copy_from_slice(&state[n..]);
        self.started = true;
        Ok(())
    }
}

/// The family's observation space: a float64 box of `n` unbounded entries.
pub fn observation_space(n: usize) -> Space {
    Space::Box {
        low: vec![f32::NEG_INFINITY; n],
        high: vec![f32::INFINITY; n],
        shape: vec![n],
        dtype: DType::Float64,
    }
}

/// The observation as `f32`: `fill` writes the `n` entries in `f64`, each then rounded.
pub fn observe_into(
    id: &'static str,
    n: usize,
    obs: &mut [f32],
    fill: impl FnOnce(&mut [f64]),
) -> Result<(), EnvError> {
    check_obs_len(id, obs, n)?;
    const STACK: usize = 128;
    let mut stack = [0.0; STACK];
    let mut heap = Vec::new();
    let o = if n <= STACK {
        &mut stack[..n]
    } else {
        heap.resize(n, 0.0);
        &mut heap[..]
    };
    fill(o);
    for (y, x) in obs.iter_mut().zip(o.iter()) {
        *y = *x as f32;
    }
    Ok(())
}

/// The observation in `f64`: `fill` writes its `n` entries.
pub fn observe_f64_into(
    id: &'static str,
    n: usize,
    obs: &mut [f64],
    fill: impl FnOnce(&mut [f64]),
) -> Result<(), EnvError> {
    check_obs_len(id, obs, n)?;
    fill(obs);
    Ok(())
}
