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

use std::io::{BufRead, Write};
use std::path::{Path, PathBuf};

use clap::{Subcommand, ValueEnum};

use super::{Cli, CmdResult, Failure, exit, load_specs, out};
use crate::envs::api::{Action, Space};
use crate::episode::StepRecord;
use crate::episode::jsonl::{parse_action, quote_input, write_reset, write_step};
use crate::experiments::landing_in_space::{self as lis, Config, Driver, EpisodeInfo, Heuristic};
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
        /// Write an SVG bar chart of mean return ± std per body.
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
            for p in [out_path, figure].into_iter().flatten() {
                output::check_file(p, *force).map_err(|e| Failure::usage(e.to_string()))?;
            }
            if let (Some(a), Some(b)) = (out_path, figure) {
                if a == b {
                    return Err(Failure::usage(format!(
                        "--out and --figure are both {}; give two different files",
                        a.display()
                    )));
                }
            }
            let specs = load_specs(cli)?;
            let (results, interactive) = match policy {
                RunPolicy::Heuristic => (
                    lis::evaluate(
                        &specs,
                        &cfg,
                        "heuristic",
                        &mut Counted {
                            inner: Heuristic,
                            progress: super::progress::Progress::counter("episodes"),
                        },
                    )
                    .map_err(Failure::usage)?,
                    false,
                ),
                RunPolicy::Stdin => {
                    let mut d = StdinDriver {
                        w: std::io::BufWriter::new(std::io::stdout().lock()),
                        r: std::io::stdin().lock(),
                        line: String::new(),
                        space: None,
                    };
                    match lis::evaluate(&specs, &cfg, "stdin", &mut d) {
                        Ok(r) => (r, true),
                        // The reader went away: stop quietly, as `rollout` does.
                        Err(e) if e == CLOSED => return Ok(exit::OK),
                        Err(e) => return Err(Failure::usage(e)),
                    }
                }
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

fn write(p: &Path, bytes: &[u8], force: bool) -> Result<(), Failure> {
    output::write_file(p, bytes, force).map_err(|e| Failure::usage(e.to_string()))
}

/// Streams episodes on stdout and reads actions from stdin.
struct StdinDriver<W: Write, R: BufRead> {
    w: W,
    r: R,
    line: String,
    space: Option<Space>,
}

const CLOSED: &str = "stdout closed";

impl<W: Write, R: BufRead> Driver for StdinDriver<W, R> {
    fn begin(
        &mut self,
        info: &EpisodeInfo,
        obs: &[f32],
        context: &serde_json::Map<String, serde_json::Value>,
    ) -> Result<(), String> {
        self.space = Some(info.action_space.clone());
        let w = &mut self.w;
        let r = serde_json::to_writer(&mut *w, &serde_json::json!({ "episode": info }))
            .map_err(std::io::Error::from)
            .and_then(|()| w.write_all(b"\n"))
            .and_then(|()| write_reset(w, obs, context, None))
            .and_then(|()| w.flush());
        emitted(r)
    }

    fn act(&mut self, t: u64, _obs: &[f32]) -> Result<Action, String> {
        loop {
            self.line.clear();
            match self.r.read_line(&mut self.line) {
                Ok(0) => return Err(format!("stdin closed before the action of step {}", t + 1)),
                Ok(_) if self.line.trim().is_empty() => continue,
                Ok(_) => break,
                Err(e) => return Err(format!("reading actions from stdin: {e}")),
            }
        }
        let v: serde_json::Value = serde_json::from_str(self.line.trim()).map_err(|e| {
            format!(
                "step {}: action \"{}\" is not JSON: {e}",
                t + 1,
                quote_input(self.line.trim())
            )
        })?;
        let space = self.space.as_ref().ok_or("no episode has begun")?;
        parse_action(&v, space).map_err(|m| format!("step {}: {m}", t + 1))
    }

    fn stepped(
        &mut self,
        t: u64,
        action: &Action,
        obs: &[f32],
        reward: f64,
        terminated: bool,
        truncated: bool,
    ) -> Result<(), String> {
        let record = StepRecord {
            t,
            action,
            obs,
            outcome: crate::envs::StepOutcome {
                reward,
                terminated,
                truncated,
            },
        };
        let r = write_step(&mut self.w, &record, None).and_then(|()| self.w.flush());
        emitted(r)
    }
}

/// A closed pipe ends the run quietly ([`CLOSED`]); any other write failure is an error.
fn emitted(r: std::io::Result<()>) -> Result<(), String> {
    match r {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Err(CLOSED.into()),
        Err(e) => Err(format!("cannot write to standard output: {e}")),
    }
}

/// A driver that counts episodes on the progress line.
struct Counted<D> {
    inner: D,
    progress: super::progress::Progress,
}

impl<D: Driver> Driver for Counted<D> {
    fn begin(
        &mut self,
        info: &EpisodeInfo,
        obs: &[f32],
        context: &serde_json::Map<String, serde_json::Value>,
    ) -> Result<(), String> {
        self.progress.inc(1);
        self.progress.message(info.body.clone());
        self.inner.begin(info, obs, context)
    }
    fn act(&mut self, t: u64, obs: &[f32]) -> Result<Action, String> {
        self.inner.act(t, obs)
    }
    fn stepped(
        &mut self,
        t: u64,
        action: &Action,
        obs: &[f32],
        reward: f64,
        terminated: bool,
        truncated: bool,
    ) -> Result<(), String> {
        self.inner.stepped(t, action, obs, reward, terminated, truncated)
    }
}
