//! Actuators and their limits: joint motors (arm joints and reaction wheels, limits from the
//! joints' effort and velocity limits) and base thrusters (force and torque limits per axis of
//! 𝒥). A command beyond a limit is clamped physically and flagged, so the simulator can record a
//! saturation event; nothing is ignored silently.
//!
//! - Torque (effort) limit: `τ ← clamp(τ, −τ_max, τ_max)`.
//! - Speed limit: a motor running at `|q̇| ≥ q̇_max` can only brake, so a torque that would
//!   drive it faster in the same direction (`τ q̇ > 0`) is set to zero. The speed can still
//!   exceed the limit slightly when the base's own motion drives the rotor (for a wheel, `q̇` is
//!   the rate relative to the base); the record shows it.
//! - Thrusters: each component of `F0` and `N0` (𝒥 axes) is clamped to its limit.
//!
//! Reaction wheels are ordinary joints of the tree (docs/physics.md). By default the simulator
//! treats as wheels the joints that [`detect_reaction_wheels`] finds: what
//! `RobotBuilder.add_reaction_wheel` creates, a symmetric rotor on a revolute joint of the base.

use nalgebra::{Vector3, Vector6};

use crate::error::{Result, SpacearmError};
use crate::model::joint::JointType;
use crate::model::Model;

/// Kind of a saturation (the integer codes of the simulation records).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum SaturationKind {
    /// A joint torque (or force) limit: code 0.
    Torque = 0,
    /// A joint speed limit: code 1.
    Speed = 1,
    /// A thruster force or torque limit: code 2.
    Thruster = 2,
}

impl SaturationKind {
    /// Bit of the kind in a per-actuator flag byte.
    #[inline]
    pub fn bit(self) -> u8 {
        1 << (self as u8)
    }

    /// All kinds, in code order.
    pub const ALL: [SaturationKind; 3] = [SaturationKind::Torque, SaturationKind::Speed, SaturationKind::Thruster];
}

/// Per-axis limits of the base thrusters, in 𝒥: `|F0_i| ≤ max_force_i`, `|N0_i| ≤ max_torque_i`
/// (infinite: unlimited).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThrusterLimits {
    /// Largest `|F0_i|` per axis of 𝒥, N.
    pub max_force: Vector3<f64>,
    /// Largest `|N0_i|` per axis of 𝒥, N·m.
    pub max_torque: Vector3<f64>,
}

impl ThrusterLimits {
    /// Validate: every limit must be > 0 (an infinite limit means none).
    pub fn new(max_force: Vector3<f64>, max_torque: Vector3<f64>) -> Result<Self> {
        for (what, v) in [("thruster max_force", &max_force), ("thruster max_torque", &max_torque)] {
            if let Some(bad) = v.iter().find(|x| !(**x > 0.0)) {
                return Err(SpacearmError::argument(format!("{what} must be > 0 on every axis (inf for no limit), got {bad}")));
            }
        }
        Ok(ThrusterLimits { max_force, max_torque })
    }
}

/// The actuators of a simulation: one motor per joint degree of freedom (actuators `0..N`) and
/// six thruster channels `[Fx, Fy, Fz, Nx, Ny, Nz]` (actuators `N..N+6`).
#[derive(Debug, Clone)]
pub struct Actuators {
    /// Whether each joint has a motor (a passive joint's torque is always zero).
    actuated: Vec<bool>,
    effort: Vec<f64>,
    speed: Vec<f64>,
    thrusters: Option<ThrusterLimits>,
}

/// Names of the six thruster channels, after the joint names in the actuator list.
pub const THRUSTER_CHANNELS: [&str; 6] = ["base_force_x", "base_force_y", "base_force_z", "base_torque_x", "base_torque_y", "base_torque_z"];

impl Actuators {
    /// Joint motors with the model's effort and velocity limits (`joint_limits = false`: no
    /// joint limits at all) and optional thrusters.
    pub fn new(model: &Model, joint_limits: bool, thrusters: Option<ThrusterLimits>) -> Self {
        let n = model.n_dof();
        let (mut effort, mut speed) = (vec![f64::INFINITY; n], vec![f64::INFINITY; n]);
        if joint_limits {
            for d in 0..n {
                let lim = model.links()[model.body_of_dof(d) - 1].joint.limits;
                effort[d] = lim.effort;
                speed[d] = lim.velocity;
            }
        }
        Actuators { actuated: model.actuated_dofs(), effort, speed, thrusters }
    }

    /// Actuator names: the joint names (dof order), then [`THRUSTER_CHANNELS`].
    pub fn names(model: &Model) -> Vec<String> {
        (0..model.n_dof())
            .map(|d| model.links()[model.body_of_dof(d) - 1].joint.name.clone())
            .chain(THRUSTER_CHANNELS.iter().map(|s| s.to_string()))
            .collect()
    }

    /// Clamp joint torques `tau` (in place) given the joint rates `qd`; OR the saturation bits
    /// into `flags[0..N]`. A passive joint (no motor) gets zero, unflagged: it has no actuator
    /// to saturate, and the record's `tau_cmd` keeps what was commanded.
    pub fn saturate_joints(&self, tau: &mut [f64], qd: &[f64], flags: &mut [u8]) {
        for d in 0..tau.len() {
            if !self.actuated[d] {
                tau[d] = 0.0;
                continue;
            }
            let t = tau[d];
            let max = self.effort[d];
            let mut out = t;
            if out > max {
                out = max;
                flags[d] |= SaturationKind::Torque.bit();
            } else if out < -max {
                out = -max;
                flags[d] |= SaturationKind::Torque.bit();
            }
            if qd[d].abs() >= self.speed[d] && out * qd[d] > 0.0 {
                out = 0.0;
                flags[d] |= SaturationKind::Speed.bit();
            }
            tau[d] = out;
        }
    }

    /// Clamp a base wrench `[F0; N0]` (in place) to the thruster limits; OR the bits into
    /// `flags[0..6]` (the thruster channels).
    pub fn saturate_thrusters(&self, wrench: &mut Vector6<f64>, flags: &mut [u8]) {
        let Some(lim) = &self.thrusters else { return };
        for i in 0..6 {
            let max = if i < 3 { lim.max_force[i] } else { lim.max_torque[i - 3] };
            let w = wrench[i];
            if w.abs() > max {
                wrench[i] = max.copysign(w);
                flags[i] |= SaturationKind::Thruster.bit();
            }
        }
    }

    /// Effort limit of joint `dof`.
    pub fn effort_limit(&self, dof: usize) -> f64 {
        self.effort[dof]
    }

    /// Speed limit of joint `dof`.
    pub fn speed_limit(&self, dof: usize) -> f64 {
        self.speed[dof]
    }
}

/// The reaction wheels of a model: degrees of freedom of revolute joints of the base whose
/// link has no children, is a symmetric rotor about the joint axis
/// ([`crate::model::link::Link::symmetric_rotor_moment`]: its CM on the axis, its inertia
/// symmetric about it; its spin changes nothing but its own angle) and that has a motor (an actuated joint). This is exactly what `RobotBuilder.add_reaction_wheel` creates.
pub fn detect_reaction_wheels(model: &Model) -> Vec<usize> {
    let mut has_children = vec![false; model.n_bodies()];
    for l in model.links() {
        has_children[l.parent] = true;
    }
    let mut wheels = Vec::new();
    for (k, link) in model.links().iter().enumerate() {
        let body = k + 1;
        if link.parent != 0 || link.joint.kind != JointType::Revolute || has_children[body] || !link.joint.dynamics.actuated {
            continue;
        }
        if link.symmetric_rotor_moment().is_some() {
            if let Some(d) = model.dof_of_body(body) {
                wheels.push(d);
            }
        }
    }
    wheels
}

/// Check explicit wheel degrees of freedom: in range, distinct, revolute joints.
pub fn check_wheels(model: &Model, wheels: &[usize]) -> Result<()> {
    let mut seen = vec![false; model.n_dof()];
    for &d in wheels {
        if d >= model.n_dof() {
            return Err(SpacearmError::NotFound(format!("wheel dof {d} does not exist (the model has dofs 0..{})", model.n_dof())));
        }
        if seen[d] {
            return Err(SpacearmError::argument(format!("wheel dof {d} is listed twice")));
        }
        seen[d] = true;
        let joint = &model.links()[model.body_of_dof(d) - 1].joint;
        if joint.kind != JointType::Revolute {
            return Err(SpacearmError::argument(format!("wheel joint '{}' must be revolute, it is {}", joint.name, joint.kind.as_str())));
        }
        if !joint.dynamics.actuated {
            return Err(SpacearmError::argument(format!("wheel joint '{}' is passive (actuated = false): a wheel needs a motor", joint.name)));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::joint::JointLimits;
    use crate::model::{LinkSpec, ModelBuilder};

    fn wheeled() -> Model {
        let mut b = ModelBuilder::new("w", "base", 100.0, [[10.0, 0.0, 0.0], [0.0, 12.0, 0.0], [0.0, 0.0, 14.0]]).unwrap();
        let spec = |name: &str, axis: [f64; 3], com: [f64; 3], inertia: [[f64; 3]; 3], parent: &str| LinkSpec {
            name: name.into(),
            parent: parent.into(),
            joint_name: None,
            kind: JointType::Revolute,
            origin_in_parent: [0.1, 0.2, 0.3],
            rotation_in_parent: [0.0, 0.0, 0.0, 1.0],
            axis,
            com_from_joint: com,
            mass: 1.0,
            inertia,
            limits: JointLimits { lower: f64::NEG_INFINITY, upper: f64::INFINITY, velocity: 50.0, effort: 0.2 },
        };
        let rotor = [[0.06, 0.0, 0.0], [0.0, 0.06, 0.0], [0.0, 0.0, 0.1]];
        b.add_link(spec("wheel", [0.0, 0.0, 1.0], [0.0, 0.0, 0.0], rotor, "base")).unwrap();
        // Off-axis CM: not a wheel.
        b.add_link(spec("arm", [0.0, 0.0, 1.0], [0.5, 0.0, 0.0], rotor, "base")).unwrap();
        // Symmetric rotor but on a link, not the base: not a wheel.
        b.add_link(spec("tip_rotor", [0.0, 0.0, 1.0], [0.0, 0.0, 0.0], rotor, "arm")).unwrap();
        // Axis not a symmetry axis: not a wheel.
        b.add_link(spec("lopsided", [1.0, 0.0, 0.0], [0.0, 0.0, 0.0], rotor, "base")).unwrap();
        b.build().unwrap()
    }

    #[test]
    fn detects_only_symmetric_rotors_on_the_base() {
        assert_eq!(detect_reaction_wheels(&wheeled()), vec![0]);
        assert!(detect_reaction_wheels(&crate::model::presets::spatial6()).is_empty());
    }

    #[test]
    fn joint_limits_clamp_and_flag() {
        let m = wheeled();
        let a = Actuators::new(&m, true, None);
        let mut flags = vec![0u8; m.n_dof()];
        // Over the effort limit; at the speed limit pushing faster; braking at the speed limit.
        let mut tau = vec![0.5, -0.1, 0.3, -0.3];
        let qd = vec![0.0, 60.0, 50.0, -50.0];
        a.saturate_joints(&mut tau, &qd, &mut flags);
        assert_eq!(tau, vec![0.2, -0.1, 0.0, -0.0]);
        assert_eq!(flags, vec![1, 0, 3, 3]);
        let unlimited = Actuators::new(&m, false, None);
        let mut tau = vec![0.5, -0.1, 0.3, -0.3];
        let mut flags = vec![0u8; 4];
        unlimited.saturate_joints(&mut tau, &qd, &mut flags);
        assert_eq!(tau, vec![0.5, -0.1, 0.3, -0.3]);
        assert_eq!(flags, vec![0; 4]);
    }

    #[test]
    fn thrusters_clamp_each_axis() {
        let m = wheeled();
        let lim = ThrusterLimits::new(Vector3::new(1.0, 1.0, 1.0), Vector3::new(0.1, f64::INFINITY, 0.1)).unwrap();
        let a = Actuators::new(&m, true, Some(lim));
        let mut w = Vector6::new(2.0, -0.5, -3.0, 0.05, 100.0, -0.2);
        let mut flags = [0u8; 6];
        a.saturate_thrusters(&mut w, &mut flags);
        assert_eq!(w, Vector6::new(1.0, -0.5, -1.0, 0.05, 100.0, -0.1));
        assert_eq!(flags, [4, 0, 4, 0, 0, 4]);
        assert!(ThrusterLimits::new(Vector3::new(1.0, 0.0, 1.0), Vector3::new(1.0, 1.0, 1.0)).is_err());
        assert!(ThrusterLimits::new(Vector3::new(1.0, f64::NAN, 1.0), Vector3::new(1.0, 1.0, 1.0)).is_err());
    }
}
