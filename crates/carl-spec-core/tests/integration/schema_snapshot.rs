//! The committed JSON Schema must equal the one generated from the Rust types.

#[test]
fn committed_schema_matches_generated() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(carl_spec_core::schema::COMMITTED_PATH);
    let committed = std::fs::read_to_string(&path).expect("schema/carl-spec.schema.json is committed");
    let generated = carl_spec_core::schema::schema_text();
    assert!(
        committed == generated,
        "schema/carl-spec.schema.json is stale: regenerate it with\n    cargo run -- schema > schema/carl-spec.schema.json"
    );
}

#[test]
fn schema_is_draft_2020_12_and_accepts_both_document_kinds() {
    let v = carl_spec_core::schema::schema_value();
    assert_eq!(v["$schema"], "https://json-schema.org/draft/2020-12/schema");
    assert!(v["$defs"]["RawEnvSpec"].is_object());
    assert!(v["$defs"]["RawFragment"].is_object());
}
