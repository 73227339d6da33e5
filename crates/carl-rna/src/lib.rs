//! RNA secondary structure prediction in pure Rust: minimum free energy (MFE) folding and energy
//! evaluation of a single strand under ViennaRNA 2.x's default model — Turner 2004 parameters,
//! 37 °C, dangles = 2 (mismatch energies on both sides of every helix end), lonely pairs allowed,
//! special hairpins, bulge/interior loops up to 30 unpaired bases.
//!
//! The recursions follow Zuker & Stiegler (1981) and the ViennaRNA 2.0 paper (Lorenz et al.,
//! Algorithms Mol. Biol. 6:26, 2011); the loop energies follow the NNDB's Turner 2004 model. When
//! several structures share the minimum energy, the one returned is the one ViennaRNA 2.x returns:
//! the traceback order was inferred from ViennaRNA's outputs (used strictly as a black-box oracle,
//! see `tests/vienna_parity.rs`), not from its source.
//!
//! ```
//! let folded = carl_rna::fold("GGGGAAACCCC").unwrap();
//! assert_eq!(folded.structure, "((((...))))");
//! assert_eq!(folded.energy, carl_rna::eval("GGGGAAACCCC", &folded.structure).unwrap());
//! ```

mod energy;
mod eval;
pub mod input;
mod mfe;
mod params;
mod sequence;

pub use eval::LoopEnergy;
pub use params::{MAXLOOP, MIN_HAIRPIN};
pub use sequence::MAX_LEN;

/// Why a sequence or structure was refused. Positions are 1-based.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum RnaError {
    InvalidBase { pos: usize, ch: char },
    TooLong { len: usize, max: usize },
    LengthMismatch { sequence: usize, structure: usize },
    InvalidStructureChar { pos: usize, ch: char },
    UnbalancedClose { pos: usize },
    UnbalancedOpen { pos: usize },
    NonCanonicalPair { i: usize, j: usize },
    HairpinTooShort { i: usize, j: usize },
}

impl std::fmt::Display for RnaError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RnaError::InvalidBase { pos, ch } => {
                write!(
                    f,
                    "position {pos}: {ch:?} is not a nucleotide (expected A, C, G, U or T)"
                )
            }
            RnaError::TooLong { len, max } => {
                write!(
                    f,
                    "sequence of {len} nt is longer than the supported maximum of {max} nt"
                )
            }
            RnaError::LengthMismatch { sequence, structure } => write!(
                f,
                "structure has {structure} characters but the sequence has {sequence} nt"
            ),
            RnaError::InvalidStructureChar { pos, ch } => {
                write!(f, "structure position {pos}: {ch:?} is not one of '.', '(' or ')'")
            }
            RnaError::UnbalancedClose { pos } => write!(f, "structure position {pos}: ')' has no matching '('"),
            RnaError::UnbalancedOpen { pos } => write!(f, "structure position {pos}: '(' is never closed"),
            RnaError::NonCanonicalPair { i, j } => {
                write!(f, "pair ({i}, {j}) is not a canonical pair (AU, CG or GU)")
            }
            RnaError::HairpinTooShort { i, j } => {
                write!(
                    f,
                    "pair ({i}, {j}) closes a hairpin of fewer than {MIN_HAIRPIN} unpaired bases"
                )
            }
        }
    }
}

impl std::error::Error for RnaError {}

/// An MFE structure: dot-bracket and free energy in dcal/mol (1 kcal/mol = 100).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Folded {
    pub structure: String,
    pub energy: i32,
}

impl Folded {
    /// Free energy in kcal/mol.
    pub fn energy_kcal(&self) -> f64 {
        f64::from(self.energy) / 100.0
    }
}

/// Minimum free energy structure of `seq` (A, C, G, U or T, any case; at most [`MAX_LEN`] nt).
/// The empty sequence folds into the empty structure with energy 0.
pub fn fold(seq: &str) -> Result<Folded, RnaError> {
    let s = sequence::encode(seq)?;
    Ok(mfe::fold_coded(&s))
}

/// Free energy (dcal/mol) of `structure` (dot-bracket) on `seq`.
pub fn eval(seq: &str, structure: &str) -> Result<i32, RnaError> {
    Ok(eval_loops(seq, structure)?.iter().map(|l| l.energy).sum())
}

/// Energy of every loop of `structure` on `seq`: the exterior loop first, then each loop by the
/// 1-based pair closing it (ViennaRNA's per-loop decomposition).
pub fn eval_loops(seq: &str, structure: &str) -> Result<Vec<LoopEnergy>, RnaError> {
    let s = sequence::encode(seq)?;
    let pairs = sequence::pair_table(structure, s.len())?;
    eval::loop_energies(&s, &pairs)
}

/// `seq` in canonical spelling (upper case, `T` → `U`), or why it is not a valid sequence.
pub fn normalize(seq: &str) -> Result<String, RnaError> {
    sequence::encode(seq).map(|s| sequence::decode(&s))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_sequences_cannot_pair() {
        for seq in ["", "G", "GC", "GGGC", "GAAAC"] {
            let f = fold(seq).unwrap();
            assert_eq!(f.structure, ".".repeat(seq.len()), "{seq}");
            assert_eq!(f.energy, 0);
        }
    }

    #[test]
    fn t_and_lower_case_read_as_rna() {
        assert_eq!(fold("gggGAAACCCC").unwrap(), fold("GGGGAAACCCC").unwrap());
        assert_eq!(fold("GGGGTTTCCCC").unwrap(), fold("GGGGUUUCCCC").unwrap());
        assert_eq!(normalize("acgt").unwrap(), "ACGU");
    }

    #[test]
    fn bad_input_is_a_located_error() {
        assert_eq!(fold("GGXA"), Err(RnaError::InvalidBase { pos: 3, ch: 'X' }));
        assert_eq!(
            fold(&"A".repeat(MAX_LEN + 1)),
            Err(RnaError::TooLong {
                len: MAX_LEN + 1,
                max: MAX_LEN
            })
        );
        assert_eq!(
            eval("GGGAAACCC", "((....))"),
            Err(RnaError::LengthMismatch {
                sequence: 9,
                structure: 8
            })
        );
        assert_eq!(
            eval("GGGAAACCC", "((....)))"),
            Err(RnaError::UnbalancedClose { pos: 9 })
        );
        assert_eq!(eval("GGGAAACCC", "(((....))"), Err(RnaError::UnbalancedOpen { pos: 1 }));
        assert_eq!(
            eval("GGGAAACCC", "((.[..)))"),
            Err(RnaError::InvalidStructureChar { pos: 4, ch: '[' })
        );
        assert_eq!(
            eval("GAGAAACCC", "(((...)))"),
            Err(RnaError::NonCanonicalPair { i: 2, j: 8 })
        );
        assert_eq!(
            eval("GGGAACCC", "(((..)))"),
            Err(RnaError::HairpinTooShort { i: 3, j: 6 })
        );
    }

    #[test]
    fn special_hairpins_replace_the_whole_loop_energy() {
        // GUUAC: ViennaRNA 690 (ff_energy 0.4.1 gives 540); CUUCGG tetraloop 370.
        assert_eq!(eval_loops("GUUAC", "(...)").unwrap()[1].energy, 690);
        assert_eq!(eval_loops("CUUCGG", "(....)").unwrap()[1].energy, 370);
    }

    #[test]
    fn mfe_equals_the_evaluated_energy_of_its_structure() {
        let seq = "GGGAAAUCCCGCGCAUAUGCGCAAGGAAACCUUUUGCGGCAAAGCCGCA";
        let f = fold(seq).unwrap();
        assert_eq!(eval(seq, &f.structure).unwrap(), f.energy);
        assert!(f.energy < 0);
    }
}
