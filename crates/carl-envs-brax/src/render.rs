//! Software rendering of a robot world: a perspective camera looking at the root link from the
//! side and above, every collider projected to a filled silhouette (convex hull of its projected
//! outline), drawn far to near (painter's order) over a gridded ground.

use rapier3d::prelude::*;

use carl_pixels::{Canvas, Color, Frame};

use super::articulated::ArticulatedWorld;
use super::world::RobotWorld;

pub const WIDTH: u32 = 480;
pub const HEIGHT: u32 = 360;
const SKY: Color = Color(214, 228, 240);
const GROUND_A: Color = Color(196, 206, 186);
const GROUND_B: Color = Color(178, 190, 168);
const PALETTE: [Color; 6] = [
    Color(201, 120, 66),
    Color(84, 122, 178),
    Color(112, 160, 96),
    Color(176, 96, 140),
    Color(196, 168, 72),
    Color(96, 150, 160),
];

/// A pinhole camera.
#[derive(Debug, Clone, Copy)]
pub struct Camera {
    pub eye: Vector,
    pub target: Vector,
    /// Focal length in pixels.
    pub focal: f32,
}

impl Camera {
    /// The default view of a world: 4 m to the side (−y) and 1.5 m above the torso.
    pub fn following(world: &RobotWorld) -> Camera {
        Camera::following_point(world.link_pose(world.torso).translation)
    }

    /// The default view of a robot whose torso is at `root`.
    pub fn following_point(root: Vector) -> Camera {
        let target = Vector::new(root.x, root.y, root.z.clamp(0.3, 3.0) * 0.6);
        Camera {
            eye: target + Vector::new(0.0, -4.0, 1.5),
            target,
            focal: 420.0,
        }
    }

    fn basis(&self) -> (Vector, Vector, Vector) {
        let fwd = (self.target - self.eye).normalize();
        let right = fwd.cross(Vector::Z).normalize();
        let up = right.cross(fwd);
        (fwd, right, up)
    }

    /// Screen position and depth of world point `p` (`None` behind the camera).
    pub fn project(&self, p: Vector) -> Option<(f64, f64, f32)> {
        let (fwd, right, up) = self.basis();
        let d = p - self.eye;
        let z = d.dot(fwd);
        if z <= 0.05 {
            return None;
        }
        let x = f64::from(WIDTH) / 2.0 + f64::from(self.focal * d.dot(right) / z);
        let y = f64::from(HEIGHT) / 2.0 - f64::from(self.focal * d.dot(up) / z);
        Some((x, y, z))
    }
}

/// Convex hull (Andrew's monotone chain) of screen points.
fn hull(mut pts: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    pts.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    let cross = |o: (f64, f64), a: (f64, f64), b: (f64, f64)| (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0);
    let mut lower: Vec<(f64, f64)> = Vec::new();
    for &p in &pts {
        while lower.len() >= 2 && cross(lower[lower.len() - 2], lower[lower.len() - 1], p) <= 0.0 {
            lower.pop();
        }
        lower.push(p);
    }
    let mut upper: Vec<(f64, f64)> = Vec::new();
    for &p in pts.iter().rev() {
        while upper.len() >= 2 && cross(upper[upper.len() - 2], upper[upper.len() - 1], p) <= 0.0 {
            upper.pop();
        }
        upper.push(p);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

/// Sample points on the surface outline of a shape (world frame).
fn outline(shape: &dyn Shape, pose: &Pose, out: &mut Vec<Vector>) {
    const N: usize = 16;
    let ring = |c: Vector, r: f32, out: &mut Vec<Vector>| {
        // Points of a sphere of radius r around c: three great circles.
        for k in 0..N {
            let a = k as f32 / N as f32 * std::f32::consts::TAU;
            let (s, co) = a.sin_cos();
            out.push(c + Vector::new(r * co, r * s, 0.0));
            out.push(c + Vector::new(r * co, 0.0, r * s));
            out.push(c + Vector::new(0.0, r * co, r * s));
        }
    };
    if let Some(b) = shape.as_ball() {
        ring(pose.translation, b.radius, out);
    } else if let Some(c) = shape.as_capsule() {
        ring(pose * c.segment.a, c.radius, out);
        ring(pose * c.segment.b, c.radius, out);
    } else if let Some(c) = shape.as_cuboid() {
        let h = c.half_extents;
        for sx in [-1.0f32, 1.0] {
            for sy in [-1.0f32, 1.0] {
                for sz in [-1.0f32, 1.0] {
                    out.push(pose * Vector::new(sx * h.x, sy * h.y, sz * h.z));
                }
            }
        }
    } else if let Some(c) = shape.as_cylinder() {
        for k in 0..N {
            let a = k as f32 / N as f32 * std::f32::consts::TAU;
            let (s, co) = a.sin_cos();
            for y in [-c.half_height, c.half_height] {
                out.push(pose * Vector::new(c.radius * co, y, c.radius * s));
            }
        }
    } else {
        let aabb = shape.compute_aabb(pose);
        for sx in [aabb.mins.x, aabb.maxs.x] {
            for sy in [aabb.mins.y, aabb.maxs.y] {
                for sz in [aabb.mins.z, aabb.maxs.z] {
                    out.push(Vector::new(sx, sy, sz));
                }
            }
        }
    }
}

/// Sutherland–Hodgman clip of a polygon to the canvas (plus a 2-pixel margin): `fill_polygon`
/// scans the polygon's bounding box, so far off-screen vertices must not reach it.
fn clip_to_screen(poly: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let (lo_x, lo_y) = (-2.0, -2.0);
    let (hi_x, hi_y) = (f64::from(WIDTH) + 2.0, f64::from(HEIGHT) + 2.0);
    // Each edge: inside test and intersection with the clip line.
    let mut out: Vec<(f64, f64)> = poly.to_vec();
    for edge in 0..4 {
        if out.is_empty() {
            break;
        }
        let inside = |p: (f64, f64)| match edge {
            0 => p.0 >= lo_x,
            1 => p.0 <= hi_x,
            2 => p.1 >= lo_y,
            _ => p.1 <= hi_y,
        };
        let cut = |a: (f64, f64), b: (f64, f64)| {
            let t = match edge {
                0 => (lo_x - a.0) / (b.0 - a.0),
                1 => (hi_x - a.0) / (b.0 - a.0),
                2 => (lo_y - a.1) / (b.1 - a.1),
                _ => (hi_y - a.1) / (b.1 - a.1),
            };
            (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1))
        };
        let input = std::mem::take(&mut out);
        for i in 0..input.len() {
            let (a, b) = (input[(i + input.len() - 1) % input.len()], input[i]);
            match (inside(a), inside(b)) {
                (true, true) => out.push(b),
                (true, false) => out.push(cut(a, b)),
                (false, true) => {
                    out.push(cut(a, b));
                    out.push(b);
                }
                (false, false) => {}
            }
        }
    }
    out
}

fn fill(canvas: &mut Canvas, poly: &[(f64, f64)], c: Color) {
    let clipped = clip_to_screen(poly);
    if clipped.len() >= 3 {
        canvas.fill_polygon(&clipped, c);
    }
}

/// A straight line of width `w` as a clipped quad.
fn stroke(canvas: &mut Canvas, a: (f64, f64), b: (f64, f64), w: f64, c: Color) {
    let len = (b.0 - a.0).hypot(b.1 - a.1);
    if len == 0.0 || !len.is_finite() {
        return;
    }
    let (nx, ny) = (-(b.1 - a.1) / len * w / 2.0, (b.0 - a.0) / len * w / 2.0);
    let quad = [
        (a.0 + nx, a.1 + ny),
        (b.0 + nx, b.1 + ny),
        (b.0 - nx, b.1 - ny),
        (a.0 - nx, a.1 - ny),
    ];
    fill(canvas, &quad, c);
}

fn shade(c: Color, k: f32) -> Color {
    let f = |v: u8| (f32::from(v) * k).clamp(0.0, 255.0) as u8;
    Color(f(c.0), f(c.1), f(c.2))
}

/// Viewing distance up to which the ground grid has 1 m cells (over 4 px apart at the target).
const GRID_1M_UP_TO: f32 = 100.0;

/// Grid spacing for a camera `distance` m from its target: 1 m up to `GRID_1M_UP_TO`, then
/// the next power of ten that keeps lines at least as far apart on screen. A far camera (a
/// target 1 km away) would otherwise draw thousands of lines merging into the horizon.
pub fn grid_step(distance: f32) -> f32 {
    if distance.is_nan() || distance <= GRID_1M_UP_TO {
        return 1.0;
    }
    let decades = (distance / GRID_1M_UP_TO).log10().ceil().min(30.0);
    10f32.powi(decades as i32)
}

/// The ground grid's lines over `[x_lo, x_hi] × [y_lo, y_hi]` at z = 0: lines of constant x
/// first, then of constant y, every [`grid_step`] metres.
pub fn ground_grid(cam: &Camera, [x_lo, x_hi]: [f32; 2], [y_lo, y_hi]: [f32; 2]) -> Vec<(Vector, Vector)> {
    let step = grid_step((cam.target - cam.eye).length());
    let mut lines = Vec::new();
    for i in ((x_lo / step).ceil() as i32)..=((x_hi / step).floor() as i32) {
        let x = i as f32 * step;
        lines.push((Vector::new(x, y_lo, 0.0), Vector::new(x, y_hi, 0.0)));
    }
    for j in ((y_lo / step).ceil() as i32)..=((y_hi / step).floor() as i32) {
        let y = j as f32 * step;
        lines.push((Vector::new(x_lo, y, 0.0), Vector::new(x_hi, y, 0.0)));
    }
    lines
}

/// A projected shape: mean depth, screen polygon, colour.
type Silhouette = (f32, Vec<(f64, f64)>, Color);

/// Render `world` from [`Camera::following`], with optional extra spheres (targets, objects)
/// given as (centre, radius, colour).
pub fn render_with(world: &RobotWorld, extra: &[(Vector, f32, Color)]) -> Frame {
    render_from(world, &Camera::following(world), extra)
}

/// Render `world` from camera `cam`, with optional extra spheres (centre, radius, colour).
pub fn render_from(world: &RobotWorld, cam: &Camera, extra: &[(Vector, f32, Color)]) -> Frame {
    let canvas = ground_canvas(cam);
    // Colliders follow their body: compose the body pose with the collider's offset.
    let shapes: Vec<(usize, &dyn Shape, Pose)> = world
        .link_colliders
        .iter()
        .enumerate()
        .flat_map(|(li, cols)| cols.iter().map(move |&ch| (li, ch)))
        .map(|(li, ch)| {
            let col = &world.pw.colliders[ch];
            let pose = match (col.parent(), col.position_wrt_parent()) {
                (Some(b), Some(rel)) => world.pw.bodies[b].position() * rel,
                _ => *col.position(),
            };
            (li, col.shape(), pose)
        })
        .collect();
    render_scene(canvas, cam, &shapes, extra)
}

/// A canvas with sky and the gridded ground as `cam` sees them.
fn ground_canvas(cam: &Camera) -> Canvas {
    let mut canvas = Canvas::new(WIDTH, HEIGHT, SKY);
    // Ground: one projected quad from just in front of the camera to the horizon region, with
    // 1 m grid lines (a single polygon fill keeps rendering cheap).
    // (24 m deep, or twice the viewing distance for a camera further away).
    let reach = (2.0 * (cam.target - cam.eye).length()).max(24.0);
    let (x_lo, x_hi) = (cam.target.x - reach * 14.0 / 24.0, cam.target.x + reach * 14.0 / 24.0);
    let (y_lo, y_hi) = (cam.eye.y + 0.6, cam.eye.y + reach);
    let quad = [(x_lo, y_lo), (x_hi, y_lo), (x_hi, y_hi), (x_lo, y_hi)];
    let pts: Option<Vec<(f64, f64)>> = quad
        .iter()
        .map(|&(x, y)| cam.project(Vector::new(x, y, 0.0)).map(|(u, v, _)| (u, v)))
        .collect();
    if let Some(pts) = pts {
        fill(&mut canvas, &pts, GROUND_A);
    }
    for (a, b) in ground_grid(cam, [x_lo, x_hi], [y_lo, y_hi]) {
        if let (Some(p), Some(q)) = (cam.project(a), cam.project(b)) {
            stroke(&mut canvas, (p.0, p.1), (q.0, q.1), 1.5, GROUND_B);
        }
    }
    canvas
}

/// A robot on the articulated engine: its spheres, capsules, cylinders and boxes.
pub fn render_articulated(world: &ArticulatedWorld) -> Frame {
    // The picture's ground is z = 0: everything is drawn relative to the floor's height
    // (Pusher's table lies 0.325 m below its shoulder).
    let floor = world
        .system()
        .model
        .geoms
        .iter()
        .find(|g| matches!(g.shape, carl_articulated::Shape::Plane))
        .map_or(0.0, |g| g.pos[2]);
    let t = world.torso_position();
    let cam = Camera::following_point(Vector::new(t[0] as f32, t[1] as f32, (t[2] - floor) as f32));
    let mut owned: Vec<(usize, SharedShape, Pose)> = Vec::new();
    for (body, shape, p, m) in world.geoms() {
        let q = carl_articulated::math::mat_to_quat(&m);
        let mut rot = Rotation::from_xyzw(q[1] as f32, q[2] as f32, q[3] as f32, q[0] as f32);
        if matches!(shape, carl_articulated::Shape::Cylinder { .. }) {
            // rapier's cylinders stand along y, the engine's along z.
            rot *= Rotation::from_rotation_x(std::f32::consts::FRAC_PI_2);
        }
        let pose = Pose::from_parts(Vector::new(p[0] as f32, p[1] as f32, (p[2] - floor) as f32), rot);
        let s = match shape {
            carl_articulated::Shape::Sphere { radius } => SharedShape::ball(radius as f32),
            carl_articulated::Shape::Capsule { radius, half_length } => {
                SharedShape::capsule_z(half_length as f32, radius as f32)
            }
            carl_articulated::Shape::Cylinder { radius, half_length } => {
                SharedShape::cylinder(half_length as f32, radius as f32)
            }
            carl_articulated::Shape::Box { half } => {
                SharedShape::cuboid(half[0] as f32, half[1] as f32, half[2] as f32)
            }
            carl_articulated::Shape::Ellipsoid { radii } => {
                // The hull of points on its surface (rapier has no ellipsoid).
                let mut pts = Vec::new();
                for i in 0..=6 {
                    let th = std::f32::consts::PI * i as f32 / 6.0;
                    for k in 0..12 {
                        let ph = std::f32::consts::TAU * k as f32 / 12.0;
                        pts.push(Vector::new(
                            radii[0] as f32 * th.sin() * ph.cos(),
                            radii[1] as f32 * th.sin() * ph.sin(),
                            radii[2] as f32 * th.cos(),
                        ));
                    }
                }
                match SharedShape::convex_hull(&pts) {
                    Some(s) => s,
                    None => continue,
                }
            }
            carl_articulated::Shape::Plane => continue,
        };
        owned.push((body, s, pose));
    }
    let shapes: Vec<(usize, &dyn Shape, Pose)> = owned.iter().map(|(b, s, p)| (*b, s.as_ref(), *p)).collect();
    render_scene(ground_canvas(&cam), &cam, &shapes, &[])
}

/// Draw `shapes` (link index for the colour, shape, world pose) and the `extra` spheres over
/// the ground already on `canvas`.
fn render_scene(
    mut canvas: Canvas,
    cam: &Camera,
    shapes: &[(usize, &dyn Shape, Pose)],
    extra: &[(Vector, f32, Color)],
) -> Frame {
    // Shapes: (depth, polygon, colour), drawn far to near.
    let mut items: Vec<Silhouette> = Vec::new();
    let mut pts3 = Vec::new();
    for &(li, shape, pose) in shapes {
        pts3.clear();
        outline(shape, &pose, &mut pts3);
        let proj: Option<Vec<(f64, f64, f32)>> = pts3.iter().map(|p| cam.project(*p)).collect();
        let Some(proj) = proj else { continue };
        let depth = proj.iter().map(|p| p.2).sum::<f32>() / proj.len() as f32;
        let poly = hull(proj.iter().map(|p| (p.0, p.1)).collect());
        let base = PALETTE[li % PALETTE.len()];
        items.push((depth, poly, shade(base, 1.1 - 0.05 * depth.min(8.0))));
    }
    for &(c, r, color) in extra {
        pts3.clear();
        outline(&Ball::new(r), &Pose::from_translation(c), &mut pts3);
        let proj: Option<Vec<(f64, f64, f32)>> = pts3.iter().map(|p| cam.project(*p)).collect();
        if let Some(proj) = proj {
            let depth = proj.iter().map(|p| p.2).sum::<f32>() / proj.len() as f32;
            items.push((depth, hull(proj.iter().map(|p| (p.0, p.1)).collect()), color));
        }
    }
    items.sort_by(|a, b| b.0.total_cmp(&a.0));
    for (_, poly, color) in &items {
        fill(&mut canvas, poly, *color);
        for k in 0..poly.len() {
            let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
            stroke(&mut canvas, a, b, 1.0, shade(*color, 0.6));
        }
    }
    Frame::from_canvas(&canvas)
}

/// Render `world` (robot and ground only).
pub fn render_world(world: &RobotWorld) -> Frame {
    render_with(world, &[])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera(distance: f32) -> Camera {
        let target = Vector::new(0.0, 0.0, 0.8);
        Camera {
            eye: target + Vector::new(0.0, -distance, 0.0),
            target,
            focal: 420.0,
        }
    }

    #[test]
    fn near_cameras_keep_the_one_metre_grid() {
        for d in [4.3, 10.0, 17.0, 100.0] {
            assert_eq!(grid_step(d), 1.0);
        }
        let lines = ground_grid(&camera(4.3), [-14.0, 14.0], [-3.7, 20.3]);
        assert_eq!(lines.len(), 29 + 24);
        assert_eq!(lines[0].0, Vector::new(-14.0, -3.7, 0.0));
        assert_eq!(lines[29].0, Vector::new(-14.0, -3.0, 0.0));
    }

    #[test]
    fn far_cameras_draw_a_bounded_number_of_grid_lines() {
        // Regression: `render fetch --context target_distance=1000` drew ~4,000 1 m lines
        // (22 s); at 10,000 about 43,000. Lines stay over 4 px apart at the target.
        assert_eq!(grid_step(101.0), 10.0);
        assert_eq!(grid_step(1300.0), 100.0);
        for d in [1300.0f32, 13_000.0, 1e7] {
            let reach = 2.0 * d;
            let lines = ground_grid(
                &camera(d),
                [-reach * 14.0 / 24.0, reach * 14.0 / 24.0],
                [-d + 0.6, -d + reach],
            );
            assert!(lines.len() <= 500, "{d} m: {} lines", lines.len());
            assert!(420.0 * grid_step(d) / d >= 4.0);
        }
        assert_eq!(grid_step(f32::INFINITY), 1e30);
    }
}
