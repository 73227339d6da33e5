//! `carl-spec bench ENV [--num-envs N] [--steps M] [--threads T]`: steps per second of one
//! scalar environment and of a `VecEnv`, as one JSON line (the measurements are
//! [`crate::bench`]'s, shared with `benches/envs.rs`).
//!
//! `steps` is the number of environment steps timed in each run (the batch run takes
//! `steps / num_envs` batch steps); left out, it is calibrated so that a run takes about a second,
//! whether a step costs 20 ns (CartPole) or a millisecond (Humanoid).

use super::{Cli, CmdResult, Failure, exit, out};
use crate::bench::{
    BenchError, calibrated_steps, check_steps, max_num_envs, observe_ns_per_call, single_ns_per_step, vec_steps_per_sec,
};
use crate::envs::registry::{ids_text, lookup};

/// More threads than this only measure the scheduler.
const MAX_THREADS: usize = 256;

fn failed(e: BenchError) -> Failure {
    match e {
        BenchError::Limit(m) => Failure::usage(m),
        e => Failure::failed(e.to_string()),
    }
}

pub fn run(cli: &Cli, env: &str, num_envs: Option<usize>, steps: Option<u64>, threads: Option<usize>) -> CmdResult {
    let specs = super::load_specs(cli)?;
    let Some(spec) = specs.get(env) else {
        let names: Vec<&str> = specs.envs().iter().map(|s| s.id.as_str()).collect();
        let hint = crate::suggest::did_you_mean(env, names)
            .map(|s| format!(" (did you mean \"{s}\"?)"))
            .unwrap_or_default();
        return Err(Failure::usage(format!(
            "unknown environment \"{env}\"{hint}; runtimes exist for: {}",
            ids_text()
        )));
    };
    let Some(reg) = lookup(&spec.id) else {
        return Err(Failure::usage(format!(
            "environment \"{}\" has a spec but no runtime; runtimes exist for: {}",
            spec.id,
            ids_text()
        )));
    };
    let progress = super::progress::Progress::bar(3, "runs timed");
    let num_envs = num_envs.unwrap_or(reg.cost.bench_num_envs());
    if num_envs == 0 || num_envs > max_num_envs(spec) {
        return Err(Failure::usage(format!(
            "--num-envs {num_envs} is outside 1..={} for {} (a limit of this command, to stay within memory)",
            max_num_envs(spec),
            spec.id
        )));
    }
    let steps = match steps {
        Some(s) => {
            check_steps(s).map_err(failed)?;
            s
        }
        None => {
            progress.message("calibrating");
            calibrated_steps(spec, 1.0).map_err(failed)?
        }
    };
    if let Some(t) = threads.filter(|t| *t > MAX_THREADS) {
        return Err(Failure::usage(format!("--threads {t} is above {MAX_THREADS}")));
    }
    let threads = threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        .clamp(1, num_envs);
    progress.message("one environment");
    let single_ns = single_ns_per_step(spec, steps).map_err(failed)?;
    progress.inc(1);
    progress.message(format!("VecEnv of {num_envs}"));
    let vec_sps = vec_steps_per_sec(spec, num_envs, threads, steps).map_err(failed)?;
    progress.inc(1);
    progress.message("observation");
    let observe_ns = observe_ns_per_call(spec, steps.min(10_000)).map_err(failed)?;
    progress.finish();
    let line = serde_json::json!({
        "env": spec.id,
        "single_steps_per_sec": (1e9 / single_ns).round(),
        "single_ns_per_step": (single_ns * 100.0).round() / 100.0,
        "observe_ns_per_call": (observe_ns * 100.0).round() / 100.0,
        "vec_steps_per_sec": vec_sps.round(),
        "num_envs": num_envs,
        "threads": threads,
        "steps": steps,
    });
    out(&format!("{line}\n"))?;
    Ok(exit::OK)
}
