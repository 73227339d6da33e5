//! Embeds every file under the workspace's `specs/` into the library, so each command works from
//! any directory.

use std::fs;
use std::path::Path;

fn collect(dir: &Path, root: &Path, out: &mut Vec<String>) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    let mut paths: Vec<_> = entries.flatten().map(|e| e.path()).collect();
    paths.sort();
    for p in paths {
        if p.is_dir() {
            collect(&p, root, out);
        } else if p.extension().is_some_and(|e| e == "json") {
            let rel = p.strip_prefix(root).unwrap().to_string_lossy().replace('\\', "/");
            out.push(rel);
        }
    }
}

/// The bundled specs, relative to this crate.
const SPECS: &str = "../../specs";

fn main() {
    // Read at run time of the build script (not baked in when it is compiled).
    let root = Path::new(&std::env::var("CARGO_MANIFEST_DIR").unwrap()).join(SPECS);
    println!("cargo:rerun-if-changed={SPECS}");
    let mut files = Vec::new();
    collect(&root, &root, &mut files);
    let mut code = String::from("/// (path relative to specs/, contents)\npub static BUNDLED: &[(&str, &str)] = &[\n");
    for f in &files {
        // Directories must be watched one by one for added files to trigger a rebuild.
        if let Some(parent) = Path::new(f).parent() {
            println!("cargo:rerun-if-changed={SPECS}/{}", parent.display());
        }
        code.push_str(&format!(
            "    ({f:?}, include_str!(concat!(env!(\"CARGO_MANIFEST_DIR\"), \"/{SPECS}/{f}\"))),\n"
        ));
    }
    code.push_str("];\n");
    let out = Path::new(&std::env::var("OUT_DIR").unwrap()).join("bundled_specs.rs");
    fs::write(out, code).unwrap();
}
