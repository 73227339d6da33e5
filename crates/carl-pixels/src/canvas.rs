//! A software rasteriser: anti-aliased by 4×4 supersampling for polygons and exact area
//! coverage for axis-aligned rectangles; text in the built-in bitmap `font`.
//!
//! Work is bounded by what lands on the canvas: shapes are scanned only over the canvas rows
//! and, per row, only between the polygon's outermost edge crossings, so a long thin shape (a
//! grid line running to the horizon) or one far off-screen costs little. Skipped pixels are
//! exactly those whose coverage would be zero, so pictures do not depend on this.

use super::color::Color;
use super::font;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stroke {
    pub color: Color,
    pub width: f64,
    /// Dash and gap length; `None` = solid.
    pub dash: Option<f64>,
}

impl Stroke {
    pub fn solid(color: Color, width: f64) -> Self {
        Stroke {
            color,
            width,
            dash: None,
        }
    }
    pub fn dashed(color: Color, width: f64, dash: f64) -> Self {
        Stroke {
            color,
            width,
            dash: Some(dash),
        }
    }
}

/// Where text sits relative to its anchor point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Anchor {
    Start,
    Middle,
    End,
}

/// An RGB canvas with floating-point channels (0..=255).
pub struct Canvas {
    pub width: u32,
    pub height: u32,
    px: Vec<[f32; 3]>,
}

/// Integer pixel range `lo.floor()..hi.ceil()` clamped to `0..=max` (saturating for
/// non-finite or huge coordinates).
fn pixel_range(lo: f64, hi: f64, max: u32) -> std::ops::Range<i64> {
    let max = i64::from(max);
    let a = (lo.floor() as i64).clamp(0, max);
    let b = (hi.ceil() as i64).clamp(0, max);
    a..b.max(a)
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
        for py in pixel_range(y0, y1, self.height) {
            let cy = (y1.min(py as f64 + 1.0) - y0.max(py as f64)).max(0.0);
            for px in pixel_range(x0, x1, self.width) {
                let cx = (x1.min(px as f64 + 1.0) - x0.max(px as f64)).max(0.0);
                self.blend(px, py, c, cx * cy * opacity);
            }
        }
    }

    /// Filled polygon (even-odd rule), 16 samples per pixel.
    ///
    /// A sample at `(x, y)` is inside when an odd number of edges cross the horizontal line
    /// through it to its right. Per sample row the crossings are computed once and sorted, so
    /// the samples of a row cost a binary search each, and only pixels between the first and
    /// last crossing are visited (outside them the count is 0 or the even total).
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
        let cols = pixel_range(minx, maxx, self.width);
        let mut rows: [Vec<f64>; 4] = Default::default();
        for py in pixel_range(miny, maxy, self.height) {
            let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
            for (sy, xs) in rows.iter_mut().enumerate() {
                let y = py as f64 + (sy as f64 + 0.5) / 4.0;
                xs.clear();
                let mut j = pts.len() - 1;
                for i in 0..pts.len() {
                    let (xi, yi) = pts[i];
                    let (xj, yj) = pts[j];
                    if (yi > y) != (yj > y) {
                        let xc = (xj - xi) * (y - yi) / (yj - yi) + xi;
                        // `x < NaN` never holds: such a crossing never counts.
                        if !xc.is_nan() {
                            xs.push(xc);
                        }
                    }
                    j = i;
                }
                xs.sort_by(f64::total_cmp);
                if let (Some(&a), Some(&b)) = (xs.first(), xs.last()) {
                    lo = lo.min(a);
                    hi = hi.max(b);
                }
            }
            if lo > hi {
                continue;
            }
            let span = pixel_range(lo - 1.0, hi + 1.0, self.width);
            for px in span.start.max(cols.start)..span.end.min(cols.end) {
                let mut hits = 0;
                for xs in &rows {
                    for sx in 0..4 {
                        let x = px as f64 + (f64::from(sx) + 0.5) / 4.0;
                        // Crossings strictly right of the sample.
                        let right = xs.len() - xs.partition_point(|&xc| xc <= x);
                        hits += right % 2;
                    }
                }
                self.blend(px, py, c, hits as f64 / 16.0);
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The rasteriser before the scanline speed-up: every pixel of the bounding box, every
    /// sample tested against every edge. The fast path must give the same pixels.
    fn reference_polygon(c: &mut Canvas, pts: &[(f64, f64)], col: Color) {
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
                c.blend(px, py, col, f64::from(hits) / 16.0);
            }
        }
    }

    #[test]
    fn scanline_fill_matches_the_bounding_box_reference() {
        // Convex, concave, self-intersecting, thin diagonal, partly off-canvas, degenerate.
        let polys: Vec<Vec<(f64, f64)>> = vec![
            vec![(3.2, 4.7), (40.1, 9.9), (22.5, 37.3)],
            vec![(5.0, 5.0), (50.0, 5.0), (50.0, 40.0), (27.5, 12.25), (5.0, 40.0)],
            vec![(2.0, 2.0), (60.0, 38.0), (60.0, 2.0), (2.0, 38.0)],
            vec![(0.3, 0.2), (0.9, 0.1), (63.7, 39.6), (63.1, 39.7)],
            vec![(-30.0, -10.0), (90.0, 15.5), (20.0, 70.0)],
            vec![(10.0, 10.0), (20.0, 10.0), (30.0, 10.0)],
            vec![(10.5, 3.0), (10.5, 30.0), (10.5 + 1e-9, 20.0)],
        ];
        for (k, p) in polys.iter().enumerate() {
            let mut fast = Canvas::new(64, 40, Color(10, 20, 30));
            let mut slow = Canvas::new(64, 40, Color(10, 20, 30));
            fast.fill_polygon(p, Color(200, 100, 50));
            reference_polygon(&mut slow, p, Color(200, 100, 50));
            assert_eq!(fast.to_rgb8(), slow.to_rgb8(), "polygon {k}");
        }
    }

    #[test]
    fn far_off_canvas_shapes_cost_nothing_and_draw_nothing() {
        let mut c = Canvas::new(8, 8, Color::WHITE);
        let before = c.to_rgb8();
        c.fill_polygon(&[(-1e12, -1e12), (-1e12 + 5.0, -1e12), (-1e12, 1e12)], Color::BLACK);
        c.fill_rect(1e9, 1e9, 1e9, 1e9, Color::BLACK, 1.0);
        c.fill_polygon(&[(f64::NAN, 0.0), (4.0, 4.0), (0.0, 4.0)], Color::BLACK);
        assert_eq!(c.to_rgb8(), before);
        // A huge shape covering the canvas fills it (in time proportional to the canvas).
        c.fill_polygon(&[(-1e12, -1e12), (1e12, -1e12), (0.0, 1e12)], Color::BLACK);
        assert!(c.to_rgb8().iter().all(|&v| v == 0));
    }
}
