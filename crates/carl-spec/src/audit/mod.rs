//! The sensitivity audit: is each feature's `affects` claim true of the runtime?
//!
//! For every context feature the audit builds the environment under the default context and under
//! a few perturbed values of that one feature ([`probes::perturbed_values`]), feeds both the same
//! base states ([`probes::base_states`]) and the same actions ([`probes::probe_actions`]), and
//! compares, with exact equality (no tolerance: the runtimes are deterministic):
//!
//! * **dynamics** — the internal state (`Env::state`) after one step;
//! * **reward**, **termination** — the reward and `terminated` flag of the same transition. A
//!   difference counts as a *direct* effect only when both next states are identical; when the next
//!   states differ, a changed reward or flag may be nothing but a consequence of the changed
//!   dynamics (Acrobot's reward is −1 until the tip reaches the line), and is recorded as *indirect*;
//! * **initial_state** — the state after `reset(seed)` for several seeds;
//! * **observation** — the observation of the same internal state (`set_state` + `observe_into`);
//! * **task_generation** — not applicable to runtimes without a task generator (reported `n/a`).
//!
//! Verdicts: claimed and measured → ok; claimed but never measured → [`Verdict::MissingEffect`];
//! measured but not claimed → [`Verdict::UndeclaredEffect`]. For reward and termination an
//! *indirect* change is consistent with either claim: it is explained by the dynamics (whose claim
//! is checked on its own), and a direct effect that shows only together with a dynamics change
//! (Pendulum's torque clipping changes both the next state and the action cost) cannot be told
//! apart from it. A claim of reward/termination with no change at all is still `MissingEffect`.
//!
//! The features are probed in parallel, one thread per core; the report does not depend on it.

pub mod probes;

use std::sync::atomic::{AtomicUsize, Ordering};

use serde::Serialize;

use crate::envs::registry::{Context, EnvOptions, MakeError, MakeOptions, has_runtime, lookup, make_env};
use crate::envs::runtime::AnyEnv;
use crate::envs::{Action, Env, EnvError};
use crate::spec::model::{Effect, EnvSpec, Feature, FeatureType, Value};

/// How much probing the audit does: declared per runtime in the environment table.
pub use crate::envs::registry::AuditProfile as AuditOptions;

/// What the measurement found for one (feature, effect).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Measured {
    /// Some probe changed.
    Changed,
    /// Reward/termination changed, but only on transitions whose next state also changed.
    ViaDynamics,
    /// No probe changed.
    Unchanged,
    /// The effect cannot be measured on this runtime.
    NotApplicable,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    Ok,
    /// Claimed, but no probe changed.
    MissingEffect,
    /// Changed, but not claimed.
    UndeclaredEffect,
    NotApplicable,
}

impl Verdict {
    pub fn is_contradiction(self) -> bool {
        matches!(self, Verdict::MissingEffect | Verdict::UndeclaredEffect)
    }
    pub fn as_str(self) -> &'static str {
        match self {
            Verdict::Ok => "ok",
            Verdict::MissingEffect => "MISSING-EFFECT",
            Verdict::UndeclaredEffect => "UNDECLARED-EFFECT",
            Verdict::NotApplicable => "n/a",
        }
    }
}

/// One (feature, effect) cell of the audit.
#[derive(Debug, Clone, Serialize)]
pub struct EffectResult {
    pub effect: Effect,
    pub claimed: bool,
    pub measured: Measured,
    pub verdict: Verdict,
    /// Largest absolute difference over the direct probes (1 for a flipped flag; infinite when one
    /// side became non-finite, serialised as `null`).
    pub max_abs_diff: f64,
    /// The perturbed value at which `max_abs_diff` was seen.
    pub at_value: Option<f64>,
    /// Direct probes compared (for reward/termination: transitions with identical next states).
    pub compared: usize,
    /// Direct probes that differed.
    pub differing: usize,
    /// Reward/termination: probes that differed on transitions whose next state also differed.
    pub via_dynamics: usize,
    /// Largest absolute difference over those.
    pub via_dynamics_max_abs_diff: f64,
}

/// The audit of one feature.
#[derive(Debug, Clone, Serialize)]
pub struct FeatureAudit {
    pub name: String,
    pub default: Option<f64>,
    pub bounds: [Option<f64>; 2],
    /// The perturbed values tried.
    pub values: Vec<f64>,
    pub claimed: Vec<Effect>,
    /// One entry per effect, in [`Effect::ALL`] order (empty when the feature was skipped).
    pub effects: Vec<EffectResult>,
    /// Why the feature was skipped, if it was.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub skipped: Option<String>,
}

impl FeatureAudit {
    pub fn effect(&self, effect: Effect) -> Option<&EffectResult> {
        self.effects.iter().find(|e| e.effect == effect)
    }
}

/// The probes every feature was measured with.
#[derive(Debug, Clone, Serialize)]
pub struct ProbeSummary {
    pub base_states: usize,
    pub actions: usize,
    pub reset_seeds: u64,
    pub options: AuditOptions,
}

/// One contradiction between a claim and a measurement.
#[derive(Debug, Clone, Serialize)]
pub struct Contradiction {
    pub feature: String,
    pub effect: Effect,
    pub verdict: Verdict,
    pub message: String,
}

/// The audit of one environment.
#[derive(Debug, Clone, Serialize)]
pub struct AuditReport {
    pub env: String,
    pub probes: ProbeSummary,
    pub features: Vec<FeatureAudit>,
    pub contradictions: Vec<Contradiction>,
    pub passed: bool,
}

impl AuditReport {
    pub fn feature(&self, name: &str) -> Option<&FeatureAudit> {
        self.features.iter().find(|f| f.name == name)
    }
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum AuditError {
    #[error("environment \"{0}\" has a spec but no runtime; runtimes exist for: {list}", list = crate::envs::registry::ids_text())]
    NoRuntime(String),
    #[error("{env}: cannot build the environment with {feature} = {value}: {source}")]
    Make {
        env: String,
        feature: String,
        value: String,
        source: Box<MakeError>,
    },
    #[error("{env}: the runtime refused a probe: {source}")]
    Env { env: String, source: EnvError },
}

/// Audit `spec` with the probes its registry entry declares.
pub fn audit(spec: &EnvSpec) -> Result<AuditReport, AuditError> {
    audit_with(spec, &lookup(&spec.id).map(|r| r.audit).unwrap_or_default())
}

/// Per-effect accumulator.
#[derive(Debug, Clone, Default)]
struct Acc {
    max: f64,
    at: Option<f64>,
    compared: usize,
    differing: usize,
    via: usize,
    via_max: f64,
}

impl Acc {
    fn direct(&mut self, diff: f64, value: f64) {
        self.compared += 1;
        if diff != 0.0 {
            self.differing += 1;
            if self.at.is_none() || diff > self.max {
                self.max = diff;
                self.at = Some(value);
            }
        }
    }
    fn via_dynamics(&mut self, diff: f64) {
        if diff != 0.0 {
            self.via += 1;
            self.via_max = self.via_max.max(diff);
        }
    }
}

/// `|a - b|` with exact equality meaning 0 (`0.0 == -0.0`, and two NaNs count as equal) and a
/// finite/non-finite mismatch meaning infinity.
fn abs_diff(a: f64, b: f64) -> f64 {
    if a == b || (a.is_nan() && b.is_nan()) {
        0.0
    } else {
        let d = (a - b).abs();
        if d.is_nan() { f64::INFINITY } else { d }
    }
}

fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    if a.len() != b.len() {
        return f64::INFINITY;
    }
    a.iter().zip(b).map(|(x, y)| abs_diff(*x, *y)).fold(0.0, f64::max)
}

fn max_abs_diff_f32(a: &[f32], b: &[f32]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| abs_diff(f64::from(*x), f64::from(*y)))
        .fold(0.0, f64::max)
}

fn feature_value(f: &Feature, x: f64) -> Value {
    if f.kind == FeatureType::Bool {
        Value::Bool(x != 0.0)
    } else {
        Value::Number(x)
    }
}

/// Audit `spec` against its runtime.
pub fn audit_with(spec: &EnvSpec, opts: &AuditOptions) -> Result<AuditReport, AuditError> {
    if !has_runtime(&spec.id) {
        return Err(AuditError::NoRuntime(spec.id.clone()));
    }
    let env_err = |source| AuditError::Env {
        env: spec.id.clone(),
        source,
    };
    // A feature that acts only with an option (`requires_option`) is audited with that option
    // set, against the defaults under the same option; the others with the default options.
    let build = |ctx: &Context, options: &EnvOptions, feature: &str, value: String| -> Result<AnyEnv, AuditError> {
        make_env(spec, ctx, MakeOptions::default(), options)
            .map(|e| e.into_inner())
            .map_err(|source| AuditError::Make {
                env: spec.id.clone(),
                feature: feature.to_string(),
                value,
                source: Box::new(source),
            })
    };
    let option_sets = |option: Option<&String>| -> EnvOptions {
        option
            .map(|o| EnvOptions::from([(o.clone(), crate::spec::model::Value::Bool(true))]))
            .unwrap_or_default()
    };
    let base = build(&Context::new(), &EnvOptions::new(), "(defaults)", "-".into())?;
    let states = probes::base_states(&base, opts).map_err(env_err)?;
    let actions = probes::probe_actions(&base.action_space());
    let reference = respond(&base, &states, &actions, opts).map_err(env_err)?;
    // Base states and reference answers under each option some feature requires.
    let mut with_option: Vec<(String, Vec<Vec<f64>>, Responses)> = Vec::new();
    for o in spec.features.iter().filter_map(|f| f.requires_option.as_ref()) {
        if with_option.iter().any(|(name, ..)| name == o) {
            continue;
        }
        let env = build(
            &Context::new(),
            &option_sets(Some(o)),
            &format!("(defaults, option {o})"),
            "-".into(),
        )?;
        let states = probes::base_states(&env, opts).map_err(env_err)?;
        let answers = respond(&env, &states, &actions, opts).map_err(env_err)?;
        with_option.push((o.clone(), states, answers));
    }

    // Each feature's probes are independent: they run on one thread per core, and the report
    // is the same as one feature after another.
    let audit_feature = |f: &Feature| -> Result<FeatureAudit, AuditError> {
        let values = probes::perturbed_values(f);
        let mut fa = FeatureAudit {
            name: f.name.clone(),
            default: f.default_f64(),
            bounds: f.bounds,
            values: values.clone(),
            claimed: f.affects.clone(),
            effects: Vec::new(),
            skipped: probes::unauditable_reason(f),
        };
        if fa.skipped.is_none() && values.is_empty() {
            fa.skipped = Some("no value inside the bounds differs from the default".into());
        }
        if fa.skipped.is_some() {
            return Ok(fa);
        }
        let options = option_sets(f.requires_option.as_ref());
        let (states, reference) = match &f.requires_option {
            Some(o) => with_option
                .iter()
                .find(|(name, ..)| name == o)
                .map(|(_, s, r)| (s, r))
                .unwrap_or((&states, &reference)),
            None => (&states, &reference),
        };
        let mut accs = Accs::default();
        for &x in &values {
            let ctx = Context::from([(f.name.clone(), feature_value(f, x))]);
            let pert = build(&ctx, &options, &f.name, x.to_string())?;
            let answers = respond(&pert, states, &actions, opts).map_err(env_err)?;
            compare(reference, &answers, x, &mut accs);
        }
        fa.effects = Effect::ALL
            .iter()
            .map(|&effect| judge(f, effect, accs.take(effect)))
            .collect();
        Ok(fa)
    };
    let features = ordered_map(&spec.features, audit_feature)
        .into_iter()
        .collect::<Result<Vec<_>, _>>()?;

    let contradictions = contradictions(&features, states.len(), actions.len(), opts);
    Ok(AuditReport {
        env: spec.id.clone(),
        probes: ProbeSummary {
            base_states: states.len(),
            actions: actions.len(),
            reset_seeds: opts.reset_seeds,
            options: *opts,
        },
        passed: contradictions.is_empty(),
        features,
        contradictions,
    })
}

/// `f` of each item, in the items' order, computed on up to one thread per core (the calling
/// thread is one of them).
fn ordered_map<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    let workers = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .clamp(1, items.len().max(1));
    let next = AtomicUsize::new(0);
    let work = || {
        let mut done = Vec::new();
        loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            let Some(item) = items.get(i) else { return done };
            done.push((i, f(item)));
        }
    };
    let mut results = std::thread::scope(|s| {
        let helpers: Vec<_> = (1..workers).map(|_| s.spawn(work)).collect();
        let mut results = work();
        for h in helpers {
            results.extend(h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)));
        }
        results
    });
    results.sort_by_key(|(i, _)| *i);
    results.into_iter().map(|(_, r)| r).collect()
}

/// Everything an environment answered to the probes.
struct Responses {
    /// Observation of each base state.
    obs: Vec<Vec<f32>>,
    /// Per (base state, action), state-major: next state, reward, terminated.
    steps: Vec<(Vec<f64>, f64, bool)>,
    /// State after `reset(seed)` for each seed.
    initial: Vec<Vec<f64>>,
}

/// Run every probe once on `env`.
fn respond(env: &AnyEnv, states: &[Vec<f64>], actions: &[Action], opts: &AuditOptions) -> Result<Responses, EnvError> {
    let mut env = env.clone();
    let mut obs = vec![0.0f32; env.obs_dim()];
    let mut r = Responses {
        obs: Vec::with_capacity(states.len()),
        steps: Vec::with_capacity(states.len() * actions.len()),
        initial: Vec::new(),
    };
    for s in states {
        env.set_state(s)?;
        env.observe_into(&mut obs)?;
        r.obs.push(obs.clone());
        for action in actions {
            env.set_state(s)?;
            let out = env.step_into(action, &mut obs)?;
            r.steps.push((env.state(), out.reward, out.terminated));
        }
    }
    for seed in 0..opts.reset_seeds {
        env.reset_into(Some(seed), &mut obs)?;
        r.initial.push(env.state());
    }
    Ok(r)
}

/// Per-effect accumulators of one feature.
#[derive(Default)]
struct Accs {
    dynamics: Acc,
    reward: Acc,
    termination: Acc,
    initial_state: Acc,
    observation: Acc,
}

impl Accs {
    fn take(&mut self, effect: Effect) -> Acc {
        match effect {
            Effect::Dynamics => std::mem::take(&mut self.dynamics),
            Effect::Reward => std::mem::take(&mut self.reward),
            Effect::Termination => std::mem::take(&mut self.termination),
            Effect::InitialState => std::mem::take(&mut self.initial_state),
            Effect::Observation => std::mem::take(&mut self.observation),
            Effect::TaskGeneration => Acc::default(),
        }
    }
}

/// Compare the default env's responses with those under `feature = value`.
fn compare(base: &Responses, pert: &Responses, value: f64, accs: &mut Accs) {
    for (a, b) in base.obs.iter().zip(&pert.obs) {
        accs.observation.direct(max_abs_diff_f32(a, b), value);
    }
    for ((sa, ra, ta), (sb, rb, tb)) in base.steps.iter().zip(&pert.steps) {
        let dyn_diff = max_abs_diff(sa, sb);
        accs.dynamics.direct(dyn_diff, value);
        let r_diff = abs_diff(*ra, *rb);
        let t_diff = if ta == tb { 0.0 } else { 1.0 };
        if dyn_diff == 0.0 {
            accs.reward.direct(r_diff, value);
            accs.termination.direct(t_diff, value);
        } else {
            accs.reward.via_dynamics(r_diff);
            accs.termination.via_dynamics(t_diff);
        }
    }
    for (a, b) in base.initial.iter().zip(&pert.initial) {
        accs.initial_state.direct(max_abs_diff(a, b), value);
    }
}

fn judge(f: &Feature, effect: Effect, acc: Acc) -> EffectResult {
    let claimed = f.affects(effect);
    let measured = if effect == Effect::TaskGeneration {
        Measured::NotApplicable
    } else if acc.differing > 0 {
        Measured::Changed
    } else if acc.via > 0 {
        Measured::ViaDynamics
    } else {
        Measured::Unchanged
    };
    let verdict = match (claimed, measured) {
        (_, Measured::NotApplicable) => Verdict::NotApplicable,
        (true, Measured::Unchanged) => Verdict::MissingEffect,
        (false, Measured::Changed) => Verdict::UndeclaredEffect,
        _ => Verdict::Ok,
    };
    EffectResult {
        effect,
        claimed,
        measured,
        verdict,
        max_abs_diff: acc.max,
        at_value: acc.at,
        compared: acc.compared,
        differing: acc.differing,
        via_dynamics: acc.via,
        via_dynamics_max_abs_diff: acc.via_max,
    }
}

fn probe_text(effect: Effect, n_states: usize, n_actions: usize, opts: &AuditOptions) -> String {
    match effect {
        Effect::InitialState => format!("{} reset seeds", opts.reset_seeds),
        Effect::Observation => format!("{n_states} states"),
        _ => format!("{n_states} states × {n_actions} actions"),
    }
}

fn contradictions(
    features: &[FeatureAudit],
    n_states: usize,
    n_actions: usize,
    opts: &AuditOptions,
) -> Vec<Contradiction> {
    let mut out = Vec::new();
    for f in features {
        let values = f.values.iter().map(|v| format_num(*v)).collect::<Vec<_>>().join(", ");
        for e in &f.effects {
            let what = match e.effect {
                Effect::Dynamics => "the next state",
                Effect::Reward => "the reward",
                Effect::Termination => "the termination flag",
                Effect::InitialState => "the initial state",
                Effect::Observation => "the observation of a state",
                Effect::TaskGeneration => "the generated task",
            };
            let probes = probe_text(e.effect, n_states, n_actions, opts);
            let message = match e.verdict {
                Verdict::MissingEffect => format!(
                    "{} claims {} but changing it never changed {what} (values {values}; {probes})",
                    f.name,
                    e.effect.as_str()
                ),
                Verdict::UndeclaredEffect => format!(
                    "{} changes {what} (max |Δ| {} at {} = {}, {}/{} probes) but does not claim {}",
                    f.name,
                    format_num(e.max_abs_diff),
                    f.name,
                    e.at_value.map_or("?".into(), format_num),
                    e.differing,
                    e.compared,
                    e.effect.as_str()
                ),
                _ => continue,
            };
            out.push(Contradiction {
                feature: f.name.clone(),
                effect: e.effect,
                verdict: e.verdict,
                message,
            });
        }
    }
    out
}

/// Compact number formatting for reports: up to 4 significant digits.
pub fn format_num(x: f64) -> String {
    if x.is_infinite() {
        return if x > 0.0 { "inf".into() } else { "-inf".into() };
    }
    if x.is_nan() {
        return "nan".into();
    }
    let ax = x.abs();
    if x == 0.0 || (1e-3..1e5).contains(&ax) {
        let decimals = if x == 0.0 {
            0
        } else {
            (3 - ax.log10().floor() as i32).max(0) as usize
        };
        let s = format!("{x:.decimals$}");
        let s = if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.')
        } else {
            &s
        };
        if s == "-0" { "0".into() } else { s.to_string() }
    } else {
        format!("{:.3e}", x)
    }
}
