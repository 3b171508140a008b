//! `spacearm._core.ModelBuilder`: the core's incremental builder (wrapped by
//! `spacearm.RobotBuilder`).

use pyo3::prelude::*;
use spacearm_core::{JointDynamics, JointLimits, JointType, LinkSpec, ModelBuilder, SpacearmError};

use crate::convert::*;
use crate::model_py::PyModel;

#[pyclass(module = "spacearm._core", name = "ModelBuilder")]
pub struct PyModelBuilder {
    inner: ModelBuilder,
}

fn joint_type(py: Python<'_>, s: &str) -> PyResult<JointType> {
    match s {
        "revolute" => Ok(JointType::Revolute),
        "prismatic" => Ok(JointType::Prismatic),
        "fixed" => Ok(JointType::Fixed),
        other => Err(to_py_err(
            py,
            SpacearmError::InvalidModel(format!("joint type must be 'revolute', 'prismatic' or 'fixed', got '{other}'")),
        )),
    }
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
                .map_err(SpacearmError::from)
                .or_raise(py)?,
        })
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
        let kind = self::joint_type(py, joint_type)?;
        let limits = match limits {
            None => JointLimits::unlimited(),
            Some([lower, upper, velocity, effort]) => JointLimits { lower, upper, velocity, effort },
        };
        self.inner
            .add_link(LinkSpec {
                name: name.to_string(),
                parent: parent.to_string(),
                joint_name,
                kind,
                origin_in_parent: origin,
                rotation_in_parent: rotation,
                axis,
                com_from_joint: com,
                mass,
                inertia,
                limits,
            })
            .map_err(SpacearmError::from)
            .or_raise(py)?;
        // `(actuated, stiffness, damping, rest)`: the joint's passive dynamics (docs/flexibility.md).
        if let Some((actuated, stiffness, damping, rest)) = dynamics {
            self.inner
                .set_joint_dynamics(name, JointDynamics { actuated, stiffness, damping, rest })
                .map_err(SpacearmError::from)
                .or_raise(py)?;
        }
        Ok(())
    }

    fn add_point(&mut self, py: Python<'_>, name: &str, body: &str, offset: [f64; 3]) -> PyResult<()> {
        self.inner.add_point(name, body, offset).map_err(SpacearmError::from).or_raise(py)?;
        Ok(())
    }

    fn set_end_effector(&mut self, name: &str) {
        self.inner.set_end_effector(name);
    }

    fn set_initial_q(&mut self, q: Vec<f64>) {
        self.inner.set_initial_q(q);
    }

    fn build(&self, py: Python<'_>) -> PyResult<PyModel> {
        Ok(PyModel::new(self.inner.build().map_err(SpacearmError::from).or_raise(py)?))
    }
}
