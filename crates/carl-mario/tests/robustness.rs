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

/// Generator names from `toad_gan/index.json` are plain folder names inside `toad_gan/`: a
/// name that climbs out (`../..`), is absolute or holds control characters is refused, naming
/// the index file and the entry, before any file is read.
#[test]
fn generator_names_are_confined_to_the_data_directory() {
    use carl_mario::DataDir;
    use carl_mario::toad_gan::generator_names;
    let root = std::env::temp_dir().join(format!("carl-mario-names-{}", std::process::id()));
    let toad = root.join("mario/toad_gan");
    std::fs::create_dir_all(&toad).unwrap();
    // A generator outside the data directory that a `../` name would reach.
    let outside = root.join("outside");
    std::fs::create_dir_all(&outside).unwrap();
    let data = DataDir::new(&root).unwrap();
    let long = "x".repeat(300);
    for bad in [
        "../../outside",
        "..",
        "/etc",
        "a/b",
        "a\\b",
        "",
        "c:x",
        "x\u{1b}[2J",
        long.as_str(),
    ] {
        let index = serde_json::json!({ "generators": [{ "name": "TOAD_GAN_1-1" }, { "name": bad }] });
        std::fs::write(toad.join("index.json"), index.to_string()).unwrap();
        let e = generator_names(&data).unwrap_err();
        assert!(
            matches!(e, MarioError::BadGeneratorName { position: 1, .. }),
            "{bad:?}: {e}"
        );
        let msg = e.to_string();
        assert!(
            msg.contains("index.json") && msg.contains("not a plain folder name"),
            "{msg}"
        );
        assert!(!msg.contains('\u{1b}') && msg.len() < 400, "{msg}");
        let e = Generator::load_index(&data, 1).unwrap_err();
        assert!(matches!(e, MarioError::BadGeneratorName { .. }), "{bad:?}: {e}");
    }
    let ok = serde_json::json!({ "generators": [{ "name": "TOAD_GAN_1-1" }, { "name": "my gen.v2" }] });
    std::fs::write(toad.join("index.json"), ok.to_string()).unwrap();
    assert_eq!(generator_names(&data).unwrap(), ["TOAD_GAN_1-1", "my gen.v2"]);
    let _ = std::fs::remove_dir_all(&root);
}
