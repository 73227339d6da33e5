//! A strict JSON (RFC 8259) parser that keeps the byte span of every value and key.
//!
//! serde_json throws spans away; the validator needs them to point at `file:line:col`. This parser
//! is iterative-free but depth-limited, so hostile input (deeply nested arrays, huge files,
//! binary garbage) yields an error instead of a stack overflow or a hang.

use std::ops::Range;

use super::{Member, Node, NodeKind};

/// Nesting deeper than this is refused (serde_json uses 128 too).
pub const MAX_DEPTH: usize = 128;

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParseError {
    /// Byte offset where the problem is.
    pub offset: usize,
    pub message: String,
}

pub fn parse(text: &str) -> Result<Node, ParseError> {
    let mut p = Parser {
        src: text.as_bytes(),
        text,
        pos: 0,
    };
    // A UTF-8 byte-order mark is tolerated: some editors on Windows write it.
    if text.starts_with('\u{feff}') {
        p.pos = 3;
    }
    p.skip_ws();
    let node = p.value(0)?;
    p.skip_ws();
    if p.pos < p.src.len() {
        return Err(p.err("unexpected content after the end of the JSON document"));
    }
    Ok(node)
}

struct Parser<'a> {
    src: &'a [u8],
    text: &'a str,
    pos: usize,
}

impl<'a> Parser<'a> {
    fn err(&self, message: impl Into<String>) -> ParseError {
        ParseError {
            offset: self.pos.min(self.src.len()),
            message: message.into(),
        }
    }

    fn peek(&self) -> Option<u8> {
        self.src.get(self.pos).copied()
    }

    fn skip_ws(&mut self) {
        while let Some(b' ' | b'\t' | b'\n' | b'\r') = self.peek() {
            self.pos += 1;
        }
    }

    fn value(&mut self, depth: usize) -> Result<Node, ParseError> {
        if depth > MAX_DEPTH {
            return Err(self.err(format!("nesting deeper than {MAX_DEPTH} levels")));
        }
        let start = self.pos;
        let kind = match self.peek() {
            None => return Err(self.err("unexpected end of input: a value is missing")),
            Some(b'{') => self.object(depth)?,
            Some(b'[') => self.array(depth)?,
            Some(b'"') => NodeKind::String(self.string()?),
            Some(b't') => self.literal("true", NodeKind::Bool(true))?,
            Some(b'f') => self.literal("false", NodeKind::Bool(false))?,
            Some(b'n') => self.literal("null", NodeKind::Null)?,
            Some(b'-' | b'0'..=b'9') => self.number()?,
            Some(b'N') | Some(b'I') => {
                return Err(self.err("NaN and Infinity are not JSON; write a number, or null for an open bound"));
            }
            Some(b'/') => return Err(self.err("comments are not allowed in JSON spec files")),
            Some(b'\'') => return Err(self.err("strings must use double quotes")),
            Some(_) => return Err(self.err(format!("unexpected {}", self.describe_here()))),
        };
        Ok(Node {
            span: start..self.pos,
            kind,
        })
    }

    fn describe_here(&self) -> String {
        match self.text.get(self.pos..).and_then(|s| s.chars().next()) {
            Some(c) if !c.is_control() => format!("character '{c}'"),
            Some(c) => format!("control character U+{:04X}", c as u32),
            None => "end of input".to_string(),
        }
    }

    fn literal(&mut self, word: &str, kind: NodeKind) -> Result<NodeKind, ParseError> {
        if self.src[self.pos..].starts_with(word.as_bytes()) {
            self.pos += word.len();
            Ok(kind)
        } else {
            Err(self.err(format!("unexpected {}: expected a JSON value", self.describe_here())))
        }
    }

    fn object(&mut self, depth: usize) -> Result<NodeKind, ParseError> {
        self.pos += 1; // '{'
        let mut members = Vec::new();
        self.skip_ws();
        if self.peek() == Some(b'}') {
            self.pos += 1;
            return Ok(NodeKind::Object(members));
        }
        loop {
            self.skip_ws();
            if self.peek() != Some(b'"') {
                return Err(if self.peek() == Some(b'}') {
                    self.err("trailing comma before '}'")
                } else {
                    self.err(format!(
                        "expected a property name in double quotes, found {}",
                        self.describe_here()
                    ))
                });
            }
            let key_start = self.pos;
            let key = self.string()?;
            let key_span: Range<usize> = key_start..self.pos;
            self.skip_ws();
            if self.peek() != Some(b':') {
                return Err(self.err(format!("expected ':' after the property name \"{key}\"")));
            }
            self.pos += 1;
            self.skip_ws();
            let value = self.value(depth + 1)?;
            members.push(Member { key, key_span, value });
            self.skip_ws();
            match self.peek() {
                Some(b',') => self.pos += 1,
                Some(b'}') => {
                    self.pos += 1;
                    return Ok(NodeKind::Object(members));
                }
                None => return Err(self.err("unexpected end of input: an object is not closed with '}'")),
                _ => return Err(self.err(format!("expected ',' or '}}', found {}", self.describe_here()))),
            }
        }
    }

    fn array(&mut self, depth: usize) -> Result<NodeKind, ParseError> {
        self.pos += 1; // '['
        let mut items = Vec::new();
        self.skip_ws();
        if self.peek() == Some(b']') {
            self.pos += 1;
            return Ok(NodeKind::Array(items));
        }
        loop {
            self.skip_ws();
            if self.peek() == Some(b']') {
                return Err(self.err("trailing comma before ']'"));
            }
            items.push(self.value(depth + 1)?);
            self.skip_ws();
            match self.peek() {
                Some(b',') => self.pos += 1,
                Some(b']') => {
                    self.pos += 1;
                    return Ok(NodeKind::Array(items));
                }
                None => return Err(self.err("unexpected end of input: an array is not closed with ']'")),
                _ => return Err(self.err(format!("expected ',' or ']', found {}", self.describe_here()))),
            }
        }
    }

    fn string(&mut self) -> Result<String, ParseError> {
        self.pos += 1; // opening quote
        let mut out = String::new();
        loop {
            let run_start = self.pos;
            while let Some(b) = self.peek() {
                if b == b'"' || b == b'\\' || b < 0x20 {
                    break;
                }
                self.pos += 1;
            }
            // The input is a &str, and we only stop at ASCII bytes, so this slice is valid UTF-8.
            out.push_str(&self.text[run_start..self.pos]);
            match self.peek() {
                None => return Err(self.err("unexpected end of input inside a string")),
                Some(b'"') => {
                    self.pos += 1;
                    return Ok(out);
                }
                Some(b'\\') => {
                    self.pos += 1;
                    self.escape(&mut out)?;
                }
                Some(_) => {
                    return Err(self.err("control character inside a string: escape it (e.g. \\n, \\t)"));
                }
            }
        }
    }

    fn escape(&mut self, out: &mut String) -> Result<(), ParseError> {
        let c = match self.peek() {
            Some(b'"') => '"',
            Some(b'\\') => '\\',
            Some(b'/') => '/',
            Some(b'b') => '\u{8}',
            Some(b'f') => '\u{c}',
            Some(b'n') => '\n',
            Some(b'r') => '\r',
            Some(b't') => '\t',
            Some(b'u') => {
                self.pos += 1;
                let hi = self.hex4()?;
                let c = if (0xD800..0xDC00).contains(&hi) {
                    if !self.src[self.pos..].starts_with(b"\\u") {
                        return Err(self.err("unpaired UTF-16 surrogate in \\u escape"));
                    }
                    self.pos += 2;
                    let lo = self.hex4()?;
                    if !(0xDC00..0xE000).contains(&lo) {
                        return Err(self.err("invalid UTF-16 low surrogate in \\u escape"));
                    }
                    char::from_u32(0x10000 + ((hi - 0xD800) << 10) + (lo - 0xDC00))
                } else {
                    char::from_u32(hi)
                };
                out.push(c.ok_or_else(|| self.err("invalid \\u escape (lone surrogate)"))?);
                return Ok(());
            }
            _ => return Err(self.err("invalid escape sequence in string")),
        };
        out.push(c);
        self.pos += 1;
        Ok(())
    }

    fn hex4(&mut self) -> Result<u32, ParseError> {
        let digits = self
            .src
            .get(self.pos..self.pos + 4)
            .ok_or_else(|| self.err("unexpected end of input in \\u escape"))?;
        let mut v = 0u32;
        for &d in digits {
            let x = (d as char)
                .to_digit(16)
                .ok_or_else(|| self.err("\\u escape needs four hex digits"))?;
            v = v * 16 + x;
        }
        self.pos += 4;
        Ok(v)
    }

    fn number(&mut self) -> Result<NodeKind, ParseError> {
        let start = self.pos;
        if self.peek() == Some(b'-') {
            self.pos += 1;
        }
        match self.peek() {
            Some(b'0') => {
                self.pos += 1;
                if matches!(self.peek(), Some(b'0'..=b'9')) {
                    return Err(self.err("leading zeros are not allowed in JSON numbers"));
                }
            }
            Some(b'1'..=b'9') => self.digits(),
            Some(b'I') => {
                return Err(self.err("-Infinity is not JSON; use null for an open bound"));
            }
            _ => return Err(self.err("a digit must follow '-'")),
        }
        let mut integer = true;
        if self.peek() == Some(b'.') {
            integer = false;
            self.pos += 1;
            if !matches!(self.peek(), Some(b'0'..=b'9')) {
                return Err(self.err("a digit must follow the decimal point"));
            }
            self.digits();
        }
        if matches!(self.peek(), Some(b'e' | b'E')) {
            integer = false;
            self.pos += 1;
            if matches!(self.peek(), Some(b'+' | b'-')) {
                self.pos += 1;
            }
            if !matches!(self.peek(), Some(b'0'..=b'9')) {
                return Err(self.err("a digit must follow the exponent"));
            }
            self.digits();
        }
        let lexeme = &self.text[start..self.pos];
        let value: f64 = lexeme.parse().map_err(|_| ParseError {
            offset: start,
            message: format!("invalid number {lexeme}"),
        })?;
        if !value.is_finite() {
            return Err(ParseError {
                offset: start,
                message: format!("number {lexeme} is out of the range of a 64-bit float"),
            });
        }
        let int = if integer { lexeme.parse::<i128>().ok() } else { None };
        Ok(NodeKind::Number { value, int })
    }

    fn digits(&mut self) {
        while matches!(self.peek(), Some(b'0'..=b'9')) {
            self.pos += 1;
        }
    }
}
