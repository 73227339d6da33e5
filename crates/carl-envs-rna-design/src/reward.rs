//! LEARNA's terminal reward: fold the design, Hamming distance d to the target, local improvement
//! when 0 < d < mutation_threshold, reward (1 − d/n)^reward_exponent.

use carl_env::cancel::{self, Interrupted, POLL_EVERY};

use super::targets::Target;

/// What the terminal step found.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// The target's id in its dataset, and its dot-bracket structure.
    pub target_id: u32,
    pub target_structure: String,
    /// The designed sequence (before local improvement).
    pub design: String,
    /// Its MFE structure (carl-rna, identical to ViennaRNA's `RNA.fold`).
    pub folded: String,
    /// Hamming distance of `folded` to the target.
    pub distance_folded: usize,
    /// Distance after local improvement (equal to `distance_folded` when it did not run).
    pub distance: usize,
    /// Sequences folded by the local improvement.
    pub improvement_folds: u64,
    pub reward: f64,
}

pub(crate) fn hamming(a: &str, b: &str) -> usize {
    a.bytes().zip(b.bytes()).filter(|(x, y)| x != y).count()
}

/// Reward of `design` for `target`. `max_folds` caps the local improvement (LEARNA: no cap, up
/// to 4^d folds): only the first `max_folds` assignments in LEARNA's order are tried. The
/// improvement polls [`carl_env::cancel::poll`] every [`carl_env::cancel::POLL_EVERY`] folds and
/// stops with `Err(Interrupted)` when the caller's check says so.
pub fn terminal_reward(
    target: &Target,
    design: &str,
    mutation_threshold: f64,
    reward_exponent: f64,
    max_folds: Option<u64>,
) -> Result<Outcome, Interrupted> {
    let folded = carl_rna::fold(design).expect("designs hold only A, C, G, U").structure;
    let distance_folded = hamming(&folded, &target.structure);
    let mut distance = distance_folded;
    let mut improvement_folds = 0;
    if distance > 0 && (distance as f64) < mutation_threshold {
        (distance, improvement_folds) = local_improvement(target, design, &folded, max_folds)?;
    }
    let n = target.len() as f64;
    let reward = (1.0 - distance as f64 / n).powf(reward_exponent);
    Ok(Outcome {
        target_id: target.id,
        target_structure: target.structure.clone(),
        design: design.to_string(),
        folded,
        distance_folded,
        distance,
        improvement_folds,
        reward,
    })
}

/// LEARNA's `_local_improvement`: every assignment of A, G, C, U (itertools.product order, last
/// site fastest) to the sites where the fold differs from the target (their partners untouched);
/// the smallest distance found, stopping at the first 0. Returns (distance, folds made).
fn local_improvement(
    target: &Target,
    design: &str,
    folded: &str,
    max_folds: Option<u64>,
) -> Result<(usize, u64), Interrupted> {
    const BASES: [u8; 4] = *b"AGCU";
    let sites: Vec<usize> = (0..target.len())
        .filter(|&k| folded.as_bytes()[k] != target.structure.as_bytes()[k])
        .collect();
    let total = 4u64.saturating_pow(sites.len() as u32);
    let limit = max_folds.map_or(total, |m| m.min(total));
    let mut seq = design.as_bytes().to_vec();
    let mut best = usize::MAX;
    for index in 0..limit {
        if index % POLL_EVERY == 0 {
            cancel::poll()?;
        }
        let mut rest = index;
        for &site in sites.iter().rev() {
            seq[site] = BASES[(rest % 4) as usize];
            rest /= 4;
        }
        let text = std::str::from_utf8(&seq).expect("ASCII");
        let d = hamming(&carl_rna::fold(text).expect("valid bases").structure, &target.structure);
        best = best.min(d);
        if d == 0 {
            return Ok((0, index + 1));
        }
    }
    Ok((best.min(hamming(folded, &target.structure)), limit))
}
