//! Environment stepping speed: `cargo bench --bench envs`.
//!
//! Every environment of the registry that runs without user data (Mario reads its levels from a
//! data directory), light ones (closed-form dynamics) and heavy ones (a physics world, a
//! picture) apart:
//!
//! * `single::*`: one environment's `step_into` (default context, random actions drawn
//!   beforehand, auto-reset when an episode ends); divan reports time per step.
//! * `vec::*`: one `VecEnv::step` over the registration's `bench` batch (1024 light, 64 heavy
//!   environments) with 1 or 2 threads; divan reports environment steps per second (items/s).
//!
//! Both step through `carl_spec::bench`'s runners, the same loops `carl-spec bench` times. The
//! families' own benches time their engines' parts (`cargo bench -p carl-envs-brax`,
//! `-p carl-envs-box2d`).

use carl_spec::bench::{SingleRunner, VecRunner};
use carl_spec::envs::registry::{REGISTRY, StepCost};
use carl_spec::spec::SpecSet;
use divan::Bencher;
use divan::counter::ItemsCount;

fn main() {
    divan::main();
}

/// The registry's environments of this cost that build with the bundled specs alone.
fn ids(cost: StepCost) -> Vec<&'static str> {
    let specs = SpecSet::bundled().expect("bundled specs");
    REGISTRY
        .iter()
        .filter(|r| r.cost == cost && SingleRunner::new(specs.get(r.id).expect("spec")).is_ok())
        .map(|r| r.id)
        .collect()
}

mod single {
    use super::*;

    fn run(bencher: Bencher, id: &str) {
        let specs = SpecSet::bundled().expect("bundled specs");
        let mut r = SingleRunner::new(specs.get(id).expect("spec")).expect("runner");
        bencher.bench_local(move || r.step());
    }

    #[divan::bench(args = ids(StepCost::Light))]
    fn light(b: Bencher, id: &str) {
        run(b, id);
    }

    #[divan::bench(args = ids(StepCost::Heavy), sample_count = 20, sample_size = 20)]
    fn heavy(b: Bencher, id: &str) {
        run(b, id);
    }
}

mod vec {
    use super::*;

    fn run(bencher: Bencher, id: &str, threads: usize) {
        let specs = SpecSet::bundled().expect("bundled specs");
        let n = carl_spec::envs::registry::lookup(id)
            .expect("registered")
            .cost
            .bench_num_envs();
        let mut r = VecRunner::new(specs.get(id).expect("spec"), n, threads).expect("VecRunner");
        bencher.counter(ItemsCount::new(n)).bench_local(move || r.step());
    }

    #[divan::bench(args = ids(StepCost::Light), consts = [1, 2])]
    fn light<const THREADS: usize>(b: Bencher, id: &str) {
        run(b, id, THREADS);
    }

    #[divan::bench(args = ids(StepCost::Heavy), consts = [1, 2], sample_count = 10, sample_size = 2)]
    fn heavy<const THREADS: usize>(b: Bencher, id: &str) {
        run(b, id, THREADS);
    }
}
