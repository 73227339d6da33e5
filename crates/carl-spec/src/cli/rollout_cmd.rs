//! `carl-spec rollout ENV …`: run one episode and print JSON Lines ([`crate::episode::jsonl`]).

use std::io::BufReader;
use std::path::PathBuf;

use clap::Args;
use serde_json::json;

use super::context_args::{ContextArgs, PolicyArg};
use super::{Cli, CmdResult, Failure, exit};
use crate::envs::Env;
use crate::envs::policy::Policy;
use crate::episode::jsonl::{ActionList, ActionStream, JsonLinesWriter};
use crate::episode::policies::policy_for;
use crate::episode::{EpisodeConfig, EpisodeError, run_episode};

#[derive(Args, Debug)]
pub struct RolloutArgs {
    /// Environment id or alias (any environment with a runtime; `carl-spec list` shows them all).
    pub env: String,
    #[command(flatten)]
    pub ctx: ContextArgs,
    /// Seed of the reset (initial state) and of the random policy.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Internal state to set right after reset, comma-separated (CartPole: x,x_dot,theta,theta_dot;
    /// Pendulum: theta,theta_dot; MountainCar: position,velocity; Acrobot: theta1,theta2,dtheta1,dtheta2).
    #[arg(long, value_name = "V1,V2,…", allow_hyphen_values = true)]
    pub initial_state: Option<String>,
    /// JSON array of actions, or `-` to read one JSON action per line from standard input.
    #[arg(long, value_name = "FILE", conflicts_with = "policy")]
    pub actions: Option<PathBuf>,
    /// Policy when no actions are given (heuristic: the environment's built-in controller).
    #[arg(long, value_enum, default_value_t = PolicyArg::Random)]
    pub policy: PolicyArg,
    /// Stop after at most N steps (the episode may end earlier).
    #[arg(long, value_name = "N")]
    pub steps: Option<u64>,
}

pub fn run(cli: &Cli, args: &RolloutArgs) -> CmdResult {
    let resolved = args.ctx.resolve(cli, &args.env, "rollout")?;
    let mut env = resolved.build()?;
    let initial_state = match &args.initial_state {
        None => None,
        Some(s) => Some(
            s.split(',')
                .map(|x| x.trim().parse::<f64>())
                .collect::<Result<Vec<f64>, _>>()
                .map_err(|_| {
                    Failure::usage(format!(
                        "--initial-state \"{}\" is not a comma-separated list of numbers",
                        crate::episode::jsonl::quote_input(s)
                    ))
                })?,
        ),
    };
    let space = env.action_space();
    let interactive = args.actions.as_ref().is_some_and(|p| p.as_os_str() == "-");
    let mut policy: Box<dyn Policy> = match &args.actions {
        Some(p) if p.as_os_str() == "-" => Box::new(ActionStream::new(BufReader::new(std::io::stdin()), space)),
        Some(p) => {
            let text = crate::input::read_file(
                p,
                crate::episode::jsonl::MAX_ACTIONS_FILE,
                "stream longer action sequences with --actions - (one per line)",
            )
            .map_err(|e| Failure::usage(format!("--actions: {e}")))?;
            Box::new(ActionList::parse(&text, &p.display().to_string(), space).map_err(Failure::usage)?)
        }
        None => policy_for(resolved.registration, args.policy.into(), &space, args.seed).map_err(Failure::usage)?,
    };
    let context = resolved
        .full_context()?
        .into_iter()
        .map(|(k, v)| (k, json!(v)))
        .collect();
    let stdout = std::io::stdout();
    let mut writer = JsonLinesWriter::new(std::io::BufWriter::new(stdout.lock()), context, interactive);
    if !resolved.noise.is_empty() {
        writer = writer.observing_context();
    }
    let config = EpisodeConfig {
        seed: args.seed,
        initial_state,
        max_steps: args.steps,
    };
    let result = run_episode(&mut env, policy.as_mut(), &config, &mut writer);
    // Lines already written stay valid JSON Lines; flush them before reporting an error.
    writer.finish().map_err(|e| Failure::failed(e.to_string()))?;
    result.map_err(|e| {
        if let EpisodeError::InitialState(e) = e {
            Failure::usage(format!("--initial-state: {e}"))
        } else if e.is_bad_input() {
            Failure::usage(e.to_string())
        } else {
            Failure::failed(e.to_string())
        }
    })?;
    Ok(exit::OK)
}
