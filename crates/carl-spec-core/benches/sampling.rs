//! Feature values per second on one core: `cargo bench --bench sampling`.
//! Each benchmark draws `N` values of one feature; divan reports the rate as items/s.

use carl_spec_core::sampling::{FeatureInfo, FeatureSampler, feature_rng};
use carl_spec_core::spec::raw::{AtBounds, FeatureType, Sampler, Value};
use divan::counter::ItemsCount;
use divan::{Bencher, black_box};

const N: usize = 100_000;

fn main() {
    divan::main();
}

fn float_feature(default: f64, bounds: [Option<f64>; 2]) -> FeatureInfo {
    FeatureInfo {
        name: "gravity".into(),
        kind: FeatureType::Float,
        default: Some(Value::Number(default)),
        bounds,
        choices: None,
    }
}

fn run(bencher: Bencher, sampler: Sampler, feature: FeatureInfo, at_bounds: AtBounds) {
    let Ok(fs) = FeatureSampler::compile(&sampler, feature, at_bounds) else {
        panic!("bench sampler must compile");
    };
    bencher.counter(ItemsCount::new(N)).bench_local(|| {
        let mut rng = feature_rng(black_box(1), "gravity");
        let mut acc = 0.0;
        for i in 0..N {
            if let Ok(Value::Number(x)) = fs.sample(&mut rng, i, N) {
                acc += x;
            }
        }
        acc
    });
}

#[divan::bench]
fn normal(b: Bencher) {
    run(
        b,
        Sampler::Normal { mean: 9.8, std: 1.0 },
        float_feature(9.8, [None, None]),
        AtBounds::Clip,
    );
}

#[divan::bench]
fn normal_clipped(b: Bencher) {
    run(
        b,
        Sampler::Normal { mean: 9.8, std: 1.0 },
        float_feature(9.8, [Some(9.0), Some(11.0)]),
        AtBounds::Clip,
    );
}

#[divan::bench]
fn relative_normal(b: Bencher) {
    run(
        b,
        Sampler::RelativeNormal {
            sigma_rel: 0.1,
            fallback_std: 0.1,
        },
        float_feature(9.8, [Some(0.0), None]),
        AtBounds::Resample,
    );
}

#[divan::bench]
fn truncated_normal(b: Bencher) {
    run(
        b,
        Sampler::TruncatedNormal {
            mean: 9.8,
            std: 1.0,
            low: 8.0,
            high: 12.0,
        },
        float_feature(9.8, [None, None]),
        AtBounds::Reject,
    );
}

#[divan::bench]
fn truncated_normal_tail(b: Bencher) {
    run(
        b,
        Sampler::TruncatedNormal {
            mean: 0.0,
            std: 1.0,
            low: 5.0,
            high: 100.0,
        },
        float_feature(0.0, [None, None]),
        AtBounds::Reject,
    );
}

#[divan::bench]
fn uniform(b: Bencher) {
    run(
        b,
        Sampler::Uniform { low: 5.0, high: 15.0 },
        float_feature(9.8, [None, None]),
        AtBounds::Clip,
    );
}

#[divan::bench]
fn raw_next_u64(bencher: Bencher) {
    bencher.counter(ItemsCount::new(N)).bench_local(|| {
        let mut rng = feature_rng(black_box(1), "gravity");
        let mut acc = 0u64;
        for _ in 0..N {
            acc ^= rng.next_u64();
        }
        acc
    });
}
