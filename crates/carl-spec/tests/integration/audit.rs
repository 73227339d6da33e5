//! The sensitivity audit: the bundled classic-control specs pass it, and it catches claims that
//! the runtime contradicts.

use std::time::Instant;

use carl_spec::audit::{AuditReport, Measured, Verdict, audit, probes};
use carl_spec::envs::registry::ids;
use carl_spec::spec::model::{Effect, EnvSpec};
use carl_spec::spec::{Feature, SpecSet};

fn spec(id: &str) -> EnvSpec {
    SpecSet::bundled().unwrap().get(id).unwrap().clone()
}

fn feature_mut<'a>(spec: &'a mut EnvSpec, name: &str) -> &'a mut Feature {
    spec.features.iter_mut().find(|f| f.name == name).unwrap()
}

/// The (feature, effect, verdict) triples of the report's contradictions.
fn contradictions(r: &AuditReport) -> Vec<(String, Effect, Verdict)> {
    r.contradictions
        .iter()
        .map(|c| (c.feature.clone(), c.effect, c.verdict))
        .collect()
}

fn measured(r: &AuditReport, feature: &str, effect: Effect) -> Measured {
    r.feature(feature).unwrap().effect(effect).unwrap().measured
}

// Every bundled runtime passes the full audit: checked once, end to end through the CLI
// (`audit --all --format json`, tests/cli.rs), rather than again here.

#[test]
fn known_traps_are_measured_as_specified() {
    let r = audit(&spec("pendulum")).unwrap();
    assert_eq!(measured(&r, "max_speed", Effect::Dynamics), Measured::Changed);
    assert_eq!(measured(&r, "max_speed", Effect::Observation), Measured::Unchanged);

    let r = audit(&spec("mountain_car")).unwrap();
    for goal in ["goal_position", "goal_velocity"] {
        assert_eq!(measured(&r, goal, Effect::Termination), Measured::Changed, "{goal}");
        assert_eq!(measured(&r, goal, Effect::Dynamics), Measured::Unchanged, "{goal}");
        assert_eq!(measured(&r, goal, Effect::Reward), Measured::Unchanged, "{goal}");
    }

    let r = audit(&spec("mountain_car_continuous")).unwrap();
    let goal = r.feature("goal_position").unwrap().effect(Effect::Reward).unwrap();
    assert_eq!(goal.measured, Measured::Changed);
    assert_eq!(goal.max_abs_diff, 100.0, "the +100 goal bonus");
    // `power` changes rewards only by moving the car into (or out of) the goal.
    assert_eq!(measured(&r, "power", Effect::Reward), Measured::ViaDynamics);

    let r = audit(&spec("acrobot")).unwrap();
    let l2 = r.feature("link_length_2").unwrap();
    assert!(l2.claimed.is_empty());
    for e in &l2.effects {
        assert!(
            matches!(e.measured, Measured::Unchanged | Measured::NotApplicable),
            "{e:?}"
        );
    }
    // Terminal states are probed: dynamics features reach the goal differently.
    assert_eq!(measured(&r, "link_mass_1", Effect::Termination), Measured::ViaDynamics);
}

#[test]
fn removing_a_true_claim_is_an_undeclared_effect() {
    let mut s = spec("cartpole");
    feature_mut(&mut s, "masscart")
        .affects
        .retain(|e| *e != Effect::Dynamics);
    let r = audit(&s).unwrap();
    assert!(!r.passed);
    assert_eq!(
        contradictions(&r),
        vec![("masscart".to_string(), Effect::Dynamics, Verdict::UndeclaredEffect)]
    );
    let msg = &r.contradictions[0].message;
    assert!(msg.contains("masscart changes the next state"), "{msg}");
}

#[test]
fn adding_a_false_claim_is_a_missing_effect() {
    let mut s = spec("cartpole");
    feature_mut(&mut s, "gravity").affects.push(Effect::Reward);
    let r = audit(&s).unwrap();
    assert_eq!(
        contradictions(&r),
        vec![("gravity".to_string(), Effect::Reward, Verdict::MissingEffect)]
    );

    // A feature that the runtime ignores cannot claim anything.
    let mut s = spec("acrobot");
    feature_mut(&mut s, "link_length_2").affects.push(Effect::Dynamics);
    let r = audit(&s).unwrap();
    assert_eq!(
        contradictions(&r),
        vec![("link_length_2".to_string(), Effect::Dynamics, Verdict::MissingEffect)]
    );
}

#[test]
fn termination_reward_and_initial_state_claims_are_checked() {
    // Goal velocity only changes termination: claiming dynamics instead is caught twice.
    let mut s = spec("mountain_car");
    feature_mut(&mut s, "goal_velocity").affects = vec![Effect::Dynamics];
    let r = audit(&s).unwrap();
    assert_eq!(
        contradictions(&r),
        vec![
            ("goal_velocity".to_string(), Effect::Dynamics, Verdict::MissingEffect),
            (
                "goal_velocity".to_string(),
                Effect::Termination,
                Verdict::UndeclaredEffect
            ),
        ]
    );

    // The continuous goal pays +100: dropping the reward claim is caught.
    let mut s = spec("mountain_car_continuous");
    feature_mut(&mut s, "goal_position").affects = vec![Effect::Termination];
    let r = audit(&s).unwrap();
    assert_eq!(
        contradictions(&r),
        vec![("goal_position".to_string(), Effect::Reward, Verdict::UndeclaredEffect)]
    );

    let mut s = spec("mountain_car");
    feature_mut(&mut s, "start_position").affects.clear();
    let r = audit(&s).unwrap();
    assert_eq!(
        contradictions(&r),
        vec![(
            "start_position".to_string(),
            Effect::InitialState,
            Verdict::UndeclaredEffect
        )]
    );
}

#[test]
fn audit_is_deterministic() {
    let s = spec("acrobot");
    let a = serde_json::to_string(&audit(&s).unwrap()).unwrap();
    let b = serde_json::to_string(&audit(&s).unwrap()).unwrap();
    assert_eq!(a, b);
}

#[test]
fn perturbed_values_stay_in_bounds() {
    let specs = SpecSet::bundled().unwrap();
    for id in ids() {
        for f in &specs.get(id).unwrap().features {
            let vals = probes::perturbed_values(f);
            // Features without a numeric default (Mario's computed `noise`, rna_design's dataset
            // names and id list) are not perturbed by the audit.
            let Some(d) = f.default_f64() else {
                assert!(vals.is_empty(), "{id}.{}: {vals:?}", f.name);
                continue;
            };
            // Three values, or every other choice of a smaller categorical (Mario's 3 states).
            let want = f.choices.as_ref().map_or(3, |c| (c.len() - 1).min(3));
            assert!(vals.len() >= want, "{id}.{}: {vals:?}", f.name);
            for v in vals {
                assert!(f.in_bounds(v) && v != d && v.is_finite(), "{id}.{} = {v}", f.name);
            }
        }
    }
    // Zero default toward a finite bound and toward an unbounded side.
    let mc = spec("mountain_car");
    let std = mc.feature("start_velocity_std").unwrap();
    assert_eq!(probes::perturbed_values(std), vec![0.01, 0.1, 1.0]);
    let cp = spec("cartpole");
    let force = cp.feature("force_magnifier").unwrap();
    assert!(
        probes::perturbed_values(force).iter().all(|v| v.fract() == 0.0),
        "int feature"
    );
}

#[test]
fn env_without_runtime_is_an_error() {
    // Every bundled spec has a runtime now: a spec under an id without one.
    let mut s = spec("cartpole");
    s.id = "no_such_runtime".into();
    let r = audit(&s);
    let e = r.unwrap_err().to_string();
    assert!(e.contains("no runtime") && e.contains("cartpole"), "{e}");
}

/// `cargo test --test audit timing -- --ignored --nocapture` prints the audit time per environment.
#[test]
#[ignore]
fn timing() {
    let specs = SpecSet::bundled().unwrap();
    for id in ids() {
        let t = Instant::now();
        let r = audit(specs.get(id).unwrap()).unwrap();
        eprintln!("{id}: {:?} ({} states)", t.elapsed(), r.probes.base_states);
    }
}

#[test]
fn categorical_features_are_probed_with_spread_out_choices() {
    let s = spec("vehicle_racing");
    let f = s.features.iter().find(|f| f.name == "VEHICLE").unwrap();
    assert_eq!(probes::unauditable_reason(f), None);
    // 28 other vehicles, 4 of them spread over the garage: a FWD race car, a street car, a bus,
    // and the tuk-tuk with trailer.
    assert_eq!(probes::perturbed_values(f), vec![1.0, 10.0, 19.0, 28.0]);
}
