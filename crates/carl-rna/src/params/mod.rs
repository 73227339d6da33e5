//! The Turner 2004 parameter set as ViennaRNA 2.x applies it at 37 °C (its compiled-in default,
//! identical to `rna_turner2004.par` of ViennaRNA v2.7.0). Energies in dcal/mol.

mod turner2004;

pub(crate) use turner2004::*;

/// "Impossible": large enough to dominate any real energy, small enough that sums of a few never
/// overflow i32.
pub const INF: i32 = 10_000_000;

/// Longest bulge/interior loop the MFE considers (ViennaRNA's MAXLOOP); evaluation extrapolates.
pub const MAXLOOP: usize = 30;
/// Smallest hairpin (unpaired bases).
pub const MIN_HAIRPIN: usize = 3;

pub(crate) const ML_CLOSING: i32 = 930;
pub(crate) const ML_INTERN: i32 = -90;
pub(crate) const ML_BASE: i32 = 0;
pub(crate) const NINIO: i32 = 60;
pub(crate) const MAX_NINIO: i32 = 300;
pub(crate) const TERMINAL_AU: i32 = 50;
/// Jacobson–Stockmayer extrapolation constant for loops longer than 30 (dcal/mol).
pub(crate) const LXC: f64 = 107.856;

/// Pair type index (AU, UA, CG, GC, GU, UG) of bases coded A=0, C=1, G=2, U=3; `NP` if they
/// cannot pair.
pub(crate) const NP: u8 = 255;
pub(crate) static PAIR: [[u8; 4]; 4] = [
    [NP, NP, NP, 0], // A·U
    [NP, NP, 2, NP], // C·G
    [NP, 3, NP, 4],  // G·C, G·U
    [1, NP, 5, NP],  // U·A, U·G
];

#[inline]
pub(crate) fn pair_type(a: u8, b: u8) -> u8 {
    PAIR[a as usize][b as usize]
}

/// Penalty of an AU or GU pair that ends a helix.
#[inline]
pub(crate) fn terminal_au(t: u8) -> i32 {
    if t == 2 || t == 3 { 0 } else { TERMINAL_AU }
}

/// `table[n]` for n ≤ 30, else `table[30] + ⌊lxc · ln(n/30)⌋` (truncated like ViennaRNA).
#[inline]
pub(crate) fn loop_initiation(table: &[i32; 31], n: usize) -> i32 {
    if n <= MAXLOOP {
        table[n]
    } else {
        table[MAXLOOP] + (LXC * (n as f64 / MAXLOOP as f64).ln()) as i32
    }
}
