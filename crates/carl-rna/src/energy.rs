//! Free energy of single loops under Turner 2004 as ViennaRNA 2.x applies it (dangles = 2,
//! special hairpins on). Positions are indices into a coded sequence (A=0, C=1, G=2, U=3);
//! pair types are the indices of `params::PAIR`. All results in dcal/mol.

use crate::params::*;

/// Hairpin closed by (i, j): special tri/tetra/hexaloop bonus (replaces everything), else
/// initiation by size plus the terminal mismatch (size > 3) or the terminal AU/GU penalty (size 3).
pub(crate) fn hairpin(s: &[u8], i: usize, j: usize) -> i32 {
    let size = j - i - 1;
    if size < MIN_HAIRPIN {
        return INF;
    }
    let t = pair_type(s[i], s[j]);
    let special = match size {
        3 => TRILOOPS,
        4 => TETRALOOPS,
        6 => HEXALOOPS,
        _ => &[],
    };
    if let Some(&(_, e)) = special
        .iter()
        .find(|(motif, _)| motif.iter().zip(&s[i..=j]).all(|(&m, &b)| m == b"ACGU"[b as usize]))
    {
        return e;
    }
    let init = loop_initiation(&HAIRPIN, size);
    if size == 3 {
        init + terminal_au(t)
    } else {
        init + MISMATCH_HAIRPIN[t as usize][s[i + 1] as usize][s[j - 1] as usize]
    }
}

/// Stack, bulge or interior loop between the outer pair (i, j) and the inner pair (p, q),
/// i < p < q < j. `t` is the type of (i, j), `t2` of the reversed inner pair (q, p).
#[inline]
pub(crate) fn interior(s: &[u8], i: usize, j: usize, p: usize, q: usize, t: u8, t2: u8) -> i32 {
    let (n1, n2) = (p - i - 1, j - q - 1);
    let (ns, nl) = if n1 < n2 { (n1, n2) } else { (n2, n1) };
    let (t, t2) = (t as usize, t2 as usize);
    if nl == 0 {
        return STACK[t][t2];
    }
    if ns == 0 {
        let init = loop_initiation(&BULGE, nl);
        return if nl == 1 {
            init + STACK[t][t2]
        } else {
            init + terminal_au(t as u8) + terminal_au(t2 as u8)
        };
    }
    let (si, sj, sp, sq) = (
        s[i + 1] as usize,
        s[j - 1] as usize,
        s[p - 1] as usize,
        s[q + 1] as usize,
    );
    let asymmetry = ((nl - ns) as i32 * NINIO).min(MAX_NINIO);
    match (ns, nl) {
        (1, 1) => INT11[t][t2][si][sj],
        (1, 2) if n1 == 1 => INT21[t][t2][si][sq][sj],
        (1, 2) => INT21[t2][t][sq][si][sp],
        (1, _) => {
            loop_initiation(&INTERIOR, nl + 1)
                + asymmetry
                + MISMATCH_INTERIOR_1N[t][si][sj]
                + MISMATCH_INTERIOR_1N[t2][sq][sp]
        }
        (2, 2) => INT22[t][t2][si][sp][sq][sj],
        (2, 3) => INTERIOR[5] + NINIO + MISMATCH_INTERIOR_23[t][si][sj] + MISMATCH_INTERIOR_23[t2][sq][sp],
        _ => {
            loop_initiation(&INTERIOR, nl + ns)
                + asymmetry
                + MISMATCH_INTERIOR[t][si][sj]
                + MISMATCH_INTERIOR[t2][sq][sp]
        }
    }
}

/// Contribution of a helix end of type `t` in the exterior loop or a multiloop under dangles = 2:
/// terminal AU/GU penalty plus the mismatch of both neighbours (paired or not), or the single
/// dangle when the helix sits at a sequence end. `d5` is the base 5′ of the pair's first base,
/// `d3` the base 3′ of its second (as seen from the loop).
#[inline]
pub(crate) fn stem(t: u8, d5: Option<u8>, d3: Option<u8>) -> i32 {
    let t = t as usize;
    terminal_au(t as u8)
        + match (d5, d3) {
            (Some(a), Some(b)) => MISMATCH_MULTI[t][a as usize][b as usize],
            (Some(a), None) => DANGLE5[t][a as usize],
            (None, Some(b)) => DANGLE3[t][b as usize],
            (None, None) => 0,
        }
}

/// A branch of a multiloop (either an inner helix or, reversed, the closing pair).
#[inline]
pub(crate) fn ml_stem(t: u8, d5: u8, d3: u8) -> i32 {
    ML_INTERN + terminal_au(t) + MISMATCH_MULTI[t as usize][d5 as usize][d3 as usize]
}

/// A lower bound of [`interior`] over every pair type and base, for loops with `n1` unpaired
/// bases on the 5′ side and `n2` on the 3′ side (`n1 + n2 ≤ MAXLOOP`): lets the MFE recursion skip
/// inner pairs that cannot beat the best decomposition found so far. Terminal AU/GU penalties are
/// ≥ 0, so leaving them out keeps the bound valid.
pub(crate) fn interior_lower_bounds() -> [[i32; MAXLOOP + 1]; MAXLOOP + 1] {
    fn min_mismatch(t: &[[[i32; 4]; 4]; 6]) -> i32 {
        t.iter().flatten().flatten().copied().min().unwrap_or(0)
    }
    let stack = STACK.iter().flatten().copied().min().unwrap_or(0);
    let int11 = INT11.iter().flatten().flatten().flatten().copied().min().unwrap_or(0);
    let int21 = INT21
        .iter()
        .flatten()
        .flatten()
        .flatten()
        .flatten()
        .copied()
        .min()
        .unwrap_or(0);
    let int22 = INT22
        .iter()
        .flatten()
        .flatten()
        .flatten()
        .flatten()
        .flatten()
        .copied()
        .min()
        .unwrap_or(0);
    let mut lb = [[INF; MAXLOOP + 1]; MAXLOOP + 1];
    for (n1, row) in lb.iter_mut().enumerate() {
        for (n2, cell) in row.iter_mut().enumerate().take(MAXLOOP + 1 - n1) {
            let (ns, nl) = (n1.min(n2), n1.max(n2));
            let asymmetry = ((nl - ns) as i32 * NINIO).min(MAX_NINIO);
            *cell = match (ns, nl) {
                (0, 0) => stack,
                (0, 1) => BULGE[1] + stack,
                (0, _) => BULGE[nl],
                (1, 1) => int11,
                (1, 2) => int21,
                (1, _) => INTERIOR[nl + 1] + asymmetry + 2 * min_mismatch(&MISMATCH_INTERIOR_1N),
                (2, 2) => int22,
                (2, 3) => INTERIOR[5] + NINIO + 2 * min_mismatch(&MISMATCH_INTERIOR_23),
                _ => INTERIOR[nl + ns] + asymmetry + 2 * min_mismatch(&MISMATCH_INTERIOR),
            };
        }
    }
    lb
}
