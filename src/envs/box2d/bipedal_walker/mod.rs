//! BipedalWalker-v3 (Gymnasium 1.4 `BipedalWalker`) with CARL's 20 context features, on
//! [`crate::physics2d`] (Box2D 2.3's solver semantics, [`WalkerEngine::Box2d`], the default) or on
//! rapier2d ([`WalkerEngine::Rapier`], the former engine).
//!
//! **Box2D engine** (`b2`): the world is built as Gymnasium builds it (terrain obstacles, one
//! static body per surface edge, hull, then per leg upper leg, lower leg, hip, knee; the legs
//! created apart from their anchors, as Gymnasium's `reset` does, and reassembled by the position
//! solver in the first steps) and stepped with `Step(1/FPS, 6·30, 2·30)`. The contact flags and
//! game over follow Box2D's begin/end contact events in Box2D's order, including those of
//! continuous collision. After `set_state` the contacts touching at the loaded pose are the
//! baseline (no events); the warm-start impulses are not part of the state. Not modelled: Box2D's
//! sleeping (Gymnasium wakes the walker every step by setting its motors) and f32 arithmetic.
//! The "deviations" below (solver substeps, limits, landings, start pose, skins, speed caps) are
//! the rapier engine's emulations of what the Box2D engine does natively.
//!
//! Same as Gymnasium (CARL overrides the module constants; here each instance has its own
//! [`BipedalWalkerParams`]):
//! * **Terrain** ([`terrain`]): the generator's state machine — flat start pad of
//!   `TERRAIN_STARTPAD` steps at `TERRAIN_HEIGHT`, then a damped random walk with roughness
//!   `U(-1,1)/SCALE` per step, grass stretches of `integers(TERRAIN_GRASS/2, TERRAIN_GRASS)` steps
//!   and, in the hardcore variant ([`BipedalWalkerOptions::hardcore`]), stumps, stairs and pits
//!   between them. Terrain friction `FRICTION`.
//! * **Walker**: hull polygon `HULL_POLY / SCALE` (density 5, friction 0.1), upper legs
//!   `LEG_W × LEG_H` and lower legs `0.8·LEG_W × LEG_H` (density 1, friction 0.2), restitution 0,
//!   Box2D's friction mixing `sqrt(f1·f2)`; walker parts collide only with the terrain. Hips at
//!   `(0, LEG_DOWN)` on the hull, limits `[-0.8, 1.1]`; knees limits `[-1.6, -0.1]`.
//! * **Motors**: `motorSpeed = SPEED_{HIP,KNEE}·sign(a)`, `maxMotorTorque = MOTORS_TORQUE·clip(|a|,0,1)`.
//! * **Start**: hull at `x = TERRAIN_STEP·TERRAIN_STARTPAD/2`, a horizontal force
//!   `U(-INITIAL_RANDOM, INITIAL_RANDOM)` on the hull during the first step; like Gymnasium's
//!   `reset`, ours ends with `step([0,0,0,0])` and returns its observation.
//! * **Observation** (24 × f32): hull angle, `2ω/FPS`, `0.3·vx·(VIEWPORT_W/SCALE)/FPS`,
//!   `0.3·vy·(VIEWPORT_H/SCALE)/FPS`, then per leg: hip angle, hip speed / `SPEED_HIP`, knee
//!   angle + 1, knee speed / `SPEED_KNEE`, lower-leg ground contact; then 10 lidar fractions
//!   (rays from the hull origin at `1.5·i/10` rad from straight down, length `LIDAR_RANGE`,
//!   closest terrain hit).
//! * **Reward**: shaping `130·x/SCALE − 5·|hull angle|` differenced, minus
//!   `0.00035·MOTORS_TORQUE·clip(|a_i|,0,1)` per joint; −100 when the hull touches the ground or
//!   `x < 0` (terminated). Reaching `x > (TERRAIN_LENGTH − TERRAIN_GRASS)·TERRAIN_STEP` terminates.
//!   The time limit (1600 steps) is the registry's `TimeLimit`.
//!
//! Where the rapier engine is not Box2D (documented deviations):
//! * **Solver.** rapier's TGS-soft solver with [`BipedalWalkerOptions::solver_iterations`]
//!   substeps (16) replaces Box2D's sequential impulses with 6·30 velocity and 2·30 position
//!   iterations. Measured by replaying Gymnasium's states one step at a time (scripted gait, seed
//!   0): at the first push-off Box2D lifts the hull (vy −0.27 → +0.21 m/s); 4 substeps left the
//!   joint chain unconverged under the 22:1 hull/lower-leg mass ratio and the hull sank (−0.12),
//!   8 gave +0.16, 16 give +0.209. More substeps change nothing measurable.
//! * **Limits.** Box2D 2.3 enforces a joint limit only if the joint is at or past it when the
//!   step starts (no speculative limit) and its position correction leaves [`ANGULAR_SLOP`] (2°)
//!   of overshoot; we switch rapier's limits on and off per step the same way
//!   (`World::box2d_limits`). Gymnasium's hips driven up rest at 1.134 / 1.128, knees at −0.066.
//! * **Foot landings and skins** ([`BipedalWalkerOptions::box2d_contacts`], off by default).
//!   Box2D's continuous collision (TOI) stops a lower leg inside the step in which it reaches
//!   the ground, on its own (a TOI island holds no joints), and sets its contact flag in that
//!   step; rapier's contact acts from the next step, through the whole leg chain (its
//!   speculative margin is 0.02 m). Box2D also rests its polygons 0.015 m off the ground (0.01 m
//!   skins minus 0.005 m slop). With the option, `landing` emulates the TOI for the lower legs,
//!   the walker's colliders carry a 0.015 m contact skin and contacts act only within 0.02 m:
//!   replaying Gymnasium's states one step at a time (seed 0, 400 steps), the landing steps then
//!   match Box2D (knee stopped, flag set; test `foot_landing_stops_the_lower_leg_inside_the_step_as_in_box2d`).
//!   It stays off by default because the scripted gait walks less far with it (README): a
//!   push-off from one toe lifts the hull with about a third of Box2D's ground impulse (seed 0,
//!   step 93: 1.1 N·s against 3.3), so the walker drops into a split stance and stalls.
//! * **Motors.** Box2D's velocity motor is reproduced by rapier's velocity motor (force-based,
//!   stiffness 0, very high damping) with `max_force = MOTORS_TORQUE·clip(|a|,0,1)`: it reaches
//!   the target speed unless the torque saturates, like Box2D's.
//! * **Start pose.** Box2D creates the legs `2·|LEG_DOWN|` above their hip anchors (the sign of
//!   `LEG_DOWN` in Gymnasium's leg position) at ±0.05 rad with knees at 0 (outside their limit);
//!   over the first two steps its position-only solver reassembles them while the feet meet the
//!   ground, folding the walker into a crouch (hips ≈ 0.44 / 0.34, knees ≈ −0.88, hull ≈ 2.35 m
//!   above the pad at default legs, measured with Gymnasium 1.4). rapier corrects joint errors
//!   with velocities, which launches the walker, so we create it already assembled in that
//!   crouch ([`START_JOINTS`]) with the hull level at the height where the lowest foot corner is
//!   5 mm above the pad (2.34 m at default legs). `LEG_DOWN`, `LEG_H`, `LEG_W` and `SCALE` shape
//!   that pose as Gymnasium's do.
//! * **Touching.** Box2D's polygons and edges carry a 0.01 m skin, so contact begins when closer
//!   than 0.02 m. We use rapier's contact manifolds with the same 0.02 m threshold on the signed
//!   distance. A lower leg's flag is "touches any terrain" (Box2D clears it when contact with *one*
//!   terrain body ends even if another still touches).
//! * **Lidar.** Exact ray/segment intersection against the generated terrain (surface edges and
//!   obstacle sides) in f64, instead of Box2D's f32 `RayCast`; like Box2D's polygon ray cast, an
//!   obstacle whose inside contains the ray origin is not reported.
//! * **Speed limits.** Box2D caps the motion per step at 2 m and π/2 rad inside its solver; we
//!   cap the velocities after each step.
//! * **Random stream.** Terrain, clouds (not drawn here) and the initial push draw from NumPy's
//!   generator in one stream in Gymnasium, so e.g. `TERRAIN_LENGTH` (number of cloud draws)
//!   changes the push. Here the terrain has its own seeded stream (its seed drawn from the
//!   environment's stream at reset) and the push comes from the environment's stream.
//!
//! **State** ([`Env::state`], [`STATE_DIM`] = 27 values): the hull's origin `x, y`, angle,
//! centre-of-mass velocity and angular velocity (0–5); the 4 joint angles (6–9) and joint speeds
//! (10–13), hip 0, knee 0, hip 1, knee 1 — reduced coordinates: the leg poses follow from the hull
//! and the joints; the two lower-leg contact flags (14, 15), game over (16), the previous shaping
//! as flag and value (17, 18); and the terrain's generator record (19–26: seed,
//! `TERRAIN_STEP`, `TERRAIN_LENGTH`, `TERRAIN_HEIGHT`, `TERRAIN_GRASS`, `TERRAIN_STARTPAD`,
//! roughness `SCALE`, hardcore flag). The course is regenerated from its record, so it does not
//! depend on the context `set_state` is called under (the terrain features act at reset, when the
//! course is generated, and on the finish line); physical properties (friction, shapes, masses,
//! gravity, motors) come from the context. `set_state` rebuilds the world assembled from the
//! joint angles: the small joint stretch of
//! rapier's soft joints and the solver's warm-start caches are not part of the state.

mod b2;
pub mod heuristic;
mod landing;
mod render;
pub mod terrain;

use rapier2d::prelude::*;

use crate::envs::api::{
    Action, DType, Env, EnvError, Space, StepOutcome, check_obs_len, check_state, context_features,
};
use crate::sampling::{Pcg64, dist};
pub use heuristic::WalkerHeuristic;
pub use terrain::{Obstacle, Terrain, TerrainSpec};

const ID: &str = "bipedal_walker";

/// Hull outline in pixels (Gymnasium's `HULL_POLY`).
pub const HULL_POLY: [(f64, f64); 5] = [(-30.0, 9.0), (6.0, 9.0), (34.0, 1.0), (34.0, -8.0), (-30.0, -8.0)];
/// Hip joint limits (rad), on the joint angle (measured from [`HIP_REFERENCE`]).
pub const HIP_LIMITS: [f64; 2] = [-0.8, 1.1];
/// Reference angles of the two hips (rad): Gymnasium creates the upper legs at `i·0.05` rad
/// (`i = −1, +1`) and pybox2d's `revoluteJointDef` sets `referenceAngle = angleB − angleA` at
/// creation, so a hip's joint angle (observation, limits, [`START_JOINTS`]) is the upper leg's
/// angle relative to the hull minus `i·0.05`: leg 0 really stands 0.05 rad further back and leg 1
/// 0.05 rad further forward than their joint angles say (measured with Gymnasium 1.4). The knees'
/// reference angles are 0.
pub const HIP_REFERENCE: [f64; 2] = [-0.05, 0.05];
/// Box2D's `b2_angularSlop` (2°): how far past a limit its position correction leaves a joint.
pub const ANGULAR_SLOP: f64 = 2.0 / 180.0 * std::f64::consts::PI;
/// A joint's limit while Box2D would not enforce it (|angle| never reaches 3 rad within the
/// limits above; rapier's angular limits stay within ±π).
const INACTIVE_LIMIT: f64 = 3.0;
/// Knee joint limits (rad).
pub const KNEE_LIMITS: [f64; 2] = [-1.6, -0.1];
/// Number of lidar rays.
pub const LIDAR_RAYS: usize = 10;
/// Observation length.
pub const OBS_DIM: usize = 24;
/// Length of [`BipedalWalker::state`] (see the module docs).
pub const STATE_DIM: usize = 27;
/// Two Box2D skins (`2 * b2_polygonRadius`): closer than this counts as touching.
pub const TOUCH_DISTANCE: f32 = 0.02;
/// Box2D's per-step motion caps (`b2_maxTranslation`, `b2_maxRotation`).
pub const MAX_TRANSLATION: f32 = 2.0;
pub const MAX_ROTATION: f32 = 0.5 * std::f32::consts::PI;
/// Damping of the velocity motors (force-based): large enough to act as Box2D's rigid motor
/// constraint, limited only by the maximum torque.
pub const MOTOR_DAMPING: f32 = 1.0e6;
/// Joint angles at reset (hip 0, knee 0, hip 1, knee 1): the crouch Box2D's position solver
/// leaves Gymnasium's walker in after reassembling its misplaced legs (measured with Gymnasium
/// 1.4, seed 0, second observation: hips 0.44 / 0.34, knees −0.88 / −0.88, hull 2.35 m above
/// the pad); see the module docs.
pub const START_JOINTS: [f64; 4] = [0.45, -0.9, 0.35, -0.9];
/// Gap between the lowest foot corner and the start pad at reset, m.
pub const START_CLEARANCE: f64 = 0.005;
/// rapier contact skin of the walker's colliders with [`BipedalWalkerOptions::box2d_contacts`]:
/// Box2D keeps polygons apart by two 0.01 m skins (`b2_polygonRadius`) minus `b2_linearSlop`
/// (0.005 m), so its walker rests 0.015 m off the ground (also the start clearance then).
pub const WALKER_SKIN: f32 = 0.015;
/// Seeds of the terrain stream are below this (exact in an f64 state component).
const TERRAIN_SEED_LIMIT: u64 = 1 << 53;

/// BipedalWalker context (CARL's 20 features). `Default` is CARL's defaults: Gymnasium's module
/// constants with `TERRAIN_HEIGHT = 5` (CARL) instead of Gymnasium's `VIEWPORT_H/SCALE/4`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BipedalWalkerParams {
    pub fps: f64,
    pub friction: f64,
    pub gravity_x: f64,
    pub gravity_y: f64,
    pub initial_random: f64,
    pub leg_down: f64,
    pub leg_h: f64,
    pub leg_w: f64,
    pub lidar_range: f64,
    pub motors_torque: f64,
    pub scale: f64,
    pub speed_hip: f64,
    pub speed_knee: f64,
    pub terrain_grass: f64,
    pub terrain_height: f64,
    pub terrain_length: f64,
    pub terrain_startpad: f64,
    pub terrain_step: f64,
    pub viewport_h: f64,
    pub viewport_w: f64,
}

impl Default for BipedalWalkerParams {
    fn default() -> Self {
        BipedalWalkerParams {
            fps: 50.0,
            friction: 2.5,
            gravity_x: 0.0,
            gravity_y: -10.0,
            initial_random: 5.0,
            leg_down: -8.0 / 30.0,
            leg_h: 34.0 / 30.0,
            leg_w: 8.0 / 30.0,
            lidar_range: 160.0 / 30.0,
            motors_torque: 80.0,
            scale: 30.0,
            speed_hip: 4.0,
            speed_knee: 6.0,
            terrain_grass: 10.0,
            terrain_height: 5.0,
            terrain_length: 200.0,
            terrain_startpad: 20.0,
            terrain_step: 14.0 / 30.0,
            viewport_h: 400.0,
            viewport_w: 600.0,
        }
    }
}

context_features!(BipedalWalkerParams, "bipedal_walker", {
    fps: "FPS",
    friction: "FRICTION",
    gravity_x: "GRAVITY_X",
    gravity_y: "GRAVITY_Y",
    initial_random: "INITIAL_RANDOM",
    leg_down: "LEG_DOWN",
    leg_h: "LEG_H",
    leg_w: "LEG_W",
    lidar_range: "LIDAR_RANGE",
    motors_torque: "MOTORS_TORQUE",
    scale: "SCALE",
    speed_hip: "SPEED_HIP",
    speed_knee: "SPEED_KNEE",
    terrain_grass: "TERRAIN_GRASS",
    terrain_height: "TERRAIN_HEIGHT",
    terrain_length: "TERRAIN_LENGTH",
    terrain_startpad: "TERRAIN_STARTPAD",
    terrain_step: "TERRAIN_STEP",
    viewport_h: "VIEWPORT_H",
    viewport_w: "VIEWPORT_W",
});

impl BipedalWalkerParams {
    /// The finish line `(TERRAIN_LENGTH − TERRAIN_GRASS)·TERRAIN_STEP`, m.
    pub fn finish_x(&self) -> f64 {
        Terrain::finish_x(self.terrain_length, self.terrain_grass, self.terrain_step)
    }
    /// Start position of the hull's x, `TERRAIN_STEP·TERRAIN_STARTPAD/2`.
    pub fn init_x(&self) -> f64 {
        self.terrain_step * self.terrain_startpad / 2.0
    }
}

/// The physics engine under the walker.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WalkerEngine {
    /// [`crate::physics2d`]: Box2D 2.3's solver semantics, stepped as Gymnasium steps Box2D
    /// (`Step(1/FPS, 6·30, 2·30)`), the walker created as Gymnasium creates it.
    Box2d,
    /// rapier2d with the emulations described in the module docs.
    Rapier,
}

/// Options that are not context features.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BipedalWalkerOptions {
    /// Physics engine.
    pub engine: WalkerEngine,
    /// `BipedalWalkerHardcore`: stumps, stairs and pits between grass stretches.
    pub hardcore: bool,
    /// rapier solver substeps per step.
    pub solver_iterations: usize,
    /// rapier PGS iterations inside each substep.
    pub pgs_iterations: usize,
    /// Box2D's contact model: the walker rests [`WALKER_SKIN`] off the ground (Box2D's skins),
    /// contacts act only closer than [`TOUCH_DISTANCE`] (not speculatively from further away),
    /// and a foot landing is Box2D's continuous collision (`landing`): the lower leg stops
    /// inside the step in which it reaches the ground, alone, and its contact flag is set in
    /// that step. Replayed Box2D landings match with it (tests/bipedal_walker.rs); off by
    /// default because Gymnasium's scripted gait walks less far with it here (README): the
    /// push-off from one toe gives the hull about a third of Box2D's lift (known gap).
    pub box2d_contacts: bool,
    /// Draw the 10 lidar rays (up to their hits) in `render`.
    pub render_lidar: bool,
    /// rapier's solver warm start (0..=1; 1, rapier's default). Known issue: with it, a
    /// landing after a jump now and then throws the walker up (seed 65 of
    /// `examples/bipedal_walker_flips.rs`, step 31: hull vy −3.9 → +8.1 m/s) and the hull flips
    /// past ±π in the air (8 of 300 random-action episodes); 0 gives no flip in 300 (largest
    /// |angle| 2.78), but moves the replayed push-off off Box2D's (vx 2.219 vs 2.249) and shortens
    /// the scripted gait's episodes, so it is not the default yet.
    pub warmstart_coefficient: f64,
}

impl Default for BipedalWalkerOptions {
    fn default() -> Self {
        BipedalWalkerOptions {
            engine: WalkerEngine::Box2d,
            hardcore: false,
            solver_iterations: 16,
            pgs_iterations: 2,
            box2d_contacts: false,
            render_lidar: true,
            warmstart_coefficient: 1.0,
        }
    }
}

/// One lidar ray: start (hull origin), end at `LIDAR_RANGE`, fraction to the closest hit.
pub type LidarRay = ((f64, f64), (f64, f64), f64);

/// Kinematic state of one body: origin position, angle, centre-of-mass velocity, ω.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BodyState {
    pub x: f64,
    pub y: f64,
    pub angle: f64,
    pub vx: f64,
    pub vy: f64,
    pub w: f64,
}

/// The walker in reduced coordinates: hull plus joint angles and speeds.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Pose {
    hull: BodyState,
    q: [f64; 4],
    dq: [f64; 4],
}

fn rot(a: f64, (x, y): (f64, f64)) -> (f64, f64) {
    let (s, c) = a.sin_cos();
    (c * x - s * y, s * x + c * y)
}

/// Centroid of the hull polygon in metres (its centre of mass at uniform density).
fn hull_centroid(scale: f64) -> (f64, f64) {
    let (mut a2, mut cx, mut cy) = (0.0, 0.0, 0.0);
    let n = HULL_POLY.len();
    for k in 0..n {
        let (x0, y0) = HULL_POLY[k];
        let (x1, y1) = HULL_POLY[(k + 1) % n];
        let cr = x0 * y1 - x1 * y0;
        a2 += cr;
        cx += (x0 + x1) * cr;
        cy += (y0 + y1) * cr;
    }
    (cx / (3.0 * a2) / scale, cy / (3.0 * a2) / scale)
}

/// Shape sizes are floored at 1e-4 m so that out-of-bounds contexts cannot make degenerate shapes.
fn size(x: f64) -> f64 {
    x.abs().max(1e-4)
}

fn wrap_pi(a: f64) -> f64 {
    let tau = std::f64::consts::TAU;
    a - tau * (a / tau).round()
}

impl Pose {
    /// The five bodies (hull, upper 0, lower 0, upper 1, lower 1) from the reduced coordinates.
    fn bodies(&self, p: &BipedalWalkerParams) -> [BodyState; 5] {
        let h = self.hull;
        let com = rot(h.angle, hull_centroid(size(p.scale)));
        let com = (h.x + com.0, h.y + com.1);
        let point_vel =
            |b: &BodyState, c: (f64, f64), pt: (f64, f64)| (b.vx - b.w * (pt.1 - c.1), b.vy + b.w * (pt.0 - c.0));
        let half = size(p.leg_h) / 2.0;
        let mut out = [h; 5];
        for leg in 0..2 {
            let (qh, qk) = (self.q[2 * leg], self.q[2 * leg + 1]);
            let (wh, wk) = (self.dq[2 * leg], self.dq[2 * leg + 1]);
            let a_off = rot(h.angle, (0.0, p.leg_down));
            let hip = (h.x + a_off.0, h.y + a_off.1);
            let v_hip = point_vel(&h, com, hip);
            // (qh + reference) first: a state read from a world rebuilds the same f32 angles.
            let au = h.angle + HIP_REFERENCE[leg] + qh;
            let wu = h.w + wh;
            let d = rot(au, (0.0, -half));
            let cu = (hip.0 + d.0, hip.1 + d.1);
            let knee = (hip.0 + 2.0 * d.0, hip.1 + 2.0 * d.1);
            let upper = BodyState {
                x: cu.0,
                y: cu.1,
                angle: au,
                vx: v_hip.0 - wu * (cu.1 - hip.1),
                vy: v_hip.1 + wu * (cu.0 - hip.0),
                w: wu,
            };
            let v_knee = (v_hip.0 - wu * (knee.1 - hip.1), v_hip.1 + wu * (knee.0 - hip.0));
            let al = au + qk;
            let wl = wu + wk;
            let d = rot(al, (0.0, -half));
            let cl = (knee.0 + d.0, knee.1 + d.1);
            let lower = BodyState {
                x: cl.0,
                y: cl.1,
                angle: al,
                vx: v_knee.0 - wl * (cl.1 - knee.1),
                vy: v_knee.1 + wl * (cl.0 - knee.0),
                w: wl,
            };
            out[1 + 2 * leg] = upper;
            out[2 + 2 * leg] = lower;
        }
        out
    }
}

const GROUND_GROUP: u32 = 0x0001;
const WALKER_GROUP: u32 = 0x0020;

fn groups(category: u32, mask: u32) -> InteractionGroups {
    InteractionGroups::new(
        Group::from_bits_truncate(category),
        Group::from_bits_truncate(mask),
        InteractionTestMode::And,
    )
}

/// The terrain's collision shapes, built once per course and shared (reference-counted) by every
/// world built on it: `set_state` then does not rebuild the surface's bounding-volume tree.
#[derive(Clone)]
struct GroundShapes {
    surface: SharedShape,
    quads: Vec<SharedShape>,
}

impl std::fmt::Debug for GroundShapes {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GroundShapes")
            .field("quads", &self.quads.len())
            .finish_non_exhaustive()
    }
}

impl GroundShapes {
    fn new(terrain: &Terrain) -> GroundShapes {
        let pts: Vec<Vector> = terrain.x.iter().zip(&terrain.y).map(|(x, y)| v2(*x, *y)).collect();
        let quads = terrain
            .quads
            .iter()
            .filter_map(|q| SharedShape::convex_hull(&q.map(|(x, y)| v2(x, y))))
            .collect();
        GroundShapes {
            surface: SharedShape::polyline(pts, None),
            quads,
        }
    }
}

/// One terrain piece in contact with a lower leg (see [`ContactListener`]).
#[derive(Debug, Clone, Copy, PartialEq)]
struct TouchedPiece {
    collider: ColliderHandle,
    subshape: u32,
    /// World x of a touching point (orders the events of one step).
    x: f32,
}

/// Gymnasium's `ContactDetector` for one lower leg: the flag is set when contact with a terrain
/// piece begins and cleared when contact with *a* piece ends, even if the leg still touches
/// another. Gymnasium's terrain is one Box2D body per surface segment, so a foot sliding or
/// rocking across a segment boundary clears its flag while it stands on the ground; the
/// scripted gait reads the flag to decide when a swinging leg has landed.
///
/// Box2D reports a step's events newest contact first; a leg moving along the course meets
/// pieces further right later, so the event that decides the flag is the one at the smallest x.
///
/// After `set_state` the pieces touched are not known (they are not part of the state): the
/// first step takes the contacts it finds as the baseline and keeps the loaded flag.
#[derive(Debug, Clone, Default)]
struct ContactListener {
    touching: Vec<TouchedPiece>,
    /// The next update only records `touching`.
    unknown: bool,
}

impl ContactListener {
    fn baseline() -> ContactListener {
        ContactListener {
            touching: Vec::new(),
            unknown: true,
        }
    }

    /// Update `flag` with this step's begin/end events, `now` being the pieces touched now.
    fn update(&mut self, now: Vec<TouchedPiece>, flag: &mut bool) {
        if std::mem::take(&mut self.unknown) {
            self.touching = now;
            return;
        }
        let same = |a: &TouchedPiece, b: &TouchedPiece| a.collider == b.collider && a.subshape == b.subshape;
        let begins = now
            .iter()
            .filter(|p| !self.touching.iter().any(|q| same(p, q)))
            .map(|p| (p.x, true));
        let ends = self
            .touching
            .iter()
            .filter(|q| !now.iter().any(|p| same(p, q)))
            .map(|q| (q.x, false));
        if let Some((_, begin)) = begins.chain(ends).min_by(|a, b| a.0.total_cmp(&b.0)) {
            *flag = begin;
        }
        self.touching = now;
    }
}

struct World {
    pw: PhysicsWorld,
    /// Hull, upper 0, lower 0, upper 1, lower 1 (Gymnasium's `hull` and `legs` order).
    bodies: [RigidBodyHandle; 5],
    /// Hip 0, knee 0, hip 1, knee 1 (Gymnasium's `joints` order).
    joints: [ImpulseJointHandle; 4],
    hull_col: ColliderHandle,
    lower_cols: [ColliderHandle; 2],
}

impl std::fmt::Debug for World {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("World").finish_non_exhaustive()
    }
}

fn v2(x: f64, y: f64) -> Vector {
    Vector::new(x as f32, y as f32)
}

impl World {
    fn build(
        p: &BipedalWalkerParams,
        opts: &BipedalWalkerOptions,
        ground: &GroundShapes,
        bodies: &[BodyState; 5],
    ) -> World {
        let mut pw = PhysicsWorld::new();
        pw.gravity = v2(p.gravity_x, p.gravity_y);
        let ip = &mut pw.integration_parameters;
        ip.dt = if p.fps > 0.0 && p.fps.is_finite() {
            (1.0 / p.fps) as f32
        } else {
            0.0
        };
        ip.num_solver_iterations = opts.solver_iterations.max(1);
        ip.num_internal_pgs_iterations = opts.pgs_iterations.max(1);
        ip.max_ccd_substeps = 1;
        ip.warmstart_coefficient = opts.warmstart_coefficient.clamp(0.0, 1.0) as f32;
        let skin = if opts.box2d_contacts {
            // Contacts act from two Box2D skins (raw gap < TOUCH_DISTANCE) as in Box2D, not
            // speculatively from further away: an approaching foot meets the ground through
            // `box2d_landing` (Box2D's TOI), not through the whole leg chain.
            ip.normalized_prediction_distance = TOUCH_DISTANCE - WALKER_SKIN;
            WALKER_SKIN
        } else {
            0.0
        };
        let friction = p.friction.max(0.0) as f32;
        let ground_col = |c: ColliderBuilder| {
            c.friction(friction)
                .restitution(0.0)
                .friction_combine_rule(CoefficientCombineRule::GeometricMean)
                .collision_groups(groups(GROUND_GROUP, 0xFFFF))
        };
        let (fixed, _) = pw.insert(
            RigidBodyBuilder::fixed(),
            ground_col(ColliderBuilder::new(ground.surface.clone())),
        );
        for q in &ground.quads {
            pw.insert_collider(ground_col(ColliderBuilder::new(q.clone())), Some(fixed));
        }

        let dynamic = |b: &BodyState| {
            RigidBodyBuilder::dynamic()
                .translation(v2(b.x, b.y))
                .rotation(b.angle as f32)
                .linvel(v2(b.vx, b.vy))
                .angvel(b.w as f32)
                .can_sleep(false)
                .ccd_enabled(true)
        };
        let walker_col = |c: ColliderBuilder, density: f32, friction: f32| {
            c.density(density)
                .friction(friction)
                .restitution(0.0)
                .contact_skin(skin)
                .friction_combine_rule(CoefficientCombineRule::GeometricMean)
                .collision_groups(groups(WALKER_GROUP, GROUND_GROUP))
        };
        let s = size(p.scale);
        let hull_pts: Vec<Vector> = HULL_POLY.iter().map(|(x, y)| v2(x / s, y / s)).collect();
        let hull_shape = ColliderBuilder::convex_hull(&hull_pts).unwrap_or_else(|| ColliderBuilder::cuboid(0.5, 0.2));
        let (hull, hull_col) = pw.insert(dynamic(&bodies[0]), walker_col(hull_shape, 5.0, 0.1));
        let (lw, lh) = (size(p.leg_w) as f32, size(p.leg_h) as f32);
        let mut handles = [hull; 5];
        let mut joints = Vec::with_capacity(4);
        let mut lower_cols = [hull_col; 2];
        for leg in 0..2 {
            let (upper, _) = pw.insert(
                dynamic(&bodies[1 + 2 * leg]),
                walker_col(ColliderBuilder::cuboid(lw / 2.0, lh / 2.0), 1.0, 0.2),
            );
            let (lower, lower_col) = pw.insert(
                dynamic(&bodies[2 + 2 * leg]),
                walker_col(ColliderBuilder::cuboid(0.8 * lw / 2.0, lh / 2.0), 1.0, 0.2),
            );
            let joint = |a1: Vector, a2: Vector, limits: [f64; 2]| {
                RevoluteJointBuilder::new()
                    .local_anchor1(a1)
                    .local_anchor2(a2)
                    .limits([limits[0] as f32, limits[1] as f32])
                    .motor_model(MotorModel::ForceBased)
                    .motor_velocity(0.0, MOTOR_DAMPING)
                    .motor_max_force(0.0)
                    .contacts_enabled(false)
            };
            // rapier's limits are on the relative angle; Box2D's on the angle from the reference.
            let r = HIP_REFERENCE[leg];
            let hip = pw.insert_impulse_joint(
                hull,
                upper,
                joint(
                    v2(0.0, p.leg_down),
                    Vector::new(0.0, lh / 2.0),
                    [HIP_LIMITS[0] + r, HIP_LIMITS[1] + r],
                ),
            );
            let knee = pw.insert_impulse_joint(
                upper,
                lower,
                joint(Vector::new(0.0, -lh / 2.0), Vector::new(0.0, lh / 2.0), KNEE_LIMITS),
            );
            handles[1 + 2 * leg] = upper;
            handles[2 + 2 * leg] = lower;
            joints.push(hip);
            joints.push(knee);
            lower_cols[leg] = lower_col;
        }
        World {
            pw,
            bodies: handles,
            joints: [joints[0], joints[1], joints[2], joints[3]],
            hull_col,
            lower_cols,
        }
    }

    fn touching(&self, c: ColliderHandle) -> bool {
        self.pw.narrow_phase.contact_pairs_with(c).any(|pair| {
            pair.manifolds()
                .iter()
                .any(|m| m.points.iter().any(|pt| pt.dist < TOUCH_DISTANCE))
        })
    }

    /// The terrain pieces (surface segments and obstacles: one Box2D body each in Gymnasium)
    /// that collider `c` touches, with the x of a touching point on each.
    fn touched_pieces(&self, c: ColliderHandle) -> Vec<TouchedPiece> {
        let mut out: Vec<TouchedPiece> = Vec::new();
        for pair in self.pw.narrow_phase.contact_pairs_with(c) {
            let other_is_1 = pair.collider2 == c;
            let other = if other_is_1 { pair.collider1 } else { pair.collider2 };
            for m in pair.manifolds() {
                let Some(pt) = m.points.iter().find(|pt| pt.dist < TOUCH_DISTANCE) else {
                    continue;
                };
                // Terrain colliders sit at the world origin: their local points are world points.
                let (sub, x) = if other_is_1 {
                    (m.subshape1, pt.local_p1.x)
                } else {
                    (m.subshape2, pt.local_p2.x)
                };
                if !out.iter().any(|p| p.collider == other && p.subshape == sub) {
                    out.push(TouchedPiece {
                        collider: other,
                        subshape: sub,
                        x,
                    });
                }
            }
        }
        out
    }

    /// Poses of the two lower legs (centre = centre of mass).
    fn lower_poses(&self) -> [landing::BoxPose; 2] {
        [2, 4].map(|k| {
            let b = &self.pw.bodies[self.bodies[k]];
            let t = b.translation();
            landing::BoxPose {
                c: (t.x as f64, t.y as f64),
                a: b.rotation().angle() as f64,
            }
        })
    }

    /// Box2D's continuous collision for lower leg `leg` ([`landing`]): if it did not touch the
    /// terrain when the step began (rapier's contacts after a step are those found at its
    /// start) and its sweep from `start` reaches the terrain, it lands inside the step. Returns
    /// whether it landed.
    fn box2d_landing(
        &mut self,
        terrain: &Terrain,
        leg: usize,
        start: landing::BoxPose,
        half: (f64, f64),
        mu: f64,
        dt: f64,
    ) -> bool {
        let end = self.lower_poses()[leg];
        let sweep = landing::Sweep { start, end, half };
        if !self.touched_pieces(self.lower_cols[leg]).is_empty() {
            return false;
        }
        let Some(alpha) = landing::time_of_impact(terrain, &sweep) else {
            return false;
        };
        let b = &mut self.pw.bodies[self.bodies[2 + 2 * leg]];
        let v = b.linvel();
        let out = landing::land(
            terrain,
            &sweep,
            alpha,
            (v.x as f64, v.y as f64),
            b.angvel() as f64,
            mu,
            dt,
        );
        b.set_translation(v2(out.pose.c.0, out.pose.c.1), false);
        b.set_rotation(Rotation::from_angle(out.pose.a as f32), false);
        b.set_linvel(v2(out.v.0, out.v.1), false);
        b.set_angvel(out.w as f32, false);
        true
    }

    fn angle(&self, k: usize) -> f64 {
        self.pw.bodies[self.bodies[k]].rotation().angle() as f64
    }
    fn body_state(&self, k: usize) -> BodyState {
        let b = &self.pw.bodies[self.bodies[k]];
        let (t, v) = (b.translation(), b.linvel());
        BodyState {
            x: t.x as f64,
            y: t.y as f64,
            angle: b.rotation().angle() as f64,
            vx: v.x as f64,
            vy: v.y as f64,
            w: b.angvel() as f64,
        }
    }
    fn angvel(&self, k: usize) -> f64 {
        self.pw.bodies[self.bodies[k]].angvel() as f64
    }

    /// Box2D's joint limits for the coming step: a limit acts only if the joint is already at or
    /// beyond it when the step starts (Box2D 2.3 decides the limit state in
    /// `InitVelocityConstraints`; there is no speculative limit), and its position correction
    /// leaves [`ANGULAR_SLOP`] of overshoot. A knee swinging at 6 rad/s therefore runs up to one
    /// step past its limit and is then held about 2° beyond it, as in Gymnasium. rapier's limits
    /// are on the angle between the bodies, Box2D's on the angle from the reference angle.
    fn box2d_limits(&mut self) {
        let (q, _) = self.joints();
        for (j, &qj) in q.iter().enumerate() {
            let (lim, reference) = if j % 2 == 0 {
                (HIP_LIMITS, HIP_REFERENCE[j / 2])
            } else {
                (KNEE_LIMITS, 0.0)
            };
            let slop = ANGULAR_SLOP;
            let [lo, hi] = if qj <= lim[0] {
                [lim[0] - slop, INACTIVE_LIMIT]
            } else if qj >= lim[1] {
                [-INACTIVE_LIMIT, lim[1] + slop]
            } else {
                [-INACTIVE_LIMIT, INACTIVE_LIMIT]
            };
            if let Some(joint) = self.pw.impulse_joints.get_mut(self.joints[j], false) {
                joint
                    .data
                    .set_limits(JointAxis::AngX, [(lo + reference) as f32, (hi + reference) as f32]);
            }
        }
    }

    /// Joint angles and speeds (Box2D's `angle = angleB − angleA − referenceAngle`,
    /// `speed = ωB − ωA`).
    fn joints(&self) -> ([f64; 4], [f64; 4]) {
        let pairs = [(0, 1), (1, 2), (0, 3), (3, 4)];
        let reference = [HIP_REFERENCE[0], 0.0, HIP_REFERENCE[1], 0.0];
        let mut q = [0.0; 4];
        let mut dq = [0.0; 4];
        for (j, (a, b)) in pairs.into_iter().enumerate() {
            q[j] = wrap_pi(self.angle(b) - self.angle(a) - reference[j]);
            dq[j] = self.angvel(b) - self.angvel(a);
        }
        (q, dq)
    }
}

/// The walker's world on one of the engines.
#[derive(Debug)]
enum Physics {
    Rapier(Box<World>),
    Box2d(Box<b2::Box2dWalker>),
}

impl Physics {
    /// Body `k` (hull, upper 0, lower 0, upper 1, lower 1): origin, engine angle, centre-of-mass
    /// velocity.
    fn body(&self, k: usize) -> BodyState {
        match self {
            Physics::Rapier(w) => w.body_state(k),
            Physics::Box2d(w) => w.body_state(k),
        }
    }
    /// Joint angles (wrapped to ±π) and speeds: Box2D's `angle = angleB − angleA −
    /// referenceAngle`, `speed = ωB − ωA`.
    fn joints(&self) -> ([f64; 4], [f64; 4]) {
        match self {
            Physics::Rapier(w) => w.joints(),
            Physics::Box2d(w) => {
                let pairs = [(0, 1), (1, 2), (0, 3), (3, 4)];
                let reference = [HIP_REFERENCE[0], 0.0, HIP_REFERENCE[1], 0.0];
                let mut q = [0.0; 4];
                let mut dq = [0.0; 4];
                for (j, (a, b)) in pairs.into_iter().enumerate() {
                    let (a, b) = (w.body_state(a), w.body_state(b));
                    q[j] = wrap_pi(b.angle - a.angle - reference[j]);
                    dq[j] = b.w - a.w;
                }
                (q, dq)
            }
        }
    }
}

/// Gymnasium's `BipedalWalker` with an explicit context; each instance owns its physics world.
#[derive(Debug)]
pub struct BipedalWalker {
    params: BipedalWalkerParams,
    opts: BipedalWalkerOptions,
    world: Option<Physics>,
    terrain: Option<Terrain>,
    /// Collision shapes of `terrain`.
    ground: Option<GroundShapes>,
    /// Unwrapped hull angle (Box2D keeps angles continuous).
    hull_angle: f64,
    ground_contact: [bool; 2],
    /// Box2D's contact events behind `ground_contact`.
    listeners: [ContactListener; 2],
    game_over: bool,
    prev_shaping: Option<f64>,
    /// Force applied at reset, acting during the first step only (Box2D clears forces).
    pending_force: bool,
    rng: Pcg64,
}

fn rng_for(seed: u64) -> Pcg64 {
    Pcg64::new(seed, crate::sampling::stream_id(ID))
}

impl Clone for BipedalWalker {
    /// The clone gets a world rebuilt from the full [`Env::state`]: bodies (to the last f32 bit
    /// of an angle, which the hips' reference angles can move), terrain and episode bookkeeping
    /// are equal; rapier's solver caches (warm-start impulses) start empty and the contact
    /// listeners take the first step's contacts as their baseline.
    fn clone(&self) -> Self {
        let mut c = BipedalWalker::with_options(self.params, self.opts);
        c.rng = self.rng.clone();
        c.terrain = self.terrain.clone();
        c.ground = self.ground.clone();
        match &self.world {
            // The Box2D world is a plain value: the clone continues exactly as the original.
            Some(Physics::Box2d(w)) => {
                c.world = Some(Physics::Box2d(w.clone()));
                c.hull_angle = self.hull_angle;
                c.ground_contact = self.ground_contact;
                c.listeners = self.listeners.clone();
                c.game_over = self.game_over;
                c.prev_shaping = self.prev_shaping;
                c.pending_force = self.pending_force;
            }
            Some(Physics::Rapier(_)) => c.load_state(&self.state_array()),
            None => {}
        }
        c
    }
}

impl Default for BipedalWalker {
    fn default() -> Self {
        BipedalWalker::new(BipedalWalkerParams::default())
    }
}

impl BipedalWalker {
    pub fn new(params: BipedalWalkerParams) -> Self {
        Self::with_options(params, BipedalWalkerOptions::default())
    }

    pub fn with_options(params: BipedalWalkerParams, opts: BipedalWalkerOptions) -> Self {
        BipedalWalker {
            params,
            opts,
            world: None,
            terrain: None,
            ground: None,
            hull_angle: 0.0,
            ground_contact: [false; 2],
            listeners: Default::default(),
            game_over: false,
            prev_shaping: None,
            pending_force: false,
            rng: rng_for(crate::envs::rng::DEFAULT_SEED),
        }
    }

    pub fn params(&self) -> &BipedalWalkerParams {
        &self.params
    }
    /// Context changes take effect at the next reset.
    pub fn params_mut(&mut self) -> &mut BipedalWalkerParams {
        &mut self.params
    }
    pub fn options(&self) -> &BipedalWalkerOptions {
        &self.opts
    }
    /// Option changes take effect at the next reset.
    pub fn options_mut(&mut self) -> &mut BipedalWalkerOptions {
        &mut self.opts
    }
    /// The current course, or `None` before reset.
    pub fn terrain(&self) -> Option<&Terrain> {
        self.terrain.as_ref()
    }
    /// Replace the current course by `terrain` (e.g. Gymnasium's recorded course, to replay its
    /// states: `examples/bipedal_walker_replay.rs`). The walker keeps its place until the next
    /// [`Env::set_state`], which keeps this course if the state carries `terrain.spec` (as
    /// [`Env::state`] reports it from now on). A state vector records only a generator spec, so
    /// a course set here is not rebuilt from a state alone.
    pub fn set_course(&mut self, terrain: Terrain) {
        self.set_terrain(terrain);
    }
    /// Whether the hull has touched the ground this episode.
    pub fn game_over(&self) -> bool {
        self.game_over
    }
    /// Poses of hull, upper 0, lower 0, upper 1, lower 1 as the physics engine has them, or
    /// `None` before reset.
    pub fn body_states(&self) -> Option<[BodyState; 5]> {
        let w = self.world.as_ref()?;
        Some(std::array::from_fn(|k| {
            let mut b = w.body(k);
            if k == 0 {
                b.angle = self.hull_angle;
            }
            b
        }))
    }
    /// Hull mass (kg) as the physics engine computed it.
    pub fn hull_mass(&self) -> Option<f64> {
        Some(match self.world.as_ref()? {
            Physics::Rapier(w) => w.pw.bodies[w.bodies[0]].mass() as f64,
            Physics::Box2d(w) => w.mass(0),
        })
    }

    /// The lidar's end points `(p1, p2)` and fractions for the current hull position.
    pub fn lidar(&self) -> Option<[LidarRay; LIDAR_RAYS]> {
        let (w, t) = (self.world.as_ref()?, self.terrain.as_ref()?);
        let hull = w.body(0);
        let p1 = (hull.x, hull.y);
        let r = self.params.lidar_range;
        Some(std::array::from_fn(|i| {
            let a = 1.5 * i as f64 / 10.0;
            let p2 = (p1.0 + a.sin() * r, p1.1 - a.cos() * r);
            (p1, p2, t.ray_fraction(p1, p2))
        }))
    }

    fn terrain_spec(&self, seed: u64) -> TerrainSpec {
        let p = &self.params;
        let int = |x: f64| if x.is_finite() { x.round() as i64 } else { 0 };
        TerrainSpec {
            seed,
            step: p.terrain_step,
            length: int(p.terrain_length).clamp(2, 1 << 20) as usize,
            height: p.terrain_height,
            grass: int(p.terrain_grass),
            startpad: int(p.terrain_startpad),
            scale: p.scale,
            hardcore: self.opts.hardcore,
        }
    }

    /// The start pose ([`START_JOINTS`]): the hull level at Gymnasium's
    /// `x = TERRAIN_STEP·TERRAIN_STARTPAD/2`, at the height where the lowest foot corner is
    /// [`START_CLEARANCE`] above `ground`.
    fn start_pose(&self, ground: f64) -> Pose {
        let p = &self.params;
        let mut pose = Pose {
            hull: BodyState {
                x: p.init_x(),
                y: p.terrain_height + 2.0 * p.leg_h,
                ..Default::default()
            },
            q: START_JOINTS,
            dq: [0.0; 4],
        };
        let (hw, hh) = (0.8 * size(p.leg_w) / 2.0, size(p.leg_h) / 2.0);
        let bodies = pose.bodies(p);
        let lowest = [bodies[2], bodies[4]]
            .iter()
            .flat_map(|b| [(-hw, -hh), (hw, -hh), (hw, hh), (-hw, hh)].map(|c| b.y + rot(b.angle, c).1))
            .fold(f64::INFINITY, f64::min);
        let clearance = if self.opts.box2d_contacts {
            f64::from(WALKER_SKIN)
        } else {
            START_CLEARANCE
        };
        pose.hull.y += ground + clearance - lowest;
        pose
    }

    fn current_pose(&self) -> Pose {
        let Some(w) = &self.world else { return Pose::default() };
        let (q, dq) = w.joints();
        Pose {
            hull: BodyState {
                angle: self.hull_angle,
                ..w.body(0)
            },
            q,
            dq,
        }
    }

    /// Everything [`Env::state`] returns, as a fixed array.
    fn state_array(&self) -> [f64; STATE_DIM] {
        let mut s = [0.0; STATE_DIM];
        let pose = self.current_pose();
        let h = pose.hull;
        s[..6].copy_from_slice(&[h.x, h.y, h.angle, h.vx, h.vy, h.w]);
        s[6..10].copy_from_slice(&pose.q);
        s[10..14].copy_from_slice(&pose.dq);
        s[14] = f64::from(u8::from(self.ground_contact[0]));
        s[15] = f64::from(u8::from(self.ground_contact[1]));
        s[16] = f64::from(u8::from(self.game_over));
        s[17] = f64::from(u8::from(self.prev_shaping.is_some()));
        s[18] = self.prev_shaping.unwrap_or(0.0);
        if let Some(t) = &self.terrain {
            let ts = &t.spec;
            s[19..].copy_from_slice(&[
                ts.seed as f64,
                ts.step,
                ts.length as f64,
                ts.height,
                ts.grass as f64,
                ts.startpad as f64,
                ts.scale,
                f64::from(u8::from(ts.hardcore)),
            ]);
        }
        s
    }

    fn load_state(&mut self, s: &[f64; STATE_DIM]) {
        let int = |x: f64, lo: f64, hi: f64| x.round().clamp(lo, hi);
        let t = &s[19..];
        let spec = TerrainSpec {
            seed: int(t[0], 0.0, (TERRAIN_SEED_LIMIT - 1) as f64) as u64,
            step: t[1],
            length: int(t[2], 2.0, (1 << 20) as f64) as usize,
            height: t[3],
            grass: int(t[4], -1e9, 1e9) as i64,
            startpad: int(t[5], -1e9, 1e9) as i64,
            scale: t[6],
            hardcore: t[7] >= 0.5,
        };
        if self.terrain.as_ref().map(|t| t.spec) != Some(spec) {
            self.set_terrain(Terrain::generate(spec));
        }
        let pose = Pose {
            hull: BodyState {
                x: s[0],
                y: s[1],
                angle: s[2],
                vx: s[3],
                vy: s[4],
                w: s[5],
            },
            q: [s[6], s[7], s[8], s[9]],
            dq: [s[10], s[11], s[12], s[13]],
        };
        self.place(&pose);
        self.ground_contact = [s[14] != 0.0, s[15] != 0.0];
        // The contacts the next step finds at the loaded pose are its baseline, not events.
        self.listeners = [ContactListener::baseline(), ContactListener::baseline()];
        self.game_over = s[16] != 0.0;
        self.prev_shaping = (s[17] != 0.0).then_some(s[18]);
        self.pending_force = false;
    }

    fn set_terrain(&mut self, terrain: Terrain) {
        self.ground = Some(GroundShapes::new(&terrain));
        self.terrain = Some(terrain);
    }

    /// Build the world with the walker at `pose` on the current terrain.
    fn place(&mut self, pose: &Pose) {
        let bodies = pose.bodies(&self.params);
        self.place_bodies(&bodies);
        if let Some(Physics::Box2d(w)) = &mut self.world {
            w.world.prime_contacts();
        }
        self.hull_angle = pose.hull.angle;
    }

    /// Build the world with the five bodies at `bodies` on the current terrain.
    fn place_bodies(&mut self, bodies: &[BodyState; 5]) {
        self.world = Some(match self.opts.engine {
            WalkerEngine::Rapier => {
                let ground = self.ground.as_ref().expect("place needs a terrain");
                Physics::Rapier(Box::new(World::build(&self.params, &self.opts, ground, bodies)))
            }
            WalkerEngine::Box2d => {
                let terrain = self.terrain.as_ref().expect("place needs a terrain");
                Physics::Box2d(Box::new(b2::Box2dWalker::build(&self.params, terrain, bodies)))
            }
        });
        self.hull_angle = bodies[0].angle;
    }

    /// The observation of the current state in f64 (Gymnasium's `state` list).
    fn state_f64(&self) -> [f64; OBS_DIM] {
        let mut s = [0.0; OBS_DIM];
        let Some(w) = &self.world else { return s };
        let p = &self.params;
        let b = w.body(0);
        let (q, dq) = w.joints();
        s[0] = self.hull_angle;
        s[1] = 2.0 * b.w / p.fps;
        s[2] = 0.3 * b.vx * (p.viewport_w / p.scale) / p.fps;
        s[3] = 0.3 * b.vy * (p.viewport_h / p.scale) / p.fps;
        for leg in 0..2 {
            let o = 4 + 5 * leg;
            s[o] = q[2 * leg];
            s[o + 1] = dq[2 * leg] / p.speed_hip;
            s[o + 2] = q[2 * leg + 1] + 1.0;
            s[o + 3] = dq[2 * leg + 1] / p.speed_knee;
            s[o + 4] = f64::from(u8::from(self.ground_contact[leg]));
        }
        if let Some(lidar) = self.lidar() {
            for (i, (_, _, f)) in lidar.iter().enumerate() {
                s[14 + i] = *f;
            }
        }
        s
    }

    /// Validate an action: 4 finite-or-NaN components (NaN means "motor off").
    fn parse_action(action: &Action) -> Result<[f64; 4], EnvError> {
        match action {
            Action::Continuous(v) if v.len() == 4 => Ok(std::array::from_fn(|i| {
                let a = v[i] as f64;
                if a.is_nan() { 0.0 } else { a }
            })),
            Action::Continuous(v) => Err(EnvError::ActionLength {
                env: ID,
                expected: 4,
                got: v.len(),
            }),
            Action::Discrete(_) => Err(EnvError::ActionKind {
                env: ID,
                expected: "continuous",
                got: "discrete",
            }),
        }
    }

    /// One Gymnasium step with a validated action, writing the observation (f64) to `obs`.
    /// Requires a world.
    fn advance(&mut self, a: &[f64; 4], obs: &mut [f64; OBS_DIM]) -> StepOutcome {
        match self.world.as_mut().expect("advance needs a world") {
            Physics::Rapier(_) => self.physics_step_rapier(a),
            Physics::Box2d(_) => self.physics_step_box2d(a),
        }
        self.finish_step(a, obs)
    }

    /// Gymnasium's motor settings: `motorSpeed = SPEED·sign(a)`, `maxMotorTorque =
    /// MOTORS_TORQUE·clip(|a|, 0, 1)`.
    fn motor(&self, j: usize, aj: f64) -> (f64, f64) {
        let p = &self.params;
        let speed = if j % 2 == 0 { p.speed_hip } else { p.speed_knee };
        let sign = if aj > 0.0 {
            1.0
        } else if aj < 0.0 {
            -1.0
        } else {
            0.0
        };
        (speed * sign, (p.motors_torque * aj.abs().clamp(0.0, 1.0)).max(0.0))
    }

    /// One `world.Step` on the Box2D engine; contact flags from its begin/end events in Box2D's
    /// order (Gymnasium's `ContactDetector`).
    fn physics_step_box2d(&mut self, a: &[f64; 4]) {
        let motors: [(f64, f64); 4] = std::array::from_fn(|j| self.motor(j, a[j]));
        let p = self.params;
        let Some(Physics::Box2d(w)) = self.world.as_mut() else {
            return;
        };
        for (j, (speed, torque)) in motors.into_iter().enumerate() {
            w.set_motor(j, speed, torque);
        }
        let dt = if p.fps > 0.0 && p.fps.is_finite() {
            1.0 / p.fps
        } else {
            0.0
        };
        w.world.step(dt, b2::VELOCITY_ITERATIONS, b2::POSITION_ITERATIONS);
        self.pending_force = false;
        for e in &w.world.events {
            if e.begin && e.involves(w.hull_fixture) {
                self.game_over = true;
            }
            for (flag, &leg) in self.ground_contact.iter_mut().zip(&w.lower_fixtures) {
                if e.involves(leg) {
                    *flag = e.begin;
                }
            }
        }
        // A hull resting on the ground in a state loaded by `set_state` (no begin event).
        if w.world.fixture_touches(w.hull_fixture) {
            self.game_over = true;
        }
        self.hull_angle = w.body_state(0).angle;
    }

    fn physics_step_rapier(&mut self, a: &[f64; 4]) {
        let p = self.params;
        let motors: [(f64, f64); 4] = std::array::from_fn(|j| self.motor(j, a[j]));
        let Some(Physics::Rapier(world)) = self.world.as_mut() else {
            return;
        };
        for (j, (speed, torque)) in motors.into_iter().enumerate() {
            if let Some(joint) = world.pw.impulse_joints.get_mut(world.joints[j], false) {
                joint
                    .data
                    .set_motor_velocity(JointAxis::AngX, speed as f32, MOTOR_DAMPING)
                    .set_motor_max_force(JointAxis::AngX, torque as f32);
            }
        }

        world.box2d_limits();
        let leg_start = world.lower_poses();
        world.pw.step();
        let dt = world.pw.integration_parameters.dt;
        if self.pending_force {
            world.pw.bodies[world.bodies[0]].reset_forces(false);
            self.pending_force = false;
        }
        for k in 0..5 {
            let b = &mut world.pw.bodies[world.bodies[k]];
            let mut v = b.linvel();
            let mut w = b.angvel();
            let tr = v.length() * dt;
            if tr > MAX_TRANSLATION && tr.is_finite() {
                v *= MAX_TRANSLATION / tr;
                b.set_linvel(v, false);
            }
            let r = w.abs() * dt;
            if r > MAX_ROTATION && r.is_finite() {
                w *= MAX_ROTATION / r;
                b.set_angvel(w, false);
            }
        }
        let mut landed = [false; 2];
        if let (Some(terrain), true) = (&self.terrain, self.opts.box2d_contacts) {
            let half = (0.8 * size(p.leg_w) / 2.0, size(p.leg_h) / 2.0);
            let mu = (0.2 * p.friction.max(0.0)).sqrt();
            for (leg, start) in leg_start.into_iter().enumerate() {
                landed[leg] = world.box2d_landing(terrain, leg, start, half, mu, dt as f64);
            }
        }
        let a_now = world.angle(0);
        self.hull_angle += wrap_pi(a_now - wrap_pi(self.hull_angle));
        if world.touching(world.hull_col) {
            self.game_over = true;
        }
        for (leg, landed) in landed.into_iter().enumerate() {
            let now = world.touched_pieces(world.lower_cols[leg]);
            self.listeners[leg].update(now, &mut self.ground_contact[leg]);
            // Box2D's TOI contact begins after the step's regular contact events.
            self.ground_contact[leg] |= landed;
        }
    }

    /// Observation, reward and termination after the physics step.
    fn finish_step(&mut self, a: &[f64; 4], obs: &mut [f64; OBS_DIM]) -> StepOutcome {
        let p = self.params;
        *obs = self.state_f64();
        let x = world_x(self.world.as_ref());
        let shaping = 130.0 * x / p.scale - 5.0 * obs[0].abs();
        let mut reward = match self.prev_shaping {
            Some(prev) => shaping - prev,
            None => 0.0,
        };
        self.prev_shaping = Some(shaping);
        for aj in a {
            reward -= 0.00035 * p.motors_torque * aj.abs().clamp(0.0, 1.0);
        }
        let mut terminated = false;
        if self.game_over || x < 0.0 {
            reward = -100.0;
            terminated = true;
        }
        if x > p.finish_x() {
            terminated = true;
        }
        StepOutcome {
            reward,
            terminated,
            truncated: false,
        }
    }

    fn write_obs(&self, obs: &mut [f32]) {
        write_f32(obs, &self.state_f64());
    }

    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        dist::uniform(&mut self.rng, lo, hi)
    }
}

fn write_f32(obs: &mut [f32], s: &[f64; OBS_DIM]) {
    for (o, s) in obs.iter_mut().zip(s) {
        *o = *s as f32;
    }
}

fn world_x(w: Option<&Physics>) -> f64 {
    w.map_or(0.0, |w| w.body(0).x)
}

impl crate::envs::runtime::Runtime for BipedalWalker {}

impl Env for BipedalWalker {
    fn id(&self) -> &'static str {
        ID
    }
    fn obs_dim(&self) -> usize {
        OBS_DIM
    }
    fn state_dim(&self) -> usize {
        STATE_DIM
    }
    fn observation_space(&self) -> Space {
        let pi = std::f32::consts::PI;
        let mut low = vec![
            -pi, -5.0, -5.0, -5.0, -pi, -5.0, -pi, -5.0, -0.0, -pi, -5.0, -pi, -5.0, -0.0,
        ];
        let mut high = vec![pi, 5.0, 5.0, 5.0, pi, 5.0, pi, 5.0, 5.0, pi, 5.0, pi, 5.0, 5.0];
        low.extend([-1.0; LIDAR_RAYS]);
        high.extend([1.0; LIDAR_RAYS]);
        Space::Box {
            low,
            high,
            shape: vec![OBS_DIM],
            dtype: DType::Float32,
        }
    }
    fn action_space(&self) -> Space {
        Space::Box {
            low: vec![-1.0; 4],
            high: vec![1.0; 4],
            shape: vec![4],
            dtype: DType::Float32,
        }
    }

    fn reset_into(&mut self, seed: Option<u64>, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(ID, obs, OBS_DIM)?;
        if let Some(seed) = seed {
            self.rng = rng_for(seed);
        }
        let terrain_seed = self.rng.next_u64() % TERRAIN_SEED_LIMIT;
        let spec = self.terrain_spec(terrain_seed);
        let terrain = Terrain::generate(spec);
        let ground = terrain.height_at(self.params.init_x());
        self.set_terrain(terrain);
        match self.opts.engine {
            WalkerEngine::Rapier => {
                let pose = self.start_pose(ground);
                self.place(&pose);
            }
            // Created where Gymnasium creates it: Box2D reassembles the legs.
            WalkerEngine::Box2d => self.place_bodies(&b2::gymnasium_start(&self.params)),
        }
        self.ground_contact = [false; 2];
        self.listeners = Default::default();
        self.game_over = false;
        self.prev_shaping = None;
        let ir = self.params.initial_random;
        let fx = self.uniform(-ir, ir);
        match self.world.as_mut() {
            Some(Physics::Rapier(w)) => w.pw.bodies[w.bodies[0]].add_force(v2(fx, 0.0), true),
            Some(Physics::Box2d(w)) => {
                let hull = w.bodies[0];
                w.world.bodies[hull].force.x += fx;
            }
            None => {}
        }
        self.pending_force = true;
        // Gymnasium's reset returns the observation of `step([0, 0, 0, 0])`.
        let mut o = [0.0; OBS_DIM];
        self.advance(&[0.0; 4], &mut o);
        write_f32(obs, &o);
        Ok(())
    }

    fn step_into(&mut self, action: &Action, obs: &mut [f32]) -> Result<StepOutcome, EnvError> {
        let a = Self::parse_action(action)?;
        check_obs_len(ID, obs, OBS_DIM)?;
        if self.world.is_none() {
            return Err(EnvError::NeedsReset { env: ID });
        }
        let mut o = [0.0; OBS_DIM];
        let out = self.advance(&a, &mut o);
        write_f32(obs, &o);
        Ok(out)
    }

    fn observe_into(&self, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(ID, obs, OBS_DIM)?;
        self.write_obs(obs);
        Ok(())
    }

    /// See the module docs for the layout.
    fn state(&self) -> Vec<f64> {
        self.state_array().to_vec()
    }

    fn set_state(&mut self, state: &[f64]) -> Result<(), EnvError> {
        let s = check_state::<STATE_DIM>(ID, state)?;
        self.load_state(&s);
        // Bookkeeping cleared as after a reset.
        self.game_over = false;
        Ok(())
    }

    fn render(&self) -> Option<crate::pixels::Frame> {
        render::render(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn piece(index: u32, subshape: u32, x: f32) -> TouchedPiece {
        TouchedPiece {
            collider: ColliderHandle::from_raw_parts(index, 0),
            subshape,
            x,
        }
    }

    #[test]
    fn contact_listener_follows_box2d_begin_and_end_events() {
        let mut l = ContactListener::default();
        let mut flag = false;
        // Landing on segment 3: begin.
        l.update(vec![piece(0, 3, 1.5)], &mut flag);
        assert!(flag);
        // Still on segment 3: no event, the flag stays.
        l.update(vec![piece(0, 3, 1.52)], &mut flag);
        assert!(flag);
        // Sliding onto segment 4 while leaving segment 3 in the same step: segment 4 begins,
        // segment 3 ends; the end (smaller x, reported last) clears the flag on the ground.
        l.update(vec![piece(0, 4, 1.9)], &mut flag);
        assert!(!flag);
        // Touching segment 5 as well: begin.
        l.update(vec![piece(0, 4, 1.95), piece(0, 5, 2.3)], &mut flag);
        assert!(flag);
        // Leaving segment 4 while 5 still touches: cleared (Gymnasium's ContactDetector).
        l.update(vec![piece(0, 5, 2.3)], &mut flag);
        assert!(!flag);
        // An obstacle (another collider) at the same subshape index is another piece.
        l.update(vec![piece(0, 5, 2.3), piece(7, 5, 2.4)], &mut flag);
        assert!(flag);
        // Lifting off everything: cleared.
        l.update(Vec::new(), &mut flag);
        assert!(!flag);
    }

    #[test]
    fn contact_listener_after_set_state_keeps_the_loaded_flag() {
        for loaded in [false, true] {
            let mut l = ContactListener::baseline();
            let mut flag = loaded;
            l.update(vec![piece(0, 3, 1.5)], &mut flag);
            assert_eq!(flag, loaded, "the first contacts are the baseline, not events");
            l.update(Vec::new(), &mut flag);
            assert!(!flag, "ending a baseline contact is an event");
        }
    }
}
