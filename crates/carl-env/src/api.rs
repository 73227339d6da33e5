//! Gymnasium-style environment API, render-free.
//!
//! * [`Env::reset`] / [`Env::step`] mirror Gymnasium's `reset(seed=...)` and the 5-tuple `step`.
//! * [`Env::reset_into`] / [`Env::step_into`] are the allocation-free variants (the caller
//!   owns the observation buffer); the convenient variants are built on them.
//! * Bad input (an out-of-range discrete action, a wrong-length action or state vector,
//!   stepping before reset) is reported as an [`EnvError`], never a panic.
//! * Episode limits live in [`TimeLimit`], like Gymnasium's wrapper of the same name.
//! * How an episode ended is the environment's own word, [`Env::outcome`] (each family names its
//!   endings; [`TIMED_OUT`] is the time limit's).

use std::collections::BTreeMap;

/// The outcome of an episode cut short by its time limit ([`TimeLimit`], the batch's step
/// count): the one outcome every environment shares. The others are each family's own
/// ([`Env::outcome`]).
pub const TIMED_OUT: &str = "timed_out";

/// Extra per-step information (Gymnasium's `info` dict). The classic-control environments
/// return it empty; an empty `BTreeMap` does not allocate.
pub type Info = BTreeMap<String, f64>;

/// An action. Discrete environments take `Discrete`, Box environments take `Continuous`
/// (float32 components, as Gymnasium's Box(float32) action spaces produce).
#[derive(Debug, Clone, PartialEq)]
pub enum Action {
    Discrete(i64),
    Continuous(Vec<f32>),
}

/// Element type of a Box space.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DType {
    Float32,
    Float64,
    /// Integers 0..=255 (image observations); delivered as `f32` values in observation buffers.
    UInt8,
}

/// Observation / action space (`gymnasium.spaces.Box` / `Discrete`).
#[derive(Debug, Clone, PartialEq)]
pub enum Space {
    Box {
        low: Vec<f32>,
        high: Vec<f32>,
        shape: Vec<usize>,
        dtype: DType,
    },
    /// Values `start, start+1, ..., start+n-1`.
    Discrete { n: i64, start: i64 },
}

impl Space {
    /// Number of scalar components (Box: product of the shape; Discrete: 1).
    pub fn flat_dim(&self) -> usize {
        match self {
            Space::Box { shape, .. } => shape.iter().product(),
            Space::Discrete { .. } => 1,
        }
    }

    /// Whether `action` lies in this space (Box: right length and within `[low, high]`).
    pub fn contains(&self, action: &Action) -> bool {
        match (self, action) {
            (Space::Discrete { n, start }, Action::Discrete(a)) => *a >= *start && *a - *start < *n,
            (Space::Box { low, high, .. }, Action::Continuous(v)) => {
                v.len() == low.len()
                    && v.iter()
                        .zip(low.iter().zip(high))
                        .all(|(x, (l, h))| *x >= *l && *x <= *h)
            }
            _ => false,
        }
    }
}

/// Reward and episode flags of one step (the observation goes to the caller's buffer).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepOutcome {
    pub reward: f64,
    pub terminated: bool,
    pub truncated: bool,
}

/// Full result of [`Env::step`].
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    pub obs: Vec<f32>,
    pub reward: f64,
    pub terminated: bool,
    pub truncated: bool,
    pub info: Info,
}

/// Errors from bad input. No environment panics on bad input.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EnvError {
    #[error("{env}: discrete action {action} is outside 0..{n}")]
    ActionOutOfRange { env: &'static str, action: i64, n: i64 },
    #[error("{env}: expected a {expected} action, got {got}")]
    ActionKind {
        env: &'static str,
        expected: &'static str,
        got: &'static str,
    },
    /// A continuous action component is NaN or infinite (an `f32`: `1e300` is infinite too).
    #[error("{env}: action component {index} is not finite ({value}); actions must be finite numbers")]
    ActionNotFinite {
        env: &'static str,
        index: usize,
        value: f32,
    },
    #[error("{env}: continuous action must have {expected} component(s), got {got}")]
    ActionLength {
        env: &'static str,
        expected: usize,
        got: usize,
    },
    #[error("{env}: state must have {expected} component(s), got {got}")]
    StateLength {
        env: &'static str,
        expected: usize,
        got: usize,
    },
    #[error("{env}: state component {index} is not finite ({value})")]
    StateNotFinite {
        env: &'static str,
        index: usize,
        value: f64,
    },
    #[error("{env}: observation buffer must have {expected} element(s), got {got}")]
    ObsBufferLength {
        env: &'static str,
        expected: usize,
        got: usize,
    },
    #[error("{env}: expected {expected} action value(s) for the batch, got {got}")]
    BatchLength {
        env: &'static str,
        expected: usize,
        got: usize,
    },
    #[error("{env}: step() called before reset() or set_state()")]
    NeedsReset { env: &'static str },
    /// A batch with autoreset disabled was stepped while environment `index` had finished its
    /// episode (reset it first, e.g. with a reset mask).
    #[error("{env}: environment {index} of the batch has finished its episode; reset it (reset mask) before stepping")]
    EpisodeOver { env: &'static str, index: usize },
    /// A context could not be produced or applied at reset (e.g. a per-reset distribution draw
    /// failed); raised by carl-spec's `ContextualEnv`.
    #[error("{env}: {message}")]
    Context { env: &'static str, message: String },
    /// The environment produced a NaN or infinite observation component or reward
    /// ([`check_finite_output`]): the context drove the dynamics outside the range where they
    /// mean anything.
    #[error(
        "{env}: the environment produced a non-finite {what} ({value}); the context drives the dynamics outside their meaningful range"
    )]
    NonFiniteOutput {
        env: &'static str,
        what: String,
        value: f64,
    },
    /// Long native work was cancelled by the check installed with [`crate::cancel::with_check`]
    /// (e.g. Ctrl-C in Python). The environment needs a reset before it steps again.
    #[error("{env}: interrupted")]
    Interrupted { env: &'static str },
}

/// The first NaN or infinite component of `obs`, or else a non-finite `reward`: what it is
/// (`observation component i` or `reward`) and its value. The one check every front end (the
/// CLI's episodes, the Python binding) applies after `reset` (with reward 0) and `step`.
pub fn non_finite_output(obs: &[f32], reward: f64) -> Option<(String, f64)> {
    if let Some((i, x)) = obs.iter().enumerate().find(|(_, x)| !x.is_finite()) {
        return Some((format!("observation component {i}"), f64::from(*x)));
    }
    (!reward.is_finite()).then(|| ("reward".to_string(), reward))
}

/// [`non_finite_output`] as [`EnvError::NonFiniteOutput`].
pub fn check_finite_output(env: &'static str, obs: &[f32], reward: f64) -> Result<(), EnvError> {
    match non_finite_output(obs, reward) {
        Some((what, value)) => Err(EnvError::NonFiniteOutput { env, what, value }),
        None => Ok(()),
    }
}

/// The first NaN or infinite component of a continuous action, as [`EnvError::ActionNotFinite`].
#[inline]
pub fn check_finite_action(env: &'static str, v: &[f32]) -> Result<(), EnvError> {
    match v.iter().position(|x| !x.is_finite()) {
        Some(index) => Err(EnvError::ActionNotFinite {
            env,
            index,
            value: v[index],
        }),
        None => Ok(()),
    }
}

/// A context feature name that an environment's `Params` does not know.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown context feature `{name}` for {env} (known: {known})")]
pub struct UnknownFeature {
    pub env: &'static str,
    pub name: String,
    pub known: String,
}

/// A reinforcement-learning environment with Gymnasium semantics.
pub trait Env {
    /// Short identifier, e.g. `"cartpole"`.
    fn id(&self) -> &'static str;
    /// Length of the observation vector.
    fn obs_dim(&self) -> usize;
    /// Length of the internal state vector used by [`Env::state`] / [`Env::set_state`].
    fn state_dim(&self) -> usize;
    fn observation_space(&self) -> Space;
    fn action_space(&self) -> Space;

    /// Reset, writing the first observation into `obs`. `Some(seed)` reseeds the
    /// environment's random stream (reproducible); `None` continues the current stream.
    fn reset_into(&mut self, seed: Option<u64>, obs: &mut [f32]) -> Result<(), EnvError>;

    /// Advance one step, writing the observation into `obs`. Allocation-free.
    fn step_into(&mut self, action: &Action, obs: &mut [f32]) -> Result<StepOutcome, EnvError>;

    /// Write the observation of the current state into `obs`.
    fn observe_into(&self, obs: &mut [f32]) -> Result<(), EnvError>;

    /// The observation of the current state at float64 precision, for runtimes whose space
    /// declares `float64` (the buffers of `reset_into` / `step_into` are float32). The default
    /// widens [`Env::observe_into`] (exact for float32 spaces); float64 runtimes override it.
    fn observe_f64_into(&self, obs: &mut [f64]) -> Result<(), EnvError> {
        let mut narrow = vec![0.0f32; obs.len()];
        self.observe_into(&mut narrow)?;
        for (w, n) in obs.iter_mut().zip(&narrow) {
            *w = f64::from(*n);
        }
        Ok(())
    }

    /// The internal (float64) state, e.g. CartPole `[x, x_dot, theta, theta_dot]`.
    fn state(&self) -> Vec<f64>;

    /// Overwrite the internal state (as after a reset: episode bookkeeping such as CartPole's
    /// "already terminated" flag is cleared). Used for parity tests and `--initial-state`.
    /// Rejects wrong lengths and non-finite values.
    fn set_state(&mut self, state: &[f64]) -> Result<(), EnvError>;

    /// Gymnasium's `reset(seed=...)`: `(observation, info)`.
    fn reset(&mut self, seed: Option<u64>) -> (Vec<f32>, Info) {
        let mut obs = vec![0.0; self.obs_dim()];
        // The buffer has the right length, so this cannot fail.
        let _ = self.reset_into(seed, &mut obs);
        (obs, self.info())
    }

    /// Gymnasium's `step(action)`.
    fn step(&mut self, action: &Action) -> Result<Step, EnvError> {
        let mut obs = vec![0.0; self.obs_dim()];
        let out = self.step_into(action, &mut obs)?;
        Ok(Step {
            obs,
            reward: out.reward,
            terminated: out.terminated,
            truncated: out.truncated,
            info: self.info(),
        })
    }

    /// The `info` that `reset` and `step` return (empty unless a wrapper has something to say).
    fn info(&self) -> Info {
        Info::new()
    }

    /// How the episode ended, once `step` has returned `terminated` (or, through [`TimeLimit`],
    /// `truncated`): a short snake_case word the environment's family defines, e.g.
    /// LunarLander's `landed` / `crashed` / `out_of_view`, `solved` where reaching a goal ends
    /// the episode, `failed` where failing does; [`TIMED_OUT`] for the time limit. `None` while
    /// the episode runs, and for environments that define no outcome (their episodes end only
    /// by the time limit, or the way they end has no name).
    fn outcome(&self) -> Option<&'static str> {
        None
    }

    /// A picture of the current state for humans (Gymnasium's `render_mode="rgb_array"`), or
    /// `None` for environments without a renderer. Never changes the simulation.
    fn render(&self) -> Option<carl_pixels::Frame> {
        None
    }

    /// Observation of the current state.
    fn observe(&self) -> Vec<f32> {
        let mut obs = vec![0.0; self.obs_dim()];
        let _ = self.observe_into(&mut obs);
        obs
    }
}

impl<E: Env + ?Sized> Env for Box<E> {
    fn id(&self) -> &'static str {
        (**self).id()
    }
    fn obs_dim(&self) -> usize {
        (**self).obs_dim()
    }
    fn state_dim(&self) -> usize {
        (**self).state_dim()
    }
    fn observation_space(&self) -> Space {
        (**self).observation_space()
    }
    fn action_space(&self) -> Space {
        (**self).action_space()
    }
    fn reset_into(&mut self, seed: Option<u64>, obs: &mut [f32]) -> Result<(), EnvError> {
        (**self).reset_into(seed, obs)
    }
    fn step_into(&mut self, action: &Action, obs: &mut [f32]) -> Result<StepOutcome, EnvError> {
        (**self).step_into(action, obs)
    }
    fn observe_into(&self, obs: &mut [f32]) -> Result<(), EnvError> {
        (**self).observe_into(obs)
    }
    fn observe_f64_into(&self, obs: &mut [f64]) -> Result<(), EnvError> {
        (**self).observe_f64_into(obs)
    }
    fn state(&self) -> Vec<f64> {
        (**self).state()
    }
    fn set_state(&mut self, state: &[f64]) -> Result<(), EnvError> {
        (**self).set_state(state)
    }
    fn info(&self) -> Info {
        (**self).info()
    }
    fn outcome(&self) -> Option<&'static str> {
        (**self).outcome()
    }
    fn render(&self) -> Option<carl_pixels::Frame> {
        (**self).render()
    }
}

/// Gymnasium's `TimeLimit`: `truncated = true` once `max_episode_steps` steps have been taken
/// since the last reset. `None` means no limit. `set_state` does not restart the count
/// (it is forwarded unchanged); `reset` does.
#[derive(Debug, Clone)]
pub struct TimeLimit<E> {
    env: E,
    max_episode_steps: Option<u64>,
    elapsed: u64,
}

impl<E: Env> TimeLimit<E> {
    pub fn new(env: E, max_episode_steps: Option<u64>) -> Self {
        TimeLimit {
            env,
            max_episode_steps,
            elapsed: 0,
        }
    }
    pub fn inner(&self) -> &E {
        &self.env
    }
    pub fn inner_mut(&mut self) -> &mut E {
        &mut self.env
    }
    pub fn into_inner(self) -> E {
        self.env
    }
    pub fn elapsed_steps(&self) -> u64 {
        self.elapsed
    }
    pub fn max_episode_steps(&self) -> Option<u64> {
        self.max_episode_steps
    }
}

impl<E: Env> Env for TimeLimit<E> {
    fn id(&self) -> &'static str {
        self.env.id()
    }
    fn obs_dim(&self) -> usize {
        self.env.obs_dim()
    }
    fn state_dim(&self) -> usize {
        self.env.state_dim()
    }
    fn observation_space(&self) -> Space {
        self.env.observation_space()
    }
    fn action_space(&self) -> Space {
        self.env.action_space()
    }
    fn reset_into(&mut self, seed: Option<u64>, obs: &mut [f32]) -> Result<(), EnvError> {
        self.env.reset_into(seed, obs)?;
        self.elapsed = 0;
        Ok(())
    }
    #[inline]
    fn step_into(&mut self, action: &Action, obs: &mut [f32]) -> Result<StepOutcome, EnvError> {
        let mut out = self.env.step_into(action, obs)?;
        self.elapsed += 1;
        if let Some(max) = self.max_episode_steps
            && self.elapsed >= max
        {
            out.truncated = true;
        }
        Ok(out)
    }
    fn observe_into(&self, obs: &mut [f32]) -> Result<(), EnvError> {
        self.env.observe_into(obs)
    }
    fn observe_f64_into(&self, obs: &mut [f64]) -> Result<(), EnvError> {
        self.env.observe_f64_into(obs)
    }
    fn state(&self) -> Vec<f64> {
        self.env.state()
    }
    fn set_state(&mut self, state: &[f64]) -> Result<(), EnvError> {
        self.env.set_state(state)
    }
    fn info(&self) -> Info {
        self.env.info()
    }
    /// The environment's own outcome when it has one, else [`TIMED_OUT`] once the limit is
    /// reached (an episode that terminates at its last allowed step ended by itself).
    fn outcome(&self) -> Option<&'static str> {
        self.env.outcome().or_else(|| {
            self.max_episode_steps
                .filter(|&max| self.elapsed >= max)
                .map(|_| TIMED_OUT)
        })
    }
    fn render(&self) -> Option<carl_pixels::Frame> {
        self.env.render()
    }
}

// ---------------------------------------------------------------------------------------
// Helpers shared by the environments.

pub fn check_obs_len<T>(env: &'static str, obs: &[T], expected: usize) -> Result<(), EnvError> {
    if obs.len() == expected {
        Ok(())
    } else {
        Err(EnvError::ObsBufferLength {
            env,
            expected,
            got: obs.len(),
        })
    }
}

pub fn check_state<const N: usize>(env: &'static str, state: &[f64]) -> Result<[f64; N], EnvError> {
    check_state_len(env, state, N)?;
    let mut arr = [0.0; N];
    arr.copy_from_slice(state);
    Ok(arr)
}

/// [`check_state`] for environments whose state length is known only at run time (the robots).
pub fn check_state_len(env: &'static str, state: &[f64], expected: usize) -> Result<(), EnvError> {
    if state.len() != expected {
        return Err(EnvError::StateLength {
            env,
            expected,
            got: state.len(),
        });
    }
    if let Some((index, value)) = state.iter().copied().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(EnvError::StateNotFinite { env, index, value });
    }
    Ok(())
}

/// Validate a discrete action in `0..n`.
#[inline]
pub fn discrete_action(env: &'static str, action: &Action, n: i64) -> Result<i64, EnvError> {
    match action {
        Action::Discrete(a) if (0..n).contains(a) => Ok(*a),
        Action::Discrete(a) => Err(EnvError::ActionOutOfRange { env, action: *a, n }),
        Action::Continuous(_) => Err(EnvError::ActionKind {
            env,
            expected: "discrete",
            got: "continuous",
        }),
    }
}

/// The components of an `n`-dimensional continuous action, all finite
/// ([`EnvError::ActionNotFinite`] names the first that is not).
#[inline]
pub fn vector_action<'a>(env: &'static str, action: &'a Action, n: usize) -> Result<&'a [f32], EnvError> {
    match action {
        Action::Continuous(v) if v.len() == n => check_finite_action(env, v).map(|()| v.as_slice()),
        Action::Continuous(v) => Err(EnvError::ActionLength {
            env,
            expected: n,
            got: v.len(),
        }),
        Action::Discrete(_) => Err(EnvError::ActionKind {
            env,
            expected: "continuous",
            got: "discrete",
        }),
    }
}

/// The single component of a 1-D continuous action, finite.
#[inline]
pub fn scalar_action(env: &'static str, action: &Action) -> Result<f32, EnvError> {
    match action {
        Action::Continuous(v) if v.len() == 1 => check_finite_action(env, v).map(|()| v[0]),
        Action::Continuous(v) => Err(EnvError::ActionLength {
            env,
            expected: 1,
            got: v.len(),
        }),
        Action::Discrete(_) => Err(EnvError::ActionKind {
            env,
            expected: "continuous",
            got: "discrete",
        }),
    }
}

/// Declares a context `Params` struct's feature table: canonical names, aliases, and
/// `set` / `get` by name.
#[macro_export]
macro_rules! context_features {
    ($ty:ident, $env:literal, { $( $field:ident : $canon:literal $( | $alias:literal )* ),* $(,)? }) => {
        impl $ty {
            /// Canonical context-feature names (CARL paper tables).
            pub const FEATURES: &'static [&'static str] = &[$($canon),*];
            /// `(alias, canonical)` pairs also accepted by `set`/`get` (carl-bench 1.1.1 names).
            pub const ALIASES: &'static [(&'static str, &'static str)] = &[$($(($alias, $canon),)*)*];

            fn unknown(name: &str) -> $crate::api::UnknownFeature {
                $crate::api::UnknownFeature {
                    env: $env,
                    name: name.to_string(),
                    known: Self::FEATURES.join(", "),
                }
            }

            /// Set a context feature by canonical name or alias.
            pub fn set(&mut self, name: &str, value: f64) -> Result<(), $crate::api::UnknownFeature> {
                match name {
                    $( $canon $( | $alias )* => { self.$field = value; Ok(()) } )*
                    _ => Err(Self::unknown(name)),
                }
            }

            /// Read a context feature by canonical name or alias.
            pub fn get(&self, name: &str) -> Result<f64, $crate::api::UnknownFeature> {
                match name {
                    $( $canon $( | $alias )* => Ok(self.$field), )*
                    _ => Err(Self::unknown(name)),
                }
            }

            /// All canonical features with their current values.
            pub fn to_pairs(&self) -> Vec<(&'static str, f64)> {
                vec![$(($canon, self.$field)),*]
            }
        }
    };
}
pub use crate::context_features;

/// The float64 `x ** 2` of CPython (`float.__pow__`) and of NumPy float64 *scalars*
/// (`np.float64.__pow__`): both call the C library's `pow(x, 2.0)`, which on glibc is not
/// always the correctly rounded `x * x`. `black_box` keeps LLVM from folding it to `x * x`.
#[inline]
pub fn py_sq(x: f64) -> f64 {
    x.powf(std::hint::black_box(2.0))
}

/// NumPy float32 scalar `x ** 2` (`powf(x, 2.0f)`).
#[inline]
pub fn np_sq_f32(x: f32) -> f32 {
    x.powf(std::hint::black_box(2.0f32))
}

/// `np.clip(x, lo, hi)` for a scalar: `min(max(x, lo), hi)` with NumPy's NaN propagation.
#[inline]
pub fn np_clip(x: f64, lo: f64, hi: f64) -> f64 {
    let m = if x.is_nan() || x > lo { x } else { lo };
    if m.is_nan() || m < hi { m } else { hi }
}

/// `np.clip` for float32.
#[inline]
pub fn np_clip_f32(x: f32, lo: f32, hi: f32) -> f32 {
    let m = if x.is_nan() || x > lo { x } else { lo };
    if m.is_nan() || m < hi { m } else { hi }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn py_sq_is_libm_pow_not_a_product() {
        // On glibc 2.36, CPython's `(-1.4119752588045307) ** 2` is 1.9936741314761215 (libm
        // pow), while the correctly rounded product is 1.9936741314761213. If this fails the
        // platform libm differs and Acrobot/Pendulum parity may not be bit-exact.
        let x = -1.4119752588045307f64;
        assert_eq!(x * x, 1.9936741314761213);
        assert_eq!(py_sq(x), 1.9936741314761215);
    }

    #[test]
    fn numpy_clip_semantics() {
        assert_eq!(np_clip(5.0, -1.0, 1.0), 1.0);
        assert_eq!(np_clip(-5.0, -1.0, 1.0), -1.0);
        assert!(np_clip(f64::NAN, -1.0, 1.0).is_nan());
        assert_eq!(np_clip_f32(0.5, -1.0, 1.0), 0.5);
    }
}
