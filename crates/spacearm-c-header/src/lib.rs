//! No code: the crate holds `tests/header.rs`, the check of the C library's committed header
//! (crates/spacearm-c/include/spacearm.h) against cbindgen's (see Cargo.toml for why it is a crate
//! of its own).
