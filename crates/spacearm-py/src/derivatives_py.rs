//! `spacearm._core.Derivatives`: the exact derivatives of `spacearm_core::derivatives` for one
//! model, with their preallocated workspace (private; wrapped by the derivative methods of
//! `spacearm.Robot`).
//!
//! Tensors of partial derivatives come out as numpy arrays with the derivative index LAST:
//! `out[i, j, k] = ∂X[i, j]/∂x_k`.

use nalgebra::DMatrix;
use numpy::{PyArray2, PyArray3, PyArrayMethods};
use pyo3::prelude::*;
use spacearm_core as core;
use spacearm_core::derivatives::{self, DerivativeData, DerivativeMethod, LinearizationInputs};

use crate::convert::*;
use crate::model_py::{wrenches as wrench_list, PyModel, WrenchList};

/// The route of the partials of inverse dynamics: analytic, or dual numbers (the test oracle).
fn method(dual: bool) -> DerivativeMethod {
    if dual {
        DerivativeMethod::DualNumbers
    } else {
        DerivativeMethod::Analytic
    }
}

/// The derivative functions of one model (a copy of the model and a workspace).
#[pyclass(module = "spacearm._core", name = "Derivatives")]
pub struct PyDerivatives {
    model: core::Model,
    work: DerivativeData,
}

/// Matrices `ms[k]` (all `rows × cols`, column-major) as one C-ordered array
/// `out[i, j, k] = ms[k][(i, j)]`.
fn stack_last<'py>(py: Python<'py>, ms: &[DMatrix<f64>], rows: usize, cols: usize) -> Bound<'py, PyArray3<f64>> {
    let depth = ms.len();
    // SAFETY: a fresh array owned by nobody else; every element is written below.
    let out = unsafe { PyArray3::<f64>::new(py, [rows, cols, depth], false) };
    let dst = unsafe { out.as_slice_mut().expect("a new array is contiguous") };
    for (k, m) in ms.iter().enumerate() {
        debug_assert_eq!(m.shape(), (rows, cols));
        for j in 0..cols {
            for i in 0..rows {
                dst[(i * cols + j) * depth + k] = m[(i, j)];
            }
        }
    }
    out
}

#[pymethods]
impl PyDerivatives {
    #[new]
    fn new(model: PyRef<'_, PyModel>) -> Self {
        let model = model.model.clone();
        let work = DerivativeData::new(&model);
        PyDerivatives { model, work }
    }

    /// `∂H/∂x_k`, shape (6+N, 6+N, 6+N), derivative index last.
    fn mass_matrix_partials<'py>(&mut self, py: Python<'py>, x: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray3<f64>>> {
        let x = vec_arg(x, "x")?;
        let nu = self.model.nu();
        let p = derivatives::mass_matrix_partials(&self.model, &mut self.work, x.as_slice()).or_raise(py)?;
        Ok(stack_last(py, p, nu, nu))
    }

    /// `Ḣ` along `u`, (6+N)².
    fn mass_matrix_derivative<'py>(&mut self, py: Python<'py>, x: &Bound<'py, PyAny>, u: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (x, u) = (vec_arg(x, "x")?, vec_arg(u, "u")?);
        let h = derivatives::mass_matrix_derivative(&self.model, &mut self.work, x.as_slice(), u.as_slice()).or_raise(py)?;
        Ok(dmat(py, h))
    }

    /// `∂H*/∂q_k`, shape (N, N, N), derivative index last.
    fn generalized_inertia_partials<'py>(&mut self, py: Python<'py>, x: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray3<f64>>> {
        let x = vec_arg(x, "x")?;
        let n = self.model.n_dof();
        let p = derivatives::generalized_inertia_partials(&self.model, &mut self.work, x.as_slice()).or_raise(py)?;
        Ok(stack_last(py, p, n, n))
    }

    /// `Ḣ*` along `u`, N×N.
    fn generalized_inertia_derivative<'py>(&mut self, py: Python<'py>, x: &Bound<'py, PyAny>, u: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (x, u) = (vec_arg(x, "x")?, vec_arg(u, "u")?);
        let h = derivatives::generalized_inertia_derivative(&self.model, &mut self.work, x.as_slice(), u.as_slice()).or_raise(py)?;
        Ok(dmat(py, h))
    }

    /// `∂J*/∂x_k` of a point, shape (6, N, 6+N), derivative index last.
    fn generalized_jacobian_partials<'py>(&mut self, py: Python<'py>, x: &Bound<'py, PyAny>, body: usize, offset: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray3<f64>>> {
        let off = vec3(offset, "offset")?;
        let x = vec_arg(x, "x")?;
        let n = self.model.n_dof();
        let p = derivatives::generalized_jacobian_partials(&self.model, &mut self.work, x.as_slice(), body, &off).or_raise(py)?;
        Ok(stack_last(py, p, 6, n))
    }

    /// `J̇*` of a point along `u`, 6×N.
    fn generalized_jacobian_derivative<'py>(
        &mut self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
        body: usize,
        offset: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let off = vec3(offset, "offset")?;
        let (x, u) = (vec_arg(x, "x")?, vec_arg(u, "u")?);
        let j = derivatives::generalized_jacobian_derivative(&self.model, &mut self.work, x.as_slice(), u.as_slice(), body, &off).or_raise(py)?;
        Ok(dmat(py, j))
    }

    /// `(∂u̇/∂x, ∂u̇/∂u, ∂u̇/∂f)`, each (6+N)², `x` in tangent coordinates; analytic route, or
    /// dual numbers if `dual` (the test oracle).
    #[allow(clippy::type_complexity)]
    #[pyo3(signature = (x, u, f, wrenches=None, dual=false))]
    fn forward_dynamics_derivatives<'py>(
        &mut self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
        f: &Bound<'py, PyAny>,
        wrenches: Option<WrenchList>,
        dual: bool,
    ) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>)> {
        let (x, u, f) = (vec_arg(x, "x")?, vec_arg(u, "u")?, vec_arg(f, "f")?);
        let ext = wrench_list(py, wrenches)?;
        let (dx, du, df) = derivatives::forward_dynamics_derivatives_with(&self.model, &mut self.work, x.as_slice(), u.as_slice(), f.as_slice(), &ext, method(dual))
            .or_raise(py)?;
        Ok((dmat(py, dx), dmat(py, du), dmat(py, df)))
    }

    /// `(∂ID/∂x, ∂ID/∂u)` of inverse dynamics, each (6+N)², `x` in tangent coordinates.
    #[pyo3(signature = (x, u, du, wrenches=None, dual=false))]
    fn inverse_dynamics_partials<'py>(
        &mut self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
        du: &Bound<'py, PyAny>,
        wrenches: Option<WrenchList>,
        dual: bool,
    ) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>)> {
        let (x, u, du) = (vec_arg(x, "x")?, vec_arg(u, "u")?, vec_arg(du, "du")?);
        let ext = wrench_list(py, wrenches)?;
        let (dx, dv) = derivatives::inverse_dynamics_partials(&self.model, &mut self.work, x.as_slice(), u.as_slice(), du.as_slice(), &ext, method(dual)).or_raise(py)?;
        Ok((dmat(py, dx), dmat(py, dv)))
    }

    /// `(A, B)` of the linearized state equation; `B` for the joint torques only if
    /// `joints_only`, else for the whole generalized force.
    #[allow(clippy::type_complexity)]
    #[pyo3(signature = (x, u, f, joints_only, dual=false))]
    fn linearize<'py>(
        &mut self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
        f: &Bound<'py, PyAny>,
        joints_only: bool,
        dual: bool,
    ) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>)> {
        let (x, u, f) = (vec_arg(x, "x")?, vec_arg(u, "u")?, vec_arg(f, "f")?);
        let inputs = if joints_only { LinearizationInputs::Joints } else { LinearizationInputs::All };
        let (a, b) = derivatives::linearize_with(&self.model, &mut self.work, x.as_slice(), u.as_slice(), f.as_slice(), inputs, method(dual)).or_raise(py)?;
        let b = b.into_owned();
        Ok((dmat(py, a), dmat(py, &b)))
    }
}
