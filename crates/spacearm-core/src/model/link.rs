//! A link as it is described to the builder ([`LinkSpec`]) and as the model keeps it
//! ([`Link`]: its joint, CM and mass properties), and a named point fixed to a body ([`Point`]).

use nalgebra::{UnitQuaternion, UnitVector3, Vector3};

use crate::model::body::MassProperties;
use crate::model::joint::{Joint, JointDynamics, JointLimits, JointType};

/// Everything that describes one link to [`ModelBuilder::add_link`](crate::model::ModelBuilder::add_link).
#[derive(Debug, Clone)]
pub struct LinkSpec {
    /// Unique link (body) name.
    pub name: String,
    /// Name of the parent body (the base or a link added before).
    pub parent: String,
    /// Unique joint name (default `<name>_joint`).
    pub joint_name: Option<String>,
    /// Revolute, prismatic or fixed.
    pub kind: JointType,
    /// Joint position in the parent frame (from the parent's CM), m.
    pub origin_in_parent: [f64; 3],
    /// Quaternion `[x, y, z, w]` of the child frame in the parent frame at `q = 0`.
    pub rotation_in_parent: [f64; 4],
    /// Joint axis in the link frame (normalized by the builder).
    pub axis: [f64; 3],
    /// Link CM from the joint, in the link frame (at `q = 0` for a prismatic joint), m.
    pub com_from_joint: [f64; 3],
    /// Mass, kg.
    pub mass: f64,
    /// Inertia about the CM in the link frame, row-major 3×3, kg·m².
    pub inertia: [[f64; 3]; 3],
    /// Position, velocity and effort limits.
    pub limits: JointLimits,
}

impl LinkSpec {
    /// A link with a principal-axes inertia `principal` (kg·m², diagonal in the link frame), the
    /// link frame parallel to the parent's at `q = 0`, no limits and the default joint name:
    /// the common case, written once (the fields are public for everything else).
    #[allow(clippy::too_many_arguments)]
    pub fn new(name: &str, parent: &str, kind: JointType, origin_in_parent: [f64; 3], axis: [f64; 3], com_from_joint: [f64; 3],
               mass: f64, principal: [f64; 3]) -> Self {
        LinkSpec {
            name: name.into(),
            parent: parent.into(),
            joint_name: None,
            kind,
            origin_in_parent,
            rotation_in_parent: [0.0, 0.0, 0.0, 1.0],
            axis,
            com_from_joint,
            mass,
            inertia: [[principal[0], 0.0, 0.0], [0.0, principal[1], 0.0], [0.0, 0.0, principal[2]]],
            limits: JointLimits::unlimited(),
        }
    }
}

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
    /// axis and the validated mass properties are known (by the builder). The joint name
    /// defaults to `<link>_joint`.
    pub(crate) fn from_spec(spec: LinkSpec, parent: usize, rotation: UnitQuaternion<f64>, axis: UnitVector3<f64>, mass: MassProperties) -> Link {
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
                dynamics: JointDynamics::default(),
            },
            com_from_joint: Vector3::from(spec.com_from_joint),
            mass,
        }
    }

    /// The spin moment `J_s = kᵀ I k` of the link about its joint axis `k` (link frame) when the
    /// link is a symmetric rotor about it — its CM on the axis (within 1e-9 m) and its inertia
    /// symmetric about the axis (`k` a principal axis and the two transverse moments equal,
    /// within 1e-9 relative), so that its spin changes nothing but its own angle — else `None`.
    /// The one test behind reaction-wheel and CMG-rotor detection.
    pub fn symmetric_rotor_moment(&self) -> Option<f64> {
        let axis = self.joint.axis.into_inner();
        let c = self.com_from_joint;
        if (c - axis * axis.dot(&c)).norm() > 1e-9 {
            return None;
        }
        let inertia = self.mass.inertia;
        let scale = inertia.norm().max(1e-300);
        let spin = axis.dot(&(inertia * axis));
        // The transverse part must be t (E − k kᵀ) with t the common transverse moment.
        let transverse = inertia - axis * axis.transpose() * spin;
        let t = 0.5 * transverse.trace();
        let iso = transverse - (nalgebra::Matrix3::identity() - axis * axis.transpose()) * t;
        ((inertia * axis - axis * spin).norm() <= 1e-9 * scale && iso.norm() <= 1e-9 * scale).then_some(spin)
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
