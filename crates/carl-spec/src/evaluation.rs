//! Evaluate a policy on every instance of a frozen set (a distribution's draws, a fixed context):
//! the engine of `carl-spec evaluate`, and of the named experiments on top of it
//! ([`crate::experiments::landing_in_space`]).
//!
//! * **Jobs.** An evaluation is a list of [`Job`]s: (instance, episode, reset seed). A set's job
//!   plays its instance whatever the seed ([`ContextualEnv::reset_instance_into`]); a
//!   distribution's job `k` resets with its seed, which draws its context; a fixed context's jobs
//!   reset with theirs.
//! * **Seeds.** [`plan`] derives each episode's seed from the evaluation's seed by [`SEED_RULE`],
//!   the rule of Python's `carl_spec.evaluate`: the CLI and Python play the same episodes, and
//!   for the same policy report the same returns, lengths and outcomes (a Python test runs both).
//!   Named experiments bring their own seeds.
//! * **Outcomes.** How each episode ended is the environment's own word ([`Env::outcome`]:
//!   `landed`, `crashed`, `solved`, ..., `timed_out` at the time limit), never decoded from
//!   rewards.
//! * **Results.** [`Evaluation`] serialises to the JSON document Python's `EvaluationResult`
//!   reads (`format` [`FORMAT`]), with the per-instance summary and the provenance: the set's
//!   name and content hash, the carl-spec and environment versions, the seed and its rule.

use std::collections::BTreeMap;

use serde::Serialize;
use serde_json::{Map, Value, json};

use crate::envs::api::{Env, EnvError, Space};
use crate::envs::contextual::{ContextSource, ContextualEnv, ContextualOptions};
use crate::envs::policy::{Policy, PolicyError, RandomPolicy};
use crate::envs::registry::{Context, EnvOptions};
use crate::episode::{EpisodeConfig, EpisodeEnd, EpisodeError, EpisodeListener, run_episode_with};
use crate::instances::FrozenSet;
use crate::spec::model::EnvSpec;
use crate::spec::raw::Split;

/// The `format` of an evaluation's JSON document (Python's `carl_spec.evaluation` reads it).
pub const FORMAT: &str = "carl-spec-evaluation/1";

/// How each episode's seed derives from the evaluation's seed (recorded in the provenance;
/// the same text as Python's `carl_spec.evaluation.SEED_RULE`).
pub const SEED_RULE: &str = "mix = SplitMix64's output function (x + 0x9E3779B97F4A7C15, then the xor-shift-multiply finalizer, mod 2^64); h = mix(mix(mix(seed mod 2^64) ^ instance) ^ episode) >> 1; instance sets: seed = h - h mod n + instance (a seeded reset of a set with round-robin selection plays instance seed mod n); distributions (instance = the draw's number) and fixed contexts (instance 0): seed = h";

/// SplitMix64's output function (wrapping).
fn mix(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The reset seed of episode `episode` of instance `instance` ([`SEED_RULE`]; `n_instances`: the
/// set's size, `None` for a distribution or a fixed context).
pub fn episode_seed(seed: u64, instance: usize, episode: usize, n_instances: Option<usize>) -> u64 {
    let h = mix(mix(mix(seed) ^ instance as u64) ^ episode as u64) >> 1;
    match n_instances {
        Some(n) if n > 0 => h - h % n as u64 + instance as u64,
        _ => h,
    }
}

/// One episode to play.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Job {
    /// The instance (a set's index, a distribution's draw number, 0 for a fixed context).
    pub instance: usize,
    /// The episode's number among its instance's episodes.
    pub episode: usize,
    /// The reset seed.
    pub seed: u64,
}

/// What is evaluated.
#[derive(Debug, Clone)]
pub enum Source {
    /// Every instance of a frozen set, `episodes` episodes each.
    Set { set: FrozenSet, episodes: usize },
    /// `draws` contexts of a distribution of the spec, one episode each.
    Distribution { name: String, draws: usize },
    /// One context (missing features at their defaults), `episodes` episodes.
    Fixed { context: Context, episodes: usize },
}

impl Source {
    /// The provenance's `source`.
    fn describe(&self) -> Value {
        match self {
            Source::Set { set, .. } => json!({
                "kind": "instances", "name": set.qualified_name(), "content_hash": set.content_hash,
            }),
            Source::Distribution { name, draws } => json!({"kind": "distribution", "name": name, "draws": draws}),
            Source::Fixed { context, .. } => json!({"kind": "context", "context": context}),
        }
    }
}

/// The jobs of `source` under `seed`, in (episode, instance) order as Python's `evaluate`
/// starts them (results are reported in (instance, episode) order).
pub fn plan(source: &Source, seed: u64) -> Vec<Job> {
    match source {
        Source::Set { set, episodes } => {
            let n = set.instances.len();
            (0..*episodes)
                .flat_map(|e| (0..n).map(move |k| (k, e)))
                .map(|(instance, episode)| Job {
                    instance,
                    episode,
                    seed: episode_seed(seed, instance, episode, Some(n)),
                })
                .collect()
        }
        Source::Distribution { draws, .. } => (0..*draws)
            .map(|instance| Job {
                instance,
                episode: 0,
                seed: episode_seed(seed, instance, 0, None),
            })
            .collect(),
        Source::Fixed { episodes, .. } => (0..*episodes)
            .map(|episode| Job {
                instance: 0,
                episode,
                seed: episode_seed(seed, 0, episode, None),
            })
            .collect(),
    }
}

/// The contextual environment that plays `source` (context hidden: the runtime's observation).
pub fn environment(spec: &EnvSpec, source: &Source, env_options: &EnvOptions) -> Result<ContextualEnv, String> {
    let src = match source {
        Source::Set { set, .. } => ContextSource::Set(set.clone()),
        Source::Distribution { name, .. } => ContextSource::Distribution { name: name.clone() },
        Source::Fixed { context, .. } => ContextSource::Fixed(context.clone()),
    };
    let options = ContextualOptions {
        env_options: env_options.clone(),
        ..Default::default()
    };
    ContextualEnv::new(spec, src, options).map_err(|e| e.to_string())
}

/// Who acts in each episode.
pub trait EpisodePolicy {
    /// The policy of the episode `job` starts (reset by the episode loop).
    fn start(&mut self, job: &Job) -> &mut dyn Policy;
}

/// One policy for every episode (a controller, actions read from a stream).
pub struct Same<P: Policy>(pub P);

impl<P: Policy> EpisodePolicy for Same<P> {
    fn start(&mut self, _job: &Job) -> &mut dyn Policy {
        &mut self.0
    }
}

/// One boxed policy for every episode.
impl EpisodePolicy for Box<dyn Policy> {
    fn start(&mut self, _job: &Job) -> &mut dyn Policy {
        self.as_mut()
    }
}

/// Uniform random actions, the stream of each episode seeded with that episode's reset seed
/// ([`RandomPolicy`]): an episode's actions do not depend on the episodes before it.
pub struct SeededRandom {
    space: Space,
    current: RandomPolicy,
}

impl SeededRandom {
    pub fn new(space: Space) -> Self {
        SeededRandom {
            current: RandomPolicy::new(space.clone(), 0),
            space,
        }
    }
}

impl EpisodePolicy for SeededRandom {
    fn start(&mut self, job: &Job) -> &mut dyn Policy {
        self.current = RandomPolicy::new(self.space.clone(), job.seed);
        &mut self.current
    }
}

/// What watches an evaluation besides the policy: told of each episode before its reset, then
/// a listener of the episode loop. A [`crate::episode::Flow::Stop`] from the listener (its reader
/// went away) ends the whole evaluation ([`EvalError::Stopped`]).
pub trait Observer: EpisodeListener<ContextualEnv> {
    /// `job` is about to start on instance `instance` (its full context: every feature).
    fn begin(&mut self, _job: &Job, _env: &ContextualEnv, _instance: &InstanceInfo) -> Result<(), String> {
        Ok(())
    }
}

/// An observer that watches nothing.
pub struct Unobserved;

impl EpisodeListener<ContextualEnv> for Unobserved {
    fn on_step(
        &mut self,
        _env: &ContextualEnv,
        _step: &crate::episode::StepRecord<'_>,
    ) -> Result<crate::episode::Flow, EpisodeError> {
        Ok(crate::episode::Flow::Continue)
    }
}

impl Observer for Unobserved {}

/// Why an evaluation did not finish.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EvalError {
    /// The observer asked to stop (the reader of a pipe went away): not a failure.
    #[error("stopped by its observer")]
    Stopped,
    /// Bad input: an action outside the action space, a policy that ran out of actions.
    #[error("{0}")]
    BadInput(String),
    #[error("{0}")]
    Failed(String),
}

impl From<String> for EvalError {
    fn from(s: String) -> Self {
        EvalError::Failed(s)
    }
}

/// One instance evaluated: its id, name, split and the features its source sets.
#[derive(Debug, Clone, Serialize)]
pub struct InstanceInfo {
    pub id: usize,
    pub name: Option<String>,
    pub split: Option<String>,
    pub context: Map<String, Value>,
}

/// One episode's result.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EpisodeResult {
    pub instance: usize,
    pub episode: usize,
    pub seed: u64,
    #[serde(rename = "return")]
    pub ret: f64,
    pub length: u64,
    pub terminated: bool,
    pub truncated: bool,
    /// The environment's outcome ([`Env::outcome`]), `None` where it defines none.
    pub outcome: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub context_seed: Option<u64>,
}

/// The split label as the spec writes it.
pub fn split_name(split: Option<Split>) -> Option<String> {
    split.map(|s| {
        match s {
            Split::InDistribution => "in_distribution",
            Split::OutOfDistribution => "out_of_distribution",
        }
        .to_string()
    })
}

/// The instances of `source` as results list them (a distribution's are filled in as drawn).
pub fn instances(source: &Source) -> Vec<InstanceInfo> {
    match source {
        Source::Set { set, .. } => set
            .instances
            .iter()
            .map(|i| InstanceInfo {
                id: i.id,
                name: i.name.clone(),
                split: split_name(i.split),
                context: i.context.iter().map(|(k, v)| (k.clone(), json!(v))).collect(),
            })
            .collect(),
        Source::Distribution { draws, .. } => (0..*draws)
            .map(|id| InstanceInfo {
                id,
                name: None,
                split: None,
                context: Map::new(),
            })
            .collect(),
        Source::Fixed { context, .. } => vec![InstanceInfo {
            id: 0,
            name: None,
            split: None,
            context: context.iter().map(|(k, v)| (k.clone(), json!(v))).collect(),
        }],
    }
}

/// Play one job in `env` (built by [`environment`] for its source; `set`: it plays a set, whose
/// job's instance is played whatever its seed). Errors do not say which job failed: the caller
/// does.
pub fn run_job(
    env: &mut ContextualEnv,
    set: bool,
    job: &Job,
    policy: &mut dyn Policy,
    listener: &mut dyn EpisodeListener<ContextualEnv>,
) -> Result<(EpisodeResult, crate::episode::EpisodeSummary), EvalError> {
    let config = EpisodeConfig {
        seed: job.seed,
        ..Default::default()
    };
    let (seed, instance) = (job.seed, job.instance);
    let mut reset = |e: &mut ContextualEnv, obs: &mut [f32]| -> Result<(), EnvError> {
        if set {
            e.reset_instance_into(Some(seed), instance, obs)
        } else {
            e.reset_into(Some(seed), obs)
        }
    };
    let summary = run_episode_with(env, policy, &config, listener, &mut reset).map_err(|e| {
        if e.is_bad_input() {
            EvalError::BadInput(e.to_string())
        } else {
            EvalError::Failed(e.to_string())
        }
    })?;
    let (terminated, truncated) = match summary.end {
        EpisodeEnd::Terminated => (true, false),
        EpisodeEnd::Truncated => (false, true),
        EpisodeEnd::ListenerStopped => return Err(EvalError::Stopped),
        EpisodeEnd::PolicyDone => {
            return Err(EvalError::BadInput(format!(
                "the policy's actions ended before step {} (the episode had not ended)",
                summary.steps + 1
            )));
        }
        EpisodeEnd::StepLimit => unreachable!("no step limit is configured"),
    };
    Ok((
        EpisodeResult {
            instance: job.instance,
            episode: job.episode,
            seed: job.seed,
            ret: summary.total_reward,
            length: summary.steps,
            terminated,
            truncated,
            outcome: env.outcome().map(str::to_string),
            context_seed: env.context_info().context_seed,
        },
        summary,
    ))
}

/// An evaluation's results: provenance, instances and episodes (see the [module docs](self)).
#[derive(Debug, Clone)]
pub struct Evaluation {
    pub provenance: Map<String, Value>,
    pub instances: Vec<InstanceInfo>,
    /// In (instance, episode) order.
    pub episodes: Vec<EpisodeResult>,
}

/// What to evaluate and how.
#[derive(Debug, Clone)]
pub struct Config {
    pub source: Source,
    pub seed: u64,
    /// The runtime's variant options (`continuous`, `crash_penalty`, ...).
    pub env_options: EnvOptions,
    /// The policy's name in the provenance.
    pub policy: String,
}

/// Evaluate: every job of [`plan`], one after the other.
pub fn evaluate(
    spec: &EnvSpec,
    cfg: &Config,
    policy: &mut dyn EpisodePolicy,
    observer: &mut dyn Observer,
) -> Result<Evaluation, EvalError> {
    let mut env = environment(spec, &cfg.source, &cfg.env_options)?;
    let jobs = plan(&cfg.source, cfg.seed);
    let mut infos = instances(&cfg.source);
    let is_set = matches!(cfg.source, Source::Set { .. });
    let mut episodes = Vec::with_capacity(jobs.len());
    for job in &jobs {
        observer.begin(job, &env, &infos[job.instance])?;
        let p = policy.start(job);
        let (result, _) = run_job(&mut env, is_set, job, p, observer).map_err(|e| {
            let at = |m: String| format!("instance {} episode {}: {m}", job.instance, job.episode);
            match e {
                EvalError::Stopped => EvalError::Stopped,
                EvalError::BadInput(m) => EvalError::BadInput(at(m)),
                EvalError::Failed(m) => EvalError::Failed(at(m)),
            }
        })?;
        if let Source::Distribution { name, .. } = &cfg.source {
            // The draw's features: what the distribution varies.
            let varied: Vec<&String> = spec
                .distributions
                .get(name)
                .map(|d| d.features.keys().collect())
                .unwrap_or_default();
            infos[job.instance].context = env
                .context_info()
                .context
                .iter()
                .filter(|(k, _)| varied.contains(&k))
                .map(|(k, v)| (k.clone(), json!(v)))
                .collect();
        }
        episodes.push(result);
    }
    episodes.sort_by_key(|e| (e.instance, e.episode));
    let episodes_per = match &cfg.source {
        Source::Set { episodes, .. } | Source::Fixed { episodes, .. } => json!(episodes),
        Source::Distribution { .. } => Value::Null,
    };
    let mut provenance = Map::new();
    let mut put = |k: &str, v: Value| {
        provenance.insert(k.to_string(), v);
    };
    put("carl_spec_version", json!(env!("CARGO_PKG_VERSION")));
    put("env", json!(spec.id));
    put("env_version", json!(spec.version));
    put("gym_id", json!(format!("carl_spec/{}", spec.versioned_id())));
    put("source", cfg.source.describe());
    put("seed", json!(cfg.seed));
    put("seed_rule", json!(SEED_RULE));
    put("episodes", episodes_per);
    put(
        "options",
        if cfg.env_options.is_empty() {
            Value::Null
        } else {
            json!(cfg.env_options)
        },
    );
    put("obs_context", Value::Null);
    put("context_noise", Value::Null);
    put("policy", json!(cfg.policy));
    put("deterministic", json!(true));
    put("run", Value::Null);
    put("num_envs", json!(1));
    put("threads", json!(1));
    put("front_end", json!("carl-spec evaluate"));
    Ok(Evaluation {
        provenance,
        instances: infos,
        episodes,
    })
}

/// One instance's episodes aggregated (Python's `InstanceSummary`).
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    pub instance: usize,
    pub name: Option<String>,
    pub split: Option<String>,
    pub context: Map<String, Value>,
    pub episodes: usize,
    pub mean: f64,
    /// Population standard deviation (ddof 0).
    pub std: f64,
    pub median: f64,
    pub min: f64,
    pub max: f64,
    pub mean_length: f64,
    pub terminated: usize,
    pub truncated: usize,
    pub outcomes: BTreeMap<String, usize>,
}

impl Evaluation {
    /// Per-instance aggregates, in instance order.
    pub fn summary(&self) -> Vec<Summary> {
        self.instances
            .iter()
            .map(|inst| {
                let eps: Vec<&EpisodeResult> = self.episodes.iter().filter(|e| e.instance == inst.id).collect();
                let n = eps.len().max(1) as f64;
                let mut r: Vec<f64> = eps.iter().map(|e| e.ret).collect();
                let mean = r.iter().sum::<f64>() / n;
                let std = (r.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n).sqrt();
                r.sort_by(f64::total_cmp);
                let median = match r.len() {
                    0 => f64::NAN,
                    k if k % 2 == 1 => r[k / 2],
                    k => (r[k / 2 - 1] + r[k / 2]) / 2.0,
                };
                let mut outcomes = BTreeMap::new();
                for e in &eps {
                    if let Some(o) = &e.outcome {
                        *outcomes.entry(o.clone()).or_insert(0) += 1;
                    }
                }
                Summary {
                    instance: inst.id,
                    name: inst.name.clone(),
                    split: inst.split.clone(),
                    context: inst.context.clone(),
                    episodes: eps.len(),
                    mean,
                    std,
                    median,
                    min: r.first().copied().unwrap_or(f64::NAN),
                    max: r.last().copied().unwrap_or(f64::NAN),
                    mean_length: eps.iter().map(|e| e.length as f64).sum::<f64>() / n,
                    terminated: eps.iter().filter(|e| e.terminated).count(),
                    truncated: eps.iter().filter(|e| e.truncated).count(),
                    outcomes,
                }
            })
            .collect()
    }

    /// The JSON document (Python's `EvaluationResult.from_json` reads it).
    pub fn to_json(&self) -> Value {
        json!({
            "format": FORMAT,
            "provenance": self.provenance,
            "instances": self.instances,
            "summary": self.summary(),
            "episodes": self.episodes,
        })
    }

    /// The provenance, the per-instance table and the per-episode table, as text.
    pub fn table(&self) -> String {
        use std::fmt::Write as _;
        let mut s = String::new();
        let p = &self.provenance;
        let src = &p["source"];
        let what = match src["kind"].as_str() {
            Some("instances") => format!(
                "{} ({})",
                src["name"].as_str().unwrap_or("?"),
                src["content_hash"].as_str().unwrap_or("?")
            ),
            Some("distribution") => format!(
                "{} distribution {} ({} draws)",
                p["env"].as_str().unwrap_or("?"),
                src["name"].as_str().unwrap_or("?"),
                src["draws"]
            ),
            _ => format!("{} context {}", p["env"].as_str().unwrap_or("?"), src["context"]),
        };
        let _ = writeln!(s, "evaluated: {what}");
        let _ = writeln!(
            s,
            "environment: {} (carl-spec {}); policy: {}; seed: {} (episode seeds: carl_spec.evaluation.SEED_RULE)",
            p["gym_id"].as_str().unwrap_or("?"),
            p["carl_spec_version"].as_str().unwrap_or("?"),
            p["policy"].as_str().unwrap_or("?"),
            p["seed"]
        );
        let feats: Vec<String> = {
            let mut f: Vec<String> = self.instances.iter().flat_map(|i| i.context.keys().cloned()).collect();
            f.sort();
            f.dedup();
            f
        };
        let _ = writeln!(s);
        let mut head = vec!["id".to_string(), "name".into(), "split".into()];
        head.extend(feats.iter().cloned());
        head.extend(
            [
                "episodes",
                "mean return",
                "std",
                "min",
                "max",
                "mean length",
                "outcomes",
            ]
            .iter()
            .map(|x| x.to_string()),
        );
        let mut rows = vec![head];
        for r in self.summary() {
            let mut row = vec![
                r.instance.to_string(),
                r.name.clone().unwrap_or_default(),
                r.split.clone().unwrap_or_default(),
            ];
            row.extend(
                feats
                    .iter()
                    .map(|f| r.context.get(f).map(num_value).unwrap_or_default()),
            );
            row.extend([
                r.episodes.to_string(),
                num(r.mean),
                num(r.std),
                num(r.min),
                num(r.max),
                num(r.mean_length),
                r.outcomes
                    .iter()
                    .map(|(k, v)| format!("{k} {v}"))
                    .collect::<Vec<_>>()
                    .join(", "),
            ]);
            rows.push(row);
        }
        s.push_str(&markdown(&rows));
        let _ = writeln!(s);
        let mut rows = vec![
            ["instance", "episode", "seed", "return", "length", "outcome"]
                .iter()
                .map(|x| x.to_string())
                .collect::<Vec<_>>(),
        ];
        for e in &self.episodes {
            rows.push(vec![
                e.instance.to_string(),
                e.episode.to_string(),
                e.seed.to_string(),
                num(e.ret),
                e.length.to_string(),
                e.outcome
                    .clone()
                    .unwrap_or_else(|| if e.terminated { "terminated" } else { "truncated" }.to_string()),
            ]);
        }
        s.push_str(&markdown(&rows));
        s
    }

    /// An error naming the first non-finite return (it would be `null` in JSON).
    pub fn check_finite(&self) -> Result<(), String> {
        match self.episodes.iter().find(|e| !e.ret.is_finite()) {
            Some(e) => Err(format!(
                "instance {} episode {}: the return is {}, not a finite number",
                e.instance, e.episode, e.ret
            )),
            None => Ok(()),
        }
    }
}

/// A number as the tables show it (Python's `_num`).
fn num(x: f64) -> String {
    if x.is_finite() && x == x.trunc() && x.abs() < 1e15 {
        format!("{x:.1}")
    } else {
        let s = format!("{x:.4e}");
        // Four significant digits, plain where that reads better.
        if x.abs() >= 1e-3 && x.abs() < 1e6 {
            let digits = 3 - x.abs().log10().floor() as i32;
            format!("{x:.*}", digits.max(0) as usize)
        } else {
            s
        }
    }
}

fn num_value(v: &Value) -> String {
    match v.as_f64() {
        Some(x) if !v.is_i64() && !v.is_u64() => num(x),
        _ => v.to_string(),
    }
}

/// A Markdown table of `rows` (the first is the header).
fn markdown(rows: &[Vec<String>]) -> String {
    let mut s = String::new();
    for (k, r) in rows.iter().enumerate() {
        s.push_str("| ");
        s.push_str(&r.join(" | "));
        s.push_str(" |\n");
        if k == 0 {
            s.push('|');
            s.push_str(&"---|".repeat(r.len()));
            s.push('\n');
        }
    }
    s
}

/// `PolicyError` as the evaluation's bad input.
impl From<PolicyError> for EvalError {
    fn from(e: PolicyError) -> Self {
        EvalError::BadInput(e.0)
    }
}
