//! Pendulum-v1 (Gymnasium 1.4 `PendulumEnv`).
//!
//! NumPy 2 typing is reproduced exactly: the action is a float32 array, so after
//! `np.clip(u, -max_torque, max_torque)[0]` the torque `u` is a float32 scalar and Python-float
//! coefficients multiplying it are rounded to float32 first (NEP 50 "weak" scalars):
//! `0.001 * u**2` and `3.0 / (m * l**2) * u` are float32 products that are then promoted to
//! float64. Scalar `** 2` is the C library's `pow`.

use std::f64::consts::PI;

use carl_env::api::{
    Action, DType, Env, EnvError, Space, StepOutcome, check_obs_len, check_state, context_features, np_clip,
    np_clip_f32, np_sq_f32, py_sq, scalar_action,
};
use carl_env::rng::{EnvRng, uniform};

const ID: &str = "pendulum";

/// Pendulum context. `Default` is Gymnasium's `PendulumEnv`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PendulumParams {
    pub dt: f64,
    pub g: f64,
    pub l: f64,
    pub m: f64,
    pub max_speed: f64,
    pub max_torque: f64,
    /// Initial angle ~ U(-initial_angle_max, initial_angle_max) (Gymnasium's `x_init`, π).
    pub initial_angle_max: f64,
    /// Initial angular velocity ~ U(-max, max) (Gymnasium's `y_init`, 1).
    pub initial_velocity_max: f64,
}

impl Default for PendulumParams {
    fn default() -> Self {
        PendulumParams {
            dt: 0.05,
            g: 10.0,
            l: 1.0,
            m: 1.0,
            max_speed: 8.0,
            max_torque: 2.0,
            initial_angle_max: PI,
            initial_velocity_max: 1.0,
        }
    }
}

context_features!(PendulumParams, "pendulum", {
    dt: "dt",
    g: "g",
    l: "l",
    m: "m",
    max_speed: "max_speed",
    max_torque: "max_torque",
    initial_angle_max: "initial_angle_max",
    initial_velocity_max: "initial_velocity_max",
});

/// `((x + pi) % (2 * pi)) - pi` with NumPy/Python floor-modulo semantics.
#[inline]
pub fn angle_normalize(x: f64) -> f64 {
    py_mod(x + PI, 2.0 * PI) - PI
}

/// Python/NumPy float `a % b` (result has the sign of `b`), as `npy_divmod` computes it.
#[inline]
pub(crate) fn py_mod(a: f64, b: f64) -> f64 {
    let m = a % b; // C fmod
    if m != 0.0 {
        if (b < 0.0) != (m < 0.0) { m + b } else { m }
    } else {
        0.0f64.copysign(b)
    }
}

#[derive(Debug, Clone)]
pub struct Pendulum {
    params: PendulumParams,
    /// `[theta, theta_dot]`
    state: [f64; 2],
    ready: bool,
    rng: EnvRng,
}

impl Pendulum {
    pub fn new(params: PendulumParams) -> Self {
        Pendulum {
            params,
            state: [0.0; 2],
            ready: false,
            rng: EnvRng::default(),
        }
    }
    pub fn params(&self) -> &PendulumParams {
        &self.params
    }
    pub fn params_mut(&mut self) -> &mut PendulumParams {
        &mut self.params
    }
    #[inline]
    fn write_obs(&self, obs: &mut [f32]) {
        let [th, thdot] = self.state;
        obs[0] = th.cos() as f32;
        obs[1] = th.sin() as f32;
        obs[2] = thdot as f32;
    }
}

impl Default for Pendulum {
    fn default() -> Self {
        Pendulum::new(PendulumParams::default())
    }
}

impl carl_env::runtime::Runtime for Pendulum {
    /// The parameters are read at every step, so a schedule's new values act from the next one.
    fn set_features(&mut self, values: &[(String, f64)]) -> Option<Result<(), carl_env::context::MakeError>> {
        Some(carl_env::context::apply("pendulum", values, |name, x| {
            self.params.set(name, x)
        }))
    }
}

impl Env for Pendulum {
    fn id(&self) -> &'static str {
        ID
    }
    fn obs_dim(&self) -> usize {
        3
    }
    fn state_dim(&self) -> usize {
        2
    }
    fn observation_space(&self) -> Space {
        let ms = self.params.max_speed as f32;
        Space::Box {
            low: vec![-1.0, -1.0, -ms],
            high: vec![1.0, 1.0, ms],
            shape: vec![3],
            dtype: DType::Float32,
        }
    }
    fn action_space(&self) -> Space {
        let mt = self.params.max_torque as f32;
        Space::Box {
            low: vec![-mt],
            high: vec![mt],
            shape: vec![1],
            dtype: DType::Float32,
        }
    }

    fn reset_into(&mut self, seed: Option<u64>, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(ID, obs, 3)?;
        if let Some(seed) = seed {
            self.rng = EnvRng::from_seed(seed);
        }
        let (x, y) = (self.params.initial_angle_max, self.params.initial_velocity_max);
        self.state = [uniform(&mut self.rng, -x, x), uniform(&mut self.rng, -y, y)];
        self.ready = true;
        self.write_obs(obs);
        Ok(())
    }

    #[inline]
    fn step_into(&mut self, action: &Action, obs: &mut [f32]) -> Result<StepOutcome, EnvError> {
        let u = scalar_action(ID, action)?;
        check_obs_len(ID, obs, 3)?;
        if !self.ready {
            return Err(EnvError::NeedsReset { env: ID });
        }
        let p = &self.params;
        let [th, thdot] = self.state;
        let mt = p.max_torque as f32;
        let u = np_clip_f32(u, -mt, mt);
        let costs = py_sq(angle_normalize(th)) + 0.1 * py_sq(thdot) + ((0.001f64 as f32) * np_sq_f32(u)) as f64;
        let torque_term = ((3.0 / (p.m * py_sq(p.l))) as f32 * u) as f64;
        let newthdot = thdot + (3.0 * p.g / (2.0 * p.l) * th.sin() + torque_term) * p.dt;
        let newthdot = np_clip(newthdot, -p.max_speed, p.max_speed);
        let newth = th + newthdot * p.dt;
        self.state = [newth, newthdot];
        self.write_obs(obs);
        Ok(StepOutcome {
            reward: -costs,
            terminated: false,
            truncated: false,
        })
    }

    fn observe_into(&self, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(ID, obs, 3)?;
        self.write_obs(obs);
        Ok(())
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

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn python_modulo() {
        assert_eq!(py_mod(-1.0, 3.0), 2.0);
        assert_eq!(py_mod(1.0, -3.0), -2.0);
        assert_eq!(py_mod(3.0, 3.0).to_bits(), 0.0f64.to_bits());
        assert_eq!(py_mod(-3.0, 3.0).to_bits(), 0.0f64.to_bits());
    }
}
