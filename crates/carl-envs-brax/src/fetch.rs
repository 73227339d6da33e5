//! Brax v0.0.x `fetch` (2021, as CARL 2021's `CARLFetch` wraps it): a dog-like robot runs to a
//! sequence of random targets.
//!
//! As Brax's task (`brax/envs/fetch.py`):
//! * each target is drawn at horizontal distance `target_radius + target_distance·U(0,1)` from the
//!   origin in a uniformly random direction, at height 1 m (one at reset, a new one whenever the
//!   current one is reached);
//! * reward `0.1·Δtorso·dir + 0.1·dt·(up·ẑ) + 0.1·dt·z_torso + 1[d < target_radius]·(dir·fwd)`:
//!   the torso's displacement towards the target, small rewards for an upright and high torso,
//!   and the hit bonus weighted by how much the torso faces the target (`d`, `dir`: distance and
//!   direction from the torso after the step to the target; `fwd`, `up`: the torso's x and z
//!   axes; `dt` = 0.02 s, Brax's `sys.config.dt`);
//! * a reached target is teleported to a new random target after the reward;
//! * no termination (the episode limit, 1000 steps, comes from the spec's `TimeLimit`); the
//!   start pose is Brax's default pose (every joint at 0, the dog standing on the ground) without
//!   noise, so a seed only chooses the targets;
//! * observation (101 values, Brax's `_get_obs` on Brax's 13 bodies: Torso, Shoulders, Hips, the
//!   eight leg segments, Ground, Target): torso x axis (3), torso z axis (3), distance to the
//!   target (1), its direction in the torso frame (3), every body's centre relative to the torso
//!   in the torso frame (13·3), every body's velocity in the torso frame (13·3), a contact flag
//!   per body (13).
//!
//! Deviations (physics on rapier3d instead of Brax's impulse solver; see also the side file):
//! * contact flags are 1 where rapier's last physics step has a non-zero normal contact impulse
//!   on the link (Brax: squared contact velocity change above 1e-5); the Ground's flag is 1 when
//!   any leg touches it (Brax counts no contact on a frozen body: 0 there), the Target's is 0;
//! * the Ground and Target bodies are frozen in Brax: their velocities are 0 here too;
//! * the observation returned by a step that reaches a target shows the new target (Brax
//!   observes before teleporting it), so that an observation is always that of the state.
//!
//! A simulation that diverges (non-finite or faster than the side file's `max_speed`) is rolled
//! back to the state before the step and the step terminates with `info["diverged"] = 1`.
//!
//! State: root pose `[x y z qw qx qy qz]` (7), joint angles (10), generalized velocities (6 + 10),
//! target position (3), contact flag per link (11).

use std::sync::Arc;

use rapier3d::prelude::{Rotation, Vector};

use carl_env::api::{Action, DType, Env, EnvError, Info, Space, StepOutcome, check_obs_len, vector_action};
use carl_env::rng::{EnvRng, uniform};

use super::model::RobotModel;
use super::params::RobotParams;
use super::vec3::{dot, from_vector, norm, sub};
use super::world::{Configuration, RobotWorld};

/// Height of every target (m), as in Brax.
pub const TARGET_HEIGHT: f64 = 1.0;
/// Weight of the moving-towards-target reward.
pub const MOVE_WEIGHT: f64 = 0.1;
/// Weight (per second of simulated time) of the upright and height rewards.
pub const POSTURE_WEIGHT: f64 = 0.1;
/// Brax's bodies in the observation: the 11 robot links, Ground and Target.
pub const OBS_BODIES: usize = 13;
/// Observation length (Brax's fetch: 3 + 3 + 1 + 3 + 3·13 + 3·13 + 13).
pub const OBS_DIM: usize = 10 + 7 * OBS_BODIES;

const ENV: &str = "fetch";

/// Reward terms of one step (Brax's `metrics`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FetchReward {
    /// `0.1 · Δtorso · dir` (Brax's `movingToTarget`).
    pub moving_to_target: f64,
    /// `0.1 · dt · (up · ẑ)` (`torsoIsUp`).
    pub torso_is_up: f64,
    /// `0.1 · dt · z_torso` (`torsoHeight`).
    pub torso_height: f64,
    /// Torso within `target_radius` of the target (`hits`).
    pub hit: bool,
    /// `hit · (dir · fwd)` (`weightedHits`).
    pub weighted_hit: f64,
    /// Distance from the torso to the target after the step.
    pub distance: f64,
}

impl FetchReward {
    pub fn total(&self) -> f64 {
        self.torso_height + self.moving_to_target + self.torso_is_up + self.weighted_hit
    }
}

/// The torso's pose as the reward needs it: centre, x axis (forward), z axis (up).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TorsoFrame {
    pub pos: [f64; 3],
    pub fwd: [f64; 3],
    pub up: [f64; 3],
}

/// Brax's fetch reward for a torso moving from `before` to `after.pos` with the target at
/// `target`; `dt` is the environment step (s).
pub fn fetch_reward(before: [f64; 3], after: &TorsoFrame, target: [f64; 3], radius: f64, dt: f64) -> FetchReward {
    let rel = sub(target, after.pos);
    let distance = norm(rel);
    let dir = rel.map(|x| x / (1e-6 + distance));
    let moving_to_target = MOVE_WEIGHT * dot(sub(after.pos, before), dir);
    let torso_is_up = POSTURE_WEIGHT * dt * after.up[2];
    let torso_height = POSTURE_WEIGHT * dt * after.pos[2];
    let hit = distance < radius;
    let weighted_hit = if hit { dot(dir, after.fwd) } else { 0.0 };
    FetchReward {
        moving_to_target,
        torso_is_up,
        torso_height,
        hit,
        weighted_hit,
        distance,
    }
}

/// Everything `info()` reports about the last step.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FetchInfo {
    pub reward: FetchReward,
    /// Targets reached since the reset.
    pub hits: u64,
    pub diverged: bool,
}

#[derive(Debug)]
pub struct Fetch {
    model: Arc<RobotModel>,
    params: RobotParams,
    world: Option<RobotWorld>,
    target: [f64; 3],
    /// Contact flag (0/1) per link from the last physics step.
    contacts: Vec<f64>,
    /// Scratch for the contact wrenches (6 per link).
    wrenches: Vec<f64>,
    rng: EnvRng,
    info: FetchInfo,
    nq: usize,
    nv: usize,
    /// (parent link, child link) of each movable joint, in joint order.
    tree: Vec<(usize, usize)>,
}

impl Clone for Fetch {
    /// The clone's world is rebuilt from [`Env::state`] (rapier's warm-start caches start empty).
    fn clone(&self) -> Self {
        let mut c = Fetch::new(self.model.clone(), self.params.clone());
        c.rng = self.rng.clone();
        c.info = self.info;
        c.target = self.target;
        if self.world.is_some() {
            c.load(&self.state_vec());
        }
        c
    }
}

impl Fetch {
    pub fn new(model: Arc<RobotModel>, params: RobotParams) -> Self {
        let nl = model.link_names.len();
        let nj = model.joint_names.len();
        let index = |name: &str| model.link_names.iter().position(|l| l == name).unwrap_or(0);
        let tree = model
            .urdf
            .joints
            .iter()
            .filter(|j| super::model::is_movable(&j.joint_type))
            .map(|j| (index(&j.parent.link), index(&j.child.link)))
            .collect();
        Fetch {
            tree,
            model,
            params,
            world: None,
            target: [0.0, 0.0, TARGET_HEIGHT],
            contacts: vec![0.0; nl],
            wrenches: vec![0.0; 6 * nl],
            rng: EnvRng::from_seed(carl_env::rng::DEFAULT_SEED),
            info: FetchInfo::default(),
            nq: 7 + nj,
            nv: 6 + nj,
        }
    }

    pub fn params(&self) -> &RobotParams {
        &self.params
    }
    pub fn model(&self) -> &RobotModel {
        &self.model
    }
    pub fn world(&self) -> Option<&RobotWorld> {
        self.world.as_ref()
    }
    pub fn last_info(&self) -> FetchInfo {
        self.info
    }
    pub fn target(&self) -> [f64; 3] {
        self.target
    }
    /// Environment step duration (s): physics step × frame skip (Brax's `dt`).
    pub fn dt(&self) -> f64 {
        self.model.side.timestep * self.model.side.frame_skip as f64
    }
    /// Contact flag (0/1) per link from the last physics step.
    pub fn contacts(&self) -> &[f64] {
        &self.contacts
    }

    /// The torso's centre and axes, or `None` before the first reset.
    pub fn torso(&self) -> Option<TorsoFrame> {
        self.world.as_ref().map(torso_frame)
    }

    /// For the sensitivity audit: each of `states` with the target moved 1.5 m ahead (+x) of the
    /// torso at Brax's target height: about 1.55 m from a standing torso, inside the default 2 m
    /// target radius and outside a 1 m one. At most 8 states, evenly spread over `states` (each
    /// audit state costs a world rebuild per probe).
    pub fn states_near_target(&self, states: &[Vec<f64>]) -> Vec<Vec<f64>> {
        let t = self.nq + self.nv;
        states
            .iter()
            .step_by(states.len().div_ceil(8).max(1))
            .filter(|s| s.len() == self.state_dim())
            .map(|s| {
                let mut g = s.clone();
                g[t..t + 3].copy_from_slice(&[s[0] + 1.5, s[1], TARGET_HEIGHT]);
                g
            })
            .collect()
    }

    /// A new target (Brax's `_random_target`): distance from the origin, then direction.
    fn random_target(&mut self) -> [f64; 3] {
        let d = self.params.target_radius + self.params.target_distance * uniform(&mut self.rng, 0.0, 1.0);
        let ang = std::f64::consts::TAU * uniform(&mut self.rng, 0.0, 1.0);
        [d * ang.cos(), d * ang.sin(), TARGET_HEIGHT]
    }

    fn init_config(&self) -> Configuration {
        let nj = self.model.joint_names.len();
        Configuration {
            root: vec![0.0, 0.0, self.model.side.root_height, 1.0, 0.0, 0.0, 0.0],
            joints: vec![0.0; nj],
            vel: vec![0.0; self.nv],
        }
    }

    fn state_vec(&self) -> Vec<f64> {
        let mut s = Vec::with_capacity(self.state_dim());
        let c = match &self.world {
            Some(w) => w.configuration(),
            None => self.init_config(),
        };
        s.extend(&c.root);
        s.extend(&c.joints);
        s.extend(&c.vel);
        s.extend(self.target);
        s.extend(&self.contacts);
        s
    }

    fn load(&mut self, s: &[f64]) {
        let q = Configuration {
            root: s[..7].to_vec(),
            joints: s[7..self.nq].to_vec(),
            vel: s[self.nq..self.nq + self.nv].to_vec(),
        };
        self.world = Some(RobotWorld::build(&self.model, &self.params, &q));
        let t = self.nq + self.nv;
        self.target.copy_from_slice(&s[t..t + 3]);
        // Flags are 0/1: anything else in a loaded state counts as "in contact" if non-zero.
        for (f, x) in self.contacts.iter_mut().zip(&s[t + 3..]) {
            *f = if *x != 0.0 && !x.is_nan() { 1.0 } else { 0.0 };
        }
    }

    fn update_contacts(&mut self) {
        let Some(w) = &self.world else { return };
        w.contact_wrenches(&mut self.wrenches);
        for (i, f) in self.contacts.iter_mut().enumerate() {
            let force = &self.wrenches[6 * i + 3..6 * i + 6];
            *f = if force.iter().any(|x| *x != 0.0) { 1.0 } else { 0.0 };
        }
    }

    /// Linear velocity of every link's centre of mass, from the generalized velocities and the
    /// current poses (the state alone: rapier refreshes the bodies' own velocities only when it
    /// steps, so a world just built from a state would show them at rest). Each link frame
    /// sits on its joint, the URDF lists parents before children.
    fn link_velocities(&self, w: &RobotWorld) -> Vec<Vector> {
        let gv = w.configuration().vel;
        let f = |i: usize| gv[i] as f32;
        let com = |i: usize| w.pw.bodies[w.links[i]].center_of_mass();
        let n = w.links.len();
        let mut lin = vec![Vector::ZERO; n];
        let mut ang = vec![Vector::ZERO; n];
        lin[0] = Vector::new(f(0), f(1), f(2));
        ang[0] = Vector::new(f(3), f(4), f(5));
        for (k, &(p, c)) in self.tree.iter().enumerate() {
            let wj = w.joint_axis_world(k) * f(6 + k);
            let pivot = w.link_pose(c).translation;
            ang[c] = ang[p] + wj;
            lin[c] = lin[p] + ang[p].cross(com(c) - com(p)) + wj.cross(com(c) - pivot);
        }
        lin
    }

    fn write_obs_from(&self, w: &RobotWorld, obs: &mut [f32]) {
        let torso = &w.pw.bodies[w.links[w.torso]];
        let rot: Rotation = *torso.rotation();
        let inv = rot.inverse();
        let centre = torso.center_of_mass();
        let fwd = rot * Vector::X;
        let up = rot * Vector::Z;
        let target = Vector::new(self.target[0] as f32, self.target[1] as f32, self.target[2] as f32);
        let target_local = inv * (target - centre);
        let mag = target_local.length();
        let dir = target_local / (1e-6 + mag);
        let mut k = 0;
        let mut put = |obs: &mut [f32], v: &[f32]| {
            obs[k..k + v.len()].copy_from_slice(v);
            k += v.len();
        };
        let v3 = |v: Vector| [v.x, v.y, v.z];
        put(obs, &v3(fwd));
        put(obs, &v3(up));
        put(obs, &[mag]);
        put(obs, &v3(dir));
        // Body centres: links, Ground (the origin), Target.
        for &h in &w.links {
            put(obs, &v3(inv * (w.pw.bodies[h].center_of_mass() - centre)));
        }
        put(obs, &v3(inv * (Vector::ZERO - centre)));
        put(obs, &v3(target_local));
        // Velocities: links, then the frozen Ground and Target.
        for v in self.link_velocities(w) {
            put(obs, &v3(inv * v));
        }
        put(obs, &[0.0; 6]);
        let k = 10 + 6 * OBS_BODIES;
        let ground = self.contacts.iter().any(|c| *c != 0.0);
        for (i, c) in self.contacts.iter().enumerate() {
            obs[k + i] = *c as f32;
        }
        obs[k + self.contacts.len()] = f32::from(u8::from(ground));
        obs[k + self.contacts.len() + 1] = 0.0;
    }

    fn write_obs(&self, obs: &mut [f32]) {
        match &self.world {
            Some(w) => self.write_obs_from(w, obs),
            None => {
                let w = RobotWorld::build(&self.model, &self.params, &self.init_config());
                self.write_obs_from(&w, obs);
            }
        }
    }

    fn controls<'a>(&self, action: &'a Action) -> Result<&'a [f32], EnvError> {
        vector_action(ENV, action, self.model.num_actuators())
    }
}

fn torso_frame(w: &RobotWorld) -> TorsoFrame {
    let b = &w.pw.bodies[w.links[w.torso]];
    let rot = *b.rotation();
    TorsoFrame {
        pos: from_vector(b.center_of_mass()),
        fwd: from_vector(rot * Vector::X),
        up: from_vector(rot * Vector::Z),
    }
}

impl carl_env::runtime::Runtime for Fetch {
    fn goal_states(&self, states: &[Vec<f64>]) -> Result<Vec<Vec<f64>>, EnvError> {
        Ok(self.states_near_target(states))
    }
}

impl Env for Fetch {
    fn id(&self) -> &'static str {
        ENV
    }
    fn obs_dim(&self) -> usize {
        OBS_DIM
    }
    fn state_dim(&self) -> usize {
        self.nq + self.nv + 3 + self.model.link_names.len()
    }
    fn observation_space(&self) -> Space {
        Space::Box {
            low: vec![f32::NEG_INFINITY; OBS_DIM],
            high: vec![f32::INFINITY; OBS_DIM],
            shape: vec![OBS_DIM],
            dtype: DType::Float32,
        }
    }
    fn action_space(&self) -> Space {
        self.model.action_space()
    }

    fn reset_into(&mut self, seed: Option<u64>, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(ENV, obs, OBS_DIM)?;
        if let Some(seed) = seed {
            self.rng = EnvRng::from_seed(seed);
        }
        self.target = self.random_target();
        self.contacts.fill(0.0);
        self.world = Some(RobotWorld::build(&self.model, &self.params, &self.init_config()));
        let distance = self.torso().map_or(f64::NAN, |t| norm(sub(self.target, t.pos)));
        self.info = FetchInfo {
            reward: FetchReward {
                distance,
                ..FetchReward::default()
            },
            ..FetchInfo::default()
        };
        self.write_obs(obs);
        Ok(())
    }

    fn step_into(&mut self, action: &Action, obs: &mut [f32]) -> Result<StepOutcome, EnvError> {
        let ctrl = self.controls(action)?;
        check_obs_len(ENV, obs, OBS_DIM)?;
        let Some(world) = self.world.as_mut() else {
            return Err(EnvError::NeedsReset { env: ENV });
        };
        let before_pos = torso_frame(world).pos;
        let before = self.state_vec();
        let world = self.world.as_mut().expect("checked");
        for _ in 0..self.model.side.frame_skip {
            world.step(ctrl);
        }
        let diverged = !world.is_sane(self.model.side.max_speed);
        if diverged {
            self.load(&before);
        } else {
            self.update_contacts();
        }
        let after = self.torso().expect("world exists");
        let mut reward = fetch_reward(before_pos, &after, self.target, self.params.target_radius, self.dt());
        if diverged {
            reward.hit = false;
            reward.weighted_hit = 0.0;
        }
        if reward.hit {
            self.target = self.random_target();
        }
        self.write_obs(obs);
        self.info = FetchInfo {
            reward,
            hits: self.info.hits + u64::from(reward.hit),
            diverged,
        };
        Ok(StepOutcome {
            reward: reward.total(),
            terminated: diverged,
            truncated: false,
        })
    }

    fn observe_into(&self, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(ENV, obs, OBS_DIM)?;
        self.write_obs(obs);
        Ok(())
    }

    /// Root pose (7), joint angles (10), generalized velocities (16), target (3), contact flags (11).
    fn state(&self) -> Vec<f64> {
        self.state_vec()
    }

    fn set_state(&mut self, state: &[f64]) -> Result<(), EnvError> {
        carl_env::api::check_state_len(ENV, state, self.state_dim())?;
        self.load(state);
        self.info = FetchInfo::default();
        Ok(())
    }

    fn info(&self) -> Info {
        let i = &self.info;
        let r = &i.reward;
        let mut m = Info::new();
        m.insert("distance".into(), r.distance);
        m.insert("moving_to_target".into(), r.moving_to_target);
        m.insert("torso_is_up".into(), r.torso_is_up);
        m.insert("torso_height".into(), r.torso_height);
        m.insert("hit".into(), f64::from(u8::from(r.hit)));
        m.insert("weighted_hit".into(), r.weighted_hit);
        m.insert("hits".into(), i.hits as f64);
        m.insert("diverged".into(), f64::from(u8::from(i.diverged)));
        m
    }

    fn render(&self) -> Option<carl_pixels::Frame> {
        let w = self.world.as_ref()?;
        let t = Vector::new(self.target[0] as f32, self.target[1] as f32, self.target[2] as f32);
        let torso = w.link_pose(w.torso).translation;
        // Look at the middle of dog and target from the side, far enough to see both.
        let mid = (torso + t) * 0.5;
        let span = (t - torso).length().max(4.0);
        let look = Vector::new(mid.x, mid.y, 0.8);
        let cam = super::render::Camera {
            eye: look + Vector::new(0.0, -1.3 * span - 4.0, 0.5 * span + 2.0),
            target: look,
            focal: 420.0,
        };
        Some(super::render::render_from(
            w,
            &cam,
            &[(t, 0.4, carl_pixels::Color(220, 60, 40))],
        ))
    }
}
