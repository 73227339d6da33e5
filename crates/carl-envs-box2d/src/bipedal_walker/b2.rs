//! The walker on [`carl_physics2d`] (Box2D 2.3 semantics): Gymnasium's bodies, fixtures and
//! joints in Gymnasium's creation order (terrain obstacles, surface edges one static body each,
//! hull, then per leg upper, lower, hip, knee), stepped with `Step(1/FPS, 6·30, 2·30)`.

use super::{
    BipedalWalkerParams, BodyState, HIP_LIMITS, HIP_REFERENCE, HULL_POLY, KNEE_LIMITS, Terrain, size, wrap_pi,
};
use carl_physics2d::{
    BodyKind, Filter, FixtureDef, Polygon, RevoluteDef, Shape, V2, World as B2World, shapes::PolygonError, v2,
};

/// Gymnasium's `world.Step(1.0 / FPS, 6 * 30, 2 * 30)`.
pub const VELOCITY_ITERATIONS: usize = 6 * 30;
pub const POSITION_ITERATIONS: usize = 2 * 30;

const TERRAIN: Filter = Filter {
    category: 0x0001,
    mask: 0xFFFF,
};
const WALKER: Filter = Filter {
    category: 0x0020,
    mask: 0x0001,
};

#[derive(Debug, Clone)]
pub(super) struct Box2dWalker {
    pub world: B2World,
    /// Hull, upper 0, lower 0, upper 1, lower 1.
    pub bodies: [usize; 5],
    /// Hip 0, knee 0, hip 1, knee 1.
    pub joints: [usize; 4],
    pub hull_fixture: usize,
    pub lower_fixtures: [usize; 2],
}

/// Where Gymnasium's `reset` creates the five bodies (legs unassembled: Box2D's position solver
/// pulls them onto their anchors in the first steps).
pub(super) fn gymnasium_start(p: &BipedalWalkerParams) -> [BodyState; 5] {
    let (x, y) = (p.init_x(), p.terrain_height + 2.0 * p.leg_h);
    let mut out = [BodyState {
        x,
        y,
        ..Default::default()
    }; 5];
    for (leg, i) in [-1.0, 1.0].into_iter().enumerate() {
        out[1 + 2 * leg] = BodyState {
            x,
            y: y - p.leg_h / 2.0 - p.leg_down,
            angle: i * 0.05,
            ..Default::default()
        };
        out[2 + 2 * leg] = BodyState {
            x,
            y: y - p.leg_h * 3.0 / 2.0 - p.leg_down,
            angle: i * 0.05,
            ..Default::default()
        };
    }
    out
}

fn hull_polygon(scale: f64) -> Result<Polygon, PolygonError> {
    let pts: Vec<V2> = HULL_POLY.iter().map(|(x, y)| v2(x / scale, y / scale)).collect();
    Polygon::from_points(&pts)
}

impl Box2dWalker {
    pub fn build(p: &BipedalWalkerParams, terrain: &Terrain, bodies: &[BodyState; 5]) -> Box2dWalker {
        let mut world = B2World::new(v2(p.gravity_x, p.gravity_y));
        let friction = p.friction.max(0.0);
        let ground = |shape| FixtureDef {
            shape,
            density: 0.0,
            friction,
            restitution: 0.0,
            filter: TERRAIN,
        };
        for q in &terrain.quads {
            let pts: Vec<V2> = q.iter().map(|&(x, y)| v2(x, y)).collect();
            if let Ok(poly) = Polygon::from_points(&pts) {
                let b = world.add_body(BodyKind::Static, V2::ZERO, 0.0);
                world.add_fixture(b, ground(Shape::Polygon(poly)));
            }
        }
        for i in 0..terrain.x.len().saturating_sub(1) {
            let b = world.add_body(BodyKind::Static, V2::ZERO, 0.0);
            let e = Shape::Edge(v2(terrain.x[i], terrain.y[i]), v2(terrain.x[i + 1], terrain.y[i + 1]));
            world.add_fixture(b, ground(e));
        }
        let dynamic = |world: &mut B2World, s: &BodyState, shape: Shape, density: f64, friction: f64| {
            let def = FixtureDef {
                shape,
                density,
                friction,
                restitution: 0.0,
                filter: WALKER,
            };
            world.add_dynamic(v2(s.x, s.y), s.angle, v2(s.vx, s.vy), s.w, def)
        };
        let sc = size(p.scale);
        let hull_shape = hull_polygon(sc).unwrap_or_else(|_| Polygon::new_box(0.5, 0.2));
        let (hull, hull_fixture) = dynamic(&mut world, &bodies[0], Shape::Polygon(hull_shape), 5.0, 0.1);
        let (lw, lh) = (size(p.leg_w), size(p.leg_h));
        let mut handles = [hull; 5];
        let mut joints = [0; 4];
        let mut lower_fixtures = [0; 2];
        for leg in 0..2 {
            let upper_shape = Shape::Polygon(Polygon::new_box(lw / 2.0, lh / 2.0));
            let (upper, _) = dynamic(&mut world, &bodies[1 + 2 * leg], upper_shape, 1.0, 0.2);
            let lower_shape = Shape::Polygon(Polygon::new_box(0.8 * lw / 2.0, lh / 2.0));
            let (lower, lower_f) = dynamic(&mut world, &bodies[2 + 2 * leg], lower_shape, 1.0, 0.2);
            let joint = |a, b, anchor_a, anchor_b, reference, limits: [f64; 2]| RevoluteDef {
                body_a: a,
                body_b: b,
                local_anchor_a: anchor_a,
                local_anchor_b: anchor_b,
                reference_angle: reference,
                enable_limit: true,
                lower: limits[0],
                upper: limits[1],
                enable_motor: true,
                motor_speed: 0.0,
                max_motor_torque: 0.0,
            };
            joints[2 * leg] = world.add_revolute(joint(
                hull,
                upper,
                v2(0.0, p.leg_down),
                v2(0.0, lh / 2.0),
                HIP_REFERENCE[leg],
                HIP_LIMITS,
            ));
            joints[2 * leg + 1] = world.add_revolute(joint(
                upper,
                lower,
                v2(0.0, -lh / 2.0),
                v2(0.0, lh / 2.0),
                0.0,
                KNEE_LIMITS,
            ));
            handles[1 + 2 * leg] = upper;
            handles[2 + 2 * leg] = lower;
            lower_fixtures[leg] = lower_f;
        }
        Box2dWalker {
            world,
            bodies: handles,
            joints,
            hull_fixture,
            lower_fixtures,
        }
    }

    pub fn body_state(&self, k: usize) -> BodyState {
        let b = &self.world.bodies[self.bodies[k]];
        let pos = b.position();
        BodyState {
            x: pos.x,
            y: pos.y,
            angle: b.angle(),
            vx: b.v.x,
            vy: b.v.y,
            w: b.w,
        }
    }

    /// Joint angles (wrapped to ±π) and speeds, hip 0, knee 0, hip 1, knee 1: Box2D's
    /// `angle = angleB − angleA − referenceAngle`, `speed = ωB − ωA`.
    pub fn joints(&self) -> ([f64; 4], [f64; 4]) {
        let pairs = [(0, 1), (1, 2), (0, 3), (3, 4)];
        let reference = [HIP_REFERENCE[0], 0.0, HIP_REFERENCE[1], 0.0];
        let mut q = [0.0; 4];
        let mut dq = [0.0; 4];
        for (j, (a, b)) in pairs.into_iter().enumerate() {
            let (a, b) = (self.body_state(a), self.body_state(b));
            q[j] = wrap_pi(b.angle - a.angle - reference[j]);
            dq[j] = b.w - a.w;
        }
        (q, dq)
    }

    pub fn set_motor(&mut self, j: usize, speed: f64, torque: f64) {
        let def = &mut self.world.joints[self.joints[j]].def;
        def.motor_speed = speed;
        def.max_motor_torque = torque;
    }

    pub fn mass(&self, k: usize) -> f64 {
        self.world.bodies[self.bodies[k]].mass
    }
}
