//! The generator network's building blocks on `(channels, rows, cols)` f32 maps: valid 3×3
//! convolution, batch norm in eval mode, LeakyReLU, softmax over channels, bilinear resizing
//! (torch's `align_corners=False`) and zero padding.
//!
//! Storage is f32 throughout; convolutions accumulate in f32 (the data guide, docs/guides/data.md: the levels'
//! argmax does not depend on torch's accumulation order, checked on every fixture).

/// A `(c, h, w)` feature map, row-major.
#[derive(Debug, Clone, PartialEq)]
pub struct Map {
    pub c: usize,
    pub h: usize,
    pub w: usize,
    pub data: Vec<f32>,
}

impl Map {
    pub fn zeros(c: usize, h: usize, w: usize) -> Self {
        Map {
            c,
            h,
            w,
            data: vec![0.0; c * h * w],
        }
    }

    fn plane(&self, c: usize) -> &[f32] {
        &self.data[c * self.h * self.w..(c + 1) * self.h * self.w]
    }

    /// Zero padding by `p` on all four sides.
    pub fn pad(&self, p: usize) -> Map {
        let (h, w) = (self.h + 2 * p, self.w + 2 * p);
        let mut out = Map::zeros(self.c, h, w);
        for c in 0..self.c {
            for y in 0..self.h {
                let src = &self.plane(c)[y * self.w..(y + 1) * self.w];
                let start = (c * h + y + p) * w + p;
                out.data[start..start + self.w].copy_from_slice(src);
            }
        }
        out
    }

    /// Bilinear resize to `(oh, ow)` with torch's `align_corners=False` semantics: source
    /// coordinate `max((dst + 0.5)·in/out − 0.5, 0)`, neighbours clamped to the edge.
    pub fn resize_bilinear(&self, oh: usize, ow: usize) -> Map {
        let ys = axis_weights(oh, self.h);
        let xs = axis_weights(ow, self.w);
        let mut out = Map::zeros(self.c, oh, ow);
        for c in 0..self.c {
            let src = self.plane(c);
            let dst = &mut out.data[c * oh * ow..(c + 1) * oh * ow];
            for (oy, &(y0, y1, ly)) in ys.iter().enumerate() {
                for (ox, &(x0, x1, lx)) in xs.iter().enumerate() {
                    let a = src[y0 * self.w + x0];
                    let b = src[y0 * self.w + x1];
                    let cc = src[y1 * self.w + x0];
                    let d = src[y1 * self.w + x1];
                    let top = a * (1.0 - lx) + b * lx;
                    let bot = cc * (1.0 - lx) + d * lx;
                    dst[oy * ow + ox] = top * (1.0 - ly) + bot * ly;
                }
            }
        }
        out
    }

    /// The centre `(h - 2p, w - 2p)` window (undoes [`Map::pad`]).
    pub fn crop(&self, p: usize) -> Map {
        let (h, w) = (self.h - 2 * p, self.w - 2 * p);
        let mut out = Map::zeros(self.c, h, w);
        for c in 0..self.c {
            for y in 0..h {
                let start = (c * self.h + y + p) * self.w + p;
                out.data[(c * h + y) * w..(c * h + y + 1) * w].copy_from_slice(&self.data[start..start + w]);
            }
        }
        out
    }
}

/// For each output index: (low source index, high source index, weight of the high one).
fn axis_weights(out: usize, inp: usize) -> Vec<(usize, usize, f32)> {
    let scale = inp as f32 / out as f32;
    (0..out)
        .map(|o| {
            let src = ((o as f32 + 0.5) * scale - 0.5).max(0.0);
            let i0 = (src.floor() as usize).min(inp - 1);
            let i1 = (i0 + 1).min(inp - 1);
            (i0, i1, src - i0 as f32)
        })
        .collect()
}

/// A 3×3 convolution, stride 1, no padding. Weights `[out][in][3][3]`.
#[derive(Debug, Clone)]
pub struct Conv3x3 {
    pub cin: usize,
    pub cout: usize,
    pub weight: Vec<f32>,
    pub bias: Vec<f32>,
}

impl Conv3x3 {
    pub fn forward(&self, x: &Map) -> Map {
        assert_eq!(x.c, self.cin, "conv input channels");
        let (h, w) = (x.h - 2, x.w - 2);
        let mut out = Map::zeros(self.cout, h, w);
        for o in 0..self.cout {
            let dst = &mut out.data[o * h * w..(o + 1) * h * w];
            for c in 0..self.cin {
                let src = x.plane(c);
                let k = &self.weight[(o * self.cin + c) * 9..(o * self.cin + c + 1) * 9];
                for ky in 0..3 {
                    for kx in 0..3 {
                        let wv = k[ky * 3 + kx];
                        for y in 0..h {
                            let s = &src[(y + ky) * x.w + kx..(y + ky) * x.w + kx + w];
                            let d = &mut dst[y * w..(y + 1) * w];
                            for (dv, sv) in d.iter_mut().zip(s) {
                                *dv += wv * sv;
                            }
                        }
                    }
                }
            }
            let b = self.bias[o];
            dst.iter_mut().for_each(|v| *v += b);
        }
        out
    }
}

/// Batch norm in eval mode (ε = 1e-5) followed by LeakyReLU(0.2), in place.
#[derive(Debug, Clone)]
pub struct BatchNormLeaky {
    pub mean: Vec<f32>,
    /// `sqrt(running_var + ε)`, per channel.
    pub std: Vec<f32>,
    pub gamma: Vec<f32>,
    pub beta: Vec<f32>,
}

impl BatchNormLeaky {
    pub fn new(mean: Vec<f32>, var: Vec<f32>, gamma: Vec<f32>, beta: Vec<f32>) -> Self {
        let std = var.iter().map(|v| (v + 1e-5f64 as f32).sqrt()).collect();
        BatchNormLeaky { mean, std, gamma, beta }
    }

    pub fn apply(&self, x: &mut Map) {
        let n = x.h * x.w;
        for c in 0..x.c {
            let (m, s, g, b) = (self.mean[c], self.std[c], self.gamma[c], self.beta[c]);
            for v in &mut x.data[c * n..(c + 1) * n] {
                let y = (*v - m) / s * g + b;
                *v = if y >= 0.0 { y } else { 0.2 * y };
            }
        }
    }
}

/// Softmax over channels (computed in f64, stored as f32), in place.
pub fn softmax_channels(x: &mut Map) {
    let n = x.h * x.w;
    for i in 0..n {
        let max = (0..x.c).map(|c| x.data[c * n + i]).fold(f32::NEG_INFINITY, f32::max);
        let e: Vec<f64> = (0..x.c).map(|c| f64::from(x.data[c * n + i] - max).exp()).collect();
        let sum: f64 = e.iter().sum();
        for (c, ev) in e.iter().enumerate() {
            x.data[c * n + i] = (ev / sum) as f32;
        }
    }
}

/// Per position, the index of the largest channel (the first on ties).
pub fn argmax_channels(x: &Map) -> Vec<usize> {
    let n = x.h * x.w;
    (0..n)
        .map(|i| {
            let mut best = 0;
            for c in 1..x.c {
                if x.data[c * n + i] > x.data[best * n + i] {
                    best = c;
                }
            }
            best
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bilinear_upsampling_follows_align_corners_false() {
        // torch: F.interpolate([[0, 1]], size=4, mode="linear") = [0, 0.25, 0.75, 1].
        let m = Map {
            c: 1,
            h: 1,
            w: 2,
            data: vec![0.0, 1.0],
        };
        assert_eq!(m.resize_bilinear(1, 4).data, vec![0.0, 0.25, 0.75, 1.0]);
    }

    #[test]
    fn pad_then_crop_is_identity_and_conv_of_ones_sums_the_kernel() {
        let m = Map {
            c: 1,
            h: 2,
            w: 3,
            data: vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0],
        };
        assert_eq!(m.pad(3).crop(3), m);
        let conv = Conv3x3 {
            cin: 1,
            cout: 1,
            weight: (1..=9).map(|v| v as f32).collect(),
            bias: vec![0.5],
        };
        let ones = Map {
            c: 1,
            h: 3,
            w: 3,
            data: vec![1.0; 9],
        };
        assert_eq!(conv.forward(&ones).data, vec![45.5]);
    }

    #[test]
    fn argmax_takes_the_first_maximum() {
        let m = Map {
            c: 3,
            h: 1,
            w: 2,
            data: vec![1.0, 0.0, 2.0, 5.0, 2.0, 5.0],
        };
        assert_eq!(argmax_channels(&m), vec![1, 1]);
    }
}
