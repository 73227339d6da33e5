//! rna_design's target list as a runtime option (`target_structure_ids`): accepted as a list, one
//! number or CLI text, refused with the reason for unknown ids, bad values, or as a context value;
//! and the finished episode's design reported with its target.

use carl_spec::envs::registry::{Context, EnvOptions, MakeError, MakeOptions, make_env};
use carl_spec::envs::rna_design::RnaDesign;
use carl_spec::envs::{Action, Env};
use carl_spec::spec::SpecSet;
use carl_spec::spec::model::Value;

fn make(options: &[(&str, Value)], context: Context) -> Result<carl_spec::envs::registry::SpecEnv, MakeError> {
    let specs = SpecSet::bundled().unwrap();
    let spec = specs.get("rna_design").unwrap();
    let options: EnvOptions = options.iter().map(|(k, v)| (k.to_string(), v.clone())).collect();
    make_env(spec, &context, MakeOptions::default(), &options)
}

fn ids(option: Value) -> Vec<u32> {
    let env = make(&[("target_structure_ids", option)], Context::new()).unwrap();
    env.inner()
        .downcast_ref::<RnaDesign>()
        .unwrap()
        .targets()
        .iter()
        .map(|t| t.id)
        .collect()
}

#[test]
fn target_ids_come_as_a_list_one_number_or_cli_text() {
    assert_eq!(ids(Value::List(vec![5.0, 1.0])), [5, 1]);
    assert_eq!(ids(Value::Number(17.0)), [17]);
    assert_eq!(ids(Value::String("3, 4,5".into())), [3, 4, 5]);
    let all = make(&[], Context::new()).unwrap();
    assert_eq!(all.inner().downcast_ref::<RnaDesign>().unwrap().targets().len(), 100);
}

#[test]
fn episodes_design_only_the_chosen_targets_and_report_them() {
    let mut env = make(&[("target_structure_ids", Value::List(vec![1.0, 5.0]))], Context::new()).unwrap();
    let mut seen = std::collections::BTreeSet::new();
    for episode in 0..4 {
        let mut obs = vec![0.0; env.obs_dim()];
        env.reset_into((episode == 0).then_some(9), &mut obs).unwrap();
        loop {
            let out = env.step_into(&Action::Discrete(0), &mut obs).unwrap();
            if out.terminated {
                break;
            }
        }
        let rna = env.inner().downcast_ref::<RnaDesign>().unwrap();
        let o = rna.last_outcome().unwrap();
        assert_eq!(o.target_id, rna.target().id);
        assert_eq!(o.target_structure, rna.target().structure);
        assert_eq!(
            (o.design.len(), o.folded.len()),
            (o.target_structure.len(), o.target_structure.len())
        );
        seen.insert(o.target_id);
    }
    assert_eq!(seen.into_iter().collect::<Vec<_>>(), [1, 5]);
}

#[test]
fn bad_target_ids_are_refused_with_the_reason() {
    let err = |v: Value| {
        make(&[("target_structure_ids", v)], Context::new())
            .unwrap_err()
            .to_string()
    };
    let unknown = err(Value::List(vec![1.0, 101.0]));
    assert!(
        unknown.contains("target_structure_ids") && unknown.contains("no target with id 101 (ids are 1..=100)"),
        "{unknown}"
    );
    for bad in [
        Value::List(vec![]),
        Value::List(vec![1.5]),
        Value::Number(-1.0),
        Value::String("1,x".into()),
        Value::Bool(true),
    ] {
        let e = err(bad.clone());
        assert!(e.contains("non-empty list of whole numbers"), "{bad:?}: {e}");
    }
    let mut ctx = Context::new();
    ctx.insert("target_structure_ids".into(), Value::List(vec![1.0]));
    let as_context = make(&[], ctx).unwrap_err().to_string();
    assert!(as_context.contains("give it as an option"), "{as_context}");
}
