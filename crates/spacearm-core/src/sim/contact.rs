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
use crate::collision::detect::contacts_after_kinematics;
use crate::collision::{CollisionShapes, ContactLaw, NormalLaw, PairFilter};
use crate::error::{Result, SpacearmError};
use crate::model::data::Data;
use crate::model::Model;

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
    /// Rigid frictional contact solved per step (collision/impact.rs): not built into the run's
    /// loop yet; [`ContactSpec::validate`] refuses it with a message that says so.
    Rigid,
}

/// Contact in a run, as data: which pairs touch and the compliant law's parameters.
///
/// ```toml
/// [contact]
/// kind = "compliant"           # "rigid": refused, not built into the loop yet
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
    /// by nothing; a force needs interpenetration).
    #[serde(default)]
    pub margin: f64,
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
        if self.kind == ContactKind::Rigid {
            return Err(SpacearmError::argument(
                "contact kind \"rigid\" in a run is not implemented yet: only the compliant law is integrated by simulate; \
                 spacearm.contact.solve_impact computes one rigid frictional impact at a state (docs/contact.md, \"Rigid frictional impacts\")",
            ));
        }
        let Some(stiffness) = self.stiffness else {
            return Err(SpacearmError::argument("contact stiffness is required by the compliant law (k, N/m^p, > 0)"));
        };
        check("stiffness", stiffness, stiffness > 0.0, "> 0 N/m^p")?;
        check("exponent", self.exponent, self.exponent >= 1.0, ">= 1")?;
        check("damping", self.damping, self.damping >= 0.0, ">= 0")?;
        check("friction", self.friction, self.friction >= 0.0, ">= 0")?;
        check("slip_velocity", self.slip_velocity, self.slip_velocity > 0.0, "> 0 m/s")?;
        check("margin", self.margin, self.margin >= 0.0, ">= 0 m")?;
        if self.pairs.as_ref().is_some_and(|p| p.is_empty()) {
            return Err(SpacearmError::argument("contact pairs is empty: give at least one pair of body or geometry names, or leave it out for every pair"));
        }
        Ok(())
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

/// The contact of a plant: the model's collision shapes, the admitted pairs, the law, and the
/// summary of the last evaluation.
pub(crate) struct PlantContact {
    shapes: CollisionShapes,
    pairs: PairFilter,
    law: ContactLaw,
    margin: f64,
    /// Pairs of geometries that act as touching while their distance is at most
    /// [`ONSET_SLACK`] (the step that starts at a located onset: [`crate::sim::contact_onset`]).
    pub(crate) forced: Vec<(usize, usize)>,
    /// The last evaluation: contacts touching or interpenetrating, their total normal force (N)
    /// and the power of the contact forces on the system (W).
    pub(crate) count: usize,
    pub(crate) normal_force: f64,
    pub(crate) power: f64,
}

impl PlantContact {
    /// `spec` (validated) resolved on `model`: names to geometry pairs, shapes built (a mesh is
    /// refused by [`CollisionShapes::from_model`]).
    pub(crate) fn new(model: &Model, spec: &ContactSpec) -> Result<Self> {
        spec.validate()?;
        let shapes = CollisionShapes::from_model(model)?;
        if shapes.shapes.len() < 2 {
            return Err(SpacearmError::argument(format!(
                "contact needs collision shapes on at least two bodies, but '{}' has {} collision geometr{} (RobotBuilder.add_geometry(..., role=\"collision\"))",
                model.name(),
                shapes.shapes.len(),
                if shapes.shapes.len() == 1 { "y" } else { "ies" }
            )));
        }
        let pairs = match &spec.pairs {
            None => PairFilter::AllButAdjacent,
            Some(list) => {
                let bodies = model.body_names();
                let geometries = model.geometries();
                // Each name: a body's collision shapes, or one collision geometry.
                let resolve = |name: &str| -> Result<Vec<usize>> {
                    if let Some(b) = bodies.iter().position(|n| n == name) {
                        let own: Vec<usize> = shapes.shapes.iter().filter(|s| s.body == b).map(|s| s.geometry).collect();
                        if own.is_empty() {
                            return Err(SpacearmError::argument(format!("contact pair: body '{name}' has no collision geometry (role=\"collision\")")));
                        }
                        return Ok(own);
                    }
                    match shapes.shapes.iter().find(|s| geometries[s.geometry].name == name) {
                        Some(s) => Ok(vec![s.geometry]),
                        None => Err(SpacearmError::argument(format!(
                            "contact pair: no body or collision geometry named '{name}' in '{}'; the bodies are {bodies:?}, the collision geometries {:?}",
                            model.name(),
                            shapes.shapes.iter().map(|s| geometries[s.geometry].name.as_str()).collect::<Vec<_>>()
                        ))),
                    }
                };
                let mut out = Vec::new();
                for [a, b] in list {
                    let (ga, gb) = (resolve(a)?, resolve(b)?);
                    for &g in &ga {
                        for &h in &gb {
                            if geometries[g].body == geometries[h].body {
                                return Err(SpacearmError::argument(format!(
                                    "contact pair ('{a}', '{b}'): both shapes are on body '{}' (a body does not touch itself)",
                                    bodies[geometries[g].body]
                                )));
                            }
                            out.push((g, h));
                        }
                    }
                }
                PairFilter::Geometries(out)
            }
        };
        Ok(PlantContact { shapes, pairs, law: spec.law(), margin: spec.margin, forced: Vec::new(), count: 0, normal_force: 0.0, power: 0.0 })
    }

    /// Append to `out` the wrenches of the contacts at `(x, u)`, the kinematics of `x` current in
    /// `data` (its body velocities are set from `u` here), and keep the evaluation's summary.
    pub(crate) fn wrenches_into(&mut self, model: &Model, data: &mut Data, u: &[f64], out: &mut Vec<ExternalWrench>) -> Result<()> {
        velocity_pass(model, data, u);
        let margin = if self.forced.is_empty() { self.margin } else { self.margin.max(ONSET_SLACK) };
        let found = contacts_after_kinematics(model, data, &self.shapes, &self.pairs, margin)?;
        (self.count, self.normal_force, self.power) = (0, 0.0, 0.0);
        for c in &found {
            let mut c = *c;
            if c.distance > 0.0 && c.distance <= ONSET_SLACK && self.forced.contains(&(c.geometry[0], c.geometry[1])) {
                c.distance = 0.0;
            }
            if let Some(f) = self.law.force(&c, data) {
                self.count += 1;
                self.normal_force += f.normal_force;
                self.power += f.power;
                out.extend_from_slice(&f.wrenches(data));
            }
        }
        Ok(())
    }

    /// The geometry pairs touching or interpenetrating at `x` (distance ≤ 0).
    pub(crate) fn touching(&self, model: &Model, data: &mut Data, x: &[f64]) -> Result<Vec<(usize, usize)>> {
        forward_kinematics(model, data, x)?;
        let found = contacts_after_kinematics(model, data, &self.shapes, &self.pairs, 0.0)?;
        Ok(found.iter().map(|c| (c.geometry[0], c.geometry[1])).collect())
    }

    /// The smallest signed distance at `x` between the geometry pairs `pairs` (m).
    pub(crate) fn distance(&self, model: &Model, data: &mut Data, x: &[f64], pairs: &[(usize, usize)]) -> Result<f64> {
        forward_kinematics(model, data, x)?;
        let found = contacts_after_kinematics(model, data, &self.shapes, &PairFilter::Geometries(pairs.to_vec()), f64::MAX / 4.0)?;
        Ok(found.iter().map(|c| c.distance).fold(f64::INFINITY, f64::min))
    }
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
        assert!(err("kind = \"rigid\"").contains("not implemented yet"), "{}", err("kind = \"rigid\""));
        assert!(toml::from_str::<ContactSpec>("stiffness = 1.0\nkind = \"soft\"").is_err());
    }
}
