//! `rna_design`: LEARNA's `RnaDesignEnvironment` (Runge et al., ICLR 2019), with carl-spec's own
//! RNA folding (crates/carl-rna, identical to ViennaRNA 2.x's `RNA.fold`).
//!
//! An episode designs a sequence for one target structure, site by site from the 5′ end: the
//! action places G, A, U or C at an unpaired site, or the pair GC, CG, AU or UA at a site opening
//! a pair (its partner is then assigned too). The observation is the window of 2·r+1 site codes
//! (`.` 0, `(` 1, `)` 2, padding 3; r = `state_radius`) centred on the first unassigned site of
//! the target padded by r on both sides. The reward is 0 until the last assignment, then
//! (1 − d/n)^`reward_exponent` with d the Hamming distance between the design's MFE structure and
//! the target after LEARNA's local improvement (see `reward`).
//!
//! Deviations from LEARNA, on purpose: the epoch order of the targets is a permutation drawn from
//! the environment's own seeded stream (LEARNA used NumPy's global RNG, so two environments in one
//! process disturbed each other); the observation after the last step is the window centred one
//! past the end (LEARNA returns `None`).

mod registry;
mod reward;
pub mod targets;

pub use registry::REGISTRATIONS;
pub use reward::{Outcome, terminal_reward};
pub use targets::{Dataset, RfamLearnSplit, Target, TargetError};

use std::path::PathBuf;

use carl_env::api::{
    Action, DType, Env, EnvError, Info, Space, StepOutcome, check_obs_len, check_state_len, discrete_action,
};
use carl_env::rng::EnvRng;

const ID: &str = "rna_design";
const UNASSIGNED: u8 = 255;
/// Site codes of the observation.
const PAD: f32 = 3.0;
/// LEARNA's action → base (unpaired site) and action → pair (site opening a pair).
const ACTION_BASE: [u8; 4] = *b"GAUC";
const ACTION_PAIR: [[u8; 2]; 4] = [*b"GC", *b"CG", *b"AU", *b"UA"];

/// The largest `state_radius` the runtime accepts, even with out-of-bounds values allowed (the
/// spec's bound is 500): the observation has 2·r+1 entries, so an unbounded radius would ask for
/// more memory than there is.
pub const MAX_STATE_RADIUS: usize = 1 << 16;

/// The context of `rna_design` (CARL's features) and the runtime's options.
#[derive(Debug, Clone, PartialEq)]
pub struct RnaDesignParams {
    /// Local improvement runs when 0 < d < mutation_threshold. Its cost is 4^d folds, so up to
    /// 4^⌈threshold−1⌉ per episode (256 at the default 5; 4^9 ≈ 262,000 at 10): see
    /// `max_improvement_folds`.
    pub mutation_threshold: f64,
    pub reward_exponent: f64,
    /// Half-width of the observation window (integer ≥ 1, at most [`MAX_STATE_RADIUS`]; the
    /// observation has 2r+1 entries).
    pub state_radius: usize,
    pub dataset: Dataset,
    /// Target ids (puzzle / file numbers) to design for; `None`: the whole dataset.
    pub target_structure_ids: Option<Vec<u32>>,
    /// Directory holding `rna/rfam_learn_*` (default `$CARL_SPEC_DATA`).
    pub data_dir: Option<PathBuf>,
    /// Opt-in cap on the local improvement's folds per episode (LEARNA: none).
    pub max_improvement_folds: Option<u64>,
}

impl Default for RnaDesignParams {
    fn default() -> Self {
        RnaDesignParams {
            mutation_threshold: 5.0,
            reward_exponent: 1.0,
            state_radius: 5,
            dataset: Dataset::Eterna,
            target_structure_ids: None,
            data_dir: None,
            max_improvement_folds: None,
        }
    }
}

#[derive(Debug, Clone)]
pub struct RnaDesign {
    params: RnaDesignParams,
    targets: Vec<Target>,
    /// Longest target: the state vector's width.
    max_len: usize,
    rng: EnvRng,
    /// Current epoch's order (indices into `targets`) and position in it.
    epoch: Vec<usize>,
    epoch_pos: usize,
    current: usize,
    design: Vec<u8>,
    site: usize,
    ready: bool,
    last: Option<Outcome>,
}

impl RnaDesign {
    pub fn new(params: RnaDesignParams) -> Result<Self, TargetError> {
        let targets = targets::load(
            params.dataset,
            params.target_structure_ids.as_deref(),
            params.data_dir.as_deref(),
        )?;
        let max_len = targets.iter().map(Target::len).max().unwrap_or(0);
        Ok(RnaDesign {
            params,
            targets,
            max_len,
            rng: EnvRng::default(),
            epoch: Vec::new(),
            epoch_pos: 0,
            current: 0,
            design: Vec::new(),
            site: 0,
            ready: false,
            last: None,
        })
    }

    pub fn params(&self) -> &RnaDesignParams {
        &self.params
    }

    pub fn targets(&self) -> &[Target] {
        &self.targets
    }

    /// The target of the current episode.
    pub fn target(&self) -> &Target {
        &self.targets[self.current]
    }

    /// The sequence designed so far (`N` at unassigned sites).
    pub fn design(&self) -> String {
        self.design
            .iter()
            .map(|&b| if b == UNASSIGNED { 'N' } else { b as char })
            .collect()
    }

    /// The last finished episode's target, design, fold and distances (kept after the next
    /// reset, so a batch that resets in the same step still reports it).
    pub fn last_outcome(&self) -> Option<&Outcome> {
        self.last.as_ref()
    }

    fn next_target(&mut self) {
        if self.epoch_pos >= self.epoch.len() {
            // A new epoch: a Fisher–Yates permutation from the env's own stream.
            self.epoch = (0..self.targets.len()).collect();
            for k in (1..self.epoch.len()).rev() {
                let j = (self.rng.next_u64() % (k as u64 + 1)) as usize;
                self.epoch.swap(k, j);
            }
            self.epoch_pos = 0;
        }
        self.current = self.epoch[self.epoch_pos];
        self.epoch_pos += 1;
    }

    fn first_unassigned(&self) -> Option<usize> {
        (self.site..self.design.len()).find(|&k| self.design[k] == UNASSIGNED)
    }

    fn write_obs(&self, obs: &mut [f32]) {
        let r = self.params.state_radius as isize;
        let target = self.target().structure.as_bytes();
        for (k, o) in obs.iter_mut().enumerate() {
            let pos = self.site as isize - r + k as isize;
            *o = if pos < 0 || pos as usize >= target.len() {
                PAD
            } else {
                match target[pos as usize] {
                    b'.' => 0.0,
                    b'(' => 1.0,
                    _ => 2.0,
                }
            };
        }
    }
}

impl Env for RnaDesign {
    fn id(&self) -> &'static str {
        ID
    }
    fn obs_dim(&self) -> usize {
        2 * self.params.state_radius + 1
    }
    /// `[target index, site code per position of the longest target]` with codes A 0, C 1, G 2,
    /// U 3 and −1 for unassigned (or beyond the current target).
    fn state_dim(&self) -> usize {
        1 + self.max_len
    }
    fn observation_space(&self) -> Space {
        let n = self.obs_dim();
        Space::Box {
            low: vec![0.0; n],
            high: vec![PAD; n],
            shape: vec![n],
            dtype: DType::Float32,
        }
    }
    fn action_space(&self) -> Space {
        Space::Discrete { n: 4, start: 0 }
    }

    fn reset_into(&mut self, seed: Option<u64>, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(ID, obs, self.obs_dim())?;
        if let Some(seed) = seed {
            self.rng = EnvRng::from_seed(seed);
            self.epoch.clear();
            self.epoch_pos = 0;
        }
        self.next_target();
        self.design = vec![UNASSIGNED; self.target().len()];
        self.site = 0;
        self.ready = true;
        self.write_obs(obs);
        Ok(())
    }

    fn step_into(&mut self, action: &Action, obs: &mut [f32]) -> Result<StepOutcome, EnvError> {
        check_obs_len(ID, obs, self.obs_dim())?;
        let a = discrete_action(ID, action, 4)? as usize;
        if !self.ready {
            return Err(EnvError::NeedsReset { env: ID });
        }
        let site = self.site;
        match self.targets[self.current].partner[site] {
            Some(partner) if partner > site => {
                self.design[site] = ACTION_PAIR[a][0];
                self.design[partner] = ACTION_PAIR[a][1];
            }
            _ => self.design[site] = ACTION_BASE[a],
        }
        self.site = self.first_unassigned().unwrap_or(self.design.len());
        self.write_obs(obs);
        if self.site < self.design.len() {
            return Ok(StepOutcome {
                reward: 0.0,
                terminated: false,
                truncated: false,
            });
        }
        self.ready = false;
        let design = String::from_utf8(self.design.clone()).expect("ASCII bases");
        let p = &self.params;
        let outcome = terminal_reward(
            self.target(),
            &design,
            p.mutation_threshold,
            p.reward_exponent,
            p.max_improvement_folds,
        )
        // The episode is over either way (`ready` is false): a reset starts the next one.
        .map_err(|_| EnvError::Interrupted { env: ID })?;
        let reward = outcome.reward;
        self.last = Some(outcome);
        Ok(StepOutcome {
            reward,
            terminated: true,
            truncated: false,
        })
    }

    fn observe_into(&self, obs: &mut [f32]) -> Result<(), EnvError> {
        check_obs_len(ID, obs, self.obs_dim())?;
        self.write_obs(obs);
        Ok(())
    }

    fn state(&self) -> Vec<f64> {
        let mut s = vec![-1.0; self.state_dim()];
        s[0] = self.current as f64;
        for (k, &b) in self.design.iter().enumerate() {
            s[1 + k] = match b {
                b'A' => 0.0,
                b'C' => 1.0,
                b'G' => 2.0,
                b'U' => 3.0,
                _ => -1.0,
            };
        }
        s
    }

    fn set_state(&mut self, state: &[f64]) -> Result<(), EnvError> {
        check_state_len(ID, state, self.state_dim())?;
        let bad = |index: usize| EnvError::Context {
            env: ID,
            message: format!("state component {index} = {} is not valid", state[index]),
        };
        let current = state[0];
        if current.fract() != 0.0 || current < 0.0 || current as usize >= self.targets.len() {
            return Err(bad(0));
        }
        let len = self.targets[current as usize].len();
        let mut design = vec![UNASSIGNED; len];
        for (k, &x) in state[1..].iter().enumerate() {
            let code = match x {
                -1.0 => UNASSIGNED,
                0.0 => b'A',
                1.0 => b'C',
                2.0 => b'G',
                3.0 => b'U',
                _ => return Err(bad(1 + k)),
            };
            if k < len {
                design[k] = code;
            } else if code != UNASSIGNED {
                return Err(bad(1 + k));
            }
        }
        self.current = current as usize;
        self.design = design;
        self.site = 0;
        self.site = self.first_unassigned().unwrap_or(len);
        self.ready = self.site < len;
        Ok(())
    }

    /// `target_id`, and after the last step `hamming_distance` (after local improvement),
    /// `hamming_distance_folded` (before), `normalized_hamming_distance` and `improvement_folds`.
    /// The designed and folded sequences: [`RnaDesign::last_outcome`].
    fn info(&self) -> Info {
        let mut info = Info::new();
        if self.targets.is_empty() || self.design.is_empty() {
            return info;
        }
        info.insert("target_id".into(), f64::from(self.target().id));
        if !self.ready
            && let Some(o) = &self.last
        {
            info.insert("hamming_distance".into(), o.distance as f64);
            info.insert("hamming_distance_folded".into(), o.distance_folded as f64);
            info.insert(
                "normalized_hamming_distance".into(),
                o.distance as f64 / self.target().len() as f64,
            );
            info.insert("improvement_folds".into(), o.improvement_folds as f64);
        }
        info
    }
}

impl carl_env::runtime::Runtime for RnaDesign {
    /// The reward features act only at an episode's last step: for every target among `states`,
    /// complete designs (each action's base and pair everywhere) with the last site left open.
    fn goal_states(&self, states: &[Vec<f64>]) -> Result<Vec<Vec<f64>>, EnvError> {
        let mut seen = std::collections::BTreeSet::new();
        let mut out = Vec::new();
        for s in states {
            let index = s.first().copied().unwrap_or(0.0);
            if index < 0.0 || index as usize >= self.targets.len() || !seen.insert(index as usize) {
                continue;
            }
            let target = &self.targets[index as usize];
            let last = (0..target.len())
                .rev()
                .find(|&k| target.partner[k].is_none_or(|p| p > k))
                .unwrap_or(0);
            for a in 0..4 {
                let mut state = vec![-1.0; self.state_dim()];
                state[0] = index;
                for k in 0..target.len() {
                    let base = match target.partner[k] {
                        Some(p) if p > k => ACTION_PAIR[a][0],
                        Some(_) => ACTION_PAIR[a][1],
                        None => ACTION_BASE[a],
                    };
                    state[1 + k] = f64::from(b"ACGU".iter().position(|&b| b == base).unwrap_or(0) as u8);
                }
                state[1 + last] = -1.0;
                if let Some(p) = target.partner[last] {
                    state[1 + p] = -1.0;
                }
                out.push(state);
            }
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env(ids: &[u32], dataset: Dataset) -> RnaDesign {
        RnaDesign::new(RnaDesignParams {
            dataset,
            target_structure_ids: Some(ids.to_vec()),
            ..Default::default()
        })
        .unwrap()
    }

    /// The spec's defaults: the dataset is a name (Eterna100), the target ids a list (none: all).
    #[test]
    fn default_dataset_is_eterna_and_all_targets() {
        let p = RnaDesignParams::default();
        assert_eq!(Dataset::from_name("eterna"), Some(p.dataset));
        assert_eq!(p.target_structure_ids, None);
    }

    #[test]
    fn all_zero_actions_on_eterna_1_design_the_solved_hairpin() {
        let mut e = env(&[1], Dataset::Eterna);
        let (obs, _) = e.reset(Some(0));
        // Window of 11 around site 0 of "(((((......)))))": 5 padding, then "((((((" .
        assert_eq!(obs, [3., 3., 3., 3., 3., 1., 1., 1., 1., 1., 0.]);
        let mut steps = 0;
        loop {
            steps += 1;
            let s = e.step(&Action::Discrete(0)).unwrap();
            if s.terminated {
                assert_eq!(s.reward, 1.0);
                assert_eq!(s.info["hamming_distance"], 0.0);
                assert_eq!(s.info["target_id"], 1.0);
                break;
            }
            assert_eq!(s.reward, 0.0);
        }
        assert_eq!(steps, 11);
        let outcome = e.last_outcome().unwrap();
        assert_eq!(outcome.design, "GGGGGGGGGGGCCCCC");
        assert_eq!(
            (outcome.target_id, outcome.target_structure.as_str()),
            (1, "(((((......)))))")
        );
        assert!(matches!(e.step(&Action::Discrete(0)), Err(EnvError::NeedsReset { .. })));
    }

    #[test]
    fn actions_place_learna_bases_and_pairs() {
        let mut e = env(&[1], Dataset::Eterna);
        e.reset(Some(0));
        for a in [0, 1, 2, 3, 0] {
            e.step(&Action::Discrete(a)).unwrap();
        }
        // Pairs GC, CG, AU, UA, GC; partners filled in from the 3′ side.
        assert_eq!(e.design(), "GCAUGNNNNNNCAUGC");
        e.step(&Action::Discrete(1)).unwrap(); // unpaired: A
        assert_eq!(&e.design()[5..6], "A");
        assert!(e.step(&Action::Discrete(4)).is_err());
    }

    /// Golden values from LEARNA's `_local_improvement` run with ViennaRNA 2.8.0's `RNA.fold`
    /// (itertools.product("AGCU") over the differing sites, stop at distance 0).
    #[test]
    fn local_improvement_matches_learna() {
        let target = targets::load(Dataset::Eterna, Some(&[1]), None).unwrap().remove(0);
        // Folds into "(((((.....)))))." (d = 2); the third assignment reaches 0.
        let repaired = terminal_reward(&target, "GGGGGAAAAACCCCCA", 5.0, 1.0, None).unwrap();
        assert_eq!(repaired.folded, "(((((.....))))).");
        assert_eq!(
            (repaired.distance_folded, repaired.distance, repaired.improvement_folds),
            (2, 0, 3)
        );
        assert_eq!(repaired.reward, 1.0);
        // Folds into ".((((.......))))" (d = 2); none of the 16 assignments does better.
        let stuck = terminal_reward(&target, "GGGGAAAAAAAAUCCC", 5.0, 2.0, None).unwrap();
        assert_eq!(
            (stuck.distance_folded, stuck.distance, stuck.improvement_folds),
            (2, 2, 16)
        );
        assert_eq!(stuck.reward, (1.0 - 2.0 / 16.0f64).powf(2.0));
        // d = 2 is not below a threshold of 2: no improvement.
        let off = terminal_reward(&target, "GGGGGAAAAACCCCCA", 2.0, 1.0, None).unwrap();
        assert_eq!((off.distance, off.improvement_folds), (2, 0));
        // The opt-in cap stops after 2 folds, before the repairing third assignment.
        let capped = terminal_reward(&target, "GGGGGAAAAACCCCCA", 5.0, 1.0, Some(2)).unwrap();
        assert_eq!(capped.improvement_folds, 2);
        assert!(capped.distance > 0);
    }

    /// The caller's cancellation check stops the local improvement (the binding's Ctrl-C) and
    /// the step reports it; work that runs no improvement never asks.
    #[test]
    fn local_improvement_can_be_cancelled() {
        use carl_env::cancel::{Interrupted, with_check};
        let target = targets::load(Dataset::Eterna, Some(&[1]), None).unwrap().remove(0);
        let stopped = with_check(|| true, || terminal_reward(&target, "GGGGAAAAAAAAUCCC", 5.0, 2.0, None));
        assert_eq!(stopped, Err(Interrupted));
        let off = with_check(|| true, || terminal_reward(&target, "GGGGAAAAAAAAUCCC", 2.0, 2.0, None));
        assert!(off.is_ok());

        let mut e = env(&[1], Dataset::Eterna);
        e.reset(Some(0));
        // The stuck design above with its last site unassigned; codes A 0, C 1, G 2, U 3.
        let code = |b: u8| match b {
            b'A' => 0.0,
            b'C' => 1.0,
            b'G' => 2.0,
            _ => 3.0,
        };
        let mut state: Vec<f64> = vec![0.0];
        state.extend(b"GGGGAAAAAAAAUCC".iter().map(|&b| code(b)));
        state.push(-1.0);
        e.set_state(&state).unwrap();
        let err = with_check(|| true, || e.step(&Action::Discrete(3))).unwrap_err();
        assert_eq!(err, EnvError::Interrupted { env: ID });
        assert!(matches!(e.step(&Action::Discrete(0)), Err(EnvError::NeedsReset { .. })));
        e.set_state(&state).unwrap();
        let done = e.step(&Action::Discrete(3)).unwrap();
        assert!(done.terminated);
        assert_eq!(e.last_outcome().map(|o| o.improvement_folds), Some(16));
    }

    #[test]
    fn epoch_order_is_a_seeded_permutation() {
        let mut a = env(&[1, 2, 3, 4, 5], Dataset::Eterna);
        let mut b = env(&[1, 2, 3, 4, 5], Dataset::Eterna);
        let order = |e: &mut RnaDesign, seed| {
            (0..5)
                .map(|k| {
                    e.reset(if k == 0 { Some(seed) } else { None });
                    e.target().id
                })
                .collect::<Vec<_>>()
        };
        let first = order(&mut a, 7);
        assert_eq!(first, order(&mut b, 7));
        let mut sorted = first.clone();
        sorted.sort();
        assert_eq!(sorted, [1, 2, 3, 4, 5]);
    }

    #[test]
    fn state_radius_sets_the_window() {
        let mut e = RnaDesign::new(RnaDesignParams {
            state_radius: 2,
            target_structure_ids: Some(vec![1]),
            ..Default::default()
        })
        .unwrap();
        assert_eq!(e.obs_dim(), 5);
        let (obs, _) = e.reset(Some(1));
        assert_eq!(obs, [3., 3., 1., 1., 1.]);
        let state = e.state();
        e.step(&Action::Discrete(0)).unwrap();
        e.set_state(&state).unwrap();
        assert_eq!(e.design(), "N".repeat(16));
    }
}
