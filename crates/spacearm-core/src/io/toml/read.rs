//! Reading a TOML model file: the document ([`super::schema`]) to a [`Model`] through the
//! [`ModelBuilder`], every error located at its line and column ([`model_from_toml_str`]).

use std::collections::{HashMap, HashSet};
use std::fmt::Write as _;
use std::ops::Range;

use toml::{Spanned, Value};

use crate::error::{ModelError, ModelField, ModelItem, Result, SpacearmError};
use crate::io::dh::{ClassicDhLink, DhArm, DhConvention, DhTable, PaperDhLink};
use crate::model::joint::{JointDynamics, JointLimits, JointType};
use crate::math::rotations::xyzw_from_rpy;
use crate::model::geometry::ShapeParts;
use crate::model::appendage::{self, beam_parts, compliant_parts, panel_parts, BeamDamping, BeamSpec, CompliantSpec, PanelBody, PanelSpec, Parts, Restoring};
use crate::model::slosh::{slosh_links, SloshModel, SloshRestoring, SloshSpec};
use crate::model::{GeometryRole, GeometrySpec, LinkSpec, Model, ModelBuilder, Shape, TriangleInequality};

use super::schema::*;

type Span = Range<usize>;

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

/// An appendage's `parent` (slosh, panel, beam), or `base` when the file leaves it out.
fn parent_or(parent: &Option<Spanned<String>>, base: &str) -> String {
    parent.as_ref().map_or_else(|| base.to_string(), |p| p.get_ref().clone())
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
        let model = SloshModel::from_name(s.model.get_ref()).map_err(|m| ctx.err(&sp(&s.model), format!("slosh '{name}': {m}")))?;
        let restoring = SloshRestoring::from_options(s.stiffness.as_ref().map(|k| *k.get_ref()), s.frequency.as_ref().map(|w| *w.get_ref()))
            .map_err(|m| ctx.err(&sp(sd), format!("slosh '{name}': {m}")))?;
        let spec = SloshSpec {
            name: name.clone(),
            parent: parent_or(&s.parent, &base_name),
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
        let refuse = |m: String| ctx.err(&sp(pd), format!("{who}: {m}"));
        let restoring = Restoring::from_options(p.stiffness, p.frequency).map_err(refuse)?;
        let inertia = p.inertia.as_ref().map(inertia_from_value).transpose().map_err(refuse)?;
        let body = PanelBody::from_options(p.size, inertia, p.com_distance).map_err(refuse)?;
        let spec = PanelSpec {
            name: name.clone(),
            parent: parent_or(&p.parent, &base_name),
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
        let damping = BeamDamping::from_options(b.damping, b.damping_ratio).map_err(|m| ctx.err(&sp(bd), format!("{who}: {m}")))?;
        let bending = appendage::bending(name, &b.axis, b.bending_axes.clone(), &ei).map_err(|e| ctx.err(&sp(bd), e))?;
        let spec = BeamSpec {
            name: name.clone(),
            parent: parent_or(&b.parent, &base_name),
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

    // [[cmg]]s: a gimbal link and its rotor (model/cmg.rs, docs/cmg.md).
    for cd in &doc.cmg {
        let parts = crate::model::cmg::cmg_parts(cd.get_ref(), &base_name, ModelItem::Link(at.links.len())).map_err(|e| ctx.err(&sp(cd), e))?;
        add_parts(&mut at, &mut builder, &parts, &sp(cd))?;
    }

    // [[gripper]]s: a palm and its capsule fingers (model/gripper.rs, docs/contact.md).
    for gd in &doc.gripper {
        let parts = crate::model::gripper::gripper_parts(gd.get_ref(), &base_name, ModelItem::Link(at.links.len())).map_err(|e| ctx.err(&sp(gd), e))?;
        add_parts(&mut at, &mut builder, &parts, &sp(gd))?;
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
        Some(r) => GeometryRole::from_name(r.get_ref()).map_err(|m| ctx.err(&sp(r), format!("{who}: {m}")))?,
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
            DhConvention::Classic => (
                &[("joint_to_com", r.joint_to_com.is_some()), ("com_to_next", r.com_to_next.is_some())],
                "the classic convention uses d, theta, a, alpha and com",
            ),
            DhConvention::Paper => (
                &[("d", r.d.is_some()), ("a", r.a.is_some()), ("com", r.com.is_some())],
                "the paper convention uses theta, alpha, joint_to_com and com_to_next",
            ),
        };
        if let Some((key, _)) = own.iter().find(|(_, present)| *present) {
            return Err(ctx.err(&span, format!("{who}: `{key}` does not belong to a {} DH table; {other}", convention.name())));
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
            DhConvention::Classic => classic.push(ClassicDhLink {
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
            DhConvention::Paper => paper.push(PaperDhLink {
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
        DhConvention::Classic => DhTable::Classic(classic),
        DhConvention::Paper => DhTable::Paper(paper),
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
