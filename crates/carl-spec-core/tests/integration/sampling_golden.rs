//! Golden vectors: exact bits of the first draws of every sampler kind. If one of these changes,
//! output bits changed: bump `SAMPLER_VERSION` and regenerate (set `CARL_SPEC_PRINT_GOLDEN=1` and
//! run this test with `--nocapture` to print the current table).

use carl_spec_core::sampling::{FeatureInfo, FeatureSampler, GENERATOR, SAMPLER_VERSION, sample_contexts, stream_id};
use carl_spec_core::spec::raw::{AtBounds, FeatureType, Sampler, Scalar, Value};

const SEED: u64 = 20_240_917;
const N: usize = 5;

fn float(name: &str, default: f64) -> FeatureInfo {
    FeatureInfo {
        name: name.into(),
        kind: FeatureType::Float,
        default: Some(Value::Number(default)),
        bounds: [Some(-1000.0), Some(1000.0)],
        choices: None,
    }
}

fn cases() -> Vec<(&'static str, FeatureInfo, Sampler)> {
    vec![
        ("normal", float("gravity", 9.8), Sampler::Normal { mean: 9.8, std: 2.0 }),
        (
            "relative_normal",
            float("pole_length", 0.5),
            Sampler::RelativeNormal {
                sigma_rel: 0.1,
                fallback_std: 0.1,
            },
        ),
        (
            "relative_normal_zero_default",
            float("initial_state_lower", 0.0),
            Sampler::RelativeNormal {
                sigma_rel: 0.1,
                fallback_std: 0.1,
            },
        ),
        (
            "truncated_normal",
            float("masscart", 1.0),
            Sampler::TruncatedNormal {
                mean: 1.0,
                std: 0.5,
                low: 0.5,
                high: 2.0,
            },
        ),
        (
            "truncated_normal_tail",
            float("force_magnitude", 10.0),
            Sampler::TruncatedNormal {
                mean: 0.0,
                std: 1.0,
                low: 6.0,
                high: 40.0,
            },
        ),
        (
            "uniform",
            float("tau", 0.02),
            Sampler::Uniform { low: 0.01, high: 0.05 },
        ),
        (
            "log_uniform",
            float("friction", 0.1),
            Sampler::LogUniform { low: 1e-3, high: 10.0 },
        ),
        (
            "int_uniform",
            FeatureInfo {
                name: "max_steps".into(),
                kind: FeatureType::Int,
                default: Some(Value::Number(200.0)),
                bounds: [Some(0.0), None],
                choices: None,
            },
            Sampler::IntUniform { low: 100, high: 500 },
        ),
        (
            "categorical",
            float("wind_power", 15.0),
            Sampler::Categorical {
                choices: Some(vec![Scalar::Number(0.0), Scalar::Number(15.0), Scalar::Number(30.0)]),
                weights: Some(vec![1.0, 2.0, 1.0]),
            },
        ),
        (
            "interval_mixture",
            float("mass", 1.0),
            Sampler::IntervalMixture {
                intervals: vec![[0.1, 0.5], [2.0, 3.0]],
                weights: None,
                stratified: false,
            },
        ),
        (
            "interval_mixture_stratified",
            float("length", 1.0),
            Sampler::IntervalMixture {
                intervals: vec![[0.1, 0.5], [2.0, 3.0]],
                weights: None,
                stratified: true,
            },
        ),
        (
            "constant",
            float("dt", 0.05),
            Sampler::Constant {
                value: Value::Number(0.05),
            },
        ),
    ]
}

/// Pinned `f64::to_bits` of the first `N` draws of each case (clip policy, SEED).
const GOLDEN: &[(&str, [u64; N])] = &[
    // 7.618258529226061, 11.952897348474497, 8.499778488614742, 13.100401344956829, 9.807226039686356
    (
        "normal",
        [
            0x401e7918c38dfef8,
            0x4027e7e229484942,
            0x4020ffe2f74fb073,
            0x402a3367ce1a20c4,
            0x40239d4cbb41dd70,
        ],
    ),
    // 0.42461647675013464, 0.48227914296020924, 0.5186587584115416, 0.5289772024181094, 0.5291619600631403
    (
        "relative_normal",
        [
            0x3fdb2cea963f033d,
            0x3fdedda956a3a602,
            0x3fe098da40a52b4e,
            0x3fe0ed619916e42a,
            0x3fe0eee510184530,
        ],
    ),
    // 0.02684893021323735, 0.016916657766602273, 0.0300511171051132, -0.06589026505911269, 0.05908680505437931
    (
        "relative_normal_zero_default",
        [
            0x3f9b7e4934cb340c,
            0x3f915299af75f20d,
            0x3f9ec5b854b2ebbd,
            0xbfb0de2f358dbcb2,
            0x3fae40a02eaad8fa,
        ],
    ),
    // 0.6340197197252677, 1.4472324631889042, 1.3909411822316509, 0.5563814158206586, 1.8867906498084317
    (
        "truncated_normal",
        [
            0x3fe449e3b927a6cc,
            0x3ff727dd3a31b1a2,
            0x3ff6414b8a858324,
            0x3fe1cde06621a936,
            0x3ffe304b6475367d,
        ],
    ),
    // 6.026684772153912, 6.0586781231970654, 6.166854135794612, 6.059033565854259, 6.166602336126159
    (
        "truncated_normal_tail",
        [
            0x40181b5340becf1e,
            0x40183c161e307cfc,
            0x4018aadbcf81c2c4,
            0x40183c734b8ad75a,
            0x4018aa99cd84656e,
        ],
    ),
    // 0.01376578549172836, 0.04456459185494138, 0.013295302218641902, 0.0488591250746082, 0.026453025815541
    (
        "uniform",
        [
            0x3f8c313c73ed0103,
            0x3fa6d12b91273308,
            0x3f8b3a9141c18ae6,
            0x3fa90410309cfcbe,
            0x3f9b168083082f24,
        ],
    ),
    // 0.2776626443050444, 0.0017586221749018422, 0.0058792442512918125, 2.378542427972838, 0.8059175729820695
    (
        "log_uniform",
        [
            0x3fd1c5398a271b62,
            0x3f5cd0322e8ad5b6,
            0x3f7814d59c8d49f0,
            0x4003074140a2558e,
            0x3fe9ca13a667598d,
        ],
    ),
    // 482, 429, 152, 294, 277
    (
        "int_uniform",
        [
            0x407e200000000000,
            0x407ad00000000000,
            0x4063000000000000,
            0x4072600000000000,
            0x4071500000000000,
        ],
    ),
    // 15, 15, 0, 15, 0
    (
        "categorical",
        [
            0x402e000000000000,
            0x402e000000000000,
            0x0000000000000000,
            0x402e000000000000,
            0x0000000000000000,
        ],
    ),
    // 0.18948619006946515, 0.22577339541216032, 0.2638551289207699, 0.11582054676333575, 0.2843338288696383
    (
        "interval_mixture",
        [
            0x3fc841155eb22cd2,
            0x3fcce62482cd11c7,
            0x3fd0e3009f662e36,
            0x3fbda66a548da960,
            0x3fd2328684090f46,
        ],
    ),
    // 0.22650692939018385, 0.3006107165317504, 0.17502109180250877, 2.814108199808779, 2.584998733741572
    (
        "interval_mixture_stratified",
        [
            0x3fccfe2dd7062c1a,
            0x3fd33d34bb152f04,
            0x3fc6671754b3745f,
            0x4006834b28ecac51,
            0x4004ae13d0ecf8c2,
        ],
    ),
    // 0.05, 0.05, 0.05, 0.05, 0.05
    (
        "constant",
        [
            0x3fa999999999999a,
            0x3fa999999999999a,
            0x3fa999999999999a,
            0x3fa999999999999a,
            0x3fa999999999999a,
        ],
    ),
];

fn bits(v: &Value) -> u64 {
    match v {
        Value::Number(x) => x.to_bits(),
        other => panic!("expected a number, got {other:?}"),
    }
}

#[test]
fn golden_vectors() {
    let print = std::env::var_os("CARL_SPEC_PRINT_GOLDEN").is_some();
    let mut seen = 0;
    for (label, info, sampler) in cases() {
        let fs = FeatureSampler::compile(&sampler, info, AtBounds::Clip).expect("golden case compiles");
        let got: Vec<u64> = fs.sample_column(SEED, N).expect("draws").iter().map(bits).collect();
        if print {
            let vals: Vec<String> = got.iter().map(|b| format!("{}", f64::from_bits(*b))).collect();
            println!("    // {}", vals.join(", "));
            println!(
                "    (\"{label}\", [{}]),",
                got.iter().map(|b| format!("{b:#018x}")).collect::<Vec<_>>().join(", ")
            );
            continue;
        }
        let want = GOLDEN.iter().find(|(l, _)| *l == label).map(|(_, w)| w);
        let want = want.unwrap_or_else(|| panic!("no golden vector for {label}"));
        assert_eq!(
            &got[..],
            &want[..],
            "{label}: output bits changed; bump SAMPLER_VERSION"
        );
        seen += 1;
    }
    assert!(print || seen == GOLDEN.len());
}

#[test]
fn version_constants() {
    assert_eq!(SAMPLER_VERSION, "carl-spec-sampling/1");
    assert!(GENERATOR.starts_with("pcg64-xslrr128/64"));
}

#[test]
fn stream_ids_are_fnv1a64() {
    // Published FNV-1a 64 test vectors.
    assert_eq!(stream_id(""), 0xcbf29ce484222325);
    assert_eq!(stream_id("a"), 0xaf63dc4c8601ec8c);
    assert_eq!(stream_id("foobar"), 0x85944171f73967e8);
}

/// Adding or reordering features never changes another feature's values.
#[test]
fn features_are_independent_streams() {
    let g = Sampler::Normal { mean: 9.8, std: 1.0 };
    let l = Sampler::Uniform { low: 0.1, high: 2.0 };
    let one = sample_contexts(7, 50, &[(float("gravity", 9.8), &g)], AtBounds::Clip).unwrap();
    let two = sample_contexts(
        7,
        50,
        &[(float("length", 0.5), &l), (float("gravity", 9.8), &g)],
        AtBounds::Clip,
    )
    .unwrap();
    for (a, b) in one.iter().zip(&two) {
        assert_eq!(a[0], b[1]);
    }
    let other_seed = sample_contexts(8, 50, &[(float("gravity", 9.8), &g)], AtBounds::Clip).unwrap();
    assert_ne!(one, other_seed);
    let dup = sample_contexts(
        7,
        5,
        &[(float("gravity", 9.8), &g), (float("gravity", 9.8), &l)],
        AtBounds::Clip,
    );
    assert!(dup.unwrap_err().to_string().contains("listed twice"));
}
