//! Gymnasium MuJoCo v5 locomotion tasks (Ant, HalfCheetah, Humanoid) on a URDF robot.
//!
//! Same as Gymnasium v5: reward `healthy_reward + forward_reward_weight·ẋ − ctrl_cost_weight·Σa²
//! − contact_cost_weight·Σclip(cfrc_ext, ±1)²` (each term with the task's weights), the torso's
//! x velocity measured over the whole frame-skipped step, the healthy z range and termination,
//! reset noise (uniform ±scale on positions, scale·N(0,1) on velocities), frame skip 5 at a
//! 0.01 s physics step, and the observation layout `qpos[skip..] ++ qvel (++ clip(cfrc_ext))`.
//!
//! Where it differs (documented deviations and known gaps) depends on the engine:
//! * Ant and Humanoid run on the articulated-body engine ([`super::articulated`]) with the
//!   bodies of Gymnasium's ant.xml and humanoid.xml (13 each, so the per-body blocks have 13
//!   rows as in v5), MuJoCo's root velocity convention (angular velocity in the torso frame) and
//!   `cfrc_ext` with normal and friction parts; what differs from MuJoCo there is the context
//!   (CARL's Brax parameters by default; the specs' `mujoco_v5` instance sets have the XMLs');
//! * on rapier3d, `cfrc_ext` comes from rapier's normal contact impulses (no friction part) and
//!   the root's generalized velocity is rapier's world-frame linear and angular velocity; on the
//!   planar engine (HalfCheetah, Hopper, Walker2d, which do not observe it) `cfrc_ext` includes
//!   friction; `cfrc_ext` is com-based (torque about the robot's centre of mass, world axes)
//!   where the task asks for it (Ant, Humanoid);
//! * masses, damping, gravity and actuator torques come from CARL's (Brax) context, not from
//!   MuJoCo's geom densities and gears.
//!
//! The physics is the side file's engine ([`Physics`]): rapier3d, the planar engine for a
//! planar robot whose task observes no com-based body terms (HalfCheetah, Hopper, Walker2d), or
//! the articulated engine (Ant, Humanoid).
//!
//! A simulation that diverges (non-finite or faster than the side file's `max_speed`) is rolled
//! back to the state before the step and the step terminates with `info["diverged"] = 1`.
//!
//! HumanoidStandup-v5 ([`TaskConfig::HUMANOID_STANDUP`]) is Humanoid-v5's observation and
//! contact cost on the humanoid lying on its back (its own robot, humanoidstandup.xml), rewarded
//! for the torso's height `qpos[2] / timestep` (the physics step, as Gymnasium) plus 1 per step,
//! never terminated.
//!
//! Humanoid-v5 ([`TaskConfig::HUMANOID`]) differs from Ant in the ways Gymnasium's does: the
//! forward velocity is that of the mass-weighted centre of mass of all bodies (so the masses of
//! the context enter the reward), the velocity reset noise is uniform, the contact cost is
//! `min(w·Σ cfrc_ext², 10)` over raw (unclipped) com-based `cfrc_ext`, and the observation is
//! `qpos[2:] ++ qvel ++ cinert ++ cvel ++ qfrc_actuator ++ cfrc_ext` over the robot's bodies
//! (the side file's `bodies`; MuJoCo's world body row is dropped as in v5), computed by the
//! engine's world ([`super::articulated::ArticulatedWorld::com_inertia`], or [`super::com`] on
//! rapier3d). Known difference there: MuJoCo's `cinert`/`cvel` after `mj_step` belong to the
//! state at the start of the last physics step, here to the state after it. The last step's
//! actuator forces are part of [`Env::state`] so that the observation is a function of the
//! state.

use std::sync::Arc;

use carl_env::api::{Action, DType, Env, EnvError, Info, Space, StepOutcome, check_obs_len, vector_action};
use carl_env::rng::{EnvRng, normal, uniform};

use super::model::{ModelError, RobotModel, RootKind};
use super::params::RobotParams;
use super::physics::{Physics, PhysicsBuilder};
use super::world::{Configuration, RobotWorld};

/// Task constants of a Gymnasium v5 locomotion environment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TaskConfig {
    pub forward_reward_weight: f64,
    pub ctrl_cost_weight: f64,
    pub contact_cost_weight: f64,
    pub healthy_reward: f64,
    /// Healthy range of the root height (`qpos[2]` for a free root, `qpos[1]` for a planar one).
    pub healthy_z_range: Option<(f64, f64)>,
    /// The range's ends count as unhealthy (Humanoid-v5's `min_z < z < max_z`; Ant-v5 includes them).
    pub healthy_z_open: bool,
    pub terminate_when_unhealthy: bool,
    pub contact: ContactCost,
    pub reset_noise_scale: f64,
    /// Distribution of the velocity reset noise (positions are always uniform).
    pub velocity_noise: VelocityNoise,
    /// Whose x velocity the forward reward uses.
    pub forward_velocity: ForwardVelocity,
    /// Leading position coordinates left out of the observation (the x/y position).
    pub obs_skip_qpos: usize,
    pub include_cfrc_ext: bool,
    /// Healthy range (open) of the root pitch `qpos[2]` of a planar robot (Hopper-v5,
    /// Walker2d-v5).
    pub healthy_angle_range: Option<(f64, f64)>,
    /// Healthy range (open) of every entry of `qpos[2:] ++ qvel` (Hopper-v5's
    /// `healthy_state_range`).
    pub healthy_state_range: Option<(f64, f64)>,
    /// The observed velocities are clipped to `±` this (Hopper-v5, Walker2d-v5: 10).
    pub obs_velocity_clip: Option<f64>,
    /// Report `z_distance_from_origin` (`qpos[1]` minus its reset value) in `info`.
    pub z_distance_info: bool,
    /// Observe `cinert`, `cvel` and `qfrc_actuator` (Humanoid-v5).
    pub include_com_terms: bool,
    /// `cfrc_ext` as MuJoCo's: torques about the robot's centre of mass (otherwise about each
    /// link's own centre of mass).
    pub com_based_cfrc: bool,
    /// Reward the root's height over the physics time step, `qpos[2] / timestep`, instead of
    /// forward progress (HumanoidStandup-v5's `uph_cost`; `info` with Gymnasium's names
    /// `reward_linup`, `reward_quadctrl`, `reward_impact`).
    pub height_reward: bool,
}

/// How contact forces enter the cost and the observation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ContactCost {
    /// Every `cfrc_ext` entry is clipped to the range, in the cost and the observation (Ant-v5).
    ClipForces(f64, f64),
    /// The weighted sum of squared raw entries is clipped to the range; the observation is raw
    /// (Humanoid-v5's `contact_cost_range`).
    ClipCost(f64, f64),
}

/// Distribution of the reset noise on velocities.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VelocityNoise {
    /// `scale · N(0, 1)` (Ant-v5, HalfCheetah-v5).
    Normal,
    /// Uniform in `±scale` (Humanoid-v5).
    Uniform,
}

/// Whose x velocity over the frame-skipped step the forward reward uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ForwardVelocity {
    /// The root link's origin (`qpos[0]`).
    Root,
    /// The mass-weighted centre of mass of all links (Humanoid-v5's `mass_center`).
    CenterOfMass,
}

impl TaskConfig {
    /// Gymnasium `Ant-v5` defaults.
    pub const ANT: TaskConfig = TaskConfig {
        forward_reward_weight: 1.0,
        ctrl_cost_weight: 0.5,
        contact_cost_weight: 5e-4,
        healthy_reward: 1.0,
        healthy_z_range: Some((0.2, 1.0)),
        healthy_z_open: false,
        terminate_when_unhealthy: true,
        contact: ContactCost::ClipForces(-1.0, 1.0),
        reset_noise_scale: 0.1,
        velocity_noise: VelocityNoise::Normal,
        forward_velocity: ForwardVelocity::Root,
        obs_skip_qpos: 2,
        include_cfrc_ext: true,
        healthy_angle_range: None,
        healthy_state_range: None,
        obs_velocity_clip: None,
        z_distance_info: false,
        include_com_terms: false,
        com_based_cfrc: true,
        height_reward: false,
    };
    /// Gymnasium `HalfCheetah-v5` defaults.
    pub const HALF_CHEETAH: TaskConfig = TaskConfig {
        forward_reward_weight: 1.0,
        ctrl_cost_weight: 0.1,
        contact_cost_weight: 0.0,
        healthy_reward: 0.0,
        healthy_z_range: None,
        healthy_z_open: false,
        terminate_when_unhealthy: false,
        contact: ContactCost::ClipForces(-1.0, 1.0),
        reset_noise_scale: 0.1,
        velocity_noise: VelocityNoise::Normal,
        forward_velocity: ForwardVelocity::Root,
        obs_skip_qpos: 1,
        include_cfrc_ext: false,
        healthy_angle_range: None,
        healthy_state_range: None,
        obs_velocity_clip: None,
        z_distance_info: false,
        include_com_terms: false,
        com_based_cfrc: false,
        height_reward: false,
    };
    /// Gymnasium `Humanoid-v5` defaults.
    pub const HUMANOID: TaskConfig = TaskConfig {
        forward_reward_weight: 1.25,
        ctrl_cost_weight: 0.1,
        contact_cost_weight: 5e-7,
        healthy_reward: 5.0,
        healthy_z_range: Some((1.0, 2.0)),
        healthy_z_open: true,
        terminate_when_unhealthy: true,
        contact: ContactCost::ClipCost(f64::NEG_INFINITY, 10.0),
        reset_noise_scale: 1e-2,
        velocity_noise: VelocityNoise::Uniform,
        forward_velocity: ForwardVelocity::CenterOfMass,
        obs_skip_qpos: 2,
        include_cfrc_ext: true,
        healthy_angle_range: None,
        healthy_state_range: None,
        obs_velocity_clip: None,
        z_distance_info: false,
        include_com_terms: true,
        com_based_cfrc: true,
        height_reward: false,
    };
    /// Gymnasium `HumanoidStandup-v5` defaults: Humanoid's observation and contact cost
    /// (weight 0.5e-6, clipped at 10), reward `qpos[2] / timestep − 0.1·Σa² − impact + 1`, never
    /// terminated (no healthy range).
    pub const HUMANOID_STANDUP: TaskConfig = TaskConfig {
        forward_reward_weight: 0.0,
        contact_cost_weight: 0.5e-6,
        healthy_reward: 1.0,
        healthy_z_range: None,
        terminate_when_unhealthy: false,
        z_distance_info: true,
        height_reward: true,
        ..TaskConfig::HUMANOID
    };
    /// Gymnasium `Hopper-v5` defaults.
    pub const HOPPER: TaskConfig = TaskConfig {
        forward_reward_weight: 1.0,
        ctrl_cost_weight: 1e-3,
        contact_cost_weight: 0.0,
        healthy_reward: 1.0,
        healthy_z_range: Some((0.7, f64::INFINITY)),
        healthy_z_open: true,
        terminate_when_unhealthy: true,
        contact: ContactCost::ClipForces(-1.0, 1.0),
        reset_noise_scale: 5e-3,
        velocity_noise: VelocityNoise::Uniform,
        forward_velocity: ForwardVelocity::Root,
        obs_skip_qpos: 1,
        include_cfrc_ext: false,
        healthy_angle_range: Some((-0.2, 0.2)),
        healthy_state_range: Some((-100.0, 100.0)),
        obs_velocity_clip: Some(10.0),
        z_distance_info: true,
        include_com_terms: false,
        com_based_cfrc: false,
        height_reward: false,
    };
    /// Gymnasium `Walker2d-v5` defaults.
    pub const WALKER2D: TaskConfig = TaskConfig {
        healthy_z_range: Some((0.8, 2.0)),
        healthy_angle_range: Some((-1.0, 1.0)),
        healthy_state_range: None,
        ..TaskConfig::HOPPER
    };
}

/// Reward terms and positions of the last step (Gymnasium's `info`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StepInfo {
    pub x_position: f64,
    pub y_position: f64,
    pub x_velocity: f64,
    pub reward_forward: f64,
    pub reward_ctrl: f64,
    pub reward_contact: f64,
    pub reward_survive: f64,
    /// The physics diverged during the last step (rolled back, episode terminated).
    pub diverged: bool,
}

/// A locomotion environment: robot model, context, task and the instance's own world.
#[derive(Debug)]
pub struct Locomotion {
    id: &'static str,
    model: Arc<RobotModel>,
    params: RobotParams,
    task: TaskConfig,
    world: Option<Physics>,
    builder: PhysicsBuilder,
    /// Raw (unclipped) contact wrenches, 6 per link.
    cfrc: Vec<f64>,
    /// Actuator forces of the last step, one per joint (only with `include_com_terms`).
    act: Vec<f64>,
    rng: EnvRng,
    info: StepInfo,
    init_root: Vec<f64>,
    /// `qpos` at reset before the noise: the free root's pose, then the side file's
    /// `initial_joints` (MuJoCo's `qpos0`).
    init_qpos: Vec<f64>,
    nq: usize,
    nv: usize,
}

impl Clone for Locomotion {
    /// A rapier clone gets a world rebuilt from the full [`Env::state`]: positions, velocities
    /// and contact wrenches are equal, rapier's solver caches (warm-start impulses) start
    /// empty. An articulated world is copied exactly.
    fn clone(&self) -> Self {
        let mut c = Locomotion {
            world: None,
            cfrc: self.cfrc.clone(),
            act: self.act.clone(),
            rng: self.rng.clone(),
            info: self.info,
            model: self.model.clone(),
            params: self.params.clone(),
            builder: self.builder.clone(),
            init_root: self.init_root.clone(),
            init_qpos: self.init_qpos.clone(),
            ..*self
        };
        match &self.world {
            Some(Physics::Articulated(w)) => c.world = Some(Physics::Articulated(w.clone())),
            Some(Physics::Rapier(_)) => c.load(&self.state_vec()),
            None => {}
        }
        c
    }
}

impl Locomotion {
    /// The task `task` of `model` under context `params`; refused if the side file asks for an
    /// engine that cannot take the model.
    pub fn new(
        id: &'static str,
        model: Arc<RobotModel>,
        params: RobotParams,
        task: TaskConfig,
    ) -> Result<Self, ModelError> {
        let nj = model.joint_names.len();
        let free = model.side.root == RootKind::Free;
        let init_root = if free {
            vec![0.0, 0.0, model.side.root_height, 1.0, 0.0, 0.0, 0.0]
        } else {
            Vec::new()
        };
        let nq = init_root.len() + nj;
        let mut init_qpos = init_root.clone();
        init_qpos.extend(model.joint_names.iter().map(|j| {
            model
                .side
                .initial_joints
                .iter()
                .find(|i| i.joint == *j)
                .map_or(0.0, |i| i.value)
        }));
        let nv = if free { 6 } else { 0 } + nj;
        let cfrc = vec![0.0; 6 * model.link_names.len()];
        let act = vec![0.0; if task.include_com_terms { nj } else { 0 }];
        let builder = PhysicsBuilder::for_model(&model, &params)?;
        Ok(Locomotion {
            builder,
            id,
            model,
            params,
            task,
            world: None,
            cfrc,
            act,
            rng: EnvRng::from_seed(carl_env::rng::DEFAULT_SEED),
            info: StepInfo::default(),
            init_root,
            init_qpos,
            nq,
            nv,
        })
    }

    pub fn params(&self) -> &RobotParams {
        &self.params
    }
    pub fn model(&self) -> &RobotModel {
        &self.model
    }
    pub fn task(&self) -> &TaskConfig {
        &self.task
    }
    /// The rapier world (`None` before the first reset and on the other engines).
    pub fn world(&self) -> Option<&RobotWorld> {
        self.world.as_ref().and_then(Physics::rapier)
    }
    /// The articulated engine's world (`None` before the first reset and on rapier).
    pub fn articulated_world(&self) -> Option<&super::articulated::ArticulatedWorld> {
        self.world.as_ref().and_then(Physics::articulated)
    }
    /// The physics of the current episode.
    pub fn physics(&self) -> Option<&Physics> {
        self.world.as_ref()
    }
    pub fn last_info(&self) -> StepInfo {
        self.info
    }
    /// Environment step duration (s): physics step × frame skip.
    pub fn dt(&self) -> f64 {
        self.model.side.timestep * self.model.side.frame_skip as f64
    }
    pub fn nq(&self) -> usize {
        self.nq
    }
    pub fn nv(&self) -> usize {
        self.nv
    }
    fn num_links(&self) -> usize {
        self.model.link_names.len()
    }

    /// Generalized positions `qpos` (MuJoCo layout: free root `[x y z qw qx qy qz]`, then joints).
    pub fn qpos(&self) -> Vec<f64> {
        let s = self.state_vec();
        s[..self.nq].to_vec()
    }

    fn root_z_index(&self) -> usize {
        if self.model.side.root == RootKind::Free { 2 } else { 1 }
    }

    fn state_vec(&self) -> Vec<f64> {
        let mut s = Vec::with_capacity(self.state_dim());
        match &self.world {
            Some(w) => {
                let c = w.configuration();
                s.extend(&c.root);
                s.extend(&c.joints);
                s.extend(&c.vel);
            }
            None => {
                s.extend(&self.init_qpos);
                s.resize(self.nq + self.nv, 0.0);
            }
        }
        s.extend(&self.cfrc);
        s.extend(&self.act);
        s
    }

    fn load(&mut self, s: &[f64]) {
        let root_len = self.init_root.len();
        let q = Configuration {
            root: s[..root_len].to_vec(),
            joints: s[root_len..self.nq].to_vec(),
            vel: s[self.nq..self.nq + self.nv].to_vec(),
        };
        self.world = Some(self.builder.build(&self.model, &self.params, &q));
        let n = self.cfrc.len();
        self.cfrc.copy_from_slice(&s[self.nq + self.nv..self.nq + self.nv + n]);
        self.act.copy_from_slice(&s[self.nq + self.nv + n..]);
    }

    fn num_bodies(&self) -> usize {
        self.model.bodies.len()
    }

    /// `cfrc_ext` of the bodies as the task observes and costs it (6 per body): com-based with
    /// `com_based_cfrc`, else about each link's centre of mass; raw.
    fn body_cfrc(&self) -> Vec<f64> {
        let bodies = &self.model.bodies;
        let mut out = vec![0.0; 6 * bodies.len()];
        let articulated = self.world.as_ref().and_then(Physics::articulated);
        match (self.world(), articulated, self.task.com_based_cfrc) {
            (Some(w), _, true) => w.com_wrenches(bodies, w.center_of_mass(), &self.cfrc, &mut out),
            (_, Some(w), true) => w.com_wrenches(bodies, w.center_of_mass(), &self.cfrc, &mut out),
            _ => {
                for (k, &i) in bodies.iter().enumerate() {
                    out[6 * k..6 * k + 6].copy_from_slice(&self.cfrc[6 * i..6 * i + 6]);
                }
            }
        }
        out
    }

    /// The contact cost (positive) of the current contact wrenches.
    fn contact_cost(&self) -> f64 {
        let w = self.task.contact_cost_weight;
        if w == 0.0 {
            return 0.0;
        }
        let cfrc = self.body_cfrc();
        match self.task.contact {
            ContactCost::ClipForces(lo, hi) => {
                w * cfrc
                    .iter()
                    .map(|f| carl_env::api::np_clip(*f, lo, hi).powi(2))
                    .sum::<f64>()
            }
            ContactCost::ClipCost(lo, hi) => {
                carl_env::api::np_clip(w * cfrc.iter().map(|f| f.powi(2)).sum::<f64>(), lo, hi)
            }
        }
    }

    /// The x coordinate whose rate is the forward velocity.
    fn forward_x(&self) -> f64 {
        match (self.task.forward_velocity, &self.world) {
            (ForwardVelocity::CenterOfMass, Some(w)) => w.center_of_mass()[0],
            _ => self.state_vec()[0],
        }
    }

    fn write_obs(&self, obs: &mut [f32]) {
        self.for_each_obs(|k, v| obs[k] = v as f32);
    }

    /// The observation as computed (float64, as the space declares).
    fn write_obs_f64(&self, obs: &mut [f64]) {
        self.for_each_obs(|k, v| obs[k] = v);
    }

    /// Calls `put(k, value)` for every observation component `k` in order.
    fn for_each_obs(&self, mut put: impl FnMut(usize, f64)) {
        let s = self.state_vec();
        let mut k = 0;
        for v in &s[self.task.obs_skip_qpos..self.nq] {
            put(k, *v);
            k += 1;
        }
        for v in &s[self.nq..self.nq + self.nv] {
            put(
                k,
                self.task
                    .obs_velocity_clip
                    .map_or(*v, |c| carl_env::api::np_clip(*v, -c, c)),
            );
            k += 1;
        }
        if self.task.include_com_terms {
            let nb = self.num_bodies();
            let mut com_terms = vec![0.0; 16 * nb];
            if let Some(w) = self.world() {
                let c = w.center_of_mass();
                w.com_inertia(&self.model.bodies, c, &mut com_terms[..10 * nb]);
                w.com_velocity(&self.model.bodies, c, &mut com_terms[10 * nb..]);
            } else if let Some(w) = self.world.as_ref().and_then(Physics::articulated) {
                let c = w.center_of_mass();
                w.com_inertia(&self.model.bodies, c, &mut com_terms[..10 * nb]);
                w.com_velocity(&self.model.bodies, c, &mut com_terms[10 * nb..]);
            }
            for v in com_terms.iter().chain(&self.act) {
                put(k, *v);
                k += 1;
            }
        }
        if self.task.include_cfrc_ext {
            let clip = match self.task.contact {
                ContactCost::ClipForces(lo, hi) => Some((lo, hi)),
                ContactCost::ClipCost(..) => None,
            };
            for f in self.body_cfrc() {
                put(k, clip.map_or(f, |(lo, hi)| carl_env::api::np_clip(f, lo, hi)));
                k += 1;
            }
        }
    }

    fn is_healthy(&self, s: &[f64]) -> bool {
        let finite = s.iter().all(|x| x.is_finite());
        let open = |(lo, hi): (f64, f64), x: f64| lo < x && x < hi;
        if let Some(r) = self.task.healthy_angle_range
            && !open(r, s[self.root_z_index() + 1])
        {
            return false;
        }
        if let Some(r) = self.task.healthy_state_range
            && !s[2..self.nq + self.nv].iter().all(|x| open(r, *x))
        {
            return false;
        }
        match self.task.healthy_z_range {
            Some((lo, hi)) => {
                let z = s[self.root_z_index()];
                let inside = if self.task.healthy_z_open {
                    lo < z && z < hi
                } else {
                    lo <= z && z <= hi
                };
                finite && inside
            }
            None => finite,
        }
    }

    fn controls<'a>(&self, action: &'a Action) -> Result<&'a [f32], EnvError> {
        vector_action(self.id, action, self.model.num_actuators())
    }
}

impl carl_env::runtime::Runtime for Locomotion {}

impl Env for Locomotion {
    fn id(&self) -> &'static str {
        self.id
    }
    fn obs_dim(&self) -> usize {
        let nb = self.num_bodies();
        self.nq - self.task.obs_skip_qpos
            + self.nv
            + if self.task.include_com_terms {
                16 * nb + self.act.len()
            } else {
                0
            }
            + if self.task.include_cfrc_ext { 6 * nb } else { 0 }
    }
    fn state_dim(&self) -> usize {
        self.nq + self.nv + 6 * self.num_links() + self.act.len()
    }
    fn observation_space(&self) -> Space {
        let n = self.obs_dim();
        Space::Box {
            low: vec![f32::NEG_INFINITY; n],
            high: vec![f32::INFINITY; n],
            shape: vec![n],
            dtype: DType::Float64,
        }
    }
    fn action_space(&self) -> Space {
        self.model.action_space()
    }

    fn reset_into(&mut self, seed: Option<u64>, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(self.id, obs, self.obs_dim())?;
        if let Some(seed) = seed {
            self.rng = EnvRng::from_seed(seed);
        }
        let ns = self.task.reset_noise_scale;
        let mut s = vec![0.0; self.state_dim()];
        s[..self.nq].copy_from_slice(&self.init_qpos);
        for v in &mut s[..self.nq] {
            *v += uniform(&mut self.rng, -ns, ns);
        }
        for v in &mut s[self.nq..self.nq + self.nv] {
            *v = match self.task.velocity_noise {
                VelocityNoise::Normal => ns * normal(&mut self.rng, 0.0, 1.0),
                VelocityNoise::Uniform => uniform(&mut self.rng, -ns, ns),
            };
        }
        self.load(&s);
        self.info = StepInfo::default();
        self.info.x_position = s[0];
        self.info.y_position = if self.init_root.is_empty() { 0.0 } else { s[1] };
        self.write_obs(obs);
        Ok(())
    }

    fn step_into(&mut self, action: &Action, obs: &mut [f32]) -> Result<StepOutcome, EnvError> {
        let ctrl = self.controls(action)?;
        check_obs_len(self.id, obs, self.obs_dim())?;
        if self.world.is_none() {
            return Err(EnvError::NeedsReset { env: self.id });
        }
        let before = self.state_vec();
        let x_before = self.forward_x();
        let world = self.world.as_mut().expect("checked");
        world.steps(ctrl, self.model.side.frame_skip);
        let diverged = !world.is_sane(self.model.side.max_speed);
        if diverged {
            self.load(&before);
        } else {
            let w = self.world.as_ref().expect("checked");
            let mut cfrc = std::mem::take(&mut self.cfrc);
            w.contact_wrenches(&mut cfrc);
            self.cfrc = cfrc;
            if !self.act.is_empty() {
                let mut act = std::mem::take(&mut self.act);
                w.actuator_forces(ctrl, &mut act);
                self.act = act;
            }
        }
        let after = self.state_vec();
        let dt = self.dt();
        let x_velocity = (self.forward_x() - x_before) / dt;
        let y_position = if self.init_root.is_empty() { 0.0 } else { after[1] };
        let reward_forward = if self.task.height_reward {
            after[self.root_z_index()] / self.model.side.timestep
        } else {
            self.task.forward_reward_weight * x_velocity
        };
        let reward_ctrl = -self.task.ctrl_cost_weight * ctrl.iter().map(|a| f64::from(*a).powi(2)).sum::<f64>();
        let reward_contact = -self.contact_cost();
        let healthy = !diverged && self.is_healthy(&after);
        let reward_survive = if healthy { self.task.healthy_reward } else { 0.0 };
        let terminated = diverged || (self.task.terminate_when_unhealthy && !healthy);
        self.info = StepInfo {
            x_position: after[0],
            y_position,
            x_velocity,
            reward_forward,
            reward_ctrl,
            reward_contact,
            reward_survive,
            diverged,
        };
        self.write_obs(obs);
        Ok(StepOutcome {
            reward: reward_forward + reward_survive + reward_ctrl + reward_contact,
            terminated,
            truncated: false,
        })
    }

    fn observe_into(&self, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(self.id, obs, self.obs_dim())?;
        self.write_obs(obs);
        Ok(())
    }

    fn observe_f64_into(&self, obs: &mut [f64]) -> Result<(), EnvError> {
        check_obs_len(self.id, obs, self.obs_dim())?;
        self.write_obs_f64(obs);
        Ok(())
    }

    /// `qpos ++ qvel ++ cfrc_ext` (6 per link, raw).
    fn state(&self) -> Vec<f64> {
        self.state_vec()
    }

    fn set_state(&mut self, state: &[f64]) -> Result<(), EnvError> {
        carl_env::api::check_state_len(self.id, state, self.state_dim())?;
        self.load(state);
        self.info = StepInfo::default();
        Ok(())
    }

    fn info(&self) -> Info {
        let i = &self.info;
        let mut m = Info::new();
        m.insert("x_position".into(), i.x_position);
        if !self.init_root.is_empty() {
            m.insert("y_position".into(), i.y_position);
        }
        if self.task.z_distance_info {
            let z = self.root_z_index();
            m.insert("z_distance_from_origin".into(), self.state_vec()[z] - self.init_qpos[z]);
        }
        if self.task.height_reward {
            m.insert("reward_linup".into(), i.reward_forward);
            m.insert("reward_quadctrl".into(), i.reward_ctrl);
            m.insert("reward_impact".into(), i.reward_contact);
            m.insert("diverged".into(), f64::from(u8::from(i.diverged)));
            return m;
        }
        m.insert("x_velocity".into(), i.x_velocity);
        m.insert("reward_forward".into(), i.reward_forward);
        m.insert("reward_ctrl".into(), i.reward_ctrl);
        if self.task.contact_cost_weight != 0.0 {
            m.insert("reward_contact".into(), i.reward_contact);
        }
        if self.task.healthy_reward != 0.0 {
            m.insert("reward_survive".into(), i.reward_survive);
        }
        m.insert("diverged".into(), f64::from(u8::from(i.diverged)));
        m
    }

    fn render(&self) -> Option<carl_pixels::Frame> {
        self.world.as_ref().map(Physics::render)
    }
}

#[cfg(test)]
mod tests {
    use crate::{default_params, make_robot};

    /// Gymnasium's healthy checks at the ends of the range: Ant-v5 `min_z <= z <= max_z`,
    /// Humanoid-v5 `min_z < z < max_z`.
    #[test]
    fn healthy_range_ends_as_in_gymnasium() {
        let at = |id: &str, z: f64| {
            let env = make_robot(id, default_params(id).unwrap()).unwrap();
            let mut s = vec![0.0; 8];
            s[env.root_z_index()] = z;
            env.is_healthy(&s)
        };
        assert!(at("ant", 0.2) && at("ant", 1.0) && !at("ant", 1.0001));
        assert!(!at("humanoid", 1.0) && !at("humanoid", 2.0) && at("humanoid", 1.5));
        assert!(!at("ant", f64::NAN));
    }
}
