//! `rna_design` with a random policy on Eterna100 (V1, LEARNA's `eterna`): steps per second,
//! terminal folds and LEARNA's local improvement included. Each sample runs 20 episodes of a
//! seeded epoch; the step count of an episode is fixed by its target (unpaired sites + pairs).

use carl_spec::envs::rna_design::{RnaDesign, RnaDesignParams};
use carl_spec::envs::{Action, Env};

fn main() {
    divan::main();
}

const EPISODES: usize = 20;

#[divan::bench(sample_count = 5, sample_size = 1)]
fn random_policy_eterna100(bencher: divan::Bencher) {
    let mut env = RnaDesign::new(RnaDesignParams::default()).expect("Eterna100 ships with the crate");
    // Steps of the 20 episodes from seed 1: the same targets are drawn in every sample.
    env.reset(Some(1));
    let mut steps = 0u64;
    for k in 0..EPISODES {
        if k > 0 {
            env.reset(None);
        }
        let t = env.target();
        steps += t
            .partner
            .iter()
            .enumerate()
            .filter(|&(i, p)| p.is_none_or(|p| p > i))
            .count() as u64;
    }
    let mut x = 0x2545_F491_4F6C_DD1Du64;
    bencher.counter(divan::counter::ItemsCount::new(steps)).bench_local(|| {
        let mut obs = vec![0.0f32; env.obs_dim()];
        env.reset_into(Some(1), &mut obs).unwrap();
        for k in 0..EPISODES {
            if k > 0 {
                env.reset_into(None, &mut obs).unwrap();
            }
            loop {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                let out = env.step_into(&Action::Discrete((x % 4) as i64), &mut obs).unwrap();
                if out.terminated {
                    break;
                }
            }
        }
    });
}
