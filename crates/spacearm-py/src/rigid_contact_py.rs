//! Binding of the core's rigid frictional impact (`spacearm_core::collision::impact`, delassus.rs,
//! admm.rs, pgs.rs; docs/contact.md, "Rigid frictional impacts"): points in, a frozen
//! `RigidImpact` out (`spacearm.contact.solve_impact` is the face users see).

use numpy::{PyArray1, PyArray2, PyArray3};
use pyo3::prelude::*;
use spacearm_core::collision::{rigid_impact as core_rigid_impact, ContactPoint, ImpactSolver, ImpactSpec, RigidImpact};
use spacearm_core::SpacearmError;

use crate::convert::*;
use crate::model_py::PyModel;

result_class! {
    /// The velocity jump of a rigid frictional impact (`spacearm_core::collision::RigidImpact`).
    /// Contact rows are three a point, `[t1, t2, n]` of its contact frame.
    PyRigidImpact as "RigidImpact", fn of(py: Python<'_>, r: &RigidImpact, k: usize, solver: &str) -> PyResult [
        let rows = |v: &nalgebra::DVector<f64>| -> Vec<Vec<f64>> { (0..k).map(|i| v.rows(3 * i, 3).iter().copied().collect()).collect() };
        let world = (0..k).map(|i| (r.frames[i] * r.impulse.fixed_rows::<3>(3 * i)).iter().copied().collect()).collect::<Vec<Vec<f64>>>();
        let frames = r.frames.iter().map(|f| (0..3).map(|row| (0..3).map(|col| f[(row, col)]).collect()).collect()).collect::<Vec<Vec<Vec<f64>>>>();
        let to2 = |v: Vec<Vec<f64>>| -> PyResult<Py<PyArray2<f64>>> { Ok(read_only(PyArray2::from_vec2(py, &v).map_err(|e| shape_error(py, e.to_string()))?)) };
    ] {
        /// (6+N,) the generalized velocity after the impact u⁺.
        u_after: Py<PyArray1<f64>> = read_only(dvec(py, &r.u_after)),
        /// (6+N,) the jump Δu = H⁻¹ Jᵀ λ.
        du: Py<PyArray1<f64>> = read_only(dvec(py, &r.du)),
        /// (k, 3) the impulses λ in each point's contact frame [t1, t2, n], N·s.
        impulse: Py<PyArray2<f64>> = to2(rows(&r.impulse))?,
        /// (k, 3) the impulse on each point's second body in 𝒥 (the first body receives its opposite), N·s.
        impulse_world: Py<PyArray2<f64>> = to2(world)?,
        /// (k, 3) the contact velocities before, J u⁻ (contact frames), m/s.
        velocity_before: Py<PyArray2<f64>> = to2(rows(&r.velocity_before))?,
        /// (k, 3) the contact velocities after, J u⁺, m/s.
        velocity_after: Py<PyArray2<f64>> = to2(rows(&r.velocity_after))?,
        /// (k, 3, 3) the contact frames: columns t1, t2, n in 𝒥.
        frames: Py<PyArray3<f64>> = read_only(PyArray3::from_vec3(py, &frames).map_err(|e| shape_error(py, e.to_string()))?),
        /// (3k, 6+N) the contact Jacobian J.
        jacobian: Py<PyArray2<f64>> = read_only(dmat(py, &r.jacobian)),
        /// (3k, 3k) the Delassus operator G = J H⁻¹ Jᵀ.
        delassus: Py<PyArray2<f64>> = read_only(dmat(py, &r.delassus)),
        /// The solver's name, "admm" or "pgs".
        solver: String = solver.to_string(),
        /// Whether the residual reached the tolerance within the iteration limit.
        converged: bool = r.solution.converged,
        /// Iterations done.
        iterations: usize = r.solution.iterations,
        /// The larger of dual_feasibility and complementarity, m/s.
        residual: f64 = r.solution.residual.max(),
        /// The velocity outside the dual cone (penetration, or slip the friction does not oppose), m/s.
        dual_feasibility: f64 = r.solution.residual.dual_feasibility,
        /// The velocity along the impulse at the points that push, m/s.
        complementarity: f64 = r.solution.residual.complementarity,
    }
}

#[pymethods]
impl PyRigidImpact {
    fn __repr__(&self) -> String {
        format!("<RigidImpact {}: converged {} in {} iterations, residual {:.3e} m/s>", self.solver, self.converged, self.iterations, self.residual)
    }
}

/// The rigid frictional impact of `model` at `(x, u_before)` through the point contacts `points`,
/// each `(body_a, body_b, point, normal, friction)` (body names, the point and the unit normal
/// from the first body towards the second in 𝒥, Coulomb's μ); `solver` "admm" or "pgs".
#[pyfunction]
#[pyo3(signature = (model, x, u_before, points, *, solver = "admm", restitution = 0.0, tolerance = 1e-10, max_iterations = 1000, proximal = 1e-8))]
#[allow(clippy::too_many_arguments)]
fn rigid_impact(
    py: Python<'_>,
    model: PyRef<'_, PyModel>,
    x: &Bound<'_, PyAny>,
    u_before: &Bound<'_, PyAny>,
    points: Vec<(String, String, Bound<'_, PyAny>, Bound<'_, PyAny>, f64)>,
    solver: &str,
    restitution: f64,
    tolerance: f64,
    max_iterations: i64,
    proximal: f64,
) -> PyResult<PyRigidImpact> {
    let (x, u) = (vec_arg(x, "x")?, vec_arg(u_before, "u_before")?);
    let m = &model.model;
    let names = m.body_names();
    let index = |name: &str| {
        names.iter().position(|n| n == name).ok_or_else(|| SpacearmError::NotFound(format!("no body named '{name}' in '{}'; the bodies are {names:?}", m.name())))
    };
    let mut contact_points = Vec::with_capacity(points.len());
    for (i, (a, b, point, normal, friction)) in points.iter().enumerate() {
        contact_points.push(ContactPoint {
            body: [index(a).or_raise(py)?, index(b).or_raise(py)?],
            point: finite3(point, &format!("the point of contact {i}"))?,
            normal: finite3(normal, &format!("the normal of contact {i}"))?,
            friction: *friction,
        });
    }
    let spec = ImpactSpec { solver: ImpactSolver::from_name(solver).or_raise(py)?, restitution, tolerance, max_iterations: max_iterations.max(0) as usize, proximal };
    let r = model.with_data(|m, d| core_rigid_impact(m, d, x.as_slice(), u.as_slice(), &contact_points, &spec)).or_raise(py)?;
    PyRigidImpact::of(py, &r, contact_points.len(), spec.solver.name())
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    add_to_module!(m, functions: [rigid_impact], classes: [PyRigidImpact],);
    Ok(())
}
