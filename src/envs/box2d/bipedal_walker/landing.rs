//! Box2D's continuous collision (time of impact, TOI) at a foot's landing, emulated for the
//! lower legs.
//!
//! Box2D 2.3 (`b2World::SolveTOI`) sweeps every dynamic body against static shapes after the
//! regular solve. A lower leg that was not touching the ground when the step began and whose
//! sweep brings its core polygon within `TOI_TARGET` of the terrain is moved back to that time
//! of impact, pushed out to `TOI_REST_GAP` by a position-only pass, and its velocity is solved
//! against the ground contacts **alone** (a TOI island holds the body and its static contacts,
//! not its joints); it then moves for the rest of the step with that velocity. The hull and the
//! upper leg keep their motion; the knee's stretch is corrected by the next step's joint solver.
//! The contact begins in that step (the gait reads the flag to end a swing). Measured by
//! replaying Gymnasium's states: a knee swinging down at 6 rad/s stops dead in the step in which
//! the foot lands, where rapier's contact would act one step later through the whole chain.

use super::terrain::Terrain;

/// Box2D's `b2_linearSlop`.
const LINEAR_SLOP: f64 = 0.005;
/// Core gap at which Box2D's TOI stops a sweep: `max(linearSlop, 2·polygonRadius − 3·linearSlop)`,
/// plus its tolerance `linearSlop / 4`.
const TOI_TARGET: f64 = LINEAR_SLOP + 0.25 * LINEAR_SLOP;
/// Gap the TOI position pass leaves: separation `−1.5·linearSlop` from two 0.01 m skins.
const TOI_REST_GAP: f64 = 0.02 - 1.5 * LINEAR_SLOP;
/// Box2D's manifold points: a polygon corner closer than two skins.
const MANIFOLD_GAP: f64 = 0.02;
/// Velocity iterations of the TOI island (Gymnasium steps with 6·30).
const VELOCITY_ITERATIONS: usize = 180;

/// Pose of a box (centre = centre of mass, angle).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoxPose {
    pub c: (f64, f64),
    pub a: f64,
}

/// A lower leg over one step: start and end poses (Box2D's `b2Sweep`, linear in centre and
/// angle), half extents, and its velocity at the end of the regular solve.
#[derive(Debug, Clone, Copy)]
pub struct Sweep {
    pub start: BoxPose,
    pub end: BoxPose,
    pub half: (f64, f64),
}

/// The leg after a landing: pose and velocity at the end of the step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Landed {
    pub pose: BoxPose,
    pub v: (f64, f64),
    pub w: f64,
}

fn rot(a: f64, (x, y): (f64, f64)) -> (f64, f64) {
    let (s, c) = a.sin_cos();
    (c * x - s * y, s * x + c * y)
}

impl BoxPose {
    fn lerp(&self, to: &BoxPose, t: f64) -> BoxPose {
        BoxPose {
            c: (self.c.0 + t * (to.c.0 - self.c.0), self.c.1 + t * (to.c.1 - self.c.1)),
            a: self.a + t * (to.a - self.a),
        }
    }

    fn corners(&self, (hw, hh): (f64, f64)) -> [(f64, f64); 4] {
        [(-hw, -hh), (hw, -hh), (hw, hh), (-hw, hh)].map(|p| {
            let r = rot(self.a, p);
            (self.c.0 + r.0, self.c.1 + r.1)
        })
    }
}

/// Smallest gap between the box and the terrain surface: its corners against the surface, and
/// surface vertices under the box against the box.
fn gap(t: &Terrain, pose: &BoxPose, half: (f64, f64)) -> f64 {
    let corners = pose.corners(half);
    let mut g = corners
        .iter()
        .map(|p| t.surface_gap(*p).0)
        .fold(f64::INFINITY, f64::min);
    let (lo, hi) = corners.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
        (lo.min(p.0), hi.max(p.0))
    });
    let step = t.spec.step;
    if step > 0.0 && !t.x.is_empty() {
        let first = (lo / step).ceil().max(0.0) as usize;
        let last = ((hi / step).floor().max(0.0) as usize).min(t.x.len() - 1);
        for i in first..=last {
            let d = (t.x[i] - pose.c.0, t.y[i] - pose.c.1);
            let l = rot(-pose.a, d);
            let (dx, dy) = (l.0.abs() - half.0, l.1.abs() - half.1);
            let outside = dx.max(0.0).hypot(dy.max(0.0));
            g = g.min(if outside > 0.0 { outside } else { dx.max(dy) });
        }
    }
    g
}

/// Fraction of the step at which the sweep first comes within [`TOI_TARGET`] of the terrain,
/// or `None` if it does not by the end or already is at the start.
pub fn time_of_impact(t: &Terrain, s: &Sweep) -> Option<f64> {
    if gap(t, &s.end, s.half) >= TOI_TARGET || gap(t, &s.start, s.half) < TOI_TARGET {
        return None;
    }
    // First crossing: coarse scan, then bisection.
    const SCAN: usize = 8;
    let mut lo = 0.0;
    let mut hi = 1.0;
    for k in 1..=SCAN {
        let f = k as f64 / SCAN as f64;
        if gap(t, &s.start.lerp(&s.end, f), s.half) < TOI_TARGET {
            hi = f;
            break;
        }
        lo = f;
    }
    for _ in 0..30 {
        let mid = 0.5 * (lo + hi);
        if gap(t, &s.start.lerp(&s.end, mid), s.half) < TOI_TARGET {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Some(lo)
}

/// A box corner against the terrain surface.
struct Corner {
    p: (f64, f64),
    gap: f64,
    normal: (f64, f64),
}

/// Box2D's TOI sub-step for a lower leg that reached the terrain at `alpha`: the pose at impact
/// pushed out to [`TOI_REST_GAP`], the velocity `(v, w)` solved against the ground contacts alone
/// (no restitution, friction `mu`), then moved for the remaining `(1 − alpha)·dt`.
pub fn land(t: &Terrain, s: &Sweep, alpha: f64, v: (f64, f64), w: f64, mu: f64, dt: f64) -> Landed {
    let mut pose = s.start.lerp(&s.end, alpha);
    // Position pass: push out along the closest corner's normal.
    let (hw, hh) = s.half;
    let corners = |pose: &BoxPose| -> [Corner; 4] {
        pose.corners(s.half).map(|p| {
            let (gap, normal) = t.surface_gap(p);
            Corner { p, gap, normal }
        })
    };
    let closest = corners(&pose)
        .into_iter()
        .min_by(|a, b| a.gap.total_cmp(&b.gap))
        .expect("a box has corners");
    if closest.gap < TOI_REST_GAP {
        let push = TOI_REST_GAP - closest.gap;
        pose.c = (pose.c.0 + push * closest.normal.0, pose.c.1 + push * closest.normal.1);
    }
    // Velocity pass over the manifold points (the closest corner at least): (arm, normal).
    let all = corners(&pose);
    let nearest = all.iter().map(|c| c.gap).fold(f64::INFINITY, f64::min);
    let points: Vec<((f64, f64), (f64, f64))> = all
        .into_iter()
        .filter(|c| c.gap < MANIFOLD_GAP || c.gap <= nearest)
        .map(|c| ((c.p.0 - pose.c.0, c.p.1 - pose.c.1), c.normal))
        .collect();
    let m = 4.0 * hw * hh; // density 1
    let inertia = m * (4.0 * hw * hw + 4.0 * hh * hh) / 12.0;
    let (inv_m, inv_i) = (1.0 / m.max(1e-12), 1.0 / inertia.max(1e-18));
    let cross = |a: (f64, f64), b: (f64, f64)| a.0 * b.1 - a.1 * b.0;
    let (mut v, mut w) = (v, w);
    let mut pn = vec![0.0f64; points.len()];
    let mut pt = vec![0.0f64; points.len()];
    let point_vel = |v: (f64, f64), w: f64, r: (f64, f64)| (v.0 - w * r.1, v.1 + w * r.0);
    for _ in 0..VELOCITY_ITERATIONS {
        // Friction first, then the normal impulses (Box2D's order).
        for (k, &(r, n)) in points.iter().enumerate() {
            let tng = (n.1, -n.0);
            let vp = point_vel(v, w, r);
            let vt = vp.0 * tng.0 + vp.1 * tng.1;
            let rt = cross(r, tng);
            let kt = inv_m + inv_i * rt * rt;
            let max = mu * pn[k];
            let new = (pt[k] - vt / kt).clamp(-max, max);
            let d = new - pt[k];
            pt[k] = new;
            v = (v.0 + d * tng.0 * inv_m, v.1 + d * tng.1 * inv_m);
            w += inv_i * rt * d;
        }
        for (k, &(r, n)) in points.iter().enumerate() {
            let vp = point_vel(v, w, r);
            let vn = vp.0 * n.0 + vp.1 * n.1;
            let rn = cross(r, n);
            let kn = inv_m + inv_i * rn * rn;
            let new = (pn[k] - vn / kn).max(0.0);
            let d = new - pn[k];
            pn[k] = new;
            v = (v.0 + d * n.0 * inv_m, v.1 + d * n.1 * inv_m);
            w += inv_i * rn * d;
        }
    }
    let rest = (1.0 - alpha) * dt;
    pose.c = (pose.c.0 + v.0 * rest, pose.c.1 + v.1 * rest);
    pose.a += w * rest;
    Landed { pose, v, w }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::envs::box2d::bipedal_walker::terrain::TerrainSpec;

    /// Flat ground at y = 1 from x = 0 to 9.
    fn flat() -> Terrain {
        let spec = TerrainSpec {
            seed: 0,
            step: 1.0,
            length: 10,
            height: 1.0,
            grass: 10,
            startpad: 20,
            scale: 30.0,
            hardcore: false,
        };
        Terrain {
            spec,
            x: (0..10).map(f64::from).collect(),
            y: vec![1.0; 10],
            quads: Vec::new(),
            kinds: Vec::new(),
        }
    }

    fn falling(from_gap: f64, drop: f64) -> Sweep {
        falling_box((0.1, 0.5), from_gap, drop)
    }

    fn falling_box(half: (f64, f64), from_gap: f64, drop: f64) -> Sweep {
        let start = BoxPose {
            c: (4.0, 1.0 + half.1 + from_gap),
            a: 0.0,
        };
        let end = BoxPose {
            c: (4.0, start.c.1 - drop),
            a: 0.0,
        };
        Sweep { start, end, half }
    }

    #[test]
    fn time_of_impact_is_where_the_sweep_reaches_box2ds_target() {
        let t = flat();
        // Gap 0.05 → −0.03 linearly: the target 0.00625 is reached at (0.05 − 0.00625) / 0.08.
        let alpha = time_of_impact(&t, &falling(0.05, 0.08)).expect("reaches the ground");
        assert!((alpha - 0.546875).abs() < 1e-6, "{alpha}");
        // Stopping short of the target, or touching from the start: no TOI event.
        assert_eq!(time_of_impact(&t, &falling(0.05, 0.04)), None);
        assert_eq!(time_of_impact(&t, &falling(0.004, 0.01)), None);
    }

    #[test]
    fn a_flat_landing_stops_the_leg_and_rests_it_at_box2ds_gap() {
        let t = flat();
        let s = falling(0.05, 0.08);
        let alpha = time_of_impact(&t, &s).expect("reaches the ground");
        // Falling at 4 m/s, sliding at 0.5 m/s: friction (0.7 of the normal impulse) holds the
        // foot and both corners push, so it stops dead.
        let out = land(&t, &s, alpha, (0.5, -4.0), 0.0, 0.7, 0.02);
        assert!(
            out.v.0.abs() < 1e-6 && out.v.1.abs() < 1e-6 && out.w.abs() < 1e-6,
            "{out:?}"
        );
        assert!((out.pose.c.1 - (1.5 + TOI_REST_GAP)).abs() < 1e-9, "{out:?}");
        // Faster, the friction at the sole tips the tall foot over its front corner.
        let out = land(&t, &s, alpha, (1.0, -4.0), 0.0, 0.7, 0.02);
        assert!(out.w < -0.1, "{out:?}");
        // A flat plank sliding faster than friction can stop keeps what is left.
        let s = falling_box((0.5, 0.05), 0.05, 0.08);
        let alpha = time_of_impact(&t, &s).expect("reaches the ground");
        let out = land(&t, &s, alpha, (5.0, -4.0), 0.0, 0.7, 0.02);
        assert!(
            out.v.1.abs() < 1e-6 && (out.v.0 - (5.0 - 0.7 * 4.0)).abs() < 1e-6,
            "{out:?}"
        );
    }
}
