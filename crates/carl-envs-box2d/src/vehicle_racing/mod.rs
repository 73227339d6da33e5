//! CARL's `CARLVehicleRacing`: Gymnasium 1.4 `CarRacing-v3` with the vehicle chosen by the
//! categorical context feature `VEHICLE` (29 vehicles of CARL's parking garage,
//! [`vehicles::VEHICLES`]).
//!
//! Same as Gymnasium/CARL: the seeded track ([`track`]: 12 checkpoints, pursuit curve, closed
//! second lap, tiles, kerbs), the start pose (`track[0]`), CARL's vehicle geometry, densities,
//! engine power, wheel moment of inertia, friction limits, drive wheels, brake bias, steering
//! limits and trailers, the `car_dynamics` tyre model (wheel angular velocity driven by engine
//! power `P·gas/I/(|ω|+5)`, brake `15·b` rad/s or lock at `b ≥ 0.9`, longitudinal and lateral slip
//! forces `205000·SIZE²·Δv` capped at the friction limit, 60 % grip off the road, gas ramp 0.1 per
//! step, steering motor `sign·min(50·Δ, 3)` rad/s), the step order (controls, tyre forces, contact
//! update, integration), reward (−0.1 per step, +1000/N per newly visited tile, tiles touched
//! during `reset`'s `step(None)` paid out with the first step), termination (all tiles visited or
//! lap completed past 95 %; hull outside the playfield: −100), the discrete actions (including
//! Gymnasium's sign: discrete action 1 "left" steers with −0.6, i.e. to the right), and the
//! pictures ([`raster`]: camera following the car with CarRacing's zoom animation, grass
//! checkerboard, road and kerbs, car bodies with wheel stripes, CARL's indicator bar with one
//! ABS bar per wheel, the reward counter).
//!
//! ## Physics: plain Rust instead of rapier
//!
//! Box2D is used by CarRacing only as a rigid-body integrator: the car's fixtures are sensors
//! or collide with nothing, all tyre forces come from `car_dynamics`, and the wheels hang on
//! revolute joints whose motor only sets the steering angle. With Box2D's 180 iterations those
//! joints are rigid, so a hull with its wheels moves as one rigid body whose wheels turn with a
//! prescribed (motor-driven, limited) angle. We therefore integrate each hull or trailer
//! *together with its wheels* as one compound body (mass, centre of mass and inertia summed from
//! the same polygons and densities), exactly, with Box2D's symplectic Euler step and its motion
//! caps, and the steering angle as the motor/limit makes it move (including Box2D's 2° limit
//! slop). Trailers are separate compound bodies joined by revolute joints with limits and a
//! speed-0 motor (hinge friction), solved with Box2D 2.3's sequential impulses and position
//! correction; the large trailer's axle hangs on two soft distance joints (1.25 m, 500 Hz,
//! undamped) solved with Box2D's soft-constraint bias ([`physics`]). As in CARL, trailer bodies
//! spawn at the hull's origin with their joints apart, and reset's first step pulls them into
//! place (the large trailer's rods push the axle 0.84 m back). This is more faithful than a
//! rapier world (whose few soft-constraint iterations let the 1:100 wheel/hull mass ratio sag),
//! simpler, deterministic and cheap; it needs no collision pipeline since nothing collides.
//!
//! Checked against carl-bench's vehicle classes run in Gymnasium 1.4 / Box2D 2.3.10 (full gas
//! from rest, seed 0): hull speeds after 11, 21 and 41 steps agree to 1e-4 m/s for the vehicles
//! without or with the small trailer and within 0.2 % for the large trailers (whose start-up
//! jolt depends on solver details); see `tests/vehicle_racing.rs`.
//!
//! ## Deviations
//!
//! * **Self-collision.** Box2D would let a trailer swung to its ±0.9 rad limit touch the car's
//!   rear wheels; vehicle parts never collide here.
//! * **Tile contacts** use a separating-axis test with Box2D's 0.02 m polygon skin instead of
//!   GJK (corner-to-corner distances are slightly underestimated).
//! * **Solver.** Joint impulses are not warm-started across steps; 60 velocity iterations per
//!   step replace Box2D's 180 warm-started ones. Everything is float64 (Box2D: float32).
//! * **Pictures.** pygame's anti-aliased outlines, skid marks (drawn only in `render`) and its
//!   font are not reproduced: the reward counter uses the crate's 5×7 bitmap font, and tiles
//!   change to the plain road colour once a wheel touched them (Gymnasium: any fixture).
//! * **TukTuk brake.** CARL's `TukTuk.brake` iterates over the front wheel's fixtures, so the
//!   front wheel is never braked; we keep that. (Its `FWD`/large-trailer variants do not exist.)
//! * **RNG.** Tracks come from the crate's PCG64, not NumPy's generator: same distribution,
//!   different tracks for the same seed.

pub mod physics;
pub mod raster;
pub mod track;
pub mod vehicles;

use std::sync::{Arc, Mutex};

use physics::{Body, BodyState, Distance, MassProps, Revolute, V2, convex_hull, polygon_mass};
use raster::Canvas;
use track::{PLAYFIELD, Track};
use vehicles::{Family, SIZE, TrailerKind, VEHICLES, Vehicle};

use carl_env::api::{Action, DType, Env, EnvError, Space, StepOutcome, check_obs_len, context_features};
use carl_spec_core::sampling::Pcg64;

const ID: &str = "vehicle_racing";

pub const FPS: f64 = 50.0;
pub const STATE_W: usize = 96;
pub const STATE_H: usize = 96;
pub const VIDEO_W: usize = 600;
pub const VIDEO_H: usize = 400;
/// pygame surface the scene is drawn on before scaling (`WINDOW_W × WINDOW_H`).
pub const WINDOW_W: f64 = 1000.0;
pub const WINDOW_H: f64 = 800.0;
pub const ZOOM: f64 = 2.7;
pub const GRASS_DIM: f64 = PLAYFIELD / 20.0;
pub const OBS_DIM: usize = STATE_W * STATE_H * 3;
/// Default supersampling factor of the observation (samples per output pixel per axis; see
/// [`VehicleRacingOptions::obs_supersample`]).
pub const OBS_SUPERSAMPLE: usize = 2;
/// Supersampling factor of `render()`.
pub const RENDER_SUPERSAMPLE: usize = 2;

pub const MAX_BODIES: usize = 3;
pub const MAX_WHEELS: usize = 8;
/// Tiles one wheel can touch at once (more are ignored).
pub const MAX_WHEEL_TILES: usize = 8;
/// Visited flags are packed 48 to a state component.
pub const VISIT_BITS: usize = 48;
pub const VISIT_WORDS: usize = 12;
/// Longest track the state can describe; longer tracks are regenerated.
pub const MAX_TILES: usize = VISIT_BITS * VISIT_WORDS;
const HEADER: usize = 5;
const BODY_DIM: usize = 6;
const WHEEL_DIM: usize = 6 + MAX_WHEEL_TILES;
/// Length of [`VehicleRacing::state`]: track seed, time, reward, previous reward, new-lap flag,
/// packed visited flags, 3 bodies × (x, y, angle, vx, vy, ω), 8 wheels × (ω, gas, brake, steer
/// target, steering angle, phase, up to 8 touched tile indices or −1).
pub const STATE_DIM: usize = HEADER + VISIT_WORDS + MAX_BODIES * BODY_DIM + MAX_WHEELS * WHEEL_DIM;

const BG_COLOR: [u8; 3] = [102, 204, 102];
const GRASS_COLOR: [u8; 3] = [102, 230, 102];
const WHEEL_WHITE: [u8; 3] = [77, 77, 77];

/// Context of the vehicle-racing environment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VehicleRacingParams {
    /// Index into [`VEHICLES`].
    pub vehicle: f64,
}

impl Default for VehicleRacingParams {
    fn default() -> Self {
        VehicleRacingParams { vehicle: 0.0 }
    }
}

context_features!(VehicleRacingParams, "vehicle_racing", {
    vehicle: "VEHICLE" | "VEHICLE_ID",
});

impl VehicleRacingParams {
    /// The selected vehicle, or an error for a non-integer or out-of-range index.
    pub fn vehicle(&self) -> Result<&'static Vehicle, String> {
        let v = self.vehicle;
        if v.is_finite() && v.fract() == 0.0 && v >= 0.0 && (v as usize) < VEHICLES.len() {
            Ok(&VEHICLES[v as usize])
        } else {
            Err(format!(
                "VEHICLE = {v} is not a vehicle index (0..={}: {})",
                VEHICLES.len() - 1,
                VEHICLES.iter().map(|v| v.name).collect::<Vec<_>>().join(", ")
            ))
        }
    }
}

/// Options that are not context features (Gymnasium's constructor arguments).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VehicleRacingOptions {
    /// `continuous=True`: actions `[steer, gas, brake]`; otherwise 5 discrete actions.
    pub continuous: bool,
    pub lap_complete_percent: f64,
    /// Samples per observation pixel per axis (1..=8). pygame averages about 10×8 surface
    /// pixels per observation pixel; 2 (4 samples) is 2.8× cheaper than 4 and differs only
    /// along edges.
    pub obs_supersample: usize,
}

impl Default for VehicleRacingOptions {
    fn default() -> Self {
        VehicleRacingOptions {
            continuous: true,
            lap_complete_percent: 0.95,
            obs_supersample: OBS_SUPERSAMPLE,
        }
    }
}

/// A polygon fixed to a body (metres, body frame, convex hull) with its colour.
#[derive(Debug, Clone, PartialEq)]
struct Shape {
    verts: Vec<V2>,
    color: [u8; 3],
}

/// Static description of one wheel.
#[derive(Debug, Clone, Copy, PartialEq)]
struct WheelDef {
    body: usize,
    /// Centre in the body frame, m.
    mount: V2,
    /// Steering-joint limit ±rad.
    limit: f64,
    half_w: f64,
    half_r: f64,
    steered: bool,
    driven: bool,
    brake: f64,
    color: [u8; 3],
}

/// Everything fixed by the vehicle choice.
#[derive(Debug, Clone, PartialEq)]
struct Model {
    vehicle: &'static Vehicle,
    props: Vec<MassProps>,
    /// Body origins in the hull frame at the start pose (all zero: CARL spawns every body at the
    /// hull's origin and lets the joints pull them into place).
    offsets: Vec<V2>,
    shapes: Vec<Vec<Shape>>,
    joints: Vec<Revolute>,
    rods: Vec<Distance>,
    wheels: Vec<WheelDef>,
    /// Centre of mass of the hull's own fixtures (Box2D's hull body, for the speed indicator).
    hull_centroid: V2,
    engine_power: f64,
    wheel_moi: f64,
    friction_limit: f64,
    wheel_rad: f64,
}

fn m(p: (f64, f64)) -> V2 {
    V2::new(p.0 * SIZE, p.1 * SIZE)
}

fn hull_of(verts: &[(f64, f64)]) -> Vec<V2> {
    convex_hull(&verts.iter().map(|&p| m(p)).collect::<Vec<_>>())
}

impl Model {
    fn new(vehicle: &'static Vehicle) -> Model {
        let f: &Family = vehicle.family;
        let s2 = SIZE * SIZE;
        let wheel_half = (f.wheel_w * SIZE, f.wheel_r * SIZE);
        let wheel_poly = |c: V2| {
            let (hw, hr) = wheel_half;
            vec![
                c + V2::new(-hw, -hr),
                c + V2::new(hw, -hr),
                c + V2::new(hw, hr),
                c + V2::new(-hw, hr),
            ]
        };
        let mut parts: Vec<Vec<(f64, V2, f64)>> = vec![Vec::new()];
        let mut shapes: Vec<Vec<Shape>> = vec![Vec::new()];
        let mut offsets = vec![V2::ZERO];
        for fx in f.hull {
            let h = hull_of(fx.verts);
            parts[0].push(polygon_mass(&h, fx.density));
            shapes[0].push(Shape {
                verts: h,
                color: f.hull_color,
            });
        }
        let hull_centroid = MassProps::from_parts(&parts[0]).com;
        let mut wheels = Vec::new();
        for (i, &pos) in f.wheels.iter().enumerate() {
            let front = pos.1 > 0.0;
            let driven = if front {
                vehicle.fwd && f.front_drive.contains(&i)
            } else {
                vehicle.rwd && f.rear_drive.contains(&i)
            };
            let color = if (front && vehicle.fwd) || (!front && vehicle.rwd) {
                vehicles::MOTOR_WHEEL_COLOR
            } else {
                vehicles::WHEEL_COLOR
            };
            wheels.push(WheelDef {
                body: 0,
                mount: m(pos),
                limit: f.wheel_limit,
                half_w: wheel_half.0,
                half_r: wheel_half.1,
                steered: f.steered.contains(&i),
                driven,
                brake: f.brake[i],
                color,
            });
        }
        let mut joints = Vec::new();
        let mut rods = Vec::new();
        let trailer_wheel = |body: usize, pos: (f64, f64), brake: f64| WheelDef {
            body,
            mount: m(pos),
            limit: 0.4,
            half_w: wheel_half.0,
            half_r: wheel_half.1,
            steered: false,
            driven: false,
            brake,
            color: vehicles::WHEEL_COLOR,
        };
        match vehicle.trailer {
            TrailerKind::None => {}
            TrailerKind::Small => {
                let t = &f.small_trailer;
                let h = hull_of(t.poly.verts);
                parts.push(vec![polygon_mass(&h, t.poly.density)]);
                shapes.push(vec![Shape {
                    verts: h,
                    color: vehicles::TRAILER_COLOR,
                }]);
                offsets.push(V2::ZERO);
                joints.push(Revolute {
                    a: 0,
                    b: 1,
                    anchor_a: m(t.hull_anchor),
                    anchor_b: m(t.trailer_anchor),
                    limit: Some(t.limit),
                    motor_torque: Some(t.motor_torque * s2),
                });
                for &p in t.wheels {
                    wheels.push(trailer_wheel(1, p, t.brake));
                }
            }
            TrailerKind::Large => {
                let t = f.large_trailer.as_ref().expect("vehicle table: large trailer");
                let ha = hull_of(t.axle.verts);
                parts.push(vec![polygon_mass(&ha, t.axle.density)]);
                shapes.push(vec![Shape {
                    verts: ha,
                    color: vehicles::AXLE_COLOR,
                }]);
                let mut tp = Vec::new();
                let mut ts = Vec::new();
                for fx in &t.body {
                    let h = hull_of(fx.verts);
                    tp.push(polygon_mass(&h, fx.density));
                    ts.push(Shape {
                        verts: h,
                        color: vehicles::TRAILER_COLOR,
                    });
                }
                parts.push(tp);
                shapes.push(ts);
                // As in CARL, axle and trailer start at the hull's origin; the two rods (1.25 m,
                // 500 Hz, undamped) push the axle back into place during reset's first step.
                offsets.push(V2::ZERO);
                offsets.push(V2::ZERO);
                for sx in [-1.0, 1.0] {
                    rods.push(Distance {
                        a: 0,
                        b: 1,
                        anchor_a: m(t.hull_anchor),
                        anchor_b: m((sx * t.axle_anchor_x, t.axle_anchor_y)),
                        length: t.rod_length,
                        frequency_hz: 500.0,
                        damping_ratio: 0.0,
                    });
                }
                joints.push(Revolute {
                    a: 1,
                    b: 2,
                    anchor_a: m(t.hinge),
                    anchor_b: m(t.hinge),
                    limit: Some(t.limit),
                    motor_torque: Some(t.motor_torque * s2),
                });
                for &p in t.wheels {
                    let body = if p.1 < -170.0 { 2 } else { 1 };
                    wheels.push(trailer_wheel(body, p, t.brake));
                }
            }
        }
        // Wheels are part of their body's compound mass (density 0.1, rectangle inertia).
        for w in &wheels {
            let poly = wheel_poly(w.mount);
            parts[w.body].push(polygon_mass(&poly, 0.1));
        }
        let props = parts.iter().map(|p| MassProps::from_parts(p)).collect();
        Model {
            vehicle,
            props,
            offsets,
            shapes,
            joints,
            rods,
            wheels,
            hull_centroid,
            engine_power: f.engine_power * s2,
            wheel_moi: f.wheel_moi * s2,
            friction_limit: f.friction_limit * s2,
            wheel_rad: f.wheel_r * SIZE,
        }
    }
}

/// Per-wheel dynamic state (`car_dynamics` wheel attributes and the steering joint angle).
#[derive(Debug, Clone, Copy, PartialEq)]
struct WheelState {
    omega: f64,
    gas: f64,
    brake: f64,
    steer: f64,
    angle: f64,
    phase: f64,
    /// Tiles touched (`w.tiles`), ascending, −1 = empty slot.
    tiles: [i32; MAX_WHEEL_TILES],
}

impl Default for WheelState {
    fn default() -> Self {
        WheelState {
            omega: 0.0,
            gas: 0.0,
            brake: 0.0,
            steer: 0.0,
            angle: 0.0,
            phase: 0.0,
            tiles: [-1; MAX_WHEEL_TILES],
        }
    }
}

impl WheelState {
    fn on_road(&self) -> bool {
        self.tiles[0] >= 0
    }
}

/// CarRacing with one of CARL's vehicles; each instance owns its track, bodies and canvas.
#[derive(Debug)]
pub struct VehicleRacing {
    params: VehicleRacingParams,
    opts: VehicleRacingOptions,
    model: Model,
    track_seed: u64,
    track: Option<Arc<Track>>,
    bodies: Vec<Body>,
    wheels: Vec<WheelState>,
    visited: Vec<bool>,
    tile_visited_count: usize,
    reward: f64,
    prev_reward: f64,
    t: f64,
    new_lap: bool,
    rng: Pcg64,
    canvas: Mutex<Canvas>,
}

impl Clone for VehicleRacing {
    fn clone(&self) -> Self {
        VehicleRacing {
            params: self.params,
            opts: self.opts,
            model: self.model.clone(),
            track_seed: self.track_seed,
            track: self.track.clone(),
            bodies: self.bodies.clone(),
            wheels: self.wheels.clone(),
            visited: self.visited.clone(),
            tile_visited_count: self.tile_visited_count,
            reward: self.reward,
            prev_reward: self.prev_reward,
            t: self.t,
            new_lap: self.new_lap,
            rng: self.rng.clone(),
            canvas: Mutex::new(Canvas::default()),
        }
    }
}

fn rng_for(seed: u64) -> Pcg64 {
    Pcg64::new(seed, carl_spec_core::sampling::stream_id(ID))
}

fn track_rng(track_seed: u64) -> Pcg64 {
    Pcg64::new(track_seed, carl_spec_core::sampling::stream_id("vehicle_racing/track"))
}

/// Largest track seed (seeds are stored exactly in a float64 state component).
pub const MAX_TRACK_SEED: u64 = (1 << 53) - 1;
/// Attempts of `_create_track` per track seed.
const TRACK_ATTEMPTS: usize = 64;

/// The track of `track_seed`, if it can be generated within the state's tile capacity.
pub fn track_for_seed(track_seed: u64) -> Option<Track> {
    let mut rng = track_rng(track_seed);
    track::generate(&mut rng, TRACK_ATTEMPTS).filter(|t| t.tiles.len() <= MAX_TILES)
}

fn np_sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// Separating-axis overlap test of two convex quads, counting shapes closer than `skin` as
/// touching.
fn quads_touch(a: &[V2; 4], b: &[V2; 4], skin: f64) -> bool {
    for (p, q) in [(a, b), (b, a)] {
        for i in 0..4 {
            let e = p[(i + 1) % 4] - p[i];
            let n = V2::new(e.y, -e.x);
            let len = n.len();
            if len == 0.0 {
                continue;
            }
            let n = n * (1.0 / len);
            let pmax = p.iter().map(|v| n.dot(*v)).fold(f64::NEG_INFINITY, f64::max);
            let pmin = p.iter().map(|v| n.dot(*v)).fold(f64::INFINITY, f64::min);
            let qmin = q.iter().map(|v| n.dot(*v)).fold(f64::INFINITY, f64::min);
            let qmax = q.iter().map(|v| n.dot(*v)).fold(f64::NEG_INFINITY, f64::max);
            if qmin - pmax >= skin || pmin - qmax >= skin {
                return false;
            }
        }
    }
    true
}

/// Box2D's polygon skin: each polygon has radius 0.01 m.
const CONTACT_SKIN: f64 = 0.02;

impl VehicleRacing {
    /// A racing environment with the default options, or an error for an invalid `VEHICLE`.
    pub fn new(params: VehicleRacingParams) -> Result<Self, String> {
        Self::with_options(params, VehicleRacingOptions::default())
    }

    pub fn with_options(params: VehicleRacingParams, opts: VehicleRacingOptions) -> Result<Self, String> {
        let vehicle = params.vehicle()?;
        let model = Model::new(vehicle);
        let n_bodies = model.props.len();
        let n_wheels = model.wheels.len();
        let mut env = VehicleRacing {
            params,
            opts,
            model,
            track_seed: 0,
            track: None,
            bodies: vec![Body::default(); n_bodies],
            wheels: vec![WheelState::default(); n_wheels],
            visited: Vec::new(),
            tile_visited_count: 0,
            reward: 0.0,
            prev_reward: 0.0,
            t: 0.0,
            new_lap: false,
            rng: rng_for(carl_env::rng::DEFAULT_SEED),
            canvas: Mutex::new(Canvas::default()),
        };
        for (b, p) in env.bodies.iter_mut().zip(&env.model.props) {
            b.props = *p;
        }
        Ok(env)
    }

    pub fn params(&self) -> &VehicleRacingParams {
        &self.params
    }
    pub fn options(&self) -> &VehicleRacingOptions {
        &self.opts
    }
    pub fn set_continuous(&mut self, continuous: bool) {
        self.opts.continuous = continuous;
    }
    pub fn vehicle(&self) -> &'static Vehicle {
        self.model.vehicle
    }
    /// The current track (after `reset` or `set_state`).
    pub fn track(&self) -> Option<&Track> {
        self.track.as_deref()
    }
    pub fn track_seed(&self) -> u64 {
        self.track_seed
    }
    /// Number of bodies (hull, trailer, axle) and wheels of the vehicle.
    pub fn n_bodies(&self) -> usize {
        self.bodies.len()
    }
    pub fn n_wheels(&self) -> usize {
        self.wheels.len()
    }
    /// Hull origin position, angle and centre-of-mass velocity.
    pub fn hull(&self) -> (f64, f64, f64, f64, f64) {
        let s = &self.bodies[0].s;
        (s.pos.x, s.pos.y, s.angle, s.vel.x, s.vel.y)
    }
    /// Speed of the hull's own centre of mass (what the speed indicator shows).
    pub fn hull_speed(&self) -> f64 {
        let b = &self.bodies[0];
        b.velocity_at(b.world_point(self.model.hull_centroid)).len()
    }
    pub fn tiles_visited(&self) -> usize {
        self.tile_visited_count
    }
    /// Accumulated reward of the episode (Gymnasium's `env.reward`).
    pub fn total_reward(&self) -> f64 {
        self.reward
    }
    /// Wheel angular velocities.
    pub fn wheel_omegas(&self) -> Vec<f64> {
        self.wheels.iter().map(|w| w.omega).collect()
    }
    /// Steering angle of wheel 0 (the joint angle).
    pub fn steering_angle(&self) -> f64 {
        self.wheels[0].angle
    }
    /// Whether wheel `i` currently grips like on road.
    pub fn wheel_on_road(&self, i: usize) -> bool {
        self.wheels[i].on_road()
    }

    /// Spawn the vehicle at rest at `(x, y)` with hull angle `angle` (every body at its offset).
    fn place_vehicle(&mut self, angle: f64, x: f64, y: f64) {
        let (s, c) = angle.sin_cos();
        for (k, b) in self.bodies.iter_mut().enumerate() {
            b.s = BodyState {
                pos: V2::new(x, y) + self.model.offsets[k].rot(s, c),
                angle,
                vel: V2::ZERO,
                w: 0.0,
            };
            b.force = V2::ZERO;
            b.torque = 0.0;
        }
        for w in &mut self.wheels {
            *w = WheelState::default();
        }
    }

    fn load_track(&mut self, track_seed: u64) -> Result<(), EnvError> {
        if self.track.is_some() && self.track_seed == track_seed {
            return Ok(());
        }
        let t = track_for_seed(track_seed).ok_or_else(|| EnvError::Context {
            env: ID,
            message: format!("track seed {track_seed} generates no usable track"),
        })?;
        self.track = Some(Arc::new(t));
        self.track_seed = track_seed;
        Ok(())
    }

    fn reset_episode(&mut self) {
        let n = self.track.as_ref().map_or(0, |t| t.tiles.len());
        self.visited.clear();
        self.visited.resize(n, false);
        self.tile_visited_count = 0;
        self.reward = 0.0;
        self.prev_reward = 0.0;
        self.t = 0.0;
        self.new_lap = false;
    }

    /// World corners of wheel `i` (half extents along its own axes).
    fn wheel_corners(&self, i: usize) -> [V2; 4] {
        let d = &self.model.wheels[i];
        let b = &self.bodies[d.body];
        let c = b.world_point(d.mount);
        let (s, co) = (b.s.angle + self.wheels[i].angle).sin_cos();
        [
            c + V2::new(-d.half_w, -d.half_r).rot(s, co),
            c + V2::new(d.half_w, -d.half_r).rot(s, co),
            c + V2::new(d.half_w, d.half_r).rot(s, co),
            c + V2::new(-d.half_w, d.half_r).rot(s, co),
        ]
    }

    /// Box2D's contact update before integration: begin/end events between wheels and tiles,
    /// paying the tile reward and detecting lap completion.
    fn update_contacts(&mut self) {
        let Some(track) = self.track.clone() else { return };
        let n = track.tiles.len();
        for i in 0..self.wheels.len() {
            let corners = self.wheel_corners(i);
            let (mut x0, mut y0, mut x1, mut y1) = (f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY);
            for c in &corners {
                x0 = x0.min(c.x);
                y0 = y0.min(c.y);
                x1 = x1.max(c.x);
                y1 = y1.max(c.y);
            }
            let mut now = [-1i32; MAX_WHEEL_TILES];
            let mut k = 0;
            if corners.iter().all(|c| c.x.is_finite() && c.y.is_finite()) {
                for (ti, bb) in track.tile_aabb.iter().enumerate() {
                    if bb[0] - CONTACT_SKIN > x1
                        || bb[2] + CONTACT_SKIN < x0
                        || bb[1] - CONTACT_SKIN > y1
                        || bb[3] + CONTACT_SKIN < y0
                    {
                        continue;
                    }
                    let q = track.tiles[ti].pts;
                    let q = [
                        V2::new(q[0].0, q[0].1),
                        V2::new(q[1].0, q[1].1),
                        V2::new(q[2].0, q[2].1),
                        V2::new(q[3].0, q[3].1),
                    ];
                    if quads_touch(&corners, &q, CONTACT_SKIN) && k < MAX_WHEEL_TILES {
                        now[k] = ti as i32;
                        k += 1;
                    }
                }
            }
            let before = self.wheels[i].tiles;
            for &ti in before.iter().filter(|&&t| t >= 0) {
                if !now.contains(&ti) {
                    self.contact_event(ti as usize, false, n);
                }
            }
            for &ti in now.iter().filter(|&&t| t >= 0) {
                if !before.contains(&ti) {
                    self.contact_event(ti as usize, true, n);
                }
            }
            self.wheels[i].tiles = now;
        }
    }

    fn contact_event(&mut self, tile: usize, begin: bool, n: usize) {
        if tile == 0 && self.tile_visited_count as f64 / n as f64 > self.opts.lap_complete_percent {
            self.new_lap = true;
        }
        if begin && tile < self.visited.len() && !self.visited[tile] {
            self.visited[tile] = true;
            self.reward += 1000.0 / n as f64;
            self.tile_visited_count += 1;
        }
    }

    /// `car.steer/gas/brake` of CARL's vehicles.
    fn apply_controls(&mut self, steer: f64, gas: f64, brake: f64) {
        let gas = gas.clamp(0.0, 1.0);
        for (w, d) in self.wheels.iter_mut().zip(&self.model.wheels) {
            if d.steered {
                w.steer = steer;
            }
            if d.driven {
                let diff = (gas - w.gas).min(0.1);
                w.gas += diff;
            }
            w.brake = brake * d.brake;
        }
    }

    /// `car.step(dt)`: tyre forces and wheel spin; returns the steering motor speed per wheel.
    fn car_step(&mut self, dt: f64, motor: &mut [f64; MAX_WHEELS]) {
        let md = &self.model;
        let k = 205_000.0 * SIZE * SIZE;
        for (i, (w, d)) in self.wheels.iter_mut().zip(&md.wheels).enumerate() {
            let diff = w.steer - w.angle;
            motor[i] = np_sign(diff) * (50.0 * diff.abs()).min(3.0);
            let friction_limit = if w.on_road() {
                md.friction_limit
            } else {
                md.friction_limit * 0.6
            };
            let b = &self.bodies[d.body];
            let p = b.world_point(d.mount);
            let (s, c) = (b.s.angle + w.angle).sin_cos();
            let forw = V2::new(-s, c);
            let side = V2::new(c, s);
            let v = b.velocity_at(p);
            let vf = forw.dot(v);
            let vs = side.dot(v);
            w.omega += dt * md.engine_power * w.gas / md.wheel_moi / (w.omega.abs() + 5.0);
            if w.brake >= 0.9 {
                w.omega = 0.0;
            } else if w.brake > 0.0 {
                let dir = -np_sign(w.omega);
                let mut val = 15.0 * w.brake;
                if val.abs() > w.omega.abs() {
                    val = w.omega.abs();
                }
                w.omega += dir * val;
            }
            w.phase += w.omega * dt;
            let vr = w.omega * md.wheel_rad;
            let mut f_force = (-vf + vr) * k;
            let mut p_force = -vs * k;
            let force = (f_force * f_force + p_force * p_force).sqrt();
            if force.abs() > friction_limit {
                f_force = f_force / force * friction_limit;
                p_force = p_force / force * friction_limit;
            }
            w.omega -= dt * f_force * md.wheel_rad / md.wheel_moi;
            let f = side * p_force + forw * f_force;
            self.bodies[d.body].apply_force(f, p);
        }
    }

    /// One Box2D `world.Step`: contacts, then integration of bodies and steering joints.
    fn world_step(&mut self, dt: f64, motor: &[f64; MAX_WHEELS]) {
        self.update_contacts();
        // Steering joints (see module docs): the motor speed, blocked at a limit the joint
        // already sat at, then Box2D's position correction with its angular slop.
        for (i, (w, d)) in self.wheels.iter_mut().zip(&self.model.wheels).enumerate() {
            let (lo, hi) = (-d.limit, d.limit);
            let a0 = w.angle;
            let mut speed = motor[i];
            if (a0 <= lo && speed < 0.0) || (a0 >= hi && speed > 0.0) {
                speed = 0.0;
            }
            let mut a = a0 + dt * speed;
            if a0 <= lo {
                a -= (a - lo + physics::ANGULAR_SLOP).clamp(-physics::MAX_ANGULAR_CORRECTION, 0.0);
            } else if a0 >= hi {
                a -= (a - hi - physics::ANGULAR_SLOP).clamp(0.0, physics::MAX_ANGULAR_CORRECTION);
            }
            w.angle = a;
        }
        physics::step(&mut self.bodies, &self.model.joints, &self.model.rods, dt);
    }

    /// Gymnasium's `step(action)` without the rendering; `None` is reset's `step(None)`.
    fn advance(&mut self, controls: Option<(f64, f64, f64)>) -> (f64, bool) {
        if let Some((steer, gas, brake)) = controls {
            self.apply_controls(steer, gas, brake);
        }
        let dt = 1.0 / FPS;
        let mut motor = [0.0; MAX_WHEELS];
        self.car_step(dt, &mut motor);
        self.world_step(dt, &motor);
        self.t += dt;
        let mut step_reward = 0.0;
        let mut terminated = false;
        if controls.is_some() {
            self.reward -= 0.1;
            step_reward = self.reward - self.prev_reward;
            self.prev_reward = self.reward;
            let n = self.visited.len();
            if self.tile_visited_count == n || self.new_lap {
                terminated = true;
            }
            let p = self.bodies[0].s.pos;
            if p.x.abs() > PLAYFIELD || p.y.abs() > PLAYFIELD || !p.x.is_finite() || !p.y.is_finite() {
                terminated = true;
                step_reward = -100.0;
            }
        }
        (step_reward, terminated)
    }

    fn controls(&self, action: &Action) -> Result<(f64, f64, f64), EnvError> {
        if self.opts.continuous {
            match action {
                Action::Continuous(v) if v.len() == 3 => {
                    carl_env::api::check_finite_action(ID, v)?;
                    Ok((-f64::from(v[0]), f64::from(v[1]), f64::from(v[2])))
                }
                Action::Continuous(v) => Err(EnvError::ActionLength {
                    env: ID,
                    expected: 3,
                    got: v.len(),
                }),
                Action::Discrete(_) => Err(EnvError::ActionKind {
                    env: ID,
                    expected: "continuous",
                    got: "discrete",
                }),
            }
        } else {
            let a = carl_env::api::discrete_action(ID, action, 5)?;
            let steer = -0.6 * f64::from(u8::from(a == 1)) + 0.6 * f64::from(u8::from(a == 2));
            Ok((
                steer,
                0.2 * f64::from(u8::from(a == 3)),
                0.8 * f64::from(u8::from(a == 4)),
            ))
        }
    }

    fn state_array(&self) -> Vec<f64> {
        let mut s = vec![0.0; STATE_DIM];
        s[0] = self.track_seed as f64;
        s[1] = self.t;
        s[2] = self.reward;
        s[3] = self.prev_reward;
        s[4] = f64::from(u8::from(self.new_lap));
        for (i, &v) in self.visited.iter().enumerate() {
            if v {
                s[HEADER + i / VISIT_BITS] += (1u64 << (i % VISIT_BITS)) as f64;
            }
        }
        let base = HEADER + VISIT_WORDS;
        for (k, b) in self.bodies.iter().enumerate() {
            let o = base + k * BODY_DIM;
            s[o..o + BODY_DIM].copy_from_slice(&[b.s.pos.x, b.s.pos.y, b.s.angle, b.s.vel.x, b.s.vel.y, b.s.w]);
        }
        let base = base + MAX_BODIES * BODY_DIM;
        for i in 0..MAX_WHEELS {
            let o = base + i * WHEEL_DIM;
            match self.wheels.get(i) {
                Some(w) => {
                    s[o..o + 6].copy_from_slice(&[w.omega, w.gas, w.brake, w.steer, w.angle, w.phase]);
                    for (j, &t) in w.tiles.iter().enumerate() {
                        s[o + 6 + j] = f64::from(t);
                    }
                }
                None => s[o + 6..o + WHEEL_DIM].fill(-1.0),
            }
        }
        s
    }

    fn load_state(&mut self, s: &[f64]) -> Result<(), EnvError> {
        let seed = (s[0].abs().floor().min(MAX_TRACK_SEED as f64)) as u64;
        self.load_track(seed)?;
        self.reset_episode();
        self.t = s[1];
        self.reward = s[2];
        self.prev_reward = s[3];
        self.new_lap = s[4] != 0.0;
        let n = self.visited.len();
        for i in 0..n {
            let word = s[HEADER + i / VISIT_BITS]
                .abs()
                .floor()
                .min(((1u64 << VISIT_BITS) - 1) as f64) as u64;
            self.visited[i] = word >> (i % VISIT_BITS) & 1 == 1;
        }
        self.tile_visited_count = self.visited.iter().filter(|v| **v).count();
        let base = HEADER + VISIT_WORDS;
        let hull = &s[base..base + BODY_DIM];
        for k in 0..self.bodies.len() {
            let o = base + k * BODY_DIM;
            let row = &s[o..o + BODY_DIM];
            self.bodies[k].s = if k > 0 && row.iter().all(|x| *x == 0.0) {
                // A state of a vehicle without this body: spawn it as at reset.
                let (sn, c) = hull[2].sin_cos();
                BodyState {
                    pos: V2::new(hull[0], hull[1]) + self.model.offsets[k].rot(sn, c),
                    angle: hull[2],
                    vel: V2::new(hull[3], hull[4]),
                    w: 0.0,
                }
            } else {
                BodyState {
                    pos: V2::new(row[0], row[1]),
                    angle: row[2],
                    vel: V2::new(row[3], row[4]),
                    w: row[5],
                }
            };
            self.bodies[k].force = V2::ZERO;
            self.bodies[k].torque = 0.0;
        }
        let base = base + MAX_BODIES * BODY_DIM;
        for (i, w) in self.wheels.iter_mut().enumerate() {
            let o = base + i * WHEEL_DIM;
            let r = &s[o..o + WHEEL_DIM];
            w.omega = r[0];
            w.gas = r[1];
            w.brake = r[2];
            w.steer = r[3];
            w.angle = r[4];
            w.phase = r[5];
            let mut tiles: Vec<i32> = r[6..]
                .iter()
                .map(|x| x.round())
                .filter(|x| *x >= 0.0 && *x < n as f64)
                .map(|x| x as i32)
                .collect();
            tiles.sort_unstable();
            tiles.dedup();
            w.tiles = [-1; MAX_WHEEL_TILES];
            for (j, t) in tiles.into_iter().enumerate() {
                w.tiles[j] = t;
            }
        }
        Ok(())
    }

    // ----------------------------------------------------------------------------- pictures

    /// Draw the scene as Gymnasium's `_render` does on its 1000×800 surface, scaled to the
    /// canvas (`sx`, `sy` canvas samples per surface pixel).
    fn draw(&self, canvas: &mut Canvas, cw: usize, ch: usize) {
        let (sx, sy) = (cw as f64 / WINDOW_W, ch as f64 / WINDOW_H);
        canvas.reset(cw, ch, [0, 0, 0]);
        let Some(track) = self.track.as_deref() else { return };
        let hull = &self.bodies[0].s;
        let angle = -hull.angle;
        let zoom = 0.1 * track::SCALE * (1.0 - self.t).max(0.0) + ZOOM * track::SCALE * self.t.min(1.0);
        let (sa, ca) = angle.sin_cos();
        let pos = hull.pos;
        let to_canvas = |x: f64, y: f64| {
            let d = V2::new(x - pos.x, y - pos.y).rot(sa, ca) * zoom;
            ((WINDOW_W / 2.0 + d.x) * sx, (WINDOW_H - (WINDOW_H / 4.0 + d.y)) * sy)
        };
        let mut buf = [(0.0f64, 0.0f64); 16];
        let mut poly = |canvas: &mut Canvas, pts: &mut dyn Iterator<Item = (f64, f64)>, color: [u8; 3]| {
            let mut n = 0;
            for (x, y) in pts {
                if n < 16 {
                    buf[n] = to_canvas(x, y);
                    n += 1;
                }
            }
            canvas.fill_polygon(&buf[..n], color);
        };
        let b = PLAYFIELD;
        poly(canvas, &mut [(b, b), (b, -b), (-b, -b), (-b, b)].into_iter(), BG_COLOR);
        // Grass checkerboard: only squares near the view (the view spans < 100 m at any zoom
        // after the first frames; the first frames are zoomed out and see everything).
        let view_r = (WINDOW_W.hypot(WINDOW_H)) / zoom.max(1e-9);
        for gx in (-20..20).step_by(2) {
            for gy in (-20..20).step_by(2) {
                let x0 = GRASS_DIM * f64::from(gx);
                let y0 = GRASS_DIM * f64::from(gy);
                let cx = x0 + GRASS_DIM / 2.0 - pos.x;
                let cy = y0 + GRASS_DIM / 2.0 - pos.y;
                if cx * cx + cy * cy > (view_r + GRASS_DIM).powi(2) {
                    continue;
                }
                let pts = [
                    (x0 + GRASS_DIM, y0),
                    (x0, y0),
                    (x0, y0 + GRASS_DIM),
                    (x0 + GRASS_DIM, y0 + GRASS_DIM),
                ];
                poly(canvas, &mut pts.into_iter(), GRASS_COLOR);
            }
        }
        for (i, q) in track.tiles.iter().enumerate() {
            let (cx, cy) = (q.pts[0].0 - pos.x, q.pts[0].1 - pos.y);
            if cx * cx + cy * cy > (view_r + 20.0).powi(2) {
                continue;
            }
            let color = if self.visited.get(i).copied().unwrap_or(false) {
                track::ROAD_COLOR
            } else {
                q.color
            };
            poly(canvas, &mut q.pts.into_iter(), color);
        }
        for q in &track.borders {
            let (cx, cy) = (q.pts[0].0 - pos.x, q.pts[0].1 - pos.y);
            if cx * cx + cy * cy > (view_r + 20.0).powi(2) {
                continue;
            }
            poly(canvas, &mut q.pts.into_iter(), q.color);
        }
        // Car: wheels (with the rotating stripe), then hull, trailer, axle.
        for (i, (w, d)) in self.wheels.iter().zip(&self.model.wheels).enumerate() {
            let corners = self.wheel_corners(i);
            poly(canvas, &mut corners.iter().map(|c| (c.x, c.y)), d.color);
            let (a1, a2) = (w.phase, w.phase + 1.2);
            let (s1, s2) = (a1.sin(), a2.sin());
            let (mut c1, mut c2) = (a1.cos(), a2.cos());
            if s1 > 0.0 && s2 > 0.0 {
                continue;
            }
            if s1 > 0.0 {
                c1 = np_sign(c1);
            }
            if s2 > 0.0 {
                c2 = np_sign(c2);
            }
            // Gymnasium's module constants WHEEL_W = 14, WHEEL_R = 27 for every vehicle.
            let (hw, hr) = (14.0 * SIZE, 27.0 * SIZE);
            let b = &self.bodies[d.body];
            let c = b.world_point(d.mount);
            let (s, co) = (b.s.angle + w.angle).sin_cos();
            let stripe = [
                V2::new(-hw, hr * c1),
                V2::new(hw, hr * c1),
                V2::new(hw, hr * c2),
                V2::new(-hw, hr * c2),
            ];
            poly(
                canvas,
                &mut stripe.iter().map(|p| c + p.rot(s, co)).map(|p| (p.x, p.y)),
                WHEEL_WHITE,
            );
        }
        let order: &[usize] = match self.bodies.len() {
            1 => &[0],
            2 => &[0, 1],
            _ => &[0, 2, 1],
        };
        for &k in order {
            let b = &self.bodies[k];
            for sh in &self.model.shapes[k] {
                poly(
                    canvas,
                    &mut sh.verts.iter().map(|v| b.world_point(*v)).map(|p| (p.x, p.y)),
                    sh.color,
                );
            }
        }
        self.draw_indicators(canvas, sx, sy);
    }

    /// CARL's `_render_indicators` (one ABS bar per wheel) and the reward counter, in surface
    /// pixels (after the flip).
    fn draw_indicators(&self, canvas: &mut Canvas, sx: f64, sy: f64) {
        let (w, h) = (WINDOW_W, WINDOW_H);
        let s = w / 40.0;
        let hh = h / 40.0;
        let quad = |canvas: &mut Canvas, pts: [(f64, f64); 4], color: [u8; 3]| {
            let p = pts.map(|(x, y)| (x * sx, y * sy));
            canvas.fill_polygon(&p, color);
        };
        quad(
            canvas,
            [(w, h), (w, h - 5.0 * hh), (0.0, h - 5.0 * hh), (0.0, h)],
            [0, 0, 0],
        );
        let vertical = |place: f64, val: f64| {
            [
                (place * s, h - (hh + hh * val)),
                ((place + 1.0) * s, h - (hh + hh * val)),
                ((place + 1.0) * s, h - hh),
                (place * s, h - hh),
            ]
        };
        let horiz = |place: f64, val: f64| {
            [
                (place * s, h - 4.0 * hh),
                ((place + val) * s, h - 4.0 * hh),
                ((place + val) * s, h - 2.0 * hh),
                (place * s, h - 2.0 * hh),
            ]
        };
        let speed = self.hull_speed();
        if speed.abs() > 1e-4 {
            quad(canvas, vertical(5.0, 0.02 * speed), [255, 255, 255]);
        }
        for (i, wh) in self.wheels.iter().enumerate() {
            if wh.omega.abs() > 1e-4 {
                quad(
                    canvas,
                    vertical(7.0 + i as f64, 0.01 * wh.omega),
                    [(i * 10) as u8, 0, 255],
                );
            }
        }
        let steer = self.wheels[0].angle;
        if steer.abs() > 1e-4 {
            quad(canvas, horiz(20.0, -10.0 * steer), [0, 255, 0]);
        }
        let gyro = self.bodies[0].s.w;
        if gyro.abs() > 1e-4 {
            quad(canvas, horiz(30.0, -0.8 * gyro), [255, 0, 0]);
        }
        // "%04i" % reward, white, centred at (60, H - 2.5 h), about 30 px cap height.
        let text = format!("{:04}", self.reward.trunc() as i64);
        let unit = 30.0 / 7.0;
        let n = text.chars().count() as f64;
        let width = (n * 6.0 - 1.0) * unit;
        let (x0, y0) = (60.0 - width / 2.0, h - 2.5 * hh - 3.5 * unit);
        for (ci, ch) in text.chars().enumerate() {
            for (col, row) in carl_pixels::font::glyph(ch) {
                let x = x0 + (ci as f64 * 6.0 + f64::from(col)) * unit;
                let y = y0 + f64::from(row) * unit;
                quad(
                    canvas,
                    [(x, y), (x + unit, y), (x + unit, y + unit), (x, y + unit)],
                    [255, 255, 255],
                );
            }
        }
    }

    fn render_obs(&self, obs: &mut [f32]) {
        let k = self.opts.obs_supersample.clamp(1, 8);
        let mut guard = self.canvas.lock().unwrap_or_else(|e| e.into_inner());
        self.draw(&mut guard, STATE_W * k, STATE_H * k);
        guard.downsample_into(k, obs);
    }

    /// The 600×400 picture (Gymnasium's `rgb_array`).
    pub fn render_frame(&self) -> Option<carl_pixels::Frame> {
        self.track.as_ref()?;
        let k = RENDER_SUPERSAMPLE;
        let mut canvas = Canvas::default();
        self.draw(&mut canvas, VIDEO_W * k, VIDEO_H * k);
        Some(carl_pixels::Frame {
            width: VIDEO_W as u32,
            height: VIDEO_H as u32,
            rgb: canvas.downsample_rgb8(k),
        })
    }
}

impl carl_env::runtime::Runtime for VehicleRacing {}

impl Env for VehicleRacing {
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
        Space::Box {
            low: vec![0.0; OBS_DIM],
            high: vec![255.0; OBS_DIM],
            shape: vec![STATE_H, STATE_W, 3],
            dtype: DType::UInt8,
        }
    }
    fn action_space(&self) -> Space {
        if self.opts.continuous {
            Space::Box {
                low: vec![-1.0, 0.0, 0.0],
                high: vec![1.0, 1.0, 1.0],
                shape: vec![3],
                dtype: DType::Float32,
            }
        } else {
            Space::Discrete { n: 5, start: 0 }
        }
    }

    fn reset_into(&mut self, seed: Option<u64>, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(ID, obs, OBS_DIM)?;
        if let Some(seed) = seed {
            self.rng = rng_for(seed);
        }
        // Gymnasium retries `_create_track` on the env's generator; we draw one track seed
        // (and another if a seed yields no track), so the track is a function of one number.
        loop {
            let ts = self.rng.next_u64() >> 11;
            if self.load_track(ts).is_ok() {
                break;
            }
        }
        self.reset_episode();
        let p = self.track.as_ref().map(|t| t.points[0]).expect("track loaded");
        self.place_vehicle(p.beta, p.x, p.y);
        self.advance(None);
        self.render_obs(obs);
        Ok(())
    }

    fn step_into(&mut self, action: &Action, obs: &mut [f32]) -> Result<StepOutcome, EnvError> {
        check_obs_len(ID, obs, OBS_DIM)?;
        if self.track.is_none() {
            return Err(EnvError::NeedsReset { env: ID });
        }
        let c = self.controls(action)?;
        let (reward, terminated) = self.advance(Some(c));
        self.render_obs(obs);
        Ok(StepOutcome {
            reward,
            terminated,
            truncated: false,
        })
    }

    fn observe_into(&self, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(ID, obs, OBS_DIM)?;
        if self.track.is_none() {
            return Err(EnvError::NeedsReset { env: ID });
        }
        self.render_obs(obs);
        Ok(())
    }

    fn state(&self) -> Vec<f64> {
        self.state_array()
    }

    fn set_state(&mut self, state: &[f64]) -> Result<(), EnvError> {
        let s: [f64; STATE_DIM] = carl_env::api::check_state(ID, state)?;
        self.load_state(&s)
    }

    fn render(&self) -> Option<carl_pixels::Frame> {
        self.render_frame()
    }
}
