//! Minimum free energy folding: Zuker–Stiegler dynamic programming with the multiloop
//! decomposition of ViennaRNA 2.x for dangles = 2, and a traceback whose tie-breaking order
//! reproduces ViennaRNA's choice among co-optimal structures.
//!
//! Tables (0-based, i < j):
//! - `c[i][j]`: MFE of the segment i..=j given that i and j pair;
//! - `fml[i][j]`: MFE of i..=j as part of a multiloop, holding at least one helix;
//! - `split[i][j]`: min over k of fml[i][k] + fml[k+1][j], i.e. at least two helices; it is the
//!   inside of a multiloop closed by (i−1, j+1), so it is kept for the row above;
//! - `f5[l]`: MFE of the prefix of length l (exterior loop).
//!
//! Traceback order (inferred from ViennaRNA's outputs on 668 tied fixtures, all reproduced):
//! exterior loop from the 3′ end, an unpaired last base first, else the helix ending there with
//! the largest 5′ start; in a pair, hairpin, then interior loops by increasing p and decreasing q,
//! then the multiloop split with the smallest k; in a multiloop segment, an unpaired 3′ base, an
//! unpaired 5′ base, a single helix, then the split with the smallest k.

use crate::Folded;
use crate::energy::{hairpin, interior, interior_lower_bounds, ml_stem, stem};
use crate::params::{INF, MAXLOOP, ML_BASE, ML_CLOSING, NP, pair_type};
use crate::sequence::dot_bracket;

/// Smallest distance j − i of a pair (a hairpin needs 3 unpaired bases).
const MIN_SPAN: usize = 4;

pub(crate) fn fold_coded(s: &[u8]) -> Folded {
    let n = s.len();
    if n == 0 {
        return Folded {
            structure: String::new(),
            energy: 0,
        };
    }
    let tables = Tables::fill(s);
    let pairs = tables.traceback();
    Folded {
        structure: dot_bracket(n, &pairs),
        energy: tables.f5[n],
    }
}

struct Tables<'a> {
    s: &'a [u8],
    n: usize,
    /// `c[i * n + j]`
    c: Vec<i32>,
    /// `fml[i * n + j]`, and its transpose `fml_t[j * n + i]` so that both halves of a split are
    /// contiguous in memory.
    fml: Vec<i32>,
    fml_t: Vec<i32>,
    f5: Vec<i32>,
    /// `bound[n1][n2]`: no interior loop of that shape costs less (see `interior_lower_bounds`).
    bound: [[i32; MAXLOOP + 1]; MAXLOOP + 1],
}

impl<'a> Tables<'a> {
    fn fill(s: &'a [u8]) -> Self {
        let n = s.len();
        let mut t = Tables {
            s,
            n,
            c: vec![INF; n * n],
            fml: vec![INF; n * n],
            fml_t: vec![INF; n * n],
            f5: vec![0; n + 1],
            bound: interior_lower_bounds(),
        };
        // split rows i+1 (previous) and i (current).
        let mut split_below = vec![INF; n];
        let mut split_here = vec![INF; n];
        for i in (0..n).rev() {
            split_here.fill(INF);
            for j in i + MIN_SPAN..n {
                let c = t.closed(i, j, split_below[j - 1]);
                t.c[i * n + j] = c;
                // Multiloop segments only exist strictly inside a closing pair.
                if i == 0 || j == n - 1 {
                    continue;
                }
                let mut fml = t
                    .ml_branch(i, j)
                    .min(t.fml[(i + 1) * n + j] + ML_BASE)
                    .min(t.fml[i * n + j - 1] + ML_BASE);
                if j > i + 2 * MIN_SPAN {
                    let left = &t.fml[i * n + i + MIN_SPAN..i * n + j - MIN_SPAN];
                    let right = &t.fml_t[j * n + i + MIN_SPAN + 1..j * n + j - MIN_SPAN + 1];
                    let split = min_sum(left, right);
                    split_here[j] = split;
                    fml = fml.min(split);
                }
                t.fml[i * n + j] = fml;
                t.fml_t[j * n + i] = fml;
            }
            std::mem::swap(&mut split_below, &mut split_here);
        }
        for l in 1..=n {
            let j = l - 1;
            let mut best = t.f5[j];
            for k in 0..(j + 1).saturating_sub(MIN_SPAN) {
                let c = t.c[k * n + j];
                if c < INF {
                    best = best.min(t.f5[k] + c + t.ext_stem(k, j));
                }
            }
            t.f5[l] = best;
        }
        t
    }

    /// Exterior-loop contribution of the helix closed by (k, j).
    fn ext_stem(&self, k: usize, j: usize) -> i32 {
        let s = self.s;
        stem(
            pair_type(s[k], s[j]),
            k.checked_sub(1).map(|x| s[x]),
            s.get(j + 1).copied(),
        )
    }

    /// c[i][j] plus the cost of (i, j) as a multiloop branch (INF if they cannot pair).
    fn ml_branch(&self, i: usize, j: usize) -> i32 {
        let c = self.c[i * self.n + j];
        if c >= INF {
            return INF;
        }
        c + ml_stem(pair_type(self.s[i], self.s[j]), self.s[i - 1], self.s[j + 1])
    }

    /// Energy of the multiloop closed by (i, j) around an inside of energy `inside`.
    fn multiloop(&self, i: usize, j: usize, inside: i32) -> i32 {
        let s = self.s;
        inside + ML_CLOSING + ml_stem(pair_type(s[j], s[i]), s[j - 1], s[i + 1])
    }

    /// c[i][j]; `multi_inside` is split[i+1][j-1].
    fn closed(&self, i: usize, j: usize, multi_inside: i32) -> i32 {
        let (s, n) = (self.s, self.n);
        let t = pair_type(s[i], s[j]);
        if t == NP {
            return INF;
        }
        let mut best = hairpin(s, i, j);
        for p in i + 1..=(i + MAXLOOP + 1).min(j.saturating_sub(MIN_SPAN + 1)) {
            let u1 = p - i - 1;
            let q_min = (p + MIN_SPAN).max((j - 1).saturating_sub(MAXLOOP - u1));
            let row = &self.c[p * n..p * n + j];
            let bound = &self.bound[u1];
            for q in (q_min..j).rev() {
                let cpq = row[q];
                // Pruning only skips candidates that cannot be strictly better, so the minimum
                // is unchanged (the traceback re-scans every candidate in order).
                if cpq + bound[j - q - 1] < best {
                    best = best.min(cpq + interior(s, i, j, p, q, t, pair_type(s[q], s[p])));
                }
            }
        }
        if multi_inside < INF {
            best = best.min(self.multiloop(i, j, multi_inside));
        }
        best
    }

    /// Pairs of one MFE structure, chosen among co-optimal ones in ViennaRNA's order.
    fn traceback(&self) -> Vec<(usize, usize)> {
        let (s, n) = (self.s, self.n);
        let mut pairs = Vec::new();
        let mut todo = Vec::new();
        let mut l = n;
        while l > MIN_SPAN {
            if self.f5[l] == self.f5[l - 1] {
                l -= 1;
                continue;
            }
            let j = l - 1;
            let k = (0..=j - MIN_SPAN)
                .rev()
                .find(|&k| {
                    let c = self.c[k * n + j];
                    c < INF && self.f5[k] + c + self.ext_stem(k, j) == self.f5[l]
                })
                .expect("f5 traceback: no decomposition reaches the table value");
            todo.push(Segment::Pair(k, j));
            l = k;
        }
        let fml = |i: usize, j: usize| if i < j { self.fml[i * n + j] } else { INF };
        while let Some(seg) = todo.pop() {
            match seg {
                Segment::Pair(i, j) => {
                    pairs.push((i, j));
                    let target = self.c[i * n + j];
                    if hairpin(s, i, j) == target {
                        continue;
                    }
                    if let Some((p, q)) = self.find_interior(i, j, target) {
                        todo.push(Segment::Pair(p, q));
                        continue;
                    }
                    let k = (i + 1 + MIN_SPAN..j - 1 - MIN_SPAN)
                        .find(|&k| self.multiloop(i, j, fml(i + 1, k) + fml(k + 1, j - 1)) == target)
                        .expect("c traceback: no decomposition reaches the table value");
                    todo.push(Segment::Multi(i + 1, k));
                    todo.push(Segment::Multi(k + 1, j - 1));
                }
                Segment::Multi(i, j) => {
                    let target = self.fml[i * n + j];
                    if fml(i, j - 1) + ML_BASE == target {
                        todo.push(Segment::Multi(i, j - 1));
                    } else if fml(i + 1, j) + ML_BASE == target {
                        todo.push(Segment::Multi(i + 1, j));
                    } else if self.ml_branch(i, j) == target {
                        todo.push(Segment::Pair(i, j));
                    } else {
                        let k = (i + MIN_SPAN..j - MIN_SPAN)
                            .find(|&k| fml(i, k) + fml(k + 1, j) == target)
                            .expect("fml traceback: no decomposition reaches the table value");
                        todo.push(Segment::Multi(i, k));
                        todo.push(Segment::Multi(k + 1, j));
                    }
                }
            }
        }
        pairs
    }

    fn find_interior(&self, i: usize, j: usize, target: i32) -> Option<(usize, usize)> {
        let (s, n) = (self.s, self.n);
        let t = pair_type(s[i], s[j]);
        for p in i + 1..=(i + MAXLOOP + 1).min(j.saturating_sub(MIN_SPAN + 1)) {
            let u1 = p - i - 1;
            let q_min = (p + MIN_SPAN).max((j - 1).saturating_sub(MAXLOOP - u1));
            for q in (q_min..j).rev() {
                let cpq = self.c[p * n + q];
                if cpq < INF && cpq + interior(s, i, j, p, q, t, pair_type(s[q], s[p])) == target {
                    return Some((p, q));
                }
            }
        }
        None
    }
}

enum Segment {
    /// (i, j) pair; decompose the loop it closes.
    Pair(usize, usize),
    /// fml[i][j]
    Multi(usize, usize),
}

/// min over k of a[k] + b[k] (INF when empty). A plain loop over equal-length slices, so the
/// compiler vectorises it.
#[inline]
fn min_sum(a: &[i32], b: &[i32]) -> i32 {
    a.iter().zip(b).fold(INF, |m, (&x, &y)| m.min(x + y))
}
