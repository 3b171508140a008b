//! Serial arms from Denavit–Hartenberg tables, in two conventions (see `docs/dh.md`).
//!
//! spacearm's own frames (docs/conventions.md) put every body frame's origin at the body's centre of
//! mass (CM). This module converts two common ways of writing down a serial arm into those
//! frames, producing ordinary [`LinkSpec`]s:
//!
//! * [`DhTable::Classic`] — the classic (distal) Denavit–Hartenberg convention: frame `i` is
//!   attached to link `i`, its `z` axis is the axis of joint `i+1`, and
//!   `ᶦ⁻¹Tᵢ = Rot_z(θᵢ) · Trans_z(dᵢ) · Trans_x(aᵢ) · Rot_x(αᵢ)`; joint `i` turns about (or
//!   slides along) `z_{i−1}`, adding `qᵢ` to `θᵢ` (revolute) or `dᵢ` (prismatic). Each link's
//!   CM and inertia are given in its DH frame `i`.
//! * [`DhTable::Paper`] — the convention of Wilde et al. (2018) §2 (also SPART's): the base is
//!   link 0; the link frame `ℒᵢ` has its origin at CM `i` and is aligned with the frame `𝒥ᵢ₊₁`
//!   of the next joint (whose `z` axis is that joint's axis); consecutive frames are related
//!   by the DH rotation `Rot_z(θᵢ + qᵢ) · Rot_x(αᵢ)`; each link gives `aᵢ` (joint `i` → CM `i`)
//!   and `bᵢ` (CM `i` → joint `i+1`), both in `ℒᵢ`.
//!
//! In both, joint 1's frame `𝒥₁` (for the classic convention: DH frame 0) is placed on the
//! parent body (normally the base) by an origin and a rotation given in the parent's CM frame.
//!
//! Conversion (both conventions): spacearm's frame of link `i` is the DH frame `i` (classic)
//! or `ℒᵢ` (paper) moved to the CM, so inertias need no rotation. Joint `i`'s rotation at
//! `q = 0` is `P · Rot_z(θᵢ) · Rot_x(αᵢ)` with `P` the pose of `𝒥₁` for `i = 1` and the
//! identity otherwise, and its axis in the child frame is `Rot_x(αᵢ)ᵀ ẑ = (0, sin αᵢ, cos αᵢ)`.
//! Classic: the joint sits at DH origin `i−1`, i.e. at `−c_{i−1}` from the parent's CM, and the
//! CM is `(aᵢ, dᵢ sin αᵢ, dᵢ cos αᵢ) + cᵢ` from the joint in frame `i`. Paper: the joint sits at
//! `b_{i−1}` and the CM at `aᵢ`.

use nalgebra::{UnitQuaternion, Vector3};

use crate::error::{ModelError, ModelField, ModelItem, Result};
use crate::model::joint::{JointLimits, JointType};
use crate::math::rotations::{unit_quaternion_from_xyzw, xyzw};
use crate::model::{LinkSpec, Model, ModelBuilder};

/// One row of a classic (distal) Denavit–Hartenberg table, with the link's mass properties.
#[derive(Debug, Clone, PartialEq)]
pub struct ClassicDhLink {
    /// Link name (default `link{i}`, `i` counted from 1).
    pub name: Option<String>,
    /// Joint name (default `joint{i}`).
    pub joint_name: Option<String>,
    /// Revolute (`q` adds to `θ`), prismatic (`q` adds to `d`) or fixed.
    pub kind: JointType,
    /// Offset along `z_{i−1}`, m (for a prismatic joint: the value at `q = 0`).
    pub d: f64,
    /// Angle about `z_{i−1}` from `x_{i−1}` to `xᵢ`, rad (for a revolute joint: at `q = 0`).
    pub theta: f64,
    /// Length of the common normal, along `xᵢ`, m.
    pub a: f64,
    /// Twist about `xᵢ` from `z_{i−1}` to `zᵢ`, rad.
    pub alpha: f64,
    /// Link CM in DH frame `i` (from its origin, on joint `i+1`'s axis), m.
    pub com: [f64; 3],
    /// Mass, kg.
    pub mass: f64,
    /// Inertia about the CM in DH frame `i`'s axes, kg·m².
    pub inertia: [[f64; 3]; 3],
    /// Joint limits.
    pub limits: JointLimits,
}

/// One link in the convention of Wilde et al. (2018) §2.
#[derive(Debug, Clone, PartialEq)]
pub struct PaperDhLink {
    /// Link name (default `link{i}`).
    pub name: Option<String>,
    /// Joint name (default `joint{i}`).
    pub joint_name: Option<String>,
    /// Revolute (about `z` of `𝒥ᵢ`), prismatic (along it) or fixed.
    pub kind: JointType,
    /// Rotation about `z` of `𝒥ᵢ` at `q = 0`, rad.
    pub theta: f64,
    /// Twist about the new `x` axis, rad.
    pub alpha: f64,
    /// `aᵢ`: from joint `i` to the link CM, in `ℒᵢ`, m.
    pub joint_to_com: [f64; 3],
    /// `bᵢ`: from the link CM to joint `i+1` (or the tip), in `ℒᵢ`, m.
    pub com_to_next: [f64; 3],
    /// Mass, kg.
    pub mass: f64,
    /// Inertia about the CM in `ℒᵢ` axes, kg·m².
    pub inertia: [[f64; 3]; 3],
    /// Joint limits.
    pub limits: JointLimits,
}

/// A DH table in one of the two conventions.
#[derive(Debug, Clone, PartialEq)]
pub enum DhTable {
    /// Classic (distal) Denavit–Hartenberg.
    Classic(Vec<ClassicDhLink>),
    /// Wilde et al. (2018) §2: CM-origin link frames, `aᵢ`/`bᵢ` vectors.
    Paper(Vec<PaperDhLink>),
}

impl DhTable {
    /// Number of links in the table.
    pub fn len(&self) -> usize {
        match self {
            DhTable::Classic(l) => l.len(),
            DhTable::Paper(l) => l.len(),
        }
    }

    /// Whether the table has no links.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// `"classic"` or `"paper"`.
    pub fn convention(&self) -> &'static str {
        match self {
            DhTable::Classic(_) => DhConvention::Classic,
            DhTable::Paper(_) => DhConvention::Paper,
        }
        .name()
    }
}

/// The two conventions of a DH table by name (a model file's `convention`, the doors'
/// `convention` argument).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DhConvention {
    /// `"classic"`: classic (distal) Denavit–Hartenberg.
    Classic,
    /// `"paper"`: Wilde et al. (2018) §2.
    Paper,
}

impl DhConvention {
    /// Every convention.
    pub const ALL: [DhConvention; 2] = [DhConvention::Classic, DhConvention::Paper];

    /// The convention named `name`, or `InvalidModel` naming the two.
    pub fn from_name(name: &str) -> Result<Self> {
        match Self::ALL.into_iter().find(|c| c.name() == name) {
            Some(c) => Ok(c),
            None => Err(crate::error::SpacearmError::InvalidModel(format!("DH convention must be 'classic' or 'paper', got '{name}'"))),
        }
    }

    /// The convention's name.
    pub fn name(self) -> &'static str {
        match self {
            DhConvention::Classic => "classic",
            DhConvention::Paper => "paper",
        }
    }
}

/// A serial arm described by a DH table and mounted on a body of the model.
#[derive(Debug, Clone, PartialEq)]
pub struct DhArm {
    /// The table.
    pub table: DhTable,
    /// Body the arm is mounted on (normally the base).
    pub parent: String,
    /// Origin of joint 1's frame `𝒥₁` (classic: DH frame 0) in the parent's CM frame, m.
    pub joint1_origin: [f64; 3],
    /// Orientation `[x, y, z, w]` of `𝒥₁` in the parent's frame (its `z` axis is joint 1's
    /// axis).
    pub joint1_rotation: [f64; 4],
    /// Extra offset of the tip point, in the last link's frame axes, m (classic: from DH frame
    /// `N`'s origin; paper: from joint `N+1`, i.e. after `b_N`).
    pub tool_offset: [f64; 3],
    /// Name of the point added at the tip (`None`: no point).
    pub tip_point: Option<String>,
}

/// Row `k`'s link name (default `link{k+1}`), the subject of its error messages and its item.
fn row_identity(k: usize, name: &Option<String>) -> (String, String, ModelItem) {
    let name = name.clone().unwrap_or_else(|| format!("link{}", k + 1));
    let who = format!("DH link {} ('{name}')", k + 1);
    (name, who, ModelItem::DhRow(k))
}

/// Joint `k` of a converted table: its kind, its position in the parent's CM frame, the child
/// frame's rotation `[x, y, z, w]` at `q = 0` and its axis in the child frame.
struct DhJoint {
    kind: JointType,
    origin: Vector3<f64>,
    rotation: [f64; 4],
    axis: [f64; 3],
}

/// The [`LinkSpec`] of row `k` (joint name default `joint{k+1}`), both conventions.
#[allow(clippy::too_many_arguments)]
fn row_link(k: usize, name: &str, parent: &str, joint_name: &Option<String>, joint: DhJoint, com_from_joint: [f64; 3], mass: f64, inertia: [[f64; 3]; 3], limits: JointLimits) -> LinkSpec {
    LinkSpec {
        name: name.to_string(),
        parent: parent.to_string(),
        joint_name: Some(joint_name.clone().unwrap_or_else(|| format!("joint{}", k + 1))),
        kind: joint.kind,
        origin_in_parent: joint.origin.into(),
        rotation_in_parent: joint.rotation,
        axis: joint.axis,
        com_from_joint,
        mass,
        inertia,
        limits,
    }
}

/// The links of a converted arm and its tip point.
#[derive(Debug, Clone)]
pub struct ConvertedArm {
    /// One spec per table row, parents first.
    pub links: Vec<LinkSpec>,
    /// `(point name, body name, offset from the body CM in its frame)` of the tip, if asked.
    pub tip: Option<(String, String, [f64; 3])>,
}

/// A DH parameter or vector must be finite; `item` is the arm or the row.
fn check_finite(item: ModelItem, field: ModelField, who: &str, what: &str, values: &[f64]) -> std::result::Result<(), ModelError> {
    if let Some(v) = values.iter().find(|v| !v.is_finite()) {
        return Err(ModelError::new(item, field, format!("{who}: {what} must be finite, got {v}")));
    }
    Ok(())
}

/// `(sin α, cos α)` with rounding residue below 1e-15 set to zero, so that a twist of
/// `π/2` (not exactly representable) gives exactly `(1, 0)`.
fn sin_cos(alpha: f64) -> (f64, f64) {
    let (s, c) = alpha.sin_cos();
    let snap = |v: f64| if v.abs() < 1e-15 { 0.0 } else { v };
    (snap(s), snap(c))
}

/// Rotation `P · Rot_z(θ) · Rot_x(α)` and child-frame axis `Rot_x(α)ᵀ ẑ = (0, sin α, cos α)`.
fn dh_rotation(p: &UnitQuaternion<f64>, theta: f64, alpha: f64) -> ([f64; 4], [f64; 3]) {
    let r = p * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), theta) * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), alpha);
    let (s, c) = sin_cos(alpha);
    (xyzw(&r), [0.0, s, c])
}

impl DhArm {
    /// Convert the table into link specs in spacearm's CM-origin frames (module docs). Only the
    /// table's own values are checked here (finite parameters, a unit mounting rotation, at
    /// least one row); the links themselves are checked by the builder they are added to.
    pub fn convert(&self) -> std::result::Result<ConvertedArm, ModelError> {
        let arm = ModelItem::DhArm;
        if self.table.is_empty() {
            return Err(ModelError::new(
                arm,
                ModelField::DhParameters,
                format!("the {} DH table has no links; give at least one", self.table.convention()),
            ));
        }
        check_finite(arm, ModelField::Origin, "DH arm", "joint1_origin", &self.joint1_origin)?;
        check_finite(arm, ModelField::Offset, "DH arm", "tool_offset", &self.tool_offset)?;
        let p1 = unit_quaternion_from_xyzw("DH arm: joint1_rotation", &self.joint1_rotation)
            .map_err(|e| ModelError::new(arm, ModelField::Rotation, e.to_string()))?;
        let identity = UnitQuaternion::identity();
        let mut links = Vec::with_capacity(self.table.len());
        let mut parent = self.parent.clone();
        // Joint i's position in the parent's CM frame.
        let mut origin = Vector3::from(self.joint1_origin);
        let last_to_tip: Vector3<f64>;
        match &self.table {
            DhTable::Classic(rows) => {
                let mut to_next = Vector3::zeros();
                for (k, row) in rows.iter().enumerate() {
                    let (name, who, item) = row_identity(k, &row.name);
                    check_finite(item, ModelField::DhParameters, &who, "d, theta, a and alpha", &[row.d, row.theta, row.a, row.alpha])?;
                    check_finite(item, ModelField::DhParameters, &who, "com", &row.com)?;
                    let p = if k == 0 { &p1 } else { &identity };
                    let (rotation, axis) = dh_rotation(p, row.theta, row.alpha);
                    let (s, c) = sin_cos(row.alpha);
                    let joint_to_origin = Vector3::new(row.a, row.d * s, row.d * c);
                    let com = Vector3::from(row.com);
                    let joint = DhJoint { kind: row.kind, origin, rotation, axis };
                    links.push(row_link(k, &name, &parent, &row.joint_name, joint, (joint_to_origin + com).into(), row.mass, row.inertia, row.limits));
                    // Joint i+1 sits at DH origin i, i.e. at -c_i from the CM.
                    to_next = Vector3::zeros() - com;
                    origin = to_next;
                    parent = name;
                }
                last_to_tip = to_next;
            }
            DhTable::Paper(rows) => {
                let mut to_next = Vector3::zeros();
                for (k, row) in rows.iter().enumerate() {
                    let (name, who, item) = row_identity(k, &row.name);
                    check_finite(item, ModelField::DhParameters, &who, "theta and alpha", &[row.theta, row.alpha])?;
                    check_finite(item, ModelField::DhParameters, &who, "joint_to_com", &row.joint_to_com)?;
                    check_finite(item, ModelField::DhParameters, &who, "com_to_next", &row.com_to_next)?;
                    let p = if k == 0 { &p1 } else { &identity };
                    let (rotation, axis) = dh_rotation(p, row.theta, row.alpha);
                    let joint = DhJoint { kind: row.kind, origin, rotation, axis };
                    links.push(row_link(k, &name, &parent, &row.joint_name, joint, row.joint_to_com, row.mass, row.inertia, row.limits));
                    to_next = Vector3::from(row.com_to_next);
                    origin = to_next;
                    parent = name;
                }
                last_to_tip = to_next;
            }
        }
        let tip = self
            .tip_point
            .as_ref()
            .map(|n| (n.clone(), parent.clone(), (last_to_tip + Vector3::from(self.tool_offset)).into()));
        Ok(ConvertedArm { links, tip })
    }

    /// Add the arm's links (and tip point) to a builder.
    pub fn add_to(&self, builder: &mut ModelBuilder) -> Result<()> {
        let arm = self.convert()?;
        for spec in arm.links {
            builder.add_link(spec)?;
        }
        if let Some((name, body, offset)) = arm.tip {
            builder.add_point(&name, &body, offset)?;
        }
        Ok(())
    }
}

/// A whole model: a base and one serial arm given by a DH table. The tip point, if named,
/// becomes the end effector; `initial_q` defaults to zeros.
pub fn model_from_dh(
    name: &str,
    base_name: &str,
    base_mass: f64,
    base_inertia: [[f64; 3]; 3],
    arm: &DhArm,
    initial_q: Option<Vec<f64>>,
) -> Result<Model> {
    let mut b = ModelBuilder::new(name, base_name, base_mass, base_inertia)?;
    arm.add_to(&mut b)?;
    if let Some(tip) = &arm.tip_point {
        b.set_end_effector(tip);
    }
    if let Some(q) = initial_q {
        b.set_initial_q(q);
    }
    Ok(b.build()?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_convention_reads_back_from_its_name_and_an_unknown_one_is_refused() {
        for c in DhConvention::ALL {
            assert_eq!(DhConvention::from_name(c.name()).unwrap(), c);
        }
        assert_eq!(DhConvention::Classic.name(), "classic");
        assert_eq!(DhTable::Paper(Vec::new()).convention(), "paper");
        let err = DhConvention::from_name("craig").unwrap_err();
        assert_eq!(err.to_string(), "invalid model: DH convention must be 'classic' or 'paper', got 'craig'");
    }
    use crate::model::data::Data;
    use crate::algorithms::kinematics::{forward_kinematics, point_position};
    use crate::model::presets;
    use nalgebra::{Matrix3, Matrix4, Rotation3};

    fn bar(m: f64, l: f64, w: f64) -> [[f64; 3]; 3] {
        let iyy = m * (l * l + w * w) / 12.0;
        [[m * w * w / 6.0, 0.0, 0.0], [0.0, iyy, 0.0], [0.0, 0.0, iyy]]
    }

    #[allow(clippy::too_many_arguments)]
    fn classic(kind: JointType, d: f64, theta: f64, a: f64, alpha: f64, com: [f64; 3], mass: f64, inertia: [[f64; 3]; 3]) -> ClassicDhLink {
        ClassicDhLink { name: None, joint_name: None, kind, d, theta, a, alpha, com, mass, inertia, limits: JointLimits::unlimited() }
    }

    fn arm(table: DhTable, origin: [f64; 3]) -> DhArm {
        DhArm {
            table,
            parent: "base".into(),
            joint1_origin: origin,
            joint1_rotation: [0.0, 0.0, 0.0, 1.0],
            tool_offset: [0.0; 3],
            tip_point: Some("end_effector".into()),
        }
    }

    fn planar4_classic() -> Model {
        let rows = (0..4).map(|_| classic(JointType::Revolute, 0.0, 0.0, 1.0, 0.0, [-0.5, 0.0, 0.0], 10.0, bar(10.0, 1.0, 0.05))).collect();
        let a = arm(DhTable::Classic(rows), [0.25, 0.0, 0.0]);
        let q0 = presets::planar4().initial_q().to_vec();
        model_from_dh("planar4", "base", 100.0, Matrix3::from_diagonal_element(4.1667).into(), &a, Some(q0)).unwrap()
    }

    fn mass_matrix(model: &Model, x: &[f64]) -> nalgebra::DMatrix<f64> {
        let mut data = Data::new(model);
        crate::algorithms::crba::crba(model, &mut data, x).unwrap().clone()
    }

    #[test]
    fn classic_planar4_equals_the_preset() {
        let dh = planar4_classic();
        let preset = presets::planar4();
        for q in [[0.0, 0.0, 0.0, 0.0], [0.3, -1.2, 2.0, 0.7], [-2.5, 0.4, -0.1, 3.0]] {
            let mut x = vec![0.1, -0.2, 0.3, 0.2, -0.1, 0.3, 0.0];
            let n = (x[3] * x[3] + x[4] * x[4] + x[5] * x[5] + 1.0f64).sqrt();
            x[3] /= n;
            x[4] /= n;
            x[5] /= n;
            x[6] = 1.0 / n;
            x.extend_from_slice(&q);
            let (h1, h2) = (mass_matrix(&dh, &x), mass_matrix(&preset, &x));
            assert!((h1 - h2).abs().max() < 1e-12);
        }
    }

    /// Standard DH product with the base at the origin, aligned.
    fn dh_product(rows: &[(f64, f64, f64, f64)], q: &[f64], t0: Matrix4<f64>) -> Matrix4<f64> {
        let mut t = t0;
        for (&(d, theta, a, alpha), &qi) in rows.iter().zip(q) {
            let (st, ct) = (theta + qi).sin_cos();
            let (sa, ca) = alpha.sin_cos();
            t *= Matrix4::new(ct, -st * ca, st * sa, a * ct, st, ct * ca, -ct * sa, a * st, 0.0, sa, ca, d, 0.0, 0.0, 0.0, 1.0);
        }
        t
    }

    #[test]
    fn classic_spatial_arm_matches_the_dh_product() {
        // A PUMA-like table with a mounting rotation and a tool offset.
        let rows = [(0.3, 0.1, 0.0, std::f64::consts::FRAC_PI_2), (0.0, -0.4, 0.6, 0.0), (0.15, 0.2, 0.05, -std::f64::consts::FRAC_PI_2), (0.5, 0.0, 0.0, 1.0)];
        let table = rows.iter().map(|&(d, th, a, al)| classic(JointType::Revolute, d, th, a, al, [0.01, -0.02, 0.03], 2.0, bar(2.0, 0.3, 0.05))).collect();
        let mut a = arm(DhTable::Classic(table), [0.2, 0.1, -0.3]);
        let p = UnitQuaternion::from_euler_angles(0.3, -0.2, 0.9);
        a.joint1_rotation = xyzw(&p);
        a.tool_offset = [0.0, 0.0, 0.1];
        let m = model_from_dh("puma", "base", 50.0, Matrix3::from_diagonal_element(5.0).into(), &a, None).unwrap();
        let mut t0 = Matrix4::identity();
        t0.fixed_view_mut::<3, 3>(0, 0).copy_from(p.to_rotation_matrix().matrix());
        t0.fixed_view_mut::<3, 1>(0, 3).copy_from(&Vector3::new(0.2, 0.1, -0.3));
        let q = [0.4, -0.7, 1.1, 0.25];
        let t = dh_product(&rows, &q, t0);
        let tip = t * nalgebra::Vector4::new(0.0, 0.0, 0.1, 1.0);
        let mut x = vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0];
        x.extend_from_slice(&q);
        let mut data = Data::new(&m);
        forward_kinematics(&m, &mut data, &x).unwrap();
        let pt = &m.points()[m.end_effector().unwrap()];
        let got = point_position(&data, pt.body, &pt.offset);
        assert!((got - tip.xyz()).norm() < 1e-12, "{got} vs {tip}");
        // The last link's frame is DH frame 4.
        let r4 = Rotation3::from_matrix_unchecked(t.fixed_view::<3, 3>(0, 0).into_owned());
        assert!((data.body_to_world[4] - r4.matrix()).abs().max() < 1e-12);
    }

    #[test]
    fn prismatic_classic_joint_slides_along_z() {
        let rows = vec![
            classic(JointType::Prismatic, 0.5, 0.3, 0.2, 0.7, [0.0, 0.0, -0.1], 1.0, bar(1.0, 0.2, 0.05)),
            classic(JointType::Revolute, 0.1, 0.0, 0.3, 0.0, [-0.15, 0.0, 0.0], 1.0, bar(1.0, 0.3, 0.05)),
        ];
        let a = arm(DhTable::Classic(rows), [0.0; 3]);
        let m = model_from_dh("p", "base", 10.0, Matrix3::from_diagonal_element(1.0).into(), &a, None).unwrap();
        let q = [0.35, 0.8];
        // Prismatic joint 1: d1 + q1; revolute joint 2: theta2 + q2.
        let t = dh_product(&[(0.5 + q[0], 0.3, 0.2, 0.7), (0.1, 0.0, 0.3, 0.0)], &[0.0, q[1]], Matrix4::identity());
        let mut x = vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0];
        x.extend_from_slice(&q);
        let mut data = Data::new(&m);
        forward_kinematics(&m, &mut data, &x).unwrap();
        let pt = &m.points()[0];
        let got = point_position(&data, pt.body, &pt.offset);
        assert!((got - t.fixed_view::<3, 1>(0, 3)).norm() < 1e-12);
    }

    #[test]
    fn paper_convention_equals_the_presets() {
        // planar4: frames aligned, a_i = b_i = (L/2, 0, 0).
        let rows = (0..4)
            .map(|_| PaperDhLink {
                name: None,
                joint_name: None,
                kind: JointType::Revolute,
                theta: 0.0,
                alpha: 0.0,
                joint_to_com: [0.5, 0.0, 0.0],
                com_to_next: [0.5, 0.0, 0.0],
                mass: 10.0,
                inertia: bar(10.0, 1.0, 0.05),
                limits: JointLimits::unlimited(),
            })
            .collect();
        let a = arm(DhTable::Paper(rows), [0.25, 0.0, 0.0]);
        let m = model_from_dh("planar4", "base", 100.0, Matrix3::from_diagonal_element(4.1667).into(), &a, None).unwrap();
        let preset = presets::planar4();
        let mut x = vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.3, -0.4, 1.3, 2.0];
        assert!((mass_matrix(&m, &x) - mass_matrix(&preset, &x)).abs().max() < 1e-12);
        x[7] = -1.0;
        assert!((mass_matrix(&m, &x) - mass_matrix(&preset, &x)).abs().max() < 1e-12);
        assert_eq!(m.points()[0].offset, preset.points()[0].offset);
    }

    #[test]
    fn bad_tables_are_rejected_with_the_link_named() {
        let a = arm(DhTable::Classic(vec![]), [0.0; 3]);
        assert!(a.convert().unwrap_err().to_string().contains("no links"));
        let a = arm(DhTable::Classic(vec![classic(JointType::Revolute, f64::NAN, 0.0, 1.0, 0.0, [0.0; 3], 1.0, bar(1.0, 1.0, 0.1))]), [0.0; 3]);
        assert!(a.convert().unwrap_err().to_string().contains("DH link 1 ('link1')"));
        let mut a = arm(DhTable::Classic(vec![classic(JointType::Revolute, 0.0, 0.0, 1.0, 0.0, [0.0; 3], -1.0, bar(1.0, 1.0, 0.1))]), [0.0; 3]);
        let err = model_from_dh("m", "base", 1.0, Matrix3::identity().into(), &a, None).unwrap_err().to_string();
        assert!(err.contains("link 'link1'") && err.contains(">= 0"), "{err}");
        a.joint1_rotation = [0.0, 0.0, 0.0, 2.0];
        assert!(a.convert().unwrap_err().to_string().contains("unit quaternion"));
    }
}
