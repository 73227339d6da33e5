//! CARL's contextual wrapper: one environment, many contexts.
//!
//! [`ContextualEnv`] picks a context at every reset, builds (or reuses) the runtime for it,
//! optionally appends the context to the observation and reports it in the info. Unlike the
//! Python reference it owns all of its state (no global RNG, no shared module state), and its
//! instance selection honours `reset(seed)`.
//!
//! # Context sources
//!
//! * [`ContextSource::Set`]: a frozen instance set. One runtime per instance is built up front
//!   (every instance is checked at construction), so a reset only switches an index and stepping
//!   never allocates. Out-of-bounds values are accepted only when the set's definition declares
//!   `allow_out_of_bounds` (e.g. Landing-in-Space's Jupiter); otherwise they are refused.
//! * [`ContextSource::Distribution`]: a named distribution of the spec, sampled afresh at every
//!   reset (one context per reset; the runtime is rebuilt then, never while stepping).
//!   Out-of-bounds draws are refused.
//! * [`ContextSource::Fixed`]: one context for every episode. Out-of-bounds values are refused.
//!
//! # Seeding: how the instance and the initial state derive from the seed
//!
//! The wrapper keeps three independent [`Pcg64`](crate::sampling::Pcg64) streams, all derived from one seed `s`:
//!
//! | stream    | generator                                                        | used for |
//! |-----------|------------------------------------------------------------------|----------|
//! | selection | `Pcg64::new(s, stream_id("carl-spec/contextual/selection"))`     | [`Selection::Random`] |
//! | context   | `Pcg64::new(s, stream_id("carl-spec/contextual/context"))`       | [`ContextSource::Distribution`] |
//! | env       | `Pcg64::new(s, stream_id("carl-spec/contextual/env"))`           | the runtime's initial state |
//!
//! (`stream_id` is FNV-1a 64 of the UTF-8 name, [`crate::sampling::stream_id`].)
//! `reset(Some(s))` re-creates all three streams from `s`; `reset(None)` continues them. Before the
//! first explicit seed they are seeded with `s = 0` ([`DEFAULT_SEED`]), so an unseeded wrapper is
//! still deterministic (the Python package seeds the first reset from OS entropy instead). At every
//! reset, in this order:
//!
//! 1. **Instance** (sets only):
//!    * `RoundRobin`: `reset(Some(s))` uses instance `s mod n`, each following `reset(None)` the
//!      next one (cyclically); before any seed the cycle starts at 0. So the seed determines the
//!      instances that follow, seeding every episode with its number (`reset(Some(episode))`)
//!      still visits every instance in order, and the environments of a batch (seeds `s + i`)
//!      start on different instances.
//!    * `Random`: index = `below(selection, n)` ([`crate::sampling::dist::below`]: Lemire's
//!      unbiased multiply-shift with rejection, one `next_u64` per draw except on rare rejections).
//!      So after `reset(Some(s))` the instance is the first such draw of the selection stream
//!      seeded with `s`, and each following `reset(None)` takes the next draw.
//!    * `Static(i)`: always instance `i`.
//! 2. **Context** (distributions only): `context_seed = context.next_u64()`, then the context is
//!    [`sample_distribution`]`(spec, name, dist, 1, context_seed)`'s single row over the spec's
//!    defaults. `context_seed` is reported in [`ContextInfo::context_seed`], so any episode's
//!    context can be re-drawn on its own.
//! 3. **Initial state**: one draw `e = env.next_u64()` is taken at every reset. A seeded reset
//!    `reset(Some(s))` resets the runtime with `Some(s)` itself, so the episode starts where the
//!    runtime (and, for the classic five, Gymnasium's env) seeded with `s` starts. An unseeded reset
//!    of a fixed context continues the runtime's own stream (`reset_into(None)`: exactly
//!    Gymnasium's `reset()` after `reset(seed=s)`); for sets and distributions, whose runtime
//!    changes between episodes, the runtime is reset with `Some(e)`.
//!
//! These rules live in [`super::context_schedule`] ([`ContextSchedule`] for the three streams,
//! [`ObservationNoise`] for the fourth, `carl-spec/contextual/noise`, which draws the context
//! noise), shared with wrappers of users' own environments.
//!
//! The draws of one stream never depend on another stream, so switching, e.g., from `RoundRobin`
//! to `Random` leaves the initial-state seeds unchanged.
//!
//! # Context in the observation
//!
//! With [`Visibility::Visible`] the chosen features' values (canonical names, as `f32`) follow the
//! runtime's observation, in spec order for [`Features::All`] or in the given order for
//! [`Features::Only`].
//!
//! The observation space depends on the environment, its version and options, the visible
//! features and the context noise only, never on the context source: a set, another set, a
//! distribution and a fixed context give one space, so an agent trained on one source is
//! evaluated on another as it is (Stable-Baselines3's `set_env` / `load(path, env=...)` compare
//! spaces). It is a `Box` of length `base + k` (flattened), with:
//!
//! * base components: the runtime's space at the spec's default context, with every component
//!   whose bounds change when some feature changes (probed by rebuilding with each feature moved
//!   off its default, [`ContextualEnv::new`]) made unbounded (`±inf`): other contexts may move
//!   them anywhere.
//! * context components: the feature's declared spec bounds as `f32`; an open side (`null` in the
//!   spec) is `-inf` / `+inf`, which is what Gymnasium's `Box(low=-np.inf, high=np.inf,
//!   dtype=float32)` stores (Gymnasium keeps infinities for float dtypes; it does not substitute
//!   `f32::MAX`). Bool features without bounds get `[0, 1]`; a feature observed with noise is
//!   unbounded. A set that deliberately goes out of bounds (`allow_out_of_bounds`, e.g. Landing
//!   in Space's Jupiter) shows its true value, outside the declared space: that is what out of
//!   bounds means.
//!
//! The action space is the current runtime's (contexts do not change it for the classic
//! environments).

use super::api::{Action, Env, EnvError, Info, Space, Step, StepOutcome, check_obs_len};
use super::context_schedule::{ContextSchedule, ObservationNoise, Pick, ScheduleKind, drawn_context};
use super::registry::{Context, EnvOptions, MakeError, MakeOptions, SpecEnv, make_env, resolve_context};
use super::rng::DEFAULT_SEED;
use super::schedules::Schedules;
use crate::instances::derive::sample_distribution;
use crate::spec::model::{Distribution, EnvSpec, FeatureType, Value};
use crate::suggest::did_you_mean;

pub use super::contextual_options::{
    CONTEXT_STREAM, ContextInfo, ContextNoise, ContextSource, ContextualError, ContextualOptions, ENV_STREAM, Features,
    NOISE_STREAM, NoiseRedraw, NoiseStd, OBSERVED_PREFIX, SELECTION_STREAM, Selection, Visibility,
};

/// One ready runtime with its context.
#[derive(Debug, Clone)]
struct Slot {
    env: SpecEnv,
    info: ContextInfo,
    /// The visible features' values, as appended to the observation.
    ctx_obs: Vec<f32>,
}

#[derive(Debug, Clone)]
enum Mode {
    Set,
    Fixed,
    Distribution { name: String, dist: Distribution },
}

/// A contextual environment: see the module docs.
#[derive(Debug, Clone)]
pub struct ContextualEnv {
    spec: EnvSpec,
    id: &'static str,
    mode: Mode,
    /// One per instance (sets), or a single slot (fixed, distribution).
    slots: Vec<Slot>,
    current: usize,
    visible: Vec<String>,
    base_dim: usize,
    obs_space: Space,
    schedule: ContextSchedule,
    noise: ObservationNoise,
    /// The slot of the episode before the latest reset (see [`ContextualEnv::previous_context_info`]),
    /// and for distributions that episode's retired draw.
    previous: Option<(usize, u64)>,
    retired: Option<ContextInfo>,
    env_options: EnvOptions,
    /// What the agent observes of the visible features this step (true value + noise).
    observed: Vec<f32>,
    resets: u64,
    /// Features changing within the episode, with each slot's own (base) values of them and
    /// where each scheduled feature sits among the visible ones.
    schedules: Schedules,
    schedule_bases: Vec<Vec<f64>>,
    schedule_visible: Vec<Option<usize>>,
    /// A curriculum's choice for the next episode ([`ContextualEnv::set_next_context`]), and
    /// the fixed context it stood in for (put back at the reset after).
    pending: Option<Slot>,
    fixed_original: Option<Slot>,
    /// `make`'s `allow_out_of_bounds`: a curriculum's contexts may leave the bounds too.
    allow_out_of_bounds: bool,
}

fn make_err(who: &str) -> impl FnOnce(MakeError) -> ContextualError + '_ {
    move |source| ContextualError::Make {
        who: who.to_string(),
        source: Box::new(source),
    }
}

/// Build the runtime for `ctx` and its info (visible values are filled in later).
fn build_slot(
    spec: &EnvSpec,
    ctx: &Context,
    opts: MakeOptions,
    env_options: &EnvOptions,
    who: &str,
    instance_id: Option<usize>,
    instance_name: Option<String>,
) -> Result<Slot, ContextualError> {
    let context = resolve_context(spec, ctx, opts).map_err(make_err(who))?;
    let env = make_env(spec, ctx, opts, env_options).map_err(make_err(who))?;
    Ok(Slot {
        env,
        info: ContextInfo {
            instance_id,
            instance_name,
            context,
            context_seed: None,
            episode: 0,
        },
        ctx_obs: Vec::new(),
    })
}

fn fill_visible(spec: &EnvSpec, slot: &mut Slot, visible: &[String], who: &str) -> Result<(), ContextualError> {
    slot.ctx_obs.clear();
    for name in visible {
        let x = slot
            .info
            .context
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, x)| *x)
            .ok_or_else(|| ContextualError::MissingValue {
                env: spec.id.clone(),
                name: name.clone(),
                who: who.to_string(),
            })?;
        slot.ctx_obs.push(x as f32);
    }
    Ok(())
}

/// Canonical names of the observed features.
fn visible_names(spec: &EnvSpec, visibility: &Visibility, first: &Slot) -> Result<Vec<String>, ContextualError> {
    match visibility {
        Visibility::Hidden => Ok(Vec::new()),
        Visibility::Visible(Features::All) => Ok(first.info.context.iter().map(|(k, _)| k.clone()).collect()),
        Visibility::Visible(Features::Only(names)) => {
            let mut out: Vec<String> = Vec::with_capacity(names.len());
            for name in names {
                let f = spec.feature(name).ok_or_else(|| {
                    let known = spec.feature_names();
                    ContextualError::UnknownFeature {
                        env: spec.id.clone(),
                        name: name.clone(),
                        hint: did_you_mean(name, known.clone())
                            .map(|s| format!(" (did you mean \"{s}\"?)"))
                            .unwrap_or_default(),
                        valid: known.collect::<Vec<_>>().join(", "),
                    }
                })?;
                if out.contains(&f.name) {
                    return Err(ContextualError::DuplicateFeature {
                        env: spec.id.clone(),
                        name: f.name.clone(),
                    });
                }
                out.push(f.name.clone());
            }
            Ok(out)
        }
    }
}

/// The base (runtime) part of the observation space, the same for every context source: the
/// space at the default context, each component whose bounds move when some feature moves off
/// its default made unbounded.
fn base_space(spec: &EnvSpec, env_options: &EnvOptions) -> Result<Space, ContextualError> {
    let defaults = spec.default_context();
    let who = format!("{} default context", spec.id);
    let mut base = make_env(spec, &defaults, MakeOptions::default(), env_options)
        .map_err(make_err(&who))?
        .observation_space();
    let allow = MakeOptions {
        allow_out_of_bounds: true,
    };
    for f in &spec.features {
        let Some(ctx) = probe_context(spec, &f.name) else {
            continue;
        };
        // A runtime that refuses the probe (e.g. an index past its data) keeps that feature's
        // bounds; the instances it does accept are checked against the space by the tests.
        let Ok(probe) = make_env(spec, &ctx, allow, env_options) else {
            continue;
        };
        if let (Space::Box { low, high, .. }, Space::Box { low: pl, high: ph, .. }) =
            (&mut base, probe.observation_space())
            && low.len() == pl.len()
        {
            for (x, y) in low.iter_mut().zip(&pl) {
                if x.to_bits() != y.to_bits() {
                    *x = f32::NEG_INFINITY;
                }
            }
            for (x, y) in high.iter_mut().zip(&ph) {
                if x.to_bits() != y.to_bits() {
                    *x = f32::INFINITY;
                }
            }
        }
    }
    Ok(base)
}

/// A context that moves `feature` off its default (for probing which bounds depend on it).
fn probe_context(spec: &EnvSpec, feature: &str) -> Option<Context> {
    let f = spec.feature(feature)?;
    let probe = match (f.kind, &f.default) {
        (FeatureType::Bool, Some(Value::Bool(b))) => Value::Bool(!b),
        (FeatureType::Float | FeatureType::Int, d) => {
            let d = match d {
                Some(Value::Number(x)) => *x,
                _ => 1.0,
            };
            Value::Number(d * 2.0 + 1.0)
        }
        _ => return None,
    };
    let mut ctx = spec.default_context();
    ctx.insert(f.name.clone(), probe);
    Some(ctx)
}

impl ContextualEnv {
    /// Build the wrapper. Every set instance (or the fixed context) is checked and built now;
    /// a distribution is checked by name now and sampled at each reset.
    pub fn new(spec: &EnvSpec, source: ContextSource, options: ContextualOptions) -> Result<Self, ContextualError> {
        let (mode, mut slots, labels): (Mode, Vec<Slot>, Vec<String>) = match source {
            ContextSource::Set(set) => {
                if !spec.matches_name(&set.env) {
                    return Err(ContextualError::WrongEnv {
                        set: set.qualified_name(),
                        set_env: set.env.clone(),
                        env: spec.id.clone(),
                    });
                }
                let n = set.instances.len();
                if n == 0 {
                    return Err(ContextualError::EmptySet(set.qualified_name()));
                }
                if let Selection::Static(index) = options.selection
                    && index >= n
                {
                    return Err(ContextualError::StaticOutOfRange {
                        index,
                        set: set.qualified_name(),
                        len: n,
                    });
                }
                let opts = MakeOptions {
                    allow_out_of_bounds: set.provenance.definition.allow_out_of_bounds,
                };
                let mut slots = Vec::with_capacity(n);
                let mut labels = Vec::with_capacity(n);
                for inst in &set.instances {
                    let who = format!("{} instance {}", set.qualified_name(), inst.label());
                    let mut ctx = spec.default_context();
                    ctx.extend(inst.context.iter().map(|(k, v)| (k.clone(), v.clone())));
                    slots.push(build_slot(
                        spec,
                        &ctx,
                        opts,
                        &options.env_options,
                        &who,
                        Some(inst.id),
                        inst.name.clone(),
                    )?);
                    labels.push(who);
                }
                (Mode::Set, slots, labels)
            }
            ContextSource::Fixed(ctx) => {
                let who = format!("{} fixed context", spec.id);
                let opts = MakeOptions {
                    allow_out_of_bounds: options.allow_out_of_bounds,
                };
                let slot = build_slot(spec, &ctx, opts, &options.env_options, &who, None, None)?;
                (Mode::Fixed, vec![slot], vec![who])
            }
            ContextSource::Distribution { name } => {
                let dist = spec.distributions.get(&name).cloned().ok_or_else(|| {
                    let known = spec.distributions.keys().map(String::as_str);
                    ContextualError::UnknownDistribution {
                        env: spec.id.clone(),
                        hint: match did_you_mean(&name, known.clone()) {
                            Some(s) => format!(" (did you mean \"{s}\"?)"),
                            None => format!("; distributions: {}", known.collect::<Vec<_>>().join(", ")),
                        },
                        name: name.clone(),
                    }
                })?;
                // Check the distribution compiles (names, types, bounds) before the first reset.
                sample_distribution(spec, &name, &dist, 1, DEFAULT_SEED)?;
                let who = format!("{} defaults (before the first reset of {name})", spec.id);
                let slot = build_slot(
                    spec,
                    &spec.default_context(),
                    MakeOptions::default(),
                    &options.env_options,
                    &who,
                    None,
                    None,
                )?;
                (Mode::Distribution { name, dist }, vec![slot], vec![who])
            }
        };

        let visible = visible_names(spec, &options.visibility, &slots[0])?;
        for (slot, who) in slots.iter_mut().zip(&labels) {
            fill_visible(spec, slot, &visible, who)?;
        }
        let noise = ObservationNoise::new(spec, &visible, &options.noise)?;
        let (schedules, schedule_bases, schedule_visible) = schedules_for(
            spec,
            &options,
            &mut slots,
            &labels,
            &visible,
            &noise,
            matches!(mode, Mode::Distribution { .. }),
        )?;

        // The space of every source alike (module docs). Where the context sets the observation's
        // length itself (rna_design's state_radius) there is no common space: the first slot's.
        let base_dim = slots[0].env.obs_dim();
        let mut base = base_space(spec, &options.env_options)?;
        if base.flat_dim() != base_dim {
            base = slots[0].env.observation_space();
        }
        let obs_space = if visible.is_empty() {
            base
        } else {
            let Space::Box {
                mut low,
                mut high,
                dtype,
                ..
            } = base
            else {
                return Err(ContextualError::NotBox { env: spec.id.clone() });
            };
            for (k, name) in visible.iter().enumerate() {
                let f = spec.feature(name).expect("visible names are canonical spec features");
                let (mut lo, mut hi) = match (f.kind, f.bounds) {
                    (FeatureType::Bool, [None, None]) => (0.0f32, 1.0f32),
                    (_, [lo, hi]) => (
                        lo.map_or(f32::NEG_INFINITY, |x| x as f32),
                        hi.map_or(f32::INFINITY, |x| x as f32),
                    ),
                };
                if noise.stds()[k] > 0.0 {
                    // A Gaussian measurement can land anywhere.
                    (lo, hi) = (f32::NEG_INFINITY, f32::INFINITY);
                }
                low.push(lo);
                high.push(hi);
            }
            Space::Box {
                shape: vec![low.len()],
                low,
                high,
                dtype,
            }
        };

        let current = match (&mode, options.selection) {
            (Mode::Set, Selection::Static(i)) => i,
            _ => 0,
        };
        let id = slots[0].env.id();
        let slots_first_ctx_obs = slots[current].ctx_obs.clone();
        let kind = match &mode {
            Mode::Set => ScheduleKind::Set {
                n: slots.len(),
                selection: options.selection,
            },
            Mode::Fixed => ScheduleKind::Fixed,
            Mode::Distribution { .. } => ScheduleKind::Distribution,
        };
        Ok(ContextualEnv {
            spec: spec.clone(),
            id,
            mode,
            slots,
            current,
            visible,
            base_dim,
            obs_space,
            // Both seeded with DEFAULT_SEED until the first seeded reset.
            schedule: ContextSchedule::new(kind),
            previous: None,
            retired: None,
            noise,
            observed: slots_first_ctx_obs,
            env_options: options.env_options.clone(),
            resets: 0,
            schedules,
            schedule_bases,
            schedule_visible,
            pending: None,
            fixed_original: None,
            allow_out_of_bounds: options.allow_out_of_bounds,
        })
    }

    /// Whether some visible feature is observed with noise (and when the noise is redrawn).
    pub fn noise(&self) -> Option<NoiseRedraw> {
        self.noise.redraw()
    }

    /// What the agent observes of the visible features now (equal to the true values without noise).
    pub fn observed_context(&self) -> &[f32] {
        &self.observed
    }

    /// The current episode's context (before the first reset: the initial slot's).
    pub fn context_info(&self) -> &ContextInfo {
        &self.slots[self.current].info
    }

    /// The context of the episode before the latest reset (`None` before the second reset):
    /// in same-step autoreset, the episode that just ended.
    pub fn previous_context_info(&self) -> Option<ContextInfo> {
        let (slot, episode) = self.previous?;
        let mut info = match (&self.mode, &self.retired) {
            (Mode::Distribution { .. } | Mode::Fixed, Some(retired)) => retired.clone(),
            _ => self.slots[slot].info.clone(),
        };
        info.episode = episode;
        Some(info)
    }

    /// Number of instances (1 for fixed contexts and distributions).
    pub fn num_instances(&self) -> usize {
        self.slots.len()
    }

    /// Position of the current instance in the set (0 for fixed contexts and distributions).
    pub fn instance_index(&self) -> usize {
        self.current
    }

    /// Canonical names of the features appended to the observation, in order.
    pub fn visible_features(&self) -> &[String] {
        &self.visible
    }

    /// Length of the runtime's own observation (the context follows it).
    pub fn base_obs_dim(&self) -> usize {
        self.base_dim
    }

    /// The runtime of the current episode.
    pub fn inner(&self) -> &SpecEnv {
        &self.slots[self.current].env
    }

    /// Whether some feature changes within episodes ([`super::schedules`]).
    pub fn has_schedules(&self) -> bool {
        !self.schedules.is_empty()
    }

    /// The scheduled features' current values (canonical names), as in the context info.
    pub fn scheduled_values(&self) -> impl Iterator<Item = (&str, f64)> + '_ {
        self.schedules
            .current()
            .map(|(i, x)| (self.spec.features[i].name.as_str(), x))
    }

    /// Number of resets so far.
    pub fn resets(&self) -> u64 {
        self.resets
    }

    /// `reset` returning the wrapper's context info.
    pub fn reset_with_info(&mut self, seed: Option<u64>) -> Result<(Vec<f32>, ContextInfo), EnvError> {
        let mut obs = vec![0.0; self.obs_dim()];
        self.reset_into(seed, &mut obs)?;
        Ok((obs, self.context_info().clone()))
    }

    /// `step` returning the wrapper's context info.
    pub fn step_with_info(&mut self, action: &Action) -> Result<(Step, ContextInfo), EnvError> {
        let mut obs = vec![0.0; self.obs_dim()];
        let out = self.step_into(action, &mut obs)?;
        Ok((
            Step {
                obs,
                reward: out.reward,
                terminated: out.terminated,
                truncated: out.truncated,
                info: Info::new(),
            },
            self.context_info().clone(),
        ))
    }

    fn write_context(&self, obs: &mut [f32]) {
        obs[self.base_dim..].copy_from_slice(&self.observed);
    }

    fn info_map(&self) -> Info {
        let ci = self.context_info();
        let mut info = Info::new();
        if let Some(id) = ci.instance_id {
            info.insert("instance_id".into(), id as f64);
        }
        if let Some(seed) = ci.context_seed {
            // Exact below 2^53 only; the exact seed is in `ContextInfo::context_seed`.
            info.insert("context_seed".into(), seed as f64);
        }
        info.insert("episode".into(), ci.episode as f64);
        for (k, v) in &ci.context {
            info.insert(format!("context.{k}"), *v);
        }
        if self.noise.redraw().is_some() {
            for (k, v) in self.visible.iter().zip(&self.observed) {
                info.insert(format!("{OBSERVED_PREFIX}{k}"), f64::from(*v));
            }
        }
        info
    }

    /// `reset_into`, playing instance `index` of the set instead of the one the selection picks
    /// (Gymnasium's `reset(options={"instance": i})`). Everything else is as in `reset_into`:
    /// the streams advance as they would (the runtime resets with the same seed), and round-robin
    /// selection continues with `index + 1` (random selection draws on, static stays put). An index outside the set, or a source that is not a
    /// set, is an [`EnvError::Context`] naming the problem; nothing is reset then.
    pub fn reset_instance_into(&mut self, seed: Option<u64>, index: usize, obs: &mut [f32]) -> Result<(), EnvError> {
        self.check_instance(index)?;
        self.reset_impl(seed, Some(index), obs)
    }

    /// The next episode plays `context` (missing features at their defaults) instead of the
    /// source's own pick: a curriculum's choice. The episodes after it return to the source (the
    /// fixed context, or fresh draws of the distribution). Checked and built now, so a context
    /// outside the bounds (unless the environment was made with `allow_out_of_bounds`), or that a
    /// schedule would take out of them, is an error naming it, and nothing changes then. Fixed
    /// contexts and distributions only: a set's instances are chosen with
    /// [`ContextualEnv::reset_instance_into`].
    pub fn set_next_context(&mut self, context: &Context) -> Result<(), ContextualError> {
        if let Mode::Set = self.mode {
            return Err(ContextualError::Curriculum(format!(
                "{}: a curriculum chooses contexts for a fixed context or a distribution; this environment \
                 plays an instance set (choose its instances with reset(options={{\"instance\": i}}))",
                self.spec.id
            )));
        }
        let who = format!("{} next context", self.spec.id);
        let mut ctx = self.spec.default_context();
        ctx.extend(context.iter().map(|(k, v)| (k.clone(), v.clone())));
        let opts = MakeOptions {
            allow_out_of_bounds: self.allow_out_of_bounds,
        };
        let mut slot = build_slot(&self.spec, &ctx, opts, &self.env_options, &who, None, None)?;
        fill_visible(&self.spec, &mut slot, &self.visible, &who)?;
        if !self.schedules.is_empty() {
            self.schedules
                .check_reach(&slot.info.context, &who)
                .map_err(|e| ContextualError::Schedule(format!("{}: {e}", self.spec.id)))?;
        }
        self.pending = Some(slot);
        Ok(())
    }

    /// Whether [`ContextualEnv::reset_instance_into`] can play instance `index` (the error it
    /// would return otherwise).
    pub fn check_instance(&self, index: usize) -> Result<(), EnvError> {
        let n = self.slots.len();
        let message = match self.mode {
            Mode::Set if index < n => return Ok(()),
            Mode::Set => format!(
                "instance {index} is outside the set: it has {n} instance(s), 0..={}",
                n - 1
            ),
            Mode::Fixed => format!(
                "an instance ({index}) was asked for, but this environment plays one fixed context, not an instance set"
            ),
            Mode::Distribution { ref name, .. } => format!(
                "an instance ({index}) was asked for, but this environment draws its contexts from the distribution {name}, not an instance set"
            ),
        };
        Err(EnvError::Context { env: self.id, message })
    }

    /// A reset (see [`Env::reset_into`]); `forced`: the instance to play instead of the
    /// selection's pick (checked by [`ContextualEnv::reset_instance_into`]).
    fn reset_impl(&mut self, seed: Option<u64>, forced: Option<usize>, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(self.id, obs, self.obs_dim())?;
        if let Some(s) = seed {
            self.noise.seed(s);
        }
        let plan = self.schedule.next(seed);
        if let (
            Some(i),
            ScheduleKind::Set {
                selection: Selection::RoundRobin,
                ..
            },
        ) = (forced, self.schedule.kind())
        {
            self.schedule.continue_after(i);
        }
        let episode = self.resets;
        let finished = (self.current, self.slots[self.current].info.episode);
        let index = match (plan.pick, &self.mode) {
            (Pick::Instance(i), _) => forced.unwrap_or(i),
            (Pick::Draw { context_seed }, Mode::Distribution { name, dist }) => {
                let slot = draw_slot(&self.spec, name, dist, &self.visible, &self.env_options, context_seed)
                    .map_err(|message| EnvError::Context { env: self.id, message })?;
                self.retired = Some(std::mem::replace(&mut self.slots[0], slot).info);
                0
            }
            _ => 0,
        };
        // A curriculum's choice plays this episode (a distribution's draw above still advanced
        // its stream, so the seeds of later episodes do not depend on the curriculum).
        if let Some(chosen) = self.pending.take() {
            let before = std::mem::replace(&mut self.slots[0], chosen);
            if let Mode::Fixed = self.mode {
                self.retired = Some(before.info.clone());
                self.fixed_original.get_or_insert(before);
            }
        } else if let Some(original) = self.fixed_original.take() {
            self.retired = Some(std::mem::replace(&mut self.slots[0], original).info);
        } else if let Mode::Fixed = self.mode {
            self.retired = None;
        }
        if episode > 0 {
            self.previous = Some(finished);
        }
        let runtime_seed = plan.runtime_seed;
        self.resets += 1;
        self.current = index;
        if !self.schedules.is_empty() {
            self.start_schedules(seed, index)?;
        }
        let slot = &mut self.slots[index];
        slot.info.episode = episode;
        slot.env.reset_into(runtime_seed, &mut obs[..self.base_dim])?;
        self.noise.observe(&self.slots[index].ctx_obs, &mut self.observed);
        self.write_context(obs);
        Ok(())
    }
}

impl ContextualEnv {
    /// A new episode in slot `index`: its own values back in place (sets and fixed contexts; a
    /// distribution's draw is checked against the schedules' reach instead), the walks' stream
    /// seeded, the runtime given the values of step 0.
    fn start_schedules(&mut self, seed: Option<u64>, index: usize) -> Result<(), EnvError> {
        let err = |message: String| EnvError::Context { env: self.id, message };
        if let Some(s) = seed {
            self.schedules.seed(s);
        }
        let slot = &mut self.slots[index];
        match self.mode {
            Mode::Distribution { .. } => {
                let who = format!("draw with seed {}", slot.info.context_seed.unwrap_or_default());
                self.schedules.check_reach(&slot.info.context, &who).map_err(err)?;
            }
            // A curriculum's context (checked when it was set): its own values.
            Mode::Fixed if self.fixed_original.is_some() => {}
            _ => {
                for ((i, _), base) in self.schedules.current().zip(&self.schedule_bases[index]) {
                    slot.info.context[i].1 = *base;
                }
            }
        }
        let values = self.schedules.start(&slot.info.context);
        apply_scheduled(&mut slot.env, values).map_err(err)?;
        self.show_scheduled_values(index, false);
        Ok(())
    }

    /// After a step: the schedules' next values into the runtime, the info and the observation.
    fn advance_schedules(&mut self) -> Result<(), EnvError> {
        let index = self.current;
        if let Some(values) = self.schedules.advance() {
            apply_scheduled(&mut self.slots[index].env, values)
                .map_err(|message| EnvError::Context { env: self.id, message })?;
            self.show_scheduled_values(index, true);
        }
        Ok(())
    }

    /// The scheduled features' current values in the slot's info and visible context (and, after
    /// a step, in what the agent observes: scheduled features carry no noise).
    fn show_scheduled_values(&mut self, index: usize, observed: bool) {
        let slot = &mut self.slots[index];
        for ((i, x), vis) in self.schedules.current().zip(&self.schedule_visible) {
            slot.info.context[i].1 = x;
            if let Some(k) = *vis {
                slot.ctx_obs[k] = x as f32;
                if observed {
                    self.observed[k] = x as f32;
                }
            }
        }
    }
}

fn apply_scheduled(env: &mut SpecEnv, values: &[(String, f64)]) -> Result<(), String> {
    match env.inner_mut().set_features(values) {
        Some(r) => r.map_err(|e| e.to_string()),
        None => Err("the runtime does not take new values within an episode".into()),
    }
}

/// The schedules of `options`, checked: the runtime takes new values mid-episode, scheduled
/// visible features carry no noise, and every instance's (or the fixed context's) episode stays
/// in the bounds. Also each slot's own values of the scheduled features and where they sit among
/// the visible features.
#[allow(clippy::type_complexity)]
fn schedules_for(
    spec: &EnvSpec,
    options: &ContextualOptions,
    slots: &mut [Slot],
    labels: &[String],
    visible: &[String],
    noise: &ObservationNoise,
    drawn: bool,
) -> Result<(Schedules, Vec<Vec<f64>>, Vec<Option<usize>>), ContextualError> {
    let schedules = Schedules::new(spec, &options.schedules).map_err(ContextualError::Schedule)?;
    if schedules.is_empty() {
        return Ok((schedules, Vec::new(), Vec::new()));
    }
    let mut probe = slots[0].env.clone();
    if probe.inner_mut().set_features(&[]).is_none() {
        return Err(ContextualError::Schedule(format!(
            "{}: its runtime fixes the context when it is built, so no feature can change within an episode \
             (schedules need a runtime that implements Runtime::set_features)",
            spec.id
        )));
    }
    let visible_at: Vec<Option<usize>> = schedules
        .current()
        .map(|(i, _)| visible.iter().position(|v| *v == spec.features[i].name))
        .collect();
    for k in visible_at.iter().flatten() {
        if noise.stds()[*k] > 0.0 {
            return Err(ContextualError::Schedule(format!(
                "{}: \"{}\" is both scheduled and observed with noise; give it one of the two",
                spec.id, visible[*k]
            )));
        }
    }
    let mut bases = Vec::with_capacity(slots.len());
    for (slot, who) in slots.iter().zip(labels) {
        if !drawn {
            schedules
                .check_reach(&slot.info.context, who)
                .map_err(|e| ContextualError::Schedule(format!("{}: {e}", spec.id)))?;
        }
        bases.push(schedules.current().map(|(i, _)| slot.info.context[i].1).collect());
    }
    Ok((schedules, bases, visible_at))
}

/// A fresh slot for one draw of a distribution (reset time only; allocates).
fn draw_slot(
    spec: &EnvSpec,
    name: &str,
    dist: &Distribution,
    visible: &[String],
    env_options: &EnvOptions,
    context_seed: u64,
) -> Result<Slot, String> {
    let ctx = drawn_context(spec, name, dist, context_seed)
        .map_err(|e| format!("drawing from {name} with seed {context_seed}: {e}"))?;
    let who = format!("{name} draw with seed {context_seed}");
    let mut slot =
        build_slot(spec, &ctx, MakeOptions::default(), env_options, &who, None, None).map_err(|e| e.to_string())?;
    fill_visible(spec, &mut slot, visible, &who).map_err(|e| e.to_string())?;
    slot.info.context_seed = Some(context_seed);
    Ok(slot)
}

impl Env for ContextualEnv {
    fn id(&self) -> &'static str {
        self.id
    }
    fn obs_dim(&self) -> usize {
        self.base_dim + self.visible.len()
    }
    fn state_dim(&self) -> usize {
        self.slots[self.current].env.state_dim()
    }
    fn observation_space(&self) -> Space {
        self.obs_space.clone()
    }
    fn action_space(&self) -> Space {
        self.slots[self.current].env.action_space()
    }

    fn reset_into(&mut self, seed: Option<u64>, obs: &mut [f32]) -> Result<(), EnvError> {
        self.reset_impl(seed, None, obs)
    }

    #[inline]
    fn step_into(&mut self, action: &Action, obs: &mut [f32]) -> Result<StepOutcome, EnvError> {
        check_obs_len(self.id, obs, self.base_dim + self.visible.len())?;
        let out = self.slots[self.current]
            .env
            .step_into(action, &mut obs[..self.base_dim])?;
        if !self.schedules.is_empty() {
            self.advance_schedules()?;
        }
        self.noise
            .after_step(&self.slots[self.current].ctx_obs, &mut self.observed);
        self.write_context(obs);
        Ok(out)
    }

    fn observe_into(&self, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(self.id, obs, self.obs_dim())?;
        self.slots[self.current].env.observe_into(&mut obs[..self.base_dim])?;
        self.write_context(obs);
        Ok(())
    }

    /// The runtime's observation at float64 precision; the context part is what the float32
    /// observation carries, widened.
    fn observe_f64_into(&self, obs: &mut [f64]) -> Result<(), EnvError> {
        check_obs_len(self.id, obs, self.obs_dim())?;
        self.slots[self.current]
            .env
            .observe_f64_into(&mut obs[..self.base_dim])?;
        for (o, x) in obs[self.base_dim..].iter_mut().zip(&self.observed) {
            *o = f64::from(*x);
        }
        Ok(())
    }

    fn state(&self) -> Vec<f64> {
        self.slots[self.current].env.state()
    }

    fn set_state(&mut self, state: &[f64]) -> Result<(), EnvError> {
        self.slots[self.current].env.set_state(state)
    }

    /// The info of Gymnasium's `reset`/`step`: `instance_id` (sets), `context_seed` (distributions),
    /// `episode` and `context.<feature>` for every feature. A failed distribution draw leaves
    /// `reset`'s observation zeroed; use [`ContextualEnv::reset_with_info`] to see the error.
    fn info(&self) -> Info {
        self.info_map()
    }

    fn outcome(&self) -> Option<&'static str> {
        self.slots[self.current].env.outcome()
    }

    fn render(&self) -> Option<crate::pixels::Frame> {
        self.slots[self.current].env.render()
    }
}
