//! Validation speed: the bundled specs in-process (the whole-process figure is on docs/performance.md).

use carl_spec_core::spec::load::bundled_inputs;
use carl_spec_core::validate;

fn main() {
    divan::main();
}

#[divan::bench]
fn validate_bundled_specs(bencher: divan::Bencher) {
    let inputs = bundled_inputs(false);
    bencher.bench(|| {
        let (resolved, report) = validate::run(divan::black_box(&inputs));
        assert!(!report.has_errors());
        resolved.len()
    });
}

#[divan::bench]
fn load_frozen_landing_in_space_train(bencher: divan::Bencher) {
    let specs = carl_spec_core::spec::SpecSet::bundled().unwrap();
    let store = carl_spec_core::instances::Store::new(&specs);
    bencher.bench(|| {
        store
            .load(divan::black_box("lunar_lander/landing_in_space_train"))
            .unwrap()
            .instances
            .len()
    });
}
