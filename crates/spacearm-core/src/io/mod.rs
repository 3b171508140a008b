//! Model input and output: TOML model files ([`toml`], `docs/model-format.md`) and
//! Denavit–Hartenberg tables ([`dh`], `docs/dh.md`). Both feed [`crate::model::ModelBuilder`],
//! so a model gets the same verdict whichever door it comes through.
//!
//! Imports: [`crate::math`], [`crate::model`], [`crate::error`] and [`crate::admission`].

pub mod dh;
pub mod toml;
