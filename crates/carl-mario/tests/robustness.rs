//! Bad input never panics: arbitrary level text either parses or gives a located error, and any
//! level that parses can be played for a while with arbitrary buttons; arbitrary bytes as
//! generator weights give an error.

mod common;

use carl_mario::MarioError;
use carl_mario::engine::level::KNOWN_TILES;
use carl_mario::engine::{Level, World};
use carl_mario::game::{ACTIONS, Game};
use carl_mario::toad_gan::Generator;
use proptest::prelude::*;

/// Level-like text: rows of tile characters (mostly known ones), sometimes ragged or with
/// stray characters and `\r\n` line ends.
fn level_text() -> impl Strategy<Value = String> {
    let known: Vec<char> = KNOWN_TILES.chars().collect();
    // Most texts use only tile characters (so they parse and get played); some have strays.
    let ch = prop_oneof![
        400 => proptest::sample::select(known),
        1 => any::<char>(),
    ];
    (1usize..20, 1usize..40, proptest::bool::weighted(0.1)).prop_flat_map(move |(h, w, ragged)| {
        proptest::collection::vec(proptest::collection::vec(ch.clone(), w), h).prop_map(move |rows| {
            let mut lines: Vec<String> = rows.iter().map(|r| r.iter().collect()).collect();
            if ragged {
                lines[0].push('-');
            }
            lines.join(if rows.len() % 3 == 0 { "\r\n" } else { "\n" })
        })
    })
}

static PLAYED: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn any_level_text_parses_or_errors_and_parsed_levels_play(text in level_text(), acts in proptest::collection::vec(0usize..10, 1..150), inertia in prop_oneof![Just(0.89f32), Just(1.5f32), 0.5f32..1.5]) {
        match Level::parse(&text, "fuzz") {
            Ok(level) => {
                PLAYED.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let mut g = Game::reset(level, inertia, (acts[0] % 3) as u8);
                for &a in &acts {
                    g.step(a);
                }
                let _ = g.completed();
                let mut w = World::new(g.world.level.clone(), 0, inertia, true, true);
                for &a in &acts {
                    w.tick(ACTIONS[a]);
                }
            }
            Err(MarioError::UnknownTile { line, column, ch, .. }) => {
                prop_assert!(!KNOWN_TILES.contains(ch) && line >= 1 && column >= 1);
            }
            Err(e) => prop_assert!(matches!(e, MarioError::BadLevel { .. }), "{e}"),
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn arbitrary_weight_bytes_are_an_error(bytes in proptest::collection::vec(any::<u8>(), 0..256), header in proptest::option::of(1u64..64)) {
        let data = common::data_dir();
        let dir = std::env::temp_dir().join(format!("carl-mario-fuzz-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::copy(data.toad_gan().join("TOAD_GAN_1-1/manifest.json"), dir.join("manifest.json")).unwrap();
        let mut file = Vec::new();
        if let Some(n) = header {
            file.extend_from_slice(&n.to_le_bytes());
        }
        file.extend_from_slice(&bytes);
        std::fs::write(dir.join("weights.safetensors"), &file).unwrap();
        let r = Generator::load(&dir);
        std::fs::remove_dir_all(&dir).unwrap();
        prop_assert!(matches!(r, Err(MarioError::CorruptWeights { .. })), "{r:?}");
    }
}

#[test]
fn fuzzing_reaches_the_engine() {
    any_level_text_parses_or_errors_and_parsed_levels_play();
    assert!(
        PLAYED.load(std::sync::atomic::Ordering::Relaxed) >= 50,
        "too few generated levels parse"
    );
}

#[test]
fn a_level_without_floor_or_wider_than_the_screen_is_playable() {
    for text in ["-", "X", "M-F", &"-".repeat(300), "--\n--\nXX"] {
        let mut g = Game::reset(Level::parse(text, "t").unwrap(), 1.5, 2);
        for k in 0..400 {
            g.step([5, 3, 8, 1][k % 4]);
        }
    }
}
