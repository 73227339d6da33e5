//! Gymnasium's hand-written BipedalWalker gait (`BipedalWalkerHeuristics`), re-implemented
//! from its control law: a three-phase state machine (stand on one leg while swinging the other
//! forward, put it down, push off with the supporting knee), PD targets for hips and knees, a
//! hull-angle correction on both hips and vertical-speed damping on both knees.

/// Gait phases.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    StayOnOneLeg,
    PutOtherDown,
    PushOff,
}

/// The controller's memory between steps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WalkerHeuristic {
    pub phase: Phase,
    pub moving_leg: usize,
    pub supporting_knee_angle: f64,
}

/// Forward speed (observation 2) above which the gait stops accelerating.
pub const SPEED: f64 = 0.29;
/// Knee target of a supporting leg (observation units, angle + 1).
pub const SUPPORT_KNEE_ANGLE: f64 = 0.1;

impl Default for WalkerHeuristic {
    fn default() -> Self {
        WalkerHeuristic {
            phase: Phase::StayOnOneLeg,
            moving_leg: 0,
            supporting_knee_angle: SUPPORT_KNEE_ANGLE,
        }
    }
}

impl WalkerHeuristic {
    /// The action for observation `s` (24 values), updating the phase.
    pub fn act(&mut self, s: &[f32]) -> [f32; 4] {
        let g = |i: usize| s.get(i).copied().unwrap_or(0.0) as f64;
        let moving = self.moving_leg;
        let supporting = 1 - moving;
        let (mb, sb) = (4 + 5 * moving, 4 + 5 * supporting);
        let mut hip_targ: [Option<f64>; 2] = [None, None];
        let mut knee_targ: [Option<f64>; 2] = [None, None];

        if self.phase == Phase::StayOnOneLeg {
            hip_targ[moving] = Some(1.1);
            knee_targ[moving] = Some(-0.6);
            self.supporting_knee_angle += 0.03;
            if g(2) > SPEED {
                self.supporting_knee_angle += 0.03;
            }
            self.supporting_knee_angle = self.supporting_knee_angle.min(SUPPORT_KNEE_ANGLE);
            knee_targ[supporting] = Some(self.supporting_knee_angle);
            if g(sb) < 0.10 {
                // The supporting leg is behind the hull.
                self.phase = Phase::PutOtherDown;
            }
        }
        if self.phase == Phase::PutOtherDown {
            hip_targ[moving] = Some(0.1);
            knee_targ[moving] = Some(SUPPORT_KNEE_ANGLE);
            knee_targ[supporting] = Some(self.supporting_knee_angle);
            if g(mb + 4) != 0.0 {
                self.phase = Phase::PushOff;
                self.supporting_knee_angle = g(mb + 2).min(SUPPORT_KNEE_ANGLE);
            }
        }
        if self.phase == Phase::PushOff {
            knee_targ[moving] = Some(self.supporting_knee_angle);
            knee_targ[supporting] = Some(1.0);
            if g(sb + 2) > 0.88 || g(2) > 1.2 * SPEED {
                self.phase = Phase::StayOnOneLeg;
                self.moving_leg = supporting;
            }
        }

        // Python tests the targets for truthiness: a target of exactly 0 counts as "none".
        let active = |t: Option<f64>| t.filter(|v| *v != 0.0);
        let mut hip_todo = [0.0f64; 2];
        let mut knee_todo = [0.0f64; 2];
        for leg in 0..2 {
            let b = 4 + 5 * leg;
            if let Some(t) = active(hip_targ[leg]) {
                hip_todo[leg] = 0.9 * (t - g(b)) - 0.25 * g(b + 1);
            }
            if let Some(t) = active(knee_targ[leg]) {
                knee_todo[leg] = 4.0 * (t - g(b + 2)) - 0.25 * g(b + 3);
            }
            // Keep the hull level; damp vertical oscillations.
            hip_todo[leg] -= 0.9 * (0.0 - g(0)) - 1.5 * g(1);
            knee_todo[leg] -= 15.0 * g(3);
        }
        let a = [hip_todo[0], knee_todo[0], hip_todo[1], knee_todo[1]];
        a.map(|x| (0.5 * x).clamp(-1.0, 1.0) as f32)
    }
}
