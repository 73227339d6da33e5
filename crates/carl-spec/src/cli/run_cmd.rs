//! `carl-spec run EXPERIMENT …`: the paper's experiments end to end (see `crate::experiments`).
//!
//! `run landing_in_space` evaluates a policy on every test body and on a train sample, prints a
//! table, and optionally writes the results JSON (`--out`) and an SVG bar chart (`--figure`).
//! With `--policy stdin` every episode is streamed on stdout as JSON lines, like `rollout
//! --actions -`: `{"episode": {"body", "gravity", "seed"}}`, the reset line, then one line per step;
//! after each observation line (flushed) one JSON action is read from stdin. The table then goes
//! to stderr so stdout carries only JSON lines.
//!
//! Arguments and output paths are checked before the evaluation starts (`crate::output`'s rule:
//! the directory must exist, nothing is replaced without `--force`, writes are atomic).

use std::io::{BufReader, Write};
use std::path::{Path, PathBuf};

use clap::{Subcommand, ValueEnum};
use serde_json::{Map, Value, json};

use super::{Cli, CmdResult, Failure, exit, load_specs, out};
use crate::envs::contextual::ContextualEnv;
use crate::episode::jsonl::{ActionStream, JsonLinesWriter};
use crate::episode::{EpisodeError, EpisodeListener, Flow, StepRecord};
use crate::experiments::landing_in_space::{self as lis, Config, EpisodeInfo, EvalError, Observer};
use crate::output;

#[derive(Subcommand, Debug)]
pub enum RunCommand {
    /// LunarLander across gravities: each test body of lunar_lander/landing_in_space_test_planets
    /// plus a sample of lunar_lander/landing_in_space_train. Episode k of row r resets with seed
    /// Pcg64::new(S, fnv1a64("landing_in_space/{r}/{k}")).next_u64().
    #[command(name = "landing_in_space", alias = "landing-in-space")]
    LandingInSpace {
        #[arg(long, value_enum, default_value_t = RunPolicy::Heuristic)]
        policy: RunPolicy,
        /// Episodes per test body, and in total on the train set (round-robin over its instances).
        #[arg(long, default_value_t = 20, value_parser = clap::value_parser!(u64).range(1..=100_000))]
        episodes: u64,
        /// Base seed S of the reset seeds.
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// Reward on crash / out of view is -P (Gymnasium 100; the paper's evaluation 10000).
        #[arg(long, default_value_t = 100.0, value_name = "P", allow_hyphen_values = true)]
        crash_penalty: f64,
        /// Write the results (per row and per episode) as JSON.
        #[arg(long, value_name = "FILE")]
        out: Option<PathBuf>,
        /// Write an SVG bar chart of mean return ± std per body (FILE must end in .svg).
        #[arg(long, value_name = "FILE")]
        figure: Option<PathBuf>,
        /// Replace existing --out / --figure files.
        #[arg(long)]
        force: bool,
    },
}

#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum)]
pub enum RunPolicy {
    /// Gymnasium's hand-written landing controller.
    Heuristic,
    /// Read one JSON action per line from stdin (episodes streamed on stdout as JSON lines).
    Stdin,
}

pub fn run(cli: &Cli, cmd: &RunCommand) -> CmdResult {
    match cmd {
        RunCommand::LandingInSpace {
            policy,
            episodes,
            seed,
            crash_penalty,
            out: out_path,
            figure,
            force,
        } => {
            let cfg = Config {
                episodes: *episodes as usize,
                seed: *seed,
                crash_penalty: *crash_penalty,
            };
            cfg.check().map_err(Failure::usage)?;
            // Before the evaluation: a bad path must not cost the whole run.
            if let Some(p) = figure {
                check_figure_extension(p)?;
            }
            for p in [out_path, figure].into_iter().flatten() {
                output::check_file(p, *force).map_err(|e| Failure::usage(e.to_string()))?;
            }
            if let (Some(a), Some(b)) = (out_path, figure)
                && a == b
            {
                return Err(Failure::usage(format!(
                    "--out and --figure are both {}; give two different files",
                    a.display()
                )));
            }
            let specs = load_specs(cli)?;
            let interactive = *policy == RunPolicy::Stdin;
            let evaluated = match policy {
                RunPolicy::Heuristic => {
                    let mut progress = Counted(super::progress::Progress::counter("episodes"));
                    lis::evaluate(&specs, &cfg, "heuristic", &mut lis::Heuristic, &mut progress)
                }
                RunPolicy::Stdin => {
                    let space = lis::action_space(&specs).map_err(Failure::failed)?;
                    let mut actions = ActionStream::new(BufReader::new(std::io::stdin()), space);
                    let mut lines = Streamed(JsonLinesWriter::new(
                        std::io::BufWriter::new(std::io::stdout().lock()),
                        Map::new(),
                        true,
                    ));
                    let r = lis::evaluate(&specs, &cfg, "stdin", &mut actions, &mut lines);
                    lines.0.finish().map_err(|e| Failure::failed(e.to_string()))?;
                    r
                }
            };
            let results = match evaluated {
                Ok(r) => r,
                // The reader went away: stop quietly, as `rollout` does.
                Err(EvalError::Stopped) => return Ok(exit::OK),
                Err(EvalError::Failed(e)) => return Err(Failure::usage(e)),
            };
            results.check_finite().map_err(Failure::failed)?;
            let table = lis::table(&results);
            if interactive {
                eprint!("{table}");
            } else {
                out(&table)?;
            }
            if let Some(p) = out_path {
                let mut text = serde_json::to_string_pretty(&results)
                    .map_err(|e| Failure::failed(format!("serialising results: {e}")))?;
                text.push('\n');
                write(p, text.as_bytes(), *force)?;
            }
            if let Some(p) = figure {
                write(
                    p,
                    lis::figure_svg(&results).map_err(Failure::failed)?.as_bytes(),
                    *force,
                )?;
            }
            Ok(exit::OK)
        }
    }
}

/// The figure is SVG: a `--figure` file must say so (`.svg`, any case), so that `x.png` does not
/// receive SVG text.
fn check_figure_extension(p: &Path) -> Result<(), Failure> {
    let ext = p.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    if ext.as_deref() == Some("svg") {
        return Ok(());
    }
    Err(Failure::usage(format!(
        "--figure {}: the figure is written as SVG; give a file name ending in .svg",
        crate::text::escape(&p.display().to_string())
    )))
}

fn write(p: &Path, bytes: &[u8], force: bool) -> Result<(), Failure> {
    output::write_file(p, bytes, force).map_err(|e| Failure::usage(e.to_string()))
}

/// `--policy stdin`: every episode on stdout as JSON lines, `{"episode": …}` before its reset line.
struct Streamed<W: Write>(JsonLinesWriter<W>);

impl<W: Write> EpisodeListener<ContextualEnv> for Streamed<W> {
    fn on_reset(&mut self, env: &ContextualEnv, obs: &[f32]) -> Result<Flow, EpisodeError> {
        self.0.on_reset(env, obs)
    }
    fn on_step(&mut self, env: &ContextualEnv, step: &StepRecord<'_>) -> Result<Flow, EpisodeError> {
        self.0.on_step(env, step)
    }
}

impl<W: Write> Observer for Streamed<W> {
    fn begin(&mut self, info: &EpisodeInfo, context: &Map<String, Value>) -> Result<(), String> {
        self.0.set_context(context.clone());
        // A closed pipe shows again (as a stop) on the reset line that follows.
        self.0
            .write_line(&json!({ "episode": info }))
            .map(drop)
            .map_err(|e| e.to_string())
    }
}

/// The heuristic's evaluation: episodes counted on the progress line.
struct Counted(super::progress::Progress);

impl EpisodeListener<ContextualEnv> for Counted {
    fn on_step(&mut self, _env: &ContextualEnv, _step: &StepRecord<'_>) -> Result<Flow, EpisodeError> {
        Ok(Flow::Continue)
    }
}

impl Observer for Counted {
    fn begin(&mut self, info: &EpisodeInfo, _context: &Map<String, Value>) -> Result<(), String> {
        self.0.inc(1);
        self.0.message(info.body.clone());
        Ok(())
    }
}
