//! Checks shared by the robot test files (`use crate::common;` in each), and a temporary folder
//! that removes itself.

// Each test file uses only some of these helpers.
#![allow(dead_code)]

use carl_spec::envs::registry::{Context, MakeOptions, make, make_with};
use carl_spec::envs::{Action, Env, Step};
use carl_spec::spec::model::{EnvSpec, Value};

/// The test range of a feature: its bounds, with an open side replaced by a value far from the
/// default (0 or 20× the default for positive defaults, 20× − 1 or +1 for others).
pub fn test_range(default: f64, bounds: [Option<f64>; 2]) -> [f64; 2] {
    let lo = bounds[0].unwrap_or(if default > 0.0 { 0.0 } else { default * 20.0 - 1.0 });
    let hi = bounds[1].unwrap_or(if default > 0.0 { default * 20.0 } else { 1.0 });
    [lo, hi]
}

/// Every feature at each end of its range, the others at their defaults: reset and `actions`
/// give finite observations, rewards and states, and the only termination is a diverged
/// (rolled back, flagged) step, after which the environment resets and goes on.
pub fn finite_at_the_spec_bounds_for_a_task_without_termination(spec: &EnvSpec, actions: &[Action]) {
    // Features acting only with an option are checked with it (goal_option.rs).
    for f in spec.features.iter().filter(|f| f.requires_option.is_none()) {
        let d = f.default_f64().unwrap();
        for x in test_range(d, f.bounds) {
            let ctx: Context = [(f.name.clone(), Value::Number(x))].into_iter().collect();
            let mut e = make(spec, &ctx).unwrap_or_else(|err| panic!("{} = {x}: {err}", f.name));
            let (obs, _) = e.reset(Some(1));
            assert!(obs.iter().all(|v| v.is_finite()), "{} = {x}", f.name);
            for a in actions {
                let out = e.step(a).unwrap();
                assert!(out.obs.iter().all(|v| v.is_finite()), "{} = {x}", f.name);
                assert!(out.reward.is_finite(), "{} = {x}", f.name);
                assert!(e.state().iter().all(|v| v.is_finite()), "{} = {x}", f.name);
                if out.terminated {
                    assert_eq!(
                        out.info["diverged"], 1.0,
                        "{} = {x}: only a diverged step terminates",
                        f.name
                    );
                    e.reset(None);
                }
            }
        }
    }
}

/// An instance driven past any physical speed by `ctx` (bounds not enforced): within `actions`
/// a step is rolled back, flagged `info["diverged"]` and terminated, and observations stay finite
/// until then. Returns the flagged step.
pub fn runaway_is_flagged(spec: &EnvSpec, ctx: &[(&str, f64)], actions: &[Action]) -> Step {
    let ctx: Context = ctx.iter().map(|(k, v)| (k.to_string(), Value::Number(*v))).collect();
    let mut e = make_with(
        spec,
        &ctx,
        MakeOptions {
            allow_out_of_bounds: true,
        },
    )
    .unwrap();
    e.reset(Some(0));
    for a in actions {
        let s = e.step(a).unwrap();
        assert!(s.obs.iter().all(|x| x.is_finite()));
        if s.info["diverged"] == 1.0 {
            assert!(s.terminated);
            return s;
        }
    }
    panic!("the runaway instance was never flagged");
}

/// Episode lengths and returns of the random policy seeded `seed` (the environment reset with
/// the same seed), one episode per seed, each on a fresh environment from `make_env`.
pub fn random_episodes<E: Env>(seeds: std::ops::Range<u64>, mut make_env: impl FnMut() -> E) -> (Vec<f64>, Vec<f64>) {
    use carl_spec::envs::policy::{Policy, RandomPolicy};
    let (mut lens, mut rets) = (Vec::new(), Vec::new());
    for seed in seeds {
        let mut e = make_env();
        let mut policy = RandomPolicy::new(e.action_space(), seed);
        let (mut obs, _) = e.reset(Some(seed));
        let (mut n, mut ret) = (0usize, 0.0);
        loop {
            let a = policy.act(&obs).unwrap().unwrap();
            let s = e.step(&a).unwrap();
            n += 1;
            ret += s.reward;
            obs = s.obs;
            if s.terminated || s.truncated {
                break;
            }
        }
        lens.push(n as f64);
        rets.push(ret);
    }
    (lens, rets)
}

/// A fresh folder under the system temp directory, removed with everything in it when dropped
/// (so a test leaves nothing behind, also when it fails).
pub struct TempDir(std::path::PathBuf);

impl TempDir {
    /// `carl-spec-<tag>-<pid>-<n>`, empty.
    pub fn new(tag: &str) -> TempDir {
        use std::sync::atomic::{AtomicUsize, Ordering};
        static N: AtomicUsize = AtomicUsize::new(0);
        let n = N.fetch_add(1, Ordering::Relaxed);
        let p = std::env::temp_dir().join(format!("carl-spec-{tag}-{}-{n}", std::process::id()));
        let _ = std::fs::remove_dir_all(&p);
        std::fs::create_dir_all(&p).unwrap();
        TempDir(p)
    }
}

impl std::ops::Deref for TempDir {
    type Target = std::path::Path;
    fn deref(&self) -> &std::path::Path {
        &self.0
    }
}

impl AsRef<std::path::Path> for TempDir {
    fn as_ref(&self) -> &std::path::Path {
        &self.0
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}
