//! A controller's model that differs from the plant: scale errors in the base and link mass
//! properties, and a fuel-slosh-like redistribution of part of the base mass (the practical
//! cause of model error the paper names for computed torque, eqs. 112–115).

use nalgebra::{Matrix3, Vector3};

use crate::model::body::MassProperties;
use crate::error::{ModelItem, Result, SpacearmError};
use crate::model::Model;

/// How a fraction of the base mass (a point mass at the base CM, e.g. fuel) differs in the
/// perturbed model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Slosh {
    /// No slosh.
    None,
    /// The fraction `f` of the (scaled) base mass moves from the base CM to `offset` (base
    /// frame): the base CM moves by `f · offset` and the inertia about the new CM gains
    /// `f m0 (1 − f) (|d|² E − d dᵀ)`.
    Moved {
        /// `f`, in `[0, 1)`.
        fraction: f64,
        /// Where the moved mass sits, from the base CM in the base frame, m.
        offset: Vector3<f64>,
    },
    /// The fraction `f` of the base mass is absent from the model (a point mass at the base CM:
    /// the inertia about the CM is unchanged).
    Removed {
        /// `f`, in `[0, 1)`.
        fraction: f64,
    },
}

fn check_scale(what: &str, v: f64) -> Result<f64> {
    if !(v.is_finite() && v > 0.0) {
        return Err(SpacearmError::argument(format!("{what} must be finite and > 0, got {v}")));
    }
    Ok(v)
}

/// A copy of `model` with the base mass scaled by `base_mass_scale`, the base inertia by
/// `base_inertia_scale`, every link's mass and inertia by `link_mass_scale` (a density error),
/// then `slosh` applied. The joint geometry is unchanged; if the base CM moves, the base frame
/// (whose origin is the base CM, docs/conventions.md) moves with it, so joint origins and points on
/// the base are re-expressed from the new CM. Joint-space quantities (`H*`, `c*`) do not
/// depend on where the base reference point is, so such a model can be evaluated at the
/// plant's state.
pub fn perturbed_model(model: &Model, base_mass_scale: f64, base_inertia_scale: f64, link_mass_scale: f64, slosh: Slosh) -> Result<Model> {
    check_scale("base_mass_scale", base_mass_scale)?;
    check_scale("base_inertia_scale", base_inertia_scale)?;
    check_scale("link_mass_scale", link_mass_scale)?;
    let mut m0 = model.base().mass * base_mass_scale;
    let mut i0 = model.base().inertia * base_inertia_scale;
    let mut cm_shift = Vector3::zeros();
    let (fraction, offset) = match slosh {
        Slosh::None => (0.0, Vector3::zeros()),
        Slosh::Moved { fraction, offset } => (fraction, offset),
        Slosh::Removed { fraction } => (fraction, Vector3::zeros()),
    };
    if !(0.0..1.0).contains(&fraction) {
        return Err(SpacearmError::argument(format!("slosh_fraction must be in [0, 1), got {fraction}")));
    }
    if offset.iter().any(|v| !v.is_finite()) {
        return Err(SpacearmError::argument(format!("slosh_offset must be finite, got [{}, {}, {}]", offset.x, offset.y, offset.z)));
    }
    match slosh {
        Slosh::None => {}
        Slosh::Moved { fraction, offset } => {
            let ms = fraction * m0;
            let c = offset * fraction;
            let pa = |m: f64, d: &Vector3<f64>| (Matrix3::identity() * d.norm_squared() - d * d.transpose()) * m;
            i0 = i0 + pa(ms, &offset) - pa(m0, &c);
            cm_shift = c;
        }
        Slosh::Removed { fraction } => {
            m0 *= 1.0 - fraction;
        }
    }
    // The copy accepts what the model accepted (published inertias that break the triangle
    // inequality stay loadable when perturbed), with the perturbed bodies' own warnings.
    let rule = model.triangle_inequality();
    let (base, warning) = MassProperties::checked(ModelItem::Base, &format!("perturbed base '{}'", model.base_name()), m0, i0, true, rule)?;
    let mut warnings: Vec<String> = warning.into_iter().collect();
    let mut links = model.links().to_vec();
    for (k, link) in links.iter_mut().enumerate() {
        let who = format!("perturbed link '{}'", link.name);
        let (mass, warning) =
            MassProperties::checked(ModelItem::Link(k), &who, link.mass.mass * link_mass_scale, link.mass.inertia * link_mass_scale, false, rule)?;
        link.mass = mass;
        warnings.extend(warning);
        if link.parent == 0 {
            link.joint.origin_in_parent -= cm_shift;
        }
    }
    let mut points = model.points().to_vec();
    for p in &mut points {
        if p.body == 0 {
            p.offset -= cm_shift;
        }
    }
    Ok(Model::new(
        format!("{}_perturbed", model.name()),
        model.base_name().to_string(),
        base,
        links,
        points,
        model.end_effector(),
        Some(model.initial_q().to_vec()),
    )?
    .with_triangle_inequality(rule, warnings))
}

/// A copy of `model` whose control-moment gyros (docs/cmg.md; found by
/// [`crate::model::cmg::detect_cmgs`]) differ from the nominal ones the way a flight unit does:
/// every rotor's inertia tensor (`J_s` and `J_t`, so it stays symmetric about the spin axis) is
/// scaled by `rotor_inertia_scale`, and CMG `i`'s whole unit — its gimbal joint frame, so the
/// gimbal axis `ĝ`, the spin axis `ŝ₀` and both bodies turn together, `ŝ₀ ⟂ ĝ` kept — is turned
/// about its gimbal joint by the rotation vector `tilts[i]` (parent frame, rad): a mounting
/// misalignment, `R' = exp(tilt×) R` (docs/conventions.md). `tilts` is empty (no misalignment) or
/// has one vector per CMG in `detect_cmgs` order. Everything else is the model's, bit for bit.
pub fn perturbed_cmgs(model: &Model, rotor_inertia_scale: f64, tilts: &[[f64; 3]]) -> Result<Model> {
    check_scale("rotor_inertia_scale", rotor_inertia_scale)?;
    let cmgs = crate::model::cmg::detect_cmgs(model);
    if cmgs.is_empty() {
        return Err(SpacearmError::argument("perturbed_cmgs: the model has no CMG (RobotBuilder.add_cmg, TOML [[cmg]], URDF <spacearm><cmg>)".to_string()));
    }
    if !tilts.is_empty() && tilts.len() != cmgs.len() {
        return Err(SpacearmError::argument(format!("perturbed_cmgs: tilts must be empty or one rotation vector per CMG ({}), got {}", cmgs.len(), tilts.len())));
    }
    if let Some(t) = tilts.iter().find(|t| t.iter().any(|v| !v.is_finite())) {
        return Err(SpacearmError::argument(format!("perturbed_cmgs: every tilt must be a finite rotation vector (rad), got {t:?}")));
    }
    let rule = model.triangle_inequality();
    let mut warnings: Vec<String> = model.inertia_warnings().to_vec();
    let mut links = model.links().to_vec();
    for (i, c) in cmgs.iter().enumerate() {
        let gimbal = model.body_of_dof(c.gimbal_dof) - 1;
        let rotor = model.body_of_dof(c.rotor_dof) - 1;
        if let Some(t) = tilts.get(i) {
            let turn = nalgebra::UnitQuaternion::from_scaled_axis(Vector3::new(t[0], t[1], t[2]));
            links[gimbal].joint.rotation_in_parent = turn * links[gimbal].joint.rotation_in_parent;
        }
        let who = format!("perturbed rotor '{}'", links[rotor].name);
        let (mass, warning) = MassProperties::checked(ModelItem::Link(rotor), &who, links[rotor].mass.mass,
                                                      links[rotor].mass.inertia * rotor_inertia_scale, false, rule)?;
        links[rotor].mass = mass;
        warnings.extend(warning);
    }
    Ok(Model::new(
        model.name().to_string(),
        model.base_name().to_string(),
        model.base().clone(),
        links,
        model.points().to_vec(),
        model.end_effector(),
        Some(model.initial_q().to_vec()),
    )?
    .with_geometries(model.geometries().to_vec())
    .with_triangle_inequality(rule, warnings))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algorithms::momentum::center_of_mass;
    use crate::Data;

    #[test]
    fn perturbed_copies_keep_the_triangle_inequality_rule() {
        use crate::model::TriangleInequality;
        let published = crate::model::presets::ets7_with(TriangleInequality::Warn);
        let m = perturbed_model(&published, 1.1, 0.9, 1.05, Slosh::None).unwrap();
        assert_eq!(m.triangle_inequality(), TriangleInequality::Warn);
        assert_eq!(m.inertia_warnings().len(), 3);
        assert!(m.inertia_warnings()[0].contains("perturbed link 'link1'"));
        // A physical model stays strict and silent.
        let strict = perturbed_model(&crate::model::presets::ets7(), 1.1, 0.9, 1.05, Slosh::None).unwrap();
        assert_eq!(strict.triangle_inequality(), TriangleInequality::Enforce);
        assert!(strict.inertia_warnings().is_empty());
    }

    #[test]
    fn moving_slosh_mass_keeps_total_mass_and_shifts_the_base_cm() {
        let plant = crate::model::presets::spatial6();
        let d = Vector3::new(0.3, -0.1, 0.2);
        let f = 0.1;
        let m = perturbed_model(&plant, 1.0, 1.0, 1.0, Slosh::Moved { fraction: f, offset: d }).unwrap();
        assert!((m.total_mass() - plant.total_mass()).abs() < 1e-12);
        // Same geometry: the system CM of the perturbed model, measured from the plant's base
        // CM, is the plant's plus m_s d / M (independent closed form).
        let x = crate::model::presets::initial_configuration(&plant);
        let rg_plant = center_of_mass(&plant, &mut Data::new(&plant), &x).unwrap();
        let rg_model = center_of_mass(&m, &mut Data::new(&m), &x).unwrap();
        // The model's base CM sits at f d from the plant's, so its r0 = x[0..3] is the plant's
        // r0 + f d: in plant coordinates, the model's CM is rg_model + f d.
        let expect = rg_plant + d * (f * plant.base().mass / plant.total_mass());
        assert!((rg_model + d * f - expect).norm() < 1e-12, "{rg_model} vs {expect}");
        // Inertia about the new CM by the parallel-axis theorem applied to the two masses.
        let ms = f * plant.base().mass;
        let c = d * f;
        let pa = |m: f64, v: &Vector3<f64>| (Matrix3::identity() * v.norm_squared() - v * v.transpose()) * m;
        let about_old = plant.base().inertia + pa(ms, &d);
        assert!((m.base().inertia + pa(plant.base().mass, &c) - about_old).norm() < 1e-12);
    }

    #[test]
    fn scales_and_removal() {
        let plant = crate::model::presets::planar4();
        let m = perturbed_model(&plant, 1.2, 0.8, 1.1, Slosh::Removed { fraction: 0.25 }).unwrap();
        assert!((m.base().mass - plant.base().mass * 1.2 * 0.75).abs() < 1e-12);
        assert!((m.base().inertia - plant.base().inertia * 0.8).norm() < 1e-12);
        assert!((m.links()[2].mass.mass - plant.links()[2].mass.mass * 1.1).abs() < 1e-12);
        assert!(perturbed_model(&plant, 0.0, 1.0, 1.0, Slosh::None).is_err());
        assert!(perturbed_model(&plant, 1.0, 1.0, 1.0, Slosh::Removed { fraction: 1.0 }).is_err());
        assert!(perturbed_model(&plant, 1.0, 1.0, 1.0, Slosh::Moved { fraction: 0.1, offset: Vector3::new(f64::NAN, 0.0, 0.0) }).is_err());
    }
}

#[cfg(test)]
mod cmg_tests {
    use super::*;
    use crate::model::builder::ModelBuilder;
    use crate::model::cmg::{cmg_parts, detect_cmgs, CmgSpec};

    fn two_cmgs() -> Model {
        let mut b = ModelBuilder::new("hub", "base", 100.0, [[10.0, 0.0, 0.0], [0.0, 12.0, 0.0], [0.0, 0.0, 14.0]]).unwrap();
        for (name, g, s) in [("a", [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]), ("b", [1.0, 0.0, 0.0], [0.0, 1.0, 0.0])] {
            let spec = CmgSpec {
                name: name.into(), parent: None, position: [0.2, 0.0, 0.1], gimbal_axis: g, spin_axis: s, rotor_inertia: 0.05,
                rotor_transverse_inertia: None, gimbal_inertia: [0.01, 0.008, 0.006], rotor_mass: 2.0, gimbal_mass: 1.0,
                variable_speed: false, max_gimbal_rate: None, max_wheel_speed: None, max_gimbal_torque: None, max_wheel_torque: None,
            };
            for (l, d) in cmg_parts(&spec, "base", ModelItem::Model).unwrap().links {
                let n = l.name.clone();
                b.add_link(l).unwrap();
                b.set_joint_dynamics(&n, d).unwrap();
            }
        }
        b.build().unwrap()
    }

    /// Rodrigues' formula, written out: `v` turned by the angle `|t|` about `t / |t|`.
    fn rodrigues(t: [f64; 3], v: [f64; 3]) -> [f64; 3] {
        let a = (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt();
        let k = [t[0] / a, t[1] / a, t[2] / a];
        let kxv = [k[1] * v[2] - k[2] * v[1], k[2] * v[0] - k[0] * v[2], k[0] * v[1] - k[1] * v[0]];
        let kv = k[0] * v[0] + k[1] * v[1] + k[2] * v[2];
        [0, 1, 2].map(|i| v[i] * a.cos() + kxv[i] * a.sin() + k[i] * kv * (1.0 - a.cos()))
    }

    #[test]
    fn rotor_inertia_scales_and_the_unit_turns_as_one() {
        let m = two_cmgs();
        let tilts = [[0.01, -0.02, 0.0], [0.0, 0.0, 0.03]];
        let p = perturbed_cmgs(&m, 1.2, &tilts).unwrap();
        let (before, after) = (detect_cmgs(&m), detect_cmgs(&p));
        assert_eq!(after.len(), 2, "both are still CMGs (spin axis still perpendicular, rotor symmetric)");
        for (i, (c0, c1)) in before.iter().zip(&after).enumerate() {
            assert!((c1.rotor_inertia - 1.2 * 0.05).abs() < 1e-15);
            let (g, s) = (rodrigues(tilts[i], c0.gimbal_axis), rodrigues(tilts[i], c0.spin_axis));
            for k in 0..3 {
                assert!((c1.gimbal_axis[k] - g[k]).abs() < 1e-15 && (c1.spin_axis[k] - s[k]).abs() < 1e-15, "{c1:?}");
            }
            // The tilt really turned the axes (not a test that passes on an identity).
            assert!((c1.gimbal_axis[0] - c0.gimbal_axis[0]).abs() + (c1.gimbal_axis[1] - c0.gimbal_axis[1]).abs() > 1e-3 || i == 1);
        }
        assert!((p.links()[1].mass.inertia - m.links()[1].mass.inertia * 1.2).norm() < 1e-16);
        assert_eq!(p.links()[0].mass.inertia, m.links()[0].mass.inertia);
        assert_eq!(p.total_mass(), m.total_mass());
        // No tilt and a unit scale: the model's links, bit for bit.
        let same = perturbed_cmgs(&m, 1.0, &[]).unwrap();
        for (a, b) in same.links().iter().zip(m.links()) {
            assert_eq!((a.mass.inertia, a.joint.rotation_in_parent), (b.mass.inertia, b.joint.rotation_in_parent));
        }
    }

    #[test]
    fn bad_perturbations_are_refused_by_name() {
        let m = two_cmgs();
        assert!(perturbed_cmgs(&m, 0.0, &[]).unwrap_err().to_string().contains("rotor_inertia_scale"));
        assert!(perturbed_cmgs(&m, 1.0, &[[0.0; 3]]).unwrap_err().to_string().contains("one rotation vector per CMG (2), got 1"));
        assert!(perturbed_cmgs(&m, 1.0, &[[f64::NAN, 0.0, 0.0], [0.0; 3]]).unwrap_err().to_string().contains("finite rotation vector"));
        let plain = crate::model::presets::spatial6();
        assert!(perturbed_cmgs(&plain, 1.1, &[]).unwrap_err().to_string().contains("has no CMG"));
    }
}
