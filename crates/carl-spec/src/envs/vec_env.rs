//! Batched stepping: [`VecEnv`] runs N environments of one kind, each with its own context.
//!
//! # Semantics
//!
//! * **Seeding.** [`VecEnv::reset`]`(seed)` resets environment `i` exactly like a scalar
//!   environment's `reset_into(Some(seed.wrapping_add(i)))` (Gymnasium's vector-env convention
//!   `seeds = [seed + i for i in range(num_envs)]`). Later automatic resets continue each
//!   environment's own random stream (`reset_into(None)`).
//! * **Autoreset: same-step** (Gymnasium's `AutoresetMode.SAME_STEP`). When environment `i`
//!   terminates or is truncated during [`VecEnv::step`], it is reset within that same call:
//!   `obs[i]` is already the first observation of the new episode, `rewards[i]`,
//!   `terminated[i]` and `truncated[i]` describe the step that ended the old one, and the
//!   last observation of the finished episode is available from [`VecEnv::final_obs`] until
//!   the next `step` / `reset`. No step is wasted on a reset.
//! * **Autoreset: next-step and disabled** ([`AutoresetMode`], chosen at construction with
//!   [`VecEnv::from_envs_with`] / [`VecEnv::from_contextual`]), as Gymnasium 1.x defines them. With
//!   `NextStep`, the step that ends an episode returns its last observation in `obs`; the next
//!   `step` resets that environment instead of stepping it (its action is ignored) and reports the
//!   first observation with reward 0 and both flags false. With `Disabled`, finished environments
//!   are never reset by `step`: [`VecEnv::reset_masked`] resets the ones the caller chooses, and
//!   stepping a finished one is an [`EnvError::EpisodeOver`]. The CartPole kernel runs all
//!   three modes.
//! * **Contexts per environment.** [`VecEnv::from_contextual`] batches
//!   [`ContextualEnv`]s: every (auto)reset of environment `i` re-selects its context (next
//!   instance of a set, fresh draw of a distribution) from that environment's own streams, and
//!   [`VecEnv::instance_ids`] reports each environment's current instance.
//! * **Outcomes.** At the step that ends an episode, [`VecEnv::outcome`] says how it ended: the
//!   environment's [`Env::outcome`] (taken before a same-step reset), or [`TIMED_OUT`].
//! * **Resets with a seed (and an instance) per environment**: [`VecEnv::reset_each`], one call
//!   for a batch of episode starts, and [`VecEnv::reset_some`], the same for a list of
//!   environments (what `carl_spec.evaluate` does between steps: its cost is that of the
//!   environments reset, not of the batch).
//! * **Time limit.** Every environment counts its steps since its last reset and reports
//!   `truncated` once the spec's `max_episode_steps` is reached, like [`TimeLimit`](super::TimeLimit).
//! * **Bad input** (wrong number of actions, an out-of-range discrete action, a discrete action
//!   for a continuous environment or the reverse, stepping before `reset`) returns an
//!   [`EnvError`] before any environment has moved; nothing panics.
//!
//! # Layout and speed
//!
//! Outputs are flat, preallocated buffers (`obs` is `num_envs × obs_dim`, row `i` is
//! environment `i`), so `step` never allocates. An environment whose registry entry declares a
//! vector kernel (CartPole) is stepped structure-of-arrays: the four state components live in
//! separate contiguous `Vec<f64>`s next to per-environment constants, and each step calls the
//! scalar environment's own step function ([`cartpole::dynamics`]), so the two are bit-identical
//! by construction (`tests/vec_env.rs` checks it anyway). The other
//! environments use an array of scalar environments (static dispatch, no allocation).
//! With `threads > 1` the batch is cut into blocks (~8 per thread, at least 16 environments,
//! or at least 1 for environments whose step is a physics world or a picture)
//! that the calling thread and a persistent worker pool claim from a shared counter, so a
//! descheduled worker never stalls a step; `threads = 1` (or a batch of a single block) runs
//! inline without any synchronisation. Results never depend on the thread count.

use std::ops::Range;
use std::sync::Mutex;

use super::api::{Action, DType, Env, EnvError, Space, TIMED_OUT};
use super::classic_control::cartpole::{self, CartPoleConstants};
use super::classic_control::{CartPole, CartPoleParams};
use super::contextual::{ContextInfo, ContextualEnv};
pub use super::pool::CallerShare;
use super::pool::Pool;
use super::registry::{Context, MakeError, MakeOptions, SpecEnv, VectorKernel, lookup, make_with};
use super::rng::EnvRng;
use super::runtime::AnyEnv;
use crate::spec::model::EnvSpec;

/// One action per environment: `Discrete` has `num_envs` entries, `Continuous` has
/// `num_envs × action_dim` entries (row `i` is environment `i`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum VecActions<'a> {
    Discrete(&'a [i64]),
    Continuous(&'a [f32]),
}

/// Results of one batch step; all slices are indexed by environment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VecStep<'a> {
    /// `num_envs × obs_dim`; for environments that just finished, the first observation of the
    /// next episode (see [`VecEnv::final_obs`] for the last one of the finished episode).
    pub obs: &'a [f32],
    pub rewards: &'a [f64],
    pub terminated: &'a [bool],
    pub truncated: &'a [bool],
}

/// Which stepping kernel to use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Kernel {
    /// The structure-of-arrays kernel where one exists (CartPole), else the array of envs.
    #[default]
    Auto,
    /// Always the array of scalar environments (for comparisons).
    ArrayOfEnvs,
}

/// When a finished environment is reset (Gymnasium's `AutoresetMode`; see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum AutoresetMode {
    /// Reset within the step that ended the episode ([`VecEnv::final_obs`] keeps the last obs).
    #[default]
    SameStep,
    /// Reset at the following step, which ignores that environment's action.
    NextStep,
    /// Never reset by `step`; the caller resets with [`VecEnv::reset_masked`].
    Disabled,
}

/// Construction options.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct VecOptions {
    /// Threads stepping the batch, including the caller (`0` or `1`: single-threaded).
    pub threads: usize,
    pub kernel: Kernel,
}

impl Default for VecOptions {
    fn default() -> Self {
        VecOptions {
            threads: 1,
            kernel: Kernel::Auto,
        }
    }
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum VecEnvError {
    #[error(transparent)]
    Make(#[from] MakeError),
    #[error("a VecEnv needs at least one environment")]
    Empty,
    #[error("a VecEnv holds one kind of environment: got {first} and {other}")]
    Mixed { first: &'static str, other: &'static str },
}

#[derive(Debug, Clone, Copy)]
enum ActionKind {
    Discrete(i64),
    Continuous(usize),
}

/// Per-environment CartPole context: the step's constants and the reset's parameters.
#[derive(Debug, Clone, Copy)]
struct CartPoleK {
    step: CartPoleConstants,
    params: CartPoleParams,
}

impl From<&CartPoleParams> for CartPoleK {
    fn from(p: &CartPoleParams) -> Self {
        CartPoleK {
            step: CartPoleConstants::from(p),
            params: *p,
        }
    }
}

#[derive(Debug)]
struct CartPoleSoa {
    x: Vec<f64>,
    x_dot: Vec<f64>,
    theta: Vec<f64>,
    theta_dot: Vec<f64>,
    k: Vec<CartPoleK>,
    rng: Vec<EnvRng>,
}

#[derive(Debug)]
enum Envs {
    CartPole(CartPoleSoa),
    /// Scalar environments plus one reusable `Action` each (so continuous actions don't allocate).
    Array(Vec<AnyEnv>, Vec<Action>),
    /// Contextual environments (each re-selects its context at every reset), with actions as above.
    Contextual(Vec<ContextualEnv>, Vec<Action>),
}

/// What a batch needs from its environments beyond [`Env`].
trait BatchEnv: Env {
    /// The current instance's id in its set, or -1.
    fn instance_id(&self) -> i64 {
        -1
    }
}
impl BatchEnv for AnyEnv {}
impl BatchEnv for ContextualEnv {
    fn instance_id(&self) -> i64 {
        self.context_info().instance_id.map_or(-1, |i| i as i64)
    }
}

/// N environments of one kind stepped as a batch; see the [module docs](self).
#[derive(Debug)]
pub struct VecEnv {
    id: &'static str,
    n: usize,
    obs_dim: usize,
    action: ActionKind,
    proto: AnyEnv,
    envs: Envs,
    max_steps: u64,
    elapsed: Vec<u64>,
    obs: Vec<f32>,
    final_obs: Vec<f32>,
    /// Float64 observations (`num_envs × obs_dim`) for spaces that declare float64, else empty.
    obs64: Vec<f64>,
    final_obs64: Vec<f64>,
    rewards: Vec<f64>,
    terminated: Vec<bool>,
    truncated: Vec<bool>,
    /// Per environment: finished and not yet reset (next-step and disabled modes).
    pending: Vec<bool>,
    instance_ids: Vec<i64>,
    /// Per environment: how its episode ended, for the environments that ended in the latest
    /// step ([`Env::outcome`]; [`TIMED_OUT`] for the batch's time limit).
    outcomes: Vec<Option<&'static str>>,
    mode: AutoresetMode,
    ready: bool,
    pool: Pool,
    /// Smallest block of environments a thread claims (see [`block_size`]).
    min_block: usize,
    error: Mutex<Option<EnvError>>,
}

/// Raw views of the buffers, shared by the chunk jobs (each touches only its own range).
struct Raw {
    obs: *mut f32,
    final_obs: *mut f32,
    /// Row width of `obs64` / `final_obs64`: `obs_dim`, or 0 when they are empty.
    d64: usize,
    obs64: *mut f64,
    final_obs64: *mut f64,
    rewards: *mut f64,
    terminated: *mut bool,
    truncated: *mut bool,
    elapsed: *mut u64,
    pending: *mut bool,
    instance_ids: *mut i64,
    outcomes: *mut Option<&'static str>,
}
unsafe impl Sync for Raw {}

/// `&mut p[r.start * w .. r.end * w]`.
///
/// # Safety
/// `p` must point to at least `r.end * w` elements, and no other live reference may overlap the range.
#[inline]
unsafe fn rows<'a, T>(p: *mut T, r: &Range<usize>, w: usize) -> &'a mut [T] {
    unsafe { std::slice::from_raw_parts_mut(p.add(r.start * w), (r.end - r.start) * w) }
}

/// Work-sharing granularity: ~8 blocks per thread, at least `min_block` environments per block
/// (batches of at most one block run inline on the calling thread).
#[inline]
fn block_size(n: usize, threads: usize, min_block: usize) -> usize {
    (n / (threads * 8)).max(min_block)
}

impl VecEnv {
    /// One environment per context, built and checked by [`make_with`] (each keeps its own context).
    pub fn new(spec: &EnvSpec, contexts: &[Context], opts: VecOptions) -> Result<VecEnv, VecEnvError> {
        Self::with_make_options(spec, contexts, MakeOptions::default(), opts)
    }

    pub fn with_make_options(
        spec: &EnvSpec,
        contexts: &[Context],
        make: MakeOptions,
        opts: VecOptions,
    ) -> Result<VecEnv, VecEnvError> {
        let envs = contexts
            .iter()
            .map(|c| make_with(spec, c, make))
            .collect::<Result<Vec<_>, _>>()?;
        Self::from_envs(envs, opts)
    }

    /// Batch existing environments (all of one kind, typically from `registry::make`). Their
    /// contexts and episode limit are kept; their random streams are replaced at [`VecEnv::reset`].
    pub fn from_envs(envs: Vec<SpecEnv>, opts: VecOptions) -> Result<VecEnv, VecEnvError> {
        Self::from_envs_with(envs, opts, AutoresetMode::SameStep)
    }

    /// [`VecEnv::from_envs`] with an autoreset mode.
    pub fn from_envs_with(envs: Vec<SpecEnv>, opts: VecOptions, mode: AutoresetMode) -> Result<VecEnv, VecEnvError> {
        let Some(first) = envs.first() else {
            return Err(VecEnvError::Empty);
        };
        let id = first.id();
        if let Some(other) = envs.iter().find(|e| e.id() != id) {
            return Err(VecEnvError::Mixed {
                first: id,
                other: other.id(),
            });
        }
        let max_steps = first.max_episode_steps().unwrap_or(u64::MAX);
        let proto = first.inner().clone();
        let n = envs.len();
        let reg = lookup(id);
        let min_block = reg.map_or(1, |r| r.cost.min_block());
        let action = match proto.action_space() {
            Space::Discrete { n, .. } => ActionKind::Discrete(n),
            s @ Space::Box { .. } => ActionKind::Continuous(s.flat_dim()),
        };
        let inner: Vec<AnyEnv> = envs.into_iter().map(|e| e.into_inner()).collect();
        let kernel = reg.and_then(|r| r.vector_kernel);
        let envs = match (kernel, opts.kernel) {
            (Some(VectorKernel::CartPole), Kernel::Auto) => {
                let k = inner
                    .iter()
                    .filter_map(|e| e.downcast_ref::<CartPole>())
                    .map(|c| CartPoleK::from(c.params()))
                    .collect();
                Envs::CartPole(CartPoleSoa {
                    x: vec![0.0; n],
                    x_dot: vec![0.0; n],
                    theta: vec![0.0; n],
                    theta_dot: vec![0.0; n],
                    k,
                    rng: vec![EnvRng::default(); n],
                })
            }
            _ => {
                let a = match action {
                    ActionKind::Discrete(_) => Action::Discrete(0),
                    ActionKind::Continuous(d) => Action::Continuous(vec![0.0; d]),
                };
                Envs::Array(inner, vec![a; n])
            }
        };
        let mut v = Self::assemble(id, proto, envs, max_steps, opts, mode, min_block);
        v.alloc_f64();
        Ok(v)
    }

    /// Batch contextual environments (all of one kind). Each keeps its own source, selection and
    /// streams; its episode limit is its own (the wrapped runtimes count their steps).
    pub fn from_contextual(
        envs: Vec<ContextualEnv>,
        opts: VecOptions,
        mode: AutoresetMode,
    ) -> Result<VecEnv, VecEnvError> {
        let Some(first) = envs.first() else {
            return Err(VecEnvError::Empty);
        };
        let id = first.id();
        if let Some(other) = envs.iter().find(|e| e.id() != id) {
            return Err(VecEnvError::Mixed {
                first: id,
                other: other.id(),
            });
        }
        let proto = first.inner().inner().clone();
        let min_block = lookup(id).map_or(1, |r| r.cost.min_block());
        let n = envs.len();
        let a = match first.action_space() {
            Space::Discrete { .. } => Action::Discrete(0),
            s @ Space::Box { .. } => Action::Continuous(vec![0.0; s.flat_dim()]),
        };
        let mut v = Self::assemble(
            id,
            proto,
            Envs::Contextual(envs, vec![a; n]),
            u64::MAX,
            opts,
            mode,
            min_block,
        );
        if let Envs::Contextual(envs, _) = &v.envs {
            v.obs_dim = envs[0].obs_dim();
            for (slot, e) in v.instance_ids.iter_mut().zip(envs) {
                *slot = e.instance_id();
            }
        }
        v.obs = vec![0.0; n * v.obs_dim];
        v.final_obs = vec![0.0; n * v.obs_dim];
        v.alloc_f64();
        Ok(v)
    }

    fn assemble(
        id: &'static str,
        proto: AnyEnv,
        envs: Envs,
        max_steps: u64,
        opts: VecOptions,
        mode: AutoresetMode,
        min_block: usize,
    ) -> VecEnv {
        let n = match &envs {
            Envs::CartPole(s) => s.k.len(),
            Envs::Array(e, _) => e.len(),
            Envs::Contextual(e, _) => e.len(),
        };
        let obs_dim = proto.obs_dim();
        let action = match proto.action_space() {
            Space::Discrete { n, .. } => ActionKind::Discrete(n),
            s @ Space::Box { .. } => ActionKind::Continuous(s.flat_dim()),
        };
        VecEnv {
            id,
            n,
            obs_dim,
            action,
            proto,
            envs,
            max_steps,
            elapsed: vec![0; n],
            obs: vec![0.0; n * obs_dim],
            final_obs: vec![0.0; n * obs_dim],
            obs64: Vec::new(),
            final_obs64: Vec::new(),
            rewards: vec![0.0; n],
            terminated: vec![false; n],
            truncated: vec![false; n],
            pending: vec![false; n],
            instance_ids: vec![-1; n],
            outcomes: vec![None; n],
            mode,
            ready: false,
            pool: Pool::new(opts.threads.clamp(1, n)),
            min_block,
            error: Mutex::new(None),
        }
    }

    /// Float64 buffers when the observation space declares float64 (the float32 ones are
    /// kept too: they are what [`VecStep::obs`] and [`VecEnv::obs`] return).
    fn alloc_f64(&mut self) {
        let wide = matches!(
            self.observation_space(),
            Space::Box {
                dtype: DType::Float64,
                ..
            }
        );
        let len = if wide { self.n * self.obs_dim } else { 0 };
        self.obs64 = vec![0.0; len];
        self.final_obs64 = vec![0.0; len];
    }

    /// Current observations at float64 precision, `num_envs × obs_dim`, when the observation
    /// space declares float64 (`None` otherwise: [`VecEnv::obs`] is exact then).
    pub fn obs_f64(&self) -> Option<&[f64]> {
        (!self.obs64.is_empty()).then_some(&self.obs64[..])
    }

    /// [`VecEnv::final_observations`] at float64 precision (float64 spaces only).
    pub fn final_observations_f64(&self) -> Option<&[f64]> {
        (!self.final_obs64.is_empty()).then_some(&self.final_obs64[..])
    }

    /// The autoreset mode chosen at construction.
    pub fn autoreset_mode(&self) -> AutoresetMode {
        self.mode
    }

    /// Each environment's current instance id in its set (-1: not from a set).
    pub fn instance_ids(&self) -> &[i64] {
        &self.instance_ids
    }

    /// Environment `i`'s current context (contextual batches only).
    pub fn context_info(&self, i: usize) -> Option<&ContextInfo> {
        match &self.envs {
            Envs::Contextual(envs, _) => envs.get(i).map(ContextualEnv::context_info),
            _ => None,
        }
    }

    /// Environment `i`'s next episode plays `context` (a curriculum's choice; see
    /// [`ContextualEnv::set_next_context`]). Contextual batches only: a plain batch has one fixed
    /// context and no wrapper to take the choice.
    pub fn set_next_context(&mut self, i: usize, context: &Context) -> Result<(), String> {
        let n = self.n;
        match &mut self.envs {
            Envs::Contextual(envs, _) => envs
                .get_mut(i)
                .ok_or_else(|| format!("environment {i} is outside the batch of {n}"))?
                .set_next_context(context)
                .map_err(|e| e.to_string()),
            _ => Err(format!(
                "{}: this batch plays one fixed context without the contextual wrapper, so no context can be chosen per episode",
                self.id
            )),
        }
    }

    /// Environment `i`'s runtime (not for the CartPole kernel, which has none per environment).
    pub fn runtime(&self, i: usize) -> Option<&AnyEnv> {
        match &self.envs {
            Envs::Contextual(envs, _) => Some(envs.get(i)?.inner().inner()),
            Envs::Array(envs, _) => envs.get(i),
            Envs::CartPole(_) => None,
        }
    }

    /// Same-step mode, after a step where environment `i` finished: the context of the episode
    /// that ended (its autoreset already chose the next one; contextual batches only).
    pub fn final_context_info(&self, i: usize) -> Option<ContextInfo> {
        match &self.envs {
            Envs::Contextual(envs, _) => envs.get(i)?.previous_context_info(),
            _ => None,
        }
    }

    /// Per environment: finished and waiting for a reset (next-step: at the next step; disabled:
    /// by [`VecEnv::reset_masked`]).
    /// How environment `i`'s episode ended, if it ended in the latest step (`terminated` or
    /// `truncated`): its [`Env::outcome`] (e.g. `landed`, `solved`), or [`TIMED_OUT`] for the
    /// time limit; `None` otherwise, and for terminations the environment gives no name.
    pub fn outcome(&self, i: usize) -> Option<&'static str> {
        let ended = self.terminated.get(i).copied().unwrap_or(false) || self.truncated.get(i).copied().unwrap_or(false);
        if ended { self.outcomes[i] } else { None }
    }

    pub fn pending_resets(&self) -> &[bool] {
        &self.pending
    }

    pub fn id(&self) -> &'static str {
        self.id
    }
    pub fn num_envs(&self) -> usize {
        self.n
    }
    pub fn obs_dim(&self) -> usize {
        self.obs_dim
    }
    /// Threads actually used (the setting, capped at `num_envs`).
    pub fn threads(&self) -> usize {
        self.pool.threads()
    }
    /// Change the number of threads (restarts the worker pool).
    pub fn set_threads(&mut self, threads: usize) {
        self.pool = Pool::new(threads.clamp(1, self.n));
    }
    /// Whether the structure-of-arrays kernel is in use (else the array of scalar environments).
    pub fn is_soa(&self) -> bool {
        matches!(self.envs, Envs::CartPole(_))
    }
    /// Single-environment observation space.
    pub fn observation_space(&self) -> Space {
        match &self.envs {
            Envs::Contextual(envs, _) => envs[0].observation_space(),
            _ => self.proto.observation_space(),
        }
    }
    /// Single-environment action space.
    pub fn action_space(&self) -> Space {
        self.proto.action_space()
    }

    /// Current observations, `num_envs × obs_dim`.
    pub fn obs(&self) -> &[f32] {
        &self.obs
    }
    pub fn rewards(&self) -> &[f64] {
        &self.rewards
    }
    pub fn terminated(&self) -> &[bool] {
        &self.terminated
    }
    pub fn truncated(&self) -> &[bool] {
        &self.truncated
    }
    /// Last observation of the episode environment `i` finished in the latest `step`
    /// (`None` if it did not finish, or `i` is out of range; always `None` unless autoreset is
    /// same-step: in the other modes `obs` itself holds it).
    pub fn final_obs(&self, i: usize) -> Option<&[f32]> {
        let done = *self.terminated.get(i)? || self.truncated[i];
        (done && self.mode == AutoresetMode::SameStep)
            .then(|| &self.final_obs[i * self.obs_dim..(i + 1) * self.obs_dim])
    }
    /// The flat final-observation buffer (`num_envs × obs_dim`); row `i` is meaningful only where
    /// `terminated[i] || truncated[i]` after the latest step.
    pub fn final_observations(&self) -> &[f32] {
        &self.final_obs
    }
    /// Steps environment `i` has taken in its current episode.
    pub fn elapsed_steps(&self, i: usize) -> Option<u64> {
        self.elapsed.get(i).copied()
    }

    /// Internal float64 state of environment `i` (as `Env::state`).
    pub fn state(&self, i: usize) -> Option<Vec<f64>> {
        if i >= self.n {
            return None;
        }
        Some(match &self.envs {
            Envs::CartPole(s) => vec![s.x[i], s.x_dot[i], s.theta[i], s.theta_dot[i]],
            Envs::Array(envs, _) => envs[i].state(),
            Envs::Contextual(envs, _) => envs[i].state(),
        })
    }

    /// Reset every environment; environment `i` is seeded with `seed.wrapping_add(i)`.
    /// Returns the first observations.
    pub fn reset(&mut self, seed: u64) -> &[f32] {
        self.reset_masked(Some(seed), None)
    }

    /// Reset the environments where `mask` is true (all of them for `None`): environment `i` is
    /// seeded with `seed.wrapping_add(i)`, or continues its own stream for `seed = None`. The
    /// others keep their state, observation and flags. Returns the observations.
    pub fn reset_masked(&mut self, seed: Option<u64>, mask: Option<&[bool]>) -> &[f32] {
        let seed_of = |i: usize| seed.map(|s| s.wrapping_add(i as u64));
        let chosen = |i: usize| mask.is_none_or(|m| m.get(i).copied().unwrap_or(false));
        self.reset_rows((0..self.n).filter(|&i| chosen(i)), seed_of, |_| None);
        &self.obs
    }

    /// Reset the environments where `mask` is true (all for `None`), environment `i` with its own
    /// seed `seeds[i]` (`None`: it continues its streams; unlike [`VecEnv::reset_masked`], no
    /// `+ i`) and, where `instances[i]` is given, playing that instance of its set
    /// ([`ContextualEnv::reset_instance_into`]). One call for a whole batch of episode starts.
    /// Wrong lengths, or an instance for a batch without a set or outside it, are errors and
    /// reset nothing.
    pub fn reset_each(
        &mut self,
        seeds: &[Option<u64>],
        instances: Option<&[Option<usize>]>,
        mask: Option<&[bool]>,
    ) -> Result<&[f32], EnvError> {
        let env = self.id;
        let n = self.n;
        let length = |got: usize| EnvError::BatchLength { env, expected: n, got };
        if seeds.len() != n {
            return Err(length(seeds.len()));
        }
        if let Some(m) = mask
            && m.len() != n
        {
            return Err(length(m.len()));
        }
        let chosen = |i: usize| mask.is_none_or(|m| m[i]);
        if let Some(inst) = instances {
            if inst.len() != n {
                return Err(length(inst.len()));
            }
            for (i, k) in inst.iter().enumerate() {
                let Some(k) = *k else { continue };
                if !chosen(i) {
                    continue;
                }
                self.check_instance(i, k)?;
            }
        }
        let instance_of = |i: usize| instances.and_then(|v| v[i]);
        self.reset_rows((0..n).filter(|&i| chosen(i)), |i| seeds[i], instance_of);
        Ok(&self.obs)
    }

    /// Reset the environments `envs[k]`, each with its own seed `seeds[k]` and, where
    /// `instances` gives `Some(i)` at `k`, playing instance `i` of its set: [`VecEnv::reset_each`]
    /// for a list of environments, at the cost of those alone (a batch whose episodes are short
    /// resets a few of its environments between most steps). An environment listed twice is
    /// reset twice. Wrong lengths, an environment outside the batch, or an instance for a batch
    /// without a set or outside it, are errors and reset nothing.
    pub fn reset_some(
        &mut self,
        envs: &[usize],
        seeds: &[u64],
        instances: Option<&[Option<usize>]>,
    ) -> Result<(), EnvError> {
        let env = self.id;
        let n = self.n;
        let length = |got: usize| EnvError::BatchLength {
            env,
            expected: envs.len(),
            got,
        };
        if seeds.len() != envs.len() {
            return Err(length(seeds.len()));
        }
        if let Some(&i) = envs.iter().find(|&&i| i >= n) {
            return Err(EnvError::Context {
                env,
                message: format!("environment {i} is outside the batch of {n}"),
            });
        }
        if let Some(inst) = instances {
            if inst.len() != envs.len() {
                return Err(length(inst.len()));
            }
            for (&i, k) in envs.iter().zip(inst) {
                if let Some(k) = *k {
                    self.check_instance(i, k)?;
                }
            }
        }
        // Rows in list order: `seeds[k]` and `instances[k]` belong to the row `envs[k]`.
        let mut k = 0;
        let mut next = |_: usize| {
            let (seed, inst) = (seeds[k], instances.and_then(|v| v[k]));
            k += 1;
            (Some(seed), inst)
        };
        self.reset_listed(envs.iter().copied(), &mut next);
        Ok(())
    }

    /// Whether environment `i` can be asked to play instance `k` (a contextual batch with a set
    /// that holds it), the error naming the environment otherwise.
    fn check_instance(&self, i: usize, k: usize) -> Result<(), EnvError> {
        let env = self.id;
        match &self.envs {
            Envs::Contextual(envs, _) => envs[i].check_instance(k).map_err(|e| match e {
                EnvError::Context { env, message } => EnvError::Context {
                    env,
                    message: format!("environment {i} of the batch: {message}"),
                },
                other => other,
            }),
            _ => Err(EnvError::Context {
                env,
                message: format!(
                    "environment {i} of the batch was asked for instance {k}, but the batch plays one fixed context, not an instance set"
                ),
            }),
        }
    }

    /// The resets of [`VecEnv::reset_masked`] and [`VecEnv::reset_each`] (instances already
    /// checked): the environments `rows`, environment `i` with seed `seed_of(i)` and instance
    /// `instance_of(i)`.
    fn reset_rows(
        &mut self,
        rows: impl Iterator<Item = usize>,
        seed_of: impl Fn(usize) -> Option<u64>,
        instance_of: impl Fn(usize) -> Option<usize>,
    ) {
        self.reset_listed(rows, &mut |i| (seed_of(i), instance_of(i)));
    }

    /// Reset the environments `rows` in order, each with the (seed, instance) that `what` gives
    /// for it (called once per row, in order; instances already checked).
    fn reset_listed(
        &mut self,
        rows: impl Iterator<Item = usize>,
        what: &mut impl FnMut(usize) -> (Option<u64>, Option<usize>),
    ) {
        let d = self.obs_dim;
        let wide = !self.obs64.is_empty();
        for i in rows {
            let (seed, instance) = what(i);
            match &mut self.envs {
                Envs::CartPole(s) => {
                    if let Some(seed) = seed {
                        s.rng[i] = EnvRng::from_seed(seed);
                    }
                    let (x, xd, th, thd) = cartpole_reset(&s.k[i], &mut s.rng[i]);
                    (s.x[i], s.x_dot[i], s.theta[i], s.theta_dot[i]) = (x, xd, th, thd);
                    write4(&mut self.obs[i * 4..i * 4 + 4], x, xd, th, thd);
                }
                Envs::Array(envs, _) => {
                    let e = &mut envs[i];
                    // The buffer has the right length, so this cannot fail.
                    let _ = e.reset_into(seed, &mut self.obs[i * d..(i + 1) * d]);
                    if wide {
                        let _ = e.observe_f64_into(&mut self.obs64[i * d..(i + 1) * d]);
                    }
                }
                Envs::Contextual(envs, _) => {
                    let e = &mut envs[i];
                    let o = &mut self.obs[i * d..(i + 1) * d];
                    // A failed distribution draw leaves zeros (see `ContextualEnv::info`);
                    // instances were checked by the caller.
                    let _ = match instance {
                        Some(k) => e.reset_instance_into(seed, k, o),
                        None => e.reset_into(seed, o),
                    };
                    if wide {
                        let _ = e.observe_f64_into(&mut self.obs64[i * d..(i + 1) * d]);
                    }
                    self.instance_ids[i] = e.instance_id();
                }
            }
            self.elapsed[i] = 0;
            self.rewards[i] = 0.0;
            self.terminated[i] = false;
            self.truncated[i] = false;
            self.pending[i] = false;
        }
        self.ready = true;
    }

    /// Step every environment with its action (auto-resetting finished ones; see the module docs).
    pub fn step(&mut self, actions: VecActions<'_>) -> Result<VecStep<'_>, EnvError> {
        self.step_with(actions, |share| share.claim_all())
    }

    /// [`VecEnv::step`], where the calling thread first runs `caller` while the worker threads
    /// already step their blocks of environments, then steps the blocks left: `caller` may do
    /// unrelated work there (the Python binding makes the step's output objects) and may take
    /// its [`CallerShare`] itself (for example with Python's GIL released). With one thread,
    /// `caller` runs before the whole batch is stepped. Not called when the actions are refused.
    pub fn step_with(
        &mut self,
        actions: VecActions<'_>,
        caller: impl FnOnce(&mut CallerShare<'_>),
    ) -> Result<VecStep<'_>, EnvError> {
        self.check(actions)?;
        let n = self.n;
        let d = self.obs_dim;
        let max_steps = self.max_steps;
        let raw = Raw {
            obs: self.obs.as_mut_ptr(),
            final_obs: self.final_obs.as_mut_ptr(),
            d64: if self.obs64.is_empty() { 0 } else { d },
            obs64: self.obs64.as_mut_ptr(),
            final_obs64: self.final_obs64.as_mut_ptr(),
            rewards: self.rewards.as_mut_ptr(),
            terminated: self.terminated.as_mut_ptr(),
            truncated: self.truncated.as_mut_ptr(),
            elapsed: self.elapsed.as_mut_ptr(),
            pending: self.pending.as_mut_ptr(),
            instance_ids: self.instance_ids.as_mut_ptr(),
            outcomes: self.outcomes.as_mut_ptr(),
        };
        let mode = self.mode;
        let block = block_size(n, self.pool.threads(), self.min_block);
        let error = &self.error;
        match (&mut self.envs, actions) {
            (Envs::CartPole(s), VecActions::Discrete(a)) => {
                let soa = SoaRaw {
                    x: s.x.as_mut_ptr(),
                    x_dot: s.x_dot.as_mut_ptr(),
                    theta: s.theta.as_mut_ptr(),
                    theta_dot: s.theta_dot.as_mut_ptr(),
                    k: s.k.as_ptr(),
                    rng: s.rng.as_mut_ptr(),
                };
                let job = |r: Range<usize>| {
                    // SAFETY: every buffer has `n` rows; the pool hands out disjoint ranges.
                    unsafe { cartpole_chunk(&soa, &raw, &a[r.clone()], r, max_steps, mode) }
                };
                self.pool.run(n, block, &job, caller);
            }
            (Envs::Array(envs, acts), actions) => {
                let env = ChunkEnv {
                    raw: &raw,
                    actions,
                    d,
                    max_steps,
                    mode,
                };
                if let Err(e) = step_array(&mut self.pool, error, envs, acts, &env, n, block, caller) {
                    self.ready = false;
                    return Err(e);
                }
            }
            (Envs::Contextual(envs, acts), actions) => {
                let env = ChunkEnv {
                    raw: &raw,
                    actions,
                    d,
                    max_steps,
                    mode,
                };
                if let Err(e) = step_array(&mut self.pool, error, envs, acts, &env, n, block, caller) {
                    self.ready = false;
                    return Err(e);
                }
            }
            (Envs::CartPole(_), VecActions::Continuous(_)) => unreachable!("rejected by check()"),
        }
        Ok(VecStep {
            obs: &self.obs,
            rewards: &self.rewards,
            terminated: &self.terminated,
            truncated: &self.truncated,
        })
    }

    /// Convenience for discrete environments.
    pub fn step_discrete(&mut self, actions: &[i64]) -> Result<VecStep<'_>, EnvError> {
        self.step(VecActions::Discrete(actions))
    }

    /// Convenience for continuous environments (`num_envs × action_dim` values).
    pub fn step_continuous(&mut self, actions: &[f32]) -> Result<VecStep<'_>, EnvError> {
        self.step(VecActions::Continuous(actions))
    }

    fn check(&self, actions: VecActions<'_>) -> Result<(), EnvError> {
        let env = self.id;
        match (self.action, actions) {
            (ActionKind::Discrete(k), VecActions::Discrete(a)) => {
                if a.len() != self.n {
                    return Err(EnvError::BatchLength {
                        env,
                        expected: self.n,
                        got: a.len(),
                    });
                }
                // Branch-free scan first; locate the culprit only on failure.
                if a.iter().fold(false, |bad, &x| bad | !(0..k).contains(&x)) {
                    let action = a.iter().copied().find(|x| !(0..k).contains(x)).unwrap_or(-1);
                    return Err(EnvError::ActionOutOfRange { env, action, n: k });
                }
            }
            (ActionKind::Continuous(dim), VecActions::Continuous(a)) => {
                if a.len() != self.n * dim {
                    return Err(EnvError::BatchLength {
                        env,
                        expected: self.n * dim,
                        got: a.len(),
                    });
                }
            }
            (ActionKind::Discrete(_), VecActions::Continuous(_)) => {
                return Err(EnvError::ActionKind {
                    env,
                    expected: "discrete",
                    got: "continuous",
                });
            }
            (ActionKind::Continuous(_), VecActions::Discrete(_)) => {
                return Err(EnvError::ActionKind {
                    env,
                    expected: "continuous",
                    got: "discrete",
                });
            }
        }
        if !self.ready {
            return Err(EnvError::NeedsReset { env });
        }
        if self.mode == AutoresetMode::Disabled
            && let Some(index) = self.pending.iter().position(|&p| p)
        {
            return Err(EnvError::EpisodeOver { env, index });
        }
        Ok(())
    }
}

struct SyncPtr<T>(*mut T);
unsafe impl<T> Sync for SyncPtr<T> {}
impl<T> SyncPtr<T> {
    fn get(&self) -> *mut T {
        self.0
    }
}

struct SoaRaw {
    x: *mut f64,
    x_dot: *mut f64,
    theta: *mut f64,
    theta_dot: *mut f64,
    k: *const CartPoleK,
    rng: *mut EnvRng,
}
unsafe impl Sync for SoaRaw {}

#[inline]
fn write4(o: &mut [f32], a: f64, b: f64, c: f64, d: f64) {
    o[0] = a as f32;
    o[1] = b as f32;
    o[2] = c as f32;
    o[3] = d as f32;
}

/// `CartPole::reset_into`'s draws (the same function).
#[inline]
fn cartpole_reset(k: &CartPoleK, rng: &mut EnvRng) -> (f64, f64, f64, f64) {
    let [x, xd, th, thd] = cartpole::initial_state(&k.params, rng);
    (x, xd, th, thd)
}

/// The CartPole step for environments `r` (actions already validated).
///
/// # Safety
/// All pointers in `s` and `o` must cover `r.end` rows, and no other thread may touch rows in `r`.
#[inline(never)]
unsafe fn cartpole_chunk(s: &SoaRaw, o: &Raw, actions: &[i64], r: Range<usize>, max_steps: u64, mode: AutoresetMode) {
    let pending = unsafe { &mut rows(o.pending, &r, 1)[..actions.len()] };
    let outs = unsafe { &mut rows(o.outcomes, &r, 1)[..actions.len()] };
    let (xs, xds, ths, thds, ks, rngs, obs, fin, rew, term, trunc, el) = unsafe {
        (
            rows(s.x, &r, 1),
            rows(s.x_dot, &r, 1),
            rows(s.theta, &r, 1),
            rows(s.theta_dot, &r, 1),
            std::slice::from_raw_parts(s.k.add(r.start), r.end - r.start),
            rows(s.rng, &r, 1),
            rows(o.obs, &r, 4),
            rows(o.final_obs, &r, 4),
            rows(o.rewards, &r, 1),
            rows(o.terminated, &r, 1),
            rows(o.truncated, &r, 1),
            rows(o.elapsed, &r, 1),
        )
    };
    // Re-slice to one common length so the indexing below needs no bounds checks.
    let len = actions.len();
    let (xs, xds, ths, thds, ks, rngs) = (
        &mut xs[..len],
        &mut xds[..len],
        &mut ths[..len],
        &mut thds[..len],
        &ks[..len],
        &mut rngs[..len],
    );
    let (obs, fin, rew, term, trunc, el) = (
        &mut obs[..len * 4],
        &mut fin[..len * 4],
        &mut rew[..len],
        &mut term[..len],
        &mut trunc[..len],
        &mut el[..len],
    );
    for j in 0..len {
        let p = &ks[j];
        let row = j * 4..j * 4 + 4;
        if pending[j] {
            // Next-step autoreset: this step resets instead of stepping (check() rejected
            // stepping a finished environment when autoreset is disabled).
            let (x, x_dot, theta, theta_dot) = cartpole_reset(p, &mut rngs[j]);
            (xs[j], xds[j], ths[j], thds[j]) = (x, x_dot, theta, theta_dot);
            write4(&mut obs[row], x, x_dot, theta, theta_dot);
            (rew[j], term[j], trunc[j], el[j], pending[j]) = (0.0, false, false, 0, false);
            continue;
        }
        // The scalar environment's step function itself.
        let next = cartpole::dynamics(&p.step, [xs[j], xds[j], ths[j], thds[j]], actions[j]);
        let terminated = cartpole::is_terminal(next);
        let [x, x_dot, theta, theta_dot] = next;
        let e = el[j] + 1;
        let truncated = e >= max_steps;
        // No env is ever stepped after termination (it is reset first, or refused when autoreset
        // is disabled), so the scalar env's "0 reward after termination" case cannot occur.
        rew[j] = 1.0;
        term[j] = terminated;
        trunc[j] = truncated;
        if terminated || truncated {
            outs[j] = Some(if terminated { cartpole::FAILED } else { TIMED_OUT });
        }
        if (terminated || truncated) && mode != AutoresetMode::SameStep {
            (xs[j], xds[j], ths[j], thds[j]) = (x, x_dot, theta, theta_dot);
            el[j] = e;
            pending[j] = true;
            write4(&mut obs[row], x, x_dot, theta, theta_dot);
        } else if terminated || truncated {
            write4(&mut fin[row.clone()], x, x_dot, theta, theta_dot);
            let (x, x_dot, theta, theta_dot) = cartpole_reset(p, &mut rngs[j]);
            (xs[j], xds[j], ths[j], thds[j]) = (x, x_dot, theta, theta_dot);
            el[j] = 0;
            write4(&mut obs[row], x, x_dot, theta, theta_dot);
        } else {
            (xs[j], xds[j], ths[j], thds[j]) = (x, x_dot, theta, theta_dot);
            el[j] = e;
            write4(&mut obs[row], x, x_dot, theta, theta_dot);
        }
    }
}

/// What every chunk of an array-of-environments step shares.
struct ChunkEnv<'a, 'b> {
    raw: &'a Raw,
    actions: VecActions<'b>,
    d: usize,
    max_steps: u64,
    mode: AutoresetMode,
}

/// Run [`array_chunk`] over the whole batch on the pool (`caller` as in [`VecEnv::step_with`]);
/// the first error wins.
#[allow(clippy::too_many_arguments)]
fn step_array<E: BatchEnv>(
    pool: &mut Pool,
    error: &Mutex<Option<EnvError>>,
    envs: &mut [E],
    acts: &mut [Action],
    c: &ChunkEnv<'_, '_>,
    n: usize,
    block: usize,
    caller: impl FnOnce(&mut CallerShare<'_>),
) -> Result<(), EnvError> {
    let envs_p = SyncPtr(envs.as_mut_ptr());
    let acts_p = SyncPtr(acts.as_mut_ptr());
    let job = |r: Range<usize>| {
        // SAFETY: every buffer has `n` rows; the pool hands out disjoint ranges.
        let (envs, acts) = unsafe { (rows(envs_p.get(), &r, 1), rows(acts_p.get(), &r, 1)) };
        if let Err(e) = unsafe { array_chunk(envs, acts, c, r) }
            && let Ok(mut slot) = error.lock()
        {
            slot.get_or_insert(e);
        }
    };
    pool.run(n, block, &job, caller);
    match error.lock().ok().and_then(|mut s| s.take()) {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// The array-of-environments step for environments `r`.
///
/// # Safety
/// As [`cartpole_chunk`]; `envs` and `acts` are the rows `r`.
unsafe fn array_chunk<E: BatchEnv>(
    envs: &mut [E],
    acts: &mut [Action],
    c: &ChunkEnv<'_, '_>,
    r: Range<usize>,
) -> Result<(), EnvError> {
    let (o, d, actions, max_steps) = (c.raw, c.d, c.actions, c.max_steps);
    let d64 = o.d64;
    let (obs64, fin64) = unsafe { (rows(o.obs64, &r, d64), rows(o.final_obs64, &r, d64)) };
    let outs = unsafe { rows(o.outcomes, &r, 1) };
    let (obs, fin, rew, term, trunc, el, pending, ids) = unsafe {
        (
            rows(o.obs, &r, d),
            rows(o.final_obs, &r, d),
            rows(o.rewards, &r, 1),
            rows(o.terminated, &r, 1),
            rows(o.truncated, &r, 1),
            rows(o.elapsed, &r, 1),
            rows(o.pending, &r, 1),
            rows(o.instance_ids, &r, 1),
        )
    };
    for j in 0..envs.len() {
        let i = r.start + j;
        let row = j * d..(j + 1) * d;
        let row64 = j * d64..(j + 1) * d64;
        if pending[j] {
            // Next-step autoreset: this step resets instead of stepping (check() rejected
            // stepping a finished environment when autoreset is disabled).
            envs[j].reset_into(None, &mut obs[row])?;
            if d64 > 0 {
                envs[j].observe_f64_into(&mut obs64[row64])?;
            }
            ids[j] = envs[j].instance_id();
            (rew[j], term[j], trunc[j], el[j], pending[j]) = (0.0, false, false, 0, false);
            continue;
        }
        match (&mut acts[j], actions) {
            (Action::Discrete(slot), VecActions::Discrete(a)) => *slot = a[i],
            (Action::Continuous(slot), VecActions::Continuous(a)) => {
                let w = slot.len();
                slot.copy_from_slice(&a[i * w..(i + 1) * w]);
            }
            _ => unreachable!("rejected by check()"),
        }
        let out = envs[j].step_into(&acts[j], &mut obs[row.clone()])?;
        if d64 > 0 {
            envs[j].observe_f64_into(&mut obs64[row64.clone()])?;
        }
        let e = el[j] + 1;
        let truncated = out.truncated || e >= max_steps;
        rew[j] = out.reward;
        term[j] = out.terminated;
        trunc[j] = truncated;
        el[j] = e;
        if out.terminated || truncated {
            // Before a same-step reset forgets how the episode ended.
            outs[j] = if out.terminated {
                envs[j].outcome()
            } else {
                Some(TIMED_OUT)
            };
            match c.mode {
                AutoresetMode::SameStep => {
                    fin[row.clone()].copy_from_slice(&obs[row.clone()]);
                    envs[j].reset_into(None, &mut obs[row])?;
                    if d64 > 0 {
                        fin64[row64.clone()].copy_from_slice(&obs64[row64.clone()]);
                        envs[j].observe_f64_into(&mut obs64[row64])?;
                    }
                    ids[j] = envs[j].instance_id();
                    el[j] = 0;
                }
                AutoresetMode::NextStep | AutoresetMode::Disabled => pending[j] = true,
            }
        }
    }
    Ok(())
}
