//! The contextual wrapper: seeded selection, round robin, static, visible context and its space,
//! info, independence of wrappers, per-reset distributions, out-of-bounds sets, errors.

use carl_spec::envs::contextual::{CONTEXT_STREAM, ENV_STREAM, SELECTION_STREAM};
use carl_spec::envs::registry::{Context, make};
use carl_spec::envs::{
    Action, ContextSource, ContextualEnv, ContextualError, ContextualOptions, Env, EnvError, Features, Selection,
    Space, Visibility,
};
use carl_spec::instances::{FrozenSet, Store};
use carl_spec::sampling::{Pcg64, dist::below, stream_id};
use carl_spec::spec::SpecSet;
use carl_spec::spec::model::{EnvSpec, Value};

const SET: &str = "pendulum/q1_g_sigma_0_5";

/// Counts heap allocations made by the current thread (tests run on parallel threads).
struct CountingAlloc;

thread_local! {
    static ALLOCS: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

unsafe impl std::alloc::GlobalAlloc for CountingAlloc {
    unsafe fn alloc(&self, layout: std::alloc::Layout) -> *mut u8 {
        let _ = ALLOCS.try_with(|c| c.set(c.get() + 1));
        unsafe { std::alloc::System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: std::alloc::Layout) {
        unsafe { std::alloc::System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: CountingAlloc = CountingAlloc;

fn allocations() -> u64 {
    ALLOCS.with(|c| c.get())
}

fn specs() -> SpecSet {
    SpecSet::bundled().unwrap()
}

fn spec<'a>(specs: &'a SpecSet, id: &str) -> &'a EnvSpec {
    specs.get(id).unwrap()
}

fn load(specs: &SpecSet, name: &str) -> FrozenSet {
    Store::new(specs).load(name).unwrap()
}

fn num(v: &Value) -> f64 {
    match v {
        Value::Number(x) => *x,
        other => panic!("not a number: {other:?}"),
    }
}

fn opts(selection: Selection, visibility: Visibility) -> ContextualOptions {
    ContextualOptions {
        selection,
        visibility,
        ..ContextualOptions::default()
    }
}

fn pendulum_set(selection: Selection, visibility: Visibility) -> ContextualEnv {
    let specs = specs();
    let set = load(&specs, SET);
    ContextualEnv::new(
        spec(&specs, "pendulum"),
        ContextSource::Set(set),
        opts(selection, visibility),
    )
    .unwrap()
}

fn torque(x: f32) -> Action {
    Action::Continuous(vec![x])
}

/// Instance ids and observations of `episodes` resets (the first seeded) with a few steps each.
fn trace(env: &mut ContextualEnv, seed: u64, episodes: usize) -> Vec<(Option<usize>, Vec<f32>)> {
    let mut out = Vec::new();
    for e in 0..episodes {
        let (obs, info) = env.reset_with_info(if e == 0 { Some(seed) } else { None }).unwrap();
        out.push((info.instance_id, obs));
        for t in 0..5 {
            let (step, _) = env.step_with_info(&torque(t as f32 * 0.3 - 0.6)).unwrap();
            out.push((info.instance_id, step.obs));
        }
    }
    out
}

#[test]
fn random_selection_is_reproducible_from_the_seed() {
    let mut a = pendulum_set(Selection::Random, Visibility::Hidden);
    let mut b = pendulum_set(Selection::Random, Visibility::Hidden);
    let ta = trace(&mut a, 7, 8);
    // `b` first runs unrelated episodes: an explicit seed must restart everything.
    trace(&mut b, 99, 3);
    let tb = trace(&mut b, 7, 8);
    assert_eq!(ta, tb);

    // The documented derivation: below(Pcg64::new(seed, stream_id(SELECTION_STREAM)), n), in turn.
    let mut rng = Pcg64::new(7, stream_id(SELECTION_STREAM));
    let expected: Vec<usize> = (0..8).map(|_| below(&mut rng, 100) as usize).collect();
    let got: Vec<usize> = ta.iter().step_by(6).map(|(id, _)| id.unwrap()).collect();
    assert_eq!(got, expected);
    assert!(
        got.windows(2).any(|w| w[0] != w[1]),
        "random selection should vary: {got:?}"
    );

    // Another seed gives another sequence.
    let mut c = pendulum_set(Selection::Random, Visibility::Hidden);
    let tc = trace(&mut c, 8, 8);
    assert_ne!(ta, tc);
}

#[test]
fn initial_state_seed_derivation_is_documented() {
    // Fixed context: a seeded reset seeds the runtime with the seed itself, an unseeded one
    // continues the runtime's stream (Gymnasium's reset(seed=s) then reset()).
    let specs = specs();
    let cp = spec(&specs, "cartpole");
    let mut w = ContextualEnv::new(cp, ContextSource::Fixed(Context::new()), ContextualOptions::default()).unwrap();
    let mut raw = make(cp, &Context::new()).unwrap();
    let (obs, _) = w.reset_with_info(Some(5)).unwrap();
    assert_eq!(obs, raw.reset(Some(5)).0);
    let (obs2, _) = w.reset_with_info(None).unwrap();
    assert_eq!(obs2, raw.reset(None).0);

    // A set: the seed itself first, then the env stream's draws (one per reset).
    let mut s = pendulum_set(Selection::Static(0), Visibility::Hidden);
    let mut raw = make(
        spec(&specs, "pendulum"),
        &s.context_info()
            .context
            .iter()
            .map(|(k, v)| (k.clone(), Value::Number(*v)))
            .collect(),
    )
    .unwrap();
    let (obs, _) = s.reset_with_info(Some(5)).unwrap();
    assert_eq!(obs, raw.reset(Some(5)).0);
    let mut rng = Pcg64::new(5, stream_id(ENV_STREAM));
    rng.next_u64();
    let (obs2, _) = s.reset_with_info(None).unwrap();
    assert_eq!(obs2, raw.reset(Some(rng.next_u64())).0);
}

#[test]
fn selection_mode_does_not_change_initial_state_seeds() {
    // Same seed, different selection modes, same instance by construction (Static 3 vs round robin
    // after reset(Some(3))): identical first observations.
    let mut rr = pendulum_set(Selection::RoundRobin, Visibility::Hidden);
    let mut st = pendulum_set(Selection::Static(3), Visibility::Hidden);
    assert_eq!(
        rr.reset_with_info(Some(3)).unwrap(),
        st.reset_with_info(Some(3)).unwrap()
    );
}

#[test]
fn round_robin_cycles_in_order_from_the_seed() {
    let specs = specs();
    let set = load(&specs, SET);
    let n = set.instances.len();
    let mut env = pendulum_set(Selection::RoundRobin, Visibility::Hidden);
    assert_eq!(env.num_instances(), n);
    for k in 0..(2 * n + 3) {
        // Seeding episodes with their number keeps the cycle in order.
        let seed = if k % 3 == 0 { Some(k as u64) } else { None };
        let (_, info) = env.reset_with_info(seed).unwrap();
        assert_eq!(info.instance_id, Some(k % n));
        assert_eq!(info.episode, k as u64);
        assert_eq!(env.instance_index(), k % n);
    }
    // A seed determines the instances that follow.
    let ids: Vec<_> = [Some(7), None, None, Some(7), None]
        .into_iter()
        .map(|s| env.reset_with_info(s).unwrap().1.instance_id.unwrap())
        .collect();
    assert_eq!(ids, [7, 8, 9, 7, 8]);
}

#[test]
fn static_selection_stays_and_checks_its_index() {
    let mut env = pendulum_set(Selection::Static(42), Visibility::Hidden);
    assert_eq!(env.context_info().instance_id, Some(42));
    for seed in [Some(1), None, Some(2), None, None] {
        let (_, info) = env.reset_with_info(seed).unwrap();
        assert_eq!(info.instance_id, Some(42));
        env.step_with_info(&torque(0.0)).unwrap();
        assert_eq!(env.context_info().instance_id, Some(42));
    }
    let specs = specs();
    let err = ContextualEnv::new(
        spec(&specs, "pendulum"),
        ContextSource::Set(load(&specs, SET)),
        opts(Selection::Static(100), Visibility::Hidden),
    )
    .unwrap_err();
    assert!(
        matches!(
            err,
            ContextualError::StaticOutOfRange {
                index: 100,
                len: 100,
                ..
            }
        ),
        "{err}"
    );
}

fn box_bounds(space: &Space) -> (Vec<f32>, Vec<f32>, Vec<usize>) {
    match space {
        Space::Box { low, high, shape, .. } => (low.clone(), high.clone(), shape.clone()),
        other => panic!("not a box: {other:?}"),
    }
}

#[test]
fn visible_context_appends_the_instance_values_and_extends_the_space() {
    let specs = specs();
    let pend = spec(&specs, "pendulum");
    let set = load(&specs, SET);
    let mut env = pendulum_set(Selection::RoundRobin, Visibility::Visible(Features::All));
    assert_eq!(env.visible_features(), ["dt", "g", "l", "m", "max_speed"]);
    assert_eq!(env.obs_dim(), 3 + 5);

    let (low, high, shape) = box_bounds(&env.observation_space());
    assert_eq!(shape, vec![8]);
    let inf = f32::INFINITY;
    // Base Pendulum bounds (the velocity's follows max_speed: unbounded), then the spec bounds.
    assert_eq!(low, vec![-1.0, -1.0, -inf, 0.0, 0.0, 1e-6, 1e-6, -inf]);
    assert_eq!(high, vec![1.0, 1.0, inf, inf, inf, inf, inf, inf]);

    for k in 0..4 {
        let (obs, info) = env.reset_with_info(Some(k)).unwrap();
        let inst = &set.instances[k as usize];
        let g = num(&inst.context["g"]);
        assert_eq!(info.instance_id, Some(inst.id));
        assert_eq!(obs.len(), 8);
        assert_eq!(&obs[3..], &[0.05, g as f32, 1.0, 1.0, 8.0]);
        let (step, _) = env.step_with_info(&torque(1.0)).unwrap();
        assert_eq!(
            &step.obs[3..],
            &obs[3..],
            "the context part is constant within an episode"
        );
        // The base part is exactly the hidden runtime's observation.
        let mut obs_buf = vec![0.0; 8];
        env.observe_into(&mut obs_buf).unwrap();
        assert_eq!(&obs_buf[..3], &env.inner().observe()[..]);
    }

    // A named subset, given by canonical name, in the given order.
    let mut sub = ContextualEnv::new(
        pend,
        ContextSource::Set(set.clone()),
        opts(
            Selection::Static(3),
            Visibility::Visible(Features::Only(vec!["m".into(), "g".into()])),
        ),
    )
    .unwrap();
    assert_eq!(sub.obs_dim(), 5);
    let (obs, _) = sub.reset(Some(0));
    assert_eq!(&obs[3..], &[1.0, num(&set.instances[3].context["g"]) as f32]);
    let (low, high, shape) = box_bounds(&sub.observation_space());
    assert_eq!(shape, vec![5]);
    assert_eq!(&low[3..], &[1e-6, 0.0]);
    assert_eq!(&high[3..], &[inf, inf]);

    // Hidden: the runtime's own space, with the velocity bound that max_speed moves unbounded.
    let hidden = pendulum_set(Selection::RoundRobin, Visibility::Hidden);
    assert_eq!(hidden.obs_dim(), 3);
    let (low, high, _) = box_bounds(&hidden.observation_space());
    let (rlow, rhigh, _) = box_bounds(&make(pend, &Context::new()).unwrap().observation_space());
    assert_eq!((&low[..2], &high[..2]), (&rlow[..2], &rhigh[..2]));
    assert_eq!((low[2], high[2]), (-inf, inf));
}

#[test]
fn one_observation_space_whatever_the_source() {
    // max_speed sets the Pendulum's velocity bound: for no source is it the default's ±8.
    let specs = specs();
    let pend = spec(&specs, "pendulum");
    let visible = || {
        opts(
            Selection::RoundRobin,
            Visibility::Visible(Features::Only(vec!["max_speed".into()])),
        )
    };
    let sources = [
        ContextSource::Set(load(&specs, "pendulum/q1_max_speed_sigma_0_5")),
        ContextSource::Set(load(&specs, SET)),
        ContextSource::Distribution {
            name: "q1_max_speed_sigma_0_5".into(),
        },
        ContextSource::Fixed(Context::new()),
        ContextSource::Fixed([("max_speed".to_string(), Value::Number(20.0))].into()),
    ];
    let spaces: Vec<Space> = sources
        .into_iter()
        .map(|src| ContextualEnv::new(pend, src, visible()).unwrap().observation_space())
        .collect();
    for s in &spaces[1..] {
        assert_eq!(s, &spaces[0]);
    }
    let (low, high, _) = box_bounds(&spaces[0]);
    assert_eq!(low, vec![-1.0, -1.0, f32::NEG_INFINITY, f32::NEG_INFINITY]);
    assert_eq!(high, vec![1.0, 1.0, f32::INFINITY, f32::INFINITY]);

    // Landing in Space: train on the train set, test on the planets; GRAVITY_Y visible has the
    // spec's declared bounds [-20, -0.01] in both (the planets' Jupiter lies below them).
    let ll = spec(&specs, "lunar_lander");
    let g = || {
        opts(
            Selection::RoundRobin,
            Visibility::Visible(Features::Only(vec!["GRAVITY_Y".into()])),
        )
    };
    let train = ContextualEnv::new(
        ll,
        ContextSource::Set(load(&specs, "lunar_lander/landing_in_space_train")),
        g(),
    )
    .unwrap();
    let mut planets = ContextualEnv::new(
        ll,
        ContextSource::Set(load(&specs, "lunar_lander/landing_in_space_test_planets")),
        g(),
    )
    .unwrap();
    let dist = ContextualEnv::new(
        ll,
        ContextSource::Distribution {
            name: "landing_in_space".into(),
        },
        g(),
    )
    .unwrap();
    assert_eq!(train.observation_space(), planets.observation_space());
    assert_eq!(dist.observation_space(), planets.observation_space());
    let (low, high, _) = box_bounds(&planets.observation_space());
    assert_eq!((low[8], high[8]), (-20.0, -0.01));
    let mut obs = vec![0.0; 9];
    planets.reset_instance_into(Some(0), 0, &mut obs).unwrap();
    assert_eq!(planets.context_info().instance_name.as_deref(), Some("Jupiter"));
    assert!(obs[8] < -20.0, "Jupiter shows its true gravity {}", obs[8]);
}

#[test]
fn reset_to_an_instance() {
    let specs = specs();
    let pend = spec(&specs, "pendulum");
    let set = load(&specs, SET);
    let n = set.instances.len();
    let mut env = ContextualEnv::new(pend, ContextSource::Set(set), ContextualOptions::default()).unwrap();
    let mut plain = env.clone();
    let mut obs = vec![0.0; 3];
    let mut obs2 = vec![0.0; 3];
    // Seed 7 alone would play instance 7 mod n; the option plays 2, from the same initial state.
    env.reset_instance_into(Some(7), 2, &mut obs).unwrap();
    assert_eq!(env.instance_index(), 2);
    plain.reset_into(Some(7), &mut obs2).unwrap();
    assert_eq!(plain.instance_index(), 7 % n);
    assert_eq!(obs, obs2, "the runtime resets with the same seed");
    // Round robin goes on from the chosen instance.
    env.reset_into(None, &mut obs).unwrap();
    assert_eq!(env.instance_index(), 3);
    // Out of range, and sources without instances: errors naming the problem, nothing reset.
    let err = env.reset_instance_into(Some(0), n, &mut obs).unwrap_err();
    assert!(matches!(err, EnvError::Context { .. }), "{err}");
    assert!(err.to_string().contains(&format!("has {n} instance(s)")), "{err}");
    assert_eq!(env.instance_index(), 3);
    let mut fixed =
        ContextualEnv::new(pend, ContextSource::Fixed(Context::new()), ContextualOptions::default()).unwrap();
    let err = fixed.reset_instance_into(Some(0), 0, &mut obs).unwrap_err();
    assert!(err.to_string().contains("not an instance set"), "{err}");
}

fn cartpole_fixed(ctx: &[(&str, f64)]) -> ContextualEnv {
    let specs = specs();
    let ctx: Context = ctx.iter().map(|(k, v)| (k.to_string(), Value::Number(*v))).collect();
    ContextualEnv::new(
        spec(&specs, "cartpole"),
        ContextSource::Fixed(ctx),
        opts(Selection::RoundRobin, Visibility::Visible(Features::All)),
    )
    .unwrap()
}

#[test]
fn two_wrappers_stepped_alternately_equal_each_run_alone() {
    let a_ctx = [("gravity", 20.0), ("pole_length", 1.0)];
    let b_ctx = [("masscart", 2.0), ("force_magnifier", 15.0)];
    let run_alone = |ctx: &[(&str, f64)]| {
        let mut env = cartpole_fixed(ctx);
        let mut out = vec![env.reset(Some(11)).0];
        for t in 0..60 {
            let s = env.step(&Action::Discrete(t % 2)).unwrap();
            out.push(s.obs);
            if s.terminated || s.truncated {
                out.push(env.reset(None).0);
            }
        }
        out
    };
    let alone_a = run_alone(&a_ctx);
    let alone_b = run_alone(&b_ctx);
    assert_ne!(alone_a, alone_b);

    let (mut a, mut b) = (cartpole_fixed(&a_ctx), cartpole_fixed(&b_ctx));
    let mut tr_a = vec![a.reset(Some(11)).0];
    let mut tr_b = vec![b.reset(Some(11)).0];
    for t in 0..60 {
        for (env, tr) in [(&mut a, &mut tr_a), (&mut b, &mut tr_b)] {
            let s = env.step(&Action::Discrete(t % 2)).unwrap();
            tr.push(s.obs);
            if s.terminated || s.truncated {
                tr.push(env.reset(None).0);
            }
        }
    }
    assert_eq!(tr_a, alone_a);
    assert_eq!(tr_b, alone_b);
    // Each observation carries its own context (All features, spec order).
    assert_eq!(&tr_a[0][4..], &[10.0, 20.0, 1.0, 0.1, 1.0, 0.02]);
    assert_eq!(&tr_b[0][4..], &[15.0, 9.8, 2.0, 0.1, 0.5, 0.02]);
}

#[test]
fn info_carries_instance_id_name_and_full_context() {
    let specs = specs();
    let set = load(&specs, SET);
    let mut env = pendulum_set(Selection::Random, Visibility::Hidden);
    let (_, info) = env.reset_with_info(Some(4)).unwrap();
    let id = info.instance_id.unwrap();
    let inst = &set.instances[id];
    assert_eq!(info.instance_name, inst.name);
    assert_eq!(info.context_seed, None);
    let g = num(&inst.context["g"]);
    assert_eq!(
        info.context,
        vec![
            ("dt".to_string(), 0.05),
            ("g".to_string(), g),
            ("l".to_string(), 1.0),
            ("m".to_string(), 1.0),
            ("max_speed".to_string(), 8.0)
        ]
    );
    // The step info reports the same context.
    let (_, step_info) = env.step_with_info(&torque(0.5)).unwrap();
    assert_eq!(step_info, info);

    // Gymnasium-style info maps carry it too.
    let (_, map) = env.reset(Some(4));
    assert_eq!(map["instance_id"], id as f64);
    assert_eq!(map["context.g"], g);
    assert_eq!(map["context.dt"], 0.05);
    let step = env.step(&torque(0.0)).unwrap();
    assert_eq!(step.info["context.g"], g);

    // Fixed contexts have no instance id but the full context.
    let mut cp = cartpole_fixed(&[("gravity", 3.0)]);
    let (_, info) = cp.reset_with_info(None).unwrap();
    assert_eq!(info.instance_id, None);
    assert!(info.context.contains(&("gravity".to_string(), 3.0)));
    assert_eq!(info.context.len(), 6);
}

fn g_of(info: &carl_spec::envs::ContextInfo) -> f64 {
    info.context.iter().find(|(k, _)| k == "g").unwrap().1
}

#[test]
fn distribution_draws_per_reset_differ_and_reproduce() {
    let specs = specs();
    let pend = spec(&specs, "pendulum");
    let new = || {
        ContextualEnv::new(
            pend,
            ContextSource::Distribution {
                name: "q1_g_sigma_0_5".into(),
            },
            opts(
                Selection::RoundRobin,
                Visibility::Visible(Features::Only(vec!["g".into()])),
            ),
        )
        .unwrap()
    };
    let draws = |env: &mut ContextualEnv, seed: u64| -> Vec<(f64, Vec<f32>, u64)> {
        (0..6)
            .map(|e| {
                let (obs, info) = env.reset_with_info(if e == 0 { Some(seed) } else { None }).unwrap();
                let step = env.step(&torque(0.2)).unwrap();
                assert_eq!(step.obs[3], g_of(&info) as f32);
                (g_of(&info), obs, info.context_seed.unwrap())
            })
            .collect()
    };
    let mut a = new();
    let da = draws(&mut a, 21);
    let gs: Vec<f64> = da.iter().map(|d| d.0).collect();
    for i in 0..gs.len() {
        for j in 0..i {
            assert_ne!(gs[i], gs[j], "draws {i} and {j} coincide: {gs:?}");
        }
    }
    for (g, obs, _) in &da {
        assert_eq!(obs[3], *g as f32, "the visible g is this episode's draw");
        assert!(*g >= 0.0, "draws respect the bounds");
    }
    let mut b = new();
    draws(&mut b, 5);
    assert_eq!(draws(&mut b, 21), da, "same seed, same draws and observations");
    assert_ne!(draws(&mut new(), 22), da);

    // The documented derivation: context seed = next_u64 of the context stream; the context is
    // that seed's single draw.
    let mut rng = Pcg64::new(21, stream_id(CONTEXT_STREAM));
    let dist = &pend.distributions["q1_g_sigma_0_5"];
    for (g, _, seed) in &da {
        assert_eq!(*seed, rng.next_u64());
        let (names, rows) =
            carl_spec::instances::derive::sample_distribution(pend, "q1_g_sigma_0_5", dist, 1, *seed).unwrap();
        assert_eq!(names, vec!["g".to_string()]);
        assert_eq!(num(&rows[0][0]), *g);
    }
}

#[test]
fn bad_feature_names_are_errors_listing_the_valid_names() {
    let specs = specs();
    let pend = spec(&specs, "pendulum");
    let make_with = |names: Vec<&str>| {
        ContextualEnv::new(
            pend,
            ContextSource::Set(load(&specs, SET)),
            opts(
                Selection::RoundRobin,
                Visibility::Visible(Features::Only(names.into_iter().map(String::from).collect())),
            ),
        )
    };
    let err = make_with(vec!["g", "gravity_x"]).unwrap_err();
    let msg = err.to_string();
    assert!(
        matches!(err, ContextualError::UnknownFeature { ref name, .. } if name == "gravity_x"),
        "{msg}"
    );
    assert!(msg.contains("valid names: dt, g, l, m, max_speed"), "{msg}");
    let msg = make_with(vec!["mass"]).unwrap_err().to_string();
    assert!(msg.contains("did you mean \"m"), "{msg}");
    let err = make_with(vec!["g", "g"]).unwrap_err();
    assert!(matches!(err, ContextualError::DuplicateFeature { .. }), "{err}");

    let err = ContextualEnv::new(
        pend,
        ContextSource::Distribution {
            name: "q1_g_sigma_05".into(),
        },
        ContextualOptions::default(),
    )
    .unwrap_err();
    assert!(err.to_string().contains("did you mean \"q1_g_sigma_0_5\""), "{err}");

    // A set of another environment.
    let err = ContextualEnv::new(
        spec(&specs, "cartpole"),
        ContextSource::Set(load(&specs, SET)),
        ContextualOptions::default(),
    )
    .unwrap_err();
    assert!(matches!(err, ContextualError::WrongEnv { .. }), "{err}");
}

#[test]
fn out_of_bounds_instances_run_only_when_the_set_allows_them() {
    // Like Landing-in-Space's Jupiter: a deliberately out-of-bounds value (g < 0 here).
    let specs = specs();
    let pend = spec(&specs, "pendulum");
    let mut set = load(&specs, SET);
    set.instances[1].context.insert("g".into(), Value::Number(-5.0));
    let visible = opts(
        Selection::Static(1),
        Visibility::Visible(Features::Only(vec!["g".into()])),
    );

    let err = ContextualEnv::new(pend, ContextSource::Set(set.clone()), visible.clone()).unwrap_err();
    assert!(err.to_string().contains("outside its bounds"), "{err}");

    set.provenance.definition.allow_out_of_bounds = true;
    let mut env = ContextualEnv::new(pend, ContextSource::Set(set), visible).unwrap();
    let (obs, info) = env.reset_with_info(Some(0)).unwrap();
    assert_eq!(g_of(&info), -5.0);
    assert_eq!(obs[3], -5.0);
    // The space is the declared one whatever the set: the out-of-bounds value lies outside it.
    let (low, _, _) = box_bounds(&env.observation_space());
    assert_eq!(low[3], 0.0);
    assert!(obs[3] < low[3]);
    env.step(&torque(1.0)).unwrap();

    // Fixed contexts never go out of bounds.
    let ctx: Context = [("g".to_string(), Value::Number(-5.0))].into();
    let err = ContextualEnv::new(pend, ContextSource::Fixed(ctx), ContextualOptions::default()).unwrap_err();
    assert!(err.to_string().contains("outside its bounds"), "{err}");
}

#[test]
fn bad_buffers_and_early_steps_are_errors() {
    let mut env = pendulum_set(Selection::RoundRobin, Visibility::Visible(Features::All));
    assert!(matches!(env.step(&torque(0.0)), Err(EnvError::NeedsReset { .. })));
    let mut short = vec![0.0; 3];
    assert!(matches!(
        env.reset_into(Some(0), &mut short),
        Err(EnvError::ObsBufferLength {
            expected: 8,
            got: 3,
            ..
        })
    ));
    let mut obs = vec![0.0; 8];
    env.reset_into(Some(0), &mut obs).unwrap();
    assert!(matches!(
        env.step_into(&torque(0.0), &mut short),
        Err(EnvError::ObsBufferLength { .. })
    ));
    assert!(matches!(
        env.step_into(&Action::Discrete(0), &mut obs),
        Err(EnvError::ActionKind { .. })
    ));
}

#[test]
fn episodes_truncate_at_the_spec_limit() {
    let mut env = pendulum_set(Selection::Random, Visibility::Hidden);
    let mut obs = vec![0.0; 3];
    env.reset_into(Some(1), &mut obs).unwrap();
    let mut steps = 0;
    loop {
        steps += 1;
        let out = env.step_into(&torque(0.0), &mut obs).unwrap();
        if out.truncated {
            break;
        }
    }
    assert_eq!(steps, 200);
}

#[test]
fn stepping_and_set_resets_do_not_allocate() {
    let mut env = pendulum_set(Selection::Random, Visibility::Visible(Features::All));
    let mut obs = vec![0.0; env.obs_dim()];
    let action = torque(0.7);
    env.reset_into(Some(0), &mut obs).unwrap();
    let before = allocations();
    for episode in 0..20 {
        env.reset_into(if episode % 2 == 0 { Some(episode) } else { None }, &mut obs)
            .unwrap();
        for _ in 0..50 {
            env.step_into(&action, &mut obs).unwrap();
        }
    }
    assert_eq!(allocations() - before, 0, "reset_into/step_into allocated");
    // The counter does count.
    let probe = std::hint::black_box(vec![0u8; 16]);
    assert!(allocations() > before);
    drop(probe);
}
