//! The validator: syntax → JSON Schema → typed model → resolution → semantic rules.
//!
//! Every problem in every file is collected (never stop at the first), each as a located
//! [`Diagnostic`] with a stable rule id. `SpecSet`'s loaders run the same pipeline, so anything the
//! library accepts has passed validation (the bundled specs' syntactic checks at test time, see
//! `Syntax::TrustEmbedded`).

mod load;
mod rules;
pub use crate::spec::model::value_text;
pub mod schema_check;

use std::collections::BTreeMap;

use crate::diagnostics::rules as rule;
pub use crate::diagnostics::{
    Diagnostic, Input, Location, MAX_DIAGNOSTICS_PER_FILE, MAX_FILE_BYTES, Report, Severity, Sink, SourceFile,
    diagnostic,
};
use crate::json::{self, Node, NodeKind};
use crate::spec::raw::{RawDocument, RawEnvSpec, RawFragment};
use crate::spec::resolve::{FragmentEntry, Resolved, resolve};
use schema_check::SchemaChecker;

/// Validate a set of documents and return the resolved environment specs of the valid ones.
pub fn run(inputs: &[Input]) -> (Vec<Resolved>, Report) {
    run_with(inputs, Syntax::CheckAll)
}

/// Which documents get the syntactic checks (duplicate keys, JSON Schema).
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Syntax {
    /// Every document (`carl-spec validate`, `cs.validate`, authors' specs).
    CheckAll,
    /// All but the bundled specs exactly as embedded at build time: the test
    /// `bundled_specs_pass_the_whole_validator` (tests/bundled_specs.rs) runs the whole validator
    /// over those very bytes, so loading them need not compile the schema again (half the cost
    /// of `import carl_spec; cs.make(...)` beyond NumPy and Gymnasium). Typed deserialization,
    /// resolution and the semantic rules still run for them.
    TrustEmbedded,
}

pub(crate) fn run_with(inputs: &[Input], syntax: Syntax) -> (Vec<Resolved>, Report) {
    let trusted: Vec<bool> = inputs
        .iter()
        .map(|i| syntax == Syntax::TrustEmbedded && crate::spec::load::is_embedded(i))
        .collect();
    // The schema is compiled only if some document needs it.
    let checker = if trusted.iter().all(|&t| t) {
        None
    } else {
        match schema_check::shared() {
            Ok(c) => Some(c),
            Err(e) => {
                let d = Diagnostic::file_level(&rule::INTERNAL, "<schema>", e, None);
                return (
                    Vec::new(),
                    Report {
                        diagnostics: vec![d],
                        ..Default::default()
                    },
                );
            }
        }
    };
    let mut early: Vec<Diagnostic> = Vec::new();
    let mut files: Vec<SourceFile> = Vec::with_capacity(inputs.len());
    let mut docs: Vec<Option<RawDocument>> = Vec::with_capacity(inputs.len());
    for (input, &trusted) in inputs.iter().zip(&trusted) {
        let (file, doc, mut diags) = check_document(input, if trusted { None } else { checker });
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
    let mut sink = Sink::new(&files, early);

    // Fragments: authors' own shadow the bundled library; duplicates among one kind are errors.
    let mut fragments: BTreeMap<String, FragmentEntry<'_>> = BTreeMap::new();
    let mut order: Vec<usize> = (0..inputs.len()).collect();
    order.sort_by_key(|&i| !inputs[i].library); // library first, so authors' files replace them
    for &i in &order {
        if let Some(RawDocument::Fragment(frag)) = &docs[i] {
            if let Some(prev) = fragments.get(&frag.fragment)
                && inputs[prev.file].library == inputs[i].library
            {
                sink.report(
                    i,
                    &rule::DUPLICATE_FRAGMENT,
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

/// Syntax, duplicate keys, schema and typed deserialization of one file (`checker` None: a
/// trusted embedded spec, see [`Syntax::TrustEmbedded`]; no duplicate-key or schema check).
fn check_document(
    input: &Input,
    checker: Option<&SchemaChecker>,
) -> (SourceFile, Option<RawDocument>, Vec<Diagnostic>) {
    let name = input.name.clone();
    if input.bytes.len() > MAX_FILE_BYTES {
        let d = Diagnostic::file_level(
            &rule::FILE_TOO_LARGE,
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
                    &rule::NOT_UTF8,
                    &name,
                    format!("invalid UTF-8 at byte {}: spec files are UTF-8 JSON", e.valid_up_to()),
                    Some("is this a binary file? re-save it as UTF-8".into()),
                )
            };
            return (file, None, vec![d]);
        }
    };
    if checker.is_none()
        && let Ok(value) = serde_json::from_str::<serde_json::Value>(&text)
    {
        // A trusted embedded spec: no located diagnostics are expected, so serde_json's parser
        // stands in for the located one (which keeps every node's position). Anything the
        // deserializer, the resolver or the rules still report is then unlocated.
        let doc = typed_document(value);
        let file = SourceFile::new(name, text, None);
        return match doc {
            Ok(doc) => (file, Some(doc), Vec::new()),
            Err(msg) => {
                let d = file.diagnostic(&rule::SCHEMA, Some("deserialize"), "", msg, None);
                (file, None, vec![d])
            }
        };
    }
    let root = match json::parse(&text) {
        Ok(root) => root,
        Err(e) => {
            let file = SourceFile::new(name.clone(), text, None);
            let (loc, snip) = file.locate_span(e.offset, e.offset + 1);
            let d = Diagnostic {
                location: Some(loc),
                snippet: Some(snip),
                ..Diagnostic::file_level(
                    &rule::JSON_SYNTAX,
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
    if checker.is_some() {
        duplicate_keys(root, "", &file, &mut diags);
        diags.truncate(MAX_DIAGNOSTICS_PER_FILE);
    }

    if !matches!(root.kind, NodeKind::Object(_)) {
        diags.push(file.diagnostic(
            &rule::SCHEMA,
            Some("type"),
            "",
            "a spec file must be a JSON object",
            Some("start from an existing spec in specs/".into()),
        ));
        return (file, None, diags);
    }
    let value = root.to_value();
    let problems = checker.map(|c| c.check(&value)).unwrap_or_default();
    if !problems.is_empty() {
        for p in problems {
            let on_key = p.keyword == "additionalProperties";
            let mut d = file.diagnostic(&rule::SCHEMA, Some(&p.keyword), &p.pointer, p.message, p.help);
            if on_key && let Some((loc, snip)) = file.locate_pointer(&p.pointer, true) {
                d.location = Some(loc);
                d.snippet = Some(snip);
            }
            diags.push(d);
        }
        return (file, None, diags);
    }
    match typed_document(value) {
        Ok(doc) => (file, Some(doc), diags),
        Err(msg) => {
            diags.push(file.diagnostic(&rule::SCHEMA, Some("deserialize"), "", msg, None));
            (file, None, diags)
        }
    }
}

/// A fragment (`fragment`, no `id`) or an environment spec.
fn typed_document(value: serde_json::Value) -> Result<RawDocument, String> {
    let is_fragment = value.get("fragment").is_some() && value.get("id").is_none();
    if is_fragment {
        serde_path_deser::<RawFragment>(value).map(RawDocument::Fragment)
    } else {
        serde_path_deser::<RawEnvSpec>(value).map(|e| RawDocument::Environment(Box::new(e)))
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
                            &rule::DUPLICATE_KEY,
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
