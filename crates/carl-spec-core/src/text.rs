//! Quoting text that came from input (file contents, names, command-line values) into messages.
//!
//! Anything a user or a file supplied may hold terminal escapes or be megabytes long. Every message
//! that repeats such text goes through [`quote`] (with quotes) or [`escape`] (without): control
//! characters become visible escapes, and long input is cut to a prefix that says how long it was.
//! This module depends on nothing else in the crate, so every layer can use it.

use std::fmt::Write as _;

/// Characters of input shown before it is cut.
pub const MAX_SHOWN_CHARS: usize = 80;

/// `text` in double quotes, escaped and cut: `"mass"`, `"a\u{1b}[31m"`, `"12345…" (100000 bytes)`.
pub fn quote(text: &str) -> String {
    let (shown, cut) = escape_cut(text, MAX_SHOWN_CHARS);
    if cut {
        format!("\"{shown}…\" ({} bytes)", text.len())
    } else {
        format!("\"{shown}\"")
    }
}

/// `text` escaped and cut like [`quote`], without the quotes (for numbers and file names).
pub fn escape(text: &str) -> String {
    let (shown, cut) = escape_cut(text, MAX_SHOWN_CHARS);
    if cut {
        format!("{shown}… ({} bytes)", text.len())
    } else {
        shown
    }
}

/// Escape control characters (C0, DEL, C1, and the bidirectional overrides that reorder what a
/// terminal shows) and `"`/`\`, keeping at most `max_chars` characters of the input.
fn escape_cut(text: &str, max_chars: usize) -> (String, bool) {
    let mut out = String::with_capacity(text.len().min(max_chars * 2));
    for (n, c) in text.chars().enumerate() {
        if n == max_chars {
            return (out, true);
        }
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if is_unsafe(c) => {
                let _ = write!(out, "\\u{{{:x}}}", c as u32);
            }
            c => out.push(c),
        }
    }
    (out, false)
}

/// Characters a terminal may interpret instead of showing.
fn is_unsafe(c: char) -> bool {
    c.is_control() || matches!(c, '\u{200e}' | '\u{200f}' | '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}')
}

/// A whole message (already composed) made safe to print: characters a terminal would interpret
/// are escaped, line breaks kept, and a message longer than `max_chars` is cut. The safety net
/// behind [`quote`] for any text that reaches a terminal.
pub fn clean(message: &str, max_chars: usize) -> String {
    let mut out = String::with_capacity(message.len().min(max_chars + 16));
    for (n, c) in message.chars().enumerate() {
        if n == max_chars {
            let _ = write!(out, "… ({} bytes)", message.len());
            break;
        }
        match c {
            '\n' | '\t' => out.push(c),
            c if is_unsafe(c) => {
                let _ = write!(out, "\\u{{{:x}}}", c as u32);
            }
            c => out.push(c),
        }
    }
    out
}

/// A number as written in the source, when the source is at hand, else Rust's shortest round-trip
/// form. `9223372036854775807` stays that, not `9223372036854776000`.
pub fn number(literal: Option<&str>, value: f64) -> String {
    match literal {
        Some(l) if !l.is_empty() => escape(l.trim()),
        _ => value.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn control_characters_are_escaped() {
        assert_eq!(quote("a\u{1b}[31mb"), "\"a\\u{1b}[31mb\"");
        assert_eq!(quote("x\ny"), "\"x\\ny\"");
        assert_eq!(quote("\u{202e}abc"), "\"\\u{202e}abc\"");
        assert_eq!(quote("say \"hi\""), "\"say \\\"hi\\\"\"");
        assert!(!quote("\u{7}\u{9b}").chars().any(char::is_control));
    }

    #[test]
    fn long_input_is_cut_with_its_length() {
        let digits = "7".repeat(100_000);
        let q = quote(&digits);
        assert!(q.len() < 120, "{q}");
        assert!(q.ends_with("…\" (100000 bytes)"), "{q}");
        let two_mb = "x".repeat(2 << 20);
        assert!(escape(&two_mb).ends_with(&format!("… ({} bytes)", 2 << 20)));
        assert_eq!(
            quote(&"y".repeat(MAX_SHOWN_CHARS)),
            format!("\"{}\"", "y".repeat(MAX_SHOWN_CHARS))
        );
    }

    #[test]
    fn messages_are_cleaned() {
        assert_eq!(clean("bad \u{1b}[2J name\nnext", 100), "bad \\u{1b}[2J name\nnext");
        assert!(clean(&"z".repeat(5000), 100).ends_with("… (5000 bytes)"));
    }

    #[test]
    fn numbers_keep_their_literal() {
        assert_eq!(
            number(Some("9223372036854775807"), 9.223372036854776e18),
            "9223372036854775807"
        );
        assert_eq!(number(None, 0.5), "0.5");
    }
}
