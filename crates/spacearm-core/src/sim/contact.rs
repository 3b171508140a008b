//! Contact in a run (docs/contact.md, "Contact dynamics"): the run description's `contact`
//! ([`ContactSpec`], serde, checked by [`ContactSpec::validate`] — the one place), resolved on a
//! model into the plant's [`PlantContact`], which at every evaluation of the dynamics finds the
//! contacts of the state (collision/detect.rs), turns each into forces by the compliant law
//! (collision/compliant.rs) and hands the pairs of equal and opposite wrenches to the forward
//! dynamics with the other external wrenches ([`crate::sim::plant`]).

use serde::{Deserialize, Serialize};

use crate::algorithms::kinematics::forward_kinematics;
use crate::algorithms::rnea::velocity_pass;
use crate::algorithms::wrench::ExternalWrench;
use nalgebra::Vector3;

use crate::collision::compliant::{point_velocity, ContactForce};
use crate::collision::detect::{contacts_of_placed, place_on_bodies, place_on_free_body};
use crate::collision::{CollisionShapes, Contact, ContactLaw, ImpactSolver, ImpactSpec, NormalLaw, PairFilter};
use crate::error::{Result, SpacearmError};
use crate::model::data::Data;
use crate::model::Model;
use crate::sim::free_target::FreeTarget;
use crate::sim::rigid_contact::{rigid_jump, RigidContact, RIGID_STABILIZATION};

/// The normal law's name in a description: `"kelvin_voigt"` or `"hunt_crossley"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum LawName {
    /// `f_n = k δ^p + d δ̇`.
    #[default]
    KelvinVoigt,
    /// `f_n = k δ^p (1 + c δ̇)`.
    HuntCrossley,
}

/// Which contact model a run uses: `"compliant"` (the default) or `"rigid"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum ContactKind {
    /// The compliant law (collision/compliant.rs), integrated with the motion.
    #[default]
    Compliant,
    /// Rigid frictional contact solved per step on the Delassus operator (the velocity-level
    /// time stepping of [`crate::sim::rigid_contact`]; RK4 runs only).
    Rigid,
}

/// Contact in a run, as data: which pairs touch and the compliant law's parameters, or the
/// rigid contact's (`kind = "rigid"`: `restitution`, `solver`, `stabilization`, `tolerance`,
/// `max_iterations`, refused with the compliant law, whose `stiffness` and `damping` the rigid
/// contact refuses in turn).
///
/// ```toml
/// [contact]
/// kind = "compliant"           # or "rigid" (sim/rigid_contact.rs)
/// pairs = [["base", "hand"]]   # body or collision-geometry names; absent: all but parent–child
/// law = "kelvin_voigt"         # or "hunt_crossley"
/// stiffness = 1e5              # k, N/m^p
/// exponent = 1.0               # p
/// damping = 20.0               # d (N·s/m) or c (s/m)
/// friction = 0.3               # μ
/// slip_velocity = 1e-3         # ε, m/s
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    /// The pairs that may touch, each two names of bodies (every collision shape of the body) or
    /// of collision geometries; absent: every pair of bodies but a body and its parent.
    #[serde(default)]
    pub pairs: Option<Vec<[String; 2]>>,
    /// The contact model (default compliant).
    #[serde(default)]
    pub kind: ContactKind,
    /// The normal law.
    #[serde(default)]
    pub law: LawName,
    /// `k`, N/m^p (> 0; required by the compliant law).
    #[serde(default)]
    pub stiffness: Option<f64>,
    /// `p` (≥ 1; default 1).
    #[serde(default = "one")]
    pub exponent: f64,
    /// `d` (Kelvin–Voigt, N·s/m) or `c` (Hunt–Crossley, s/m), ≥ 0 (default 0).
    #[serde(default)]
    pub damping: f64,
    /// Coulomb's `μ` (≥ 0; default 0).
    #[serde(default)]
    pub friction: f64,
    /// The friction's regularization velocity `ε`, m/s (> 0; default 1e-3).
    #[serde(default = "default_slip")]
    pub slip_velocity: f64,
    /// The detection margin, m (≥ 0; default 0): shapes this far apart are found (and counted
    /// by nothing; a force needs interpenetration). Rigid contact: the points this far apart
    /// enter each step's cone problem, allowed to close their gap in the step and no more.
    #[serde(default)]
    pub margin: f64,
    /// Rigid: Newton's restitution `e` in [0, 1] (default 0).
    #[serde(default)]
    pub restitution: Option<f64>,
    /// Rigid: the cone solver, `"admm"` (default) or `"pgs"`.
    #[serde(default)]
    pub solver: Option<ImpactSolver>,
    /// Rigid: the position-error stabilization `β` in [0, 1] (default 0.2): a point in
    /// interpenetration by `δ` is pushed out at `β δ / h` (a Baumgarte velocity bias).
    #[serde(default)]
    pub stabilization: Option<f64>,
    /// Rigid: the solver's tolerance on the cone problem's residual, m/s (> 0; default 1e-10).
    #[serde(default)]
    pub tolerance: Option<f64>,
    /// Rigid: the solver's iteration limit per step (≥ 1; default 1000).
    #[serde(default)]
    pub max_iterations: Option<usize>,
}


fn one() -> f64 {
    1.0
}

fn default_slip() -> f64 {
    1e-3
}

impl ContactSpec {
    /// Check every value that needs no model.
    pub fn validate(&self) -> Result<()> {
        let check = |name: &str, v: f64, ok: bool, expected: &str| {
            if v.is_finite() && ok {
                Ok(())
            } else {
                Err(SpacearmError::argument(format!("contact {name} must be finite and {expected}, got {v}")))
            }
        };
        check("margin", self.margin, self.margin >= 0.0, ">= 0 m")?;
        check("friction", self.friction, self.friction >= 0.0, ">= 0")?;
        if self.pairs.as_ref().is_some_and(|p| p.is_empty()) {
            return Err(SpacearmError::argument("contact pairs is empty: give at least one pair of body or geometry names, or leave it out for every pair"));
        }
        if self.kind == ContactKind::Rigid {
            if self.stiffness.is_some() || self.damping != 0.0 {
                return Err(SpacearmError::argument(
                    "contact kind \"rigid\" has no stiffness or damping (they are the compliant law's): leave them out, or use kind=\"compliant\"",
                ));
            }
            self.impact_spec().validate()?;
            let beta = self.stabilization.unwrap_or(RIGID_STABILIZATION);
            return check("stabilization", beta, (0.0..=1.0).contains(&beta), "in [0, 1]");
        }
        if let Some(name) = [
            ("restitution", self.restitution.is_some()),
            ("solver", self.solver.is_some()),
            ("stabilization", self.stabilization.is_some()),
            ("tolerance", self.tolerance.is_some()),
            ("max_iterations", self.max_iterations.is_some()),
        ]
        .iter()
        .find_map(|(n, given)| given.then_some(n))
        {
            return Err(SpacearmError::argument(format!(
                "contact {name} is a setting of the rigid contact (kind=\"rigid\"), not of the compliant law: leave it out, or give kind=\"rigid\""
            )));
        }
        let Some(stiffness) = self.stiffness else {
            return Err(SpacearmError::argument("contact stiffness is required by the compliant law (k, N/m^p, > 0)"));
        };
        check("stiffness", stiffness, stiffness > 0.0, "> 0 N/m^p")?;
        check("exponent", self.exponent, self.exponent >= 1.0, ">= 1")?;
        check("damping", self.damping, self.damping >= 0.0, ">= 0")?;
        check("slip_velocity", self.slip_velocity, self.slip_velocity > 0.0, "> 0 m/s")?;
        Ok(())
    }

    /// The rigid contact's solver settings (restitution, solver, tolerance, iterations; the
    /// proximal weight its default) as one impact's (collision/impact.rs).
    pub fn impact_spec(&self) -> ImpactSpec {
        ImpactSpec {
            solver: self.solver.unwrap_or_default(),
            restitution: self.restitution.unwrap_or(0.0),
            tolerance: self.tolerance.unwrap_or(ImpactSpec::default().tolerance),
            max_iterations: self.max_iterations.unwrap_or(ImpactSpec::default().max_iterations),
            ..ImpactSpec::default()
        }
    }

    /// The law's parameters.
    pub fn law(&self) -> ContactLaw {
        ContactLaw {
            law: match self.law {
                LawName::KelvinVoigt => NormalLaw::KelvinVoigt,
                LawName::HuntCrossley => NormalLaw::HuntCrossley,
            },
            stiffness: self.stiffness.unwrap_or(f64::NAN), // validated: present
            exponent: self.exponent,
            damping: self.damping,
            friction: self.friction,
            slip_velocity: self.slip_velocity,
        }
    }
}

/// The refusal of rigid contact with a free target, in a plain run and in a run with
/// topology events alike (docs/contact.md, "What is not handled").
pub(crate) fn rigid_with_target_refused() -> SpacearmError {
    SpacearmError::argument(
        "rigid contact (kind=\"rigid\") with a free target is not implemented yet: use the compliant law with a target, or \
         rigid contact between the robot's own bodies (docs/contact.md, \"What is not handled\")",
    )
}

/// The contact of a plant: the model's collision shapes, the admitted pairs, the law, a free
/// target's body if the run has one ([`crate::sim::free_target`]), and the summary of the last
/// evaluation.
pub(crate) struct PlantContact {
    shapes: CollisionShapes,
    pairs: PairFilter,
    law: ContactLaw,
    margin: f64,
    /// Rigid contact (`kind = "rigid"`): its settings and state ([`crate::sim::rigid_contact`]);
    /// `None`: the compliant law.
    pub(crate) rigid: Option<RigidContact>,
    /// The free target, its 13-state integrated with the robot's ([`crate::sim::free_target`]).
    pub(crate) target: Option<FreeTarget>,
    /// Pairs of geometries that act as touching while their distance is at most
    /// [`ONSET_SLACK`] (the step that starts at a located onset: [`crate::sim::contact_onset`]).
    pub(crate) forced: Vec<(usize, usize)>,
    /// The last evaluation: contacts touching or interpenetrating, their total normal force (N)
    /// and the power of the contact forces on the system (W).
    pub(crate) count: usize,
    pub(crate) normal_force: f64,
    pub(crate) power: f64,
    /// The last evaluation's contacts that exert a force, each with its point, normal and force
    /// (the record `contact_forces`: [`crate::sim::record`]).
    pub(crate) active: Vec<ContactForce>,
}

impl PlantContact {
    /// `spec` (validated) resolved on `model` and the free `target` if any: names to geometry
    /// pairs (a target's geometries numbered after the model's), shapes built (a mesh is refused
    /// by [`CollisionShapes::from_model`]).
    pub(crate) fn new(model: &Model, spec: &ContactSpec, target: Option<FreeTarget>) -> Result<Self> {
        spec.validate()?;
        let shapes = CollisionShapes::from_model(model)?;
        let needed = if target.is_some() { 1 } else { 2 };
        if shapes.shapes.len() < needed {
            return Err(SpacearmError::argument(format!(
                "contact needs collision shapes on at least {}, but '{}' has {} collision geometr{} (RobotBuilder.add_geometry(..., role=\"collision\"))",
                if target.is_some() { "one body of the robot (beside the target's)" } else { "two bodies" },
                model.name(),
                shapes.shapes.len(),
                if shapes.shapes.len() == 1 { "y" } else { "ies" }
            )));
        }
        let pairs = match &spec.pairs {
            None => PairFilter::AllButAdjacent,
            Some(list) => PairFilter::Geometries(resolve_pairs(model, &shapes, target.as_ref(), list)?),
        };
        let rigid = match spec.kind {
            ContactKind::Rigid if target.is_some() => return Err(rigid_with_target_refused()),
            ContactKind::Rigid => Some(RigidContact::new(spec.impact_spec(), spec.stabilization.unwrap_or(RIGID_STABILIZATION), spec.friction)),
            ContactKind::Compliant => None,
        };
        Ok(PlantContact { shapes, pairs, law: spec.law(), margin: spec.margin, rigid, target, forced: Vec::new(), count: 0, normal_force: 0.0, power: 0.0, active: Vec::new() })
    }

    /// The contacts at the ODE state `y` (the kinematics of its `x` current in `data`) between
    /// the admitted pairs, distance at most `margin`.
    fn found(&self, model: &Model, data: &Data, y: &[f64], pairs: &PairFilter, margin: f64) -> Result<Vec<Contact>> {
        let mut placed = place_on_bodies(data, &self.shapes);
        if let Some(t) = &self.target {
            place_on_free_body(&t.shapes, &FreeTarget::pose(t.state(y)), t.body, t.first_geometry, &mut placed);
        }
        contacts_of_placed(model, &placed, pairs, margin)
    }

    /// Append to `out` the wrenches on the robot's bodies of the contacts at the ODE state `y`
    /// (`[x; u; W; s]`), the kinematics of `x` current in `data` (its body velocities are set
    /// here), set the free target's force and moment, and keep the evaluation's summary.
    pub(crate) fn wrenches_into(&mut self, model: &Model, data: &mut Data, y: &[f64], out: &mut Vec<ExternalWrench>) -> Result<()> {
        if self.rigid.is_some() {
            // Rigid contact acts by the impulses of each step (sim/rigid_contact.rs), not by
            // forces; the summary is the last step's.
            return Ok(());
        }
        let nx = model.nx();
        velocity_pass(model, data, &y[nx..nx + model.nu()]);
        let margin = if self.forced.is_empty() { self.margin } else { self.margin.max(ONSET_SLACK) };
        let found = self.found(model, data, y, &self.pairs, margin)?;
        (self.count, self.normal_force, self.power) = (0, 0.0, 0.0);
        self.active.clear();
        let target = self.target.as_ref().map(|t| (t.body, t.state(y)));
        let (mut target_force, mut target_torque) = (Vector3::zeros(), Vector3::zeros());
        for c in &found {
            let mut c = *c;
            if c.distance > 0.0 && c.distance <= ONSET_SLACK && self.forced.contains(&(c.geometry[0], c.geometry[1])) {
                c.distance = 0.0;
            }
            let velocity = |body: usize, p: &Vector3<f64>| match target {
                Some((tb, s)) if tb == body => FreeTarget::point_velocity(s, p),
                _ => point_velocity(data, body, p),
            };
            if let Some(f) = self.law.force_with(&c, velocity) {
                self.count += 1;
                self.normal_force += f.normal_force;
                self.power += f.power;
                self.active.push(f);
                // −force on the first body, +force on the second, both at the point.
                for (body, force) in [(f.body[0], -f.force), (f.body[1], f.force)] {
                    match target {
                        Some((tb, s)) if tb == body => {
                            target_force += force;
                            target_torque += (f.point - Vector3::new(s[0], s[1], s[2])).cross(&force);
                        }
                        _ => out.push(ExternalWrench {
                            body,
                            offset: data.body_to_world[body].transpose() * (f.point - data.com_in_world[body]),
                            force,
                            torque: Vector3::zeros(),
                        }),
                    }
                }
            }
        }
        if let Some(t) = &mut self.target {
            (t.force, t.torque) = (target_force, target_torque);
        }
        Ok(())
    }

    /// Rigid contact: the velocity jump of the step of length `h` from the ODE state `y` at `t`
    /// ([`crate::sim::rigid_contact`]), `du` the forward dynamics just evaluated there (the
    /// kinematics of `x` current in `data`); the summary kept. Whether a jump was applied.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn rigid_step(&mut self, model: &Model, data: &mut Data, t: f64, h: f64, y: &mut [f64], du: &[f64]) -> Result<bool> {
        let found = self.found(model, data, y, &self.pairs, self.margin)?;
        let Some(rigid) = self.rigid.as_mut() else {
            return Ok(false);
        };
        let s = rigid_jump(model, data, rigid, &found, t, h, y, du)?;
        (self.count, self.normal_force) = (s.count, s.normal_force);
        // Impulses in the cone are all zero unless a normal one is positive.
        Ok(s.count > 0)
    }

    /// The geometry pairs touching or interpenetrating at the ODE state `y` (distance ≤ 0).
    pub(crate) fn touching(&self, model: &Model, data: &mut Data, y: &[f64]) -> Result<Vec<(usize, usize)>> {
        forward_kinematics(model, data, &y[..model.nx()])?;
        let found = self.found(model, data, y, &self.pairs, 0.0)?;
        Ok(found.iter().map(|c| (c.geometry[0], c.geometry[1])).collect())
    }

    /// The smallest signed distance at the ODE state `y` between the geometry pairs `pairs` (m).
    pub(crate) fn distance(&self, model: &Model, data: &mut Data, y: &[f64], pairs: &[(usize, usize)]) -> Result<f64> {
        forward_kinematics(model, data, &y[..model.nx()])?;
        let found = self.found(model, data, y, &PairFilter::Geometries(pairs.to_vec()), f64::MAX / 4.0)?;
        Ok(found.iter().map(|c| c.distance).fold(f64::INFINITY, f64::min))
    }
}

/// The named pairs of a description as geometry pairs: each name a body of the robot (its
/// collision shapes), a collision geometry of the robot, or — with a free target — `"target"`,
/// the target model's name or body name (all its shapes) or one of its collision geometries
/// (numbered after the robot's).
fn resolve_pairs(model: &Model, shapes: &CollisionShapes, target: Option<&FreeTarget>, list: &[[String; 2]]) -> Result<Vec<(usize, usize)>> {
    let bodies = model.body_names();
    let geometries = model.geometries();
    let target_names = |t: &FreeTarget| -> Vec<String> { t.shapes.shapes.iter().map(|s| t.geometry_names[s.geometry].clone()).collect() };
    let resolve = |name: &str| -> Result<Vec<usize>> {
        if let Some(b) = bodies.iter().position(|n| n == name) {
            let own: Vec<usize> = shapes.shapes.iter().filter(|s| s.body == b).map(|s| s.geometry).collect();
            if own.is_empty() {
                return Err(SpacearmError::argument(format!("contact pair: body '{name}' has no collision geometry (role=\"collision\")")));
            }
            return Ok(own);
        }
        if let Some(s) = shapes.shapes.iter().find(|s| geometries[s.geometry].name == name) {
            return Ok(vec![s.geometry]);
        }
        if let Some(t) = target {
            if name == "target" || name == t.name || name == t.body_name {
                return Ok(t.shapes.shapes.iter().map(|s| t.first_geometry + s.geometry).collect());
            }
            if let Some(s) = t.shapes.shapes.iter().find(|s| t.geometry_names[s.geometry] == name) {
                return Ok(vec![t.first_geometry + s.geometry]);
            }
        }
        Err(SpacearmError::argument(format!(
            "contact pair: no body or collision geometry named '{name}' in '{}'{}; the bodies are {bodies:?}, the collision geometries {:?}{}",
            model.name(),
            if target.is_some() { " or in the target" } else { "" },
            shapes.shapes.iter().map(|s| geometries[s.geometry].name.as_str()).collect::<Vec<_>>(),
            target.map(|t| format!("; the target is 'target' (or '{}'), its collision geometries {:?}", t.name, target_names(t))).unwrap_or_default()
        )))
    };
    let body_of = |g: usize| match target {
        Some(t) if g >= t.first_geometry => t.body,
        _ => geometries[g].body,
    };
    let mut out = Vec::new();
    for [a, b] in list {
        let (ga, gb) = (resolve(a)?, resolve(b)?);
        for &g in &ga {
            for &h in &gb {
                if body_of(g) == body_of(h) {
                    return Err(SpacearmError::argument(format!("contact pair ('{a}', '{b}'): both shapes are on one body (a body does not touch itself)")));
                }
                out.push((g, h));
            }
        }
    }
    Ok(out)
}

/// How far apart (m) the pairs of a located onset may be and still act as touching in the step
/// that starts there: the onset is located to a few ulps of time, so they are apart by far less.
pub(crate) const ONSET_SLACK: f64 = 1e-9;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_description_reads_with_its_defaults_and_bad_values_are_named() {
        let spec: ContactSpec = toml::from_str("stiffness = 1e4\npairs = [[\"base\", \"hand\"]]").unwrap();
        assert_eq!((spec.law, spec.exponent, spec.damping, spec.friction, spec.slip_velocity, spec.margin), (LawName::KelvinVoigt, 1.0, 0.0, 0.0, 1e-3, 0.0));
        spec.validate().unwrap();
        let err = |text: &str| toml::from_str::<ContactSpec>(text).unwrap().validate().unwrap_err().to_string();
        assert!(err("stiffness = -1.0").contains("contact stiffness must be finite and > 0"), "{}", err("stiffness = -1.0"));
        assert!(err("stiffness = 1.0\nfriction = -0.1").contains("contact friction"));
        assert!(err("stiffness = 1.0\nexponent = 0.5").contains("contact exponent"));
        assert!(err("stiffness = 1.0\nslip_velocity = 0.0").contains("slip_velocity"));
        assert!(err("stiffness = 1.0\npairs = []").contains("pairs is empty"));
        assert!(toml::from_str::<ContactSpec>("stiffness = 1.0\nlaw = \"rigid\"").is_err());
        assert!(err("damping = 1.0").contains("stiffness is required"));
        toml::from_str::<ContactSpec>("kind = \"rigid\"\nrestitution = 0.5\nsolver = \"pgs\"").unwrap().validate().unwrap();
        assert!(err("kind = \"rigid\"\nstiffness = 1.0").contains("has no stiffness or damping"));
        assert!(err("kind = \"rigid\"\nrestitution = 1.5").contains("restitution must be in [0, 1]"));
        assert!(err("kind = \"rigid\"\nstabilization = -0.1").contains("contact stabilization"));
        assert!(err("kind = \"rigid\"\ntolerance = 0.0").contains("tolerance"));
        assert!(err("stiffness = 1.0\nrestitution = 0.5").contains("restitution is a setting of the rigid contact"));
        assert!(toml::from_str::<ContactSpec>("kind = \"rigid\"\nsolver = \"lcp\"").is_err());
        assert!(toml::from_str::<ContactSpec>("stiffness = 1.0\nkind = \"soft\"").is_err());
    }
}
