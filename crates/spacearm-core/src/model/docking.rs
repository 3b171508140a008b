//! A probe–drogue docking mechanism as collision geometry (docs/contact.md, "Probe and
//! drogue"): shapes fixed to existing bodies, no links.
//!
//! - the **probe** `<name>`: a capsule of radius `r` on `body`, its segment from `position`
//!   (body frame, from the CM) along the `+z` of `rotation` (`[x, y, z, w]`) for `length`, and
//!   its head `<name>_head`, a ball of radius `head_radius` (default `r`) centred on the
//!   segment's end, where the point `<name>_tip` is. The head is what meets the drogue: a ball
//!   against the ribs' capsules is a closed-form query of the collision library, where two
//!   interpenetrating capsules go through its GJK/EPA, whose EPA can fail (no contact found);
//! - the **drogue** `<name>`: a cone approximated by `ribs` capsules (radius `ρ`) in the frame
//!   at `position` turned by `rotation`, whose `+z` is the drogue's axis out of its mouth: rib
//!   `i` joins the throat point `(r_t cos θᵢ, r_t sin θᵢ, 0)` to the mouth point
//!   `(R_m cos θᵢ, R_m sin θᵢ, h)`, `θᵢ = 2πi/N`; a cylinder of radius `r_t + ρ` and thickness
//!   `2ρ` closes the throat, its face the plane `z = 0`; the points `<name>_throat` (the
//!   throat's centre) and `<name>_mouth` (`(0, 0, h)`). A probe tip of radius `r` cannot pass
//!   between two ribs at the mouth when `r > R_m sin(π/N) − ρ`; the ribs are capsules because
//!   the collision library handles them in closed form against the probe's capsule.

use nalgebra::{UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::error::{ModelError, ModelField, ModelItem};
use crate::math::rotations::xyzw;
use crate::model::appendage::Parts;
use crate::model::geometry::{GeometryRole, GeometrySpec, Shape};
use crate::model::validate::positive;

/// Everything [`probe_parts`] needs (module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProbeSpec {
    /// The probe's name (its capsule's; the tip point is `<name>_tip`).
    pub name: String,
    /// The body carrying it.
    pub body: String,
    /// The probe's root in the body frame, from the CM, m.
    #[serde(default)]
    pub position: [f64; 3],
    /// The probe's frame in the body frame, `[x, y, z, w]` (the probe along its `+z`).
    #[serde(default = "identity")]
    pub rotation: [f64; 4],
    /// The capsule's segment length, m (> 0).
    pub length: f64,
    /// Its radius, m (> 0).
    pub radius: f64,
    /// The head ball's radius, m (> 0; default `radius`).
    #[serde(default)]
    pub head_radius: Option<f64>,
}

/// Everything [`drogue_parts`] needs (module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DrogueSpec {
    /// The drogue's name (its ribs are `<name>_rib<i>`, the throat's plate `<name>_throat_plate`).
    pub name: String,
    /// The body carrying it.
    pub body: String,
    /// The throat's centre in the body frame, from the CM, m.
    #[serde(default)]
    pub position: [f64; 3],
    /// The drogue's frame in the body frame, `[x, y, z, w]` (its axis, out of the mouth, `+z`).
    #[serde(default = "identity")]
    pub rotation: [f64; 4],
    /// `R_m`, the radius of the mouth's circle of rib ends, m (> throat_radius).
    pub mouth_radius: f64,
    /// `r_t`, the radius of the throat's circle of rib ends, m (> 0).
    pub throat_radius: f64,
    /// `h`, the mouth's height above the throat, m (> 0).
    pub depth: f64,
    /// `ρ`, the ribs' radius, m (> 0).
    pub rib_radius: f64,
    /// `N`, the number of ribs (≥ 3; default 12).
    #[serde(default = "twelve")]
    pub ribs: usize,
}

fn identity() -> [f64; 4] {
    [0.0, 0.0, 0.0, 1.0]
}
fn twelve() -> usize {
    12
}

fn frame(who: &str, item: ModelItem, q: [f64; 4]) -> Result<UnitQuaternion<f64>, ModelError> {
    let norm = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    if !(norm.is_finite() && (norm - 1.0).abs() < 1e-6) {
        return Err(ModelError::new(item, ModelField::Rotation, format!("{who}: rotation must be a unit quaternion [x, y, z, w], got {q:?}")));
    }
    Ok(UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q[3], q[0], q[1], q[2])))
}

fn lengths(who: &str, item: ModelItem, values: &[(&str, f64)]) -> Result<(), ModelError> {
    for &(what, v) in values {
        if !positive(v) {
            return Err(ModelError::new(item, ModelField::Offset, format!("{who}: {what} must be finite and > 0 m, got {v}")));
        }
    }
    Ok(())
}

/// A capsule from `a` to `b` (body frame) of radius `radius` on `body`.
fn segment(name: String, body: &str, a: Vector3<f64>, b: Vector3<f64>, radius: f64) -> GeometrySpec {
    let along = b - a;
    let turn = UnitQuaternion::rotation_between(&Vector3::z(), &along).unwrap_or_else(|| UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI));
    GeometrySpec {
        name: Some(name),
        origin: ((a + b) * 0.5).into(),
        rotation: xyzw(&turn),
        ..GeometrySpec::new(body, GeometryRole::Collision, Shape::Capsule { radius, length: along.norm() })
    }
}

/// The probe's capsule and tip point (module docs); every value checked, naming the probe.
pub fn probe_parts(spec: &ProbeSpec, item: ModelItem) -> Result<Parts, ModelError> {
    let who = format!("probe '{}'", spec.name);
    let head = spec.head_radius.unwrap_or(spec.radius);
    lengths(&who, item, &[("length", spec.length), ("radius", spec.radius), ("head_radius", head)])?;
    let r = frame(&who, item, spec.rotation)?;
    let root = Vector3::from(spec.position);
    if !root.iter().all(|v| v.is_finite()) {
        return Err(ModelError::new(item, ModelField::Offset, format!("{who}: position must be finite, got {:?}", spec.position)));
    }
    let tip = root + r * Vector3::new(0.0, 0.0, spec.length);
    let mut parts = Parts::default();
    parts.geometries.push(segment(spec.name.clone(), &spec.body, root, tip, spec.radius));
    parts.geometries.push(GeometrySpec {
        name: Some(format!("{}_head", spec.name)),
        origin: tip.into(),
        ..GeometrySpec::new(&spec.body, GeometryRole::Collision, Shape::Sphere { radius: head })
    });
    parts.points.push((format!("{}_tip", spec.name), spec.body.clone(), tip.into()));
    Ok(parts)
}

/// The drogue's ribs, throat plate and points (module docs); every value checked, naming the
/// drogue.
pub fn drogue_parts(spec: &DrogueSpec, item: ModelItem) -> Result<Parts, ModelError> {
    let who = format!("drogue '{}'", spec.name);
    lengths(&who, item, &[("mouth_radius", spec.mouth_radius), ("throat_radius", spec.throat_radius), ("depth", spec.depth), ("rib_radius", spec.rib_radius)])?;
    if spec.mouth_radius <= spec.throat_radius {
        return Err(ModelError::new(item, ModelField::Offset, format!("{who}: mouth_radius {} m must exceed throat_radius {} m (a cone opening out of the throat)", spec.mouth_radius, spec.throat_radius)));
    }
    if spec.ribs < 3 {
        return Err(ModelError::new(item, ModelField::Name, format!("{who}: ribs must be at least 3, got {}", spec.ribs)));
    }
    let r = frame(&who, item, spec.rotation)?;
    let at = Vector3::from(spec.position);
    if !at.iter().all(|v| v.is_finite()) {
        return Err(ModelError::new(item, ModelField::Offset, format!("{who}: position must be finite, got {:?}", spec.position)));
    }
    let (rt, rm, h, rho) = (spec.throat_radius, spec.mouth_radius, spec.depth, spec.rib_radius);
    let mut parts = Parts::default();
    for i in 0..spec.ribs {
        let th = 2.0 * std::f64::consts::PI * i as f64 / spec.ribs as f64;
        let (c, s) = (th.cos(), th.sin());
        let a = at + r * Vector3::new(rt * c, rt * s, 0.0);
        let b = at + r * Vector3::new(rm * c, rm * s, h);
        parts.geometries.push(segment(format!("{}_rib{i}", spec.name), &spec.body, a, b, rho));
    }
    parts.geometries.push(GeometrySpec {
        name: Some(format!("{}_throat_plate", spec.name)),
        origin: (at + r * Vector3::new(0.0, 0.0, -rho)).into(),
        rotation: xyzw(&r),
        ..GeometrySpec::new(&spec.body, GeometryRole::Collision, Shape::Cylinder { radius: rt + rho, length: 2.0 * rho })
    });
    parts.points.push((format!("{}_throat", spec.name), spec.body.clone(), at.into()));
    parts.points.push((format!("{}_mouth", spec.name), spec.body.clone(), (at + r * Vector3::new(0.0, 0.0, h)).into()));
    Ok(parts)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn drogue() -> DrogueSpec {
        DrogueSpec {
            name: "cone".into(),
            body: "target".into(),
            position: [0.1, 0.0, 0.0],
            rotation: [0.0, -std::f64::consts::FRAC_1_SQRT_2, 0.0, std::f64::consts::FRAC_1_SQRT_2], // +z → −x
            mouth_radius: 0.2,
            throat_radius: 0.04,
            depth: 0.3,
            rib_radius: 0.01,
            ribs: 8,
        }
    }

    #[test]
    fn ribs_join_the_throat_circle_to_the_mouth_circle() {
        let parts = drogue_parts(&drogue(), ModelItem::Model).unwrap();
        assert_eq!(parts.geometries.len(), 9);
        for (i, g) in parts.geometries[..8].iter().enumerate() {
            let Shape::Capsule { radius, length } = g.shape else { panic!("a rib is a capsule") };
            let q = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(g.rotation[3], g.rotation[0], g.rotation[1], g.rotation[2]));
            let half = q * Vector3::new(0.0, 0.0, 0.5 * length);
            let (a, b) = (Vector3::from(g.origin) - half, Vector3::from(g.origin) + half);
            // the frame turns +z to −x: the throat at x = 0.1, the mouth at x = 0.1 − 0.3
            let th = 2.0 * std::f64::consts::PI * i as f64 / 8.0;
            let ra = Vector3::new(0.1 + 0.0, 0.04 * th.sin(), 0.04 * th.cos());
            let rb = Vector3::new(0.1 - 0.3, 0.2 * th.sin(), 0.2 * th.cos());
            assert!((a - ra).norm() < 1e-14 && (b - rb).norm() < 1e-14, "rib {i}: {a} {b}");
            assert_eq!(radius, 0.01);
        }
        let mouth = Vector3::from(parts.points[1].2);
        assert!((mouth - Vector3::new(0.1 - 0.3, 0.0, 0.0)).norm() < 1e-15, "{mouth}");
    }

    #[test]
    fn bad_drogues_and_probes_are_named() {
        let err = |d: DrogueSpec| drogue_parts(&d, ModelItem::Model).unwrap_err().to_string();
        assert!(err(DrogueSpec { mouth_radius: 0.03, ..drogue() }).contains("drogue 'cone': mouth_radius 0.03 m must exceed throat_radius"));
        assert!(err(DrogueSpec { ribs: 2, ..drogue() }).contains("ribs must be at least 3"));
        assert!(err(DrogueSpec { depth: -1.0, ..drogue() }).contains("depth must be finite and > 0"));
        assert!(err(DrogueSpec { rotation: [0.0, 0.0, 0.0, 2.0], ..drogue() }).contains("unit quaternion"));
        let probe = ProbeSpec { name: "p".into(), body: "base".into(), position: [1.0, 0.0, 0.0], rotation: [0.0, 0.0, 0.0, 1.0], length: 0.5, radius: 0.0, head_radius: None };
        assert!(probe_parts(&probe, ModelItem::Model).unwrap_err().to_string().contains("probe 'p': radius must be finite and > 0"));
        let parts = probe_parts(&ProbeSpec { radius: 0.02, ..probe }, ModelItem::Model).unwrap();
        assert_eq!(parts.points[0].2, [1.0, 0.0, 0.5]);
        assert_eq!(parts.geometries[0].origin, [1.0, 0.0, 0.25]);
        assert_eq!((parts.geometries[1].origin, parts.geometries[1].shape.clone()), ([1.0, 0.0, 0.5], Shape::Sphere { radius: 0.02 }));
    }
}
