//! Specs and runtimes agree: every spec feature reaches the runtime, defaults match Gymnasium's,
//! and bad contexts are refused with useful errors.

use carl_spec::envs::Env;
use carl_spec::envs::registry::{Context, MakeError, MakeOptions, ids, lookup, make, make_with};
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
        let reg = lookup(id).unwrap();
        for f in &spec.features {
            // A computed default (Mario's `noise`: CARL's sampling) has no value to compare.
            if f.default.is_none() {
                assert!(
                    f.default_from.is_some(),
                    "{id}: {} has neither default nor default_from",
                    f.name
                );
                continue;
            }
            // A string choice (RNA's `dataset`) or a list has no numeric value to compare.
            if f.default_f64().is_none() {
                continue;
            }
            let runtime_default = (reg.runtime_default)(&f.name)
                .unwrap_or_else(|| panic!("{id}: the runtime does not know spec feature {}", f.name));
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
