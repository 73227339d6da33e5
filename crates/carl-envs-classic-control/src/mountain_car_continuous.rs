//! MountainCarContinuous-v0 (Gymnasium 1.4 `Continuous_MountainCarEnv`).
//!
//! Gymnasium stores the state as a float32 array after every step (but as float64 after
//! `reset`), so from the second step on `position`/`velocity` are NumPy float32 scalars and
//! the arithmetic mixes float32, float64 and Python floats under NumPy 2's NEP 50 rules.
//! `Num` reproduces those rules so the trajectory is bit-identical.

use carl_env::api::{
    Action, DType, Env, EnvError, Space, StepOutcome, check_obs_len, check_state, context_features, scalar_action,
};
use carl_env::rng::{EnvRng, uniform};

const ID: &str = "mountain_car_continuous";
/// The outcome of an episode that terminated: the car reached the goal ([`Env::outcome`]).
pub const SOLVED: &str = "solved";
const MIN_ACTION: f64 = -1.0;
const MAX_ACTION: f64 = 1.0;

/// MountainCarContinuous context. `Default` is Gymnasium's `Continuous_MountainCarEnv`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MountainCarContinuousParams {
    pub min_position: f64,
    pub max_position: f64,
    pub max_speed: f64,
    pub goal_position: f64,
    pub goal_velocity: f64,
    pub power: f64,
    /// Initial position ~ U(min_position_start, max_position_start).
    pub min_position_start: f64,
    pub max_position_start: f64,
    /// Initial velocity ~ U(min_velocity_start, max_velocity_start) (Gymnasium: exactly 0).
    pub min_velocity_start: f64,
    pub max_velocity_start: f64,
}

impl Default for MountainCarContinuousParams {
    fn default() -> Self {
        MountainCarContinuousParams {
            min_position: -1.2,
            max_position: 0.6,
            max_speed: 0.07,
            goal_position: 0.45,
            goal_velocity: 0.0,
            power: 0.0015,
            min_position_start: -0.6,
            max_position_start: -0.4,
            min_velocity_start: 0.0,
            max_velocity_start: 0.0,
        }
    }
}

context_features!(MountainCarContinuousParams, "mountain_car_continuous", {
    min_position: "min_position",
    max_position: "max_position",
    max_speed: "max_speed",
    goal_position: "goal_position",
    goal_velocity: "goal_velocity",
    power: "power",
    min_position_start: "min_position_start",
    max_position_start: "max_position_start",
    min_velocity_start: "min_velocity_start",
    max_velocity_start: "max_velocity_start",
});

/// A NumPy/Python scalar with its type, combined under NumPy 2 (NEP 50) promotion:
/// Python floats/ints are "weak" and take the other operand's NumPy type.
#[derive(Debug, Clone, Copy)]
enum Num {
    /// `np.float32`
    F32(f32),
    /// `np.float64`
    F64(f64),
    /// Python `float` (or `int`)
    Py(f64),
}

use Num::{F32, F64, Py};

impl Num {
    #[inline]
    fn f64(self) -> f64 {
        match self {
            F32(x) => x as f64,
            F64(x) | Py(x) => x,
        }
    }
    #[inline]
    fn to_f32(self) -> f32 {
        match self {
            F32(x) => x,
            F64(x) | Py(x) => x as f32,
        }
    }
    #[inline]
    fn binop(self, o: Num, f32op: fn(f32, f32) -> f32, f64op: fn(f64, f64) -> f64) -> Num {
        match (self, o) {
            (F32(a), F32(b)) => F32(f32op(a, b)),
            (F32(a), Py(b)) => F32(f32op(a, b as f32)),
            (Py(a), F32(b)) => F32(f32op(a as f32, b)),
            (Py(a), Py(b)) => Py(f64op(a, b)),
            (a, b) => F64(f64op(a.f64(), b.f64())),
        }
    }
    #[inline]
    fn add(self, o: Num) -> Num {
        self.binop(o, |a, b| a + b, |a, b| a + b)
    }
    #[inline]
    fn sub(self, o: Num) -> Num {
        self.binop(o, |a, b| a - b, |a, b| a - b)
    }
    #[inline]
    fn mul(self, o: Num) -> Num {
        self.binop(o, |a, b| a * b, |a, b| a * b)
    }
    /// Comparison operands in the promoted type (f32 when one side is float32 and the other
    /// float32 or weak).
    #[inline]
    fn cmp_pair(self, o: Num) -> (f64, f64) {
        match (self, o) {
            (F32(a), Py(b)) => (a as f64, (b as f32) as f64),
            (Py(a), F32(b)) => ((a as f32) as f64, b as f64),
            (a, b) => (a.f64(), b.f64()),
        }
    }
    #[inline]
    fn gt(self, o: Num) -> bool {
        let (a, b) = self.cmp_pair(o);
        a > b
    }
    #[inline]
    fn lt(self, o: Num) -> bool {
        let (a, b) = self.cmp_pair(o);
        a < b
    }
    #[inline]
    fn ge(self, o: Num) -> bool {
        let (a, b) = self.cmp_pair(o);
        a >= b
    }
    #[inline]
    fn eq(self, o: Num) -> bool {
        let (a, b) = self.cmp_pair(o);
        a == b
    }
}

#[derive(Debug, Clone)]
pub struct MountainCarContinuous {
    params: MountainCarContinuousParams,
    /// `[position, velocity]`
    state: [f64; 2],
    /// Whether Gymnasium would hold the state as float32 (true after any step).
    state_is_f32: bool,
    /// The last step terminated (the goal was reached): its outcome.
    solved: bool,
    ready: bool,
    rng: EnvRng,
}

impl MountainCarContinuous {
    pub fn new(params: MountainCarContinuousParams) -> Self {
        MountainCarContinuous {
            params,
            state: [0.0; 2],
            state_is_f32: false,
            solved: false,
            ready: false,
            rng: EnvRng::default(),
        }
    }
    pub fn params(&self) -> &MountainCarContinuousParams {
        &self.params
    }
    pub fn params_mut(&mut self) -> &mut MountainCarContinuousParams {
        &mut self.params
    }
    #[inline]
    fn write_obs(&self, obs: &mut [f32]) {
        obs[0] = self.state[0] as f32;
        obs[1] = self.state[1] as f32;
    }
}

impl Default for MountainCarContinuous {
    fn default() -> Self {
        MountainCarContinuous::new(MountainCarContinuousParams::default())
    }
}

impl carl_env::runtime::Runtime for MountainCarContinuous {
    /// The parameters are read at every step, so a schedule's new values act from the next one.
    fn set_features(&mut self, values: &[(String, f64)]) -> Option<Result<(), carl_env::context::MakeError>> {
        Some(carl_env::context::apply(
            "mountain_car_continuous",
            values,
            |name, x| self.params.set(name, x),
        ))
    }
}

impl Env for MountainCarContinuous {
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
        Space::Box {
            low: vec![MIN_ACTION as f32],
            high: vec![MAX_ACTION as f32],
            shape: vec![1],
            dtype: DType::Float32,
        }
    }

    fn reset_into(&mut self, seed: Option<u64>, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(ID, obs, 2)?;
        if let Some(seed) = seed {
            self.rng = EnvRng::from_seed(seed);
        }
        let p = &self.params;
        let pos = uniform(&mut self.rng, p.min_position_start, p.max_position_start);
        // Gymnasium's velocity is the constant 0; only draw when there is a range.
        let vel = if p.min_velocity_start == p.max_velocity_start {
            p.min_velocity_start
        } else {
            uniform(&mut self.rng, p.min_velocity_start, p.max_velocity_start)
        };
        self.state = [pos, vel];
        self.state_is_f32 = false;
        self.solved = false;
        self.ready = true;
        self.write_obs(obs);
        Ok(())
    }

    #[inline]
    fn step_into(&mut self, action: &Action, obs: &mut [f32]) -> Result<StepOutcome, EnvError> {
        let a = scalar_action(ID, action)?;
        check_obs_len(ID, obs, 2)?;
        if !self.ready {
            return Err(EnvError::NeedsReset { env: ID });
        }
        let p = &self.params;
        let (mut position, mut velocity) = if self.state_is_f32 {
            (F32(self.state[0] as f32), F32(self.state[1] as f32))
        } else {
            (F64(self.state[0]), F64(self.state[1]))
        };
        // force = min(max(action[0], min_action), max_action)  (Python builtins)
        let mut force = F32(a);
        if Py(MIN_ACTION).gt(force) {
            force = Py(MIN_ACTION);
        }
        if Py(MAX_ACTION).lt(force) {
            force = Py(MAX_ACTION);
        }
        // velocity += force * power - 0.0025 * math.cos(3 * position)
        let cos_term = Py(0.0025 * Py(3.0).mul(position).f64().cos());
        velocity = velocity.add(force.mul(Py(p.power)).sub(cos_term));
        if velocity.gt(Py(p.max_speed)) {
            velocity = Py(p.max_speed);
        }
        if velocity.lt(Py(-p.max_speed)) {
            velocity = Py(-p.max_speed);
        }
        position = position.add(velocity);
        if position.gt(Py(p.max_position)) {
            position = Py(p.max_position);
        }
        if position.lt(Py(p.min_position)) {
            position = Py(p.min_position);
        }
        if position.eq(Py(p.min_position)) && velocity.lt(Py(0.0)) {
            velocity = Py(0.0);
        }
        let terminated = position.ge(Py(p.goal_position)) && velocity.ge(Py(p.goal_velocity));
        let mut reward = 0.0;
        if terminated {
            reward = 100.0;
        }
        // math.pow(action[0], 2): the *unclipped* float32 action, promoted to double.
        reward -= (a as f64).powf(std::hint::black_box(2.0)) * 0.1;

        self.state = [position.to_f32() as f64, velocity.to_f32() as f64];
        self.state_is_f32 = true;
        self.solved = terminated;
        self.write_obs(obs);
        Ok(StepOutcome {
            reward,
            terminated,
            truncated: false,
        })
    }

    fn observe_into(&self, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(ID, obs, 2)?;
        self.write_obs(obs);
        Ok(())
    }
    /// [`SOLVED`] after the step that reached the goal.
    fn outcome(&self) -> Option<&'static str> {
        self.solved.then_some(SOLVED)
    }
    fn state(&self) -> Vec<f64> {
        self.state.to_vec()
    }
    /// Sets a float64 state, as `env.unwrapped.state = np.array([...])` (or a reset) does.
    fn set_state(&mut self, state: &[f64]) -> Result<(), EnvError> {
        self.state = check_state::<2>(ID, state)?;
        self.state_is_f32 = false;
        self.solved = false;
        self.ready = true;
        Ok(())
    }
}
