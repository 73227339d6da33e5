//! MFE folding time at the lengths of the ViennaRNA comparison (scripts/rna_bench.py runs both).
//! Sequences: uniform random A/C/G/U from a fixed-seed generator, 5 per length.

fn main() {
    divan::main();
}

fn random_sequence(len: usize, seed: u64) -> String {
    // SplitMix64: tiny, deterministic, no dependency.
    let mut x = seed;
    (0..len)
        .map(|_| {
            x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = x;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            b"ACGU"[((z ^ (z >> 31)) % 4) as usize] as char
        })
        .collect()
}

#[divan::bench(args = [100, 200, 500, 800], sample_count = 5, sample_size = 1)]
fn fold(bencher: divan::Bencher, len: usize) {
    let seqs: Vec<String> = (0..5).map(|k| random_sequence(len, 1 + k)).collect();
    let mut k = 0;
    bencher.bench_local(|| {
        k = (k + 1) % seqs.len();
        carl_rna::fold(divan::black_box(&seqs[k])).unwrap()
    });
}
