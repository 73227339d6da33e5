//! `dmc_walker`: dm_control's `walker` domain (task `walk`; `stand` and `run` through the
//! `move_speed` option) with carl-bench 1.1.1's `CARLDmcWalkerEnv` context features.
//!
//! As dm_control 1.0.50's `walker.py`: a planar biped (torso on two slides and a hinge, two
//! legs of thigh, leg and foot capsules, six motors of gear 100, 50, 20 per leg) on a floor.
//! Observation: `orientations` (the `xx` and `xz` entries of each body's rotation, 14),
//! `height` (the torso's z), `velocity` (`qvel`, 9). Reward: `stand · (5 move + 1) / 6`, where
//! `stand = (3 tolerance(height, (1.2, ∞), margin 0.6) + (1 + torso_zz) / 2) / 4` and
//! `move = tolerance(v, (speed, ∞), margin speed / 2, linear, 0.5 at the margin)` of the
//! horizontal velocity `v` of the whole body's centre of mass (the `torso_subtreelinvel`
//! sensor); `stand` alone for speed 0. Reset: dm_control's `randomize_limited_and_rotational_joints`
//! (the six leg joints uniform over their ranges, the torso's pitch uniform over ±π), at rest.
//! Control step 0.025 s (ten physics steps of 0.0025 s), 1000 steps (25 s), never terminated.
//!
//! Context: the family's 14 physics features ([`crate::mjcf`]); `gravity` is its magnitude
//! (MuJoCo's gravity z = −gravity, as carl-bench writes it).

use std::sync::Arc;

use carl_env::api::{Action, DType, Env, EnvError, Space, StepOutcome, UnknownFeature, check_obs_len, vector_action};
use carl_env::rng::{EnvRng, uniform};
use carl_pixels::canvas::{Canvas, Stroke};
use carl_pixels::color::Color;

use crate::mjcf::{Common, Desc, build, substeps};
use crate::physics::{Physics, observation_space, observe_f64_into, observe_into};
use crate::rewards::{DEFAULT_VALUE_AT_MARGIN, Sigmoid, tolerance};

const ID: &str = "dmc_walker";
const MODEL: &str = include_str!("../models/walker.json");
/// dm_control's control step.
pub const CONTROL_STEP: f64 = 0.025;
const STAND_HEIGHT: f64 = 1.2;
/// dm_control's `walk` speed (m/s); `run` is 8, `stand` 0.
pub const WALK_SPEED: f64 = 1.0;
const OBS: usize = 24;
/// A step whose speeds exceed this is rolled back and ends the episode (a diverged simulation).
const MAX_SPEED: f64 = 1e3;

/// The context: the family's 14 physics features.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Params {
    pub common: Common,
}

impl Default for Params {
    /// dm_control's values (carl-bench's defaults, but `joint_stiffness` 1: a multiplier).
    fn default() -> Params {
        Params {
            common: Common::dm_control(0.0025),
        }
    }
}

impl Params {
    pub fn set(&mut self, name: &str, value: f64) -> Result<(), UnknownFeature> {
        *self.common.slot(name).ok_or_else(|| UnknownFeature {
            env: ID,
            name: name.to_string(),
            known: "carl-bench's CARLDmcWalkerEnv features".into(),
        })? = value;
        Ok(())
    }
    pub fn get(&self, name: &str) -> Option<f64> {
        let mut p = *self;
        p.common.slot(name).map(|x| *x)
    }
}

/// One instance.
#[derive(Debug, Clone)]
pub struct Walker {
    move_speed: f64,
    physics: Physics,
    torso: usize,
    rng: EnvRng,
    /// Capsules to draw: (geom, half-length, radius).
    capsules: Arc<Vec<(usize, f64, f64)>>,
    /// What dm_control's reset draws: (qpos address, range, or `None` for the unlimited hinge).
    random_joints: Arc<Vec<(usize, Option<[f64; 2]>)>>,
}

impl Walker {
    /// The environment under `params` for the task of `move_speed` (0: stand, 1: walk, 8: run).
    pub fn new(params: Params, move_speed: f64) -> Result<Walker, String> {
        let desc = Desc::parse(MODEL)?;
        let torso = desc.body("torso").ok_or("the model has no torso")?;
        let c = &params.common;
        let model = build(&desc, &c.physics(CONTROL_STEP, [0.0, 0.0, -c.gravity]))?;
        let capsules = model
            .geoms
            .iter()
            .enumerate()
            .filter_map(|(g, geom)| match geom.shape {
                carl_articulated::Shape::Capsule { radius, half_length } => Some((g, half_length, radius)),
                _ => None,
            })
            .collect();
        // dm_control's randomize_limited_and_rotational_joints: limited hinges and slides
        // uniform over their ranges, unlimited hinges over ±π, joint by joint.
        let random_joints = model
            .joints
            .iter()
            .enumerate()
            .filter(|(_, j)| j.range.is_some() || j.kind == carl_articulated::JointKind::Hinge)
            .map(|(i, j)| (model.jnt_qposadr[i], j.range))
            .collect();
        let physics = Physics::new(
            ID,
            Arc::new(model),
            substeps(CONTROL_STEP, c.timestep).0,
            Some(MAX_SPEED),
        );
        Ok(Walker {
            move_speed,
            physics,
            torso,
            rng: EnvRng::from_seed(carl_env::rng::DEFAULT_SEED),
            capsules: Arc::new(capsules),
            random_joints: Arc::new(random_joints),
        })
    }

    fn torso_height(&self) -> f64 {
        self.physics.data.xpos[self.torso][2]
    }

    /// The x velocity of the whole body's centre of mass (MuJoCo's `subtreelinvel` of the
    /// torso, the root of every moving body).
    fn horizontal_velocity(&self) -> f64 {
        let d = &self.physics.data;
        let m = d.model();
        let (mut p, mut mass) = (0.0, 0.0);
        for b in 1..m.bodies.len() {
            let c = d.xipos[b];
            let (w, v0) = carl_articulated::math::split(&d.cvel[b]);
            let v = carl_articulated::math::add(v0, carl_articulated::math::cross(w, c));
            p += m.bodies[b].mass * v[0];
            mass += m.bodies[b].mass;
        }
        if mass > 0.0 { p / mass } else { 0.0 }
    }

    fn reward(&self) -> f64 {
        let standing = tolerance(
            self.torso_height(),
            (STAND_HEIGHT, f64::INFINITY),
            STAND_HEIGHT / 2.0,
            Sigmoid::Gaussian,
            DEFAULT_VALUE_AT_MARGIN,
        );
        let upright = (1.0 + self.physics.data.xmat[self.torso][2][2]) / 2.0;
        let stand = (3.0 * standing + upright) / 4.0;
        if self.move_speed == 0.0 {
            return stand;
        }
        let s = self.move_speed;
        let mv = tolerance(
            self.horizontal_velocity(),
            (s, f64::INFINITY),
            s / 2.0,
            Sigmoid::Linear,
            0.5,
        );
        stand * (5.0 * mv + 1.0) / 6.0
    }

    fn obs_f64(&self, o: &mut [f64]) {
        let d = &self.physics.data;
        for b in 1..8 {
            o[2 * (b - 1)] = d.xmat[b][0][0];
            o[2 * (b - 1) + 1] = d.xmat[b][0][2];
        }
        o[14] = self.torso_height();
        o[15..].copy_from_slice(&d.qvel);
    }
}

impl Env for Walker {
    fn id(&self) -> &'static str {
        ID
    }
    fn obs_dim(&self) -> usize {
        OBS
    }
    fn state_dim(&self) -> usize {
        self.physics.state_dim(0)
    }
    fn observation_space(&self) -> Space {
        observation_space(OBS)
    }
    fn action_space(&self) -> Space {
        Space::Box {
            low: vec![-1.0; 6],
            high: vec![1.0; 6],
            shape: vec![6],
            dtype: DType::Float32,
        }
    }

    fn reset_into(&mut self, seed: Option<u64>, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(ID, obs, OBS)?;
        if let Some(seed) = seed {
            self.rng = EnvRng::from_seed(seed);
        }
        self.physics.reset();
        let d = &mut self.physics.data;
        for &(qa, range) in self.random_joints.iter() {
            let [lo, hi] = range.unwrap_or([-std::f64::consts::PI, std::f64::consts::PI]);
            d.qpos[qa] = uniform(&mut self.rng, lo, hi);
        }
        d.update_kinematics();
        self.physics.start();
        observe_into(ID, OBS, obs, |o| self.obs_f64(o))
    }

    fn step_into(&mut self, action: &Action, obs: &mut [f32]) -> Result<StepOutcome, EnvError> {
        let a = vector_action(ID, action, 6)?;
        check_obs_len(ID, obs, OBS)?;
        // A diverged step is rolled back; the poses are the state's either way.
        let diverged = self.physics.step(a, None)?;
        self.physics.data.update_kinematics();
        let reward = self.reward();
        observe_into(ID, OBS, obs, |o| self.obs_f64(o))?;
        Ok(StepOutcome {
            reward,
            terminated: diverged,
            truncated: false,
        })
    }

    fn observe_into(&self, obs: &mut [f32]) -> Result<(), EnvError> {
        observe_into(ID, OBS, obs, |o| self.obs_f64(o))
    }

    fn observe_f64_into(&self, obs: &mut [f64]) -> Result<(), EnvError> {
        observe_f64_into(ID, OBS, obs, |o| self.obs_f64(o))
    }

    /// `qpos` (9), `qvel` (9).
    fn state(&self) -> Vec<f64> {
        self.physics.state(&[])
    }

    fn set_state(&mut self, state: &[f64]) -> Result<(), EnvError> {
        self.physics.set_state(state, &mut [])?;
        self.physics.data.update_kinematics();
        Ok(())
    }

    fn render(&self) -> Option<carl_pixels::Frame> {
        Some(self.draw())
    }
}

impl carl_env::Runtime for Walker {}

impl Walker {
    /// Side view (x right, z up) following the torso: the floor and every capsule.
    fn draw(&self) -> carl_pixels::Frame {
        const W: u32 = 320;
        const H: u32 = 240;
        let scale = 90.0;
        let cx = self.physics.data.xpos[self.torso][0];
        let px = |x: f64, z: f64| (f64::from(W) / 2.0 + (x - cx) * scale, f64::from(H) - 20.0 - z * scale);
        let mut c = Canvas::new(W, H, Color(40, 48, 64));
        let (_, fy) = px(0.0, 0.0);
        c.fill_rect(0.0, fy, f64::from(W), f64::from(H) - fy, Color(70, 90, 120), 1.0);
        let tick = Stroke::solid(Color(95, 115, 145), 1.0);
        let first = (cx - 2.0).floor() as i64;
        for k in first..first + 5 {
            let (x, y) = px(k as f64, 0.0);
            c.line((x, y), (x, f64::from(H)), tick);
        }
        for &(g, half, r) in self.capsules.iter() {
            let p = self.physics.data.geom_xpos[g];
            let m = &self.physics.data.geom_xmat[g];
            let axis = [m[0][2], m[1][2], m[2][2]];
            let a = px(p[0] - half * axis[0], p[2] - half * axis[2]);
            let b = px(p[0] + half * axis[0], p[2] + half * axis[2]);
            c.line(a, b, Stroke::solid(Color(230, 200, 90), 2.0 * r * scale));
        }
        carl_pixels::Frame::from_canvas(&c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// dm_control's reset: leg joints within their ranges, the torso pitched anywhere, at rest;
    /// the walker falls and rests on the floor (torso below its standing height).
    #[test]
    fn resets_and_falls() {
        let mut e = Walker::new(Params::default(), WALK_SPEED).unwrap();
        for seed in 0..5 {
            e.reset(Some(seed));
            let s = e.state();
            assert!(s[2].abs() <= std::f64::consts::PI && s[9..].iter().all(|v| *v == 0.0));
            for _ in 0..200 {
                e.step(&Action::Continuous(vec![0.0; 6])).unwrap();
            }
            assert!(e.torso_height() < 1.0 && e.torso_height() > 0.0, "{}", e.torso_height());
        }
    }
}
