//! Typed errors of the core. Every fallible public function returns [`Result`].
//!
//! The bindings map each variant onto one Python exception class (see `spacearm.errors`),
//! so the variant names are part of the user-facing contract: keep them stable.

use thiserror::Error;

/// Result alias used throughout the core.
pub type Result<T> = std::result::Result<T, SpacearmError>;

/// Everything that can go wrong in the core, each variant naming what was wrong and what was
/// expected.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SpacearmError {
    /// The model description violates a physical or structural rule (DESIGN.md §4).
    #[error("invalid model: {0}")]
    InvalidModel(String),

    /// An array argument has the wrong length.
    #[error("{what} must have length {expected}, got {got}")]
    Dimension {
        what: String,
        expected: String,
        got: usize,
    },

    /// An argument contains NaN or an infinity.
    #[error("{what} must be finite, but entry {index} is {value}")]
    NonFinite {
        what: String,
        index: usize,
        value: f64,
    },

    /// A quaternion is not unit length within the stated tolerance.
    #[error(
        "{what} must be a unit quaternion [x, y, z, w] (|q| = 1 within {tolerance:e}), got norm {norm}"
    )]
    NotUnitQuaternion {
        what: String,
        norm: f64,
        tolerance: f64,
    },

    /// A name or index does not refer to anything in the model.
    #[error("{0}")]
    NotFound(String),

    /// A matrix that must be invertible is singular (or numerically so).
    #[error("{0} is singular (or numerically singular) at this configuration")]
    Singular(String),

    /// A model file could not be parsed; the message carries line and column.
    #[error("{0}")]
    Parse(String),

    /// An option or argument has an invalid value (a negative duration, an unknown mode name,
    /// a limit that is not positive); the message names it and what was expected.
    #[error("{0}")]
    InvalidArgument(String),

    /// A simulation could not continue (the state diverged, the adaptive step size fell below
    /// its floor, the step budget ran out, or a controller failed); the message says when.
    #[error("{0}")]
    Simulation(String),
}

impl SpacearmError {
    pub(crate) fn model(msg: impl Into<String>) -> Self {
        SpacearmError::InvalidModel(msg.into())
    }

    pub(crate) fn argument(msg: impl Into<String>) -> Self {
        SpacearmError::InvalidArgument(msg.into())
    }
}

/// Check that `values` has `expected` entries and that all are finite.
pub(crate) fn check_vector(what: &str, values: &[f64], expected: usize) -> Result<()> {
    if values.len() != expected {
        return Err(SpacearmError::Dimension {
            what: what.to_string(),
            expected: expected.to_string(),
            got: values.len(),
        });
    }
    check_finite(what, values)
}

/// Check that every entry of `values` is finite.
pub(crate) fn check_finite(what: &str, values: &[f64]) -> Result<()> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(SpacearmError::NonFinite {
            what: what.to_string(),
            index,
            value: values[index],
        }),
        None => Ok(()),
    }
}
