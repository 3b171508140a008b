//! The contacts of a state (docs/contact.md): for every pair of collision shapes that the
//! [`PairFilter`] admits, parry's `query::contact` on the two shapes placed by the state's
//! forward kinematics, kept when their signed distance is at most `margin`.

use nalgebra::{Isometry3, Rotation3, Translation3, UnitQuaternion, Vector3};

use crate::algorithms::kinematics::{body_poses, forward_kinematics};
use crate::collision::shapes::CollisionShapes;
use crate::error::{Result, SpacearmError};
use crate::model::data::Data;
use crate::model::Model;

/// Which pairs of bodies are tested.
#[derive(Debug, Clone, PartialEq)]
pub enum PairFilter {
    /// Every pair of different bodies but a body and its parent (they touch at their joint by
    /// construction; MuJoCo leaves them out by default too).
    AllButAdjacent,
    /// These pairs of bodies (indices, base 0), in either order.
    Bodies(Vec<(usize, usize)>),
    /// These pairs of geometries (indices into the model's geometries), in either order.
    Geometries(Vec<(usize, usize)>),
}

/// A contact between two collision shapes, in the inertial frame 𝒥.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// Geometry indices (into the model's geometries) of the two shapes.
    pub geometry: [usize; 2],
    /// Their bodies.
    pub body: [usize; 2],
    /// The closest (or deepest) point of each shape's surface, m.
    pub point: [Vector3<f64>; 2],
    /// Unit normal from the first shape towards the second.
    pub normal: Vector3<f64>,
    /// Signed distance, m: > 0 apart, < 0 interpenetrating (its magnitude the depth).
    pub distance: f64,
}

/// The contacts of the state `x` between the shape pairs that `pairs` admits, with signed
/// distance at most `margin` (m, ≥ 0; 0: touching or interpenetrating only). Pairs on one body
/// are never tested. Ordered by geometry index of the first shape, then of the second.
pub fn contacts(model: &Model, data: &mut Data, shapes: &CollisionShapes, x: &[f64], pairs: &PairFilter, margin: f64) -> Result<Vec<Contact>> {
    if !(margin.is_finite() && margin >= 0.0) {
        return Err(SpacearmError::argument(format!("margin must be finite and >= 0 m, got {margin}")));
    }
    let n_bodies = model.links().len() + 1;
    if let PairFilter::Bodies(list) = pairs {
        if let Some((a, b)) = list.iter().find(|(a, b)| *a >= n_bodies || *b >= n_bodies) {
            return Err(SpacearmError::NotFound(format!("pair ({a}, {b}): the model has bodies 0..{}", n_bodies - 1)));
        }
    }
    if let PairFilter::Geometries(list) = pairs {
        let n = model.geometries().len();
        if let Some((a, b)) = list.iter().find(|(a, b)| *a >= n || *b >= n) {
            return Err(SpacearmError::NotFound(format!("geometry pair ({a}, {b}): the model has geometries 0..{}", n.saturating_sub(1))));
        }
    }
    forward_kinematics(model, data, x)?;
    contacts_after_kinematics(model, data, shapes, pairs, margin)
}

/// [`contacts`] on the kinematics already in `data` (forward kinematics done), `pairs` and
/// `margin` checked by the caller: what the simulation's plant calls at every evaluation.
pub(crate) fn contacts_after_kinematics(model: &Model, data: &Data, shapes: &CollisionShapes, pairs: &PairFilter, margin: f64) -> Result<Vec<Contact>> {
    let poses = body_poses(data);
    let world: Vec<Isometry3<f64>> = shapes
        .shapes
        .iter()
        .map(|s| {
            let (r, p) = &poses[s.body];
            let body = Isometry3::from_parts(Translation3::from(*p), UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(*r)));
            body * s.in_body
        })
        .collect();
    let parent = |b: usize| if b == 0 { usize::MAX } else { model.links()[b - 1].parent };
    let admitted = |a: usize, b: usize| match pairs {
        PairFilter::AllButAdjacent => parent(a) != b && parent(b) != a,
        PairFilter::Bodies(list) => list.iter().any(|&(p, q)| (p, q) == (a, b) || (q, p) == (a, b)),
        PairFilter::Geometries(_) => true,
    };
    let admitted_shapes = |g: usize, h: usize| match pairs {
        PairFilter::Geometries(list) => list.iter().any(|&(p, q)| (p, q) == (g, h) || (q, p) == (g, h)),
        _ => true,
    };
    let mut out = Vec::new();
    for i in 0..shapes.shapes.len() {
        for j in i + 1..shapes.shapes.len() {
            let (s1, s2) = (&shapes.shapes[i], &shapes.shapes[j]);
            if s1.body == s2.body || !admitted(s1.body, s2.body) || !admitted_shapes(s1.geometry, s2.geometry) {
                continue;
            }
            let found = parry3d_f64::query::contact(&world[i], s1.shape.as_ref(), &world[j], s2.shape.as_ref(), margin).map_err(|_| {
                SpacearmError::argument(format!("no contact query between geometries {} and {} (an unsupported pair of shapes)", s1.geometry, s2.geometry))
            })?;
            if let Some(c) = found {
                out.push(Contact {
                    geometry: [s1.geometry, s2.geometry],
                    body: [s1.body, s2.body],
                    point: [c.point1.coords, c.point2.coords],
                    normal: c.normal1.into_inner(),
                    distance: c.dist,
                });
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::geometry::{GeometryRole, GeometrySpec, Shape};
    use crate::model::joint::JointType;
    use crate::model::link::LinkSpec;
    use crate::model::ModelBuilder;

    fn shape(body: &str, shape: Shape, origin: [f64; 3]) -> GeometrySpec {
        GeometrySpec { origin, ..GeometrySpec::new(body, GeometryRole::Collision, shape) }
    }

    /// A base with a ball of radius 0.3 at its CM; a slider on x (its parent the base) with a
    /// ball of 0.2 and a z-cylinder (radius 0.1, length 2) 1.5 m above; a hinge on the slider
    /// with a 0.2 m cube 1 m out along x.
    fn model() -> Model {
        let mut b = ModelBuilder::new("shapes", "base", 100.0, [[10.0, 0.0, 0.0], [0.0, 10.0, 0.0], [0.0, 0.0, 10.0]]).unwrap();
        b.add_link(LinkSpec::new("slider", "base", JointType::Prismatic, [0.0; 3], [1.0, 0.0, 0.0], [0.0; 3], 1.0, [0.1; 3])).unwrap();
        b.add_link(LinkSpec::new("hinge", "slider", JointType::Revolute, [1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0; 3], 1.0, [0.1; 3])).unwrap();
        b.add_geometry(shape("base", Shape::Sphere { radius: 0.3 }, [0.0; 3])).unwrap();
        b.add_geometry(shape("slider", Shape::Sphere { radius: 0.2 }, [0.0; 3])).unwrap();
        b.add_geometry(shape("slider", Shape::Cylinder { radius: 0.1, length: 2.0 }, [0.0, 0.0, 1.5])).unwrap();
        b.add_geometry(shape("hinge", Shape::Box { size: [0.2, 0.2, 0.2] }, [0.0; 3])).unwrap();
        b.build().unwrap()
    }

    fn state(q: [f64; 2]) -> Vec<f64> {
        vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, q[0], q[1]]
    }

    fn find(found: &[Contact], g: [usize; 2]) -> Contact {
        *found.iter().find(|c| c.geometry == g).unwrap_or_else(|| panic!("no contact {g:?} in {found:?}"))
    }

    #[test]
    fn two_balls_interpenetrate_by_the_closed_form_depth_along_the_line_of_centres() {
        let m = model();
        let mut data = Data::new(&m);
        let shapes = CollisionShapes::from_model(&m).unwrap();
        let found = contacts(&m, &mut data, &shapes, &state([0.4, 0.0]), &PairFilter::Bodies(vec![(1, 0)]), 0.0).unwrap();
        let c = find(&found, [0, 1]);
        assert!((c.distance - (0.4 - 0.5)).abs() < 1e-14, "{c:?}");
        assert!((c.normal - Vector3::x()).norm() < 1e-14);
        assert!((c.point[0] - Vector3::new(0.3, 0.0, 0.0)).norm() < 1e-14 && (c.point[1] - Vector3::new(0.2, 0.0, 0.0)).norm() < 1e-14);
        // The base and the slider are parent and child: left out by default.
        let default = contacts(&m, &mut data, &shapes, &state([0.4, 0.0]), &PairFilter::AllButAdjacent, 0.0).unwrap();
        assert!(default.iter().all(|c| c.body != [0, 1]), "{default:?}");
    }

    #[test]
    fn a_cylinder_lies_along_its_z_and_a_box_turns_with_its_hinge() {
        let m = model();
        let mut data = Data::new(&m);
        let shapes = CollisionShapes::from_model(&m).unwrap();
        let pairs = PairFilter::Bodies(vec![(0, 1), (0, 2)]);
        let found = contacts(&m, &mut data, &shapes, &state([0.5, 0.0]), &pairs, 5.0).unwrap();
        // Cylinder (axis z through (0.5, 0, 1.5), z in [0.5, 2.5], radius 0.1) to the ball at the
        // origin: its nearest point is (0.4, 0, 0.5).
        let c = find(&found, [0, 2]);
        assert!((c.distance - ((0.4f64 * 0.4 + 0.25).sqrt() - 0.3)).abs() < 1e-9, "{c:?}");
        // The cube 1 m beyond the slider: its face at x = 1.4 at q = (0.5, 0).
        let c = find(&found, [0, 3]);
        assert!((c.distance - (1.4 - 0.3)).abs() < 1e-9, "{c:?}");
        // Turned by 45° about z, the cube's edge comes 0.1 (√2 − 1) nearer.
        let found = contacts(&m, &mut data, &shapes, &state([0.5, std::f64::consts::FRAC_PI_4]), &pairs, 5.0).unwrap();
        let c = find(&found, [0, 3]);
        // The hinge turns the cube's CM frame too; the cube sits at the hinge's CM (1 m along the slider).
        assert!((c.distance - (1.5 - 0.1 * 2f64.sqrt() - 0.3)).abs() < 1e-9, "{c:?}");
        // Beyond the margin: nothing.
        assert!(contacts(&m, &mut data, &shapes, &state([0.7, 0.0]), &pairs, 0.05).unwrap().is_empty());
    }

    #[test]
    fn bad_input_is_refused() {
        let m = model();
        let mut data = Data::new(&m);
        let shapes = CollisionShapes::from_model(&m).unwrap();
        assert!(contacts(&m, &mut data, &shapes, &state([0.0, 0.0]), &PairFilter::AllButAdjacent, -1.0).is_err());
        assert!(contacts(&m, &mut data, &shapes, &state([0.0, 0.0]), &PairFilter::Bodies(vec![(0, 7)]), 0.0).is_err());
        let mut b = ModelBuilder::from_model(&m);
        b.add_geometry(GeometrySpec { name: Some("hull".into()), ..shape("base", Shape::Mesh { file: "hull.stl".into(), scale: [1.0; 3] }, [0.0; 3]) }).unwrap();
        let err = CollisionShapes::from_model(&b.build().unwrap()).err().unwrap().to_string();
        assert!(err.contains("'hull' is a mesh"), "{err}");
    }
}
