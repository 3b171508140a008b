//! The constant description of a spacecraft-manipulator system: a base and a tree of links.
//!
//! A [`Model`] is immutable once built and validated: its fields are private, it is made only
//! by [`crate::model::ModelBuilder`] (which applies every rule of [`crate::model::validate`]),
//! and it is read through accessors, so its derived data (degree-of-freedom numbering, total
//! mass) always agree with its links. All per-configuration quantities live in
//! [`crate::Data`] (Pinocchio's Model/Data split). Bodies are indexed `0` (the base) and
//! `1..=n_links` (the links, each listed after its parent). Degrees of freedom are numbered in
//! link order over the non-fixed joints, so `q` has `N = n_dof` entries.


use crate::error::{ModelError, Result, SpacearmError};
use crate::model::body::{MassProperties, TriangleInequality};
use crate::model::geometry::Geometry;
use crate::model::joint::{JointDynamics, JointType};
/// At their former path too (`model::system::Link`, ...).
pub use crate::model::link::{Link, Point};
use crate::model::structure::check_structure;

/// Spacecraft-manipulator model: base + tree of links + named points. Made by
/// [`crate::model::ModelBuilder`]; read through its accessors.
#[derive(Debug, Clone, PartialEq)]
pub struct Model {
    name: String,
    base_name: String,
    /// Base mass properties (frame at the base CM, docs/conventions.md).
    base: MassProperties,
    /// Links in topological order (each after its parent).
    links: Vec<Link>,
    points: Vec<Point>,
    /// Index into `points` of the end effector, if any.
    end_effector: Option<usize>,
    /// Initial (nominal) joint coordinates, length `n_dof`.
    initial_q: Vec<f64>,
    // Derived from the fields above by `Model::new`.
    dof_of_body: Vec<Option<usize>>,
    body_of_dof: Vec<usize>,
    /// Degrees of freedom on the path from the base to each body (see [`Model::path_dofs`]).
    path_dofs: Vec<usize>,
    total_mass: f64,
    /// Each degree of freedom's joint dynamics (actuation, spring–damper), dof order.
    dof_dynamics: Vec<JointDynamics>,
    /// Whether some joint carries a spring or damper.
    has_passive_forces: bool,
    /// Whether inertias breaking the triangle inequality were accepted, and the warnings they
    /// gave (set by the builder; see [`TriangleInequality`]).
    triangle_inequality: TriangleInequality,
    inertia_warnings: Vec<String>,
    /// Visual and collision shapes fixed to the bodies (model/geometry.rs); no mass.
    geometries: Vec<Geometry>,
}

impl Model {
    /// Assemble a model from validated parts, after the whole-model rules of
    /// [`check_structure`]. `initial_q` defaults to zeros when `None`. Only the builder (and
    /// the perturbed copies of [`crate::control::mismatch`], whose parts come from a valid
    /// model) call this.
    pub(crate) fn new(
        name: String,
        base_name: String,
        base: MassProperties,
        links: Vec<Link>,
        points: Vec<Point>,
        end_effector: Option<usize>,
        initial_q: Option<Vec<f64>>,
    ) -> std::result::Result<Self, ModelError> {
        let mut dof_of_body = vec![None];
        let mut body_of_dof = Vec::new();
        for (k, link) in links.iter().enumerate() {
            if link.joint.kind == JointType::Fixed {
                dof_of_body.push(None);
            } else {
                dof_of_body.push(Some(body_of_dof.len()));
                body_of_dof.push(k + 1);
            }
        }
        let initial_q = initial_q.unwrap_or_else(|| vec![0.0; body_of_dof.len()]);
        check_structure(&base, &links, &points, end_effector, &initial_q)?;
        // Parents come before their children (checked above), so one pass suffices.
        let mut path_dofs = vec![0usize; links.len() + 1];
        for (k, link) in links.iter().enumerate() {
            path_dofs[k + 1] = path_dofs[link.parent] + usize::from(dof_of_body[k + 1].is_some());
        }
        let total_mass = links.iter().fold(base.mass, |m, l| m + l.mass.mass);
        let dof_dynamics: Vec<JointDynamics> = body_of_dof.iter().map(|&b| links[b - 1].joint.dynamics).collect();
        let has_passive_forces = dof_dynamics.iter().any(JointDynamics::has_passive_force);
        Ok(Model {
            name,
            base_name,
            base,
            links,
            points,
            end_effector,
            initial_q,
            dof_of_body,
            body_of_dof,
            path_dofs,
            total_mass,
            dof_dynamics,
            has_passive_forces,
            triangle_inequality: TriangleInequality::Enforce,
            inertia_warnings: Vec::new(),
            geometries: Vec::new(),
        })
    }

    /// The model with its geometry (checked by the builder: each on a body of this model).
    pub(crate) fn with_geometries(mut self, geometries: Vec<Geometry>) -> Self {
        self.geometries = geometries;
        self
    }

    /// Visual and collision geometry, in the order given to the builder; each placed in its
    /// body's frame (origin at the CM). Carries no mass.
    pub fn geometries(&self) -> &[Geometry] {
        &self.geometries
    }

    /// The model with the triangle-inequality rule it was built under and the warnings of the
    /// bodies that break it (see [`TriangleInequality`]).
    pub(crate) fn with_triangle_inequality(mut self, rule: TriangleInequality, warnings: Vec<String>) -> Self {
        self.triangle_inequality = rule;
        self.inertia_warnings = warnings;
        self
    }

    /// Whether this model was built accepting inertias that break the triangle inequality
    /// (copies of it, e.g. perturbed ones, are built the same way).
    pub fn triangle_inequality(&self) -> TriangleInequality {
        self.triangle_inequality
    }

    /// One message per body whose inertia breaks the triangle inequality (empty unless the
    /// model was built with [`TriangleInequality::Warn`]).
    pub fn inertia_warnings(&self) -> &[String] {
        &self.inertia_warnings
    }

    /// Model name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Name of the base body.
    pub fn base_name(&self) -> &str {
        &self.base_name
    }

    /// Base mass properties (frame at the base CM).
    pub fn base(&self) -> &MassProperties {
        &self.base
    }

    /// Links in topological order (each after its parent); link `k` is body `k + 1`.
    pub fn links(&self) -> &[Link] {
        &self.links
    }

    /// Named points.
    pub fn points(&self) -> &[Point] {
        &self.points
    }

    /// Index into [`Model::points`] of the end effector, if any.
    pub fn end_effector(&self) -> Option<usize> {
        self.end_effector
    }

    /// Initial (nominal) joint coordinates, length `N`.
    pub fn initial_q(&self) -> &[f64] {
        &self.initial_q
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

    /// Each degree of freedom's joint dynamics — actuation and spring–damper — in dof order
    /// (docs/flexibility.md).
    #[inline]
    pub fn dof_dynamics(&self) -> &[JointDynamics] {
        &self.dof_dynamics
    }

    /// Whether some joint carries a spring or a damper (a passive force in the dynamics).
    #[inline]
    pub fn has_passive_forces(&self) -> bool {
        self.has_passive_forces
    }

    /// Whether each degree of freedom is driven by a motor (dof order).
    pub fn actuated_dofs(&self) -> Vec<bool> {
        self.dof_dynamics.iter().map(|d| d.actuated).collect()
    }

    /// Degree-of-freedom index of a body's joint (`None` for the base and fixed joints).
    #[inline]
    pub fn dof_of_body(&self, body: usize) -> Option<usize> {
        self.dof_of_body[body]
    }

    /// The number of degrees of freedom on the path from the base to `body`, its own joint
    /// included: the non-zero columns of its Jacobians `J_Ti`, `J_Ri` (paper eqs. 20–21).
    #[inline]
    pub fn path_dofs(&self, body: usize) -> usize {
        self.path_dofs[body]
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
