//! CARL's Mario (`CARLMarioEnv`) on carl-spec's own clean-room engine (crate `carl-mario`):
//! TOAD-GAN levels generated in Rust from the user's converted generator weights, the platformer
//! engine (tick-identical to the CARL jar on the oracle traces) and CARL's `MarioEnv` wrapper.
//!
//! * Actions: CARL's 10 button sets; one step = `frame_skip` = 2 engine ticks.
//! * Observation: grayscale frames, the last `frame_stack` (4) stacked, each the 256×256 screen
//!   downsampled nearest-neighbour to `frame_dim`×`frame_dim` — 64 (the paper, CARL 2021:
//!   `frame_dim=64`) by default, 84 (carl-bench 1.1.1) as an option; values 0..=255. Drawn with
//!   carl-spec's neutral art ([`carl_mario::render`]).
//! * Reward, termination and truncation: CARL's `computeReward` / `computeDone` /
//!   `computeTimeout`, all documented quirks kept (events of a step's first tick are lost, rewards
//!   repeat during the 9-tick pause, HURT while invulnerable, the time-out double count).
//! * Context: `level_index` (generator 0..=14: all 15 of the paper, including 8-1, which CARL's
//!   code cannot reach), `noise_seed` and `level_width` (carl-bench 1.1.1), `noise` (σ, scale of
//!   the generator's initial noise; 1 = CARL's sampling), `mario_state`, `mario_inertia`.
//! * Data: levels need the TOAD-GAN weights from the data directory (`CARL_SPEC_DATA`, see
//!   [`carl_mario::DataDir`]); nothing Nintendo-derived is in this repository.

mod params;
mod registry;

pub use params::MarioParams;
pub use registry::REGISTRATIONS;

use carl_mario::engine::Level;
use carl_mario::game::{ACTIONS, Game};
use carl_mario::toad_gan::{Generator, WidthMismatch};
use carl_mario::{DataDir, MarioError};

use carl_env::api::{
    Action, DType, Env, EnvError, Info, Space, StepOutcome, check_obs_len, check_state_len, discrete_action,
};
use carl_env::rng::EnvRng;
use carl_env::runtime::Runtime;

const ID: &str = "mario";

/// Options that are not context features.
#[derive(Debug, Clone, PartialEq)]
pub struct MarioOptions {
    /// Side of the observation frames: 64 (paper, default) or 84 (carl-bench 1.1.1); any 16..=256.
    pub frame_dim: usize,
    /// Frames stacked in the observation (CARL's grayscale `frame_stack`, 4).
    pub frame_stack: usize,
    /// Probability of repeating the previous action (CARL's default 0.1 draws from Python's
    /// global, unseeded `random`; here it is seeded by `reset(seed)`). Default 0 (as the traces).
    pub sticky_action_probability: f64,
    /// Reward 1 only when the level is completed (CARL's `sparse_rewards`).
    pub sparse_rewards: bool,
    /// What to do on the (generator, width) pairs where CARL crashes.
    pub width_mismatch: WidthMismatch,
}

impl Default for MarioOptions {
    fn default() -> Self {
        MarioOptions {
            frame_dim: 64,
            frame_stack: 4,
            sticky_action_probability: 0.0,
            sparse_rewards: false,
            width_mismatch: WidthMismatch::Reject,
        }
    }
}

/// The Mario environment.
#[derive(Debug, Clone)]
pub struct Mario {
    params: MarioParams,
    options: MarioOptions,
    level_text: String,
    level: Level,
    inertia: f32,
    state: u8,
    game: Option<Game>,
    /// `frame_stack` frames of `frame_dim²` gray values, oldest first.
    frames: Vec<u8>,
    last_action: Option<usize>,
    rng: EnvRng,
}

impl Mario {
    /// Generates the context's level with the generators in `data`.
    pub fn new(params: MarioParams, options: MarioOptions, data: &DataDir) -> Result<Self, MarioError> {
        let p = params.checked()?;
        let generator = Generator::load_index(data, p.level_index)?;
        let text = generator.generate_scaled(p.level_width, p.noise_seed, p.noise, options.width_mismatch)?;
        Self::with_level(params, options, &text)
    }

    /// Builds the environment from resolved context values (canonical feature name → value, as
    /// the registry produces them) with the data directory from `CARL_SPEC_DATA`, else
    /// `shared/data` beside the working directory or one of its parents.
    pub fn from_context(values: &[(String, f64)]) -> Result<Self, MarioError> {
        Self::from_context_with(values, MarioOptions::default())
    }

    /// [`Mario::from_context`] with options.
    pub fn from_context_with(values: &[(String, f64)], options: MarioOptions) -> Result<Self, MarioError> {
        let mut params = MarioParams::default();
        for (name, x) in values {
            params.set(name, *x).map_err(|e| MarioError::BadLevel {
                origin: "mario context".into(),
                reason: e.to_string(),
            })?;
        }
        let cwd = std::env::current_dir().map_err(|e| MarioError::DataDirMissing {
            reason: format!("no working directory: {e}"),
        })?;
        Self::new(params, options, &DataDir::discover(&cwd)?)
    }

    /// Plays the given level text instead of a generated one (the context's generator features
    /// are then unused), e.g. one of CARL's original levels.
    pub fn with_level(params: MarioParams, options: MarioOptions, text: &str) -> Result<Self, MarioError> {
        let p = params.checked()?;
        if !(16..=256).contains(&options.frame_dim) || !(1..=16).contains(&options.frame_stack) {
            return Err(MarioError::BadLevel {
                origin: "mario options".into(),
                reason: format!(
                    "frame_dim {} must be in 16..=256 and frame_stack {} in 1..=16",
                    options.frame_dim, options.frame_stack
                ),
            });
        }
        if !(0.0..=1.0).contains(&options.sticky_action_probability) {
            return Err(MarioError::BadLevel {
                origin: "mario options".into(),
                reason: format!(
                    "sticky_action_probability {} is not in [0, 1]",
                    options.sticky_action_probability
                ),
            });
        }
        let level = Level::parse(text, "level")?;
        let frames = vec![0; options.frame_stack * options.frame_dim * options.frame_dim];
        Ok(Mario {
            params,
            options,
            level_text: text.to_string(),
            level,
            inertia: p.inertia,
            state: p.mario_state,
            game: None,
            frames,
            last_action: None,
            rng: EnvRng::default(),
        })
    }

    pub fn params(&self) -> &MarioParams {
        &self.params
    }

    /// The level being played (16 rows joined by `\n`).
    pub fn level_text(&self) -> &str {
        &self.level_text
    }

    /// The running game (after `reset`).
    pub fn game(&self) -> Option<&Game> {
        self.game.as_ref()
    }

    fn frame_len(&self) -> usize {
        self.options.frame_dim * self.options.frame_dim
    }

    /// Shifts the stack and appends the current frame.
    fn push_frame(&mut self) {
        let n = self.frame_len();
        self.frames.copy_within(n.., 0);
        let start = self.frames.len() - n;
        if let Some(g) = &self.game {
            carl_mario::render::observe_gray(&g.world, self.options.frame_dim, &mut self.frames[start..]);
        }
    }

    fn write_obs(&self, obs: &mut [f32]) {
        for (o, f) in obs.iter_mut().zip(&self.frames) {
            *o = f32::from(*f);
        }
    }
}

impl Runtime for Mario {}

impl Env for Mario {
    fn id(&self) -> &'static str {
        ID
    }
    fn obs_dim(&self) -> usize {
        self.frames.len()
    }
    /// Mario's `[x, y, xa, ya, is_large, is_fire]`.
    fn state_dim(&self) -> usize {
        6
    }
    fn observation_space(&self) -> Space {
        let n = self.obs_dim();
        Space::Box {
            low: vec![0.0; n],
            high: vec![255.0; n],
            shape: vec![self.options.frame_stack, self.options.frame_dim, self.options.frame_dim],
            dtype: DType::UInt8,
        }
    }
    fn action_space(&self) -> Space {
        Space::Discrete {
            n: ACTIONS.len() as i64,
            start: 0,
        }
    }

    fn reset_into(&mut self, seed: Option<u64>, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(ID, obs, self.obs_dim())?;
        if let Some(seed) = seed {
            self.rng = EnvRng::from_seed(seed);
        }
        self.game = Some(Game::reset(self.level.clone(), self.inertia, self.state));
        self.last_action = None;
        self.frames.fill(0);
        self.push_frame();
        self.write_obs(obs);
        Ok(())
    }

    fn step_into(&mut self, action: &Action, obs: &mut [f32]) -> Result<StepOutcome, EnvError> {
        let mut a = discrete_action(ID, action, ACTIONS.len() as i64)? as usize;
        check_obs_len(ID, obs, self.obs_dim())?;
        if self.game.is_none() {
            return Err(EnvError::NeedsReset { env: ID });
        }
        if self.options.sticky_action_probability > 0.0 {
            match self.last_action {
                Some(prev) if self.rng.next_f64() < self.options.sticky_action_probability => a = prev,
                _ => self.last_action = Some(a),
            }
        }
        let game = self.game.as_mut().expect("checked above");
        let r = game.step(a);
        let reward = if self.options.sparse_rewards {
            f32::from(u8::from(game.completed() == 1.0))
        } else {
            r.reward
        };
        self.push_frame();
        self.write_obs(obs);
        Ok(StepOutcome {
            reward: f64::from(reward),
            terminated: r.terminated,
            truncated: r.truncated,
        })
    }

    fn observe_into(&self, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(ID, obs, self.obs_dim())?;
        self.write_obs(obs);
        Ok(())
    }

    fn state(&self) -> Vec<f64> {
        match &self.game {
            Some(g) => {
                let m = g.world.mario();
                let st = &g.world.mario;
                vec![
                    f64::from(m.x),
                    f64::from(m.y),
                    f64::from(m.xa),
                    f64::from(m.ya),
                    f64::from(u8::from(st.is_large)),
                    f64::from(u8::from(st.is_fire)),
                ]
            }
            None => vec![0.0; 6],
        }
    }

    /// Resets the game and then places Mario: position, velocity and power state (the level,
    /// enemies and timer are those after the reset tick). The frame stack is redrawn.
    fn set_state(&mut self, state: &[f64]) -> Result<(), EnvError> {
        check_state_len(ID, state, 6)?;
        let mut game = Game::reset(self.level.clone(), self.inertia, self.state);
        {
            let m = &mut game.world.sprites[0];
            m.x = state[0] as f32;
            m.y = state[1] as f32;
            m.xa = state[2] as f32;
            m.ya = state[3] as f32;
            game.world.mario.is_large = state[4] != 0.0 || state[5] != 0.0;
            game.world.mario.is_fire = state[5] != 0.0;
            // Mario's height follows his size (as his next update would set it).
            m.h = if game.world.mario.is_large { 24 } else { 12 };
        }
        self.game = Some(game);
        self.frames.fill(0);
        self.push_frame();
        Ok(())
    }

    /// Mario's position `x`, `y`, velocity `xa`, `ya` (pixels, pixels per tick), `mario_state`
    /// (0 small, 1 large, 2 fire), `completed` (x / exit x; 1 on a win), `status` (0 running,
    /// 1 win, 2 lose, 3 time-out), `coins`, `ticks` (engine tick count).
    fn info(&self) -> Info {
        let mut info = Info::new();
        if let Some(g) = &self.game {
            let w = &g.world;
            let m = w.mario();
            for (k, v) in [
                ("x", m.x),
                ("y", m.y),
                ("xa", m.xa),
                ("ya", m.ya),
                ("completed", g.completed()),
            ] {
                info.insert(k.into(), f64::from(v));
            }
            let state = if w.mario.is_fire { 2 } else { u8::from(w.mario.is_large) };
            info.insert("mario_state".into(), f64::from(state));
            info.insert("status".into(), f64::from(w.status.code()));
            info.insert("coins".into(), f64::from(w.coins));
            info.insert("ticks".into(), f64::from(w.tick_count));
        }
        info
    }

    fn render(&self) -> Option<carl_pixels::Frame> {
        let g = self.game.as_ref()?;
        let size = carl_mario::render::SCREEN as u32;
        Some(carl_pixels::Frame {
            width: size,
            height: size,
            rgb: carl_mario::render::frame_rgb(&g.world),
        })
    }
}
