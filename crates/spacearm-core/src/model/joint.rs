//! Joint types and the description of one joint.

use nalgebra::{UnitQuaternion, UnitVector3, Vector3};
use serde::{Deserialize, Serialize};

use crate::error::{Result, SpacearmError};

/// The kind of a joint connecting a link to its parent.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum JointType {
    /// One rotational degree of freedom about the joint axis (coordinate in rad).
    Revolute,
    /// One translational degree of freedom along the joint axis (coordinate in m).
    Prismatic,
    /// No degree of freedom: the link is rigidly attached to its parent.
    Fixed,
}

impl JointType {
    /// Number of degrees of freedom the joint contributes to `q`.
    pub fn dof(self) -> usize {
        match self {
            JointType::Fixed => 0,
            _ => 1,
        }
    }

    /// Lower-case name as used in model files.
    pub fn as_str(self) -> &'static str {
        match self {
            JointType::Revolute => "revolute",
            JointType::Prismatic => "prismatic",
            JointType::Fixed => "fixed",
        }
    }

    /// The joint type named `name` (a name of [`JointType::as_str`]); any other name is an
    /// invalid model.
    pub fn from_name(name: &str) -> Result<JointType> {
        [JointType::Revolute, JointType::Prismatic, JointType::Fixed]
            .into_iter()
            .find(|kind| kind.as_str() == name)
            .ok_or_else(|| SpacearmError::InvalidModel(format!("joint type must be 'revolute', 'prismatic' or 'fixed', got '{name}'")))
    }
}

/// Optional limits of a joint, kept in the model for controllers and planners (the dynamics
/// algorithms do not enforce them).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct JointLimits {
    /// Lower position limit (rad or m); `-inf` when absent.
    pub lower: f64,
    /// Upper position limit (rad or m); `+inf` when absent.
    pub upper: f64,
    /// Maximum speed (rad/s or m/s); `+inf` when absent.
    pub velocity: f64,
    /// Maximum effort (N·m or N); `+inf` when absent.
    pub effort: f64,
}

impl JointLimits {
    /// No limits at all.
    pub fn unlimited() -> Self {
        JointLimits {
            lower: f64::NEG_INFINITY,
            upper: f64::INFINITY,
            velocity: f64::INFINITY,
            effort: f64::INFINITY,
        }
    }
}

/// The passive dynamics of a joint (docs/flexibility.md): whether a motor drives it, and the
/// linear spring–damper it carries. The joint's passive generalized force is
/// `Q = −stiffness·(q − rest) − damping·q̇` (MuJoCo's `qfrc_passive` of a joint with
/// `stiffness`, `springref` and `damping`), added to the applied force in every forward
/// dynamics; the spring stores `½ stiffness (q − rest)²`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct JointDynamics {
    /// Whether a motor applies the commanded torque (or force); a passive joint (`false`) gets
    /// none, whatever is commanded.
    pub actuated: bool,
    /// Spring stiffness `k` ≥ 0: N·m/rad (revolute) or N/m (prismatic).
    pub stiffness: f64,
    /// Viscous damping `c` ≥ 0: N·m·s/rad (revolute) or N·s/m (prismatic).
    pub damping: f64,
    /// The spring's rest coordinate (rad or m).
    pub rest: f64,
}

impl Default for JointDynamics {
    /// An actuated joint without spring or damper (a rigid model's joint).
    fn default() -> Self {
        JointDynamics { actuated: true, stiffness: 0.0, damping: 0.0, rest: 0.0 }
    }
}

impl JointDynamics {
    /// Whether the joint contributes a passive force (a spring or a damper).
    pub fn has_passive_force(&self) -> bool {
        self.stiffness != 0.0 || self.damping != 0.0
    }

    /// The passive generalized force `−k (q − rest) − c q̇`.
    #[inline]
    pub fn force(&self, q: f64, qd: f64) -> f64 {
        -self.stiffness * (q - self.rest) - self.damping * qd
    }

    /// The spring's potential energy `½ k (q − rest)²`, J.
    #[inline]
    pub fn spring_energy(&self, q: f64) -> f64 {
        0.5 * self.stiffness * (q - self.rest) * (q - self.rest)
    }
}

/// A joint: where it sits on the parent, how the child frame is oriented at `q = 0`, and the
/// axis it moves about or along.
///
/// Frames (docs/conventions.md): every body frame has its origin at the body's centre of mass. The joint
/// sits at `origin_in_parent`, a point given in the parent's (CM) frame. The child's frame axes
/// are the parent's rotated by `rotation_in_parent` and then, for a revolute joint, by `q` about
/// `axis`; `axis` is expressed in the child's frame (it is unchanged by the joint's own motion).
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    /// Unique joint name.
    pub name: String,
    /// Revolute, prismatic or fixed.
    pub kind: JointType,
    /// Joint position in the parent frame (from the parent's CM), m.
    pub origin_in_parent: Vector3<f64>,
    /// Orientation of the child frame relative to the parent frame at `q = 0`.
    pub rotation_in_parent: UnitQuaternion<f64>,
    /// Unit joint axis in the child frame (ignored for fixed joints).
    pub axis: UnitVector3<f64>,
    /// Position, velocity and effort limits.
    pub limits: JointLimits,
    /// Actuation and the spring–damper ([`JointDynamics`]).
    pub dynamics: JointDynamics,
}
