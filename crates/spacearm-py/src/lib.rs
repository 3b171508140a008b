//! PyO3 bindings of `spacearm-core`, built as the private extension `spacearm._core`.
//!
//! Thin by design: each method converts numpy arrays to slices, calls one core function and
//! converts the result back; errors are the exception classes of `errors_py.rs`, re-exported by `spacearm.errors`; every
//! per-state method runs through the one batch driver of `batch.rs`. The Python package
//! (`python/spacearm`) is the face users see.

mod analysis_py;
mod analysis_results_py;
mod batch;
mod batch_simulator_py;
mod builder_py;
mod events_py;
mod contact_py;
mod controller_spec_py;
mod convert;
mod derivatives_py;
mod description_py;
mod edit_py;
mod errors_py;
mod interrupt;
mod model_io_py;
mod model_py;
mod orbit_py;
mod records_py;
mod rollout_py;
mod rotations_py;
mod rule_tables_py;
mod rules_py;
mod sim_options_py;
mod simulate_py;
mod simulator_py;

use pyo3::prelude::*;

/// A preset model by name (`planar4`, `spatial6`, ...); `allow_nonphysical_inertia` keeps
/// published inertias that break the triangle inequality (only `ets7` has such data).
#[pyfunction]
#[pyo3(signature = (name, allow_nonphysical_inertia = false))]
fn preset(py: Python<'_>, name: &str, allow_nonphysical_inertia: bool) -> PyResult<model_py::PyModel> {
    match spacearm_core::model::presets::by_name_with(name, convert::triangle_inequality(allow_nonphysical_inertia)) {
        Some(m) => Ok(model_py::PyModel::new(m)),
        None => Err(convert::to_py_err(
            py,
            spacearm_core::SpacearmError::NotFound(format!(
                "no preset named '{name}'; presets are {:?}",
                spacearm_core::model::presets::NAMES
            )),
        )),
    }
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    errors_py::register(m)?;
    m.add_function(wrap_pyfunction!(batch::set_batch_threads, m)?)?;
    m.add_function(wrap_pyfunction!(batch::batch_threads, m)?)?;
    m.add_class::<model_py::PyModel>()?;
    m.add_class::<model_py::PyTape>()?;
    m.add_class::<builder_py::PyModelBuilder>()?;
    m.add_function(wrap_pyfunction!(builder_py::slosh_links, m)?)?;
    m.add_function(wrap_pyfunction!(builder_py::panel_parts, m)?)?;
    m.add_function(wrap_pyfunction!(builder_py::beam_parts, m)?)?;
    m.add_function(wrap_pyfunction!(builder_py::compliant_parts, m)?)?;
    m.add_function(wrap_pyfunction!(builder_py::cylinder_slosh, m)?)?;
    m.add_function(wrap_pyfunction!(builder_py::sphere_slosh, m)?)?;
    m.add_function(wrap_pyfunction!(builder_py::sphere_fill_height, m)?)?;
    m.add_function(wrap_pyfunction!(builder_py::cylinder_fill_height, m)?)?;
    m.add_function(wrap_pyfunction!(edit_py::model_attach_body, m)?)?;
    m.add_function(wrap_pyfunction!(edit_py::model_attach_model, m)?)?;
    m.add_function(wrap_pyfunction!(edit_py::model_remove_subtree, m)?)?;
    m.add_class::<derivatives_py::PyDerivatives>()?;
    m.add_class::<description_py::PyModelDescription>()?;
    m.add_class::<description_py::PyBaseDescription>()?;
    m.add_class::<description_py::PyLinkDescription>()?;
    m.add_class::<description_py::PyJointLimits>()?;
    m.add_class::<description_py::PyPointDescription>()?;
    m.add_class::<description_py::PyGeometryDescription>()?;
    m.add_class::<rule_tables_py::PySimDefaults>()?;
    m.add_class::<rule_tables_py::PyModelBounds>()?;
    m.add_class::<rule_tables_py::PyDlsDefaults>()?;
    m.add_function(wrap_pyfunction!(preset, m)?)?;
    m.add_function(wrap_pyfunction!(model_io_py::model_from_toml, m)?)?;
    m.add_function(wrap_pyfunction!(model_io_py::model_to_toml, m)?)?;
    m.add_function(wrap_pyfunction!(model_io_py::model_from_classic_dh, m)?)?;
    m.add_function(wrap_pyfunction!(model_io_py::model_from_paper_dh, m)?)?;
    analysis_py::register(m)?;
    contact_py::register(m)?;
    m.add_class::<analysis_py::PyRmrcOptions>()?;
    m.add_class::<analysis_results_py::PyJacobianMeasures>()?;
    m.add_class::<analysis_results_py::PySingularityReport>()?;
    m.add_class::<analysis_results_py::PyDetection>()?;
    m.add_class::<analysis_results_py::PyScanResult>()?;
    m.add_class::<analysis_results_py::PyWorkspaceShells>()?;
    m.add_class::<analysis_results_py::PyReactionNullSpace>()?;
    m.add_class::<analysis_results_py::PyRmrcRates>()?;
    m.add_class::<analysis_results_py::PyRmrcMotion>()?;
    rules_py::register(m)?;
    rotations_py::register(m)?;
    orbit_py::register(m)?;
    m.add_function(wrap_pyfunction!(simulate_py::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(rollout_py::rollout, m)?)?;
    m.add_class::<simulator_py::PySimulator>()?;
    m.add_class::<batch_simulator_py::PyBatchSimulator>()?;
    // The typed inputs of simulate, rollout and Simulator.
    m.add_class::<sim_options_py::PyRunOptions>()?;
    m.add_class::<sim_options_py::PyThrusterLimits>()?;
    m.add_class::<events_py::PyStopCondition>()?;
    m.add_class::<controller_spec_py::PyJointReference>()?;
    m.add_class::<controller_spec_py::PyInputShaper>()?;
    m.add_class::<controller_spec_py::PyFreeBodyReference>()?;
    m.add_class::<controller_spec_py::PyControllerSpec>()?;
    m.add_function(wrap_pyfunction!(controller_spec_py::check_spec, m)?)?;
    // The typed results of simulate, rollout and Simulator.
    m.add_class::<records_py::PyRunRecords>()?;
    m.add_class::<records_py::PyRunEvents>()?;
    m.add_class::<records_py::PyConservedDrift>()?;
    m.add_class::<records_py::PyRunMeta>()?;
    m.add_class::<records_py::PyRunResult>()?;
    m.add_class::<records_py::PyRolloutBatch>()?;
    m.add_function(wrap_pyfunction!(simulate_py::perturbed, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_py::conserved_drift, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_py::default_wheel_dofs, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
