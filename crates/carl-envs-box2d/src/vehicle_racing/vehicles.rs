//! CARL's parking garage as a data table: the 29 vehicles of carl-bench's `PARKING_GARAGE`, in
//! its order (`VEHICLE` = index into [`VEHICLES`]).
//!
//! Source: automl/CARL (`carl/envs/gymnasium/box2d/parking_garage/{race_car,street_car,bus,trike}.py`,
//! commit 14c8fee4, the code carl-bench 1.1.1 ships) and Gymnasium 1.4 `car_dynamics.py` for the
//! race car. Lengths are in CARL's "pixel" units, multiplied by [`SIZE`] to get metres; engine
//! power, wheel moment of inertia and friction limit are given as the factor that CARL multiplies
//! by `SIZE²`. Polygons are listed as in the sources (Box2D takes their convex hull).

/// Pixel-to-metre factor of the vehicle geometry (`SIZE`).
pub const SIZE: f64 = 0.02;

/// A fixture: polygon vertices (px, body frame) and density (kg/m²).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fixture {
    pub verts: &'static [(f64, f64)],
    pub density: f64,
}

/// Small trailer: one body hinged to the hull (revolute joint with limits and a friction motor).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SmallTrailer {
    pub poly: Fixture,
    /// Hinge anchor on the hull and on the trailer (px).
    pub hull_anchor: (f64, f64),
    pub trailer_anchor: (f64, f64),
    /// `maxMotorTorque` of the hinge (motor speed 0), in units of `SIZE²`.
    pub motor_torque: f64,
    /// Hinge limit ±rad.
    pub limit: f64,
    pub wheels: &'static [(f64, f64)],
    /// Brake factor of the trailer wheels (`w.brake = b * factor`).
    pub brake: f64,
}

/// Large trailer: an axle body tied to the hull by two distance joints (rods of `rod_length` m
/// from `hull_anchor` to `axle_anchor_x` = ±x at `axle_anchor_y`) and a trailer body hinged to the
/// axle at `hinge` (same local point on both). Wheels with `y > -170` px sit on the axle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LargeTrailer {
    pub axle: Fixture,
    pub body: [Fixture; 2],
    pub hull_anchor: (f64, f64),
    pub axle_anchor_x: f64,
    pub axle_anchor_y: f64,
    pub rod_length: f64,
    pub hinge: (f64, f64),
    pub motor_torque: f64,
    pub limit: f64,
    pub wheels: &'static [(f64, f64)],
    pub brake: f64,
}

/// One vehicle family (race car, street car, bus, tuk-tuk): body, engine, tyres, trailers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Family {
    pub name: &'static str,
    /// `ENGINE_POWER / SIZE²`.
    pub engine_power: f64,
    /// `WHEEL_MOMENT_OF_INERTIA / SIZE²`.
    pub wheel_moi: f64,
    /// `FRICTION_LIMIT / SIZE²`.
    pub friction_limit: f64,
    /// Wheel half-length (`WHEEL_R`) and half-width (`WHEEL_W`), px.
    pub wheel_r: f64,
    pub wheel_w: f64,
    pub hull: &'static [Fixture],
    pub hull_color: [u8; 3],
    /// Wheel centres (px), in `WHEELPOS` order.
    pub wheels: &'static [(f64, f64)],
    /// Steering-joint limit ±rad of the body's wheels.
    pub wheel_limit: f64,
    /// Wheels that steer.
    pub steered: &'static [usize],
    /// Wheels driven with front- and with rear-wheel drive.
    pub front_drive: &'static [usize],
    pub rear_drive: &'static [usize],
    /// Brake factor of each body wheel.
    pub brake: &'static [f64],
    pub small_trailer: SmallTrailer,
    pub large_trailer: Option<LargeTrailer>,
}

/// Which trailer a vehicle pulls.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TrailerKind {
    None,
    Small,
    Large,
}

/// One entry of the parking garage.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Vehicle {
    pub name: &'static str,
    pub family: &'static Family,
    pub fwd: bool,
    pub rwd: bool,
    pub trailer: TrailerKind,
}

const WHEEL_COLOR_DRIVEN: [u8; 3] = [153, 153, 204];
pub const MOTOR_WHEEL_COLOR: [u8; 3] = WHEEL_COLOR_DRIVEN;
pub const WHEEL_COLOR: [u8; 3] = [0, 0, 0];
pub const TRAILER_COLOR: [u8; 3] = [0, 0, 204];
pub const AXLE_COLOR: [u8; 3] = [0, 204, 204];

const fn fx(verts: &'static [(f64, f64)], density: f64) -> Fixture {
    Fixture { verts, density }
}

/// Gymnasium's car (`car_dynamics.py`), CARL's `RaceCar`.
pub const RACE_CAR: Family = Family {
    name: "race car",
    engine_power: 100_000_000.0,
    wheel_moi: 4_000.0,
    friction_limit: 1_000_000.0,
    wheel_r: 27.0,
    wheel_w: 14.0,
    hull: &[
        fx(&[(-60.0, 130.0), (60.0, 130.0), (60.0, 110.0), (-60.0, 110.0)], 1.0),
        fx(&[(-15.0, 120.0), (15.0, 120.0), (20.0, 20.0), (-20.0, 20.0)], 1.0),
        fx(
            &[
                (25.0, 20.0),
                (50.0, -10.0),
                (50.0, -40.0),
                (20.0, -90.0),
                (-20.0, -90.0),
                (-50.0, -40.0),
                (-50.0, -10.0),
                (-25.0, 20.0),
            ],
            1.0,
        ),
        fx(&[(-50.0, -120.0), (50.0, -120.0), (50.0, -90.0), (-50.0, -90.0)], 1.0),
    ],
    hull_color: [204, 0, 0],
    wheels: &[(-55.0, 80.0), (55.0, 80.0), (-55.0, -82.0), (55.0, -82.0)],
    wheel_limit: 0.4,
    steered: &[0, 1],
    front_drive: &[0, 1],
    rear_drive: &[2, 3],
    brake: &[0.4, 0.4, 0.6, 0.6],
    small_trailer: SmallTrailer {
        poly: fx(
            &[
                (-15.0, -130.0),
                (15.0, -130.0),
                (-60.0, -160.0),
                (60.0, -160.0),
                (-60.0, -300.0),
                (60.0, -300.0),
            ],
            0.75,
        ),
        hull_anchor: (0.0, -120.0),
        trailer_anchor: (0.0, -135.0),
        motor_torque: 180.0 * 900.0,
        limit: 0.9,
        wheels: &[(-65.0, -230.0), (65.0, -230.0)],
        brake: 0.7,
    },
    large_trailer: Some(LargeTrailer {
        axle: fx(&[(-60.0, -140.0), (60.0, -140.0), (-60.0, -170.0), (60.0, -170.0)], 0.5),
        body: [
            fx(&[(-10.0, -140.0), (10.0, -140.0), (-10.0, -200.0), (10.0, -200.0)], 5.0),
            fx(&[(-60.0, -200.0), (60.0, -200.0), (-60.0, -500.0), (60.0, -500.0)], 0.5),
        ],
        hull_anchor: (0.0, -120.0),
        axle_anchor_x: 7.5,
        axle_anchor_y: -140.0,
        rod_length: 1.25,
        hinge: (0.0, -155.0),
        motor_torque: 360.0 * 3000.0,
        limit: 0.5,
        wheels: &[(-65.0, -155.0), (65.0, -155.0), (-65.0, -485.0), (65.0, -485.0)],
        brake: 0.8,
    }),
};

/// CARL's `StreetCar`.
pub const STREET_CAR: Family = Family {
    name: "street car",
    engine_power: 10_000_000.0,
    wheel_moi: 1_000.0,
    friction_limit: 750_000.0,
    wheel_r: 27.0,
    wheel_w: 10.0,
    hull: &[
        fx(&[(-40.0, 180.0), (40.0, 180.0), (55.0, 160.0), (-55.0, 160.0)], 1.0),
        fx(&[(-55.0, 160.0), (55.0, 160.0), (55.0, -60.0), (-55.0, -60.0)], 1.0),
        fx(&[(55.0, -40.0), (-55.0, -40.0), (-65.0, -75.0), (65.0, -75.0)], 1.0),
    ],
    hull_color: [255, 79, 0],
    wheels: &[(-60.0, 140.0), (60.0, 140.0), (-60.0, -30.0), (60.0, -30.0)],
    wheel_limit: 0.4,
    steered: &[0, 1],
    front_drive: &[0, 1],
    rear_drive: &[2, 3],
    brake: &[0.4, 0.4, 0.6, 0.6],
    small_trailer: SmallTrailer {
        poly: fx(
            &[
                (-15.0, -85.0),
                (15.0, -85.0),
                (-60.0, -115.0),
                (60.0, -115.0),
                (-60.0, -255.0),
                (60.0, -255.0),
            ],
            0.75,
        ),
        hull_anchor: (0.0, -75.0),
        trailer_anchor: (0.0, -85.0),
        motor_torque: 180.0 * 900.0,
        limit: 0.9,
        wheels: &[(-65.0, -185.0), (65.0, -185.0)],
        brake: 0.7,
    },
    large_trailer: Some(LargeTrailer {
        axle: fx(&[(-60.0, -95.0), (60.0, -95.0), (-60.0, -125.0), (60.0, -125.0)], 0.5),
        body: [
            fx(&[(-10.0, -95.0), (10.0, -95.0), (-10.0, -155.0), (10.0, -155.0)], 5.0),
            fx(&[(-60.0, -155.0), (60.0, -155.0), (-60.0, -455.0), (60.0, -455.0)], 0.5),
        ],
        hull_anchor: (0.0, -75.0),
        axle_anchor_x: 7.5,
        axle_anchor_y: -95.0,
        rod_length: 1.25,
        hinge: (0.0, -110.0),
        motor_torque: 360.0 * 3000.0,
        limit: 0.5,
        wheels: &[(-65.0, -110.0), (65.0, -110.0), (-65.0, -420.0), (65.0, -420.0)],
        brake: 0.8,
    }),
};

/// CARL's `Bus`.
pub const BUS: Family = Family {
    name: "bus",
    engine_power: 50_000_000.0,
    wheel_moi: 6_000.0,
    friction_limit: 1_250_000.0,
    wheel_r: 27.0,
    wheel_w: 20.0,
    hull: &[
        fx(&[(-70.0, 700.0), (70.0, 700.0), (80.0, 550.0), (-80.0, 550.0)], 0.66),
        fx(&[(-90.0, 550.0), (90.0, 550.0), (90.0, -60.0), (-90.0, -60.0)], 0.2),
    ],
    hull_color: [255, 216, 0],
    wheels: &[(-85.0, 650.0), (85.0, 650.0), (-85.0, -30.0), (85.0, -30.0)],
    wheel_limit: 0.7,
    steered: &[0, 1],
    front_drive: &[0, 1],
    rear_drive: &[2, 3],
    brake: &[0.4, 0.4, 0.6, 0.6],
    small_trailer: SmallTrailer {
        poly: fx(
            &[
                (-15.0, -70.0),
                (15.0, -70.0),
                (-60.0, -100.0),
                (60.0, -100.0),
                (-60.0, -240.0),
                (60.0, -240.0),
            ],
            2.0,
        ),
        hull_anchor: (0.0, -60.0),
        trailer_anchor: (0.0, -70.0),
        motor_torque: 180.0 * 100.0,
        limit: 0.9,
        wheels: &[(-65.0, -170.0), (65.0, -170.0)],
        brake: 0.7,
    },
    large_trailer: Some(LargeTrailer {
        axle: fx(&[(-90.0, -80.0), (90.0, -80.0), (-90.0, -110.0), (90.0, -110.0)], 0.5),
        body: [
            fx(&[(-40.0, -80.0), (40.0, -80.0), (-40.0, -140.0), (40.0, -140.0)], 5.0),
            fx(&[(-90.0, -140.0), (90.0, -140.0), (-90.0, -640.0), (90.0, -640.0)], 1.5),
        ],
        hull_anchor: (0.0, -60.0),
        axle_anchor_x: 7.5,
        axle_anchor_y: -80.0,
        rod_length: 1.25,
        hinge: (0.0, -95.0),
        motor_torque: 360.0 * 3000.0,
        limit: 0.5,
        wheels: &[(-95.0, -95.0), (95.0, -95.0), (-95.0, -605.0), (95.0, -605.0)],
        brake: 0.8,
    }),
};

/// CARL's `TukTuk` (`trike.py`): one steered front wheel, two driven rear wheels. Its `brake`
/// loops over `self.wheels[0]`, which iterates the front wheel's Box2D *fixtures* (pybox2d bodies
/// are iterable) and sets an unused attribute on them: the front wheel is never braked. We keep
/// that (factor 0) rather than the evident intent (`10 * b`).
pub const TUK_TUK: Family = Family {
    name: "tuk-tuk",
    engine_power: 25_000_000.0,
    wheel_moi: 2_000.0,
    friction_limit: 1_000_000.0,
    wheel_r: 30.0,
    wheel_w: 10.0,
    hull: &[
        fx(&[(-15.0, 70.0), (15.0, 70.0), (20.0, 50.0), (-20.0, 50.0)], 1.0),
        fx(&[(-65.0, -120.0), (65.0, -120.0), (45.0, 50.0), (-45.0, 50.0)], 1.0),
    ],
    hull_color: [51, 127, 255],
    wheels: &[(0.0, 80.0), (-70.0, -82.0), (70.0, -82.0)],
    wheel_limit: 0.9,
    steered: &[0],
    front_drive: &[],
    rear_drive: &[1, 2],
    brake: &[0.0, 0.6, 0.6],
    small_trailer: SmallTrailer {
        poly: fx(
            &[
                (-15.0, -130.0),
                (15.0, -130.0),
                (-60.0, -160.0),
                (60.0, -160.0),
                (-60.0, -300.0),
                (60.0, -300.0),
            ],
            0.75,
        ),
        hull_anchor: (0.0, -120.0),
        trailer_anchor: (0.0, -135.0),
        motor_torque: 180.0 * 900.0,
        limit: 0.9,
        wheels: &[(-65.0, -230.0), (65.0, -230.0)],
        brake: 0.8,
    },
    large_trailer: None,
};

const fn v(name: &'static str, family: &'static Family, fwd: bool, rwd: bool, trailer: TrailerKind) -> Vehicle {
    Vehicle {
        name,
        family,
        fwd,
        rwd,
        trailer,
    }
}

use TrailerKind::{Large, None as NoTrailer, Small};

/// carl-bench's `PARKING_GARAGE`, in order.
pub const VEHICLES: [Vehicle; 29] = [
    v("RaceCar", &RACE_CAR, false, true, NoTrailer),
    v("FWDRaceCar", &RACE_CAR, true, false, NoTrailer),
    v("AWDRaceCar", &RACE_CAR, true, true, NoTrailer),
    v("RaceCarSmallTrailer", &RACE_CAR, false, true, Small),
    v("FWDRaceCarSmallTrailer", &RACE_CAR, true, false, Small),
    v("AWDRaceCarSmallTrailer", &RACE_CAR, true, true, Small),
    v("RaceCarLargeTrailer", &RACE_CAR, false, true, Large),
    v("FWDRaceCarLargeTrailer", &RACE_CAR, true, false, Large),
    v("AWDRaceCarLargeTrailer", &RACE_CAR, true, true, Large),
    v("StreetCar", &STREET_CAR, false, true, NoTrailer),
    v("FWDStreetCar", &STREET_CAR, true, false, NoTrailer),
    v("AWDStreetCar", &STREET_CAR, true, true, NoTrailer),
    v("StreetCarSmallTrailer", &STREET_CAR, false, true, Small),
    v("FWDStreetCarSmallTrailer", &STREET_CAR, true, false, Small),
    v("AWDStreetCarSmallTrailer", &STREET_CAR, true, true, Small),
    v("StreetCarLargeTrailer", &STREET_CAR, false, true, Large),
    v("FWDStreetCarLargeTrailer", &STREET_CAR, true, false, Large),
    v("AWDStreetCarLargeTrailer", &STREET_CAR, true, true, Large),
    v("Bus", &BUS, false, true, NoTrailer),
    v("FWDBus", &BUS, true, false, NoTrailer),
    v("AWDBus", &BUS, true, true, NoTrailer),
    v("BusSmallTrailer", &BUS, false, true, Small),
    v("FWDBusSmallTrailer", &BUS, true, false, Small),
    v("AWDBusSmallTrailer", &BUS, true, true, Small),
    v("BusLargeTrailer", &BUS, false, true, Large),
    v("FWDBusLargeTrailer", &BUS, true, false, Large),
    v("AWDBusLargeTrailer", &BUS, true, true, Large),
    v("TukTuk", &TUK_TUK, false, true, NoTrailer),
    v("TukTukSmallTrailer", &TUK_TUK, false, true, Small),
];
