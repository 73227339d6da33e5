//! Shared test helpers: the data directory (`$CARL_SPEC_DATA`, else `shared/data` beside the
//! checkout) and the fixture files in it.
#![allow(dead_code)]

use carl_mario::DataDir;
use serde_json::Value;
use std::path::Path;

pub mod traces;

/// The data directory; a clear failure (not a skip) when it is missing, since CI has it.
pub fn data_dir() -> DataDir {
    DataDir::discover(Path::new(env!("CARGO_MANIFEST_DIR")))
        .unwrap_or_else(|e| panic!("tests need the Mario data directory: {e}"))
}

/// The records of a JSON-lines file in `mario/`.
pub fn jsonl(name: &str) -> Vec<Value> {
    let path = data_dir().mario().join(name);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.lines()
        .map(|l| serde_json::from_str(l).expect("fixture line is JSON"))
        .collect()
}
