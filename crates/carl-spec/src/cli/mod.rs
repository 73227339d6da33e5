//! The `carl-spec` command line. Each subcommand lives in its own module; this file only parses
//! arguments and maps outcomes to exit codes (0 ok, 1 invalid specs / failed check, 2 usage or I/O).

#[cfg(feature = "envs")]
mod audit_cmd;
#[cfg(feature = "envs")]
mod bench_cmd;
#[cfg(feature = "envs")]
mod context_args;
#[cfg(feature = "envs")]
mod evaluate_cmd;
#[cfg(feature = "envs")]
mod fold_cmd;
mod instances_cmd;
mod plot_cmd;
#[cfg(feature = "envs")]
mod progress;
#[cfg(feature = "envs")]
mod render_cmd;
#[cfg(feature = "envs")]
mod rollout_cmd;
#[cfg(feature = "envs")]
mod run_cmd;
mod specs_cmd;
mod validate_cmd;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};

#[derive(Parser, Debug)]
#[command(
    name = "carl-spec",
    version,
    about = "The CARL contextual-RL benchmark as declarative, verifiable specs"
)]
pub struct Cli {
    /// An extra directory of spec files, added to the bundled specs.
    #[arg(long, global = true, value_name = "DIR")]
    pub specs: Option<PathBuf>,
    /// The data directory for user-supplied data (Mario levels and TOAD-GAN weights, Rfam-Learn
    /// targets): `mario/` and `rna/` folders as the docs' data guide lays out; overrides the
    /// CARL_SPEC_DATA variable.
    #[arg(long, global = true, value_name = "DIR")]
    pub data_dir: Option<PathBuf>,
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Validate spec files (default: the bundled specs). Exit 0 valid, 1 invalid, 2 usage/I-O error.
    Validate {
        /// Spec files or directories (every *.json below, except frozen instance sets).
        paths: Vec<PathBuf>,
        #[arg(long, value_enum, default_value_t = Format::Text)]
        format: Format,
    },
    /// List the environments: id, family, upstream, number of features.
    List {
        #[arg(long, value_enum, default_value_t = Format::Text)]
        format: Format,
    },
    /// Print one environment's resolved spec (includes merged).
    Show {
        /// Environment id or alias, e.g. `cartpole` or `CARLCartPoleEnv`.
        id: String,
        #[arg(long, value_enum, default_value_t = Format::Text)]
        format: Format,
    },
    /// Print the JSON Schema of spec files.
    Schema,
    /// Instance sets: list, show one, verify all frozen files.
    #[command(subcommand)]
    Instances(instances_cmd::InstancesCommand),
    /// Derive instance sets and write them (atomically) to specs/instances/ENV/SET.json.
    Freeze {
        /// ENV/SET or ENV (all its sets); none: every declared set.
        names: Vec<String>,
        /// Spec directory to write bundled specs' sets into (default: ./specs of the repository).
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// Replace frozen files whose content differs (their old values are lost).
        #[arg(long)]
        force: bool,
    },
    /// Sample contexts ad hoc from a named distribution (nothing is written).
    Sample {
        /// Environment id or alias.
        env: String,
        #[arg(long)]
        distribution: String,
        /// Number of contexts: 1 to 1,000,000, and at most 1,000,000 values (contexts × varied features).
        #[arg(short = 'n', long = "num", value_name = "N")]
        n: u64,
        #[arg(long)]
        seed: u64,
        #[arg(long, value_enum, default_value_t = Format::Text)]
        format: Format,
    },
    #[cfg(feature = "envs")]
    /// Run one episode and print JSON Lines (reset line, then one line per step).
    Rollout(rollout_cmd::RolloutArgs),
    #[cfg(feature = "envs")]
    /// Check every feature's `affects` claim against the runtime by perturbing it within its bounds.
    /// Exit 0 all claims hold, 1 a contradiction, 2 unknown environment or no runtime.
    Audit {
        /// Environment id or alias (one with a runtime), e.g. `cartpole`.
        #[arg(required_unless_present = "all", conflicts_with = "all")]
        env: Option<String>,
        /// Audit every environment that has a runtime.
        #[arg(long)]
        all: bool,
        #[arg(long, value_enum, default_value_t = Format::Text)]
        format: Format,
    },
    #[cfg(feature = "envs")]
    /// Evaluate a policy on every instance of a frozen set (or a distribution's draws, or one
    /// context): per-episode and per-instance return, length and outcome, with provenance.
    /// Exit 0 done, 1 a failed run, 2 bad input (unknown set, a set of another environment,
    /// an action outside the action space).
    Evaluate(evaluate_cmd::EvaluateArgs),
    #[cfg(feature = "envs")]
    /// Run one of the paper's experiments end to end, e.g. `run landing_in_space`.
    #[command(subcommand)]
    Run(run_cmd::RunCommand),
    /// Draw an instance set: a histogram per varied feature, its bounds, marked named instances.
    Plot(plot_cmd::PlotArgs),
    #[cfg(feature = "envs")]
    /// Draw an instance: one PNG, an animated GIF of an episode, or a directory of PNG frames.
    Render(render_cmd::RenderArgs),
    /// Counts over all environments: features, share affecting dynamics/reward, share continuous.
    Stats {
        #[arg(long, value_enum, default_value_t = Format::Text)]
        format: Format,
    },
    #[cfg(feature = "envs")]
    /// RNA secondary structure (MFE, ViennaRNA 2.x default model) like RNAfold; `fold eval` like RNAeval.
    Fold(fold_cmd::FoldArgs),
    #[cfg(feature = "envs")]
    /// Steps per second of one environment and of a VecEnv (random actions, auto-reset), as one JSON line.
    Bench {
        /// Environment id or alias, e.g. `cartpole`.
        env: String,
        /// Environments in the VecEnv run (default: 1024; 64 for physics and pixel environments).
        #[arg(long)]
        num_envs: Option<usize>,
        /// Environment steps timed in each run (default: about one second's worth, measured,
        /// at most 20 000 000).
        #[arg(long)]
        steps: Option<u64>,
        /// Threads for the VecEnv run (default: available cores).
        #[arg(long)]
        threads: Option<usize>,
    },
}

#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum)]
pub enum Format {
    Text,
    Json,
    /// GitHub Actions workflow annotations (validate only; other commands print text).
    Github,
}

/// Exit statuses shared by every command.
pub mod exit {
    pub const OK: u8 = 0;
    pub const FAILED: u8 = 1;
    pub const USAGE: u8 = 2;
}

/// A command's failure: a message for stderr and the exit status.
#[derive(Debug)]
pub struct Failure {
    pub code: u8,
    pub message: String,
}

impl Failure {
    pub fn usage(message: impl Into<String>) -> Self {
        Failure {
            code: exit::USAGE,
            message: message.into(),
        }
    }
    pub fn failed(message: impl Into<String>) -> Self {
        Failure {
            code: exit::FAILED,
            message: message.into(),
        }
    }
}

impl From<crate::spec::LoadError> for Failure {
    fn from(e: crate::spec::LoadError) -> Self {
        match e {
            crate::spec::LoadError::Io { .. } | crate::spec::LoadError::NoSpecFiles { .. } => {
                Failure::usage(e.to_string())
            }
            crate::spec::LoadError::Invalid { .. } => Failure::failed(e.to_string()),
        }
    }
}

pub type CmdResult = Result<u8, Failure>;

/// The `carl-spec` binary's entry point: [`run`] on the process's arguments.
pub fn main() -> ExitCode {
    ExitCode::from(run(std::env::args_os()))
}

/// The whole command line (`args` starts with the program name), returning the exit code. The
/// binary and the Python package's `carl-spec` script both come here, at process start-up:
/// `--data-dir` sets `CARL_SPEC_DATA` for the runtimes built later, which is sound only
/// while no other thread of the process reads the environment.
pub fn run<I, T>(args: I) -> u8
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let cli = match Cli::try_parse_from(args) {
        Ok(c) => c,
        Err(e) => {
            let _ = e.print();
            return if e.use_stderr() { exit::USAGE } else { exit::OK };
        }
    };
    if let Some(dir) = &cli.data_dir {
        if !dir.is_dir() {
            eprintln!("error: --data-dir {}: not a directory", dir.display());
            return exit::USAGE;
        }
        // SAFETY: set once at start-up (see above); the runtimes read CARL_SPEC_DATA when they
        // are built.
        unsafe { std::env::set_var("CARL_SPEC_DATA", dir) };
    }
    let result = match &cli.command {
        Command::Validate { paths, format } => validate_cmd::run(paths, *format),
        Command::List { format } => specs_cmd::list(&cli, *format),
        Command::Show { id, format } => specs_cmd::show(&cli, id, *format),
        Command::Schema => specs_cmd::schema(),
        Command::Stats { format } => specs_cmd::stats(&cli, *format),
        #[cfg(feature = "envs")]
        Command::Rollout(args) => rollout_cmd::run(&cli, args),
        #[cfg(feature = "envs")]
        Command::Evaluate(args) => evaluate_cmd::run(&cli, args),
        #[cfg(feature = "envs")]
        Command::Run(cmd) => run_cmd::run(&cli, cmd),
        Command::Instances(cmd) => instances_cmd::instances(&cli, cmd),
        Command::Freeze { names, out, force } => instances_cmd::freeze(&cli, names, out.as_ref(), *force),
        Command::Plot(args) => plot_cmd::plot(&cli, args),
        #[cfg(feature = "envs")]
        Command::Render(args) => render_cmd::run(&cli, args),
        Command::Sample {
            env,
            distribution,
            n,
            seed,
            format,
        } => instances_cmd::sample(&cli, env, distribution, *n, *seed, *format),
        #[cfg(feature = "envs")]
        Command::Bench {
            env,
            num_envs,
            steps,
            threads,
        } => bench_cmd::run(&cli, env, *num_envs, *steps, *threads),
        #[cfg(feature = "envs")]
        Command::Audit { env, all, format } => audit_cmd::run(&cli, env.as_deref(), *all, *format),
        #[cfg(feature = "envs")]
        Command::Fold(args) => fold_cmd::run(args),
    };
    match result {
        Ok(code) => code,
        Err(f) => {
            eprintln!("error: {}", f.message.trim_end());
            f.code
        }
    }
}

/// Write to stdout, treating a closed pipe (`carl-spec list | head`) as success; any other
/// failure (a full disk: `> /dev/full`) is an error, never a silently truncated result.
pub fn out(text: &str) -> Result<(), Failure> {
    use std::io::Write;
    let mut stdout = std::io::stdout().lock();
    match stdout.write_all(text.as_bytes()).and_then(|()| stdout.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(Failure::failed(format!("cannot write to standard output: {e}")))
        }
        _ => Ok(()),
    }
}

pub(crate) fn load_specs(cli: &Cli) -> Result<crate::spec::SpecSet, Failure> {
    Ok(crate::spec::SpecSet::bundled_with(cli.specs.as_deref())?)
}
