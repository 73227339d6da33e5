//! `dmc_point_mass`: dm_control's `point_mass` domain (tasks `easy` and, with the `hard` option,
//! `hard`) with carl-bench 1.1.1's `CARLDmcPointMassEnv` context features.
//!
//! As dm_control 1.0.50's `point_mass.py`: a 0.3 kg ball on two damped slides (x, y, range
//! ±0.29 m, damping 1) driven by two motors (gear 0.1, controls in [−1, 1]) through fixed
//! tendons; `easy`: tendon `t1` is x, `t2` is y; `hard`: each episode both tendons are random
//! unit directions, the second not within `|cos| > 0.9` of the first (dm_control's rejection).
//! Observation: `position` (x, y), `velocity` (ẋ, ẏ). Reward: `near · (small_control + 4) / 5`,
//! `near = tolerance(|mass − target|, (0, 0.015), margin 0.015)` (gaussian, 0.1 at the margin),
//! `small_control` the mean over both controls of `tolerance(u, margin 1, value_at_margin 0,
//! quadratic)`. Control step 0.02 s (dm_control's: one physics step), 1000 steps (20 s), never
//! terminated.
//!
//! Context (carl-bench's names), where each enters:
//! * `mass`: the ball's mass (its inertia scales with it);
//! * `starting_x`, `starting_y`: where the ball starts (its slide coordinates, moved onto the
//!   arena's edge if outside); dm_control draws each uniformly over the slide's range instead,
//!   which the `random_start` option does;
//! * `target_x`, `target_y`: the target's centre (the reward's);
//! * `area_size`: the arena's side: the slides' range is `±(area_size / 2 − 0.01)` (the ball's
//!   radius inside the walls; 0.6 gives dm_control's ±0.29); a target outside it is unreachable;
//! * `timestep`, `joint_damping`, `actuator_strength`, `density`, `viscosity`, `wind_x`,
//!   `wind_y`: as the family's ([`crate::mjcf`]);
//! * `gravity`, the three friction multipliers, `joint_stiffness`, `geom_density`, `wind_z`:
//!   no effect (the ball slides in a horizontal plane, contacts are disabled, no joint has a
//!   spring, the ball's mass is given, the medium's vertical motion drags nothing that moves).

use std::sync::Arc;

use carl_articulated::Model;
use carl_env::api::{Action, DType, Env, EnvError, Space, StepOutcome, UnknownFeature, check_obs_len, vector_action};
use carl_env::rng::{EnvRng, normal, uniform};
use carl_pixels::canvas::{Canvas, Stroke};
use carl_pixels::color::Color;

use crate::mjcf::{Common, Desc, build, substeps};
use crate::physics::{Physics, observation_space, observe_f64_into, observe_into};
use crate::rewards::{DEFAULT_VALUE_AT_MARGIN, Sigmoid, tolerance};

const ID: &str = "dmc_point_mass";
const MODEL: &str = include_str!("../models/point_mass.json");
/// dm_control's control step (its physics step; no substeps).
pub const CONTROL_STEP: f64 = 0.02;
/// The ball's and the target's radii (the XML's geom sizes).
const BALL_RADIUS: f64 = 0.01;
const TARGET_RADIUS: f64 = 0.015;
const OBS: usize = 4;

/// The context: the family's 14 physics features, then PointMass's own, in carl-bench's order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Params {
    pub common: Common,
    pub mass: f64,
    pub starting_x: f64,
    pub starting_y: f64,
    pub target_x: f64,
    pub target_y: f64,
    pub area_size: f64,
}

impl Default for Params {
    /// carl-bench's defaults, except where they are not dm_control's model: `timestep` 0.02
    /// (carl-bench: 0.004) and `density` 0 (carl-bench: 5000), both copied from its Fish, and
    /// `joint_stiffness` 1 (a multiplier; carl-bench's 0). `gravity` is the vertical component.
    fn default() -> Params {
        Params {
            common: Common {
                gravity: -9.81,
                ..Common::dm_control(CONTROL_STEP)
            },
            mass: 0.3,
            starting_x: 0.14,
            starting_y: 0.14,
            target_x: 0.0,
            target_y: 0.0,
            area_size: 0.6,
        }
    }
}

impl Params {
    fn slot(&mut self, name: &str) -> Option<&mut f64> {
        Some(match name {
            "mass" => &mut self.mass,
            "starting_x" => &mut self.starting_x,
            "starting_y" => &mut self.starting_y,
            "target_x" => &mut self.target_x,
            "target_y" => &mut self.target_y,
            "area_size" => &mut self.area_size,
            _ => return self.common.slot(name),
        })
    }
    pub fn set(&mut self, name: &str, value: f64) -> Result<(), UnknownFeature> {
        *self.slot(name).ok_or_else(|| UnknownFeature {
            env: ID,
            name: name.to_string(),
            known: "carl-bench's CARLDmcPointMassEnv features".into(),
        })? = value;
        Ok(())
    }
    pub fn get(&self, name: &str) -> Option<f64> {
        let mut p = *self;
        p.slot(name).map(|x| *x)
    }
    /// The slides' half-range in this arena.
    fn half_range(&self) -> f64 {
        self.area_size / 2.0 - BALL_RADIUS
    }
}

/// The episode's task variant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Variant {
    /// dm_control's `hard`: random actuation directions each episode.
    pub hard: bool,
    /// dm_control's reset: each slide uniform over its range (else at `starting_x/y`).
    pub random_start: bool,
}

/// One instance.
#[derive(Debug, Clone)]
pub struct PointMass {
    params: Params,
    variant: Variant,
    desc: Arc<Desc>,
    physics: Physics,
    rng: EnvRng,
}

impl PointMass {
    /// The environment under `params`, or why the context cannot be built.
    pub fn new(params: Params, variant: Variant) -> Result<PointMass, String> {
        let desc = Desc::parse(MODEL)?;
        let r = params.half_range();
        if r.is_nan() || r <= 0.0 {
            return Err(format!(
                "area_size = {} leaves the ball no room (it needs more than twice the ball's radius, {})",
                params.area_size,
                2.0 * BALL_RADIUS
            ));
        }
        if params.mass.is_nan() || params.mass <= 0.0 {
            return Err(format!("mass = {} must be positive", params.mass));
        }
        let desc = Arc::new(desc);
        let (n, _) = substeps(CONTROL_STEP, params.common.timestep);
        let model = Self::model(&desc, &params, None)?;
        // No divergence check (the ball's slides are limited and damped; dmc_point_mass never
        // had one).
        let physics = Physics::new(ID, Arc::new(model), n, None);
        Ok(PointMass {
            params,
            variant,
            desc,
            physics,
            rng: EnvRng::from_seed(carl_env::rng::DEFAULT_SEED),
        })
    }

    /// The engine model, with the tendons' directions of the `hard` task when given.
    fn model(desc: &Desc, p: &Params, dirs: Option<[[f64; 2]; 2]>) -> Result<Model, String> {
        let mut d = desc.clone();
        let ball = d.body("pointmass").ok_or("the model has no pointmass body")?;
        let b = &mut d.bodies[ball];
        let k = p.mass / b.mass;
        b.mass = p.mass;
        b.inertia = b.inertia.map(|i| i * k);
        let r = p.half_range();
        for j in &mut d.joints {
            j.range = Some([-r, r]);
        }
        if let Some(dirs) = dirs {
            for (t, dir) in d.tendons.iter_mut().zip(dirs) {
                for ((_, coef), c) in t.iter_mut().zip(dir) {
                    *coef = c;
                }
            }
        }
        // The vertical component (carl-bench writes −gravity, pointing its default up); the
        // ball moves in the horizontal plane, so it does nothing either way.
        let physics = p.common.physics(CONTROL_STEP, [0.0, 0.0, p.common.gravity]);
        build(&d, &physics)
    }

    pub fn params(&self) -> &Params {
        &self.params
    }

    /// dm_control's `hard` directions: two random unit vectors, redrawn while `|cos| > 0.9`.
    fn random_directions(&mut self) -> [[f64; 2]; 2] {
        let unit = |rng: &mut EnvRng| loop {
            let v = [normal(rng, 0.0, 1.0), normal(rng, 0.0, 1.0)];
            let n = v[0].hypot(v[1]);
            if n > 0.0 {
                return [v[0] / n, v[1] / n];
            }
        };
        let d1 = unit(&mut self.rng);
        loop {
            let d2 = unit(&mut self.rng);
            if (d1[0] * d2[0] + d1[1] * d2[1]).abs() <= 0.9 {
                return [d1, d2];
            }
        }
    }

    fn mass_to_target(&self) -> f64 {
        let (x, y) = (self.physics.data.qpos[0], self.physics.data.qpos[1]);
        (x - self.params.target_x).hypot(y - self.params.target_y)
    }

    fn obs_f64(&self, o: &mut [f64]) {
        let d = &self.physics.data;
        o.copy_from_slice(&[d.qpos[0], d.qpos[1], d.qvel[0], d.qvel[1]]);
    }
}

/// dm_control's reward for the distance to the target and the controls.
pub fn reward(dist: f64, ctrl: &[f64]) -> f64 {
    let near = tolerance(
        dist,
        (0.0, TARGET_RADIUS),
        TARGET_RADIUS,
        Sigmoid::Gaussian,
        DEFAULT_VALUE_AT_MARGIN,
    );
    let control: f64 = ctrl
        .iter()
        .map(|&u| tolerance(u, (0.0, 0.0), 1.0, Sigmoid::Quadratic, 0.0))
        .sum::<f64>()
        / ctrl.len() as f64;
    near * (control + 4.0) / 5.0
}

impl Env for PointMass {
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
            low: vec![-1.0; 2],
            high: vec![1.0; 2],
            shape: vec![2],
            dtype: DType::Float32,
        }
    }

    fn reset_into(&mut self, seed: Option<u64>, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(ID, obs, OBS)?;
        if let Some(seed) = seed {
            self.rng = EnvRng::from_seed(seed);
        }
        if self.variant.hard {
            let dirs = self.random_directions();
            let model = Self::model(&self.desc, &self.params, Some(dirs))
                .map_err(|message| EnvError::Context { env: ID, message })?;
            self.physics.replace_model(Arc::new(model));
        }
        self.physics.reset();
        let d = &mut self.physics.data;
        if self.variant.random_start {
            let r = self.params.half_range();
            d.qpos[0] = uniform(&mut self.rng, -r, r);
            d.qpos[1] = uniform(&mut self.rng, -r, r);
        } else {
            // A start outside a small arena is moved onto its edge.
            let r = self.params.half_range();
            d.qpos[0] = self.params.starting_x.clamp(-r, r);
            d.qpos[1] = self.params.starting_y.clamp(-r, r);
        }
        self.physics.start();
        observe_into(ID, OBS, obs, |o| self.obs_f64(o))
    }

    fn step_into(&mut self, action: &Action, obs: &mut [f32]) -> Result<StepOutcome, EnvError> {
        let a = vector_action(ID, action, 2)?;
        check_obs_len(ID, obs, OBS)?;
        self.physics.step(a, None)?;
        let ctrl = [f64::from(a[0]), f64::from(a[1])];
        let reward = reward(self.mass_to_target(), &ctrl);
        observe_into(ID, OBS, obs, |o| self.obs_f64(o))?;
        Ok(StepOutcome {
            reward,
            terminated: false,
            truncated: false,
        })
    }

    fn observe_into(&self, obs: &mut [f32]) -> Result<(), EnvError> {
        observe_into(ID, OBS, obs, |o| self.obs_f64(o))
    }

    fn observe_f64_into(&self, obs: &mut [f64]) -> Result<(), EnvError> {
        observe_f64_into(ID, OBS, obs, |o| self.obs_f64(o))
    }

    /// `qpos` (x, y), `qvel` (ẋ, ẏ).
    fn state(&self) -> Vec<f64> {
        self.physics.state(&[])
    }

    fn set_state(&mut self, state: &[f64]) -> Result<(), EnvError> {
        self.physics.set_state(state, &mut [])?;
        self.physics.data.time = 0.0;
        Ok(())
    }

    fn render(&self) -> Option<carl_pixels::Frame> {
        let d = &self.physics.data;
        Some(render(&self.params, [d.qpos[0], d.qpos[1]]))
    }
}

impl carl_env::Runtime for PointMass {
    /// The given states with the ball on the target (where `target_x/y` decide the reward).
    fn goal_states(&self, states: &[Vec<f64>]) -> Result<Vec<Vec<f64>>, EnvError> {
        Ok(states
            .iter()
            .map(|s| {
                let mut g = s.clone();
                g[0] = self.params.target_x;
                g[1] = self.params.target_y;
                g
            })
            .collect())
    }
}

/// Top view: the arena's floor and walls, the target and the ball.
fn render(p: &Params, ball: [f64; 2]) -> carl_pixels::Frame {
    const SIZE: u32 = 256;
    let half = (p.area_size / 2.0).max(0.05) * 1.1;
    let scale = f64::from(SIZE) / (2.0 * half);
    let px = |x: f64, y: f64| ((x + half) * scale, (half - y) * scale);
    let mut c = Canvas::new(SIZE, SIZE, Color(40, 48, 64));
    let a = p.area_size / 2.0;
    let (x0, y0) = px(-a, a);
    c.fill_rect(x0, y0, 2.0 * a * scale, 2.0 * a * scale, Color(70, 90, 120), 1.0);
    let grid = Stroke::solid(Color(95, 115, 145), 1.0);
    for k in -5..=5 {
        let t = a * f64::from(k) / 5.0;
        c.line(px(t, -a), px(t, a), grid);
        c.line(px(-a, t), px(a, t), grid);
    }
    let wall = Stroke::solid(Color(200, 170, 120), 3.0);
    c.line(px(-a, -a), px(a, -a), wall);
    c.line(px(a, -a), px(a, a), wall);
    c.line(px(a, a), px(-a, a), wall);
    c.line(px(-a, a), px(-a, -a), wall);
    let disc = |c: &mut Canvas, x: f64, y: f64, r: f64, col: Color| {
        let (cx, cy) = px(x, y);
        let pts: Vec<(f64, f64)> = (0..32)
            .map(|i| {
                let t = f64::from(i) * std::f64::consts::TAU / 32.0;
                (cx + r * scale * t.cos(), cy + r * scale * t.sin())
            })
            .collect();
        c.fill_polygon(&pts, col);
    };
    disc(&mut c, p.target_x, p.target_y, TARGET_RADIUS, Color(200, 70, 70));
    disc(&mut c, ball[0], ball[1], BALL_RADIUS, Color(230, 200, 90));
    carl_pixels::Frame::from_canvas(&c)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// dm_control's easy reset (uniform over ±0.29) and the tendon-driven push: a full control
    /// on x accelerates the ball along x only.
    #[test]
    fn pushes_along_its_tendons() {
        let mut e = PointMass::new(Params::default(), Variant::default()).unwrap();
        e.reset(Some(0));
        e.set_state(&[0.0, 0.0, 0.0, 0.0]).unwrap();
        e.step(&Action::Continuous(vec![1.0, 0.0])).unwrap();
        let s = e.state();
        assert!(s[2] > 0.0 && s[3] == 0.0, "{s:?}");
        let mut r = PointMass::new(
            Params::default(),
            Variant {
                hard: false,
                random_start: true,
            },
        )
        .unwrap();
        for seed in 0..20 {
            r.reset(Some(seed));
            let s = r.state();
            assert!(s[0].abs() <= 0.29 && s[1].abs() <= 0.29);
        }
    }

    #[test]
    fn reward_is_one_at_the_target_without_control() {
        assert_eq!(reward(0.0, &[0.0, 0.0]), 1.0);
        assert!((reward(0.0, &[1.0, 1.0]) - 0.8).abs() < 1e-12);
    }

    #[test]
    fn bad_contexts_are_errors() {
        let p = Params {
            area_size: 0.0,
            ..Params::default()
        };
        assert!(PointMass::new(p, Variant::default()).is_err());
    }
}
