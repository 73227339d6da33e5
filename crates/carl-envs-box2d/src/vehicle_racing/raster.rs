//! A small dedicated rasteriser for CarRacing's pictures: filled polygons point-sampled on a
//! supersampled RGB canvas, then box-filtered down to the output size. This stands in for
//! Gymnasium's pipeline (pygame draws on a 1000×800 surface, `smoothscale` averages it down to
//! 96×96 or 600×400): each output pixel is the average of `k × k` samples of the same scene.
//! Polygons are filled with the even–odd rule at sample centres; there is no per-edge blending,
//! so abutting road tiles leave no seams.

/// An RGB canvas of `w × h` samples. Each sample is one `u64` with red, green and blue in
/// 16-bit fields (bits 32, 16, 0), so summing up to 257 samples is one integer addition each.
#[derive(Debug, Clone, Default)]
pub struct Canvas {
    pub w: usize,
    pub h: usize,
    pub px: Vec<u64>,
}

/// `ceil(x)` clamped to `[0, max]`, without a libm call (baseline x86-64 has no `roundsd`).
#[inline]
fn ceil_clamped(x: f64, max: usize) -> usize {
    if x.is_nan() || x <= 0.0 {
        return 0;
    }
    if x >= max as f64 {
        return max;
    }
    let t = x as usize;
    if (t as f64) < x { t + 1 } else { t }
}

#[inline]
fn pack(c: [u8; 3]) -> u64 {
    (u64::from(c[0]) << 32) | (u64::from(c[1]) << 16) | u64::from(c[2])
}

impl Canvas {
    /// Resize (reusing the allocation) and fill with `color`.
    pub fn reset(&mut self, w: usize, h: usize, color: [u8; 3]) {
        self.w = w;
        self.h = h;
        self.px.clear();
        self.px.resize(w * h, pack(color));
    }

    /// The sample at column `x`, row `y`.
    pub fn sample(&self, x: usize, y: usize) -> [u8; 3] {
        let p = self.px[y * self.w + x];
        [(p >> 32) as u8, (p >> 16) as u8, p as u8]
    }

    /// Fill the polygon `pts` (canvas coordinates, any orientation, up to 16 vertices).
    pub fn fill_polygon(&mut self, pts: &[(f64, f64)], color: [u8; 3]) {
        let n = pts.len();
        if !(3..=16).contains(&n) {
            return;
        }
        let (mut ymin, mut ymax) = (f64::INFINITY, f64::NEG_INFINITY);
        let (mut xmin, mut xmax) = (f64::INFINITY, f64::NEG_INFINITY);
        for &(x, y) in pts {
            if !(x.is_finite() && y.is_finite()) {
                return;
            }
            ymin = ymin.min(y);
            ymax = ymax.max(y);
            xmin = xmin.min(x);
            xmax = xmax.max(x);
        }
        if xmax < 0.0 || ymax < 0.0 || xmin > self.w as f64 || ymin > self.h as f64 {
            return;
        }
        // Sample rows whose centres j + 0.5 lie in [ymin, ymax).
        let j0 = ceil_clamped(ymin - 0.5, self.h);
        let j1 = ceil_clamped(ymax - 0.5, self.h);
        let mut xs = [0.0f64; 16];
        let color = pack(color);
        for j in j0..j1 {
            let yc = j as f64 + 0.5;
            let mut m = 0;
            for i in 0..n {
                let (x1, y1) = pts[i];
                let (x2, y2) = pts[(i + 1) % n];
                if (y1 <= yc && yc < y2) || (y2 <= yc && yc < y1) {
                    xs[m] = x1 + (yc - y1) * (x2 - x1) / (y2 - y1);
                    m += 1;
                }
            }
            let xs = &mut xs[..m];
            xs.sort_unstable_by(f64::total_cmp);
            let row = j * self.w;
            for pair in xs.chunks_exact(2) {
                let a = ceil_clamped(pair[0] - 0.5, self.w);
                let b = ceil_clamped(pair[1] - 0.5, self.w);
                if b > a {
                    self.px[row + a..row + b].fill(color);
                }
            }
        }
    }

    /// Average `k × k` blocks into `out` (`(w/k) × (h/k) × 3`, HWC), rounded half up
    /// (`k` at most 16).
    pub fn downsample_into(&self, k: usize, out: &mut [f32]) {
        let (ow, oh) = (self.w / k, self.h / k);
        let kk = (k * k) as u64;
        // floor((acc + kk/2) / kk) as a multiply-shift, exact for acc < 2^16 and kk <= 256.
        let magic = (1u64 << 32).div_ceil(kk);
        let mut acc = vec![0u64; ow];
        for oy in 0..oh {
            acc.fill(0);
            for sy in 0..k {
                let start = (oy * k + sy) * self.w;
                let row = &self.px[start..start + ow * k];
                for (a, block) in acc.iter_mut().zip(row.chunks_exact(k)) {
                    *a += block.iter().sum::<u64>();
                }
            }
            let dst = &mut out[3 * oy * ow..3 * (oy + 1) * ow];
            for (d, &a) in dst.chunks_exact_mut(3).zip(&acc) {
                for (c, shift) in d.iter_mut().zip([32u32, 16, 0]) {
                    let v = (a >> shift) & 0xFFFF;
                    *c = (((v + kk / 2) * magic) >> 32) as f32;
                }
            }
        }
    }

    /// Like [`Canvas::downsample_into`], to bytes.
    pub fn downsample_rgb8(&self, k: usize) -> Vec<u8> {
        let mut f = vec![0.0f32; (self.w / k) * (self.h / k) * 3];
        self.downsample_into(k, &mut f);
        f.into_iter().map(|x| x as u8).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fills_a_square_exactly() {
        let mut c = Canvas::default();
        c.reset(8, 8, [0, 0, 0]);
        c.fill_polygon(&[(2.0, 2.0), (6.0, 2.0), (6.0, 6.0), (2.0, 6.0)], [255, 0, 0]);
        let inside = (0..8)
            .flat_map(|y| (0..8).map(move |x| (x, y)))
            .filter(|&(x, y)| c.sample(x, y)[0] == 255);
        assert_eq!(inside.count(), 16);
        assert_eq!(c.sample(2, 2), [255, 0, 0]);
        assert_eq!(c.sample(6, 6), [0, 0, 0]);
        let mut out = vec![0.0; 4 * 4 * 3];
        c.downsample_into(2, &mut out);
        assert_eq!(out[3 * (4 + 1)], 255.0);
        assert_eq!(out[0], 0.0);
    }

    #[test]
    fn half_covered_pixel_averages() {
        let mut c = Canvas::default();
        c.reset(2, 2, [0, 0, 0]);
        c.fill_polygon(&[(0.0, 0.0), (1.0, 0.0), (1.0, 2.0), (0.0, 2.0)], [200, 100, 50]);
        let mut out = vec![0.0; 3];
        c.downsample_into(2, &mut out);
        assert_eq!(out, vec![100.0, 50.0, 25.0]);
    }
}
