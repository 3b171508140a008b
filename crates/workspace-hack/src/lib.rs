//! No code: a dependency that makes the C library's feature resolution equal the extension's, so
//! one release build of spacearm-core serves both (see this crate's Cargo.toml).
