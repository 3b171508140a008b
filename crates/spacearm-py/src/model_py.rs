//! `spacearm._core.Model`: a core `Model` with a pool of `Data` workspaces, one thin method
//! per core function. Every per-state method takes one state or a batch of states (a 2-D `x`,
//! one state per row; the other vectors with the same number of rows or one row for all) and
//! runs through the one driver of [`crate::batch`]. Argument checking beyond numpy conversion
//! happens in the core.

use nalgebra::{Dim, Matrix, RawStorage, Vector3, Vector6};
use numpy::{PyArray1, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyString, PyTuple};
use spacearm_core as core;
use spacearm_core::algorithms::dynamics::ForwardDynamicsMethod;
use spacearm_core::algorithms::{aba, crba, dynamics, inertia, kinematics, momentum, passive, rnea};
use spacearm_core::{gjm, Data, ExternalWrench, JointType};

use crate::batch::{Batched, Input, Pool};
use crate::description_py::PyModelDescription;
use crate::convert::*;

/// A validated spacecraft-manipulator model with its workspaces (private; wrapped by
/// `spacearm.Robot`). Immutable: every method takes `&self` and a workspace of the pool, so
/// one model may be used from several threads at once.
#[pyclass(module = "spacearm._core", name = "Model", frozen)]
pub struct PyModel {
    pub model: core::Model,
    pub workspaces: Pool<Data>,
}
crate::batch::batched!(PyModel, Data);

impl PyModel {
    pub fn new(model: core::Model) -> Self {
        PyModel { model, workspaces: Pool::new() }
    }

    /// Run `f` with a workspace of this model (for the bindings that are not per-state methods).
    pub fn with_data<R>(&self, f: impl FnOnce(&core::Model, &mut Data) -> R) -> R {
        self.workspaces.with(|| Data::new(&self.model), |d| f(&self.model, d))
    }
}

/// Write a matrix into `out` row after row (numpy's C order), reading nalgebra's storage
/// through its strides: plain loads and stores, no bounds check per element.
///
/// Column-major storage with adjacent rows (every owned nalgebra matrix) is copied four rows
/// at a time: each step reads four neighbouring values of a column and writes them down a
/// column of `out`; the one-at-a-time walk copies the remaining rows and any other layout.
/// (The measurements behind both choices: benchmarks/README.md, "Profiler history".)
pub fn put<R: Dim, C: Dim, S: RawStorage<f64, R, C>>(m: &Matrix<f64, R, C, S>, out: &mut [f64]) {
    let (rows, cols) = m.shape();
    let (row_stride, col_stride) = m.strides();
    assert_eq!(out.len(), rows * cols, "output of the matrix's size");
    // Element (i, j) is at i·row_stride + j·col_stride from `as_ptr()` (nalgebra's
    // `RawStorage` contract); element (i, j) of `out` at i·cols + j.
    let (src0, dst0) = (m.as_ptr(), out.as_mut_ptr());
    let mut first_row = 0;
    if row_stride == 1 {
        while first_row + 4 <= rows {
            let (mut src, mut dst) = (src0.wrapping_add(first_row), dst0.wrapping_add(first_row * cols));
            for _ in 0..cols {
                // SAFETY: `src` is element (first_row, j) and rows first_row..first_row+4 exist
                // (loop condition), adjacent in storage (row_stride 1); `dst` is element
                // (first_row, j) of `out`, and rows first_row..first_row+4 of `out` exist.
                unsafe {
                    *dst = *src;
                    *dst.add(cols) = *src.add(1);
                    *dst.add(2 * cols) = *src.add(2);
                    *dst.add(3 * cols) = *src.add(3);
                }
                src = src.wrapping_add(col_stride);
                dst = dst.wrapping_add(1);
            }
            first_row += 4;
        }
    }
    let mut dst = dst0.wrapping_add(first_row * cols);
    for i in first_row..rows {
        let mut src = src0.wrapping_add(i * row_stride);
        for _ in 0..cols {
            // SAFETY: `src` points at element (i, j) (above); `dst` advances through the
            // remaining elements of `out` (length asserted) exactly once.
            unsafe {
                *dst = *src;
                dst = dst.add(1);
            }
            src = src.wrapping_add(col_stride);
        }
    }
}

/// A kernel's one result as the row of its output: a matrix or vector in C order ([`put`]), a
/// number as itself.
pub trait Output {
    fn write_into(&self, out: &mut [f64]);
}

impl<R: Dim, C: Dim, S: RawStorage<f64, R, C>> Output for Matrix<f64, R, C, S> {
    fn write_into(&self, out: &mut [f64]) {
        put(self, out);
    }
}

impl<T: Output + ?Sized> Output for &T {
    fn write_into(&self, out: &mut [f64]) {
        (**self).write_into(out);
    }
}

impl Output for f64 {
    fn write_into(&self, out: &mut [f64]) {
        out[0] = *self;
    }
}

/// The body of a one-output [`Batched::batch`] kernel: its result written into the output row.
pub fn write(result: spacearm_core::Result<impl Output>, out: &mut [f64]) -> spacearm_core::Result<()> {
    result?.write_into(out);
    Ok(())
}

/// External wrenches as `Robot._wrenches` passes them: `(body, offset, force, torque)`.
pub(crate) type WrenchList = Vec<(usize, Vec<f64>, Vec<f64>, Vec<f64>)>;

pub(crate) fn wrenches(py: Python<'_>, list: Option<WrenchList>) -> PyResult<Vec<ExternalWrench>> {
    let mut out = Vec::new();
    for (body, offset, force, torque) in list.unwrap_or_default() {
        for (what, v) in [("wrench point", &offset), ("wrench force", &force), ("wrench torque", &torque)] {
            if v.len() != 3 {
                return Err(to_py_err(py, core::SpacearmError::Dimension { what: what.into(), expected: "3".into(), got: v.len() }));
            }
        }
        out.push(ExternalWrench {
            body,
            offset: Vector3::from_column_slice(&offset),
            force: Vector3::from_column_slice(&force),
            torque: Vector3::from_column_slice(&torque),
        });
    }
    Ok(out)
}

pymethods_with_getters! {
#[pymethods]
impl PyModel {
    getters(self) {
        name: String = self.model.name().to_string();
        n_dof: usize = self.model.n_dof();
        n_bodies: usize = self.model.n_bodies();
        /// Whether the model was built accepting inertias that break the triangle inequality.
        allows_nonphysical_inertia: bool = self.model.triangle_inequality() == spacearm_core::model::TriangleInequality::Warn;
        /// One message per body whose inertia breaks the triangle inequality.
        inertia_warnings: Vec<String> = self.model.inertia_warnings().to_vec();
        total_mass: f64 = self.model.total_mass();
        body_names: Vec<String> = self.model.body_names();
        point_names: Vec<String> = self.model.points().iter().map(|p| p.name.clone()).collect();
        end_effector: Option<String> = self.model.end_effector().map(|i| self.model.points()[i].name.clone());
        /// Whether each degree of freedom has a motor (dof order; docs/flexibility.md).
        actuated_dofs: Vec<bool> = self.model.actuated_dofs();
        /// Body index moved by each degree of freedom.
        body_of_dof: Vec<usize> = (0..self.model.n_dof()).map(|d| self.model.body_of_dof(d)).collect();
    }

    #[getter]
    fn initial_q<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array1(py, self.model.initial_q())
    }
    fn body_index(&self, py: Python<'_>, name: &str) -> PyResult<usize> {
        self.model.body_index(name).or_raise(py)
    }
    fn point(&self, py: Python<'_>, name: &str) -> PyResult<(usize, [f64; 3])> {
        let i = self.model.point_index(name).or_raise(py)?;
        let p = &self.model.points()[i];
        Ok((p.body, [p.offset.x, p.offset.y, p.offset.z]))
    }

    /// The whole model, typed: base, links in tree order, points, end effector, initial `q`.
    fn describe(&self, py: Python<'_>) -> PyResult<PyModelDescription> {
        PyModelDescription::of(py, &self.model)
    }

    /// The model as the TOML text of a model file (floats in shortest round-trip form: read
    /// back bit-identical); what a controller's own model travels as in a run's description.
    fn to_toml(&self) -> String {
        core::io::toml::model_to_toml(&self.model)
    }

    /// The model as TOML text, the form it pickles in (the core's writer prints every float
    /// in its shortest round-trip form, so a model read back is bit-identical).
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let reader = py.import("spacearm._core")?.getattr("model_from_toml")?;
        let text = core::io::toml::model_to_toml(&self.model);
        let source = format!("<pickled model '{}'>", self.model.name());
        let args = (text, source, self.allows_nonphysical_inertia()).into_pyobject(py)?;
        Ok((reader, args))
    }

    /// Check a configuration (length, finite values, unit quaternion) without computing.
    fn check_configuration(&self, py: Python<'_>, x: &Bound<'_, PyAny>) -> PyResult<()> {
        let x = vec_arg(x, "x")?;
        kinematics::split_configuration(&self.model, x.as_slice()).or_raise(py)?;
        Ok(())
    }

    /// The small-oscillation modes of the joints' springs at `x` (core
    /// `analysis::passive_modes`): `(dofs, frequencies rad/s, damping ratios, shapes N × modes)`;
    /// `held`: the actuated joints are held still, else every joint moves.
    fn passive_modes<'py>(&self, py: Python<'py>, x: &Bound<'py, PyAny>, held: bool) -> PyResult<Bound<'py, PyTuple>> {
        use spacearm_core::analysis::passive_modes::{passive_modes, ActuatedJoints};
        let x = vec_arg(x, "x")?;
        let which = if held { ActuatedJoints::Held } else { ActuatedJoints::Free };
        let modes = self.with_data(|m, d| passive_modes(m, d, x.as_slice(), which)).or_raise(py)?;
        (modes.dofs, array1(py, &modes.frequencies), array1(py, &modes.damping_ratios), matrix(py, &modes.shapes)).into_pyobject(py)
    }

    /// Forward kinematics: (body_to_world (nb,3,3), com_in_world (nb,3),
    /// joint_position_in_world (nb,3), joint_axis_in_world (nb,3)).
    fn forward_kinematics<'py>(&self, py: Python<'py>, x: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let nb = self.model.n_bodies();
        self.batch(py, "forward_kinematics", [self.x_arg(x)?], [&[nb, 3, 3], &[nb, 3], &[nb, 3], &[nb, 3]], |m, d, [x], [r, c, p, a]| {
            kinematics::forward_kinematics(m, d, x)?;
            for b in 0..nb {
                put(&d.body_to_world[b], &mut r[9 * b..9 * b + 9]);
                c[3 * b..3 * b + 3].copy_from_slice(d.com_in_world[b].as_slice());
                p[3 * b..3 * b + 3].copy_from_slice(d.joint_position_in_world[b].as_slice());
                a[3 * b..3 * b + 3].copy_from_slice(d.joint_axis_in_world[b].as_slice());
            }
            Ok(())
        })
    }

    /// The tape of a function of the equations of motion (`spacearm_core::taped`): the core's
    /// recursions recorded on a recording scalar, for `spacearm.casadi` to replay on CasADi
    /// symbols. `body` (and `offset`, default zero) name the point of `generalized_jacobian`
    /// and `point_position`.
    #[pyo3(signature = (function, body = None, offset = None))]
    fn tape(&self, py: Python<'_>, function: &str, body: Option<usize>, offset: Option<&Bound<'_, PyAny>>) -> PyResult<PyTape> {
        use core::taped::{record, TapedFunction};
        let point = match (body, offset) {
            (Some(b), Some(o)) => Some((b, finite3(o, "offset")?)),
            (Some(b), None) => Some((b, Vector3::zeros())),
            (None, _) => None,
        };
        let m = &self.model;
        let f = TapedFunction::from_name(function, point).or_raise(py)?;
        let tape = py.detach(|| record(m, &f)).or_raise(py)?;
        let n = tape.len();
        let args: Vec<u32> = tape.args.iter().flat_map(|a| a.iter().copied()).collect();
        Ok(PyTape {
            ops: PyArray1::from_vec(py, tape.ops).unbind(),
            args: PyArray1::from_vec(py, args).reshape([n, 2])?.unbind(),
            constants: PyArray1::from_vec(py, tape.constants).unbind(),
            outputs: PyArray1::from_vec(py, tape.outputs).unbind(),
            n_inputs: tape.n_inputs,
            inputs: f.inputs(m).into_iter().map(|(name, k)| (name.to_string(), k)).collect(),
            outputs_shapes: f.outputs(m).into_iter().map(|(name, r, c)| (name.to_string(), r, c)).collect(),
        })
    }

    fn point_position<'py>(&self, py: Python<'py>, x: &Bound<'py, PyAny>, body: usize, offset: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let off = finite3(offset, "offset")?;
        self.batch(py, "point_position", [self.x_arg(x)?], [&[3]], |m, d, [x], [out]| {
            kinematics::forward_kinematics(m, d, x)?;
            kinematics::check_body(m, body)?;
            out.copy_from_slice(kinematics::point_position(d, body, &off).as_slice());
            Ok(())
        })
    }

    /// `(J_0X (6,6), J_mX (6,N))` of a point.
    fn point_jacobians<'py>(&self, py: Python<'py>, x: &Bound<'py, PyAny>, body: usize, offset: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let off = finite3(offset, "offset")?;
        let n = self.model.n_dof();
        self.batch(py, "point_jacobian", [self.x_arg(x)?], [&[6, 6], &[6, n]], |m, d, [x], [j0, jm]| {
            kinematics::forward_kinematics(m, d, x)?;
            let (a, b) = kinematics::point_jacobians(m, d, body, &off)?;
            put(&a, j0);
            put(&b, jm);
            Ok(())
        })
    }

    /// `(J_Ti (3,N), J_Ri (3,N))` of a body's CM.
    fn link_jacobians<'py>(&self, py: Python<'py>, x: &Bound<'py, PyAny>, body: usize) -> PyResult<Bound<'py, PyAny>> {
        let n = self.model.n_dof();
        self.batch(py, "link_jacobians", [self.x_arg(x)?], [&[3, n], &[3, n]], |m, d, [x], [jt, jr]| {
            kinematics::forward_kinematics(m, d, x)?;
            kinematics::check_body(m, body)?;
            let (a, b) = kinematics::link_jacobians(m, d, body);
            put(&a, jt);
            put(&b, jr);
            Ok(())
        })
    }

    /// The paper's inertia blocks (eqs. 27–36) as a tuple in the order of
    /// `spacearm.InertiaBlocks`: (M, r_0g, H_S, J_TS, H_Sq, H0, H0m, Hm, H).
    fn inertia_blocks<'py>(&self, py: Python<'py>, x: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let (n, nu) = (self.model.n_dof(), self.model.nu());
        let inputs = [self.x_arg(x)?];
        let shapes: [&[usize]; 9] = [&[], &[3], &[3, 3], &[3, n], &[3, n], &[6, 6], &[6, n], &[n, n], &[nu, nu]];
        self.batch(py, "inertia_blocks", inputs, shapes, |m, d, [x], [mass, r0g, hs, jts, hsq, h0, h0m, hm, h]| {
            let b = inertia::inertia_blocks(m, d, x)?;
            mass[0] = b.total_mass;
            r0g.copy_from_slice(b.base_to_com.as_slice());
            put(&b.h_s, hs);
            put(&b.j_ts, jts);
            put(&b.h_sq, hsq);
            put(&b.h0, h0);
            put(&b.h0m, h0m);
            put(&b.hm, hm);
            put(&b.mass_matrix(), h);
            Ok(())
        })
    }

    /// The mass matrix `H` by the paper's Jacobian sums (eqs. 27–36) alone.
    fn mass_matrix_paper<'py>(&self, py: Python<'py>, x: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let nu = self.model.nu();
        self.batch(py, "mass_matrix", [self.x_arg(x)?], [&[nu, nu]], |m, d, [x], [out]| write(inertia::inertia_blocks(m, d, x).map(|b| b.mass_matrix()), out))
    }

    fn mass_matrix_crba<'py>(&self, py: Python<'py>, x: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let nu = self.model.nu();
        self.batch(py, "mass_matrix", [self.x_arg(x)?], [&[nu, nu]], |m, d, [x], [out]| write(crba::crba(m, d, x), out))
    }

    fn base_inertia_inverse<'py>(&self, py: Python<'py>, x: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        self.batch(py, "base_inertia_inverse", [self.x_arg(x)?], [&[6, 6]], |m, d, [x], [out]| {
            let h0 = crba::crba(m, d, x)?.fixed_view::<6, 6>(0, 0).into_owned();
            write(inertia::base_inertia_inverse(&h0), out)
        })
    }

    fn bias_forces<'py>(&self, py: Python<'py>, x: &Bound<'py, PyAny>, u: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let nu = self.model.nu();
        self.batch(py, "bias_forces", [self.x_arg(x)?, self.u_arg(u)?], [&[nu]], |m, d, [x, u], [out]| write(rnea::bias_forces(m, d, x, u), out))
    }

    #[pyo3(signature = (x, u, du, wrenches=None))]
    fn inverse_dynamics<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
        du: &Bound<'py, PyAny>,
        wrenches: Option<WrenchList>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let nu = self.model.nu();
        let inputs = [self.x_arg(x)?, self.u_arg(u)?, Input::arg(du, "du", nu)?];
        let ext = self::wrenches(py, wrenches)?;
        self.batch(py, "inverse_dynamics", inputs, [&[nu]], |m, d, [x, u, du], [out]| write(rnea::rnea(m, d, x, u, du, &ext), out))
    }

    /// Forward dynamics under the generalized force `f`, by `method` ("aba", "mass_matrix" or
    /// "reduced"; the last takes no external wrenches). `f` is converted before `x` and `u`,
    /// in the order `Robot.forward_dynamics` always used.
    #[pyo3(signature = (x, u, f, wrenches, method))]
    fn forward_dynamics<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
        f: &Bound<'py, PyAny>,
        wrenches: Option<WrenchList>,
        method: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let nu = self.model.nu();
        let f = Input::arg(f, "f", nu)?;
        self.forward_dynamics_of(py, x, u, f, None, wrenches, method)
    }

    /// Forward dynamics under `f = [base_wrench; tau]` (either `None`: zero), assembled in the
    /// kernel so that this form costs one native call like the `f` form; `tau` is converted
    /// before `base_wrench`, and each is checked under its own name.
    #[pyo3(signature = (x, u, tau, base_wrench, wrenches, method))]
    #[allow(clippy::too_many_arguments)]
    fn forward_dynamics_tau<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
        tau: Option<&Bound<'py, PyAny>>,
        base_wrench: Option<&Bound<'py, PyAny>>,
        wrenches: Option<WrenchList>,
        method: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let n = self.model.n_dof();
        let tau = Input::optional(tau, "tau", n)?;
        let base_wrench = Input::optional(base_wrench, "base_wrench", 6)?;
        self.forward_dynamics_of(py, x, u, tau, Some(base_wrench), wrenches, method)
    }

    fn generalized_inertia<'py>(&self, py: Python<'py>, x: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let n = self.model.n_dof();
        self.batch(py, "generalized_inertia", [self.x_arg(x)?], [&[n, n]], |m, d, [x], [out]| write(gjm::compute_generalized_inertia(m, d, x), out))
    }

    fn generalized_bias<'py>(&self, py: Python<'py>, x: &Bound<'py, PyAny>, u: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let n = self.model.n_dof();
        self.batch(py, "generalized_bias", [self.x_arg(x)?, self.u_arg(u)?], [&[n]], |m, d, [x, u], [out]| write(gjm::compute_generalized_bias(m, d, x, u), out))
    }

    fn generalized_jacobian<'py>(&self, py: Python<'py>, x: &Bound<'py, PyAny>, body: usize, offset: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let off = finite3(offset, "offset")?;
        let n = self.model.n_dof();
        self.batch(py, "generalized_jacobian", [self.x_arg(x)?], [&[6, n]], |m, d, [x], [out]| write(gjm::compute_generalized_jacobian(m, d, x, body, &off), out))
    }

    /// The twist `[v_X; ω] = J* q̇ + J_0X H0⁻¹ M0` of a point when the joints move at `qd` and
    /// the system has linear momentum `P` and angular momentum `L` about the origin of 𝒥.
    #[allow(clippy::too_many_arguments)]
    fn point_twist<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        qd: &Bound<'py, PyAny>,
        body: usize,
        offset: &Bound<'py, PyAny>,
        linear: &Bound<'py, PyAny>,
        angular_origin: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let off = finite3(offset, "offset")?;
        let n = self.model.n_dof();
        self.batch(py, "point_twist", [self.x_arg(x)?, Input::arg(qd, "qd", n)?, Input::arg(linear, "P", 3)?, Input::arg(angular_origin, "L", 3)?], [&[6]], |m, d, [x, qd, p, l], [out]| {
            kinematics::check_joint_vector(m, "qd", qd)?;
            let (p, l) = (momentum3(m, "P", p)?, momentum3(m, "L", l)?);
            let from_joints = gjm::compute_generalized_jacobian(m, d, x, body, &off)? * nalgebra::DVectorView::from_slice(qd, n);
            let from_momentum = gjm::momentum_twist(m, d, x, body, &off, &p, &l)?;
            out.copy_from_slice((from_joints + from_momentum).as_slice());
            Ok(())
        })
    }

    fn momentum_twist<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        body: usize,
        offset: &Bound<'py, PyAny>,
        linear: &Bound<'py, PyAny>,
        angular_origin: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let off = finite3(offset, "offset")?;
        self.batch(py, "momentum_twist", [self.x_arg(x)?, Input::arg(linear, "P", 3)?, Input::arg(angular_origin, "L", 3)?], [&[6]], |m, d, [x, p, l], [out]| {
            let (p, l) = (momentum3(m, "P", p)?, momentum3(m, "L", l)?);
            write(gjm::momentum_twist(m, d, x, body, &off, &p, &l), out)
        })
    }

    fn base_velocity_from_momentum<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        qd: &Bound<'py, PyAny>,
        linear: &Bound<'py, PyAny>,
        angular_origin: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let n = self.model.n_dof();
        self.batch(py, "base_velocity_from_momentum", [self.x_arg(x)?, Input::arg(qd, "qd", n)?, Input::arg(linear, "P", 3)?, Input::arg(angular_origin, "L", 3)?], [&[6]], |m, d, [x, qd, p, l], [out]| {
            let (p, l) = (momentum3(m, "P", p)?, momentum3(m, "L", l)?);
            write(gjm::base_velocity_from_momentum(m, d, x, qd, &p, &l), out)
        })
    }

    /// (P, L_origin, L_base, L_com)
    fn momentum<'py>(&self, py: Python<'py>, x: &Bound<'py, PyAny>, u: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        self.batch(py, "momentum", [self.x_arg(x)?, self.u_arg(u)?], [&[3], &[3], &[3], &[3]], |m, d, [x, u], [p, lo, lb, lc]| {
            let h = momentum::momentum(m, d, x, u)?;
            p.copy_from_slice(h.linear.as_slice());
            lo.copy_from_slice(h.angular_about_origin.as_slice());
            lb.copy_from_slice(h.angular_about_base.as_slice());
            lc.copy_from_slice(h.angular_about_com.as_slice());
            Ok(())
        })
    }

    fn kinetic_energy<'py>(&self, py: Python<'py>, x: &Bound<'py, PyAny>, u: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        self.batch(py, "kinetic_energy", [self.x_arg(x)?, self.u_arg(u)?], [&[]], |m, d, [x, u], [out]| write(momentum::kinetic_energy(m, d, x, u), out))
    }

    /// The drift scales of the momenta and the energy at `(x, u)`: `[Σ|pᵢ|, Σ(|rᵢ×pᵢ| + |Iᵢωᵢ|)
    /// about the origin, the same about the system CM, kinetic plus spring energy]`
    /// (`algorithms::momentum::momentum_scales`), (4,) for one state, (B, 4) for a batch.
    fn momentum_scales<'py>(&self, py: Python<'py>, x: &Bound<'py, PyAny>, u: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        self.batch(py, "momentum_scales", [self.x_arg(x)?, self.u_arg(u)?], [&[4]], |m, d, [x, u], [out]| {
            let s = momentum::momentum_scales(m, d, x, u)?;
            out.copy_from_slice(&[s.linear, s.angular_about_origin, s.angular_about_com, s.energy]);
            Ok(())
        })
    }

    fn passive_forces<'py>(&self, py: Python<'py>, x: &Bound<'py, PyAny>, u: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let nu = self.model.nu();
        self.batch(py, "passive_forces", [self.x_arg(x)?, self.u_arg(u)?], [&[nu]], |m, _, [x, u], [out]| write(passive::passive_forces(m, x, u), out))
    }

    fn spring_energy<'py>(&self, py: Python<'py>, x: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        self.batch(py, "spring_energy", [self.x_arg(x)?], [&[]], |m, _, [x], [out]| write(passive::spring_energy(m, x), out))
    }

    fn center_of_mass<'py>(&self, py: Python<'py>, x: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        self.batch(py, "center_of_mass", [self.x_arg(x)?], [&[3]], |m, d, [x], [out]| write(momentum::center_of_mass(m, d, x), out))
    }

    fn joint_types(&self) -> Vec<&'static str> {
        self.model.links().iter().map(|l| l.joint.kind.as_str()).collect()
    }

    fn __repr__(&self) -> String {
        format!(
            "<spacearm._core.Model '{}': {} bodies, N = {} dof, {} fixed joints>",
            self.model.name(),
            self.model.n_bodies(),
            self.model.n_dof(),
            self.model.links().iter().filter(|l| l.joint.kind == JointType::Fixed).count()
        )
    }
}
}

/// `NonFinite` naming `what` and its first non-finite entry, if any (one row's check).
fn finite_row(what: &str, v: &[f64]) -> core::Result<()> {
    match v.iter().position(|x| !x.is_finite()) {
        Some(index) => Err(core::SpacearmError::NonFinite { what: what.into(), index, value: v[index] }),
        None => Ok(()),
    }
}

/// A momentum argument of one row as a 3-vector (length and finiteness checked under `what`).
fn momentum3(_model: &core::Model, what: &str, v: &[f64]) -> core::Result<Vector3<f64>> {
    if v.len() != 3 {
        return Err(core::SpacearmError::Dimension { what: what.into(), expected: "3".into(), got: v.len() });
    }
    finite_row(what, v)?;
    Ok(Vector3::from_column_slice(v))
}

/// The forward-dynamics method a Python string names (the core's table,
/// [`ForwardDynamicsMethod::NAMES`]). Compared as Python strings: the names Python code passes
/// are interned, so the common case is one pointer comparison, where extracting a `&str` (abi3
/// for Python 3.9 has no borrowed UTF-8 view) would build a bytes object on every call
/// (benchmarks/README.md, "Profiler history").
fn fd_method(py: Python<'_>, name: &Bound<'_, PyAny>) -> PyResult<ForwardDynamicsMethod> {
    static NAMES: PyOnceLock<Vec<Py<PyString>>> = PyOnceLock::new();
    let names = NAMES.get_or_init(py, || ForwardDynamicsMethod::NAMES.iter().map(|n| PyString::intern(py, n).unbind()).collect());
    for (text, method) in names.iter().zip(ForwardDynamicsMethod::ALL) {
        if name.is(text) {
            return Ok(method);
        }
    }
    fd_method_by_value(py, name)
}

/// [`fd_method`] for a name that is not one of the interned strings (built at run time, or
/// wrong): compared by value, out of line.
#[inline(never)]
fn fd_method_by_value(py: Python<'_>, name: &Bound<'_, PyAny>) -> PyResult<ForwardDynamicsMethod> {
    for (text, method) in ForwardDynamicsMethod::NAMES.iter().zip(ForwardDynamicsMethod::ALL) {
        if name.eq(text)? {
            return Ok(method);
        }
    }
    let got = match name.cast::<PyString>() {
        Ok(s) => format!("'{}'", s.to_cow()?),
        Err(_) => format!("{} of type {}", name.repr()?, name.get_type().name()?),
    };
    let names = ForwardDynamicsMethod::NAMES.map(|n| format!("'{n}'"));
    let (last, rest) = names.split_last().expect("three names");
    Err(to_py_err(py, core::SpacearmError::InvalidArgument(format!("method must be {} or {last}, got {got}", rest.join(", ")))))
}

/// Room for the assembled `f` on the stack: models up to `FORCE_ON_STACK - 6` joints need no
/// allocation per row.
const FORCE_ON_STACK: usize = 64;

impl PyModel {
    #[allow(clippy::too_many_arguments)]
    fn forward_dynamics_of<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
        force: Input<'py>,
        base_wrench: Option<Input<'py>>,
        wrenches: Option<WrenchList>,
        method: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let nu = self.model.nu();
        let method = fd_method(py, method)?;
        let from_parts = base_wrench.is_some();
        let base_wrench = base_wrench.unwrap_or_else(|| Input::constant("base_wrench", Vec::new()));
        let inputs = [force, base_wrench, self.x_arg(x)?, self.u_arg(u)?];
        let ext = self::wrenches(py, wrenches)?;
        if matches!(method, ForwardDynamicsMethod::Reduced) && !ext.is_empty() {
            return Err(to_py_err(py, core::SpacearmError::InvalidArgument("method='reduced' takes no external wrenches; use 'aba' or 'mass_matrix'".into())));
        }
        let solve = |m: &core::Model, d: &mut Data, x: &[f64], u: &[f64], f: &[f64], out: &mut [f64]| -> core::Result<()> {
            let du = match method {
                ForwardDynamicsMethod::Aba => aba::aba(m, d, x, u, f, &ext)?,
                ForwardDynamicsMethod::MassMatrix => dynamics::compute_forward_dynamics_via_mass_matrix(m, d, x, u, f, &ext)?,
                ForwardDynamicsMethod::Reduced => {
                    kinematics::check_velocity(m, "f", f)?;
                    let fb = Vector6::from_column_slice(&f[..6]);
                    gjm::compute_reduced_forward_dynamics(m, d, x, u, &f[6..], &fb)?
                }
            };
            out.copy_from_slice(du.as_slice());
            Ok(())
        };
        self.batch(py, "forward_dynamics", inputs, [&[nu]], |m, d, [force, fb, x, u], [out]| {
            if !from_parts {
                return solve(m, d, x, u, force, out);
            }
            with_assembled_force(nu, force, fb, |f| solve(m, d, x, u, f, out))
        })
    }
}

/// Run `kernel` on `f = [base_wrench; tau]` of a model with `nu = 6 + N` generalized
/// velocities, after checking `tau` (length N, finite) and then `base_wrench` (length 6,
/// finite), each under its own name. The assembled `f` lives on the stack for models up to
/// `FORCE_ON_STACK - 6` joints, so the tau/base_wrench form of a one-state call allocates
/// nothing more than the `f` form. Shared by every binding that takes the two parts.
pub(crate) fn with_assembled_force<R>(nu: usize, tau: &[f64], base_wrench: &[f64], kernel: impl FnOnce(&[f64]) -> core::Result<R>) -> core::Result<R> {
    if tau.len() != nu - 6 {
        return Err(core::SpacearmError::Dimension { what: "tau".into(), expected: (nu - 6).to_string(), got: tau.len() });
    }
    finite_row("tau", tau)?;
    if base_wrench.len() != 6 {
        return Err(core::SpacearmError::Dimension { what: "base_wrench".into(), expected: "6".into(), got: base_wrench.len() });
    }
    finite_row("base_wrench", base_wrench)?;
    let mut on_stack = [0.0; FORCE_ON_STACK];
    let mut on_heap = Vec::new();
    let buf: &mut [f64] = if nu <= FORCE_ON_STACK {
        &mut on_stack[..nu]
    } else {
        on_heap.resize(nu, 0.0);
        &mut on_heap
    };
    buf[..6].copy_from_slice(base_wrench);
    buf[6..].copy_from_slice(tau);
    kernel(buf)
}

/// A recorded function of the equations of motion (`spacearm_core::math::tape::Tape` with the
/// names of its inputs and outputs): node `i` is the operation `ops[i]` on the nodes
/// `args[i]` (operands precede their node), an input (`args[i, 0]` its number) or a constant
/// (`constants[args[i, 0]]`). Operation codes: 0 input, 1 constant, 2 add, 3 sub, 4 mul, 5 div,
/// 6 atan2, 16 neg, 17 sqrt, 18 sin, 19 cos, 20 tan, 21 asin, 22 acos, 23 atan, 24 exp, 25 ln,
/// 26 abs.
#[pyclass(module = "spacearm._core", name = "Tape", frozen, get_all)]
pub struct PyTape {
    /// (n,) uint8: the operation of each node.
    ops: Py<PyArray1<u8>>,
    /// (n, 2) uint32: the operands of each node (the second is 0 for a unary operation).
    args: Py<numpy::PyArray2<u32>>,
    /// float64: the constants of the `Const` nodes.
    constants: Py<PyArray1<f64>>,
    /// uint32: the node of each output value (outputs concatenated, matrices column-major).
    outputs: Py<PyArray1<u32>>,
    /// Number of inputs (the inputs concatenated).
    n_inputs: usize,
    /// `[(name, length)]` of the inputs, in order.
    inputs: Vec<(String, usize)>,
    /// `[(name, rows, columns)]` of the outputs, in order.
    outputs_shapes: Vec<(String, usize, usize)>,
}

#[pymethods]
impl PyTape {
    fn __repr__(&self, py: Python<'_>) -> String {
        format!("<Tape: {} nodes, {} inputs, {} outputs>", PyUntypedArrayMethods::len(self.ops.bind(py)), self.n_inputs, PyUntypedArrayMethods::len(self.outputs.bind(py)))
    }
}
