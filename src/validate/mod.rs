//! The validator: syntax → JSON Schema → typed model → resolution → semantic rules.
//!
//! Every problem in every file is collected (never stop at the first), each as a located
//! [`Diagnostic`] with a stable rule id. `SpecSet::load` runs the same pipeline, so anything the
//! library accepts has passed validation.

pub mod diagnostic;
mod rules;
pub use rules::value_text;
pub mod schema_check;

use std::collections::BTreeMap;

pub use diagnostic::{Diagnostic, Location, Severity, SourceFile};

use crate::json::{self, Node, NodeKind};
use crate::spec::raw::{RawDocument, RawEnvSpec, RawFragment};
use crate::spec::resolve::{FragmentEntry, Resolved, resolve};
use schema_check::SchemaChecker;

/// Files larger than this are refused: no spec is anywhere near it, and it bounds time and memory.
pub const MAX_FILE_BYTES: usize = 16 * 1024 * 1024;

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

/// At most this many diagnostics are kept per file (each costs a line/column lookup).
pub const MAX_DIAGNOSTICS_PER_FILE: usize = 200;

/// Collects diagnostics against the files of a run.
pub struct Sink<'a> {
    pub files: &'a [SourceFile],
    pub out: Vec<Diagnostic>,
    /// Diagnostics kept / dropped per file index.
    counts: BTreeMap<usize, (usize, usize)>,
}

impl Sink<'_> {
    pub fn error(&mut self, file: usize, rule: &str, pointer: &str, message: impl Into<String>, help: Option<String>) {
        self.push(Severity::Error, file, rule, pointer, message, help);
    }
    pub fn warning(
        &mut self,
        file: usize,
        rule: &str,
        pointer: &str,
        message: impl Into<String>,
        help: Option<String>,
    ) {
        self.push(Severity::Warning, file, rule, pointer, message, help);
    }
    fn push(
        &mut self,
        sev: Severity,
        file: usize,
        rule: &str,
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
        let d = self.files[file].diagnostic(sev, rule, pointer, message, help);
        self.out.push(d);
    }

    /// One closing note per file whose diagnostics were cut.
    fn finish(mut self) -> Vec<Diagnostic> {
        for (&file, &(_, dropped)) in &self.counts {
            if dropped > 0 {
                self.out.push(Diagnostic::file_level(
                    Severity::Error,
                    "too-many-problems",
                    &self.files[file].name,
                    format!("{dropped} more problem(s) in this file not shown"),
                    Some("fix the ones above and run again".into()),
                ));
            }
        }
        self.out
    }
}

/// Validate a set of documents and return the resolved environment specs of the valid ones.
pub fn run(inputs: &[Input]) -> (Vec<Resolved>, Report) {
    let checker = match schema_check::shared() {
        Ok(c) => c,
        Err(e) => {
            let d = Diagnostic::file_level(Severity::Error, "internal", "<schema>", e, None);
            return (
                Vec::new(),
                Report {
                    diagnostics: vec![d],
                    ..Default::default()
                },
            );
        }
    };
    let mut early: Vec<Diagnostic> = Vec::new();
    let mut files: Vec<SourceFile> = Vec::with_capacity(inputs.len());
    let mut docs: Vec<Option<RawDocument>> = Vec::with_capacity(inputs.len());
    for input in inputs {
        let (file, doc, mut diags) = check_document(input, checker);
        files.push(file);
        docs.push(doc);
        early.append(&mut diags);
    }

    // Early (per-document) diagnostics are capped too.
    let mut per_file: BTreeMap<String, usize> = BTreeMap::new();
    early.retain(|d| {
        let n = per_file.entry(d.file.clone()).or_default();
        *n += 1;
        *n <= MAX_DIAGNOSTICS_PER_FILE
    });
    let mut sink = Sink {
        files: &files,
        out: early,
        counts: BTreeMap::new(),
    };

    // Fragments: authors' own shadow the bundled library; duplicates among one kind are errors.
    let mut fragments: BTreeMap<String, FragmentEntry<'_>> = BTreeMap::new();
    let mut order: Vec<usize> = (0..inputs.len()).collect();
    order.sort_by_key(|&i| !inputs[i].library); // library first, so authors' files replace them
    for &i in &order {
        if let Some(RawDocument::Fragment(frag)) = &docs[i] {
            if let Some(prev) = fragments.get(&frag.fragment)
                && inputs[prev.file].library == inputs[i].library
            {
                sink.error(
                    i,
                    "duplicate-fragment",
                    "/fragment",
                    format!(
                        "fragment \"{}\" is also defined in {}",
                        frag.fragment, files[prev.file].name
                    ),
                    Some("give one of them another name".into()),
                );
                continue;
            }
            rules::check_fragment(frag, i, &mut sink);
            fragments.insert(
                frag.fragment.clone(),
                FragmentEntry {
                    fragment: frag,
                    file: i,
                },
            );
        }
    }

    let mut resolved: Vec<Resolved> = Vec::new();
    for (i, doc) in docs.iter().enumerate() {
        if let Some(RawDocument::Environment(raw)) = doc {
            let raw: &RawEnvSpec = raw;
            resolved.push(resolve(raw, i, &inputs[i].name, &fragments, &mut sink));
        }
    }
    for r in &resolved {
        rules::check_env(r, &mut sink);
    }
    rules::check_set(&resolved, &mut sink);

    // Library diagnostics only matter if an author's file uses them; bundled specs are tested anyway.
    let mut diagnostics = sink.finish();
    let library_names: Vec<&str> = inputs.iter().filter(|i| i.library).map(|i| i.name.as_str()).collect();
    diagnostics.retain(|d| !library_names.contains(&d.file.as_str()));
    diagnostics.sort_by(|a, b| {
        let la = a.location.as_ref().map(|l| (l.line, l.column));
        let lb = b.location.as_ref().map(|l| (l.line, l.column));
        (&a.file, la, &a.rule).cmp(&(&b.file, lb, &b.rule))
    });
    let report = Report {
        diagnostics,
        files_checked: inputs.iter().filter(|i| !i.library).count(),
        environments: resolved.len(),
    };
    (resolved, report)
}

/// Syntax, duplicate keys, schema and typed deserialization of one file.
fn check_document(input: &Input, checker: &SchemaChecker) -> (SourceFile, Option<RawDocument>, Vec<Diagnostic>) {
    let name = input.name.clone();
    if input.bytes.len() > MAX_FILE_BYTES {
        let d = Diagnostic::file_level(
            Severity::Error,
            "file-too-large",
            &name,
            format!(
                "file is {} bytes; spec files are limited to {} bytes",
                input.bytes.len(),
                MAX_FILE_BYTES
            ),
            Some("is this really a spec file? split it, or check the path".into()),
        );
        return (SourceFile::new(name, String::new(), None), None, vec![d]);
    }
    let text = match std::str::from_utf8(&input.bytes) {
        Ok(t) => t.to_string(),
        Err(e) => {
            let text = String::from_utf8_lossy(&input.bytes).into_owned();
            let valid = String::from_utf8_lossy(&input.bytes[..e.valid_up_to()]).len();
            let file = SourceFile::new(name.clone(), text, None);
            let (loc, snip) = file.locate_span(valid, valid + 1);
            let d = Diagnostic {
                location: Some(loc),
                snippet: Some(snip),
                ..Diagnostic::file_level(
                    Severity::Error,
                    "not-utf8",
                    &name,
                    format!("invalid UTF-8 at byte {}: spec files are UTF-8 JSON", e.valid_up_to()),
                    Some("is this a binary file? re-save it as UTF-8".into()),
                )
            };
            return (file, None, vec![d]);
        }
    };
    let root = match json::parse(&text) {
        Ok(root) => root,
        Err(e) => {
            let file = SourceFile::new(name.clone(), text, None);
            let (loc, snip) = file.locate_span(e.offset, e.offset + 1);
            let d = Diagnostic {
                location: Some(loc),
                snippet: Some(snip),
                ..Diagnostic::file_level(
                    Severity::Error,
                    "json-syntax",
                    &name,
                    e.message,
                    Some("fix the JSON syntax here".into()),
                )
            };
            return (file, None, vec![d]);
        }
    };
    let file = SourceFile::new(name, text, Some(root));
    let root = file.root.as_ref().expect("just set");
    let mut diags = Vec::new();
    duplicate_keys(root, "", &file, &mut diags);
    diags.truncate(MAX_DIAGNOSTICS_PER_FILE);

    if !matches!(root.kind, NodeKind::Object(_)) {
        diags.push(file.diagnostic(
            Severity::Error,
            "schema/type",
            "",
            "a spec file must be a JSON object",
            Some("start from an existing spec in specs/".into()),
        ));
        return (file, None, diags);
    }
    let value = root.to_value();
    let problems = checker.check(&value);
    if !problems.is_empty() {
        for p in problems {
            let rule = format!("schema/{}", p.keyword);
            let on_key = p.keyword == "additionalProperties";
            let mut d = file.diagnostic(Severity::Error, &rule, &p.pointer, p.message, p.help);
            if on_key && let Some((loc, snip)) = file.locate_pointer(&p.pointer, true) {
                d.location = Some(loc);
                d.snippet = Some(snip);
            }
            diags.push(d);
        }
        return (file, None, diags);
    }
    let is_fragment = root.get("fragment").is_some() && root.get("id").is_none();
    let doc = if is_fragment {
        serde_path_deser::<RawFragment>(value).map(RawDocument::Fragment)
    } else {
        serde_path_deser::<RawEnvSpec>(value).map(|e| RawDocument::Environment(Box::new(e)))
    };
    match doc {
        Ok(doc) => (file, Some(doc), diags),
        Err(msg) => {
            diags.push(file.diagnostic(Severity::Error, "schema/deserialize", "", msg, None));
            (file, None, diags)
        }
    }
}

fn serde_path_deser<T: serde::de::DeserializeOwned>(value: serde_json::Value) -> Result<T, String> {
    serde_json::from_value(value).map_err(|e| e.to_string())
}

fn duplicate_keys(node: &Node, pointer: &str, file: &SourceFile, out: &mut Vec<Diagnostic>) {
    match &node.kind {
        NodeKind::Object(members) => {
            for (i, m) in members.iter().enumerate() {
                let child = format!("{pointer}/{}", json::escape_token(&m.key));
                if members[..i].iter().any(|p| p.key == m.key) {
                    let (loc, snip) = file.locate_span(m.key_span.start, m.key_span.end);
                    out.push(Diagnostic {
                        location: Some(loc),
                        snippet: Some(snip),
                        pointer: child.clone(),
                        ..Diagnostic::file_level(
                            Severity::Error,
                            "duplicate-key",
                            &file.name,
                            format!("property \"{}\" appears more than once in this object", m.key),
                            Some("JSON readers silently keep only one of them: remove the duplicate".into()),
                        )
                    });
                }
                duplicate_keys(&m.value, &child, file, out);
            }
        }
        NodeKind::Array(items) => {
            for (i, item) in items.iter().enumerate() {
                duplicate_keys(item, &format!("{pointer}/{i}"), file, out);
            }
        }
        _ => {}
    }
}
