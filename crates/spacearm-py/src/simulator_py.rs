//! `spacearm._core.Simulator`: a plant stepped from Python one RK4 step (or `n`) at a time
//! (`spacearm_core::sim::stepper::Rk4Stepper`, the loop of `simulate`), with an optional joint
//! torque and base wrench held over each call. Wrapped by `spacearm.Simulator`.

use std::sync::Mutex;

use nalgebra::Vector6;
use numpy::PyArray1;
use pyo3::prelude::*;
use spacearm_core::control::{Controller, ZeroTorque};
use spacearm_core::sim::integrate::IntegratorKind;
use spacearm_core::sim::simulate::{check_initial_state, Plant, SimOptions};
use spacearm_core::sim::stepper::Rk4Stepper;
use spacearm_core::{Model, SpacearmError};

use crate::convert::*;
use crate::interrupt::run_reporting;
use crate::model_py::PyModel;
use crate::controller_spec_py::{build_controller, error_slot, take_error, ErrorSlot};
use crate::records_py::PyRunResult;
use crate::sim_options_py::PyRunOptions;


/// `n` of `step`: a Python int (not a bool) >= 1, else a `SpacearmTypeError` or `ArgumentError`.
fn step_count(py: Python<'_>, n: &Bound<'_, PyAny>) -> PyResult<usize> {
    use pyo3::types::{PyBool, PyInt};
    if n.is_instance_of::<PyBool>() || !(n.is_instance_of::<PyInt>() || n.hasattr("__index__")?) {
        return Err(type_error(py, format!("n must be an int >= 1 (a number of steps), got {}", n.get_type().name()?)));
    }
    let value: i128 = n.call_method0("__index__")?.extract().map_err(|_| to_py_err(py, bad("n must be an int >= 1, got one too large".into())))?;
    if value < 1 {
        return Err(to_py_err(py, bad(format!("n must be >= 1 (a number of steps), got {value}"))));
    }
    usize::try_from(value).map_err(|_| to_py_err(py, bad(format!("n must be at most {} (a number of steps), got {value}", usize::MAX))))
}

/// The state of a simulator between calls.
#[pyclass(module = "spacearm._core", name = "Simulator")]
pub struct PySimulator {
    model: Model,
    opts: SimOptions,
    float32: bool,
    /// The controller's spec, built anew at every reset (a fresh controller each run).
    spec: Option<Py<PyAny>>,
    /// `record_every`, or `None`: nothing recorded.
    record_every: Option<usize>,
    /// Behind a mutex so that the object may be used from any Python thread.
    stepper: Mutex<Option<Rk4Stepper<'static>>>,
    slot: ErrorSlot,
    /// Reused buffer of the held torque.
    tau: Vec<f64>,
}

/// The stepper of a simulator that was reset, else `ArgumentError` saying to call `reset` (a
/// function of the field, so that a method may borrow the simulator's other fields beside it).
fn started<'a>(py: Python<'_>, stepper: &'a mut Mutex<Option<Rk4Stepper<'static>>>) -> PyResult<&'a mut Rk4Stepper<'static>> {
    stepper.get_mut().map_err(|_| not_reset(py))?.as_mut().ok_or_else(|| not_reset(py))
}

fn not_reset(py: Python<'_>) -> PyErr {
    to_py_err(py, bad("the simulator has no state yet; call reset(x0, u0) first".into()))
}

/// The error of a failed step or command: the exception a callback controller raised (kept in
/// `slot`), else the core's `err`.
fn raised(py: Python<'_>, slot: &ErrorSlot, err: SpacearmError) -> PyErr {
    take_error(slot).unwrap_or_else(|| to_py_err(py, err))
}

#[pymethods]
impl PySimulator {
    #[new]
    #[pyo3(signature = (model, options, controller_spec=None, record_every=None))]
    fn new(py: Python<'_>, model: &Bound<'_, PyModel>, options: PyRef<'_, PyRunOptions>, controller_spec: Option<Bound<'_, PyAny>>, record_every: Option<usize>) -> PyResult<Self> {
        let (opts, float32) = (options.sim_options(1.0), options.records_float32());
        if opts.integrator != IntegratorKind::Rk4 {
            return Err(to_py_err(py, bad("the Simulator steps with integrator 'rk4' only; use spacearm.simulate for 'dopri5'".into())));
        }
        opts.validate().or_raise(py)?;
        opts.refuse_stop("the Simulator").or_raise(py)?;
        if record_every == Some(0) {
            return Err(to_py_err(py, bad("record_every must be an integer >= 1".into())));
        }
        let model = model.borrow().model.clone();
        let n = model.n_dof();
        Ok(PySimulator {
            model,
            opts,
            float32,
            spec: controller_spec.filter(|s| !s.is_none()).map(Bound::unbind),
            record_every,
            stepper: Mutex::new(None),
            slot: error_slot(),
            tau: vec![0.0; n],
        })
    }

    /// Start again at `t = 0` from `(x0, u0)` with a fresh controller and empty records.
    fn reset(&mut self, py: Python<'_>, x0: &Bound<'_, PyAny>, u0: &Bound<'_, PyAny>) -> PyResult<()> {
        let x0 = vec_arg(x0, "x0")?;
        let u0 = vec_arg(u0, "u0")?;
        check_initial_state(&self.model, x0.as_slice(), u0.as_slice()).or_raise(py)?;
        let controller: Box<dyn Controller> = match &self.spec {
            Some(s) => build_controller(s.bind(py), &self.model, &self.slot)?,
            None => Box::new(ZeroTorque),
        };
        let plant = Plant::owned(self.model.clone(), &self.opts, controller).or_raise(py)?;
        let recording = self.record_every.map(|every| (1024, every));
        let stepper = Rk4Stepper::new(plant, x0.as_slice(), u0.as_slice(), recording).or_raise(py)?;
        *self.stepper.get_mut().map_err(|_| not_reset(py))? = Some(stepper);
        Ok(())
    }

    /// Advance `n` steps of `dt` (an int >= 1; None: one), adding `tau` (N) and `base_wrench` (6) to the
    /// controller's command throughout (None: nothing added). Steps land on `t = i·dt`. The
    /// records the steps would add are admitted first; Ctrl-C stops a long call within 0.1 s.
    #[pyo3(signature = (tau=None, n=None, base_wrench=None))]
    /// Advance `n` steps and return the new state `[x; u]` (a new array).
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        tau: Option<&Bound<'_, PyAny>>,
        n: Option<&Bound<'_, PyAny>>,
        base_wrench: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let n = match n {
            Some(n) => step_count(py, n)?,
            None => 1,
        };
        let n_dof = self.model.n_dof();
        let held = match (tau, base_wrench) {
            (None, None) => None,
            (t, w) => {
                match t {
                    Some(t) => {
                        let v = vec_arg_n(t, "tau", n_dof)?;
                        check_finite(py, "tau", v.as_slice())?;
                        self.tau.copy_from_slice(v.as_slice());
                    }
                    None => self.tau.fill(0.0),
                }
                let w = match w {
                    Some(w) => {
                        let w = vec6(w, "base_wrench")?;
                        check_finite(py, "base_wrench", w.as_slice())?;
                        w
                    }
                    None => Vector6::zeros(),
                };
                Some(w)
            }
        };
        let dt = self.opts.dt;
        let tau = &self.tau;
        let stepper = started(py, &mut self.stepper)?;
        stepper.admit_steps(n).or_raise(py)?;
        stepper.plant_mut().set_held_input(held.map(|w| (tau.as_slice(), w)));
        let (result, interrupted) = if n == 1 {
            // One step is a few microseconds: releasing the GIL would cost a noticeable part of it.
            let t_next = (stepper.n_steps() + 1) as f64 * dt;
            (stepper.step_to(t_next), None)
        } else {
            // Ctrl-C checked at the progress reports (every 0.1 s of wall time); the steps taken
            // so far stay taken (the simulator can go on).
            run_reporting(py, None, |progress| {
                for _ in 0..n {
                    let t_next = (stepper.n_steps() + 1) as f64 * dt;
                    stepper.step_to(t_next)?;
                    progress(0.0)?;
                }
                Ok(())
            })
        };
        if let Some(e) = interrupted {
            return Err(e);
        }
        result.map_err(|e| raised(py, &self.slot, e))?;
        Ok(PyArray1::from_slice(py, stepper.state()))
    }

    /// The command the plant applies at `(t, x, u)`, without stepping: `(tau, base_wrench)` (N
    /// joint torques; `[F0, N0]` at the base CM in 𝒥), the controller's law (with the input of
    /// the last `step`, if any, added) through the actuator limits and the mode's mask, as at
    /// every stage of a step. The controller keeps its internal state across calls (the state a
    /// run would give it): a flight-software module samples the law this way
    /// (`spacearm.basilisk.ControllerModule`). Needs a `reset` first.
    fn command<'py>(
        &mut self,
        py: Python<'py>,
        t: f64,
        x: &Bound<'_, PyAny>,
        u: &Bound<'_, PyAny>,
    ) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>)> {
        if !t.is_finite() {
            return Err(to_py_err(py, bad(format!("t must be finite (s), got {t}"))));
        }
        let x = vec_arg(x, "x")?;
        let u = vec_arg(u, "u")?;
        // The initial-state checks, their messages naming `x` and `u` (not `x0`, `u0`).
        check_initial_state(&self.model, x.as_slice(), u.as_slice()).map_err(|e| to_py_err(py, match e {
            SpacearmError::Dimension { what, expected, got } => SpacearmError::Dimension { what: what.trim_end_matches('0').into(), expected, got },
            SpacearmError::NonFinite { what, index, value } => SpacearmError::NonFinite { what: what.trim_end_matches('0').into(), index, value },
            other => other,
        }))?;
        let stepper = started(py, &mut self.stepper)?;
        let plant = stepper.plant_mut();
        // A measured state is a sample of a sampled law (spacearm.control.MPC).
        let y: Vec<f64> = x.as_slice().iter().chain(u.as_slice()).copied().collect();
        plant.sample(t, &y).map_err(|e| raised(py, &self.slot, e))?;
        plant.apply_command(t, x.as_slice(), u.as_slice()).map_err(|e| raised(py, &self.slot, e))?;
        let (tau, wrench) = plant.applied();
        Ok((PyArray1::from_slice(py, tau), PyArray1::from_slice(py, wrench.as_slice())))
    }

    /// The current time, s.
    #[getter]
    fn time(&mut self, py: Python<'_>) -> PyResult<f64> {
        Ok(started(py, &mut self.stepper)?.time())
    }

    /// The current state `[x; u]` (a new array).
    #[getter]
    fn state<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(PyArray1::from_slice(py, started(py, &mut self.stepper)?.state()))
    }

    /// Steps taken since the last reset.
    #[getter]
    fn n_steps(&mut self, py: Python<'_>) -> PyResult<usize> {
        Ok(started(py, &mut self.stepper)?.n_steps())
    }

    /// The records so far with the current state as the last sample, as the `RunResult` of
    /// `spacearm._core.simulate` (the simulator goes on unchanged).
    fn result(&mut self, py: Python<'_>) -> PyResult<PyRunResult> {
        let (nx, nu, n) = (self.model.nx(), self.model.nu(), self.model.n_dof());
        let mut opts = self.opts.clone();
        opts.record_every = self.record_every.unwrap_or(usize::MAX);
        let stepper = started(py, &mut self.stepper)?;
        let res = stepper.snapshot().map_err(|e| raised(py, &self.slot, e))?;
        opts.duration = stepper.time();
        PyRunResult::of_run(py, res, &opts, self.float32, (nx, nu, n))
    }
}
