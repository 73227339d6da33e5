//! `ContextualEnv::set_next_context`, what curricula stand on: the chosen context plays exactly
//! the next episode, then the source's own contexts return; a distribution's draws (and so every
//! later episode's seeds) do not depend on the choices; bad choices are refused, changing nothing.

use carl_spec::envs::{ContextSource, ContextualEnv, ContextualOptions, Env};
use carl_spec::spec::SpecSet;
use carl_spec::spec::model::Value;

fn env(source: ContextSource) -> ContextualEnv {
    let specs = SpecSet::bundled().unwrap();
    ContextualEnv::new(specs.get("pendulum").unwrap(), source, ContextualOptions::default()).unwrap()
}

fn g(env: &ContextualEnv) -> f64 {
    env.context_info().context.iter().find(|(k, _)| k == "g").unwrap().1
}

fn choose(g: f64) -> carl_spec::envs::registry::Context {
    [("g".to_string(), Value::Number(g))].into()
}

#[test]
fn the_choice_plays_one_episode_then_the_fixed_context_returns() {
    let mut e = env(ContextSource::Fixed(choose(9.0)));
    let mut obs = vec![0.0f32; 3];
    e.reset_into(Some(0), &mut obs).unwrap();
    assert_eq!(g(&e), 9.0);
    e.set_next_context(&choose(4.0)).unwrap();
    e.reset_into(None, &mut obs).unwrap();
    assert_eq!(g(&e), 4.0);
    e.set_next_context(&choose(5.0)).unwrap();
    e.reset_into(None, &mut obs).unwrap();
    assert_eq!(g(&e), 5.0);
    assert_eq!(e.previous_context_info().unwrap().context[1].1, 4.0);
    e.reset_into(None, &mut obs).unwrap();
    assert_eq!(g(&e), 9.0);
    assert_eq!(e.previous_context_info().unwrap().context[1].1, 5.0);
    e.reset_into(None, &mut obs).unwrap();
    assert_eq!(e.previous_context_info().unwrap().context[1].1, 9.0);
}

#[test]
fn a_distributions_draws_do_not_depend_on_the_choices() {
    let source = || ContextSource::Distribution {
        name: "q1_g_sigma_0_5".into(),
    };
    let (mut a, mut b) = (env(source()), env(source()));
    let (mut oa, mut ob) = (vec![0.0f32; 3], vec![0.0f32; 3]);
    a.reset_into(Some(3), &mut oa).unwrap();
    b.reset_into(Some(3), &mut ob).unwrap();
    b.set_next_context(&choose(2.0)).unwrap();
    a.reset_into(None, &mut oa).unwrap();
    b.reset_into(None, &mut ob).unwrap();
    assert_eq!(g(&b), 2.0);
    for _ in 0..3 {
        a.reset_into(None, &mut oa).unwrap();
        b.reset_into(None, &mut ob).unwrap();
        assert_eq!(
            (g(&a), a.context_info().context_seed),
            (g(&b), b.context_info().context_seed)
        );
        assert_eq!(oa, ob);
    }
}

#[test]
fn bad_choices_are_refused_and_change_nothing() {
    let mut e = env(ContextSource::Fixed(choose(9.0)));
    let mut obs = vec![0.0f32; 3];
    e.reset_into(Some(0), &mut obs).unwrap();
    assert!(
        e.set_next_context(&choose(-1.0))
            .unwrap_err()
            .to_string()
            .contains("outside its bounds")
    );
    let unknown = [("gg".to_string(), Value::Number(1.0))].into();
    assert!(e.set_next_context(&unknown).unwrap_err().to_string().contains("gg"));
    e.reset_into(None, &mut obs).unwrap();
    assert_eq!(g(&e), 9.0);
    let specs = SpecSet::bundled().unwrap();
    let set = carl_spec::instances::Store::new(&specs)
        .load("pendulum/g_l_train")
        .unwrap();
    let mut s = env(ContextSource::Set(set));
    assert!(
        s.set_next_context(&choose(9.0))
            .unwrap_err()
            .to_string()
            .contains("instance set")
    );
}
