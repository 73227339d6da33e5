//! No shared state between environments, for every runtime of the environment table: two
//! instances with different contexts, stepped alternately in one process, each produce exactly
//! what they produce alone.

use carl_spec::audit::probes::perturbed_values;
use carl_spec::envs::policy::RandomPolicy;
use carl_spec::envs::registry::{Context, REGISTRY, SpecEnv, make};
use carl_spec::envs::{Action, Env};
use carl_spec::spec::SpecSet;
use carl_spec::spec::model::{Effect, Value};

/// Steps per instance: as many as fit ~40 ms of stepping (at least 12, at most 300): enough for
/// contacts and a reset in the light environments, few for the heavy ones. Both instances and
/// both runs take the same number, so the comparison stays exact.
fn steps(env: &SpecEnv, actions: &[Action]) -> usize {
    let mut probe = env.clone();
    probe.reset(Some(0));
    let start = std::time::Instant::now();
    let mut n = 0;
    while n < actions.len() && start.elapsed() < std::time::Duration::from_millis(40) {
        let s = probe.step(&actions[n]).unwrap();
        if s.terminated || s.truncated {
            probe.reset(Some(0));
        }
        n += 1;
    }
    n.max(12)
}

/// One trajectory record: observation bits, reward bits and flags per step.
type Trace = Vec<(Vec<u32>, u64, bool, bool)>;

fn step(env: &mut SpecEnv, a: &Action, trace: &mut Trace, reset_seed: &mut u64) {
    let s = env.step(a).unwrap();
    trace.push((
        s.obs.iter().map(|x| x.to_bits()).collect(),
        s.reward.to_bits(),
        s.terminated,
        s.truncated,
    ));
    if s.terminated || s.truncated {
        *reset_seed += 1;
        env.reset(Some(*reset_seed));
    }
}

#[test]
fn two_instances_stepped_alternately_equal_each_alone_for_every_runtime() {
    let specs = SpecSet::bundled().unwrap();
    for reg in REGISTRY {
        let spec = specs.get(reg.id).unwrap();
        let build = |ctx: &Context| make(spec, ctx).unwrap();
        let mut policy = RandomPolicy::new(build(&Context::new()).action_space(), 7);
        let mut actions: Vec<Action> = (0..300).map(|_| policy.sample()).collect();
        actions.truncate(steps(&build(&Context::new()), &actions));
        let alone = |ctx: &Context| {
            let mut e = build(ctx);
            e.reset(Some(0));
            let (mut trace, mut seed) = (Trace::new(), 0);
            for a in &actions {
                step(&mut e, a, &mut trace, &mut seed);
            }
            trace
        };
        let want_a = alone(&Context::new());
        // The first feature the spec says changes the dynamics (else, for runtimes without one
        // such as rna_design, the reward or observation) that, moved to the far end of its audit
        // probes, changes this trajectory (else the comparison would prove nothing).
        let dynamics = spec.features.iter().filter(|f| f.affects.contains(&Effect::Dynamics));
        let others = spec.features.iter().filter(|f| {
            !f.affects.contains(&Effect::Dynamics)
                && (f.affects.contains(&Effect::Reward) || f.affects.contains(&Effect::Observation))
        });
        let (other, want_b) = dynamics
            .chain(others)
            .flat_map(|f| perturbed_values(f).into_iter().rev().map(move |v| (f.name.clone(), v)))
            .map(|(name, v)| {
                let ctx: Context = [(name, Value::Number(v))].into_iter().collect();
                let trace = alone(&ctx);
                (ctx, trace)
            })
            .find(|(_, t)| *t != want_a)
            .unwrap_or_else(|| panic!("{}: no dynamics feature changes the trajectory", reg.id));

        let (mut a, mut b) = (build(&Context::new()), build(&other));
        a.reset(Some(0));
        b.reset(Some(0));
        let (mut ta, mut tb, mut sa, mut sb) = (Trace::new(), Trace::new(), 0, 0);
        for act in &actions {
            step(&mut a, act, &mut ta, &mut sa);
            step(&mut b, act, &mut tb, &mut sb);
        }
        assert!(
            ta == want_a,
            "{}: the default instance changed when stepped beside another",
            reg.id
        );
        assert!(
            tb == want_b,
            "{}: the {other:?} instance changed beside another",
            reg.id
        );
    }
}
