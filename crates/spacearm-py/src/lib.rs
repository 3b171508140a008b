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
mod capture_py;
mod collision_py;
mod contact_py;
mod controller_spec_py;
mod convert;
mod derivatives_py;
mod description_py;
mod edit_py;
mod errors_py;
mod events_py;
mod interrupt;
mod model_io_py;
mod model_py;
mod mpc_py;
mod orbit_py;
mod records_py;
mod rigid_contact_py;
mod grasp_outcome_py;
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
    use convert::add_to_module;
    errors_py::register(m)?;
    add_to_module!(
        m,
        functions: [
            batch::set_batch_threads, batch::batch_threads,
            builder_py::slosh_links, builder_py::panel_parts, builder_py::beam_parts, builder_py::compliant_parts,
            builder_py::cmg_parts, builder_py::cmgs, builder_py::cmg_velocity, builder_py::gripper_parts, builder_py::grippers, builder_py::docking_parts,
            builder_py::cylinder_slosh, builder_py::sphere_slosh, builder_py::sphere_fill_height, builder_py::cylinder_fill_height,
            edit_py::model_attach_body, edit_py::model_attach_model, edit_py::model_remove_subtree,
            preset,
            model_io_py::model_from_toml, model_io_py::model_to_toml, model_io_py::model_from_dh,
        ],
        classes: [
            model_py::PyModel, model_py::PyTape, builder_py::PyModelBuilder, derivatives_py::PyDerivatives,
            description_py::PyModelDescription, description_py::PyBaseDescription, description_py::PyLinkDescription,
            description_py::PyJointLimits, description_py::PyPointDescription, description_py::PyGeometryDescription,
            rule_tables_py::PySimDefaults, rule_tables_py::PyModelBounds, rule_tables_py::PyDlsDefaults,
        ],
    );
    analysis_py::register(m)?;
    contact_py::register(m)?;
    collision_py::register(m)?;
    rigid_contact_py::register(m)?;
    grasp_outcome_py::register(m)?;
    capture_py::register(m)?;
    add_to_module!(
        m,
        classes: [
            analysis_py::PyRmrcOptions,
            analysis_results_py::PyJacobianMeasures, analysis_results_py::PySingularityReport, analysis_results_py::PyDetection,
            analysis_results_py::PyScanResult, analysis_results_py::PyWorkspaceShells, analysis_results_py::PyReactionNullSpace,
            analysis_results_py::PyRmrcRates, analysis_results_py::PyRmrcMotion,
        ],
    );
    rules_py::register(m)?;
    rotations_py::register(m)?;
    orbit_py::register(m)?;
    add_to_module!(
        m,
        functions: [
            simulate_py::simulate, rollout_py::rollout, controller_spec_py::check_spec, mpc_py::mpc_solve,
            simulate_py::perturbed, simulate_py::perturbed_cmgs_py, simulate_py::conserved_drift, simulate_py::default_wheel_dofs,
        ],
        classes: [
            simulator_py::PySimulator, batch_simulator_py::PyBatchSimulator,
            // The typed inputs of simulate, rollout and Simulator.
            sim_options_py::PyRunOptions, sim_options_py::PyThrusterLimits,
            controller_spec_py::PyJointReference, controller_spec_py::PyInputShaper,
            controller_spec_py::PyFreeBodyReference, controller_spec_py::PyControllerSpec,
            // The typed results of simulate, rollout and Simulator.
            records_py::PyRunRecords, records_py::PyRunEvents, records_py::PyConservedDrift,
            records_py::PyRunMeta, records_py::PyRunResult, records_py::PyRolloutBatch,
        ],
    );
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
