//! TOML model files: [`model_from_toml_str`] reads one, [`model_to_toml`] writes one (the
//! round trip is exact: `model_from_toml_str(&model_to_toml(&m), ..) == m`). Schema, units,
//! frames and every validation rule: `docs/model-format.md`.
//!
//! ```toml
//! [model]
//! name = "demo"
//! end_effector = "tip"           # optional, names a [[point]]
//! initial_q = [0.3]              # optional, length N (default zeros)
//!
//! [base]
//! mass = 100.0                   # kg, > 0
//! inertia = [10.0, 10.0, 10.0]   # about the base CM: [ixx, iyy, izz], 3x3, or {ixx = .., ixy = ..}
//!
//! [[link]]
//! name = "arm"
//! parent = "base"
//! com = [0.5, 0.0, 0.0]          # CM from the joint, in the link frame
//! mass = 5.0
//! inertia = [0.01, 0.4, 0.4]     # about the link CM, link axes
//! joint = { type = "revolute", origin = [0.5, 0.0, 0.0], axis = [0.0, 0.0, 1.0] }
//!
//! [[point]]
//! name = "tip"
//! body = "arm"
//! offset = [0.5, 0.0, 0.0]       # from the body CM, body frame
//! ```
//!
//! A `[dh]` section with `[[dh.link]]` rows builds a serial arm on the base from a
//! Denavit–Hartenberg table ([`crate::io::dh`], `docs/dh.md`).
//!
//! Every error is [`SpacearmError::Parse`](crate::SpacearmError::Parse) and starts with `source:line:column:`; the
//! structural ones (syntax, unknown key, wrong type, missing field) come from the TOML parser,
//! the semantic ones (unknown parent, negative mass, ...) name the link, joint or point and
//! point at the offending value. No input makes this module panic.
//!
//! The file's schema is [`schema`] (serde types), the reading [`read`] (schema → builder),
//! the writing [`write`](mod@write) (model → text).

pub mod read;
pub mod schema;
#[cfg(test)]
mod tests;
pub mod write;

pub use read::{model_from_toml_file, model_from_toml_str, model_from_toml_str_with};
pub use schema::FORMAT_VERSION;
pub use write::model_to_toml;
