//! Golden trajectories: one hash per environment and version. Each environment of the registry
//! runs a fixed episode prefix (default context, reset seed, actions from a fixed stream) alone
//! and as environment 0 of vector batches (1 and 3 environments, 1 and 2 threads); every run
//! must give the hash recorded for `<id>-v<version>` in `golden/trajectories.json`. A change of
//! dynamics, observation, reward or termination fails here until the spec's `version` is bumped
//! and the new hash recorded (`CARL_SPEC_BLESS=1 cargo test -p carl-spec golden` adds the
//! missing entries; it never rewrites a recorded one).

use std::collections::BTreeMap;
use std::path::PathBuf;

use carl_spec::bench::ActionTable;
use carl_spec::envs::registry::{Context, REGISTRY, make};
use carl_spec::envs::vec_env::{VecActions, VecEnv, VecOptions};
use carl_spec::envs::{Action, Env};
use carl_spec::sampling::Fnv1a64;
use carl_spec::spec::SpecSet;

/// Steps per trajectory: past the first resets of the short episodes, a few hundred
/// milliseconds for the heaviest environment.
const STEPS: usize = 200;
const SEED: u64 = 20;
const ACTION_SEED: u64 = 7;

fn golden_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/integration/golden/trajectories.json")
}

/// FNV-1a over the bits of every observation, reward and flag.
#[derive(Clone, Copy)]
struct Hash(Fnv1a64);

impl Hash {
    fn new() -> Self {
        Hash(Fnv1a64::new())
    }
    fn bytes(&mut self, b: &[u8]) {
        self.0.update(b);
    }
    fn step(&mut self, obs: &[f32], reward: f64, terminated: bool, truncated: bool) {
        for o in obs {
            self.bytes(&o.to_bits().to_le_bytes());
        }
        self.bytes(&reward.to_bits().to_le_bytes());
        self.bytes(&[u8::from(terminated), u8::from(truncated)]);
    }
    fn hex(self) -> String {
        format!("{:016x}", self.0.finish())
    }
}

/// Environment 0's trajectory in a batch of `n` (same-step autoreset: the observation after a
/// finished episode is the next episode's first, as in the scalar loop below).
fn batch_hash(spec: &carl_spec::spec::model::EnvSpec, n: usize, threads: usize, table: &ActionTable) -> String {
    let contexts = vec![Context::new(); n];
    let mut venv = VecEnv::new(
        spec,
        &contexts,
        VecOptions {
            threads,
            ..Default::default()
        },
    )
    .unwrap();
    let d = venv.obs_dim();
    let mut h = Hash::new();
    h.step(&venv.reset(SEED)[..d], 0.0, false, false);
    for t in 0..STEPS {
        let step = venv.step(rows(table, t, n)).unwrap();
        h.step(&step.obs[..d], step.rewards[0], step.terminated[0], step.truncated[0]);
    }
    h.hex()
}

/// Step `t`'s actions of the first `n` environments: the table's entries `3t .. 3t + n`, so
/// environment 0 sees the same actions in every batch size.
fn rows(table: &ActionTable, t: usize, n: usize) -> VecActions<'_> {
    match table {
        ActionTable::Discrete(a) => VecActions::Discrete(&a[3 * t..3 * t + n]),
        ActionTable::Continuous { values, dim } => VecActions::Continuous(&values[3 * t * dim..(3 * t + n) * dim]),
    }
}

fn scalar_hash(spec: &carl_spec::spec::model::EnvSpec, actions: &[Action]) -> String {
    let mut env = make(spec, &Context::new()).unwrap();
    let mut obs = vec![0.0f32; env.obs_dim()];
    env.reset_into(Some(SEED), &mut obs).unwrap();
    let mut h = Hash::new();
    h.step(&obs, 0.0, false, false);
    for a in actions.iter().take(STEPS) {
        let out = env.step_into(a, &mut obs).unwrap();
        if out.terminated || out.truncated {
            env.reset_into(None, &mut obs).unwrap();
        }
        h.step(&obs, out.reward, out.terminated, out.truncated);
    }
    h.hex()
}

#[test]
fn every_environment_version_keeps_its_golden_trajectory() {
    let specs = SpecSet::bundled().unwrap();
    let path = golden_path();
    let mut golden: BTreeMap<String, String> =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap_or_else(|_| "{}".into())).unwrap();
    let bless = std::env::var_os("CARL_SPEC_BLESS").is_some();
    let mut missing = Vec::new();
    for reg in REGISTRY {
        let spec = specs.get(reg.id).unwrap();
        let space = make(spec, &Context::new()).unwrap().action_space();
        let table = ActionTable::new(&space, STEPS * 3, ACTION_SEED);
        let all = table.actions();
        let env0: Vec<Action> = (0..STEPS).map(|t| all[3 * t].clone()).collect();
        let want = scalar_hash(spec, &env0);
        for (n, threads) in [(1, 1), (3, 1), (3, 2)] {
            assert_eq!(
                batch_hash(spec, n, threads, &table),
                want,
                "{}: environment 0 of {n} on {threads} thread(s) differs from the environment alone",
                reg.id
            );
        }
        let key = spec.versioned_id();
        match golden.get(&key) {
            Some(recorded) => assert_eq!(
                *recorded, want,
                "{key}: the trajectory changed; if the dynamics, observation, reward or termination changed on purpose, \
                 bump \"version\" in specs/{}.json and record the new hash (CARL_SPEC_BLESS=1)",
                reg.id
            ),
            None => missing.push((key, want)),
        }
    }
    if bless && !missing.is_empty() {
        golden.extend(missing);
        std::fs::write(&path, serde_json::to_string_pretty(&golden).unwrap() + "\n").unwrap();
    } else {
        assert!(
            missing.is_empty(),
            "no golden trajectory for {missing:?}: record them with CARL_SPEC_BLESS=1"
        );
    }
}
