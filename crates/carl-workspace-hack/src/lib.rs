//! Feature unification only; nothing to import. Cargo.toml says why this crate exists.
