//! What the audit feeds the environments: perturbed feature values, base states and actions.
//! Everything is derived deterministically from the spec, the default-context runtime and fixed
//! seeds, so two runs of the audit probe exactly the same transitions.

use crate::envs::rng::{EnvRng, uniform};
use crate::envs::runtime::AnyEnv;
use crate::envs::{Action, Env, EnvError, Space};
use crate::spec::model::{Feature, FeatureType, Scalar};

use super::AuditOptions;

/// Multiplicative perturbations of a non-zero default.
pub const FACTORS: [f64; 5] = [0.5, 0.9, 1.1, 1.5, 2.0];
/// Offsets from a zero default toward an unbounded side (signed by the side).
pub const ZERO_OFFSETS: [f64; 3] = [0.01, 0.1, 1.0];
/// Fractions of the way from a zero default to a finite, non-zero bound.
pub const BOUND_FRACTIONS: [f64; 3] = [0.1, 0.5, 1.0];

/// Other choices a categorical feature is audited with: at most this many, spread evenly over
/// its choice list (a categorical feature has no order, so "near the default" means nothing; the
/// spread covers different kinds of choices, e.g. a car, a bus and a tuk-tuk).
pub const MAX_CATEGORICAL_PROBES: usize = 4;

/// The numeric choices of a categorical feature, in spec order.
fn numeric_choices(f: &Feature) -> Vec<f64> {
    f.choices
        .iter()
        .flatten()
        .filter_map(|c| match c {
            Scalar::Number(x) if x.is_finite() => Some(*x),
            _ => None,
        })
        .collect()
}

/// Why a feature cannot be perturbed (the audit reports it and skips the feature).
pub fn unauditable_reason(f: &Feature) -> Option<String> {
    match f.kind {
        FeatureType::Float | FeatureType::Int | FeatureType::Bool => {}
        FeatureType::Categorical if !numeric_choices(f).is_empty() => {}
        FeatureType::Categorical => {
            return Some("categorical features without numeric choices are not perturbed by the audit".into());
        }
        FeatureType::ListInt => {
            return Some(format!("{:?} features are not perturbed by the audit", f.kind).to_lowercase());
        }
    }
    match f.default_f64() {
        Some(d) if d.is_finite() => None,
        Some(_) => Some("the default is not finite".into()),
        None => Some("no numeric default (computed default)".into()),
    }
}

/// The values the audit tries for `f`, sorted, all inside the bounds and different from the default:
///
/// * non-zero default `d`: `d·{0.5, 0.9, 1.1, 1.5, 2}`;
/// * zero default: per side, `{0.1, 0.5, 1}·bound` toward a finite non-zero bound, or
///   `±{0.01, 0.1, 1}` toward an unbounded side;
/// * both finite bounds themselves (effects that appear only at the extremes);
/// * `int` features rounded, `bool` features flipped;
/// * categorical features: up to [`MAX_CATEGORICAL_PROBES`] other choices, evenly spread.
pub fn perturbed_values(f: &Feature) -> Vec<f64> {
    if unauditable_reason(f).is_some() {
        return Vec::new();
    }
    let Some(d) = f.default_f64() else {
        return Vec::new();
    };
    if f.kind == FeatureType::Bool {
        return vec![if d == 0.0 { 1.0 } else { 0.0 }];
    }
    if f.kind == FeatureType::Categorical {
        let others: Vec<f64> = numeric_choices(f).into_iter().filter(|x| *x != d).collect();
        let n = others.len();
        let k = MAX_CATEGORICAL_PROBES.min(n);
        let mut out: Vec<f64> = (0..k)
            .map(|i| {
                others[if k > 1 {
                    (i * (n - 1) + (k - 1) / 2) / (k - 1)
                } else {
                    n - 1
                }]
            })
            .collect();
        out.dedup();
        return out;
    }
    let [lo, hi] = f.bounds;
    let mut v: Vec<f64> = Vec::new();
    if d != 0.0 {
        v.extend(FACTORS.iter().map(|k| d * k));
    } else {
        for (bound, sign) in [(lo, -1.0), (hi, 1.0)] {
            match bound {
                Some(b) if b != 0.0 && b.signum() == sign => v.extend(BOUND_FRACTIONS.iter().map(|k| k * b)),
                Some(_) => {} // the default sits on this bound
                None => v.extend(ZERO_OFFSETS.iter().map(|k| sign * k)),
            }
        }
    }
    v.extend(lo.iter().chain(hi.iter()).copied());
    let mut out: Vec<f64> = v
        .into_iter()
        .map(|x| {
            let x = lo.map_or(x, |l| x.max(l));
            let x = hi.map_or(x, |h| x.min(h));
            if f.kind == FeatureType::Int { x.round() } else { x }
        })
        .filter(|x| x.is_finite() && *x != d && f.in_bounds(*x))
        .collect();
    out.sort_by(f64::total_cmp);
    out.dedup();
    out
}

/// One step's action set: every discrete action; for a Box, a grid over `[low, high]`
/// (5 points for a 1-D box, 3 per dimension up to 3 dimensions, else centre and per-axis extremes).
pub fn probe_actions(space: &Space) -> Vec<Action> {
    match space {
        Space::Discrete { n, start } => (*start..*start + *n).map(Action::Discrete).collect(),
        Space::Box { low, high, .. } => {
            let lerp = |i: usize, t: f32| low[i] + (high[i] - low[i]) * t;
            let dims = low.len();
            if dims == 1 {
                return [0.0, 0.25, 0.5, 0.75, 1.0]
                    .iter()
                    .map(|t| Action::Continuous(vec![lerp(0, *t)]))
                    .collect();
            }
            if dims <= 3 {
                let mut out = vec![Vec::new()];
                for i in 0..dims {
                    out = out
                        .into_iter()
                        .flat_map(|p: Vec<f32>| {
                            [0.0, 0.5, 1.0].iter().map(move |t| {
                                let mut q = p.clone();
                                q.push(lerp(i, *t));
                                q
                            })
                        })
                        .collect();
                }
                return out.into_iter().map(Action::Continuous).collect();
            }
            let centre: Vec<f32> = (0..dims).map(|i| lerp(i, 0.5)).collect();
            let mut out = vec![centre.clone()];
            for i in 0..dims {
                for t in [0.0, 1.0] {
                    let mut q = centre.clone();
                    q[i] = lerp(i, t);
                    out.push(q);
                }
            }
            out.into_iter().map(Action::Continuous).collect()
        }
    }
}

/// A fixed-seed random action from `space` (used for the trajectories that produce base states).
fn random_action(space: &Space, rng: &mut EnvRng) -> Action {
    match space {
        Space::Discrete { n, start } => Action::Discrete(start + (rng.next_u64() % (*n).max(1) as u64) as i64),
        Space::Box { low, high, .. } => Action::Continuous(
            low.iter()
                .zip(high)
                .map(|(l, h)| uniform(rng, f64::from(*l), f64::from(*h)) as f32)
                .collect(),
        ),
    }
}

/// The base states every transition starts from, all produced under the *default* context:
///
/// 1. trajectory states: `reset(seed)` for `trajectory_seeds` seeds, then up to
///    `trajectory_steps` steps of fixed-seed random actions (stopping at termination);
/// 2. box states: `random_states` points drawn uniformly from a box over the internal state. Where
///    the state and observation have the same layout, a finite observation bound is used (this
///    reaches e.g. MountainCar's goal region); otherwise the trajectories' range per component,
///    widened threefold around its centre, and for angles at least their full circle.
pub fn base_states(env: &AnyEnv, opts: &AuditOptions) -> Result<Vec<Vec<f64>>, EnvError> {
    let mut env = env.clone();
    let space = env.action_space();
    let mut obs = vec![0.0f32; env.obs_dim()];
    let mut states = Vec::new();
    for seed in 0..opts.trajectory_seeds {
        env.reset_into(Some(seed), &mut obs)?;
        states.push(env.state());
        let mut rng = EnvRng::from_seed(0x5EED_0000 + seed);
        for _ in 0..opts.trajectory_steps {
            let a = random_action(&space, &mut rng);
            let out = env.step_into(&a, &mut obs)?;
            let s = env.state();
            if s.iter().all(|x| x.is_finite()) {
                states.push(s);
            }
            if out.terminated {
                break;
            }
        }
    }

    let dim = env.state_dim();
    let mut bounds: Vec<(f64, f64)> = (0..dim)
        .map(|i| {
            let (lo, hi) = states
                .iter()
                .map(|s| s[i])
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| (l.min(x), h.max(x)));
            let (mid, half) = if lo.is_finite() && hi.is_finite() {
                ((lo + hi) / 2.0, ((hi - lo) / 2.0).max(1e-3))
            } else {
                (0.0, 1.0)
            };
            (mid - 3.0 * half, mid + 3.0 * half)
        })
        .collect();
    if let Space::Box { low, high, .. } = env.observation_space()
        && low.len() == dim
    {
        for (i, b) in bounds.iter_mut().enumerate() {
            let (l, h) = (f64::from(low[i]), f64::from(high[i]));
            if l.is_finite() && h.is_finite() && l < h {
                *b = (l, h);
            }
        }
    }
    for (b, h) in bounds.iter_mut().zip(opts.state_hint) {
        *b = (b.0.min(h.0), b.1.max(h.1));
    }
    // Goal states: a reach task's trajectory states with the target just touching the end
    // effector, where the target radius decides the reward.
    let goal_states = env.goal_states(&states)?;
    let mut rng = EnvRng::from_seed(0xA0D1_7000);
    for _ in 0..opts.random_states {
        states.push(bounds.iter().map(|(l, h)| uniform(&mut rng, *l, *h)).collect());
    }
    states.extend(goal_states);
    Ok(states)
}
