//! `spacearm._core.Model`: a core `Model` with its `Data` workspace, one thin method per core
//! function. Argument checking beyond numpy conversion happens in the core.

use nalgebra::{Vector3, Vector6};
use numpy::{PyArray1, PyArray2, PyArray3};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use spacearm_core as core;
use spacearm_core::{Data, ExternalWrench, JointType};

use crate::convert::*;

/// A validated spacecraft-manipulator model with its workspace (private; wrapped by
/// `spacearm.Robot`).
#[pyclass(module = "spacearm._core", name = "Model")]
pub struct PyModel {
    pub model: core::Model,
    pub data: Data,
}

impl PyModel {
    pub fn new(model: core::Model) -> Self {
        let data = Data::new(&model);
        PyModel { model, data }
    }
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

/// Room for the assembled `f` on the stack: models up to `FORCE_ON_STACK - 6` joints need no
/// allocation per call.
const FORCE_ON_STACK: usize = 64;

/// Run `compute` on the generalized force `f = [base_wrench; tau]` of the `tau=`/`base_wrench=`
/// form of forward dynamics, assembled here so that this form costs one native call like the `f`
/// form (either part may be `None`: zero). `tau` is converted before `base_wrench`, and each is
/// checked for length and finiteness under its own name (an error names `tau`, not `f`).
fn with_force_from_parts<R>(
    py: Python<'_>,
    model: &core::Model,
    tau: Option<&Bound<'_, PyAny>>,
    base_wrench: Option<&Bound<'_, PyAny>>,
    compute: impl FnOnce(&[f64]) -> PyResult<R>,
) -> PyResult<R> {
    let n = model.n_dof();
    let mut on_stack = [0.0; FORCE_ON_STACK];
    let mut on_heap = Vec::new();
    let f: &mut [f64] = if 6 + n <= FORCE_ON_STACK {
        &mut on_stack[..6 + n]
    } else {
        on_heap.resize(6 + n, 0.0);
        &mut on_heap
    };
    // Each slice is copied out before the next conversion runs Python code (see `VecArg`).
    if let Some(tau) = tau {
        let tau = vec_arg_n(tau, "tau", n)?;
        check_finite(py, "tau", tau.as_slice())?;
        f[6..].copy_from_slice(tau.as_slice());
    }
    if let Some(fb) = base_wrench {
        let fb = vec_arg_n(fb, "base_wrench", 6)?;
        check_finite(py, "base_wrench", fb.as_slice())?;
        f[..6].copy_from_slice(fb.as_slice());
    }
    compute(f)
}

#[pymethods]
impl PyModel {
    #[getter]
    fn name(&self) -> String {
        self.model.name().to_string()
    }
    #[getter]
    fn n_dof(&self) -> usize {
        self.model.n_dof()
    }
    #[getter]
    fn n_bodies(&self) -> usize {
        self.model.n_bodies()
    }
    /// Whether the model was built accepting inertias that break the triangle inequality.
    #[getter]
    fn allows_nonphysical_inertia(&self) -> bool {
        self.model.triangle_inequality() == spacearm_core::model::TriangleInequality::Warn
    }
    /// One message per body whose inertia breaks the triangle inequality.
    #[getter]
    fn inertia_warnings(&self) -> Vec<String> {
        self.model.inertia_warnings().to_vec()
    }
    #[getter]
    fn total_mass(&self) -> f64 {
        self.model.total_mass()
    }
    #[getter]
    fn body_names(&self) -> Vec<String> {
        self.model.body_names()
    }
    #[getter]
    fn point_names(&self) -> Vec<String> {
        self.model.points().iter().map(|p| p.name.clone()).collect()
    }
    #[getter]
    fn end_effector(&self) -> Option<String> {
        self.model.end_effector().map(|i| self.model.points()[i].name.clone())
    }
    #[getter]
    fn initial_q<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array1(py, self.model.initial_q())
    }
    /// Body index moved by each degree of freedom.
    #[getter]
    fn body_of_dof(&self) -> Vec<usize> {
        (0..self.model.n_dof()).map(|d| self.model.body_of_dof(d)).collect()
    }
    fn body_index(&self, py: Python<'_>, name: &str) -> PyResult<usize> {
        self.model.body_index(name).or_raise(py)
    }
    fn point(&self, py: Python<'_>, name: &str) -> PyResult<(usize, [f64; 3])> {
        let i = self.model.point_index(name).or_raise(py)?;
        let p = &self.model.points()[i];
        Ok((p.body, [p.offset.x, p.offset.y, p.offset.z]))
    }

    /// The whole model as plain Python data (base, links in tree order, points).
    fn describe<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let m = &self.model;
        let out = PyDict::new(py);
        out.set_item("name", m.name())?;
        let base = PyDict::new(py);
        base.set_item("name", m.base_name())?;
        base.set_item("mass", m.base().mass)?;
        base.set_item("inertia", rows3(&m.base().inertia))?;
        out.set_item("base", base)?;
        let links = PyList::empty(py);
        for l in m.links() {
            let d = PyDict::new(py);
            d.set_item("name", &l.name)?;
            d.set_item("parent", m.body_name(l.parent))?;
            d.set_item("parent_index", l.parent)?;
            d.set_item("joint", &l.joint.name)?;
            d.set_item("type", l.joint.kind.as_str())?;
            let o = l.joint.origin_in_parent;
            d.set_item("origin", [o.x, o.y, o.z])?;
            let q = l.joint.rotation_in_parent;
            d.set_item("rotation", [q.i, q.j, q.k, q.w])?;
            let a = l.joint.axis;
            d.set_item("axis", [a.x, a.y, a.z])?;
            let c = l.com_from_joint;
            d.set_item("com", [c.x, c.y, c.z])?;
            d.set_item("mass", l.mass.mass)?;
            d.set_item("inertia", rows3(&l.mass.inertia))?;
            let lim = l.joint.limits;
            d.set_item("limits", [lim.lower, lim.upper, lim.velocity, lim.effort])?;
            d.set_item("dof", m.dof_of_body(m.body_index(&l.name).unwrap_or(0)))?;
            links.append(d)?;
        }
        out.set_item("links", links)?;
        let points = PyList::empty(py);
        for p in m.points() {
            points.append((p.name.clone(), m.body_name(p.body).to_string(), [p.offset.x, p.offset.y, p.offset.z]))?;
        }
        out.set_item("points", points)?;
        out.set_item("end_effector", self.end_effector())?;
        out.set_item("initial_q", m.initial_q().to_vec())?;
        Ok(out)
    }

    /// Forward kinematics: (body_to_world (nb,3,3), com_in_world (nb,3),
    /// joint_position_in_world (nb,3), joint_axis_in_world (nb,3)).
    #[allow(clippy::type_complexity)]
    fn forward_kinematics<'py>(
        &mut self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
    ) -> PyResult<(Bound<'py, PyArray3<f64>>, Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>)> {
        let x = vec_arg(x, "x")?;
        core::algorithms::kinematics::forward_kinematics(&self.model, &mut self.data, x.as_slice()).or_raise(py)?;
        let d = &self.data;
        Ok((
            stack_mat3(py, &d.body_to_world),
            stack_vec3(py, &d.com_in_world),
            stack_vec3(py, &d.joint_position_in_world),
            stack_vec3(py, &d.joint_axis_in_world),
        ))
    }

    fn point_position<'py>(&mut self, py: Python<'py>, x: &Bound<'py, PyAny>, body: usize, offset: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let off = vec3(offset, "offset")?;
        let x = vec_arg(x, "x")?;
        core::algorithms::kinematics::forward_kinematics(&self.model, &mut self.data, x.as_slice()).or_raise(py)?;
        core::algorithms::kinematics::check_body(&self.model, body).or_raise(py)?;
        Ok(array1(py, core::algorithms::kinematics::point_position(&self.data, body, &off).as_slice()))
    }

    fn point_jacobians<'py>(&mut self, py: Python<'py>, x: &Bound<'py, PyAny>, body: usize, offset: &Bound<'py, PyAny>) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>)> {
        let off = vec3(offset, "offset")?;
        let x = vec_arg(x, "x")?;
        core::algorithms::kinematics::forward_kinematics(&self.model, &mut self.data, x.as_slice()).or_raise(py)?;
        let (j0, jm) = core::algorithms::kinematics::point_jacobians(&self.model, &self.data, body, &off).or_raise(py)?;
        Ok((mat6(py, &j0), dmat(py, &jm)))
    }

    fn link_jacobians<'py>(&mut self, py: Python<'py>, x: &Bound<'py, PyAny>, body: usize) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>)> {
        let x = vec_arg(x, "x")?;
        core::algorithms::kinematics::forward_kinematics(&self.model, &mut self.data, x.as_slice()).or_raise(py)?;
        core::algorithms::kinematics::check_body(&self.model, body).or_raise(py)?;
        let (jt, jr) = core::algorithms::kinematics::link_jacobians(&self.model, &self.data, body);
        Ok((dmat(py, &jt), dmat(py, &jr)))
    }

    /// The paper's inertia blocks (eqs. 27–36) as a dict.
    fn inertia_blocks<'py>(&mut self, py: Python<'py>, x: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyDict>> {
        let x = vec_arg(x, "x")?;
        let b = core::algorithms::inertia::inertia_blocks(&self.model, &mut self.data, x.as_slice()).or_raise(py)?;
        let d = PyDict::new(py);
        d.set_item("M", b.total_mass)?;
        d.set_item("r_0g", array1(py, b.base_to_com.as_slice()))?;
        d.set_item("H_S", mat3(py, &b.h_s))?;
        d.set_item("J_TS", dmat(py, &b.j_ts))?;
        d.set_item("H_Sq", dmat(py, &b.h_sq))?;
        d.set_item("H0", mat6(py, &b.h0))?;
        d.set_item("H0m", dmat(py, &b.h0m))?;
        d.set_item("Hm", dmat(py, &b.hm))?;
        d.set_item("H", dmat(py, &b.mass_matrix()))?;
        Ok(d)
    }

    /// The mass matrix `H` by the paper's Jacobian sums (eqs. 27–36) alone.
    fn mass_matrix_paper<'py>(&mut self, py: Python<'py>, x: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let x = vec_arg(x, "x")?;
        let b = core::algorithms::inertia::inertia_blocks(&self.model, &mut self.data, x.as_slice()).or_raise(py)?;
        Ok(dmat(py, &b.mass_matrix()))
    }

    fn mass_matrix_crba<'py>(&mut self, py: Python<'py>, x: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let x = vec_arg(x, "x")?;
        let h = core::algorithms::crba::crba(&self.model, &mut self.data, x.as_slice()).or_raise(py)?;
        Ok(dmat(py, h))
    }

    fn base_inertia_inverse<'py>(&mut self, py: Python<'py>, x: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let x = vec_arg(x, "x")?;
        let h = core::algorithms::crba::crba(&self.model, &mut self.data, x.as_slice()).or_raise(py)?;
        let h0 = h.fixed_view::<6, 6>(0, 0).into_owned();
        Ok(mat6(py, &core::algorithms::inertia::base_inertia_inverse(&h0).or_raise(py)?))
    }

    fn bias_forces<'py>(&mut self, py: Python<'py>, x: &Bound<'py, PyAny>, u: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (x, u) = (vec_arg(x, "x")?, vec_arg(u, "u")?);
        let c = core::algorithms::rnea::bias_forces(&self.model, &mut self.data, x.as_slice(), u.as_slice()).or_raise(py)?;
        Ok(dvec(py, c))
    }

    #[pyo3(signature = (x, u, du, wrenches=None))]
    fn inverse_dynamics<'py>(
        &mut self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
        du: &Bound<'py, PyAny>,
        wrenches: Option<WrenchList>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (x, u, du) = (vec_arg(x, "x")?, vec_arg(u, "u")?, vec_arg(du, "du")?);
        let ext = self::wrenches(py, wrenches)?;
        let f = core::algorithms::rnea::rnea(&self.model, &mut self.data, x.as_slice(), u.as_slice(), du.as_slice(), &ext).or_raise(py)?;
        Ok(dvec(py, f))
    }

    /// `f` is converted before `x` and `u`, in the order `Robot.forward_dynamics` always used.
    #[pyo3(signature = (x, u, f, wrenches=None))]
    fn forward_dynamics_aba<'py>(
        &mut self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
        f: &Bound<'py, PyAny>,
        wrenches: Option<WrenchList>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let f = vec_arg(f, "f")?;
        let (x, u) = (vec_arg(x, "x")?, vec_arg(u, "u")?);
        let ext = self::wrenches(py, wrenches)?;
        let a = core::algorithms::aba::aba(&self.model, &mut self.data, x.as_slice(), u.as_slice(), f.as_slice(), &ext).or_raise(py)?;
        Ok(dvec(py, a))
    }

    #[pyo3(signature = (x, u, f, wrenches=None))]
    fn forward_dynamics_mass_matrix<'py>(
        &mut self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
        f: &Bound<'py, PyAny>,
        wrenches: Option<WrenchList>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let f = vec_arg(f, "f")?;
        let (x, u) = (vec_arg(x, "x")?, vec_arg(u, "u")?);
        let ext = self::wrenches(py, wrenches)?;
        let a = core::algorithms::dynamics::compute_forward_dynamics_via_mass_matrix(&self.model, &mut self.data, x.as_slice(), u.as_slice(), f.as_slice(), &ext)
            .or_raise(py)?;
        Ok(dvec(py, a))
    }

    /// Forward dynamics by ABA under `f = [base_wrench; tau]` (either `None`: zero), in one
    /// call: the same numbers as `forward_dynamics_aba` with the assembled `f`.
    #[pyo3(signature = (x, u, tau=None, base_wrench=None, wrenches=None))]
    fn forward_dynamics_aba_tau<'py>(
        &mut self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
        tau: Option<&Bound<'py, PyAny>>,
        base_wrench: Option<&Bound<'py, PyAny>>,
        wrenches: Option<WrenchList>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        with_force_from_parts(py, &self.model, tau, base_wrench, |f| {
            let (x, u) = (vec_arg(x, "x")?, vec_arg(u, "u")?);
            let ext = self::wrenches(py, wrenches)?;
            let a = core::algorithms::aba::aba(&self.model, &mut self.data, x.as_slice(), u.as_slice(), f, &ext).or_raise(py)?;
            Ok(dvec(py, a))
        })
    }

    /// Forward dynamics through `H` under `f = [base_wrench; tau]` (either `None`: zero).
    #[pyo3(signature = (x, u, tau=None, base_wrench=None, wrenches=None))]
    fn forward_dynamics_mass_matrix_tau<'py>(
        &mut self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
        tau: Option<&Bound<'py, PyAny>>,
        base_wrench: Option<&Bound<'py, PyAny>>,
        wrenches: Option<WrenchList>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        with_force_from_parts(py, &self.model, tau, base_wrench, |f| {
            let (x, u) = (vec_arg(x, "x")?, vec_arg(u, "u")?);
            let ext = self::wrenches(py, wrenches)?;
            let a = core::algorithms::dynamics::compute_forward_dynamics_via_mass_matrix(&self.model, &mut self.data, x.as_slice(), u.as_slice(), f, &ext)
                .or_raise(py)?;
            Ok(dvec(py, a))
        })
    }

    /// Reduced forward dynamics (the `H*` route) under joint torques `tau` and base wrench
    /// `base_wrench` (either `None`: zero).
    #[pyo3(signature = (x, u, tau=None, base_wrench=None))]
    fn reduced_forward_dynamics<'py>(
        &mut self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
        tau: Option<&Bound<'py, PyAny>>,
        base_wrench: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        with_force_from_parts(py, &self.model, tau, base_wrench, |f| {
            let (x, u) = (vec_arg(x, "x")?, vec_arg(u, "u")?);
            let fb = Vector6::from_column_slice(&f[..6]);
            let a = core::gjm::compute_reduced_forward_dynamics(&self.model, &mut self.data, x.as_slice(), u.as_slice(), &f[6..], &fb)
                .or_raise(py)?;
            Ok(dvec(py, a))
        })
    }

    /// Reduced forward dynamics from the full generalized force `f = [F_b; τ]` (what
    /// `Robot.forward_dynamics(method="reduced")` passes), without splitting it in Python.
    fn reduced_forward_dynamics_f<'py>(&mut self, py: Python<'py>, x: &Bound<'py, PyAny>, u: &Bound<'py, PyAny>, f: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let f = vec_arg(f, "f")?;
        let nu = self.model.nu();
        let n_f = f.as_slice().len();
        if n_f != nu {
            return Err(to_py_err(py, core::SpacearmError::Dimension { what: "f".into(), expected: format!("6+N = {nu}"), got: n_f }));
        }
        let (x, u) = (vec_arg(x, "x")?, vec_arg(u, "u")?);
        let fs = f.as_slice();
        let fb = Vector6::from_column_slice(&fs[..6]);
        let a = core::gjm::compute_reduced_forward_dynamics(&self.model, &mut self.data, x.as_slice(), u.as_slice(), &fs[6..], &fb).or_raise(py)?;
        Ok(dvec(py, a))
    }

    fn generalized_inertia<'py>(&mut self, py: Python<'py>, x: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let x = vec_arg(x, "x")?;
        let h = core::gjm::compute_generalized_inertia(&self.model, &mut self.data, x.as_slice()).or_raise(py)?;
        Ok(dmat(py, h))
    }

    fn generalized_bias<'py>(&mut self, py: Python<'py>, x: &Bound<'py, PyAny>, u: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (x, u) = (vec_arg(x, "x")?, vec_arg(u, "u")?);
        let c = core::gjm::compute_generalized_bias(&self.model, &mut self.data, x.as_slice(), u.as_slice()).or_raise(py)?;
        Ok(dvec(py, c))
    }

    fn generalized_jacobian<'py>(&mut self, py: Python<'py>, x: &Bound<'py, PyAny>, body: usize, offset: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let off = vec3(offset, "offset")?;
        let x = vec_arg(x, "x")?;
        let j = core::gjm::compute_generalized_jacobian(&self.model, &mut self.data, x.as_slice(), body, &off).or_raise(py)?;
        Ok(dmat(py, j))
    }

    fn momentum_twist<'py>(
        &mut self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        body: usize,
        offset: &Bound<'py, PyAny>,
        linear: &Bound<'py, PyAny>,
        angular_origin: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let off = vec3(offset, "offset")?;
        let p = vec3(linear, "linear momentum")?;
        let l = vec3(angular_origin, "angular momentum")?;
        let x = vec_arg(x, "x")?;
        let t = core::gjm::momentum_twist(&self.model, &mut self.data, x.as_slice(), body, &off, &p, &l).or_raise(py)?;
        Ok(array1(py, t.as_slice()))
    }

    fn base_velocity_from_momentum<'py>(
        &mut self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        qd: &Bound<'py, PyAny>,
        linear: &Bound<'py, PyAny>,
        angular_origin: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let p = vec3(linear, "linear momentum")?;
        let l = vec3(angular_origin, "angular momentum")?;
        let (x, qd) = (vec_arg(x, "x")?, vec_arg(qd, "qd")?);
        let v = core::gjm::base_velocity_from_momentum(&self.model, &mut self.data, x.as_slice(), qd.as_slice(), &p, &l).or_raise(py)?;
        Ok(array1(py, v.as_slice()))
    }

    /// (P, L_origin, L_base, L_com)
    #[allow(clippy::type_complexity)]
    fn momentum<'py>(
        &mut self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
    ) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>)> {
        let (x, u) = (vec_arg(x, "x")?, vec_arg(u, "u")?);
        let m = core::algorithms::momentum::momentum(&self.model, &mut self.data, x.as_slice(), u.as_slice()).or_raise(py)?;
        Ok((
            array1(py, m.linear.as_slice()),
            array1(py, m.angular_about_origin.as_slice()),
            array1(py, m.angular_about_base.as_slice()),
            array1(py, m.angular_about_com.as_slice()),
        ))
    }

    fn kinetic_energy<'py>(&mut self, py: Python<'py>, x: &Bound<'py, PyAny>, u: &Bound<'py, PyAny>) -> PyResult<f64> {
        let (x, u) = (vec_arg(x, "x")?, vec_arg(u, "u")?);
        core::algorithms::momentum::kinetic_energy(&self.model, &mut self.data, x.as_slice(), u.as_slice()).or_raise(py)
    }

    fn center_of_mass<'py>(&mut self, py: Python<'py>, x: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let x = vec_arg(x, "x")?;
        let c = core::algorithms::momentum::center_of_mass(&self.model, &mut self.data, x.as_slice()).or_raise(py)?;
        Ok(array1(py, c.as_slice()))
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
