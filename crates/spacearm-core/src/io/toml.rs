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
//! Every error is [`SpacearmError::Parse`] and starts with `source:line:column:`; the
//! structural ones (syntax, unknown key, wrong type, missing field) come from the TOML parser,
//! the semantic ones (unknown parent, negative mass, ...) name the link, joint or point and
//! point at the offending value. No input makes this module panic.

use std::collections::{HashMap, HashSet};
use std::fmt::Write as _;
use std::ops::Range;

use nalgebra::Matrix3;
use serde::Deserialize;
use toml::{Spanned, Value};

use crate::error::{ModelError, ModelField, ModelItem, Result, SpacearmError};
use crate::io::dh::{ClassicDhLink, DhArm, DhTable, PaperDhLink};
use crate::model::joint::{JointDynamics, JointLimits, JointType};
use crate::math::rotations::xyzw_from_rpy;
use crate::model::geometry::ShapeParts;
use crate::model::appendage::{self, beam_parts, compliant_parts, panel_parts, BeamDamping, BeamSpec, CompliantSpec, PanelBody, PanelSpec, Parts, Restoring};
use crate::model::slosh::{slosh_links, SloshModel, SloshRestoring, SloshSpec};
use crate::model::{GeometryRole, GeometrySpec, LinkSpec, Model, ModelBuilder, Shape, TriangleInequality};

/// The file format version written by [`model_to_toml`] and accepted by the reader
/// (`[model] format_version`, optional).
pub const FORMAT_VERSION: i64 = 1;

type Span = Range<usize>;

// ---- the document, as serde sees it --------------------------------------------------------

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileDoc {
    model: Spanned<ModelDoc>,
    base: Spanned<BaseDoc>,
    #[serde(default)]
    link: Vec<Spanned<LinkDoc>>,
    #[serde(default)]
    point: Vec<Spanned<PointDoc>>,
    #[serde(default)]
    geometry: Vec<Spanned<GeometryDoc>>,
    #[serde(default)]
    slosh: Vec<Spanned<SloshDoc>>,
    #[serde(default)]
    panel: Vec<Spanned<PanelDoc>>,
    #[serde(default)]
    beam: Vec<Spanned<BeamDoc>>,
    dh: Option<Spanned<DhDoc>>,
    end_effector: Option<Spanned<String>>,
    initial_q: Option<Spanned<Vec<f64>>>,
}

/// A `[[slosh]]` table: an equivalent mechanical slosh model (docs/flexibility.md), added as
/// passive links by [`ModelBuilder::add_slosh`].
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SloshDoc {
    name: Spanned<String>,
    parent: Option<Spanned<String>>,
    model: Spanned<String>,
    mass: Spanned<f64>,
    position: Spanned<[f64; 3]>,
    axis: Spanned<[f64; 3]>,
    hinge: Option<Spanned<[f64; 3]>>,
    length: Option<Spanned<f64>>,
    stiffness: Option<Spanned<f64>>,
    frequency: Option<Spanned<f64>>,
    #[serde(default)]
    damping: f64,
}

/// A `[[panel]]` table: a hinged rigid panel (docs/flexibility.md), added by
/// [`crate::model::appendage::panel_parts`].
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PanelDoc {
    name: Spanned<String>,
    parent: Option<Spanned<String>>,
    hinge_position: [f64; 3],
    hinge_axis: [f64; 3],
    direction: [f64; 3],
    mass: f64,
    size: Option<[f64; 3]>,
    inertia: Option<Value>,
    com_distance: Option<f64>,
    stiffness: Option<f64>,
    frequency: Option<f64>,
    #[serde(default)]
    damping: f64,
    #[serde(default)]
    rest: f64,
}

/// A `[[beam]]` table: a flexible beam by the rigid finite element method
/// (docs/flexibility.md), added by [`crate::model::appendage::beam_parts`].
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
struct BeamDoc {
    name: Spanned<String>,
    parent: Option<Spanned<String>>,
    root_position: [f64; 3],
    axis: [f64; 3],
    length: f64,
    segments: usize,
    EI: Value,
    bending_axes: Option<Vec<[f64; 3]>>,
    GJ: Option<f64>,
    rho_A: f64,
    #[serde(default)]
    rho_J: f64,
    damping: Option<f64>,
    damping_ratio: Option<f64>,
}

/// A joint table's `compliant = { stiffness, rotor_inertia, damping, gear_ratio }` (Spong's
/// elastic joint, [`crate::model::appendage::compliant_parts`]).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CompliantDoc {
    stiffness: f64,
    rotor_inertia: f64,
    #[serde(default)]
    damping: f64,
    gear_ratio: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ModelDoc {
    name: Spanned<String>,
    format_version: Option<Spanned<i64>>,
    end_effector: Option<Spanned<String>>,
    initial_q: Option<Spanned<Vec<f64>>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct BaseDoc {
    name: Option<Spanned<String>>,
    mass: Spanned<f64>,
    inertia: Spanned<Value>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LinkDoc {
    name: Spanned<String>,
    parent: Spanned<String>,
    joint: Spanned<JointDoc>,
    com: Spanned<[f64; 3]>,
    mass: Spanned<f64>,
    inertia: Spanned<Value>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct JointDoc {
    #[serde(rename = "type")]
    kind: Spanned<JointType>,
    name: Option<Spanned<String>>,
    origin: Spanned<[f64; 3]>,
    rotation: Option<Spanned<[f64; 4]>>,
    rpy: Option<Spanned<[f64; 3]>>,
    axis: Option<Spanned<[f64; 3]>>,
    limits: Option<Spanned<LimitsDoc>>,
    /// The joint's passive dynamics (docs/flexibility.md): motor, spring, damper.
    actuated: Option<Spanned<bool>>,
    stiffness: Option<Spanned<f64>>,
    damping: Option<Spanned<f64>>,
    rest: Option<Spanned<f64>>,
    /// Spong's elastic joint: a motor rotor and a series spring (docs/flexibility.md).
    compliant: Option<Spanned<CompliantDoc>>,
}

impl JointDoc {
    /// The joint dynamics the table gives, and the span of its first dynamics key; `None` when it
    /// gives none (an actuated joint without spring).
    fn dynamics(&self) -> Option<(JointDynamics, Span)> {
        let d = JointDynamics::default();
        let spans = [self.actuated.as_ref().map(sp), self.stiffness.as_ref().map(sp), self.damping.as_ref().map(sp), self.rest.as_ref().map(sp)];
        let span = spans.into_iter().flatten().min_by_key(|s| s.start)?;
        Some((
            JointDynamics {
                actuated: self.actuated.as_ref().map_or(d.actuated, |v| *v.get_ref()),
                stiffness: self.stiffness.as_ref().map_or(d.stiffness, |v| *v.get_ref()),
                damping: self.damping.as_ref().map_or(d.damping, |v| *v.get_ref()),
                rest: self.rest.as_ref().map_or(d.rest, |v| *v.get_ref()),
            },
            span,
        ))
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LimitsDoc {
    lower: Option<f64>,
    upper: Option<f64>,
    velocity: Option<f64>,
    effort: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PointDoc {
    name: Spanned<String>,
    body: Spanned<String>,
    offset: Spanned<[f64; 3]>,
}

/// A `[[geometry]]` table (docs/geometry.md): `shape` says which dimension keys it takes.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct GeometryDoc {
    name: Option<Spanned<String>>,
    body: Spanned<String>,
    role: Option<Spanned<String>>,
    shape: Spanned<String>,
    size: Option<Spanned<[f64; 3]>>,
    radius: Option<Spanned<f64>>,
    length: Option<Spanned<f64>>,
    file: Option<Spanned<String>>,
    scale: Option<Spanned<[f64; 3]>>,
    origin: Option<Spanned<[f64; 3]>>,
    rotation: Option<Spanned<[f64; 4]>>,
    rpy: Option<Spanned<[f64; 3]>>,
    rgba: Option<Spanned<[f64; 4]>>,
}

#[derive(Deserialize, Clone, Copy, PartialEq)]
#[serde(rename_all = "lowercase")]
enum Convention {
    Classic,
    Paper,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DhDoc {
    convention: Spanned<Convention>,
    joint1_origin: Option<Spanned<[f64; 3]>>,
    joint1_rotation: Option<Spanned<[f64; 4]>>,
    joint1_rpy: Option<Spanned<[f64; 3]>>,
    tool_offset: Option<Spanned<[f64; 3]>>,
    tip_point: Option<Spanned<String>>,
    #[serde(default)]
    link: Vec<Spanned<DhLinkDoc>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DhLinkDoc {
    name: Option<Spanned<String>>,
    joint_name: Option<Spanned<String>>,
    #[serde(rename = "type")]
    kind: Option<Spanned<JointType>>,
    d: Option<Spanned<f64>>,
    theta: Option<Spanned<f64>>,
    a: Option<Spanned<f64>>,
    alpha: Option<Spanned<f64>>,
    com: Option<Spanned<[f64; 3]>>,
    joint_to_com: Option<Spanned<[f64; 3]>>,
    com_to_next: Option<Spanned<[f64; 3]>>,
    mass: Spanned<f64>,
    inertia: Spanned<Value>,
    limits: Option<Spanned<LimitsDoc>>,
}

// ---- locating errors -----------------------------------------------------------------------

/// 1-based line and column (in characters) of byte `offset` of `text`.
fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let mut offset = offset.min(text.len());
    while offset > 0 && !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let col = before[line_start..].chars().count() + 1;
    (line, col)
}

struct Ctx<'a> {
    text: &'a str,
    source: &'a str,
}

impl Ctx<'_> {
    /// `source:line:col: message`, then the offending line with a caret under the column.
    fn at(&self, span: Option<Span>, message: impl std::fmt::Display) -> SpacearmError {
        let Some(span) = span else {
            return SpacearmError::Parse(format!("{}: {message}", self.source));
        };
        let (line, col) = line_col(self.text, span.start);
        let mut out = format!("{}:{line}:{col}: {message}", self.source);
        if let Some(content) = self.text.split('\n').nth(line - 1) {
            let content = content.trim_end_matches('\r');
            if content.chars().count() <= 200 {
                let gutter = line.to_string().len();
                let _ = write!(out, "\n {line} | {content}\n {:gutter$} | {:>col$}", "", "^");
            }
        }
        SpacearmError::Parse(out)
    }

    /// An error of the TOML reader. A line of the text is quoted only when the text is a
    /// model file: TOML with a `[model]` table (it breaks the schema), or text with a `[model]`
    /// header line (a model file with a syntax error). Any other file is one the reader was
    /// pointed at by mistake or by an attacker (`/etc/shadow`, a credentials file): it is
    /// refused as not TOML, or not a model, without a line of its content (issue 38).
    fn parse_error(&self, e: toml::de::Error) -> SpacearmError {
        let table = toml::from_str::<toml::Table>(self.text);
        let model_like = match &table {
            Ok(t) => t.get("model").is_some_and(toml::Value::is_table),
            Err(_) => self.text.lines().any(|l| l.trim_start().starts_with("[model]")),
        };
        if model_like {
            return self.at(e.span(), e.message());
        }
        if table.is_ok() {
            return SpacearmError::Parse(format!(
                "{}: not a spacearm model file: it is TOML, but has no [model] table (docs/model-format.md)",
                self.source
            ));
        }
        let at = e.span().map(|span| {
            let (line, col) = line_col(self.text, span.start);
            format!(":{line}:{col}")
        });
        SpacearmError::Parse(format!(
            "{}{}: not a spacearm model file: not TOML ({}); a model file is TOML with a [model] table (docs/model-format.md)",
            self.source,
            at.unwrap_or_default(),
            e.message().trim_end()
        ))
    }

    fn err(&self, span: &Span, message: impl std::fmt::Display) -> SpacearmError {
        self.at(Some(span.clone()), message)
    }
}

fn sp<T>(s: &Spanned<T>) -> Span {
    s.span()
}

// ---- value conversion ----------------------------------------------------------------------

fn number(v: &Value) -> Option<f64> {
    match v {
        Value::Float(f) => Some(*f),
        Value::Integer(i) => Some(*i as f64),
        _ => None,
    }
}

const INERTIA_FORMS: &str =
    "[ixx, iyy, izz], a 3x3 array [[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]], or a table {ixx, iyy, izz, ixy, ixz, iyz}";

/// An inertia tensor from its three accepted forms.
fn inertia_from_value(v: &Value) -> std::result::Result<[[f64; 3]; 3], String> {
    let bad = || format!("inertia must be {INERTIA_FORMS}, got {}", describe_value(v));
    match v {
        Value::Array(items) if items.len() == 3 && items.iter().all(|x| number(x).is_some()) => {
            let d: Vec<f64> = items.iter().filter_map(number).collect();
            Ok([[d[0], 0.0, 0.0], [0.0, d[1], 0.0], [0.0, 0.0, d[2]]])
        }
        Value::Array(rows) if rows.len() == 3 => {
            let mut m = [[0.0; 3]; 3];
            for (i, row) in rows.iter().enumerate() {
                match row {
                    Value::Array(r) if r.len() == 3 => {
                        for (j, x) in r.iter().enumerate() {
                            m[i][j] = number(x).ok_or_else(bad)?;
                        }
                    }
                    _ => return Err(bad()),
                }
            }
            Ok(m)
        }
        Value::Table(t) => {
            for k in t.keys() {
                if !["ixx", "iyy", "izz", "ixy", "ixz", "iyz"].contains(&k.as_str()) {
                    return Err(format!("unknown inertia key `{k}`, expected ixx, iyy, izz, ixy, ixz, iyz"));
                }
            }
            let get = |k: &str, required: bool| -> std::result::Result<f64, String> {
                match t.get(k) {
                    None if required => Err(format!("inertia table is missing `{k}` (ixx, iyy and izz are required)")),
                    None => Ok(0.0),
                    Some(x) => number(x).ok_or_else(|| format!("inertia `{k}` must be a number, got {}", describe_value(x))),
                }
            };
            let (ixx, iyy, izz) = (get("ixx", true)?, get("iyy", true)?, get("izz", true)?);
            let (ixy, ixz, iyz) = (get("ixy", false)?, get("ixz", false)?, get("iyz", false)?);
            Ok([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
        }
        _ => Err(bad()),
    }
}

fn describe_value(v: &Value) -> String {
    match v {
        Value::Array(a) => format!("an array of {} item(s)", a.len()),
        Value::Table(_) => "a table with other keys".into(),
        other => format!("{} {}", other.type_str(), other),
    }
}

fn limits(doc: &Option<Spanned<LimitsDoc>>) -> JointLimits {
    let u = JointLimits::unlimited();
    match doc {
        None => u,
        Some(l) => {
            let l = l.get_ref();
            JointLimits {
                lower: l.lower.unwrap_or(u.lower),
                upper: l.upper.unwrap_or(u.upper),
                velocity: l.velocity.unwrap_or(u.velocity),
                effort: l.effort.unwrap_or(u.effort),
            }
        }
    }
}

/// `[x, y, z, w]` from `rotation` or `rpy` (URDF roll-pitch-yaw, `Rz(yaw) Ry(pitch) Rx(roll)`).
fn rotation_xyzw(
    ctx: &Ctx<'_>,
    who: &str,
    rotation: &Option<Spanned<[f64; 4]>>,
    rpy: &Option<Spanned<[f64; 3]>>,
    names: (&str, &str),
) -> Result<[f64; 4]> {
    match (rotation, rpy) {
        (Some(r), Some(_)) => Err(ctx.err(&sp(r), format!("{who}: give `{}` or `{}`, not both", names.0, names.1))),
        (Some(r), None) => Ok(*r.get_ref()),
        (None, Some(e)) => {
            if !e.get_ref().iter().all(|v| v.is_finite()) {
                return Err(ctx.err(&sp(e), format!("{who}: `{}` must be finite, got {:?}", names.1, e.get_ref())));
            }
            Ok(xyzw_from_rpy(e.get_ref()))
        }
        (None, None) => Ok([0.0, 0.0, 0.0, 1.0]),
    }
}

// ---- reading -------------------------------------------------------------------------------

/// Parse a model from TOML text. `source` names the text in error messages (a file name, or
/// `"<string>"`). See the module docs and `docs/model-format.md`.
pub fn model_from_toml_str(text: &str, source: &str) -> Result<Model> {
    model_from_toml_str_with(text, source, TriangleInequality::Enforce)
}

/// As [`model_from_toml_str`], choosing what an inertia that breaks the triangle inequality
/// does (refused, or accepted with a warning: see [`TriangleInequality`]).
pub fn model_from_toml_str_with(text: &str, source: &str, triangle_inequality: TriangleInequality) -> Result<Model> {
    admit_document(text, source)?;
    let ctx = Ctx { text, source };
    let doc: FileDoc = toml::from_str(text).map_err(|e| ctx.parse_error(e))?;
    build(&ctx, doc, triangle_inequality)
}

/// Memory the TOML parser takes per value of the document (its tree of spanned values), bytes:
/// measured at about 260 for a long array of numbers.
const PARSE_BYTES_PER_VALUE: f64 = 256.0;

/// Admission control of a document ([`crate::admission`]): the parser's tree holds every value
/// at once, so a huge array (an `initial_q` of 10⁷ entries) would take gigabytes before any
/// rule could refuse it. The values are counted from the separators (`,` and `=`, an upper
/// bound), in one pass over the text.
fn admit_document(text: &str, source: &str) -> Result<()> {
    let values = text.bytes().filter(|&b| b == b',' || b == b'=').count() + 1;
    crate::admission::admit(
        format_args!("{source}: parsing about {values} values"),
        values as f64 * PARSE_BYTES_PER_VALUE,
        "a model file holds at most a few million values (a 10⁵-link model has about 3·10⁶); check that the file is a model",
    )
}

/// Read a model file (UTF-8 TOML). I/O and decoding errors are [`SpacearmError::Parse`] too.
pub fn model_from_toml_file(path: &std::path::Path) -> Result<Model> {
    let bytes = std::fs::read(path).map_err(|e| SpacearmError::Parse(format!("{}: cannot read the model file: {e}", path.display())))?;
    let text = String::from_utf8(bytes).map_err(|e| {
        SpacearmError::Parse(format!("{}: the model file is not valid UTF-8 (byte {})", path.display(), e.utf8_error().valid_up_to()))
    })?;
    model_from_toml_str(&text, &path.display().to_string())
}

/// The spans of one model item in the file, to point at the field a [`ModelError`] names.
#[derive(Clone)]
struct ItemSpans {
    /// The whole item (a `[[link]]` table, a DH row, a `[[point]]`), for fields without a span.
    whole: Span,
    fields: Vec<(ModelField, Span)>,
}

impl ItemSpans {
    /// One span for every field (a DH row, whose link fields are computed from the row).
    fn uniform(span: Span) -> Self {
        ItemSpans { whole: span, fields: Vec::new() }
    }

    fn of(&self, field: ModelField) -> Span {
        self.fields.iter().find(|(f, _)| *f == field).map_or_else(|| self.whole.clone(), |(_, s)| s.clone())
    }
}

/// Where every item given to the builder sits in the file, in the builder's order; maps a
/// [`ModelError`]'s item and field to a span, and names the first definition of a duplicate.
struct Located<'a> {
    ctx: &'a Ctx<'a>,
    model: ItemSpans,
    base: ItemSpans,
    links: Vec<ItemSpans>,
    points: Vec<ItemSpans>,
    geometries: Vec<ItemSpans>,
    dh_arm: ItemSpans,
    dh_rows: Vec<Span>,
    /// Body names with the span of their definition, base first, in the builder's order.
    bodies: Vec<(String, Span)>,
    /// Joint names with the span of their definition, in link order.
    joints: Vec<(String, Span)>,
}

impl Located<'_> {
    fn span(&self, e: &ModelError) -> Span {
        match e.item {
            ModelItem::Model => self.model.of(e.field),
            ModelItem::Base => self.base.of(e.field),
            ModelItem::Link(k) => self.links.get(k).map_or_else(|| self.model.whole.clone(), |s| s.of(e.field)),
            ModelItem::Point(k) => self.points.get(k).map_or_else(|| self.model.whole.clone(), |s| s.of(e.field)),
            ModelItem::Geometry(k) => self.geometries.get(k).map_or_else(|| self.model.whole.clone(), |s| s.of(e.field)),
            ModelItem::DhArm => self.dh_arm.of(e.field),
            ModelItem::DhRow(k) => self.dh_rows.get(k).cloned().unwrap_or_else(|| self.dh_arm.whole.clone()),
        }
    }

    /// ` (first on line N)` for a duplicated body or joint name.
    fn first_definition(&self, e: &ModelError) -> String {
        let ModelItem::Link(k) = e.item else { return String::new() };
        // `bodies[0]` is the base, so link `k` is `bodies[k + 1]` and `joints[k]`.
        let (earlier, this) = match e.field {
            ModelField::Name => (self.bodies.get(..k + 1), self.bodies.get(k + 1)),
            ModelField::JointName => (self.joints.get(..k), self.joints.get(k)),
            _ => return String::new(),
        };
        let (Some(earlier), Some((name, _))) = (earlier, this) else { return String::new() };
        earlier
            .iter()
            .find(|(n, _)| n == name)
            .map_or_else(String::new, |(_, first)| format!(" (first on line {})", line_col(self.ctx.text, first.start).0))
    }

    /// The model error as a parse error at the offending text.
    fn err(&self, e: ModelError) -> SpacearmError {
        let span = self.span(&e);
        let message = format!("{}{}", e, self.first_definition(&e));
        self.ctx.err(&span, message)
    }
}

/// Add an appendage's parts (model/appendage.rs) from the table at `span`: every link, point
/// and shape it makes is located there.
fn add_parts(at: &mut Located<'_>, builder: &mut ModelBuilder, parts: &Parts, span: &Span) -> Result<()> {
    for (link, dynamics) in &parts.links {
        at.bodies.push((link.name.clone(), span.clone()));
        at.joints.push((link.joint_name.clone().unwrap_or_else(|| format!("{}_joint", link.name)), span.clone()));
        at.links.push(ItemSpans::uniform(span.clone()));
        builder.add_link(link.clone()).map_err(|e| at.err(e))?;
        if *dynamics != JointDynamics::default() {
            builder.set_joint_dynamics(&link.name, *dynamics).map_err(|e| at.err(e))?;
        }
    }
    for (name, body, offset) in &parts.points {
        at.points.push(ItemSpans::uniform(span.clone()));
        builder.add_point(name, body, *offset).map_err(|e| at.err(e))?;
    }
    for g in &parts.geometries {
        at.geometries.push(ItemSpans::uniform(span.clone()));
        builder.add_geometry(g.clone()).map_err(|e| at.err(e))?;
    }
    Ok(())
}

fn build(ctx: &Ctx<'_>, doc: FileDoc, triangle_inequality: TriangleInequality) -> Result<Model> {
    let model_doc = doc.model.get_ref();
    if let Some(v) = &model_doc.format_version {
        if *v.get_ref() != FORMAT_VERSION {
            return Err(ctx.err(
                &sp(v),
                format!("format_version {} is not supported; this version of spacearm reads format_version = {FORMAT_VERSION}", v.get_ref()),
            ));
        }
    }
    let end_effector = match (&model_doc.end_effector, &doc.end_effector) {
        (Some(_), Some(b)) => return Err(ctx.err(&sp(b), "end_effector is given both in [model] and at the top level; keep one")),
        (a, b) => a.as_ref().or(b.as_ref()),
    };
    let initial_q = match (&model_doc.initial_q, &doc.initial_q) {
        (Some(_), Some(b)) => return Err(ctx.err(&sp(b), "initial_q is given both in [model] and at the top level; keep one")),
        (a, b) => a.as_ref().or(b.as_ref()),
    };
    let dh_span = doc.dh.as_ref().map_or_else(|| sp(&doc.model), sp);
    let mut model_spans = ItemSpans::uniform(sp(&doc.model));
    if let Some(e) = end_effector {
        model_spans.fields.push((ModelField::EndEffector, sp(e)));
    } else if let Some(t) = doc.dh.as_ref().and_then(|d| d.get_ref().tip_point.as_ref()) {
        model_spans.fields.push((ModelField::EndEffector, sp(t)));
    }
    if let Some(q) = initial_q {
        model_spans.fields.push((ModelField::InitialQ, sp(q)));
    }

    // Base.
    let base_doc = doc.base.get_ref();
    let base_name = base_doc.name.as_ref().map_or_else(|| "base".to_string(), |n| n.get_ref().clone());
    let base_name_span = base_doc.name.as_ref().map_or_else(|| sp(&doc.base), sp);
    let mut at = Located {
        ctx,
        model: model_spans,
        base: ItemSpans {
            whole: sp(&doc.base),
            fields: vec![(ModelField::Name, base_name_span.clone()), (ModelField::Mass, sp(&base_doc.mass)), (ModelField::Inertia, sp(&base_doc.inertia))],
        },
        links: Vec::new(),
        points: Vec::new(),
        geometries: Vec::new(),
        dh_arm: ItemSpans::uniform(dh_span.clone()),
        dh_rows: Vec::new(),
        bodies: vec![(base_name.clone(), base_name_span)],
        joints: Vec::new(),
    };
    let base_inertia = inertia_from_value(base_doc.inertia.get_ref()).map_err(|m| ctx.err(&sp(&base_doc.inertia), format!("base '{base_name}': {m}")))?;
    let name = model_doc.name.get_ref();
    let mut builder = ModelBuilder::with_triangle_inequality(name, &base_name, *base_doc.mass.get_ref(), base_inertia, triangle_inequality)
        .map_err(|e| at.err(e))?;

    // A DH arm first (its links can carry further [[link]]s and [[point]]s).
    if let Some(dh) = &doc.dh {
        let (arm, row_spans) = dh_arm(ctx, dh, &base_name)?;
        let d = dh.get_ref();
        for (field, span) in [(ModelField::Origin, &d.joint1_origin), (ModelField::Offset, &d.tool_offset)] {
            if let Some(s) = span {
                at.dh_arm.fields.push((field, sp(s)));
            }
        }
        if let Some(s) = d.joint1_rotation.as_ref().map(sp).or_else(|| d.joint1_rpy.as_ref().map(sp)) {
            at.dh_arm.fields.push((ModelField::Rotation, s));
        }
        at.dh_rows = row_spans.clone();
        let converted = arm.convert().map_err(|e| at.err(e))?;
        for (spec, row) in converted.links.into_iter().zip(row_spans) {
            at.bodies.push((spec.name.clone(), row.clone()));
            at.joints.push((spec.joint_name.clone().unwrap_or_else(|| format!("{}_joint", spec.name)), row.clone()));
            at.links.push(ItemSpans::uniform(row));
            builder.add_link(spec).map_err(|e| at.err(e))?;
        }
        if let Some((name, body, offset)) = converted.tip {
            at.points.push(ItemSpans::uniform(d.tip_point.as_ref().map_or_else(|| dh_span.clone(), sp)));
            builder.add_point(&name, &body, offset).map_err(|e| at.err(e))?;
            if end_effector.is_none() {
                builder.set_end_effector(&name);
            }
        }
    }

    // [[link]]s, parents first. `known` mirrors `at.bodies` as a set, so that checking a parent
    // costs O(1) and a file of N links reads in O(N).
    let mut known: HashSet<String> = at.bodies.iter().map(|(n, _)| n.clone()).collect();
    let all_links: HashMap<&str, (usize, &str)> =
        doc.link.iter().enumerate().map(|(k, l)| (l.get_ref().name.get_ref().as_str(), (k, l.get_ref().parent.get_ref().as_str()))).collect();
    for (k, ld) in doc.link.iter().enumerate() {
        let l = ld.get_ref();
        let name = l.name.get_ref();
        let parent = l.parent.get_ref();
        if !known.contains(parent.as_str()) {
            return Err(ctx.err(&sp(&l.parent), missing_parent(ctx, &doc, &all_links, k, &at.bodies)));
        }
        let j = l.joint.get_ref();
        let kind = *j.kind.get_ref();
        let who = format!("link '{name}'");
        let axis = match (&j.axis, kind) {
            (Some(a), _) => *a.get_ref(),
            (None, JointType::Fixed) => [0.0, 0.0, 1.0],
            (None, _) => {
                return Err(ctx.err(&sp(&l.joint), format!("{who}: a {} joint needs an `axis` (in the link frame)", kind.as_str())));
            }
        };
        let rotation = rotation_xyzw(ctx, &who, &j.rotation, &j.rpy, ("rotation", "rpy"))?;
        let inertia = inertia_from_value(l.inertia.get_ref()).map_err(|m| ctx.err(&sp(&l.inertia), format!("{who}: {m}")))?;
        let spec = LinkSpec {
            name: name.clone(),
            parent: parent.clone(),
            joint_name: j.name.as_ref().map(|n| n.get_ref().clone()),
            kind,
            origin_in_parent: *j.origin.get_ref(),
            rotation_in_parent: rotation,
            axis,
            com_from_joint: *l.com.get_ref(),
            mass: *l.mass.get_ref(),
            inertia,
            limits: limits(&j.limits),
        };
        let joint_span = j.name.as_ref().map_or_else(|| sp(&l.joint), sp);
        let dynamics = j.dynamics();
        let rotation_span = j.rotation.as_ref().map(sp).or_else(|| j.rpy.as_ref().map(sp)).unwrap_or_else(|| sp(&l.joint));
        at.links.push(ItemSpans {
            whole: sp(ld),
            fields: vec![
                (ModelField::Name, sp(&l.name)),
                (ModelField::Parent, sp(&l.parent)),
                (ModelField::JointName, joint_span.clone()),
                (ModelField::Origin, sp(&j.origin)),
                (ModelField::Rotation, rotation_span),
                (ModelField::Axis, j.axis.as_ref().map_or_else(|| sp(&l.joint), sp)),
                (ModelField::Com, sp(&l.com)),
                (ModelField::Mass, sp(&l.mass)),
                (ModelField::Inertia, sp(&l.inertia)),
                (ModelField::Limits, j.limits.as_ref().map_or_else(|| sp(&l.joint), sp)),
                (ModelField::JointDynamics, dynamics.as_ref().map_or_else(|| sp(&l.joint), |(_, s)| s.clone())),
            ],
        });
        at.bodies.push((name.clone(), sp(&l.name)));
        known.insert(name.clone());
        if let Some(c) = &j.compliant {
            if let Some((_, s)) = &dynamics {
                return Err(ctx.err(s, format!("{who}: a compliant joint takes no actuated, stiffness, damping or rest of its own")));
            }
            let cd = c.get_ref();
            let cspec = CompliantSpec { stiffness: cd.stiffness, rotor_inertia: cd.rotor_inertia, damping: cd.damping, gear_ratio: cd.gear_ratio.unwrap_or(1.0) };
            let parts = compliant_parts(&spec, &cspec, ModelItem::Link(at.links.len())).map_err(|e| ctx.err(&sp(c), e))?;
            at.links.pop();
            at.bodies.pop();
            add_parts(&mut at, &mut builder, &parts, &sp(ld))?;
            continue;
        }
        at.joints.push((spec.joint_name.clone().unwrap_or_else(|| format!("{name}_joint")), joint_span));
        builder.add_link(spec).map_err(|e| at.err(e))?;
        if let Some((d, _)) = dynamics {
            builder.set_joint_dynamics(name, d).map_err(|e| at.err(e))?;
        }
    }

    // The links the file lists itself; the appendages below add passive links after them.
    let listed_links = at.links.len();
    // [[slosh]] modes: passive links on bodies defined above.
    for sd in &doc.slosh {
        let s = sd.get_ref();
        let name = s.name.get_ref();
        let model = SloshModel::from_name(s.model.get_ref())
            .ok_or_else(|| ctx.err(&sp(&s.model), format!("slosh '{name}': model must be one of {:?}, got '{}'", SloshModel::NAMES, s.model.get_ref())))?;
        let restoring = match (&s.stiffness, &s.frequency) {
            (Some(k), None) => SloshRestoring::Stiffness(*k.get_ref()),
            (None, Some(w)) => SloshRestoring::Frequency(*w.get_ref()),
            _ => return Err(ctx.err(&sp(sd), format!("slosh '{name}': give stiffness or frequency (one of them)"))),
        };
        let spec = SloshSpec {
            name: name.clone(),
            parent: s.parent.as_ref().map_or_else(|| base_name.clone(), |p| p.get_ref().clone()),
            model,
            mass: *s.mass.get_ref(),
            position: *s.position.get_ref(),
            axis: *s.axis.get_ref(),
            hinge: s.hinge.as_ref().map(|h| *h.get_ref()),
            length: s.length.as_ref().map(|l| *l.get_ref()),
            restoring,
            damping: s.damping,
        };
        let links = slosh_links(&spec, ModelItem::Link(at.links.len())).map_err(|e| ctx.err(&sp(sd), e))?;
        for (link, dynamics) in links {
            at.bodies.push((link.name.clone(), sp(&s.name)));
            at.joints.push((link.joint_name.clone().unwrap_or_default(), sp(sd)));
            at.links.push(ItemSpans::uniform(sp(sd)));
            let link_name = link.name.clone();
            builder.add_link(link).map_err(|e| at.err(e))?;
            builder.set_joint_dynamics(&link_name, dynamics).map_err(|e| at.err(e))?;
        }
    }

    // [[panel]]s and [[beam]]s: passive links on bodies defined above.
    for pd in &doc.panel {
        let p = pd.get_ref();
        let name = p.name.get_ref();
        let who = format!("panel '{name}'");
        let restoring = match (p.stiffness, p.frequency) {
            (Some(k), None) => Restoring::Stiffness(k),
            (None, Some(w)) => Restoring::Frequency(w),
            _ => return Err(ctx.err(&sp(pd), format!("{who}: give stiffness or frequency (one of them)"))),
        };
        let body = match (&p.size, &p.inertia, p.com_distance) {
            (Some(s), None, None) => PanelBody::Size(*s),
            (None, Some(i), Some(d)) => PanelBody::Inertia { com_distance: d, inertia: inertia_from_value(i).map_err(|m| ctx.err(&sp(pd), format!("{who}: {m}")))? },
            _ => return Err(ctx.err(&sp(pd), format!("{who}: give size = [length, width, thickness], or inertia and com_distance"))),
        };
        let spec = PanelSpec {
            name: name.clone(),
            parent: p.parent.as_ref().map_or_else(|| base_name.clone(), |v| v.get_ref().clone()),
            hinge_position: p.hinge_position,
            hinge_axis: p.hinge_axis,
            direction: p.direction,
            body,
            mass: p.mass,
            restoring,
            damping: p.damping,
            rest: p.rest,
        };
        let parts = panel_parts(&spec, ModelItem::Link(at.links.len())).map_err(|e| ctx.err(&sp(pd), e))?;
        add_parts(&mut at, &mut builder, &parts, &sp(pd))?;
    }
    for bd in &doc.beam {
        let b = bd.get_ref();
        let name = b.name.get_ref();
        let who = format!("beam '{name}'");
        let ei: Vec<f64> = match &b.EI {
            Value::Float(v) => vec![*v],
            Value::Integer(v) => vec![*v as f64],
            Value::Array(a) => a.iter().map(|v| v.as_float().or_else(|| v.as_integer().map(|i| i as f64))).collect::<Option<Vec<f64>>>()
                .ok_or_else(|| ctx.err(&sp(bd), format!("{who}: EI must be a number or an array of numbers")))?,
            _ => return Err(ctx.err(&sp(bd), format!("{who}: EI must be a number or an array of numbers"))),
        };
        let damping = match (b.damping, b.damping_ratio) {
            (Some(c), None) => BeamDamping::PerJoint(c),
            (None, Some(z)) => BeamDamping::Ratio(z),
            (None, None) => BeamDamping::PerJoint(0.0),
            _ => return Err(ctx.err(&sp(bd), format!("{who}: give damping or damping_ratio, not both"))),
        };
        let bending = appendage::bending(name, &b.axis, b.bending_axes.clone(), &ei).map_err(|e| ctx.err(&sp(bd), e))?;
        let spec = BeamSpec {
            name: name.clone(),
            parent: b.parent.as_ref().map_or_else(|| base_name.clone(), |v| v.get_ref().clone()),
            root_position: b.root_position,
            axis: b.axis,
            length: b.length,
            segments: b.segments,
            bending,
            torsion: b.GJ,
            rho_a: b.rho_A,
            rho_j: b.rho_J,
            damping,
        };
        let parts = beam_parts(&spec, ModelItem::Link(at.links.len())).map_err(|e| ctx.err(&sp(bd), e))?;
        add_parts(&mut at, &mut builder, &parts, &sp(bd))?;
    }

    // [[point]]s.
    for pd in &doc.point {
        let p = pd.get_ref();
        at.points.push(ItemSpans {
            whole: sp(pd),
            fields: vec![(ModelField::Name, sp(&p.name)), (ModelField::Body, sp(&p.body)), (ModelField::Offset, sp(&p.offset))],
        });
        builder.add_point(p.name.get_ref(), p.body.get_ref(), *p.offset.get_ref()).map_err(|e| at.err(e))?;
    }

    // [[geometry]]s.
    for gd in &doc.geometry {
        let (spec, spans) = geometry_spec(ctx, gd)?;
        at.geometries.push(spans);
        builder.add_geometry(spec).map_err(|e| at.err(e))?;
    }

    // End effector, initial q, and the rules that need the whole model.
    if let Some(e) = end_effector {
        builder.set_end_effector(e.get_ref());
    }
    if let Some(q) = initial_q {
        // An initial_q of the listed links' coordinates only is completed with the appendages'
        // passive coordinates at their springs' rest (issue 37 item 5: a model with an initial_q
        // was refused once a [[slosh]], [[panel]] or [[beam]] was appended, until the user
        // counted the generated coordinates); one of every coordinate is taken as it is.
        let q = builder.initial_q_completed_at_rest(q.get_ref(), listed_links).unwrap_or_else(|| q.get_ref().clone());
        builder.set_initial_q(q);
    }
    builder.build().map_err(|e| at.err(e))
}

/// Why the parent of `[[link]]` number `k` is not a body defined above it: the link is its own
/// parent, the parents form a cycle, the parent comes later in the file, or it does not exist.
fn missing_parent(ctx: &Ctx<'_>, doc: &FileDoc, all_links: &HashMap<&str, (usize, &str)>, k: usize, bodies: &[(String, Span)]) -> String {
    let l = doc.link[k].get_ref();
    let name = l.name.get_ref().as_str();
    let parent = l.parent.get_ref().as_str();
    if parent == name {
        return format!("link '{name}' cannot be its own parent");
    }
    if let Some(&(later, _)) = all_links.get(parent).filter(|(j, _)| *j > k) {
        // Is it a cycle? Follow the parents from `parent`.
        let mut chain = vec![name, parent];
        let mut cur = parent;
        for _ in 0..all_links.len() {
            match all_links.get(cur) {
                Some(&(_, p)) if p == name => {
                    chain.push(name);
                    let c: Vec<String> = chain.iter().map(|s| format!("'{s}'")).collect();
                    return format!("link '{name}': the parents form a cycle {}; a model is a tree rooted at the base", c.join(" -> "));
                }
                Some(&(_, p)) if all_links.contains_key(p) && !chain.contains(&p) => {
                    chain.push(p);
                    cur = p;
                }
                _ => break,
            }
        }
        let (line, _) = line_col(ctx.text, doc.link[later].span().start);
        return format!("link '{name}': parent '{parent}' is defined later in the file (line {line}); list every link after its parent");
    }
    let known: Vec<&str> = bodies.iter().map(|(n, _)| n.as_str()).collect();
    format!("link '{name}': parent '{parent}' is not a body of the model; bodies defined so far: {known:?}")
}

/// A `[[geometry]]` table as the builder's spec, with the spans of its fields: the shape's
/// dimension keys are those of its kind (docs/geometry.md), each required, no other allowed.
fn geometry_spec(ctx: &Ctx<'_>, gd: &Spanned<GeometryDoc>) -> Result<(GeometrySpec, ItemSpans)> {
    let g = gd.get_ref();
    let who = g.name.as_ref().map_or_else(|| format!("geometry on '{}'", g.body.get_ref()), |n| format!("geometry '{}'", n.get_ref()));
    let role = match &g.role {
        None => GeometryRole::Visual,
        Some(r) => GeometryRole::from_name(r.get_ref())
            .ok_or_else(|| ctx.err(&sp(r), format!("{who}: role must be \"visual\" or \"collision\", got {:?}", r.get_ref())))?,
    };
    let present: [(&str, Option<Span>); 5] = [
        ("size", g.size.as_ref().map(sp)),
        ("radius", g.radius.as_ref().map(sp)),
        ("length", g.length.as_ref().map(sp)),
        ("file", g.file.as_ref().map(sp)),
        ("scale", g.scale.as_ref().map(sp)),
    ];
    let parts = ShapeParts {
        size: g.size.as_ref().map(|v| *v.get_ref()),
        radius: g.radius.as_ref().map(|v| *v.get_ref()),
        length: g.length.as_ref().map(|v| *v.get_ref()),
        file: g.file.as_ref().map(|v| v.get_ref().clone()),
        scale: g.scale.as_ref().map(|v| *v.get_ref()),
    };
    let shape = Shape::from_parts(g.shape.get_ref(), parts).map_err(|m| {
        // Point at the key named in the message (an extra key), else at the shape.
        let span = present.iter().find(|(k, s)| s.is_some() && m.contains(&format!("`{k}`"))).and_then(|(_, s)| s.clone());
        let span = span.unwrap_or_else(|| if m.contains("needs") { sp(gd) } else { sp(&g.shape) });
        ctx.err(&span, format!("{who}: {m}"))
    })?;
    let rotation = rotation_xyzw(ctx, &who, &g.rotation, &g.rpy, ("rotation", "rpy"))?;
    let shape_span = present.iter().find_map(|(_, s)| s.clone()).unwrap_or_else(|| sp(&g.shape));
    let spans = ItemSpans {
        whole: sp(gd),
        fields: vec![
            (ModelField::Name, g.name.as_ref().map_or_else(|| sp(gd), sp)),
            (ModelField::Body, sp(&g.body)),
            (ModelField::Shape, shape_span),
            (ModelField::Origin, g.origin.as_ref().map_or_else(|| sp(gd), sp)),
            (ModelField::Rotation, g.rotation.as_ref().map(sp).or_else(|| g.rpy.as_ref().map(sp)).unwrap_or_else(|| sp(gd))),
            (ModelField::Color, g.rgba.as_ref().map_or_else(|| sp(gd), sp)),
        ],
    };
    let spec = GeometrySpec {
        name: g.name.as_ref().map(|n| n.get_ref().clone()),
        body: g.body.get_ref().clone(),
        role,
        shape,
        origin: g.origin.as_ref().map_or([0.0; 3], |o| *o.get_ref()),
        rotation,
        rgba: g.rgba.as_ref().map(|c| *c.get_ref()),
    };
    Ok((spec, spans))
}

/// The `[dh]` section as a [`DhArm`] on the base, with the span of each row.
fn dh_arm(ctx: &Ctx<'_>, dh: &Spanned<DhDoc>, base_name: &str) -> Result<(DhArm, Vec<Span>)> {
    let d = dh.get_ref();
    let convention = *d.convention.get_ref();
    let rotation = rotation_xyzw(ctx, "[dh]", &d.joint1_rotation, &d.joint1_rpy, ("joint1_rotation", "joint1_rpy"))?;
    let mut classic = Vec::new();
    let mut paper = Vec::new();
    let mut spans = Vec::new();
    for (k, rd) in d.link.iter().enumerate() {
        let r = rd.get_ref();
        let who = format!("DH link {}", k + 1);
        let span = sp(rd);
        let kind = r.kind.as_ref().map_or(JointType::Revolute, |t| *t.get_ref());
        let inertia = inertia_from_value(r.inertia.get_ref()).map_err(|m| ctx.err(&sp(&r.inertia), format!("{who}: {m}")))?;
        let (own, other): (&[(&str, bool)], &str) = match convention {
            Convention::Classic => (
                &[("joint_to_com", r.joint_to_com.is_some()), ("com_to_next", r.com_to_next.is_some())],
                "the classic convention uses d, theta, a, alpha and com",
            ),
            Convention::Paper => (
                &[("d", r.d.is_some()), ("a", r.a.is_some()), ("com", r.com.is_some())],
                "the paper convention uses theta, alpha, joint_to_com and com_to_next",
            ),
        };
        if let Some((key, _)) = own.iter().find(|(_, present)| *present) {
            return Err(ctx.err(&span, format!("{who}: `{key}` does not belong to a {} DH table; {other}", convention_name(convention))));
        }
        let need = |v: Option<&Spanned<f64>>, key: &str| -> Result<f64> {
            v.map(|s| *s.get_ref()).ok_or_else(|| ctx.err(&span, format!("{who}: missing `{key}` ({other})")))
        };
        let need3 = |v: Option<&Spanned<[f64; 3]>>, key: &str| -> Result<[f64; 3]> {
            v.map(|s| *s.get_ref()).ok_or_else(|| ctx.err(&span, format!("{who}: missing `{key}` ({other})")))
        };
        let name = r.name.as_ref().map(|n| n.get_ref().clone());
        let joint_name = r.joint_name.as_ref().map(|n| n.get_ref().clone());
        match convention {
            Convention::Classic => classic.push(ClassicDhLink {
                name,
                joint_name,
                kind,
                d: need(r.d.as_ref(), "d")?,
                theta: need(r.theta.as_ref(), "theta")?,
                a: need(r.a.as_ref(), "a")?,
                alpha: need(r.alpha.as_ref(), "alpha")?,
                com: need3(r.com.as_ref(), "com")?,
                mass: *r.mass.get_ref(),
                inertia,
                limits: limits(&r.limits),
            }),
            Convention::Paper => paper.push(PaperDhLink {
                name,
                joint_name,
                kind,
                theta: r.theta.as_ref().map_or(0.0, |s| *s.get_ref()),
                alpha: r.alpha.as_ref().map_or(0.0, |s| *s.get_ref()),
                joint_to_com: need3(r.joint_to_com.as_ref(), "joint_to_com")?,
                com_to_next: need3(r.com_to_next.as_ref(), "com_to_next")?,
                mass: *r.mass.get_ref(),
                inertia,
                limits: limits(&r.limits),
            }),
        }
        spans.push(span);
    }
    let table = match convention {
        Convention::Classic => DhTable::Classic(classic),
        Convention::Paper => DhTable::Paper(paper),
    };
    let arm = DhArm {
        table,
        parent: base_name.to_string(),
        joint1_origin: d.joint1_origin.as_ref().map_or([0.0; 3], |s| *s.get_ref()),
        joint1_rotation: rotation,
        tool_offset: d.tool_offset.as_ref().map_or([0.0; 3], |s| *s.get_ref()),
        tip_point: Some(d.tip_point.as_ref().map_or_else(|| "end_effector".to_string(), |s| s.get_ref().clone())),
    };
    Ok((arm, spans))
}

fn convention_name(c: Convention) -> &'static str {
    match c {
        Convention::Classic => "classic",
        Convention::Paper => "paper",
    }
}

// ---- writing -------------------------------------------------------------------------------

/// A float as TOML: Rust's shortest round-trip representation (`1.0`, `0.1`, `1e-7`, `inf`).
fn num(x: f64) -> String {
    if x.is_nan() {
        "nan".into()
    } else {
        format!("{x:?}")
    }
}

fn vec_str(v: &[f64]) -> String {
    let items: Vec<String> = v.iter().map(|&x| num(x)).collect();
    format!("[{}]", items.join(", "))
}

/// A TOML basic string.
fn string(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            '\r' => out.push_str("\\r"),
            c if (c as u32) < 0x20 || c as u32 == 0x7f => {
                let _ = write!(out, "\\u{:04X}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

fn inertia_str(m: &Matrix3<f64>) -> String {
    if m[(0, 1)] == 0.0 && m[(0, 2)] == 0.0 && m[(1, 2)] == 0.0 && m[(1, 0)] == 0.0 && m[(2, 0)] == 0.0 && m[(2, 1)] == 0.0 {
        vec_str(&[m[(0, 0)], m[(1, 1)], m[(2, 2)]])
    } else {
        let rows: Vec<String> = (0..3).map(|i| vec_str(&[m[(i, 0)], m[(i, 1)], m[(i, 2)]])).collect();
        format!("[{}]", rows.join(", "))
    }
}

/// Write a model as a TOML model file (format [`FORMAT_VERSION`]). Reading the text back with
/// [`model_from_toml_str`] gives a model equal to `model` (every number is written in its
/// shortest exact form).
pub fn model_to_toml(model: &Model) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# spacearm model file. Schema: docs/model-format.md");
    let _ = writeln!(s, "# SI units (m, kg, kg·m², rad). Every body frame has its origin at the body's centre of mass;");
    let _ = writeln!(s, "# a joint's origin is given in its parent's frame, com/axis/inertia in the link's own frame.");
    let _ = writeln!(s, "\n[model]");
    let _ = writeln!(s, "name = {}", string(model.name()));
    let _ = writeln!(s, "format_version = {FORMAT_VERSION}");
    if let Some(e) = model.end_effector() {
        let _ = writeln!(s, "end_effector = {}", string(&model.points()[e].name));
    }
    let _ = writeln!(s, "initial_q = {}", vec_str(model.initial_q()));
    let _ = writeln!(s, "\n[base]");
    let _ = writeln!(s, "name = {}", string(model.base_name()));
    let _ = writeln!(s, "mass = {}", num(model.base().mass));
    let _ = writeln!(s, "inertia = {}", inertia_str(&model.base().inertia));
    for l in model.links() {
        let j = &l.joint;
        let _ = writeln!(s, "\n[[link]]");
        let _ = writeln!(s, "name = {}", string(&l.name));
        let _ = writeln!(s, "parent = {}", string(model.body_name(l.parent)));
        let _ = writeln!(s, "com = {}", vec_str(l.com_from_joint.as_slice()));
        let _ = writeln!(s, "mass = {}", num(l.mass.mass));
        let _ = writeln!(s, "inertia = {}", inertia_str(&l.mass.inertia));
        let _ = writeln!(s, "[link.joint]");
        let _ = writeln!(s, "name = {}", string(&j.name));
        let _ = writeln!(s, "type = {}", string(j.kind.as_str()));
        let _ = writeln!(s, "origin = {}", vec_str(j.origin_in_parent.as_slice()));
        let q = j.rotation_in_parent;
        if !(q.i == 0.0 && q.j == 0.0 && q.k == 0.0 && q.w == 1.0) {
            let _ = writeln!(s, "rotation = {}", vec_str(&[q.i, q.j, q.k, q.w]));
        }
        let _ = writeln!(s, "axis = {}", vec_str(j.axis.as_slice()));
        let lim = j.limits;
        let u = JointLimits::unlimited();
        let mut parts = Vec::new();
        for (key, v, d) in [("lower", lim.lower, u.lower), ("upper", lim.upper, u.upper), ("velocity", lim.velocity, u.velocity), ("effort", lim.effort, u.effort)] {
            if v != d {
                parts.push(format!("{key} = {}", num(v)));
            }
        }
        if !parts.is_empty() {
            let _ = writeln!(s, "limits = {{ {} }}", parts.join(", "));
        }
        let (d, none) = (j.dynamics, JointDynamics::default());
        if d.actuated != none.actuated {
            let _ = writeln!(s, "actuated = {}", d.actuated);
        }
        for (key, v, dv) in [("stiffness", d.stiffness, none.stiffness), ("damping", d.damping, none.damping), ("rest", d.rest, none.rest)] {
            if v != dv {
                let _ = writeln!(s, "{key} = {}", num(v));
            }
        }
    }
    for p in model.points() {
        let _ = writeln!(s, "\n[[point]]");
        let _ = writeln!(s, "name = {}", string(&p.name));
        let _ = writeln!(s, "body = {}", string(model.body_name(p.body)));
        let _ = writeln!(s, "offset = {}", vec_str(p.offset.as_slice()));
    }
    for g in model.geometries() {
        let _ = writeln!(s, "\n[[geometry]]");
        let _ = writeln!(s, "name = {}", string(&g.name));
        let _ = writeln!(s, "body = {}", string(model.body_name(g.body)));
        let _ = writeln!(s, "role = {}", string(g.role.as_str()));
        let _ = writeln!(s, "shape = {}", string(g.shape.kind()));
        match &g.shape {
            Shape::Box { size } => {
                let _ = writeln!(s, "size = {}", vec_str(size));
            }
            Shape::Sphere { radius } => {
                let _ = writeln!(s, "radius = {}", num(*radius));
            }
            Shape::Cylinder { radius, length } | Shape::Capsule { radius, length } => {
                let _ = writeln!(s, "radius = {}\nlength = {}", num(*radius), num(*length));
            }
            Shape::Mesh { file, scale } => {
                let _ = writeln!(s, "file = {}\nscale = {}", string(file), vec_str(scale));
            }
        }
        let _ = writeln!(s, "origin = {}", vec_str(g.origin.as_slice()));
        let q = g.rotation;
        if !(q.i == 0.0 && q.j == 0.0 && q.k == 0.0 && q.w == 1.0) {
            let _ = writeln!(s, "rotation = {}", vec_str(&[q.i, q.j, q.k, q.w]));
        }
        let _ = writeln!(s, "rgba = {}", vec_str(&g.rgba));
    }
    s
}

#[cfg(test)]
mod tests {
    #[test]
    fn errors_quote_lines_of_model_files_only() {
        // Pointed at any file, the reader quoted the line of its first syntax error: the
        // content of /etc/shadow or a credentials file ended up in the message (issue 38).
        for (text, want) in [
            ("root:SECRETHASH:19000:0:99999:7:::\ndaemon:*:19000\n", "not TOML"),
            ("token = \"SECRET-abc\"\ntoken = \"SECRET-abc\"\n", "not TOML"),
            ("[server]\npassword = \"SECRET-abc\"\n", "no [model] table"),
            ("\u{0}\u{1}SECRET\u{ff}", "not TOML"),
        ] {
            let e = model_from_toml_str(text, "secrets.txt").unwrap_err().to_string();
            assert!(e.starts_with("secrets.txt") && e.contains(want) && !e.contains("SECRET") && !e.contains('\n'), "{e}");
        }
        // A model file that breaks the schema still gets its line quoted, with the caret.
        let e = model_from_toml_str("[model]\nname = 5\n", "m.toml").unwrap_err().to_string();
        assert!(e.starts_with("m.toml:2:8: ") && e.contains("\n 2 | name = 5\n"), "{e}");
    }

    use super::*;
    use crate::math::rotations::xyzw;
    use crate::model::presets;
    use nalgebra::{UnitQuaternion, Vector3};

    const DEMO: &str = r#"
[model]
name = "demo"
end_effector = "tip"
initial_q = [0.3, 0.1]

[base]
mass = 100
inertia = { ixx = 10, iyy = 12, izz = 14, ixy = 0.5 }

[[link]]
name = "arm"
parent = "base"
com = [0.5, 0.0, 0.0]
mass = 5.0
inertia = [0.01, 0.4, 0.4]
joint = { type = "revolute", origin = [0.5, 0.0, 0.0], axis = [0.0, 0.0, 2.0], limits = { lower = -1.0, upper = 1.0 } }

[[link]]
name = "slider"
parent = "arm"
com = [0.1, 0.0, 0.0]
mass = 1.0
inertia = [[0.01, 0.0, 0.0], [0.0, 0.02, 0.0], [0.0, 0.0, 0.02]]
[link.joint]
type = "prismatic"
name = "slide"
origin = [0.5, 0.0, 0.0]
rpy = [0.0, 0.0, 1.5707963267948966]
axis = [1.0, 0.0, 0.0]

[[point]]
name = "tip"
body = "slider"
offset = [0.2, 0.0, 0.0]
"#;

    fn err(text: &str) -> String {
        match model_from_toml_str(text, "test.toml") {
            Ok(_) => panic!("expected an error for:\n{text}"),
            Err(e) => {
                assert!(matches!(e, SpacearmError::Parse(_)), "{e:?}");
                e.to_string()
            }
        }
    }

    #[test]
    fn reads_a_valid_document() {
        let m = model_from_toml_str(DEMO, "demo.toml").unwrap();
        assert_eq!(m.name(), "demo");
        assert_eq!(m.n_dof(), 2);
        assert_eq!(m.base().inertia[(0, 1)], 0.5);
        assert_eq!(m.links()[0].joint.name, "arm_joint");
        assert_eq!(m.links()[0].joint.axis.into_inner(), Vector3::z());
        assert_eq!(m.links()[0].joint.limits.upper, 1.0);
        assert_eq!(m.links()[0].joint.limits.effort, f64::INFINITY);
        assert_eq!(m.links()[1].joint.kind, JointType::Prismatic);
        assert!((m.links()[1].joint.rotation_in_parent.angle() - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        assert_eq!(m.points()[m.end_effector().unwrap()].name, "tip");
        assert_eq!(m.initial_q(), vec![0.3, 0.1]);
    }

    #[test]
    fn round_trip_is_exact() {
        for m in [presets::planar4(), presets::spatial6(), model_from_toml_str(DEMO, "demo.toml").unwrap()] {
            let text = model_to_toml(&m);
            let back = model_from_toml_str(&text, "round.toml").unwrap();
            assert_eq!(back, m, "{text}");
            assert_eq!(model_to_toml(&back), text);
        }
    }

    #[test]
    fn round_trip_of_awkward_values() {
        let rotation = xyzw(&UnitQuaternion::from_euler_angles(0.1, 0.2, 0.3));
        let mut b = ModelBuilder::new("we\"ird\\ name 'é' #[x] = λ", "base", 100.0, [[10.0, 0.5, 0.0], [0.5, 12.0, 0.0], [0.0, 0.0, 14.0]]).unwrap();
        b.add_link(LinkSpec {
            name: "arm".into(),
            parent: "base".into(),
            joint_name: None,
            kind: JointType::Revolute,
            origin_in_parent: [0.5, 0.0, 0.0],
            rotation_in_parent: rotation,
            axis: [0.0, 0.6, 0.8],
            com_from_joint: [1e-300, -0.1, 1.0 / 3.0],
            mass: 5.0,
            inertia: [[0.01, 0.0, 0.0], [0.0, 0.4, 0.0], [0.0, 0.0, 0.4]],
            limits: JointLimits { velocity: 7.5, ..JointLimits::unlimited() },
        })
        .unwrap();
        let m = b.build().unwrap();
        let text = model_to_toml(&m);
        assert_eq!(model_from_toml_str(&text, "x").unwrap(), m, "{text}");
    }

    #[test]
    fn syntax_errors_carry_line_and_column() {
        let e = err("[model]\nname = \"x\"\n\n[base]\nmass = = 3\n");
        assert!(e.starts_with("test.toml:5:"), "{e}");
        assert!(e.contains("mass = = 3"), "{e}");
        let e = err("[model\nname = 1");
        assert!(e.starts_with("test.toml:1:"), "{e}");
    }

    #[test]
    fn unknown_keys_are_named() {
        let e = err(&DEMO.replace("mass = 5.0", "mas = 5.0"));
        assert!(e.contains("unknown field `mas`"), "{e}");
        assert!(e.starts_with("test.toml:15:"), "{e}");
        let e = err(&DEMO.replace("[[point]]", "[[points]]"));
        assert!(e.contains("unknown field `points`"), "{e}");
    }

    #[test]
    fn wrong_types_and_missing_fields() {
        let e = err(&DEMO.replace("mass = 5.0", "mass = \"five\""));
        assert!(e.starts_with("test.toml:15:") && e.contains("invalid type"), "{e}");
        let e = err(&DEMO.replace("com = [0.5, 0.0, 0.0]\n", ""));
        assert!(e.contains("missing field `com`"), "{e}");
        assert!(e.starts_with("test.toml:"), "{e}");
        let e = err(&DEMO.replace("offset = [0.2, 0.0, 0.0]", "offset = [0.2, 0.0]"));
        assert!(e.contains("test.toml:35:") && e.contains("length 3"), "{e}");
        let e = err(&DEMO.replace("type = \"prismatic\"", "type = \"hinge\""));
        assert!(e.contains("hinge") && e.contains("revolute"), "{e}");
        let e = err(&DEMO.replace("inertia = [0.01, 0.4, 0.4]", "inertia = [0.01, 0.4]"));
        assert!(e.contains("link 'arm': inertia must be [ixx, iyy, izz]"), "{e}");
    }

    #[test]
    fn semantic_errors_name_the_link_and_line() {
        let e = err(&DEMO.replace("mass = 5.0", "mass = -5.0"));
        assert!(e.starts_with("test.toml:15:8:") && e.contains("link 'arm'") && e.contains(">= 0"), "{e}");
        let e = err(&DEMO.replace("inertia = [0.01, 0.4, 0.4]", "inertia = [0.01, 0.4, 1.4]"));
        assert!(e.contains("link 'arm'") && e.contains("triangle"), "{e}");
        let e = err(&DEMO.replace("axis = [0.0, 0.0, 2.0]", "axis = [0.0, 0.0, 0.0]"));
        assert!(e.contains("link 'arm'") && e.contains("non-zero"), "{e}");
        let e = err(&DEMO.replace("rpy = [0.0, 0.0, 1.5707963267948966]", "rotation = [0.0, 0.0, 0.0, 2.0]"));
        assert!(e.contains("link 'slider'") && e.contains("unit quaternion") && e.starts_with("test.toml:29:"), "{e}");
        let e = err(&DEMO.replace("parent = \"arm\"", "parent = \"nope\""));
        assert!(e.contains("parent 'nope'") && e.contains("\"base\", \"arm\""), "{e}");
        let e = err(&DEMO.replace("parent = \"base\"", "parent = \"slider\""));
        assert!(e.contains("cycle 'arm' -> 'slider' -> 'arm'"), "{e}");
        let e = err(&DEMO.replace("parent = \"base\"", "parent = \"arm\""));
        assert!(e.contains("its own parent"), "{e}");
        let e = err(&DEMO.replace("initial_q = [0.3, 0.1]", "initial_q = [0.3]"));
        assert!(e.contains("N = 2") && e.starts_with("test.toml:5:"), "{e}");
        let e = err(&DEMO.replace("body = \"slider\"", "body = \"hand\""));
        assert!(e.contains("point 'tip'") && e.contains("'hand'"), "{e}");
        let e = err(&DEMO.replace("end_effector = \"tip\"", "end_effector = \"hand\""));
        assert!(e.contains("end effector 'hand'"), "{e}");
        let e = err(&DEMO.replace("limits = { lower = -1.0, upper = 1.0 }", "limits = { lower = 1.0, upper = -1.0 }"));
        assert!(e.contains("lower <= upper") && e.contains("arm_joint"), "{e}");
        let e = err(&DEMO.replace("name = \"slider\"", "name = \"arm\""));
        assert!(e.contains("'arm' is used twice"), "{e}");
        let e = err(&DEMO.replace("[base]\nmass = 100", "[base]\nmass = 0"));
        assert!(e.contains("base 'base'") && e.contains("> 0"), "{e}");
    }

    #[test]
    fn forward_reference_is_explained() {
        let text = r#"
[model]
name = "f"
[base]
mass = 1
inertia = [1, 1, 1]
[[link]]
name = "b"
parent = "a"
com = [0, 0, 0]
mass = 1
inertia = [1, 1, 1]
joint = { type = "revolute", origin = [0, 0, 0], axis = [0, 0, 1] }
[[link]]
name = "a"
parent = "base"
com = [0, 0, 0]
mass = 1
inertia = [1, 1, 1]
joint = { type = "revolute", origin = [0, 0, 0], axis = [0, 0, 1] }
"#;
        let e = err(text);
        assert!(e.starts_with("test.toml:9:") && e.contains("defined later in the file (line 14)"), "{e}");
    }

    #[test]
    fn dh_section_builds_the_planar4_preset() {
        let q0 = presets::planar4().initial_q().to_vec();
        let text = format!(
            r#"
[model]
name = "planar4"
initial_q = {}
[base]
mass = 100.0
inertia = [4.1667, 4.1667, 4.1667]
[dh]
convention = "classic"
joint1_origin = [0.25, 0.0, 0.0]
{}"#,
            vec_str(&q0),
            (0..4)
                .map(|_| "[[dh.link]]\nd = 0.0\ntheta = 0.0\na = 1.0\nalpha = 0.0\ncom = [-0.5, 0.0, 0.0]\nmass = 10.0\n\
                          inertia = [0.004166666666666667, 0.8354166666666667, 0.8354166666666667]\n")
                .collect::<String>()
        );
        let m = model_from_toml_str(&text, "dh.toml").unwrap();
        let p = presets::planar4();
        assert_eq!(m.n_dof(), 4);
        assert_eq!(m.points()[m.end_effector().unwrap()].name, "end_effector");
        for (a, b) in m.links().iter().zip(p.links()) {
            assert!((a.joint.origin_in_parent - b.joint.origin_in_parent).norm() < 1e-15);
            assert!((a.com_from_joint - b.com_from_joint).norm() < 1e-15);
            assert!((a.mass.inertia - b.mass.inertia).abs().max() < 1e-15);
        }
        let e = err(&text.replace("a = 1.0\n", "a = 1.0\ncom_to_next = [1.0, 0.0, 0.0]\n"));
        assert!(e.contains("DH link 1") && e.contains("`com_to_next` does not belong to a classic"), "{e}");
        let e = err(&text.replacen("alpha = 0.0\n", "", 1));
        assert!(e.contains("DH link 1: missing `alpha`"), "{e}");
        let e = err(&text.replacen("mass = 10.0", "mass = -1.0", 1));
        assert!(e.contains("link 'link1'") && e.starts_with("test.toml:11:1:"), "{e}");
    }

    #[test]
    fn mutated_documents_never_panic() {
        use rand::{Rng, SeedableRng};
        let mut r = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let base = model_to_toml(&presets::spatial6());
        let pieces = ["", "0", "-1", "1e400", "nan", "\"", "[", "]", "{", "}", "=", "\n", "[[link]]", "inf", "1e308", ",", "\u{e9}", "#"];
        for _ in 0..3000 {
            let mut t: Vec<char> = base.chars().collect();
            for _ in 0..r.random_range(1..4) {
                let pos = r.random_range(0..=t.len());
                match r.random_range(0..3) {
                    0 if pos < t.len() => {
                        t.remove(pos);
                    }
                    1 => {
                        let p = pieces[r.random_range(0..pieces.len())];
                        for (k, c) in p.chars().enumerate() {
                            t.insert(pos + k, c);
                        }
                    }
                    _ => {
                        let end = (pos + r.random_range(0..40)).min(t.len());
                        t.drain(pos..end);
                    }
                }
            }
            let text: String = t.into_iter().collect();
            if let Err(e) = model_from_toml_str(&text, "fuzz") {
                assert!(matches!(e, SpacearmError::Parse(_)));
                assert!(e.to_string().starts_with("fuzz"));
            }
        }
    }

    #[test]
    fn huge_inertias_are_rejected_not_panicking() {
        let e = err(&DEMO.replace("inertia = [0.01, 0.4, 0.4]", "inertia = [[1e308, 1e308, 1e308], [1e308, 1e308, 1e308], [1e308, 1e308, 1e308]]"));
        assert!(e.contains("link 'arm'"), "{e}");
    }

    #[test]
    fn geometry_tables_read_write_and_round_trip() {
        let text = format!(
            "{DEMO}\n[[geometry]]\nbody = \"base\"\nshape = \"box\"\nsize = [1.0, 0.8, 0.6]\nrgba = [0.9, 0.7, 0.3, 1.0]\n\
             [[geometry]]\nname = \"arm_rod\"\nbody = \"arm\"\nshape = \"capsule\"\nradius = 0.05\nlength = 0.9\nrpy = [0.0, 1.5707963267948966, 0.0]\n\
             [[geometry]]\nbody = \"arm\"\nrole = \"collision\"\nshape = \"cylinder\"\nradius = 0.06\nlength = 1.0\norigin = [0.0, 0.0, 0.1]\n\
             [[geometry]]\nbody = \"slider\"\nshape = \"sphere\"\nradius = 0.1\n\
             [[geometry]]\nbody = \"slider\"\nshape = \"mesh\"\nfile = \"meshes/hand.stl\"\nscale = [0.001, 0.001, 0.001]\n"
        );
        let m = model_from_toml_str(&text, "g.toml").unwrap();
        let g = m.geometries();
        assert_eq!(g.len(), 5);
        assert_eq!((g[0].name.as_str(), g[0].body, g[0].role), ("base_visual0", 0, GeometryRole::Visual));
        assert_eq!(g[0].shape, Shape::Box { size: [1.0, 0.8, 0.6] });
        assert_eq!(g[0].rgba, [0.9, 0.7, 0.3, 1.0]);
        assert_eq!(g[1].name, "arm_rod");
        // rpy (0, π/2, 0) is Ry(π/2): it turns the capsule's z onto the body's x.
        let z = g[1].rotation * Vector3::z();
        assert!((z - Vector3::x()).norm() < 1e-15, "{z:?}");
        assert_eq!((g[2].name.as_str(), g[2].role), ("arm_collision0", GeometryRole::Collision));
        assert_eq!(g[2].origin, Vector3::new(0.0, 0.0, 0.1));
        assert_eq!(g[3].shape, Shape::Sphere { radius: 0.1 });
        assert_eq!(g[4].shape, Shape::Mesh { file: "meshes/hand.stl".into(), scale: [0.001; 3] });
        assert_eq!(g[4].rgba, crate::model::geometry::DEFAULT_RGBA);
        let again = model_from_toml_str(&model_to_toml(&m), "again.toml").unwrap();
        assert_eq!(again, m);
        // Errors point at the offending key.
        let bad = |geometry: &str| err(&format!("{DEMO}\n[[geometry]]\n{geometry}"));
        let e = bad("body = \"ghost\"\nshape = \"sphere\"\nradius = 1.0\n");
        assert!(e.contains("'ghost': not a body") && e.contains("body = \"ghost\""), "{e}");
        let e = bad("body = \"arm\"\nshape = \"sphere\"\nradius = -1.0\n");
        assert!(e.contains("sphere radius must be a finite length > 0") && e.contains("radius = -1.0"), "{e}");
        let e = bad("body = \"arm\"\nshape = \"box\"\nradius = 1.0\n");
        assert!(e.contains("a box takes size, not `radius`"), "{e}");
        let e = bad("body = \"arm\"\nshape = \"cylinder\"\nradius = 1.0\n");
        assert!(e.contains("a cylinder needs `length`"), "{e}");
        let e = bad("body = \"arm\"\nshape = \"cone\"\nradius = 1.0\n");
        assert!(e.contains("shape must be \"box\""), "{e}");
        let e = bad("body = \"arm\"\nrole = \"both\"\nshape = \"sphere\"\nradius = 1.0\n");
        assert!(e.contains("role must be \"visual\" or \"collision\""), "{e}");
        let e = bad("body = \"arm\"\nshape = \"sphere\"\nradius = 1.0\nrgba = [1.0, 1.0, 1.0, 2.0]\n");
        assert!(e.contains("rgba must be 4 numbers in [0, 1]") && e.contains("rgba = [1.0"), "{e}");
        let e = bad("name = \"g\"\nbody = \"arm\"\nshape = \"sphere\"\nradius = 1.0\n[[geometry]]\nname = \"g\"\nbody = \"arm\"\nshape = \"sphere\"\nradius = 1.0\n");
        assert!(e.contains("geometry name 'g' is used twice"), "{e}");
    }

}
