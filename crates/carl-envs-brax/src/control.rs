//! Gymnasium MuJoCo v5's small control tasks on a robot welded to the world:
//! InvertedPendulum-v5, InvertedDoublePendulum-v5, Reacher-v5 and Pusher-v5 ([`ControlTask`]).
//!
//! As Gymnasium 1.4's: observation layout, reward terms and weights, termination, reset
//! noise and frame skip (the time step is the side file's, MuJoCo's). The physics is the side
//! file's engine through [`Physics`] (the articulated engine for all four); the task reads
//! coordinates, rates, sites and constraint forces only.
//!
//! * InvertedPendulum: observation `qpos ++ qvel` (cart x, pole angle, their rates); reward 1
//!   while `|angle| ≤ 0.2` and the observation is finite, terminated otherwise; reset noise
//!   uniform ±0.01 on `qpos` and `qvel`; frame skip 2.
//! * InvertedDoublePendulum: observation `x, sin θ₁, sin θ₂, cos θ₁, cos θ₂,
//!   clip(qvel, ±10), clip(qfrc_constraint[0], ±10)`; reward `10·alive − (0.01 x_tip² +
//!   (z_tip − 2)²) − (1e-3 θ̇₁² + 5e-3 θ̇₂²)`, terminated when the tip site is at `z ≤ 1`; reset
//!   noise uniform ±0.1 on `qpos`, `0.1·N(0, 1)` on `qvel`; frame skip 5.
//! * Reacher: `qpos` is the two arm angles and the target's position (Gymnasium's target
//!   slides, which no force moves: task state here); observation `cos θ, sin θ, target,
//!   θ̇, (fingertip − target)[:2]`; reward `−|fingertip − target| − Σa²`; never terminates;
//!   reset: arm angles uniform ±0.1, the target uniform in the disc of radius 0.2 (rejection
//!   from the square, as Gymnasium), arm rates uniform ±0.005; frame skip 2.
//! * Pusher: `qpos` is the seven arm angles and the object's two slides (`obj_slidey`,
//!   `obj_slidex`, MuJoCo's order); Gymnasium's goal slides, which no force moves, are the
//!   context's goal position here; observation `qpos[:7], qvel[:7]`, the fingertip's, the
//!   object's and the goal's positions (centres of mass, world frame); reward
//!   `−|object − goal| − 0.1·Σa² − 0.5·|object − fingertip|`; never terminates; reset: the arm
//!   at rest at 0 with rates uniform ±0.005, the object's slides (y, x) uniform in
//!   `[−0.3, 0] × [−0.2, 0.2]` drawn until the object is more than 0.17 m from the goal (in x-y),
//!   the object at rest; frame skip 5.
//!
//! A simulation that diverges (non-finite or faster than the side file's `max_speed`) is rolled
//! back to the state before the step and the step terminates with `info["diverged"] = 1`.

use std::sync::Arc;

use carl_env::api::{Action, DType, Env, EnvError, Info, Space, StepOutcome, check_obs_len, np_clip, vector_action};
use carl_env::rng::{EnvRng, normal, uniform};

use super::model::{ModelError, RobotModel};
use super::params::{RobotParams, finite_or};
use super::physics::{Physics, PhysicsBuilder};
use super::world::Configuration;

/// Which Gymnasium task.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ControlTask {
    InvertedPendulum,
    InvertedDoublePendulum,
    Reacher,
    Pusher,
}

impl ControlTask {
    /// Observation size.
    fn obs_dim(self) -> usize {
        match self {
            ControlTask::InvertedPendulum => 4,
            ControlTask::InvertedDoublePendulum => 9,
            ControlTask::Reacher => 10,
            ControlTask::Pusher => 23,
        }
    }
    /// Entries of the state after `q ++ v` (IDP: the slider's constraint force; Reacher: the
    /// target, which sits between the arm's angles and rates as in MuJoCo's `qpos`).
    fn extra(self) -> usize {
        match self {
            ControlTask::InvertedPendulum | ControlTask::Pusher => 0,
            ControlTask::InvertedDoublePendulum => 1,
            ControlTask::Reacher => 2,
        }
    }
}

/// Reward terms of the last step (Gymnasium's `info`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Terms {
    survive: f64,
    distance: f64,
    velocity: f64,
    dist: f64,
    ctrl: f64,
    near: f64,
    diverged: bool,
}

/// One instance of a control task.
#[derive(Debug)]
pub struct Control {
    id: &'static str,
    task: ControlTask,
    model: Arc<RobotModel>,
    params: RobotParams,
    builder: PhysicsBuilder,
    world: Option<Physics>,
    /// IDP: `qfrc_constraint[0]` of the last step; Reacher: the target (x, y).
    extra: Vec<f64>,
    /// The sites whose positions the task reads (IDP's tip, Reacher's fingertip, Pusher's
    /// fingertip and object).
    sites: Vec<(usize, [f64; 3])>,
    /// Pusher: the goal's position (world) and the object's x-y at slides 0.
    goal: [f64; 3],
    object_origin: [f64; 2],
    rng: EnvRng,
    terms: Terms,
    n: usize,
}

impl Clone for Control {
    /// An articulated world is copied exactly; a rapier one is rebuilt from the state.
    fn clone(&self) -> Self {
        let mut c = Control {
            world: None,
            model: self.model.clone(),
            params: self.params.clone(),
            builder: self.builder.clone(),
            extra: self.extra.clone(),
            sites: self.sites.clone(),
            rng: self.rng.clone(),
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

impl Control {
    /// Task `task` on `model` under context `params`; refused if the model lacks the site the
    /// task reads or its engine cannot take it.
    pub fn new(
        id: &'static str,
        model: Arc<RobotModel>,
        params: RobotParams,
        task: ControlTask,
    ) -> Result<Self, ModelError> {
        let site_names: &[&str] = match task {
            ControlTask::InvertedPendulum => &[],
            ControlTask::InvertedDoublePendulum => &["tip"],
            ControlTask::Reacher => &["fingertip"],
            ControlTask::Pusher => &["tips_arm", "object"],
        };
        let sites = site_names
            .iter()
            .map(|s| {
                model.site(s).ok_or_else(|| ModelError::Side {
                    robot: model.name,
                    message: format!("the task needs a site named {s}"),
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let builder = PhysicsBuilder::for_model(&model, &params)?;
        let n = model.joint_names.len();
        // The goal: x, y in the world, z above the table (the floor).
        let goal = [
            finite_or(params.goal_position[0], 0.0),
            finite_or(params.goal_position[1], 0.0),
            model.side.floor_height + finite_or(params.goal_position[2], 0.0),
        ];
        let object_origin = match (task, sites.get(1)) {
            (ControlTask::Pusher, Some(&(link, p))) => {
                let zero = Configuration {
                    root: Vec::new(),
                    joints: vec![0.0; n],
                    vel: vec![0.0; n],
                };
                let rest = builder.build(&model, &params, &zero);
                let o = rest.link_point(link, p);
                [o[0], o[1]]
            }
            _ => [0.0; 2],
        };
        Ok(Control {
            id,
            task,
            builder,
            world: None,
            extra: vec![0.0; task.extra()],
            sites,
            goal,
            object_origin,
            rng: EnvRng::from_seed(carl_env::rng::DEFAULT_SEED),
            terms: Terms::default(),
            n,
            model,
            params,
        })
    }

    pub fn params(&self) -> &RobotParams {
        &self.params
    }
    pub fn model(&self) -> &RobotModel {
        &self.model
    }
    /// The physics of the current episode (`None` before the first reset).
    pub fn physics(&self) -> Option<&Physics> {
        self.world.as_ref()
    }
    /// Environment step duration (s): physics step × frame skip.
    pub fn dt(&self) -> f64 {
        self.model.side.timestep * self.model.side.frame_skip as f64
    }

    fn q_v(&self) -> (Vec<f64>, Vec<f64>) {
        match &self.world {
            Some(w) => {
                let c = w.configuration();
                (c.joints, c.vel)
            }
            None => (vec![0.0; self.n], vec![0.0; self.n]),
        }
    }

    /// `qpos ++ qvel (++ qfrc_constraint[0])`; Reacher: `arm angles ++ target ++ arm rates`.
    fn state_vec(&self) -> Vec<f64> {
        let (q, v) = self.q_v();
        let mut s = Vec::with_capacity(self.state_dim());
        s.extend(&q);
        if self.task == ControlTask::Reacher {
            s.extend(&self.extra);
            s.extend(&v);
        } else {
            s.extend(&v);
            s.extend(&self.extra);
        }
        s
    }

    fn load(&mut self, s: &[f64]) {
        let n = self.n;
        let k = self.task.extra();
        let (joints, vel, extra) = if self.task == ControlTask::Reacher {
            (&s[..n], &s[n + k..], &s[n..n + k])
        } else {
            (&s[..n], &s[n..2 * n], &s[2 * n..])
        };
        let c = Configuration {
            root: Vec::new(),
            joints: joints.to_vec(),
            vel: vel.to_vec(),
        };
        self.world = Some(self.builder.build(&self.model, &self.params, &c));
        self.extra.copy_from_slice(extra);
    }

    /// World position of the task's site `k` (MuJoCo coordinates: Reacher's URDF z is MuJoCo's y).
    fn site_pos(&self, k: usize) -> [f64; 3] {
        match (&self.world, self.sites.get(k)) {
            (Some(w), Some(&(link, p))) => w.link_point(link, p),
            _ => [0.0; 3],
        }
    }

    fn for_each_obs(&self, mut put: impl FnMut(usize, f64)) {
        let (q, v) = self.q_v();
        let mut k = 0;
        let mut push = |x: f64| {
            put(k, x);
            k += 1;
        };
        match self.task {
            ControlTask::InvertedPendulum => q.iter().chain(&v).for_each(|x| push(*x)),
            ControlTask::InvertedDoublePendulum => {
                push(q[0]);
                q[1..].iter().for_each(|a| push(a.sin()));
                q[1..].iter().for_each(|a| push(a.cos()));
                v.iter().for_each(|x| push(np_clip(*x, -10.0, 10.0)));
                push(np_clip(self.extra[0], -10.0, 10.0));
            }
            ControlTask::Reacher => {
                q.iter().for_each(|a| push(a.cos()));
                q.iter().for_each(|a| push(a.sin()));
                self.extra.iter().for_each(|x| push(*x));
                v.iter().for_each(|x| push(*x));
                let tip = self.site_pos(0);
                push(tip[0] - self.extra[0]);
                push(tip[2] - self.extra[1]);
            }
            ControlTask::Pusher => {
                q[..7].iter().chain(&v[..7]).for_each(|x| push(*x));
                [self.site_pos(0), self.site_pos(1), self.goal]
                    .iter()
                    .flatten()
                    .for_each(|x| push(*x));
            }
        }
    }

    fn write_obs(&self, obs: &mut [f32]) {
        self.for_each_obs(|k, v| obs[k] = v as f32);
    }

    fn controls<'a>(&self, action: &'a Action) -> Result<&'a [f32], EnvError> {
        vector_action(self.id, action, self.model.num_actuators())
    }

    /// Reward and termination of the state after a step with controls `ctrl`.
    fn outcome(&mut self, ctrl: &[f32], diverged: bool) -> StepOutcome {
        let mut t = Terms {
            diverged,
            ..Terms::default()
        };
        let (reward, terminated) = match self.task {
            ControlTask::InvertedPendulum => {
                let mut obs = [0.0; 4];
                self.for_each_obs(|k, v| obs[k] = v);
                let terminated = diverged || !obs.iter().all(|x| x.is_finite()) || obs[1].abs() > 0.2;
                t.survive = if terminated { 0.0 } else { 1.0 };
                (t.survive, terminated)
            }
            ControlTask::InvertedDoublePendulum => {
                let tip = self.site_pos(0);
                let (x, y) = (tip[0], tip[2]);
                let (_, v) = self.q_v();
                let terminated = diverged || y <= 1.0;
                t.distance = -(0.01 * x * x + (y - 2.0).powi(2));
                t.velocity = -(1e-3 * v[1] * v[1] + 5e-3 * v[2] * v[2]);
                t.survive = if terminated { 0.0 } else { 10.0 };
                (t.survive + t.distance + t.velocity, terminated)
            }
            ControlTask::Reacher => {
                let tip = self.site_pos(0);
                let (dx, dy) = (tip[0] - self.extra[0], tip[2] - self.extra[1]);
                t.dist = -(dx * dx + dy * dy).sqrt();
                t.ctrl = -ctrl.iter().map(|a| f64::from(*a).powi(2)).sum::<f64>();
                (t.dist + t.ctrl, diverged)
            }
            ControlTask::Pusher => {
                let (tip, object) = (self.site_pos(0), self.site_pos(1));
                let dist = |a: [f64; 3], b: [f64; 3]| (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt();
                t.near = -0.5 * dist(object, tip);
                t.dist = -dist(object, self.goal);
                t.ctrl = -0.1 * ctrl.iter().map(|a| f64::from(*a).powi(2)).sum::<f64>();
                (t.dist + t.ctrl + t.near, diverged)
            }
        };
        self.terms = t;
        StepOutcome {
            reward,
            terminated,
            truncated: false,
        }
    }
}

impl carl_env::runtime::Runtime for Control {}

impl Env for Control {
    fn id(&self) -> &'static str {
        self.id
    }
    fn obs_dim(&self) -> usize {
        self.task.obs_dim()
    }
    fn state_dim(&self) -> usize {
        2 * self.n + self.task.extra()
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
        let n = self.n;
        let mut s = vec![0.0; self.state_dim()];
        let rng = &mut self.rng;
        match self.task {
            ControlTask::InvertedPendulum => {
                for x in &mut s {
                    *x = uniform(rng, -0.01, 0.01);
                }
            }
            ControlTask::InvertedDoublePendulum => {
                for x in &mut s[..n] {
                    *x = uniform(rng, -0.1, 0.1);
                }
                for x in &mut s[n..2 * n] {
                    *x = 0.1 * normal(rng, 0.0, 1.0);
                }
            }
            ControlTask::Reacher => {
                // Gymnasium draws all four qpos (the target's two are then replaced), the
                // target by rejection, then all four qvel (the target's two set to 0).
                for x in &mut s[..n + 2] {
                    *x = uniform(rng, -0.1, 0.1);
                }
                let goal = loop {
                    let g = [uniform(rng, -0.2, 0.2), uniform(rng, -0.2, 0.2)];
                    if (g[0] * g[0] + g[1] * g[1]).sqrt() < 0.2 {
                        break g;
                    }
                };
                s[n..n + 2].copy_from_slice(&goal);
                for x in &mut s[n + 2..] {
                    *x = uniform(rng, -0.005, 0.005);
                }
                let _ = (uniform(rng, -0.005, 0.005), uniform(rng, -0.005, 0.005));
            }
            ControlTask::Pusher => {
                // Gymnasium: slides (y, x) = (U(-0.3, 0), U(-0.2, 0.2)) until the object is
                // more than 0.17 m from the goal; the arm at 0; rates uniform ±0.005 but the
                // object's (Gymnasium's four object and goal rates are drawn, then zeroed).
                let (o, g) = (self.object_origin, self.goal);
                let mut slides = [0.0; 2];
                for _ in 0..10_000 {
                    slides = [uniform(rng, -0.3, 0.0), uniform(rng, -0.2, 0.2)];
                    if (o[0] + slides[1] - g[0]).hypot(o[1] + slides[0] - g[1]) > 0.17 {
                        break;
                    }
                }
                s[n - 2..n].copy_from_slice(&slides);
                for x in &mut s[n..2 * n - 2] {
                    *x = uniform(rng, -0.005, 0.005);
                }
                for _ in 0..4 {
                    uniform(rng, -0.005, 0.005);
                }
            }
        }
        self.load(&s);
        self.terms = Terms::default();
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
        let world = self.world.as_mut().expect("checked");
        world.steps(ctrl, self.model.side.frame_skip);
        let diverged = !world.is_sane(self.model.side.max_speed);
        if diverged {
            self.load(&before);
        } else if self.task == ControlTask::InvertedDoublePendulum {
            let mut f = vec![0.0; self.n];
            world.constraint_forces(&mut f);
            self.extra[0] = f[0];
        }
        let out = self.outcome(ctrl, diverged);
        self.write_obs(obs);
        Ok(out)
    }

    fn observe_into(&self, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(self.id, obs, self.obs_dim())?;
        self.write_obs(obs);
        Ok(())
    }

    fn observe_f64_into(&self, obs: &mut [f64]) -> Result<(), EnvError> {
        check_obs_len(self.id, obs, self.obs_dim())?;
        self.for_each_obs(|k, v| obs[k] = v);
        Ok(())
    }

    /// InvertedPendulum: `qpos ++ qvel`; InvertedDoublePendulum: `qpos ++ qvel ++
    /// qfrc_constraint[0]` (observed); Reacher: `arm angles ++ target ++ arm rates`.
    fn state(&self) -> Vec<f64> {
        self.state_vec()
    }

    fn set_state(&mut self, state: &[f64]) -> Result<(), EnvError> {
        carl_env::api::check_state_len(self.id, state, self.state_dim())?;
        self.load(state);
        self.terms = Terms::default();
        Ok(())
    }

    fn info(&self) -> Info {
        let t = &self.terms;
        let mut m = Info::new();
        match self.task {
            ControlTask::InvertedPendulum => {
                m.insert("reward_survive".into(), t.survive);
            }
            ControlTask::InvertedDoublePendulum => {
                m.insert("reward_survive".into(), t.survive);
                m.insert("distance_penalty".into(), t.distance);
                m.insert("velocity_penalty".into(), t.velocity);
            }
            ControlTask::Reacher => {
                m.insert("reward_dist".into(), t.dist);
                m.insert("reward_ctrl".into(), t.ctrl);
            }
            ControlTask::Pusher => {
                m.insert("reward_dist".into(), t.dist);
                m.insert("reward_ctrl".into(), t.ctrl);
                m.insert("reward_near".into(), t.near);
            }
        }
        m.insert("diverged".into(), f64::from(u8::from(t.diverged)));
        m
    }

    fn render(&self) -> Option<carl_pixels::Frame> {
        self.world.as_ref().map(Physics::render)
    }
}

#[cfg(test)]
mod tests {
    use carl_env::api::{Action, Env};

    use crate::{default_params, make_control};

    /// Gymnasium's reset distributions: IP within ±0.01, Reacher's target in the disc of
    /// radius 0.2 and its arm rates within ±0.005.
    #[test]
    fn resets_as_gymnasium() {
        for seed in 0..20 {
            let mut ip = make_control("inverted_pendulum", default_params("inverted_pendulum").unwrap()).unwrap();
            ip.reset(Some(seed));
            assert!(ip.state().iter().all(|x| x.abs() <= 0.01));
            let mut r = make_control("reacher", default_params("reacher").unwrap()).unwrap();
            r.reset(Some(seed));
            let s = r.state();
            assert!(s[2].hypot(s[3]) < 0.2 && s[0].abs() <= 0.1 && s[4].abs() <= 0.005);
        }
    }

    /// Pusher-v5's reset: the arm at 0 with small rates, the object's slides in
    /// `[-0.3, 0] x [-0.2, 0.2]` more than 0.17 m from the goal, at rest; the observation ends
    /// with the fingertip (the wrist's origin, 0.821 m out), the object and the goal.
    #[test]
    fn pusher_resets_as_gymnasium() {
        let mut p = default_params("pusher").unwrap();
        for (name, v) in [
            ("goal_position_x", 0.45),
            ("goal_position_y", -0.05),
            ("goal_position_z", 0.002),
        ] {
            p.set(name, v).unwrap();
        }
        for seed in 0..20 {
            let mut e = make_control("pusher", p.clone()).unwrap();
            let (obs, _) = e.reset(Some(seed));
            let s = e.state();
            assert!(s[..7].iter().all(|x| *x == 0.0) && s[9..16].iter().all(|v| v.abs() <= 0.005));
            assert!((-0.3..=0.0).contains(&s[7]) && (-0.2..=0.2).contains(&s[8]) && s[16] == 0.0 && s[17] == 0.0);
            assert!(s[7].hypot(s[8]) > 0.17, "{s:?}");
            let o: Vec<f64> = obs.iter().map(|x| f64::from(*x)).collect();
            assert!((o[14] - 0.821).abs() < 1e-5 && (o[15] + 0.6).abs() < 1e-5 && o[16].abs() < 1e-5);
            assert!((o[17] - (0.45 + s[8])).abs() < 1e-5 && (o[18] - (-0.05 + s[7])).abs() < 1e-5);
            assert!((o[19] + 0.275).abs() < 1e-6 && (o[22] + 0.323).abs() < 1e-6);
        }
    }

    /// The upright double pendulum's tip is at 1.2 m: healthy (z > 1) with reward
    /// 10 − (1.2 − 2)² − small terms; tipped over it terminates.
    #[test]
    fn double_pendulum_tip_and_termination() {
        let mut e = make_control(
            "inverted_double_pendulum",
            default_params("inverted_double_pendulum").unwrap(),
        )
        .unwrap();
        e.reset(Some(0));
        e.set_state(&[0.0; 7]).unwrap();
        let s = e.step(&Action::Continuous(vec![0.0])).unwrap();
        assert!(!s.terminated && (s.reward - (10.0 - 0.64)).abs() < 0.05, "{}", s.reward);
        e.set_state(&[0.0, 1.5, 0.0, 0.0, 0.0, 0.0, 0.0]).unwrap();
        assert!(e.step(&Action::Continuous(vec![0.0])).unwrap().terminated);
    }
}
