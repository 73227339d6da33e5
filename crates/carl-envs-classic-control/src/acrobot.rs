//! Acrobot-v1 (Gymnasium 1.4 `AcrobotEnv`): RK4 over one `dt = 0.2` interval, `wrap`ped angles,
//! `bound`ed velocities, "book" dynamics by default.
//!
//! The float64 arithmetic follows Gymnasium's `_dsdt` / `rk4` term by term; every `x**2` on a
//! Python or NumPy scalar is the C library `pow(x, 2)` (see `py_sq`).

use std::f64::consts::PI;

use carl_env::api::{
    Action, DType, Env, EnvError, Space, StepOutcome, check_obs_len, check_state, context_features, discrete_action,
    py_sq,
};
use carl_env::rng::{EnvRng, uniform};

const ID: &str = "acrobot";
/// The outcome of an episode that terminated: the free end swung above the line
/// ([`Env::outcome`]).
pub const SOLVED: &str = "solved";
const AVAIL_TORQUE: [f64; 3] = [-1.0, 0.0, 1.0];
const G: f64 = 9.8;

/// Equations of motion variant (Gymnasium's `book_or_nips`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Dynamics {
    /// Sutton & Barto's book (Gymnasium default).
    #[default]
    Book,
    /// The NIPS 1996 paper (drops the `dtheta1**2` term).
    Nips,
}

/// Acrobot context. `Default` is Gymnasium's `AcrobotEnv`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AcrobotParams {
    pub link_length_1: f64,
    /// Only used by rendering in Gymnasium (termination is angle-based); kept for the context.
    pub link_length_2: f64,
    pub link_mass_1: f64,
    pub link_mass_2: f64,
    pub link_com_1: f64,
    pub link_com_2: f64,
    /// Moment of inertia of both links.
    pub link_moi: f64,
    pub max_velocity_1: f64,
    pub max_velocity_2: f64,
    /// Torque noise ~ U(-max, max) added when > 0 (drawn from the env's random stream).
    pub torque_noise_max: f64,
    /// All four state components start ~ U(initial_*_lower, initial_*_upper).
    pub initial_angle_lower: f64,
    pub initial_angle_upper: f64,
    pub initial_velocity_lower: f64,
    pub initial_velocity_upper: f64,
    /// Not a context feature: integration interval (Gymnasium `dt`, 0.2).
    pub dt: f64,
    /// Not a context feature: Gymnasium `book_or_nips`.
    pub dynamics: Dynamics,
}

impl Default for AcrobotParams {
    fn default() -> Self {
        AcrobotParams {
            link_length_1: 1.0,
            link_length_2: 1.0,
            link_mass_1: 1.0,
            link_mass_2: 1.0,
            link_com_1: 0.5,
            link_com_2: 0.5,
            link_moi: 1.0,
            max_velocity_1: 4.0 * PI,
            max_velocity_2: 9.0 * PI,
            torque_noise_max: 0.0,
            initial_angle_lower: -0.1,
            initial_angle_upper: 0.1,
            initial_velocity_lower: -0.1,
            initial_velocity_upper: 0.1,
            dt: 0.2,
            dynamics: Dynamics::Book,
        }
    }
}

context_features!(AcrobotParams, "acrobot", {
    link_length_1: "link_length_1" | "LINK_LENGTH_1",
    link_length_2: "link_length_2" | "LINK_LENGTH_2",
    link_mass_1: "link_mass_1" | "LINK_MASS_1",
    link_mass_2: "link_mass_2" | "LINK_MASS_2",
    link_com_1: "link_com_1" | "LINK_COM_POS_1",
    link_com_2: "link_com_2" | "LINK_COM_POS_2",
    link_moi: "link_moi" | "LINK_MOI",
    max_velocity_1: "max_velocity_1" | "MAX_VEL_1",
    max_velocity_2: "max_velocity_2" | "MAX_VEL_2",
    torque_noise_max: "torque_noise_max",
    initial_angle_lower: "initial_angle_lower" | "INITIAL_ANGLE_LOWER",
    initial_angle_upper: "initial_angle_upper" | "INITIAL_ANGLE_UPPER",
    initial_velocity_lower: "initial_velocity_lower" | "INITIAL_VELOCITY_LOWER",
    initial_velocity_upper: "initial_velocity_upper" | "INITIAL_VELOCITY_UPPER",
});

/// Gymnasium's `_dsdt` for `s = [theta1, theta2, dtheta1, dtheta2, torque]`.
#[inline]
fn dsdt(p: &AcrobotParams, s: &[f64; 5]) -> [f64; 5] {
    let (m1, m2, l1) = (p.link_mass_1, p.link_mass_2, p.link_length_1);
    let (lc1, lc2) = (p.link_com_1, p.link_com_2);
    let (i1, i2) = (p.link_moi, p.link_moi);
    let [theta1, theta2, dtheta1, dtheta2, a] = *s;
    let d1 = m1 * py_sq(lc1) + m2 * (py_sq(l1) + py_sq(lc2) + 2.0 * l1 * lc2 * theta2.cos()) + i1 + i2;
    let d2 = m2 * (py_sq(lc2) + l1 * lc2 * theta2.cos()) + i2;
    let phi2 = m2 * lc2 * G * (theta1 + theta2 - PI / 2.0).cos();
    let phi1 = -m2 * l1 * lc2 * py_sq(dtheta2) * theta2.sin() - 2.0 * m2 * l1 * lc2 * dtheta2 * dtheta1 * theta2.sin()
        + (m1 * lc1 + m2 * l1) * G * (theta1 - PI / 2.0).cos()
        + phi2;
    let ddtheta2 = match p.dynamics {
        Dynamics::Nips => (a + d2 / d1 * phi1 - phi2) / (m2 * py_sq(lc2) + i2 - py_sq(d2) / d1),
        Dynamics::Book => {
            (a + d2 / d1 * phi1 - m2 * l1 * lc2 * py_sq(dtheta1) * theta2.sin() - phi2)
                / (m2 * py_sq(lc2) + i2 - py_sq(d2) / d1)
        }
    };
    let ddtheta1 = -(d2 * ddtheta2 + phi1) / d1;
    [dtheta1, dtheta2, ddtheta1, ddtheta2, 0.0]
}

#[inline]
fn axpy(y: &[f64; 5], h: f64, k: &[f64; 5]) -> [f64; 5] {
    std::array::from_fn(|i| y[i] + h * k[i])
}

/// Gymnasium's `rk4(derivs, y0, [0, dt])`, returning the first four components.
#[inline]
fn rk4(p: &AcrobotParams, y0: &[f64; 5], dt_total: f64) -> [f64; 4] {
    let dt = dt_total - 0.0; // t[i + 1] - t[i]
    let dt2 = dt / 2.0;
    let k1 = dsdt(p, y0);
    let k2 = dsdt(p, &axpy(y0, dt2, &k1));
    let k3 = dsdt(p, &axpy(y0, dt2, &k2));
    let k4 = dsdt(p, &axpy(y0, dt, &k3));
    let h = dt / 6.0;
    std::array::from_fn(|i| y0[i] + h * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]))
}

/// Gymnasium's `wrap(x, m, M)` (repeated subtraction/addition of `M - m`). For inputs so far
/// out of range that the loop would effectively never end (Gymnasium would hang), a single
/// floor-modulo step is used first; this cannot happen from a finite bounded state.
#[inline]
pub fn wrap(mut x: f64, m: f64, big_m: f64) -> f64 {
    let diff = big_m - m;
    if !x.is_finite() {
        return x;
    }
    if (x - big_m) / diff > 1.0e6 || (m - x) / diff > 1.0e6 {
        x = m + crate::pendulum::py_mod(x - m, diff);
    }
    while x > big_m {
        x -= diff;
    }
    while x < m {
        x += diff;
    }
    x
}

/// Gymnasium's `bound(x, m, M)`: `min(max(x, m), M)` with Python builtins.
#[inline]
pub fn bound(x: f64, m: f64, big_m: f64) -> f64 {
    let y = if m > x { m } else { x };
    if big_m < y { big_m } else { y }
}

#[derive(Debug, Clone)]
pub struct Acrobot {
    params: AcrobotParams,
    /// `[theta1, theta2, dtheta1, dtheta2]`
    state: [f64; 4],
    ready: bool,
    rng: EnvRng,
}

impl Acrobot {
    pub fn new(params: AcrobotParams) -> Self {
        Acrobot {
            params,
            state: [0.0; 4],
            ready: false,
            rng: EnvRng::default(),
        }
    }
    pub fn params(&self) -> &AcrobotParams {
        &self.params
    }
    pub fn params_mut(&mut self) -> &mut AcrobotParams {
        &mut self.params
    }
    #[inline]
    fn write_obs(&self, obs: &mut [f32]) {
        let s = &self.state;
        obs[0] = s[0].cos() as f32;
        obs[1] = s[0].sin() as f32;
        obs[2] = s[1].cos() as f32;
        obs[3] = s[1].sin() as f32;
        obs[4] = s[2] as f32;
        obs[5] = s[3] as f32;
    }
}

impl Default for Acrobot {
    fn default() -> Self {
        Acrobot::new(AcrobotParams::default())
    }
}

impl carl_env::runtime::Runtime for Acrobot {
    /// The parameters are read at every step, so a schedule's new values act from the next one.
    fn set_features(&mut self, values: &[(String, f64)]) -> Option<Result<(), carl_env::context::MakeError>> {
        Some(carl_env::context::apply("acrobot", values, |name, x| {
            self.params.set(name, x)
        }))
    }
}

impl Env for Acrobot {
    fn id(&self) -> &'static str {
        ID
    }
    fn obs_dim(&self) -> usize {
        6
    }
    fn state_dim(&self) -> usize {
        4
    }
    fn observation_space(&self) -> Space {
        let (v1, v2) = (self.params.max_velocity_1 as f32, self.params.max_velocity_2 as f32);
        Space::Box {
            low: vec![-1.0, -1.0, -1.0, -1.0, -v1, -v2],
            high: vec![1.0, 1.0, 1.0, 1.0, v1, v2],
            shape: vec![6],
            dtype: DType::Float32,
        }
    }
    fn action_space(&self) -> Space {
        Space::Discrete { n: 3, start: 0 }
    }

    /// Like Gymnasium, the sampled initial state is rounded to float32.
    fn reset_into(&mut self, seed: Option<u64>, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(ID, obs, 6)?;
        if let Some(seed) = seed {
            self.rng = EnvRng::from_seed(seed);
        }
        let p = &self.params;
        let (al, au) = (p.initial_angle_lower, p.initial_angle_upper);
        let (vl, vu) = (p.initial_velocity_lower, p.initial_velocity_upper);
        let rng = &mut self.rng;
        self.state = [
            uniform(rng, al, au) as f32 as f64,
            uniform(rng, al, au) as f32 as f64,
            uniform(rng, vl, vu) as f32 as f64,
            uniform(rng, vl, vu) as f32 as f64,
        ];
        self.ready = true;
        self.write_obs(obs);
        Ok(())
    }

    #[inline]
    fn step_into(&mut self, action: &Action, obs: &mut [f32]) -> Result<StepOutcome, EnvError> {
        let a = discrete_action(ID, action, 3)?;
        check_obs_len(ID, obs, 6)?;
        if !self.ready {
            return Err(EnvError::NeedsReset { env: ID });
        }
        let p = self.params;
        let mut torque = AVAIL_TORQUE[a as usize];
        if p.torque_noise_max > 0.0 {
            torque += uniform(&mut self.rng, -p.torque_noise_max, p.torque_noise_max);
        }
        let s = self.state;
        let ns = rk4(&p, &[s[0], s[1], s[2], s[3], torque], p.dt);
        self.state = [
            wrap(ns[0], -PI, PI),
            wrap(ns[1], -PI, PI),
            bound(ns[2], -p.max_velocity_1, p.max_velocity_1),
            bound(ns[3], -p.max_velocity_2, p.max_velocity_2),
        ];
        let s = &self.state;
        let terminated = -s[0].cos() - (s[1] + s[0]).cos() > 1.0;
        self.write_obs(obs);
        Ok(StepOutcome {
            reward: if terminated { 0.0 } else { -1.0 },
            terminated,
            truncated: false,
        })
    }

    fn observe_into(&self, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(ID, obs, 6)?;
        self.write_obs(obs);
        Ok(())
    }
    /// [`SOLVED`] once the free end is above the line (the step's termination test).
    fn outcome(&self) -> Option<&'static str> {
        let s = &self.state;
        (self.ready && -s[0].cos() - (s[1] + s[0]).cos() > 1.0).then_some(SOLVED)
    }
    fn state(&self) -> Vec<f64> {
        self.state.to_vec()
    }
    fn set_state(&mut self, state: &[f64]) -> Result<(), EnvError> {
        self.state = check_state::<4>(ID, state)?;
        self.ready = true;
        Ok(())
    }
}
