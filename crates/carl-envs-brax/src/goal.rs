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
        // Exact zeros on the axes (cos 90° is 6e-17 in floating point).
        let exact = |v: f64| if v.abs() < 1e-12 { 0.0 } else { v };
        [exact(b.sin()), exact(b.cos())]
    }
}

/// carl-bench's 16 codes, in its `directions` order.
pub const DIRECTIONS: [Direction; 16] = [
    Direction {
        code: 1,
        name: "north",
        bearing_deg: 0.0,
    },
    Direction {
        code: 3,
        name: "south",
        bearing_deg: 180.0,
    },
    Direction {
        code: 2,
        name: "east",
        bearing_deg: 90.0,
    },
    Direction {
        code: 4,
        name: "west",
        bearing_deg: 270.0,
    },
    Direction {
        code: 12,
        name: "north east",
        bearing_deg: 45.0,
    },
    Direction {
        code: 32,
        name: "south east",
        bearing_deg: 135.0,
    },
    Direction {
        code: 14,
        name: "north west",
        bearing_deg: 315.0,
    },
    Direction {
        code: 34,
        name: "south west",
        bearing_deg: 225.0,
    },
    Direction {
        code: 112,
        name: "north north east",
        bearing_deg: 22.5,
    },
    Direction {
        code: 332,
        name: "south south east",
        bearing_deg: 157.5,
    },
    Direction {
        code: 114,
        name: "north north west",
        bearing_deg: 337.5,
    },
    Direction {
        code: 334,
        name: "south south west",
        bearing_deg: 202.5,
    },
    Direction {
        code: 212,
        name: "east north east",
        bearing_deg: 67.5,
    },
    Direction {
        code: 232,
        name: "east south east",
        bearing_deg: 112.5,
    },
    Direction {
        code: 414,
        name: "west north west",
        bearing_deg: 292.5,
    },
    Direction {
        code: 434,
        name: "west south west",
        bearing_deg: 247.5,
    },
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

    /// The torso's `(x, y)` at the episode's start.
    pub fn start(&self) -> [f64; 2] {
        self.start
    }
    /// The torso's `(x, y)` now.
    pub fn torso_position(&self) -> [f64; 2] {
        self.torso_xy(&self.task.state())
    }
    /// The goal's position `(x, y)`.
    pub fn goal(&self) -> [f64; 2] {
        let u = self.direction.unit();
        [
            self.start[0] + self.distance * u[0],
            self.start[1] + self.distance * u[1],
        ]
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
    use crate::{default_params, make_robot};
    use carl_env::rng::{EnvRng, uniform};

    fn goal_env(id: &str, set: impl FnOnce(&mut RobotParams)) -> GoalLocomotion {
        let mut p = default_params(id).unwrap();
        set(&mut p);
        GoalLocomotion::new(make_robot(id, p).unwrap()).unwrap()
    }

    fn random_action(env: &GoalLocomotion, rng: &mut EnvRng) -> Action {
        let n = match env.action_space() {
            Space::Box { shape, .. } => shape[0],
            other => panic!("{other:?}"),
        };
        Action::Continuous((0..n).map(|_| uniform(rng, -1.0, 1.0) as f32).collect())
    }

    /// The reward is the decrease of the torso's true x-y distance to the goal (never
    /// negative), `info` reports that distance, the goal lies `target_distance` away on the
    /// bearing of the code.
    #[test]
    fn reward_is_the_decrease_of_the_torsos_distance_to_the_goal() {
        for id in ["ant", "half_cheetah", "hopper"] {
            for code in [2.0, 14.0, 232.0] {
                let mut env = goal_env(id, |p| {
                    p.target_direction = code;
                    p.target_distance = 3.0;
                    p.target_radius = 0.1;
                });
                let mut obs = vec![0.0; env.obs_dim()];
                env.reset_into(Some(3), &mut obs).unwrap();
                let start = env.torso_xy(&env.task().state());
                let u = direction(code).unwrap().unit();
                let g = env.goal();
                assert!((g[0] - start[0] - 3.0 * u[0]).abs() < 1e-12 && (g[1] - start[1] - 3.0 * u[1]).abs() < 1e-12);
                let dist = |p: [f64; 2]| (g[0] - p[0]).hypot(g[1] - p[1]);
                assert!((env.info()["goal_distance"] - 3.0).abs() < 1e-12, "{id}");
                let mut rng = EnvRng::from_seed(9);
                let mut positive = 0;
                for _ in 0..30 {
                    let before = dist(env.torso_xy(&env.task().state()));
                    let a = random_action(&env, &mut rng);
                    let out = env.step_into(&a, &mut obs).unwrap();
                    let after = dist(env.torso_xy(&env.task().state()));
                    assert_eq!(out.reward, (before - after).max(0.0), "{id} {code}");
                    assert_eq!(env.info()["goal_distance"], after);
                    assert_eq!(env.info()["goal_direction"], code);
                    positive += usize::from(out.reward > 0.0);
                    if out.terminated {
                        break;
                    }
                }
                assert!(positive > 0, "{id} {code}: the torso never came closer");
            }
        }
    }

    /// Within `target_radius` the episode terminates with `success = 1`; outside it goes on.
    #[test]
    fn reaching_the_goal_terminates_with_success() {
        let mut env = goal_env("ant", |p| {
            p.target_distance = 10.0;
            p.target_radius = 2.0;
            p.target_direction = 12.0;
        });
        let mut obs = vec![0.0; env.obs_dim()];
        env.reset_into(Some(0), &mut obs).unwrap();
        assert_eq!(env.info()["success"], 0.0);
        let zero = Action::Continuous(vec![0.0; 8]);
        let out = env.step_into(&zero, &mut obs).unwrap();
        assert!(!out.terminated && env.info()["success"] == 0.0);
        // Move the start so that the goal lies 1 m ahead of the torso: inside the radius.
        let mut s = env.state();
        let n = s.len() - 2;
        let p = env.torso_xy(&s);
        let u = env.direction().unit();
        s[n] = p[0] - 9.0 * u[0];
        s[n + 1] = p[1] - 9.0 * u[1];
        env.set_state(&s).unwrap();
        assert!((env.info()["goal_distance"] - 1.0).abs() < 1e-9);
        let out = env.step_into(&zero, &mut obs).unwrap();
        assert!(out.terminated && !out.truncated);
        assert_eq!(env.info()["success"], 1.0);
        // The same state with a smaller radius is not a success.
        let mut small = goal_env("ant", |p| {
            p.target_distance = 10.0;
            p.target_radius = 0.5;
            p.target_direction = 12.0;
        });
        small.set_state(&s).unwrap();
        let out = small.step_into(&zero, &mut obs).unwrap();
        assert!(!out.terminated && small.info()["success"] == 0.0);
        // A goal at the start is reached on the first step.
        let mut here = goal_env("hopper", |p| p.target_distance = 0.0);
        here.reset_into(Some(1), &mut obs[..11]).unwrap();
        let out = here
            .step_into(&Action::Continuous(vec![0.0; 3]), &mut obs[..11])
            .unwrap();
        assert!(out.terminated && here.info()["success"] == 1.0);
    }

    /// The goal variant steps the task's physics unchanged: same states, observations and
    /// (unhealthy) termination as the task itself.
    #[test]
    fn the_goal_leaves_the_tasks_physics_and_observation_alone() {
        let mut task = make_robot("walker2d", default_params("walker2d").unwrap()).unwrap();
        let mut env = goal_env("walker2d", |_| {});
        let (mut oa, mut ob) = (vec![0.0; task.obs_dim()], vec![0.0; env.obs_dim()]);
        task.reset_into(Some(5), &mut oa).unwrap();
        env.reset_into(Some(5), &mut ob).unwrap();
        assert_eq!(oa, ob);
        let mut rng = EnvRng::from_seed(1);
        for _ in 0..40 {
            let a = random_action(&env, &mut rng);
            let x = task.step_into(&a, &mut oa).unwrap();
            let y = env.step_into(&a, &mut ob).unwrap();
            assert_eq!(oa, ob);
            assert_eq!(task.state(), env.task().state());
            assert_eq!(x.terminated, y.terminated);
            if x.terminated {
                break;
            }
        }
    }

    #[test]
    fn a_direction_that_is_no_code_is_refused_and_bad_states_are_errors() {
        let mut p = default_params("ant").unwrap();
        p.target_direction = 5.0;
        assert!(GoalLocomotion::new(make_robot("ant", p).unwrap()).is_none());
        let mut env = goal_env("ant", |_| {});
        let mut s = env.state();
        assert!(env.set_state(&s[..s.len() - 1]).is_err());
        let n = s.len();
        s[n - 1] = f64::NAN;
        assert!(env.set_state(&s).is_err());
    }

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
        assert_eq!(
            DIRECTIONS
                .iter()
                .map(|d| d.code)
                .collect::<std::collections::BTreeSet<_>>()
                .len(),
            16
        );
        assert!(direction(5.0).is_none() && direction(1.0).is_some());
    }
}
