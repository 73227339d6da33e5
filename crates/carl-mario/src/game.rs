//! CARL's `MarioEnv` around the engine (engine_behaviour.md §12): reset with the reset tick,
//! agent steps of `frame_skip` ticks, `computeReward` with all its documented quirks kept for
//! fidelity, termination and completion.

use crate::engine::Level;
use crate::engine::world::{Buttons, Status, World, event};

/// CARL's 10 actions as (left, right, down, speed, jump).
pub const ACTIONS: [Buttons; 10] = {
    const fn b(left: bool, right: bool, down: bool, speed: bool, jump: bool) -> Buttons {
        Buttons {
            left,
            right,
            down,
            speed,
            jump,
        }
    }
    [
        b(false, false, false, false, false),
        b(false, false, true, false, false),
        b(false, true, false, false, false),
        b(false, true, false, true, false),
        b(false, true, false, false, true),
        b(false, true, false, true, true),
        b(true, false, false, false, false),
        b(true, false, false, false, true),
        b(true, false, false, true, true),
        b(false, false, false, false, true),
    ]
};

/// CARL's timer (seconds) and frame skip.
pub const CARL_TIMER: i32 = 100;
pub const CARL_FRAME_SKIP: usize = 2;

/// Result of one agent step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepResult {
    pub reward: f32,
    pub terminated: bool,
    pub truncated: bool,
}

/// One CARL Mario episode.
#[derive(Debug, Clone)]
pub struct Game {
    pub world: World,
    /// The reward's checkpoint tile.
    pub last_tile: f32,
    pub frame_skip: usize,
}

impl Game {
    /// CARL's reset: build the world, set Mario's state (0 small, 1 large, 2 fire), run one tick
    /// with no buttons, checkpoint 0.
    pub fn reset(level: Level, inertia: f32, mario_state: u8) -> Game {
        let mut world = World::new(level, CARL_TIMER, inertia, mario_state > 0, mario_state > 1);
        world.tick(Buttons::default());
        Game {
            world,
            last_tile: 0.0,
            frame_skip: CARL_FRAME_SKIP,
        }
    }

    /// One agent step with a CARL action id (0..10; larger ids are a caller bug and panic).
    pub fn step(&mut self, action: usize) -> StepResult {
        let b = ACTIONS[action];
        for _ in 0..self.frame_skip {
            self.world.tick(b);
        }
        self.result()
    }

    /// Reward and flags after the ticks of a step (the step's `computeReward`).
    pub fn result(&mut self) -> StepResult {
        let reward = self.reward();
        let status = self.world.status;
        StepResult {
            reward,
            terminated: matches!(status, Status::Win | Status::Lose),
            truncated: status == Status::TimeOut,
        }
    }

    fn reward(&mut self) -> f32 {
        let tile = (self.world.mario().x / 16.0) as i32 as f32;
        let mut r = 0.0f32;
        for e in &self.world.events {
            match e.kind {
                event::COLLECT => r += 1.0,
                event::STOMP_KILL | event::FIRE_KILL | event::SHELL_KILL | event::FALL_KILL
                    if tile > self.last_tile =>
                {
                    r += 1.0
                }
                event::HURT => r -= 1.0,
                event::WIN => r += 10.0,
                _ => {}
            }
        }
        if tile > self.last_tile + 8.0 {
            self.last_tile = tile;
            r += 1.0;
        }
        r
    }

    /// `mario.x / (16·exitX)` (1.0 on a win, as the engine clamps x to the exit).
    pub fn completed(&self) -> f32 {
        self.world.mario().x / (16 * self.world.level.exit.0) as f32
    }
}
