//! Flexible appendages and compliant joints as plain passive joints (docs/flexibility.md):
//!
//! - [`panel_parts`]: a **hinged rigid panel**, a plate on one passive revolute joint with a
//!   torsional spring. The hinge sits at `hinge_position` (parent frame, from the parent's CM),
//!   turns about `hinge_axis`; the plate extends from the hinge line along `direction`
//!   (perpendicular to the hinge), its CM at `com_distance·direction` from the hinge point
//!   (`length/2` for a uniform plate of `size = (length, width, thickness)`: length along
//!   `direction`, width along the hinge, thickness along `direction × hinge_axis`). A `frequency`
//!   ω gives `k = I_h ω²`, `I_h` the plate's moment about the hinge line (the frequency on a
//!   clamped parent).
//! - [`beam_parts`]: a **flexible beam by the rigid finite element method** (Wittbrodt,
//!   Adamiec-Wójcik & Wojciech, *Dynamics of Flexible Multibody Systems: Rigid Finite Element
//!   Method*, Springer 2006, ch. 4). The beam of length `L` is cut into `N` primary segments of
//!   length `l = L/N`; a spring–damping element sits at the middle of each, at `(i − ½) l` from the
//!   root (`i = 1..N`), and the rigid elements lie between them: a root half-element `[0, l/2]`
//!   fixed to the parent (`<name>_root`), `N − 1` elements of length `l` and a tip half-element of
//!   length `l/2` (`<name>_1 … <name>_N`). Each station has a passive revolute joint per bending
//!   axis with `k = EI/l` and, with `GJ`, one about the beam axis with `k = GJ/l`. Element `j` of
//!   length `s` has mass `ρA s` at its middle and the inertia
//!   `(ρA s³/12 + ρJ s/2)(E − a aᵀ) + ρJ s a aᵀ` about it (`ρJ`: mass moment of inertia per length
//!   about the axis; `ρJ/2` per length about each transverse axis is the rotary inertia of an
//!   axisymmetric section, neglected by Euler–Bernoulli, which keeps each element physical). The rigid-body dynamics of the chain is exact, so the centrifugal (geometric)
//!   stiffening of a spinning beam is kept.
//! - [`compliant_parts`]: a **compliant (elastic) joint** in the manner of Spong (1987): the link's
//!   joint becomes an actuated motor joint carrying a rotor body (`<link>_rotor`, axial inertia
//!   `n² B`, the rotor inertia reflected through the gear ratio `n`) and, after it on the same axis,
//!   a passive joint `<joint>_deflection` whose coordinate `δ = q_link − θ` carries the series
//!   spring `−k δ − c δ̇` (`q_link = θ + δ`).
//!
//! Every part is checked again by the builder's rules when it is added.

use crate::error::{ModelError, ModelField, ModelItem};
use crate::model::builder::{LinkSpec, ModelBuilder};
use crate::model::geometry::{GeometryRole, GeometrySpec, Shape};
use crate::model::joint::{JointDynamics, JointLimits, JointType};
use crate::model::validate::{non_negative, positive, stiffness_or_frequency, PartRules};
use crate::math::spatial::{cross3 as cross, dot3 as dot, unit3 as normalized};

/// The first Euler–Bernoulli cantilever eigenvalue `β₁L` (`cos βL cosh βL = −1`).
pub const CANTILEVER_BETA1_L: f64 = 1.875_104_068_711_961;

/// The links (each with its joint's dynamics), points and shapes an appendage adds, in order.
#[derive(Debug, Clone, Default)]
pub struct Parts {
    /// Links in the order they are added, each with its joint's passive dynamics.
    pub links: Vec<(LinkSpec, JointDynamics)>,
    /// Named points `(name, body, offset)` (body frame, from its CM).
    pub points: Vec<(String, String, [f64; 3])>,
    /// Visual shapes.
    pub geometries: Vec<GeometrySpec>,
}

/// The restoring spring of a panel's hinge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Restoring {
    /// The hinge stiffness, N·m/rad.
    Stiffness(f64),
    /// The frequency on a clamped parent, rad/s (`k = I_h ω²`).
    Frequency(f64),
}

impl Restoring {
    /// From a door's options `stiffness` and `frequency` (one of them; [`stiffness_or_frequency`]).
    pub fn from_options(stiffness: Option<f64>, frequency: Option<f64>) -> Result<Self, String> {
        stiffness_or_frequency(stiffness, frequency, Restoring::Stiffness, Restoring::Frequency)
    }
}

/// The panel's mass distribution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PanelBody {
    /// A uniform plate `(length, width, thickness)`, m (module docs), drawn as a box.
    Size([f64; 3]),
    /// A CM at `com_distance` along `direction` from the hinge and the inertia about the CM, in
    /// the parent's axes at `q = 0`.
    Inertia {
        /// The CM's distance from the hinge along `direction`, m.
        com_distance: f64,
        /// The inertia about the CM in the parent's axes at `q = 0`, kg·m².
        inertia: [[f64; 3]; 3],
    },
}

impl PanelBody {
    /// From a door's options: `size`, or `inertia` with `com_distance` (the one rule of every
    /// door; the door prefixes the panel's name to the message).
    pub fn from_options(size: Option<[f64; 3]>, inertia: Option<[[f64; 3]; 3]>, com_distance: Option<f64>) -> Result<Self, String> {
        match (size, inertia, com_distance) {
            (Some(s), None, None) => Ok(PanelBody::Size(s)),
            (None, Some(inertia), Some(com_distance)) => Ok(PanelBody::Inertia { com_distance, inertia }),
            _ => Err("give size (length, width, thickness), or inertia and com_distance".into()),
        }
    }
}

/// Everything [`panel_parts`] needs (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct PanelSpec {
    /// Link name; the joint is `<name>_hinge`.
    pub name: String,
    /// The body carrying the hinge.
    pub parent: String,
    /// The hinge point, parent frame, from the parent's CM, m.
    pub hinge_position: [f64; 3],
    /// The hinge axis, parent frame.
    pub hinge_axis: [f64; 3],
    /// From the hinge line into the panel at `q = 0` (perpendicular to the hinge), parent frame.
    pub direction: [f64; 3],
    /// The plate's mass distribution.
    pub body: PanelBody,
    /// Mass, kg (> 0).
    pub mass: f64,
    /// The hinge spring.
    pub restoring: Restoring,
    /// Hinge damping, N·m·s/rad.
    pub damping: f64,
    /// The spring's rest angle, rad.
    pub rest: f64,
}

/// Damping of a beam's joints.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BeamDamping {
    /// The same viscous coefficient on every joint, N·m·s/rad.
    PerJoint(f64),
    /// Stiffness-proportional damping `c = (2ζ/ω₁) k` per joint, `ω₁` the first clamped
    /// Euler–Bernoulli frequency of that joint's family: `(β₁L)² √(EI/(ρA L⁴))` in bending,
    /// `(π/2) √(GJ/(ρJ L²))` in torsion; the first clamped mode then has the ratio `ζ`.
    Ratio(f64),
}

impl BeamDamping {
    /// From a door's options `damping` (per joint) and `damping_ratio`: at most one of them,
    /// none is no damping (the one rule of every door; the door prefixes the beam's name).
    pub fn from_options(damping: Option<f64>, damping_ratio: Option<f64>) -> Result<Self, String> {
        match (damping, damping_ratio) {
            (Some(c), None) => Ok(BeamDamping::PerJoint(c)),
            (None, Some(z)) => Ok(BeamDamping::Ratio(z)),
            (None, None) => Ok(BeamDamping::PerJoint(0.0)),
            _ => Err("give damping or damping_ratio, not both".into()),
        }
    }
}

/// Everything [`beam_parts`] needs (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct BeamSpec {
    /// Name stem: links `<name>_root`, `<name>_1 … <name>_N`, point `<name>_tip`.
    pub name: String,
    /// The body the root is clamped to.
    pub parent: String,
    /// The root point, parent frame, from the parent's CM, m.
    pub root_position: [f64; 3],
    /// Along the beam, root to tip, parent frame.
    pub axis: [f64; 3],
    /// Length `L`, m.
    pub length: f64,
    /// Number of primary segments `N` (≥ 1).
    pub segments: usize,
    /// Bending axes (perpendicular to `axis`, parent frame) with their `EI`, N·m², in the
    /// order of the joints at each station (one or two).
    pub bending: Vec<([f64; 3], f64)>,
    /// Torsional stiffness `GJ`, N·m² (a twist joint per station), or none.
    pub torsion: Option<f64>,
    /// Mass per length `ρA`, kg/m.
    pub rho_a: f64,
    /// Mass moment of inertia per length about the axis `ρJ`, kg·m (needed with `torsion`).
    pub rho_j: f64,
    /// Joint damping.
    pub damping: BeamDamping,
}

/// A compliant joint's series elasticity (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CompliantSpec {
    /// The series spring `k`, N·m/rad, on the link side (> 0).
    pub stiffness: f64,
    /// The rotor's inertia about its axis `B`, kg·m², on the motor side (> 0).
    pub rotor_inertia: f64,
    /// The spring's damping, N·m·s/rad.
    pub damping: f64,
    /// Gear ratio `n` (motor angle = `n θ`, ≥ 1 not required, > 0).
    pub gear_ratio: f64,
}

fn scaled(a: &[f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// `α E + β a aᵀ` (a unit).
fn axial(a: &[f64; 3], alpha: f64, beta: f64) -> [[f64; 3]; 3] {
    let mut m = [[0.0; 3]; 3];
    for (i, row) in m.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = beta * a[i] * a[j] + if i == j { alpha } else { 0.0 };
        }
    }
    m
}

fn link(name: String, parent: String, joint: String, kind: JointType, origin: [f64; 3], axis: [f64; 3], com: [f64; 3], mass: f64, inertia: [[f64; 3]; 3]) -> LinkSpec {
    LinkSpec {
        name,
        parent,
        joint_name: Some(joint),
        kind,
        origin_in_parent: origin,
        rotation_in_parent: [0.0, 0.0, 0.0, 1.0],
        axis,
        com_from_joint: com,
        mass,
        inertia,
        limits: JointLimits::unlimited(),
    }
}

/// The quaternion `[x, y, z, w]` of the rotation whose columns are `c0, c1, c2` (right-handed,
/// orthonormal), by the one rotation home (`math::rotations::xyzw_from_matrix`).
fn quat_from_columns(c0: &[f64; 3], c1: &[f64; 3], c2: &[f64; 3]) -> [f64; 4] {
    let m = nalgebra::Matrix3::new(c0[0], c1[0], c2[0], c0[1], c1[1], c2[1], c0[2], c1[2], c2[2]);
    crate::math::rotations::xyzw_from_matrix(&m)
}

/// A hinged rigid panel (module docs): one link on a passive revolute joint `<name>_hinge`, and
/// a box shape for a uniform plate.
pub fn panel_parts(spec: &PanelSpec, item: ModelItem) -> Result<Parts, ModelError> {
    let who = format!("panel '{}'", spec.name);
    let bad = |field: ModelField, msg: String| Err(ModelError::new(item, field, format!("{who}: {msg}")));
    let rules = PartRules { item, who: &who };
    rules.positive(ModelField::Mass, "mass", " kg", spec.mass)?;
    let hinge = rules.direction("hinge_axis", &spec.hinge_axis)?;
    let dir = rules.direction("direction", &spec.direction)?;
    if dot(&hinge, &dir).abs() > 1e-9 {
        return bad(ModelField::Axis, format!("direction {dir:?} must be perpendicular to hinge_axis {hinge:?}"));
    }
    if !(non_negative(spec.damping) && spec.rest.is_finite()) {
        return bad(ModelField::JointDynamics, format!("damping must be finite and >= 0 and rest finite, got {} and {}", spec.damping, spec.rest));
    }
    let normal = cross(&dir, &hinge);
    let (d, inertia, geometry) = match spec.body {
        PanelBody::Size(size) => {
            if !size.iter().all(|s| positive(*s)) {
                return bad(ModelField::Inertia, format!("size (length, width, thickness) must be 3 finite lengths > 0 m, got {size:?}"));
            }
            let [l, w, t] = size;
            let k = spec.mass / 12.0;
            let moments = [k * (w * w + t * t), k * (l * l + t * t), k * (l * l + w * w)];
            let cols = [dir, hinge, normal];
            let mut i = [[0.0; 3]; 3];
            for (r, row) in i.iter_mut().enumerate() {
                for (c, v) in row.iter_mut().enumerate() {
                    *v = (0..3).map(|a| cols[a][r] * moments[a] * cols[a][c]).sum();
                }
            }
            let g = GeometrySpec {
                name: Some(format!("{}_plate", spec.name)),
                body: spec.name.clone(),
                role: GeometryRole::Visual,
                shape: Shape::Box { size },
                origin: [0.0; 3],
                rotation: quat_from_columns(&dir, &hinge, &normal),
                rgba: Some([0.2, 0.3, 0.7, 1.0]),
            };
            (l / 2.0, i, Some(g))
        }
        PanelBody::Inertia { com_distance, inertia } => {
            if !non_negative(com_distance) {
                return bad(ModelField::Com, format!("com_distance must be finite and >= 0 m, got {com_distance}"));
            }
            (com_distance, inertia, None)
        }
    };
    let i_hinge = (0..3).map(|r| (0..3).map(|c| hinge[r] * inertia[r][c] * hinge[c]).sum::<f64>()).sum::<f64>() + spec.mass * d * d;
    let stiffness = match spec.restoring {
        Restoring::Stiffness(k) => k,
        Restoring::Frequency(w) if non_negative(w) => i_hinge * w * w,
        Restoring::Frequency(w) => return bad(ModelField::JointDynamics, format!("frequency must be finite and >= 0 rad/s, got {w}")),
    };
    let dynamics = JointDynamics { actuated: false, stiffness, damping: spec.damping, rest: spec.rest };
    let l = link(spec.name.clone(), spec.parent.clone(), format!("{}_hinge", spec.name), JointType::Revolute, spec.hinge_position, hinge, scaled(&dir, d), spec.mass, inertia);
    Ok(Parts { links: vec![(l, dynamics)], points: Vec::new(), geometries: geometry.into_iter().collect() })
}

/// A beam's bending axes paired with their `EI`: `axes` as given, or by default two, `b₁` the
/// parent axis along `axis`'s smallest component made perpendicular to it and `b₂ = axis × b₁`;
/// `ei` one value for every axis or one per axis.
pub fn bending(name: &str, axis: &[f64; 3], axes: Option<Vec<[f64; 3]>>, ei: &[f64]) -> Result<Vec<([f64; 3], f64)>, ModelError> {
    let bad = |msg: String| Err(ModelError::new(ModelItem::Model, ModelField::JointDynamics, format!("beam '{name}': {msg}")));
    let axes = match axes {
        Some(a) => a,
        None => {
            let Some(u) = normalized(axis) else {
                return Err(ModelError::new(ModelItem::Model, ModelField::Axis, format!("beam '{name}': axis must be a finite non-zero vector, got {axis:?}")));
            };
            let k = (0..3).min_by(|&i, &j| u[i].abs().total_cmp(&u[j].abs())).unwrap_or(0);
            let mut e = [0.0; 3];
            e[k] = 1.0;
            let d = dot(&e, &u);
            let b1 = normalized(&[e[0] - d * u[0], e[1] - d * u[1], e[2] - d * u[2]]).unwrap_or([1.0, 0.0, 0.0]);
            vec![b1, cross(&u, &b1)]
        }
    };
    match ei.len() {
        1 => Ok(axes.iter().map(|a| (*a, ei[0])).collect()),
        n if n == axes.len() => Ok(axes.iter().zip(ei).map(|(a, e)| (*a, *e)).collect()),
        n => bad(format!("EI must be one number or one per bending axis ({}), got {n}", axes.len())),
    }
}

/// The stiffness of each joint at a beam station, with its family's first clamped frequency
/// (for [`BeamDamping::Ratio`]): the bending joints then the twist joint (module docs).
fn beam_station(spec: &BeamSpec, l: f64) -> Vec<([f64; 3], f64, f64, &'static str)> {
    let big_l = spec.length;
    let mut out: Vec<([f64; 3], f64, f64, &'static str)> = spec
        .bending
        .iter()
        .enumerate()
        .map(|(k, (a, ei))| {
            let w1 = CANTILEVER_BETA1_L * CANTILEVER_BETA1_L * (ei / (spec.rho_a * big_l.powi(4))).sqrt();
            (*a, ei / l, w1, if k == 0 { "bend1" } else { "bend2" })
        })
        .collect();
    if let Some(gj) = spec.torsion {
        let w1 = std::f64::consts::FRAC_PI_2 * (gj / (spec.rho_j * big_l * big_l)).sqrt();
        out.push((spec.axis, gj / l, w1, "twist"));
    }
    out
}

/// A flexible beam by the rigid finite element method (module docs): the root half-element on a
/// fixed joint, then `N` stations of passive joints each followed by its rigid element, and the
/// point `<name>_tip` at the free end.
pub fn beam_parts(spec: &BeamSpec, item: ModelItem) -> Result<Parts, ModelError> {
    let who = format!("beam '{}'", spec.name);
    let bad = |field: ModelField, msg: String| Err(ModelError::new(item, field, format!("{who}: {msg}")));
    let rules = PartRules { item, who: &who };
    let axis = rules.direction("axis", &spec.axis)?;
    rules.positive(ModelField::Com, "length", " m", spec.length)?;
    if !(1..=1000).contains(&spec.segments) {
        return bad(ModelField::Name, format!("segments must be between 1 and 1000, got {}", spec.segments));
    }
    rules.positive(ModelField::Mass, "rho_A (mass per length)", " kg/m", spec.rho_a)?;
    rules.non_negative(ModelField::Inertia, "rho_J", " kg m", spec.rho_j)?;
    if spec.bending.is_empty() && spec.torsion.is_none() {
        return bad(ModelField::JointDynamics, "give at least one bending axis (with its EI) or GJ".into());
    }
    if spec.bending.len() > 2 {
        return bad(ModelField::Axis, format!("at most two bending axes, got {}", spec.bending.len()));
    }
    let mut bending = Vec::new();
    for (a, ei) in &spec.bending {
        let Some(b) = normalized(a) else {
            return bad(ModelField::Axis, format!("bending axis must be a finite non-zero vector, got {a:?}"));
        };
        if dot(&b, &axis).abs() > 1e-9 {
            return bad(ModelField::Axis, format!("bending axis {b:?} must be perpendicular to the beam axis {axis:?}"));
        }
        if !positive(*ei) {
            return bad(ModelField::JointDynamics, format!("EI must be finite and > 0 N m^2, got {ei}"));
        }
        bending.push((b, *ei));
    }
    if bending.len() == 2 && dot(&bending[0].0, &bending[1].0).abs() > 1e-9 {
        return bad(ModelField::Axis, format!("the two bending axes {:?} and {:?} must be perpendicular", bending[0].0, bending[1].0));
    }
    if let Some(gj) = spec.torsion {
        if !positive(gj) {
            return bad(ModelField::JointDynamics, format!("GJ must be finite and > 0 N m^2, got {gj}"));
        }
        if !positive(spec.rho_j) {
            return bad(ModelField::Inertia, "a beam with GJ (a twist joint) needs rho_J > 0, the mass moment of inertia per length about its axis".into());
        }
    }
    let ratio = match spec.damping {
        BeamDamping::PerJoint(c) if non_negative(c) => None,
        BeamDamping::Ratio(z) if non_negative(z) => Some(z),
        BeamDamping::PerJoint(v) | BeamDamping::Ratio(v) => return bad(ModelField::JointDynamics, format!("damping must be finite and >= 0, got {v}")),
    };
    let spec = BeamSpec { axis, bending, ..spec.clone() };
    let n = spec.segments;
    let l = spec.length / n as f64;
    // Transverse: the slender rod's ρA s³/12 plus the section's rotary inertia ρJ s/2 (an
    // axisymmetric section, I_y = I_z = J/2), which keeps every element a physical body.
    let element = |s: f64| {
        let transverse = spec.rho_a * s * s * s / 12.0 + spec.rho_j * s / 2.0;
        (spec.rho_a * s, axial(&axis, transverse, spec.rho_j * s - transverse))
    };
    let mut parts = Parts::default();
    let root = format!("{}_root", spec.name);
    let (m0, i0) = element(l / 2.0);
    parts.links.push((
        link(root.clone(), spec.parent.clone(), format!("{}_root_joint", spec.name), JointType::Fixed, spec.root_position, axis, scaled(&axis, l / 4.0), m0, i0),
        JointDynamics::default(),
    ));
    let station = beam_station(&spec, l);
    let mut parent = root;
    // The previous element's CM to the next station: l/4 from the root half-element, l/2 after.
    let mut to_next = l / 4.0;
    for i in 1..=n {
        let s = if i == n { l / 2.0 } else { l };
        let (m, inertia) = element(s);
        for (k, (a, stiffness, w1, tag)) in station.iter().enumerate() {
            let last = k + 1 == station.len();
            let name = if last { format!("{}_{i}", spec.name) } else { format!("{}_{i}_{tag}", spec.name) };
            let damping = match (ratio, spec.damping) {
                (Some(z), _) => 2.0 * z / w1 * stiffness,
                (None, BeamDamping::PerJoint(c)) => c,
                (None, BeamDamping::Ratio(_)) => 0.0,
            };
            let origin = if k == 0 { scaled(&axis, to_next) } else { [0.0; 3] };
            let (com, mass, inertia) = if last { (scaled(&axis, s / 2.0), m, inertia) } else { ([0.0; 3], 0.0, [[0.0; 3]; 3]) };
            parts.links.push((
                link(name.clone(), parent.clone(), format!("{}_{i}_{tag}", spec.name), JointType::Revolute, origin, *a, com, mass, inertia),
                JointDynamics { actuated: false, stiffness: *stiffness, damping, rest: 0.0 },
            ));
            parent = name;
        }
        to_next = s / 2.0;
    }
    parts.points.push((format!("{}_tip", spec.name), parent, scaled(&axis, l / 4.0)));
    Ok(parts)
}

/// A compliant joint (module docs): `link` (its own fields as given to the builder) becomes the
/// rotor `<link>_rotor` on the actuated joint (the link's joint name, kind, origin, rotation, axis
/// and limits) and the link itself on the passive joint `<joint>_deflection` about the same
/// axis, with the series spring. Revolute joints only.
pub fn compliant_parts(link_spec: &LinkSpec, spec: &CompliantSpec, item: ModelItem) -> Result<Parts, ModelError> {
    let who = format!("link '{}': compliant joint", link_spec.name);
    let bad = |field: ModelField, msg: String| Err(ModelError::new(item, field, format!("{who}: {msg}")));
    let rules = PartRules { item, who: &who };
    if link_spec.kind != JointType::Revolute {
        return bad(ModelField::JointDynamics, format!("only a revolute joint can be compliant, got {}", link_spec.kind.as_str()));
    }
    rules.positive(ModelField::JointDynamics, "stiffness", " N m/rad", spec.stiffness)?;
    rules.positive(ModelField::Inertia, "rotor_inertia", " kg m^2", spec.rotor_inertia)?;
    rules.non_negative(ModelField::JointDynamics, "damping", " N m s/rad", spec.damping)?;
    rules.positive(ModelField::JointDynamics, "gear_ratio", "", spec.gear_ratio)?;
    let axis = rules.direction("axis", &link_spec.axis)?;
    let joint = link_spec.joint_name.clone().unwrap_or_else(|| format!("{}_joint", link_spec.name));
    // The rotor: axial inertia n² B; transverse 0.6 n² B (a disc, as the reaction wheels').
    let j = spec.gear_ratio * spec.gear_ratio * spec.rotor_inertia;
    let rotor_name = format!("{}_rotor", link_spec.name);
    let rotor = LinkSpec {
        name: rotor_name.clone(),
        joint_name: Some(joint.clone()),
        axis,
        com_from_joint: [0.0; 3],
        mass: 0.0,
        inertia: axial(&axis, 0.6 * j, 0.4 * j),
        ..link_spec.clone()
    };
    let body = LinkSpec {
        parent: rotor_name,
        joint_name: Some(format!("{joint}_deflection")),
        origin_in_parent: [0.0; 3],
        rotation_in_parent: [0.0, 0.0, 0.0, 1.0],
        axis,
        limits: JointLimits::unlimited(),
        ..link_spec.clone()
    };
    let spring = JointDynamics { actuated: false, stiffness: spec.stiffness, damping: spec.damping, rest: 0.0 };
    Ok(Parts { links: vec![(rotor, JointDynamics::default()), (body, spring)], points: Vec::new(), geometries: Vec::new() })
}

/// The compliant joints of a built model: `(motor dof, deflection dof)` for each passive revolute
/// joint that turns about the same line as its parent's actuated revolute joint (the child's axis,
/// rotated into the parent's frame, is the parent's axis and the child's joint point lies on the
/// parent's axis line; [`compliant_parts`] builds exactly this). Two revolute joints about one
/// line compose by adding their angles, so the link's angle is `q_link = θ + δ` exactly, whatever
/// the rest of the chain does; the motor's tracking error misses `δ`
/// ([`crate::sim::simulate::Records::link_tracking_error`]).
pub fn compliant_pairs(model: &crate::model::Model) -> Vec<(usize, usize)> {
    const TOL: f64 = 1e-12;
    let dynamics = model.dof_dynamics();
    let mut pairs = Vec::new();
    for (k, link) in model.links().iter().enumerate() {
        let (Some(delta), Some(theta)) = (model.dof_of_body(k + 1), model.dof_of_body(link.parent)) else { continue };
        let parent = &model.links()[link.parent - 1];
        if link.joint.kind != JointType::Revolute || parent.joint.kind != JointType::Revolute || dynamics[delta].actuated || !dynamics[theta].actuated {
            continue;
        }
        let axis = parent.joint.axis.into_inner();
        let coaxial = (link.joint.rotation_in_parent * link.joint.axis.into_inner() - axis).norm() <= TOL;
        // From the parent's joint point (at −com_from_joint from its CM) to the child's.
        let offset = link.joint.origin_in_parent + parent.com_from_joint;
        if coaxial && offset.cross(&axis).norm() <= TOL * (1.0 + offset.norm()) {
            pairs.push((theta, delta));
        }
    }
    pairs
}

impl ModelBuilder {
    /// Add an appendage's links, points and shapes, in order; each is checked by the usual
    /// rules when it is added.
    pub fn add_parts(&mut self, parts: &Parts) -> Result<&mut Self, ModelError> {
        for (link, dynamics) in &parts.links {
            self.add_link(link.clone())?;
            if *dynamics != JointDynamics::default() {
                self.set_joint_dynamics(&link.name, *dynamics)?;
            }
        }
        for (name, body, offset) in &parts.points {
            self.add_point(name, body, *offset)?;
        }
        for g in &parts.geometries {
            self.add_geometry(g.clone())?;
        }
        Ok(self)
    }

    /// Add a hinged rigid panel ([`panel_parts`]).
    pub fn add_panel(&mut self, spec: &PanelSpec) -> Result<&mut Self, ModelError> {
        let parts = panel_parts(spec, ModelItem::Link(self.n_links()))?;
        self.add_parts(&parts)
    }

    /// Add a flexible beam by the rigid finite element method ([`beam_parts`]).
    pub fn add_beam(&mut self, spec: &BeamSpec) -> Result<&mut Self, ModelError> {
        let parts = beam_parts(spec, ModelItem::Link(self.n_links()))?;
        self.add_parts(&parts)
    }

    /// Add a link whose revolute joint is compliant ([`compliant_parts`]).
    pub fn add_compliant_link(&mut self, link: &LinkSpec, spec: &CompliantSpec) -> Result<&mut Self, ModelError> {
        let parts = compliant_parts(link, spec, ModelItem::Link(self.n_links()))?;
        self.add_parts(&parts)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_either_or_options_of_every_door_follow_one_rule() {
        use crate::model::slosh::{SloshModel, SloshRestoring};
        assert_eq!(Restoring::from_options(Some(2.0), None), Ok(Restoring::Stiffness(2.0)));
        assert_eq!(Restoring::from_options(None, Some(3.0)), Ok(Restoring::Frequency(3.0)));
        assert_eq!(SloshRestoring::from_options(Some(2.0), None), Ok(SloshRestoring::Stiffness(2.0)));
        assert_eq!(SloshRestoring::from_options(None, Some(3.0)), Ok(SloshRestoring::Frequency(3.0)));
        for (k, w) in [(None, None), (Some(1.0), Some(1.0))] {
            assert_eq!(Restoring::from_options(k, w), Err("give stiffness or frequency (one of them)".to_string()));
            assert_eq!(SloshRestoring::from_options(k, w), Err("give stiffness or frequency (one of them)".to_string()));
        }
        let i = [[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 3.0]];
        assert_eq!(PanelBody::from_options(Some([1.0, 0.5, 0.01]), None, None), Ok(PanelBody::Size([1.0, 0.5, 0.01])));
        assert_eq!(PanelBody::from_options(None, Some(i), Some(0.4)), Ok(PanelBody::Inertia { com_distance: 0.4, inertia: i }));
        for (s, i, d) in [(None, None, None), (Some([1.0; 3]), Some(i), Some(0.4)), (None, Some(i), None), (Some([1.0; 3]), None, Some(0.4))] {
            assert!(PanelBody::from_options(s, i, d).unwrap_err().starts_with("give size"), "{s:?} {d:?}");
        }
        assert_eq!(BeamDamping::from_options(None, None), Ok(BeamDamping::PerJoint(0.0)));
        assert_eq!(BeamDamping::from_options(Some(0.2), None), Ok(BeamDamping::PerJoint(0.2)));
        assert_eq!(BeamDamping::from_options(None, Some(0.05)), Ok(BeamDamping::Ratio(0.05)));
        assert_eq!(BeamDamping::from_options(Some(0.2), Some(0.05)), Err("give damping or damping_ratio, not both".to_string()));
        for (k, name) in SloshModel::NAMES.iter().enumerate() {
            assert_eq!(SloshModel::from_name(name), Ok([SloshModel::SpringMass, SloshModel::Pendulum, SloshModel::SphericalPendulum][k]));
        }
        assert_eq!(SloshModel::from_name("slushy"), Err("model must be one of [\"spring-mass\", \"pendulum\", \"spherical-pendulum\"], got 'slushy'".to_string()));
    }

    fn beam(n: usize) -> BeamSpec {
        BeamSpec {
            name: "b".into(),
            parent: "base".into(),
            root_position: [0.1, 0.0, 0.0],
            axis: [2.0, 0.0, 0.0],
            length: 4.0,
            segments: n,
            bending: bending("b", &[1.0, 0.0, 0.0], None, &[10.0]).unwrap(),
            torsion: Some(3.0),
            rho_a: 0.5,
            rho_j: 0.01,
            damping: BeamDamping::Ratio(0.02),
        }
    }

    #[test]
    fn beam_parts_are_the_rfem_chain() {
        let p = beam_parts(&beam(5), ModelItem::Model).unwrap();
        // root + 5 stations × (2 bending + twist) links.
        assert_eq!(p.links.len(), 1 + 15);
        let mass: f64 = p.links.iter().map(|(l, _)| l.mass).sum();
        assert!((mass - 0.5 * 4.0).abs() < 1e-14);
        let l = 4.0 / 5.0;
        let (root, _) = &p.links[0];
        assert_eq!(root.kind, JointType::Fixed);
        assert!((root.mass - 0.5 * l / 2.0).abs() < 1e-15 && (root.com_from_joint[0] - l / 4.0).abs() < 1e-15);
        let w_bend = CANTILEVER_BETA1_L.powi(2) * (10.0 / (0.5 * 4.0_f64.powi(4))).sqrt();
        for (link, d) in &p.links[1..] {
            assert!(!d.actuated);
            let want = if link.axis == [1.0, 0.0, 0.0] { 3.0 / l } else { 10.0 / l };
            assert!((d.stiffness - want).abs() < 1e-12, "{}", link.name);
            if link.axis != [1.0, 0.0, 0.0] {
                assert!((d.damping - 2.0 * 0.02 / w_bend * want).abs() < 1e-12);
            }
        }
        // The default bending axes: y (x's smallest component ties; the first) then x × y = z.
        assert_eq!(p.links[1].0.axis, [0.0, 1.0, 0.0]);
        assert_eq!(p.links[2].0.axis, [0.0, 0.0, 1.0]);
        assert_eq!(p.points, vec![("b_tip".to_string(), "b_5".to_string(), [l / 4.0, 0.0, 0.0])]);
    }

    #[test]
    fn bad_beams_and_panels_are_refused() {
        let mut b = beam(3);
        b.rho_j = 0.0;
        assert!(beam_parts(&b, ModelItem::Model).unwrap_err().message.contains("rho_J"));
        let mut b = beam(3);
        b.segments = 0;
        assert!(beam_parts(&b, ModelItem::Model).is_err());
        assert!(bending("b", &[1.0, 0.0, 0.0], None, &[1.0, 2.0, 3.0]).is_err());
        let panel = PanelSpec {
            name: "p".into(),
            parent: "base".into(),
            hinge_position: [0.0; 3],
            hinge_axis: [0.0, 0.0, 1.0],
            direction: [1.0, 0.0, 0.0],
            body: PanelBody::Size([1.0, 0.5, 0.01]),
            mass: 2.0,
            restoring: Restoring::Frequency(2.0),
            damping: 0.0,
            rest: 0.0,
        };
        let p = panel_parts(&panel, ModelItem::Model).unwrap();
        let i_h = 2.0 / 12.0 * (1.0 + 0.0001) + 2.0 * 0.25;
        assert!((p.links[0].1.stiffness - 4.0 * i_h).abs() < 1e-12);
        assert!(panel_parts(&PanelSpec { direction: [1.0, 0.0, 1.0], ..panel.clone() }, ModelItem::Model).is_err());
        assert!(panel_parts(&PanelSpec { mass: 0.0, ..panel }, ModelItem::Model).is_err());
    }

    #[test]
    fn compliant_pairs_are_the_coaxial_motor_and_deflection_joints() {
        let diag = |a: f64, b: f64, c: f64| [[a, 0.0, 0.0], [0.0, b, 0.0], [0.0, 0.0, c]];
        let mut b = ModelBuilder::new("m", "base", 10.0, diag(1.0, 1.0, 1.0)).unwrap();
        // dof 0: a rigid actuated joint; dofs 1, 2: a compliant joint on a tilted axis in a
        // rotated frame; dof 3: a passive spring joint off its actuated parent's axis (a panel,
        // not a deflection); dof 4: a passive joint on the base.
        b.add_link(LinkSpec::new("r", "base", JointType::Revolute, [0.3, 0.0, 0.0], [0.0, 1.0, 0.0], [0.2, 0.0, 0.0], 1.0, [0.01, 0.05, 0.05])).unwrap();
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let c = LinkSpec { rotation_in_parent: [0.0, 0.0, s, s], ..LinkSpec::new("c", "r", JointType::Revolute, [0.4, 0.0, 0.0], [1.0, 1.0, 0.5], [0.3, 0.0, 0.0], 2.0, [0.01, 0.1, 0.1]) };
        b.add_compliant_link(&c, &CompliantSpec { stiffness: 30.0, rotor_inertia: 0.02, damping: 0.1, gear_ratio: 2.0 }).unwrap();
        b.add_link(LinkSpec::new("p", "c_rotor", JointType::Revolute, [0.1, 0.0, 0.0], [0.0, 0.0, 1.0], [0.2, 0.0, 0.0], 0.5, [0.01, 0.02, 0.02])).unwrap();
        b.set_joint_dynamics("p", JointDynamics { actuated: false, stiffness: 5.0, damping: 0.0, rest: 0.0 }).unwrap();
        b.add_link(LinkSpec::new("q", "base", JointType::Revolute, [0.0, 0.3, 0.0], [0.0, 0.0, 1.0], [0.2, 0.0, 0.0], 0.5, [0.01, 0.02, 0.02])).unwrap();
        b.set_joint_dynamics("q", JointDynamics { actuated: false, stiffness: 5.0, damping: 0.0, rest: 0.0 }).unwrap();
        let m = b.build().unwrap();
        assert_eq!(m.n_dof(), 5);
        let actuated: Vec<bool> = m.dof_dynamics().iter().map(|d| d.actuated).collect();
        assert_eq!(actuated, vec![true, true, false, false, false]);
        assert_eq!(compliant_pairs(&m), vec![(1, 2)]);
        // The rule the pairs stand for: the link's orientation is that of the motor joint
        // turned by θ + δ (two turns about one line add).
        let (theta, delta) = (0.4, -0.15);
        let link = m.body_index("c").unwrap();
        let rotation = |q: [f64; 5]| {
            let mut x = vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0];
            x.extend_from_slice(&q);
            let mut data = crate::model::Data::new(&m);
            crate::algorithms::kinematics::forward_kinematics(&m, &mut data, &x).unwrap();
            data.body_to_world[link]
        };
        let apart = rotation([0.2, theta, delta, 0.0, 0.0]);
        assert!((apart - rotation([0.2, theta + delta, 0.0, 0.0, 0.0])).norm() < 1e-14);
        assert!((apart - rotation([0.2, theta, 0.0, 0.0, 0.0])).norm() > 0.1);
    }
}
