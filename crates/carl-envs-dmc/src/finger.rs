//! `dmc_finger`: dm_control's `finger` domain (task `spin`; `turn_easy` and `turn_hard` through
//! the `target_radius` option) with carl-bench 1.1.1's `CARLDmcFingerEnv` context features.
//!
//! As dm_control 1.0.50's `finger.py`: a planar two-link finger (hinges `proximal`, with
//! `ref` −90°, and `distal`, limited to ±110°, damping 2.5, motors of gear 30 and 15) and a
//! spinner of two capsules on a hinge with dry friction (`frictionloss` 0.1), gravity off,
//! MuJoCo's elliptic friction cone. Observation: `position` (the two finger angles and the
//! spinner tip's (x, z) relative to the hinge), `velocity` (the three joint rates), `touch`
//! (`log1p` of the `touchtop` and `touchbottom` sensors: MuJoCo's `touch`, the normal forces of
//! the distal body's contacts whose ray from the contact point along the normal, away from the
//! body, meets the site's ellipsoid: here, contacts inside it); turn adds `target_position` (relative to the hinge) and `dist_to_target` (to the
//! target's surface). Reward: spin `hinge velocity ≤ −15 rad/s`; turn `dist_to_target ≤ 0`.
//! Reset: spin sets the hinge damping to 0.03 (as dm_control's `Spin`); turn draws the target
//! angle uniform over ±π on the circle of radius `spinner_radius + spinner_length/2`; then the
//! finger joints uniform over their ranges and the hinge over ±π, redrawn until no two geoms
//! touch (1000 attempts, as dm_control; the last draw is kept otherwise), at rest.
//! Control step 0.02 s (two physics steps of 0.01 s), 1000 steps (20 s), never terminated.
//!
//! Context: the family's 14 physics features ([`crate::mjcf`]) and the finger's sizes:
//! `limb_length_0` / `limb_length_1` (the proximal and distal capsules; the distal body sits
//! 1 cm below the proximal capsule's end, the fingertip and the touch sites follow the distal
//! one's end), `spinner_radius` (the two capsules' radius, their offsets ±r/2, the decoration's
//! radius r/2) and `spinner_length` (the capsules' length; the tip site 4 cm beyond their end).
//! At the defaults these are dm_control's model exactly. The bodies' masses and inertias are
//! recomputed from the geoms' shapes at density 1000 as MuJoCo's compiler does ([`body_inertia`]).
//! carl-bench regenerates the XML with the fingertip 3 cm beyond the distal capsule instead of
//! on it and the capsules tilted (`fromto` endpoints mixed), so its default model is not
//! dm_control's; here the defaults are. Geometries where the finger cannot reach the spinner
//! (carl-bench's `check_constraints`) are refused with an error naming the sizes.
//!
//! `gravity`: finger.xml disables gravity, so carl-bench's `gravity` is dead. Here it is the
//! magnitude of a gravity pointing down (−z), default 0 (dm_control's model); a positive value
//! turns gravity on.

use std::sync::Arc;

use carl_articulated::math::{M3, V3, add, mat_vec, sub};
use carl_env::api::{Action, DType, Env, EnvError, Space, StepOutcome, UnknownFeature, check_obs_len, vector_action};
use carl_env::rng::{EnvRng, uniform};
use carl_pixels::canvas::{Canvas, Stroke};
use carl_pixels::color::Color;

use crate::mjcf::{Common, Desc, build, substeps};
use crate::physics::{Physics, observation_space, observe_f64_into, observe_into};

const ID: &str = "dmc_finger";
const MODEL: &str = include_str!("../models/finger.json");
/// dm_control's control step (s).
pub const CONTROL_STEP: f64 = 0.02;
/// The spin reward's threshold (rad/s, the hinge turning in −y).
pub const SPIN_VELOCITY: f64 = 15.0;
/// dm_control's `turn_easy` and `turn_hard` target radii (m).
pub const EASY_TARGET: f64 = 0.07;
pub const HARD_TARGET: f64 = 0.03;
/// The hinge damping dm_control's `Spin` task sets.
const SPIN_DAMPING: f64 = 0.03;
/// MuJoCo's default geom density (kg/m³).
const DENSITY: f64 = 1000.0;
/// A step whose speeds exceed this is rolled back and ends the episode (a diverged simulation).
const MAX_SPEED: f64 = 1e3;

/// The finger's sizes (m), carl-bench's names.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sizes {
    pub limb_length_0: f64,
    pub limb_length_1: f64,
    pub spinner_radius: f64,
    pub spinner_length: f64,
}

/// The context: the family's 14 physics features and the finger's sizes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Params {
    pub common: Common,
    pub sizes: Sizes,
}

impl Default for Params {
    /// dm_control's values (carl-bench's defaults, but `joint_stiffness` 1, a multiplier;
    /// `timestep` dm_control's 0.01 where carl-bench says 0.0025; `gravity` 0 as finger.xml).
    fn default() -> Params {
        let mut common = Common::dm_control(0.01);
        common.gravity = 0.0;
        Params {
            common,
            sizes: Sizes {
                limb_length_0: 0.17,
                limb_length_1: 0.16,
                spinner_radius: 0.04,
                spinner_length: 0.18,
            },
        }
    }
}

impl Params {
    fn slot(&mut self, name: &str) -> Option<&mut f64> {
        match name {
            "limb_length_0" => Some(&mut self.sizes.limb_length_0),
            "limb_length_1" => Some(&mut self.sizes.limb_length_1),
            "spinner_radius" => Some(&mut self.sizes.spinner_radius),
            "spinner_length" => Some(&mut self.sizes.spinner_length),
            _ => self.common.slot(name),
        }
    }
    pub fn set(&mut self, name: &str, value: f64) -> Result<(), UnknownFeature> {
        *self.slot(name).ok_or_else(|| UnknownFeature {
            env: ID,
            name: name.to_string(),
            known: "carl-bench's CARLDmcFingerEnv features".into(),
        })? = value;
        Ok(())
    }
    pub fn get(&self, name: &str) -> Option<f64> {
        let mut p = *self;
        p.slot(name).map(|x| *x)
    }
}

/// A site: body, position in the body frame, ellipsoid semi-axes.
#[derive(Debug, Clone, Copy)]
struct Site {
    body: usize,
    pos: V3,
    size: V3,
}

#[derive(Debug, Deserialize)]
struct SiteDesc {
    name: String,
    body: usize,
    size: [f64; 3],
    pos: [f64; 3],
}

#[derive(Debug, Deserialize)]
struct SitesFile {
    model: SitesOnly,
}

#[derive(Debug, Deserialize)]
struct SitesOnly {
    sites: Vec<SiteDesc>,
}

use serde::Deserialize;

/// Mass, centre of mass and inertia tensor about it of a geom of MuJoCo's `shape` ("capsule",
/// "cylinder"; sizes as MuJoCo holds them) at `pos` with rotation `rot`, density `DENSITY`.
fn geom_inertia(shape: &str, size: [f64; 3], pos: V3, rot: &M3) -> Result<(f64, V3, M3), String> {
    let (r, half) = (size[0], size[1]);
    let h = 2.0 * half;
    let pi = std::f64::consts::PI;
    let (m, ixx, izz) = match shape {
        "capsule" => {
            let ms = DENSITY * 4.0 / 3.0 * pi * r * r * r;
            let mc = DENSITY * pi * r * r * h;
            let si = 2.0 * ms * r * r / 5.0;
            (
                ms + mc,
                mc * (3.0 * r * r + h * h) / 12.0 + si + ms * h * (3.0 * r + 2.0 * h) / 8.0,
                mc * r * r / 2.0 + si,
            )
        }
        "cylinder" => {
            let m = DENSITY * pi * r * r * h;
            (m, m * (3.0 * r * r + h * h) / 12.0, m * r * r / 2.0)
        }
        other => return Err(format!("no inertia for a {other} geom")),
    };
    let d = [ixx, ixx, izz];
    let mut t = [[0.0; 3]; 3];
    for a in 0..3 {
        for b in 0..3 {
            t[a][b] = (0..3).map(|k| rot[a][k] * d[k] * rot[b][k]).sum();
        }
    }
    Ok((m, pos, t))
}

/// A body's mass, centre of mass and principal inertia from its geoms, as MuJoCo's compiler
/// sums them (parallel axes about the common centre of mass). The finger's bodies are
/// symmetric about their frames' axes, so the tensor is diagonal there: `None` if it is not.
pub fn body_inertia(parts: &[(f64, V3, M3)]) -> Option<(f64, V3, V3)> {
    let mass: f64 = parts.iter().map(|p| p.0).sum();
    if mass <= 0.0 {
        return None;
    }
    let mut c = [0.0; 3];
    for (m, p, _) in parts {
        for k in 0..3 {
            c[k] += m * p[k] / mass;
        }
    }
    let mut t = [[0.0; 3]; 3];
    for (m, p, i) in parts {
        let d = sub(*p, c);
        let dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        for a in 0..3 {
            for b in 0..3 {
                let delta = if a == b { dd } else { 0.0 };
                t[a][b] += i[a][b] + m * (delta - d[a] * d[b]);
            }
        }
    }
    let off = t[0][1].abs().max(t[0][2].abs()).max(t[1][2].abs());
    let scale = t[0][0].abs().max(t[1][1].abs()).max(t[2][2].abs());
    if off > 1e-12 * scale {
        return None;
    }
    Some((mass, c, [t[0][0], t[1][1], t[2][2]]))
}

fn quat_mat(q: [f64; 4]) -> M3 {
    carl_articulated::math::quat_to_mat(q)
}

/// dm_control's model with the finger's sizes `s`: geoms, sites and bodies' inertias rebuilt.
fn sized_model(s: &Sizes) -> Result<(Desc, Vec<(String, Site)>), String> {
    let finite = [s.limb_length_0, s.limb_length_1, s.spinner_radius, s.spinner_length];
    if finite.iter().any(|x| !(x.is_finite() && *x > 0.0)) {
        return Err(format!("the finger's sizes must be finite and positive: {s:?}"));
    }
    // carl-bench's check_constraints (finger at x = −0.2, spinner at x = 0.2).
    let half = s.spinner_length / 2.0;
    if 0.4 - half < 0.0 {
        return Err(format!(
            "spinner_length {} reaches the finger's hinge (at most 0.8): the spinner cannot spin",
            s.spinner_length
        ));
    }
    let gap = (0.2 - half) - (-0.2 + s.limb_length_0 + s.limb_length_1);
    // (A rounding margin: the bounds' corners, e.g. 0.15 + 0.16 + 0.09, reach exactly.)
    if gap > 1e-12 {
        return Err(format!(
            "the finger cannot reach the spinner ({gap:.4} m short): limb_length_0 + limb_length_1 + spinner_length/2 must be at least 0.4 (here {} + {} + {})",
            s.limb_length_0, s.limb_length_1, half
        ));
    }
    let mut d = Desc::parse(MODEL)?;
    let geom = |d: &Desc, n: &str| d.geom(n).ok_or_else(|| format!("the model has no geom {n}"));
    let (l0, l1, r) = (s.limb_length_0, s.limb_length_1, s.spinner_radius);
    let g = geom(&d, "proximal")?;
    d.geoms[g].size[1] = l0 / 2.0;
    d.geoms[g].pos = [0.0, 0.0, -l0 / 2.0];
    let distal = d.body("distal").ok_or("the model has no distal body")?;
    d.bodies[distal].pos = [0.0, 0.0, -(l0 + 0.01)];
    let g = geom(&d, "distal")?;
    d.geoms[g].size[1] = l1 / 2.0;
    d.geoms[g].pos = [0.0, 0.0, -l1 / 2.0];
    // dm_control's fingertip runs from 3 cm above the distal capsule's end to 1 mm beyond it.
    let g = geom(&d, "fingertip")?;
    d.geoms[g].size[1] = 0.0155;
    d.geoms[g].pos = [0.0, 0.0, -(l1 - 0.0145)];
    for (name, x) in [("cap1", r / 2.0), ("cap2", -r / 2.0)] {
        let g = geom(&d, name)?;
        d.geoms[g].size = [r, half, 0.0];
        d.geoms[g].pos = [x, 0.0, 0.0];
    }
    let g = geom(&d, "spinner_decoration")?;
    d.geoms[g].size[0] = r / 2.0;
    let file: SitesFile = serde_json::from_str(MODEL).map_err(|e| e.to_string())?;
    let mut sites = Vec::new();
    for sd in file.model.sites {
        let mut site = Site {
            body: sd.body,
            pos: sd.pos,
            size: sd.size,
        };
        match sd.name.as_str() {
            "touchtop" | "touchbottom" => site.pos[2] = -(l1 + 0.01),
            "tip" => site.pos[2] = half + 0.04,
            _ => {}
        }
        sites.push((sd.name, site));
    }
    // Masses and inertias of the bodies made of geoms, from density 1000.
    for b in 1..d.bodies.len() {
        let mut parts = Vec::new();
        for gd in d.geoms.iter().filter(|gd| gd.body == b) {
            parts.push(geom_inertia(&gd.shape, gd.size, gd.pos, &quat_mat(gd.quat))?);
        }
        let (mass, ipos, inertia) =
            body_inertia(&parts).ok_or_else(|| format!("body {}: no diagonal inertia", d.names.bodies[b]))?;
        let body = &mut d.bodies[b];
        body.mass = mass;
        body.ipos = ipos;
        body.iquat = [1.0, 0.0, 0.0, 0.0];
        body.inertia = inertia;
    }
    Ok((d, sites))
}

/// The task.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Task {
    Spin,
    /// Turn the spinner's tip into a target of this radius.
    Turn(f64),
}

/// One instance.
#[derive(Debug, Clone)]
pub struct Finger {
    task: Task,
    physics: Physics,
    spinner: usize,
    hinge_dof: usize,
    /// The spinner tip, touchtop, touchbottom sites.
    tip: Site,
    touch: [Site; 2],
    /// The target's centre (world x, z) and radius.
    target: [f64; 2],
    target_radius: f64,
    /// Hinge position (world x, z) and the target circle's radius.
    hinge: [f64; 2],
    circle: f64,
    rng: EnvRng,
    /// Geoms to draw: (geom, half-length, radius) of the capsules.
    capsules: Arc<Vec<(usize, f64, f64)>>,
    /// (qpos address, range) of the joints dm_control's reset draws.
    random_joints: Arc<Vec<(usize, Option<[f64; 2]>)>>,
}

impl Finger {
    /// The environment under `params` for `task`.
    pub fn new(params: Params, task: Task) -> Result<Finger, String> {
        if let Task::Turn(r) = task
            && !(r.is_finite() && r > 0.0)
        {
            return Err(format!("the target radius must be finite and positive, not {r}"));
        }
        let (mut desc, sites) = sized_model(&params.sizes)?;
        let hinge = desc.joint("hinge").ok_or("the model has no hinge")?;
        if task == Task::Spin {
            desc.joints[hinge].damping = SPIN_DAMPING;
        }
        let spinner = desc.body("spinner").ok_or("the model has no spinner")?;
        let c = &params.common;
        if !(c.gravity.is_finite() && c.gravity >= 0.0) {
            return Err(format!("gravity must be a finite magnitude ≥ 0, not {}", c.gravity));
        }
        let model = build(&desc, &c.physics(CONTROL_STEP, [0.0, 0.0, -c.gravity]))?;
        let site = |n: &str| {
            sites
                .iter()
                .find(|(name, _)| name == n)
                .map(|(_, s)| *s)
                .ok_or_else(|| format!("the model has no site {n}"))
        };
        let target_site = site("target")?;
        let capsules = model
            .geoms
            .iter()
            .enumerate()
            .filter_map(|(g, geom)| match geom.shape {
                carl_articulated::Shape::Capsule { radius, half_length } => Some((g, half_length, radius)),
                _ => None,
            })
            .collect();
        let random_joints = model
            .joints
            .iter()
            .enumerate()
            .map(|(i, j)| (model.jnt_qposadr[i], j.range))
            .collect();
        let hinge_dof = model.jnt_dofadr[hinge];
        let anchor = model.bodies[spinner].pos;
        let physics = Physics::new(
            ID,
            Arc::new(model),
            substeps(CONTROL_STEP, c.timestep).0,
            Some(MAX_SPEED),
        );
        let s = &params.sizes;
        Ok(Finger {
            task,
            physics,
            spinner,
            hinge_dof,
            tip: site("tip")?,
            touch: [site("touchtop")?, site("touchbottom")?],
            target: [target_site.pos[0], target_site.pos[2]],
            target_radius: match task {
                Task::Spin => target_site.size[0],
                Task::Turn(r) => r,
            },
            hinge: [anchor[0], anchor[2]],
            circle: s.spinner_radius + s.spinner_length / 2.0,
            rng: EnvRng::from_seed(carl_env::rng::DEFAULT_SEED),
            capsules: Arc::new(capsules),
            random_joints: Arc::new(random_joints),
        })
    }

    fn obs_dim_of(task: Task) -> usize {
        match task {
            Task::Spin => 9,
            Task::Turn(_) => 12,
        }
    }

    fn site_pos(&self, s: &Site) -> V3 {
        add(
            self.physics.data.xpos[s.body],
            mat_vec(&self.physics.data.xmat[s.body], s.pos),
        )
    }

    /// The spinner tip's (x, z) relative to the hinge.
    fn tip_position(&self) -> [f64; 2] {
        let t = self.site_pos(&self.tip);
        let h = self.physics.data.xpos[self.spinner];
        [t[0] - h[0], t[2] - h[2]]
    }

    fn target_position(&self) -> [f64; 2] {
        let h = self.physics.data.xpos[self.spinner];
        [self.target[0] - h[0], self.target[1] - h[2]]
    }

    fn dist_to_target(&self) -> f64 {
        let (t, p) = (self.target_position(), self.tip_position());
        (t[0] - p[0]).hypot(t[1] - p[1]) - self.target_radius
    }

    fn hinge_velocity(&self) -> f64 {
        self.physics.data.qvel[self.hinge_dof]
    }

    /// MuJoCo's `touch` of site `s`: the normal forces of the contacts of its body whose ray
    /// from the contact point along the normal (pointing away from the body) meets the ellipsoid.
    fn touch(&self, s: &Site) -> f64 {
        let d = &self.physics.data;
        let m = d.model();
        let centre = self.site_pos(s);
        let rot = &d.xmat[s.body];
        let mut total = 0.0;
        for (ci, c) in d.contacts().iter().enumerate() {
            let pair = &m.pairs[c.pair];
            let (b1, b2) = (m.geoms[pair.g1].body, m.geoms[pair.g2].body);
            if b1 != s.body && b2 != s.body {
                continue;
            }
            let fnorm = d.contact_normal_force(ci);
            if fnorm <= 0.0 {
                continue;
            }
            // The normal points from geom 1 to geom 2; the ray leaves the site's body towards
            // the other one (MuJoCo flips it when the site's body is geom 2's).
            let sign = if b2 == s.body { -1.0 } else { 1.0 };
            let dir = c.frame[0].map(|x| x * sign);
            if ray_hits_ellipsoid(centre, rot, s.size, c.pos, dir) {
                total += fnorm;
            }
        }
        total
    }

    fn reward(&self) -> f64 {
        let hit = match self.task {
            Task::Spin => self.hinge_velocity() <= -SPIN_VELOCITY,
            Task::Turn(_) => self.dist_to_target() <= 0.0,
        };
        if hit { 1.0 } else { 0.0 }
    }

    fn obs_f64(&self, o: &mut [f64]) {
        let d = &self.physics.data;
        let tip = self.tip_position();
        o[0] = d.qpos[0];
        o[1] = d.qpos[1];
        o[2] = tip[0];
        o[3] = tip[1];
        o[4..7].copy_from_slice(&d.qvel[..3]);
        o[7] = self.touch(&self.touch[0]).ln_1p();
        o[8] = self.touch(&self.touch[1]).ln_1p();
        if let Task::Turn(_) = self.task {
            let t = self.target_position();
            o[9] = t[0];
            o[10] = t[1];
            o[11] = self.dist_to_target();
        }
    }

    /// The state's poses and the last solve's contact forces (the touch sensors'): a set state's
    /// forward pass.
    fn refresh(&mut self) {
        let d = &mut self.physics.data;
        d.forward();
        d.update_kinematics();
    }
}

/// Whether the ray `p + t·dir` (`t ≥ 0`) meets the ellipsoid of semi-axes `size` centred at
/// `centre` with rotation `rot` (MuJoCo's `mju_rayGeom` for an ellipsoid site).
fn ray_hits_ellipsoid(centre: V3, rot: &M3, size: V3, p: V3, dir: V3) -> bool {
    let rel = sub(p, centre);
    // Into the ellipsoid's frame, scaled to the unit sphere.
    let local = |v: V3| [0, 1, 2].map(|k| (rot[0][k] * v[0] + rot[1][k] * v[1] + rot[2][k] * v[2]) / size[k]);
    let (o, u) = (local(rel), local(dir));
    let a = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
    let b = o[0] * u[0] + o[1] * u[1] + o[2] * u[2];
    let c = o[0] * o[0] + o[1] * o[1] + o[2] * o[2] - 1.0;
    if a <= 0.0 {
        return c <= 0.0;
    }
    let disc = b * b - a * c;
    if disc < 0.0 {
        return false;
    }
    // The larger root ≥ 0: the ray meets the surface ahead (or starts inside).
    (-b + disc.sqrt()) / a >= 0.0
}

impl Env for Finger {
    fn id(&self) -> &'static str {
        ID
    }
    fn obs_dim(&self) -> usize {
        Self::obs_dim_of(self.task)
    }
    fn state_dim(&self) -> usize {
        self.physics.state_dim(0)
    }
    fn observation_space(&self) -> Space {
        observation_space(self.obs_dim())
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
        check_obs_len(ID, obs, self.obs_dim())?;
        if let Some(seed) = seed {
            self.rng = EnvRng::from_seed(seed);
        }
        if let Task::Turn(_) = self.task {
            let angle = uniform(&mut self.rng, -std::f64::consts::PI, std::f64::consts::PI);
            self.target = [
                self.hinge[0] + self.circle * angle.sin(),
                self.hinge[1] + self.circle * angle.cos(),
            ];
        }
        for _ in 0..1000 {
            self.physics.reset();
            let d = &mut self.physics.data;
            for &(qa, range) in self.random_joints.iter() {
                let [lo, hi] = range.unwrap_or([-std::f64::consts::PI, std::f64::consts::PI]);
                d.qpos[qa] = uniform(&mut self.rng, lo, hi);
            }
            d.forward();
            if d.ncon == 0 {
                break;
            }
        }
        self.physics.start();
        observe_into(ID, self.obs_dim(), obs, |o| self.obs_f64(o))
    }

    fn step_into(&mut self, action: &Action, obs: &mut [f32]) -> Result<StepOutcome, EnvError> {
        let a = vector_action(ID, action, 2)?;
        check_obs_len(ID, obs, self.obs_dim())?;
        let diverged = self.physics.step(a, None)?;
        if diverged {
            // Rolled back: the forward pass of the state before the step (as after a set state).
            self.refresh();
        }
        // Positions after the step; the touch sensors the forces of the last step's solve (as
        // dm_control reads them after mj_step).
        self.physics.data.update_kinematics();
        let reward = self.reward();
        observe_into(ID, self.obs_dim(), obs, |o| self.obs_f64(o))?;
        Ok(StepOutcome {
            reward,
            terminated: diverged,
            truncated: false,
        })
    }

    fn observe_into(&self, obs: &mut [f32]) -> Result<(), EnvError> {
        observe_into(ID, self.obs_dim(), obs, |o| self.obs_f64(o))
    }

    fn observe_f64_into(&self, obs: &mut [f64]) -> Result<(), EnvError> {
        observe_f64_into(ID, self.obs_dim(), obs, |o| self.obs_f64(o))
    }

    /// `qpos` (proximal, distal, hinge), `qvel` (3).
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

impl carl_env::Runtime for Finger {}

impl Finger {
    /// Front view (x right, z up): the capsules, the spinner's tip and (turn) the target.
    fn draw(&self) -> carl_pixels::Frame {
        const W: u32 = 320;
        const H: u32 = 240;
        let scale = 400.0;
        let px = |x: f64, z: f64| (f64::from(W) / 2.0 + x * scale, f64::from(H) / 2.0 - (z - 0.4) * scale);
        let mut c = Canvas::new(W, H, Color(40, 48, 64));
        if let Task::Turn(_) = self.task {
            let (x, y) = px(self.target[0], self.target[1]);
            c.line(
                (x - 0.01, y),
                (x + 0.01, y),
                Stroke::solid(Color(220, 80, 80), 2.0 * self.target_radius * scale),
            );
        }
        for &(g, half, r) in self.capsules.iter() {
            let p = self.physics.data.geom_xpos[g];
            let m = &self.physics.data.geom_xmat[g];
            let axis = [m[0][2], m[1][2], m[2][2]];
            let a = px(p[0] - half * axis[0], p[2] - half * axis[2]);
            let b = px(p[0] + half * axis[0], p[2] + half * axis[2]);
            c.line(a, b, Stroke::solid(Color(230, 200, 90), 2.0 * r * scale));
        }
        let t = self.site_pos(&self.tip);
        let (x, y) = px(t[0], t[2]);
        c.line(
            (x - 0.01, y),
            (x + 0.01, y),
            Stroke::solid(Color(120, 220, 120), 0.04 * scale),
        );
        carl_pixels::Frame::from_canvas(&c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// At the defaults the rebuilt bodies are MuJoCo's compiled ones (masses, centres and
    /// inertia tensors).
    #[test]
    fn default_sizes_reproduce_mujocos_inertias() {
        let compiled = Desc::parse(MODEL).unwrap();
        let (rebuilt, _) = sized_model(&Params::default().sizes).unwrap();
        for b in 1..compiled.bodies.len() {
            let (x, y) = (&compiled.bodies[b], &rebuilt.bodies[b]);
            assert!((x.mass - y.mass).abs() < 1e-11, "{b}: mass {} vs {}", x.mass, y.mass);
            for k in 0..3 {
                assert!((x.ipos[k] - y.ipos[k]).abs() < 1e-11);
            }
            let (rx, ry) = (quat_mat(x.iquat), quat_mat(y.iquat));
            for a in 0..3 {
                for c in 0..3 {
                    let tx: f64 = (0..3).map(|k| rx[a][k] * x.inertia[k] * rx[c][k]).sum();
                    let ty: f64 = (0..3).map(|k| ry[a][k] * y.inertia[k] * ry[c][k]).sum();
                    assert!((tx - ty).abs() < 1e-12, "{b}: inertia[{a}][{c}] {tx} vs {ty}");
                }
            }
        }
    }

    /// At other sizes the rebuilt bodies are MuJoCo's compiling dm_control's XML with those
    /// sizes (`scripts/dmc_finger_sizes.py`).
    #[test]
    fn other_sizes_match_mujocos_compiler() {
        let text = include_str!("../tests/fixtures/finger_sizes.json");
        let fx: serde_json::Value = serde_json::from_str(text).unwrap();
        let f = |v: &serde_json::Value| v.as_f64().unwrap();
        for case in fx["cases"].as_array().unwrap() {
            let z = &case["sizes"];
            let sizes = Sizes {
                limb_length_0: f(&z["limb_length_0"]),
                limb_length_1: f(&z["limb_length_1"]),
                spinner_radius: f(&z["spinner_radius"]),
                spinner_length: f(&z["spinner_length"]),
            };
            let (d, _) = sized_model(&sizes).unwrap();
            for (name, b) in case["bodies"].as_object().unwrap() {
                let body = &d.bodies[d.body(name).unwrap()];
                assert!((body.mass - f(&b["mass"])).abs() < 1e-12, "{name}: mass");
                for k in 0..3 {
                    assert!((body.ipos[k] - f(&b["ipos"][k])).abs() < 1e-12, "{name}: ipos");
                    for c in 0..3 {
                        let ours = if k == c { body.inertia[k] } else { 0.0 };
                        let theirs = f(&b["inertia"][k][c]);
                        assert!(
                            (ours - theirs).abs() < 1e-12,
                            "{name}: inertia[{k}][{c}] {ours} vs {theirs} at {sizes:?}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn unreachable_spinner_is_an_error() {
        let mut p = Params::default();
        p.sizes.limb_length_0 = 0.05;
        p.sizes.limb_length_1 = 0.05;
        let e = Finger::new(p, Task::Spin).unwrap_err();
        assert!(e.contains("cannot reach"), "{e}");
    }

    /// Reset finds a collision-free pose; driving the finger makes it touch and turn the
    /// spinner.
    #[test]
    fn resets_and_spins() {
        let mut e = Finger::new(Params::default(), Task::Spin).unwrap();
        let mut touched = false;
        let mut spun = 0.0f64;
        for seed in 0..5 {
            e.reset(Some(seed));
            assert_eq!(e.physics.data.ncon, 0);
            for k in 0..200 {
                let u = if (k / 25) % 2 == 0 { 1.0 } else { -1.0 };
                let o = e.step(&Action::Continuous(vec![u, -u])).unwrap();
                touched |= o.obs[7] > 0.0 || o.obs[8] > 0.0;
                spun = spun.max(e.hinge_velocity().abs());
            }
        }
        assert!(touched && spun > 1.0, "touched {touched}, spin {spun}");
    }
}
