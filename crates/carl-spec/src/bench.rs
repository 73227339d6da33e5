//! Speed measurements shared by `carl-spec bench` and the divan benchmarks (`benches/envs.rs`):
//! the same action tables and the same stepping loops, so both report the same thing.
//!
//! Actions are uniformly random, drawn beforehand from a fixed seed (drawing them is not timed);
//! finished episodes are reset automatically (the cost of resets is part of the figure).

use std::hint::black_box;
use std::time::Instant;

use crate::envs::registry::{Context, MakeError, SpecEnv, lookup, make};
use crate::envs::rng::EnvRng;
use crate::envs::vec_env::{VecActions, VecEnv, VecEnvError, VecOptions};
use crate::envs::{Action, Env, EnvError, Space};
use crate::spec::model::EnvSpec;

/// Largest `--steps` (CartPole runs 10^8 steps in a few seconds; a robot would take a day).
pub const MAX_STEPS: u64 = 100_000_000;
/// Largest `--num-envs` for closed-form environments (1 GiB of CartPole state is 2^25 envs;
/// this keeps every buffer far below the machine's memory).
pub const MAX_NUM_ENVS_LIGHT: usize = 65_536;
/// Largest `--num-envs` for physics and pixel environments (each owns a world or a picture).
pub const MAX_NUM_ENVS_HEAVY: usize = 4_096;
/// Steps a calibrated run aims for at most.
pub const MAX_CALIBRATED_STEPS: u64 = 20_000_000;

/// Why a measurement could not run.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    #[error(transparent)]
    Make(#[from] MakeError),
    #[error(transparent)]
    Vec(#[from] VecEnvError),
    #[error(transparent)]
    Env(#[from] EnvError),
    #[error("{0}")]
    Limit(String),
}

/// Random actions of one space: discrete as `i64`, continuous as `f32` rows of `dim` values.
#[derive(Debug, Clone)]
pub enum ActionTable {
    Discrete(Vec<i64>),
    Continuous { values: Vec<f32>, dim: usize },
}

impl ActionTable {
    /// `len` actions of `space` from a generator seeded with `seed`.
    pub fn new(space: &Space, len: usize, seed: u64) -> Self {
        let mut rng = EnvRng::from_seed(seed);
        match space {
            Space::Discrete { n, start } => ActionTable::Discrete(
                (0..len)
                    .map(|_| start + (rng.next_u64() % (*n).max(1) as u64) as i64)
                    .collect(),
            ),
            Space::Box { low, high, .. } => {
                let dim = low.len();
                let values = (0..len * dim)
                    .map(|k| {
                        let (lo, hi) = (f64::from(low[k % dim]), f64::from(high[k % dim]));
                        (lo + (hi - lo) * rng.next_f64()) as f32
                    })
                    .collect();
                ActionTable::Continuous { values, dim }
            }
        }
    }

    /// The table as scalar-environment actions.
    pub fn actions(&self) -> Vec<Action> {
        match self {
            ActionTable::Discrete(a) => a.iter().copied().map(Action::Discrete).collect(),
            ActionTable::Continuous { values, dim } => values
                .chunks((*dim).max(1))
                .map(|c| Action::Continuous(c.to_vec()))
                .collect(),
        }
    }

    /// Batch `k` of `n` environments' actions (the table holds whole batches).
    pub fn batch(&self, k: usize, n: usize) -> VecActions<'_> {
        match self {
            ActionTable::Discrete(a) => VecActions::Discrete(&a[k * n..(k + 1) * n]),
            ActionTable::Continuous { values, dim } => VecActions::Continuous(&values[k * n * dim..(k + 1) * n * dim]),
        }
    }
}

/// One environment stepped with a cycle of random actions, reset when an episode ends.
pub struct SingleRunner {
    env: SpecEnv,
    actions: Vec<Action>,
    obs: Vec<f32>,
    t: usize,
}

/// Length of the random action cycle of a [`SingleRunner`].
const CYCLE: usize = 4096;

impl SingleRunner {
    /// The spec's default context, reset with seed 0.
    pub fn new(spec: &EnvSpec) -> Result<Self, BenchError> {
        let mut env = make(spec, &Context::new())?;
        let actions = ActionTable::new(&env.action_space(), CYCLE, 0x5eed).actions();
        let mut obs = vec![0.0f32; env.obs_dim()];
        env.reset_into(Some(0), &mut obs)?;
        Ok(SingleRunner {
            env,
            actions,
            obs,
            t: 0,
        })
    }

    /// One step (and a reset if the episode ended).
    #[inline]
    pub fn step(&mut self) -> Result<(), EnvError> {
        self.t = (self.t + 1) % CYCLE;
        let out = self.env.step_into(black_box(&self.actions[self.t]), &mut self.obs)?;
        if out.terminated || out.truncated {
            self.env.reset_into(None, &mut self.obs)?;
        }
        black_box(&self.obs);
        Ok(())
    }

    /// The environment (e.g. to time `observe_into`).
    pub fn env(&self) -> &SpecEnv {
        &self.env
    }
}

/// A `VecEnv` stepped with batches of random actions (auto-reset).
pub struct VecRunner {
    venv: VecEnv,
    table: ActionTable,
    batches: usize,
    k: usize,
}

impl VecRunner {
    /// `num_envs` default environments on `threads` threads, reset with seed 0.
    pub fn new(spec: &EnvSpec, num_envs: usize, threads: usize) -> Result<Self, BenchError> {
        check_num_envs(spec, num_envs)?;
        let opts = VecOptions {
            threads,
            ..Default::default()
        };
        let mut venv = VecEnv::new(spec, &vec![Context::new(); num_envs], opts)?;
        let batches = (65_536 / num_envs).clamp(1, 64);
        let table = ActionTable::new(&venv.action_space(), batches * num_envs, 0x5eed);
        venv.reset(0);
        Ok(VecRunner {
            venv,
            table,
            batches,
            k: 0,
        })
    }

    /// One batch step.
    #[inline]
    pub fn step(&mut self) -> Result<(), EnvError> {
        self.k = (self.k + 1) % self.batches;
        let n = self.venv.num_envs();
        let s = self.venv.step(self.table.batch(self.k, n))?;
        black_box(s.obs);
        Ok(())
    }

    pub fn num_envs(&self) -> usize {
        self.venv.num_envs()
    }
    pub fn threads(&self) -> usize {
        self.venv.threads()
    }
}

/// The largest VecEnv `bench` builds for `spec`'s environment.
pub fn max_num_envs(spec: &EnvSpec) -> usize {
    match lookup(&spec.id).map(|r| r.cost) {
        Some(crate::envs::registry::StepCost::Light) => MAX_NUM_ENVS_LIGHT,
        _ => MAX_NUM_ENVS_HEAVY,
    }
}

fn check_num_envs(spec: &EnvSpec, num_envs: usize) -> Result<(), BenchError> {
    let max = max_num_envs(spec);
    if num_envs == 0 || num_envs > max {
        return Err(BenchError::Limit(format!(
            "--num-envs {num_envs} is outside 1..={max} for {}",
            spec.id
        )));
    }
    Ok(())
}

/// Refuse step counts above [`MAX_STEPS`].
pub fn check_steps(steps: u64) -> Result<(), BenchError> {
    if steps == 0 || steps > MAX_STEPS {
        return Err(BenchError::Limit(format!("--steps {steps} is outside 1..={MAX_STEPS}")));
    }
    Ok(())
}

/// Nanoseconds per step of one environment (`steps` steps after a short warm-up).
pub fn single_ns_per_step(spec: &EnvSpec, steps: u64) -> Result<f64, BenchError> {
    let mut r = SingleRunner::new(spec)?;
    for _ in 0..(steps / 10).min(100_000) {
        r.step()?;
    }
    let t0 = Instant::now();
    for _ in 0..steps {
        r.step()?;
    }
    Ok(t0.elapsed().as_secs_f64() * 1e9 / steps.max(1) as f64)
}

/// Nanoseconds per `observe_into` after a reset (the cost of the observation alone; for pixel
/// environments, the rendering).
pub fn observe_ns_per_call(spec: &EnvSpec, calls: u64) -> Result<f64, BenchError> {
    let r = SingleRunner::new(spec)?;
    let mut obs = vec![0.0f32; r.env().obs_dim()];
    let t0 = Instant::now();
    for _ in 0..calls {
        r.env().observe_into(&mut obs)?;
        black_box(&obs);
    }
    Ok(t0.elapsed().as_secs_f64() * 1e9 / calls.max(1) as f64)
}

/// Environment steps per second of a `VecEnv` of `num_envs` default environments.
pub fn vec_steps_per_sec(spec: &EnvSpec, num_envs: usize, threads: usize, steps: u64) -> Result<f64, BenchError> {
    let mut r = VecRunner::new(spec, num_envs, threads)?;
    let batch_steps = (steps / num_envs as u64).max(1);
    for _ in 0..(batch_steps / 10).clamp(1, 1000) {
        r.step()?;
    }
    let t0 = Instant::now();
    for _ in 0..batch_steps {
        r.step()?;
    }
    Ok((batch_steps * num_envs as u64) as f64 / t0.elapsed().as_secs_f64())
}

/// Steps that take about `seconds` for one environment (from short timed runs; 1000 at least).
pub fn calibrated_steps(spec: &EnvSpec, seconds: f64) -> Result<u64, BenchError> {
    let mut n = 100u64;
    loop {
        let ns = single_ns_per_step(spec, n)?;
        let elapsed = ns * n as f64 * 1e-9;
        if elapsed > 0.1 || n >= MAX_CALIBRATED_STEPS {
            return Ok(((seconds * 1e9 / ns.max(1e-3)) as u64).clamp(1000, MAX_CALIBRATED_STEPS));
        }
        n *= 10;
    }
}
