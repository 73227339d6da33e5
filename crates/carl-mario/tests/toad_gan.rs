//! TOAD-GAN against the reference fixtures (`toad_gan_fixtures.jsonl`, made with CARL's code on
//! torch 2.4.1): torch's noise bit for bit, every level tile for tile, and exactly the 303
//! (generator, width) pairs on which CARL crashes are rejected.

mod common;

use carl_mario::MarioError;
use carl_mario::toad_gan::{Generator, MAX_WIDTH, MIN_WIDTH, WidthMismatch, generator_names, noise};
use sha2::{Digest, Sha256};
use std::collections::BTreeSet;

fn generators() -> Vec<Generator> {
    let data = common::data_dir();
    let n = generator_names(&data).unwrap().len();
    assert_eq!(n, 15, "the data directory has all 15 generators");
    (0..n).map(|i| Generator::load_index(&data, i).unwrap()).collect()
}

fn hex_f32(v: &[f32]) -> Vec<String> {
    v.iter().map(|x| format!("{:08x}", x.to_bits())).collect()
}

#[test]
fn noise_equals_torch_randn_bit_for_bit() {
    let mut checked = 0;
    for rec in common::jsonl("toad_gan_fixtures.jsonl") {
        if rec["kind"] != "level" {
            continue;
        }
        for scale in rec["noise"].as_array().unwrap() {
            let n: u64 = scale["shape"]
                .as_array()
                .unwrap()
                .iter()
                .map(|d| d.as_u64().unwrap())
                .product();
            let seed = scale["seed"].as_u64().unwrap();
            let z = noise::randn(n as usize, seed);
            let hex = |k: &str| -> Vec<String> {
                scale[k]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|v| v.as_str().unwrap().to_string())
                    .collect()
            };
            assert_eq!(hex_f32(&z[..16]), hex("first16_f32_hex"), "seed {seed}, n {n}");
            assert_eq!(hex_f32(&z[z.len() - 16..]), hex("last16_f32_hex"), "seed {seed}, n {n}");
            let bytes: Vec<u8> = z.iter().flat_map(|v| v.to_le_bytes()).collect();
            let sha = format!("{:x}", Sha256::digest(&bytes));
            assert_eq!(sha, scale["sha256_f32le"].as_str().unwrap(), "seed {seed}, n {n}");
            checked += 1;
        }
    }
    assert!(checked >= 3 * 172, "only {checked} noise tensors checked");
}

#[test]
fn levels_equal_the_reference_tile_for_tile() {
    let gens = generators();
    let mut per_generator = [0usize; 15];
    for rec in common::jsonl("toad_gan_fixtures.jsonl") {
        if rec["kind"] != "level" {
            continue;
        }
        let li = rec["level_index"].as_u64().unwrap() as usize;
        let seed = rec["seed"].as_u64().unwrap() as u32;
        let width = rec["width"].as_u64().unwrap() as usize;
        assert_eq!(gens[li].name(), rec["generator"].as_str().unwrap());
        let level = gens[li].generate(width, seed, WidthMismatch::Reject).unwrap();
        let want = rec["level"].as_str().unwrap();
        assert_eq!(level, want, "{} seed {seed} width {width}", gens[li].name());
        assert_eq!(
            format!("{:x}", Sha256::digest(level.as_bytes())),
            rec["sha256_level"].as_str().unwrap()
        );
        per_generator[li] += 1;
    }
    assert!(
        per_generator.iter().all(|&n| n >= 10),
        "every generator checked: {per_generator:?}"
    );
}

#[test]
fn exactly_carls_crash_widths_are_rejected() {
    let gens = generators();
    let crashes: BTreeSet<(usize, usize)> = common::jsonl("toad_gan_fixtures.jsonl")
        .iter()
        .filter(|r| r["kind"] == "crash")
        .map(|r| {
            (
                r["level_index"].as_u64().unwrap() as usize,
                r["width"].as_u64().unwrap() as usize,
            )
        })
        .collect();
    assert_eq!(crashes.len(), 303);
    let mut rejected = BTreeSet::new();
    for (li, g) in gens.iter().enumerate() {
        for width in MIN_WIDTH..=MAX_WIDTH {
            if !g.carl_accepts_width(width) {
                rejected.insert((li, width));
            }
        }
    }
    assert_eq!(rejected, crashes);
}

#[test]
fn a_crash_width_gets_a_clear_error_or_a_level_on_request() {
    let data = common::data_dir();
    let g = Generator::load_index(&data, 0).unwrap();
    let err = g.generate(59, 0, WidthMismatch::Reject).unwrap_err();
    match &err {
        MarioError::WidthCrashesInCarl {
            initial_noise_width: 30,
            scale0_width: 29,
            below: Some(b),
            above: Some(a),
            ..
        } => {
            assert!(g.carl_accepts_width(*b) && g.carl_accepts_width(*a) && *b < 59 && *a > 59);
        }
        other => panic!("unexpected {other:?}"),
    }
    assert!(err.to_string().contains("TOAD_GAN_1-1") && err.to_string().contains("59"));
    let level = g.generate(59, 0, WidthMismatch::UseScale0Width).unwrap();
    let rows: Vec<&str> = level.split('\n').collect();
    assert_eq!(rows.len(), 16);
    assert!(
        rows.iter()
            .all(|r| r.chars().count() == 59 && r.chars().all(|c| g.tokens().contains(&c)))
    );
    // Deterministic.
    assert_eq!(level, g.generate(59, 0, WidthMismatch::UseScale0Width).unwrap());
}

#[test]
fn bad_widths_and_indices_are_errors() {
    let data = common::data_dir();
    let g = Generator::load_index(&data, 0).unwrap();
    for w in [0, 15, 1001] {
        assert!(matches!(
            g.generate(w, 0, WidthMismatch::UseScale0Width),
            Err(MarioError::WidthOutOfRange { .. })
        ));
    }
    assert!(matches!(
        Generator::load_index(&data, 15),
        Err(MarioError::UnknownGenerator {
            index: 15,
            available: 15
        })
    ));
}

fn expect_corrupt(mutate: impl Fn(&mut Vec<u8>), needle: &str) {
    let data = common::data_dir();
    let src = data.toad_gan().join("TOAD_GAN_1-1");
    let dir = std::env::temp_dir().join(format!("carl-mario-corrupt-{}-{}", std::process::id(), needle.len()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(src.join("manifest.json"), dir.join("manifest.json")).unwrap();
    let mut w = std::fs::read(src.join("weights.safetensors")).unwrap();
    mutate(&mut w);
    std::fs::write(dir.join("weights.safetensors"), &w).unwrap();
    let err = Generator::load(&dir).unwrap_err();
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(matches!(err, MarioError::CorruptWeights { .. }), "{err:?}");
    assert!(err.to_string().contains(needle), "{err}");
}

#[test]
fn corrupt_weights_are_reported_not_panicked_on() {
    expect_corrupt(|w| w.truncate(w.len() - 4), "do not fit");
    expect_corrupt(|w| w.truncate(5), "shorter than");
    expect_corrupt(|w| w[..8].copy_from_slice(&u64::MAX.to_le_bytes()), "exceeds");
    expect_corrupt(|w| w[8] = b'!', "not a JSON object");
    expect_corrupt(
        |w| {
            let n = w.len();
            w[n - 4..].copy_from_slice(&f32::NAN.to_le_bytes());
        },
        "not finite",
    );
}

#[test]
fn missing_data_directory_says_how_to_get_it() {
    let err = carl_mario::DataDir::new("/nonexistent/carl-data").unwrap_err();
    let msg = err.to_string();
    assert!(
        msg.contains("CARL_SPEC_DATA") && msg.contains("gen_toad_gan_weights.py"),
        "{msg}"
    );
}

#[test]
fn noise_scale_one_is_carls_level_and_zero_removes_the_seed() {
    let data = common::data_dir();
    let g = Generator::load_index(&data, 0).unwrap();
    let carl = g.generate(100, 3, WidthMismatch::Reject).unwrap();
    assert_eq!(g.generate_scaled(100, 3, 1.0, WidthMismatch::Reject).unwrap(), carl);
    let calm = g.generate_scaled(100, 3, 0.0, WidthMismatch::Reject).unwrap();
    assert_eq!(
        calm,
        g.generate_scaled(100, 4, 0.0, WidthMismatch::Reject).unwrap(),
        "σ = 0: the seed no longer matters"
    );
    assert_ne!(
        g.generate_scaled(100, 3, 2.0, WidthMismatch::Reject).unwrap(),
        carl,
        "σ changes the level"
    );
}
