//! `carl-spec bench ENV [--num-envs N] [--steps M] [--threads T]`: steps per second of one
//! scalar environment and of a `VecEnv`, as one JSON line.
//!
//! Both runs use the spec's default context, uniformly random actions drawn beforehand from a
//! fixed seed (so drawing them is not timed), and automatic resets. `steps` is the number of
//! environment steps timed in each run (the batch run takes `steps / num_envs` batch steps);
//! left out, it is calibrated so that a run takes about a second, whether a step costs 20 ns
//! (CartPole) or a millisecond (Humanoid).

use std::hint::black_box;
use std::time::Instant;

use super::{Cli, CmdResult, Failure, exit, out};
use crate::envs::registry::{Context, RUNTIMES, has_runtime, make};
use crate::envs::rng::EnvRng;
use crate::envs::vec_env::{VecActions, VecEnv, VecOptions};
use crate::envs::{Action, Env, Space};
use crate::spec::model::EnvSpec;

/// Random actions for `n` environments, `batches` times over.
enum Table {
    Discrete(Vec<i64>),
    Continuous(Vec<f32>, usize),
}

fn table(space: &Space, len: usize) -> Table {
    let mut rng = EnvRng::from_seed(0x5eed);
    match space {
        Space::Discrete { n, start } => {
            Table::Discrete((0..len).map(|_| start + (rng.next_u64() % *n as u64) as i64).collect())
        }
        Space::Box { low, high, .. } => {
            let dim = low.len();
            let v = (0..len * dim)
                .map(|k| {
                    let (lo, hi) = (low[k % dim] as f64, high[k % dim] as f64);
                    (lo + (hi - lo) * rng.next_f64()) as f32
                })
                .collect();
            Table::Continuous(v, dim)
        }
    }
}

/// Nanoseconds per step of one environment (`steps` steps, auto-reset).
pub fn single_ns_per_step(spec: &EnvSpec, steps: u64) -> Result<f64, Failure> {
    let mut env = make(spec, &Context::new()).map_err(|e| Failure::usage(e.to_string()))?;
    const LEN: usize = 4096;
    let actions: Vec<Action> = match table(&env.action_space(), LEN) {
        Table::Discrete(a) => a.into_iter().map(Action::Discrete).collect(),
        Table::Continuous(a, dim) => a.chunks(dim).map(|c| Action::Continuous(c.to_vec())).collect(),
    };
    let mut obs = vec![0.0f32; env.obs_dim()];
    env.reset_into(Some(0), &mut obs)
        .map_err(|e| Failure::failed(e.to_string()))?;
    let run = |env: &mut crate::envs::registry::SpecEnv, obs: &mut [f32], steps: u64| -> Result<(), Failure> {
        for t in 0..steps {
            let out = env
                .step_into(black_box(&actions[t as usize % LEN]), obs)
                .map_err(|e| Failure::failed(e.to_string()))?;
            if out.terminated || out.truncated {
                env.reset_into(None, obs).map_err(|e| Failure::failed(e.to_string()))?;
            }
            black_box(&*obs);
        }
        Ok(())
    };
    run(&mut env, &mut obs, (steps / 10).min(100_000))?;
    let t0 = Instant::now();
    run(&mut env, &mut obs, steps)?;
    Ok(t0.elapsed().as_secs_f64() * 1e9 / steps.max(1) as f64)
}

/// Nanoseconds per `observe_into` of one environment after a reset (the cost of producing the
/// observation alone; for pixel environments, the rendering).
pub fn observe_ns_per_call(spec: &EnvSpec, calls: u64) -> Result<f64, Failure> {
    let mut env = make(spec, &Context::new()).map_err(|e| Failure::usage(e.to_string()))?;
    let mut obs = vec![0.0f32; env.obs_dim()];
    env.reset_into(Some(0), &mut obs)
        .map_err(|e| Failure::failed(e.to_string()))?;
    let t0 = Instant::now();
    for _ in 0..calls {
        env.observe_into(&mut obs).map_err(|e| Failure::failed(e.to_string()))?;
        black_box(&obs);
    }
    Ok(t0.elapsed().as_secs_f64() * 1e9 / calls.max(1) as f64)
}

/// Environment steps per second of a `VecEnv` of `num_envs` default environments.
pub fn vec_steps_per_sec(spec: &EnvSpec, num_envs: usize, threads: usize, steps: u64) -> Result<f64, Failure> {
    let contexts = vec![Context::new(); num_envs];
    let opts = VecOptions {
        threads,
        ..Default::default()
    };
    let mut v = VecEnv::new(spec, &contexts, opts).map_err(|e| Failure::usage(e.to_string()))?;
    let batches = (65_536 / num_envs).clamp(1, 64);
    let t = table(&v.action_space(), batches * num_envs);
    v.reset(0);
    let batch_steps = (steps / num_envs as u64).max(1);
    let run = |v: &mut VecEnv, n: u64| -> Result<(), Failure> {
        for b in 0..n {
            let k = b as usize % batches;
            let a = match &t {
                Table::Discrete(a) => VecActions::Discrete(&a[k * num_envs..(k + 1) * num_envs]),
                Table::Continuous(a, d) => VecActions::Continuous(&a[k * num_envs * d..(k + 1) * num_envs * d]),
            };
            let s = v.step(a).map_err(|e| Failure::failed(e.to_string()))?;
            black_box(s.obs);
        }
        Ok(())
    };
    run(&mut v, (batch_steps / 10).clamp(1, 1000))?;
    let t0 = Instant::now();
    run(&mut v, batch_steps)?;
    Ok((batch_steps * num_envs as u64) as f64 / t0.elapsed().as_secs_f64())
}

/// Steps that take about `seconds` for one environment (a short timed run; 1000 at least).
fn calibrated_steps(spec: &EnvSpec, seconds: f64) -> Result<u64, Failure> {
    let mut n = 100u64;
    loop {
        let ns = single_ns_per_step(spec, n)?;
        let elapsed = ns * n as f64 * 1e-9;
        if elapsed > 0.1 || n >= MAX_STEPS {
            return Ok(((seconds * 1e9 / ns.max(1e-3)) as u64).clamp(1000, MAX_STEPS));
        }
        n *= 10;
    }
}

const MAX_STEPS: u64 = 20_000_000;

pub fn run(cli: &Cli, env: &str, num_envs: Option<usize>, steps: Option<u64>, threads: Option<usize>) -> CmdResult {
    let specs = super::load_specs(cli)?;
    let Some(spec) = specs.get(env) else {
        let names: Vec<&str> = specs.envs().iter().map(|s| s.id.as_str()).collect();
        let hint = crate::suggest::did_you_mean(env, names)
            .map(|s| format!(" (did you mean \"{s}\"?)"))
            .unwrap_or_default();
        return Err(Failure::usage(format!(
            "unknown environment \"{env}\"{hint}; runtimes exist for: {}",
            RUNTIMES.join(", ")
        )));
    };
    if !has_runtime(&spec.id) {
        return Err(Failure::usage(format!(
            "environment \"{}\" has a spec but no runtime; runtimes exist for: {}",
            spec.id,
            RUNTIMES.join(", ")
        )));
    }
    if num_envs == Some(0) || steps == Some(0) {
        return Err(Failure::usage("--num-envs and --steps must be at least 1"));
    }
    let heavy = make(spec, &Context::new()).is_ok_and(|e| e.inner().is_heavy());
    let num_envs = num_envs.unwrap_or(if heavy { 64 } else { 1024 });
    let steps = match steps {
        Some(s) => s,
        None => calibrated_steps(spec, 1.0)?,
    };
    let threads = threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        .clamp(1, num_envs);
    let single_ns = single_ns_per_step(spec, steps)?;
    let vec_sps = vec_steps_per_sec(spec, num_envs, threads, steps)?;
    let observe_ns = observe_ns_per_call(spec, steps.min(10_000))?;
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
    out(&format!("{line}\n"));
    Ok(exit::OK)
}
