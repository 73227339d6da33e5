//! Specs and runtimes agree: every spec feature reaches the runtime, defaults match Gymnasium's,
//! and bad contexts are refused with useful errors.

use carl_spec::envs::Env;
use carl_spec::envs::registry::{Context, MakeError, MakeOptions, ids, make, make_with};
use carl_spec::spec::SpecSet;
use carl_spec::spec::model::Value;

#[test]
fn spec_defaults_equal_runtime_defaults() {
    let specs = SpecSet::bundled().unwrap();
    for id in ids() {
        let spec = specs.get(id).unwrap();
        let default_env = make(spec, &Context::new()).unwrap();
        // The env built from the spec's defaults behaves exactly like the runtime's own default.
        let mut a = default_env.clone();
        let (oa, _) = a.reset(Some(7));
        let mut b = default_env;
        let (ob, _) = b.reset(Some(7));
        assert_eq!(oa, ob);
        if id == "rna_design" {
            // The dataset default is a name, target_structure_ids a list (no default: all).
            use carl_spec::envs::rna_design::{Dataset, RnaDesignParams};
            let p = RnaDesignParams::default();
            assert_eq!(Dataset::from_name("eterna"), Some(p.dataset));
            assert_eq!(p.target_structure_ids, None);
        }
        for f in &spec.features {
            // rna_design's dataset name and id list have no numeric default.
            if id == "rna_design" && f.default_f64().is_none() {
                continue;
            }
            // A computed default (Mario's `noise`: CARL's sampling) has no value to compare.
            if f.default.is_none() {
                assert!(
                    f.default_from.is_some(),
                    "{id}: {} has neither default nor default_from",
                    f.name
                );
                continue;
            }
            // A string choice (RNA's `dataset`) has no numeric value to compare.
            if f.default_f64().is_none() {
                continue;
            }
            let runtime_default = runtime_default(id, &f.name);
            assert_eq!(
                Some(runtime_default),
                f.default_f64(),
                "{id}: {} spec default vs runtime default",
                f.name
            );
            let ctx = Context::from([(f.name.clone(), f.default.clone().unwrap())]);
            assert!(make(spec, &ctx).is_ok(), "{id}: {} at its default", f.name);
        }
    }
}

#[test]
fn unknown_and_out_of_bounds_features_are_refused() {
    let specs = SpecSet::bundled().unwrap();
    let spec = specs.get("cartpole").unwrap();
    let e = make(spec, &Context::from([("gravty".to_string(), Value::Number(1.0))])).unwrap_err();
    let msg = e.to_string();
    assert!(matches!(e, MakeError::UnknownFeature { .. }));
    assert!(
        msg.contains("did you mean \"gravity\"") && msg.contains("masscart"),
        "{msg}"
    );

    let ctx = Context::from([("masscart".to_string(), Value::Number(50.0))]);
    assert!(matches!(make(spec, &ctx), Err(MakeError::OutOfBounds { .. })));
    assert!(
        make_with(
            spec,
            &ctx,
            MakeOptions {
                allow_out_of_bounds: true
            }
        )
        .is_ok()
    );

    // Aliases (carl-bench names) are accepted.
    assert!(make(spec, &Context::from([("tau".to_string(), Value::Number(0.01))])).is_ok());
    let e = make(
        spec,
        &Context::from([("force_magnifier".to_string(), Value::Number(10.5))]),
    )
    .unwrap_err();
    assert!(matches!(e, MakeError::BadValue { .. }));
}

#[test]
fn specs_without_runtime_say_so() {
    let specs = SpecSet::bundled().unwrap();
    // Every bundled spec has a runtime; a spec under any other id says it has none.
    for spec in specs.envs() {
        assert!(carl_spec::envs::registry::has_runtime(&spec.id), "{}", spec.id);
    }
    let mut spec = specs.get("cartpole").unwrap().clone();
    spec.id = "no_such_runtime".into();
    let e = make(&spec, &Context::new()).unwrap_err();
    assert!(matches!(e, MakeError::NoRuntime { .. }), "{e}");
}

fn runtime_default(id: &str, name: &str) -> f64 {
    use carl_spec::envs::classic_control::*;
    if id == "rna_design" {
        let p = carl_spec::envs::rna_design::RnaDesignParams::default();
        return match name {
            "mutation_threshold" => p.mutation_threshold,
            "reward_exponent" => p.reward_exponent,
            "state_radius" => p.state_radius as f64,
            other => panic!("rna_design: no numeric runtime default for {other}"),
        };
    }
    match id {
        "cartpole" => CartPoleParams::default().get(name),
        "pendulum" => PendulumParams::default().get(name),
        "mountain_car" => MountainCarParams::default().get(name),
        "mountain_car_continuous" => MountainCarContinuousParams::default().get(name),
        "acrobot" => AcrobotParams::default().get(name),
        "lunar_lander" => carl_spec::envs::box2d::LunarLanderParams::default().get(name),
        "bipedal_walker" => carl_spec::envs::box2d::BipedalWalkerParams::default().get(name),
        "vehicle_racing" => carl_spec::envs::box2d::VehicleRacingParams::default().get(name),
        "mario" => carl_spec::envs::mario::MarioParams::default().get(name),
        robot if carl_spec::envs::brax::is_robot(robot) => {
            carl_spec::envs::brax::default_params(robot).unwrap().get(name)
        }
        "rna_design" => {
            let p = carl_spec::envs::rna_design::RnaDesignParams::default();
            match name {
                "mutation_threshold" => Ok(p.mutation_threshold),
                "reward_exponent" => Ok(p.reward_exponent),
                "state_radius" => Ok(p.state_radius as f64),
                _ => Err(carl_spec::envs::UnknownFeature {
                    env: "rna_design",
                    name: name.to_string(),
                    known: "mutation_threshold, reward_exponent, state_radius".into(),
                }),
            }
        }
        _ => unreachable!(),
    }
    .unwrap_or_else(|e| panic!("{id}: runtime lacks spec feature {name}: {e}"))
}
