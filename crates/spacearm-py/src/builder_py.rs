//! `spacearm._core.ModelBuilder`: the core's incremental builder (wrapped by
//! `spacearm.RobotBuilder`).

use pyo3::prelude::*;
use pyo3::IntoPyObjectExt;
use spacearm_core::model::geometry::ShapeParts;
use spacearm_core::{GeometryRole, GeometrySpec, JointDynamics, JointLimits, JointType, LinkSpec, ModelBuilder, Shape, SpacearmError};

use crate::convert::*;
use crate::model_py::PyModel;

#[pyclass(module = "spacearm._core", name = "ModelBuilder")]
pub struct PyModelBuilder {
    inner: ModelBuilder,
}

/// The joint limits of the doors' `[lower, upper, velocity, effort]` (None: unlimited).
pub(crate) fn joint_limits(limits: Option<[f64; 4]>) -> JointLimits {
    match limits {
        None => JointLimits::unlimited(),
        Some([lower, upper, velocity, effort]) => JointLimits { lower, upper, velocity, effort },
    }
}

/// Joint `name`'s passive dynamics from the doors' `(actuated, stiffness, damping, rest)`
/// (docs/flexibility.md); `None` leaves the joint as built.
fn set_joint_dynamics(py: Python<'_>, b: &mut ModelBuilder, name: &str, dynamics: Option<(bool, f64, f64, f64)>) -> PyResult<()> {
    if let Some((actuated, stiffness, damping, rest)) = dynamics {
        b.set_joint_dynamics(name, JointDynamics { actuated, stiffness, damping, rest }).or_raise(py)?;
    }
    Ok(())
}

/// A link as the doors hand it over: `ModelBuilder.add_link`'s arguments but the dynamics,
/// `(name, parent, joint_type, origin, rotation, axis, com, mass, inertia, joint_name, limits)`
/// (what `compliant_parts` takes; the appendages' parts hand links back the same way, with the
/// dynamics after).
pub(crate) type LinkArgs = (String, String, String, [f64; 3], [f64; 4], [f64; 3], [f64; 3], f64, [[f64; 3]; 3], Option<String>, Option<[f64; 4]>);

/// The [`LinkSpec`] of a link's arguments ([`LinkArgs`]).
fn link_spec(py: Python<'_>, (name, parent, joint_type, origin, rotation, axis, com, mass, inertia, joint_name, limits): LinkArgs) -> PyResult<LinkSpec> {
    Ok(LinkSpec {
        name,
        parent,
        joint_name,
        kind: JointType::from_name(&joint_type).or_raise(py)?,
        origin_in_parent: origin,
        rotation_in_parent: rotation,
        axis,
        com_from_joint: com,
        mass,
        inertia,
        limits: joint_limits(limits),
    })
}

/// Add the link of `link` ([`LinkArgs`]) to `b` and set its joint's `dynamics`: how every door
/// of the binding adds one link (`ModelBuilder.add_link`, `model_attach_body`).
pub(crate) fn add_link_to(py: Python<'_>, b: &mut ModelBuilder, link: LinkArgs, dynamics: Option<(bool, f64, f64, f64)>) -> PyResult<()> {
    let spec = link_spec(py, link)?;
    let name = spec.name.clone();
    b.add_link(spec).or_raise(py)?;
    set_joint_dynamics(py, b, &name, dynamics)
}

#[pymethods]
impl PyModelBuilder {
    #[new]
    #[pyo3(signature = (name, base_name, base_mass, base_inertia, allow_nonphysical_inertia=false))]
    fn new(
        py: Python<'_>,
        name: &str,
        base_name: &str,
        base_mass: f64,
        base_inertia: [[f64; 3]; 3],
        allow_nonphysical_inertia: bool,
    ) -> PyResult<Self> {
        let rule = triangle_inequality(allow_nonphysical_inertia);
        Ok(PyModelBuilder {
            inner: ModelBuilder::with_triangle_inequality(name, base_name, base_mass, base_inertia, rule)
                .or_raise(py)?,
        })
    }

    /// A builder holding `model` exactly (core `ModelBuilder::from_model`, model/edit.rs), to edit.
    #[staticmethod]
    fn from_model(model: &crate::model_py::PyModel) -> Self {
        PyModelBuilder { inner: ModelBuilder::from_model(&model.model) }
    }

    /// Rename the model being built.
    fn set_name(&mut self, py: Python<'_>, name: &str) -> PyResult<()> {
        self.inner.set_name(name).or_raise(py)?;
        Ok(())
    }

    /// Judge every body's inertia again: refused (`allow_nonphysical_inertia=False`) or warned.
    fn set_allow_nonphysical_inertia(&mut self, py: Python<'_>, allow_nonphysical_inertia: bool) -> PyResult<()> {
        self.inner.set_triangle_inequality(triangle_inequality(allow_nonphysical_inertia)).or_raise(py)?;
        Ok(())
    }

    /// Drop every geometry.
    fn clear_geometries(&mut self) {
        self.inner.clear_geometries();
    }

    /// Remove the link `body`, its subtree, and the points and geometries on them.
    fn remove_subtree(&mut self, py: Python<'_>, body: &str) -> PyResult<()> {
        self.inner.remove_subtree(body).or_raise(py)?;
        Ok(())
    }

    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (name, parent, joint_type, origin, rotation, axis, com, mass, inertia, joint_name=None, limits=None, dynamics=None))]
    fn add_link(
        &mut self,
        py: Python<'_>,
        name: &str,
        parent: &str,
        joint_type: &str,
        origin: [f64; 3],
        rotation: [f64; 4],
        axis: [f64; 3],
        com: [f64; 3],
        mass: f64,
        inertia: [[f64; 3]; 3],
        joint_name: Option<String>,
        limits: Option<[f64; 4]>,
        dynamics: Option<(bool, f64, f64, f64)>,
    ) -> PyResult<()> {
        add_link_to(py, &mut self.inner, (name.into(), parent.into(), joint_type.into(), origin, rotation, axis, com, mass, inertia, joint_name, limits), dynamics)
    }

    fn add_point(&mut self, py: Python<'_>, name: &str, body: &str, offset: [f64; 3]) -> PyResult<()> {
        self.inner.add_point(name, body, offset).or_raise(py)?;
        Ok(())
    }

    /// Add a visual or collision shape to `body` (model/geometry.rs: the shape from `shape`
    /// and its keys, checked with the placement and colour by the core's builder).
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (body, role, shape, origin, rotation, size=None, radius=None, length=None, file=None, scale=None, rgba=None, name=None))]
    fn add_geometry(
        &mut self,
        py: Python<'_>,
        body: &str,
        role: &str,
        shape: &str,
        origin: [f64; 3],
        rotation: [f64; 4],
        size: Option<[f64; 3]>,
        radius: Option<f64>,
        length: Option<f64>,
        file: Option<String>,
        scale: Option<[f64; 3]>,
        rgba: Option<[f64; 4]>,
        name: Option<String>,
    ) -> PyResult<()> {
        let who = name.as_ref().map_or_else(|| format!("geometry on '{body}'"), |n| format!("geometry '{n}'"));
        let invalid = |m: String| to_py_err(py, SpacearmError::InvalidModel(format!("{who}: {m}")));
        let role = GeometryRole::from_name(role).map_err(invalid)?;
        let shape = Shape::from_parts(shape, ShapeParts { size, radius, length, file, scale }).map_err(invalid)?;
        self.inner
            .add_geometry(GeometrySpec { name, body: body.to_string(), role, shape, origin, rotation, rgba })
            .or_raise(py)?;
        Ok(())
    }

    fn set_end_effector(&mut self, name: &str) {
        self.inner.set_end_effector(name);
    }

    fn set_initial_q(&mut self, q: Vec<f64>) {
        self.inner.set_initial_q(q);
    }

    fn build(&self, py: Python<'_>) -> PyResult<PyModel> {
        Ok(PyModel::new(self.inner.build().or_raise(py)?))
    }
}

/// The links of a slosh mode (core `model::slosh::slosh_links`, docs/flexibility.md), each as
/// the arguments of `ModelBuilder.add_link`: `(name, parent, joint_type, origin, rotation, axis,
/// com, mass, inertia, joint_name, limits, dynamics)`. Give `stiffness` or `frequency`.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
#[pyo3(signature = (name, parent, model, mass, position, axis, hinge, length, stiffness, frequency, damping))]
pub fn slosh_links(
    py: Python<'_>,
    name: &str,
    parent: &str,
    model: &str,
    mass: f64,
    position: [f64; 3],
    axis: [f64; 3],
    hinge: Option<[f64; 3]>,
    length: Option<f64>,
    stiffness: Option<f64>,
    frequency: Option<f64>,
    damping: f64,
) -> PyResult<Vec<Py<PyAny>>> {
    use spacearm_core::error::ModelItem;
    use spacearm_core::model::slosh::{self, SloshModel, SloshRestoring, SloshSpec};
    let invalid = |msg: String| to_py_err(py, SpacearmError::InvalidModel(format!("slosh '{name}': {msg}")));
    let kind = SloshModel::from_name(model).map_err(invalid)?;
    let restoring = SloshRestoring::from_options(stiffness, frequency).map_err(invalid)?;
    let spec = SloshSpec { name: name.into(), parent: parent.into(), model: kind, mass, position, axis, hinge, length, restoring, damping };
    let links = slosh::slosh_links(&spec, ModelItem::Model).or_raise(py)?;
    links.into_iter().map(|(l, d)| add_link_args(py, l, None, Some((d.actuated, d.stiffness, d.damping, d.rest)))).collect()
}

/// The arguments of `ModelBuilder.add_link` that build `l`, as a tuple: `(name, parent,
/// joint_type, origin, rotation, axis, com, mass, inertia, joint_name, limits, dynamics)`.
fn add_link_args(py: Python<'_>, l: LinkSpec, limits: Option<[f64; 4]>, dynamics: Option<(bool, f64, f64, f64)>) -> PyResult<Py<PyAny>> {
    let kind = l.kind.as_str();
    (l.name, l.parent, kind, l.origin_in_parent, l.rotation_in_parent, l.axis, l.com_from_joint, l.mass, l.inertia, l.joint_name, limits, dynamics).into_py_any(py)
}

/// A part's link's limits as `add_link` takes them: its own for a moving joint, None for a
/// fixed one.
fn moving_limits(l: &LinkSpec) -> Option<[f64; 4]> {
    let lim = l.limits;
    (l.kind != JointType::Fixed).then_some([lim.lower, lim.upper, lim.velocity, lim.effort])
}

/// `(links, points, geometries)` of an appendage (core `model::appendage`): each link as the
/// arguments of `ModelBuilder.add_link`, each point as `(name, body, offset)`, each geometry as
/// `(name, body, size, origin, rotation, rgba)` of a box.
fn parts_to_py(py: Python<'_>, parts: spacearm_core::model::appendage::Parts) -> PyResult<Py<PyAny>> {
    let mut links = Vec::new();
    for (l, d) in parts.links {
        let dynamics = (d != JointDynamics::default()).then_some((d.actuated, d.stiffness, d.damping, d.rest));
        let limits = moving_limits(&l);
        links.push(add_link_args(py, l, limits, dynamics)?);
    }
    let mut geometries = Vec::new();
    for g in parts.geometries {
        let Shape::Box { size } = g.shape else { continue };
        geometries.push((g.name, g.body, size, g.origin, g.rotation, g.rgba).into_py_any(py)?);
    }
    (links, parts.points, geometries).into_py_any(py)
}

/// A hinged rigid panel's parts (core `model::appendage::panel_parts`, docs/flexibility.md):
/// `size` `(length, width, thickness)` or `inertia` with `com_distance`; `stiffness` or `frequency`.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
#[pyo3(signature = (name, parent, hinge_position, hinge_axis, direction, mass, size, inertia, com_distance, stiffness, frequency, damping, rest))]
pub fn panel_parts(
    py: Python<'_>,
    name: &str,
    parent: &str,
    hinge_position: [f64; 3],
    hinge_axis: [f64; 3],
    direction: [f64; 3],
    mass: f64,
    size: Option<[f64; 3]>,
    inertia: Option<[[f64; 3]; 3]>,
    com_distance: Option<f64>,
    stiffness: Option<f64>,
    frequency: Option<f64>,
    damping: f64,
    rest: f64,
) -> PyResult<Py<PyAny>> {
    use spacearm_core::error::ModelItem;
    use spacearm_core::model::appendage::{self, PanelBody, PanelSpec, Restoring};
    let invalid = |msg: String| to_py_err(py, SpacearmError::InvalidModel(format!("panel '{name}': {msg}")));
    let restoring = Restoring::from_options(stiffness, frequency).map_err(invalid)?;
    let body = PanelBody::from_options(size, inertia, com_distance).map_err(invalid)?;
    let spec = PanelSpec { name: name.into(), parent: parent.into(), hinge_position, hinge_axis, direction, body, mass, restoring, damping, rest };
    let parts = appendage::panel_parts(&spec, ModelItem::Model).or_raise(py)?;
    parts_to_py(py, parts)
}

/// A flexible beam's parts by the rigid finite element method (core
/// `model::appendage::beam_parts`, docs/flexibility.md). `bending_axes` (default:
/// `appendage::bending`) with `ei` (one, or one per axis);
/// `damping` (per joint) or `damping_ratio`.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
#[pyo3(signature = (name, parent, root_position, axis, length, segments, bending_axes, ei, torsion, rho_a, rho_j, damping, damping_ratio))]
pub fn beam_parts(
    py: Python<'_>,
    name: &str,
    parent: &str,
    root_position: [f64; 3],
    axis: [f64; 3],
    length: f64,
    segments: usize,
    bending_axes: Option<Vec<[f64; 3]>>,
    ei: Vec<f64>,
    torsion: Option<f64>,
    rho_a: f64,
    rho_j: f64,
    damping: Option<f64>,
    damping_ratio: Option<f64>,
) -> PyResult<Py<PyAny>> {
    use spacearm_core::error::ModelItem;
    use spacearm_core::model::appendage::{self, BeamDamping, BeamSpec};
    let damping = BeamDamping::from_options(damping, damping_ratio).map_err(|m| to_py_err(py, SpacearmError::InvalidModel(format!("beam '{name}': {m}"))))?;
    let bending = appendage::bending(name, &axis, bending_axes, &ei).or_raise(py)?;
    let spec = BeamSpec { name: name.into(), parent: parent.into(), root_position, axis, length, segments, bending, torsion, rho_a, rho_j, damping };
    let parts = appendage::beam_parts(&spec, ModelItem::Model).or_raise(py)?;
    parts_to_py(py, parts)
}

/// The two links of a compliant revolute joint (core `model::appendage::compliant_parts`): the
/// link's own `ModelBuilder.add_link` arguments (without dynamics, [`LinkArgs`]) and the series
/// elasticity.
#[pyfunction]
pub fn compliant_parts(
    py: Python<'_>,
    link: LinkArgs,
    stiffness: f64,
    rotor_inertia: f64,
    damping: f64,
    gear_ratio: f64,
) -> PyResult<Py<PyAny>> {
    use spacearm_core::error::ModelItem;
    use spacearm_core::model::appendage::{self, CompliantSpec};
    let link = link_spec(py, link)?;
    let spec = CompliantSpec { stiffness, rotor_inertia, damping, gear_ratio };
    let parts = appendage::compliant_parts(&link, &spec, ModelItem::Model).or_raise(py)?;
    parts_to_py(py, parts)
}

/// The equivalent mechanical model of the liquid in an upright flat-bottomed cylinder (core
/// `model::slosh_tank::cylinder_slosh`): a dict with `liquid_mass`, `fill_height`, `radius`,
/// `axial_acceleration`, `liquid_cm_height`, `fixed_mass`, `fixed_height`, `fixed_inertia` (None for a
/// sphere) and `modes`, a list of
/// dicts with `mass`, `height`, `frequency`, `stiffness`, `length`.
#[pyfunction]
#[pyo3(signature = (radius, fill_height, liquid_mass, axial_acceleration, modes=1))]
pub fn cylinder_slosh(py: Python<'_>, radius: f64, fill_height: f64, liquid_mass: f64, axial_acceleration: f64, modes: usize) -> PyResult<Py<PyAny>> {
    let t = spacearm_core::model::slosh_tank::cylinder_slosh(radius, fill_height, liquid_mass, axial_acceleration, modes).or_raise(py)?;
    tank_slosh_to_py(py, &t)
}

/// The equivalent mechanical model of the liquid in a spherical tank (core
/// `model::slosh_sphere::sphere_slosh`, a Ritz-Trefftz solution): the same dict as
/// `cylinder_slosh` (`liquid_cm_height` above the bottom pole).
#[pyfunction]
#[pyo3(signature = (radius, fill_height, liquid_mass, axial_acceleration, modes=1))]
pub fn sphere_slosh(py: Python<'_>, radius: f64, fill_height: f64, liquid_mass: f64, axial_acceleration: f64, modes: usize) -> PyResult<Py<PyAny>> {
    let t = spacearm_core::model::slosh_sphere::sphere_slosh(radius, fill_height, liquid_mass, axial_acceleration, modes).or_raise(py)?;
    tank_slosh_to_py(py, &t)
}

/// The fill height (m) of a sphere of `radius` holding `fill_fraction` of its volume (core
/// `model::slosh_sphere::sphere_fill_height`).
#[pyfunction]
pub fn sphere_fill_height(py: Python<'_>, radius: f64, fill_fraction: f64) -> PyResult<f64> {
    spacearm_core::model::slosh_sphere::sphere_fill_height(radius, fill_fraction).or_raise(py)
}

/// The fill height (m) of an upright cylinder of `tank_height` holding `fill_fraction` of its
/// height, in (0, 1) (core `model::slosh_tank::cylinder_fill_height`: a full tank does not slosh).
#[pyfunction]
pub fn cylinder_fill_height(py: Python<'_>, tank_height: f64, fill_fraction: f64) -> PyResult<f64> {
    spacearm_core::model::slosh_tank::cylinder_fill_height(tank_height, fill_fraction).or_raise(py)
}

/// The dict of a tank's slosh model: the core's `TankSlosh` field by field, `modes` a list of
/// `SloshMode` dicts.
fn tank_slosh_to_py(py: Python<'_>, t: &spacearm_core::model::slosh_tank::TankSlosh) -> PyResult<Py<PyAny>> {
    Ok(crate::controller_spec_py::to_data(py, t)?.unbind())
}

/// A control-moment gyro's gimbal and rotor links (core `model::cmg::cmg_parts`, docs/cmg.md)
/// from the plain data of a core `CmgSpec` (the fields of a TOML `[[cmg]]` table); `base` is
/// the base's name (the parent when `spec` names none).
#[pyfunction]
pub fn cmg_parts(py: Python<'_>, spec: &Bound<'_, PyAny>, base: &str) -> PyResult<Py<PyAny>> {
    use spacearm_core::error::ModelItem;
    use spacearm_core::model::cmg::{self, CmgSpec};
    let spec: CmgSpec = crate::controller_spec_py::from_data(spec, "cmg")?;
    let parts = cmg::cmg_parts(&spec, base, ModelItem::Model).or_raise(py)?;
    parts_to_py(py, parts)
}

/// The CMGs of a model (core `model::cmg::detect_cmgs`), each as a dict: `name`, `parent`
/// (body index), `gimbal_dof`, `rotor_dof`, `gimbal_axis`, `spin_axis` (parent frame, at zero
/// gimbal angle), `rotor_inertia`, `variable_speed`, `max_gimbal_rate`, `max_wheel_speed`.
#[pyfunction]
pub fn cmgs<'py>(py: Python<'py>, model: &Bound<'py, PyModel>) -> PyResult<Bound<'py, PyAny>> {
    crate::controller_spec_py::to_data(py, &spacearm_core::model::cmg::detect_cmgs(&model.borrow().model))
}

/// The generalized velocity with every CMG rotor at `wheel_speed` (one value, or one per CMG)
/// and everything else at rest (core `model::cmg::cmg_velocity`).
#[pyfunction]
pub fn cmg_velocity(py: Python<'_>, model: &Bound<'_, PyModel>, wheel_speed: Vec<f64>) -> PyResult<Vec<f64>> {
    spacearm_core::model::cmg::cmg_velocity(&model.borrow().model, &wheel_speed).or_raise(py)
}

/// A gripper's palm and finger links, points and capsule collision shapes (core
/// `model::gripper::gripper_parts`, docs/contact.md "Grippers") from the plain data of a core
/// `GripperSpec` (the fields of a TOML `[[gripper]]` table); `base` is the base's name. Returns
/// `(links, points, geometries)`, each geometry `(name, body, role, shape, radius, length,
/// origin, rotation)`.
#[pyfunction]
pub fn gripper_parts(py: Python<'_>, spec: &Bound<'_, PyAny>, base: &str) -> PyResult<Py<PyAny>> {
    use spacearm_core::error::ModelItem;
    use spacearm_core::model::gripper::{self, GripperSpec};
    let spec: GripperSpec = crate::controller_spec_py::from_data(spec, "gripper")?;
    let parts = gripper::gripper_parts(&spec, base, ModelItem::Model).or_raise(py)?;
    let mut links = Vec::new();
    for (l, _) in parts.links {
        let limits = moving_limits(&l);
        links.push(add_link_args(py, l, limits, None)?);
    }
    let mut geometries = Vec::new();
    for g in parts.geometries {
        let Shape::Capsule { radius, length } = g.shape else { continue };
        let role = if g.role == GeometryRole::Collision { "collision" } else { "visual" };
        geometries.push((g.name, g.body, role, "capsule", radius, length, g.origin, g.rotation).into_py_any(py)?);
    }
    (links, parts.points, geometries).into_py_any(py)
}

/// A probe's or a drogue's collision shapes and points (core `model::docking`, docs/contact.md
/// "Probe and drogue") from the plain data of a core `ProbeSpec` (`kind = "probe"`) or
/// `DrogueSpec` (`"drogue"`). Returns `(points, geometries)`, each geometry `(name, body, role,
/// shape, radius, length, origin, rotation)`.
#[pyfunction]
pub fn docking_parts(py: Python<'_>, kind: &str, spec: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
    use spacearm_core::error::ModelItem;
    use spacearm_core::model::docking::{self, DrogueSpec, ProbeSpec};
    let parts = match kind {
        "probe" => docking::probe_parts(&crate::controller_spec_py::from_data::<ProbeSpec>(spec, "probe")?, ModelItem::Model),
        "drogue" => docking::drogue_parts(&crate::controller_spec_py::from_data::<DrogueSpec>(spec, "drogue")?, ModelItem::Model),
        other => return Err(SpacearmError::InvalidArgument(format!("docking part must be \"probe\" or \"drogue\", got {other:?}"))).or_raise(py),
    }
    .or_raise(py)?;
    let mut geometries = Vec::new();
    for g in parts.geometries {
        let (shape, radius, length) = match g.shape {
            Shape::Capsule { radius, length } => ("capsule", radius, length),
            Shape::Cylinder { radius, length } => ("cylinder", radius, length),
            Shape::Sphere { radius } => ("sphere", radius, 0.0),
            _ => continue,
        };
        geometries.push((g.name, g.body, "collision", shape, radius, length, g.origin, g.rotation).into_py_any(py)?);
    }
    (parts.points, geometries).into_py_any(py)
}

/// The grippers of a model (core `model::gripper::detect_grippers`), each as a dict: `name`,
/// `palm` (body index), `finger_dofs`, `kind` (`"prismatic"` or `"revolute"`).
#[pyfunction]
pub fn grippers(py: Python<'_>, model: &Bound<'_, PyModel>) -> PyResult<Vec<Py<PyAny>>> {
    use pyo3::types::PyDict;
    let mut out = Vec::new();
    for g in spacearm_core::model::gripper::detect_grippers(&model.borrow().model) {
        let d = PyDict::new(py);
        d.set_item("name", g.name)?;
        d.set_item("palm", g.palm)?;
        d.set_item("finger_dofs", g.finger_dofs)?;
        d.set_item("kind", g.kind.as_str())?;
        out.push(d.into_any().unbind());
    }
    Ok(out)
}
