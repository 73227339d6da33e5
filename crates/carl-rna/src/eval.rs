//! Free energy of a given secondary structure: the sum of its loops' energies.

use crate::RnaError;
use crate::energy::{hairpin, interior, ml_stem, stem};
use crate::params::{ML_BASE, ML_CLOSING, NP, pair_type};

/// One loop of a structure and its energy. `closing` is the 1-based closing pair, `None` for the
/// exterior loop (ViennaRNA's `[0, 0, e]`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LoopEnergy {
    pub closing: Option<(usize, usize)>,
    pub energy: i32,
}

/// Energy (dcal/mol) of every loop of `pairs` (0-based partner table) on the coded sequence `s`,
/// exterior loop first, then loops in order of their closing pair's 5′ base.
pub(crate) fn loop_energies(s: &[u8], pairs: &[Option<usize>]) -> Result<Vec<LoopEnergy>, RnaError> {
    let n = s.len();
    for (i, &p) in pairs.iter().enumerate() {
        if let Some(j) = p.filter(|&j| j > i) {
            if pair_type(s[i], s[j]) == NP {
                return Err(RnaError::NonCanonicalPair { i: i + 1, j: j + 1 });
            }
            if j - i - 1 < crate::params::MIN_HAIRPIN {
                return Err(RnaError::HairpinTooShort { i: i + 1, j: j + 1 });
            }
        }
    }
    // Helices directly inside the region (from, to), as (p, q) pairs.
    let branches = |from: usize, to: usize| {
        let mut out = Vec::new();
        let mut k = from;
        while k < to {
            match pairs[k] {
                Some(q) if q > k => {
                    out.push((k, q));
                    k = q + 1;
                }
                _ => k += 1,
            }
        }
        out
    };
    let mut loops = Vec::new();
    let exterior: i32 = branches(0, n)
        .into_iter()
        .map(|(p, q)| {
            let d5 = p.checked_sub(1).map(|k| s[k]);
            let d3 = s.get(q + 1).copied();
            stem(pair_type(s[p], s[q]), d5, d3)
        })
        .sum();
    loops.push(LoopEnergy {
        closing: None,
        energy: exterior,
    });
    for i in 0..n {
        let Some(j) = pairs[i].filter(|&j| j > i) else { continue };
        let inner = branches(i + 1, j);
        let t = pair_type(s[i], s[j]);
        let energy = match inner.as_slice() {
            [] => hairpin(s, i, j),
            [(p, q)] => interior(s, i, j, *p, *q, t, pair_type(s[*q], s[*p])),
            _ => {
                let paired: usize = inner.iter().map(|(p, q)| q - p + 1).sum();
                let unpaired = (j - i - 1 - paired) as i32;
                ML_CLOSING
                    + ml_stem(pair_type(s[j], s[i]), s[j - 1], s[i + 1])
                    + inner
                        .iter()
                        .map(|&(p, q)| ml_stem(pair_type(s[p], s[q]), s[p - 1], s[q + 1]))
                        .sum::<i32>()
                    + ML_BASE * unpaired
            }
        };
        loops.push(LoopEnergy {
            closing: Some((i + 1, j + 1)),
            energy,
        });
    }
    Ok(loops)
}
