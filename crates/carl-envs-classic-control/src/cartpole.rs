//! CartPole-v1 (Gymnasium 1.4 `CartPoleEnv`, Euler integrator, reward 1 per step).

use carl_env::api::{
    Action, DType, Env, EnvError, Space, StepOutcome, check_obs_len, check_state, context_features, discrete_action,
};
use carl_env::rng::{EnvRng, uniform};

const ID: &str = "cartpole";
/// The outcome of an episode that terminated: the pole fell past its angle or the cart left
/// the track ([`Env::outcome`]).
pub const FAILED: &str = "failed";

/// CartPole context. `Default` is Gymnasium's `CartPoleEnv`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CartPoleParams {
    pub gravity: f64,
    pub masscart: f64,
    pub masspole: f64,
    /// Half the pole's length (Gymnasium's `length`).
    pub pole_length: f64,
    pub force_magnifier: f64,
    /// Integration step in seconds (Gymnasium's `tau`).
    pub update_interval: f64,
    /// All four state components start ~ U(initial_state_lower, initial_state_upper).
    pub initial_state_lower: f64,
    pub initial_state_upper: f64,
}

impl Default for CartPoleParams {
    fn default() -> Self {
        CartPoleParams {
            gravity: 9.8,
            masscart: 1.0,
            masspole: 0.1,
            pole_length: 0.5,
            force_magnifier: 10.0,
            update_interval: 0.02,
            initial_state_lower: -0.05,
            initial_state_upper: 0.05,
        }
    }
}

context_features!(CartPoleParams, "cartpole", {
    gravity: "gravity",
    masscart: "masscart",
    masspole: "masspole",
    pole_length: "pole_length" | "length",
    force_magnifier: "force_magnifier" | "force_mag",
    update_interval: "update_interval" | "tau",
    initial_state_lower: "initial_state_lower",
    initial_state_upper: "initial_state_upper",
});

impl CartPoleParams {
    /// `masspole + masscart`, recomputed from the context (carl-bench 1.1.1 forgets to).
    #[inline]
    pub fn total_mass(&self) -> f64 {
        self.masspole + self.masscart
    }
    /// `masspole * length`, recomputed from the context.
    #[inline]
    pub fn polemass_length(&self) -> f64 {
        self.masspole * self.pole_length
    }
}

/// What one step needs from the context, derived as Gymnasium derives it (`total_mass`,
/// `polemass_length` recomputed from the masses and length: carl-bench 1.1.1 forgets to).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CartPoleConstants {
    pub gravity: f64,
    pub masspole: f64,
    pub pole_length: f64,
    pub force_mag: f64,
    pub tau: f64,
    pub total_mass: f64,
    pub polemass_length: f64,
}

impl From<&CartPoleParams> for CartPoleConstants {
    #[inline]
    fn from(p: &CartPoleParams) -> Self {
        CartPoleConstants {
            gravity: p.gravity,
            masspole: p.masspole,
            pole_length: p.pole_length,
            force_mag: p.force_magnifier,
            tau: p.update_interval,
            total_mass: p.total_mass(),
            polemass_length: p.polemass_length(),
        }
    }
}

/// One step of CartPole's dynamics (Gymnasium's Euler integrator, operation by operation):
/// the single definition both [`CartPole`] and `VecEnv`'s structure-of-arrays kernel call, so
/// they are bit-identical by construction.
#[inline(always)]
pub fn dynamics(k: &CartPoleConstants, [x, x_dot, theta, theta_dot]: [f64; 4], action: i64) -> [f64; 4] {
    let force = if action == 1 { k.force_mag } else { -k.force_mag };
    let costheta = theta.cos();
    let sintheta = theta.sin();
    let temp = (force + k.polemass_length * (theta_dot * theta_dot) * sintheta) / k.total_mass;
    let thetaacc = (k.gravity * sintheta - costheta * temp)
        / (k.pole_length * (4.0 / 3.0 - k.masspole * (costheta * costheta) / k.total_mass));
    let xacc = temp - k.polemass_length * thetaacc * costheta / k.total_mass;
    let tau = k.tau;
    [
        x + tau * x_dot,
        x_dot + tau * xacc,
        theta + tau * theta_dot,
        theta_dot + tau * thetaacc,
    ]
}

/// Gymnasium's termination test. Written as its four comparisons on purpose: with a NaN state
/// they are all false (not terminated), whereas `!range.contains(&x)` would report termination.
#[inline(always)]
#[allow(clippy::manual_range_contains)]
pub fn is_terminal([x, _, theta, _]: [f64; 4]) -> bool {
    x < -X_THRESHOLD || x > X_THRESHOLD || theta < -THETA_THRESHOLD_RADIANS || theta > THETA_THRESHOLD_RADIANS
}

/// The reset draws: every component `uniform(lower, upper)`, in order x, x_dot, theta, theta_dot.
#[inline]
pub fn initial_state(p: &CartPoleParams, rng: &mut EnvRng) -> [f64; 4] {
    let (lo, hi) = (p.initial_state_lower, p.initial_state_upper);
    [
        uniform(rng, lo, hi),
        uniform(rng, lo, hi),
        uniform(rng, lo, hi),
        uniform(rng, lo, hi),
    ]
}

/// `12 * 2 * math.pi / 360`
pub const THETA_THRESHOLD_RADIANS: f64 = 12.0 * 2.0 * std::f64::consts::PI / 360.0;
pub const X_THRESHOLD: f64 = 2.4;

#[derive(Debug, Clone)]
pub struct CartPole {
    params: CartPoleParams,
    state: [f64; 4],
    ready: bool,
    /// Gymnasium's `steps_beyond_terminated is not None`.
    terminated_before: bool,
    rng: EnvRng,
}

impl CartPole {
    pub fn new(params: CartPoleParams) -> Self {
        CartPole {
            params,
            state: [0.0; 4],
            ready: false,
            terminated_before: false,
            rng: EnvRng::default(),
        }
    }
    pub fn params(&self) -> &CartPoleParams {
        &self.params
    }
    /// Changes take effect at the next step (derived masses are recomputed every step).
    pub fn params_mut(&mut self) -> &mut CartPoleParams {
        &mut self.params
    }

    #[inline]
    fn write_obs(&self, obs: &mut [f32]) {
        for (o, s) in obs.iter_mut().zip(self.state) {
            *o = s as f32;
        }
    }
}

impl Default for CartPole {
    fn default() -> Self {
        CartPole::new(CartPoleParams::default())
    }
}

impl carl_env::runtime::Runtime for CartPole {
    /// The parameters are read at every step, so a schedule's new values act from the next one.
    fn set_features(&mut self, values: &[(String, f64)]) -> Option<Result<(), carl_env::context::MakeError>> {
        Some(carl_env::context::apply("cartpole", values, |name, x| {
            self.params.set(name, x)
        }))
    }
}

impl Env for CartPole {
    fn id(&self) -> &'static str {
        ID
    }
    fn obs_dim(&self) -> usize {
        4
    }
    fn state_dim(&self) -> usize {
        4
    }
    fn observation_space(&self) -> Space {
        let high = [
            (X_THRESHOLD * 2.0) as f32,
            f32::INFINITY,
            (THETA_THRESHOLD_RADIANS * 2.0) as f32,
            f32::INFINITY,
        ];
        Space::Box {
            low: high.iter().map(|h| -h).collect(),
            high: high.to_vec(),
            shape: vec![4],
            dtype: DType::Float32,
        }
    }
    fn action_space(&self) -> Space {
        Space::Discrete { n: 2, start: 0 }
    }

    fn reset_into(&mut self, seed: Option<u64>, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(ID, obs, 4)?;
        if let Some(seed) = seed {
            self.rng = EnvRng::from_seed(seed);
        }
        self.state = initial_state(&self.params, &mut self.rng);
        self.ready = true;
        self.terminated_before = false;
        self.write_obs(obs);
        Ok(())
    }

    #[inline]
    fn step_into(&mut self, action: &Action, obs: &mut [f32]) -> Result<StepOutcome, EnvError> {
        let a = discrete_action(ID, action, 2)?;
        check_obs_len(ID, obs, 4)?;
        if !self.ready {
            return Err(EnvError::NeedsReset { env: ID });
        }
        self.state = dynamics(&CartPoleConstants::from(&self.params), self.state, a);
        let terminated = is_terminal(self.state);
        // Gymnasium: 1 per step including the terminating one, 0 for steps taken after that.
        let reward = if !terminated {
            1.0
        } else if !self.terminated_before {
            self.terminated_before = true;
            1.0
        } else {
            0.0
        };
        self.write_obs(obs);
        Ok(StepOutcome {
            reward,
            terminated,
            truncated: false,
        })
    }

    fn observe_into(&self, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(ID, obs, 4)?;
        self.write_obs(obs);
        Ok(())
    }
    /// [`FAILED`] once the state is terminal (the pole fell or the cart left the track).
    fn outcome(&self) -> Option<&'static str> {
        (self.ready && is_terminal(self.state)).then_some(FAILED)
    }
    fn state(&self) -> Vec<f64> {
        self.state.to_vec()
    }
    fn set_state(&mut self, state: &[f64]) -> Result<(), EnvError> {
        self.state = check_state::<4>(ID, state)?;
        self.ready = true;
        self.terminated_before = false;
        Ok(())
    }
}
