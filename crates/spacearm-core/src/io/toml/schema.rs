//! The TOML model file as serde reads it: one struct per table (`[model]`, `[base]`,
//! `[[link]]`, `[[point]]`, `[[geometry]]`, `[[slosh]]`, `[[panel]]`, `[[beam]]`, `[[cmg]]`, `[dh]`), each
//! value [`Spanned`] so the reader can point at it; the schema's words are docs/model-format.md.
//! Read by [`super::read`]; written by [`super::write`].

use serde::Deserialize;
use toml::{Spanned, Value};

use crate::model::joint::JointType;

/// The file format version written by [`model_to_toml`](super::write::model_to_toml) and accepted by the reader
/// (`[model] format_version`, optional).
pub const FORMAT_VERSION: i64 = 1;

// ---- the document, as serde sees it --------------------------------------------------------

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileDoc {
    pub(super) model: Spanned<ModelDoc>,
    pub(super) base: Spanned<BaseDoc>,
    #[serde(default)]
    pub(super) link: Vec<Spanned<LinkDoc>>,
    #[serde(default)]
    pub(super) point: Vec<Spanned<PointDoc>>,
    #[serde(default)]
    pub(super) geometry: Vec<Spanned<GeometryDoc>>,
    #[serde(default)]
    pub(super) slosh: Vec<Spanned<SloshDoc>>,
    #[serde(default)]
    pub(super) panel: Vec<Spanned<PanelDoc>>,
    #[serde(default)]
    pub(super) beam: Vec<Spanned<BeamDoc>>,
    /// `[[cmg]]` tables: control-moment gyros, read straight into the core's
    /// [`crate::model::cmg::CmgSpec`] (docs/cmg.md).
    #[serde(default)]
    pub(super) cmg: Vec<Spanned<crate::model::cmg::CmgSpec>>,
    /// [`crate::model::gripper::GripperSpec`] (docs/contact.md, "Grippers").
    #[serde(default)]
    pub(super) gripper: Vec<Spanned<crate::model::gripper::GripperSpec>>,
    pub(super) dh: Option<Spanned<DhDoc>>,
    pub(super) end_effector: Option<Spanned<String>>,
    pub(super) initial_q: Option<Spanned<Vec<f64>>>,
}

/// A `[[slosh]]` table: an equivalent mechanical slosh model (docs/flexibility.md), added as
/// passive links by [`ModelBuilder::add_slosh`].
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SloshDoc {
    pub(super) name: Spanned<String>,
    pub(super) parent: Option<Spanned<String>>,
    pub(super) model: Spanned<String>,
    pub(super) mass: Spanned<f64>,
    pub(super) position: Spanned<[f64; 3]>,
    pub(super) axis: Spanned<[f64; 3]>,
    pub(super) hinge: Option<Spanned<[f64; 3]>>,
    pub(super) length: Option<Spanned<f64>>,
    pub(super) stiffness: Option<Spanned<f64>>,
    pub(super) frequency: Option<Spanned<f64>>,
    #[serde(default)]
    pub(super) damping: f64,
}

/// A `[[panel]]` table: a hinged rigid panel (docs/flexibility.md), added by
/// [`crate::model::appendage::panel_parts`].
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PanelDoc {
    pub(super) name: Spanned<String>,
    pub(super) parent: Option<Spanned<String>>,
    pub(super) hinge_position: [f64; 3],
    pub(super) hinge_axis: [f64; 3],
    pub(super) direction: [f64; 3],
    pub(super) mass: f64,
    pub(super) size: Option<[f64; 3]>,
    pub(super) inertia: Option<Value>,
    pub(super) com_distance: Option<f64>,
    pub(super) stiffness: Option<f64>,
    pub(super) frequency: Option<f64>,
    #[serde(default)]
    pub(super) damping: f64,
    #[serde(default)]
    pub(super) rest: f64,
}

/// A `[[beam]]` table: a flexible beam by the rigid finite element method
/// (docs/flexibility.md), added by [`crate::model::appendage::beam_parts`].
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub(super) struct BeamDoc {
    pub(super) name: Spanned<String>,
    pub(super) parent: Option<Spanned<String>>,
    pub(super) root_position: [f64; 3],
    pub(super) axis: [f64; 3],
    pub(super) length: f64,
    pub(super) segments: usize,
    pub(super) EI: Value,
    pub(super) bending_axes: Option<Vec<[f64; 3]>>,
    pub(super) GJ: Option<f64>,
    pub(super) rho_A: f64,
    #[serde(default)]
    pub(super) rho_J: f64,
    pub(super) damping: Option<f64>,
    pub(super) damping_ratio: Option<f64>,
}

/// A joint table's `compliant = { stiffness, rotor_inertia, damping, gear_ratio }` (Spong's
/// elastic joint, [`crate::model::appendage::compliant_parts`]).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct CompliantDoc {
    pub(super) stiffness: f64,
    pub(super) rotor_inertia: f64,
    #[serde(default)]
    pub(super) damping: f64,
    pub(super) gear_ratio: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ModelDoc {
    pub(super) name: Spanned<String>,
    pub(super) format_version: Option<Spanned<i64>>,
    pub(super) end_effector: Option<Spanned<String>>,
    pub(super) initial_q: Option<Spanned<Vec<f64>>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct BaseDoc {
    pub(super) name: Option<Spanned<String>>,
    pub(super) mass: Spanned<f64>,
    pub(super) inertia: Spanned<Value>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct LinkDoc {
    pub(super) name: Spanned<String>,
    pub(super) parent: Spanned<String>,
    pub(super) joint: Spanned<JointDoc>,
    pub(super) com: Spanned<[f64; 3]>,
    pub(super) mass: Spanned<f64>,
    pub(super) inertia: Spanned<Value>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct JointDoc {
    #[serde(rename = "type")]
    pub(super) kind: Spanned<JointType>,
    pub(super) name: Option<Spanned<String>>,
    pub(super) origin: Spanned<[f64; 3]>,
    pub(super) rotation: Option<Spanned<[f64; 4]>>,
    pub(super) rpy: Option<Spanned<[f64; 3]>>,
    pub(super) axis: Option<Spanned<[f64; 3]>>,
    pub(super) limits: Option<Spanned<LimitsDoc>>,
    /// The joint's passive dynamics (docs/flexibility.md): motor, spring, damper.
    pub(super) actuated: Option<Spanned<bool>>,
    pub(super) stiffness: Option<Spanned<f64>>,
    pub(super) damping: Option<Spanned<f64>>,
    pub(super) rest: Option<Spanned<f64>>,
    /// Spong's elastic joint: a motor rotor and a series spring (docs/flexibility.md).
    pub(super) compliant: Option<Spanned<CompliantDoc>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct LimitsDoc {
    pub(super) lower: Option<f64>,
    pub(super) upper: Option<f64>,
    pub(super) velocity: Option<f64>,
    pub(super) effort: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PointDoc {
    pub(super) name: Spanned<String>,
    pub(super) body: Spanned<String>,
    pub(super) offset: Spanned<[f64; 3]>,
}

/// A `[[geometry]]` table (docs/geometry.md): `shape` says which dimension keys it takes.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct GeometryDoc {
    pub(super) name: Option<Spanned<String>>,
    pub(super) body: Spanned<String>,
    pub(super) role: Option<Spanned<String>>,
    pub(super) shape: Spanned<String>,
    pub(super) size: Option<Spanned<[f64; 3]>>,
    pub(super) radius: Option<Spanned<f64>>,
    pub(super) length: Option<Spanned<f64>>,
    pub(super) file: Option<Spanned<String>>,
    pub(super) scale: Option<Spanned<[f64; 3]>>,
    pub(super) origin: Option<Spanned<[f64; 3]>>,
    pub(super) rotation: Option<Spanned<[f64; 4]>>,
    pub(super) rpy: Option<Spanned<[f64; 3]>>,
    pub(super) rgba: Option<Spanned<[f64; 4]>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct DhDoc {
    pub(super) convention: Spanned<crate::io::dh::DhConvention>,
    pub(super) joint1_origin: Option<Spanned<[f64; 3]>>,
    pub(super) joint1_rotation: Option<Spanned<[f64; 4]>>,
    pub(super) joint1_rpy: Option<Spanned<[f64; 3]>>,
    pub(super) tool_offset: Option<Spanned<[f64; 3]>>,
    pub(super) tip_point: Option<Spanned<String>>,
    #[serde(default)]
    pub(super) link: Vec<Spanned<DhLinkDoc>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct DhLinkDoc {
    pub(super) name: Option<Spanned<String>>,
    pub(super) joint_name: Option<Spanned<String>>,
    #[serde(rename = "type")]
    pub(super) kind: Option<Spanned<JointType>>,
    pub(super) d: Option<Spanned<f64>>,
    pub(super) theta: Option<Spanned<f64>>,
    pub(super) a: Option<Spanned<f64>>,
    pub(super) alpha: Option<Spanned<f64>>,
    pub(super) com: Option<Spanned<[f64; 3]>>,
    pub(super) joint_to_com: Option<Spanned<[f64; 3]>>,
    pub(super) com_to_next: Option<Spanned<[f64; 3]>>,
    pub(super) mass: Spanned<f64>,
    pub(super) inertia: Spanned<Value>,
    pub(super) limits: Option<Spanned<LimitsDoc>>,
}
