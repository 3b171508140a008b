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
use crate::math::rotations::{unit_quaternion_from_xyzw, xyzw};
use crate::model::appendage::Parts;
use crate::model::geometry::{GeometryRole, GeometrySpec, Shape};
use crate::model::validate::{self, positive};

/// Where a docking part sits, the keys every part has: its name, the body carrying it and its
/// frame on that body (module docs). Read flattened into [`ProbeSpec`] and [`DrogueSpec`], whose
/// tables carry these keys beside their own.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DockingMount {
    /// The part's name (its shapes' and points' names derive from it, module docs).
    pub name: String,
    /// The body carrying it.
    pub body: String,
    /// The part frame's origin in the body frame, from the CM, m: the probe's root, the
    /// drogue's throat centre.
    #[serde(default)]
    pub position: [f64; 3],
    /// The part's frame in the body frame, `[x, y, z, w]`: its `+z` is the probe's direction, the
    /// drogue's axis out of its mouth.
    #[serde(default = "identity")]
    pub rotation: [f64; 4],
}

/// Everything [`probe_parts`] needs (module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProbeSpec {
    /// The probe's name (its capsule's; the tip point is `<name>_tip`), body and frame.
    #[serde(flatten)]
    pub mount: DockingMount,
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
    /// The drogue's name (its ribs are `<name>_rib<i>`, the throat's plate
    /// `<name>_throat_plate`), body and frame.
    #[serde(flatten)]
    pub mount: DockingMount,
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

impl DockingMount {
    /// The part's origin and rotation in the body frame: a finite position within the model's
    /// lengths and a unit quaternion ([`validate::position`], [`unit_quaternion_from_xyzw`]).
    fn frame(&self, who: &str, item: ModelItem) -> Result<(Vector3<f64>, UnitQuaternion<f64>), ModelError> {
        let rotation = unit_quaternion_from_xyzw(&format!("{who}: rotation"), &self.rotation).map_err(|e| ModelError::new(item, ModelField::Rotation, e.to_string()))?;
        Ok((validate::position(item, ModelField::Offset, who, "position", &self.position)?, rotation))
    }
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
    let DockingMount { name, body, .. } = &spec.mount;
    let who = format!("probe '{name}'");
    let head = spec.head_radius.unwrap_or(spec.radius);
    lengths(&who, item, &[("length", spec.length), ("radius", spec.radius), ("head_radius", head)])?;
    let (root, r) = spec.mount.frame(&who, item)?;
    let tip = root + r * Vector3::new(0.0, 0.0, spec.length);
    let mut parts = Parts::default();
    parts.geometries.push(segment(name.clone(), body, root, tip, spec.radius));
    parts.geometries.push(GeometrySpec {
        name: Some(format!("{name}_head")),
        origin: tip.into(),
        ..GeometrySpec::new(body, GeometryRole::Collision, Shape::Sphere { radius: head })
    });
    parts.points.push((format!("{name}_tip"), body.clone(), tip.into()));
    Ok(parts)
}

/// The drogue's ribs, throat plate and points (module docs); every value checked, naming the
/// drogue.
pub fn drogue_parts(spec: &DrogueSpec, item: ModelItem) -> Result<Parts, ModelError> {
    let DockingMount { name, body, .. } = &spec.mount;
    let who = format!("drogue '{name}'");
    lengths(&who, item, &[("mouth_radius", spec.mouth_radius), ("throat_radius", spec.throat_radius), ("depth", spec.depth), ("rib_radius", spec.rib_radius)])?;
    if spec.mouth_radius <= spec.throat_radius {
        return Err(ModelError::new(item, ModelField::Offset, format!("{who}: mouth_radius {} m must exceed throat_radius {} m (a cone opening out of the throat)", spec.mouth_radius, spec.throat_radius)));
    }
    if spec.ribs < 3 {
        return Err(ModelError::new(item, ModelField::Name, format!("{who}: ribs must be at least 3, got {}", spec.ribs)));
    }
    let (at, r) = spec.mount.frame(&who, item)?;
    let (rt, rm, h, rho) = (spec.throat_radius, spec.mouth_radius, spec.depth, spec.rib_radius);
    let mut parts = Parts::default();
    for i in 0..spec.ribs {
        let th = 2.0 * std::f64::consts::PI * i as f64 / spec.ribs as f64;
        let (c, s) = (th.cos(), th.sin());
        let a = at + r * Vector3::new(rt * c, rt * s, 0.0);
        let b = at + r * Vector3::new(rm * c, rm * s, h);
        parts.geometries.push(segment(format!("{name}_rib{i}"), body, a, b, rho));
    }
    parts.geometries.push(GeometrySpec {
        name: Some(format!("{name}_throat_plate")),
        origin: (at + r * Vector3::new(0.0, 0.0, -rho)).into(),
        rotation: xyzw(&r),
        ..GeometrySpec::new(body, GeometryRole::Collision, Shape::Cylinder { radius: rt + rho, length: 2.0 * rho })
    });
    parts.points.push((format!("{name}_throat"), body.clone(), at.into()));
    parts.points.push((format!("{name}_mouth"), body.clone(), (at + r * Vector3::new(0.0, 0.0, h)).into()));
    Ok(parts)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn drogue() -> DrogueSpec {
        DrogueSpec {
            mount: DockingMount {
                name: "cone".into(),
                body: "target".into(),
                position: [0.1, 0.0, 0.0],
                rotation: [0.0, -std::f64::consts::FRAC_1_SQRT_2, 0.0, std::f64::consts::FRAC_1_SQRT_2], // +z → −x
            },
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
        let turned = |rotation| DrogueSpec { mount: DockingMount { rotation, ..drogue().mount }, ..drogue() };
        assert!(err(turned([0.0, 0.0, 0.0, 2.0])).contains("drogue 'cone': rotation must be a unit quaternion"));
        let moved = DrogueSpec { mount: DockingMount { position: [f64::NAN, 0.0, 0.0], ..drogue().mount }, ..drogue() };
        assert!(err(moved).contains("drogue 'cone': position must be finite"));
        let mount = DockingMount { name: "p".into(), body: "base".into(), position: [1.0, 0.0, 0.0], rotation: [0.0, 0.0, 0.0, 1.0] };
        let probe = ProbeSpec { mount, length: 0.5, radius: 0.0, head_radius: None };
        assert!(probe_parts(&probe, ModelItem::Model).unwrap_err().to_string().contains("probe 'p': radius must be finite and > 0"));
        let parts = probe_parts(&ProbeSpec { radius: 0.02, ..probe }, ModelItem::Model).unwrap();
        assert_eq!(parts.points[0].2, [1.0, 0.0, 0.5]);
        assert_eq!(parts.geometries[0].origin, [1.0, 0.0, 0.25]);
        assert_eq!((parts.geometries[1].origin, parts.geometries[1].shape.clone()), ([1.0, 0.0, 0.5], Shape::Sphere { radius: 0.02 }));
    }

    #[test]
    fn the_tables_read_the_mount_keys_beside_their_own_and_refuse_unknown_ones() {
        let probe: ProbeSpec = toml::from_str("name = 'p'\nbody = 'base'\nposition = [1, 0, 0]\nlength = 0.5\nradius = 0.02").unwrap();
        assert_eq!(probe.mount, DockingMount { name: "p".into(), body: "base".into(), position: [1.0, 0.0, 0.0], rotation: [0.0, 0.0, 0.0, 1.0] });
        assert_eq!((probe.length, probe.radius, probe.head_radius), (0.5, 0.02, None));
        let drogue: DrogueSpec = toml::from_str("name = 'cone'\nbody = 't'\nrotation = [0, 0, 1, 0]\nmouth_radius = 0.2\nthroat_radius = 0.04\ndepth = 0.3\nrib_radius = 0.01").unwrap();
        assert_eq!((drogue.mount.rotation, drogue.mount.position, drogue.ribs), ([0.0, 0.0, 1.0, 0.0], [0.0; 3], 12));
        let unknown = toml::from_str::<ProbeSpec>("name = 'p'\nbody = 'base'\nlength = 0.5\nradius = 0.02\nspeed = 3").unwrap_err().to_string();
        assert!(unknown.contains("unknown field `speed`"), "{unknown}");
        let unknown = toml::from_str::<DrogueSpec>("name = 'c'\nbody = 't'\nmouth_radius = 0.2\nthroat_radius = 0.04\ndepth = 0.3\nrib_radius = 0.01\nrib = 3").unwrap_err().to_string();
        assert!(unknown.contains("unknown field `rib`"), "{unknown}");
        assert!(toml::from_str::<ProbeSpec>("body = 'base'\nlength = 0.5\nradius = 0.02").unwrap_err().to_string().contains("name"));
    }
}
