//! Visual and collision geometry fixed to a body: a primitive shape (box, cylinder, sphere,
//! capsule) or a mesh file, placed in the body's frame (origin at the body's CM, body axes:
//! docs/conventions.md) by a position and a rotation. Geometry is for seeing the model (the
//! MJCF and URDF exports, the viewer, videos) and for collision shapes in other engines; it
//! carries no mass: the dynamics use only the bodies' mass properties (docs/geometry.md).
//!
//! Shapes follow URDF and MuJoCo: a box is given by its full side lengths, a cylinder and a
//! capsule lie along the geometry frame's `z` axis (`length` is the cylinder part, without the
//! capsule's hemispherical caps), a mesh names its file (as written in the model file: the
//! readers in Python resolve it) with a scale per axis.

use nalgebra::{UnitQuaternion, Vector3};

use crate::error::{ModelError, ModelField, ModelItem};
use crate::model::validate::{self, MAX_LENGTH};

/// What a geometry is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum GeometryRole {
    /// Drawn (URDF `<visual>`, an MJCF geom of group 1 without contacts).
    Visual,
    /// Used for contacts by engines that have them (URDF `<collision>`, an MJCF geom of group 3).
    Collision,
}

impl GeometryRole {
    /// `"visual"` or `"collision"`: the name in model files and the bindings.
    pub fn as_str(self) -> &'static str {
        match self {
            GeometryRole::Visual => "visual",
            GeometryRole::Collision => "collision",
        }
    }

    /// The role called `name`; any other name is refused with the one message of every door
    /// (which prefixes the geometry's name).
    pub fn from_name(name: &str) -> Result<Self, String> {
        match name {
            "visual" => Ok(GeometryRole::Visual),
            "collision" => Ok(GeometryRole::Collision),
            _ => Err(format!("role must be 'visual' or 'collision', got '{name}'")),
        }
    }
}

/// A geometry's shape, in its own frame (centred at its origin). Lengths in m.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// A box.
    Box {
        /// Full side lengths along x, y, z.
        size: [f64; 3],
    },
    /// A cylinder along z.
    Cylinder {
        /// Radius.
        radius: f64,
        /// Total length.
        length: f64,
    },
    /// A sphere.
    Sphere {
        /// Radius.
        radius: f64,
    },
    /// A capsule along z: a cylinder with hemispherical caps.
    Capsule {
        /// Radius of the cylinder and the caps.
        radius: f64,
        /// Length of the cylinder part (without the caps).
        length: f64,
    },
    /// A mesh file (STL, OBJ or DAE).
    Mesh {
        /// The file, as the model states it (resolved by the Python readers).
        file: String,
        /// Scale along the mesh's x, y, z.
        scale: [f64; 3],
    },
}

impl Shape {
    /// The shape's kind: `"box"`, `"cylinder"`, `"sphere"`, `"capsule"` or `"mesh"`.
    pub fn kind(&self) -> &'static str {
        match self {
            Shape::Box { .. } => "box",
            Shape::Cylinder { .. } => "cylinder",
            Shape::Sphere { .. } => "sphere",
            Shape::Capsule { .. } => "capsule",
            Shape::Mesh { .. } => "mesh",
        }
    }
}

/// The dimension keys each shape kind takes, in the order of [`Shape::from_parts`].
pub const SHAPE_KEYS: [(&str, &[&str]); 5] =
    [("box", &["size"]), ("cylinder", &["radius", "length"]), ("sphere", &["radius"]), ("capsule", &["radius", "length"]), ("mesh", &["file", "scale"])];

/// Optional dimension keys of a shape, as the doors give them (a model file table, keyword
/// arguments): [`Shape::from_parts`] turns them into a [`Shape`].
#[derive(Debug, Clone, Default)]
pub struct ShapeParts {
    /// Box side lengths.
    pub size: Option<[f64; 3]>,
    /// Sphere, cylinder or capsule radius.
    pub radius: Option<f64>,
    /// Cylinder or capsule length.
    pub length: Option<f64>,
    /// Mesh file.
    pub file: Option<String>,
    /// Mesh scale (default 1).
    pub scale: Option<[f64; 3]>,
}

impl Shape {
    /// The shape of kind `kind` from its dimension keys: each key of that kind required (a
    /// mesh's `scale` defaults to 1), no other allowed. The error says which key and why.
    pub fn from_parts(kind: &str, parts: ShapeParts) -> Result<Shape, String> {
        let Some((_, wanted)) = SHAPE_KEYS.iter().find(|(k, _)| *k == kind) else {
            return Err(format!("shape must be \"box\", \"cylinder\", \"sphere\", \"capsule\" or \"mesh\", got {kind:?}"));
        };
        let given = [
            ("size", parts.size.is_some()),
            ("radius", parts.radius.is_some()),
            ("length", parts.length.is_some()),
            ("file", parts.file.is_some()),
            ("scale", parts.scale.is_some()),
        ];
        if let Some((key, _)) = given.iter().find(|(k, g)| *g && !wanted.contains(k)) {
            return Err(format!("a {kind} takes {}, not `{key}`", wanted.join(" and ")));
        }
        let missing = |key: &str| format!("a {kind} needs `{key}`");
        Ok(match kind {
            "box" => Shape::Box { size: parts.size.ok_or_else(|| missing("size"))? },
            "sphere" => Shape::Sphere { radius: parts.radius.ok_or_else(|| missing("radius"))? },
            "cylinder" => Shape::Cylinder {
                radius: parts.radius.ok_or_else(|| missing("radius"))?,
                length: parts.length.ok_or_else(|| missing("length"))?,
            },
            "capsule" => Shape::Capsule {
                radius: parts.radius.ok_or_else(|| missing("radius"))?,
                length: parts.length.ok_or_else(|| missing("length"))?,
            },
            _ => Shape::Mesh { file: parts.file.ok_or_else(|| missing("file"))?, scale: parts.scale.unwrap_or([1.0; 3]) },
        })
    }
}

/// Colour of a geometry that states none: a light grey, opaque.
pub const DEFAULT_RGBA: [f64; 4] = [0.7, 0.7, 0.7, 1.0];

/// A shape fixed to a body of a model.
#[derive(Debug, Clone, PartialEq)]
pub struct Geometry {
    /// Unique geometry name (default `<body>_<role><k>`).
    pub name: String,
    /// Body index it is fixed to (0 = base).
    pub body: usize,
    /// Visual or collision.
    pub role: GeometryRole,
    /// The shape in the geometry's own frame.
    pub shape: Shape,
    /// The geometry frame's origin in the body frame (from the body's CM), m.
    pub origin: Vector3<f64>,
    /// The geometry frame's axes in the body frame.
    pub rotation: UnitQuaternion<f64>,
    /// Red, green, blue, alpha, each in `[0, 1]`.
    pub rgba: [f64; 4],
}

/// Everything that describes one geometry to [`crate::model::ModelBuilder::add_geometry`].
#[derive(Debug, Clone)]
pub struct GeometrySpec {
    /// Unique name (default `<body>_<role><k>`, `k` counting that body's geometries of that role).
    pub name: Option<String>,
    /// Name of the body it is fixed to.
    pub body: String,
    /// Visual or collision.
    pub role: GeometryRole,
    /// The shape.
    pub shape: Shape,
    /// Origin in the body frame (from the CM), m.
    pub origin: [f64; 3],
    /// Quaternion `[x, y, z, w]` of the geometry frame in the body frame.
    pub rotation: [f64; 4],
    /// Colour (default [`DEFAULT_RGBA`]).
    pub rgba: Option<[f64; 4]>,
}

impl GeometrySpec {
    /// `shape` in the role `role` at the CM of `body`, in its axes, with the default name and
    /// colour; the other fields by struct update (`GeometrySpec { origin, ..GeometrySpec::new(..) }`).
    pub fn new(body: &str, role: GeometryRole, shape: Shape) -> Self {
        GeometrySpec { name: None, body: body.to_string(), role, shape, origin: [0.0; 3], rotation: [0.0, 0.0, 0.0, 1.0], rgba: None }
    }
}

/// The longest mesh file name a model accepts, in characters (a path's `PATH_MAX`).
pub const MAX_FILE_CHARS: usize = 4096;

/// A shape's dimensions: each length finite, `> 0` and at most [`MAX_LENGTH`]; a mesh's file
/// name not empty, at most [`MAX_FILE_CHARS`] characters and free of control characters, and
/// its scale finite and non-zero.
pub fn check_shape(item: ModelItem, who: &str, shape: &Shape) -> Result<(), ModelError> {
    let bad = |m: String| Err(ModelError::new(item, ModelField::Shape, format!("{who}: {m}")));
    let lengths: Vec<(&str, f64)> = match shape {
        Shape::Box { size } => vec![("box size x", size[0]), ("box size y", size[1]), ("box size z", size[2])],
        Shape::Cylinder { radius, length } => vec![("cylinder radius", *radius), ("cylinder length", *length)],
        Shape::Sphere { radius } => vec![("sphere radius", *radius)],
        Shape::Capsule { radius, length } => vec![("capsule radius", *radius), ("capsule length", *length)],
        Shape::Mesh { file, scale } => {
            if file.trim().is_empty() {
                return bad("a mesh needs a file name, got an empty one".into());
            }
            // The file name is written into exported URDFs and read back as a path: a control
            // character (NUL, newline, ...) would make a malformed file, an overlong one no path.
            let n = file.chars().count();
            if n > MAX_FILE_CHARS {
                let head: String = file.chars().take(40).collect();
                return bad(format!("a mesh file name must be at most {MAX_FILE_CHARS} characters, got {n} ('{head}...')"));
            }
            if let Some(c) = file.chars().find(|c| c.is_control()) {
                let shown: String = file.chars().take(60).map(|c| if c.is_control() { '?' } else { c }).collect();
                return bad(format!("a mesh file name must not contain control characters (NUL, newline, ...), got U+{:04X} in '{shown}'", c as u32));
            }
            if scale.iter().any(|s| !s.is_finite() || *s == 0.0 || s.abs() > MAX_LENGTH) {
                return bad(format!("mesh scale must be 3 finite non-zero numbers within {MAX_LENGTH:e}, got {scale:?}"));
            }
            Vec::new()
        }
    };
    for (what, v) in lengths {
        if !(v.is_finite() && v > 0.0 && v <= MAX_LENGTH) {
            return bad(format!("{what} must be a finite length > 0 m and at most {MAX_LENGTH:e} m, got {v}"));
        }
    }
    Ok(())
}

/// Each colour component finite and in `[0, 1]`.
pub fn check_rgba(item: ModelItem, who: &str, rgba: &[f64; 4]) -> Result<(), ModelError> {
    if rgba.iter().any(|c| !(0.0..=1.0).contains(c)) {
        return Err(ModelError::new(item, ModelField::Color, format!("{who}: rgba must be 4 numbers in [0, 1], got {rgba:?}")));
    }
    Ok(())
}

/// The placement of a geometry: origin a position (finite, within [`MAX_LENGTH`]) and rotation
/// a unit quaternion (the joint-rotation rule of [`validate`]).
pub fn check_placement(
    item: ModelItem,
    who: &str,
    origin: &[f64; 3],
    rotation: &[f64; 4],
) -> Result<(Vector3<f64>, UnitQuaternion<f64>), ModelError> {
    let origin = validate::position(item, ModelField::Origin, who, "geometry origin", origin)?;
    let rotation = validate::joint_rotation(item, who, rotation)
        .map_err(|e| ModelError::new(item, ModelField::Rotation, e.message.replace("joint rotation", "geometry rotation")))?;
    Ok((origin, rotation))
}

/// Side lengths of the uniform box whose principal moments about its centre are `moments`
/// (kg·m²) for `mass` (kg): `s_x² = 6 (I_yy + I_zz − I_xx) / m` and cyclically (the inverse of
/// [`crate::model::body::MassProperties::solid_box`]); a side whose second moment is not
/// positive gets 1 % of the largest side. For drawing a body whose shape the data do not give.
pub fn box_of_moments(mass: f64, moments: [f64; 3]) -> [f64; 3] {
    let [a, b, c] = moments;
    let side = |s: f64| (6.0 * s / mass).max(0.0).sqrt();
    let mut out = [side(b + c - a), side(a + c - b), side(a + b - c)];
    let largest = out.iter().copied().fold(0.0, f64::max);
    for v in &mut out {
        *v = v.max(0.01 * largest);
    }
    out
}

/// The placement (centre and rotation `[x, y, z, w]`) of a cylinder or capsule along `z` that
/// joins `from` to `to` (body frame), and its length; `None` when the points coincide.
pub fn segment(from: [f64; 3], to: [f64; 3]) -> Option<([f64; 3], [f64; 4], f64)> {
    let (a, b) = (Vector3::from(from), Vector3::from(to));
    let d = b - a;
    let length = d.norm();
    if length.is_nan() || length <= 0.0 {
        return None;
    }
    let rotation = UnitQuaternion::rotation_between(&Vector3::z(), &d)
        .unwrap_or_else(|| UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI));
    let c = (a + b) * 0.5;
    Some(([c.x, c.y, c.z], [rotation.i, rotation.j, rotation.k, rotation.w], length))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_of_moments_inverts_the_solid_box() {
        let i = crate::model::body::MassProperties::solid_box(500.0, 1.2, 1.0, 0.8);
        let s = box_of_moments(500.0, [i[(0, 0)], i[(1, 1)], i[(2, 2)]]);
        for (got, want) in s.iter().zip([1.2, 1.0, 0.8]) {
            assert!((got - want).abs() < 1e-12, "{s:?}");
        }
    }

    #[test]
    fn segment_points_z_from_one_end_to_the_other() {
        for (from, to) in [([0.0; 3], [0.0, 0.0, 2.0]), ([1.0, 0.0, 0.0], [1.0, 0.0, -3.0]), ([0.1, 0.2, 0.3], [-0.4, 0.9, 0.0])] {
            let (c, q, l) = segment(from, to).unwrap();
            let rot = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q[3], q[0], q[1], q[2]));
            let tip = Vector3::from(c) + rot * Vector3::new(0.0, 0.0, l / 2.0);
            assert!((tip - Vector3::from(to)).norm() < 1e-12, "{tip:?}");
        }
        assert!(segment([1.0; 3], [1.0; 3]).is_none());
    }

    #[test]
    fn shapes_need_positive_finite_dimensions() {
        let item = ModelItem::Geometry(0);
        assert!(check_shape(item, "g", &Shape::Box { size: [1.0, 2.0, 3.0] }).is_ok());
        assert!(check_shape(item, "g", &Shape::Capsule { radius: 0.1, length: 0.5 }).is_ok());
        for bad in [
            Shape::Box { size: [1.0, 0.0, 3.0] },
            Shape::Sphere { radius: -1.0 },
            Shape::Cylinder { radius: f64::NAN, length: 1.0 },
            Shape::Capsule { radius: 0.1, length: f64::INFINITY },
            Shape::Sphere { radius: 2e6 },
            Shape::Mesh { file: " ".into(), scale: [1.0; 3] },
            Shape::Mesh { file: "a.stl".into(), scale: [1.0, 0.0, 1.0] },
        ] {
            let e = check_shape(item, "geometry 'g'", &bad).unwrap_err();
            assert_eq!((e.item, e.field), (item, ModelField::Shape), "{e}");
            assert!(e.message.starts_with("geometry 'g': "), "{e}");
        }
        assert_eq!(check_rgba(item, "g", &[0.0, 0.5, 1.0, 1.5]).unwrap_err().field, ModelField::Color);
        assert!(check_shape(item, "g", &Shape::Mesh { file: "package://arm/meshes/link 1.stl".into(), scale: [1.0; 3] }).is_ok());
    }

    #[test]
    fn mesh_file_names_refuse_control_characters_and_overlong_names() {
        // A NUL or newline in a mesh file name was written as it is into exported URDFs
        // (malformed XML / a path no OS opens) (issue 38).
        let item = ModelItem::Geometry(0);
        for file in ["a\0.stl", "a\n.stl", "meshes/\r\nb.stl", "x\u{1b}[31m.stl"] {
            let e = check_shape(item, "geometry 'g'", &Shape::Mesh { file: file.into(), scale: [1.0; 3] }).unwrap_err();
            assert!(e.message.contains("control characters") && !e.message.contains('\0') && !e.message.contains('\n'), "{e}");
        }
        let long = "a/".repeat(MAX_FILE_CHARS) + "b.stl";
        let e = check_shape(item, "geometry 'g'", &Shape::Mesh { file: long, scale: [1.0; 3] }).unwrap_err();
        assert!(e.message.contains(&format!("at most {MAX_FILE_CHARS} characters")) && e.message.len() < 300, "{e}");
        assert!(check_rgba(item, "g", &[0.0, 0.5, 1.0, 1.0]).is_ok());
        let e = check_placement(item, "geometry 'g'", &[0.0; 3], &[0.0, 0.0, 0.0, 2.0]).unwrap_err();
        assert!(e.field == ModelField::Rotation && e.message.contains("geometry rotation"), "{e}");
        assert_eq!(check_placement(item, "g", &[f64::NAN, 0.0, 0.0], &[0.0, 0.0, 0.0, 1.0]).unwrap_err().field, ModelField::Origin);
    }
}
