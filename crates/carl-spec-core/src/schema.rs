//! The JSON Schema of spec files, generated from the raw serde types (draft 2020-12).
//!
//! `schema/carl-spec.schema.json` is this output, committed; a test fails when they drift.

use schemars::generate::SchemaSettings;

use crate::spec::raw::RawDocument;

/// Where the committed copy lives, relative to the crate root.
pub const COMMITTED_PATH: &str = "schema/carl-spec.schema.json";

/// The generated schema as a JSON value.
pub fn schema_value() -> serde_json::Value {
    let schema = SchemaSettings::draft2020_12()
        .into_generator()
        .into_root_schema_for::<RawDocument>();
    let mut value = schema.to_value();
    if let Some(obj) = value.as_object_mut() {
        obj.insert(
            "$id".into(),
            "https://carl-spec.invalid/schema/carl-spec.schema.json".into(),
        );
        obj.insert(
            "description".into(),
            "A carl-spec document: an environment spec (has `id`) or a shared feature fragment (has `fragment`)."
                .into(),
        );
    }
    value
}

/// The schema as committed: pretty-printed with a trailing newline.
pub fn schema_text() -> String {
    let mut s = serde_json::to_string_pretty(&schema_value()).unwrap_or_default();
    s.push('\n');
    s
}

/// The schema with its root replaced by one of its definitions (e.g. `RawEnvSpec`), so a document
/// known to be an environment spec gets that branch's precise errors, not an `anyOf` summary.
pub fn schema_for_definition(def: &str) -> serde_json::Value {
    let mut value = schema_value();
    if let Some(obj) = value.as_object_mut() {
        for key in ["anyOf", "oneOf", "title", "description"] {
            obj.remove(key);
        }
        obj.insert("$ref".into(), format!("#/$defs/{def}").into());
    }
    value
}
