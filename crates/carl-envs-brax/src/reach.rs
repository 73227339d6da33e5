//! UR5e reach task (Brax v0.0.x `ur5e`): move the end effector (the flange, origin of
//! `wrist_3_link`) to a sequence of random targets.
//!
//! As Brax's task:
//! * each target is drawn at horizontal distance `target_radius + target_distance·U(0,1)` from
//!   the base axis in a uniformly random direction, at height 0.5 m;
//! * reward `0.1 · (ee_after − ee_before)·(target − ee_after)/(1e-6 + |target − ee_after|) +
//!   1[|target − ee_after| < target_radius]`: a small reward for moving towards the target and a
//!   bonus of 1 for touching it; no control cost;
//! * a touched target is teleported to a new random target (same rule) after the reward;
//! * no termination (the episode limit, 1000 steps, comes from the spec's `TimeLimit`).
//!
//! Deviations: the observation is ours (joint angles as sin/cos, joint velocities, end-effector
//! position, target position; Brax's is an egocentric layout of every body's position and
//! velocity plus contact flags), the arm starts in UR's upright home pose
//! `[0, −π/2, 0, −π/2, 0, 0]` at rest instead of Brax's zero pose, and the end effector is the
//! flange rather than the wrist_3 body's centre of mass.
//!
//! State: joint angles (6), joint velocities (6), target position (3).

use std::sync::Arc;

use rapier3d::prelude::Vector;

use carl_env::api::{Action, DType, Env, EnvError, Info, Space, StepOutcome, check_obs_len, vector_action};
use carl_env::rng::{EnvRng, uniform};

use super::model::RobotModel;
use super::params::RobotParams;
use super::vec3::{norm, sub};
use super::world::{Configuration, RobotWorld};

/// UR's upright home pose (rad).
pub const HOME: [f64; 6] = [
    0.0,
    -std::f64::consts::FRAC_PI_2,
    0.0,
    -std::f64::consts::FRAC_PI_2,
    0.0,
    0.0,
];
/// Height of every target (m), as in Brax.
pub const TARGET_HEIGHT: f64 = 0.5;
/// Weight of the moving-towards-target reward.
pub const MOVE_WEIGHT: f64 = 0.1;
/// Reward for touching a target.
pub const HIT_BONUS: f64 = 1.0;

const NJ: usize = 6;

/// Reward terms of the last step.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ReachInfo {
    pub distance: f64,
    pub reward_move: f64,
    pub hit: bool,
    pub hits: u64,
    pub diverged: bool,
}

#[derive(Debug)]
pub struct Reach {
    model: Arc<RobotModel>,
    params: RobotParams,
    world: Option<RobotWorld>,
    target: [f64; 3],
    rng: EnvRng,
    info: ReachInfo,
    ee_link: usize,
}

impl Clone for Reach {
    fn clone(&self) -> Self {
        let mut c = Reach::new(self.model.clone(), self.params.clone());
        c.rng = self.rng.clone();
        c.info = self.info;
        c.target = self.target;
        if self.world.is_some() {
            c.load(&self.state_vec());
        }
        c
    }
}

impl Reach {
    pub fn new(model: Arc<RobotModel>, params: RobotParams) -> Self {
        let ee_link = model
            .link_names
            .iter()
            .position(|l| l == "wrist_3_link")
            .unwrap_or(model.link_names.len() - 1);
        Reach {
            model,
            params,
            world: None,
            target: [0.0, 0.0, TARGET_HEIGHT],
            rng: EnvRng::from_seed(carl_env::rng::DEFAULT_SEED),
            info: ReachInfo::default(),
            ee_link,
        }
    }

    pub fn params(&self) -> &RobotParams {
        &self.params
    }
    pub fn world(&self) -> Option<&RobotWorld> {
        self.world.as_ref()
    }
    pub fn last_info(&self) -> ReachInfo {
        self.info
    }
    pub fn target(&self) -> [f64; 3] {
        self.target
    }
    /// Environment step duration (s).
    pub fn dt(&self) -> f64 {
        self.model.side.timestep * self.model.side.frame_skip as f64
    }

    /// End-effector (flange) position in the world, or the home pose's before the first reset.
    pub fn ee_position(&self) -> [f64; 3] {
        match &self.world {
            Some(w) => {
                let t = w.link_pose(self.ee_link).translation;
                [f64::from(t.x), f64::from(t.y), f64::from(t.z)]
            }
            None => [f64::NAN; 3],
        }
    }

    /// For the sensitivity audit: each of `states` with the target moved to 15 mm above the
    /// end effector (inside the default 20 mm target radius, outside a 10 mm one).
    pub fn states_near_target(&self, states: &[Vec<f64>]) -> Result<Vec<Vec<f64>>, EnvError> {
        let mut probe = self.clone();
        let mut out = Vec::with_capacity(states.len());
        for s in states {
            probe.set_state(s)?;
            let ee = probe.ee_position();
            let mut g = s.clone();
            g[2 * NJ..2 * NJ + 3].copy_from_slice(&[ee[0], ee[1], ee[2] + 0.015]);
            out.push(g);
        }
        Ok(out)
    }

    fn random_target(&mut self) -> [f64; 3] {
        let d = self.params.target_radius + self.params.target_distance * uniform(&mut self.rng, 0.0, 1.0);
        let ang = std::f64::consts::TAU * uniform(&mut self.rng, 0.0, 1.0);
        [d * ang.cos(), d * ang.sin(), TARGET_HEIGHT]
    }

    fn state_vec(&self) -> Vec<f64> {
        let mut s = Vec::with_capacity(2 * NJ + 3);
        match &self.world {
            Some(w) => {
                let c = w.configuration();
                s.extend(&c.joints);
                s.extend(&c.vel);
            }
            None => {
                s.extend(HOME);
                s.extend([0.0; NJ]);
            }
        }
        s.extend(self.target);
        s
    }

    fn load(&mut self, s: &[f64]) {
        let q = Configuration {
            root: Vec::new(),
            joints: s[..NJ].to_vec(),
            vel: s[NJ..2 * NJ].to_vec(),
        };
        self.world = Some(RobotWorld::build(&self.model, &self.params, &q));
        self.target.copy_from_slice(&s[2 * NJ..2 * NJ + 3]);
    }

    fn write_obs(&self, obs: &mut [f32]) {
        let s = self.state_vec();
        for j in 0..NJ {
            obs[2 * j] = s[j].sin() as f32;
            obs[2 * j + 1] = s[j].cos() as f32;
        }
        for j in 0..NJ {
            obs[2 * NJ + j] = s[NJ + j] as f32;
        }
        let ee = self.ee_position();
        for k in 0..3 {
            obs[3 * NJ + k] = ee[k] as f32;
            obs[3 * NJ + 3 + k] = self.target[k] as f32;
        }
    }

    fn controls<'a>(&self, action: &'a Action) -> Result<&'a [f32], EnvError> {
        vector_action("ur5e", action, NJ)
    }
}

/// Brax's ur5e reward for an end effector moving from `ee_before` to `ee_after` with the
/// target at `target`: returns (moving-towards-target term, hit).
pub fn reach_reward(ee_before: [f64; 3], ee_after: [f64; 3], target: [f64; 3], radius: f64) -> (f64, bool) {
    let rel = sub(target, ee_after);
    let dist = norm(rel);
    let delta = sub(ee_after, ee_before);
    let along = (delta[0] * rel[0] + delta[1] * rel[1] + delta[2] * rel[2]) / (1e-6 + dist);
    (MOVE_WEIGHT * along, dist < radius)
}

impl carl_env::runtime::Runtime for Reach {
    fn goal_states(&self, states: &[Vec<f64>]) -> Result<Vec<Vec<f64>>, EnvError> {
        self.states_near_target(states)
    }
}

impl Env for Reach {
    fn id(&self) -> &'static str {
        "ur5e"
    }
    /// sin/cos of the 6 joint angles, 6 joint velocities, end-effector and target positions.
    fn obs_dim(&self) -> usize {
        3 * NJ + 6
    }
    fn state_dim(&self) -> usize {
        2 * NJ + 3
    }
    fn observation_space(&self) -> Space {
        let n = self.obs_dim();
        let mut low = vec![f32::NEG_INFINITY; n];
        let mut high = vec![f32::INFINITY; n];
        for i in 0..2 * NJ {
            low[i] = -1.0;
            high[i] = 1.0;
        }
        Space::Box {
            low,
            high,
            shape: vec![n],
            dtype: DType::Float32,
        }
    }
    fn action_space(&self) -> Space {
        self.model.action_space()
    }

    fn reset_into(&mut self, seed: Option<u64>, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len("ur5e", obs, self.obs_dim())?;
        if let Some(seed) = seed {
            self.rng = EnvRng::from_seed(seed);
        }
        let target = self.random_target();
        let mut s = vec![0.0; self.state_dim()];
        s[..NJ].copy_from_slice(&HOME);
        s[2 * NJ..].copy_from_slice(&target);
        self.load(&s);
        self.info = ReachInfo {
            distance: norm(sub(self.target, self.ee_position())),
            ..ReachInfo::default()
        };
        self.write_obs(obs);
        Ok(())
    }

    fn step_into(&mut self, action: &Action, obs: &mut [f32]) -> Result<StepOutcome, EnvError> {
        let ctrl = self.controls(action)?;
        check_obs_len("ur5e", obs, self.obs_dim())?;
        if self.world.is_none() {
            return Err(EnvError::NeedsReset { env: "ur5e" });
        }
        let before = self.state_vec();
        let ee_before = self.ee_position();
        let world = self.world.as_mut().expect("checked");
        for _ in 0..self.model.side.frame_skip {
            world.step(ctrl);
        }
        let diverged = !world.is_sane(self.model.side.max_speed);
        if diverged {
            self.load(&before);
        }
        let ee_after = self.ee_position();
        let (reward_move, hit) = reach_reward(ee_before, ee_after, self.target, self.params.target_radius);
        let hit = hit && !diverged;
        let distance = norm(sub(self.target, ee_after));
        if hit {
            self.target = self.random_target();
        }
        self.info = ReachInfo {
            distance,
            reward_move,
            hit,
            hits: self.info.hits + u64::from(hit),
            diverged,
        };
        self.write_obs(obs);
        Ok(StepOutcome {
            reward: reward_move + if hit { HIT_BONUS } else { 0.0 },
            terminated: diverged,
            truncated: false,
        })
    }

    fn observe_into(&self, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len("ur5e", obs, self.obs_dim())?;
        self.write_obs(obs);
        Ok(())
    }

    /// Joint angles (6), joint velocities (6), target position (3).
    fn state(&self) -> Vec<f64> {
        self.state_vec()
    }

    fn set_state(&mut self, state: &[f64]) -> Result<(), EnvError> {
        carl_env::api::check_state_len("ur5e", state, self.state_dim())?;
        self.load(state);
        self.info = ReachInfo::default();
        Ok(())
    }

    fn info(&self) -> Info {
        let i = &self.info;
        let mut m = Info::new();
        m.insert("distance".into(), i.distance);
        m.insert("reward_move".into(), i.reward_move);
        m.insert("hit".into(), f64::from(u8::from(i.hit)));
        m.insert("hits".into(), i.hits as f64);
        m.insert("diverged".into(), f64::from(u8::from(i.diverged)));
        m
    }

    fn render(&self) -> Option<carl_pixels::Frame> {
        let w = self.world.as_ref()?;
        let t = Vector::new(self.target[0] as f32, self.target[1] as f32, self.target[2] as f32);
        let r = (self.params.target_radius as f32).max(0.03);
        Some(super::render::render_with(
            w,
            &[(t, r, carl_pixels::Color(220, 60, 40))],
        ))
    }
}
