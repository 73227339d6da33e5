//! Episodes: one loop that runs a policy in an environment, and what listens to it.
//!
//! * [`run_episode`] ([`run_episode_with`] for a reset of the caller's): reset (optionally to a
//!   given internal state), then act and step until the
//!   episode ends, the policy has no more actions, a step limit is reached or the listener says
//!   stop. Every observation and reward is checked: a non-finite value is an error naming the
//!   step and the component, never a silent `NaN` downstream.
//! * [`jsonl`]: the JSON Lines protocol of `carl-spec rollout` (one line per reset and step,
//!   actions read from a pipe).
//! * [`policies`]: a [`Policy`] by kind for a registry entry (random, no-op, heuristic).
//!
//! The CLI's `rollout` and `render` are thin shells over this module.

pub mod jsonl;
pub mod policies;

use crate::envs::api::{Action, Env, EnvError, StepOutcome};
use crate::envs::policy::{Policy, PolicyError};

/// How an episode starts and how long it may run.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct EpisodeConfig {
    /// Seed of the reset (`reset(seed)`).
    pub seed: u64,
    /// Internal state to set right after the reset (`Env::set_state`).
    pub initial_state: Option<Vec<f64>>,
    /// Stop after at most this many steps (the episode may end earlier).
    pub max_steps: Option<u64>,
}

/// Whether the loop goes on after a listener has seen a reset or a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Flow {
    Continue,
    /// The listener needs nothing more (e.g. the reader of a pipe went away).
    Stop,
}

/// What the loop reports to (JSON Lines out, frames collected, statistics).
pub trait EpisodeListener<E: Env + ?Sized> {
    fn on_reset(&mut self, _env: &E, _obs: &[f32]) -> Result<Flow, EpisodeError> {
        Ok(Flow::Continue)
    }
    fn on_step(&mut self, env: &E, step: &StepRecord<'_>) -> Result<Flow, EpisodeError>;
}

/// One step as listeners see it.
#[derive(Debug, Clone, Copy)]
pub struct StepRecord<'a> {
    /// 1-based step number.
    pub t: u64,
    pub action: &'a Action,
    pub obs: &'a [f32],
    pub outcome: StepOutcome,
}

/// Why an episode stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EpisodeEnd {
    Terminated,
    Truncated,
    /// [`EpisodeConfig::max_steps`] reached.
    StepLimit,
    /// The policy had no more actions.
    PolicyDone,
    /// A listener asked to stop.
    ListenerStopped,
}

impl EpisodeEnd {
    pub fn as_str(self) -> &'static str {
        match self {
            EpisodeEnd::Terminated => "terminated",
            EpisodeEnd::Truncated => "truncated",
            EpisodeEnd::StepLimit => "step limit",
            EpisodeEnd::PolicyDone => "actions exhausted",
            EpisodeEnd::ListenerStopped => "stopped",
        }
    }
}

/// What an episode came to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EpisodeSummary {
    pub steps: u64,
    pub total_reward: f64,
    pub end: EpisodeEnd,
}

/// Why an episode could not go on.
#[derive(Debug, thiserror::Error)]
pub enum EpisodeError {
    /// The reset or `set_state` failed (bad initial state, context that cannot be built).
    #[error("reset: {0}")]
    Reset(EnvError),
    #[error("initial state: {0}")]
    InitialState(EnvError),
    /// The environment refused the action (out of range, wrong shape).
    #[error("step {t}: {source}")]
    Step { t: u64, source: EnvError },
    #[error("step {t}: {source}")]
    Policy { t: u64, source: PolicyError },
    /// A reward or observation component is NaN or infinite: the context drove the dynamics
    /// outside the range where they mean anything.
    #[error(
        "{where_}: the environment produced a non-finite {what} ({value}); the context drives the dynamics outside their meaningful range"
    )]
    NonFinite { where_: String, what: String, value: f64 },
    /// A listener failed (e.g. writing the output).
    #[error("{0}")]
    Listener(String),
}

impl EpisodeError {
    /// Whether the input was at fault (bad action, bad initial state) rather than the run.
    pub fn is_bad_input(&self) -> bool {
        match self {
            EpisodeError::InitialState(_) | EpisodeError::Policy { .. } => true,
            EpisodeError::Step { source, .. } => !matches!(source, EnvError::Context { .. }),
            _ => false,
        }
    }
}

/// The first non-finite component of `obs` or the reward
/// ([`non_finite_output`](crate::envs::api::non_finite_output)), as an error at `where_`.
pub fn check_finite(where_: impl FnOnce() -> String, obs: &[f32], reward: f64) -> Result<(), EpisodeError> {
    match crate::envs::api::non_finite_output(obs, reward) {
        Some((what, value)) => Err(EpisodeError::NonFinite {
            where_: where_(),
            what,
            value,
        }),
        None => Ok(()),
    }
}

/// Run one episode of `policy` in `env` (see the [module docs](self)).
pub fn run_episode<E: Env + ?Sized>(
    env: &mut E,
    policy: &mut dyn Policy,
    config: &EpisodeConfig,
    listener: &mut dyn EpisodeListener<E>,
) -> Result<EpisodeSummary, EpisodeError> {
    let seed = config.seed;
    run_episode_with(env, policy, config, listener, &mut |env: &mut E, obs: &mut [f32]| {
        env.reset_into(Some(seed), obs)
    })
}

/// [`run_episode`] with the reset done by `reset` (e.g. a contextual environment reset to a
/// chosen instance, [`crate::envs::contextual::ContextualEnv::reset_instance_into`]) instead of
/// `reset_into(Some(config.seed))`.
pub fn run_episode_with<E: Env + ?Sized>(
    env: &mut E,
    policy: &mut dyn Policy,
    config: &EpisodeConfig,
    listener: &mut dyn EpisodeListener<E>,
    reset: &mut dyn FnMut(&mut E, &mut [f32]) -> Result<(), EnvError>,
) -> Result<EpisodeSummary, EpisodeError> {
    let mut obs = vec![0.0f32; env.obs_dim()];
    reset(env, &mut obs).map_err(EpisodeError::Reset)?;
    if let Some(state) = &config.initial_state {
        env.set_state(state).map_err(EpisodeError::InitialState)?;
        env.observe_into(&mut obs).map_err(EpisodeError::InitialState)?;
    }
    check_finite(|| "reset".into(), &obs, 0.0)?;
    policy.reset();
    let mut summary = EpisodeSummary {
        steps: 0,
        total_reward: 0.0,
        end: EpisodeEnd::ListenerStopped,
    };
    if listener.on_reset(env, &obs)? == Flow::Stop {
        return Ok(summary);
    }
    loop {
        if config.max_steps.is_some_and(|n| summary.steps >= n) {
            summary.end = EpisodeEnd::StepLimit;
            return Ok(summary);
        }
        let t = summary.steps + 1;
        let Some(action) = policy.act(&obs).map_err(|source| EpisodeError::Policy { t, source })? else {
            summary.end = EpisodeEnd::PolicyDone;
            return Ok(summary);
        };
        let outcome = env
            .step_into(&action, &mut obs)
            .map_err(|source| EpisodeError::Step { t, source })?;
        check_finite(|| format!("step {t}"), &obs, outcome.reward)?;
        summary.steps = t;
        summary.total_reward += outcome.reward;
        let record = StepRecord {
            t,
            action: &action,
            obs: &obs,
            outcome,
        };
        if listener.on_step(env, &record)? == Flow::Stop {
            return Ok(summary);
        }
        if outcome.terminated || outcome.truncated {
            summary.end = if outcome.terminated {
                EpisodeEnd::Terminated
            } else {
                EpisodeEnd::Truncated
            };
            return Ok(summary);
        }
    }
}
