//! MountainCar-v0 (Gymnasium 1.4 `MountainCarEnv`).

use carl_env::api::{
    Action, DType, Env, EnvError, Space, StepOutcome, check_obs_len, check_state, context_features, discrete_action,
    np_clip,
};
use carl_env::rng::{EnvRng, normal, uniform};

const ID: &str = "mountain_car";
/// The outcome of an episode that terminated: the car reached the goal ([`Env::outcome`]).
pub const SOLVED: &str = "solved";

/// How `reset` draws the initial state from `start_*` / `start_*_std`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StartDistribution {
    /// position ~ U(start_position ± start_position_std), velocity ~ U(start_velocity ±
    /// start_velocity_std). With the defaults this is Gymnasium's U(-0.6, -0.4), 0 — the bounds
    /// `-0.5 ∓ 0.1` are exactly the doubles -0.6 and -0.4.
    #[default]
    Uniform,
    /// position ~ N(start_position, start_position_std), velocity ~ N(start_velocity,
    /// start_velocity_std): the CARL 2021 (`neurips_ecorl_workshop_2021`) semantics.
    Normal,
}

/// MountainCar context. `Default` is Gymnasium's `MountainCarEnv`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MountainCarParams {
    pub force: f64,
    pub goal_position: f64,
    pub goal_velocity: f64,
    pub gravity: f64,
    pub max_position: f64,
    pub max_speed: f64,
    pub min_position: f64,
    pub start_position: f64,
    pub start_position_std: f64,
    pub start_velocity: f64,
    pub start_velocity_std: f64,
    /// Not a context feature: how the `start_*` features are interpreted.
    pub start_distribution: StartDistribution,
}

impl Default for MountainCarParams {
    fn default() -> Self {
        MountainCarParams {
            force: 0.001,
            goal_position: 0.5,
            goal_velocity: 0.0,
            gravity: 0.0025,
            max_position: 0.6,
            max_speed: 0.07,
            min_position: -1.2,
            start_position: -0.5,
            start_position_std: 0.1,
            start_velocity: 0.0,
            start_velocity_std: 0.0,
            start_distribution: StartDistribution::Uniform,
        }
    }
}

context_features!(MountainCarParams, "mountain_car", {
    force: "force",
    goal_position: "goal_position",
    goal_velocity: "goal_velocity",
    gravity: "gravity",
    max_position: "max_position",
    max_speed: "max_speed",
    min_position: "min_position",
    start_position: "start_position",
    start_position_std: "start_position_std",
    start_velocity: "start_velocity",
    start_velocity_std: "start_velocity_std",
});

#[derive(Debug, Clone)]
pub struct MountainCar {
    params: MountainCarParams,
    /// `[position, velocity]`
    state: [f64; 2],
    ready: bool,
    rng: EnvRng,
}

impl MountainCar {
    pub fn new(params: MountainCarParams) -> Self {
        MountainCar {
            params,
            state: [0.0; 2],
            ready: false,
            rng: EnvRng::default(),
        }
    }
    pub fn params(&self) -> &MountainCarParams {
        &self.params
    }
    pub fn params_mut(&mut self) -> &mut MountainCarParams {
        &mut self.params
    }
    #[inline]
    fn write_obs(&self, obs: &mut [f32]) {
        obs[0] = self.state[0] as f32;
        obs[1] = self.state[1] as f32;
    }
}

impl Default for MountainCar {
    fn default() -> Self {
        MountainCar::new(MountainCarParams::default())
    }
}

impl carl_env::runtime::Runtime for MountainCar {
    /// The parameters are read at every step, so a schedule's new values act from the next one.
    fn set_features(&mut self, values: &[(String, f64)]) -> Option<Result<(), carl_env::context::MakeError>> {
        Some(carl_env::context::apply("mountain_car", values, |name, x| {
            self.params.set(name, x)
        }))
    }
}

impl Env for MountainCar {
    fn id(&self) -> &'static str {
        ID
    }
    fn obs_dim(&self) -> usize {
        2
    }
    fn state_dim(&self) -> usize {
        2
    }
    fn observation_space(&self) -> Space {
        let p = &self.params;
        Space::Box {
            low: vec![p.min_position as f32, -p.max_speed as f32],
            high: vec![p.max_position as f32, p.max_speed as f32],
            shape: vec![2],
            dtype: DType::Float32,
        }
    }
    fn action_space(&self) -> Space {
        Space::Discrete { n: 3, start: 0 }
    }

    fn reset_into(&mut self, seed: Option<u64>, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(ID, obs, 2)?;
        if let Some(seed) = seed {
            self.rng = EnvRng::from_seed(seed);
        }
        let p = &self.params;
        self.state = match p.start_distribution {
            StartDistribution::Uniform => {
                let (ps, vs) = (p.start_position_std, p.start_velocity_std);
                let pos = uniform(&mut self.rng, p.start_position - ps, p.start_position + ps);
                // Gymnasium's velocity is the constant 0; only draw when there is a range.
                let vel = if vs == 0.0 {
                    p.start_velocity
                } else {
                    uniform(&mut self.rng, p.start_velocity - vs, p.start_velocity + vs)
                };
                [pos, vel]
            }
            StartDistribution::Normal => [
                normal(&mut self.rng, p.start_position, p.start_position_std),
                normal(&mut self.rng, p.start_velocity, p.start_velocity_std),
            ],
        };
        self.ready = true;
        self.write_obs(obs);
        Ok(())
    }

    #[inline]
    fn step_into(&mut self, action: &Action, obs: &mut [f32]) -> Result<StepOutcome, EnvError> {
        let a = discrete_action(ID, action, 3)?;
        check_obs_len(ID, obs, 2)?;
        if !self.ready {
            return Err(EnvError::NeedsReset { env: ID });
        }
        let p = &self.params;
        let [position, velocity] = self.state;
        // velocity += (action - 1) * force + math.cos(3 * position) * (-gravity)
        let velocity = velocity + ((a - 1) as f64 * p.force + (3.0 * position).cos() * (-p.gravity));
        let mut velocity = np_clip(velocity, -p.max_speed, p.max_speed);
        let position = position + velocity;
        let position = np_clip(position, p.min_position, p.max_position);
        if position == p.min_position && velocity < 0.0 {
            velocity = 0.0;
        }
        let terminated = position >= p.goal_position && velocity >= p.goal_velocity;
        self.state = [position, velocity];
        self.write_obs(obs);
        Ok(StepOutcome {
            reward: -1.0,
            terminated,
            truncated: false,
        })
    }

    fn observe_into(&self, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(ID, obs, 2)?;
        self.write_obs(obs);
        Ok(())
    }
    /// [`SOLVED`] once the car is at the goal (the step's termination test on the state it keeps).
    fn outcome(&self) -> Option<&'static str> {
        let p = &self.params;
        let [position, velocity] = self.state;
        (self.ready && position >= p.goal_position && velocity >= p.goal_velocity).then_some(SOLVED)
    }
    fn state(&self) -> Vec<f64> {
        self.state.to_vec()
    }
    fn set_state(&mut self, state: &[f64]) -> Result<(), EnvError> {
        self.state = check_state::<2>(ID, state)?;
        self.ready = true;
        Ok(())
    }
}
