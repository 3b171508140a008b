//! Model input and output: TOML model files (`spacearm-core::io::toml`) and
//! Denavit–Hartenberg tables (`spacearm-core::io::dh`). Wrapped by `spacearm.model_file` and
//! `spacearm.dh`, which normalize the arguments.

use pyo3::prelude::*;
use spacearm_core::io::dh::{ClassicDhLink, DhArm, DhConvention, DhTable, PaperDhLink};
use spacearm_core::JointType;

use crate::builder_py::joint_limits;

use crate::convert::*;
use crate::model_py::PyModel;

/// Parse a model from TOML text; `source` names it in error messages;
/// `allow_nonphysical_inertia` accepts inertias that break the triangle inequality (with
/// warnings kept on the model).
#[pyfunction]
#[pyo3(signature = (text, source = "<string>", allow_nonphysical_inertia = false))]
pub fn model_from_toml(py: Python<'_>, text: &str, source: &str, allow_nonphysical_inertia: bool) -> PyResult<PyModel> {
    let rule = triangle_inequality(allow_nonphysical_inertia);
    let model = py.detach(|| spacearm_core::io::toml::model_from_toml_str_with(text, source, rule));
    model.map(PyModel::new).or_raise(py)
}

/// The model as TOML text (exact round trip).
#[pyfunction]
pub fn model_to_toml(model: PyRef<'_, PyModel>) -> String {
    spacearm_core::io::toml::model_to_toml(&model.model)
}

/// One classic DH row: `(name, joint_name, type, d, theta, a, alpha, com, mass, inertia,
/// limits)`.
type ClassicRow = (Option<String>, Option<String>, String, f64, f64, f64, f64, [f64; 3], f64, [[f64; 3]; 3], Option<[f64; 4]>);

/// One paper-convention row: `(name, joint_name, type, theta, alpha, joint_to_com,
/// com_to_next, mass, inertia, limits)`.
type PaperRow = (Option<String>, Option<String>, String, f64, f64, [f64; 3], [f64; 3], f64, [[f64; 3]; 3], Option<[f64; 4]>);

/// The rows of `convention` (`"classic"` or `"paper"`) as a core DH table.
fn dh_table(convention: &str, rows: &Bound<'_, PyAny>) -> PyResult<spacearm_core::Result<DhTable>> {
    let convention = match DhConvention::from_name(convention) {
        Ok(c) => c,
        Err(e) => return Ok(Err(e)),
    };
    Ok(match convention {
        DhConvention::Classic => rows
            .extract::<Vec<ClassicRow>>()?
            .into_iter()
            .map(|(name, joint_name, kind, d, theta, a, alpha, com, mass, inertia, lim)| {
                Ok(ClassicDhLink { name, joint_name, kind: JointType::from_name(&kind)?, d, theta, a, alpha, com, mass, inertia, limits: joint_limits(lim) })
            })
            .collect::<spacearm_core::Result<_>>()
            .map(DhTable::Classic),
        DhConvention::Paper => rows
            .extract::<Vec<PaperRow>>()?
            .into_iter()
            .map(|(name, joint_name, kind, theta, alpha, joint_to_com, com_to_next, mass, inertia, lim)| {
                Ok(PaperDhLink {
                    name,
                    joint_name,
                    kind: JointType::from_name(&kind)?,
                    theta,
                    alpha,
                    joint_to_com,
                    com_to_next,
                    mass,
                    inertia,
                    limits: joint_limits(lim),
                })
            })
            .collect::<spacearm_core::Result<_>>()
            .map(DhTable::Paper),
    })
}

/// A model whose arm is given by a DH table in `convention`: `"classic"` (distal DH, rows
/// `ClassicRow`) or `"paper"` (Wilde et al. (2018) §2, rows `PaperRow`); see `docs/dh.md`.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
#[pyo3(signature = (convention, name, base_name, base_mass, base_inertia, rows, joint1_origin, joint1_rotation, tool_offset, tip_point, initial_q=None))]
pub fn model_from_dh(
    py: Python<'_>,
    convention: &str,
    name: &str,
    base_name: &str,
    base_mass: f64,
    base_inertia: [[f64; 3]; 3],
    rows: &Bound<'_, PyAny>,
    joint1_origin: [f64; 3],
    joint1_rotation: [f64; 4],
    tool_offset: [f64; 3],
    tip_point: Option<String>,
    initial_q: Option<Vec<f64>>,
) -> PyResult<PyModel> {
    dh_table(convention, rows)?
        .and_then(|table| {
            let arm = DhArm { table, parent: base_name.to_string(), joint1_origin, joint1_rotation, tool_offset, tip_point };
            spacearm_core::io::dh::model_from_dh(name, base_name, base_mass, base_inertia, &arm, initial_q)
        })
        .map(PyModel::new)
        .or_raise(py)
}
