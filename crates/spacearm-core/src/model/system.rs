//! The constant description of a spacecraft-manipulator system: a base and a tree of links.
//!
//! A [`Model`] is immutable once built and validated; all per-configuration quantities live in
//! [`crate::Data`] (Pinocchio's Model/Data split). Bodies are indexed `0` (the base) and
//! `1..=n_links` (the links, each listed after its parent). Degrees of freedom are numbered in
//! link order over the non-fixed joints, so `q` has `N = n_dof` entries.

use std::collections::HashSet;

use nalgebra::{Matrix3, Unit, UnitQuaternion, Vector3};

use crate::model::body::MassProperties;
use crate::error::{Result, SpacearmError};
use crate::math::rotations::unit_quaternion_from_xyzw;
use crate::model::joint::{Joint, JointLimits, JointType};

/// A link: a rigid body attached to its parent body through one joint.
#[derive(Debug, Clone, PartialEq)]
pub struct Link {
    /// Unique link name.
    pub name: String,
    /// Parent body index: 0 for the base, `k` for `links[k - 1]`.
    pub parent: usize,
    /// The joint connecting this link to its parent.
    pub joint: Joint,
    /// Position of the link CM relative to the joint, in the link frame (at `q = 0` for a
    /// prismatic joint), m.
    pub com_from_joint: Vector3<f64>,
    /// Mass and inertia about the CM, in the link frame.
    pub mass: MassProperties,
}

impl Link {
    /// Assemble a link from its description once the parent index, the normalized rotation and
    /// axis and the validated mass properties are known (shared by the builder and the model
    /// file reader). The joint name defaults to `<link>_joint`.
    pub(crate) fn from_spec(spec: LinkSpec, parent: usize, rotation: UnitQuaternion<f64>, axis: nalgebra::UnitVector3<f64>, mass: MassProperties) -> Link {
        let joint_name = spec.joint_name.clone().unwrap_or_else(|| format!("{}_joint", spec.name));
        Link {
            name: spec.name,
            parent,
            joint: Joint {
                name: joint_name,
                kind: spec.kind,
                origin_in_parent: Vector3::from(spec.origin_in_parent),
                rotation_in_parent: rotation,
                axis,
                limits: spec.limits,
            },
            com_from_joint: Vector3::from(spec.com_from_joint),
            mass,
        }
    }
}

/// A named point fixed to a body (an end effector, a grasp point, a sensor).
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    /// Unique point name.
    pub name: String,
    /// Body index the point is fixed to (0 = base).
    pub body: usize,
    /// Position in that body's frame (from its CM), m.
    pub offset: Vector3<f64>,
}

/// Spacecraft-manipulator model: base + tree of links + named points.
#[derive(Debug, Clone, PartialEq)]
pub struct Model {
    /// Model name.
    pub name: String,
    /// Name of the base body.
    pub base_name: String,
    /// Base mass properties (frame at the base CM, DESIGN.md §1).
    pub base: MassProperties,
    /// Links in topological order (each after its parent).
    pub links: Vec<Link>,
    /// Named points.
    pub points: Vec<Point>,
    /// Index into `points` of the end effector, if any.
    pub end_effector: Option<usize>,
    /// Initial (nominal) joint coordinates, length `n_dof`.
    pub initial_q: Vec<f64>,
    // Derived, kept in sync by `Model::new` (the fields above are validated together).
    dof_of_body: Vec<Option<usize>>,
    body_of_dof: Vec<usize>,
    total_mass: f64,
}

impl Model {
    /// Validate and assemble a model. `initial_q` defaults to zeros when `None`.
    pub fn new(
        name: impl Into<String>,
        base_name: impl Into<String>,
        base: MassProperties,
        links: Vec<Link>,
        points: Vec<Point>,
        end_effector: Option<usize>,
        initial_q: Option<Vec<f64>>,
    ) -> Result<Self> {
        let base_name = base_name.into();
        let mut names = HashSet::new();
        names.insert(base_name.clone());
        let mut joint_names = HashSet::new();
        let mut dof_of_body = vec![None];
        let mut body_of_dof = Vec::new();
        let mut total_mass = base.mass;
        for (k, link) in links.iter().enumerate() {
            let body = k + 1;
            let who = format!("link '{}'", link.name);
            if !names.insert(link.name.clone()) {
                return Err(SpacearmError::model(format!("body name '{}' is used twice", link.name)));
            }
            if !joint_names.insert(link.joint.name.clone()) {
                return Err(SpacearmError::model(format!("joint name '{}' is used twice", link.joint.name)));
            }
            if link.parent >= body {
                return Err(SpacearmError::model(format!(
                    "{who}: parent index {} must name the base (0) or a link listed before it (1..={}); \
                     links must be given parents first and the tree cannot contain cycles",
                    link.parent, k
                )));
            }
            let j = &link.joint;
            for (what, v) in [("joint origin", &j.origin_in_parent), ("com", &link.com_from_joint)] {
                if v.iter().any(|x| !x.is_finite()) {
                    return Err(SpacearmError::model(format!("{who}: {what} must be finite, got {v:?}")));
                }
            }
            if j.axis.iter().any(|x| !x.is_finite()) || j.rotation_in_parent.coords.iter().any(|x| !x.is_finite()) {
                return Err(SpacearmError::model(format!("{who}: joint '{}' axis and rotation must be finite", j.name)));
            }
            let lim = &j.limits;
            if lim.lower.is_nan() || lim.upper.is_nan() || lim.lower > lim.upper {
                return Err(SpacearmError::model(format!(
                    "joint '{}': position limits must satisfy lower <= upper, got [{}, {}]",
                    j.name, lim.lower, lim.upper
                )));
            }
            if !(lim.velocity >= 0.0) || !(lim.effort >= 0.0) {
                return Err(SpacearmError::model(format!(
                    "joint '{}': velocity and effort limits must be >= 0, got {} and {}",
                    j.name, lim.velocity, lim.effort
                )));
            }
            total_mass += link.mass.mass;
            if j.kind == JointType::Fixed {
                dof_of_body.push(None);
            } else {
                dof_of_body.push(Some(body_of_dof.len()));
                body_of_dof.push(body);
            }
        }
        let n_dof = body_of_dof.len();
        // A moving joint must carry something: with no mass and no inertia anywhere downstream
        // its acceleration is undetermined and H is singular for every configuration.
        let mut subtree_mass: Vec<f64> = std::iter::once(base.mass).chain(links.iter().map(|l| l.mass.mass)).collect();
        let mut subtree_inertia: Vec<f64> =
            std::iter::once(base.inertia.trace()).chain(links.iter().map(|l| l.mass.inertia.trace())).collect();
        for k in (0..links.len()).rev() {
            let body = k + 1;
            if links[k].joint.kind != JointType::Fixed && subtree_mass[body] == 0.0 && subtree_inertia[body] == 0.0 {
                return Err(SpacearmError::model(format!(
                    "joint '{}' moves link '{}', but that link and everything attached to it have zero mass and inertia: \
                     the joint's acceleration would be undetermined",
                    links[k].joint.name, links[k].name
                )));
            }
            let p = links[k].parent;
            subtree_mass[p] += subtree_mass[body];
            subtree_inertia[p] += subtree_inertia[body];
        }
        for p in &points {
            if !names.insert(p.name.clone()) {
                return Err(SpacearmError::model(format!("point name '{}' is already used by a body or point", p.name)));
            }
            if p.body > links.len() {
                return Err(SpacearmError::model(format!(
                    "point '{}': body index {} does not exist (the model has bodies 0..={})",
                    p.name,
                    p.body,
                    links.len()
                )));
            }
            if p.offset.iter().any(|x| !x.is_finite()) {
                return Err(SpacearmError::model(format!("point '{}': offset must be finite", p.name)));
            }
        }
        if let Some(e) = end_effector {
            if e >= points.len() {
                return Err(SpacearmError::model(format!("end effector index {e} does not name a point")));
            }
        }
        let initial_q = initial_q.unwrap_or_else(|| vec![0.0; n_dof]);
        crate::error::check_vector("initial joint coordinates", &initial_q, n_dof)
            .map_err(|e| SpacearmError::model(e.to_string()))?;
        Ok(Model {
            name: name.into(),
            base_name,
            base,
            links,
            points,
            end_effector,
            initial_q,
            dof_of_body,
            body_of_dof,
            total_mass,
        })
    }

    /// Number of joint degrees of freedom `N` (length of `q`).
    pub fn n_dof(&self) -> usize {
        self.body_of_dof.len()
    }

    /// Number of bodies including the base.
    pub fn n_bodies(&self) -> usize {
        self.links.len() + 1
    }

    /// Length of the configuration `x = [r0, quat0, q]`: `7 + N`.
    pub fn nx(&self) -> usize {
        7 + self.n_dof()
    }

    /// Length of the generalized velocity `u = [v0, ω0, q̇]`: `6 + N`.
    pub fn nu(&self) -> usize {
        6 + self.n_dof()
    }

    /// Total mass `M = m0 + Σ mᵢ`, kg.
    pub fn total_mass(&self) -> f64 {
        self.total_mass
    }

    /// Degree-of-freedom index of a body's joint (`None` for the base and fixed joints).
    #[inline]
    pub fn dof_of_body(&self, body: usize) -> Option<usize> {
        self.dof_of_body[body]
    }

    /// Body index moved by degree of freedom `dof`.
    #[inline]
    pub fn body_of_dof(&self, dof: usize) -> usize {
        self.body_of_dof[dof]
    }

    /// Parent body of `body` (`None` for the base).
    #[inline]
    pub fn parent(&self, body: usize) -> Option<usize> {
        if body == 0 {
            None
        } else {
            Some(self.links[body - 1].parent)
        }
    }

    /// Mass properties of body `body` (0 = base).
    #[inline]
    pub fn mass_properties(&self, body: usize) -> &MassProperties {
        if body == 0 {
            &self.base
        } else {
            &self.links[body - 1].mass
        }
    }

    /// Name of body `body` (0 = base).
    pub fn body_name(&self, body: usize) -> &str {
        if body == 0 {
            &self.base_name
        } else {
            &self.links[body - 1].name
        }
    }

    /// Index of the body called `name`.
    pub fn body_index(&self, name: &str) -> Result<usize> {
        if name == self.base_name {
            return Ok(0);
        }
        self.links
            .iter()
            .position(|l| l.name == name)
            .map(|k| k + 1)
            .ok_or_else(|| SpacearmError::NotFound(format!("no body named '{name}'; bodies are {:?}", self.body_names())))
    }

    /// Names of all bodies, base first.
    pub fn body_names(&self) -> Vec<String> {
        std::iter::once(self.base_name.clone()).chain(self.links.iter().map(|l| l.name.clone())).collect()
    }

    /// Index of the point called `name`.
    pub fn point_index(&self, name: &str) -> Result<usize> {
        self.points.iter().position(|p| p.name == name).ok_or_else(|| {
            let names: Vec<&str> = self.points.iter().map(|p| p.name.as_str()).collect();
            SpacearmError::NotFound(format!("no point named '{name}'; points are {names:?}"))
        })
    }

    /// Whether body `ancestor` lies on the path from the base to `body` (a body is its own
    /// ancestor).
    pub fn is_ancestor(&self, ancestor: usize, mut body: usize) -> bool {
        loop {
            if body == ancestor {
                return true;
            }
            match self.parent(body) {
                Some(p) => body = p,
                None => return false,
            }
        }
    }

    /// Degrees of freedom on the path from the base to `body`, nearest the base first.
    pub fn dofs_supporting(&self, mut body: usize) -> Vec<usize> {
        let mut out = Vec::new();
        while body != 0 {
            if let Some(d) = self.dof_of_body[body] {
                out.push(d);
            }
            body = self.links[body - 1].parent;
        }
        out.reverse();
        out
    }
}

/// Incremental builder for [`Model`], used by the Python API, the TOML reader and the DH
/// converter. Names are resolved and everything is validated by [`ModelBuilder::build`] and by
/// each `add_*` call where possible.
#[derive(Debug, Clone)]
pub struct ModelBuilder {
    name: String,
    base_name: String,
    base: MassProperties,
    links: Vec<Link>,
    points: Vec<Point>,
    end_effector: Option<String>,
    initial_q: Option<Vec<f64>>,
}

/// Everything that describes one link to [`ModelBuilder::add_link`].
#[derive(Debug, Clone)]
pub struct LinkSpec {
    pub name: String,
    pub parent: String,
    pub joint_name: Option<String>,
    pub kind: JointType,
    pub origin_in_parent: [f64; 3],
    /// Quaternion `[x, y, z, w]` of the child frame in the parent frame at `q = 0`.
    pub rotation_in_parent: [f64; 4],
    pub axis: [f64; 3],
    pub com_from_joint: [f64; 3],
    pub mass: f64,
    /// Inertia about the CM in the link frame, row-major 3×3.
    pub inertia: [[f64; 3]; 3],
    pub limits: JointLimits,
}

fn matrix3(rows: &[[f64; 3]; 3]) -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| rows[i][j])
}

impl ModelBuilder {
    /// Start a model with its base: mass (kg, > 0) and inertia about the base CM in base axes.
    pub fn new(name: &str, base_name: &str, base_mass: f64, base_inertia: [[f64; 3]; 3]) -> Result<Self> {
        let base = MassProperties::new(&format!("base '{base_name}'"), base_mass, matrix3(&base_inertia), true)?;
        Ok(ModelBuilder {
            name: name.to_string(),
            base_name: base_name.to_string(),
            base,
            links: Vec::new(),
            points: Vec::new(),
            end_effector: None,
            initial_q: None,
        })
    }

    fn body_index(&self, name: &str) -> Result<usize> {
        if name == self.base_name {
            return Ok(0);
        }
        self.links.iter().position(|l| l.name == name).map(|k| k + 1).ok_or_else(|| {
            SpacearmError::model(format!(
                "parent body '{name}' is not defined (yet); known bodies: {:?}; add parents before children",
                std::iter::once(self.base_name.as_str()).chain(self.links.iter().map(|l| l.name.as_str())).collect::<Vec<_>>()
            ))
        })
    }

    /// Add a link attached to an existing body.
    pub fn add_link(&mut self, spec: LinkSpec) -> Result<&mut Self> {
        let who = format!("link '{}'", spec.name);
        let parent = self.body_index(&spec.parent)?;
        let axis_v = Vector3::from(spec.axis);
        if axis_v.iter().any(|x| !x.is_finite()) {
            return Err(SpacearmError::model(format!("{who}: joint axis must be finite, got {:?}", spec.axis)));
        }
        let axis = if spec.kind == JointType::Fixed {
            Unit::new_normalize(if axis_v.norm() > 0.0 { axis_v } else { Vector3::z() })
        } else {
            // Scale by the largest component first so that the norm cannot overflow
            // (an axis like [1e154, 0, 1] must become [1, 0, 0], not NaN or zero).
            let largest = axis_v.amax();
            if !(largest > 1e-9) {
                return Err(SpacearmError::model(format!(
                    "{who}: joint axis must be a non-zero vector (it is normalized), got {:?}",
                    spec.axis
                )));
            }
            Unit::new_normalize(axis_v / largest)
        };
        let rotation = unit_quaternion_from_xyzw(&format!("{who}: joint rotation"), &spec.rotation_in_parent)
            .map_err(|e| SpacearmError::model(e.to_string()))?;
        let mass = MassProperties::new(&who, spec.mass, matrix3(&spec.inertia), false)?;
        self.links.push(Link::from_spec(spec, parent, rotation, axis, mass));
        Ok(self)
    }

    /// Add a named point fixed to `body` at `offset` (body frame, from its CM).
    pub fn add_point(&mut self, name: &str, body: &str, offset: [f64; 3]) -> Result<&mut Self> {
        let b = self.body_index(body)?;
        self.points.push(Point { name: name.to_string(), body: b, offset: Vector3::from(offset) });
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

    /// Validate everything and produce the immutable model.
    pub fn build(&self) -> Result<Model> {
        let ee = match &self.end_effector {
            None => None,
            Some(n) => Some(self.points.iter().position(|p| &p.name == n).ok_or_else(|| {
                SpacearmError::model(format!("end effector '{n}' is not a defined point"))
            })?),
        };
        Model::new(
            self.name.clone(),
            self.base_name.clone(),
            self.base.clone(),
            self.links.clone(),
            self.points.clone(),
            ee,
            self.initial_q.clone(),
        )
    }
}
