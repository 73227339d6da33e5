//! Reading sequences (and structures) from text the way RNAfold/RNAeval accept it: FASTA
//! (`>name` header, then the record's lines) or bare lines without headers.

/// One input record: its FASTA name (if any) and its non-empty lines, trimmed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Record {
    pub name: Option<String>,
    pub lines: Vec<String>,
}

/// Splits `text` into records. With `>` headers, a record is a header and the lines up to the
/// next header; without, every group of `lines_per_record` consecutive non-empty lines is one
/// (1 for sequences, 2 for sequence + structure). Blank lines and `;` comments are ignored.
pub fn records(text: &str, lines_per_record: usize) -> Vec<Record> {
    let lines = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with(';'));
    let mut out: Vec<Record> = Vec::new();
    let mut headerless = Vec::new();
    for line in lines {
        if let Some(name) = line.strip_prefix('>') {
            out.push(Record {
                name: Some(name.trim().to_string()),
                lines: Vec::new(),
            });
        } else if let Some(last) = out.last_mut() {
            last.lines.push(line.to_string());
        } else {
            headerless.push(line.to_string());
        }
    }
    let mut bare: Vec<Record> = headerless
        .chunks(lines_per_record.max(1))
        .map(|c| Record {
            name: None,
            lines: c.to_vec(),
        })
        .collect();
    bare.extend(out);
    bare
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fasta_records_join_under_their_header() {
        let r = records(">a first\nGGGG\nAAAC\n\n>b\nCCCC\n", 1);
        assert_eq!(r.len(), 2);
        assert_eq!(r[0].name.as_deref(), Some("a first"));
        assert_eq!(r[0].lines, ["GGGG", "AAAC"]);
        assert_eq!(r[1].lines, ["CCCC"]);
    }

    #[test]
    fn bare_lines_group_by_record_size() {
        let r = records("GGGAAACCC\n(((...)))\nGGGGAAAACCCC\n((((....))))\n", 2);
        assert_eq!(r.len(), 2);
        assert_eq!(r[1].lines, ["GGGGAAAACCCC", "((((....))))"]);
        assert_eq!(records("A\n\nC\n", 1).len(), 2);
    }
}
