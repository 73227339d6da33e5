//! carl-bench's goal-directed variant of the locomotion robots (the `goal` option of ant,
//! half_cheetah, hopper, humanoid and walker2d).
//!
//! At reset the goal is placed `target_distance` metres from the torso's start, on the compass
//! bearing of `target_direction` (x is east, y is north). Each step the reward is how much closer
//! the torso came to the goal, `max(0, d_before − d_after)` (it replaces the task's reward); the
//! episode terminates once the torso is within `target_radius` of the goal (`info["success"] = 1`),
//! or when the task itself terminates (an unhealthy robot); truncation at the episode limit is
//! the task's. The observation is the task's.
//!
//! Where it differs from carl-bench 1.1.1's `BraxWalkerGoalWrapper` (deliberately):
//! * the position is the torso's true x-y position (the root's `qpos`), where carl-bench sums
//!   velocity observations times the physics timestep instead of the control step, so its
//!   distances are off by the frame skip;
//! * the 22.5° codes point where their names say (112 "north north east" is 22.5° east of north;
//!   carl-bench gives it the vector of east-north-east, and likewise for the other seven);
//! * on the planar robots (half_cheetah, hopper, walker2d) the torso moves along x only: a goal
//!   with a north or south component keeps that component out of reach (codes 1 and 3 can never
//!   be reached, their reward is only earned by moving back towards x = 0).
//!
//! The state is the task's state followed by the torso's start position `(x, y)`, from which
//! the goal follows (with the context); the distance before a step is the torso's at the state
//! stepped from, so `set_state` fully determines the next step.

use carl_env::api::{Action, Env, EnvError, Info, Space, StepOutcome, check_state_len};

use super::locomotion::Locomotion;
use super::model::RootKind;
use super::params::RobotParams;

/// A compass code of carl-bench's `target_direction`, its name and its bearing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Direction {
    /// carl-bench's code: digits 1 north, 2 east, 3 south, 4 west, combined.
    pub code: u16,
    /// carl-bench's `DIRECTION_NAMES` entry.
    pub name: &'static str,
    /// Compass bearing in degrees, clockwise from north.
    pub bearing_deg: f64,
}

impl Direction {
    /// Unit vector `(east, north)` of the bearing.
    pub fn unit(&self) -> [f64; 2] {
        let b = self.bearing_deg.to_radians();
        [b.sin(), b.cos()]
    }
}

/// carl-bench's 16 codes, in its `directions` order.
pub const DIRECTIONS: [Direction; 16] = [
    Direction { code: 1, name: "north", bearing_deg: 0.0 },
    Direction { code: 3, name: "south", bearing_deg: 180.0 },
    Direction { code: 2, name: "east", bearing_deg: 90.0 },
    Direction { code: 4, name: "west", bearing_deg: 270.0 },
    Direction { code: 12, name: "north east", bearing_deg: 45.0 },
    Direction { code: 32, name: "south east", bearing_deg: 135.0 },
    Direction { code: 14, name: "north west", bearing_deg: 315.0 },
    Direction { code: 34, name: "south west", bearing_deg: 225.0 },
    Direction { code: 112, name: "north north east", bearing_deg: 22.5 },
    Direction { code: 332, name: "south south east", bearing_deg: 157.5 },
    Direction { code: 114, name: "north north west", bearing_deg: 337.5 },
    Direction { code: 334, name: "south south west", bearing_deg: 202.5 },
    Direction { code: 212, name: "east north east", bearing_deg: 67.5 },
    Direction { code: 232, name: "east south east", bearing_deg: 112.5 },
    Direction { code: 414, name: "west north west", bearing_deg: 292.5 },
    Direction { code: 434, name: "west south west", bearing_deg: 247.5 },
];

/// The direction of code `code` (`None` for a number that is not one of the 16 codes).
pub fn direction(code: f64) -> Option<&'static Direction> {
    DIRECTIONS.iter().find(|d| f64::from(d.code) == code)
}

/// The goal's state of the last reset or step (for `info`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct GoalInfo {
    distance: f64,
    success: bool,
}

/// A locomotion task with carl-bench's positional goal (see the module docs).
#[derive(Debug, Clone)]
pub struct GoalLocomotion {
    task: Locomotion,
    direction: &'static Direction,
    distance: f64,
    radius: f64,
    /// Torso position `(x, y)` at the episode's start.
    start: [f64; 2],
    info: GoalInfo,
}

impl GoalLocomotion {
    /// `task` with the goal of its context (`target_distance`, `target_direction`,
    /// `target_radius`); `None` if the direction is not one of the 16 codes.
    pub fn new(task: Locomotion) -> Option<Self> {
        let p: &RobotParams = task.params();
        let direction = direction(p.target_direction)?;
        let (distance, radius) = (p.target_distance, p.target_radius);
        let mut g = GoalLocomotion {
            task,
            direction,
            distance,
            radius,
            start: [0.0; 2],
            info: GoalInfo::default(),
        };
        g.start = g.torso_xy(&g.task.state());
        g.info.distance = g.distance_from(g.start);
        Some(g)
    }

    pub fn task(&self) -> &Locomotion {
        &self.task
    }
    pub fn direction(&self) -> &'static Direction {
        self.direction
    }

    /// The goal's position `(x, y)`.
    pub fn goal(&self) -> [f64; 2] {
        let u = self.direction.unit();
        [self.start[0] + self.distance * u[0], self.start[1] + self.distance * u[1]]
    }

    /// The torso's `(x, y)` in a task state (`y = 0` on a planar robot).
    fn torso_xy(&self, task_state: &[f64]) -> [f64; 2] {
        let free = self.task.model().side.root == RootKind::Free;
        [task_state[0], if free { task_state[1] } else { 0.0 }]
    }

    fn distance_from(&self, p: [f64; 2]) -> f64 {
        let g = self.goal();
        (g[0] - p[0]).hypot(g[1] - p[1])
    }
}

impl carl_env::runtime::Runtime for GoalLocomotion {
    /// The states given, each with its start moved so that the torso stands just inside, and
    /// just outside, the goal's radius: where `target_radius` decides termination.
    fn goal_states(&self, states: &[Vec<f64>]) -> Result<Vec<Vec<f64>>, EnvError> {
        let u = self.direction.unit();
        let n = self.task.state_dim();
        let mut out = Vec::with_capacity(2 * states.len());
        for s in states.iter().filter(|s| s.len() == n + 2) {
            let p = self.torso_xy(s);
            for k in [0.9, 1.1] {
                // The goal `k · radius` ahead of the torso along the goal's bearing.
                let back = self.distance - k * self.radius;
                let mut t = s.clone();
                t[n] = p[0] - back * u[0];
                t[n + 1] = p[1] - back * u[1];
                out.push(t);
            }
        }
        Ok(out)
    }
}

impl Env for GoalLocomotion {
    fn id(&self) -> &'static str {
        self.task.id()
    }
    fn obs_dim(&self) -> usize {
        self.task.obs_dim()
    }
    /// The task's state, then the torso's start `(x, y)`.
    fn state_dim(&self) -> usize {
        self.task.state_dim() + 2
    }
    fn observation_space(&self) -> Space {
        self.task.observation_space()
    }
    fn action_space(&self) -> Space {
        self.task.action_space()
    }

    fn reset_into(&mut self, seed: Option<u64>, obs: &mut [f32]) -> Result<(), EnvError> {
        self.task.reset_into(seed, obs)?;
        self.start = self.torso_xy(&self.task.state());
        self.info = GoalInfo {
            distance: self.distance_from(self.start),
            success: false,
        };
        Ok(())
    }

    fn step_into(&mut self, action: &Action, obs: &mut [f32]) -> Result<StepOutcome, EnvError> {
        let before = self.distance_from(self.torso_xy(&self.task.state()));
        let out = self.task.step_into(action, obs)?;
        let after = self.distance_from(self.torso_xy(&self.task.state()));
        let success = after <= self.radius;
        self.info = GoalInfo {
            distance: after,
            success,
        };
        Ok(StepOutcome {
            reward: (before - after).max(0.0),
            terminated: out.terminated || success,
            truncated: out.truncated,
        })
    }

    fn observe_into(&self, obs: &mut [f32]) -> Result<(), EnvError> {
        self.task.observe_into(obs)
    }
    fn observe_f64_into(&self, obs: &mut [f64]) -> Result<(), EnvError> {
        self.task.observe_f64_into(obs)
    }

    fn state(&self) -> Vec<f64> {
        let mut s = self.task.state();
        s.extend(self.start);
        s
    }

    fn set_state(&mut self, state: &[f64]) -> Result<(), EnvError> {
        check_state_len(self.id(), state, self.state_dim())?;
        let n = self.task.state_dim();
        self.task.set_state(&state[..n])?;
        self.start = [state[n], state[n + 1]];
        self.info = GoalInfo {
            distance: self.distance_from(self.torso_xy(&state[..n])),
            success: false,
        };
        Ok(())
    }

    /// The task's `info` with `goal_direction` (the code; Python reports its name),
    /// `goal_distance` (the torso's distance to the goal, m) and `success` (1 once within
    /// `target_radius`).
    fn info(&self) -> Info {
        let mut m = self.task.info();
        m.insert("goal_direction".into(), f64::from(self.direction.code));
        m.insert("goal_distance".into(), self.info.distance);
        m.insert("success".into(), f64::from(u8::from(self.info.success)));
        m
    }

    fn render(&self) -> Option<carl_pixels::Frame> {
        self.task.render()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_code_points_where_its_name_says() {
        let word = |w: &str| -> [f64; 2] {
            match w {
                "north" => [0.0, 1.0],
                "south" => [0.0, -1.0],
                "east" => [1.0, 0.0],
                "west" => [-1.0, 0.0],
                _ => panic!("{w}"),
            }
        };
        for d in &DIRECTIONS {
            let u = d.unit();
            assert!((u[0].hypot(u[1]) - 1.0).abs() < 1e-12, "{}", d.name);
            let words: Vec<&str> = d.name.split(' ').collect();
            // The named words, averaged, point the way (a compass name's last word is the
            // principal direction, each earlier word pulls towards it).
            let mut v = [0.0, 0.0];
            for w in &words {
                let x = word(w);
                v = [v[0] + x[0], v[1] + x[1]];
            }
            let expect_bearing = match words.len() {
                1 | 2 => v[0].atan2(v[1]).to_degrees().rem_euclid(360.0),
                // "north north east": halfway between north and north east.
                _ => {
                    let first = word(words[0]);
                    let rest = [v[0] - first[0], v[1] - first[1]];
                    let half = rest[0].atan2(rest[1]);
                    let main = first[0].atan2(first[1]);
                    let mut diff = half - main;
                    if diff > std::f64::consts::PI {
                        diff -= 2.0 * std::f64::consts::PI;
                    }
                    if diff < -std::f64::consts::PI {
                        diff += 2.0 * std::f64::consts::PI;
                    }
                    (main + diff / 2.0).to_degrees().rem_euclid(360.0)
                }
            };
            assert!(
                (expect_bearing - d.bearing_deg).abs() < 1e-9,
                "{} {}: bearing {} vs {}",
                d.code,
                d.name,
                d.bearing_deg,
                expect_bearing
            );
        }
        assert_eq!(DIRECTIONS.iter().map(|d| d.code).collect::<std::collections::BTreeSet<_>>().len(), 16);
        assert!(direction(5.0).is_none() && direction(1.0).is_some());
    }
}
