//! LunarLander-v3 (Gymnasium 1.4 `LunarLander`) on Box2D's semantics, with CARL's 16 context
//! features.
//!
//! Same as Gymnasium: the lander polygon, leg boxes, densities (5 and 1), friction (0.1 lander
//! and terrain, 0.2 legs and the bottom edge, combined as Box2D does with the geometric mean),
//! restitution 0, collision filtering (lander and legs collide only with the ground), the leg
//! revolute joints (anchors, reference angle, limits, motor speed ±0.3, max torque
//! `LEG_SPRING_TORQUE`), random terrain of 11 chunks with a flat helipad (including Python's
//! `height[-1]` wrap in the smoothing), the random initial force `±INITIAL_RANDOM`, the engine
//! impulses applied at points with the two dispersion draws per step, the 8-dimensional
//! observation and its normalisation, the potential-based shaping reward with fuel costs
//! 0.3/0.03, and termination by crash (a contact of the lander body begins), out-of-view
//! (`|x| >= 1`) or rest ("not awake", +100). Like Gymnasium's `reset`, ours ends with one
//! `step(noop)` whose observation it returns.
//!
//! **Two ways to step, both Box2D's.**
//! * *Where the lander is one rigid body* (`rigid`), in closed form. Gymnasium creates the legs
//!   unassembled (beside the lander, turned 0.05 rad, their anchors `LEG_DOWN` too high); Box2D's
//!   first step moves lander and legs as one rigid body at the legs' creation geometry (so the
//!   random push spins the lander about −0.113 rad/s per m/s of sideways push) and then snaps the
//!   legs onto their joints ~0.14 rad wide, from where the motors swing them in at 0.3 rad/s.
//!   That step and all free flight (every step in which no body can reach the ground within two
//!   steps' travel) are computed as Box2D's converged solver has them: lander and legs keep their
//!   total momentum, the legs turn at their motors' speed. This is what makes 64 landers several
//!   times faster than envpool's Box2D.
//! * *Near the ground*, [`carl_physics2d`]: sequential impulses with Gymnasium's
//!   `world.Step(1/FPS, 6*30, 2*30)`, Box2D's contact manifolds, skins, block solver, leg motors
//!   pressed into their limits, position correction and per-step motion caps. The contact
//!   flags and the crash follow the solver's begin/end contact events in Box2D's order, as
//!   Gymnasium's `ContactDetector` sees them. Joint warm-start impulses start from zero when the
//!   solver takes over from a flight (a world rebuilt from the state would do the same).
//!
//! Gymnasium's heuristic flies the same trajectory as in Box2D to 3 mm until the touchdown
//! (`tests/lunar_lander.rs`, against `tests/fixtures/lunar_lander_flight_box2d.json`) and,
//! seeds 0–49 per body with Gymnasium's own terrains, lands 94 % on Earth (Gymnasium: 92 %),
//! 96 % on Mars (96 %), 76 % on the Moon (78 %), 32 % on Pluto (34 %), 74 % on Neptune (80 %,
//! crashing 18 % against 12 %) and crashes 100 % on Jupiter (100 %); 289 of those 300 episodes
//! end as in Box2D.
//!
//! **Rest ("not awake").** Box2D's island sleep test, evaluated here (the solver does not
//! sleep): the lander is at rest once the lander and both legs have been slower than 0.01 m/s
//! and 2 °/s for 0.5 s (`b2_linearSleepTolerance`, `b2_angularSleepTolerance`,
//! `b2_timeToSleep`).
//!
//! A flight step clears the legs' ground flags: its bodies start more than 5 cm from the ground,
//! where Box2D's contact update at the start of the step ends every contact too. Where this is
//! not Box2D: Box2D computes in `f32`, this in `f64`.

mod render;
mod rigid;

use carl_physics2d::{self as b2, BodyKind, Filter, FixtureDef, Polygon, RevoluteDef, Shape, V2, v2};

use carl_env::api::{Action, DType, Env, EnvError, Space, StepOutcome, check_obs_len, check_state, context_features};
use carl_env::rng::{self, EnvRng};

const ID: &str = "lunar_lander";

/// Lander outline in pixels (Gymnasium's `LANDER_POLY`).
pub const LANDER_POLY: [(f64, f64); 6] = [
    (-14.0, 17.0),
    (-17.0, 0.0),
    (-17.0, -10.0),
    (17.0, -10.0),
    (17.0, 0.0),
    (14.0, 17.0),
];
/// Main engine's distance below the lander origin, px (`MAIN_ENGINE_Y_LOCATION`).
pub const MAIN_ENGINE_Y_LOCATION: f64 = 4.0;
/// Terrain chunks (`CHUNKS`).
pub const CHUNKS: usize = 11;
/// Box2D's sleep criterion (b2Settings.h, 2.3): a body is still below these speeds.
pub const LINEAR_SLEEP_TOLERANCE: f64 = 0.01;
pub const ANGULAR_SLEEP_TOLERANCE: f64 = 2.0 / 180.0 * std::f64::consts::PI;
/// Box2D's `b2_timeToSleep`: how long an island must be still before it sleeps.
pub const TIME_TO_SLEEP: f64 = 0.5;
/// Length of [`LunarLander::state`]: 11 terrain heights, 3 bodies × (x, y, angle, vx, vy, ω),
/// 2 leg contacts, game-over flag, rest time, has-previous-shaping flag, previous shaping.
pub const STATE_DIM: usize = CHUNKS + 18 + 6;

/// LunarLander context (CARL's 16 features). `Default` is Gymnasium's module constants with
/// CARL's default gravity (0, -10).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LunarLanderParams {
    pub fps: f64,
    pub scale: f64,
    pub main_engine_power: f64,
    pub side_engine_power: f64,
    pub initial_random: f64,
    pub gravity_x: f64,
    pub gravity_y: f64,
    pub leg_away: f64,
    pub leg_down: f64,
    pub leg_w: f64,
    pub leg_h: f64,
    pub leg_spring_torque: f64,
    pub side_engine_height: f64,
    pub side_engine_away: f64,
    pub viewport_w: f64,
    pub viewport_h: f64,
}

impl Default for LunarLanderParams {
    fn default() -> Self {
        LunarLanderParams {
            fps: 50.0,
            scale: 30.0,
            main_engine_power: 13.0,
            side_engine_power: 0.6,
            initial_random: 1000.0,
            gravity_x: 0.0,
            gravity_y: -10.0,
            leg_away: 20.0,
            leg_down: 18.0,
            leg_w: 2.0,
            leg_h: 8.0,
            leg_spring_torque: 40.0,
            side_engine_height: 14.0,
            side_engine_away: 12.0,
            viewport_w: 600.0,
            viewport_h: 400.0,
        }
    }
}

context_features!(LunarLanderParams, "lunar_lander", {
    fps: "FPS",
    scale: "SCALE",
    main_engine_power: "MAIN_ENGINE_POWER",
    side_engine_power: "SIDE_ENGINE_POWER",
    initial_random: "INITIAL_RANDOM",
    gravity_x: "GRAVITY_X",
    gravity_y: "GRAVITY_Y",
    leg_away: "LEG_AWAY",
    leg_down: "LEG_DOWN",
    leg_w: "LEG_W",
    leg_h: "LEG_H",
    leg_spring_torque: "LEG_SPRING_TORQUE",
    side_engine_height: "SIDE_ENGINE_HEIGHT",
    side_engine_away: "SIDE_ENGINE_AWAY",
    viewport_w: "VIEWPORT_W",
    viewport_h: "VIEWPORT_H",
});

impl LunarLanderParams {
    /// World width in metres (`VIEWPORT_W / SCALE`).
    pub fn world_w(&self) -> f64 {
        self.viewport_w / self.scale
    }
    /// World height in metres (`VIEWPORT_H / SCALE`).
    pub fn world_h(&self) -> f64 {
        self.viewport_h / self.scale
    }
    /// Helipad height (`H / 4`).
    pub fn helipad_y(&self) -> f64 {
        self.world_h() / 4.0
    }
}

/// Options that are not context features.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LunarLanderOptions {
    /// `LunarLanderContinuous`: actions are `[main, lateral]` in `[-1, 1]`.
    pub continuous: bool,
    /// Reward on crash / out of view is `-crash_penalty` (Gymnasium: 100; CARL's evaluation
    /// in the paper: 10000).
    pub crash_penalty: f64,
}

impl Default for LunarLanderOptions {
    fn default() -> Self {
        LunarLanderOptions {
            continuous: false,
            crash_penalty: 100.0,
        }
    }
}

/// How the last step ended (for evaluation statistics).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    Running,
    /// Came to rest (+100).
    Landed,
    /// Lander body touched the ground.
    Crashed,
    /// `|x| >= 1`.
    OutOfView,
}

impl Outcome {
    /// Every ending with its name as [`Env::outcome`] reports it.
    const NAMED: [(Outcome, &'static str); 3] = [
        (Outcome::Landed, "landed"),
        (Outcome::Crashed, "crashed"),
        (Outcome::OutOfView, "out_of_view"),
    ];

    /// The outcome's name as [`Env::outcome`] reports it (`None` while running).
    pub fn name(self) -> Option<&'static str> {
        Self::NAMED.iter().find(|(o, _)| *o == self).map(|(_, n)| *n)
    }

    /// The ending [`Outcome::name`] names (`None` for other words, e.g. `timed_out`).
    pub fn from_name(name: &str) -> Option<Outcome> {
        Self::NAMED.iter().find(|(_, n)| *n == name).map(|(o, _)| *o)
    }
}

/// Kinematic state of one body: origin position, (unwrapped) angle, COM velocity, ω.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct BodyState {
    x: f64,
    y: f64,
    angle: f64,
    vx: f64,
    vy: f64,
    w: f64,
}

/// Gymnasium's `world.Step(1/FPS, 6*30, 2*30)`.
const VELOCITY_ITERATIONS: usize = 180;
const POSITION_ITERATIONS: usize = 60;

#[derive(Debug, Clone)]
struct World {
    b2: b2::World,
    dt: f64,
    /// Body indices: lander, leg 0, leg 1 (Gymnasium's creation order after the ground).
    bodies: [usize; 3],
    lander_fixture: usize,
    leg_fixtures: [usize; 2],
    joints: [usize; 2],
    /// The legs' joints and how their motors drive them, for [`rigid`]'s steps.
    leg_joints: [rigid::LegJoint; 2],
    leg_drive: rigid::LegDrive,
    /// Whether the last step was the solver's (its contacts and warm-start impulses are current).
    solver_stepped: bool,
    /// The ground as segments `[x1, y1, x2, y2]` (bottom edge and terrain chunks).
    ground: [[f64; 4]; CHUNKS],
    /// Radius of each body (lander, legs) around its centre of mass, skin included.
    radii: [f64; 3],
}

/// Where the closed-form flight holds a leg pressed into its inner joint limit, as the angle
/// between leg and lander. Gymnasium's limit is 0.4 rad of *joint* angle, measured from the
/// creation angle (`LEG_CREATION_ANGLE`, the joint's reference angle), i.e. 0.35 rad between
/// the bodies; the motor presses the leg a little past it. Measured in Gymnasium 1.4: 0.349 rad
/// at 50 FPS, 0.340 at 25 FPS, whatever the gravity or spring torque.
const LEG_REST_ANGLE: f64 = 0.345;
/// Gymnasium creates leg `i` (−1, +1) turned `i · 0.05` rad from the lander; the joint's
/// reference angle.
const LEG_CREATION_ANGLE: f64 = 0.05;
/// Gymnasium's joint limits for leg `i` (−1, +1), in joint angle (from the reference angle).
fn joint_limits(i: f64) -> (f64, f64) {
    if i < 0.0 { (0.4, 0.9) } else { (-0.9, -0.4) }
}
/// Leg `i`'s limits as angles between leg and lander for the closed-form flight: Gymnasium's,
/// with the inner one where Box2D holds the leg (see [`LEG_REST_ANGLE`]).
fn leg_limits(i: f64) -> (f64, f64) {
    let outer = 0.9 - LEG_CREATION_ANGLE;
    if i < 0.0 {
        (LEG_REST_ANGLE, outer)
    } else {
        (-outer, -LEG_REST_ANGLE)
    }
}

/// Gymnasium's leg motor speed (`motorSpeed = +0.3 * i`), rad/s: in flight, a leg wider than its
/// rest angle swings in at this speed (after the first step, or after a bounce).
const LEG_SWING_SPEED: f64 = 0.3;
const GROUND_CATEGORY: u16 = 0x0001;
const LANDER_CATEGORY: u16 = 0x0010;
const LEG_CATEGORY: u16 = 0x0020;

/// Shape sizes are floored at 1e-4 m so that out-of-bounds contexts cannot make degenerate shapes.
fn size(x: f64) -> f64 {
    x.max(1e-4)
}

impl World {
    /// Build the world for `params` with terrain `smooth_y` and the three bodies' states, in
    /// Gymnasium's creation order (ground, lander, leg −1 and its joint, leg +1 and its joint).
    fn build(p: &LunarLanderParams, smooth_y: &[f64; CHUNKS], bodies: &[BodyState; 3]) -> World {
        let mut b2 = b2::World::new(v2(p.gravity_x, p.gravity_y));
        let dt = if p.fps > 0.0 && p.fps.is_finite() {
            1.0 / p.fps
        } else {
            0.0
        };
        let w = p.world_w();
        let mut ground = [[0.0, 0.0, w, 0.0]; CHUNKS];
        for i in 0..CHUNKS - 1 {
            let x = |j: usize| w / (CHUNKS - 1) as f64 * j as f64;
            ground[1 + i] = [x(i), smooth_y[i], x(i + 1), smooth_y[i + 1]];
        }
        // The moon: a static body with the bottom edge (Box2D's default friction 0.2) and the
        // ten chunk edges (friction 0.1).
        let moon = b2.add_body(BodyKind::Static, V2::ZERO, 0.0);
        for (k, &[x1, y1, x2, y2]) in ground.iter().enumerate() {
            b2.add_fixture(
                moon,
                FixtureDef {
                    shape: Shape::Edge(v2(x1, y1), v2(x2, y2)),
                    density: 0.0,
                    friction: if k == 0 { 0.2 } else { 0.1 },
                    restitution: 0.0,
                    filter: Filter {
                        category: GROUND_CATEGORY,
                        mask: 0xFFFF,
                    },
                },
            );
        }
        let s = size(p.scale);
        let pts: Vec<V2> = LANDER_POLY.iter().map(|&(x, y)| v2(x / s, y / s)).collect();
        let hull = Polygon::from_points(&pts).unwrap_or_else(|_| Polygon::new_box(0.5, 0.5));
        let dynamic =
            |b2: &mut b2::World, st: &BodyState, shape: Polygon, density: f64, friction: f64, category: u16| {
                let def = FixtureDef {
                    shape: Shape::Polygon(shape),
                    density,
                    friction,
                    restitution: 0.0,
                    filter: Filter {
                        category,
                        mask: GROUND_CATEGORY,
                    },
                };
                b2.add_dynamic(v2(st.x, st.y), st.angle, v2(st.vx, st.vy), st.w, def)
            };
        let (lander, lander_fixture) = dynamic(&mut b2, &bodies[0], hull, 5.0, 0.1, LANDER_CATEGORY);
        let leg_box = Polygon::new_box(size(p.leg_w / s), size(p.leg_h / s));
        let mut legs = [lander; 2];
        let mut leg_fixtures = [lander_fixture; 2];
        let mut joints = [0; 2];
        for (k, i) in [-1.0f64, 1.0].into_iter().enumerate() {
            (legs[k], leg_fixtures[k]) = dynamic(&mut b2, &bodies[1 + k], leg_box, 1.0, 0.2, LEG_CATEGORY);
            let (lower, upper) = joint_limits(i);
            joints[k] = b2.add_revolute(RevoluteDef {
                body_a: lander,
                body_b: legs[k],
                local_anchor_a: V2::ZERO,
                local_anchor_b: v2(i * p.leg_away / s, p.leg_down / s),
                reference_angle: i * LEG_CREATION_ANGLE,
                enable_limit: true,
                lower,
                upper,
                enable_motor: true,
                motor_speed: LEG_SWING_SPEED * i,
                max_motor_torque: p.leg_spring_torque.max(0.0),
            });
        }
        let bodies_ix = [lander, legs[0], legs[1]];
        let radii = [lander_fixture, leg_fixtures[0], leg_fixtures[1]].map(|f| {
            let fx = &b2.fixtures[f];
            let c = b2.bodies[fx.body].sweep.local_center;
            let r = match fx.def.shape {
                Shape::Polygon(poly) => poly.vertices().iter().map(|v| (*v - c).length()).fold(0.0, f64::max),
                Shape::Edge(..) => 0.0,
            };
            r + fx.def.shape.radius()
        });
        World {
            b2,
            dt,
            bodies: bodies_ix,
            lander_fixture,
            leg_fixtures,
            joints,
            leg_joints: [-1.0f64, 1.0].map(|i| rigid::LegJoint {
                anchor_lander: [0.0, 0.0],
                anchor_leg: [i * p.leg_away / s, p.leg_down / s],
                limits: leg_limits(i),
            }),
            leg_drive: rigid::LegDrive {
                limit: [
                    joint_limits(-1.0).0 - LEG_CREATION_ANGLE,
                    joint_limits(1.0).1 + LEG_CREATION_ANGLE,
                ],
                swing_speed: LEG_SWING_SPEED,
                max_torque: p.leg_spring_torque.max(0.0),
            },
            solver_stepped: false,
            ground,
            radii,
        }
    }

    fn body(&self, k: usize) -> &b2::Body {
        &self.b2.bodies[self.bodies[k]]
    }

    /// Lander, leg 0 and leg 1 as plain rigid bodies (for [`rigid`]).
    fn rigid_bodies(&self) -> [rigid::Body; 3] {
        [0, 1, 2].map(|k| {
            let b = self.body(k);
            let lc = b.sweep.local_center;
            rigid::Body {
                com: [b.sweep.c.x, b.sweep.c.y],
                angle: b.sweep.a,
                mass: b.mass,
                inertia: b.inertia,
                local_com: [lc.x, lc.y],
                vel: [b.v.x, b.v.y],
                w: b.w,
            }
        })
    }

    /// Writes [`rigid`]'s results back into the bodies and their broad-phase boxes.
    fn set_rigid_bodies(&mut self, bodies: &[rigid::Body; 3]) {
        for (k, b) in bodies.iter().enumerate() {
            let ix = self.bodies[k];
            let body = &mut self.b2.bodies[ix];
            let (sn, cs) = b.angle.sin_cos();
            let lc = b.local_com;
            let origin = v2(
                b.com[0] - (cs * lc[0] - sn * lc[1]),
                b.com[1] - (sn * lc[0] + cs * lc[1]),
            );
            body.set_transform(origin, b.angle);
            body.v = v2(b.vel[0], b.vel[1]);
            body.w = b.w;
            self.b2.synchronize_fixtures(ix);
        }
        self.b2.find_new_contacts();
    }

    /// Whether no body can reach the ground within two steps: each body's bounding circle is
    /// farther from every ground segment than twice its fastest point moves in a step, plus a
    /// margin. Then nothing touches, and free flight applies.
    fn airborne(&self) -> bool {
        (0..3).all(|k| {
            let (b, r) = (self.body(k), self.radii[k]);
            let (cx, cy) = (b.sweep.c.x, b.sweep.c.y);
            let speed = b.v.length() + b.w.abs() * r;
            let margin = r + 2.0 * speed * self.dt + 0.05;
            self.ground.iter().all(|&[x1, y1, x2, y2]| {
                let (dx, dy) = (x2 - x1, y2 - y1);
                let len2 = dx * dx + dy * dy;
                let t = if len2 > 0.0 {
                    (((cx - x1) * dx + (cy - y1) * dy) / len2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let (ex, ey) = (cx - x1 - t * dx, cy - y1 - t * dy);
                ex * ex + ey * ey > margin * margin
            })
        })
    }

    /// One step: Box2D's first step when `initial_force` is given, free flight in closed form
    /// where it applies (see [`rigid`]), the Box2D-semantics solver otherwise. Returns whether
    /// the solver stepped (its contact events are only current then; in flight there are none).
    fn step(&mut self, initial_force: Option<[f64; 2]>) -> bool {
        let mut bodies = self.rigid_bodies();
        let gravity = [self.b2.gravity.x, self.b2.gravity.y];
        let closed_form = match initial_force {
            Some(force) => {
                rigid::first_step(&mut bodies, &self.leg_joints, &self.leg_drive, force, gravity, self.dt);
                true
            }
            None => {
                self.airborne() && rigid::flight_step(&mut bodies, &self.leg_joints, &self.leg_drive, gravity, self.dt)
            }
        };
        if closed_form {
            self.set_rigid_bodies(&bodies);
            // In flight nothing touches: contacts Box2D would have ended (without events here:
            // the legs' flags are cleared by the caller).
            for c in &mut self.b2.contacts {
                c.touching = false;
                c.manifold = Default::default();
            }
            self.solver_stepped = false;
            return false;
        }
        if !self.solver_stepped {
            // The joints' warm-start impulses are from before the flight: start afresh, as a
            // world rebuilt from this state would.
            for &j in &self.joints {
                let joint = &mut self.b2.joints[j];
                joint.impulse = [0.0; 3];
                joint.motor_impulse = 0.0;
            }
        }
        self.b2.step(self.dt, VELOCITY_ITERATIONS, POSITION_ITERATIONS);
        self.solver_stepped = true;
        true
    }

    fn body_state(&self, k: usize) -> BodyState {
        let b = self.body(k);
        BodyState {
            x: b.xf.p.x,
            y: b.xf.p.y,
            angle: b.sweep.a,
            vx: b.v.x,
            vy: b.v.y,
            w: b.w,
        }
    }

    /// Applies Gymnasium's `ApplyLinearImpulse(impulse, point)` to the lander.
    fn lander_impulse(&mut self, impulse: V2, point: V2) {
        let b = &mut self.b2.bodies[self.bodies[0]];
        b.v += b.inv_mass * impulse;
        b.w += b.inv_inertia * (point - b.sweep.c).cross(impulse);
    }
}

/// The bodies as Gymnasium's `reset` creates them: lander at `(W/2, H)`, each leg at the
/// lander's height, `LEG_AWAY` to the side and turned `i · 0.05` rad, its joint anchor
/// `LEG_DOWN` above the lander's; the first step assembles them ([`rigid::first_step`]).
fn creation_bodies(p: &LunarLanderParams) -> [BodyState; 3] {
    let (x0, y0) = (p.world_w() / 2.0, p.world_h());
    let mut out = [BodyState {
        x: x0,
        y: y0,
        ..Default::default()
    }; 3];
    for (k, i) in [-1.0f64, 1.0].into_iter().enumerate() {
        out[1 + k] = BodyState {
            x: x0 - i * p.leg_away / p.scale,
            y: y0,
            angle: i * LEG_CREATION_ANGLE,
            ..Default::default()
        };
    }
    out
}

/// Gymnasium's `LunarLander` with an explicit context; each instance owns its world (a clone
/// copies it exactly, solver warm-start impulses included).
#[derive(Debug, Clone)]
pub struct LunarLander {
    params: LunarLanderParams,
    opts: LunarLanderOptions,
    world: Option<World>,
    smooth_y: [f64; CHUNKS],
    leg_contact: [bool; 2],
    game_over: bool,
    rest_time: f64,
    prev_shaping: Option<f64>,
    /// Gymnasium's random push at reset, acting during the first step only (Box2D clears
    /// forces); that step assembles the legs ([`rigid::first_step`]).
    initial_force: Option<[f64; 2]>,
    outcome: Outcome,
    /// Engine powers of the last step `(main, side direction, side)`, for rendering flames.
    last_engines: (f64, f64, f64),
    /// NumPy's generator, seeded as Gymnasium's `np_random` (same terrain and pushes per seed).
    rng: EnvRng,
}

/// Gymnasium's `np_random` after `reset(seed=seed)`: the terrain, the initial push and every
/// step's engine dispersion are drawn in Gymnasium's order, so a seed gives Gymnasium's episode
/// start exactly (`tests/lunar_lander.rs` checks the terrain against Box2D's).
fn rng_for(seed: u64) -> EnvRng {
    EnvRng::from_seed(seed)
}

impl Default for LunarLander {
    fn default() -> Self {
        LunarLander::new(LunarLanderParams::default())
    }
}

impl LunarLander {
    pub fn new(params: LunarLanderParams) -> Self {
        Self::with_options(params, LunarLanderOptions::default())
    }

    pub fn with_options(params: LunarLanderParams, opts: LunarLanderOptions) -> Self {
        LunarLander {
            params,
            opts,
            world: None,
            smooth_y: [0.0; CHUNKS],
            leg_contact: [false; 2],
            game_over: false,
            rest_time: 0.0,
            prev_shaping: None,
            initial_force: None,
            outcome: Outcome::Running,
            last_engines: (0.0, 0.0, 0.0),
            rng: rng_for(carl_env::rng::DEFAULT_SEED),
        }
    }

    pub fn params(&self) -> &LunarLanderParams {
        &self.params
    }
    /// Context changes take effect at the next reset (the world is built from it there).
    pub fn params_mut(&mut self) -> &mut LunarLanderParams {
        &mut self.params
    }
    pub fn options(&self) -> &LunarLanderOptions {
        &self.opts
    }
    /// Option changes take effect at the next reset.
    pub fn options_mut(&mut self) -> &mut LunarLanderOptions {
        &mut self.opts
    }
    /// How the episode stands after the last step.
    pub fn outcome(&self) -> Outcome {
        self.outcome
    }
    /// Terrain heights at the 11 chunk boundaries (after smoothing).
    pub fn terrain(&self) -> &[f64; CHUNKS] {
        &self.smooth_y
    }
    /// Lander origin `(x, y)` in metres and its (unwrapped) angle, or `None` before reset.
    pub fn lander_pose(&self) -> Option<(f64, f64, f64)> {
        let b = self.world.as_ref()?.body_state(0);
        Some((b.x, b.y, b.angle))
    }
    /// Poses `(x, y, angle)` of the lander, leg 0 and leg 1 (body origins, metres), or `None`
    /// before reset.
    pub fn body_poses(&self) -> Option<[(f64, f64, f64); 3]> {
        let w = self.world.as_ref()?;
        Some([0, 1, 2].map(|k| {
            let b = w.body_state(k);
            (b.x, b.y, b.angle)
        }))
    }
    /// Leg ground contacts as in the observation.
    pub fn leg_contacts(&self) -> [bool; 2] {
        self.leg_contact
    }
    /// Engine powers of the last step: `(main, side direction -1/0/+1, side)`.
    pub fn last_engines(&self) -> (f64, f64, f64) {
        self.last_engines
    }
    /// Lander COM velocity `(vx, vy)` and angular velocity, or `None` before reset.
    pub fn lander_velocity(&self) -> Option<(f64, f64, f64)> {
        let b = self.world.as_ref()?.body_state(0);
        Some((b.vx, b.vy, b.w))
    }
    /// Lander mass (kg) as the physics engine computed it.
    pub fn lander_mass(&self) -> Option<f64> {
        Some(self.world.as_ref()?.body(0).mass)
    }

    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        rng::uniform(&mut self.rng, lo, hi)
    }

    fn generate_terrain(&mut self) {
        let p = self.params;
        let (w, h) = (p.world_w(), p.world_h());
        let mut height = [0.0f64; CHUNKS + 1];
        for v in height.iter_mut() {
            *v = self.uniform(0.0, h / 2.0);
        }
        let helipad_y = p.helipad_y();
        for v in &mut height[CHUNKS / 2 - 2..=CHUNKS / 2 + 2] {
            *v = helipad_y;
        }
        let _ = w;
        for i in 0..CHUNKS {
            // Python's height[i - 1] for i = 0 is height[-1], the last element.
            let prev = if i == 0 { height[CHUNKS] } else { height[i - 1] };
            self.smooth_y[i] = 0.33 * (prev + height[i] + height[i + 1]);
        }
    }

    /// Everything [`Env::state`] returns, as a fixed array.
    fn state_array(&self) -> [f64; STATE_DIM] {
        let mut s = [0.0; STATE_DIM];
        s[..CHUNKS].copy_from_slice(&self.smooth_y);
        if let Some(w) = &self.world {
            for k in 0..3 {
                let b = w.body_state(k);
                let o = CHUNKS + 6 * k;
                s[o..o + 6].copy_from_slice(&[b.x, b.y, b.angle, b.vx, b.vy, b.w]);
            }
        }
        let o = CHUNKS + 18;
        s[o] = f64::from(u8::from(self.leg_contact[0]));
        s[o + 1] = f64::from(u8::from(self.leg_contact[1]));
        s[o + 2] = f64::from(u8::from(self.game_over));
        s[o + 3] = self.rest_time;
        s[o + 4] = f64::from(u8::from(self.prev_shaping.is_some()));
        s[o + 5] = self.prev_shaping.unwrap_or(0.0);
        s
    }

    fn load_state(&mut self, s: &[f64; STATE_DIM]) {
        self.smooth_y.copy_from_slice(&s[..CHUNKS]);
        let mut bodies = [BodyState::default(); 3];
        for (k, b) in bodies.iter_mut().enumerate() {
            let o = CHUNKS + 6 * k;
            let v = |j: usize| s[o + j];
            *b = BodyState {
                x: v(0),
                y: v(1),
                angle: v(2),
                vx: v(3),
                vy: v(4),
                w: v(5),
            };
        }
        let o = CHUNKS + 18;
        self.leg_contact = [s[o] != 0.0, s[o + 1] != 0.0];
        self.world = Some(World::build(&self.params, &self.smooth_y, &bodies));
        self.game_over = s[o + 2] != 0.0;
        self.rest_time = s[o + 3];
        self.prev_shaping = (s[o + 4] != 0.0).then_some(s[o + 5]);
        self.initial_force = None;
        self.outcome = Outcome::Running;
        self.last_engines = (0.0, 0.0, 0.0);
    }

    /// The observation of the current state in float64 (Gymnasium's `state` list).
    fn state_f64(&self) -> [f64; 8] {
        let Some(w) = &self.world else { return [0.0; 8] };
        let p = &self.params;
        let b = w.body_state(0);
        let (hw, hh) = (p.world_w() / 2.0, p.world_h() / 2.0);
        [
            (b.x - hw) / hw,
            (b.y - (p.helipad_y() + p.leg_down / p.scale)) / hh,
            b.vx * hw / p.fps,
            b.vy * hh / p.fps,
            b.angle,
            20.0 * b.w / p.fps,
            f64::from(u8::from(self.leg_contact[0])),
            f64::from(u8::from(self.leg_contact[1])),
        ]
    }

    /// Parse an action into (main power, side direction, side power), Gymnasium's rules.
    fn engine_powers(&self, action: &Action) -> Result<(f64, f64, f64), EnvError> {
        if self.opts.continuous {
            let v = match action {
                Action::Continuous(v) if v.len() == 2 => v,
                Action::Continuous(v) => {
                    return Err(EnvError::ActionLength {
                        env: ID,
                        expected: 2,
                        got: v.len(),
                    });
                }
                Action::Discrete(_) => {
                    return Err(EnvError::ActionKind {
                        env: ID,
                        expected: "continuous",
                        got: "discrete",
                    });
                }
            };
            carl_env::api::check_finite_action(ID, v)?;
            // np.clip(action, -1, 1) in float64.
            let a0 = carl_env::api::np_clip(v[0] as f64, -1.0, 1.0);
            let a1 = carl_env::api::np_clip(v[1] as f64, -1.0, 1.0);
            let m = if a0 > 0.0 {
                (a0.clamp(0.0, 1.0) + 1.0) * 0.5
            } else {
                0.0
            };
            let (dir, s) = if a1.abs() > 0.5 {
                (a1.signum(), a1.abs().clamp(0.5, 1.0))
            } else {
                (0.0, 0.0)
            };
            Ok((m, dir, s))
        } else {
            let a = carl_env::api::discrete_action(ID, action, 4)?;
            Ok(match a {
                2 => (1.0, 0.0, 0.0),
                1 | 3 => (0.0, (a - 2) as f64, 1.0),
                _ => (0.0, 0.0, 0.0),
            })
        }
    }

    /// One Gymnasium step with validated engine powers. Requires a world.
    fn advance(&mut self, m_power: f64, direction: f64, s_power: f64) -> StepOutcome {
        let p = self.params;
        self.last_engines = (m_power, direction, s_power);
        let scale = p.scale;
        let world = self.world.as_mut().expect("advance needs a world");
        let lander = world.body_state(0);
        let tip = (lander.angle.sin(), lander.angle.cos());
        let side = (-tip.1, tip.0);
        let d0 = rng::uniform(&mut self.rng, -1.0, 1.0) / scale;
        let d1 = rng::uniform(&mut self.rng, -1.0, 1.0) / scale;
        let (px, py) = (lander.x, lander.y);
        if m_power > 0.0 {
            let ox = tip.0 * (MAIN_ENGINE_Y_LOCATION / scale + 2.0 * d0) + side.0 * d1;
            let oy = -tip.1 * (MAIN_ENGINE_Y_LOCATION / scale + 2.0 * d0) - side.1 * d1;
            let impulse = v2(-ox * p.main_engine_power * m_power, -oy * p.main_engine_power * m_power);
            world.lander_impulse(impulse, v2(px + ox, py + oy));
        }
        if s_power > 0.0 {
            let lever = 3.0 * d1 + direction * p.side_engine_away / scale;
            let ox = tip.0 * d0 + side.0 * lever;
            let oy = -tip.1 * d0 - side.1 * lever;
            let at = v2(
                px + ox - tip.0 * 17.0 / scale,
                py + oy + tip.1 * p.side_engine_height / scale,
            );
            let impulse = v2(-ox * p.side_engine_power * s_power, -oy * p.side_engine_power * s_power);
            world.lander_impulse(impulse, at);
        }

        let solver_stepped = world.step(self.initial_force.take());
        let dt = world.dt;

        // Box2D's island sleep test: lander and legs (one island through the joints) all slower
        // than the sleep tolerances for `TIME_TO_SLEEP`; then the lander is "not awake".
        let resting = (0..3).all(|k| {
            let b = world.body(k);
            b.v.length_squared() <= LINEAR_SLEEP_TOLERANCE * LINEAR_SLEEP_TOLERANCE
                && b.w * b.w <= ANGULAR_SLEEP_TOLERANCE * ANGULAR_SLEEP_TOLERANCE
        });
        self.rest_time = if resting { self.rest_time + dt } else { 0.0 };
        let awake = self.rest_time < TIME_TO_SLEEP;

        // Gymnasium's contact listener: a lander contact beginning ends the game, a leg's flag
        // follows its contacts beginning and ending, in Box2D's event order. In flight nothing
        // touches.
        if solver_stepped {
            for e in &world.b2.events {
                if e.begin && e.involves(world.lander_fixture) {
                    self.game_over = true;
                }
                for (flag, &leg) in self.leg_contact.iter_mut().zip(&world.leg_fixtures) {
                    if e.involves(leg) {
                        *flag = e.begin;
                    }
                }
            }
        } else {
            self.leg_contact = [false; 2];
        }

        let s = self.state_f64();
        let shaping = -100.0 * (s[0] * s[0] + s[1] * s[1]).sqrt()
            - 100.0 * (s[2] * s[2] + s[3] * s[3]).sqrt()
            - 100.0 * s[4].abs()
            + 10.0 * s[6]
            + 10.0 * s[7];
        let mut reward = match self.prev_shaping {
            Some(prev) => shaping - prev,
            None => 0.0,
        };
        self.prev_shaping = Some(shaping);
        reward -= m_power * 0.30;
        reward -= s_power * 0.03;
        let mut terminated = false;
        self.outcome = Outcome::Running;
        if self.game_over || s[0].abs() >= 1.0 {
            terminated = true;
            reward = -self.opts.crash_penalty;
            self.outcome = if self.game_over {
                Outcome::Crashed
            } else {
                Outcome::OutOfView
            };
        }
        if !awake {
            terminated = true;
            reward = 100.0;
            self.outcome = Outcome::Landed;
        }
        StepOutcome {
            reward,
            terminated,
            truncated: false,
        }
    }

    fn write_obs(&self, obs: &mut [f32]) {
        for (o, s) in obs.iter_mut().zip(self.state_f64()) {
            *o = s as f32;
        }
    }
}

impl carl_env::runtime::Runtime for LunarLander {}

impl Env for LunarLander {
    fn id(&self) -> &'static str {
        ID
    }
    fn obs_dim(&self) -> usize {
        8
    }
    fn state_dim(&self) -> usize {
        STATE_DIM
    }
    fn observation_space(&self) -> Space {
        let tau = 2.0 * std::f32::consts::PI;
        Space::Box {
            low: vec![-2.5, -2.5, -10.0, -10.0, -tau, -10.0, -0.0, -0.0],
            high: vec![2.5, 2.5, 10.0, 10.0, tau, 10.0, 1.0, 1.0],
            shape: vec![8],
            dtype: DType::Float32,
        }
    }
    fn action_space(&self) -> Space {
        if self.opts.continuous {
            Space::Box {
                low: vec![-1.0; 2],
                high: vec![1.0; 2],
                shape: vec![2],
                dtype: DType::Float32,
            }
        } else {
            Space::Discrete { n: 4, start: 0 }
        }
    }

    fn reset_into(&mut self, seed: Option<u64>, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(ID, obs, 8)?;
        if let Some(seed) = seed {
            self.rng = rng_for(seed);
        }
        self.generate_terrain();
        let bodies = creation_bodies(&self.params);
        self.world = Some(World::build(&self.params, &self.smooth_y, &bodies));
        self.leg_contact = [false; 2];
        self.game_over = false;
        self.rest_time = 0.0;
        self.prev_shaping = None;
        self.outcome = Outcome::Running;
        let ir = self.params.initial_random;
        let fx = self.uniform(-ir, ir);
        let fy = self.uniform(-ir, ir);
        self.initial_force = Some([fx, fy]);
        // Gymnasium's reset returns the observation of `step(0)`.
        self.advance(0.0, 0.0, 0.0);
        self.write_obs(obs);
        Ok(())
    }

    fn step_into(&mut self, action: &Action, obs: &mut [f32]) -> Result<StepOutcome, EnvError> {
        let (m, dir, s) = self.engine_powers(action)?;
        check_obs_len(ID, obs, 8)?;
        if self.world.is_none() {
            return Err(EnvError::NeedsReset { env: ID });
        }
        let out = self.advance(m, dir, s);
        self.write_obs(obs);
        Ok(out)
    }

    fn observe_into(&self, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(ID, obs, 8)?;
        self.write_obs(obs);
        Ok(())
    }

    /// 11 terrain heights; lander, leg 0, leg 1 as (x, y, angle, vx, vy, ω); leg contacts;
    /// game over; rest time; has-previous-shaping; previous shaping.
    fn state(&self) -> Vec<f64> {
        self.state_array().to_vec()
    }

    /// `landed`, `crashed` or `out_of_view` after the step that ended the episode ([`Outcome`]).
    fn outcome(&self) -> Option<&'static str> {
        self.outcome.name()
    }

    fn render(&self) -> Option<carl_pixels::Frame> {
        render::draw(self)
    }

    fn set_state(&mut self, state: &[f64]) -> Result<(), EnvError> {
        let s = check_state::<STATE_DIM>(ID, state)?;
        self.load_state(&s);
        // Bookkeeping cleared as after a reset.
        self.game_over = false;
        Ok(())
    }
}
