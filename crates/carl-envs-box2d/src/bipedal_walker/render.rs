//! Gymnasium's BipedalWalker picture (`render_mode="rgb_array"`): sky, the ground under the
//! terrain edges, obstacles, lidar rays, legs and hull in Gymnasium's colours, the start flag,
//! with the camera following the hull (`scroll = x − VIEWPORT_W/SCALE/5`, never left of 0).
//! Clouds are not drawn (they are decoration drawn from the same random stream in Gymnasium).

use super::{BipedalWalker, HULL_POLY, rot, size};
use carl_pixels::{Canvas, Color, Frame, Stroke};

pub const SKY: Color = Color(215, 215, 255);
pub const GROUND: Color = Color(102, 153, 76);
pub const OBSTACLE_FILL: Color = Color(255, 255, 255);
pub const OBSTACLE_EDGE: Color = Color(153, 153, 153);
pub const HULL_FILL: Color = Color(127, 51, 229);
pub const HULL_EDGE: Color = Color(76, 76, 127);
pub const LIDAR: Color = Color(255, 0, 0);

/// Leg colours of Gymnasium (`i = -1` for leg 0, `+1` for leg 1): (fill, outline).
pub fn leg_colors(leg: usize) -> (Color, Color) {
    let i: i32 = if leg == 0 { -1 } else { 1 };
    let c = |v: i32| (v - i * 25) as u8;
    (Color(c(153), c(76), c(127)), Color(c(102), c(51), c(76)))
}

fn outline(canvas: &mut Canvas, pts: &[(f64, f64)], color: Color) {
    for k in 0..pts.len() {
        let s = Stroke {
            color,
            width: 1.0,
            dash: None,
        };
        canvas.line(pts[k], pts[(k + 1) % pts.len()], s);
    }
}

pub(super) fn render(env: &BipedalWalker) -> Option<Frame> {
    let p = env.params();
    let terrain = env.terrain()?;
    let bodies = env.body_states()?;
    let (w, h) = (
        p.viewport_w.round().clamp(1.0, 8192.0) as u32,
        p.viewport_h.round().clamp(1.0, 8192.0) as u32,
    );
    let scale = size(p.scale);
    let left = (bodies[0].x - p.viewport_w / scale / 5.0).max(0.0);
    let to_px = |(x, y): (f64, f64)| ((x - left) * scale, h as f64 - y * scale);
    let visible = |x0: f64, x1: f64| x1 >= left && x0 <= left + w as f64 / scale;
    let mut c = Canvas::new(w, h, SKY);

    // Ground below the surface, the surface edges (alternating greens), then the obstacles on
    // top (Gymnasium's draw list puts the edges first).
    for i in 0..terrain.x.len().saturating_sub(1) {
        let (x0, x1) = (terrain.x[i], terrain.x[i + 1]);
        if !visible(x0, x1) {
            continue;
        }
        let (y0, y1) = (terrain.y[i], terrain.y[i + 1]);
        let poly = [(x0, y0), (x1, y1), (x1, 0.0), (x0, 0.0)].map(to_px);
        c.fill_polygon(&poly, GROUND);
    }
    for i in 0..terrain.x.len().saturating_sub(1) {
        let (x0, x1) = (terrain.x[i], terrain.x[i + 1]);
        if !visible(x0, x1) {
            continue;
        }
        let color = Color(76, if i % 2 == 0 { 255 } else { 204 }, 76);
        let s = Stroke {
            color,
            width: 1.0,
            dash: None,
        };
        c.line(to_px((x0, terrain.y[i])), to_px((x1, terrain.y[i + 1])), s);
    }

    for (q, _) in terrain.quads.iter().zip(&terrain.kinds) {
        let (x0, x1) = q
            .iter()
            .fold((f64::MAX, f64::MIN), |(l, h), p| (l.min(p.0), h.max(p.0)));
        if !visible(x0, x1) {
            continue;
        }
        let poly = q.map(to_px);
        c.fill_polygon(&poly, OBSTACLE_FILL);
        outline(&mut c, &poly, OBSTACLE_EDGE);
    }
    if env.options().render_lidar
        && let Some(rays) = env.lidar()
    {
        for (p1, p2, f) in rays {
            let hit = (p1.0 + f * (p2.0 - p1.0), p1.1 + f * (p2.1 - p1.1));
            let s = Stroke {
                color: LIDAR,
                width: 1.0,
                dash: None,
            };
            c.line(to_px(p1), to_px(hit), s);
        }
    }

    // Legs (Gymnasium draws leg 0's upper, lower, then leg 1's), then the hull on top.
    let (lw, lh) = (size(p.leg_w), size(p.leg_h));
    for (k, b) in bodies.iter().enumerate().skip(1) {
        let leg = (k - 1) / 2;
        let hw = if k % 2 == 0 { 0.8 * lw / 2.0 } else { lw / 2.0 };
        let corners = [(-hw, -lh / 2.0), (hw, -lh / 2.0), (hw, lh / 2.0), (-hw, lh / 2.0)];
        let poly = corners.map(|v| {
            let r = rot(b.angle, v);
            to_px((b.x + r.0, b.y + r.1))
        });
        let (fill, edge) = leg_colors(leg);
        c.fill_polygon(&poly, fill);
        outline(&mut c, &poly, edge);
    }
    let hb = bodies[0];
    let hull = HULL_POLY.map(|(x, y)| {
        let r = rot(hb.angle, (x / scale, y / scale));
        to_px((hb.x + r.0, hb.y + r.1))
    });
    c.fill_polygon(&hull, HULL_FILL);
    outline(&mut c, &hull, HULL_EDGE);

    // Start flag at 3 terrain steps, 50 px pole.
    let fx = p.terrain_step * 3.0;
    let base = to_px((fx, p.terrain_height));
    let top = (base.0, base.1 - 50.0);
    c.line(
        base,
        top,
        Stroke {
            color: Color::BLACK,
            width: 1.0,
            dash: None,
        },
    );
    let flag = [top, (top.0, top.1 + 10.0), (top.0 + 25.0, top.1 + 5.0)];
    c.fill_polygon(&flag, Color(230, 51, 0));
    outline(&mut c, &flag, Color::BLACK);
    Some(Frame::from_canvas(&c))
}
