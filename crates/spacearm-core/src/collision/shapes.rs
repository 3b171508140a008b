//! A model's collision geometries as parry shapes, each with its pose in its body's frame
//! (docs/geometry.md: the body frame's origin is the body's CM; a cylinder and a capsule lie
//! along their geometry frame's `z`, parry's along `y`, so their parry pose turns `y` onto `z`).

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use parry3d_f64::shape::{Ball, Capsule, Cuboid, Cylinder, SharedShape};

use crate::error::{Result, SpacearmError};
use crate::model::geometry::{GeometryRole, Shape};
use crate::model::Model;

/// One collision shape: the geometry's index in [`Model::geometries`], its body, the parry shape
/// and its pose in the body's frame.
pub struct BodyShape {
    /// Index of the geometry in the model.
    pub geometry: usize,
    /// Index of its body (0: the base).
    pub body: usize,
    /// The parry shape.
    pub shape: SharedShape,
    /// Its pose in the body's frame.
    pub in_body: Isometry3<f64>,
}

/// The collision shapes of a model: its geometries of role `collision` (docs/geometry.md).
pub struct CollisionShapes {
    /// The shapes, in the model's geometry order.
    pub shapes: Vec<BodyShape>,
}

impl CollisionShapes {
    /// The model's collision geometries as parry shapes. A mesh is refused: its vertices live
    /// in a file the core does not read (docs/contact.md, "What is not handled"); give the body a
    /// primitive collision shape.
    pub fn from_model(model: &Model) -> Result<Self> {
        let mut shapes = Vec::new();
        for (k, g) in model.geometries().iter().enumerate() {
            if g.role != GeometryRole::Collision {
                continue;
            }
            let (shape, turn) = match &g.shape {
                Shape::Box { size } => (SharedShape::new(Cuboid::new(Vector3::from(*size) * 0.5)), false),
                Shape::Sphere { radius } => (SharedShape::new(Ball::new(*radius)), false),
                Shape::Cylinder { radius, length } => (SharedShape::new(Cylinder::new(0.5 * length, *radius)), true),
                Shape::Capsule { radius, length } => (SharedShape::new(Capsule::new_y(0.5 * length, *radius)), true),
                Shape::Mesh { file, .. } => {
                    return Err(SpacearmError::argument(format!(
                        "collision geometry '{}' is a mesh ('{file}'): collision detection takes boxes, spheres, cylinders and capsules \
                         (a mesh's vertices are not in the model); give body {} a primitive collision shape",
                        g.name,
                        model.body_names()[g.body]
                    )))
                }
            };
            // parry's cylinder and capsule lie along y: turned by +90° about x, y goes to z.
            let turn = if turn { UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2) } else { UnitQuaternion::identity() };
            let in_body = Isometry3::from_parts(Translation3::from(g.origin), g.rotation * turn);
            shapes.push(BodyShape { geometry: k, body: g.body, shape, in_body });
        }
        Ok(CollisionShapes { shapes })
    }
}
