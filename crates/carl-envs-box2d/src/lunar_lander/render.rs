//! LunarLander as Gymnasium draws it: white ground under a black sky cut by the terrain, the
//! purple lander and legs with dark outlines, the two yellow helipad flags, plus flames for the
//! engines that fired in the last step (Gymnasium draws exhaust particles instead). One pixel
//! per `1/SCALE` m, `VIEWPORT_W × VIEWPORT_H` pixels, y up in the world and down in the image.
//!
//! It lives beside the environment (and is reached only through `Env::render`) so the lander
//! and its picture change together; it draws with the crate's lowest layer, `carl_pixels`.

use super::{CHUNKS, LANDER_POLY, LunarLander, MAIN_ENGINE_Y_LOCATION};
use carl_pixels::{Canvas, Color, Frame, Stroke};

const SKY: Color = Color(0, 0, 0);
const GROUND: Color = Color(255, 255, 255);
const BODY: Color = Color(128, 102, 230);
const OUTLINE: Color = Color(77, 77, 128);
const FLAG: Color = Color(204, 204, 0);
const FLAME: Color = Color(255, 140, 0);
/// Largest image side drawn (an out-of-bounds viewport must not allocate gigabytes).
pub const MAX_SIDE: f64 = 4096.0;

/// The current state as a frame, or `None` before the first reset.
pub fn draw(env: &LunarLander) -> Option<Frame> {
    let poses = env.body_poses()?;
    let p = env.params();
    let scale = if p.scale.is_finite() && p.scale > 0.0 {
        p.scale
    } else {
        1.0
    };
    let side = |v: f64| {
        if v.is_finite() {
            v.round().clamp(1.0, MAX_SIDE)
        } else {
            1.0
        }
    };
    let (w_px, h_px) = (side(p.viewport_w), side(p.viewport_h));
    let mut c = Canvas::new(w_px as u32, h_px as u32, GROUND);
    // World metres to image pixels.
    let px = |x: f64, y: f64| (x * scale, h_px - y * scale);

    // Sky: one polygon per terrain chunk, from the surface up to the top of the view.
    let (w, h) = (p.world_w(), p.world_h());
    let ys = env.terrain();
    let chunk_x = |i: usize| w / (CHUNKS - 1) as f64 * i as f64;
    for i in 0..CHUNKS - 1 {
        let poly = [
            px(chunk_x(i), ys[i]),
            px(chunk_x(i + 1), ys[i + 1]),
            px(chunk_x(i + 1), h),
            px(chunk_x(i), h),
        ];
        c.fill_polygon(&poly, SKY);
    }

    // Helipad flags at the two chunk boundaries around the centre.
    let helipad_y = p.helipad_y();
    for x in [chunk_x(CHUNKS / 2 - 1), chunk_x(CHUNKS / 2 + 1)] {
        let top = helipad_y + 50.0 / scale;
        c.line(px(x, helipad_y), px(x, top), Stroke::solid(GROUND, 1.0));
        c.fill_polygon(
            &[
                px(x, top),
                px(x, top - 10.0 / scale),
                px(x + 25.0 / scale, top - 5.0 / scale),
            ],
            FLAG,
        );
    }

    let to_world = |(x0, y0, a): (f64, f64, f64), (lx, ly): (f64, f64)| {
        let (s, co) = a.sin_cos();
        px(x0 + co * lx - s * ly, y0 + s * lx + co * ly)
    };

    // Flames first, so the lander is drawn over their roots.
    let (main, dir, side_power) = env.last_engines();
    let lander = poses[0];
    if main > 0.0 {
        let len = (10.0 + 20.0 * main) / scale;
        let y0 = -MAIN_ENGINE_Y_LOCATION / scale - 6.0 / scale;
        let flame = [(-4.0 / scale, y0), (4.0 / scale, y0), (0.0, y0 - len)];
        c.fill_polygon(&flame.map(|q| to_world(lander, q)), FLAME);
    }
    if side_power > 0.0 && dir != 0.0 {
        // The side engine on the opposite side of the push fires outwards.
        let x0 = -dir * p.side_engine_away / scale;
        let y0 = p.side_engine_height / scale - 17.0 / scale;
        let len = 12.0 * side_power / scale;
        let flame = [(x0, y0 + 3.0 / scale), (x0, y0 - 3.0 / scale), (x0 - dir * len, y0)];
        c.fill_polygon(&flame.map(|q| to_world(lander, q)), FLAME);
    }

    // Legs (boxes of half-size LEG_W × LEG_H px), then the lander polygon.
    let (hw, hh) = (p.leg_w / scale, p.leg_h / scale);
    for leg in [poses[1], poses[2]] {
        let corners = [(-hw, -hh), (hw, -hh), (hw, hh), (-hw, hh)].map(|q| to_world(leg, q));
        outlined(&mut c, &corners);
    }
    let hull = LANDER_POLY.map(|(x, y)| to_world(lander, (x / scale, y / scale)));
    outlined(&mut c, &hull);
    Some(Frame::from_canvas(&c))
}

/// A filled polygon with Gymnasium's dark outline.
fn outlined(c: &mut Canvas, pts: &[(f64, f64)]) {
    c.fill_polygon(pts, BODY);
    for k in 0..pts.len() {
        c.line(pts[k], pts[(k + 1) % pts.len()], Stroke::solid(OUTLINE, 1.5));
    }
}

#[cfg(test)]
mod tests {
    use super::super::LunarLanderParams;
    use super::*;
    use carl_env::api::Env;

    #[test]
    fn nothing_before_reset_then_the_viewport() {
        let mut env = LunarLander::default();
        assert!(env.render().is_none());
        env.reset(Some(3));
        let f = env.render().unwrap();
        assert_eq!((f.width, f.height), (600, 400));
        assert_eq!(f.rgb.len(), 600 * 400 * 3);
    }

    #[test]
    fn lander_sky_and_ground_are_where_the_state_says() {
        let mut env = LunarLander::default();
        env.reset(Some(1));
        let f = env.render().unwrap();
        let (x, y, _) = env.body_poses().unwrap()[0];
        let s = env.params().scale;
        // The lander's centre (slightly above its origin) is purple.
        let (cx, cy) = ((x * s).round() as u32, (400.0 - (y + 5.0 / s) * s).round() as u32);
        assert_eq!(f.pixel(cx, cy), [128, 102, 230]);
        // Top-left corner is sky, bottom row is ground.
        assert_eq!(f.pixel(2, 2), [0, 0, 0]);
        assert_eq!(f.pixel(300, 398), [255, 255, 255]);
        // The helipad surface (y ≈ 3.3 m) separates sky above from ground below at the centre.
        let pad = 400.0 - env.terrain()[CHUNKS / 2] * s;
        assert_eq!(f.pixel(250, (pad - 3.0) as u32), [0, 0, 0]);
        assert_eq!(f.pixel(250, (pad + 3.0) as u32), [255, 255, 255]);
    }

    #[test]
    fn the_viewport_context_sets_the_image_size_and_same_state_same_bytes() {
        let p = LunarLanderParams {
            viewport_w: 800.0,
            viewport_h: 500.0,
            ..Default::default()
        };
        let mut a = LunarLander::new(p);
        let mut b = LunarLander::new(p);
        a.reset(Some(9));
        b.reset(Some(9));
        let (fa, fb) = (a.render().unwrap(), b.render().unwrap());
        assert_eq!((fa.width, fa.height), (800, 500));
        assert_eq!(fa, fb);
    }

    #[test]
    fn main_engine_draws_a_flame_below_the_lander() {
        let mut env = LunarLander::new(LunarLanderParams {
            initial_random: 0.0,
            ..Default::default()
        });
        env.reset(Some(0));
        let orange = |f: &Frame| f.rgb.chunks(3).filter(|p| p == &[255, 140, 0]).count();
        let off = orange(&env.render().unwrap());
        env.step(&carl_env::api::Action::Discrete(2)).unwrap();
        let on = orange(&env.render().unwrap());
        assert_eq!(off, 0);
        assert!(on > 20, "{on} flame pixels");
    }
}
