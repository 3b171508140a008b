//! `spacearm._core.Derivatives`: the exact derivatives of `spacearm_core::derivatives` for one
//! model, with their preallocated workspace (private; wrapped by the derivative methods of
//! `spacearm.Robot`).
//!
//! Tensors of partial derivatives come out as numpy arrays with the derivative index LAST:
//! `out[i, j, k] = ∂X[i, j]/∂x_k`.

use nalgebra::DMatrix;
use pyo3::prelude::*;
use spacearm_core as core;
use spacearm_core::derivatives::{self, DerivativeData, DerivativeMethod, LinearizationInputs};

use crate::batch::{Batched, Input, Pool};
use crate::convert::*;
use crate::model_py::{put, with_assembled_force, write, wrenches as wrench_list, PyModel, WrenchList};

/// The route of the partials of inverse dynamics: analytic, or dual numbers (the test oracle).
fn method(dual: bool) -> DerivativeMethod {
    if dual {
        DerivativeMethod::DualNumbers
    } else {
        DerivativeMethod::Analytic
    }
}

/// The derivative functions of one model (a copy of the model and a pool of workspaces; see
/// [`crate::batch`]: every method takes one state or a batch).
#[pyclass(module = "spacearm._core", name = "Derivatives", frozen)]
pub struct PyDerivatives {
    model: core::Model,
    workspaces: Pool<DerivativeData>,
}
crate::batch::batched!(PyDerivatives, DerivativeData);

/// Write matrices `ms[k]` (all `rows × cols`) into `out` in C order with the derivative index
/// last: `out[(i·cols + j)·depth + k] = ms[k][(i, j)]`.
fn put_last(ms: &[DMatrix<f64>], out: &mut [f64]) {
    let depth = ms.len();
    for (k, m) in ms.iter().enumerate() {
        let cols = m.ncols();
        for j in 0..cols {
            for i in 0..m.nrows() {
                out[(i * cols + j) * depth + k] = m[(i, j)];
            }
        }
    }
}

/// One row of both forms of `forward_dynamics_derivatives` (`f`, or `f = [base_wrench; tau]`
/// assembled by [`with_assembled_force`]): `(∂u̇/∂x, ∂u̇/∂u, ∂u̇/∂f)` written into `out`.
fn forward_dynamics_partials(
    m: &core::Model,
    w: &mut DerivativeData,
    (x, u, f): (&[f64], &[f64], &[f64]),
    ext: &[core::ExternalWrench],
    route: DerivativeMethod,
    [dx, du, df]: &mut [&mut [f64]; 3],
) -> core::Result<()> {
    let (a, b, c) = derivatives::forward_dynamics_derivatives_with(m, w, x, u, f, ext, route)?;
    put(a, dx);
    put(b, du);
    put(c, df);
    Ok(())
}

#[pymethods]
impl PyDerivatives {
    #[new]
    fn new(py: Python<'_>, model: PyRef<'_, PyModel>) -> PyResult<Self> {
        // Refused before any workspace is allocated (the cubic tensors are sized on first use).
        DerivativeData::admit(&model.model).or_raise(py)?;
        Ok(PyDerivatives { model: model.model.clone(), workspaces: Pool::new() })
    }

    /// `∂H/∂x_k`, shape (6+N, 6+N, 6+N), derivative index last.
    fn mass_matrix_partials<'py>(&self, py: Python<'py>, x: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let nu = self.model.nu();
        self.batch(py, "mass_matrix_partials", [self.x_arg(x)?], [&[nu, nu, nu]], |m, w, [x], [out]| {
            put_last(derivatives::mass_matrix_partials(m, w, x)?, out);
            Ok(())
        })
    }

    /// `Ḣ` along `u`, (6+N)².
    fn mass_matrix_derivative<'py>(&self, py: Python<'py>, x: &Bound<'py, PyAny>, u: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let nu = self.model.nu();
        self.batch(py, "mass_matrix_derivative", [self.x_arg(x)?, self.u_arg(u)?], [&[nu, nu]], |m, w, [x, u], [out]| write(derivatives::mass_matrix_derivative(m, w, x, u), out))
    }

    /// `∂H*/∂q_k`, shape (N, N, N), derivative index last.
    fn generalized_inertia_partials<'py>(&self, py: Python<'py>, x: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let n = self.model.n_dof();
        self.batch(py, "generalized_inertia_partials", [self.x_arg(x)?], [&[n, n, n]], |m, w, [x], [out]| {
            put_last(derivatives::generalized_inertia_partials(m, w, x)?, out);
            Ok(())
        })
    }

    /// `Ḣ*` along `u`, N×N.
    fn generalized_inertia_derivative<'py>(&self, py: Python<'py>, x: &Bound<'py, PyAny>, u: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let n = self.model.n_dof();
        self.batch(py, "generalized_inertia_derivative", [self.x_arg(x)?, self.u_arg(u)?], [&[n, n]], |m, w, [x, u], [out]| write(derivatives::generalized_inertia_derivative(m, w, x, u), out))
    }

    /// `∂J*/∂x_k` of a point, shape (6, N, 6+N), derivative index last.
    fn generalized_jacobian_partials<'py>(&self, py: Python<'py>, x: &Bound<'py, PyAny>, body: usize, offset: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let off = finite3(offset, "offset")?;
        let (n, nu) = (self.model.n_dof(), self.model.nu());
        self.batch(py, "generalized_jacobian_partials", [self.x_arg(x)?], [&[6, n, nu]], |m, w, [x], [out]| {
            put_last(derivatives::generalized_jacobian_partials(m, w, x, body, &off)?, out);
            Ok(())
        })
    }

    /// `J̇*` of a point along `u`, 6×N.
    fn generalized_jacobian_derivative<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
        body: usize,
        offset: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let off = finite3(offset, "offset")?;
        let n = self.model.n_dof();
        self.batch(py, "generalized_jacobian_derivative", [self.x_arg(x)?, self.u_arg(u)?], [&[6, n]], |m, w, [x, u], [out]| write(derivatives::generalized_jacobian_derivative(m, w, x, u, body, &off), out))
    }

    /// `(∂u̇/∂x, ∂u̇/∂u, ∂u̇/∂f)`, each (6+N)², `x` in tangent coordinates; analytic route, or
    /// dual numbers if `dual` (the test oracle). `wrenches` act on every state of a batch.
    #[pyo3(signature = (x, u, f, wrenches=None, dual=false))]
    fn forward_dynamics_derivatives<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
        f: &Bound<'py, PyAny>,
        wrenches: Option<WrenchList>,
        dual: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        let nu = self.model.nu();
        let ext = wrench_list(py, wrenches)?;
        let route = method(dual);
        self.batch(py, "forward_dynamics_derivatives", [self.x_arg(x)?, self.u_arg(u)?, Input::arg(f, "f", nu)?], [&[nu, nu]; 3], |m, w, [x, u, f], out| {
            forward_dynamics_partials(m, w, (x, u, f), &ext, route, out)
        })
    }

    /// [`PyDerivatives::forward_dynamics_derivatives`] under `f = [base_wrench; tau]` (either
    /// `None`: zero), assembled in the kernel so that this form costs one native call like the
    /// `f` form and gives bit-identical results; `tau` is converted and checked before
    /// `base_wrench`, each under its own name, then `x` and `u`.
    #[pyo3(signature = (x, u, tau=None, base_wrench=None, wrenches=None, dual=false))]
    #[allow(clippy::too_many_arguments)]
    fn forward_dynamics_derivatives_tau<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
        tau: Option<&Bound<'py, PyAny>>,
        base_wrench: Option<&Bound<'py, PyAny>>,
        wrenches: Option<WrenchList>,
        dual: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        let nu = self.model.nu();
        let tau = Input::optional(tau, "tau", nu - 6)?;
        let base_wrench = Input::optional(base_wrench, "base_wrench", 6)?;
        let ext = wrench_list(py, wrenches)?;
        let route = method(dual);
        self.batch(py, "forward_dynamics_derivatives", [tau, base_wrench, self.x_arg(x)?, self.u_arg(u)?], [&[nu, nu]; 3], |m, w, [tau, fb, x, u], out| {
            with_assembled_force(nu, tau, fb, |f| forward_dynamics_partials(m, w, (x, u, f), &ext, route, out))
        })
    }

    /// `(∂ID/∂x, ∂ID/∂u)` of inverse dynamics, each (6+N)², `x` in tangent coordinates.
    #[pyo3(signature = (x, u, du, wrenches=None, dual=false))]
    fn inverse_dynamics_partials<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
        du: &Bound<'py, PyAny>,
        wrenches: Option<WrenchList>,
        dual: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        let nu = self.model.nu();
        let ext = wrench_list(py, wrenches)?;
        let route = method(dual);
        self.batch(py, "inverse_dynamics_partials", [self.x_arg(x)?, self.u_arg(u)?, Input::arg(du, "du", nu)?], [&[nu, nu], &[nu, nu]], |m, w, [x, u, du], [dx_out, dv_out]| {
            let (dx, dv) = derivatives::inverse_dynamics_partials(m, w, x, u, du, &ext, route)?;
            put(dx, dx_out);
            put(dv, dv_out);
            Ok(())
        })
    }

    /// `(A, B)` of the linearized state equation; `B` for the joint torques only if
    /// `joints_only`, else for the whole generalized force.
    #[pyo3(signature = (x, u, f, joints_only, dual=false))]
    fn linearize<'py>(&self, py: Python<'py>, x: &Bound<'py, PyAny>, u: &Bound<'py, PyAny>, f: &Bound<'py, PyAny>, joints_only: bool, dual: bool) -> PyResult<Bound<'py, PyAny>> {
        let nu = self.model.nu();
        let route = method(dual);
        let inputs = [self.x_arg(x)?, self.u_arg(u)?, Input::arg(f, "f", nu)?];
        let (kind, b_cols) = if joints_only { (LinearizationInputs::Joints, self.model.n_dof()) } else { (LinearizationInputs::All, nu) };
        self.batch(py, "linearize", inputs, [&[2 * nu, 2 * nu], &[2 * nu, b_cols]], |m, w, [x, u, f], [a_out, b_out]| {
            let (a, b) = derivatives::linearize_with(m, w, x, u, f, kind, route)?;
            put(a, a_out);
            put(&b, b_out);
            Ok(())
        })
    }
}
