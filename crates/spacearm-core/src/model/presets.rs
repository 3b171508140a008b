//! The preset models. `planar4` carries exactly the planar values of SPART's `ResolvedMotion`
//! example; `spatial6`, `dual_arm` and `spatial7` are defined by this project; `ets7` is the
//! flown ETS-VII robot from published parameters (see [`ets7`]). None of them is the case study
//! of Wilde et al. (2018), whose parameters are not available. The Python presets
//! (`spacearm.presets`) are these same models.
//!
//! The project-defined ones follow the paper's link convention: every link frame aligns with the base frame at
//! `q = 0`, links extend along their x axis with the CM at mid-length, and joint `i+1` sits at
//! the tip of link `i`; the end effector is the tip of the last link.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

use crate::error::Result;
use crate::math::rotations::xyzw_from_rpy;
use crate::model::joint::{JointLimits, JointType};
use crate::model::geometry::{box_of_moments, segment};
use crate::model::{GeometryRole, GeometrySpec, LinkSpec, Model, ModelBuilder, Shape, TriangleInequality};

/// Names of the presets, as accepted by [`by_name`].
pub const NAMES: [&str; 5] = ["planar4", "spatial6", "dual_arm", "spatial7", "ets7"];

/// Inertia of a square bar of length `l` along x and side `w`: `Ixx = m w²/6`,
/// `Iyy = Izz = m (l² + w²)/12`.
fn bar_moments(m: f64, l: f64, w: f64) -> [f64; 3] {
    let iyy = m * (l * l + w * w) / 12.0;
    [m * w * w / 6.0, iyy, iyy]
}

struct SerialArm<'a> {
    name: &'a str,
    base_mass: f64,
    base_inertia: [f64; 3],
    first_joint: [f64; 3],
    axes: &'a [[f64; 3]],
    lengths: &'a [f64],
    masses: &'a [f64],
    width: f64,
    initial_q: Vec<f64>,
    /// Joint limits, one per joint (empty: unlimited).
    limits: &'a [JointLimits],
}

/// Colours of the presets' shapes: the base a pale gold (foil), the links a light grey.
const BASE_RGBA: [f64; 4] = [0.85, 0.72, 0.35, 1.0];
const LINK_RGBA: [f64; 4] = [0.75, 0.77, 0.8, 1.0];

/// A visual box of full sides `size` centred at the CM of `body`, in its axes.
fn add_box(b: &mut ModelBuilder, body: &str, size: [f64; 3], rgba: [f64; 4]) -> Result<()> {
    b.add_geometry(GeometrySpec { rgba: Some(rgba), ..GeometrySpec::new(body, GeometryRole::Visual, Shape::Box { size }) })?;
    Ok(())
}

/// Add a chain of bars on the base (links `{prefix}link1..`, joints `{prefix}joint1..`) and
/// return the last link's name with the tip's offset from its CM.
fn add_chain(b: &mut ModelBuilder, prefix: &str, spec: &SerialArm<'_>) -> Result<(String, [f64; 3])> {
    let mut parent = "base".to_string();
    let mut origin = spec.first_joint;
    for (i, ((axis, &l), &m)) in spec.axes.iter().zip(spec.lengths).zip(spec.masses).enumerate() {
        let name = format!("{prefix}link{}", i + 1);
        b.add_link(LinkSpec {
            joint_name: Some(format!("{prefix}joint{}", i + 1)),
            limits: spec.limits.get(i).copied().unwrap_or_else(JointLimits::unlimited),
            ..LinkSpec::new(&name, &parent, JointType::Revolute, origin, *axis, [l / 2.0, 0.0, 0.0], m, bar_moments(m, l, spec.width))
        })?;
        // The bar itself: l × w × w about its CM, along the link's x.
        add_box(b, &name, [l, spec.width, spec.width], LINK_RGBA)?;
        parent = name;
        // The next joint is at this link's tip, half a length beyond its CM.
        origin = [l / 2.0, 0.0, 0.0];
    }
    Ok((parent, origin))
}

fn serial_arm(spec: SerialArm<'_>) -> Result<Model> {
    let [ixx, iyy, izz] = spec.base_inertia;
    let mut b = ModelBuilder::new(spec.name, "base", spec.base_mass, [[ixx, 0.0, 0.0], [0.0, iyy, 0.0], [0.0, 0.0, izz]])?;
    add_box(&mut b, "base", box_of_moments(spec.base_mass, spec.base_inertia), BASE_RGBA)?;
    let (parent, origin) = add_chain(&mut b, "", &spec)?;
    b.add_point("end_effector", &parent, origin)?;
    b.set_end_effector("end_effector");
    b.set_initial_q(spec.initial_q);
    Ok(b.build()?)
}

/// Planar 4-link arm on a 100 kg, 0.5 m cube: the planar values of SPART's `ResolvedMotion`
/// example (four 10 kg, 1 m links; initial angles [π/4, −π/4, −π/4, π/4]).
pub fn planar4() -> Model {
    serial_arm(SerialArm {
        name: "planar4",
        base_mass: 100.0,
        base_inertia: [4.1667; 3],
        first_joint: [0.25, 0.0, 0.0],
        axes: &[[0.0, 0.0, 1.0]; 4],
        lengths: &[1.0; 4],
        masses: &[10.0; 4],
        width: 0.05,
        initial_q: vec![FRAC_PI_4, -FRAC_PI_4, -FRAC_PI_4, FRAC_PI_4],
        limits: &[],
    })
    .expect("the planar4 preset is a valid model")
}

/// Spatial 6-link arm on a 500 kg, 1.2 × 1.0 × 0.8 m box (defined by this project).
pub fn spatial6() -> Model {
    let (x, y) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
    serial_arm(SerialArm {
        name: "spatial6",
        base_mass: 500.0,
        base_inertia: [68.33, 86.67, 101.67],
        first_joint: [0.6, 0.0, 0.0],
        axes: &[x, y, y, x, y, x],
        lengths: &[0.2, 1.0, 1.0, 0.15, 0.15, 0.2],
        masses: &[8.0, 15.0, 12.0, 4.0, 3.0, 3.0],
        width: 0.1,
        initial_q: vec![0.0, FRAC_PI_4, -2.0 * FRAC_PI_4, 0.0, FRAC_PI_4, 0.0],
        limits: &[],
    })
    .expect("the spatial6 preset is a valid model")
}

/// Dual-arm servicer: two 6-DOF arms on a 600 kg, 1.2 × 1.0 × 1.0 m box.
///
/// Base inertia `m (b² + c²)/12`: Ixx 100, Iyy = Izz 122 kg·m². The arms' first joints are at
/// (0.6, ±0.35, 0) m from the base CM; axes z, y, y, x, y, x (yaw, shoulder, elbow, wrist
/// roll-pitch-roll); lengths 0.2, 0.8, 0.8, 0.15, 0.15, 0.2 m; masses 6, 10, 8, 2, 1.5, 1.5 kg;
/// 0.08 m square bars. Links `left_link1..6` / `right_link1..6`, joints `left_joint1..6` /
/// `right_joint1..6` (q[0..6] left, q[6..12] right), points `left_tool` and `right_tool` at the
/// tips; the end effector is `left_tool`. Initial angles: elbows bent, arms mirror images.
pub fn dual_arm() -> Model {
    let (x, y, z) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
    let build = || -> Result<Model> {
        let mut b = ModelBuilder::new("dual_arm", "base", 600.0, [[100.0, 0.0, 0.0], [0.0, 122.0, 0.0], [0.0, 0.0, 122.0]])?;
        add_box(&mut b, "base", [1.2, 1.0, 1.0], BASE_RGBA)?;
        let mut initial_q = Vec::new();
        for (side, sign) in [("left", 1.0), ("right", -1.0)] {
            let arm = SerialArm {
                name: "dual_arm",
                base_mass: 600.0,
                base_inertia: [100.0, 122.0, 122.0],
                first_joint: [0.6, 0.35 * sign, 0.0],
                axes: &[z, y, y, x, y, x],
                lengths: &[0.2, 0.8, 0.8, 0.15, 0.15, 0.2],
                masses: &[6.0, 10.0, 8.0, 2.0, 1.5, 1.5],
                width: 0.08,
                initial_q: Vec::new(),
                limits: &[],
            };
            let (tip_link, tip) = add_chain(&mut b, &format!("{side}_"), &arm)?;
            b.add_point(&format!("{side}_tool"), &tip_link, tip)?;
            initial_q.extend([0.3 * sign, FRAC_PI_4, -2.0 * FRAC_PI_4, 0.0, FRAC_PI_4, 0.0]);
        }
        b.set_end_effector("left_tool");
        b.set_initial_q(initial_q);
        Ok(b.build()?)
    };
    build().expect("the dual_arm preset is a valid model")
}

/// Redundant 7-DOF arm (shoulder roll–pitch–roll, elbow pitch, wrist roll–pitch–roll) on the
/// spatial6 base (500 kg, 1.2 × 1.0 × 0.8 m; Ixx 68.33, Iyy 86.67, Izz 101.67 kg·m²): the
/// redundancy-resolution example (docs/redundancy.md).
///
/// Joint 1 at (0.6, 0, 0) m; axes x, y, x, y, x, y, x; lengths 0.2, 0.1, 0.9, 0.1, 0.9, 0.1,
/// 0.15 m; masses 8, 4, 12, 4, 10, 3, 3 kg; 0.1 m square bars. Limits: roll joints (1, 3, 5, 7)
/// ±2.97 rad (±170°), pitch joints 2 and 6 ±2.09 rad (±120°), elbow (joint 4) −2.9…0.1 rad; every
/// joint 1.5 rad/s and 100 N·m. Initial angles [0, π/4, 0, −π/2, 0, π/4, 0] (elbow bent).
pub fn spatial7() -> Model {
    let (x, y) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
    let lim = |lower: f64, upper: f64| JointLimits { lower, upper, velocity: 1.5, effort: 100.0 };
    let (roll, pitch) = (lim(-2.97, 2.97), lim(-2.09, 2.09));
    serial_arm(SerialArm {
        name: "spatial7",
        base_mass: 500.0,
        base_inertia: [68.33, 86.67, 101.67],
        first_joint: [0.6, 0.0, 0.0],
        axes: &[x, y, x, y, x, y, x],
        lengths: &[0.2, 0.1, 0.9, 0.1, 0.9, 0.1, 0.15],
        masses: &[8.0, 4.0, 12.0, 4.0, 10.0, 3.0, 3.0],
        width: 0.1,
        initial_q: vec![0.0, FRAC_PI_4, 0.0, -2.0 * FRAC_PI_4, 0.0, FRAC_PI_4, 0.0],
        limits: &[roll, pitch, roll, lim(-2.9, 0.1), roll, pitch, roll],
    })
    .expect("the spatial7 preset is a valid model")
}

/// One ETS-VII arm link as transcribed: joint origin (m) and roll-pitch-yaw (rad) of the joint
/// frame in the parent link frame, mass (kg), principal moments (Ixx, Iyy, Izz) about the link
/// frame origin (kg·m²; the products of inertia are zero in the transcription).
struct Ets7Link {
    origin: [f64; 3],
    rpy: [f64; 3],
    mass: f64,
    moments: [f64; 3],
}

/// The ETS-VII arm as transcribed (see [`ets7`]). The transcription's angles 3.1416, 1.5708 and
/// 1.570796 rad are read as π and π/2.
const ETS7_LINKS: [Ets7Link; 6] = [
    Ets7Link { origin: [-0.79, -0.29, 1.0], rpy: [0.0, 0.0, PI], mass: 35.0, moments: [0.25, 0.25, 1.69] },
    Ets7Link { origin: [0.0, -0.275, 0.35], rpy: [-FRAC_PI_2, 0.0, 0.0], mass: 22.5, moments: [0.1, 1.31, 3.75] },
    Ets7Link { origin: [0.0, -0.87, 0.0], rpy: [0.0, 0.0, 0.0], mass: 21.9, moments: [0.1, 0.71, 2.53] },
    Ets7Link { origin: [-0.63, 0.0, 0.0], rpy: [0.0, 0.0, 0.0], mass: 16.5, moments: [0.15, 0.15, 0.073] },
    Ets7Link { origin: [0.0, 0.0, 0.26], rpy: [FRAC_PI_2, 0.0, 0.0], mass: 26.0, moments: [0.15, 0.15, 0.13] },
    Ets7Link { origin: [0.0, 0.0, 0.28], rpy: [0.0, -FRAC_PI_2, 0.0], mass: 18.5, moments: [0.97, 0.97, 0.26] },
];

/// ETS-VII base (the satellite): mass, kg, and inertia about its CM in its axes, kg·m².
const ETS7_BASE_MASS: f64 = 2550.0;
const ETS7_BASE_INERTIA: [[f64; 3]; 3] = [[6200.0, 48.2, 78.5], [48.2, 3540.0, -29.2], [78.5, -29.2, 7090.0]];

/// End effector: on link 6's z axis, 0.53 m from its frame origin.
const ETS7_END_EFFECTOR: [f64; 3] = [0.0, 0.0, 0.53];

/// The smallest physical correction of diagonal moments `(Ixx, Iyy, Izz)` (about principal
/// axes) that break the triangle inequality. The moments imply the second moments of mass
/// `Sxx = ∫x² dm = (Iyy + Izz − Ixx)/2` and cyclically; a broken inequality `Ixx + Iyy < Izz` is
/// a negative `Szz`. The correction sets that second moment to zero and keeps the other two, so
/// the body becomes flat in the plane where the data put it: it raises the two smaller moments by
/// the same `δ = (Izz − Ixx − Iyy)/2` and keeps the largest (for ETS-VII links 1–3, the moment
/// about the joint axis z) and their difference. Physical moments are returned unchanged.
pub fn flatten_negative_second_moment(moments: [f64; 3]) -> [f64; 3] {
    let mut out = moments;
    let largest = (1..3).fold(0, |l, k| if moments[k] > moments[l] { k } else { l });
    let sum: f64 = moments.iter().sum();
    let deficit = moments[largest] - (sum - moments[largest]);
    if deficit > 0.0 {
        for (k, m) in out.iter_mut().enumerate() {
            if k != largest {
                *m += deficit / 2.0;
            }
        }
    }
    out
}

/// ETS-VII (Engineering Test Satellite VII, flown 1997–1999): a 6-DOF arm on a 2.55 t satellite.
///
/// Sources: kinematics from K. Yoshida, "Engineering test satellite VII flight experiments for
/// space robot dynamics and control", Int. J. Robotics Research 22(5):321–335, 2003; inertial
/// parameters from K. Yoshida and S. Abiko, "Inertia parameter identification for a free-flying
/// space robot", AIAA GNC Conference, 2002; both as transcribed in S. Vyas's public URDF
/// ("TraceableRobotModels", 2020). The transcription puts each link's CM at its link (joint)
/// frame origin, so every `com` is zero and each joint origin is measured from the parent's CM;
/// these are the transcribed values of the papers, with that CM simplification, not a flight
/// dataset. All six joints are revolute about their frame's z; no joint limits; the end
/// effector is 0.53 m along link 6's z axis; initial angles zero (a non-singular pose).
///
/// The transcribed moments of links 1, 2 and 3 — (0.25, 0.25, 1.69), (0.1, 1.31, 3.75) and
/// (0.1, 0.71, 2.53) kg·m² — break the triangle inequality. `TriangleInequality::Enforce` (the
/// default preset) corrects them by [`flatten_negative_second_moment`] to (0.845, 0.845, 1.69),
/// (1.27, 2.48, 3.75) and (0.96, 1.57, 2.53); `TriangleInequality::Warn` keeps the published
/// values and records a warning per link in [`Model::inertia_warnings`].
pub fn ets7_with(triangle_inequality: TriangleInequality) -> Model {
    let build = || -> Result<Model> {
        let mut b = ModelBuilder::with_triangle_inequality("ets7", "base", ETS7_BASE_MASS, ETS7_BASE_INERTIA, triangle_inequality)?;
        let i = ETS7_BASE_INERTIA;
        add_box(&mut b, "base", box_of_moments(ETS7_BASE_MASS, [i[0][0], i[1][1], i[2][2]]), BASE_RGBA)?;
        let mut parent = "base".to_string();
        for (i, link) in ETS7_LINKS.iter().enumerate() {
            let [ixx, iyy, izz] = match triangle_inequality {
                TriangleInequality::Enforce => flatten_negative_second_moment(link.moments),
                TriangleInequality::Warn => link.moments,
            };
            let name = format!("link{}", i + 1);
            b.add_link(LinkSpec {
                joint_name: Some(format!("joint{}", i + 1)),
                rotation_in_parent: xyzw_from_rpy(&link.rpy),
                ..LinkSpec::new(&name, &parent, JointType::Revolute, link.origin, [0.0, 0.0, 1.0], [0.0; 3], link.mass, [ixx, iyy, izz])
            })?;
            // A 0.06 m radius capsule from this joint to the next (or to the end effector).
            let next = ETS7_LINKS.get(i + 1).map_or(ETS7_END_EFFECTOR, |l| l.origin);
            if let Some((origin, rotation, length)) = segment([0.0; 3], next) {
                b.add_geometry(GeometrySpec { origin, rotation, rgba: Some(LINK_RGBA), ..GeometrySpec::new(&name, GeometryRole::Visual, Shape::Capsule { radius: 0.06, length }) })?;
            }
            parent = name;
        }
        b.add_point("end_effector", &parent, ETS7_END_EFFECTOR)?;
        b.set_end_effector("end_effector");
        b.set_initial_q(vec![0.0; 6]);
        Ok(b.build()?)
    };
    build().expect("the ets7 preset is a valid model")
}

/// ETS-VII with the physical correction of the links whose published moments break the
/// triangle inequality (see [`ets7_with`]).
pub fn ets7() -> Model {
    ets7_with(TriangleInequality::Enforce)
}

/// A preset by name (see [`NAMES`]).
pub fn by_name(name: &str) -> Option<Model> {
    by_name_with(name, TriangleInequality::Enforce)
}

/// A preset by name, choosing what inertias that break the triangle inequality do: only
/// `ets7` has such published data, which [`TriangleInequality::Warn`] keeps (the other presets
/// are physical and unchanged by the choice).
pub fn by_name_with(name: &str, triangle_inequality: TriangleInequality) -> Option<Model> {
    match name {
        "planar4" => Some(planar4()),
        "spatial6" => Some(spatial6()),
        "dual_arm" => Some(dual_arm()),
        "spatial7" => Some(spatial7()),
        "ets7" => Some(ets7_with(triangle_inequality)),
        _ => None,
    }
}

/// Configuration `x` with the base at the origin, aligned with 𝒥, and the model's initial
/// joint angles.
pub fn initial_configuration(model: &Model) -> Vec<f64> {
    let mut x = vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0];
    x.extend_from_slice(model.initial_q());
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_have_the_issue_parameters() {
        let p = planar4();
        assert_eq!(p.n_dof(), 4);
        assert!((p.total_mass() - 140.0).abs() < 1e-12);
        let s = spatial6();
        assert_eq!(s.n_dof(), 6);
        assert!((s.total_mass() - 545.0).abs() < 1e-12);
        // Link 2 of spatial6: 15 kg, 1.0 m, 0.1 m bar.
        let l2 = &s.links()[1].mass;
        assert!((l2.inertia[(0, 0)] - 15.0 * 0.01 / 6.0).abs() < 1e-15);
        assert!((l2.inertia[(1, 1)] - 15.0 * 1.01 / 12.0).abs() < 1e-15);
        let d = dual_arm();
        assert_eq!(d.n_dof(), 12);
        assert!((d.total_mass() - 658.0).abs() < 1e-12);
        // the right arm hangs off the base, not off the left arm
        assert_eq!(d.links()[6].parent, 0);
        let s7 = spatial7();
        assert_eq!(s7.n_dof(), 7);
        assert!((s7.total_mass() - 544.0).abs() < 1e-12);
        assert_eq!(s7.links()[3].joint.limits.upper, 0.1);
        let e = ets7();
        assert_eq!(e.n_dof(), 6);
        assert!((e.total_mass() - (2550.0 + 35.0 + 22.5 + 21.9 + 16.5 + 26.0 + 18.5)).abs() < 1e-9);
        assert!(e.inertia_warnings().is_empty());
    }

    #[test]
    fn ets7_published_inertias_need_the_option() {
        let published = ets7_with(TriangleInequality::Warn);
        // Links 1, 2 and 3 break the triangle inequality, each with its own warning.
        assert_eq!(published.inertia_warnings().len(), 3);
        for (k, w) in published.inertia_warnings().iter().enumerate() {
            assert!(w.contains(&format!("link 'link{}'", k + 1)) && w.contains("triangle"), "{w}");
        }
        assert_eq!(published.links()[0].mass.inertia[(2, 2)], 1.69);
        assert_eq!(published.links()[0].mass.inertia[(0, 0)], 0.25);
        // The correction: Szz = (Ixx + Iyy - Izz)/2 becomes zero, Sxx and Syy are kept.
        let corrected = ets7();
        for (link, published) in corrected.links().iter().zip(&ETS7_LINKS) {
            let [a, b, c] = published.moments;
            let i = &link.mass.inertia;
            let (x, y, z) = (i[(0, 0)], i[(1, 1)], i[(2, 2)]);
            assert!((y + z - x - (b + c - a)).abs() < 1e-12 && (x + z - y - (a + c - b)).abs() < 1e-12);
            assert!((x + y - z - (a + b - c).max(0.0)).abs() < 1e-12);
        }
    }
}
