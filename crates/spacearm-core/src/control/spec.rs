//! What to run, as data: the controllers, their references, input shapers and thruster limits,
//! declared once as serde types (docs/architecture.md, "A run is data").
//!
//! Every door reads these types and nothing else: Python's `spacearm.control` classes are turned
//! into this data by one generic reader (`python/spacearm/_util/spec.py`) and deserialized by the
//! binding (`pythonize`); the C stepper and the FMUs deserialize the `[controller]` table of
//! their TOML options straight into [`ControllerSpec`]; the CLI's and campaigns' controller names
//! resolve through [`controller_kind`]. One home each:
//!
//! * the names: the serde tags of [`ControllerSpec`] (`kind = "computed_torque"`), listed in
//!   [`CONTROLLER_KINDS`], with the CLI's hyphenated spellings and short aliases in
//!   [`CONTROLLER_ALIASES`];
//! * the checks that need no plant: [`ControllerSpec::validate`] (finite gains, positive
//!   limits, unit quaternions, well-formed references — through the references' own
//!   constructors);
//! * the construction: [`ControllerSpec::build`], against the plant (point and body names, task
//!   names and `"auto"`, the end effector as the default point); the controller's
//!   [`super::Controller::setup`] then checks the dimensions against the plant and the mode.
//!
//! A controller the door supplies itself (a Python callable) is `kind = "external"` with an
//! index: [`ControllerSpec::build`] asks the door for it; a door that supplies none refuses it.

use std::fmt;

use nalgebra::Vector3;
use serde::de::{self, Deserializer, SeqAccess, Visitor};
use serde::{Deserialize, Serialize};

use super::attitude::{AttitudeControl, LvlhReference};
use super::cmg_steering::{CmgSteering, SteeringOptions};
use super::cmg_unloading::MomentumUnloading;
use super::computed_torque::{ComputedTorque, PassiveTreatment};
use super::coordinated::{CoordinatedFlying, CoordinatedGains};
use super::momentum_damping::{JointTorqueLimit, MomentumDamping};
use super::mpc::ModelPredictive;
use super::pd::JointPd;
use super::rmrc::ResolvedMotionRate;
use super::shaping::{InputShaper, ShaperKind};
use super::thrusters::BaseThrusterControl;
use super::{Combined, Controller, ZeroTorque};
use crate::algorithms::kinematics::forward_kinematics;
use crate::optimal::ProblemSpec;
use crate::analysis::redundancy::Strategy;
use crate::analysis::Task;
use crate::error::{Result, SpacearmError};
use crate::math::rotations::QUATERNION_TOLERANCE;
use crate::model::{Data, Model};
use crate::scenario::actuators::ThrusterLimits;
use crate::scenario::free_body::FreeBody;
pub use crate::scenario::free_body::{FreeBodySpec, InertiaSpec};
use crate::scenario::orbit::Orbit;
use crate::scenario::reference::{CartesianLine, JointReference, PointReference, Quintic};

fn bad(msg: impl Into<String>) -> SpacearmError {
    SpacearmError::argument(msg.into())
}

// ---- the `kind` tag, with the path of a wrong field -------------------------------------------

// A spec tagged by `kind` is read as a generic table first, turned into serde's externally
// tagged form `{<kind> = {fields}}` and read by the enum's derived (`remote = "Self"`) code through
// `serde_path_to_error`: serde's own internally tagged form buffers the table and loses the
// path, so an error would not say which field was wrong. Written back the same way round.

fn external_form(v: toml::Value) -> std::result::Result<toml::Value, String> {
    let toml::Value::Table(mut t) = v else {
        return Err(format!("expected a table with a 'kind', got {}", v.type_str()));
    };
    match t.remove("kind") {
        Some(toml::Value::String(k)) => Ok(toml::Value::Table(toml::map::Map::from_iter([(k, toml::Value::Table(t))]))),
        Some(other) => Err(format!("'kind' must be a string, got {}", other.type_str())),
        None => Err("missing field `kind`".into()),
    }
}

fn internal_form(v: toml::Value) -> std::result::Result<toml::Value, String> {
    match v {
        toml::Value::String(k) => Ok(toml::Value::Table(toml::map::Map::from_iter([("kind".to_string(), toml::Value::String(k))]))),
        toml::Value::Table(t) if t.len() == 1 => {
            let (k, inner) = t.into_iter().next().expect("one entry");
            let mut out = toml::map::Map::new();
            out.insert("kind".into(), toml::Value::String(k));
            match inner {
                toml::Value::Table(fields) => out.extend(fields),
                other => return Err(format!("a tagged spec's fields must be a table, got {}", other.type_str())),
            }
            Ok(toml::Value::Table(out))
        }
        other => Err(format!("not a tagged spec: {}", other.type_str())),
    }
}

/// `'field.path': message`, the path without its first segment (the kind).
fn with_path(path: &serde_path_to_error::Path, msg: &str) -> String {
    let path = path.to_string();
    let rest = path.split_once('.').map(|(_, r)| r).unwrap_or("");
    // toml's errors end with a line "in `field`" of their own: the path says it.
    let msg = msg.trim().lines().next().unwrap_or("");
    if rest.is_empty() || path == "." {
        msg.to_string()
    } else {
        format!("'{rest}': {msg}")
    }
}

/// Read an enum tagged by `kind` from `v` through its derived externally tagged code `read`.
fn read_tagged<T, E: de::Error>(v: toml::Value, read: impl FnOnce(serde_path_to_error::Deserializer<'_, '_, toml::Value>) -> std::result::Result<T, toml::de::Error>) -> std::result::Result<T, E> {
    let external = external_form(v).map_err(E::custom)?;
    let mut track = serde_path_to_error::Track::new();
    let out = read(serde_path_to_error::Deserializer::new(external, &mut track));
    out.map_err(|e| E::custom(with_path(&track.path(), &e.to_string())))
}

/// `Serialize` and `Deserialize` of an enum whose derive is `remote = "Self"`, in the form
/// `{kind = "<variant>", <fields>}`.
macro_rules! tagged_by_kind {
    ($t:ty) => {
        impl Serialize for $t {
            fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
                struct External<'a>(&'a $t);
                impl Serialize for External<'_> {
                    fn serialize<S2: serde::Serializer>(&self, s: S2) -> std::result::Result<S2::Ok, S2::Error> {
                        <$t>::serialize(self.0, s)
                    }
                }
                let v = toml::Value::try_from(External(self)).map_err(serde::ser::Error::custom)?;
                internal_form(v).map_err(serde::ser::Error::custom)?.serialize(s)
            }
        }
        impl<'de> Deserialize<'de> for $t {
            fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
                read_tagged(toml::Value::deserialize(d)?, |de| <$t>::deserialize(de))
            }
        }
    };
}

// ---- value forms shared by the specs ---------------------------------------------------------

/// One number or a list of them (gains: one for every joint, or one per joint).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(transparent)]
pub struct Gains(pub Vec<f64>);

impl<'de> Deserialize<'de> for Gains {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Gains;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number or a list of numbers")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> std::result::Result<Gains, E> {
                Ok(Gains(vec![v]))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> std::result::Result<Gains, E> {
                Ok(Gains(vec![v as f64]))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> std::result::Result<Gains, E> {
                Ok(Gains(vec![v as f64]))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> std::result::Result<Gains, A::Error> {
                let mut out = Vec::new();
                while let Some(v) = seq.next_element::<f64>()? {
                    out.push(v);
                }
                Ok(Gains(out))
            }
        }
        d.deserialize_any(V)
    }
}

/// A per-axis limit: one number for all three axes of 𝒥, or three.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(transparent)]
pub struct PerAxis(pub [f64; 3]);

impl<'de> Deserialize<'de> for PerAxis {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let g = Gains::deserialize(d)?;
        match g.0.as_slice() {
            [v] => Ok(PerAxis([*v; 3])),
            [a, b, c] => Ok(PerAxis([*a, *b, *c])),
            other => Err(de::Error::invalid_length(other.len(), &"one number or three (one per axis)")),
        }
    }
}

impl Default for PerAxis {
    fn default() -> Self {
        PerAxis([f64::INFINITY; 3])
    }
}

/// Rows of knot values: a list of rows (K × n), or a list of numbers (K × 1).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(transparent)]
pub struct Rows(pub Vec<Vec<f64>>);

impl<'de> Deserialize<'de> for Rows {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Row {
            One(f64),
            Many(Vec<f64>),
        }
        let rows = Vec::<Row>::deserialize(d)?;
        Ok(Rows(rows.into_iter().map(|r| match r {
            Row::One(v) => vec![v],
            Row::Many(v) => v,
        }).collect()))
    }
}

/// A body: its index (0 the base) or its name.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum BodySpec {
    /// The body's index.
    Index(usize),
    /// The body's name.
    Name(String),
}

/// A point of the robot: a point name or a body name (its CM), or `[body, offset]` with the
/// offset in the body's frame from its CM, m. Absent: the end effector.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum PointSpec {
    /// A named point of the model, or a body's name (its CM).
    Named(String),
    /// A body and an offset in its frame, m.
    At(BodySpec, [f64; 3]),
}

impl PointSpec {
    /// `(body, offset)` on `model`; `None` resolves to the end effector.
    pub fn resolve(point: Option<&PointSpec>, model: &Model) -> Result<(usize, Vector3<f64>)> {
        let body_index = |b: &BodySpec| -> Result<usize> {
            match b {
                BodySpec::Index(i) if *i < model.n_bodies() => Ok(*i),
                BodySpec::Index(i) => Err(SpacearmError::NotFound(format!("body index {i}: the model has {} bodies (0 is the base)", model.n_bodies()))),
                BodySpec::Name(n) => model.body_index(n),
            }
        };
        let named = |name: &str| -> Result<(usize, Vector3<f64>)> {
            match model.points().iter().find(|p| p.name == name) {
                Some(p) => Ok((p.body, p.offset)),
                None => Ok((model.body_index(name)?, Vector3::zeros())),
            }
        };
        match point {
            None => match model.end_effector() {
                Some(k) => Ok((model.points()[k].body, model.points()[k].offset)),
                None => Err(SpacearmError::NotFound("the model has no end effector; name a point or give [body, offset]".into())),
            },
            Some(PointSpec::Named(n)) => named(n),
            Some(PointSpec::At(b, off)) => {
                let off = Vector3::from(*off);
                if !off.iter().all(|v| v.is_finite()) {
                    return Err(bad(format!("a point's offset must be finite, got {:?}", off.as_slice())));
                }
                Ok((body_index(b)?, off))
            }
        }
    }
}

/// The rows of a point twist a task drives: a name of [`TASK_NAMES`], `"auto"` (`"planar"` for
/// a planar arm with every joint axis along z, else `"position"`), or row indices 0–5.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum TaskSpec {
    /// A named task or `"auto"`.
    Named(String),
    /// Row indices into `[v; ω]`.
    Rows(Vec<usize>),
}

/// The named tasks: rows of the point twist `[vx, vy, vz, ωx, ωy, ωz]` (in 𝒥). The one table
/// (exported to Python as `_core.TASKS`).
pub const TASK_NAMES: &[(&str, &[usize])] = &[
    ("position", &[0, 1, 2]),
    ("planar", &[0, 1]),
    ("planar_pose", &[0, 1, 5]),
    ("orientation", &[3, 4, 5]),
    ("full", &[0, 1, 2, 3, 4, 5]),
];

impl Default for TaskSpec {
    fn default() -> Self {
        TaskSpec::Named("position".into())
    }
}

impl TaskSpec {
    /// The task's rows on `model`.
    pub fn resolve(&self, model: &Model) -> Result<Task> {
        match self {
            TaskSpec::Rows(r) => Task::new(r),
            TaskSpec::Named(n) if n == "auto" => Task::new(if is_planar(model)? { &[0, 1] } else { &[0, 1, 2] }),
            TaskSpec::Named(n) => match TASK_NAMES.iter().find(|(k, _)| k == n) {
                Some((_, rows)) => Task::new(rows),
                None => {
                    let names: Vec<&str> = TASK_NAMES.iter().map(|(k, _)| *k).collect();
                    Err(bad(format!("unknown task '{n}': expected one of {}, auto, or a list of rows 0-5", names.join(", "))))
                }
            },
        }
    }
}

/// Whether every joint axis is along z (in 𝒥) at the initial configuration: a planar arm in
/// the x–y plane (what task `"auto"` reads).
pub fn is_planar(model: &Model) -> Result<bool> {
    let mut x = vec![0.0; model.nx()];
    x[6] = 1.0;
    x[7..].copy_from_slice(model.initial_q());
    let mut data = Data::new(model);
    forward_kinematics(model, &mut data, &x)?;
    let n = model.n_dof();
    Ok(n > 0 && (0..n).all(|d| (data.joint_axis_in_world[model.body_of_dof(d)][2].abs() - 1.0).abs() < 1e-12))
}

fn finite(what: &str, v: f64) -> Result<f64> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(bad(format!("{what} must be finite, got {v}")))
    }
}

fn positive_or_inf(what: &str, v: f64) -> Result<f64> {
    if v > 0.0 {
        Ok(v)
    } else {
        Err(bad(format!("{what} must be > 0 (inf: no limit), got {v}")))
    }
}

fn unit_quaternion(what: &str, q: [f64; 4]) -> Result<[f64; 4]> {
    let norm = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    if (norm - 1.0).abs() > QUATERNION_TOLERANCE || norm.is_nan() {
        return Err(SpacearmError::NotUnitQuaternion { what: what.into(), norm, tolerance: QUATERNION_TOLERANCE });
    }
    Ok(q)
}

fn orbit(o: &Option<Orbit>) -> Result<Option<Orbit>> {
    o.map(|o| Orbit::from_state(o.body, o.r0, o.v0, o.j2)).transpose()
}

// ---- references ------------------------------------------------------------------------------

/// A joint-space reference of the arm joints ([`JointReference`]); a plain list of numbers is a
/// constant set point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(remote = "Self", rename_all = "snake_case", deny_unknown_fields)]
pub enum JointReferenceSpec {
    /// Hold `q` (rad or m per arm joint).
    Constant {
        /// The set point.
        q: Vec<f64>,
    },
    /// Rest-to-rest quintic from `q_start` to `q_goal` over `[t_start, t_end]`, s (the core's
    /// own data, [`Quintic`]).
    Quintic(Quintic),
    /// The quintic Hermite interpolant of knots `t` (K ≥ 2, increasing) with `q`, `qd`, `qdd`
    /// (K × n each).
    Sampled(SampledSpec),
    /// `reference` convolved with an input shaper.
    Shaped {
        /// The reference shaped.
        reference: Box<JointReferenceSpec>,
        /// The shaper.
        shaper: ShaperSpec,
    },
}

impl Serialize for JointReferenceSpec {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        struct External<'a>(&'a JointReferenceSpec);
        impl Serialize for External<'_> {
            fn serialize<S2: serde::Serializer>(&self, s: S2) -> std::result::Result<S2::Ok, S2::Error> {
                JointReferenceSpec::serialize(self.0, s)
            }
        }
        let v = toml::Value::try_from(External(self)).map_err(serde::ser::Error::custom)?;
        internal_form(v).map_err(serde::ser::Error::custom)?.serialize(s)
    }
}

impl<'de> Deserialize<'de> for JointReferenceSpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        // A set point (a list of numbers) is a constant reference.
        let v = toml::Value::deserialize(d)?;
        if let toml::Value::Array(_) = v {
            let q: Vec<f64> = v.try_into().map_err(|e: toml::de::Error| de::Error::custom(e.to_string().trim()))?;
            return Ok(JointReferenceSpec::Constant { q });
        }
        read_tagged(v, |de| JointReferenceSpec::deserialize(de))
    }
}

/// The knots of a sampled reference as rows ([`JointReference::Sampled`] keeps them row-major):
/// the data of the `sampled` joint and point references.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SampledSpec {
    /// Knot times, s.
    pub t: Vec<f64>,
    /// Positions at the knots, K × n.
    pub q: Rows,
    /// Velocities at the knots, K × n.
    pub qd: Rows,
    /// Accelerations at the knots, K × n.
    pub qdd: Rows,
}

impl SampledSpec {
    /// The core reference (checked by [`JointReference::sampled`]); `n`: the width the rows
    /// must have (`None`: that of the first row of `q`).
    pub fn build(&self, n: Option<usize>) -> Result<JointReference> {
        let k = self.t.len();
        let (q, n) = flatten("q", &self.q, k, n)?;
        let (qd, _) = flatten("qd", &self.qd, k, Some(n))?;
        let (qdd, _) = flatten("qdd", &self.qdd, k, Some(n))?;
        JointReference::sampled(self.t.clone(), q, qd, qdd, n)
    }
}

/// `(values, n)` of K rows of n columns, row-major, or an error naming `what`.
fn flatten(what: &str, rows: &Rows, k: usize, n: Option<usize>) -> Result<(Vec<f64>, usize)> {
    let n = n.or_else(|| rows.0.first().map(Vec::len)).unwrap_or(0);
    if rows.0.len() != k || rows.0.iter().any(|r| r.len() != n) {
        let shape: Vec<usize> = rows.0.iter().map(Vec::len).collect();
        return Err(SpacearmError::Dimension {
            what: format!("sampled reference '{what}'"),
            expected: format!("{k} rows (one per knot time) of {n} values, the same n for q, qd and qdd"),
            got: if rows.0.len() != k { rows.0.len() } else { shape.into_iter().find(|&l| l != n).unwrap_or(0) },
        });
    }
    Ok((rows.0.concat(), n))
}

impl JointReferenceSpec {
    /// The core reference (checked by its constructors).
    pub fn build(&self) -> Result<JointReference> {
        match self {
            JointReferenceSpec::Constant { q } => JointReference::constant(q.clone()),
            JointReferenceSpec::Quintic(motion) => JointReference::from_quintic(motion.clone()),
            JointReferenceSpec::Sampled(knots) => knots.build(None),
            JointReferenceSpec::Shaped { reference, shaper } => Ok(shaper.build()?.shape(reference.build()?)),
        }
    }
}

/// A ZV or ZVD input shaper for the mode of natural `frequency` (rad/s) and `damping` ratio
/// ([`InputShaper`], Singer & Seering 1990).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShaperSpec {
    /// `"zv"` or `"zvd"` ([`ShaperKind::NAMES`]).
    pub kind: String,
    /// Natural frequency of the mode, rad/s.
    pub frequency: f64,
    /// Damping ratio of the mode, 0 ≤ ζ < 1.
    #[serde(default)]
    pub damping: f64,
}

impl ShaperSpec {
    /// The shaper (checked by [`InputShaper::new`]).
    pub fn build(&self) -> Result<InputShaper> {
        InputShaper::new(ShaperKind::from_name(&self.kind)?, self.frequency, self.damping)
    }
}

/// A moving point that a point controller follows ([`PointReference`]), with the robot's point
/// that follows it (absent: the end effector, or the controller's own `point`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(remote = "Self", rename_all = "snake_case", deny_unknown_fields)]
pub enum PointReferenceSpec {
    /// A straight line from `p_start` to `p_goal` (m, in 𝒥) with quintic timing.
    Line {
        /// Start point, m, in 𝒥.
        p_start: [f64; 3],
        /// End point, m, in 𝒥.
        p_goal: [f64; 3],
        /// Start of the motion, s.
        t_start: f64,
        /// End of the motion, s.
        t_end: f64,
        /// The robot's point that follows the line.
        #[serde(default)]
        point: Option<PointSpec>,
    },
    /// A point fixed to a rigid body moving freely (the grasp point of a tumbling target).
    FreeBody {
        /// The body and its point (its fields stand beside `point` and `orbit`).
        #[serde(flatten)]
        body: FreeBodySpec,
        /// The robot's point that follows it.
        #[serde(default)]
        point: Option<PointSpec>,
        /// The run's orbit (the state relative to its point at time 0, ECI axes; docs/orbit.md).
        #[serde(default)]
        orbit: Option<Orbit>,
    },
    /// A sampled path of the point's three coordinates in 𝒥 (a [`JointReference::Sampled`] of 3:
    /// rows of 3).
    Sampled(SampledSpec),
}

tagged_by_kind!(PointReferenceSpec);

impl PointReferenceSpec {
    /// The robot's point this reference names, if any.
    pub fn point(&self) -> Option<&PointSpec> {
        match self {
            PointReferenceSpec::Line { point, .. } | PointReferenceSpec::FreeBody { point, .. } => point.as_ref(),
            PointReferenceSpec::Sampled { .. } => None,
        }
    }

    /// The line of a `Line` spec (checked by [`CartesianLine::new`]).
    pub fn line(&self) -> Result<CartesianLine> {
        match self {
            PointReferenceSpec::Line { p_start, p_goal, t_start, t_end, .. } => CartesianLine::new(Vector3::from(*p_start), Vector3::from(*p_goal), *t_start, *t_end),
            _ => Err(bad("this controller needs a straight-line reference (kind 'line')")),
        }
    }

    /// The free body of a `FreeBody` spec (checked by [`FreeBody::new`]).
    pub fn free_body(&self) -> Result<FreeBody> {
        match self {
            PointReferenceSpec::FreeBody { body, orbit, .. } => body.build_in(orbit.as_ref()),
            _ => Err(bad("not a free-body reference")),
        }
    }

    /// The core reference.
    pub fn build(&self) -> Result<PointReference> {
        match self {
            PointReferenceSpec::Line { .. } => Ok(PointReference::Line(self.line()?)),
            PointReferenceSpec::FreeBody { .. } => Ok(PointReference::FreeBody(Box::new(self.free_body()?))),
            PointReferenceSpec::Sampled(knots) => Ok(PointReference::Sampled(knots.build(Some(3))?)),
        }
    }
}

// ---- actuator limits -------------------------------------------------------------------------

/// Base thruster limits per axis of 𝒥 ([`ThrusterLimits`]); a number applies to all three axes,
/// `inf` (the default) means no limit.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct ThrusterLimitsSpec {
    /// Largest force per axis, N.
    #[serde(default)]
    pub max_force: PerAxis,
    /// Largest torque per axis, N·m.
    #[serde(default)]
    pub max_torque: PerAxis,
}

impl ThrusterLimitsSpec {
    /// The limits (checked by [`ThrusterLimits::new`]).
    pub fn build(&self) -> Result<ThrusterLimits> {
        ThrusterLimits::new(Vector3::from(self.max_force.0), Vector3::from(self.max_torque.0))
    }
}

// ---- controllers -----------------------------------------------------------------------------

/// A controller's own model of the plant, as the TOML text of a model file (docs/model-files.md):
/// the form every door can carry, bit-exact (floats in shortest round-trip form).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct ModelText(pub String);

impl ModelText {
    fn build(text: &Option<ModelText>) -> Result<Option<Model>> {
        text.as_ref().map(|t| crate::io::toml::model_from_toml_str(&t.0, "a controller's model")).transpose()
    }
}

fn inf() -> f64 {
    f64::INFINITY
}
fn one() -> f64 {
    1.0
}
fn two() -> f64 {
    2.0
}
fn drift() -> String {
    PassiveTreatment::Drift.name().into()
}
fn naive() -> String {
    "naive".into()
}
fn dls_max_damping() -> f64 {
    crate::math::dls::DampingLaw::default().max_damping
}
fn dls_threshold() -> f64 {
    crate::math::dls::DampingLaw::default().threshold
}
fn sr_lambda0() -> f64 {
    0.01
}

fn fifty() -> f64 {
    50.0
}
fn hundred() -> f64 {
    100.0
}
fn twenty() -> f64 {
    20.0
}
fn twenty_five() -> f64 {
    25.0
}
fn ten() -> f64 {
    10.0
}

fn half_pi() -> f64 {
    std::f64::consts::FRAC_PI_2
}
fn unload_above() -> f64 {
    0.8
}
fn unload_below() -> f64 {
    0.2
}

/// A native control law and everything it needs, as data. The serde tag `kind` is the law's
/// name ([`CONTROLLER_KINDS`]); each variant's fields are the law's parameters, with the units
/// and defaults of `spacearm.control` (docs/simulation-core.md).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(remote = "Self", rename_all = "snake_case", deny_unknown_fields)]
pub enum ControllerSpec {
    /// No control: zero joint torques and no base wrench.
    None {},
    /// Joint PD on the actuated arm joints ([`JointPd`]).
    JointPd {
        /// Proportional gains, one or one per actuated arm joint, N·m/rad.
        kp: Gains,
        /// Derivative gains, N·m·s/rad.
        kd: Gains,
        /// The joint reference (a list: a constant set point).
        reference: JointReferenceSpec,
    },
    /// Computed torque on the reduced equations of motion ([`ComputedTorque`], paper eqs. 112–115).
    ComputedTorque {
        /// Proportional gains, 1/s².
        kp: Gains,
        /// Derivative gains, 1/s.
        kd: Gains,
        /// The joint reference.
        reference: JointReferenceSpec,
        /// The controller's own model (absent: the plant's).
        #[serde(default)]
        model: Option<ModelText>,
        /// The passive joints: `"drift"` (measured) or `"frozen"` (a rigid model).
        #[serde(default = "drift")]
        passive: String,
    },
    /// Resolved-motion-rate control of a point through `J*` ([`ResolvedMotionRate`], paper eq. 110).
    ResolvedMotionRate {
        /// The point's path (`reference_cartesian`: Python's spelling).
        #[serde(alias = "reference_cartesian")]
        reference: PointReferenceSpec,
        /// Position feedback gain, 1/s.
        gain: f64,
        /// The largest damping λ_max, m.
        #[serde(default = "dls_max_damping")]
        max_damping: f64,
        /// The singular value below which damping starts, m.
        #[serde(default = "dls_threshold")]
        threshold: f64,
        /// Joint-rate tracking gain, 1/s.
        #[serde(default = "fifty")]
        velocity_gain: f64,
        /// The robot's point (absent: the reference's, else the end effector).
        #[serde(default)]
        point: Option<PointSpec>,
        /// The cap on the joint-rate command, rad/s or m/s (inf: none).
        #[serde(default = "inf")]
        max_joint_rate: f64,
        /// The rows of the point twist driven.
        #[serde(default)]
        task: TaskSpec,
        /// The treatment of the base: `"naive"`, `"reactionless"` or `"minimum_disturbance"`.
        #[serde(default = "naive")]
        strategy: String,
    },
    /// Base attitude control with reaction wheels ([`AttitudeControl`]).
    Attitude {
        /// The attitude held, `[x, y, z, w]` of 𝒥 (with `orbit`: of LVLH).
        quat_ref: [f64; 4],
        /// Stiffness, N·m/rad.
        kp: f64,
        /// Damping, N·m·s/rad.
        kd: f64,
        /// Hold the attitude relative to this orbit's LVLH frame (docs/orbit.md).
        #[serde(default)]
        orbit: Option<Orbit>,
    },
    /// Base attitude control with the plant's CMG cluster ([`CmgSteering`], docs/cmg.md).
    CmgSteering {
        /// The attitude held, `[x, y, z, w]` of 𝒥.
        quat_ref: [f64; 4],
        /// Stiffness, N·m/rad.
        kp: f64,
        /// Damping, N·m·s/rad.
        kd: f64,
        /// The SR inverse's weight `λ₀` (dimensionless; 0: the pseudo-inverse).
        #[serde(default = "sr_lambda0")]
        lambda0: f64,
        /// The SR inverse's `μ` in `λ = λ₀ h̄² exp(−μ m)`.
        #[serde(default = "ten")]
        mu: f64,
        /// The gimbal rate loop's bandwidth, 1/s.
        #[serde(default = "fifty")]
        rate_gain: f64,
        /// The GSR inverse's dither amplitude `ε₀` (dimensionless, `< 1/2`; 0: the SR inverse).
        #[serde(default)]
        dither: f64,
        /// The dither's frequency, rad/s (Wie's π/2).
        #[serde(default = "half_pi")]
        dither_frequency: f64,
        /// The null-motion gain, rad/s (0: no null motion).
        #[serde(default)]
        null_gain: f64,
        /// The VSCMG steering's wheel weight `W_s0` ([`crate::control::vscmg_steering`]; 0: the
        /// gimbals alone).
        #[serde(default)]
        wheel_weight: f64,
        /// Its `μ` in `W_s = W_s0 exp(−μ m)`.
        #[serde(default = "ten")]
        wheel_mu: f64,
        /// Momentum unloading by the thrusters ([`crate::control::cmg_unloading`]): the gain
        /// `k` of `N_u = −k (H − H_goal)`, 1/s (0: no unloading).
        #[serde(default)]
        unload_gain: f64,
        /// The envelope fraction at which unloading starts.
        #[serde(default = "unload_above")]
        unload_above: f64,
        /// The envelope fraction at which it stops.
        #[serde(default = "unload_below")]
        unload_below: f64,
        /// `H_goal`, the cluster momentum unloading drives to, N·m·s in 𝒥.
        #[serde(default)]
        unload_goal: [f64; 3],
    },
    /// Base regulation by thrusters ([`BaseThrusterControl`]).
    BaseThrusters {
        /// The system CM held, m, in 𝒥 (absent: the initial one).
        #[serde(default)]
        com_ref: Option<[f64; 3]>,
        /// The base attitude held (absent: the initial one).
        #[serde(default)]
        quat_ref: Option<[f64; 4]>,
        /// CM stiffness, 1/s².
        #[serde(default = "one")]
        kp_position: f64,
        /// CM damping, 1/s.
        #[serde(default = "two")]
        kd_position: f64,
        /// Attitude stiffness, N·m/rad.
        #[serde(default)]
        kp_attitude: f64,
        /// Attitude damping, N·m·s/rad.
        #[serde(default)]
        kd_attitude: f64,
        /// Hold the attitude relative to this orbit's LVLH frame.
        #[serde(default)]
        orbit: Option<Orbit>,
    },
    /// Coordinated end-effector and base-pose control in the flying mode ([`CoordinatedFlying`]).
    CoordinatedFlying {
        /// The end effector's straight line (kind `"line"`).
        ee_reference: PointReferenceSpec,
        /// The base pose held, `[r0, quat]` (absent: the initial one).
        #[serde(default)]
        base_pose_ref: Option<([f64; 3], [f64; 4])>,
        /// End-effector stiffness, 1/s².
        #[serde(default = "hundred")]
        kp_ee: f64,
        /// End-effector damping, 1/s.
        #[serde(default = "twenty")]
        kd_ee: f64,
        /// Base stiffness, 1/s².
        #[serde(default = "twenty_five")]
        kp_base: f64,
        /// Base damping, 1/s.
        #[serde(default = "ten")]
        kd_base: f64,
        /// The robot's point (absent: the reference's, else the end effector).
        #[serde(default)]
        point: Option<PointSpec>,
        /// The largest damping λ_max, m.
        #[serde(default = "dls_max_damping")]
        max_damping: f64,
        /// The singular value below which damping starts, m.
        #[serde(default = "dls_threshold")]
        threshold: f64,
    },
    /// Thruster damping of the system momentum ([`MomentumDamping`]).
    MomentumDamping {
        /// Time constant τ, s.
        time_constant: f64,
        /// Norm limit of the force, N (inf: none).
        #[serde(default = "inf")]
        max_force: f64,
        /// Norm limit of the torque, N·m (inf: none).
        #[serde(default = "inf")]
        max_torque: f64,
        /// The law's model of the plant (absent: the plant's).
        #[serde(default)]
        model: Option<ModelText>,
    },
    /// Receding-horizon model-predictive control ([`ModelPredictive`], docs/mpc.md): the
    /// problem solved at every sample, its first control held until the next.
    Mpc {
        /// The optimal-control problem (the data of a one-off solve, `spacearm.mpc.Problem`).
        problem: ProblemSpec,
        /// The horizon, steps (absent: the problem's).
        #[serde(default)]
        horizon: Option<usize>,
        /// The step of the plan and the sample period of the law, s (absent: the problem's).
        #[serde(default)]
        dt: Option<f64>,
        /// The most solver iterations per sample.
        #[serde(default = "ten_iterations")]
        max_iterations: usize,
        /// The most wall-clock time per solve, s (absent: none; with it the states depend on
        /// the machine's speed).
        #[serde(default)]
        time_limit: Option<f64>,
    },
    /// An arm controller and a base controller together ([`Combined`]): the base runs first.
    Combined {
        /// The arm controller.
        arm: Box<ControllerSpec>,
        /// The base controller.
        base: Box<ControllerSpec>,
    },
    /// Another controller's joint torques clamped to `±limit` ([`JointTorqueLimit`]).
    TorqueLimit {
        /// The clamped controller.
        controller: Box<ControllerSpec>,
        /// The limit, N·m (N for prismatic joints).
        limit: f64,
    },
    /// A controller the door supplies (a Python callable), by its index in the door's list.
    External {
        /// The index.
        index: usize,
    },
}

tagged_by_kind!(ControllerSpec);

/// The controller kinds (the serde tags of [`ControllerSpec`]), each with the words a person
/// reads ([`super::CONTROLLER_LABELS`] names the controllers that ran).
pub const CONTROLLER_KINDS: &[&str] = &[
    "none",
    "joint_pd",
    "computed_torque",
    "resolved_motion_rate",
    "attitude",
    "cmg_steering",
    "base_thrusters",
    "coordinated_flying",
    "momentum_damping",
    "mpc",
    "combined",
    "torque_limit",
    "external",
];

/// Short names the CLI and campaigns accept for a kind (besides the kind itself and its
/// hyphenated spelling, `computed-torque`).
pub const CONTROLLER_ALIASES: &[(&str, &str)] = &[("pd", "joint_pd"), ("ct", "computed_torque"), ("rmrc", "resolved_motion_rate"), ("coordinated", "coordinated_flying")];

/// The kind a user's name means: a kind of [`CONTROLLER_KINDS`], its hyphenated spelling, or an
/// alias of [`CONTROLLER_ALIASES`].
pub fn controller_kind(name: &str) -> Result<&'static str> {
    let snake = name.trim().replace('-', "_");
    if let Some(k) = CONTROLLER_KINDS.iter().find(|k| **k == snake) {
        return Ok(k);
    }
    if let Some((_, k)) = CONTROLLER_ALIASES.iter().find(|(a, _)| *a == snake) {
        return Ok(k);
    }
    let aliases: Vec<&str> = CONTROLLER_ALIASES.iter().map(|(a, _)| *a).collect();
    Err(bad(format!("unknown controller '{name}': expected one of {} (or {})", CONTROLLER_KINDS.join(", "), aliases.join(", "))))
}

impl ControllerSpec {
    /// The kind (the serde tag).
    pub fn kind(&self) -> &'static str {
        match self {
            ControllerSpec::None {} => "none",
            ControllerSpec::JointPd { .. } => "joint_pd",
            ControllerSpec::ComputedTorque { .. } => "computed_torque",
            ControllerSpec::ResolvedMotionRate { .. } => "resolved_motion_rate",
            ControllerSpec::Attitude { .. } => "attitude",
            ControllerSpec::CmgSteering { .. } => "cmg_steering",
            ControllerSpec::BaseThrusters { .. } => "base_thrusters",
            ControllerSpec::CoordinatedFlying { .. } => "coordinated_flying",
            ControllerSpec::MomentumDamping { .. } => "momentum_damping",
            ControllerSpec::Mpc { .. } => "mpc",
            ControllerSpec::Combined { .. } => "combined",
            ControllerSpec::TorqueLimit { .. } => "torque_limit",
            ControllerSpec::External { .. } => "external",
        }
    }

    /// The spec as the TOML text of a `[controller]` table (what the C stepper and the FMUs read);
    /// refused for an `external` controller, which only its door can run.
    pub fn to_toml(&self) -> Result<String> {
        if self.walk().iter().any(|s| matches!(s, ControllerSpec::External { .. })) {
            return Err(bad("a Python callback controller cannot be written to a file: it runs only from Python"));
        }
        toml::to_string(self).map_err(|e| bad(format!("controller to TOML: {e}")))
    }

    /// The controllers inside this one, this one first (depth first).
    pub fn walk(&self) -> Vec<&ControllerSpec> {
        let mut out = vec![self];
        match self {
            ControllerSpec::Combined { arm, base } => {
                out.extend(arm.walk());
                out.extend(base.walk());
            }
            ControllerSpec::TorqueLimit { controller, .. } => out.extend(controller.walk()),
            _ => {}
        }
        out
    }

    /// Every check that needs no plant: names, finite and positive numbers, unit quaternions,
    /// the references and models (built once and dropped). The plant's checks (dimensions,
    /// points, the mode) come at [`ControllerSpec::build`] and the controller's setup.
    pub fn validate(&self) -> Result<()> {
        let w = self.kind();
        match self {
            ControllerSpec::None {} | ControllerSpec::External { .. } => {}
            ControllerSpec::JointPd { kp, kd, reference } => {
                gains(w, "kp", kp)?;
                gains(w, "kd", kd)?;
                reference.build()?;
            }
            ControllerSpec::ComputedTorque { kp, kd, reference, model, passive } => {
                gains(w, "kp", kp)?;
                gains(w, "kd", kd)?;
                reference.build()?;
                PassiveTreatment::from_name(passive)?;
                ModelText::build(model)?;
            }
            ControllerSpec::ResolvedMotionRate { reference, gain, max_damping, threshold, velocity_gain, max_joint_rate, task, strategy, .. } => {
                reference.build()?;
                for (k, v) in [("gain", gain), ("max_damping", max_damping), ("threshold", threshold), ("velocity_gain", velocity_gain)] {
                    finite(&format!("{w} '{k}'"), *v)?;
                }
                positive_or_inf(&format!("{w} 'max_joint_rate'"), *max_joint_rate)?;
                if let TaskSpec::Rows(r) = task {
                    Task::new(r)?;
                }
                Strategy::from_name(strategy)?;
            }
            ControllerSpec::Attitude { quat_ref, kp, kd, orbit: o } => {
                unit_quaternion("attitude 'quat_ref'", *quat_ref)?;
                finite(&format!("{w} 'kp'"), *kp)?;
                finite(&format!("{w} 'kd'"), *kd)?;
                orbit(o)?;
            }
            ControllerSpec::CmgSteering { quat_ref, kp, kd, lambda0, mu, rate_gain, dither, dither_frequency, null_gain, wheel_weight, wheel_mu, unload_gain, unload_above, unload_below, unload_goal } => {
                unit_quaternion("cmg_steering 'quat_ref'", *quat_ref)?;
                if *unload_gain != 0.0 {
                    crate::control::cmg_unloading::check(*unload_gain, *unload_above, *unload_below, *unload_goal)?;
                }
                SteeringOptions { dither: *dither, dither_frequency: *dither_frequency, null_gain: *null_gain, wheel_weight: *wheel_weight, wheel_mu: *wheel_mu }.check(*lambda0)?;
                for (k, v) in [("kp", kp), ("kd", kd), ("lambda0", lambda0), ("mu", mu)] {
                    if !(v.is_finite() && *v >= 0.0) {
                        return Err(bad(format!("{w} '{k}' must be finite and >= 0, got {v}")));
                    }
                }
                if !(rate_gain.is_finite() && *rate_gain > 0.0) {
                    return Err(bad(format!("{w} 'rate_gain' must be finite and > 0 1/s, got {rate_gain}")));
                }
            }
            ControllerSpec::BaseThrusters { com_ref, quat_ref, kp_position, kd_position, kp_attitude, kd_attitude, orbit: o } => {
                for (k, v) in [("kp_position", kp_position), ("kd_position", kd_position), ("kp_attitude", kp_attitude), ("kd_attitude", kd_attitude)] {
                    finite(&format!("{w} '{k}'"), *v)?;
                }
                if let Some(c) = com_ref {
                    c.iter().try_for_each(|v| finite(&format!("{w} 'com_ref'"), *v).map(|_| ()))?;
                }
                if let Some(q) = quat_ref {
                    unit_quaternion("base_thrusters 'quat_ref'", *q)?;
                }
                orbit(o)?;
            }
            ControllerSpec::CoordinatedFlying { ee_reference, base_pose_ref, kp_ee, kd_ee, kp_base, kd_base, max_damping, threshold, .. } => {
                ee_reference.line()?;
                for (k, v) in [("kp_ee", kp_ee), ("kd_ee", kd_ee), ("kp_base", kp_base), ("kd_base", kd_base), ("max_damping", max_damping), ("threshold", threshold)] {
                    finite(&format!("{w} '{k}'"), *v)?;
                }
                if let Some((r, q)) = base_pose_ref {
                    r.iter().try_for_each(|v| finite(&format!("{w} base position"), *v).map(|_| ()))?;
                    unit_quaternion("coordinated_flying base quaternion", *q)?;
                }
            }
            ControllerSpec::MomentumDamping { time_constant, max_force, max_torque, model } => {
                if !(time_constant.is_finite() && *time_constant > 0.0) {
                    return Err(bad(format!("momentum_damping 'time_constant' must be finite and > 0 s, got {time_constant}")));
                }
                positive_or_inf(&format!("{w} 'max_force'"), *max_force)?;
                positive_or_inf(&format!("{w} 'max_torque'"), *max_torque)?;
                ModelText::build(model)?;
            }
            ControllerSpec::Mpc { .. } => {
                self.mpc_law()?;
            }
            ControllerSpec::Combined { arm, base } => {
                arm.validate()?;
                base.validate()?;
            }
            ControllerSpec::TorqueLimit { controller, limit } => {
                positive_or_inf(&format!("{w} 'limit'"), *limit)?;
                controller.validate()?;
            }
        }
        Ok(())
    }

    /// A fresh controller for a run on `plant` (each run owns its controller: they keep
    /// workspaces). `external(index)` supplies a `kind = "external"` controller; a door that has
    /// none passes [`no_external`].
    pub fn build(&self, plant: &Model, external: &mut dyn FnMut(usize) -> Result<Box<dyn Controller>>) -> Result<Box<dyn Controller>> {
        self.validate()?;
        self.build_checked(plant, external)
    }

    fn build_checked(&self, plant: &Model, external: &mut dyn FnMut(usize) -> Result<Box<dyn Controller>>) -> Result<Box<dyn Controller>> {
        Ok(match self {
            ControllerSpec::None {} => Box::new(ZeroTorque),
            ControllerSpec::JointPd { kp, kd, reference } => Box::new(JointPd::new(kp.0.clone(), kd.0.clone(), reference.build()?)),
            ControllerSpec::ComputedTorque { kp, kd, reference, model, passive } => {
                Box::new(ComputedTorque::new(kp.0.clone(), kd.0.clone(), reference.build()?, ModelText::build(model)?).with_passive(PassiveTreatment::from_name(passive)?))
            }
            ControllerSpec::ResolvedMotionRate { reference, gain, max_damping, threshold, velocity_gain, point, max_joint_rate, task, strategy } => {
                let (body, offset) = PointSpec::resolve(point.as_ref().or(reference.point()), plant)?;
                Box::new(
                    ResolvedMotionRate::new(reference.build()?, *gain, *max_damping, *threshold, *velocity_gain, body, offset)
                        .with_max_joint_rate(*max_joint_rate)
                        .with_task(task.resolve(plant)?)
                        .with_strategy(Strategy::from_name(strategy)?),
                )
            }
            ControllerSpec::Attitude { quat_ref, kp, kd, orbit: o } => {
                let c = AttitudeControl::new(*quat_ref, *kp, *kd);
                match orbit(o)? {
                    Some(o) => Box::new(c.with_lvlh(LvlhReference::new(&o, Some(*quat_ref))?)),
                    None => Box::new(c),
                }
            }
            ControllerSpec::CmgSteering { quat_ref, kp, kd, lambda0, mu, rate_gain, dither, dither_frequency, null_gain, wheel_weight, wheel_mu, unload_gain, unload_above, unload_below, unload_goal } => {
                let law = CmgSteering::new(*quat_ref, *kp, *kd, *lambda0, *mu, *rate_gain)
                    .with_options(SteeringOptions { dither: *dither, dither_frequency: *dither_frequency, null_gain: *null_gain, wheel_weight: *wheel_weight, wheel_mu: *wheel_mu });
                if *unload_gain != 0.0 {
                    Box::new(law.with_unloading(MomentumUnloading::new(*unload_gain, *unload_above, *unload_below, *unload_goal)?))
                } else {
                    Box::new(law)
                }
            }
            ControllerSpec::BaseThrusters { com_ref, quat_ref, kp_position, kd_position, kp_attitude, kd_attitude, orbit: o } => {
                let c = BaseThrusterControl::new(com_ref.map(Vector3::from), *quat_ref, *kp_position, *kd_position, *kp_attitude, *kd_attitude);
                match orbit(o)? {
                    Some(o) => Box::new(c.with_lvlh(LvlhReference::new(&o, *quat_ref)?)),
                    None => Box::new(c),
                }
            }
            ControllerSpec::CoordinatedFlying { ee_reference, base_pose_ref, kp_ee, kd_ee, kp_base, kd_base, point, max_damping, threshold } => {
                let (body, offset) = PointSpec::resolve(point.as_ref().or(ee_reference.point()), plant)?;
                let gains = CoordinatedGains { kp_ee: *kp_ee, kd_ee: *kd_ee, kp_base: *kp_base, kd_base: *kd_base };
                let base_ref = base_pose_ref.map(|(r, q)| (Vector3::from(r), q));
                Box::new(CoordinatedFlying::new(ee_reference.line()?, body, offset, base_ref, gains, *max_damping, *threshold))
            }
            ControllerSpec::MomentumDamping { time_constant, max_force, max_torque, model } => {
                Box::new(MomentumDamping::new(*time_constant, *max_force, *max_torque, ModelText::build(model)?))
            }
            ControllerSpec::Mpc { .. } => Box::new(self.mpc_law()?),
            ControllerSpec::Combined { arm, base } => Box::new(Combined::new(arm.build_checked(plant, external)?, base.build_checked(plant, external)?)),
            ControllerSpec::TorqueLimit { controller, limit } => Box::new(JointTorqueLimit::new(controller.build_checked(plant, external)?, *limit)),
            ControllerSpec::External { index } => external(*index)?,
        })
    }
}

impl ControllerSpec {
    /// The law of an `mpc` spec (its numbers checked); `None` for every other kind.
    fn mpc_law(&self) -> Result<ModelPredictive> {
        let ControllerSpec::Mpc { problem, horizon, dt, max_iterations, time_limit } = self else {
            return Err(bad(format!("{} is not an mpc law", self.kind())));
        };
        if let Some(t) = time_limit {
            if !(*t > 0.0) {
                return Err(bad(format!("mpc 'time_limit' must be > 0 s (absent: none), got {t}")));
            }
        }
        ModelPredictive::new(problem, horizon.unwrap_or(problem.horizon), dt.unwrap_or(problem.dt), *max_iterations, time_limit.unwrap_or(f64::INFINITY))

    }
}

fn ten_iterations() -> usize {
    10
}

/// The `external` supplier of a door that has no controllers of its own (C, the FMUs, files).
pub fn no_external(index: usize) -> Result<Box<dyn Controller>> {
    Err(bad(format!("controller kind 'external' (index {index}) is a callable supplied from Python; this door has none")))
}

fn gains(w: &str, what: &str, g: &Gains) -> Result<()> {
    if g.0.is_empty() {
        return Err(bad(format!("{w} '{what}' must be a number or a non-empty list of numbers")));
    }
    if let Some(v) = g.0.iter().find(|v| !(v.is_finite() && **v >= 0.0)) {
        return Err(bad(format!("{w} '{what}' must be finite and >= 0, got {v}")));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::presets;

    fn spec(text: &str) -> Result<ControllerSpec> {
        toml::from_str(text).map_err(|e| bad(e.to_string()))
    }

    #[test]
    fn every_kind_is_a_tag_and_a_label() {
        for k in CONTROLLER_KINDS {
            assert_eq!(controller_kind(k).unwrap(), *k);
            assert_eq!(controller_kind(&k.replace('_', "-")).unwrap(), *k);
        }
        let labelled: Vec<&str> = super::super::CONTROLLER_LABELS.iter().map(|(k, _)| *k).collect();
        for k in CONTROLLER_KINDS.iter().filter(|k| !["torque_limit", "external"].contains(k)) {
            assert!(labelled.contains(k), "{k} has no label");
        }
        assert!(controller_kind("nonsense").is_err());
        // The table is the enum's tags, no more and no fewer: every kind is a variant (a table
        // naming it fails on its fields, never on its kind), and a kind not in the table is not.
        for k in CONTROLLER_KINDS {
            match spec(&format!("kind = '{k}'")) {
                Ok(s) => assert_eq!(s.kind(), *k),
                Err(e) => assert!(e.to_string().contains("missing field"), "{k}: {e}"),
            }
        }
        assert!(spec("kind = 'lqr'").unwrap_err().to_string().contains("unknown variant"));
    }

    #[test]
    fn a_set_point_is_a_constant_reference_and_gains_broadcast() {
        let s = spec("kind = 'joint_pd'\nkp = 100\nkd = [1.0, 2.0]\nreference = [0.1, 0.2]").unwrap();
        match &s {
            ControllerSpec::JointPd { kp, kd, reference } => {
                assert_eq!(kp.0, vec![100.0]);
                assert_eq!(kd.0, vec![1.0, 2.0]);
                assert_eq!(reference, &JointReferenceSpec::Constant { q: vec![0.1, 0.2] });
            }
            other => panic!("{other:?}"),
        }
        // Round trip through TOML text.
        let back: ControllerSpec = toml::from_str(&toml::to_string(&s).unwrap()).unwrap();
        assert_eq!(back, s);
    }

    #[test]
    fn unknown_fields_and_bad_values_are_refused_with_their_names() {
        let e = spec("kind = 'joint_pd'\nkp = 1\nkd = 1\nreference = [0.0]\nkpp = 3").unwrap_err().to_string();
        assert!(e.contains("kpp"), "{e}");
        let e = spec("kind = 'joint_pd'\nkp = 1\nkd = 1\nreference = {kind = 'quintic', q_start = [0.0], q_goal = [1.0], t_start = 2.0, t_end = 1.0}")
            .unwrap()
            .validate()
            .unwrap_err()
            .to_string();
        assert!(e.contains("t_end"), "{e}");
        let e = spec("kind = 'attitude'\nquat_ref = [0.0, 0.0, 0.0, 2.0]\nkp = 1\nkd = 1").unwrap().validate().unwrap_err().to_string();
        assert!(e.contains("quat_ref"), "{e}");
        let e = spec("kind = 'momentum_damping'\ntime_constant = 0.0").unwrap().validate().unwrap_err().to_string();
        assert!(e.contains("time_constant"), "{e}");
        let e = spec("kind = 'joint_pd'\nkp = -1\nkd = 1\nreference = [0.0]").unwrap().validate().unwrap_err().to_string();
        assert!(e.contains("kp"), "{e}");
    }

    #[test]
    fn a_wrong_value_is_named_by_its_path() {
        let e = spec("kind = 'joint_pd'\nkp = 'a'\nkd = 1\nreference = [0.0]").unwrap_err().to_string();
        assert!(e.contains("'kp'") && e.contains("a number or a list of numbers"), "{e}");
        let e = spec("kind = 'combined'\n[arm]\nkind = 'joint_pd'\nkp = 1\nkd = 1\nreference = {kind = 'quintic', q_start = [0.0], q_goal = [1.0], t_start = 0.0, t_end = 'late'}\n[base]\nkind = 'none'")
            .unwrap_err()
            .to_string();
        assert!(e.contains("'arm'") && e.contains("'reference'") && e.contains("'t_end'"), "{e}");
        let e = spec("kind = 'resolved_motion_rate'\ngain = 1.0\nstrategy = 1\nreference = {kind = 'line', p_start = [0.0, 0.0, 0.0], p_goal = [1.0, 0.0, 0.0], t_start = 0.0, t_end = 1.0}")
            .unwrap_err()
            .to_string();
        assert!(e.contains("'strategy'"), "{e}");
        assert!(spec("kp = 1").unwrap_err().to_string().contains("missing field `kind`"));
        // And written back in the same form: `kind` and the fields side by side.
        let s = spec("kind = 'none'").unwrap();
        assert_eq!(toml::to_string(&s).unwrap().trim(), "kind = \"none\"");
    }

    #[test]
    fn points_and_tasks_resolve_on_the_plant() {
        let m = presets::planar4();
        let ee = m.end_effector().unwrap();
        let (b, off) = PointSpec::resolve(None, &m).unwrap();
        assert_eq!((b, off), (m.points()[ee].body, m.points()[ee].offset));
        let (b, off) = PointSpec::resolve(Some(&PointSpec::At(BodySpec::Index(2), [0.1, 0.0, 0.0])), &m).unwrap();
        assert_eq!((b, off), (2, Vector3::new(0.1, 0.0, 0.0)));
        assert!(PointSpec::resolve(Some(&PointSpec::Named("no such point".into())), &m).is_err());
        assert!(PointSpec::resolve(Some(&PointSpec::At(BodySpec::Index(99), [0.0; 3])), &m).is_err());
        // planar4's joint axes are all along z; spatial6's are not.
        assert_eq!(TaskSpec::Named("auto".into()).resolve(&m).unwrap().rows(), &[0, 1]);
        assert_eq!(TaskSpec::Named("auto".into()).resolve(&presets::spatial6()).unwrap().rows(), &[0, 1, 2]);
        assert!(TaskSpec::Named("sideways".into()).resolve(&m).is_err());
    }

    #[test]
    fn external_needs_a_supplier() {
        let m = presets::planar4();
        let s = spec("kind = 'external'\nindex = 0").unwrap();
        assert!(s.build(&m, &mut no_external).is_err());
        assert!(s.build(&m, &mut |_| Ok(Box::new(ZeroTorque))).is_ok());
    }
}
