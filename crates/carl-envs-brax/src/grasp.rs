//! Grasp (Brax v0.0.x `grasp`): a claw hand picks up a ball (`Object`) and carries it to a
//! sequence of random targets.
//!
//! As Brax v0.0.9's task (`brax/envs/grasp.py`, the version CARL 2021 wrapped):
//! * action (19, in `[-1, 1]`): the first 16 components command the finger joints' angles,
//!   `lo + (hi − lo)·(a + 1)/2` within each joint's limits (Brax's `angle` actuators, a torque
//!   `actuator_strength·(target − angle)`), in Brax's order (per finger: distal, middle,
//!   proximal x, proximal y); the last 3 a palm goal in `[−10, 10]×[−10, 10]×[3.5, 13.5]`
//!   towards which the palm moves by 15 % of the way per step, at most 0.3 m;
//! * reward `0.1·dt·v_hand·û_object + 0.1·dt/(1 + d_xy(palm, object)) + 0.2·dt·touching +
//!   1.5·dt·v_object·û_target + 5·hit` with `dt` = 0.02 s, `v_hand` the velocity of
//!   `HandThumbProximal`, `û` unit directions (palm → object, object → target), `touching` Brax's
//!   `contacts[3] + contacts[9] + contacts[12] + contacts[15]` (indices of Brax's body list: the
//!   first finger's distal phalanx, two proximal phalanges and the target; only the first can
//!   ever touch anything, so in Brax as here the term counts the first finger's fingertip), `hit`
//!   when the object is within `target_radius` of the target;
//! * a hit target moves to `target_radius + target_distance·U(0,1)` from the origin in a uniform
//!   direction, at height `target_height·U(0,1)`;
//! * reset: Brax's default pose (joint angles at mid-limit, hand lifted to touch z = 0, object on
//!   the ground under the palm) and the target at its config place (0, 0, 1.1) — Brax's random
//!   initial target is commented out, so the first step always scores a hit and draws the first
//!   random target; no termination (the spec's `TimeLimit` ends episodes).
//!
//! Deviations (documented in the spec's `source`):
//! * the palm is not teleported: it rides on three slides whose velocities are set every physics
//!   substep to follow Brax's palm path within the step (a very heavy, velocity-driven palm);
//!   its observed velocity is the real one (Brax's frozen palm reports 0);
//! * Brax's soft joints are exact reduced-coordinate joints (a universal joint is two hinges);
//!   the angle actuators are rapier implicit joint springs (`actuator_strength` N·m/rad);
//! * a contact flag is set when the body's contact impulses within the step exceed
//!   0.00316 N·s (Brax: squared velocity change above 1e-5 with unit masses); as in Brax only the
//!   object and the four distal phalanges can be flagged (ground and palm are static to Brax);
//! * the observation is computed after a hit target has moved (Brax computes it before).
//! * a diverging step (non-finite or faster than the side file's `max_speed`) is rolled back,
//!   terminates with reward 0 and sets `info["diverged"]`.
//!
//! State (54): 19 joint coordinates (3 palm slides, then per finger the two knuckle axes and the
//! two curl hinges, URDF order), their 19 velocities, object position (3), orientation
//! `[w, x, y, z]` (4), linear (3) and angular (3) velocity, target position (3).

use std::sync::Arc;

use rapier3d::prelude::*;

use carl_env::api::{Action, DType, Env, EnvError, Info, Space, StepOutcome, check_obs_len, vector_action};
use carl_env::rng::{EnvRng, uniform};

use super::model::RobotModel;
use super::params::{RobotParams, finite_or};
use super::vec3::{dot, from_vector, norm, sub};
use super::world::{Configuration, RobotWorld};

/// Brax's environment step (s): the time factor of the shaping rewards.
pub const BRAX_DT: f64 = 0.02;
/// Palm goal range: low corner and size (m), Brax's `_min_act`/`_range_act` tail.
pub const PALM_LOW: [f64; 3] = [-10.0, -10.0, 3.5];
pub const PALM_RANGE: [f64; 3] = [20.0, 20.0, 10.0];
/// Fraction of the way to the goal the palm moves per step, and the goal distance beyond which
/// the step is capped (at `PALM_GAIN·PALM_CAP` = 0.3 m).
pub const PALM_GAIN: f64 = 0.15;
pub const PALM_CAP: f64 = 2.0;
/// Object: capsule radius and half segment (Brax: radius 1, length 2.02), mass, inertia.
pub const OBJECT_RADIUS: f64 = 1.0;
pub const OBJECT_HALF_SEGMENT: f64 = 0.01;
pub const OBJECT_MASS: f64 = 1.0;
pub const OBJECT_INERTIA: f64 = 1.0;
/// Brax's default places of object and target (lifted onto the ground by `default_qp`).
pub const OBJECT_START: [f64; 3] = [0.0, 0.0, 1.0];
pub const TARGET_START: [f64; 3] = [0.0, 0.0, 1.1];
/// Reward weights (per unit of `BRAX_DT` for the shaping terms) and the hit bonus.
pub const W_MOVE_TO_OBJECT: f64 = 0.1;
pub const W_CLOSE_TO_OBJECT: f64 = 0.1;
pub const W_TOUCHING: f64 = 0.2;
pub const W_MOVE_TO_TARGET: f64 = 1.5;
pub const HIT_BONUS: f64 = 5.0;
/// Contact impulse (N·s) within a step above which a body counts as touching.
pub const CONTACT_IMPULSE: f64 = 0.003_162_277_7;
/// Reflected inertia (kg) of the palm slides: Brax's palm is frozen (infinite mass).
pub const SLIDE_ARMATURE: f32 = 1.0e4;

/// Brax's body list (the observation's order).
pub const BODIES: [&str; 16] = [
    "Ground",
    "Object",
    "HandThumbProximal",
    "HandThumbDistal",
    "HandThumbMiddle",
    "HandPalm",
    "HandThumbProximalTwo",
    "HandThumbMiddleTwo",
    "HandThumbDistalTwo",
    "HandThumbProximalThree",
    "HandThumbMiddleThree",
    "HandThumbDistalThree",
    "HandThumbProximalFour",
    "HandThumbMiddleFour",
    "HandThumbDistalFour",
    "Target",
];
const OBJECT: usize = 1;
const HAND: usize = 2;
const PALM: usize = 5;
const TARGET: usize = 15;
/// Brax's `touching_object` indices.
pub const TOUCH_INDICES: [usize; 4] = [3, 9, 12, 15];
/// Brax bodies that can collide with the object.
const DISTALS: [usize; 4] = [3, 8, 11, 14];

const NJ: usize = 19;
const NA: usize = 19;
const NF: usize = 16;
const STATE_DIM: usize = 2 * NJ + 16;
const OBS_DIM: usize = 132;

const GROUP_GROUND: Group = Group::GROUP_1;
const GROUP_OBJECT: Group = Group::GROUP_2;
const GROUP_HAND: Group = Group::GROUP_3;

/// Reward terms and diagnostics of the last step.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct GraspInfo {
    pub moving_to_object: f64,
    pub close_to_object: f64,
    pub touching_object: f64,
    pub moving_to_target: f64,
    pub hit: bool,
    pub hits: u64,
    /// Object–target distance after the step (before a hit target moves).
    pub target_distance: f64,
    pub diverged: bool,
}

/// What Brax's grasp reward reads after a physics step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RewardInput {
    pub palm: [f64; 3],
    pub object: [f64; 3],
    pub object_vel: [f64; 3],
    /// Velocity of `HandThumbProximal` (Brax's `hand_idx`).
    pub hand_vel: [f64; 3],
    pub target: [f64; 3],
    /// Contact flags in Brax's body order.
    pub contacts: [bool; 16],
    pub target_radius: f64,
}

/// Brax's grasp reward: returns the terms (with `hit`, `hits` 0) and the total.
pub fn grasp_reward(r: &RewardInput) -> (GraspInfo, f64) {
    let object_rel = sub(r.object, r.palm);
    let object_dist = norm(object_rel);
    let planar = (object_rel[0] * object_rel[0] + object_rel[1] * object_rel[1]).sqrt();
    let object_dir = object_rel.map(|x| x / (1e-6 + object_dist));
    let moving_to_object = W_MOVE_TO_OBJECT * BRAX_DT * dot(r.hand_vel, object_dir);
    let close_to_object = W_CLOSE_TO_OBJECT * BRAX_DT / (1.0 + planar);
    let target_rel = sub(r.target, r.object);
    let target_dist = norm(target_rel);
    let target_dir = target_rel.map(|x| x / (1e-6 + target_dist));
    let moving_to_target = W_MOVE_TO_TARGET * BRAX_DT * dot(r.object_vel, target_dir);
    let touches = TOUCH_INDICES.iter().filter(|&&i| r.contacts[i]).count();
    let touching_object = W_TOUCHING * BRAX_DT * touches as f64;
    let hit = target_dist < r.target_radius;
    let total =
        moving_to_object + close_to_object + touching_object + moving_to_target + if hit { HIT_BONUS } else { 0.0 };
    let info = GraspInfo {
        moving_to_object,
        close_to_object,
        touching_object,
        moving_to_target,
        hit,
        hits: 0,
        target_distance: target_dist,
        diverged: false,
    };
    (info, total)
}

/// The physics of one instance: the hand's world plus the free object.
#[derive(Debug)]
struct Physics {
    world: RobotWorld,
    object: RigidBodyHandle,
    object_collider: ColliderHandle,
}

#[derive(Debug)]
pub struct Grasp {
    model: Arc<RobotModel>,
    params: RobotParams,
    phys: Option<Physics>,
    target: [f64; 3],
    rng: EnvRng,
    info: GraspInfo,
    contacts: [bool; 16],
    /// URDF link index of each Brax body (None: ground, object, target).
    body_link: [Option<usize>; 16],
    /// Joint index (URDF movable-joint order) of each finger actuator, in action order.
    actuator_joint: [usize; NF],
    /// Angle limits (rad) of each finger actuator.
    limits: [[f64; 2]; NF],
    /// Joint indices of the palm slides x, y, z.
    slides: [usize; 3],
    /// Servo stiffness (N·m/rad) of each finger actuator under this context.
    stiffness: [f32; NF],
    /// Default joint coordinates (Brax's `default_qp`).
    home: [f64; NJ],
}

impl Clone for Grasp {
    fn clone(&self) -> Self {
        let mut c = Grasp::new(self.model.clone(), self.params.clone());
        c.rng = self.rng.clone();
        c.info = self.info;
        c.target = self.target;
        c.contacts = self.contacts;
        if self.phys.is_some() {
            c.load(&self.state_vec());
        }
        c
    }
}

fn coord(x: f64) -> f32 {
    finite_or(x, 0.0).clamp(-1e6, 1e6) as f32
}

impl Grasp {
    pub fn new(model: Arc<RobotModel>, params: RobotParams) -> Self {
        let joint = |name: &str| model.joint_names.iter().position(|n| n == name);
        let body_link = BODIES.map(|b| model.link_names.iter().position(|l| l == b));
        let mut actuator_joint = [0usize; NF];
        let mut limits = [[0.0; 2]; NF];
        let strength = params.actuator_strength.map_or(1.0, |s| {
            finite_or(s, model.side.strength_reference) / model.side.strength_reference
        });
        let mut stiffness = [0.0f32; NF];
        for (i, a) in model.side.actuators.iter().take(NF).enumerate() {
            actuator_joint[i] = joint(&a.joint).unwrap_or(0);
            if let Some(j) = model.urdf.joints.iter().find(|j| j.name == a.joint) {
                limits[i] = [j.limit.lower, j.limit.upper];
            }
            stiffness[i] = (a.gear * strength).max(0.0) as f32;
        }
        let slides = ["slide_x", "slide_y", "slide_z"].map(|n| joint(n).unwrap_or(0));
        let mut home = [0.0; NJ];
        home[slides[2]] = model.side.root_height;
        for (i, &j) in actuator_joint.iter().enumerate() {
            home[j] = 0.5 * (limits[i][0] + limits[i][1]);
        }
        Grasp {
            model,
            params,
            phys: None,
            target: TARGET_START,
            rng: EnvRng::from_seed(carl_env::rng::DEFAULT_SEED),
            info: GraspInfo::default(),
            contacts: [false; 16],
            body_link,
            actuator_joint,
            limits,
            slides,
            stiffness,
            home,
        }
    }

    pub fn params(&self) -> &RobotParams {
        &self.params
    }
    pub fn world(&self) -> Option<&RobotWorld> {
        self.phys.as_ref().map(|p| &p.world)
    }
    pub fn last_info(&self) -> GraspInfo {
        self.info
    }
    pub fn target(&self) -> [f64; 3] {
        self.target
    }
    /// Contact flags of the last step, in Brax's body order.
    pub fn contacts(&self) -> [bool; 16] {
        self.contacts
    }
    /// Environment step duration (s).
    pub fn dt(&self) -> f64 {
        self.model.side.timestep * self.model.side.frame_skip as f64
    }
    /// The joint coordinates of Brax's default pose (URDF movable-joint order).
    pub fn home(&self) -> [f64; NJ] {
        self.home
    }
    /// Index into the state of the joint named `name` (URDF movable-joint order).
    pub fn joint_index(&self, name: &str) -> Option<usize> {
        self.model.joint_names.iter().position(|n| n == name)
    }
    /// Joint index of finger actuator `i` (action order) and its angle limits (rad).
    pub fn actuator(&self, i: usize) -> Option<(usize, [f64; 2])> {
        (i < NF).then(|| (self.actuator_joint[i], self.limits[i]))
    }

    /// World position of Brax body `i` (centre of mass), or `None` before the first reset.
    pub fn body_position(&self, i: usize) -> Option<[f64; 3]> {
        let p = self.phys.as_ref()?;
        Some(match i {
            0 => [0.0; 3],
            OBJECT => from_vector(p.world.pw.bodies[p.object].center_of_mass()),
            TARGET => self.target,
            _ => from_vector(p.world.pw.bodies[p.world.links[self.body_link[i]?]].center_of_mass()),
        })
    }

    /// World velocity of Brax body `i`.
    pub fn body_velocity(&self, i: usize) -> Option<[f64; 3]> {
        let p = self.phys.as_ref()?;
        Some(match i {
            0 | TARGET => [0.0; 3],
            OBJECT => from_vector(p.world.pw.bodies[p.object].linvel()),
            _ => from_vector(p.world.pw.bodies[p.world.links[self.body_link[i]?]].linvel()),
        })
    }

    /// Object (ball) position.
    pub fn object_position(&self) -> [f64; 3] {
        self.body_position(OBJECT).unwrap_or([f64::NAN; 3])
    }
    /// Palm position.
    pub fn palm_position(&self) -> [f64; 3] {
        self.body_position(PALM).unwrap_or([f64::NAN; 3])
    }

    /// For the sensitivity audit: each of `states` with the target moved next to the object,
    /// 0.5 m away (inside the default 1.1 m target radius, outside a 0.4 m one).
    pub fn states_near_target(&self, states: &[Vec<f64>]) -> Vec<Vec<f64>> {
        states
            .iter()
            .map(|s| {
                let mut g = s.clone();
                let o = 2 * NJ;
                let t = STATE_DIM - 3;
                g[t] = s[o];
                g[t + 1] = s[o + 1];
                g[t + 2] = s[o + 2] + 0.5;
                g
            })
            .collect()
    }

    fn random_target(&mut self) -> [f64; 3] {
        let d = self.params.target_radius + self.params.target_distance * uniform(&mut self.rng, 0.0, 1.0);
        let ang = std::f64::consts::TAU * uniform(&mut self.rng, 0.0, 1.0);
        let z = self.params.target_height * uniform(&mut self.rng, 0.0, 1.0);
        [d * ang.cos(), d * ang.sin(), z]
    }

    fn state_vec(&self) -> Vec<f64> {
        let mut s = Vec::with_capacity(STATE_DIM);
        match &self.phys {
            Some(p) => {
                let c = p.world.configuration();
                s.extend(&c.joints);
                s.extend(&c.vel);
                let b = &p.world.pw.bodies[p.object];
                let t = b.translation();
                let r = b.rotation();
                s.extend(from_vector(t));
                s.extend([r.w, r.x, r.y, r.z].map(f64::from));
                s.extend(from_vector(b.linvel()));
                s.extend(from_vector(b.angvel()));
            }
            None => {
                s.extend(self.home);
                s.extend([0.0; NJ]);
                s.extend(OBJECT_START);
                s.extend([1.0, 0.0, 0.0, 0.0]);
                s.extend([0.0; 6]);
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
        let mut world = RobotWorld::build(&self.model, &self.params, &q);
        let friction = finite_or(self.params.friction, 0.0).max(0.0) as f32;
        // Contacts as Brax's config: object–ground, object–distal phalanges, object–palm.
        world.pw.colliders[world.ground].set_collision_groups(InteractionGroups::new(
            GROUP_GROUND,
            GROUP_OBJECT,
            InteractionTestMode::And,
        ));
        for (i, l) in self.body_link.iter().enumerate() {
            let Some(l) = *l else { continue };
            let groups = if DISTALS.contains(&i) || i == PALM {
                InteractionGroups::new(GROUP_HAND, GROUP_OBJECT, InteractionTestMode::And)
            } else {
                InteractionGroups::none()
            };
            for &c in &world.link_colliders[l] {
                world.pw.colliders[c].set_collision_groups(groups);
            }
        }
        for (li, cols) in world.link_colliders.iter().enumerate() {
            if self.body_link.contains(&Some(li)) {
                continue;
            }
            for &c in cols {
                world.pw.colliders[c].set_collision_groups(InteractionGroups::none());
            }
        }
        // The palm slides: undamped, with a large reflected inertia (a frozen palm in Brax).
        for &j in &self.slides {
            let dof = world.joint_dof(j);
            world.multibody_mut().armature_mut()[dof] = SLIDE_ARMATURE;
        }
        // The object: a free body; contacts multiply the two friction coefficients (Brax).
        let o = 2 * NJ;
        let mut rot = Rotation::from_xyzw(coord(s[o + 4]), coord(s[o + 5]), coord(s[o + 6]), coord(s[o + 3]));
        let n = rot.length();
        rot = if n.is_finite() && n > 1e-6 {
            rot / n
        } else {
            Rotation::IDENTITY
        };
        let body = RigidBodyBuilder::dynamic()
            .can_sleep(false)
            .linvel(Vector::new(coord(s[o + 7]), coord(s[o + 8]), coord(s[o + 9])))
            .angvel(Vector::new(coord(s[o + 10]), coord(s[o + 11]), coord(s[o + 12])));
        let collider = ColliderBuilder::capsule_y(OBJECT_HALF_SEGMENT as f32, OBJECT_RADIUS as f32)
            .mass_properties(MassProperties::new(
                Vector::ZERO,
                OBJECT_MASS as f32,
                Vector::splat(OBJECT_INERTIA as f32),
            ))
            .friction(friction)
            .friction_combine_rule(CoefficientCombineRule::Multiply)
            .restitution(self.model.side.restitution as f32)
            .collision_groups(InteractionGroups::new(
                GROUP_OBJECT,
                GROUP_GROUND | GROUP_HAND,
                InteractionTestMode::And,
            ));
        let (object, object_collider) = world.pw.insert(body, collider);
        world.pw.bodies[object].set_position(
            Pose::from_parts(Vector::new(coord(s[o]), coord(s[o + 1]), coord(s[o + 2])), rot),
            true,
        );
        self.target.copy_from_slice(&s[STATE_DIM - 3..STATE_DIM]);
        self.phys = Some(Physics {
            world,
            object,
            object_collider,
        });
    }

    fn write_obs(&self, obs: &mut [f32]) {
        let mut pos = [[0.0f64; 3]; 16];
        let mut vel = [[0.0f64; 3]; 16];
        for i in 0..16 {
            pos[i] = self.body_position(i).unwrap_or([0.0; 3]);
            vel[i] = self.body_velocity(i).unwrap_or([0.0; 3]);
        }
        let palm = pos[PALM];
        let inv = self
            .phys
            .as_ref()
            .and_then(|p| self.body_link[PALM].map(|l| p.world.link_pose(l).rotation.inverse()))
            .unwrap_or(Rotation::IDENTITY);
        let local = |v: [f64; 3]| from_vector(inv * Vector::new(v[0] as f32, v[1] as f32, v[2] as f32));
        let pos_local: Vec<[f64; 3]> = pos.iter().map(|p| local(sub(*p, palm))).collect();
        let vel_local: Vec<[f64; 3]> = vel.iter().map(|v| local(*v)).collect();
        let mut out: Vec<f64> = Vec::with_capacity(OBS_DIM);
        let mag_dir = |out: &mut Vec<f64>, v: [f64; 3]| {
            let m = norm(v);
            out.push(m);
            out.extend(v.map(|x| x / (1e-6 + m)));
        };
        mag_dir(&mut out, pos_local[OBJECT]);
        mag_dir(&mut out, pos_local[TARGET]);
        for p in &pos_local {
            out.extend(p);
        }
        for v in &vel_local {
            out.extend(v);
        }
        let hand_to_obj = sub(pos[OBJECT], palm);
        let m = norm(hand_to_obj);
        let hand_vel = vel[HAND];
        out.extend(hand_to_obj);
        out.extend(hand_vel);
        out.push(dot(hand_to_obj.map(|x| x / (1e-6 + m)), hand_vel));
        let obj_to_target = sub(pos[TARGET], pos[OBJECT]);
        let m = norm(obj_to_target);
        let dir = obj_to_target.map(|x| x / (1e-6 + m));
        out.push(m);
        out.extend(dir);
        out.push(dot(dir, vel[OBJECT]));
        out.extend(self.contacts.map(|c| f64::from(u8::from(c))));
        for (o, x) in obs.iter_mut().zip(out) {
            *o = x as f32;
        }
    }

    fn controls<'a>(&self, action: &'a Action) -> Result<&'a [f32], EnvError> {
        vector_action("grasp", action, NA)
    }

    fn is_sane(&self) -> bool {
        let Some(p) = &self.phys else { return true };
        let lim = self.model.side.max_speed as f32;
        let b = &p.world.pw.bodies[p.object];
        p.world.is_sane(self.model.side.max_speed)
            && b.translation().is_finite()
            && b.rotation().is_finite()
            && b.linvel().length() <= lim
            && b.angvel().length() <= lim
    }

    /// Advance the physics by one environment step under `ctrl` (already validated).
    fn advance(&mut self, ctrl: &[f32]) {
        let a = |i: usize| {
            let x = ctrl[i];
            if x.is_nan() { 0.0 } else { f64::from(x.clamp(-1.0, 1.0)) }
        };
        let side = &self.model.side;
        let dt = side.timestep as f32;
        let frames = side.frame_skip;
        let decay = (finite_or(self.params.angular_damping, 0.0) * side.timestep).exp() as f32;
        let palm0 = self.palm_position();
        let goal: [f64; 3] = std::array::from_fn(|k| PALM_LOW[k] + PALM_RANGE[k] * (a(NF + k) + 1.0) / 2.0);
        let delta = sub(goal, palm0);
        let n = norm(delta);
        let scale = if n > PALM_CAP { PALM_CAP / n } else { 1.0 };
        let step: [f64; 3] = delta.map(|d| scale * d * PALM_GAIN);
        let Some(p) = self.phys.as_mut() else { return };
        for i in 0..NF {
            let [lo, hi] = self.limits[i];
            let target = lo + (hi - lo) * (a(i) + 1.0) / 2.0;
            p.world
                .set_joint_spring(self.actuator_joint[i], self.stiffness[i], target as f32);
        }
        let slide_dofs = self.slides.map(|j| p.world.joint_dof(j));
        let palm_link = self.body_link[PALM].unwrap_or(0);
        let mut impulse = [0.0f64; 16];
        for f in 0..frames {
            let frac = (f + 1) as f64 / frames as f64;
            let now = from_vector(p.world.pw.bodies[p.world.links[palm_link]].translation());
            {
                let mut v = p.world.multibody_mut().generalized_velocity_mut();
                for k in 0..3 {
                    let want = palm0[k] + frac * step[k];
                    v[slide_dofs[k]] = ((want - now[k]) / f64::from(dt)) as f32;
                }
            }
            p.world.step(&[]);
            let b = &mut p.world.pw.bodies[p.object];
            let w = b.angvel();
            b.set_angvel(w * decay, false);
            // Contact impulses on the object, by the body it touches.
            for pair in p.world.pw.contact_pairs_with(p.object_collider) {
                let other = if pair.collider1 == p.object_collider {
                    pair.collider2
                } else {
                    pair.collider1
                };
                let j: f64 = pair
                    .solver_manifolds()
                    .iter()
                    .flat_map(|m| m.points.iter())
                    .map(|pt| f64::from(pt.data.impulse.abs()))
                    .sum();
                if j == 0.0 {
                    continue;
                }
                impulse[OBJECT] += j;
                for &d in &DISTALS {
                    if let Some(l) = self.body_link[d]
                        && p.world.link_colliders[l].contains(&other)
                    {
                        impulse[d] += j;
                    }
                }
            }
        }
        self.contacts = impulse.map(|j| j > CONTACT_IMPULSE);
    }
}

impl carl_env::runtime::Runtime for Grasp {
    fn goal_states(&self, states: &[Vec<f64>]) -> Result<Vec<Vec<f64>>, EnvError> {
        Ok(self.states_near_target(states))
    }
}

impl Env for Grasp {
    fn id(&self) -> &'static str {
        "grasp"
    }
    /// Brax's grasp observation (132): see the module docs.
    fn obs_dim(&self) -> usize {
        OBS_DIM
    }
    fn state_dim(&self) -> usize {
        STATE_DIM
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
        Space::Box {
            low: vec![-1.0; NA],
            high: vec![1.0; NA],
            shape: vec![NA],
            dtype: DType::Float32,
        }
    }

    fn reset_into(&mut self, seed: Option<u64>, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len("grasp", obs, OBS_DIM)?;
        if let Some(seed) = seed {
            self.rng = EnvRng::from_seed(seed);
        }
        let mut s = vec![0.0; STATE_DIM];
        s[..NJ].copy_from_slice(&self.home);
        let o = 2 * NJ;
        s[o..o + 3].copy_from_slice(&OBJECT_START);
        s[o + 3] = 1.0;
        s[STATE_DIM - 3..].copy_from_slice(&TARGET_START);
        self.load(&s);
        self.contacts = [false; 16];
        self.info = GraspInfo {
            target_distance: norm(sub(self.target, self.object_position())),
            ..GraspInfo::default()
        };
        self.write_obs(obs);
        Ok(())
    }

    fn step_into(&mut self, action: &Action, obs: &mut [f32]) -> Result<StepOutcome, EnvError> {
        let ctrl = self.controls(action)?;
        check_obs_len("grasp", obs, OBS_DIM)?;
        if self.phys.is_none() {
            return Err(EnvError::NeedsReset { env: "grasp" });
        }
        let before = self.state_vec();
        self.advance(ctrl);
        let diverged = !self.is_sane();
        if diverged {
            self.load(&before);
            self.contacts = [false; 16];
        }
        let input = RewardInput {
            palm: self.palm_position(),
            object: self.object_position(),
            object_vel: self.body_velocity(OBJECT).unwrap_or([0.0; 3]),
            hand_vel: self.body_velocity(HAND).unwrap_or([0.0; 3]),
            target: self.target,
            contacts: self.contacts,
            target_radius: self.params.target_radius,
        };
        let (mut info, reward) = grasp_reward(&input);
        info.hit &= !diverged;
        info.hits = self.info.hits + u64::from(info.hit);
        info.diverged = diverged;
        if info.hit {
            self.target = self.random_target();
        }
        self.info = info;
        self.write_obs(obs);
        Ok(StepOutcome {
            reward: if diverged { 0.0 } else { reward },
            terminated: diverged,
            truncated: false,
        })
    }

    fn observe_into(&self, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len("grasp", obs, OBS_DIM)?;
        self.write_obs(obs);
        Ok(())
    }

    /// Joint coordinates (19), joint velocities (19), object pose (7) and velocity (6), target (3).
    fn state(&self) -> Vec<f64> {
        self.state_vec()
    }

    fn set_state(&mut self, state: &[f64]) -> Result<(), EnvError> {
        carl_env::api::check_state_len("grasp", state, STATE_DIM)?;
        self.load(state);
        self.contacts = [false; 16];
        self.info = GraspInfo::default();
        Ok(())
    }

    fn info(&self) -> Info {
        let i = &self.info;
        let mut m = Info::new();
        m.insert("moving_to_object".into(), i.moving_to_object);
        m.insert("close_to_object".into(), i.close_to_object);
        m.insert("touching_object".into(), i.touching_object);
        m.insert("moving_to_target".into(), i.moving_to_target);
        m.insert("target_distance".into(), i.target_distance);
        m.insert("hit".into(), f64::from(u8::from(i.hit)));
        m.insert("hits".into(), i.hits as f64);
        m.insert("diverged".into(), f64::from(u8::from(i.diverged)));
        m
    }

    fn render(&self) -> Option<carl_pixels::Frame> {
        let p = self.phys.as_ref()?;
        let palm = self.palm_position();
        let o = self.object_position();
        let look = Vector::new(
            (0.5 * (palm[0] + o[0])) as f32,
            (0.5 * (palm[1] + o[1])) as f32,
            (0.5 * (palm[2] + o[2])) as f32,
        );
        let cam = super::render::Camera {
            eye: look + Vector::new(0.0, -22.0, 9.0),
            target: look,
            focal: 420.0,
        };
        let t = self.target;
        let target = Vector::new(t[0] as f32, t[1] as f32, t[2] as f32);
        let object = Vector::new(o[0] as f32, o[1] as f32, o[2] as f32);
        Some(super::render::render_from(
            &p.world,
            &cam,
            &[
                (
                    target,
                    (self.params.target_radius as f32).max(0.1),
                    carl_pixels::Color(220, 60, 40),
                ),
                (object, OBJECT_RADIUS as f32, carl_pixels::Color(230, 200, 60)),
            ],
        ))
    }
}
