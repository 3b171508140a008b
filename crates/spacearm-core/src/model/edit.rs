//! Editing a validated [`Model`]: attach a body, attach a whole model, remove a subtree, each
//! giving a new validated model (issue 32). A [`Model`] never changes; an edit is a
//! [`ModelBuilder`] seeded from it ([`ModelBuilder::from_model`]), changed, and built — the
//! builder's rules applied once, to what the edit adds, and the whole-model rules of
//! [`ModelBuilder::build`] to the result.
//!
//! The seeded builder holds the model's validated parts as they are (no re-normalized axis,
//! no re-symmetrized inertia), so every quantity of the part an edit leaves alone — mass
//! properties, joints, limits, passive dynamics, points, geometry, initial `q` — is
//! bit-identical in the result, and so are the algorithms' numbers that depend only on it.
//!
//! Attaching a model is Pinocchio's `appendModel` and MuJoCo's `mjs_attach` for this crate's
//! models: the attached model's base becomes a link of the host on a fixed joint at a given
//! pose in the parent body's frame (its CM frame, docs/conventions.md), its links follow in
//! their order with their joints, limits, passive dynamics and initial coordinates, and its
//! points and geometries ride along; every name it brings is prefixed, so that two copies of
//! one model can be attached. A rigid grasp is this edit (the target fixed to the gripper).

use std::collections::{HashMap, HashSet};

use crate::error::{ModelError, ModelField, ModelItem};
use crate::model::body::{MassProperties, TriangleInequality};
use crate::model::builder::{LinkSpec, ModelBuilder};
use crate::model::geometry::Geometry;
use crate::model::joint::{Joint, JointDynamics, JointLimits, JointType};
use crate::model::system::{Link, Model, Point};
use crate::model::validate;

/// Where an attached body or model goes: its parent body (by name) and the pose of the attached
/// body's frame (origin at its CM) in the parent's frame at the attachment.
#[derive(Debug, Clone, PartialEq)]
pub struct Mount {
    /// The parent body's name (the base or a link of the host model).
    pub parent: String,
    /// The attached body's CM in the parent's frame (from the parent's CM), m.
    pub origin_in_parent: [f64; 3],
    /// Quaternion `[x, y, z, w]` of the attached body's axes in the parent's frame.
    pub rotation_in_parent: [f64; 4],
}

impl Mount {
    /// A mount on `parent` at `origin_in_parent`, axes at `rotation_in_parent` (`[x, y, z, w]`).
    pub fn new(parent: &str, origin_in_parent: [f64; 3], rotation_in_parent: [f64; 4]) -> Self {
        Mount { parent: parent.to_string(), origin_in_parent, rotation_in_parent }
    }
}

impl LinkSpec {
    /// A rigid payload: a body of `mass` (kg) and `inertia` (about its CM, in its own axes,
    /// row-major kg·m²) on a fixed joint `<name>_joint` at `mount`, its CM at the mount's
    /// origin. The joint space is unchanged; the payload's mass properties merge with the
    /// parent's in every algorithm.
    pub fn payload(name: &str, mount: &Mount, mass: f64, inertia: [[f64; 3]; 3]) -> Self {
        LinkSpec {
            name: name.to_string(),
            parent: mount.parent.clone(),
            joint_name: None,
            kind: JointType::Fixed,
            origin_in_parent: mount.origin_in_parent,
            rotation_in_parent: mount.rotation_in_parent,
            axis: [0.0, 0.0, 1.0],
            com_from_joint: [0.0; 3],
            mass,
            inertia,
            limits: JointLimits::unlimited(),
        }
    }
}

/// Error of an edit that names a body the model does not have, or the base where a link is
/// needed.
fn not_a_link(what: &str, body: &str, names: Vec<&str>) -> ModelError {
    ModelError::new(ModelItem::Model, ModelField::Body, format!("{what}: '{body}' is not a link of the model; links: {names:?}"))
}

impl ModelBuilder {
    /// A builder holding `model` exactly: its base, links (joints, limits, passive dynamics),
    /// points, geometries, end effector, triangle-inequality rule and warnings, and its initial
    /// `q` kept per moving link (so links added or removed afterwards leave the others' initial
    /// coordinates; a new joint starts at its spring rest, 0 unless set). Building it unchanged
    /// gives a model equal to `model`, bit for bit.
    pub fn from_model(model: &Model) -> Self {
        let links = model.links().to_vec();
        let body_by_name: HashMap<String, usize> = model.body_names().into_iter().enumerate().map(|(k, n)| (n, k)).collect();
        let mut geometry_counts = HashMap::new();
        for g in model.geometries() {
            *geometry_counts.entry((g.body, g.role)).or_insert(0) += 1;
        }
        let initial_q_by_link = (0..model.n_dof()).map(|d| (links[model.body_of_dof(d) - 1].name.clone(), model.initial_q()[d])).collect();
        ModelBuilder {
            name: model.name().to_string(),
            base_name: model.base_name().to_string(),
            base: model.base().clone(),
            joint_names: links.iter().map(|l| l.joint.name.clone()).collect(),
            links,
            point_names: model.points().iter().map(|p| p.name.clone()).collect(),
            points: model.points().to_vec(),
            end_effector: model.end_effector().map(|k| model.points()[k].name.clone()),
            initial_q: None,
            body_by_name,
            triangle_inequality: model.triangle_inequality(),
            inertia_warnings: model.inertia_warnings().to_vec(),
            geometry_names: model.geometries().iter().map(|g| g.name.clone()).collect(),
            geometries: model.geometries().to_vec(),
            geometry_counts,
            initial_q_by_link,
        }
    }

    /// Judge every body's inertia again under `rule` (a seeded builder keeps its model's rule):
    /// the same check and message as [`ModelBuilder::add_link`]'s, the warnings of
    /// [`TriangleInequality::Warn`] kept anew. Nothing changes when an error is returned.
    pub fn set_triangle_inequality(&mut self, rule: TriangleInequality) -> Result<&mut Self, ModelError> {
        let who = format!("base '{}'", self.base_name);
        let (_, base) = MassProperties::checked(ModelItem::Base, &who, self.base.mass, self.base.inertia, true, rule)?;
        let mut warnings: Vec<String> = base.into_iter().collect();
        for (k, link) in self.links.iter().enumerate() {
            let who = format!("link '{}'", link.name);
            warnings.extend(MassProperties::checked(ModelItem::Link(k), &who, link.mass.mass, link.mass.inertia, false, rule)?.1);
        }
        self.triangle_inequality = rule;
        self.inertia_warnings = warnings;
        Ok(self)
    }

    /// Drop every geometry (the model's shapes, docs/geometry.md); bodies and points stay.
    pub fn clear_geometries(&mut self) -> &mut Self {
        self.geometries.clear();
        self.geometry_names.clear();
        self.geometry_counts.clear();
        self
    }

    /// Rename the model being built (an edited model is often named after its parts).
    pub fn set_name(&mut self, name: &str) -> Result<&mut Self, ModelError> {
        validate::non_empty_name(ModelItem::Model, ModelField::Name, "model name", name)?;
        self.name = name.to_string();
        Ok(self)
    }

    /// The initial `q` of a seeded builder (see [`ModelBuilder::from_model`]): each moving
    /// link's kept coordinate, else its spring rest. `None` when nothing was seeded.
    pub(super) fn seeded_initial_q(&self) -> Option<Vec<f64>> {
        if self.initial_q_by_link.is_empty() {
            return None;
        }
        let moving = self.links.iter().filter(|l| l.joint.kind.dof() == 1);
        Some(moving.map(|l| self.initial_q_by_link.get(&l.name).copied().unwrap_or(l.joint.dynamics.rest)).collect())
    }

    /// An explicit initial `q` (set by [`ModelBuilder::set_initial_q`]) kept per moving link
    /// instead, before an edit changes the joints; left as it is when its length does not
    /// match (the build then says so).
    fn initial_q_per_link(&mut self) {
        let moving: Vec<&Link> = self.links.iter().filter(|l| l.joint.kind.dof() == 1).collect();
        if let Some(q) = &self.initial_q {
            if q.len() == moving.len() {
                self.initial_q_by_link = moving.iter().zip(q).map(|(l, &v)| (l.name.clone(), v)).collect();
                self.initial_q = None;
            }
        }
    }

    /// Attach `other` to this model: its base becomes the link `base_link` (default
    /// `<prefix><other's base name>`) on the fixed joint `<base_link>_joint` at `mount`; its
    /// links follow (parents remapped), their joints, limits, passive dynamics and initial
    /// coordinates carried over; its points and geometries ride on the same bodies. Every other
    /// name it brings (links, joints, points, geometries) gets `prefix`. Its end effector is
    /// not carried (this model keeps its own). Each attached body's inertia is judged by this
    /// builder's triangle-inequality rule. Nothing changes when an error is returned.
    pub fn attach_model(&mut self, other: &Model, mount: &Mount, prefix: &str, base_link: Option<&str>) -> Result<&mut Self, ModelError> {
        let mut next = self.clone();
        next.initial_q_per_link();
        let first = next.links.len();
        let base_link = base_link.map_or_else(|| format!("{prefix}{}", other.base_name()), str::to_string);
        // The base: a fixed link checked by the builder's own rules, as any payload.
        let mut spec = LinkSpec::payload(&base_link, mount, other.base().mass, [[0.0; 3]; 3]);
        spec.inertia = std::array::from_fn(|i| std::array::from_fn(|j| other.base().inertia[(i, j)]));
        next.add_link(spec)?;
        // Its links, parts already validated by `other`'s builder: their names are new here
        // and their mass properties meet this builder's rule (the checks keep the values: a
        // symmetric inertia comes back bit for bit).
        let body_of = |b: usize| if b == 0 { first + 1 } else { first + 1 + b };
        for link in other.links() {
            let item = ModelItem::Link(next.links.len());
            let name = format!("{prefix}{}", link.name);
            let joint_name = format!("{prefix}{}", link.joint.name);
            validate::non_empty_name(item, ModelField::Name, "link name", &name)?;
            let taken = validate::NamesTaken {
                by_body: next.body_by_name.contains_key(&name),
                by_point: next.point_names.contains(&name),
                joint_by_joint: next.joint_names.contains(&joint_name),
            };
            validate::new_link_names(item, &name, &joint_name, taken)?;
            let who = format!("link '{name}'");
            let (mass, warning) = MassProperties::checked(item, &who, link.mass.mass, link.mass.inertia, false, next.triangle_inequality)?;
            next.inertia_warnings.extend(warning);
            next.body_by_name.insert(name.clone(), next.links.len() + 1);
            next.joint_names.insert(joint_name.clone());
            next.links.push(Link { name, parent: body_of(link.parent), joint: Joint { name: joint_name, ..link.joint.clone() }, mass, ..link.clone() });
        }
        for d in 0..other.n_dof() {
            let name = &next.links[first + other.body_of_dof(d)].name;
            next.initial_q_by_link.insert(name.clone(), other.initial_q()[d]);
        }
        for p in other.points() {
            let item = ModelItem::Point(next.points.len());
            let name = format!("{prefix}{}", p.name);
            validate::non_empty_name(item, ModelField::Name, "point name", &name)?;
            validate::new_point_name(item, &name, next.body_by_name.contains_key(&name) || next.point_names.contains(&name))?;
            next.point_names.insert(name.clone());
            next.points.push(Point { name, body: body_of(p.body), offset: p.offset });
        }
        for g in other.geometries() {
            let name = format!("{prefix}{}", g.name);
            if next.geometry_names.contains(&name) {
                return Err(ModelError::new(ModelItem::Geometry(next.geometries.len()), ModelField::Name, format!("geometry name '{name}' is used twice")));
            }
            let body = body_of(g.body);
            next.geometry_names.insert(name.clone());
            *next.geometry_counts.entry((body, g.role)).or_insert(0) += 1;
            next.geometries.push(Geometry { name, body, ..g.clone() });
        }
        *self = next;
        Ok(self)
    }

    /// Remove the link called `body`, every link below it, and the points and geometries on
    /// them; the end effector too when it is one of those points (set another with
    /// [`ModelBuilder::set_end_effector`]). The other links keep their order, parts and initial
    /// coordinates. The base cannot be removed. Nothing changes when an error is returned.
    pub fn remove_subtree(&mut self, body: &str) -> Result<&mut Self, ModelError> {
        let root = match self.body_index_of(body) {
            Some(b) if b > 0 => b,
            Some(_) => {
                return Err(ModelError::new(
                    ModelItem::Model,
                    ModelField::Body,
                    format!("remove_subtree: '{body}' is the base, which cannot be removed (start a new model instead)"),
                ))
            }
            None => return Err(not_a_link("remove_subtree", body, self.links.iter().map(|l| l.name.as_str()).collect())),
        };
        self.initial_q_per_link();
        // Parents come before their children: one pass marks the subtree.
        let mut removed = vec![false; self.links.len() + 1];
        for (k, link) in self.links.iter().enumerate() {
            removed[k + 1] = k + 1 == root || removed[link.parent];
        }
        let mut new_index = vec![0usize; removed.len()];
        let mut kept = 0;
        for b in 1..removed.len() {
            if !removed[b] {
                kept += 1;
                new_index[b] = kept;
            }
        }
        let links = std::mem::take(&mut self.links);
        let mut removed_names = HashSet::new();
        for (k, link) in links.into_iter().enumerate() {
            if removed[k + 1] {
                removed_names.insert(link.name);
            } else {
                self.links.push(Link { parent: new_index[link.parent], ..link });
            }
        }
        let end_effector = self.end_effector.take();
        let points = std::mem::take(&mut self.points);
        self.points = points.into_iter().filter(|p| !removed[p.body]).map(|p| Point { body: new_index[p.body], ..p }).collect();
        self.end_effector = end_effector.filter(|n| self.points.iter().any(|p| &p.name == n));
        let geometries = std::mem::take(&mut self.geometries);
        self.geometries = geometries.into_iter().filter(|g| !removed[g.body]).map(|g| Geometry { body: new_index[g.body], ..g }).collect();
        // The look-ups, again from what is left.
        self.body_by_name = std::iter::once((self.base_name.clone(), 0)).chain(self.links.iter().enumerate().map(|(k, l)| (l.name.clone(), k + 1))).collect();
        self.joint_names = self.links.iter().map(|l| l.joint.name.clone()).collect();
        self.point_names = self.points.iter().map(|p| p.name.clone()).collect();
        self.geometry_names = self.geometries.iter().map(|g| g.name.clone()).collect();
        self.geometry_counts.clear();
        for g in &self.geometries {
            *self.geometry_counts.entry((g.body, g.role)).or_insert(0) += 1;
        }
        self.initial_q_by_link.retain(|name, _| !removed_names.contains(name));
        self.inertia_warnings.retain(|w| !removed_names.iter().any(|n| w.starts_with(&format!("link '{n}':"))));
        Ok(self)
    }

    fn body_index_of(&self, name: &str) -> Option<usize> {
        self.body_by_name.get(name).copied()
    }
}

impl Model {
    /// A [`ModelBuilder`] holding this model exactly ([`ModelBuilder::from_model`]), to edit.
    pub fn to_builder(&self) -> ModelBuilder {
        ModelBuilder::from_model(self)
    }

    /// This model with the link `spec` added (a payload: [`LinkSpec::payload`]; or any joint),
    /// its joint's passive dynamics `dynamics` if given. The link is checked by the builder's
    /// rules, the result by the whole-model rules.
    pub fn attach_body(&self, spec: LinkSpec, dynamics: Option<JointDynamics>) -> Result<Model, ModelError> {
        let mut b = self.to_builder();
        let name = spec.name.clone();
        b.add_link(spec)?;
        if let Some(d) = dynamics {
            b.set_joint_dynamics(&name, d)?;
        }
        b.build()
    }

    /// This model with `other` attached at `mount` ([`ModelBuilder::attach_model`]).
    pub fn attach_model(&self, other: &Model, mount: &Mount, prefix: &str, base_link: Option<&str>) -> Result<Model, ModelError> {
        self.to_builder().attach_model(other, mount, prefix, base_link)?.build()
    }

    /// This model without the link `body` and its subtree ([`ModelBuilder::remove_subtree`]).
    pub fn remove_subtree(&self, body: &str) -> Result<Model, ModelError> {
        self.to_builder().remove_subtree(body)?.build()
    }

}
