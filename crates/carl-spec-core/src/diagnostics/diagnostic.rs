//! One diagnostic: structured data first (rule id, file, JSON pointer, line/column), text second.

use std::fmt::Write as _;

use serde::Serialize;

use super::rules::Rule;
use crate::json::{LineIndex, Node};

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    Error,
    Warning,
}

/// Where in a source file a diagnostic points. Lines and columns are 1-based; columns count characters.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Location {
    pub line: usize,
    pub column: usize,
    pub end_line: usize,
    pub end_column: usize,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Diagnostic {
    pub severity: Severity,
    /// Stable rule id, e.g. `default-out-of-bounds`. Documented on the rules page (docs/reference/rules.md).
    pub rule: String,
    pub message: String,
    /// How to fix it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub help: Option<String>,
    /// File as given on the command line (or `bundled:<path>`).
    pub file: String,
    /// RFC 6901 pointer to the offending value inside the file ("" for the whole document).
    pub pointer: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub location: Option<Location>,
    /// The source line, for text rendering (not part of the JSON output).
    #[serde(skip)]
    pub snippet: Option<Snippet>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Snippet {
    pub line_text: String,
    /// Character offset of the underline within the line, and its length (≥ 1).
    pub start: usize,
    pub len: usize,
}

/// A parsed source file, able to turn pointers and byte offsets into locations.
#[derive(Debug, Clone)]
pub struct SourceFile {
    pub name: String,
    pub text: String,
    pub lines: LineIndex,
    pub root: Option<Node>,
}

impl SourceFile {
    pub fn new(name: String, text: String, root: Option<Node>) -> Self {
        let lines = LineIndex::new(&text);
        SourceFile {
            name,
            text,
            lines,
            root,
        }
    }

    /// Location and snippet of a byte range.
    pub fn locate_span(&self, start: usize, end: usize) -> (Location, Snippet) {
        let (line, column) = self.lines.line_col(&self.text, start);
        let (mut end_line, mut end_column) = self.lines.line_col(&self.text, end.max(start));
        if end <= start {
            (end_line, end_column) = (line, column + 1);
        }
        let line_text: String = self
            .lines
            .line_text(&self.text, line)
            .chars()
            .map(|c| if c.is_control() && c != '\t' { '\u{fffd}' } else { c })
            .collect();
        let line_text = line_text.as_str();
        let line_chars = line_text.chars().count();
        let start_char = column - 1;
        let len = if end_line == line {
            end_column.saturating_sub(column).max(1)
        } else {
            line_chars.saturating_sub(start_char).max(1)
        };
        // Very long lines (minified files) are cut around the underline.
        let (shown, start_char) = clip_line(line_text, start_char, 160);
        (
            Location {
                line,
                column,
                end_line,
                end_column,
            },
            Snippet {
                line_text: shown,
                start: start_char,
                len: len.min(120),
            },
        )
    }

    /// Locate a JSON pointer: the value it names, or its key when `on_key` (errors about a name).
    pub fn locate_pointer(&self, pointer: &str, on_key: bool) -> Option<(Location, Snippet)> {
        let root = self.root.as_ref()?;
        // Walk up to the nearest existing ancestor: a missing property is reported on its parent.
        let mut p = pointer.to_string();
        loop {
            if let Some((node, key)) = root.pointer_target(&p) {
                let span = match (on_key && p == pointer, key) {
                    (true, Some(k)) => k,
                    _ => node.span.clone(),
                };
                // Multi-line objects and arrays: underline only their opening bracket.
                let multiline = self.text.get(span.clone()).is_some_and(|t| t.contains('\n'));
                let end = if multiline { span.start + 1 } else { span.end };
                return Some(self.locate_span(span.start, end));
            }
            match p.rfind('/') {
                Some(i) => p.truncate(i),
                None => return None,
            }
        }
    }

    /// A located diagnostic of `rule` (`keyword` names the failed keyword of the schema family).
    pub fn diagnostic(
        &self,
        rule: &Rule,
        keyword: Option<&str>,
        pointer: &str,
        message: impl Into<String>,
        help: Option<String>,
    ) -> Diagnostic {
        let located = self.locate_pointer(pointer, rule.on_key);
        Diagnostic {
            severity: rule.severity,
            rule: rule.id_for(keyword),
            message: clean(&message.into()),
            help: help.as_deref().map(clean),
            file: self.name.clone(),
            pointer: pointer.to_string(),
            location: located.as_ref().map(|(l, _)| l.clone()),
            snippet: located.map(|(_, s)| s),
        }
    }

    /// The source text of the value at `pointer` (e.g. a number exactly as written).
    pub fn text_at(&self, pointer: &str) -> Option<&str> {
        let (node, _) = self.root.as_ref()?.pointer_target(pointer)?;
        self.text.get(node.span.clone())
    }
}

/// Messages quote input (names, values): terminal escapes are neutralised and runaway text cut.
fn clean(text: &str) -> String {
    crate::text::clean(text, MAX_MESSAGE_CHARS)
}

/// Longest message kept; input quoted into messages is cut far earlier (`text::quote`).
pub const MAX_MESSAGE_CHARS: usize = 1000;

fn clip_line(line: &str, start: usize, width: usize) -> (String, usize) {
    let n = line.chars().count();
    if n <= width {
        return (line.to_string(), start);
    }
    let from = start.saturating_sub(width / 2).min(n.saturating_sub(width));
    let shown: String = line.chars().skip(from).take(width).collect();
    (shown, start - from)
}

impl Diagnostic {
    /// A diagnostic about a file as a whole (I/O, encoding) or with no source to point into.
    pub fn file_level(rule: &Rule, file: &str, message: impl Into<String>, help: Option<String>) -> Self {
        Diagnostic {
            severity: rule.severity,
            rule: rule.id.to_string(),
            message: clean(&message.into()),
            help: help.as_deref().map(clean),
            file: file.to_string(),
            pointer: String::new(),
            location: None,
            snippet: None,
        }
    }

    /// Human rendering, in the style of rustc/miette.
    pub fn render_text(&self, color: bool) -> String {
        let (red, yellow, blue, bold, reset) = if color {
            ("\x1b[31m", "\x1b[33m", "\x1b[34m", "\x1b[1m", "\x1b[0m")
        } else {
            ("", "", "", "", "")
        };
        let (label, c) = match self.severity {
            Severity::Error => ("error", red),
            Severity::Warning => ("warning", yellow),
        };
        let mut out = String::new();
        let _ = writeln!(
            out,
            "{bold}{c}{label}[{}]{reset}{bold}: {}{reset}",
            self.rule, self.message
        );
        match &self.location {
            Some(loc) => {
                let gutter = loc.line.to_string().len();
                let pad = " ".repeat(gutter);
                let _ = writeln!(
                    out,
                    "{pad}{blue}-->{reset} {}:{}:{}",
                    crate::text::clean(&self.file, MAX_MESSAGE_CHARS),
                    loc.line,
                    loc.column
                );
                if let Some(s) = &self.snippet {
                    let _ = writeln!(out, "{pad} {blue}|{reset}");
                    let _ = writeln!(out, "{blue}{}{reset} {blue}|{reset} {}", loc.line, s.line_text);
                    let _ = writeln!(
                        out,
                        "{pad} {blue}|{reset} {}{c}{}{reset}",
                        " ".repeat(s.start),
                        "^".repeat(s.len)
                    );
                }
                if let Some(h) = &self.help {
                    let _ = writeln!(out, "{pad} {blue}={reset} {bold}help{reset}: {h}");
                }
            }
            None => {
                let _ = writeln!(
                    out,
                    "  {blue}-->{reset} {}",
                    crate::text::clean(&self.file, MAX_MESSAGE_CHARS)
                );
                if let Some(h) = &self.help {
                    let _ = writeln!(out, "   {blue}={reset} {bold}help{reset}: {h}");
                }
            }
        }
        out
    }

    /// A GitHub Actions workflow command (`::error file=…,line=…::message`).
    pub fn render_github(&self) -> String {
        let level = match self.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        };
        let mut props = format!("file={}", escape_gh_property(&self.file));
        if let Some(l) = &self.location {
            let _ = write!(
                props,
                ",line={},col={},endLine={},endColumn={}",
                l.line, l.column, l.end_line, l.end_column
            );
        }
        let _ = write!(
            props,
            ",title={}",
            escape_gh_property(&format!("carl-spec {}", self.rule))
        );
        let mut msg = self.message.clone();
        if let Some(h) = &self.help {
            msg.push_str("\nhelp: ");
            msg.push_str(h);
        }
        format!("::{level} {props}::{}", escape_gh_data(&msg))
    }
}

fn escape_gh_data(s: &str) -> String {
    s.replace('%', "%25").replace('\r', "%0D").replace('\n', "%0A")
}

fn escape_gh_property(s: &str) -> String {
    escape_gh_data(s).replace(':', "%3A").replace(',', "%2C")
}
