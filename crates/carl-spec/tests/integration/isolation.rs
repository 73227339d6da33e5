//! No shared state between environments, for every runtime of the environment table: two
//! instances with different contexts, stepped alternately in one process, each produce exactly
//! what they produce alone.

use carl_spec::audit::probes::perturbed_values;
use carl_spec::envs::policy::RandomPolicy;
use carl_spec::envs::registry::{Context, REGISTRY, SpecEnv, make};
use carl_spec::envs::{Action, Env};
use carl_spec::spec::SpecSet;
use carl_spec::spec::model::{Effect, Value};

/// Steps per instance: enough for contacts and a reset in the light environments, few for the
/// heavy ones (each step is a 3-D physics world).
fn steps(id: &str) -> usize {
    match id {
        "humanoid" | "grasp" | "fetch" => 12,
        "ant" | "half_cheetah" | "ur5e" | "vehicle_racing" => 30,
        _ => 300,
    }
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
        let n = steps(reg.id);
        let mut policy = RandomPolicy::new(build(&Context::new()).action_space(), 7);
        let actions: Vec<Action> = (0..n).map(|_| policy.sample()).collect();
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
