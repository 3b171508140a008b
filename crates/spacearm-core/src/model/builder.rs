//! [`ModelBuilder`]: the one way to make a [`Model`]. Every door feeds it — the Python
//! `RobotBuilder` and URDF loader through the bindings, the TOML reader, the DH converter — so
//! every rule of [`crate::model::validate`] is applied once, the same way, whatever the source.

use std::collections::{HashMap, HashSet};

use nalgebra::Matrix3;

use crate::error::{ModelError, ModelField, ModelItem};
use crate::model::body::{MassProperties, TriangleInequality};
use crate::model::geometry::{self, Geometry, GeometryRole, GeometrySpec, DEFAULT_RGBA};
use crate::model::joint::JointDynamics;
use crate::model::link::{Link, Point};
use crate::model::system::Model;
use crate::model::validate;

/// At its former path too (`model::builder::LinkSpec`).
pub use crate::model::link::LinkSpec;

/// Incremental builder for [`Model`]. Names are resolved when a link or point is added, each
/// link's own fields are checked then, and the rules that need the whole model when
/// [`ModelBuilder::build`] runs. Every error is a [`ModelError`] that names the item (the base,
/// the `k`-th link or point given, the model) and the field at fault.
#[derive(Debug, Clone)]
pub struct ModelBuilder {
    pub(super) name: String,
    pub(super) base_name: String,
    pub(super) base: MassProperties,
    pub(super) links: Vec<Link>,
    pub(super) points: Vec<Point>,
    pub(super) end_effector: Option<String>,
    pub(super) initial_q: Option<Vec<f64>>,
    /// Body index by name (base 0), point and joint names: name look-ups in O(1), so that a
    /// model of N items builds in O(N).
    pub(super) body_by_name: HashMap<String, usize>,
    pub(super) point_names: HashSet<String>,
    pub(super) joint_names: HashSet<String>,
    pub(super) triangle_inequality: TriangleInequality,
    /// Warnings of the bodies accepted under [`TriangleInequality::Warn`].
    pub(super) inertia_warnings: Vec<String>,
    pub(super) geometries: Vec<Geometry>,
    pub(super) geometry_names: HashSet<String>,
    /// Geometries given so far per (body, role): the `k` of a default name `<body>_<role><k>`
    /// in O(1), so that N unnamed geometries load in O(N) (a scan per geometry was O(N²):
    /// 160k unnamed URDF `<visual>`s took 49.5 s).
    pub(super) geometry_counts: HashMap<(usize, GeometryRole), usize>,
    /// Initial coordinates per moving link, by link name, of a builder seeded from a model
    /// (model/edit.rs): used by [`ModelBuilder::build`] when no `initial_q` is set, so that the
    /// links edited in keep theirs and new joints start at their spring rest (0 unless set).
    pub(super) initial_q_by_link: HashMap<String, f64>,
}

fn matrix3(rows: &[[f64; 3]; 3]) -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| rows[i][j])
}

impl ModelBuilder {
    /// Start a model with its base: mass (kg, > 0) and inertia about the base CM in base axes.
    pub fn new(name: &str, base_name: &str, base_mass: f64, base_inertia: [[f64; 3]; 3]) -> Result<Self, ModelError> {
        Self::with_triangle_inequality(name, base_name, base_mass, base_inertia, TriangleInequality::Enforce)
    }

    /// As [`ModelBuilder::new`], choosing what every body's inertia that breaks the triangle
    /// inequality does: refused ([`TriangleInequality::Enforce`], the default) or accepted with a
    /// warning kept in [`Model::inertia_warnings`] ([`TriangleInequality::Warn`], the option
    /// `allow_nonphysical_inertia` of the other doors).
    pub fn with_triangle_inequality(
        name: &str,
        base_name: &str,
        base_mass: f64,
        base_inertia: [[f64; 3]; 3],
        triangle_inequality: TriangleInequality,
    ) -> Result<Self, ModelError> {
        validate::non_empty_name(ModelItem::Model, ModelField::Name, "model name", name)?;
        validate::non_empty_name(ModelItem::Base, ModelField::Name, "base name", base_name)?;
        let (base, warning) =
            MassProperties::checked(ModelItem::Base, &format!("base '{base_name}'"), base_mass, matrix3(&base_inertia), true, triangle_inequality)?;
        Ok(ModelBuilder {
            name: name.to_string(),
            base_name: base_name.to_string(),
            base,
            links: Vec::new(),
            points: Vec::new(),
            end_effector: None,
            initial_q: None,
            body_by_name: HashMap::from([(base_name.to_string(), 0)]),
            point_names: HashSet::new(),
            joint_names: HashSet::new(),
            triangle_inequality,
            inertia_warnings: warning.into_iter().collect(),
            geometries: Vec::new(),
            geometry_names: HashSet::new(),
            geometry_counts: HashMap::new(),
            initial_q_by_link: HashMap::new(),
        })
    }

    /// Names of the bodies added so far, base first.
    fn body_names(&self) -> Vec<&str> {
        std::iter::once(self.base_name.as_str()).chain(self.links.iter().map(|l| l.name.as_str())).collect()
    }

    /// Index of the body called `name` among those added so far.
    fn body_index(&self, name: &str) -> Option<usize> {
        self.body_by_name.get(name).copied()
    }

    /// Add a link attached to a body added before (its parent).
    pub fn add_link(&mut self, spec: LinkSpec) -> Result<&mut Self, ModelError> {
        let item = ModelItem::Link(self.links.len());
        validate::non_empty_name(item, ModelField::Name, "link name", &spec.name)?;
        let who = format!("link '{}'", spec.name);
        if let Some(joint_name) = &spec.joint_name {
            validate::non_empty_name(item, ModelField::JointName, &format!("{who}: joint name"), joint_name)?;
        }
        let parent = self.body_index(&spec.parent).ok_or_else(|| {
            ModelError::new(
                item,
                ModelField::Parent,
                format!(
                    "parent body '{}' is not defined (yet); known bodies: {:?}; add parents before children",
                    spec.parent,
                    self.body_names()
                ),
            )
        })?;
        validate::position(item, ModelField::Origin, &who, "joint origin", &spec.origin_in_parent)?;
        validate::position(item, ModelField::Com, &who, "com", &spec.com_from_joint)?;
        let axis = validate::joint_axis(item, &who, spec.kind, &spec.axis)?;
        let rotation = validate::joint_rotation(item, &who, &spec.rotation_in_parent)?;
        let joint_name = spec.joint_name.clone().unwrap_or_else(|| format!("{}_joint", spec.name));
        let taken = validate::NamesTaken {
            by_body: self.body_by_name.contains_key(&spec.name),
            by_point: self.point_names.contains(&spec.name),
            joint_by_joint: self.joint_names.contains(&joint_name),
        };
        validate::new_link_names(item, &spec.name, &joint_name, taken)?;
        validate::joint_limits(item, &format!("joint '{joint_name}' of link '{}'", spec.name), &spec.limits)?;
        let (mass, warning) = MassProperties::checked(item, &who, spec.mass, matrix3(&spec.inertia), false, self.triangle_inequality)?;
        self.inertia_warnings.extend(warning);
        self.body_by_name.insert(spec.name.clone(), self.links.len() + 1);
        self.joint_names.insert(joint_name);
        self.links.push(Link::from_spec(spec, parent, rotation, axis, mass));
        Ok(self)
    }

    /// Set the passive dynamics of the joint of the link called `link` (added before):
    /// actuation and the spring–damper ([`JointDynamics`], docs/flexibility.md), checked by
    /// [`validate::joint_dynamics`]. A link's joint is actuated and without spring until then.
    pub fn set_joint_dynamics(&mut self, link: &str, dynamics: JointDynamics) -> Result<&mut Self, ModelError> {
        let k = match self.body_index(link) {
            Some(b) if b > 0 => b - 1,
            _ => {
                let links: Vec<&str> = self.links.iter().map(|l| l.name.as_str()).collect();
                return Err(ModelError::new(
                    ModelItem::Model,
                    ModelField::JointDynamics,
                    format!("joint dynamics: '{link}' is not a link of the model (the base has no joint); links: {links:?}"),
                ));
            }
        };
        let joint = &self.links[k].joint;
        validate::joint_dynamics(ModelItem::Link(k), &format!("joint '{}' of link '{link}'", joint.name), joint.kind, &dynamics)?;
        self.links[k].joint.dynamics = dynamics;
        Ok(self)
    }

    /// Number of links added so far.
    pub(crate) fn n_links(&self) -> usize {
        self.links.len()
    }

    /// Add a named point fixed to `body` at `offset` (body frame, from its CM).
    pub fn add_point(&mut self, name: &str, body: &str, offset: [f64; 3]) -> Result<&mut Self, ModelError> {
        let item = ModelItem::Point(self.points.len());
        validate::non_empty_name(item, ModelField::Name, "point name", name)?;
        validate::new_point_name(item, name, self.body_by_name.contains_key(name) || self.point_names.contains(name))?;
        let who = format!("point '{name}'");
        let b = self.body_index(body).ok_or_else(|| {
            ModelError::new(
                item,
                ModelField::Body,
                format!("{who}: body '{body}' is not a body of the model; bodies defined so far: {:?}", self.body_names()),
            )
        })?;
        let offset = validate::position(item, ModelField::Offset, &who, "offset", &offset)?;
        self.point_names.insert(name.to_string());
        self.points.push(Point { name: name.to_string(), body: b, offset });
        Ok(self)
    }

    /// Add a visual or collision shape fixed to `spec.body` (model/geometry.rs): its shape,
    /// placement and colour are checked here; its name (default `<body>_<role><k>`) must differ
    /// from every geometry's given before.
    pub fn add_geometry(&mut self, spec: GeometrySpec) -> Result<&mut Self, ModelError> {
        let item = ModelItem::Geometry(self.geometries.len());
        let body = self.body_index(&spec.body).ok_or_else(|| {
            ModelError::new(
                item,
                ModelField::Body,
                format!("geometry on '{}': not a body of the model; bodies defined so far: {:?}", spec.body, self.body_names()),
            )
        })?;
        let name = match spec.name {
            Some(n) => {
                validate::non_empty_name(item, ModelField::Name, "geometry name", &n)?;
                n
            }
            None => {
                let k = self.geometry_counts.get(&(body, spec.role)).copied().unwrap_or(0);
                let mut n = format!("{}_{}{k}", spec.body, spec.role.as_str());
                while self.geometry_names.contains(&n) {
                    n.push('_');
                }
                n
            }
        };
        if self.geometry_names.contains(&name) {
            return Err(ModelError::new(item, ModelField::Name, format!("geometry name '{name}' is used twice")));
        }
        let who = format!("geometry '{name}'");
        geometry::check_shape(item, &who, &spec.shape)?;
        let rgba = spec.rgba.unwrap_or(DEFAULT_RGBA);
        geometry::check_rgba(item, &who, &rgba)?;
        let (origin, rotation) = geometry::check_placement(item, &who, &spec.origin, &spec.rotation)?;
        self.geometry_names.insert(name.clone());
        *self.geometry_counts.entry((body, spec.role)).or_insert(0) += 1;
        self.geometries.push(Geometry { name, body, role: spec.role, shape: spec.shape, origin, rotation, rgba });
        Ok(self)
    }

    /// Designate the point called `name` as the end effector.
    pub fn set_end_effector(&mut self, name: &str) -> &mut Self {
        self.end_effector = Some(name.to_string());
        self
    }

    /// Set the initial joint coordinates (length `N`).
    pub fn set_initial_q(&mut self, q: Vec<f64>) -> &mut Self {
        self.initial_q = Some(q);
        self
    }

    /// The number of degrees of freedom of the first `links` links (in the order they were added).
    pub fn dofs_of_first(&self, links: usize) -> usize {
        self.links.iter().take(links).map(|l| l.joint.kind.dof()).sum()
    }

    /// `q`, the initial coordinates of the degrees of freedom of the first `links` links,
    /// completed with the spring rest of every later one (the passive coordinates that
    /// appendages — slosh modes, panels, beams — add after them start at rest): the initial `q`
    /// of the whole model. `None` when `q` does not have the first links' length.
    pub fn initial_q_completed_at_rest(&self, q: &[f64], links: usize) -> Option<Vec<f64>> {
        if q.len() != self.dofs_of_first(links) {
            return None;
        }
        let rest = self.links.iter().skip(links).filter(|l| l.joint.kind.dof() == 1).map(|l| l.joint.dynamics.rest);
        Some(q.iter().copied().chain(rest).collect())
    }

    /// Apply the whole-model rules and produce the immutable model.
    pub fn build(&self) -> Result<Model, ModelError> {
        let ee = match &self.end_effector {
            None => None,
            Some(n) => Some(self.points.iter().position(|p| &p.name == n).ok_or_else(|| {
                let names: Vec<&str> = self.points.iter().map(|p| p.name.as_str()).collect();
                ModelError::new(ModelItem::Model, ModelField::EndEffector, format!("end effector '{n}' is not a defined point; points: {names:?}"))
            })?),
        };
        Ok(Model::new(
            self.name.clone(),
            self.base_name.clone(),
            self.base.clone(),
            self.links.clone(),
            self.points.clone(),
            ee,
            self.initial_q.clone().or_else(|| self.seeded_initial_q()),
        )?
        .with_triangle_inequality(self.triangle_inequality, self.inertia_warnings.clone())
        .with_geometries(self.geometries.clone()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::joint::{JointLimits, JointType};
    use crate::io::dh::{ClassicDhLink, DhArm, DhTable};
    use crate::io::toml::model_from_toml_str;
    use crate::SpacearmError;

    fn spec(axis: [f64; 3], mass: f64, limits: JointLimits) -> LinkSpec {
        LinkSpec {
            name: "arm".into(),
            parent: "base".into(),
            joint_name: None,
            kind: JointType::Revolute,
            origin_in_parent: [0.5, 0.0, 0.0],
            rotation_in_parent: [0.0, 0.0, 0.0, 1.0],
            axis,
            com_from_joint: [0.5, 0.0, 0.0],
            mass,
            inertia: [[0.01, 0.0, 0.0], [0.0, 0.4, 0.0], [0.0, 0.0, 0.4]],
            limits,
        }
    }

    fn through_builder(s: LinkSpec) -> SpacearmError {
        let mut b = ModelBuilder::new("m", "base", 100.0, [[10.0, 0.0, 0.0], [0.0, 10.0, 0.0], [0.0, 0.0, 10.0]]).unwrap();
        let e = match b.add_link(s) {
            Err(e) => e,
            Ok(b) => b.build().unwrap_err(),
        };
        assert_eq!(e.item, ModelItem::Link(0), "{e}");
        e.into()
    }

    fn toml_number(x: f64) -> String {
        format!("{x:?}")
    }

    fn through_toml(s: &LinkSpec) -> SpacearmError {
        let [a0, a1, a2] = s.axis.map(toml_number);
        let l = &s.limits;
        let limits = if l.lower.is_finite() { format!(", limits = {{ lower = {:?}, upper = {:?} }}", l.lower, l.upper) } else { String::new() };
        let text = format!(
            "[model]\nname = \"m\"\n[base]\nmass = 100.0\ninertia = [10.0, 10.0, 10.0]\n[[link]]\nname = \"arm\"\nparent = \"base\"\n\
             com = [0.5, 0.0, 0.0]\nmass = {:?}\ninertia = [0.01, 0.4, 0.4]\n\
             joint = {{ type = \"revolute\", origin = [0.5, 0.0, 0.0], axis = [{a0}, {a1}, {a2}]{limits} }}\n",
            s.mass
        );
        model_from_toml_str(&text, "doors.toml").unwrap_err()
    }

    fn through_dh(mass: f64, limits: JointLimits) -> SpacearmError {
        // A DH row cannot state an axis (it is z of the DH frame); mass and limits it can.
        let row = ClassicDhLink {
            name: Some("arm".into()),
            joint_name: Some("arm_joint".into()),
            kind: JointType::Revolute,
            d: 0.0,
            theta: 0.0,
            a: 1.0,
            alpha: 0.0,
            com: [-0.5, 0.0, 0.0],
            mass,
            inertia: [[0.01, 0.0, 0.0], [0.0, 0.4, 0.0], [0.0, 0.0, 0.4]],
            limits,
        };
        let arm = DhArm {
            table: DhTable::Classic(vec![row]),
            parent: "base".into(),
            joint1_origin: [0.5, 0.0, 0.0],
            joint1_rotation: [0.0, 0.0, 0.0, 1.0],
            tool_offset: [0.0; 3],
            tip_point: None,
        };
        crate::io::dh::model_from_dh("m", "base", 100.0, [[10.0, 0.0, 0.0], [0.0, 10.0, 0.0], [0.0, 0.0, 10.0]], &arm, None).unwrap_err()
    }

    /// The message of an invalid-model error, and that of a model-file error after its
    /// `file:line:column: ` prefix and without the quoted source line under it.
    fn core(e: &SpacearmError) -> String {
        match e {
            SpacearmError::InvalidModel(m) => format!("invalid model: {m}"),
            SpacearmError::Parse(m) => {
                let first = m.lines().next().unwrap();
                first.splitn(4, ':').nth(3).unwrap().trim_start().to_string()
            }
            other => panic!("not a model error: {other:?}"),
        }
    }

    #[test]
    fn every_door_gives_the_same_verdict() {
        let ok = JointLimits::unlimited();
        let inverted = JointLimits { lower: 1.0, upper: -1.0, ..ok };
        // A tiny axis: every component below the 1e-9 floor although the norm is above it.
        let tiny = [8e-10, 8e-10, 8e-10];
        let builder = through_builder(spec(tiny, 5.0, ok));
        let toml = through_toml(&spec(tiny, 5.0, ok));
        assert!(matches!(builder, SpacearmError::InvalidModel(_)) && matches!(toml, SpacearmError::Parse(_)), "{builder:?} {toml:?}");
        assert_eq!(core(&builder), core(&toml));
        assert!(core(&builder).contains("link 'arm': joint axis must be a non-zero vector"), "{builder}");
        for (mass, limits, expect) in [(-1.0, ok, "mass must be >= 0 kg"), (5.0, inverted, "position limits must satisfy lower <= upper")] {
            let builder = through_builder(spec([0.0, 0.0, 1.0], mass, limits));
            let toml = through_toml(&spec([0.0, 0.0, 1.0], mass, limits));
            let dh = through_dh(mass, limits);
            assert!(core(&builder).contains(expect), "{builder}");
            assert!(matches!(dh, SpacearmError::InvalidModel(_)), "{dh:?}");
            assert_eq!(core(&builder), core(&toml));
            assert_eq!(core(&builder), core(&dh));
        }
    }

    #[test]
    fn errors_name_the_item_and_field() {
        let mut b = ModelBuilder::new("m", "base", 1.0, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]).unwrap();
        b.add_link(spec([0.0, 0.0, 1.0], 1.0, JointLimits::unlimited())).unwrap();
        let e = b.add_link(spec([0.0, 0.0, 0.0], 1.0, JointLimits::unlimited())).unwrap_err();
        assert_eq!((e.item, e.field), (ModelItem::Link(1), ModelField::Axis));
        let mut s = spec([0.0, 0.0, 1.0], 1.0, JointLimits::unlimited());
        s.parent = "ghost".into();
        assert_eq!(b.add_link(s).unwrap_err().field, ModelField::Parent);
        b.add_point("tip", "arm", [0.0; 3]).unwrap();
        assert_eq!(b.add_point("p", "arm", [f64::NAN, 0.0, 0.0]).unwrap_err().field, ModelField::Offset);
        assert_eq!(b.add_point("", "arm", [0.0; 3]).unwrap_err().field, ModelField::Name);
        let e = b.add_link(spec([0.0, 0.0, 1.0], 1.0, JointLimits::unlimited())).unwrap_err();
        assert_eq!((e.item, e.field), (ModelItem::Link(1), ModelField::Name), "{e}");
        assert!(e.message.contains("body name 'arm' is used twice"));
        let mut other = spec([0.0, 0.0, 1.0], 1.0, JointLimits::unlimited());
        other.name = "other".into();
        other.joint_name = Some("arm_joint".into());
        let e = b.add_link(other).unwrap_err();
        assert_eq!((e.item, e.field), (ModelItem::Link(1), ModelField::JointName), "{e}");
        assert_eq!(b.add_point("arm", "arm", [0.0; 3]).unwrap_err().field, ModelField::Name);
        let mut b = ModelBuilder::new("m", "base", 1.0, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]).unwrap();
        let mut massless = spec([0.0, 0.0, 1.0], 0.0, JointLimits::unlimited());
        massless.inertia = [[0.0; 3]; 3];
        b.add_link(massless).unwrap();
        b.set_initial_q(vec![0.0]);
        let e = b.build().unwrap_err();
        assert!(e.field == ModelField::Mass && e.message.contains("zero mass and inertia"), "{e}");
    }

    #[test]
    fn unit_axes_and_rotations_are_kept_exactly_others_normalized() {
        let mut b = ModelBuilder::new("m", "base", 1.0, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]).unwrap();
        let (s, c) = 0.3f64.sin_cos();
        let mut l = spec([0.0, s, c], 1.0, JointLimits::unlimited());
        l.rotation_in_parent = [0.0, 0.0, s, c];
        b.add_link(l).unwrap();
        let mut l = spec([0.0, 0.0, 2.0], 1.0, JointLimits::unlimited());
        l.name = "second".into();
        b.add_link(l).unwrap();
        let m = b.build().unwrap();
        assert_eq!(m.links()[0].joint.axis.into_inner(), nalgebra::Vector3::new(0.0, s, c));
        assert_eq!(m.links()[0].joint.rotation_in_parent.coords, nalgebra::Vector4::new(0.0, 0.0, s, c));
        assert_eq!(m.links()[1].joint.axis.into_inner(), nalgebra::Vector3::z());
    }

    #[test]
    fn unnamed_geometries_keep_their_default_names_through_60k_additions() {
        use crate::model::geometry::Shape;
        // The default name's k was found by scanning every geometry given before: N unnamed
        // geometries cost O(N²) (160k URDF <visual>s: 49.5 s) (issue 38). Now a count per
        // (body, role): 60k of them take milliseconds (the scan took ~30 s in release).
        let add = |b: &mut ModelBuilder, body: &str, role: GeometryRole, name: Option<&str>| {
            b.add_geometry(GeometrySpec { name: name.map(str::to_string), ..GeometrySpec::new(body, role, Shape::Sphere { radius: 0.1 }) }).map(|_| ())
        };
        let mut b = ModelBuilder::new("m", "base", 1.0, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]).unwrap();
        b.add_link(spec([0.0, 0.0, 1.0], 1.0, JointLimits::unlimited())).unwrap();
        // The names are those of before: <body>_<role><k>, k counting that body's and role's
        // geometries, a '_' appended while the name is taken.
        add(&mut b, "base", GeometryRole::Visual, Some("base_visual1")).unwrap();
        add(&mut b, "base", GeometryRole::Visual, None).unwrap();
        add(&mut b, "arm", GeometryRole::Collision, None).unwrap();
        add(&mut b, "base", GeometryRole::Collision, None).unwrap();
        add(&mut b, "base", GeometryRole::Visual, None).unwrap();
        let names: Vec<String> = b.geometries.iter().map(|g| g.name.clone()).collect();
        assert_eq!(names, ["base_visual1", "base_visual1_", "arm_collision0", "base_collision0", "base_visual2"]);
        // 60k more keep the rule (their time is not asserted: speed is measured in benchmarks,
        // never in tests; the quadratic scan made this test take ~30 s, now milliseconds).
        for _ in 0..60_000 {
            add(&mut b, "base", GeometryRole::Visual, None).unwrap();
        }
        assert_eq!(b.geometries.last().unwrap().name, "base_visual60002");
        assert_eq!(b.build().unwrap().geometries().len(), 60_005);
    }
}
