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
    /// The model description violates a physical or structural rule (the rules:
    /// [`crate::model::validate`]; docs/model-format.md). Raised from a [`ModelError`], which
    /// also says where the rule is broken.
    #[error("invalid model: {0}")]
    InvalidModel(String),

    /// An array argument has the wrong length.
    #[error("{what} must have length {expected}, got {got}")]
    Dimension {
        /// The argument.
        what: String,
        /// The length expected (a number or a formula such as `7+N = 13`).
        expected: String,
        /// The length given.
        got: usize,
    },

    /// An argument contains NaN or an infinity.
    #[error("{what} must be finite, but entry {index} is {value}")]
    NonFinite {
        /// The argument.
        what: String,
        /// Index of the first non-finite entry.
        index: usize,
        /// Its value.
        value: f64,
    },

    /// A quaternion is not unit length within the stated tolerance.
    #[error(
        "{what} must be a unit quaternion [x, y, z, w] (|q| = 1 within {tolerance:e}), got norm {norm}"
    )]
    NotUnitQuaternion {
        /// The argument.
        what: String,
        /// Its norm.
        norm: f64,
        /// The tolerance on `| |q| − 1 |`.
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

    /// An option or numerical argument has an invalid value (a negative duration, an unknown
    /// mode name, a limit that is not positive, a tolerance, gain, step or resolution out of
    /// range); the message names it and what was expected.
    #[error("{0}")]
    InvalidArgument(String),

    /// A simulation could not continue (the state diverged, the adaptive step size fell below
    /// its floor, the step budget ran out, or a controller failed); the message says when.
    #[error("{0}")]
    Simulation(String),

    /// A request would allocate more than [`crate::admission::MEMORY_LIMIT_BYTES`]; the message
    /// names the request, its size and the way out. Refused before anything is allocated.
    #[error("{0}")]
    ResourceLimit(String),
}

/// Which item of a model description a [`ModelError`] is about. Links and points are counted
/// from 0 in the order they were given to [`crate::model::ModelBuilder`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModelItem {
    /// The model as a whole (its end effector, its initial joint coordinates).
    Model,
    /// The base body.
    Base,
    /// The `k`-th link given to the builder.
    Link(usize),
    /// The `k`-th point given to the builder.
    Point(usize),
    /// A Denavit–Hartenberg table as a whole (its rows, mounting pose and tool offset).
    DhArm,
    /// Row `k` of a Denavit–Hartenberg table (from 0).
    DhRow(usize),
    /// The `k`-th geometry given to the builder (model/geometry.rs).
    Geometry(usize),
}

/// Which field of a [`ModelItem`] breaks a rule.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModelField {
    /// The item's name (a duplicate, or empty).
    Name,
    /// The parent body of a link.
    Parent,
    /// The name of a link's joint.
    JointName,
    /// A joint's position in its parent (or a DH arm's `joint1_origin`).
    Origin,
    /// A joint's rotation at `q = 0` (or a DH arm's `joint1_rotation`).
    Rotation,
    /// A joint's axis.
    Axis,
    /// A link's centre of mass from its joint.
    Com,
    /// A body's mass (also: a moving joint that carries no mass at all).
    Mass,
    /// A body's inertia tensor.
    Inertia,
    /// A joint's limits.
    Limits,
    /// The body a point is fixed to.
    Body,
    /// A point's offset (or a DH arm's tool offset).
    Offset,
    /// The model's end effector.
    EndEffector,
    /// The model's initial joint coordinates.
    InitialQ,
    /// The geometric parameters of a DH row (`d`, `theta`, `a`, `alpha`, CM vectors).
    DhParameters,
    /// A geometry's shape (its dimensions, mesh file or scale).
    Shape,
    /// A geometry's colour.
    Color,
    /// A joint's passive dynamics: `actuated`, `stiffness`, `damping`, `rest`.
    JointDynamics,
}

/// A model description that breaks a rule: the message (naming the body, joint or point, what
/// was wrong and what was expected) and where, as an item and a field, so that a reader of a
/// model file can point at the offending text from its own parse tree. Becomes
/// [`SpacearmError::InvalidModel`] with the same message.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("invalid model: {message}")]
pub struct ModelError {
    /// The item the message is about.
    pub item: ModelItem,
    /// Its offending field.
    pub field: ModelField,
    /// What was wrong and what was expected.
    pub message: String,
}

impl ModelError {
    /// An error about `field` of `item`.
    pub fn new(item: ModelItem, field: ModelField, message: impl Into<String>) -> Self {
        ModelError { item, field, message: message.into() }
    }
}

impl From<ModelError> for SpacearmError {
    fn from(e: ModelError) -> Self {
        SpacearmError::InvalidModel(e.message)
    }
}

impl SpacearmError {
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
