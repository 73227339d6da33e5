//! BipedalWalker terrain: Gymnasium's generator (grass random walk; stumps, stairs and pits in
//! the hardcore variant) and the lidar's ray cast against it.
//!
//! The terrain is a pure function of a [`TerrainSpec`] (seed and the generator's context
//! features), so it can be regenerated exactly from the environment's state vector.

use carl_spec_core::sampling::{Pcg64, dist};

/// What the terrain generator needs: a seed and the context features that shape the course.
/// Recorded in the environment's state, so `set_state` rebuilds exactly the same course.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TerrainSpec {
    /// Seed of the terrain's random stream (an integer below 2⁵³, exact in an f64).
    pub seed: u64,
    /// `TERRAIN_STEP`, m.
    pub step: f64,
    /// `TERRAIN_LENGTH`, steps.
    pub length: usize,
    /// `TERRAIN_HEIGHT`, m.
    pub height: f64,
    /// `TERRAIN_GRASS`, steps.
    pub grass: i64,
    /// `TERRAIN_STARTPAD`, steps.
    pub startpad: i64,
    /// `SCALE` (px/m): the grass roughness is `U(-1, 1) / SCALE` per step.
    pub scale: f64,
    /// Stumps, stairs and pits (`BipedalWalkerHardcore`).
    pub hardcore: bool,
}

/// A static convex obstacle (stump, stair step or pit wall), corners counter-clockwise or
/// clockwise as Gymnasium lists them.
pub type Quad = [(f64, f64); 4];

/// A generated course.
#[derive(Debug, Clone, PartialEq)]
pub struct Terrain {
    pub spec: TerrainSpec,
    /// Surface points `(i·STEP, y_i)`, `i = 0..TERRAIN_LENGTH`.
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    /// Obstacles (hardcore only).
    pub quads: Vec<Quad>,
    /// Obstacles in generation order with their kind, for rendering.
    pub kinds: Vec<Obstacle>,
}

/// Kind of a hardcore obstacle quad.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Obstacle {
    Stump,
    Stairs,
    Pit,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum State {
    Grass,
    Stump,
    Stairs,
    Pit,
}

/// Python's `np.sign`.
fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// NumPy's `integers(low, high)`: uniform in `[low, high)`; `low` when the range is empty.
fn integers(rng: &mut Pcg64, low: i64, high: i64) -> i64 {
    if high <= low {
        low
    } else {
        low + dist::below(rng, (high - low) as u64) as i64
    }
}

impl Terrain {
    /// Run Gymnasium's `_generate_terrain` for `spec` (same state machine, same order of draws;
    /// the random stream is this crate's PCG64, not NumPy's).
    pub fn generate(spec: TerrainSpec) -> Terrain {
        let mut rng = Pcg64::new(spec.seed, carl_spec_core::sampling::stream_id("bipedal_walker/terrain"));
        let n = spec.length.max(2);
        let step = spec.step;
        let grass = spec.grass;
        let mut state = State::Grass;
        let mut velocity = 0.0f64;
        let mut y = spec.height;
        let mut counter: i64 = spec.startpad;
        let mut oneshot = false;
        let mut xs = Vec::with_capacity(n);
        let mut ys = Vec::with_capacity(n);
        let mut quads = Vec::new();
        let mut kinds = Vec::new();
        let (mut stair_steps, mut stair_width, mut stair_height) = (0i64, 0i64, 0i64);
        let mut original_y = 0.0f64;
        for i in 0..n {
            let x = i as f64 * step;
            xs.push(x);
            match (state, oneshot) {
                (State::Grass, false) => {
                    velocity = 0.8 * velocity + 0.01 * sign(spec.height - y);
                    if i as i64 > spec.startpad {
                        velocity += dist::uniform(&mut rng, -1.0, 1.0) / spec.scale;
                    }
                    y += velocity;
                }
                (State::Pit, true) => {
                    counter = integers(&mut rng, 3, 5);
                    let poly = [(x, y), (x + step, y), (x + step, y - 4.0 * step), (x, y - 4.0 * step)];
                    quads.push(poly);
                    kinds.push(Obstacle::Pit);
                    let dx = step * counter as f64;
                    quads.push(poly.map(|(px, py)| (px + dx, py)));
                    kinds.push(Obstacle::Pit);
                    counter += 2;
                    original_y = y;
                }
                (State::Pit, false) => {
                    y = original_y;
                    if counter > 1 {
                        y -= 4.0 * step;
                    }
                }
                (State::Stump, true) => {
                    counter = integers(&mut rng, 1, 3);
                    let s = counter as f64 * step;
                    quads.push([(x, y), (x + s, y), (x + s, y + s), (x, y + s)]);
                    kinds.push(Obstacle::Stump);
                }
                (State::Stairs, true) => {
                    stair_height = if rng.next_f64() > 0.5 { 1 } else { -1 };
                    stair_width = integers(&mut rng, 4, 5);
                    stair_steps = integers(&mut rng, 3, 5);
                    original_y = y;
                    let (w, h) = (stair_width as f64, stair_height as f64);
                    for s in 0..stair_steps {
                        let s = s as f64;
                        quads.push([
                            (x + s * w * step, y + s * h * step),
                            (x + (1.0 + s) * w * step, y + s * h * step),
                            (x + (1.0 + s) * w * step, y + (-1.0 + s * h) * step),
                            (x + s * w * step, y + (-1.0 + s * h) * step),
                        ]);
                        kinds.push(Obstacle::Stairs);
                    }
                    counter = stair_steps * stair_width;
                }
                (State::Stairs, false) => {
                    let s = (stair_steps * stair_width - counter - stair_height) as f64;
                    let nst = s / stair_width.max(1) as f64;
                    y = original_y + nst * stair_height as f64 * step;
                }
                (State::Grass, true) | (State::Stump, false) => {}
            }
            oneshot = false;
            ys.push(y);
            counter -= 1;
            if counter == 0 {
                // `integers(TERRAIN_GRASS / 2, TERRAIN_GRASS)`.
                counter = integers(&mut rng, grass / 2, grass).max(1);
                if state == State::Grass && spec.hardcore {
                    state = match integers(&mut rng, 1, 4) {
                        1 => State::Stump,
                        2 => State::Stairs,
                        _ => State::Pit,
                    };
                } else {
                    state = State::Grass;
                }
                oneshot = true;
            }
        }
        Terrain {
            spec,
            x: xs,
            y: ys,
            quads,
            kinds,
        }
    }

    /// The x of the finish line: `(TERRAIN_LENGTH - TERRAIN_GRASS) · TERRAIN_STEP`.
    pub fn finish_x(length: f64, grass: f64, step: f64) -> f64 {
        (length - grass) * step
    }

    /// Surface height under `x` (linear between points; the end heights outside the course).
    pub fn height_at(&self, x: f64) -> f64 {
        let step = self.spec.step;
        let n = self.x.len();
        if x <= 0.0 || step <= 0.0 {
            return self.y[0];
        }
        let i = (x / step).floor() as usize;
        if i + 1 >= n {
            return self.y[n - 1];
        }
        let t = (x - self.x[i]) / step;
        self.y[i] + t * (self.y[i + 1] - self.y[i])
    }

    /// Fraction along the ray `p1 → p2` of the closest terrain surface (edge or obstacle
    /// side), or 1 if none: Box2D's `RayCast` with a callback that clips to the closest hit.
    pub fn ray_fraction(&self, p1: (f64, f64), p2: (f64, f64)) -> f64 {
        let mut best = 1.0f64;
        let (xmin, xmax) = (p1.0.min(p2.0), p1.0.max(p2.0));
        let step = self.spec.step;
        let n = self.x.len();
        if step > 0.0 && n >= 2 {
            let lo = ((xmin / step).floor() - 1.0).max(0.0);
            let hi = ((xmax / step).ceil() + 1.0).min((n - 2) as f64);
            if lo <= hi {
                for i in lo as usize..=hi as usize {
                    let a = (self.x[i], self.y[i]);
                    let b = (self.x[i + 1], self.y[i + 1]);
                    if let Some(t) = segment_hit(p1, p2, a, b) {
                        best = best.min(t);
                    }
                }
            }
        }
        for q in &self.quads {
            let (qx0, qx1) = q
                .iter()
                .fold((f64::MAX, f64::MIN), |(l, h), p| (l.min(p.0), h.max(p.0)));
            if qx1 < xmin || qx0 > xmax || point_in_quad(p1, q) {
                // Box2D's polygon ray cast reports nothing for a ray starting inside.
                continue;
            }
            for k in 0..4 {
                if let Some(t) = segment_hit(p1, p2, q[k], q[(k + 1) % 4]) {
                    best = best.min(t);
                }
            }
        }
        best
    }
}

/// Fraction `t ∈ [0, 1]` where `p1 + t (p2 - p1)` crosses segment `ab` (either side).
fn segment_hit(p1: (f64, f64), p2: (f64, f64), a: (f64, f64), b: (f64, f64)) -> Option<f64> {
    let d = (p2.0 - p1.0, p2.1 - p1.1);
    let e = (b.0 - a.0, b.1 - a.1);
    let denom = d.0 * e.1 - d.1 * e.0;
    if denom == 0.0 {
        return None;
    }
    let w = (a.0 - p1.0, a.1 - p1.1);
    let t = (w.0 * e.1 - w.1 * e.0) / denom;
    let s = (w.0 * d.1 - w.1 * d.0) / denom;
    ((0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&s)).then_some(t)
}

fn point_in_quad(p: (f64, f64), q: &Quad) -> bool {
    let mut sgn = 0.0f64;
    for k in 0..4 {
        let (a, b) = (q[k], q[(k + 1) % 4]);
        let c = (b.0 - a.0) * (p.1 - a.1) - (b.1 - a.1) * (p.0 - a.0);
        if c == 0.0 {
            continue;
        }
        if sgn == 0.0 {
            sgn = c.signum();
        } else if c.signum() != sgn {
            return false;
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(seed: u64, hardcore: bool) -> TerrainSpec {
        TerrainSpec {
            seed,
            step: 14.0 / 30.0,
            length: 200,
            height: 5.0,
            grass: 10,
            startpad: 20,
            scale: 30.0,
            hardcore,
        }
    }

    #[test]
    fn startpad_is_flat_and_course_is_seeded() {
        let t = Terrain::generate(spec(1, false));
        assert_eq!(t.x.len(), 200);
        assert!(t.y[..=20].iter().all(|y| *y == 5.0), "{:?}", &t.y[..22]);
        assert_ne!(t.y[60], 5.0);
        assert!(t.quads.is_empty());
        assert_eq!(t, Terrain::generate(spec(1, false)));
        assert_ne!(t.y, Terrain::generate(spec(2, false)).y);
    }

    #[test]
    fn hardcore_has_all_obstacle_kinds() {
        let mut seen = [false; 3];
        for seed in 0..10 {
            let t = Terrain::generate(spec(seed, true));
            for k in &t.kinds {
                seen[*k as usize] = true;
            }
        }
        assert_eq!(seen, [true; 3]);
    }

    #[test]
    fn ray_hits_flat_ground_at_the_analytic_fraction() {
        let t = Terrain::generate(spec(3, false));
        // Straight down from 2 m above the flat startpad, range 5 m: fraction 0.4.
        let f = t.ray_fraction((3.0, 7.0), (3.0, 2.0));
        assert!((f - 0.4).abs() < 1e-12, "{f}");
        assert_eq!(t.ray_fraction((3.0, 7.0), (3.0, 6.0)), 1.0);
    }
}
