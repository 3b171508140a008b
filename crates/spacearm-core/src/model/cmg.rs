//! Control-moment gyros (CMG, VSCMG) as two ordinary links (docs/cmg.md):
//!
//! - the **gimbal** `<name>` on the revolute joint `<name>_gimbal` of its parent body (the
//!   base by default), at `position` (parent frame, from the parent's CM), turning about the
//!   gimbal axis `ĝ`; its CM on the gimbal axis at the joint, its principal moments
//!   `gimbal_inertia = (I_g, I_s', I_t')` along `(ĝ, ŝ₀, ĝ × ŝ₀)`;
//! - the **rotor** `<name>_rotor` on the revolute joint `<name>_spin` of the gimbal, its CM at
//!   the gimbal joint, spinning about `ŝ ⟂ ĝ` (`ŝ₀` at gimbal angle `δ = 0`, parent frame),
//!   its inertia `J_t E + (J_s − J_t) ŝ ŝᵀ` symmetric about the spin axis (it does not change as
//!   the rotor turns).
//!
//! Because both are ordinary links, every quantity of the model (H, H*, J*, momenta, forward and
//! inverse dynamics, their derivatives, the CasADi tapes, the five modes) includes the CMG with
//! no code of its own: the rotor's momentum `h = J_s ω_s ŝ` and the gyroscopic torque
//! `h × δ̇ ĝ` come out of the recursive dynamics.
//!
//! **The rotor's speed.** A VSCMG (`variable_speed = true`) has a motor on the spin joint: its
//! torque is a control, like a reaction wheel's. A single-gimbal CMG (`variable_speed = false`)
//! has a *passive* spin joint (no motor, no spring): with no torque about the axis of
//! symmetry, Euler's equation `J_s ω̇_s = 0` keeps the rotor's absolute spin `ω_s = ŝ · ω_G + Ω`
//! (`ω_G` the gimbal's angular velocity, `Ω` the joint rate) constant exactly, so
//! `|h| = J_s ω_s` is the constant of the SGCMG steering laws. (The joint rate `Ω` then moves by
//! `−ŝ · ω_G`, what an ideal speed loop on `Ω` would cancel: a relative change of order
//! `|ω_base| / Ω`.) The wheel speed is the run's initial condition (the rotor joint's rate in
//! `u0`, [`cmg_velocity`]), not a model parameter.
//!
//! A CMG is recognized in a model ([`detect_cmgs`]) by these names and this structure, so it
//! survives every file format that keeps links, joints and names.

use serde::{Deserialize, Serialize};

use crate::error::{ModelError, ModelField, ModelItem};
use crate::math::spatial::{cross3 as cross, dot3 as dot, unit3 as normalized};
use crate::model::appendage::Parts;
use crate::model::builder::LinkSpec;
use crate::model::joint::{JointDynamics, JointLimits, JointType};
use crate::model::validate::{non_negative, positive};
use crate::model::system::Model;

/// Default transverse rotor moment as a fraction of the spin moment (a disc 0.77 radii thick;
/// the same default as `RobotBuilder.add_reaction_wheel`).
pub const DEFAULT_TRANSVERSE_RATIO: f64 = 0.6;

/// Everything [`cmg_parts`] needs (module docs). TOML `[[cmg]]` reads exactly these fields.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CmgSpec {
    /// Gimbal link name; the rotor is `<name>_rotor`, the joints `<name>_gimbal`, `<name>_spin`.
    pub name: String,
    /// The body carrying the gimbal (the base when `None`).
    #[serde(default)]
    pub parent: Option<String>,
    /// The gimbal joint (and both CMs), parent frame, from the parent's CM, m.
    #[serde(default)]
    pub position: [f64; 3],
    /// The gimbal axis `ĝ`, parent frame.
    pub gimbal_axis: [f64; 3],
    /// The spin axis `ŝ₀` at `δ = 0`, parent frame, perpendicular to `ĝ`.
    pub spin_axis: [f64; 3],
    /// The rotor's spin moment `J_s`, kg·m² (> 0).
    pub rotor_inertia: f64,
    /// The rotor's transverse moment `J_t`, kg·m² (default `0.6 J_s`).
    #[serde(default)]
    pub rotor_transverse_inertia: Option<f64>,
    /// The gimbal's principal moments along `(ĝ, ŝ₀, ĝ × ŝ₀)`, kg·m² (default zero).
    #[serde(default)]
    pub gimbal_inertia: [f64; 3],
    /// Rotor mass, kg (default 0: counted in the parent).
    #[serde(default)]
    pub rotor_mass: f64,
    /// Gimbal mass, kg (default 0).
    #[serde(default)]
    pub gimbal_mass: f64,
    /// A motor on the spin joint (VSCMG); otherwise a free rotor (SGCMG, module docs).
    #[serde(default)]
    pub variable_speed: bool,
    /// The gimbal joint's velocity limit, rad/s (default none).
    #[serde(default)]
    pub max_gimbal_rate: Option<f64>,
    /// The spin joint's velocity limit, rad/s (default none).
    #[serde(default)]
    pub max_wheel_speed: Option<f64>,
    /// The gimbal motor's torque limit, N·m (default none).
    #[serde(default)]
    pub max_gimbal_torque: Option<f64>,
    /// The spin motor's torque limit, N·m (VSCMG only; default none).
    #[serde(default)]
    pub max_wheel_torque: Option<f64>,
}

/// One CMG found in a model by [`detect_cmgs`]; as data (the Python `_core.cmgs` dicts), the
/// body carrying the gimbal is `parent`.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Cmg {
    /// The gimbal link's name (the CMG's name).
    pub name: String,
    /// The body carrying the gimbal.
    #[serde(rename = "parent")]
    pub parent_body: usize,
    /// The gimbal joint's degree of freedom.
    pub gimbal_dof: usize,
    /// The spin joint's degree of freedom.
    pub rotor_dof: usize,
    /// `ĝ`, in the parent body's frame.
    pub gimbal_axis: [f64; 3],
    /// `ŝ₀` (at `δ = 0`), in the parent body's frame.
    pub spin_axis: [f64; 3],
    /// The rotor's spin moment `J_s`, kg·m².
    pub rotor_inertia: f64,
    /// Whether the spin joint has a motor (VSCMG).
    pub variable_speed: bool,
    /// Gimbal-rate limit, rad/s (infinite when none).
    pub max_gimbal_rate: f64,
    /// Wheel-speed limit, rad/s (infinite when none).
    pub max_wheel_speed: f64,
}

fn limit(v: Option<f64>) -> f64 {
    v.unwrap_or(f64::INFINITY)
}

/// `Σ m_k a_k a_kᵀ` over the orthonormal axes `a_k`.
fn principal(axes: &[[f64; 3]; 3], moments: &[f64; 3]) -> [[f64; 3]; 3] {
    let mut i = [[0.0; 3]; 3];
    for (r, row) in i.iter_mut().enumerate() {
        for (c, v) in row.iter_mut().enumerate() {
            *v = (0..3).map(|k| axes[k][r] * moments[k] * axes[k][c]).sum();
        }
    }
    i
}

/// The gimbal and rotor links of a CMG (module docs), each with its joint's dynamics; `base`
/// is the base's name (the parent when the spec names none). Every rule is checked here, with
/// a message naming the CMG, the field and what was expected; the builder checks the links again.
pub fn cmg_parts(spec: &CmgSpec, base: &str, item: ModelItem) -> Result<Parts, ModelError> {
    let who = format!("cmg '{}'", spec.name);
    let bad = |field: ModelField, msg: String| Err(ModelError::new(item, field, format!("{who}: {msg}")));
    let Some(g) = normalized(&spec.gimbal_axis) else {
        return bad(ModelField::Axis, format!("gimbal_axis must be a finite non-zero vector, got {:?}", spec.gimbal_axis));
    };
    let Some(s) = normalized(&spec.spin_axis) else {
        return bad(ModelField::Axis, format!("spin_axis must be a finite non-zero vector, got {:?}", spec.spin_axis));
    };
    if dot(&g, &s).abs() > 1e-9 {
        return bad(ModelField::Axis, format!("spin_axis {s:?} must be perpendicular to gimbal_axis {g:?}"));
    }
    if !positive(spec.rotor_inertia) {
        return bad(ModelField::Inertia, format!("rotor_inertia must be finite and > 0 kg m^2, got {}", spec.rotor_inertia));
    }
    let j_s = spec.rotor_inertia;
    let j_t = spec.rotor_transverse_inertia.unwrap_or(DEFAULT_TRANSVERSE_RATIO * j_s);
    if !positive(j_t) {
        return bad(ModelField::Inertia, format!("rotor_transverse_inertia must be finite and > 0 kg m^2, got {j_t}"));
    }
    if !spec.gimbal_inertia.iter().all(|v| non_negative(*v)) {
        return bad(ModelField::Inertia, format!("gimbal_inertia must be 3 finite moments >= 0 kg m^2 along (gimbal, spin, gimbal x spin), got {:?}", spec.gimbal_inertia));
    }
    for (what, m) in [("rotor_mass", spec.rotor_mass), ("gimbal_mass", spec.gimbal_mass)] {
        if !non_negative(m) {
            return bad(ModelField::Mass, format!("{what} must be finite and >= 0 kg, got {m}"));
        }
    }
    for (what, v) in [("max_gimbal_rate", spec.max_gimbal_rate), ("max_wheel_speed", spec.max_wheel_speed), ("max_gimbal_torque", spec.max_gimbal_torque), ("max_wheel_torque", spec.max_wheel_torque)] {
        if let Some(v) = v {
            if v.is_nan() || v <= 0.0 {
                return bad(ModelField::Limits, format!("{what} must be > 0 (or absent: no limit), got {v}"));
            }
        }
    }
    if !spec.variable_speed && spec.max_wheel_torque.is_some() {
        return bad(ModelField::Limits, "max_wheel_torque needs variable_speed = true: a single-gimbal CMG's rotor has no motor (docs/cmg.md)".into());
    }
    let parent = spec.parent.clone().unwrap_or_else(|| base.to_string());
    let t = cross(&g, &s);
    let gimbal = LinkSpec {
        name: spec.name.clone(),
        parent,
        joint_name: Some(format!("{}_gimbal", spec.name)),
        kind: JointType::Revolute,
        origin_in_parent: spec.position,
        rotation_in_parent: [0.0, 0.0, 0.0, 1.0],
        axis: g,
        com_from_joint: [0.0; 3],
        mass: spec.gimbal_mass,
        inertia: principal(&[g, s, t], &spec.gimbal_inertia),
        limits: JointLimits { velocity: limit(spec.max_gimbal_rate), effort: limit(spec.max_gimbal_torque), ..JointLimits::unlimited() },
    };
    let rotor = LinkSpec {
        name: format!("{}_rotor", spec.name),
        parent: spec.name.clone(),
        joint_name: Some(format!("{}_spin", spec.name)),
        kind: JointType::Revolute,
        origin_in_parent: [0.0; 3],
        rotation_in_parent: [0.0, 0.0, 0.0, 1.0],
        axis: s,
        com_from_joint: [0.0; 3],
        mass: spec.rotor_mass,
        inertia: principal(&[s, g, t], &[j_s, j_t, j_t]),
        limits: JointLimits { velocity: limit(spec.max_wheel_speed), effort: limit(spec.max_wheel_torque), ..JointLimits::unlimited() },
    };
    let spin = JointDynamics { actuated: spec.variable_speed, ..JointDynamics::default() };
    Ok(Parts { links: vec![(gimbal, JointDynamics::default()), (rotor, spin)], points: Vec::new(), geometries: Vec::new() })
}

/// The CMGs of a model, in link order: a revolute link `L` whose joint is `L_gimbal` and whose
/// one child is the leaf `L_rotor` on the revolute joint `L_spin` (what [`cmg_parts`] makes),
/// with the spin axis perpendicular to the gimbal axis, the rotor's CM on both axes and its
/// inertia symmetric about the spin axis (1e-9 relative). Anything else is not a CMG.
pub fn detect_cmgs(model: &Model) -> Vec<Cmg> {
    let links = model.links();
    let mut children = vec![Vec::new(); model.n_bodies()];
    for (k, l) in links.iter().enumerate() {
        children[l.parent].push(k + 1);
    }
    let mut out = Vec::new();
    for (k, gl) in links.iter().enumerate() {
        let body = k + 1;
        if gl.joint.kind != JointType::Revolute || gl.joint.name != format!("{}_gimbal", gl.name) || children[body].len() != 1 {
            continue;
        }
        let rb = children[body][0];
        let rl = &links[rb - 1];
        if rl.joint.kind != JointType::Revolute || rl.name != format!("{}_rotor", gl.name) || rl.joint.name != format!("{}_spin", gl.name) || !children[rb].is_empty() {
            continue;
        }
        // Axes in the gimbal frame: ĝ (gimbal link frame) and ŝ (rotor frame → gimbal frame).
        let g = gl.joint.axis.into_inner();
        let s = rl.joint.rotation_in_parent * rl.joint.axis.into_inner();
        if g.dot(&s).abs() > 1e-9 {
            continue;
        }
        // The rotor's CM (gimbal frame, from the gimbal joint) on the gimbal axis; the rotor a
        // symmetric rotor about its spin axis (Link::symmetric_rotor_moment).
        let rotor_cm_on_gimbal_axis = {
            let p = gl.com_from_joint + rl.joint.origin_in_parent + rl.joint.rotation_in_parent * rl.com_from_joint;
            (p - g * g.dot(&p)).norm() <= 1e-9
        };
        let Some(spin) = rl.symmetric_rotor_moment().filter(|_| rotor_cm_on_gimbal_axis) else { continue };
        let (Some(gimbal_dof), Some(rotor_dof)) = (model.dof_of_body(body), model.dof_of_body(rb)) else { continue };
        let to_parent = gl.joint.rotation_in_parent;
        let gp = to_parent * g;
        let sp = to_parent * s;
        out.push(Cmg {
            name: gl.name.clone(),
            parent_body: gl.parent,
            gimbal_dof,
            rotor_dof,
            gimbal_axis: [gp.x, gp.y, gp.z],
            spin_axis: [sp.x, sp.y, sp.z],
            rotor_inertia: spin,
            variable_speed: rl.joint.dynamics.actuated,
            max_gimbal_rate: gl.joint.limits.velocity,
            max_wheel_speed: rl.joint.limits.velocity,
        });
    }
    out
}

/// The generalized velocity `u` (length `6 + n`) with every CMG's spin joint at `wheel_speed`
/// (one value for all, or one per CMG in [`detect_cmgs`] order) and everything else at rest:
/// the initial condition of a run whose rotors spin (module docs).
pub fn cmg_velocity(model: &Model, wheel_speed: &[f64]) -> Result<Vec<f64>, ModelError> {
    let cmgs = detect_cmgs(model);
    let bad = |msg: String| Err(ModelError::new(ModelItem::Model, ModelField::JointDynamics, msg));
    if cmgs.is_empty() {
        return bad("the model has no CMG (add one with RobotBuilder.add_cmg or a [[cmg]] table)".into());
    }
    let speeds: Vec<f64> = match wheel_speed.len() {
        1 => vec![wheel_speed[0]; cmgs.len()],
        n if n == cmgs.len() => wheel_speed.to_vec(),
        n => return bad(format!("wheel_speed must be one value or one per CMG ({}), got {n}", cmgs.len())),
    };
    let mut u = vec![0.0; 6 + model.n_dof()];
    for (c, w) in cmgs.iter().zip(speeds) {
        if !w.is_finite() || w.abs() > c.max_wheel_speed {
            return bad(format!("cmg '{}': wheel_speed must be finite and within max_wheel_speed {} rad/s, got {w}", c.name, c.max_wheel_speed));
        }
        u[6 + c.rotor_dof] = w;
    }
    Ok(u)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::builder::ModelBuilder;

    fn spec(name: &str, g: [f64; 3], s: [f64; 3], variable: bool) -> CmgSpec {
        CmgSpec {
            name: name.into(),
            parent: None,
            position: [0.1, 0.0, 0.0],
            gimbal_axis: g,
            spin_axis: s,
            rotor_inertia: 0.05,
            rotor_transverse_inertia: None,
            gimbal_inertia: [0.01, 0.008, 0.006],
            rotor_mass: 2.0,
            gimbal_mass: 1.0,
            variable_speed: variable,
            max_gimbal_rate: Some(1.0),
            max_wheel_speed: Some(700.0),
            max_gimbal_torque: None,
            max_wheel_torque: None,
        }
    }

    fn model(specs: &[CmgSpec]) -> Model {
        let mut b = ModelBuilder::new("hub", "base", 100.0, [[10.0, 0.0, 0.0], [0.0, 12.0, 0.0], [0.0, 0.0, 14.0]]).unwrap();
        for s in specs {
            for (l, d) in cmg_parts(s, "base", ModelItem::Model).unwrap().links {
                let n = l.name.clone();
                b.add_link(l).unwrap();
                b.set_joint_dynamics(&n, d).unwrap();
            }
        }
        b.build().unwrap()
    }

    #[test]
    fn parts_are_found_again_with_their_axes_and_speeds() {
        let m = model(&[spec("a", [0.0, 0.0, 1.0], [1.0, 0.0, 0.0], false), spec("b", [1.0, 0.0, 0.0], [0.0, 2.0, 0.0], true)]);
        let c = detect_cmgs(&m);
        assert_eq!(c.len(), 2);
        assert_eq!((c[0].gimbal_dof, c[0].rotor_dof, c[1].gimbal_dof, c[1].rotor_dof), (0, 1, 2, 3));
        assert_eq!(c[1].spin_axis, [0.0, 1.0, 0.0]);
        assert!((c[0].rotor_inertia - 0.05).abs() < 1e-15);
        assert!(!c[0].variable_speed && c[1].variable_speed);
        assert!(!m.dof_dynamics()[1].actuated && m.dof_dynamics()[3].actuated);
        assert_eq!(c[0].max_gimbal_rate, 1.0);
        let u = cmg_velocity(&m, &[300.0, -200.0]).unwrap();
        assert_eq!(u[6 + 1], 300.0);
        assert_eq!(u[6 + 3], -200.0);
        assert_eq!(u.iter().filter(|v| **v != 0.0).count(), 2);
        assert!(cmg_velocity(&m, &[800.0]).is_err());
        assert!(cmg_velocity(&m, &[1.0, 2.0, 3.0]).is_err());
    }

    #[test]
    fn bad_specs_are_refused_by_name() {
        let mut s = spec("a", [0.0, 0.0, 1.0], [1.0, 0.0, 1.0], false);
        let e = cmg_parts(&s, "base", ModelItem::Model).unwrap_err();
        assert!(e.to_string().contains("cmg 'a'") && e.to_string().contains("perpendicular"), "{e}");
        s.spin_axis = [1.0, 0.0, 0.0];
        s.rotor_inertia = 0.0;
        assert!(cmg_parts(&s, "base", ModelItem::Model).unwrap_err().to_string().contains("rotor_inertia"));
        s.rotor_inertia = 0.05;
        s.max_wheel_torque = Some(1.0);
        assert!(cmg_parts(&s, "base", ModelItem::Model).unwrap_err().to_string().contains("variable_speed"));
        s.max_wheel_torque = None;
        s.max_gimbal_rate = Some(-1.0);
        assert!(cmg_parts(&s, "base", ModelItem::Model).unwrap_err().to_string().contains("max_gimbal_rate"));
    }

    #[test]
    fn a_renamed_or_unbalanced_pair_is_not_a_cmg() {
        let s = spec("a", [0.0, 0.0, 1.0], [1.0, 0.0, 0.0], false);
        let mut parts = cmg_parts(&s, "base", ModelItem::Model).unwrap();
        parts.links[1].0.com_from_joint = [0.0, 0.0, 0.01]; // rotor CM off the spin axis
        let mut b = ModelBuilder::new("hub", "base", 100.0, [[10.0, 0.0, 0.0], [0.0, 10.0, 0.0], [0.0, 0.0, 10.0]]).unwrap();
        for (l, _) in parts.links {
            b.add_link(l).unwrap();
        }
        assert!(detect_cmgs(&b.build().unwrap()).is_empty());
    }

    #[test]
    fn serde_reads_the_toml_fields() {
        let s: CmgSpec = toml::from_str("name = 'c1'\ngimbal_axis = [0, 0, 1]\nspin_axis = [1, 0, 0]\nrotor_inertia = 0.05\nvariable_speed = true").unwrap();
        assert_eq!(s.name, "c1");
        assert!(s.variable_speed && s.parent.is_none() && s.max_gimbal_rate.is_none());
        assert!(toml::from_str::<CmgSpec>("name = 'c1'\ngimbal_axis = [0, 0, 1]\nspin_axis = [1, 0, 0]\nrotor_inertia = 0.05\nspeed = 3").is_err());
    }
}
