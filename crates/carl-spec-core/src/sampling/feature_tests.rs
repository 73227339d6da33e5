//! Unit and property tests of `FeatureSampler` (compile checks, bounds policies, statistics).

use super::*;
use proptest::prelude::*;

fn float(bounds: Bounds) -> FeatureInfo {
    FeatureInfo {
        name: "length".into(),
        kind: FeatureType::Float,
        default: Some(Value::Number(0.5)),
        bounds,
        choices: None,
    }
}

fn int(bounds: Bounds) -> FeatureInfo {
    FeatureInfo {
        name: "steps".into(),
        kind: FeatureType::Int,
        default: Some(Value::Number(3.0)),
        bounds,
        choices: None,
    }
}

fn compile(s: Sampler, f: FeatureInfo, p: AtBounds) -> Result<FeatureSampler, SamplingError> {
    FeatureSampler::compile(&s, f, p)
}

fn numbers(fs: &FeatureSampler, n: usize) -> Vec<f64> {
    let mut rng = Pcg64::new(99, 1);
    (0..n)
        .map(|i| match fs.sample(&mut rng, i, n) {
            Ok(Value::Number(x)) => x,
            other => panic!("expected a number, got {other:?}"),
        })
        .collect()
}

fn message(e: SamplingError) -> String {
    e.to_string()
}

#[test]
fn compile_errors_are_clear() {
    let cases: Vec<(Sampler, FeatureInfo, &str)> = vec![
        (
            Sampler::Normal { mean: 0.0, std: 0.0 },
            float([None, None]),
            "std must be finite and > 0",
        ),
        (
            Sampler::Normal {
                mean: f64::NAN,
                std: 1.0,
            },
            float([None, None]),
            "mean must be finite",
        ),
        (
            Sampler::Uniform { low: 2.0, high: 1.0 },
            float([None, None]),
            "low 2 must be < high 1",
        ),
        (
            Sampler::LogUniform { low: 0.0, high: 1.0 },
            float([None, None]),
            "low must be > 0",
        ),
        (
            Sampler::Uniform { low: 5.0, high: 6.0 },
            float([Some(0.0), Some(1.0)]),
            "entirely outside the bounds",
        ),
        (
            Sampler::Normal { mean: 0.0, std: 1.0 },
            int([None, None]),
            "integer-valued sampler",
        ),
        (
            Sampler::IntUniform { low: 0, high: 3 },
            float([Some(2.0), Some(1.0)]),
            "not an interval",
        ),
        (
            Sampler::IntUniform { low: 0, high: 3 },
            int([Some(1.2), Some(1.8)]),
            "contain no integer",
        ),
        (
            Sampler::Categorical {
                choices: Some(vec![Scalar::Number(1.0)]),
                weights: Some(vec![-1.0]),
            },
            float([None, None]),
            "weights must be finite and >= 0",
        ),
        (
            Sampler::Categorical {
                choices: Some(vec![Scalar::Number(1.0)]),
                weights: Some(vec![0.0]),
            },
            float([None, None]),
            "finite positive sum",
        ),
        (
            Sampler::Categorical {
                choices: Some(vec![Scalar::Number(1.5)]),
                weights: None,
            },
            int([None, None]),
            "does not fit a int feature",
        ),
        (
            Sampler::IntervalMixture {
                intervals: vec![[0.0, 1.0]],
                weights: Some(vec![1.0]),
                stratified: true,
            },
            float([None, None]),
            "exclude each other",
        ),
        (
            Sampler::Constant {
                value: Value::Number(7.0),
            },
            float([Some(0.0), Some(1.0)]),
            "outside the bounds",
        ),
        (
            Sampler::TruncatedNormal {
                mean: 0.0,
                std: 1e-300,
                low: 1.0,
                high: 2.0,
            },
            float([None, None]),
            "no representable mass",
        ),
    ];
    for (s, f, want) in cases {
        let kind = kind_name(&s);
        match compile(s, f, AtBounds::Clip) {
            Err(e) => {
                let m = message(e);
                assert!(m.contains(want), "{kind}: `{m}` should contain `{want}`");
            }
            Ok(fs) => panic!("{kind}: compiled unexpectedly: {fs:?}"),
        }
    }
}

#[test]
fn categorical_choice_must_be_a_feature_choice() {
    let f = FeatureInfo {
        name: "terrain".into(),
        kind: FeatureType::Categorical,
        default: Some(Value::String("flat".into())),
        bounds: [None, None],
        choices: Some(vec![Scalar::String("flat".into()), Scalar::String("hills".into())]),
    };
    let s = Sampler::Categorical {
        choices: Some(vec![Scalar::String("moon".into())]),
        weights: None,
    };
    let e = message(compile(s, f.clone(), AtBounds::Reject).unwrap_err());
    assert!(
        e.contains("terrain") && e.contains("not among the feature's choices"),
        "{e}"
    );
    let s = Sampler::Categorical {
        choices: None,
        weights: Some(vec![3.0, 1.0]),
    };
    let fs = compile(s, f, AtBounds::Reject).unwrap();
    let mut rng = Pcg64::new(5, 5);
    let flat = (0..40_000)
        .filter(|&i| fs.sample(&mut rng, i, 40_000) == Ok(Value::String("flat".into())))
        .count();
    assert!((29_400..30_600).contains(&flat), "{flat}");
}

#[test]
fn bool_feature_defaults_to_false_true() {
    let f = FeatureInfo {
        name: "flag".into(),
        kind: FeatureType::Bool,
        default: None,
        bounds: [None, None],
        choices: None,
    };
    let fs = compile(
        Sampler::Categorical {
            choices: None,
            weights: None,
        },
        f,
        AtBounds::Clip,
    )
    .unwrap();
    let mut rng = Pcg64::new(1, 1);
    let t = (0..10_000)
        .filter(|&i| fs.sample(&mut rng, i, 10_000) == Ok(Value::Bool(true)))
        .count();
    assert!((4_800..5_200).contains(&t), "{t}");
}

#[test]
fn relative_normal_follows_the_paper_rule() {
    let s = Sampler::RelativeNormal {
        sigma_rel: 0.1,
        fallback_std: 0.5,
    };
    let mut f = float([None, None]);
    f.default = Some(Value::Number(-20.0));
    let xs = numbers(&compile(s.clone(), f.clone(), AtBounds::Clip).unwrap(), 100_000);
    let m = xs.iter().sum::<f64>() / xs.len() as f64;
    let sd = (xs.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / xs.len() as f64).sqrt();
    assert!((m + 20.0).abs() < 0.03 && (sd - 2.0).abs() < 0.03, "{m} {sd}");
    f.default = Some(Value::Number(0.0));
    let xs = numbers(&compile(s.clone(), f.clone(), AtBounds::Clip).unwrap(), 100_000);
    let sd = (xs.iter().map(|x| x * x).sum::<f64>() / xs.len() as f64).sqrt();
    assert!((sd - 0.5).abs() < 0.01, "{sd}");
    f.default = None;
    assert!(message(compile(s, f, AtBounds::Clip).unwrap_err()).contains("default"));
}

#[test]
fn policies() {
    let s = Sampler::Normal { mean: 0.0, std: 1.0 };
    let xs = numbers(
        &compile(s.clone(), float([Some(-0.5), Some(0.5)]), AtBounds::Clip).unwrap(),
        10_000,
    );
    assert!(xs.iter().all(|x| (-0.5..=0.5).contains(x)));
    assert!(
        xs.iter().filter(|&&x| x == 0.5).count() > 2_000,
        "clip pins the tail mass to the bound"
    );
    let xs = numbers(
        &compile(s.clone(), float([Some(-0.5), Some(0.5)]), AtBounds::Resample).unwrap(),
        10_000,
    );
    assert!(xs.iter().all(|x| (-0.5..=0.5).contains(x)));
    assert!(xs.iter().filter(|&&x| x == 0.5).count() < 5);

    let fs = compile(s.clone(), float([Some(-0.5), Some(0.5)]), AtBounds::Reject).unwrap();
    let mut rng = Pcg64::new(1, 1);
    let err = (0..100)
        .find_map(|i| fs.sample(&mut rng, i, 100).err())
        .expect("some draw leaves [-0.5, 0.5]");
    let m = message(err);
    assert!(
        m.contains("length") && m.contains("at_bounds = reject") && m.contains("bound 0.5") || m.contains("bound -0.5"),
        "{m}"
    );

    // Resample that cannot succeed names the feature instead of looping.
    let fs = compile(s, float([Some(40.0), None]), AtBounds::Resample).unwrap();
    let e = message(fs.sample(&mut Pcg64::new(1, 1), 0, 1).unwrap_err());
    assert!(e.contains("length") && e.contains("10000 tries"), "{e}");
}

#[test]
fn int_features_stay_integral_when_clipped() {
    let s = Sampler::IntUniform { low: -10, high: 10 };
    let xs = numbers(
        &compile(s, int([Some(-2.5), Some(4.5)]), AtBounds::Clip).unwrap(),
        5_000,
    );
    assert!(xs.iter().all(|x| x.fract() == 0.0 && (-2.0..=4.0).contains(x)));
    assert!(xs.contains(&-2.0) && xs.contains(&4.0));
}

#[test]
fn stratified_mixture_blocks() {
    let s = Sampler::IntervalMixture {
        intervals: vec![[0.0, 1.0], [10.0, 11.0], [20.0, 21.0]],
        weights: None,
        stratified: true,
    };
    let xs = numbers(&compile(s, float([None, None]), AtBounds::Reject).unwrap(), 7);
    // floor(i*3/7): 0,0,0,1,1,2,2
    let blocks: Vec<u32> = xs.iter().map(|x| (x / 10.0) as u32).collect();
    assert_eq!(blocks, [0, 0, 0, 1, 1, 2, 2]);
    let fs = compile(
        Sampler::IntervalMixture {
            intervals: vec![[0.0, 1.0]],
            weights: None,
            stratified: true,
        },
        float([None, None]),
        AtBounds::Clip,
    )
    .unwrap();
    assert!(matches!(
        fs.sample(&mut Pcg64::new(1, 1), 3, 3),
        Err(SamplingError::IndexOutOfRange { .. })
    ));
}

#[test]
fn constant_list_checked_per_element() {
    let f = FeatureInfo {
        name: "layers".into(),
        kind: FeatureType::ListInt,
        default: None,
        bounds: [Some(1.0), Some(8.0)],
        choices: None,
    };
    let ok = Sampler::Constant {
        value: Value::List(vec![2.0, 8.0]),
    };
    assert!(compile(ok, f.clone(), AtBounds::Reject).is_ok());
    let bad = Sampler::Constant {
        value: Value::List(vec![2.0, 9.0]),
    };
    assert!(message(compile(bad, f.clone(), AtBounds::Clip).unwrap_err()).contains("element 9"));
    let frac = Sampler::Constant {
        value: Value::List(vec![2.5]),
    };
    assert!(compile(frac, f, AtBounds::Clip).is_err());
}

fn any_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        -1e3f64..1e3,
        any::<f64>(),
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        Just(0.0),
        Just(f64::MAX),
        Just(f64::MIN_POSITIVE),
    ]
}

fn any_sampler() -> impl Strategy<Value = Sampler> {
    prop_oneof![
        (any_f64(), any_f64()).prop_map(|(mean, std)| Sampler::Normal { mean, std }),
        (any_f64(), any_f64()).prop_map(|(sigma_rel, fallback_std)| Sampler::RelativeNormal {
            sigma_rel,
            fallback_std
        }),
        (any_f64(), any_f64(), any_f64(), any_f64())
            .prop_map(|(mean, std, low, high)| { Sampler::TruncatedNormal { mean, std, low, high } }),
        (any_f64(), any_f64()).prop_map(|(low, high)| Sampler::Uniform { low, high }),
        (any_f64(), any_f64()).prop_map(|(low, high)| Sampler::LogUniform { low, high }),
        (any::<i64>(), any::<i64>()).prop_map(|(low, high)| Sampler::IntUniform { low, high }),
        (-50i64..50, 0i64..50).prop_map(|(low, w)| Sampler::IntUniform { low, high: low + w }),
        (
            proptest::collection::vec(any_f64(), 0..4),
            proptest::option::of(proptest::collection::vec(any_f64(), 0..4))
        )
            .prop_map(|(c, weights)| Sampler::Categorical {
                choices: Some(c.into_iter().map(Scalar::Number).collect()),
                weights
            }),
        (
            proptest::collection::vec((any_f64(), any_f64()).prop_map(|(a, b)| [a, b]), 0..4),
            proptest::option::of(proptest::collection::vec(any_f64(), 0..4)),
            any::<bool>()
        )
            .prop_map(|(intervals, weights, stratified)| Sampler::IntervalMixture {
                intervals,
                weights,
                stratified
            }),
        any_f64().prop_map(|x| Sampler::Constant {
            value: Value::Number(x)
        }),
    ]
}

fn any_bounds() -> impl Strategy<Value = Bounds> {
    (proptest::option::of(any_f64()), proptest::option::of(any_f64())).prop_map(|(a, b)| [a, b])
}

fn any_policy() -> impl Strategy<Value = AtBounds> {
    prop_oneof![Just(AtBounds::Clip), Just(AtBounds::Resample), Just(AtBounds::Reject)]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2_000, ..ProptestConfig::default() })]

    /// Compile and sample never panic; any returned number is finite, inside the bounds, and
    /// integral for int features, whatever the policy.
    #[test]
    fn never_out_of_bounds(
        s in any_sampler(),
        bounds in any_bounds(),
        policy in any_policy(),
        is_int in any::<bool>(),
        default in any_f64(),
        seed in any::<u64>(),
    ) {
        let mut f = if is_int { int(bounds) } else { float(bounds) };
        f.default = Some(Value::Number(default));
        if let Ok(fs) = FeatureSampler::compile(&s, f, policy) {
            let mut rng = Pcg64::new(seed, 3);
            for i in 0..20 {
                match fs.sample(&mut rng, i, 20) {
                    Ok(Value::Number(x)) => {
                        prop_assert!(x.is_finite());
                        prop_assert!(bounds[0].is_none_or(|lo| x >= lo), "{x} below {bounds:?}");
                        prop_assert!(bounds[1].is_none_or(|hi| x <= hi), "{x} above {bounds:?}");
                        if is_int {
                            prop_assert!(x.fract() == 0.0, "{x} not integral");
                        }
                    }
                    Ok(other) => prop_assert!(false, "unexpected {other:?}"),
                    // Reject/resample may fail; clip must not (except a truncation cap, never seen).
                    Err(e) => prop_assert!(policy != AtBounds::Clip, "clip failed: {e}"),
                }
            }
        }
    }

    /// With finite, sane parameters and bounds that meet the support, clip and resample succeed
    /// and stay inside the bounds.
    #[test]
    fn finite_params_within_bounds(
        mean in -100.0f64..100.0,
        std in 0.01f64..50.0,
        lo in -100.0f64..100.0,
        width in 0.5f64..100.0,
        clip in any::<bool>(),
        seed in any::<u64>(),
    ) {
        let (hi, policy) = (lo + width, if clip { AtBounds::Clip } else { AtBounds::Resample });
        let samplers = [
            Sampler::TruncatedNormal { mean, std, low: lo, high: hi },
            Sampler::Uniform { low: lo - width, high: hi + width },
            Sampler::IntervalMixture { intervals: vec![[lo - 1.0, lo + width / 2.0], [hi - width / 4.0, hi + 1.0]], weights: None, stratified: false },
        ];
        for s in samplers {
            let fs = FeatureSampler::compile(&s, float([Some(lo), Some(hi)]), policy);
            prop_assert!(fs.is_ok(), "{s:?}: {fs:?}");
            let Ok(fs) = fs else { continue };
            let mut rng = Pcg64::new(seed, 9);
            for i in 0..50 {
                let v = fs.sample(&mut rng, i, 50);
                prop_assert!(matches!(v, Ok(Value::Number(x)) if lo <= x && x <= hi), "{s:?} -> {v:?}");
            }
        }
    }
}
