//! `spacearm._core.BatchSimulator`: `B` plants stepped one RK4 step each per call on native
//! threads with the GIL released (`spacearm_core::sim::batch_stepper::BatchStepper`), each
//! copy holding its own joint torque (and base wrench) over its step. Behind the vectorized
//! environments of `spacearm.gym`.

use std::sync::Mutex;

use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyList;
use spacearm_core::control::ZeroTorque;
use spacearm_core::sim::batch_stepper::{admit_batch, BatchStepper};
use spacearm_core::sim::integrate::IntegratorKind;
use spacearm_core::sim::simulate::{check_initial_state, Plant, SimOptions};
use spacearm_core::sim::stepper::Rk4Stepper;
use spacearm_core::{Model, SpacearmError};

use crate::convert::*;
use crate::model_py::PyModel;
use crate::sim_options_py::PyRunOptions;

/// What one call holds while it works: the copies and the held inputs.
struct Inner {
    batch: BatchStepper,
    tau: Vec<f64>,
    wrench: Vec<f64>,
}

/// A batch of plants stepped together.
#[pyclass(module = "spacearm._core", name = "BatchSimulator")]
pub struct PyBatchSimulator {
    opts: SimOptions,
    n_dof: usize,
    nx: usize,
    nu: usize,
    copies: usize,
    /// Taken by every method for its whole call (released only by the call itself): a second
    /// thread calling while one works gets a `SimulationError` saying so, not a borrow error.
    inner: Mutex<Inner>,
}

fn new_copy(py: Python<'_>, model: Model, opts: &SimOptions, x0: &[f64], u0: &[f64], i: usize) -> PyResult<Rk4Stepper<'static>> {
    let for_copy = |e| to_py_err_in(py, &format!("copy {i}"), e);
    check_initial_state(&model, x0, u0).map_err(for_copy)?;
    let plant = Plant::owned(model, opts, Box::new(ZeroTorque)).map_err(for_copy)?;
    Rk4Stepper::new(plant, x0, u0, None).map_err(for_copy)
}

fn core_model(py: Python<'_>, m: &Bound<'_, PyAny>) -> PyResult<Model> {
    m.cast::<PyModel>().map(|m| m.borrow().model.clone()).map_err(|_| to_py_err(py, bad("models must be spacearm core models".into())))
}

/// `values` (B copies of `width` each) if every one is finite, else a `NonFiniteError` naming the
/// copy and the entry within it (not the flat index).
fn check_copies_finite(py: Python<'_>, what: &str, values: &[f64], width: usize) -> PyResult<()> {
    if let Some(k) = values.iter().position(|v| !v.is_finite()) {
        let (copy, entry) = (k / width.max(1), k % width.max(1));
        return Err(to_py_err(py, SpacearmError::NonFinite { what: format!("{what} of copy {copy}"), index: entry, value: values[k] }));
    }
    Ok(())
}

impl PyBatchSimulator {
    /// The batch for this call, or a `SimulationError` when another thread is using it.
    fn lock(&self, py: Python<'_>) -> PyResult<std::sync::MutexGuard<'_, Inner>> {
        match self.inner.try_lock() {
            Ok(guard) => Ok(guard),
            Err(std::sync::TryLockError::WouldBlock) => Err(to_py_err(
                py,
                SpacearmError::Simulation(
                    "the BatchSimulator (or the vector environment on it) is in use by another thread: step, reset and read it from \
                     one thread at a time (one environment per thread)"
                        .into(),
                ),
            )),
            Err(std::sync::TryLockError::Poisoned(_)) => Err(to_py_err(py, bad("the batch is poisoned".into()))),
        }
    }
}

#[pymethods]
impl PyBatchSimulator {
    /// `models`: one core model per copy (all with the same joints); `x0` (B·nx) and `u0`
    /// (B·nu): the copies' initial states, row after row; `threads`: None (rayon's pool) or
    /// 1..=1024. The batch is admitted first (`BatchSimulator.admit`): a batch too large for
    /// the memory limit is a `ResourceLimitError` before anything is allocated.
    #[new]
    #[pyo3(signature = (models, x0, u0, options, threads=None))]
    fn new(py: Python<'_>, models: &Bound<'_, PyList>, x0: &Bound<'_, PyAny>, u0: &Bound<'_, PyAny>, options: PyRef<'_, PyRunOptions>, threads: Option<usize>) -> PyResult<Self> {
        let opts = options.sim_options(1.0);
        if opts.integrator != IntegratorKind::Rk4 {
            return Err(to_py_err(py, bad("the BatchSimulator steps with integrator 'rk4' only".into())));
        }
        opts.validate().or_raise(py)?;
        opts.refuse_stop("the BatchSimulator").or_raise(py)?;
        let b = models.len();
        let first = match models.iter().next() {
            Some(m) => core_model(py, &m)?,
            None => return Err(to_py_err(py, bad("a batch needs at least one model".into()))),
        };
        admit_batch(&first, b).or_raise(py)?;
        let (nx, nu, n_dof) = (first.nx(), first.nu(), first.n_dof());
        let x0 = vec_arg_n(x0, "x0", b * nx)?;
        let u0 = vec_arg_n(u0, "u0", b * nu)?;
        let (x0, u0) = (x0.as_slice().to_vec(), u0.as_slice().to_vec());
        let mut copies = Vec::with_capacity(b);
        for (i, m) in models.iter().enumerate() {
            py.check_signals()?;
            let m = if i == 0 { first.clone() } else { core_model(py, &m)? };
            same_joints("model", i, &m, n_dof).or_raise(py)?;
            copies.push(new_copy(py, m, &opts, &x0[i * nx..(i + 1) * nx], &u0[i * nu..(i + 1) * nu], i)?);
        }
        let batch = BatchStepper::new(copies, opts.dt, threads).or_raise(py)?;
        let inner = Inner { batch, tau: vec![0.0; b * n_dof], wrench: vec![0.0; b * 6] };
        Ok(PyBatchSimulator { opts, n_dof, nx, nu, copies: b, inner: Mutex::new(inner) })
    }

    /// Admit a batch of `copies` copies of `model` (the core's `batch_stepper::admit_batch`), or
    /// raise `ResourceLimitError` naming its size and the limit: what the constructor checks
    /// first, for callers that build large arguments (the copies' states) before it.
    #[staticmethod]
    fn admit(py: Python<'_>, model: &Bound<'_, PyAny>, copies: usize) -> PyResult<()> {
        let m = core_model(py, model)?;
        admit_batch(&m, copies).or_raise(py)
    }

    /// The number of copies.
    fn __len__(&self) -> usize {
        self.copies
    }

    /// Start copy `index` again at `t = 0` from `(x0, u0)`, with the plant `model` (None: its
    /// current one).
    #[pyo3(signature = (index, x0, u0, model=None))]
    fn reset(&self, py: Python<'_>, index: usize, x0: &Bound<'_, PyAny>, u0: &Bound<'_, PyAny>, model: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
        let x0 = vec_arg_n(x0, "x0", self.nx)?;
        let u0 = vec_arg_n(u0, "u0", self.nu)?;
        let model = model.filter(|m| !m.is_none()).map(|m| core_model(py, m)).transpose()?;
        let mut inner = self.lock(py)?;
        let batch = &mut inner.batch;
        if index >= batch.len() {
            return Err(to_py_err(py, bad(format!("copy index {index} out of range for a batch of {}", batch.len()))));
        }
        let model = match model {
            Some(m) if m.n_dof() != self.n_dof => {
                return Err(to_py_err(py, bad(format!("the new model has {} joints, the batch {}", m.n_dof(), self.n_dof))));
            }
            Some(m) => m,
            None => batch.copy(index).model().clone(),
        };
        let stepper = new_copy(py, model, &self.opts, x0.as_slice(), u0.as_slice(), index)?;
        batch.replace(index, stepper).or_raise(py)
    }

    /// `n` (>= 1) steps of `dt` of every copy, copy `i` holding the joint torque `tau[i]` (N)
    /// and base wrench `base_wrench[i]` (6; None: zero) over them (steps land on `t = k·dt`, as
    /// `Simulator.step`'s); `tau` (B·N) and `base_wrench` (B·6)
    /// row after row. Returns the new states, (B, 13+2N). The GIL is released while the copies
    /// step, one step of all of them at a time, with a check for Ctrl-C between the steps (a
    /// `KeyboardInterrupt` leaves the copies where they are). A copy that fails raises its
    /// error (`copy i: ...`) after the step in which it failed (the others took that step
    /// too); it needs a reset. A non-finite input is named by its copy and entry.
    #[pyo3(signature = (tau, base_wrench=None, n=1))]
    fn step<'py>(&self, py: Python<'py>, tau: &Bound<'_, PyAny>, base_wrench: Option<&Bound<'_, PyAny>>, n: usize) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let b = self.copies;
        let tau = vec_arg_n(tau, "tau", b * self.n_dof)?;
        check_copies_finite(py, "tau", tau.as_slice(), self.n_dof)?;
        let wrench = match base_wrench.filter(|w| !w.is_none()) {
            Some(w) => {
                let w = vec_arg_n(w, "base_wrench", b * 6)?;
                check_copies_finite(py, "base_wrench", w.as_slice(), 6)?;
                Some(w)
            }
            None => None,
        };
        if n == 0 {
            return Err(to_py_err(py, bad("steps must be >= 1".into())));
        }
        let mut guard = self.lock(py)?;
        let inner = &mut *guard;
        inner.tau.copy_from_slice(tau.as_slice());
        if let Some(w) = &wrench {
            inner.wrench.copy_from_slice(w.as_slice());
        }
        let with_wrench = wrench.is_some();
        let dim = self.nx + self.nu;
        let mut out = vec![0.0; b * dim];
        let (tau, wrench, batch) = (&inner.tau, &inner.wrench, &mut inner.batch);
        for k in 0..n {
            if k > 0 {
                py.check_signals()?;
            }
            let outcomes = py.detach(|| batch.step(tau, with_wrench.then_some(wrench.as_slice()), 1, &mut out)).or_raise(py)?;
            if let Some((i, e)) = outcomes.into_iter().enumerate().find_map(|(i, r)| r.err().map(|e| (i, e))) {
                return Err(to_py_err_in(py, &format!("copy {i}"), e));
            }
        }
        Ok(PyArray1::from_vec(py, out).reshape([b, dim])?)
    }

    /// The copies' current states, (B, 13+2N) (a new array).
    #[getter]
    fn states<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let inner = self.lock(py)?;
        let batch = &inner.batch;
        let dim = batch.state_dim();
        let flat: Vec<f64> = (0..batch.len()).flat_map(|i| batch.copy(i).state().to_vec()).collect();
        Ok(PyArray1::from_vec(py, flat).reshape([batch.len(), dim])?)
    }

    /// The copies' current times, s, (B,).
    #[getter]
    fn times<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let inner = self.lock(py)?;
        let t: Vec<f64> = (0..inner.batch.len()).map(|i| inner.batch.copy(i).time()).collect();
        Ok(PyArray1::from_vec(py, t))
    }

    /// Steps each copy took since its last reset, (B,).
    #[getter]
    fn n_steps(&self, py: Python<'_>) -> PyResult<Vec<usize>> {
        let inner = self.lock(py)?;
        Ok((0..inner.batch.len()).map(|i| inner.batch.copy(i).n_steps()).collect())
    }
}
