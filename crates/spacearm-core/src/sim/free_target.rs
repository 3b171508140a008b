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

#[cfg(test)]
mod tests {
    use nalgebra::Vector3;

    use super::*;
    use crate::control::ZeroTorque;
    use crate::model::geometry::{GeometryRole, GeometrySpec, Shape};
    use crate::model::joint::JointType;
    use crate::model::link::LinkSpec;
    use crate::model::ModelBuilder;
    use crate::scenario::free_body::FreeBody;
    use crate::sim::contact::ContactSpec;
    use crate::sim::options::SimOptions;
    use crate::sim::simulate::simulate_with_target;

    fn ball(body: &str, radius: f64, origin: [f64; 3]) -> GeometrySpec {
        GeometrySpec { name: None, body: body.into(), role: GeometryRole::Collision, shape: Shape::Sphere { radius }, origin, rotation: [0.0, 0.0, 0.0, 1.0], rgba: None }
    }

    /// A floating base (ball 0.3) with a hinged arm whose tip ball (0.1) sweeps beside it; a
    /// 2 kg ball target (0.2) of unequal moments.
    fn scene() -> (Model, Model) {
        let mut b = ModelBuilder::new("bus", "base", 100.0, [[3.6, 0.0, 0.0], [0.0, 3.6, 0.0], [0.0, 0.0, 3.6]]).unwrap();
        b.add_link(LinkSpec::new("l1", "base", JointType::Revolute, [0.5, 0.0, 0.0], [0.0, 0.0, 1.0], [0.3, 0.0, 0.0], 3.0, [0.02, 0.1, 0.1])).unwrap();
        b.add_geometry(ball("base", 0.3, [0.0; 3])).unwrap();
        b.add_geometry(ball("l1", 0.1, [0.3, 0.0, 0.0])).unwrap();
        let robot = b.build().unwrap();
        let mut t = ModelBuilder::new("rock", "rock", 2.0, [[0.08, 0.0, 0.0], [0.0, 0.1, 0.0], [0.0, 0.0, 0.12]]).unwrap();
        t.add_geometry(ball("rock", 0.2, [0.0; 3])).unwrap();
        (robot, t.build().unwrap())
    }

    fn contact(pairs: &[[&str; 2]]) -> ContactSpec {
        let mut c: ContactSpec = toml::from_str("stiffness = 2e4\ndamping = 30.0\nfriction = 0.4\nslip_velocity = 0.01").unwrap();
        c.pairs = Some(pairs.iter().map(|[a, b]| [a.to_string(), b.to_string()]).collect());
        c
    }

    #[test]
    fn untouched_the_target_is_the_torque_free_body() {
        let (robot, rock) = scene();
        let q = nalgebra::UnitQuaternion::from_euler_angles(0.3, -0.2, 0.5);
        let s0 = [3.0, -2.0, 0.5, q.i, q.j, q.k, q.w, 0.1, 0.0, -0.05, 0.8, -1.2, 1.5];
        let opts = SimOptions { duration: 2.0, dt: 1e-3, contact: Some(contact(&[["base", "target"]])), ..SimOptions::default() };
        let (x0, u0) = (vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0], vec![0.0; 7]);
        let r = simulate_with_target(&robot, &x0, &u0, &opts, &mut ZeroTorque, &rock, &s0, &mut |_| Ok(())).unwrap();
        let states = r.records.target_state.as_ref().unwrap();
        // FreeBody: L constant, r in closed form, the attitude by RK4 on a fine grid.
        let mut fb = FreeBody::new(rock.base().inertia, &s0, Vector3::zeros(), 1e-4).unwrap();
        let mut worst: f64 = 0.0;
        for (k, t) in r.records.t.iter().enumerate() {
            let s = &states[13 * k..13 * k + 13];
            let e = fb.state(*t).unwrap();
            let sign = if (3..7).map(|i| s[i] * e[i]).sum::<f64>() < 0.0 { -1.0 } else { 1.0 };
            for i in 0..13 {
                let expected = if (3..7).contains(&i) { sign * e[i] } else { e[i] };
                worst = worst.max((s[i] - expected).abs());
            }
        }
        assert!(worst < 1e-9, "{worst}");
        assert!(r.records.contact_count.as_ref().unwrap().iter().all(|&c| c == 0.0));
    }

    #[test]
    fn through_a_frictional_contact_robot_and_target_keep_their_momentum() {
        let (robot, rock) = scene();
        let s0 = [0.8, 0.4, 0.03, 0.0, 0.0, 0.0, 1.0, 0.0, -0.5, 0.0, 0.3, -0.2, 0.5];
        let opts = SimOptions { duration: 0.6, dt: 1e-4, record_every: 5, contact: Some(contact(&[["l1", "rock"]])), ..SimOptions::default() };
        let (x0, u0) = (vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0], vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.02, 0.4]);
        let r = simulate_with_target(&robot, &x0, &u0, &opts, &mut ZeroTorque, &rock, &s0, &mut |_| Ok(())).unwrap();
        let rec = &r.records;
        let (p_r, l_r, s) = (&rec.linear_momentum, &rec.angular_momentum_origin, rec.target_state.as_ref().unwrap());
        let n = rec.n_samples;
        let touched = rec.contact_count.as_ref().unwrap().iter().filter(|&&c| c > 0.0).count();
        assert!(touched > 20 && touched < n - 20, "{touched} of {n}");
        // The target's momentum from its state here (m v, r × m v + R I Rᵀ ω).
        let total = |k: usize| -> [f64; 6] {
            let t = &s[13 * k..13 * k + 13];
            let rot = crate::math::rotations::matrix_from_xyzw(&[t[3], t[4], t[5], t[6]]);
            let v = Vector3::new(t[7], t[8], t[9]) * 2.0;
            let l = Vector3::new(t[0], t[1], t[2]).cross(&v) + rot * rock.base().inertia * rot.transpose() * Vector3::new(t[10], t[11], t[12]);
            [p_r[3 * k] + v.x, p_r[3 * k + 1] + v.y, p_r[3 * k + 2] + v.z, l_r[3 * k] + l.x, l_r[3 * k + 1] + l.y, l_r[3 * k + 2] + l.z]
        };
        let first = total(0);
        // Relative to the sizes of the two momenta (the robot's and the target's largest).
        let size = |v: &[f64], stride: usize, from: usize| (0..n).map(|k| (0..3).map(|i| v[stride * k + from + i].abs()).fold(0.0, f64::max)).fold(0.0, f64::max);
        let scale_p = size(p_r, 3, 0) + 2.0 * size(s, 13, 7);
        let scale_l = size(l_r, 3, 0) + (0..n).map(|k| total(k)[3..].iter().map(|v| v.abs()).fold(0.0, f64::max)).fold(0.0, f64::max);
        let target_change = (2.0 * (s[13 * (n - 1) + 7] - s[7])).abs() + (2.0 * (s[13 * (n - 1) + 8] - s[8])).abs();
        assert!(target_change > 0.3, "the contact changed the target's momentum: {target_change}");
        for k in 0..n {
            let now = total(k);
            for i in 0..6 {
                let scale = if i < 3 { scale_p } else { scale_l };
                assert!((now[i] - first[i]).abs() < 1e-12 * scale, "sample {k} entry {i}: {} vs {} (scale {scale})", now[i], first[i]);
            }
        }
        assert!(r.drift.iter().all(|(_, d)| *d < 1e-9), "{:?}", r.drift);
    }
}
