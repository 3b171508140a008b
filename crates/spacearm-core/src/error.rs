//! Typed errors of the core. Every fallible public function returns [`Result`].
//!
//! Each variant has an [`ErrorKind`], and the kinds' one table gives each its status code in the
//! C ABI and its exception class in `spacearm.errors`, which the doors look up; the variant
//! names are part of the user-facing contract: keep them stable.

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
    #[error("invalid model: {}", compact_numbers(.0))]
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
        "{what} must be a unit quaternion [x, y, z, w] (|q| = 1 within {tolerance:e}), got norm {}", compact_numbers(&norm.to_string())
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
    #[error("{}", compact_numbers(.0))]
    NotFound(String),

    /// A matrix that must be invertible is singular (or numerically so).
    #[error("{0} is singular (or numerically singular) at this configuration")]
    Singular(String),

    /// A model file could not be parsed; the message carries line and column.
    #[error("{}", compact_numbers(.0))]
    Parse(String),

    /// An option or numerical argument has an invalid value (a negative duration, an unknown
    /// mode name, a limit that is not positive, a tolerance, gain, step or resolution out of
    /// range); the message names it and what was expected.
    #[error("{}", compact_numbers(.0))]
    InvalidArgument(String),

    /// A simulation could not continue (the state diverged, the adaptive step size fell below
    /// its floor, the step budget ran out, or a controller failed); the message says when.
    #[error("{}", compact_numbers(.0))]
    Simulation(String),

    /// A request would allocate more than [`crate::admission::MEMORY_LIMIT_BYTES`]; the message
    /// names the request, its size and the way out. Refused before anything is allocated.
    #[error("{}", compact_numbers(.0))]
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
#[error("invalid model: {}", compact_numbers(.message))]
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

    /// The kind of this error: what every door maps it by (its C status code and its Python
    /// class are rows of [`ErrorKind`]'s table).
    pub fn kind(&self) -> ErrorKind {
        match self {
            SpacearmError::InvalidModel(_) => ErrorKind::InvalidModel,
            SpacearmError::Dimension { .. } => ErrorKind::Dimension,
            SpacearmError::NonFinite { .. } => ErrorKind::NonFinite,
            SpacearmError::NotUnitQuaternion { .. } => ErrorKind::NotUnitQuaternion,
            SpacearmError::NotFound(_) => ErrorKind::NotFound,
            SpacearmError::Singular(_) => ErrorKind::Singular,
            SpacearmError::Parse(_) => ErrorKind::Parse,
            SpacearmError::InvalidArgument(_) => ErrorKind::InvalidArgument,
            SpacearmError::Simulation(_) => ErrorKind::Simulation,
            SpacearmError::ResourceLimit(_) => ErrorKind::ResourceLimit,
        }
    }
}

/// The kind of a [`SpacearmError`], one per variant (the same names): the key by which the
/// doors map the core's errors. Its table ([`ErrorKind::ALL`] with [`ErrorKind::name`],
/// [`ErrorKind::status_code`], [`ErrorKind::exception`]) is the one place that says which status
/// code of the C ABI (`SpacearmStatus`, docs/c-api.md "Errors") and which exception class of
/// `spacearm.errors` a kind is; the C crate and the Python binding each look the kind up there.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ErrorKind {
    /// [`SpacearmError::InvalidModel`].
    InvalidModel,
    /// [`SpacearmError::Dimension`].
    Dimension,
    /// [`SpacearmError::NonFinite`].
    NonFinite,
    /// [`SpacearmError::NotUnitQuaternion`].
    NotUnitQuaternion,
    /// [`SpacearmError::NotFound`].
    NotFound,
    /// [`SpacearmError::Singular`].
    Singular,
    /// [`SpacearmError::Parse`].
    Parse,
    /// [`SpacearmError::InvalidArgument`].
    InvalidArgument,
    /// [`SpacearmError::Simulation`].
    Simulation,
    /// [`SpacearmError::ResourceLimit`].
    ResourceLimit,
}

/// The table of the kinds, in the order of [`ErrorKind`]: the kind, its name (the variant's),
/// its status code in the C ABI and its exception class in `spacearm.errors`.
const KIND_TABLE: [(ErrorKind, &str, i32, &str); 10] = [
    (ErrorKind::InvalidModel, "InvalidModel", 1, "ModelError"),
    (ErrorKind::Dimension, "Dimension", 2, "ShapeError"),
    (ErrorKind::NonFinite, "NonFinite", 3, "NonFiniteError"),
    (ErrorKind::NotUnitQuaternion, "NotUnitQuaternion", 4, "QuaternionError"),
    (ErrorKind::NotFound, "NotFound", 5, "NotFoundError"),
    (ErrorKind::Singular, "Singular", 6, "SingularError"),
    (ErrorKind::Parse, "Parse", 7, "ModelFileError"),
    (ErrorKind::InvalidArgument, "InvalidArgument", 8, "ArgumentError"),
    (ErrorKind::Simulation, "Simulation", 9, "SimulationError"),
    (ErrorKind::ResourceLimit, "ResourceLimit", 10, "ResourceLimitError"),
];

impl ErrorKind {
    /// Every kind, in the order of the table.
    pub const ALL: [ErrorKind; KIND_TABLE.len()] = {
        let mut all = [ErrorKind::InvalidModel; KIND_TABLE.len()];
        let mut k = 0;
        while k < all.len() {
            all[k] = KIND_TABLE[k].0;
            k += 1;
        }
        all
    };

    fn row(self) -> &'static (ErrorKind, &'static str, i32, &'static str) {
        &KIND_TABLE[self as usize]
    }

    /// The kind's name: that of its [`SpacearmError`] variant (`"InvalidModel"`).
    pub fn name(self) -> &'static str {
        self.row().1
    }

    /// Its status code in the C ABI (`SpacearmStatus`; `0` is success, so never `0`).
    pub fn status_code(self) -> i32 {
        self.row().2
    }

    /// The name of its exception class in `spacearm.errors` (`"ModelError"`).
    pub fn exception(self) -> &'static str {
        self.row().3
    }
}

/// Digits a number of a message may have before it is shown in scientific notation.
const MAX_MESSAGE_DIGITS: usize = 17;

/// An enum of unit variants that is data by its name. `named_by!(Enum, "what", [Variant =
/// "name", ...])` writes the name table once: `NAMES`,
/// `from_name` (any other name refused naming the table and `what`, [`by_name`]) and `name`
/// (the variant's entry of `NAMES`), and the serde below. `named_by!(Enum)` alone, beside
/// `#[serde(try_from = "String", into = "&'static str")]` on the enum, reads it with its
/// `from_name` and writes it with its `name`.
macro_rules! named_by {
    ($t:ident, $what:literal, [$($variant:ident = $name:literal),+ $(,)?]) => {
        impl $t {
            #[doc = concat!("The names accepted by [`", stringify!($t), "::from_name`], in the variants' order.")]
            pub const NAMES: [&'static str; [$($name),+].len()] = [$($name),+];

            #[doc = concat!("The variant named `name` (one of [`", stringify!($t), "::NAMES`]); any other name is refused naming the table.")]
            pub fn from_name(name: &str) -> $crate::error::Result<Self> {
                $crate::error::by_name($what, &Self::NAMES, &[$($t::$variant),+], name)
            }

            #[doc = concat!("The name (the variant's entry of [`", stringify!($t), "::NAMES`]).")]
            pub fn name(self) -> &'static str {
                match self {
                    $($t::$variant => $name),+
                }
            }
        }
        $crate::error::named_by!($t);
    };
    ($t:ty) => {
        impl TryFrom<String> for $t {
            type Error = $crate::error::SpacearmError;
            fn try_from(name: String) -> $crate::error::Result<Self> {
                <$t>::from_name(&name)
            }
        }

        impl From<$t> for &'static str {
            fn from(value: $t) -> &'static str {
                value.name()
            }
        }
    };
}
pub(crate) use named_by;

/// The entry of `values` whose name (same position in `names`) is `name`, for the `from_name`
/// of the enums with a name table; else [`SpacearmError::InvalidArgument`] "`what` must be one
/// of [names], got '`name`'".
pub fn by_name<T: Copy>(what: &str, names: &[&str], values: &[T], name: &str) -> Result<T> {
    debug_assert_eq!(names.len(), values.len());
    match names.iter().position(|n| *n == name) {
        Some(k) => Ok(values[k]),
        None => Err(SpacearmError::argument(format!("{what} must be one of {names:?}, got '{name}'"))),
    }
}

/// `message` with every number of more than 17 digits in its first line written in scientific
/// notation with 7 significant digits (`1e130`, `5.542982e37`): Rust writes an `f64` in full
/// (`1e130` as 131 digits), and a message quoting a user's value must stay readable. The lines
/// after the first (a model file's quoted line) are kept as they are. Every error's `Display`
/// applies it, so every door (Python, C, the CLI) shows the same compact message.
pub fn compact_numbers(message: &str) -> std::borrow::Cow<'_, str> {
    let first = message.split('\n').next().unwrap_or("");
    let b = first.as_bytes();
    let mut digits_in_a_row = 0;
    if !b.iter().any(|c| {
        digits_in_a_row = if c.is_ascii_digit() { digits_in_a_row + 1 } else { 0 };
        digits_in_a_row > MAX_MESSAGE_DIGITS
    }) {
        return std::borrow::Cow::Borrowed(message);
    }
    let mut out = String::with_capacity(message.len());
    let mut i = 0;
    while i < b.len() {
        let word_before = i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_' || b[i - 1] == b'.');
        if b[i].is_ascii_digit() && !word_before {
            let mut j = i;
            while j < b.len() && b[j].is_ascii_digit() {
                j += 1;
            }
            if j + 1 < b.len() && b[j] == b'.' && b[j + 1].is_ascii_digit() {
                j += 1;
                while j < b.len() && b[j].is_ascii_digit() {
                    j += 1;
                }
            }
            let token = &first[i..j];
            let word_after = j < b.len() && (b[j].is_ascii_alphanumeric() || b[j] == b'_');
            let n_digits = token.bytes().filter(u8::is_ascii_digit).count();
            match token.parse::<f64>() {
                Ok(v) if n_digits > MAX_MESSAGE_DIGITS && !word_after && v.is_finite() => {
                    let sci = format!("{v:.6e}");
                    let (mantissa, exponent) = sci.split_once('e').unwrap_or((&sci, "0"));
                    let mantissa = if mantissa.contains('.') { mantissa.trim_end_matches('0').trim_end_matches('.') } else { mantissa };
                    out.push_str(mantissa);
                    out.push('e');
                    out.push_str(exponent);
                }
                _ => out.push_str(token),
            }
            i = j;
        } else {
            let len = first[i..].chars().next().map_or(1, char::len_utf8);
            out.push_str(&first[i..i + len]);
            i += len;
        }
    }
    out.push_str(&message[first.len()..]);
    std::borrow::Cow::Owned(out)
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn by_name_reads_every_table_and_refuses_other_names_naming_the_table() {
        use crate::algorithms::impulse::JointsAtImpact;
        use crate::math::integrate::IntegratorKind;
        assert_eq!(IntegratorKind::from_name("rk4").unwrap(), IntegratorKind::Rk4);
        assert_eq!(IntegratorKind::from_name("dopri5").unwrap(), IntegratorKind::Dopri5);
        for name in IntegratorKind::NAMES {
            assert_eq!(IntegratorKind::from_name(name).unwrap().name(), name);
        }
        assert_eq!(JointsAtImpact::from_name("free").unwrap(), JointsAtImpact::Free);
        assert_eq!(JointsAtImpact::from_name("locked").unwrap(), JointsAtImpact::Locked);
        match IntegratorKind::from_name("euler") {
            Err(SpacearmError::InvalidArgument(m)) => assert_eq!(m, r#"integrator must be one of ["rk4", "dopri5"], got 'euler'"#),
            other => panic!("expected an argument error, got {other:?}"),
        }
        match JointsAtImpact::from_name("Free") {
            Err(SpacearmError::InvalidArgument(m)) => assert_eq!(m, r#"arm must be one of ["free", "locked"], got 'Free'"#),
            other => panic!("expected an argument error, got {other:?}"),
        }
        use crate::algorithms::impulse::GraspContact;
        use crate::analysis::reaction_null_space::BaseMotion;
        assert_eq!(BaseMotion::from_name("angular").unwrap(), BaseMotion::Angular);
        assert_eq!(BaseMotion::from_name("full").unwrap(), BaseMotion::Full);
        // The tables of `named_by!`: each name reads back to itself.
        for name in BaseMotion::NAMES {
            assert_eq!(BaseMotion::from_name(name).unwrap().name(), name);
        }
        for name in JointsAtImpact::NAMES {
            assert_eq!(JointsAtImpact::from_name(name).unwrap().name(), name);
        }
        use crate::analysis::rmrc_solver::Strategy;
        use crate::control::computed_torque::PassiveTreatment;
        use crate::control::shaping::ShaperKind;
        for name in Strategy::NAMES {
            assert_eq!(Strategy::from_name(name).unwrap().name(), name);
        }
        for name in PassiveTreatment::NAMES {
            assert_eq!(PassiveTreatment::from_name(name).unwrap().name(), name);
        }
        for name in ShaperKind::NAMES {
            assert_eq!(ShaperKind::from_name(name).unwrap().name(), name);
        }
        assert_eq!(Strategy::MinimumBaseDisturbance.name(), "minimum_disturbance");
        assert_eq!(ShaperKind::from_name("zvd").unwrap(), ShaperKind::Zvd);
        match PassiveTreatment::from_name("rigid") {
            Err(SpacearmError::InvalidArgument(m)) => assert_eq!(m, r#"computed_torque 'passive' must be one of ["drift", "frozen"], got 'rigid'"#),
            other => panic!("expected an argument error, got {other:?}"),
        }
        assert_eq!(JointsAtImpact::Locked.name(), "locked");
        assert_eq!(BaseMotion::Full.name(), "full");
        let n = Some(nalgebra::Vector3::new(0.0, 0.0, 1.0));
        assert_eq!(GraspContact::from_name("rigid", n).unwrap(), GraspContact::Rigid);
        assert_eq!(GraspContact::from_name("point", n).unwrap(), GraspContact::Point { normal: n });
        for (e, expected) in [
            (BaseMotion::from_name("linear").map(|_| ()), r#"base_motion must be one of ["angular", "full"], got 'linear'"#),
            (GraspContact::from_name("glue", None).map(|_| ()), r#"kind must be one of ["rigid", "point"], got 'glue'"#),
        ] {
            assert!(matches!(&e, Err(SpacearmError::InvalidArgument(m)) if m == expected), "{e:?}");
        }
    }

    #[test]
    fn every_kind_has_one_row_a_distinct_status_code_and_a_distinct_exception_class() {
        use std::collections::HashSet;
        assert_eq!(ErrorKind::ALL.len(), 10);
        for (k, kind) in ErrorKind::ALL.into_iter().enumerate() {
            assert_eq!(kind as usize, k, "the table's rows are in the order of the enum");
            assert_eq!(format!("{kind:?}"), kind.name());
            assert!(kind.status_code() > 0, "{kind:?}: 0 is the C ABI's success");
            assert!(kind.exception().ends_with("Error"), "{kind:?}");
        }
        assert_eq!(ErrorKind::ALL.iter().map(|k| k.status_code()).collect::<HashSet<_>>().len(), ErrorKind::ALL.len());
        assert_eq!(ErrorKind::ALL.iter().map(|k| k.exception()).collect::<HashSet<_>>().len(), ErrorKind::ALL.len());
        // One error of each variant has the kind of the same name.
        let errors = [
            SpacearmError::InvalidModel("m".into()),
            SpacearmError::Dimension { what: "x".into(), expected: "3".into(), got: 2 },
            SpacearmError::NonFinite { what: "x".into(), index: 0, value: f64::NAN },
            SpacearmError::NotUnitQuaternion { what: "q".into(), norm: 2.0, tolerance: 1e-6 },
            SpacearmError::NotFound("n".into()),
            SpacearmError::Singular("H".into()),
            SpacearmError::Parse("p".into()),
            SpacearmError::argument("a"),
            SpacearmError::Simulation("s".into()),
            SpacearmError::ResourceLimit("r".into()),
        ];
        for (e, kind) in errors.iter().zip(ErrorKind::ALL) {
            assert_eq!(e.kind(), kind);
            assert!(format!("{e:?}").starts_with(kind.name()), "{e:?}");
        }
    }

    #[test]
    fn long_numbers_in_messages_are_compact() {
        // A user's 1e130 was printed in full, 131 digits, by every message quoting it (issue 38).
        let huge = format!("box size x must be at most 1e6 m, got {}", 1e130_f64);
        assert!(huge.len() > 150);
        let e = SpacearmError::InvalidModel(huge).to_string();
        assert_eq!(e, "invalid model: box size x must be at most 1e6 m, got 1e130");
        let e = SpacearmError::argument(format!("mode λ = {} at t = 0 s, dt = 0.01 s", 55429823419145777172668967157528713605.0_f64));
        assert_eq!(e.to_string(), "mode λ = 5.542982e37 at t = 0 s, dt = 0.01 s");
        assert_eq!(SpacearmError::argument(format!("got {}", -1e-19_f64)).to_string(), "got -1e-19");
        let q = SpacearmError::NotUnitQuaternion { what: "x[3:7]".into(), norm: 2e51, tolerance: 1e-6 };
        assert!(q.to_string().ends_with("got norm 2e51"), "{q}");
        let m = ModelError::new(ModelItem::Base, ModelField::Mass, format!("got {}", -1e18_f64));
        assert_eq!(m.to_string(), "invalid model: got -1e18");
        // Short numbers, names with digits, and the lines after the first (a quoted file line) stay.
        let kept = "link 'arm_123456789012345678901' at 0.125 m, 12345678901234567 steps\n 4 | mass = 100000000000000000000";
        assert_eq!(SpacearmError::Parse(kept.into()).to_string(), kept);
    }
}
