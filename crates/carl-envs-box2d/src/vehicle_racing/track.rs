//! CarRacing's random track (Gymnasium 1.4 `CarRacing._create_track`): 12 noisy checkpoints
//! around a circle, a pursuit curve that steers toward them at a limited turn rate, the second lap
//! cut out as a closed loop, road tiles 2·`TRACK_WIDTH` wide between consecutive points, and
//! red/white kerbs on sustained hard turns.

use carl_spec_core::sampling::{Pcg64, dist};

/// Track scale (`SCALE`).
pub const SCALE: f64 = 6.0;
pub const TRACK_RAD: f64 = 900.0 / SCALE;
pub const PLAYFIELD: f64 = 2000.0 / SCALE;
pub const TRACK_DETAIL_STEP: f64 = 21.0 / SCALE;
pub const TRACK_TURN_RATE: f64 = 0.31;
pub const TRACK_WIDTH: f64 = 40.0 / SCALE;
pub const BORDER: f64 = 8.0 / SCALE;
pub const BORDER_MIN_COUNT: usize = 4;
pub const CHECKPOINTS: usize = 12;

/// A point of the track centre line: `(alpha, beta, x, y)` as in Gymnasium.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackPoint {
    pub alpha: f64,
    pub beta: f64,
    pub x: f64,
    pub y: f64,
}

/// A convex quadrilateral with its colour.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quad {
    pub pts: [(f64, f64); 4],
    pub color: [u8; 3],
}

/// A generated track: centre line, one road tile per point (tile `i` joins point `i-1` and `i`),
/// and the kerb quads.
#[derive(Debug, Clone, PartialEq)]
pub struct Track {
    pub points: Vec<TrackPoint>,
    pub tiles: Vec<Quad>,
    /// Axis-aligned bounds of each tile, `[xmin, ymin, xmax, ymax]`.
    pub tile_aabb: Vec<[f64; 4]>,
    pub borders: Vec<Quad>,
}

pub const ROAD_COLOR: [u8; 3] = [102, 102, 102];

fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// One attempt of `_create_track`; `None` when Gymnasium's version returns `False`.
fn attempt(rng: &mut Pcg64) -> Option<Track> {
    use std::f64::consts::PI;
    let mut checkpoints = [(0.0f64, 0.0f64, 0.0f64); CHECKPOINTS];
    let mut start_alpha = 0.0;
    for (c, cp) in checkpoints.iter_mut().enumerate() {
        let noise = dist::uniform(rng, 0.0, 2.0 * PI / CHECKPOINTS as f64);
        let mut alpha = 2.0 * PI * c as f64 / CHECKPOINTS as f64 + noise;
        let mut rad = dist::uniform(rng, TRACK_RAD / 3.0, TRACK_RAD);
        if c == 0 {
            alpha = 0.0;
            rad = 1.5 * TRACK_RAD;
        }
        if c == CHECKPOINTS - 1 {
            alpha = 2.0 * PI * c as f64 / CHECKPOINTS as f64;
            start_alpha = 2.0 * PI * (-0.5) / CHECKPOINTS as f64;
            rad = 1.5 * TRACK_RAD;
        }
        *cp = (alpha, rad * alpha.cos(), rad * alpha.sin());
    }

    let (mut x, mut y, mut beta) = (1.5 * TRACK_RAD, 0.0f64, 0.0f64);
    let mut dest_i = 0usize;
    let mut laps = 0;
    let mut track: Vec<TrackPoint> = Vec::with_capacity(2500);
    let mut no_freeze = 2500;
    let mut visited_other_side = false;
    loop {
        let mut alpha = y.atan2(x);
        if visited_other_side && alpha > 0.0 {
            laps += 1;
            visited_other_side = false;
        }
        if alpha < 0.0 {
            visited_other_side = true;
            alpha += 2.0 * PI;
        }
        let (mut dest_x, mut dest_y);
        loop {
            let mut failed = true;
            loop {
                let (dest_alpha, dx, dy) = checkpoints[dest_i % CHECKPOINTS];
                dest_x = dx;
                dest_y = dy;
                if alpha <= dest_alpha {
                    failed = false;
                    break;
                }
                dest_i += 1;
                if dest_i.is_multiple_of(CHECKPOINTS) {
                    break;
                }
            }
            if !failed {
                break;
            }
            alpha -= 2.0 * PI;
        }
        let (r1x, r1y) = (beta.cos(), beta.sin());
        let (p1x, p1y) = (-r1y, r1x);
        let dest_dx = dest_x - x;
        let dest_dy = dest_y - y;
        let mut proj = r1x * dest_dx + r1y * dest_dy;
        while beta - alpha > 1.5 * PI {
            beta -= 2.0 * PI;
        }
        while beta - alpha < -1.5 * PI {
            beta += 2.0 * PI;
        }
        let prev_beta = beta;
        proj *= SCALE;
        if proj > 0.3 {
            beta -= TRACK_TURN_RATE.min((0.001 * proj).abs());
        }
        if proj < -0.3 {
            beta += TRACK_TURN_RATE.min((0.001 * proj).abs());
        }
        x += p1x * TRACK_DETAIL_STEP;
        y += p1y * TRACK_DETAIL_STEP;
        track.push(TrackPoint {
            alpha,
            beta: prev_beta * 0.5 + beta * 0.5,
            x,
            y,
        });
        if laps > 4 {
            break;
        }
        no_freeze -= 1;
        if no_freeze == 0 {
            break;
        }
    }

    // Closed loop i1..i2: the last two passes through the start angle.
    let (mut i1, mut i2) = (None, None);
    let mut i = track.len();
    loop {
        i -= 1;
        if i == 0 {
            return None;
        }
        let pass = track[i].alpha > start_alpha && track[i - 1].alpha <= start_alpha;
        if pass && i2.is_none() {
            i2 = Some(i);
        } else if pass && i1.is_none() {
            i1 = Some(i);
            break;
        }
    }
    let (i1, i2) = (i1?, i2?);
    if i2 < i1 + 2 {
        return None;
    }
    let track: Vec<TrackPoint> = track[i1..i2 - 1].to_vec();
    let n = track.len();
    if n < BORDER_MIN_COUNT + 2 {
        return None;
    }

    let first_beta = track[0].beta;
    let (fpx, fpy) = (first_beta.cos(), first_beta.sin());
    let glue = ((fpx * (track[0].x - track[n - 1].x)).powi(2) + (fpy * (track[0].y - track[n - 1].y)).powi(2)).sqrt();
    if glue > TRACK_DETAIL_STEP {
        return None;
    }

    // Python's negative indices wrap: track[i - k] for i < k is track[n + i - k].
    let at = |i: usize, back: usize| track[(i + n - back % n) % n];
    let mut border = vec![false; n];
    for (i, b) in border.iter_mut().enumerate() {
        let mut good = true;
        let mut oneside = 0.0;
        for neg in 0..BORDER_MIN_COUNT {
            let beta1 = at(i, neg).beta;
            let beta2 = at(i, neg + 1).beta;
            good &= (beta1 - beta2).abs() > TRACK_TURN_RATE * 0.2;
            oneside += sign(beta1 - beta2);
        }
        good &= oneside.abs() == BORDER_MIN_COUNT as f64;
        *b = good;
    }
    // In place, as in Python: border[i - neg] |= border[i] (with wrap-around).
    for i in 0..n {
        let bi = border[i];
        for neg in 0..BORDER_MIN_COUNT {
            border[(i + n - neg) % n] |= bi;
        }
    }

    let mut tiles = Vec::with_capacity(n);
    let mut tile_aabb = Vec::with_capacity(n);
    let mut borders = Vec::new();
    for i in 0..n {
        let p1 = track[i];
        let p2 = at(i, 1);
        let (c1, s1) = (p1.beta.cos(), p1.beta.sin());
        let (c2, s2) = (p2.beta.cos(), p2.beta.sin());
        let road1_l = (p1.x - TRACK_WIDTH * c1, p1.y - TRACK_WIDTH * s1);
        let road1_r = (p1.x + TRACK_WIDTH * c1, p1.y + TRACK_WIDTH * s1);
        let road2_l = (p2.x - TRACK_WIDTH * c2, p2.y - TRACK_WIDTH * s2);
        let road2_r = (p2.x + TRACK_WIDTH * c2, p2.y + TRACK_WIDTH * s2);
        let pts = [road1_l, road1_r, road2_r, road2_l];
        // t.color = road_color + 0.01 * (i % 3) * 255, drawn as int(c).
        let c = (0.01 * (i % 3) as f64 * 255.0) as u8;
        let color = [ROAD_COLOR[0] + c, ROAD_COLOR[1] + c, ROAD_COLOR[2] + c];
        let mut bb = [f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY];
        for &(x, y) in &pts {
            bb = [bb[0].min(x), bb[1].min(y), bb[2].max(x), bb[3].max(y)];
        }
        tiles.push(Quad { pts, color });
        tile_aabb.push(bb);
        if border[i] {
            let side = sign(p2.beta - p1.beta);
            let b1_l = (p1.x + side * TRACK_WIDTH * c1, p1.y + side * TRACK_WIDTH * s1);
            let b1_r = (
                p1.x + side * (TRACK_WIDTH + BORDER) * c1,
                p1.y + side * (TRACK_WIDTH + BORDER) * s1,
            );
            let b2_l = (p2.x + side * TRACK_WIDTH * c2, p2.y + side * TRACK_WIDTH * s2);
            let b2_r = (
                p2.x + side * (TRACK_WIDTH + BORDER) * c2,
                p2.y + side * (TRACK_WIDTH + BORDER) * s2,
            );
            let color = if i % 2 == 0 { [255, 255, 255] } else { [255, 0, 0] };
            borders.push(Quad {
                pts: [b1_l, b1_r, b2_r, b2_l],
                color,
            });
        }
    }
    Some(Track {
        points: track,
        tiles,
        tile_aabb,
        borders,
    })
}

/// Generate a track from `rng`, retrying like Gymnasium until an attempt succeeds (at most
/// `max_attempts`; `None` after that).
pub fn generate(rng: &mut Pcg64, max_attempts: usize) -> Option<Track> {
    (0..max_attempts).find_map(|_| attempt(rng))
}
