//! `spacearm._core.mpc_solve`: one optimal-control solve by the core's FDDP
//! (`spacearm_core::optimal`), the problem and the solver options as the core's serde data
//! (`ProblemSpec`, `SolverOptions`); wrapped by `spacearm.mpc.solve`.

use numpy::PyArray2;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use spacearm_core::optimal::{solve, ProblemSpec, RobotProblem, SolverOptions};

use crate::controller_spec_py::from_data;
use crate::convert::*;
use crate::model_py::PyModel;

/// Rows of a 2-D array argument, each of `cols` numbers, `rows` of them.
fn rows_arg(obj: &Bound<'_, PyAny>, what: &str, rows: usize, cols: usize) -> PyResult<Vec<Vec<f64>>> {
    let (v, r, c) = matrix_arg(obj, what)?;
    if r != rows || c != cols {
        return Err(shape_error(obj.py(), format!("{what} must have shape ({rows}, {cols}), got ({r}, {c})")));
    }
    Ok(v.chunks(cols).map(|s| s.to_vec()).collect())
}

fn rows_array<'py>(py: Python<'py>, rows: &[Vec<f64>], from: usize, len: usize) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let v: Vec<Vec<f64>> = rows.iter().map(|r| r[from..from + len].to_vec()).collect();
    PyArray2::from_vec2(py, &v).map_err(|e| to_py_err(py, spacearm_core::SpacearmError::InvalidArgument(format!("{e}"))))
}

/// Solve `problem` (the data of a `ProblemSpec`) on `model` from `(x0, u0)` with `options`
/// (the data of `SolverOptions`); warm start from `states` (`(T+1, 13+2N)`, rows `[x; u]`) and
/// `controls` (`(T, m)`). Returns a dict: `x`, `u`, `controls`, `control_columns`, `cost`,
/// `iterations`, `steps`, `stop`, `converged`, `gap`, `expected_decrease`, `regularization`,
/// `solve_time`.
#[pyfunction]
#[pyo3(signature = (model, problem, x0, u0, options, states=None, controls=None))]
#[allow(clippy::too_many_arguments)]
pub fn mpc_solve<'py>(
    py: Python<'py>,
    model: &Bound<'py, PyModel>,
    problem: &Bound<'py, PyAny>,
    x0: &Bound<'py, PyAny>,
    u0: &Bound<'py, PyAny>,
    options: &Bound<'py, PyAny>,
    states: Option<&Bound<'py, PyAny>>,
    controls: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let spec: ProblemSpec = from_data(problem, "mpc problem")?;
    let opts: SolverOptions = from_data(options, "mpc solver options")?;
    let model = model.borrow().model.clone();
    let mut z0 = vec_arg_n(x0, "x0", model.nx())?.as_slice().to_vec();
    z0.extend_from_slice(vec_arg_n(u0, "u0", model.nu())?.as_slice());
    let mut shooting = RobotProblem::new(&model, &spec, &z0).or_raise(py)?;
    let (t, nz, m) = (spec.horizon, model.nx() + model.nu(), shooting.control_columns().len());
    let zs = states.filter(|s| !s.is_none()).map(|s| rows_arg(s, "states", t + 1, nz)).transpose()?;
    let cs = controls.filter(|s| !s.is_none()).map(|s| rows_arg(s, "controls", t, m)).transpose()?;
    let sol = py.detach(|| solve(&mut shooting, zs.as_deref(), cs.as_deref(), &opts)).or_raise(py)?;
    let out = PyDict::new(py);
    out.set_item("x", rows_array(py, &sol.zs, 0, model.nx())?)?;
    out.set_item("u", rows_array(py, &sol.zs, model.nx(), model.nu())?)?;
    out.set_item("controls", rows_array(py, &sol.cs, 0, m)?)?;
    out.set_item("control_columns", shooting.control_columns().to_vec())?;
    out.set_item("cost", sol.cost)?;
    out.set_item("iterations", sol.iterations)?;
    out.set_item("steps", sol.steps)?;
    out.set_item("stop", sol.stop.name())?;
    out.set_item("converged", sol.converged())?;
    out.set_item("gap", sol.gap)?;
    out.set_item("expected_decrease", sol.expected_decrease)?;
    out.set_item("regularization", sol.regularization)?;
    out.set_item("solve_time", sol.solve_time)?;
    Ok(out)
}
