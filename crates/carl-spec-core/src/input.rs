//! Reading input with a size limit: a file, `/dev/zero` or an endless pipe is read only up to the
//! limit (plus one byte, to tell "exactly the limit" from "more"), never whole into memory first.
//! The error names what was read and the limit.
//!
//! This module depends on nothing else in the crate.

use std::io::{BufRead, Read};
use std::path::Path;

/// Input longer than its limit, or unreadable, or not UTF-8.
#[derive(Debug, thiserror::Error)]
pub enum InputError {
    #[error("{what} is longer than the limit of {limit} bytes; {hint}")]
    TooLong {
        what: String,
        limit: u64,
        hint: &'static str,
    },
    #[error("cannot read {what}: {source}")]
    Io { what: String, source: std::io::Error },
    #[error("{what} is not UTF-8 text")]
    NotUtf8 { what: String },
}

/// Read all of `reader` as UTF-8, refusing more than `limit` bytes (`what` names the input in
/// errors, `hint` says what to do instead).
pub fn read_to_string(reader: impl Read, limit: u64, what: &str, hint: &'static str) -> Result<String, InputError> {
    let mut bytes = Vec::new();
    reader
        .take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|source| InputError::Io {
            what: what.to_string(),
            source,
        })?;
    if bytes.len() as u64 > limit {
        return Err(InputError::TooLong {
            what: what.to_string(),
            limit,
            hint,
        });
    }
    String::from_utf8(bytes).map_err(|_| InputError::NotUtf8 { what: what.to_string() })
}

/// [`read_to_string`] of the file at `path` (named by its path in errors).
pub fn read_file(path: &Path, limit: u64, hint: &'static str) -> Result<String, InputError> {
    let what = crate::text::escape(&path.display().to_string());
    let file = std::fs::File::open(path).map_err(|source| InputError::Io {
        what: what.clone(),
        source,
    })?;
    read_to_string(file, limit, &what, hint)
}

/// Read one line (up to and including `\n`) into `line` (cleared first), refusing a line of more
/// than `limit` bytes: at most `limit + 1` bytes are read. Returns the bytes read; 0 at the end.
pub fn read_line(
    reader: &mut impl BufRead,
    line: &mut String,
    limit: u64,
    what: &str,
    hint: &'static str,
) -> Result<usize, InputError> {
    line.clear();
    let mut bytes = Vec::new();
    let n = reader
        .by_ref()
        .take(limit.saturating_add(1))
        .read_until(b'\n', &mut bytes)
        .map_err(|source| InputError::Io {
            what: what.to_string(),
            source,
        })?;
    let content = bytes.strip_suffix(b"\n").unwrap_or(&bytes);
    if content.len() as u64 > limit {
        return Err(InputError::TooLong {
            what: what.to_string(),
            limit,
            hint,
        });
    }
    line.push_str(std::str::from_utf8(&bytes).map_err(|_| InputError::NotUtf8 { what: what.to_string() })?);
    Ok(n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn endless_input_is_cut_at_the_limit() {
        let zeros = std::io::repeat(0);
        let e = read_to_string(zeros, 1000, "stdin", "split it")
            .unwrap_err()
            .to_string();
        assert_eq!(e, "stdin is longer than the limit of 1000 bytes; split it");
        assert_eq!(read_to_string(&b"abc"[..], 3, "x", "").unwrap(), "abc");
        assert!(read_to_string(&b"abcd"[..], 3, "x", "").is_err());
        assert!(matches!(
            read_to_string(&[0xff, 0xfe][..], 3, "x", ""),
            Err(InputError::NotUtf8 { .. })
        ));
    }

    #[test]
    fn lines_are_cut_at_the_limit() {
        let mut line = String::new();
        let mut r = std::io::BufReader::new(&b"12345\n1234\n123456"[..]);
        assert_eq!(read_line(&mut r, &mut line, 5, "line", "").unwrap(), 6);
        assert_eq!(line, "12345\n");
        assert_eq!(read_line(&mut r, &mut line, 5, "line", "").unwrap(), 5);
        assert_eq!(line, "1234\n");
        let e = read_line(&mut r, &mut line, 5, "action line", "one per line").unwrap_err();
        assert_eq!(
            e.to_string(),
            "action line is longer than the limit of 5 bytes; one per line"
        );
        let mut endless = std::io::BufReader::new(std::io::repeat(b'x'));
        assert!(read_line(&mut endless, &mut line, 1 << 20, "line", "").is_err());
        let mut empty = std::io::BufReader::new(&b""[..]);
        assert_eq!(read_line(&mut empty, &mut line, 5, "line", "").unwrap(), 0);
    }
}
