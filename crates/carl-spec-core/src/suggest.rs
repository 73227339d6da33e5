//! "Did you mean …?" for unknown names (edit distance, case-insensitive).

/// The closest known name, if it is close enough to be a plausible typo.
pub fn did_you_mean<'a>(name: &str, known: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let lower = name.to_lowercase();
    let mut best: Option<(usize, &str)> = None;
    for k in known {
        let d = distance(&lower, &k.to_lowercase());
        if best.is_none_or(|(bd, _)| d < bd) {
            best = Some((d, k));
        }
    }
    let (d, k) = best?;
    let limit = (name.chars().count() / 3).max(2);
    (d <= limit || k.to_lowercase().contains(&lower) || lower.contains(&k.to_lowercase())).then_some(k)
}

/// Levenshtein distance over chars; inputs are short names, so O(n·m) is fine.
pub fn distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    let mut cur = vec![0; b.len() + 1];
    for (i, ca) in a.chars().enumerate() {
        cur[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let sub = prev[j] + usize::from(ca != *cb);
            cur[j + 1] = sub.min(prev[j + 1] + 1).min(cur[j] + 1);
        }
        std::mem::swap(&mut prev, &mut cur);
    }
    prev[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggests_close_names_only() {
        let known = ["gravity", "masscart", "masspole", "pole_length"];
        assert_eq!(did_you_mean("gravty", known), Some("gravity"));
        assert_eq!(did_you_mean("MASSCART", known), Some("masscart"));
        assert_eq!(did_you_mean("length", known), Some("pole_length"));
        assert_eq!(did_you_mean("zzzzzz", known), None);
        assert_eq!(distance("kitten", "sitting"), 3);
    }
}
