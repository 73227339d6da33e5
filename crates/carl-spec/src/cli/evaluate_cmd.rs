//! `carl-spec evaluate ENV/SET …`: a policy on every instance of a frozen set (a distribution's
//! draws, a fixed context), per-episode and per-instance results with their provenance, as a
//! table or as the JSON document Python's `carl_spec.EvaluationResult` reads
//! ([`crate::evaluation`]).
//!
//! With `--policy stdin` every episode is streamed on stdout as JSON lines, as `rollout --actions -`
//! streams one: `{"episode": {"instance", "episode", "seed"}}`, the reset line (with the episode's
//! full context), then one line per step; after each observation line (flushed) one JSON action is
//! read from stdin. The results then go to stderr (or `--out`) so stdout carries only JSON lines.

use std::io::{BufReader, Write};
use std::path::PathBuf;

use clap::{Args, ValueEnum};
use serde_json::{Map, Value, json};

use super::context_args::{parse_value, split_kv};
use super::{Cli, CmdResult, Failure, exit, load_specs, out};
use crate::envs::Env;
use crate::envs::contextual::ContextualEnv;
use crate::envs::policy::PolicyKind;
use crate::envs::registry::{Context, EnvOptions, MakeOptions, lookup, resolve_context};
use crate::episode::jsonl::{ActionStream, JsonLinesWriter};
use crate::episode::policies::policy_for;
use crate::episode::{EpisodeError, EpisodeListener, Flow, StepRecord};
use crate::evaluation::{self, Config, EpisodePolicy, EvalError, InstanceInfo, Job, Observer, SeededRandom, Source};
use crate::instances::Store;
use crate::output;

/// Most episodes per instance, and most draws of a distribution.
const MAX_EPISODES: u64 = 1_000_000;

#[derive(Args, Debug)]
pub struct EvaluateArgs {
    /// `ENV/SET`: every instance of a frozen set (`carl-spec instances list`); or `ENV` with
    /// `--distribution`, or `ENV` alone (its default context, or `--context`).
    pub target: String,
    /// Who acts: the environment's hand-written controller, uniform random actions (each
    /// episode's stream seeded with its reset seed), or one JSON action per line from stdin.
    #[arg(long, value_enum, default_value_t = EvalPolicy::Heuristic)]
    pub policy: EvalPolicy,
    /// Episodes per instance (sets, fixed contexts; default 10).
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..=MAX_EPISODES))]
    pub episodes: Option<u64>,
    /// Seed of the evaluation: episode seeds derive from it as in Python's `carl_spec.evaluate`.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Evaluate `--draws` contexts of this distribution of the spec (one episode each).
    #[arg(long, value_name = "NAME", conflicts_with = "context")]
    pub distribution: Option<String>,
    /// Contexts drawn from `--distribution` (default 100).
    #[arg(long, value_name = "N", requires = "distribution",
          value_parser = clap::value_parser!(u64).range(1..=MAX_EPISODES))]
    pub draws: Option<u64>,
    /// A fixed context's feature, `NAME=VALUE` (repeatable; the others keep their defaults).
    #[arg(long = "context", value_name = "NAME=VALUE")]
    pub context: Vec<String>,
    /// A variant option of the environment, e.g. `--option crash_penalty=10000` (LunarLander).
    #[arg(long = "option", value_name = "NAME=VALUE")]
    pub options: Vec<String>,
    /// The environment the set must belong to (a set of another environment is refused).
    #[arg(long, value_name = "ENV")]
    pub env: Option<String>,
    /// Print the results as JSON (Python's `EvaluationResult.from_json` reads it) instead of tables.
    #[arg(long)]
    pub json: bool,
    /// Also write the results as JSON to FILE.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Replace an existing --out file.
    #[arg(long)]
    pub force: bool,
}

#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum)]
pub enum EvalPolicy {
    /// The environment's hand-written controller (e.g. Gymnasium's lander heuristic).
    Heuristic,
    /// Uniform over the action space; each episode's stream is seeded with its reset seed.
    Random,
    /// Read one JSON action per line from stdin (episodes streamed on stdout as JSON lines).
    Stdin,
}

pub fn run(cli: &Cli, args: &EvaluateArgs) -> CmdResult {
    if let Some(p) = &args.out {
        output::check_file(p, args.force).map_err(|e| Failure::usage(e.to_string()))?;
    }
    let specs = load_specs(cli)?;
    let (env_name, set_name) = match args.target.split_once('/') {
        Some((e, s)) => (e, Some(s)),
        None => (args.target.as_str(), None),
    };
    let spec = specs.require(env_name).map_err(Failure::usage)?;
    if let Some(want) = &args.env {
        let want = specs.require(want).map_err(Failure::usage)?;
        if want.id != spec.id {
            return Err(Failure::usage(format!(
                "{} belongs to {}, not to {}; evaluate {} on one of its own sets (carl-spec instances list)",
                args.target, spec.id, want.id, want.id
            )));
        }
    }
    let Some(registration) = lookup(&spec.id) else {
        return Err(Failure::usage(format!(
            "{} has a spec but no runtime yet; evaluate works for: {}",
            spec.id,
            crate::envs::registry::ids_text()
        )));
    };
    let episodes = args.episodes.unwrap_or(10) as usize;
    let source = match (set_name, &args.distribution) {
        (Some(_), Some(_)) => {
            return Err(Failure::usage(
                "--distribution evaluates an environment's draws: give ENV, not ENV/SET",
            ));
        }
        (Some(_), None) if !args.context.is_empty() => {
            return Err(Failure::usage("--context sets a fixed context: give ENV, not ENV/SET"));
        }
        (Some(_), None) => {
            let set = Store::new(&specs)
                .load(&args.target)
                .map_err(|e| Failure::usage(e.to_string()))?;
            Source::Set { set, episodes }
        }
        (None, Some(name)) => {
            if args.episodes.is_some() {
                return Err(Failure::usage(
                    "a distribution is evaluated on --draws contexts, one episode each; pass --draws, not --episodes",
                ));
            }
            Source::Distribution {
                name: name.clone(),
                draws: args.draws.unwrap_or(100) as usize,
            }
        }
        (None, None) => {
            let mut context = Context::new();
            for kv in &args.context {
                let (k, v) = split_kv("--context", kv)?;
                context.insert(k.to_string(), parse_value(v));
            }
            resolve_context(spec, &context, MakeOptions::default()).map_err(|e| Failure::usage(e.to_string()))?;
            Source::Fixed { context, episodes }
        }
    };
    let mut env_options = EnvOptions::new();
    for kv in &args.options {
        let (k, v) = split_kv("--option", kv)?;
        env_options.insert(k.to_string(), parse_value(v));
    }
    // Everything is checked (the set, its instances, the options) before the first episode.
    let probe = evaluation::environment(spec, &source, &env_options).map_err(Failure::usage)?;
    let space = probe.action_space();
    drop(probe);
    let label = match args.policy {
        EvalPolicy::Heuristic => "heuristic",
        EvalPolicy::Random => "random",
        EvalPolicy::Stdin => "stdin",
    };
    let cfg = Config {
        source,
        seed: args.seed,
        env_options,
        policy: format!("{label} (carl-spec evaluate --policy {label})"),
    };
    let evaluated = match args.policy {
        EvalPolicy::Heuristic | EvalPolicy::Random => {
            let mut policy: Box<dyn EpisodePolicy> = if args.policy == EvalPolicy::Random {
                Box::new(SeededRandom::new(space))
            } else {
                Box::new(policy_for(registration, PolicyKind::Heuristic, &space, 0).map_err(Failure::usage)?)
            };
            let mut progress = Counted(super::progress::Progress::counter("episodes"));
            let r = evaluation::evaluate(spec, &cfg, policy.as_mut(), &mut progress);
            progress.0.finish();
            r
        }
        EvalPolicy::Stdin => {
            let actions = ActionStream::new(BufReader::new(std::io::stdin()), space);
            let mut lines = Streamed(JsonLinesWriter::new(
                std::io::BufWriter::new(std::io::stdout().lock()),
                Map::new(),
                true,
            ));
            let r = evaluation::evaluate(spec, &cfg, &mut evaluation::Same(actions), &mut lines);
            lines.0.finish().map_err(|e| Failure::failed(e.to_string()))?;
            r
        }
    };
    let results = match evaluated {
        Ok(r) => r,
        // The reader went away: stop quietly, as `rollout` does.
        Err(EvalError::Stopped) => return Ok(exit::OK),
        Err(EvalError::BadInput(e)) => return Err(Failure::usage(e)),
        Err(EvalError::Failed(e)) => return Err(Failure::failed(e)),
    };
    results.check_finite().map_err(Failure::failed)?;
    let mut json_text = serde_json::to_string_pretty(&results.to_json())
        .map_err(|e| Failure::failed(format!("serialising results: {e}")))?;
    json_text.push('\n');
    if let Some(p) = &args.out {
        output::write_file(p, json_text.as_bytes(), args.force).map_err(|e| Failure::usage(e.to_string()))?;
    }
    let text = if args.json { json_text } else { results.table() };
    if args.policy == EvalPolicy::Stdin {
        eprint!("{text}");
    } else {
        out(&text)?;
    }
    Ok(exit::OK)
}

/// `--policy stdin`: every episode on stdout as JSON lines, `{"episode": …}` before its reset
/// line, whose `context` is the episode's full context.
struct Streamed<W: Write>(JsonLinesWriter<W>);

impl<W: Write> EpisodeListener<ContextualEnv> for Streamed<W> {
    fn on_reset(&mut self, env: &ContextualEnv, obs: &[f32]) -> Result<Flow, EpisodeError> {
        let context: Map<String, Value> = env
            .context_info()
            .context
            .iter()
            .map(|(k, v)| (k.clone(), json!(v)))
            .collect();
        self.0.set_context(context);
        self.0.on_reset(env, obs)
    }
    fn on_step(&mut self, env: &ContextualEnv, step: &StepRecord<'_>) -> Result<Flow, EpisodeError> {
        self.0.on_step(env, step)
    }
}

impl<W: Write> Observer for Streamed<W> {
    fn begin(&mut self, job: &Job, _env: &ContextualEnv, instance: &InstanceInfo) -> Result<(), String> {
        let mut head = json!({"instance": job.instance, "episode": job.episode, "seed": job.seed});
        if let Some(name) = &instance.name {
            head["instance_name"] = json!(name);
        }
        // A closed pipe shows again (as a stop) on the reset line that follows.
        self.0
            .write_line(&json!({ "episode": head }))
            .map(drop)
            .map_err(|e| e.to_string())
    }
}

/// Episodes counted on the progress line (terminals only).
struct Counted(super::progress::Progress);

impl EpisodeListener<ContextualEnv> for Counted {
    fn on_step(&mut self, _env: &ContextualEnv, _step: &StepRecord<'_>) -> Result<Flow, EpisodeError> {
        Ok(Flow::Continue)
    }
}

impl Observer for Counted {
    fn begin(&mut self, job: &Job, _env: &ContextualEnv, instance: &InstanceInfo) -> Result<(), String> {
        self.0.inc(1);
        self.0.message(
            instance
                .name
                .clone()
                .unwrap_or_else(|| format!("instance {}", job.instance)),
        );
        Ok(())
    }
}
