//! BipedalWalker-v3 (Gymnasium 1.4 `BipedalWalker`) with CARL's 20 context features, on
//! [`carl_physics2d`] (Box2D 2.3's solver semantics).
//!
//! **Physics** (`b2.rs`): the world is built as Gymnasium builds it (terrain obstacles, one
//! static body per surface edge, hull, then per leg upper leg, lower leg, hip, knee; the legs
//! created apart from their anchors, as Gymnasium's `reset` does, and reassembled by the position
//! solver in the first steps) and stepped with `Step(1/FPS, 6·30, 2·30)`. The contact flags and
//! game over follow Box2D's begin/end contact events in Box2D's order, including those of
//! continuous collision. After `set_state` the contacts touching at the loaded pose are the
//! baseline (no events); the warm-start impulses are not part of the state. Not modelled: Box2D's
//! sleeping (Gymnasium wakes the walker every step by setting its motors) and f32 arithmetic.
//! (A former rapier2d engine, which had to emulate Box2D's joint limits, landings and start pose,
//! was removed: CHANGELOG.md, "BipedalWalker".)
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
//! Where this is not Box2D:
//! * **Lidar.** Exact ray/segment intersection against the generated terrain (surface edges and
//!   obstacle sides) in f64, instead of Box2D's f32 `RayCast`; like Box2D's polygon ray cast, an
//!   obstacle whose inside contains the ray origin is not reported.
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
//! roughness `SCALE`, hardcore flag; a `TERRAIN_LENGTH` above [`MAX_TERRAIN_LENGTH`] is refused,
//! at `make` as in `set_state`). The course is regenerated from its record, so it does not
//! depend on the context `set_state` is called under (the terrain features act at reset, when the
//! course is generated, and on the finish line); physical properties (friction, shapes, masses,
//! gravity, motors) come from the context. `set_state` rebuilds the world assembled from the
//! joint angles: the solver's small joint separations and its warm-start impulses are not part
//! of the state.

mod b2;
pub mod heuristic;
mod render;
pub mod terrain;

use carl_env::api::{Action, DType, Env, EnvError, Space, StepOutcome, check_obs_len, check_state, context_features};
use carl_spec_core::sampling::{Pcg64, dist};
pub use heuristic::WalkerHeuristic;
pub use terrain::{Obstacle, Terrain, TerrainSpec};

const ID: &str = "bipedal_walker";

/// Hull outline in pixels (Gymnasium's `HULL_POLY`).
pub const HULL_POLY: [(f64, f64); 5] = [(-30.0, 9.0), (6.0, 9.0), (34.0, 1.0), (34.0, -8.0), (-30.0, -8.0)];
/// Hip joint limits (rad), on the joint angle (measured from [`HIP_REFERENCE`]).
pub const HIP_LIMITS: [f64; 2] = [-0.8, 1.1];
/// Reference angles of the two hips (rad): Gymnasium creates the upper legs at `i·0.05` rad
/// (`i = −1, +1`) and pybox2d's `revoluteJointDef` sets `referenceAngle = angleB − angleA` at
/// creation, so a hip's joint angle (observation, limits) is the upper leg's angle relative to
/// the hull minus `i·0.05`: leg 0 really stands 0.05 rad further back and leg 1 0.05 rad further
/// forward than their joint angles say (measured with Gymnasium 1.4). The knees' reference angles
/// are 0.
pub const HIP_REFERENCE: [f64; 2] = [-0.05, 0.05];
/// Knee joint limits (rad).
pub const KNEE_LIMITS: [f64; 2] = [-1.6, -0.1];
/// Number of lidar rays.
pub const LIDAR_RAYS: usize = 10;
/// Observation length.
pub const OBS_DIM: usize = 24;
/// Length of [`BipedalWalker::state`] (see the module docs).
pub const STATE_DIM: usize = 27;
/// Seeds of the terrain stream are below this (exact in an f64 state component).
const TERRAIN_SEED_LIMIT: u64 = 1 << 53;
/// The longest course the runtime builds (`TERRAIN_LENGTH` steps), even with out-of-bounds
/// values allowed (the spec's bound is 500): every step is a static edge in the physics world,
/// and each physics step tests the walker's fixtures against all of them, so a longer course
/// costs memory and time in proportion without being a different task. `make` refuses a
/// longer one, and so does `set_state`.
pub const MAX_TERRAIN_LENGTH: usize = 10_000;

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

/// Options that are not context features.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BipedalWalkerOptions {
    /// `BipedalWalkerHardcore`: stumps, stairs and pits between grass stretches.
    pub hardcore: bool,
    /// Draw the 10 lidar rays (up to their hits) in `render`.
    pub render_lidar: bool,
}

impl Default for BipedalWalkerOptions {
    fn default() -> Self {
        BipedalWalkerOptions {
            hardcore: false,
            render_lidar: true,
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

/// Gymnasium's `BipedalWalker` with an explicit context; each instance owns its physics world.
/// A clone continues exactly as the original: the world is a plain value.
#[derive(Debug, Clone)]
pub struct BipedalWalker {
    params: BipedalWalkerParams,
    opts: BipedalWalkerOptions,
    world: Option<Box<b2::Box2dWalker>>,
    terrain: Option<Terrain>,
    /// Unwrapped hull angle (Box2D keeps angles continuous).
    hull_angle: f64,
    ground_contact: [bool; 2],
    game_over: bool,
    prev_shaping: Option<f64>,
    rng: Pcg64,
}

fn rng_for(seed: u64) -> Pcg64 {
    Pcg64::new(seed, carl_spec_core::sampling::stream_id(ID))
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
            hull_angle: 0.0,
            ground_contact: [false; 2],
            game_over: false,
            prev_shaping: None,
            rng: rng_for(carl_env::rng::DEFAULT_SEED),
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
            let mut b = w.body_state(k);
            if k == 0 {
                b.angle = self.hull_angle;
            }
            b
        }))
    }
    /// Hull mass (kg) as the physics engine computed it.
    pub fn hull_mass(&self) -> Option<f64> {
        Some(self.world.as_ref()?.mass(0))
    }

    /// The lidar's end points `(p1, p2)` and fractions for the current hull position.
    pub fn lidar(&self) -> Option<[LidarRay; LIDAR_RAYS]> {
        let (w, t) = (self.world.as_ref()?, self.terrain.as_ref()?);
        let hull = w.body_state(0);
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
            length: int(p.terrain_length).clamp(2, MAX_TERRAIN_LENGTH as i64) as usize,
            height: p.terrain_height,
            grass: int(p.terrain_grass),
            startpad: int(p.terrain_startpad),
            scale: p.scale,
            hardcore: self.opts.hardcore,
        }
    }

    fn current_pose(&self) -> Pose {
        let Some(w) = &self.world else { return Pose::default() };
        let (q, dq) = w.joints();
        Pose {
            hull: BodyState {
                angle: self.hull_angle,
                ..w.body_state(0)
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
            length: int(t[2], 2.0, MAX_TERRAIN_LENGTH as f64) as usize,
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
        self.game_over = s[16] != 0.0;
        self.prev_shaping = (s[17] != 0.0).then_some(s[18]);
    }

    fn set_terrain(&mut self, terrain: Terrain) {
        self.terrain = Some(terrain);
    }

    /// Build the world with the walker at `pose` on the current terrain.
    fn place(&mut self, pose: &Pose) {
        let bodies = pose.bodies(&self.params);
        self.place_bodies(&bodies);
        if let Some(w) = &mut self.world {
            // The contacts touching at the loaded pose are the next step's baseline, not events.
            w.world.prime_contacts();
        }
        self.hull_angle = pose.hull.angle;
    }

    /// Build the world with the five bodies at `bodies` on the current terrain.
    fn place_bodies(&mut self, bodies: &[BodyState; 5]) {
        let terrain = self.terrain.as_ref().expect("place needs a terrain");
        self.world = Some(Box::new(b2::Box2dWalker::build(&self.params, terrain, bodies)));
        self.hull_angle = bodies[0].angle;
    }

    /// The observation of the current state in f64 (Gymnasium's `state` list).
    fn state_f64(&self) -> [f64; OBS_DIM] {
        let mut s = [0.0; OBS_DIM];
        let Some(w) = &self.world else { return s };
        let p = &self.params;
        let b = w.body_state(0);
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

    /// Validate an action: 4 finite components (NaN or ±inf is refused, naming the component).
    fn parse_action(action: &Action) -> Result<[f64; 4], EnvError> {
        match action {
            Action::Continuous(v) if v.len() == 4 => {
                carl_env::api::check_finite_action(ID, v)?;
                Ok(std::array::from_fn(|i| f64::from(v[i])))
            }
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
        self.physics_step(a);
        self.finish_step(a, obs)
    }

    /// Gymnasium's motor settings: `motorSpeed = SPEED·sign(a)`, `maxMotorTorque =
    /// MOTORS_TORQUE·clip(|a|, 0, 1)`.
    fn motor(&self, j: usize, aj: f64) -> (f64, f64) {
        let p = &self.params;
        let speed = if j.is_multiple_of(2) { p.speed_hip } else { p.speed_knee };
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
    fn physics_step(&mut self, a: &[f64; 4]) {
        let motors: [(f64, f64); 4] = std::array::from_fn(|j| self.motor(j, a[j]));
        let p = self.params;
        let Some(w) = self.world.as_mut() else {
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

    /// Observation, reward and termination after the physics step.
    fn finish_step(&mut self, a: &[f64; 4], obs: &mut [f64; OBS_DIM]) -> StepOutcome {
        let p = self.params;
        *obs = self.state_f64();
        let x = world_x(self.world.as_deref());
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

fn world_x(w: Option<&b2::Box2dWalker>) -> f64 {
    w.map_or(0.0, |w| w.body_state(0).x)
}

impl carl_env::runtime::Runtime for BipedalWalker {}

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
        self.set_terrain(Terrain::generate(spec));
        // Created where Gymnasium creates it: Box2D reassembles the legs.
        self.place_bodies(&b2::gymnasium_start(&self.params));
        self.ground_contact = [false; 2];
        self.game_over = false;
        self.prev_shaping = None;
        let ir = self.params.initial_random;
        let fx = self.uniform(-ir, ir);
        if let Some(w) = self.world.as_mut() {
            // Box2D clears forces after each step: the push acts during the first step only.
            let hull = w.bodies[0];
            w.world.bodies[hull].force.x += fx;
        }
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
        if s[21] > MAX_TERRAIN_LENGTH as f64 {
            return Err(EnvError::Context {
                env: ID,
                message: format!(
                    "state component 21 (the course's TERRAIN_LENGTH) = {} is more than this runtime builds (at most {MAX_TERRAIN_LENGTH})",
                    s[21]
                ),
            });
        }
        self.load_state(&s);
        // Bookkeeping cleared as after a reset.
        self.game_over = false;
        Ok(())
    }

    /// After the step that ended the episode: `fell` (the hull touched the ground, or the walker
    /// left the course backwards; reward -100) or `solved` (it reached the course's end).
    fn outcome(&self) -> Option<&'static str> {
        self.world.as_ref()?;
        let x = world_x(self.world.as_deref());
        if self.game_over || x < 0.0 {
            Some("fell")
        } else if x > self.params.finish_x() {
            Some("solved")
        } else {
            None
        }
    }

    fn render(&self) -> Option<carl_pixels::Frame> {
        render::render(self)
    }
}
