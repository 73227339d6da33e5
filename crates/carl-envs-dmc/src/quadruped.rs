//! `dmc_quadruped`: dm_control's `quadruped` domain (task `walk`; `run` through the
//! `move_speed` option) with carl-bench 1.1.1's `CARLDmcQuadrupedEnv` context features.
//!
//! As dm_control 1.0.50's `quadruped.py` with `make_model(floor_size, terrain=False,
//! rangefinders=False, walls_and_ball=False)`: an ellipsoid torso on a free joint, four legs of
//! hip (yaw and pitch hinges), knee and ankle hinges and a toe sphere, each leg's pitch, knee
//! and ankle coupled by a tendon equality; twelve servo actuators (`general`, gain 1000, bias
//! `−1000 · length`, a 0.1 s filter on the control: an activation state) on the yaw joints and
//! the `lift` and `extend` tendons. Observation (78): `egocentric_state` (the 16 hinges'
//! positions and velocities and the 12 activations), `torso_velocity` (the torso's
//! velocimeter), `torso_upright` (the torso's `zz`), `imu` (accelerometer then gyro at the
//! torso), `force_torque` (`arcsinh` of the four toes' force then torque sensors). As in
//! dm_control, the position and velocity sensors read the state after the step and the
//! acceleration sensors (accelerometer, force, torque) the last physics step's forward pass
//! (MuJoCo's `mj_step` computes them before it integrates). Reward: `upright · move`,
//! `upright = tolerance(zz, (1, ∞), margin 2, linear, 0)`, `move = tolerance(vₓ, (speed, ∞),
//! margin speed, linear, 0.5)` of the torso's forward velocity (its velocimeter's x). Reset:
//! dm_control's — the joints at zero, a uniformly random orientation (a normalized 4-vector of
//! standard normals), the torso raised from the floor in 1 cm steps until nothing touches,
//! at rest. Control step 0.02 s (four physics steps of 0.005 s), 1000 steps (20 s), never
//! terminated.
//!
//! Context: the family's 14 physics features ([`crate::mjcf`]); `gravity` is its magnitude.

use std::sync::Arc;

use carl_articulated::{Data, Site};
use carl_env::api::{Action, DType, Env, EnvError, Space, StepOutcome, UnknownFeature, check_obs_len, vector_action};
use carl_env::rng::{EnvRng, normal};
use carl_pixels::canvas::{Canvas, Stroke};
use carl_pixels::color::Color;

use crate::mjcf::{Common, Desc, build, substeps};
use crate::physics::{Physics, observation_space, observe_f64_into, observe_into};
use crate::rewards::{Sigmoid, tolerance};

const ID: &str = "dmc_quadruped";
const MODEL: &str = include_str!("../models/quadruped.json");
/// dm_control's control step.
pub const CONTROL_STEP: f64 = 0.02;
/// dm_control's `walk` speed (m/s); `run` is [`RUN_SPEED`].
pub const WALK_SPEED: f64 = 0.5;
pub const RUN_SPEED: f64 = 5.0;
const NU: usize = 12;
const OBS: usize = 78;
/// A step whose speeds exceed this is rolled back and ends the episode (a diverged simulation).
const MAX_SPEED: f64 = 1e3;
/// dm_control's `_find_non_contacting_height` gives up after this many 1 cm raises.
const MAX_RAISES: usize = 10_000;
const TOES: [&str; 4] = ["toe_front_left", "toe_front_right", "toe_back_right", "toe_back_left"];

/// The context: the family's 14 physics features.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Params {
    pub common: Common,
}

impl Default for Params {
    /// dm_control's values (carl-bench's defaults, but `joint_stiffness` 1: a multiplier).
    fn default() -> Params {
        Params {
            common: Common::dm_control(0.005),
        }
    }
}

impl Params {
    pub fn set(&mut self, name: &str, value: f64) -> Result<(), UnknownFeature> {
        *self.common.slot(name).ok_or_else(|| UnknownFeature {
            env: ID,
            name: name.to_string(),
            known: "carl-bench's CARLDmcQuadrupedEnv features".into(),
        })? = value;
        Ok(())
    }
    pub fn get(&self, name: &str) -> Option<f64> {
        let mut p = *self;
        p.common.slot(name).map(|x| *x)
    }
}

/// What the model's layout gives the observation and reset.
#[derive(Debug)]
struct Layout {
    torso: usize,
    /// qpos and qvel addresses of the hinges, in joint order.
    hinges: Vec<(usize, usize)>,
    torso_site: Site,
    toe_sites: [Site; 4],
    /// Geoms to draw: (geom, kind) for the torso ellipsoid, capsules and spheres.
    draw: Vec<usize>,
}

/// One instance.
#[derive(Debug, Clone)]
pub struct Quadruped {
    move_speed: f64,
    physics: Physics,
    layout: Arc<Layout>,
    /// The acceleration sensors of the last forward pass: accelerometer, then the toes' forces
    /// and torques (MuJoCo's sensordata order).
    acc_sensors: [f64; 27],
    rng: EnvRng,
}

impl Quadruped {
    /// The environment under `params` for the task of `move_speed` (0.5: walk, 5: run).
    pub fn new(params: Params, move_speed: f64) -> Result<Quadruped, String> {
        if !(move_speed.is_finite() && move_speed > 0.0) {
            return Err(format!("move_speed must be finite and positive, got {move_speed}"));
        }
        let desc = Desc::parse(MODEL)?;
        let torso = desc.body("torso").ok_or("the model has no torso")?;
        let c = &params.common;
        let model = build(&desc, &c.physics(CONTROL_STEP, [0.0, 0.0, -c.gravity]))?;
        if model.actuators.len() != NU || model.na != NU {
            return Err(format!(
                "the model has {} actuators and {} activations, not {NU}",
                model.actuators.len(),
                model.na
            ));
        }
        let hinges = model
            .joints
            .iter()
            .enumerate()
            .filter(|(_, j)| j.kind == carl_articulated::JointKind::Hinge)
            .map(|(i, _)| (model.jnt_qposadr[i], model.jnt_dofadr[i]))
            .collect::<Vec<_>>();
        if hinges.len() != 16 {
            return Err(format!("the model has {} hinges, not 16", hinges.len()));
        }
        let site = |n: &str| desc.site(n).ok_or_else(|| format!("the model has no site {n}"));
        let toe_sites = [site(TOES[0])?, site(TOES[1])?, site(TOES[2])?, site(TOES[3])?];
        let draw = model
            .geoms
            .iter()
            .enumerate()
            .filter(|(_, g)| g.body != 0)
            .map(|(i, _)| i)
            .collect();
        let layout = Layout {
            torso,
            hinges,
            torso_site: site("torso")?,
            toe_sites,
            draw,
        };
        let physics = Physics::new(
            ID,
            Arc::new(model),
            substeps(CONTROL_STEP, c.timestep).0,
            Some(MAX_SPEED),
        );
        Ok(Quadruped {
            move_speed,
            physics,
            layout: Arc::new(layout),
            acc_sensors: [0.0; 27],
            rng: EnvRng::from_seed(carl_env::rng::DEFAULT_SEED),
        })
    }

    /// The engine's state (for tests and comparisons).
    pub fn data(&self) -> &Data {
        &self.physics.data
    }

    /// The torso's `zz`: 1 upright, −1 upside down.
    pub fn upright(&self) -> f64 {
        self.physics.data.xmat[self.layout.torso][2][2]
    }

    /// The torso's velocimeter (its linear velocity in its frame).
    pub fn torso_velocity(&self) -> [f64; 3] {
        self.physics.data.velocimeter(&self.layout.torso_site)
    }

    fn read_acc_sensors(l: &Layout, d: &Data) -> [f64; 27] {
        let mut s = [0.0; 27];
        s[..3].copy_from_slice(&d.accelerometer(&l.torso_site));
        for (k, site) in l.toe_sites.iter().enumerate() {
            s[3 + 3 * k..6 + 3 * k].copy_from_slice(&d.force_sensor(site));
            s[15 + 3 * k..18 + 3 * k].copy_from_slice(&d.torque_sensor(site));
        }
        s
    }

    fn reward(&self) -> f64 {
        let upright = tolerance(self.upright(), (1.0, f64::INFINITY), 2.0, Sigmoid::Linear, 0.0);
        let s = self.move_speed;
        let mv = tolerance(self.torso_velocity()[0], (s, f64::INFINITY), s, Sigmoid::Linear, 0.5);
        upright * mv
    }

    fn obs_f64(&self, o: &mut [f64]) {
        let d = &self.physics.data;
        let l = &self.layout;
        for (k, &(qa, da)) in l.hinges.iter().enumerate() {
            o[k] = d.qpos[qa];
            o[16 + k] = d.qvel[da];
        }
        for (k, a) in self.activations().iter().enumerate() {
            o[32 + k] = *a;
        }
        o[44..47].copy_from_slice(&self.torso_velocity());
        o[47] = self.upright();
        o[48..51].copy_from_slice(&self.acc_sensors[..3]);
        o[51..54].copy_from_slice(&d.gyro(&l.torso_site));
        for k in 0..24 {
            o[54 + k] = self.acc_sensors[3 + k].asinh();
        }
    }

    /// The actuators' activations (MuJoCo's `act`).
    fn activations(&self) -> [f64; NU] {
        let mut a = [0.0; NU];
        for (x, y) in a.iter_mut().zip(&self.physics.data.act) {
            *x = *y;
        }
        a
    }

    /// The forward pass of the current state and its acceleration sensors (dm_control's
    /// `physics.forward()` after a reset or a set state).
    fn refresh(&mut self) {
        let d = &mut self.physics.data;
        d.forward();
        d.rne_post_constraint();
        self.acc_sensors = Self::read_acc_sensors(&self.layout, d);
    }
}

impl Env for Quadruped {
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
        let m = self.physics.data.model();
        let (low, high) = m
            .actuators
            .iter()
            .map(|a| {
                let [lo, hi] = a.ctrlrange.unwrap_or([-1.0, 1.0]);
                (lo as f32, hi as f32)
            })
            .unzip();
        Space::Box {
            low,
            high,
            shape: vec![NU],
            dtype: DType::Float32,
        }
    }

    fn reset_into(&mut self, seed: Option<u64>, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(ID, obs, OBS)?;
        if let Some(seed) = seed {
            self.rng = EnvRng::from_seed(seed);
        }
        let mut quat = [0.0; 4];
        for q in &mut quat {
            *q = normal(&mut self.rng, 0.0, 1.0);
        }
        let n = quat.iter().map(|x| x * x).sum::<f64>().sqrt();
        let quat = if n > 0.0 {
            quat.map(|x| x / n)
        } else {
            [1.0, 0.0, 0.0, 0.0]
        };
        self.physics.reset();
        let d = &mut self.physics.data;
        d.qpos[3..7].copy_from_slice(&quat);
        // dm_control's _find_non_contacting_height: from the floor up in 1 cm steps.
        let mut found = false;
        for k in 0..MAX_RAISES {
            d.qpos[..3].copy_from_slice(&[0.0, 0.0, 0.01 * k as f64]);
            if d.count_contacts() == 0 {
                found = true;
                break;
            }
        }
        if !found {
            return Err(EnvError::Context {
                env: ID,
                message: "no non-contacting height found for the reset orientation".into(),
            });
        }
        self.refresh();
        self.physics.start();
        observe_into(ID, OBS, obs, |o| self.obs_f64(o))
    }

    fn step_into(&mut self, action: &Action, obs: &mut [f32]) -> Result<StepOutcome, EnvError> {
        let a = vector_action(ID, action, NU)?;
        check_obs_len(ID, obs, OBS)?;
        // The acceleration sensors read the last physics step's forward pass.
        let layout = Arc::clone(&self.layout);
        let mut acc = self.acc_sensors;
        let diverged = self
            .physics
            .step(a, Some(&mut |d: &Data| acc = Self::read_acc_sensors(&layout, d)))?;
        self.acc_sensors = acc;
        if diverged {
            // Rolled back: the sensors of the state before the step (as after a set state).
            self.refresh();
        }
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

    /// `qpos` (23), `qvel` (22), then the actuators' activations (12).
    fn state(&self) -> Vec<f64> {
        self.physics.state(&[])
    }

    fn set_state(&mut self, state: &[f64]) -> Result<(), EnvError> {
        self.physics.set_state(state, &mut [])?;
        self.refresh();
        Ok(())
    }

    fn render(&self) -> Option<carl_pixels::Frame> {
        Some(self.draw())
    }
}

impl carl_env::Runtime for Quadruped {}

impl Quadruped {
    /// An oblique view (x right and away, z up) following the torso: the floor's grid and every
    /// geom of the body (capsules as thick lines, spheres and the torso as discs).
    fn draw(&self) -> carl_pixels::Frame {
        const W: u32 = 320;
        const H: u32 = 240;
        let scale = 150.0;
        let d = &self.physics.data;
        let m = d.model();
        let c = d.xpos[self.layout.torso];
        // Camera: looking along +y rotated 30° about z, tilted down 20°.
        let (yaw, pitch) = (0.5f64, 0.35f64);
        let project = |p: [f64; 3]| {
            let (x, y, z) = (p[0] - c[0], p[1] - c[1], p[2]);
            let u = x * yaw.cos() - y * yaw.sin();
            let depth = x * yaw.sin() + y * yaw.cos();
            let v = z * pitch.cos() + depth * pitch.sin();
            ((f64::from(W) / 2.0 + u * scale, f64::from(H) * 0.7 - v * scale), depth)
        };
        let mut canvas = Canvas::new(W, H, Color(40, 48, 64));
        let grid = Stroke::solid(Color(80, 100, 130), 1.0);
        let (gx, gy) = (c[0].floor(), c[1].floor());
        for k in -3..=3 {
            let k = f64::from(k);
            canvas.line(
                project([gx + k, gy - 3.0, 0.0]).0,
                project([gx + k, gy + 3.0, 0.0]).0,
                grid,
            );
            canvas.line(
                project([gx - 3.0, gy + k, 0.0]).0,
                project([gx + 3.0, gy + k, 0.0]).0,
                grid,
            );
        }
        // Far geoms first.
        let mut order: Vec<(f64, usize)> = self
            .layout
            .draw
            .iter()
            .map(|&g| (project(d.geom_xpos[g]).1, g))
            .collect();
        order.sort_by(|a, b| b.0.total_cmp(&a.0));
        for (_, g) in order {
            let p = d.geom_xpos[g];
            let r = &d.geom_xmat[g];
            match m.geoms[g].shape {
                carl_articulated::Shape::Capsule { radius, half_length } => {
                    let axis = [r[0][2], r[1][2], r[2][2]];
                    let a = project([
                        p[0] - half_length * axis[0],
                        p[1] - half_length * axis[1],
                        p[2] - half_length * axis[2],
                    ])
                    .0;
                    let b = project([
                        p[0] + half_length * axis[0],
                        p[1] + half_length * axis[1],
                        p[2] + half_length * axis[2],
                    ])
                    .0;
                    canvas.line(a, b, Stroke::solid(Color(230, 200, 90), 2.0 * radius * scale));
                }
                carl_articulated::Shape::Sphere { radius } => {
                    let (q, _) = project(p);
                    disc(&mut canvas, q, radius * scale, Color(240, 140, 80));
                }
                carl_articulated::Shape::Ellipsoid { radii } => {
                    let (q, _) = project(p);
                    disc(&mut canvas, q, radii[1] * scale, Color(200, 170, 80));
                    let fwd = [r[0][0], r[1][0], r[2][0]];
                    let nose = project([
                        p[0] + radii[0] * fwd[0],
                        p[1] + radii[0] * fwd[1],
                        p[2] + radii[0] * fwd[2],
                    ])
                    .0;
                    canvas.line(q, nose, Stroke::solid(Color(250, 230, 160), 4.0));
                }
                _ => {}
            }
        }
        carl_pixels::Frame::from_canvas(&canvas)
    }
}

/// A filled disc of radius `r` (pixels) centred at `c`.
fn disc(canvas: &mut Canvas, c: (f64, f64), r: f64, color: Color) {
    let pts: Vec<(f64, f64)> = (0..20)
        .map(|k| {
            let t = std::f64::consts::TAU * f64::from(k) / 20.0;
            (c.0 + r * t.cos(), c.1 + r * t.sin())
        })
        .collect();
    canvas.fill_polygon(&pts, color);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A seeded reset replays the same episode whatever came before it (the constraint solver
    /// starts cold: its tendon-equality rows are active at every step).
    #[test]
    fn a_seeded_reset_replays_its_episode_after_another() {
        let mut e = Quadruped::new(Params::default(), WALK_SPEED).unwrap();
        let a = Action::Continuous(vec![0.3; NU]);
        let mut first = Vec::new();
        for _ in 0..2 {
            e.reset(Some(123));
            first.push(e.step(&a).unwrap().obs);
            for _ in 0..5 {
                e.step(&a).unwrap();
            }
        }
        assert_eq!(first[0], first[1]);
    }

    /// dm_control's reset: the joints at zero, at rest, nothing touching the floor; the body
    /// falls onto it and comes to rest.
    #[test]
    fn resets_off_the_floor_and_falls() {
        let mut e = Quadruped::new(Params::default(), WALK_SPEED).unwrap();
        for seed in 0..4 {
            e.reset(Some(seed));
            assert_eq!(e.physics.data.ncon, 0);
            assert!(e.physics.data.qvel.iter().all(|v| *v == 0.0));
            for _ in 0..150 {
                e.step(&Action::Continuous(vec![0.0; NU])).unwrap();
            }
            let z = e.physics.data.xpos[e.layout.torso][2];
            assert!(z > 0.1 && z < 1.0, "torso height {z}");
            assert!(
                e.physics.data.qvel.iter().all(|v| v.abs() < 0.5),
                "{:?}",
                e.physics.data.qvel
            );
        }
    }

    #[test]
    fn bad_move_speed_is_an_error() {
        assert!(Quadruped::new(Params::default(), 0.0).is_err());
        assert!(Quadruped::new(Params::default(), f64::NAN).is_err());
    }
}
