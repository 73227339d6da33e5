//! `carl-spec rollout ENV …`: run one episode and print JSON Lines.
//!
//! First line `{"reset": {"obs": […], "context": {…}}}`, then one line per step
//! `{"t": 1, "action": …, "obs": […], "reward": r, "terminated": b, "truncated": b}`, stopping at
//! termination or truncation. With `--actions -` each action is read from standard input (one JSON
//! value per line) and the step's line is written and flushed before the next is read, so any
//! program can drive an environment in a closed loop through a pipe.

use std::io::{BufRead, Write};
use std::path::PathBuf;

use clap::Args;
use serde_json::json;

use super::{Cli, CmdResult, Failure, exit};
use crate::envs::api::{Action, Env, Space};
use crate::envs::registry::{MakeOptions, make_with, resolve_context};
use crate::sampling::{Pcg64, dist};

#[derive(Args, Debug)]
pub struct RolloutArgs {
    /// Environment id or alias (any environment with a runtime; `carl-spec list` shows them all).
    pub env: String,
    #[command(flatten)]
    pub ctx: super::context_args::ContextArgs,
    /// Seed of the reset (initial state) and of the random policy.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Internal state to set right after reset, comma-separated (CartPole: x,x_dot,theta,theta_dot;
    /// Pendulum: theta,theta_dot; MountainCar: position,velocity; Acrobot: theta1,theta2,dtheta1,dtheta2).
    #[arg(long, value_name = "V1,V2,…", allow_hyphen_values = true)]
    pub initial_state: Option<String>,
    /// JSON array of actions, or `-` to read one JSON action per line from standard input.
    #[arg(long, value_name = "FILE")]
    pub actions: Option<PathBuf>,
    /// Policy when no actions are given.
    #[arg(long, value_enum, default_value_t = Policy::Random)]
    pub policy: Policy,
    /// Stop after at most N steps (the episode may end earlier).
    #[arg(long, value_name = "N")]
    pub steps: Option<u64>,
}

#[derive(Copy, Clone, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Policy {
    /// Uniform over the action space, from a generator seeded with `--seed`.
    Random,
}

// Lines are structs so their keys come out in the documented order.
#[derive(serde::Serialize)]
pub(super) struct ResetLine<'a> {
    pub(super) reset: ResetBody<'a>,
}

#[derive(serde::Serialize)]
pub(super) struct ResetBody<'a> {
    pub(super) obs: &'a [f32],
    pub(super) context: &'a serde_json::Map<String, serde_json::Value>,
}

#[derive(serde::Serialize)]
pub(super) struct StepLine<'a> {
    pub(super) t: u64,
    pub(super) action: &'a serde_json::Value,
    pub(super) obs: &'a [f32],
    pub(super) reward: f64,
    pub(super) terminated: bool,
    pub(super) truncated: bool,
}

enum ActionSource {
    List(std::vec::IntoIter<serde_json::Value>),
    Stdin(std::io::StdinLock<'static>),
    Random(Pcg64),
}

pub fn run(cli: &Cli, args: &RolloutArgs) -> CmdResult {
    let resolved = args.ctx.resolve(cli, &args.env, "rollout")?;
    let (spec, ctx, allow) = (&resolved.spec, &resolved.context, resolved.allow_out_of_bounds);
    let opts = MakeOptions {
        allow_out_of_bounds: allow,
    };
    let mut env = make_with(spec, ctx, opts).map_err(|e| Failure::usage(e.to_string()))?;
    let full: serde_json::Map<String, serde_json::Value> = resolve_context(spec, ctx, opts)
        .map_err(|e| Failure::usage(e.to_string()))?
        .into_iter()
        .map(|(k, v)| (k, json!(v)))
        .collect();

    let initial_state = match &args.initial_state {
        None => None,
        Some(s) => Some(
            s.split(',')
                .map(|x| x.trim().parse::<f64>())
                .collect::<Result<Vec<f64>, _>>()
                .map_err(|_| {
                    Failure::usage(format!(
                        "--initial-state \"{s}\" is not a comma-separated list of numbers"
                    ))
                })?,
        ),
    };

    let mut source = match &args.actions {
        Some(p) if p.as_os_str() == "-" => ActionSource::Stdin(std::io::stdin().lock()),
        Some(p) => {
            let text =
                std::fs::read_to_string(p).map_err(|e| Failure::usage(format!("cannot read {}: {e}", p.display())))?;
            let v: serde_json::Value =
                serde_json::from_str(&text).map_err(|e| Failure::usage(format!("{}: not JSON: {e}", p.display())))?;
            let list = v
                .as_array()
                .cloned()
                .ok_or_else(|| Failure::usage(format!("{}: expected a JSON array of actions", p.display())))?;
            ActionSource::List(list.into_iter())
        }
        None => ActionSource::Random(Pcg64::new(args.seed, crate::sampling::stream_id("rollout-policy"))),
    };

    let stdout = std::io::stdout();
    let mut w = std::io::BufWriter::new(stdout.lock());

    let mut obs = vec![0.0f32; env.obs_dim()];
    env.reset_into(Some(args.seed), &mut obs)
        .map_err(|e| Failure::failed(e.to_string()))?;
    if let Some(state) = &initial_state {
        env.set_state(state)
            .map_err(|e| Failure::usage(format!("--initial-state: {e}")))?;
        env.observe_into(&mut obs).map_err(|e| Failure::failed(e.to_string()))?;
    }
    let interactive = matches!(source, ActionSource::Stdin(_));
    let reset_line = ResetLine {
        reset: ResetBody {
            obs: &obs,
            context: &full,
        },
    };
    if !emit(&mut w, &reset_line, interactive) {
        return Ok(exit::OK);
    }
    let action_space = env.action_space();
    let mut t = 0u64;
    let mut line = String::new();
    while args.steps.is_none_or(|n| t < n) {
        let action_json = match &mut source {
            ActionSource::List(it) => match it.next() {
                Some(a) => a,
                None => break,
            },
            ActionSource::Stdin(lock) => {
                line.clear();
                match lock.read_line(&mut line) {
                    Ok(0) => break,
                    Ok(_) if line.trim().is_empty() => continue,
                    Ok(_) => serde_json::from_str(line.trim()).map_err(|e| {
                        Failure::usage(format!("step {}: action \"{}\" is not JSON: {e}", t + 1, line.trim()))
                    })?,
                    Err(e) => return Err(Failure::usage(format!("reading actions from stdin: {e}"))),
                }
            }
            ActionSource::Random(rng) => random_action(rng, &action_space),
        };
        let action =
            parse_action(&action_json, &action_space).map_err(|m| Failure::usage(format!("step {}: {m}", t + 1)))?;
        let out = env
            .step_into(&action, &mut obs)
            .map_err(|e| Failure::usage(format!("step {}: {e}", t + 1)))?;
        t += 1;
        let line_out = StepLine {
            t,
            action: &action_json,
            obs: &obs,
            reward: out.reward,
            terminated: out.terminated,
            truncated: out.truncated,
        };
        if !emit(&mut w, &line_out, interactive) {
            return Ok(exit::OK);
        }
        if out.terminated || out.truncated {
            break;
        }
    }
    let _ = w.flush();
    Ok(exit::OK)
}

/// Write one JSON line; false when stdout is closed (the reader went away: stop quietly).
pub(super) fn emit(w: &mut impl Write, v: &impl serde::Serialize, flush: bool) -> bool {
    serde_json::to_writer(&mut *w, v).is_ok() && w.write_all(b"\n").is_ok() && (!flush || w.flush().is_ok())
}

pub(super) fn random_action(rng: &mut Pcg64, space: &Space) -> serde_json::Value {
    match space {
        Space::Discrete { n, start } => json!(start + dist::below(rng, (*n).max(1) as u64) as i64),
        Space::Box { low, high, .. } => {
            let v: Vec<f32> = low
                .iter()
                .zip(high)
                .map(|(l, h)| dist::uniform(rng, *l as f64, *h as f64) as f32)
                .collect();
            json!(v)
        }
    }
}

pub(super) fn parse_action(v: &serde_json::Value, space: &Space) -> Result<Action, String> {
    match space {
        Space::Discrete { n, start } => {
            let a = v
                .as_i64()
                .ok_or_else(|| format!("expected an integer action in {start}..{}, got {v}", start + n))?;
            Ok(Action::Discrete(a))
        }
        Space::Box { low, .. } => {
            let xs: Vec<f32> = match v {
                serde_json::Value::Number(x) if low.len() == 1 => vec![x.as_f64().unwrap_or(f64::NAN) as f32],
                serde_json::Value::Array(items) => items
                    .iter()
                    .map(|x| {
                        x.as_f64()
                            .map(|f| f as f32)
                            .ok_or_else(|| format!("action element {x} is not a number"))
                    })
                    .collect::<Result<_, _>>()?,
                _ => return Err(format!("expected an array of {} number(s), got {v}", low.len())),
            };
            if xs.len() != low.len() {
                return Err(format!("expected {} number(s), got {}", low.len(), xs.len()));
            }
            if xs.iter().any(|x| !x.is_finite()) {
                return Err("action values must be finite".into());
            }
            Ok(Action::Continuous(xs))
        }
    }
}
