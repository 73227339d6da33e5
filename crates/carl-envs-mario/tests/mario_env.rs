//! The `mario` environment through the `Env` API: levels generated from the data directory,
//! CARL's action set and reward end to end (the `env` variant of `completion_rates.json`),
//! observations, info and errors. Needs the data directory (`CARL_SPEC_DATA`, else
//! `shared/data` beside the checkout).

use carl_env::api::{Action, Env, Space};
use carl_envs_mario::{Mario, MarioOptions, MarioParams};
use carl_mario::DataDir;
use carl_mario::toad_gan::WidthMismatch;
use serde_json::Value;
use std::path::Path;

fn data() -> DataDir {
    DataDir::discover(Path::new(env!("CARGO_MANIFEST_DIR")))
        .unwrap_or_else(|e| panic!("tests need the Mario data directory: {e}"))
}

fn params(state: f64, inertia: f64) -> MarioParams {
    MarioParams {
        mario_state: state,
        mario_inertia: inertia,
        ..MarioParams::default()
    }
}

#[test]
fn default_context_generates_carls_level_and_plays_the_oracle_episode() {
    let data = data();
    let fixture: Value = std::fs::read_to_string(data.mario().join("toad_gan_fixtures.jsonl"))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str::<Value>(l).unwrap())
        .find(|r| r["kind"] == "level" && r["level_index"] == 0 && r["seed"] == 0 && r["width"] == 100)
        .unwrap();
    let rates: Value =
        serde_json::from_slice(&std::fs::read(data.mario().join("completion_rates.json")).unwrap()).unwrap();
    let rows = rates["per_level"]["g00_s0_w100"].as_array().unwrap();
    let mut checked = 0;
    for row in rows.iter().filter(|r| r[0] == "env" && r[3] == "p0") {
        let (state, inertia) = (row[1].as_f64().unwrap(), row[2].as_f64().unwrap());
        let mut env = Mario::new(params(state, inertia), MarioOptions::default(), &data).unwrap();
        assert_eq!(env.level_text(), fixture["level"].as_str().unwrap());
        env.reset(Some(0));
        let (mut steps, mut total) = (0u64, 0f32);
        let info = loop {
            let s = env.step(&Action::Discrete(3)).unwrap();
            steps += 1;
            total += s.reward as f32;
            if s.terminated || s.truncated {
                break s.info;
            }
        };
        let status = ["R", "W", "L", "T"][info["status"] as usize];
        assert_eq!(status, row[4].as_str().unwrap(), "{row}");
        assert_eq!(info["completed"] as f32, row[5].as_f64().unwrap() as f32, "{row}");
        assert_eq!(steps, row[7].as_u64().unwrap(), "{row}");
        assert_eq!(total, row[8].as_f64().unwrap() as f32, "{row}");
        checked += 1;
    }
    assert_eq!(checked, 12, "3 Mario states × 4 inertias");
}

#[test]
fn observation_is_a_stack_of_grayscale_frames() {
    let data = data();
    let mut env = Mario::new(MarioParams::default(), MarioOptions::default(), &data).unwrap();
    let Space::Box { shape, .. } = env.observation_space() else {
        panic!()
    };
    assert_eq!(shape, vec![4, 64, 64]);
    let (obs, info) = env.reset(Some(1));
    assert_eq!(obs.len(), 4 * 64 * 64);
    assert!(
        obs[..3 * 4096].iter().all(|v| *v == 0.0),
        "older frames are blank after reset"
    );
    assert!(obs[3 * 4096..].iter().any(|v| *v > 0.0));
    assert_eq!(info["mario_state"], 0.0);
    let first = obs[3 * 4096..].to_vec();
    let s = env.step(&Action::Discrete(3)).unwrap();
    assert_eq!(
        &s.obs[2 * 4096..3 * 4096],
        &first[..],
        "the stack shifts by one frame per step"
    );
    assert!(s.obs.iter().all(|v| (0.0..=255.0).contains(v) && v.fract() == 0.0));
    // carl-bench 1.1.1's 84×84 frames as an option.
    let opts = MarioOptions {
        frame_dim: 84,
        ..MarioOptions::default()
    };
    let mut env84 = Mario::new(MarioParams::default(), opts, &data).unwrap();
    assert_eq!(env84.reset(None).0.len(), 4 * 84 * 84);
    let frame = env84.render().unwrap();
    assert_eq!((frame.width, frame.height, frame.rgb.len()), (256, 256, 256 * 256 * 3));
}

#[test]
fn context_changes_the_level_and_mario() {
    let data = data();
    let level = |p: MarioParams| {
        Mario::new(p, MarioOptions::default(), &data)
            .unwrap()
            .level_text()
            .to_string()
    };
    let base = level(MarioParams::default());
    assert_ne!(
        base,
        level(MarioParams {
            noise_seed: 1.0,
            ..MarioParams::default()
        })
    );
    assert_ne!(
        base,
        level(MarioParams {
            level_index: 14.0,
            ..MarioParams::default()
        }),
        "8-1 (index 14) is reachable"
    );
    assert_ne!(
        base,
        level(MarioParams {
            noise: 0.0,
            ..MarioParams::default()
        })
    );
    let wide = level(MarioParams {
        level_width: 150.0,
        ..MarioParams::default()
    });
    assert!(wide.lines().all(|l| l.len() == 150));
    let mut large = Mario::new(params(1.0, 0.89), MarioOptions::default(), &data).unwrap();
    large.reset(None);
    assert_eq!(large.state()[4..], [1.0, 0.0]);
    assert_eq!(large.info()["mario_state"], 1.0);
}

#[test]
fn bad_contexts_and_actions_are_errors() {
    let data = data();
    let err = |p: MarioParams| Mario::new(p, MarioOptions::default(), &data).unwrap_err().to_string();
    let e = err(MarioParams {
        level_width: 59.0,
        ..MarioParams::default()
    });
    assert!(e.contains("crashes") && e.contains("59"), "{e}");
    let ok = MarioOptions {
        width_mismatch: WidthMismatch::UseScale0Width,
        ..MarioOptions::default()
    };
    assert!(
        Mario::new(
            MarioParams {
                level_width: 59.0,
                ..MarioParams::default()
            },
            ok,
            &data
        )
        .is_ok()
    );
    assert!(
        err(MarioParams {
            level_index: 15.0,
            ..MarioParams::default()
        })
        .contains("out of range")
    );
    assert!(
        err(MarioParams {
            level_width: 100.5,
            ..MarioParams::default()
        })
        .contains("integer")
    );
    assert!(
        err(MarioParams {
            mario_state: 3.0,
            ..MarioParams::default()
        })
        .contains("mario_state")
    );
    assert!(
        err(MarioParams {
            mario_inertia: f64::NAN,
            ..MarioParams::default()
        })
        .contains("mario_inertia")
    );
    let mut env = Mario::new(MarioParams::default(), MarioOptions::default(), &data).unwrap();
    assert!(env.step(&Action::Discrete(0)).is_err(), "step before reset");
    env.reset(None);
    assert!(env.step(&Action::Discrete(10)).is_err());
    assert!(env.step(&Action::Continuous(vec![0.0])).is_err());
    let e = Mario::with_level(MarioParams::default(), MarioOptions::default(), "--Z\nXXX").unwrap_err();
    assert!(e.to_string().contains("unknown tile"), "{e}");
}

#[test]
fn sticky_actions_are_seeded() {
    let data = data();
    let opts = MarioOptions {
        sticky_action_probability: 0.5,
        ..MarioOptions::default()
    };
    let run = |seed| {
        let mut env = Mario::new(MarioParams::default(), opts.clone(), &data).unwrap();
        env.reset(Some(seed));
        (0..60)
            .map(|k| env.step(&Action::Discrete([3, 6, 9][k % 3])).unwrap().info["x"])
            .collect::<Vec<_>>()
    };
    assert_eq!(run(1), run(1));
    assert_ne!(run(1), run(2));
}

#[test]
fn from_context_resolves_the_data_directory_and_names() {
    let env = Mario::from_context(&[("level_index".into(), 3.0), ("noise_seed".into(), 2.0)]).unwrap();
    assert_eq!(env.params().level_index, 3.0);
    let e = Mario::from_context(&[("level_idx".into(), 3.0)])
        .unwrap_err()
        .to_string();
    assert!(e.contains("level_idx") && e.contains("level_index"), "{e}");
}
