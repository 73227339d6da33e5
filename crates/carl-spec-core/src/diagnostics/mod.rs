//! Located diagnostics and the rule registry: the low layer that the spec language (resolution),
//! the validator and the loaders all report through. Depends only on `json` (source positions)
//! and `text` (quoting input).
//!
//! * [`rules`]: every rule id, declared once ([`Rule`]).
//! * [`diagnostic`]: one diagnostic, its location, and its text / GitHub renderings.
//! * [`Sink`]: collects diagnostics of a run against its files; [`Report`] is the outcome.

pub mod diagnostic;
pub mod rules;

use std::collections::BTreeMap;

pub use diagnostic::{Diagnostic, Location, Severity, Snippet, SourceFile};
pub use rules::Rule;

/// Files larger than this are refused: no spec is anywhere near it, and it bounds time and memory.
pub const MAX_FILE_BYTES: usize = 16 * 1024 * 1024;

/// At most this many diagnostics are kept per file (each costs a line/column lookup).
pub const MAX_DIAGNOSTICS_PER_FILE: usize = 200;

/// One spec document to validate.
#[derive(Debug, Clone)]
pub struct Input {
    /// Display name: the path as given, or `bundled:<path>`.
    pub name: String,
    pub bytes: Vec<u8>,
    /// Library inputs (bundled fragments offered to an author's specs) are only reported on when used.
    pub library: bool,
}

/// The outcome of a validation run.
#[derive(Debug, Clone, Default)]
pub struct Report {
    pub diagnostics: Vec<Diagnostic>,
    pub files_checked: usize,
    pub environments: usize,
}

impl Report {
    pub fn errors(&self) -> usize {
        self.diagnostics
            .iter()
            .filter(|d| d.severity == Severity::Error)
            .count()
    }
    pub fn warnings(&self) -> usize {
        self.diagnostics
            .iter()
            .filter(|d| d.severity == Severity::Warning)
            .count()
    }
    pub fn has_errors(&self) -> bool {
        self.errors() > 0
    }
    /// The document `carl-spec validate --format json` prints (and `cs.validate` reads).
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::json!({
            "valid": !self.has_errors(),
            "files": self.files_checked,
            "environments": self.environments,
            "errors": self.errors(),
            "warnings": self.warnings(),
            "diagnostics": self.diagnostics,
        })
    }
    /// All diagnostics rendered as text (no color), for error messages.
    pub fn render_text(&self) -> String {
        self.diagnostics
            .iter()
            .map(|d| d.render_text(false))
            .collect::<Vec<_>>()
            .join("\n")
    }
}

impl std::fmt::Display for Report {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.render_text())
    }
}

impl std::error::Error for Report {}

/// Collects diagnostics against the files of a run.
pub struct Sink<'a> {
    pub files: &'a [SourceFile],
    pub out: Vec<Diagnostic>,
    /// Diagnostics kept / dropped per file index.
    counts: BTreeMap<usize, (usize, usize)>,
}

impl<'a> Sink<'a> {
    /// A sink over `files`, starting with diagnostics found earlier (syntax, schema).
    pub fn new(files: &'a [SourceFile], early: Vec<Diagnostic>) -> Self {
        Sink {
            files,
            out: early,
            counts: BTreeMap::new(),
        }
    }

    /// Report a problem of `rule` at `pointer` in file `file` (severity is the rule's).
    pub fn report(
        &mut self,
        file: usize,
        rule: &Rule,
        pointer: &str,
        message: impl Into<String>,
        help: Option<String>,
    ) {
        let c = self.counts.entry(file).or_default();
        if c.0 >= MAX_DIAGNOSTICS_PER_FILE {
            c.1 += 1;
            return;
        }
        c.0 += 1;
        let d = self.files[file].diagnostic(rule, None, pointer, message, help);
        self.out.push(d);
    }

    /// The number at `pointer` as written in file `file` (falls back to `value`'s shortest form).
    pub fn number_text(&self, file: usize, pointer: &str, value: f64) -> String {
        crate::text::number(self.files.get(file).and_then(|f| f.text_at(pointer)), value)
    }

    /// One closing note per file whose diagnostics were cut.
    pub fn finish(mut self) -> Vec<Diagnostic> {
        for (&file, &(_, dropped)) in &self.counts {
            if dropped > 0 {
                self.out.push(Diagnostic::file_level(
                    &rules::TOO_MANY_PROBLEMS,
                    &self.files[file].name,
                    format!("{dropped} more problem(s) in this file not shown"),
                    Some("fix the ones above and run again".into()),
                ));
            }
        }
        self.out
    }
}
