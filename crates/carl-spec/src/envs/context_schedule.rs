//! Which context each reset uses, with which seed the runtime resets, and what the agent observes
//! of the visible features: the per-reset rules of [`ContextualEnv`](super::ContextualEnv) (see
//! its module docs for the derivation), in one place so that wrappers of environments carl-spec
//! does not ship (the Python binding's `ContextChooser` behind `carl_spec.wrap`) follow exactly
//! the same rules from the same seed.
//!
//! * [`ContextSchedule`]: the selection, context and env streams; at every reset it names the
//!   instance (sets) or the distribution seed (distributions) and the runtime's reset seed.
//! * [`ObservationNoise`]: the noise stream and the noisy measurement of the visible features.

use super::contextual_options::{
    CONTEXT_STREAM, ContextNoise, ContextualError, ENV_STREAM, NOISE_STREAM, NoiseRedraw, NoiseStd, SELECTION_STREAM,
    Selection,
};
use super::registry::Context;
use super::rng::DEFAULT_SEED;
use crate::instances::derive::{DeriveError, sample_distribution};
use crate::sampling::{Pcg64, dist::below, dist::std_normal, stream_id};
use crate::spec::model::{Distribution, EnvSpec};
use crate::suggest::did_you_mean;

/// Which instance of a set each reset uses (the rule of step 1 in the contextual module docs).
#[derive(Debug, Clone)]
pub struct InstanceSelector {
    selection: Selection,
    n: u64,
    rng: Pcg64,
    /// Round robin: the instance of the next unseeded reset.
    round_robin_next: u64,
}

impl InstanceSelector {
    /// A selector over `n >= 1` instances, its stream seeded with [`DEFAULT_SEED`].
    pub fn new(selection: Selection, n: usize) -> Self {
        InstanceSelector {
            selection,
            n: n.max(1) as u64,
            rng: Pcg64::new(DEFAULT_SEED, stream_id(SELECTION_STREAM)),
            round_robin_next: 0,
        }
    }

    /// Re-create the selection stream from `seed` (what `reset(Some(seed))` does first).
    pub fn seed(&mut self, seed: u64) {
        self.rng = Pcg64::new(seed, stream_id(SELECTION_STREAM));
    }

    /// The instance of this reset (`seed`: the reset's seed, already given to [`Self::seed`]).
    pub fn next(&mut self, seed: Option<u64>) -> usize {
        match self.selection {
            Selection::RoundRobin => {
                let i = seed.map_or(self.round_robin_next, |s| s % self.n);
                self.round_robin_next = (i + 1) % self.n;
                i as usize
            }
            Selection::Random => below(&mut self.rng, self.n) as usize,
            Selection::Static(i) => i,
        }
    }

    /// Continue from instance `i` (carl-bench's `context_id` setter): round robin takes `i + 1`
    /// next, static selection stays on `i`.
    pub fn continue_after(&mut self, i: usize) {
        self.round_robin_next = (i as u64 + 1) % self.n;
        if let Selection::Static(s) = &mut self.selection {
            *s = i;
        }
    }
}

/// Where a schedule's contexts come from (the data itself stays with the caller).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScheduleKind {
    /// A set of `n` instances chosen by `selection`.
    Set { n: usize, selection: Selection },
    /// One context for every episode.
    Fixed,
    /// A fresh draw of a distribution at every reset.
    Distribution,
}

/// The context of one reset.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pick {
    /// Instance `i` of the set.
    Instance(usize),
    /// The fixed context.
    Fixed,
    /// Draw the distribution with this seed ([`drawn_context`]).
    Draw { context_seed: u64 },
}

/// What one reset uses: its context, and the seed the runtime resets with (`None`: the runtime
/// continues its own stream, as Gymnasium's `reset()` after `reset(seed=s)`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ResetPlan {
    pub pick: Pick,
    pub runtime_seed: Option<u64>,
}

/// The selection, context and env streams of a contextual environment.
#[derive(Debug, Clone)]
pub struct ContextSchedule {
    kind: ScheduleKind,
    selector: Option<InstanceSelector>,
    context_rng: Pcg64,
    env_rng: Pcg64,
}

impl ContextSchedule {
    /// A schedule seeded with [`DEFAULT_SEED`] until the first seeded reset.
    pub fn new(kind: ScheduleKind) -> Self {
        let mut schedule = ContextSchedule {
            kind,
            selector: match kind {
                ScheduleKind::Set { n, selection } => Some(InstanceSelector::new(selection, n)),
                _ => None,
            },
            context_rng: Pcg64::new(DEFAULT_SEED, 0),
            env_rng: Pcg64::new(DEFAULT_SEED, 0),
        };
        schedule.seed(DEFAULT_SEED);
        schedule
    }

    pub fn kind(&self) -> ScheduleKind {
        self.kind
    }

    /// Re-create every stream from `seed`.
    pub fn seed(&mut self, seed: u64) {
        if let Some(s) = &mut self.selector {
            s.seed(seed);
        }
        self.context_rng = Pcg64::new(seed, stream_id(CONTEXT_STREAM));
        self.env_rng = Pcg64::new(seed, stream_id(ENV_STREAM));
    }

    /// The plan of a reset with `seed` (`Some`: the streams are re-created from it first).
    pub fn next(&mut self, seed: Option<u64>) -> ResetPlan {
        if let Some(s) = seed {
            self.seed(s);
        }
        let pick = match (&mut self.selector, self.kind) {
            (Some(selector), _) => Pick::Instance(selector.next(seed)),
            (None, ScheduleKind::Distribution) => Pick::Draw {
                context_seed: self.context_rng.next_u64(),
            },
            (None, _) => Pick::Fixed,
        };
        // A draw is taken at every reset, so the env stream's position depends only on the
        // number of resets since the seed, whatever the kind.
        let drawn = self.env_rng.next_u64();
        let runtime_seed = match (seed, pick) {
            (Some(s), _) => Some(s),
            (None, Pick::Fixed) => None,
            (None, _) => Some(drawn),
        };
        ResetPlan { pick, runtime_seed }
    }

    /// Continue after instance `i` (sets only; see [`InstanceSelector::continue_after`]).
    pub fn continue_after(&mut self, i: usize) {
        if let Some(s) = &mut self.selector {
            s.continue_after(i);
        }
    }
}

/// The context of one draw of distribution `name`: the sampled features over the spec's defaults.
pub fn drawn_context(
    spec: &EnvSpec,
    name: &str,
    dist: &Distribution,
    context_seed: u64,
) -> Result<Context, DeriveError> {
    let (names, rows) = sample_distribution(spec, name, dist, 1, context_seed)?;
    let mut ctx = spec.default_context();
    if let Some(row) = rows.into_iter().next() {
        ctx.extend(names.into_iter().zip(row));
    }
    Ok(ctx)
}

/// The noise on what the agent observes of the visible features (see [`ContextNoise`]): the
/// std per visible feature, when it is redrawn, and its own stream ([`NOISE_STREAM`]).
#[derive(Debug, Clone)]
pub struct ObservationNoise {
    /// Per visible feature: the std in the feature's unit (0: observed exactly).
    stds: Vec<f64>,
    redraw: NoiseRedraw,
    rng: Pcg64,
}

impl ObservationNoise {
    /// Check `noise` against the spec and the visible features (canonical names, in observation
    /// order): unknown or invisible features, relative noise on a zero default, negative or
    /// non-finite stds, stds above [`MAX_NOISE_STD`] and features listed twice are refused.
    pub fn new(spec: &EnvSpec, visible: &[String], noise: &ContextNoise) -> Result<Self, ContextualError> {
        Ok(ObservationNoise {
            stds: noise_stds(spec, visible, noise)?,
            redraw: noise.redraw,
            rng: Pcg64::new(DEFAULT_SEED, stream_id(NOISE_STREAM)),
        })
    }

    /// Re-create the noise stream from `seed` (at `reset(Some(seed))`).
    pub fn seed(&mut self, seed: u64) {
        self.rng = Pcg64::new(seed, stream_id(NOISE_STREAM));
    }

    /// Whether some feature is noisy, and when its noise is redrawn.
    pub fn redraw(&self) -> Option<NoiseRedraw> {
        self.stds.iter().any(|s| *s > 0.0).then_some(self.redraw)
    }

    /// Per visible feature, the std in the feature's unit (0: observed exactly).
    pub fn stds(&self) -> &[f64] {
        &self.stds
    }

    /// `observed = truth + std · N(0, 1)` per visible feature (fresh draws; exact where std is 0).
    /// Called at every reset.
    pub fn observe(&mut self, truth: &[f32], observed: &mut Vec<f32>) {
        observed.clear();
        for (x, std) in truth.iter().zip(&self.stds) {
            let noisy = if *std > 0.0 {
                (f64::from(*x) + std * std_normal(&mut self.rng)) as f32
            } else {
                *x
            };
            observed.push(noisy);
        }
    }

    /// After a step: redraw when the noise is per step (else `observed` keeps the episode's).
    pub fn after_step(&mut self, truth: &[f32], observed: &mut Vec<f32>) {
        if self.redraw == NoiseRedraw::Step && !self.stds.is_empty() {
            self.observe(truth, observed);
        }
    }
}

/// The largest noise std accepted (in the feature's unit, absolute or from a relative std):
/// `truth + std · N(0, 1)` is observed as float32, whose largest value is 3.4e38; a normal draw
/// beyond 40 σ does not happen, so 1e30 keeps every observed value finite.
pub const MAX_NOISE_STD: f64 = 1e30;

/// Per visible feature, the noise std in the feature's unit (0 where there is no noise).
fn noise_stds(spec: &EnvSpec, visible: &[String], noise: &ContextNoise) -> Result<Vec<f64>, ContextualError> {
    let mut stds = vec![0.0; visible.len()];
    for (name, std) in &noise.features {
        let err = |message: String| ContextualError::Noise {
            env: spec.id.clone(),
            name: name.clone(),
            message,
        };
        let f = spec.feature(name).ok_or_else(|| {
            let hint = did_you_mean(name, spec.feature_names())
                .map(|s| format!(" (did you mean \"{s}\"?)"))
                .unwrap_or_default();
            err(format!("no such context feature{hint}"))
        })?;
        let k = visible.iter().position(|v| *v == f.name).ok_or_else(|| {
            err("the feature is not observed; noise applies to visible features (make it visible first)".into())
        })?;
        let sd = match *std {
            NoiseStd::Absolute(sd) => sd,
            NoiseStd::Relative(r) => {
                let d = f.default_f64().unwrap_or(0.0).abs();
                if d == 0.0 && r > 0.0 {
                    return Err(err(
                        "relative noise on a feature whose default is 0 is always 0; give an absolute std".into(),
                    ));
                }
                r * d
            }
        };
        if !sd.is_finite() || sd < 0.0 {
            return Err(err(format!("the std must be finite and >= 0, got {sd}")));
        }
        if sd > MAX_NOISE_STD {
            return Err(err(format!(
                "the std {sd:e} is more than {MAX_NOISE_STD:e}: the observation is float32 (at most 3.4e38), and noise that large makes it infinite"
            )));
        }
        if stds[k] != 0.0 {
            return Err(err("listed twice".into()));
        }
        stds[k] = sd;
    }
    Ok(stds)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_robin_starts_at_the_seed_and_cycles() {
        let mut s = ContextSchedule::new(ScheduleKind::Set {
            n: 3,
            selection: Selection::RoundRobin,
        });
        let picks: Vec<Pick> = [Some(5), None, None, None]
            .into_iter()
            .map(|seed| s.next(seed).pick)
            .collect();
        assert_eq!(
            picks,
            [
                Pick::Instance(2),
                Pick::Instance(0),
                Pick::Instance(1),
                Pick::Instance(2)
            ]
        );
        s.continue_after(0);
        assert_eq!(s.next(None).pick, Pick::Instance(1));
    }

    #[test]
    fn a_seed_determines_every_following_plan() {
        for kind in [
            ScheduleKind::Set {
                n: 7,
                selection: Selection::Random,
            },
            ScheduleKind::Distribution,
            ScheduleKind::Fixed,
        ] {
            let mut a = ContextSchedule::new(kind);
            let mut b = ContextSchedule::new(kind);
            a.next(Some(1));
            a.next(None);
            let run = |s: &mut ContextSchedule| [s.next(Some(9)), s.next(None), s.next(None)];
            assert_eq!(run(&mut a), run(&mut b), "{kind:?}");
        }
    }

    #[test]
    fn runtime_seed_is_the_reset_seed_then_a_draw_except_for_fixed_contexts() {
        let mut fixed = ContextSchedule::new(ScheduleKind::Fixed);
        assert_eq!(fixed.next(Some(4)).runtime_seed, Some(4));
        assert_eq!(fixed.next(None).runtime_seed, None);
        let mut dist = ContextSchedule::new(ScheduleKind::Distribution);
        assert_eq!(dist.next(Some(4)).runtime_seed, Some(4));
        let second = dist.next(None);
        assert!(second.runtime_seed.is_some_and(|s| s != 4));
        // Same env-stream position in every kind: the instance choice does not move it.
        let mut set = ContextSchedule::new(ScheduleKind::Set {
            n: 2,
            selection: Selection::Random,
        });
        set.next(Some(4));
        assert_eq!(set.next(None).runtime_seed, second.runtime_seed);
    }
}
