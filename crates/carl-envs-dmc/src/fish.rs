//! `dmc_fish`: dm_control's `fish` domain (task `swim`; `upright` through the `upright` option)
//! with carl-bench 1.1.1's `CARLDmcFishEnv` context features.
//!
//! As dm_control 1.0.50's `fish.py`: a small fish (a 29 g torso on a free joint, a two-segment
//! tail on three hinges, two fins on two hinges each) in a dense medium (MuJoCo's inertia-box
//! fluid model, density 5000) without gravity or constraints, five position servos (`tail`,
//! `tail_twist`, `fins_flap` on the fins' antisymmetric tendon, `finleft_pitch`,
//! `finright_pitch`; controls in [−1, 1]); the fins' symmetric tendon is a spring.
//! Observation (dm_control's flat observation): `joint_angles` (7: tail1, tail_twist, tail2,
//! finright roll and pitch, finleft roll and pitch), `upright` (the torso's `zz`), `target`
//! (target minus mouth in the mouth's frame, 3), `velocity` (`qvel`, 13). Reward `swim`:
//! `(7 in_target + (upright + 1) / 2) / 8`, `in_target = tolerance(|mouth → target|, (0, r),
//! margin 2 r)` with `r` 0.045 (the mouth's and the target's radii); `upright`:
//! `tolerance(upright, (1, 1), margin 1)`. Reset: the torso's orientation a normalized
//! 4-vector of standard normals, the seven joints uniform in ±0.2 rad, at rest at the origin's
//! 0.1 m height, and (swim) the target uniform in x, y ∈ ±0.4, z ∈ [0.1, 0.3] (state). Control
//! step 0.04 s (ten physics steps of 0.004 s), 1000 steps (40 s), never terminated.
//!
//! The `upright` task keeps the same 24 entries (dm_control's upright observation leaves out
//! `target`, entries 8..11, and keeps its target at the XML's place).
//!
//! Context: the family's 14 physics features ([`crate::mjcf`]), fish.xml's values by default.
//! `gravity` acts along −z (MuJoCo's gravity z = −gravity, carl-bench's rule); 0, the default,
//! is dm_control's model (fish.xml disables gravity, so carl-bench's gravity feature does
//! nothing); a non-zero value turns gravity on: MuJoCo's fluid model has no buoyancy, so the
//! fish sinks (positive) or rises (negative) at the terminal speed its drag sets. `joint_stiffness` multiplies tail2's spring and the fins' tendon spring
//! (carl-bench's default 0 removes them; here 1). `friction_*` do nothing (no contacts).

use std::sync::Arc;

use carl_articulated::math::{M3, V3, add, mat_mul, mat_t_vec, mat_vec, norm, quat_to_mat, sub};
use carl_env::api::{Action, DType, Env, EnvError, Space, StepOutcome, UnknownFeature, check_obs_len, vector_action};
use carl_env::rng::{EnvRng, normal, uniform};
use carl_pixels::canvas::{Canvas, Stroke};
use carl_pixels::color::Color;

use crate::mjcf::{Common, Desc, build, substeps};
use crate::physics::{Physics, observation_space, observe_f64_into, observe_into};
use crate::rewards::{DEFAULT_VALUE_AT_MARGIN, Sigmoid, tolerance};

const ID: &str = "dmc_fish";
const MODEL: &str = include_str!("../models/fish.json");
/// dm_control's control step.
pub const CONTROL_STEP: f64 = 0.04;
/// dm_control's physics step (fish.xml's timestep).
pub const TIMESTEP: f64 = 0.004;
/// dm_control's medium density (fish.xml's).
pub const DENSITY: f64 = 5000.0;
const JOINTS: [&str; 7] = [
    "tail1",
    "tail_twist",
    "tail2",
    "finright_roll",
    "finright_pitch",
    "finleft_roll",
    "finleft_pitch",
];
pub const OBS: usize = 24;
const NQ: usize = 14;
const NV: usize = 13;
/// A step whose speeds exceed this is rolled back and ends the episode (a diverged simulation).
const MAX_SPEED: f64 = 1e3;

/// The context: the family's 14 physics features.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Params {
    pub common: Common,
}

impl Default for Params {
    /// dm_control's values: time step 0.004, density 5000, gravity 0 (fish.xml disables it),
    /// `joint_stiffness` 1 (a multiplier; carl-bench's 0 removes the springs).
    fn default() -> Params {
        Params {
            common: Common {
                gravity: 0.0,
                density: DENSITY,
                ..Common::dm_control(TIMESTEP)
            },
        }
    }
}

impl Params {
    pub fn set(&mut self, name: &str, value: f64) -> Result<(), UnknownFeature> {
        *self.common.slot(name).ok_or_else(|| UnknownFeature {
            env: ID,
            name: name.to_string(),
            known: "carl-bench's CARLDmcFishEnv features".into(),
        })? = value;
        Ok(())
    }
    pub fn get(&self, name: &str) -> Option<f64> {
        let mut p = *self;
        p.common.slot(name).map(|x| *x)
    }
}

/// An ellipsoid to draw: body, position and orientation in it, half-sizes.
#[derive(Debug, Clone, Copy)]
struct Shape {
    body: usize,
    pos: V3,
    mat: M3,
    half: V3,
}

/// One instance.
#[derive(Debug, Clone)]
pub struct Fish {
    upright_task: bool,
    physics: Physics,
    torso: usize,
    mouth: usize,
    /// The target's centre (world frame; part of the state).
    target: V3,
    target_home: V3,
    /// The mouth's and the target's radii.
    radii: f64,
    joint_qpos: [usize; 7],
    root_qpos: usize,
    rng: EnvRng,
    shapes: Arc<Vec<Shape>>,
}

impl Fish {
    /// The environment under `params`; `upright` selects dm_control's upright task.
    pub fn new(params: Params, upright: bool) -> Result<Fish, String> {
        let desc = Desc::parse(MODEL)?;
        let c = &params.common;
        if !c.gravity.is_finite() {
            return Err(format!("gravity = {} must be finite", c.gravity));
        }
        let model = build(&desc, &c.physics(CONTROL_STEP, [0.0, 0.0, -c.gravity]))?;
        let torso = model.body_index("torso").ok_or("the model has no torso")?;
        let mouth = model.geom_index("mouth").ok_or("the model has no mouth")?;
        let tg = desc.geom("target").ok_or("the model has no target")?;
        let mg = desc.geom("mouth").ok_or("the model has no mouth")?;
        let radii = desc.geoms[tg].size[0] + desc.geoms[mg].size[0];
        let mut joint_qpos = [0; 7];
        for (q, name) in joint_qpos.iter_mut().zip(JOINTS) {
            let j = model
                .joint_index(name)
                .ok_or_else(|| format!("the model has no joint {name}"))?;
            *q = model.jnt_qposadr[j];
        }
        let root = model.joint_index("root").ok_or("the model has no root")?;
        let root_qpos = model.jnt_qposadr[root];
        if model.nq != NQ || model.nv != NV {
            return Err(format!("fish.json: {} coordinates and {} rates", model.nq, model.nv));
        }
        let shapes = desc
            .geoms
            .iter()
            .filter(|g| g.shape == "ellipsoid")
            .map(|g| Shape {
                body: g.body,
                pos: g.pos,
                mat: quat_to_mat(g.quat),
                half: g.size,
            })
            .collect();
        if model.na != 0 {
            return Err(format!("fish.json: {} activations, not 0", model.na));
        }
        let physics = Physics::new(
            ID,
            Arc::new(model),
            substeps(CONTROL_STEP, c.timestep).0,
            Some(MAX_SPEED),
        );
        let target_home = desc.geoms[tg].pos;
        Ok(Fish {
            upright_task: upright,
            physics,
            torso,
            mouth,
            target: target_home,
            target_home,
            radii,
            joint_qpos,
            root_qpos,
            rng: EnvRng::from_seed(carl_env::rng::DEFAULT_SEED),
            shapes: Arc::new(shapes),
        })
    }

    fn upright(&self) -> f64 {
        self.physics.data.xmat[self.torso][2][2]
    }

    /// The target minus the mouth, in the mouth's frame.
    fn mouth_to_target(&self) -> V3 {
        let d = &self.physics.data;
        mat_t_vec(&d.geom_xmat[self.mouth], sub(self.target, d.geom_xpos[self.mouth]))
    }

    fn reward(&self) -> f64 {
        if self.upright_task {
            return tolerance(
                self.upright(),
                (1.0, 1.0),
                1.0,
                Sigmoid::Gaussian,
                DEFAULT_VALUE_AT_MARGIN,
            );
        }
        let in_target = tolerance(
            norm(self.mouth_to_target()),
            (0.0, self.radii),
            2.0 * self.radii,
            Sigmoid::Gaussian,
            DEFAULT_VALUE_AT_MARGIN,
        );
        (7.0 * in_target + 0.5 * (self.upright() + 1.0)) / 8.0
    }

    fn obs_f64(&self, o: &mut [f64]) {
        let d = &self.physics.data;
        for (x, &q) in o.iter_mut().zip(&self.joint_qpos) {
            *x = d.qpos[q];
        }
        o[7] = self.upright();
        o[8..11].copy_from_slice(&self.mouth_to_target());
        o[11..].copy_from_slice(&d.qvel);
    }
}

impl Env for Fish {
    fn id(&self) -> &'static str {
        ID
    }
    fn obs_dim(&self) -> usize {
        OBS
    }
    fn state_dim(&self) -> usize {
        self.physics.state_dim(3)
    }
    fn observation_space(&self) -> Space {
        observation_space(OBS)
    }
    fn action_space(&self) -> Space {
        Space::Box {
            low: vec![-1.0; 5],
            high: vec![1.0; 5],
            shape: vec![5],
            dtype: DType::Float32,
        }
    }

    fn reset_into(&mut self, seed: Option<u64>, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(ID, obs, OBS)?;
        if let Some(seed) = seed {
            self.rng = EnvRng::from_seed(seed);
        }
        self.physics.reset();
        let rng = &mut self.rng;
        let mut q = [0.0; 4];
        let mut n = 0.0;
        while n == 0.0 {
            q = std::array::from_fn(|_| normal(rng, 0.0, 1.0));
            n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
        }
        let d = &mut self.physics.data;
        for (x, qk) in d.qpos[self.root_qpos + 3..self.root_qpos + 7].iter_mut().zip(q) {
            *x = qk / n;
        }
        for &qa in &self.joint_qpos {
            d.qpos[qa] = uniform(rng, -0.2, 0.2);
        }
        self.target = if self.upright_task {
            self.target_home
        } else {
            [uniform(rng, -0.4, 0.4), uniform(rng, -0.4, 0.4), uniform(rng, 0.1, 0.3)]
        };
        d.update_kinematics();
        self.physics.start();
        observe_into(ID, OBS, obs, |o| self.obs_f64(o))
    }

    fn step_into(&mut self, action: &Action, obs: &mut [f32]) -> Result<StepOutcome, EnvError> {
        let a = vector_action(ID, action, 5)?;
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

    /// `qpos` (14), `qvel` (13), the target's position (3).
    fn state(&self) -> Vec<f64> {
        self.physics.state(&self.target)
    }

    fn set_state(&mut self, state: &[f64]) -> Result<(), EnvError> {
        self.physics.set_state(state, &mut self.target)?;
        self.physics.data.update_kinematics();
        Ok(())
    }

    fn render(&self) -> Option<carl_pixels::Frame> {
        Some(self.draw())
    }
}

impl carl_env::Runtime for Fish {
    /// The given states with the target at the mouth (swim; upright has no goal position).
    fn goal_states(&self, states: &[Vec<f64>]) -> Result<Vec<Vec<f64>>, EnvError> {
        let mut probe = self.clone();
        states
            .iter()
            .map(|s| {
                probe.set_state(s)?;
                let mut g = s.clone();
                g[NQ + NV..].copy_from_slice(&probe.physics.data.geom_xpos[probe.mouth]);
                Ok(g)
            })
            .collect()
    }
}

/// The convex hull (counter-clockwise) of points in the plane.
fn hull(mut p: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    p.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let cross = |o: (f64, f64), a: (f64, f64), b: (f64, f64)| (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0);
    let mut h: Vec<(f64, f64)> = Vec::with_capacity(2 * p.len());
    for pass in 0..2 {
        let start = h.len();
        for &q in &p {
            while h.len() >= start + 2 && cross(h[h.len() - 2], h[h.len() - 1], q) <= 0.0 {
                h.pop();
            }
            h.push(q);
        }
        h.pop();
        if pass == 0 {
            p.reverse();
        }
    }
    h
}

impl Fish {
    /// Top view (x right, y up) of the arena's floor, the target and the fish's ellipsoids
    /// (lower ones first).
    fn draw(&self) -> carl_pixels::Frame {
        const SIZE: u32 = 256;
        let half = 0.55;
        let scale = f64::from(SIZE) / (2.0 * half);
        let px = |p: V3| ((p[0] + half) * scale, (half - p[1]) * scale);
        let mut c = Canvas::new(SIZE, SIZE, Color(30, 50, 80));
        let (x0, y0) = px([-0.5, 0.5, 0.0]);
        c.fill_rect(x0, y0, scale, scale, Color(50, 80, 115), 1.0);
        let grid = Stroke::solid(Color(70, 100, 135), 1.0);
        for k in -5..=5 {
            let t = 0.1 * f64::from(k);
            c.line(px([t, -0.5, 0.0]), px([t, 0.5, 0.0]), grid);
            c.line(px([-0.5, t, 0.0]), px([0.5, t, 0.0]), grid);
        }
        let d = &self.physics.data;
        let outline = |centre: V3, r: &M3, h: V3| {
            let mut pts = Vec::with_capacity(96);
            for i in 0..8 {
                let phi = std::f64::consts::PI * (f64::from(i) + 0.5) / 8.0;
                for k in 0..12 {
                    let th = std::f64::consts::TAU * f64::from(k) / 12.0;
                    let l = [
                        h[0] * th.cos() * phi.sin(),
                        h[1] * th.sin() * phi.sin(),
                        h[2] * phi.cos(),
                    ];
                    pts.push(px(add(centre, mat_vec(r, l))));
                }
            }
            hull(pts)
        };
        let ident = carl_articulated::math::IDENTITY;
        c.fill_polygon(&outline(self.target, &ident, [0.04; 3]), Color(200, 70, 70));
        let mut shapes: Vec<(f64, Vec<(f64, f64)>)> = self
            .shapes
            .iter()
            .map(|s| {
                let centre = add(d.xpos[s.body], mat_vec(&d.xmat[s.body], s.pos));
                let r = mat_mul(&d.xmat[s.body], &s.mat);
                (centre[2], outline(centre, &r, s.half))
            })
            .collect();
        shapes.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (_, pts) in &shapes {
            c.fill_polygon(pts, Color(235, 175, 80));
        }
        let m = d.geom_xpos[self.mouth];
        c.fill_polygon(&outline(m, &ident, [0.006; 3]), Color(240, 240, 240));
        carl_pixels::Frame::from_canvas(&c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// dm_control's reset: a unit root quaternion, joints within ±0.2, the target in its box, at
    /// rest; without control the fish stays near where it started (no gravity).
    #[test]
    fn resets_and_drifts() {
        let mut e = Fish::new(Params::default(), false).unwrap();
        for seed in 0..3 {
            e.reset(Some(seed));
            let s = e.state();
            let qn: f64 = s[3..7].iter().map(|x| x * x).sum();
            assert!((qn - 1.0).abs() < 1e-12);
            assert!(s[7..NQ].iter().all(|x| x.abs() <= 0.2));
            assert!(s[NQ..NQ + NV].iter().all(|v| *v == 0.0));
            assert!(s[NQ + NV + 2] >= 0.1 && s[NQ + NV + 2] <= 0.3);
            for _ in 0..25 {
                e.step(&Action::Continuous(vec![0.0; 5])).unwrap();
            }
            let s = e.state();
            assert!(norm([s[0], s[1], s[2] - 0.1]) < 0.05, "{s:?}");
        }
    }

    /// With gravity the fish sinks (MuJoCo's fluid model has no buoyancy).
    #[test]
    fn sinks_with_gravity() {
        let mut p = Params::default();
        p.set("gravity", 9.81).unwrap();
        let mut e = Fish::new(p, false).unwrap();
        e.reset(Some(0));
        for _ in 0..25 {
            e.step(&Action::Continuous(vec![0.0; 5])).unwrap();
        }
        assert!(e.state()[2] < 0.0, "{:?}", e.state());
    }
}
