//! From spec + context to a running environment.
//!
//! A context is a plain value (`Context`: feature name → value). `make` checks every name and
//! value against the environment's spec (unknown names and out-of-bounds values are errors unless
//! explicitly allowed), writes them into the runtime's `Params`, and wraps the result in the spec's
//! episode limit. Nothing is shared between environments: each owns its `Params`.

use std::collections::BTreeMap;

use super::api::{Action, Env, EnvError, Space, StepOutcome, TimeLimit};
use super::box2d::{
    BipedalWalker, BipedalWalkerParams, LunarLander, LunarLanderParams, VehicleRacing, VehicleRacingParams,
};
use super::classic::{Acrobot, CartPole, MountainCar, MountainCarContinuous, Pendulum};
use crate::spec::model::{EnvSpec, FeatureType, Scalar, Value};
use crate::suggest::did_you_mean;

/// Feature values by name (canonical names or aliases); missing features take their defaults.
pub type Context = BTreeMap<String, Value>;

/// Environment ids that have a runtime in this crate.
pub const RUNTIMES: &[&str] = &[
    "cartpole",
    "pendulum",
    "mountain_car",
    "mountain_car_continuous",
    "acrobot",
    "lunar_lander",
    "bipedal_walker",
    "vehicle_racing",
    "ant",
    "half_cheetah",
    "ur5e",
    "fetch",
    "humanoid",
    "grasp",
];

pub fn has_runtime(id: &str) -> bool {
    RUNTIMES.contains(&id)
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MakeError {
    #[error("environment \"{0}\" has a spec but no runtime yet; runtimes exist for: {list}", list = RUNTIMES.join(", "))]
    NoRuntime(String),
    #[error("{env} has no context feature \"{name}\"{hint}; valid names: {valid}")]
    UnknownFeature {
        env: String,
        name: String,
        hint: String,
        valid: String,
    },
    #[error("{env}: {name} = {value} is outside its bounds {bounds} (use --allow-out-of-bounds to run it anyway)")]
    OutOfBounds {
        env: String,
        name: String,
        value: f64,
        bounds: String,
    },
    #[error("{env}: {name} needs a {expected} value, got {got}")]
    BadValue {
        env: String,
        name: String,
        expected: &'static str,
        got: String,
    },
    #[error("{env}: {name} = {value} is not finite")]
    NotFinite { env: String, name: String, value: f64 },
}

/// The runtime environments behind one type (static dispatch keeps stepping cheap): the
/// classic-control ones and, boxed because they own physics worlds and tracks, LunarLander,
/// BipedalWalker, VehicleRacing and the robots.
#[derive(Debug, Clone)]
pub enum ClassicEnv {
    CartPole(CartPole),
    Pendulum(Pendulum),
    MountainCar(MountainCar),
    MountainCarContinuous(MountainCarContinuous),
    Acrobot(Acrobot),
    LunarLander(Box<LunarLander>),
    BipedalWalker(Box<BipedalWalker>),
    VehicleRacing(Box<VehicleRacing>),
    /// An articulated robot on rapier3d (see [`crate::envs::robots`]).
    Robot(Box<super::robots::Locomotion>),
    /// The UR5e reach task on rapier3d (see [`crate::envs::robots::reach`]).
    Reach(Box<super::robots::Reach>),
    /// Brax's fetch task on rapier3d (see [`crate::envs::robots::fetch`]).
    Fetch(Box<super::robots::Fetch>),
    /// Brax's grasp task on rapier3d (see [`crate::envs::robots::grasp`]).
    Grasp(Box<super::robots::Grasp>),
}

impl ClassicEnv {
    /// Whether one step costs microseconds or more (a physics world or a rendered picture)
    /// rather than nanoseconds: a [`VecEnv`](super::vec_env::VecEnv) then shares work between
    /// threads environment by environment instead of in blocks of 16.
    pub fn is_heavy(&self) -> bool {
        !matches!(
            self,
            ClassicEnv::CartPole(_)
                | ClassicEnv::Pendulum(_)
                | ClassicEnv::MountainCar(_)
                | ClassicEnv::MountainCarContinuous(_)
                | ClassicEnv::Acrobot(_)
        )
    }

    /// The LunarLander inside, to set its options (continuous actions, crash penalty).
    pub fn as_lunar_lander_mut(&mut self) -> Option<&mut LunarLander> {
        match self {
            ClassicEnv::LunarLander(l) => Some(l),
            _ => None,
        }
    }

    /// The BipedalWalker inside, to set its options (hardcore terrain, solver, lidar drawing).
    pub fn as_bipedal_walker_mut(&mut self) -> Option<&mut BipedalWalker> {
        match self {
            ClassicEnv::BipedalWalker(w) => Some(w),
            _ => None,
        }
    }

    /// The VehicleRacing inside, to set its options (discrete actions).
    pub fn as_vehicle_racing_mut(&mut self) -> Option<&mut VehicleRacing> {
        match self {
            ClassicEnv::VehicleRacing(v) => Some(v),
            _ => None,
        }
    }
}

macro_rules! dispatch {
    ($self:expr, $e:ident => $body:expr) => {
        match $self {
            ClassicEnv::CartPole($e) => $body,
            ClassicEnv::Pendulum($e) => $body,
            ClassicEnv::MountainCar($e) => $body,
            ClassicEnv::MountainCarContinuous($e) => $body,
            ClassicEnv::Acrobot($e) => $body,
            ClassicEnv::LunarLander($e) => $body,
            ClassicEnv::BipedalWalker($e) => $body,
            ClassicEnv::VehicleRacing($e) => $body,
            ClassicEnv::Robot($e) => $body,
            ClassicEnv::Reach($e) => $body,
            ClassicEnv::Fetch($e) => $body,
            ClassicEnv::Grasp($e) => $body,
        }
    };
}

impl Env for ClassicEnv {
    fn id(&self) -> &'static str {
        dispatch!(self, e => e.id())
    }
    fn obs_dim(&self) -> usize {
        dispatch!(self, e => e.obs_dim())
    }
    fn state_dim(&self) -> usize {
        dispatch!(self, e => e.state_dim())
    }
    fn observation_space(&self) -> Space {
        dispatch!(self, e => e.observation_space())
    }
    fn action_space(&self) -> Space {
        dispatch!(self, e => e.action_space())
    }
    #[inline]
    fn reset_into(&mut self, seed: Option<u64>, obs: &mut [f32]) -> Result<(), EnvError> {
        dispatch!(self, e => e.reset_into(seed, obs))
    }
    #[inline]
    fn step_into(&mut self, action: &Action, obs: &mut [f32]) -> Result<StepOutcome, EnvError> {
        dispatch!(self, e => e.step_into(action, obs))
    }
    fn observe_into(&self, obs: &mut [f32]) -> Result<(), EnvError> {
        dispatch!(self, e => e.observe_into(obs))
    }
    fn state(&self) -> Vec<f64> {
        dispatch!(self, e => e.state())
    }
    fn set_state(&mut self, state: &[f64]) -> Result<(), EnvError> {
        dispatch!(self, e => e.set_state(state))
    }
    fn info(&self) -> super::api::Info {
        dispatch!(self, e => e.info())
    }
    fn render(&self) -> Option<crate::pixels::Frame> {
        dispatch!(self, e => e.render())
    }
}

/// A runtime environment as `make` returns it: the spec's episode limit around the dynamics.
pub type SpecEnv = TimeLimit<ClassicEnv>;

/// Options for [`make_with`].
#[derive(Debug, Clone, Copy, Default)]
pub struct MakeOptions {
    /// Accept values outside the spec's bounds (deliberate out-of-distribution runs).
    pub allow_out_of_bounds: bool,
}

/// Build `spec`'s environment under `context` (bounds enforced).
pub fn make(spec: &EnvSpec, context: &Context) -> Result<SpecEnv, MakeError> {
    make_with(spec, context, MakeOptions::default())
}

pub fn make_with(spec: &EnvSpec, context: &Context, opts: MakeOptions) -> Result<SpecEnv, MakeError> {
    // "No runtime" first: a spec-only environment may have features (strings, lists) that no
    // runtime could take, and the missing runtime is what the user needs to hear.
    if !has_runtime(&spec.id) {
        return Err(MakeError::NoRuntime(spec.id.clone()));
    }
    let values = resolve_context(spec, context, opts)?;
    let env = build(&spec.id, &values)?;
    Ok(TimeLimit::new(env, spec.max_episode_steps))
}

/// Check a context against the spec and return every feature's numeric value (defaults filled in),
/// keyed by canonical name, in spec order.
pub fn resolve_context(spec: &EnvSpec, context: &Context, opts: MakeOptions) -> Result<Vec<(String, f64)>, MakeError> {
    let env = spec.id.clone();
    for name in context.keys() {
        if spec.feature(name).is_none() {
            let names = spec.feature_names();
            let hint = did_you_mean(name, names.clone())
                .map(|s| format!(" (did you mean \"{s}\"?)"))
                .unwrap_or_default();
            return Err(MakeError::UnknownFeature {
                env,
                name: name.clone(),
                hint,
                valid: names.collect::<Vec<_>>().join(", "),
            });
        }
    }
    let mut out = Vec::with_capacity(spec.features.len());
    for f in &spec.features {
        let given = context.iter().find(|(k, _)| f.matches_name(k)).map(|(_, v)| v);
        let value = given.or(f.default.as_ref());
        let Some(value) = value else { continue };
        let x = match (f.kind, value) {
            (FeatureType::Float | FeatureType::Int, Value::Number(x)) => *x,
            (FeatureType::Bool, Value::Bool(b)) => f64::from(u8::from(*b)),
            // A categorical feature takes one of its numeric choices, or the label of one.
            (FeatureType::Categorical, Value::Number(x)) => *x,
            (FeatureType::Categorical, Value::String(label)) => {
                let idx = f
                    .choice_labels
                    .as_ref()
                    .and_then(|labels| labels.iter().position(|l| l == label));
                match idx.and_then(|i| f.choices.as_ref()?.get(i)) {
                    Some(Scalar::Number(x)) => *x,
                    _ => {
                        return Err(MakeError::BadValue {
                            env,
                            name: f.name.clone(),
                            expected: "choice or choice label",
                            got: label.clone(),
                        });
                    }
                }
            }
            (_, v) => {
                return Err(MakeError::BadValue {
                    env,
                    name: f.name.clone(),
                    expected: "numeric",
                    got: crate::validate::value_text(v),
                });
            }
        };
        if !x.is_finite() {
            return Err(MakeError::NotFinite {
                env,
                name: f.name.clone(),
                value: x,
            });
        }
        if f.kind == FeatureType::Int && x.fract() != 0.0 {
            return Err(MakeError::BadValue {
                env,
                name: f.name.clone(),
                expected: "integer",
                got: x.to_string(),
            });
        }
        if f.kind == FeatureType::Categorical && given.is_some() && !opts.allow_out_of_bounds {
            let choices = f.choices.as_deref().unwrap_or_default();
            let numeric = choices.iter().any(|c| matches!(c, Scalar::Number(_)));
            if numeric && !choices.iter().any(|c| matches!(c, Scalar::Number(v) if *v == x)) {
                return Err(MakeError::OutOfBounds {
                    env,
                    name: f.name.clone(),
                    value: x,
                    bounds: format!(
                        "choices {}",
                        crate::validate::value_text(&Value::List(
                            choices
                                .iter()
                                .filter_map(|c| match c {
                                    Scalar::Number(v) => Some(*v),
                                    _ => None,
                                })
                                .collect()
                        ))
                    ),
                });
            }
        }
        if given.is_some() && !opts.allow_out_of_bounds && !f.in_bounds(x) {
            let b = |v: Option<f64>, inf: &str| v.map_or(inf.to_string(), |v| v.to_string());
            return Err(MakeError::OutOfBounds {
                env,
                name: f.name.clone(),
                value: x,
                bounds: format!("[{}, {}]", b(f.bounds[0], "-inf"), b(f.bounds[1], "inf")),
            });
        }
        out.push((f.name.clone(), x));
    }
    Ok(out)
}

/// Write every `(feature, value)` into a runtime's parameters with `set`; a name the runtime does
/// not know means the spec and the runtime disagree.
fn apply(
    id: &str,
    values: &[(String, f64)],
    mut set: impl FnMut(&str, f64) -> Result<(), super::api::UnknownFeature>,
) -> Result<(), MakeError> {
    for (name, x) in values {
        set(name, *x).map_err(|e| MakeError::UnknownFeature {
            env: id.to_string(),
            name: name.clone(),
            hint: " (the spec names a feature the runtime does not know)".into(),
            valid: e.known,
        })?;
    }
    Ok(())
}

fn build(id: &str, values: &[(String, f64)]) -> Result<ClassicEnv, MakeError> {
    macro_rules! with_params {
        ($params:ty, $env:ident, $variant:ident) => {{
            let mut p = <$params>::default();
            apply(id, values, |name, x| p.set(name, x))?;
            ClassicEnv::$variant($env::new(p))
        }};
    }
    use super::classic::*;
    Ok(match id {
        "cartpole" => with_params!(CartPoleParams, CartPole, CartPole),
        "pendulum" => with_params!(PendulumParams, Pendulum, Pendulum),
        "mountain_car" => with_params!(MountainCarParams, MountainCar, MountainCar),
        "mountain_car_continuous" => with_params!(
            MountainCarContinuousParams,
            MountainCarContinuous,
            MountainCarContinuous
        ),
        "acrobot" => with_params!(AcrobotParams, Acrobot, Acrobot),
        "lunar_lander" => {
            let mut p = LunarLanderParams::default();
            apply(id, values, |name, x| p.set(name, x))?;
            ClassicEnv::LunarLander(Box::new(LunarLander::new(p)))
        }
        "bipedal_walker" => {
            let mut p = BipedalWalkerParams::default();
            apply(id, values, |name, x| p.set(name, x))?;
            ClassicEnv::BipedalWalker(Box::new(BipedalWalker::new(p)))
        }
        "vehicle_racing" => {
            let mut p = VehicleRacingParams::default();
            apply(id, values, |name, x| p.set(name, x))?;
            let env = VehicleRacing::new(p).map_err(|message| MakeError::BadValue {
                env: id.to_string(),
                name: "VEHICLE".into(),
                expected: "vehicle index in 0..=28",
                got: message,
            })?;
            ClassicEnv::VehicleRacing(Box::new(env))
        }
        other => {
            let Some(mut p) = super::robots::blank_params(other) else {
                return Err(MakeError::NoRuntime(other.to_string()));
            };
            apply(id, values, |name, x| p.set(name, x))?;
            if other == "ur5e" {
                let env = super::robots::make_reach(p).ok_or_else(|| MakeError::NoRuntime(other.to_string()))?;
                ClassicEnv::Reach(Box::new(env))
            } else if other == "fetch" {
                let env = super::robots::make_fetch(p).ok_or_else(|| MakeError::NoRuntime(other.to_string()))?;
                ClassicEnv::Fetch(Box::new(env))
            } else if other == "grasp" {
                let env = super::robots::make_grasp(p).ok_or_else(|| MakeError::NoRuntime(other.to_string()))?;
                ClassicEnv::Grasp(Box::new(env))
            } else {
                let env = super::robots::make_robot(other, p).ok_or_else(|| MakeError::NoRuntime(other.to_string()))?;
                ClassicEnv::Robot(Box::new(env))
            }
        }
    })
}
