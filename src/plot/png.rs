//! PNG output: the scene rasterized in software (anti-aliased by 4×4 supersampling for polygons
//! and exact area coverage for rectangles), text drawn with the built-in bitmap font, encoded by
//! the pure-Rust `png` crate. No system fonts or libraries are involved, and the same scene always
//! gives the same bytes.

use super::font;
use super::scene::{Anchor, Color, Scene, Shape, Stroke};

/// An RGB canvas with floating-point channels (0..=255).
pub struct Canvas {
    pub width: u32,
    pub height: u32,
    px: Vec<[f32; 3]>,
}

impl Canvas {
    pub fn new(width: u32, height: u32, bg: Color) -> Self {
        let c = [f32::from(bg.0), f32::from(bg.1), f32::from(bg.2)];
        Canvas {
            width,
            height,
            px: vec![c; (width as usize) * (height as usize)],
        }
    }

    fn blend(&mut self, x: i64, y: i64, c: Color, alpha: f64) {
        if x < 0 || y < 0 || x >= i64::from(self.width) || y >= i64::from(self.height) || alpha <= 0.0 {
            return;
        }
        let a = alpha.min(1.0) as f32;
        let p = &mut self.px[y as usize * self.width as usize + x as usize];
        for (ch, v) in p.iter_mut().zip([c.0, c.1, c.2]) {
            *ch = *ch * (1.0 - a) + f32::from(v) * a;
        }
    }

    /// Axis-aligned rectangle with exact area coverage at its edges.
    pub fn fill_rect(&mut self, x: f64, y: f64, w: f64, h: f64, c: Color, opacity: f64) {
        let (x0, y0, x1, y1) = (x, y, x + w, y + h);
        for py in y0.floor() as i64..y1.ceil() as i64 {
            let cy = (y1.min(py as f64 + 1.0) - y0.max(py as f64)).max(0.0);
            for px in x0.floor() as i64..x1.ceil() as i64 {
                let cx = (x1.min(px as f64 + 1.0) - x0.max(px as f64)).max(0.0);
                self.blend(px, py, c, cx * cy * opacity);
            }
        }
    }

    /// Filled polygon (even-odd rule), 16 samples per pixel.
    pub fn fill_polygon(&mut self, pts: &[(f64, f64)], c: Color) {
        if pts.len() < 3 {
            return;
        }
        let (mut minx, mut miny, mut maxx, mut maxy) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
        for &(x, y) in pts {
            minx = minx.min(x);
            miny = miny.min(y);
            maxx = maxx.max(x);
            maxy = maxy.max(y);
        }
        let inside = |x: f64, y: f64| {
            let mut odd = false;
            let mut j = pts.len() - 1;
            for i in 0..pts.len() {
                let (xi, yi) = pts[i];
                let (xj, yj) = pts[j];
                if (yi > y) != (yj > y) && x < (xj - xi) * (y - yi) / (yj - yi) + xi {
                    odd = !odd;
                }
                j = i;
            }
            odd
        };
        for py in miny.floor() as i64..maxy.ceil() as i64 {
            for px in minx.floor() as i64..maxx.ceil() as i64 {
                let mut hits = 0;
                for sy in 0..4 {
                    for sx in 0..4 {
                        let x = px as f64 + (f64::from(sx) + 0.5) / 4.0;
                        let y = py as f64 + (f64::from(sy) + 0.5) / 4.0;
                        if inside(x, y) {
                            hits += 1;
                        }
                    }
                }
                self.blend(px, py, c, f64::from(hits) / 16.0);
            }
        }
    }

    /// A line as a filled quad; dashed lines as a series of quads.
    pub fn line(&mut self, (x1, y1): (f64, f64), (x2, y2): (f64, f64), s: Stroke) {
        let len = (x2 - x1).hypot(y2 - y1);
        if len == 0.0 {
            return;
        }
        let (ux, uy) = ((x2 - x1) / len, (y2 - y1) / len);
        let segments: Vec<(f64, f64)> = match s.dash {
            Some(d) if d > 0.0 => {
                let mut v = Vec::new();
                let mut t = 0.0;
                while t < len {
                    v.push((t, (t + d).min(len)));
                    t += 2.0 * d;
                }
                v
            }
            _ => vec![(0.0, len)],
        };
        let (nx, ny) = (-uy * s.width / 2.0, ux * s.width / 2.0);
        for (a, b) in segments {
            let (ax, ay) = (x1 + ux * a, y1 + uy * a);
            let (bx, by) = (x1 + ux * b, y1 + uy * b);
            if ux == 0.0 || uy == 0.0 {
                // Axis-aligned: exact coverage.
                let (lx, hx) = (ax.min(bx) - nx.abs(), ax.max(bx) + nx.abs());
                let (ly, hy) = (ay.min(by) - ny.abs(), ay.max(by) + ny.abs());
                self.fill_rect(lx, ly, hx - lx, hy - ly, s.color, 1.0);
            } else {
                self.fill_polygon(
                    &[
                        (ax + nx, ay + ny),
                        (bx + nx, by + ny),
                        (bx - nx, by - ny),
                        (ax - nx, ay - ny),
                    ],
                    s.color,
                );
            }
        }
    }

    /// Text in the built-in bitmap font; `y` is the baseline.
    #[allow(clippy::too_many_arguments)]
    pub fn text(
        &mut self,
        x: f64,
        y: f64,
        text: &str,
        scale: u32,
        anchor: Anchor,
        c: Color,
        bold: bool,
        vertical: bool,
    ) {
        let w = font::text_width(text, scale);
        let offset = match anchor {
            Anchor::Start => 0.0,
            Anchor::Middle => -w / 2.0,
            Anchor::End => -w,
        };
        let s = i64::from(scale);
        let (bx, by) = (x.round() as i64, y.round() as i64);
        let start = offset.round() as i64;
        for (i, ch) in text.chars().enumerate() {
            let cx = start + i as i64 * i64::from(font::ADVANCE) * s;
            for (gx, gy) in font::glyph(ch) {
                // Position along the text (u) and down from the cap line (v), in pixels.
                let u = cx + i64::from(gx) * s;
                let v = (i64::from(gy) - i64::from(font::ASCENT)) * s;
                for dy in 0..s {
                    for dx in 0..s + i64::from(bold) {
                        let (px, py) = if vertical {
                            (bx + v + dy, by - u - dx)
                        } else {
                            (bx + u + dx, by + v + dy)
                        };
                        self.blend(px, py, c, 1.0);
                    }
                }
            }
        }
    }

    /// Rows of 8-bit RGB.
    pub fn to_rgb8(&self) -> Vec<u8> {
        self.px
            .iter()
            .flat_map(|p| p.iter().map(|v| v.round().clamp(0.0, 255.0) as u8))
            .collect()
    }
}

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

/// The scene as PNG bytes (8-bit RGB, with a `Title` text chunk).
pub fn render(scene: &Scene) -> Result<Vec<u8>, png::EncodingError> {
    let canvas = rasterize(scene);
    let mut bytes = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut bytes, canvas.width, canvas.height);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.add_text_chunk("Title".to_string(), scene.title.clone())?;
        enc.add_text_chunk("Software".to_string(), "carl-spec".to_string())?;
        let mut w = enc.write_header()?;
        w.write_image_data(&canvas.to_rgb8())?;
        w.finish()?;
    }
    Ok(bytes)
}
