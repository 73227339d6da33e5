//! [`AnyEnv`]: any runtime of the [registry](super::registry) behind one type.
//!
//! Every environment implements [`Env`]; declaring `impl Runtime for MyEnv {}` in its module
//! (plus [`Runtime::goal_states`] where the task has goals) is all it takes to be held by an
//! `AnyEnv`. Dispatch is dynamic: one indirect call per step, which is noise beside a physics
//! world and a few nanoseconds beside CartPole (whose batched stepping goes through its own
//! vector kernel anyway).

use std::any::Any;
use std::fmt;

use super::api::{Action, Env, EnvError, Info, Space, StepOutcome};
use super::context::MakeError;

/// An environment the registry can hold: an [`Env`] that can be cloned, sent to worker
/// threads and inspected as its concrete type.
pub trait Runtime: Env + RuntimeBase + Send + Sync + fmt::Debug + 'static {
    /// States near the task's goals, derived from `states` (e.g. a reach task's states with the
    /// target just touching the end effector): where a goal feature decides reward or
    /// termination, so the sensitivity audit probes them. Tasks without goals return none.
    fn goal_states(&self, _states: &[Vec<f64>]) -> Result<Vec<Vec<f64>>, EnvError> {
        Ok(Vec::new())
    }

    /// Change context features in the middle of an episode (context schedules): the parameters
    /// take the new values from the next step on, the state stays. `None`: this runtime fixes
    /// its context when it is built (the default); the contextual wrapper then refuses schedules
    /// for it, naming the environments that take them.
    fn set_features(&mut self, _values: &[(String, f64)]) -> Option<Result<(), MakeError>> {
        None
    }
}

/// What [`Runtime`] needs from every environment type, implemented once for all `Clone` types.
pub trait RuntimeBase {
    fn clone_runtime(&self) -> Box<dyn Runtime>;
    fn as_any(&self) -> &dyn Any;
    fn as_any_mut(&mut self) -> &mut dyn Any;
}

impl<T: Runtime + Clone> RuntimeBase for T {
    fn clone_runtime(&self) -> Box<dyn Runtime> {
        Box::new(self.clone())
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}

/// Any runtime environment (what [`make`](super::registry::make) builds).
pub struct AnyEnv(Box<dyn Runtime>);

impl AnyEnv {
    pub fn new<T: Runtime>(env: T) -> Self {
        AnyEnv(Box::new(env))
    }

    /// The concrete environment inside, e.g. `env.downcast_ref::<LunarLander>()`.
    pub fn downcast_ref<T: Runtime>(&self) -> Option<&T> {
        self.0.as_any().downcast_ref()
    }

    /// Mutable access to the concrete environment (to set options such as a crash penalty).
    pub fn downcast_mut<T: Runtime>(&mut self) -> Option<&mut T> {
        self.0.as_any_mut().downcast_mut()
    }

    /// See [`Runtime::goal_states`].
    pub fn goal_states(&self, states: &[Vec<f64>]) -> Result<Vec<Vec<f64>>, EnvError> {
        self.0.goal_states(states)
    }

    /// See [`Runtime::set_features`].
    pub fn set_features(&mut self, values: &[(String, f64)]) -> Option<Result<(), MakeError>> {
        self.0.set_features(values)
    }
}

impl Clone for AnyEnv {
    fn clone(&self) -> Self {
        AnyEnv(self.0.clone_runtime())
    }
}

impl fmt::Debug for AnyEnv {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.fmt(f)
    }
}

impl Env for AnyEnv {
    fn id(&self) -> &'static str {
        self.0.id()
    }
    fn obs_dim(&self) -> usize {
        self.0.obs_dim()
    }
    fn state_dim(&self) -> usize {
        self.0.state_dim()
    }
    fn observation_space(&self) -> Space {
        self.0.observation_space()
    }
    fn action_space(&self) -> Space {
        self.0.action_space()
    }
    #[inline]
    fn reset_into(&mut self, seed: Option<u64>, obs: &mut [f32]) -> Result<(), EnvError> {
        self.0.reset_into(seed, obs)
    }
    #[inline]
    fn step_into(&mut self, action: &Action, obs: &mut [f32]) -> Result<StepOutcome, EnvError> {
        self.0.step_into(action, obs)
    }
    fn observe_into(&self, obs: &mut [f32]) -> Result<(), EnvError> {
        self.0.observe_into(obs)
    }
    fn observe_f64_into(&self, obs: &mut [f64]) -> Result<(), EnvError> {
        self.0.observe_f64_into(obs)
    }
    fn state(&self) -> Vec<f64> {
        self.0.state()
    }
    fn set_state(&mut self, state: &[f64]) -> Result<(), EnvError> {
        self.0.set_state(state)
    }
    fn info(&self) -> Info {
        self.0.info()
    }
    fn outcome(&self) -> Option<&'static str> {
        self.0.outcome()
    }
    fn render(&self) -> Option<carl_pixels::Frame> {
        self.0.render()
    }
}
