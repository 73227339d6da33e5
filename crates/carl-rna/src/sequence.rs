//! Parsing of RNA sequences and dot-bracket structures into the coded forms the algorithms use.

use crate::RnaError;

/// Longest sequence accepted: the DP keeps three n×n tables of i32 (12·n² bytes, 183 MiB at
/// this length) and runs in O(n³) time.
pub const MAX_LEN: usize = 4000;

/// Bases coded A=0, C=1, G=2, U=3. `T` is read as `U`, lower case as upper case (as RNAfold does).
pub fn encode(seq: &str) -> Result<Vec<u8>, RnaError> {
    let len = seq.chars().count();
    if len > MAX_LEN {
        return Err(RnaError::TooLong { len, max: MAX_LEN });
    }
    seq.chars()
        .enumerate()
        .map(|(pos, ch)| match ch.to_ascii_uppercase() {
            'A' => Ok(0),
            'C' => Ok(1),
            'G' => Ok(2),
            'U' | 'T' => Ok(3),
            _ => Err(RnaError::InvalidBase { pos: pos + 1, ch }),
        })
        .collect()
}

/// Canonical spelling (upper case, `T` → `U`) of a sequence [`encode`] accepted.
pub fn decode(codes: &[u8]) -> String {
    codes.iter().map(|&c| b"ACGU"[c as usize] as char).collect()
}

/// Partner of every position (`None` when unpaired), 0-based, from a dot-bracket of `len`
/// characters (`.` unpaired, `(`/`)` pairs; anything else is an error).
pub fn pair_table(structure: &str, len: usize) -> Result<Vec<Option<usize>>, RnaError> {
    let got = structure.chars().count();
    if got != len {
        return Err(RnaError::LengthMismatch {
            sequence: len,
            structure: got,
        });
    }
    let mut table = vec![None; len];
    let mut open = Vec::new();
    for (pos, ch) in structure.chars().enumerate() {
        match ch {
            '.' => {}
            '(' => open.push(pos),
            ')' => {
                let i = open.pop().ok_or(RnaError::UnbalancedClose { pos: pos + 1 })?;
                table[i] = Some(pos);
                table[pos] = Some(i);
            }
            _ => return Err(RnaError::InvalidStructureChar { pos: pos + 1, ch }),
        }
    }
    if let Some(&i) = open.last() {
        return Err(RnaError::UnbalancedOpen { pos: i + 1 });
    }
    Ok(table)
}

/// Dot-bracket of a set of pairs (0-based, non-crossing).
pub fn dot_bracket(len: usize, pairs: &[(usize, usize)]) -> String {
    let mut s = vec![b'.'; len];
    for &(i, j) in pairs {
        s[i] = b'(';
        s[j] = b')';
    }
    String::from_utf8(s).expect("ASCII")
}
