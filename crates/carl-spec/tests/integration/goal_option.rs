//! The `goal` option of the locomotion robots (carl-bench's goal-directed walkers): features that
//! act only with an option are refused without it, the option off leaves the task alone.

use carl_spec::envs::Env;
use carl_spec::envs::registry::{Context, EnvOptions, MakeError, MakeOptions, lookup, make, make_env};
use carl_spec::spec::SpecSet;
use carl_spec::spec::model::Value;

const GOAL_ENVS: [&str; 5] = ["ant", "half_cheetah", "hopper", "humanoid", "walker2d"];

fn goal_on() -> EnvOptions {
    EnvOptions::from([("goal".to_string(), Value::Bool(true))])
}

#[test]
fn target_features_without_the_goal_option_are_refused_naming_it() {
    let specs = SpecSet::bundled().unwrap();
    for id in GOAL_ENVS {
        let spec = specs.get(id).unwrap();
        for (name, v) in [
            ("target_distance", Value::Number(20.0)),
            ("target_direction", Value::Number(2.0)),
            ("target_radius", Value::Number(1.0)),
        ] {
            let ctx = Context::from([(name.to_string(), v.clone())]);
            let e = make(spec, &ctx).unwrap_err();
            let msg = e.to_string();
            assert!(matches!(e, MakeError::NeedsOption { .. }), "{id} {name}: {msg}");
            assert!(msg.contains("option goal") && msg.contains(name), "{msg}");
            assert!(
                make_env(spec, &ctx, MakeOptions::default(), &goal_on()).is_ok(),
                "{id} {name}"
            );
        }
        // At their defaults they are accepted without the option (a full default context).
        let ctx = Context::from([("target_distance".to_string(), Value::Number(100.0))]);
        assert!(make(spec, &ctx).is_ok(), "{id}");
        // A label names a direction.
        let ctx = Context::from([("target_direction".to_string(), Value::String("south west".into()))]);
        let mut env = make_env(spec, &ctx, MakeOptions::default(), &goal_on()).unwrap();
        let (_, info) = env.reset(Some(0));
        assert_eq!(info.get("goal_direction"), Some(&34.0), "{id}");
    }
}

#[test]
fn every_option_feature_names_a_bool_option_of_its_runtime() {
    let specs = SpecSet::bundled().unwrap();
    let mut seen = 0;
    for id in carl_spec::envs::registry::ids() {
        let spec = specs.get(id).unwrap();
        for f in &spec.features {
            let Some(o) = &f.requires_option else { continue };
            seen += 1;
            let reg = lookup(&spec.id).unwrap_or_else(|| panic!("{}: no runtime", spec.id));
            let decl = reg.options.iter().find(|d| d.name == o);
            assert!(
                matches!(
                    decl.map(|d| d.kind),
                    Some(carl_spec::envs::registry::OptionKind::Bool { default: false })
                ),
                "{}: {} requires option {o}, which the runtime does not declare as a bool off by default",
                spec.id,
                f.name
            );
        }
    }
    assert_eq!(seen, 15);
}

#[test]
fn the_goal_option_off_is_the_task_and_on_replaces_reward_and_adds_info() {
    let specs = SpecSet::bundled().unwrap();
    for id in GOAL_ENVS {
        let spec = specs.get(id).unwrap();
        let off = EnvOptions::from([("goal".to_string(), Value::Bool(false))]);
        let mut a = make(spec, &Context::new()).unwrap();
        let mut b = make_env(spec, &Context::new(), MakeOptions::default(), &off).unwrap();
        let mut c = make_env(spec, &Context::new(), MakeOptions::default(), &goal_on()).unwrap();
        let (oa, _) = a.reset(Some(2));
        let (ob, _) = b.reset(Some(2));
        let (oc, ic) = c.reset(Some(2));
        assert_eq!(oa, ob);
        assert_eq!(oa, oc);
        assert_eq!(ic.get("success"), Some(&0.0));
        assert!((ic["goal_distance"] - 100.0).abs() < 1e-9, "{id}: {ic:?}");
        let n = match a.action_space() {
            carl_spec::envs::Space::Box { shape, .. } => shape[0],
            _ => unreachable!(),
        };
        for t in 0..5 {
            let act =
                carl_spec::envs::Action::Continuous((0..n).map(|k| ((t + k) as f32 * 0.37).sin() * 0.4).collect());
            let sa = a.step(&act).unwrap();
            let sb = b.step(&act).unwrap();
            let sc = c.step(&act).unwrap();
            assert_eq!((&sa.obs, sa.reward, sa.terminated), (&sb.obs, sb.reward, sb.terminated));
            assert_eq!(sa.obs, sc.obs, "{id}: the goal changes no observation");
            assert!(sc.reward >= 0.0 && !sa.info.contains_key("success"));
            assert_eq!(sc.info.get("goal_direction"), Some(&1.0));
        }
    }
}

/// With the option on, every goal feature at each of its finite bounds (and every direction)
/// gives finite observations and rewards.
#[test]
fn the_goal_variant_is_finite_at_the_goal_features_bounds() {
    let specs = SpecSet::bundled().unwrap();
    for id in ["ant", "hopper"] {
        let spec = specs.get(id).unwrap();
        let mut contexts: Vec<Context> = Vec::new();
        for f in spec.features.iter().filter(|f| f.requires_option.is_some()) {
            for b in f.bounds.iter().flatten() {
                contexts.push(Context::from([(f.name.clone(), Value::Number(*b))]));
            }
            for c in f.choices.iter().flatten() {
                if let carl_spec::spec::model::Scalar::Number(x) = c {
                    contexts.push(Context::from([(f.name.clone(), Value::Number(*x))]));
                }
            }
        }
        assert!(contexts.len() >= 20);
        for ctx in contexts {
            let mut env = make_env(spec, &ctx, MakeOptions::default(), &goal_on()).unwrap();
            let (obs, _) = env.reset(Some(0));
            assert!(obs.iter().all(|x| x.is_finite()));
            let n = match env.action_space() {
                carl_spec::envs::Space::Box { shape, .. } => shape[0],
                _ => unreachable!(),
            };
            for _ in 0..3 {
                let s = env.step(&carl_spec::envs::Action::Continuous(vec![0.3; n])).unwrap();
                assert!(s.reward.is_finite() && s.reward >= 0.0, "{id} {ctx:?}");
                assert!(s.info["goal_distance"].is_finite());
                if s.terminated {
                    break;
                }
            }
        }
    }
}
