//! The engine against the oracle traces (`engine_traces.jsonl`, the CARL jar driven like CARL's
//! `MarioEnv`): per-tick Mario state, flags, events and sprites on the 160 detail runs, and the
//! SHA-256 digest, end state and rewards of all 1,920 runs.

mod common;

use common::traces::{self, TickState, Traces};
use serde_json::Value;
use std::collections::BTreeMap;

/// `(type, x, y, xa, ya, facing)` of one sprite.
type SpriteRecord = (i64, f32, f32, f32, f32, i64);

fn f(v: &Value) -> f32 {
    v.as_f64().unwrap() as f32
}

/// Expected per-tick states of a detail run.
fn expected_ticks(run: &Value) -> Vec<TickState> {
    let n = run["detail_ticks"].as_u64().unwrap() as usize;
    let s = |k: &str| run[k].as_str().unwrap().as_bytes().to_vec();
    let flag_strs: Vec<Vec<u8>> = [
        "onGround",
        "isLarge",
        "isFire",
        "isDucking",
        "mayJump",
        "canShoot",
        "facing",
        "status",
        "jumpTime",
        "pauseTimer",
    ]
    .iter()
    .map(|k| s(k))
    .collect();
    let changes = |k: &str| -> BTreeMap<usize, i64> {
        run[k]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| (c[0].as_u64().unwrap() as usize, c[1].as_i64().unwrap()))
            .collect()
    };
    let (coins, inv) = (changes("coins"), changes("invulnerableTime"));
    let mut events: BTreeMap<usize, Vec<(i64, i64)>> = BTreeMap::new();
    for e in run["events"].as_array().unwrap() {
        events
            .entry(e[0].as_u64().unwrap() as usize)
            .or_default()
            .push((e[1].as_i64().unwrap(), e[2].as_i64().unwrap()));
    }
    let mut sprites: BTreeMap<usize, (i64, Vec<SpriteRecord>)> = BTreeMap::new();
    for rec in run["sprites"].as_array().unwrap() {
        let list = rec[2]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| {
                (
                    s[0].as_i64().unwrap(),
                    f(&s[1]),
                    f(&s[2]),
                    f(&s[3]),
                    f(&s[4]),
                    s[5].as_i64().unwrap(),
                )
            })
            .collect();
        sprites.insert(rec[0].as_u64().unwrap() as usize, (rec[1].as_i64().unwrap(), list));
    }
    let last = |m: &BTreeMap<usize, i64>, t: usize| *m.range(..=t).next_back().map(|(_, v)| v).unwrap_or(&0);
    (0..n)
        .map(|t| {
            let (mario_index, sp) = sprites.get(&t).cloned().unwrap_or_default();
            TickState {
                x: f(&run["x"][t]),
                y: f(&run["y"][t]),
                xa: f(&run["xa"][t]),
                ya: f(&run["ya"][t]),
                flags: flag_strs.iter().map(|s| s[t] as char).collect(),
                events: events.get(&t).cloned().unwrap_or_default(),
                sprites: sp,
                mario_index,
                coins: last(&coins, t),
                invulnerable: last(&inv, t),
            }
        })
        .collect()
}

/// First difference between the replay and the trace, as a readable message.
fn first_difference(tr: &Traces, run: &Value) -> Option<String> {
    let want = expected_ticks(run);
    let got = traces::replay(tr, run, want.len()).ticks;
    for (t, w) in want.iter().enumerate() {
        let Some(g) = got.get(t) else {
            return Some(format!("run ended at tick {} before {}", got.len(), want.len()));
        };
        let mut g = g.clone();
        if t % 10 != 0 {
            g.sprites.clear();
            g.mario_index = 0;
        }
        if &g != w {
            return Some(format!("tick {t}:\n  want {w:?}\n  got  {g:?}"));
        }
    }
    None
}

#[test]
fn detail_runs_match_tick_for_tick() {
    let tr = traces::load();
    let detail: Vec<&Value> = tr.runs.iter().filter(|r| r["detail"] == true).collect();
    assert_eq!(detail.len(), 160);
    let mut failures = Vec::new();
    for run in &detail {
        if let Some(d) = first_difference(&tr, run) {
            failures.push(format!("{}: {d}", run["id"].as_str().unwrap()));
        }
    }
    for f in failures.iter().take(5) {
        eprintln!("{f}");
    }
    assert!(
        failures.is_empty(),
        "{}/{} detail runs differ",
        failures.len(),
        detail.len()
    );
}

#[test]
fn every_run_digest_end_state_and_reward_match() {
    let tr = traces::load();
    assert_eq!(tr.runs.len(), 1920);
    let mut failures = Vec::new();
    for run in &tr.runs {
        let r = traces::replay(&tr, run, 0);
        let end = &run["end"];
        let w = &r.game.world;
        let status = ["R", "W", "L", "T"][w.status.code() as usize];
        let nonzero: Vec<(usize, f32)> = r
            .step_rewards
            .iter()
            .enumerate()
            .filter(|(_, v)| **v != 0.0)
            .map(|(i, v)| (i + 1, *v))
            .collect();
        let want_nonzero: Vec<(usize, f32)> = run["rewards_nonzero"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| (p[0].as_u64().unwrap() as usize, f(&p[1])))
            .collect();
        let ok = r.sha256 == run["sha256"].as_str().unwrap()
            && r.n_steps as u64 == run["n_steps"].as_u64().unwrap()
            && status == end["status"].as_str().unwrap()
            && w.mario().x == f(&end["x"])
            && r.game.completed() == f(&end["completed"])
            && w.coins as i64 == end["coins"].as_i64().unwrap()
            && w.tick_count as i64 == end["current_tick"].as_i64().unwrap()
            && nonzero == want_nonzero;
        if !ok {
            failures.push(run["id"].as_str().unwrap().to_string());
        }
    }
    eprintln!("{}/{} runs match", tr.runs.len() - failures.len(), tr.runs.len());
    assert!(
        failures.is_empty(),
        "{} runs differ, e.g. {:?}",
        failures.len(),
        &failures[..failures.len().min(10)]
    );
}
