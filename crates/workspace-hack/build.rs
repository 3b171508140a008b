//! Empty: cargo resolves `[build-dependencies]` only for a crate with a build script, and this
//! crate's build-dependencies exist to unify host-side features (Cargo.toml).
fn main() {}
