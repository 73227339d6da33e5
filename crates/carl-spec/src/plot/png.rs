//! PNG output: the scene rasterized by the pixel layer's [`Canvas`] (anti-aliased, text in the
//! built-in bitmap font) and encoded by [`crate::pixels::encode`]. No system fonts or libraries
//! are involved, and the same scene always gives the same bytes.

use super::scene::{Scene, Shape};
use crate::pixels::encode::png_bytes;
use crate::pixels::{Canvas, Color, Frame};

pub fn rasterize(scene: &Scene) -> Canvas {
    let mut c = Canvas::new(scene.width, scene.height, Color::WHITE);
    for item in &scene.items {
        match &item.shape {
            Shape::Rect {
                x,
                y,
                w,
                h,
                fill,
                opacity,
            } => c.fill_rect(*x, *y, *w, *h, *fill, *opacity),
            Shape::Line { x1, y1, x2, y2, stroke } => c.line((*x1, *y1), (*x2, *y2), *stroke),
            Shape::Polygon { points, fill } => c.fill_polygon(points, *fill),
            Shape::Text {
                x,
                y,
                text,
                scale,
                anchor,
                color,
                bold,
                vertical,
            } => c.text(*x, *y, text, *scale, *anchor, *color, *bold, *vertical),
            Shape::GroupStart | Shape::GroupEnd => {}
        }
    }
    c
}

/// The scene as PNG bytes (8-bit RGB, with `Title` and `Software` text chunks).
pub fn render(scene: &Scene) -> Result<Vec<u8>, String> {
    let frame = Frame::from_canvas(&rasterize(scene));
    png_bytes(&frame, &[("Title", &scene.title), ("Software", "carl-spec")])
}
