//! Contexts that change within an episode: declared schedules of dynamics features.
//!
//! A [`Schedule`] moves one feature during every episode, starting from the episode's own value
//! (the instance's, the draw's or the fixed context's, called the base `b`), as a function of the
//! step `t` (0 at reset; the value of step `t` acts on the transition from step `t` to `t + 1`):
//!
//! | kind | value at step t |
//! |---|---|
//! | `step` `{at, to}` | `b` before step `at`, `to` from step `at` on |
//! | `linear` `{to, over}` | `b + (to − b) · min(t / over, 1)`: reaches `to` after `over` steps, then holds |
//! | `sine` `{amplitude, period, phase = 0}` | `b + amplitude · sin(2π t / period + phase)` |
//! | `random_walk` `{std, low, high}` | `b` at reset, then `+ std · N(0, 1)` per step, reflected into `[low, high]` |
//!
//! Every value a schedule can take is inside the feature's bounds: checked when the environment is
//! built for each instance (sets and fixed contexts) and at each reset for a distribution's draw,
//! so a schedule that would leave them is an error naming the feature, the instance and the value,
//! never a clipped or silently wrong context. The random walk draws from its own stream
//! (`carl-spec/contextual/schedule`, [`SCHEDULE_STREAM`]), re-created from the seed of every seeded
//! reset like the wrapper's other streams, so the same seed gives the same walk.
//!
//! Only features that act on the dynamics can be scheduled, and only on runtimes that take new
//! values mid-episode ([`Runtime::set_features`](carl_env::runtime::Runtime::set_features)); the
//! wrapper reports the current value as `context.<feature>` in the info and, when the feature is
//! visible, in the observation.

use serde::Deserialize;

use crate::sampling::{Pcg64, dist::std_normal, stream_id};
use crate::spec::model::{EnvSpec, Feature};
use crate::spec::raw::Effect;

/// Stream name of the random walks' generator.
pub const SCHEDULE_STREAM: &str = "carl-spec/contextual/schedule";

/// How one feature moves within an episode (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Schedule {
    Step {
        at: u64,
        to: f64,
    },
    Linear {
        to: f64,
        over: u64,
    },
    Sine {
        amplitude: f64,
        period: f64,
        #[serde(default)]
        phase: f64,
    },
    RandomWalk {
        std: f64,
        low: f64,
        high: f64,
    },
}

impl Schedule {
    /// Parameters that cannot describe a schedule, whatever the feature.
    fn check_params(&self) -> Result<(), String> {
        let finite = |name: &str, x: f64| {
            if x.is_finite() {
                Ok(())
            } else {
                Err(format!("{name} = {x} is not finite"))
            }
        };
        match *self {
            Schedule::Step { to, .. } => finite("to", to),
            Schedule::Linear { to, over } => {
                finite("to", to)?;
                if over == 0 {
                    return Err("over = 0: a linear drift needs at least one step (use a step schedule at 0)".into());
                }
                Ok(())
            }
            Schedule::Sine {
                amplitude,
                period,
                phase,
            } => {
                finite("amplitude", amplitude)?;
                finite("phase", phase)?;
                if !(period.is_finite() && period > 0.0) {
                    return Err(format!("period = {period} must be finite and > 0 (in steps)"));
                }
                Ok(())
            }
            Schedule::RandomWalk { std, low, high } => {
                if !(std.is_finite() && std > 0.0) {
                    return Err(format!("std = {std} must be finite and > 0"));
                }
                if !(low.is_finite() && high.is_finite() && low < high) {
                    return Err(format!("the walk's range [{low}, {high}] needs finite low < high"));
                }
                Ok(())
            }
        }
    }

    /// The smallest and largest value an episode starting at `base` can take.
    fn range(&self, base: f64) -> (f64, f64) {
        match *self {
            Schedule::Step { to, .. } | Schedule::Linear { to, .. } => (base.min(to), base.max(to)),
            Schedule::Sine { amplitude, .. } => (base - amplitude.abs(), base + amplitude.abs()),
            Schedule::RandomWalk { low, high, .. } => (low.min(base), high.max(base)),
        }
    }

    /// The value at step `t >= 1`, given the previous one (for the walk).
    fn value(&self, base: f64, t: u64, previous: f64, rng: &mut Pcg64) -> f64 {
        match *self {
            Schedule::Step { at, to } => {
                if t >= at {
                    to
                } else {
                    base
                }
            }
            Schedule::Linear { to, over } => base + (to - base) * (t.min(over) as f64 / over as f64),
            Schedule::Sine {
                amplitude,
                period,
                phase,
            } => base + amplitude * (std::f64::consts::TAU * t as f64 / period + phase).sin(),
            Schedule::RandomWalk { std, low, high } => reflect(previous + std * std_normal(rng), low, high),
        }
    }

    /// The value at reset.
    fn start(&self, base: f64) -> f64 {
        match *self {
            Schedule::Step { at: 0, to } => to,
            Schedule::Sine { amplitude, phase, .. } => base + amplitude * phase.sin(),
            _ => base,
        }
    }
}

/// `x` folded back into `[low, high]` at its edges (a walk that reflects).
fn reflect(x: f64, low: f64, high: f64) -> f64 {
    let w = high - low;
    let mut y = (x - low).rem_euclid(2.0 * w);
    if y > w {
        y = 2.0 * w - y;
    }
    low + y
}

/// The schedules of one contextual environment and their state in the current episode.
#[derive(Debug, Clone)]
pub struct Schedules {
    /// (canonical feature name, its index in the context, the schedule)
    items: Vec<(String, usize, Schedule)>,
    bounds: Vec<(Option<f64>, Option<f64>)>,
    base: Vec<f64>,
    current: Vec<f64>,
    t: u64,
    rng: Pcg64,
    /// Reused for the runtime's `set_features`.
    values: Vec<(String, f64)>,
}

impl Schedules {
    /// Resolve `schedules` (feature name or alias -> schedule) against the spec: every feature
    /// known, acting on the dynamics and scheduled once, every schedule's parameters valid.
    pub fn new(spec: &EnvSpec, schedules: &[(String, Schedule)]) -> Result<Self, String> {
        let mut items: Vec<(String, usize, Schedule)> = Vec::new();
        let mut bounds = Vec::new();
        for (name, schedule) in schedules {
            let f: &Feature = spec.feature(name).ok_or_else(|| {
                let hint = crate::suggest::did_you_mean(name, spec.feature_names())
                    .map(|s| format!(" (did you mean \"{s}\"?)"))
                    .unwrap_or_default();
                format!("{} has no context feature \"{name}\" to schedule{hint}", spec.id)
            })?;
            if !f.is_continuous() {
                return Err(format!(
                    "{}: only float features can be scheduled; \"{}\" is not one",
                    spec.id, f.name
                ));
            }
            if !f.affects(Effect::Dynamics) {
                return Err(format!(
                    "{}: \"{}\" does not act on the dynamics (it affects {}), so it cannot change within an episode",
                    spec.id,
                    f.name,
                    f.affects
                        .iter()
                        .map(|e| format!("{e:?}").to_lowercase())
                        .collect::<Vec<_>>()
                        .join(", ")
                ));
            }
            if items.iter().any(|(n, ..)| *n == f.name) {
                return Err(format!("{}: \"{}\" is scheduled twice", spec.id, f.name));
            }
            schedule
                .check_params()
                .map_err(|e| format!("{}: schedule of \"{}\": {e}", spec.id, f.name))?;
            if let Schedule::RandomWalk { low, high, .. } = schedule
                && !(f.in_bounds(*low) && f.in_bounds(*high))
            {
                return Err(format!(
                    "{}: the random walk of \"{}\" ranges over [{low}, {high}], outside the feature's bounds",
                    spec.id, f.name
                ));
            }
            let index = spec
                .features
                .iter()
                .position(|g| g.name == f.name)
                .expect("a spec feature");
            items.push((f.name.clone(), index, *schedule));
            bounds.push((f.bounds[0], f.bounds[1]));
        }
        let n = items.len();
        Ok(Schedules {
            values: items.iter().map(|(name, ..)| (name.clone(), 0.0)).collect(),
            items,
            bounds,
            base: vec![0.0; n],
            current: vec![0.0; n],
            t: 0,
            rng: Pcg64::new(super::rng::DEFAULT_SEED, stream_id(SCHEDULE_STREAM)),
        })
    }

    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// The scheduled features' positions in the context (spec order), with their current values.
    pub fn current(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.items.iter().map(|(_, i, _)| *i).zip(self.current.iter().copied())
    }

    /// Every value an episode from `context` (every feature's value, spec order) can reach lies
    /// in the features' bounds; else the reason, naming `who`.
    pub fn check_reach(&self, context: &[(String, f64)], who: &str) -> Result<(), String> {
        for ((name, index, schedule), (lo, hi)) in self.items.iter().zip(&self.bounds) {
            let base = context[*index].1;
            let (a, b) = schedule.range(base);
            let outside = |x: f64| lo.is_some_and(|l| x < l) || hi.is_some_and(|h| x > h);
            if outside(a) || outside(b) {
                let fmt = |x: Option<f64>| x.map_or("unbounded".to_string(), |x| x.to_string());
                return Err(format!(
                    "the schedule of \"{name}\" from {base} ({who}) reaches [{a}, {b}], outside the bounds [{}, {}]",
                    fmt(*lo),
                    fmt(*hi)
                ));
            }
        }
        Ok(())
    }

    /// Re-create the walk's stream from a reset's seed.
    pub fn seed(&mut self, seed: u64) {
        self.rng = Pcg64::new(seed, stream_id(SCHEDULE_STREAM));
    }

    /// A new episode from `context`: the values at step 0, for the runtime's `set_features`.
    pub fn start(&mut self, context: &[(String, f64)]) -> &[(String, f64)] {
        self.t = 0;
        for (k, (_, index, schedule)) in self.items.iter().enumerate() {
            self.base[k] = context[*index].1;
            self.current[k] = schedule.start(self.base[k]);
            self.values[k].1 = self.current[k];
        }
        &self.values
    }

    /// After a step: the values for the next one, when some changed.
    pub fn advance(&mut self) -> Option<&[(String, f64)]> {
        self.t += 1;
        let mut changed = false;
        for (k, (_, _, schedule)) in self.items.iter().enumerate() {
            let x = schedule.value(self.base[k], self.t, self.current[k], &mut self.rng);
            changed |= x.to_bits() != self.current[k].to_bits();
            self.current[k] = x;
            self.values[k].1 = x;
        }
        changed.then_some(&self.values[..])
    }
}

/// Parse `{"feature": {"kind": ..., ...}, ...}` (the CLI's `--schedule` and Python's `schedules=`).
pub fn parse_schedules(json: &str) -> Result<Vec<(String, Schedule)>, String> {
    let map: serde_json::Map<String, serde_json::Value> =
        serde_json::from_str(json).map_err(|e| format!("schedules: {e} (write {{\"feature\": {{\"kind\": ...}}}})"))?;
    map.into_iter()
        .map(|(name, v)| {
            serde_json::from_value(v)
                .map(|s| (name.clone(), s))
                .map_err(|e| format!("schedule of \"{name}\": {e} (kinds: step {{at, to}}, linear {{to, over}}, sine {{amplitude, period, phase}}, random_walk {{std, low, high}})"))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_follow_the_declared_shapes() {
        let mut rng = Pcg64::new(0, 1);
        let s = Schedule::Step { at: 3, to: 5.0 };
        assert_eq!(
            (
                s.start(1.0),
                s.value(1.0, 2, 1.0, &mut rng),
                s.value(1.0, 3, 1.0, &mut rng)
            ),
            (1.0, 1.0, 5.0)
        );
        let l = Schedule::Linear { to: 3.0, over: 4 };
        let v: Vec<f64> = (1..=6).map(|t| l.value(1.0, t, 0.0, &mut rng)).collect();
        assert_eq!(v, [1.5, 2.0, 2.5, 3.0, 3.0, 3.0]);
        let w = Schedule::Sine {
            amplitude: 2.0,
            period: 4.0,
            phase: 0.0,
        };
        assert!((w.value(10.0, 1, 0.0, &mut rng) - 12.0).abs() < 1e-12);
        assert!((w.value(10.0, 3, 0.0, &mut rng) - 8.0).abs() < 1e-12);
        assert_eq!(w.range(10.0), (8.0, 12.0));
    }

    #[test]
    fn the_random_walk_stays_in_its_range_and_reflects() {
        assert_eq!(reflect(1.5, 0.0, 1.0), 0.5);
        assert_eq!(reflect(-0.25, 0.0, 1.0), 0.25);
        assert_eq!(reflect(2.25, 0.0, 1.0), 0.25);
        let r = Schedule::RandomWalk {
            std: 0.7,
            low: 0.0,
            high: 1.0,
        };
        let mut rng = Pcg64::new(3, 4);
        let mut x = 0.5;
        for t in 1..10_000 {
            x = r.value(0.5, t, x, &mut rng);
            assert!((0.0..=1.0).contains(&x), "{x}");
        }
    }

    #[test]
    fn bad_parameters_are_refused() {
        for json in [
            r#"{"g": {"kind": "linear", "to": 1, "over": 0}}"#,
            r#"{"g": {"kind": "sine", "amplitude": 1, "period": 0}}"#,
            r#"{"g": {"kind": "random_walk", "std": 1, "low": 2, "high": 1}}"#,
        ] {
            let parsed = parse_schedules(json).unwrap();
            assert!(parsed[0].1.check_params().is_err(), "{json}");
        }
        assert!(
            parse_schedules(r#"{"g": {"kind": "wobble"}}"#)
                .unwrap_err()
                .contains("kinds: step")
        );
        assert!(parse_schedules(r#"{"g": {"kind": "step", "at": 1}}"#).is_err());
        assert!(parse_schedules("[1]").is_err());
    }
}
