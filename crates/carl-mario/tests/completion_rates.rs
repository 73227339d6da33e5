//! The scripted policies' completion table (`completion_rates.json`, oracle output): every
//! per-level row (end status, completion, ticks, steps, total reward) and every summary row
//! (wins, mean completion), in both variants: `tick` (a decision per engine tick) and `env`
//! (a decision per agent step of 2 ticks with CARL actions 3 / 5).

mod common;

use carl_mario::engine::Level;
use carl_mario::game::Game;
use serde_json::Value;
use std::collections::HashMap;

struct Outcome {
    status: &'static str,
    completed: f32,
    ticks: u64,
    steps: u64,
    total_reward: f32,
}

/// p0 = hold right+speed (action 3); p1 = p0 plus a jump (action 5) held 11 ticks whenever
/// Mario is on the ground and may jump at the start of a decision.
fn play(level: &Level, inertia: f32, state: u8, p1: bool, frame_skip: usize) -> Outcome {
    let mut g = Game::reset(level.clone(), inertia, state);
    g.frame_skip = frame_skip;
    let hold = if frame_skip == 1 {
        11
    } else {
        11usize.div_ceil(frame_skip)
    };
    let (mut jump_hold, mut steps, mut total) = (0, 0u64, 0f32);
    loop {
        let mut a = 3;
        if p1 {
            if jump_hold > 0 {
                a = 5;
                jump_hold -= 1;
            } else if g.world.mario().on_ground && g.world.mario.may_jump {
                a = 5;
                jump_hold = hold - 1;
            }
        }
        let r = g.step(a);
        steps += 1;
        total += r.reward;
        if r.terminated || r.truncated {
            break;
        }
    }
    Outcome {
        status: ["R", "W", "L", "T"][g.world.status.code() as usize],
        completed: g.completed(),
        ticks: steps * frame_skip as u64,
        steps,
        total_reward: total,
    }
}

#[test]
fn completion_rates_equal_the_oracle_in_both_variants() {
    let data = common::data_dir();
    let rates: Value =
        serde_json::from_slice(&std::fs::read(data.mario().join("completion_rates.json")).unwrap()).unwrap();
    let mut generated = HashMap::new();
    for r in common::jsonl("toad_gan_fixtures.jsonl") {
        if r["kind"] == "level" && r["width"] == 100 {
            let id = format!(
                "g{:02}_s{}_w100",
                r["level_index"].as_u64().unwrap(),
                r["seed"].as_u64().unwrap()
            );
            generated.insert(id, r["level"].as_str().unwrap().to_string());
        }
    }
    let mut results: HashMap<(String, String, u64, String, String), Outcome> = HashMap::new();
    let mut mismatches = Vec::new();
    let mut rows = 0;
    for (lid, level_rows) in rates["per_level"].as_object().unwrap() {
        let text = match lid.strip_prefix("lvl-") {
            Some(n) => std::fs::read_to_string(data.original_level(n.parse().unwrap())).unwrap(),
            None => generated[lid].clone(),
        };
        let level = Level::parse(&text, lid).unwrap();
        for row in level_rows.as_array().unwrap() {
            let variant = row[0].as_str().unwrap();
            let state = row[1].as_u64().unwrap();
            let inertia = row[2].as_f64().unwrap().to_string();
            let policy = row[3].as_str().unwrap();
            let fs = if variant == "tick" { 1 } else { 2 };
            let o = play(&level, inertia.parse().unwrap(), state as u8, policy == "p1", fs);
            let ok = o.status == row[4].as_str().unwrap()
                && o.completed == row[5].as_f64().unwrap() as f32
                && o.ticks == row[6].as_u64().unwrap()
                && o.steps == row[7].as_u64().unwrap()
                && o.total_reward == row[8].as_f64().unwrap() as f32;
            if !ok {
                mismatches.push(format!(
                    "{lid} {row}: got {} {} {} {} {}",
                    o.status, o.completed, o.ticks, o.steps, o.total_reward
                ));
            }
            rows += 1;
            let group = if lid.starts_with("lvl-") {
                "original"
            } else {
                "generated"
            };
            results.insert(
                (variant.into(), group.into(), state, inertia, format!("{policy}|{lid}")),
                o,
            );
        }
    }
    assert_eq!(rows, 90 * 2 * 3 * 4 * 2);
    assert!(
        mismatches.is_empty(),
        "{} of {rows} rows differ, e.g.\n{}",
        mismatches.len(),
        mismatches[..mismatches.len().min(5)].join("\n")
    );
    // The summary table, recomputed from our runs.
    for s in rates["summary"].as_array().unwrap() {
        let key = |k: &str| s[k].as_str().unwrap().to_string();
        let (variant, group, policy) = (key("variant"), key("levels"), key("policy"));
        let (state, inertia) = (
            s["mario_state"].as_u64().unwrap(),
            s["inertia"].as_f64().unwrap().to_string(),
        );
        let outs: Vec<&Outcome> = results
            .iter()
            .filter(|(k, _)| {
                k.0 == variant
                    && k.1 == group
                    && k.2 == state
                    && k.3 == inertia
                    && k.4.starts_with(&format!("{policy}|"))
            })
            .map(|(_, o)| o)
            .collect();
        assert_eq!(outs.len() as u64, s["n"].as_u64().unwrap());
        let wins = outs.iter().filter(|o| o.status == "W").count() as u64;
        let mean = outs.iter().map(|o| f64::from(o.completed).min(1.0)).sum::<f64>() / outs.len() as f64;
        assert_eq!(wins, s["wins"].as_u64().unwrap(), "{s}");
        assert_eq!((mean * 1e4).round() / 1e4, s["mean_completed"].as_f64().unwrap(), "{s}");
    }
}
