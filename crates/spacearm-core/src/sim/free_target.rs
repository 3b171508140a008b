//! A free target in the loop of a run with contact (docs/contact.md, "Contact with a free
//! target"): a rigid body outside the robot's model — the capture target of topology events and
//! of docs/capture.md, a model of one body without joints — whose 13-state
//! `s = [r (3), quat [x, y, z, w] (4), v (3), ω (3)]` (CM position, attitude mapping body axes to 𝒥,
//! CM velocity and angular velocity in 𝒥: the convention of [`crate::scenario::free_body`] and of
//! the topology events' `target_state`) is integrated WITH the robot's state by the run's
//! integrator, the plant carrying it after `[x; u; W]` (`W` the contact work).
//!
//! The contact forces between the robot's and the target's collision shapes act on both, equal
//! and opposite at the contact point ([`crate::sim::contact`]); their sum on the target,
//! `F` and the moment `N` about its CM, drive Newton–Euler in 𝒥 (docs/equations.md, the rigid
//! body's equations of motion):
//!
//! `ṙ = v`, `quaṫ = ½ [ω; 0] ⊗ quat`, `m v̇ = F`, `I_𝒥 ω̇ = N − ω × I_𝒥 ω`, `I_𝒥 = R I Rᵀ`.
//!
//! Without contact the body is torque-free and this is the motion that
//! [`crate::scenario::free_body::FreeBody`] propagates in closed form for `r` and `L`.

use nalgebra::{Isometry3, Matrix3, Quaternion, Translation3, UnitQuaternion, Vector3};

use crate::collision::CollisionShapes;
use crate::error::{check_finite, Result, SpacearmError};
use crate::math::rotations::{matrix_from_xyzw, quaternion_rate};
use crate::model::Model;

/// The free target of a run (module docs).
pub(crate) struct FreeTarget {
    /// Its model's name (for messages).
    pub(crate) name: String,
    /// Its body names and collision geometry names (for the contact pairs).
    pub(crate) body_name: String,
    /// Mass, kg.
    pub(crate) mass: f64,
    /// Inertia about the CM in body axes, kg·m², and its inverse.
    inertia: Matrix3<f64>,
    inertia_inv: Matrix3<f64>,
    /// Its collision shapes (on its body 0).
    pub(crate) shapes: CollisionShapes,
    /// Its geometry names, in its model's order.
    pub(crate) geometry_names: Vec<String>,
    /// The initial 13-state (quaternion normalized).
    pub(crate) state0: [f64; 13],
    /// Where its 13-state starts in the ODE state.
    pub(crate) offset: usize,
    /// Its body index in the contacts (one past the robot's bodies) and its first geometry
    /// index (one past the robot's geometries).
    pub(crate) body: usize,
    pub(crate) first_geometry: usize,
    /// The contact force on it and its moment about its CM, in 𝒥, at the last evaluation.
    pub(crate) force: Vector3<f64>,
    pub(crate) torque: Vector3<f64>,
}

/// The target's momentum about the origin of 𝒥 and kinetic energy, and the sizes of their terms.
#[derive(Debug, Clone, Copy)]
pub(crate) struct TargetMomentum {
    pub(crate) linear: Vector3<f64>,
    pub(crate) angular_about_origin: Vector3<f64>,
    pub(crate) energy: f64,
    /// `|m v|`, `|r × m v| + |I ω|`, `|I ω|`.
    pub(crate) linear_scale: f64,
    pub(crate) angular_scale: f64,
    pub(crate) spin_scale: f64,
}

impl FreeTarget {
    /// `target` (one rigid body with collision shapes) at `state` (13, finite, non-zero
    /// quaternion: normalized here) beside `robot`.
    pub(crate) fn new(robot: &Model, target: &Model, state: &[f64]) -> Result<Self> {
        if !target.links().is_empty() {
            return Err(SpacearmError::argument(format!(
                "target '{}' has {} link(s): contact with a free target takes one rigid body (a model without links; put the handle on it as a collision geometry)",
                target.name(),
                target.links().len()
            )));
        }
        if state.len() != 13 {
            return Err(SpacearmError::Dimension { what: "target_state".into(), expected: "13 ([r, quat xyzw, v, w])".into(), got: state.len() });
        }
        check_finite("target_state", state)?;
        let mut s = [0.0; 13];
        s.copy_from_slice(state);
        let norm = s[3..7].iter().map(|v| v * v).sum::<f64>().sqrt();
        if !(norm > 1e-12) {
            return Err(SpacearmError::argument(format!("target_state's quaternion (entries 3..7) must be non-zero, got {:?}", &s[3..7])));
        }
        for v in &mut s[3..7] {
            *v /= norm;
        }
        let base = target.base();
        let inertia = base.inertia;
        let inertia_inv = inertia
            .cholesky()
            .map(|c| c.inverse())
            .ok_or_else(|| SpacearmError::argument(format!("target '{}': its inertia must be positive definite", target.name())))?;
        let shapes = CollisionShapes::from_model(target)?;
        if shapes.shapes.is_empty() {
            return Err(SpacearmError::argument(format!(
                "target '{}' has no collision geometry: contact with a free target needs its shapes (add_geometry(..., role=\"collision\"))",
                target.name()
            )));
        }
        Ok(FreeTarget {
            name: target.name().to_string(),
            body_name: target.body_names()[0].clone(),
            mass: base.mass,
            inertia,
            inertia_inv,
            shapes,
            geometry_names: target.geometries().iter().map(|g| g.name.clone()).collect(),
            state0: s,
            offset: 0,
            body: robot.n_bodies(),
            first_geometry: robot.geometries().len(),
            force: Vector3::zeros(),
            torque: Vector3::zeros(),
        })
    }

    /// The 13-state in the ODE state `y`.
    pub(crate) fn state<'y>(&self, y: &'y [f64]) -> &'y [f64] {
        &y[self.offset..self.offset + 13]
    }

    /// The CM frame's pose in 𝒥 at the 13-state `s`.
    pub(crate) fn pose(s: &[f64]) -> Isometry3<f64> {
        let q = UnitQuaternion::from_quaternion(Quaternion::new(s[6], s[3], s[4], s[5]));
        Isometry3::from_parts(Translation3::new(s[0], s[1], s[2]), q)
    }

    /// The velocity in 𝒥 of the target's material point at `point` (𝒥): `v + ω × (point − r)`.
    pub(crate) fn point_velocity(s: &[f64], point: &Vector3<f64>) -> Vector3<f64> {
        let (r, v, w) = (Vector3::new(s[0], s[1], s[2]), Vector3::new(s[7], s[8], s[9]), Vector3::new(s[10], s[11], s[12]));
        v + w.cross(&(point - r))
    }

    /// The inertia about the CM in 𝒥 at the 13-state `s`.
    fn inertia_world(&self, s: &[f64]) -> (Matrix3<f64>, Matrix3<f64>) {
        let rot = matrix_from_xyzw(&[s[3], s[4], s[5], s[6]]);
        (rot * self.inertia * rot.transpose(), rot * self.inertia_inv * rot.transpose())
    }

    /// `ṡ` at `s` under [`FreeTarget::force`] and [`FreeTarget::torque`] (module docs).
    pub(crate) fn derivative(&self, s: &[f64], ds: &mut [f64]) {
        let w = Vector3::new(s[10], s[11], s[12]);
        let (i_w, i_w_inv) = self.inertia_world(s);
        ds[0..3].copy_from_slice(&s[7..10]);
        ds[3..7].copy_from_slice(&quaternion_rate(&s[3..7], &w));
        let a = self.force / self.mass;
        let wd = i_w_inv * (self.torque - w.cross(&(i_w * w)));
        ds[7..10].copy_from_slice(a.as_slice());
        ds[10..13].copy_from_slice(wd.as_slice());
    }

    /// Re-normalize the quaternion of the 13-state in `y`.
    pub(crate) fn project(&self, y: &mut [f64]) {
        let q = &mut y[self.offset + 3..self.offset + 7];
        let norm = q.iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm > 0.0 && norm.is_finite() {
            for v in q.iter_mut() {
                *v /= norm;
            }
        }
    }

    /// Momentum about the origin of 𝒥 and kinetic energy at `s`, with their scales.
    pub(crate) fn momentum(&self, s: &[f64]) -> TargetMomentum {
        let (r, v, w) = (Vector3::new(s[0], s[1], s[2]), Vector3::new(s[7], s[8], s[9]), Vector3::new(s[10], s[11], s[12]));
        let (i_w, _) = self.inertia_world(s);
        let p = v * self.mass;
        let spin = i_w * w;
        TargetMomentum {
            linear: p,
            angular_about_origin: r.cross(&p) + spin,
            energy: 0.5 * (self.mass * v.norm_squared() + w.dot(&spin)),
            linear_scale: p.norm(),
            angular_scale: r.cross(&p).norm() + spin.norm(),
            spin_scale: spin.norm(),
        }
    }
}
