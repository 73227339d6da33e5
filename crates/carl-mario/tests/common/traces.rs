//! Replaying `engine_traces.jsonl`: levels, action programs, the run digest and per-tick records.

use carl_mario::engine::Level;
use carl_mario::game::Game;
use serde_json::Value;
use sha2::{Digest, Sha256};
use std::collections::HashMap;
use std::fmt::Write;

pub struct Traces {
    pub meta: Value,
    pub levels: HashMap<String, Level>,
    pub runs: Vec<Value>,
}

pub fn load() -> Traces {
    let data = super::data_dir();
    let mut meta = Value::Null;
    let mut levels = HashMap::new();
    let mut runs = Vec::new();
    for rec in super::jsonl("engine_traces.jsonl") {
        match rec["kind"].as_str().unwrap() {
            "meta" => meta = rec,
            "level" => {
                let id = rec["level_id"].as_str().unwrap().to_string();
                let text = match rec["ascii"].as_str() {
                    Some(a) => a.to_string(),
                    None => {
                        let n: usize = id.strip_prefix("lvl-").unwrap().parse().unwrap();
                        std::fs::read_to_string(data.original_level(n)).unwrap()
                    }
                };
                assert_eq!(
                    format!("{:x}", Sha256::digest(text.as_bytes())),
                    rec["sha256"].as_str().unwrap(),
                    "{id}"
                );
                levels.insert(id.clone(), Level::parse(&text, &id).unwrap());
            }
            "run" => runs.push(rec),
            other => panic!("unknown record kind {other}"),
        }
    }
    Traces { meta, levels, runs }
}

/// Action of agent step `k` (0-based) of a run.
pub fn action(traces: &Traces, run: &Value, k: usize) -> usize {
    let program = &traces.meta["programs"][run["program"].as_str().unwrap()];
    let digits = match program["kind"].as_str().unwrap() {
        "cycle" => program["cycle"].as_str().unwrap(),
        _ => run["actions"].as_str().unwrap(),
    };
    let b = digits.as_bytes();
    (b[k % b.len()] - b'0') as usize
}

/// Mario's state after one tick, as the detail records give it.
#[derive(Debug, Clone, PartialEq)]
pub struct TickState {
    pub x: f32,
    pub y: f32,
    pub xa: f32,
    pub ya: f32,
    pub flags: String,
    pub events: Vec<(i64, i64)>,
    pub sprites: Vec<(i64, f32, f32, f32, f32, i64)>,
    pub mario_index: i64,
    pub coins: i64,
    pub invulnerable: i64,
}

pub struct Replay {
    pub sha256: String,
    pub ticks: Vec<TickState>,
    pub step_rewards: Vec<f32>,
    pub n_steps: usize,
    pub game: Game,
}

fn hex(v: f32) -> String {
    format!("{:08x}", v.to_bits())
}

fn tick_state(g: &Game) -> TickState {
    let w = &g.world;
    let m = w.mario();
    let b = |v: bool| if v { '1' } else { '0' };
    let st = &w.mario;
    let flags: String = [
        b(m.on_ground),
        b(st.is_large),
        b(st.is_fire),
        b(st.is_ducking),
        b(st.may_jump),
        b(st.can_shoot),
        if m.facing >= 0 { '+' } else { '-' },
        ['R', 'W', 'L', 'T'][w.status.code() as usize],
        char::from_digit(st.jump_time.clamp(0, 9) as u32, 10).unwrap(),
        char::from_digit(w.pause.clamp(0, 9) as u32, 10).unwrap(),
    ]
    .into_iter()
    .collect();
    let mut sprites = Vec::new();
    let mut mario_index = -1;
    for (i, &id) in w.list.iter().enumerate() {
        let s = &w.sprites[id];
        if id == 0 {
            mario_index = i as i64;
        } else {
            sprites.push((s.kind as i64, s.x, s.y, s.xa, s.ya, s.facing as i64));
        }
    }
    TickState {
        x: m.x,
        y: m.y,
        xa: m.xa,
        ya: m.ya,
        flags,
        events: w.events.iter().map(|e| (e.kind as i64, e.param as i64)).collect(),
        sprites,
        mario_index,
        coins: w.coins as i64,
        invulnerable: st.invulnerable as i64,
    }
}

/// Runs a trace's configuration to its end; `keep_ticks` per-tick states are kept.
pub fn replay(traces: &Traces, run: &Value, keep_ticks: usize) -> Replay {
    let level = traces.levels[run["level_id"].as_str().unwrap()].clone();
    let inertia = f32::from_bits(u32::from_str_radix(run["inertia_f32_hex"].as_str().unwrap(), 16).unwrap());
    let state = run["mario_state"].as_u64().unwrap() as u8;
    let mut game = Game::reset(level, inertia, state);
    let fs = game.frame_skip;
    let mut text = String::new();
    let mut ticks = Vec::new();
    let mut step_rewards = Vec::new();
    let mut t = 0usize;
    let emit = |g: &Game, t: usize, text: &mut String, ticks: &mut Vec<TickState>| {
        let w = &g.world;
        let m = w.mario();
        let b = |v: bool| if v { 1 } else { 0 };
        writeln!(
            text,
            "T {t} {} {} {} {} {}{}{} {}",
            hex(m.x),
            hex(m.y),
            hex(m.xa),
            hex(m.ya),
            b(m.on_ground),
            b(w.mario.is_large),
            b(w.mario.is_fire),
            w.status.code()
        )
        .unwrap();
        if t.is_multiple_of(10) {
            write!(text, "S {t}").unwrap();
            for &id in &w.list {
                if id != 0 {
                    let s = &w.sprites[id];
                    write!(text, " {},{},{}", s.kind, hex(s.x), hex(s.y)).unwrap();
                }
            }
            text.push('\n');
        }
        if t < keep_ticks {
            ticks.push(tick_state(g));
        }
    };
    emit(&game, 0, &mut text, &mut ticks);
    let mut k = 0;
    loop {
        let a = action(traces, run, k);
        let buttons = carl_mario::game::ACTIONS[a];
        for _ in 0..fs {
            game.world.tick(buttons);
            t += 1;
            if !t.is_multiple_of(fs) {
                emit(&game, t, &mut text, &mut ticks);
            }
        }
        let r = game.result();
        emit(&game, t, &mut text, &mut ticks);
        writeln!(
            text,
            "P {} {a} {} {}{}",
            t / fs,
            hex(r.reward),
            r.terminated as u8,
            r.truncated as u8
        )
        .unwrap();
        step_rewards.push(r.reward);
        k += 1;
        if r.terminated || r.truncated {
            break;
        }
        assert!(k < 100_000, "run does not end");
    }
    Replay {
        sha256: format!("{:x}", Sha256::digest(text.as_bytes())),
        ticks,
        step_rewards,
        n_steps: k,
        game,
    }
}
