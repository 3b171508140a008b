//! The constant description of a spacecraft-manipulator system and its per-configuration
//! workspace: mass properties ([`body`]), joints ([`joint`]), the validated [`Model`] and its
//! builder ([`system`]), the workspace [`Data`] ([`data`]) and the paper's case-study models
//! ([`presets`]).
//!
//! Imports: [`crate::math`] and [`crate::error`] only.

pub mod body;
pub mod data;
pub mod joint;
pub mod presets;
pub mod system;

pub use data::{Data, DataT};
pub use system::{Link, LinkSpec, Model, ModelBuilder, Point};
