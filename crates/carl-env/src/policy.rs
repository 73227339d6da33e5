//! Who acts: the [`Policy`] trait and the policies every environment has (uniform random,
//! no-op). Environments with a hand-written controller declare it in the
//! [registry](super::registry) (`heuristic`); the episode layer adds the external stream
//! (actions read from a program through a pipe).
//!
//! A policy sees the observation only, as an agent does; it owns its random stream, so two
//! policies never share state.

use super::api::{Action, Space};
use carl_spec_core::sampling::{Pcg64, dist, stream_id};

/// A policy's failure (e.g. an external program sent a malformed action).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct PolicyError(pub String);

/// Chooses actions from observations.
pub trait Policy: Send {
    /// A new episode begins (controllers with memory forget the last one).
    fn reset(&mut self) {}
    /// The action for observation `obs`, or `None` when the policy has no more actions
    /// (an external stream ended): the episode stops there.
    fn act(&mut self, obs: &[f32]) -> Result<Option<Action>, PolicyError>;
}

/// The policies a command can name (`--policy`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PolicyKind {
    /// Uniform over the action space, from a stream seeded with the episode's seed.
    Random,
    /// Action 0 (discrete) or all zeros (continuous).
    Noop,
    /// The environment's hand-written controller (registry entries that declare one).
    Heuristic,
}

/// Uniform random actions from `Pcg64::new(seed, stream_id("rollout-policy"))`: a discrete action
/// is `start + below(n)`, a Box component `uniform(low, high)` in order.
#[derive(Debug, Clone)]
pub struct RandomPolicy {
    rng: Pcg64,
    space: Space,
}

impl RandomPolicy {
    pub fn new(space: Space, seed: u64) -> Self {
        RandomPolicy {
            rng: Pcg64::new(seed, stream_id("rollout-policy")),
            space,
        }
    }

    /// The next action (never fails).
    pub fn sample(&mut self) -> Action {
        match &self.space {
            Space::Discrete { n, start } => {
                Action::Discrete(start + dist::below(&mut self.rng, (*n).max(1) as u64) as i64)
            }
            Space::Box { low, high, .. } => Action::Continuous(
                low.iter()
                    .zip(high)
                    .map(|(l, h)| dist::uniform(&mut self.rng, f64::from(*l), f64::from(*h)) as f32)
                    .collect(),
            ),
        }
    }
}

impl Policy for RandomPolicy {
    fn act(&mut self, _obs: &[f32]) -> Result<Option<Action>, PolicyError> {
        Ok(Some(self.sample()))
    }
}

/// Always the same "do nothing" action.
#[derive(Debug, Clone)]
pub struct NoopPolicy(Action);

impl NoopPolicy {
    pub fn new(space: &Space) -> Self {
        NoopPolicy(match space {
            Space::Discrete { start, .. } => Action::Discrete(*start),
            Space::Box { low, .. } => Action::Continuous(vec![0.0; low.len()]),
        })
    }
}

impl Policy for NoopPolicy {
    fn act(&mut self, _obs: &[f32]) -> Result<Option<Action>, PolicyError> {
        Ok(Some(self.0.clone()))
    }
}

/// A stateless controller `obs → action` as a policy (e.g. Gymnasium's lander heuristic).
pub struct FnPolicy(pub fn(&[f32]) -> Action);

impl Policy for FnPolicy {
    fn act(&mut self, obs: &[f32]) -> Result<Option<Action>, PolicyError> {
        Ok(Some((self.0)(obs)))
    }
}
