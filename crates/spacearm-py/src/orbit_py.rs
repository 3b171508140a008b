//! The orbit of a run (`spacearm_core::sim::orbit`) as typed frozen classes: `CentralBody` (the
//! gravity constants), `OrbitalElements` (osculating two-body elements) and `Orbit` (the body,
//! J2 on or off, the ECI state at t = 0; propagation, elements, LVLH frames, J2 secular rates);
//! docs/orbit.md.

use nalgebra::Vector3;
use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArray3, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict};
use spacearm_core::sim::orbit::{clohessy_wiltshire, lvlh_to_eci, safety_ellipse, CentralBody, Elements, Orbit, RelativeState, EARTH};

use crate::convert::*;
use crate::sim_options_py::{refuse_unknown, type_name};

/// The core model of `obj`: a `spacearm.Robot` (its `core_model`) or a `spacearm._core.Model`;
/// anything else a `SpacearmTypeError` naming what was given.
fn model_of<'py>(py: Python<'py>, obj: &Bound<'py, PyAny>) -> PyResult<Bound<'py, crate::model_py::PyModel>> {
    if let Ok(m) = obj.cast::<crate::model_py::PyModel>() {
        return Ok(m.clone());
    }
    let refuse = || type_error(py, format!("model must be a spacearm.Robot (or its core_model), got {}", type_name(obj)));
    if !obj.hasattr("core_model").unwrap_or(false) {
        return Err(refuse());
    }
    let inner = obj.getattr("core_model")?;
    inner.cast::<crate::model_py::PyModel>().map(|m| m.clone()).map_err(|_| refuse())
}

/// A central body's gravity constants: μ (m³/s²), the equatorial radius R (m) and J2.
#[pyclass(module = "spacearm._core", name = "CentralBody", frozen)]
#[derive(Clone)]
pub struct PyCentralBody {
    pub inner: CentralBody,
}

pymethods_with_getters! {
#[pymethods]
impl PyCentralBody {
    getters(self) {
        /// Gravitational parameter μ, m³/s².
        mu: f64 = self.inner.mu;
        /// Equatorial (J2 reference) radius, m.
        radius: f64 = self.inner.radius;
        /// Second zonal harmonic J2.
        j2: f64 = self.inner.j2;
    }

    #[new]
    #[pyo3(signature = (*, mu, radius, j2, **unknown))]
    fn new(py: Python<'_>, mu: f64, radius: f64, j2: f64, unknown: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        refuse_unknown::<Self>(py, unknown)?;
        let inner = CentralBody { mu, radius, j2 };
        inner.validate().or_raise(py)?;
        Ok(PyCentralBody { inner })
    }

    /// The Earth: μ = 3.986004418e14 m³/s², R = 6378137 m, J2 = 1.08262668e-3.
    #[staticmethod]
    fn earth() -> Self {
        PyCentralBody { inner: EARTH }
    }

    fn __repr__(&self) -> String {
        format!("<spacearm._core.CentralBody mu={:e} m^3/s^2 radius={} m j2={:e}>", self.inner.mu, self.inner.radius, self.inner.j2)
    }
}
}

/// Osculating classical elements (two-body, with the body's μ): a (m), e, i, raan, argp,
/// true_anomaly (rad). Circular orbits: argp = 0 and true_anomaly is the argument of latitude;
/// equatorial ones: raan = 0.
#[pyclass(module = "spacearm._core", name = "OrbitalElements", frozen)]
pub struct PyOrbitalElements {
    pub inner: Elements,
}

pymethods_with_getters! {
#[pymethods]
impl PyOrbitalElements {
    getters(self) {
        /// Semi-major axis, m.
        a: f64 = self.inner.a;
        /// Eccentricity.
        e: f64 = self.inner.e;
        /// Inclination, rad.
        i: f64 = self.inner.i;
        /// Right ascension of the ascending node, rad.
        raan: f64 = self.inner.raan;
        /// Argument of perigee, rad.
        argp: f64 = self.inner.argp;
        /// True anomaly, rad.
        true_anomaly: f64 = self.inner.true_anomaly;
    }

    fn __repr__(&self) -> String {
        let e = &self.inner;
        format!(
            "<spacearm._core.OrbitalElements a={} m e={} i={} raan={} argp={} true_anomaly={} (rad)>",
            e.a, e.e, e.i, e.raan, e.argp, e.true_anomaly
        )
    }
}
}

/// `body`: "earth" or a CentralBody.
fn central_body(py: Python<'_>, body: &Bound<'_, PyAny>) -> PyResult<CentralBody> {
    if let Ok(b) = body.cast::<PyCentralBody>() {
        return Ok(b.get().inner);
    }
    match body.extract::<String>().ok().as_deref() {
        Some("earth") => Ok(EARTH),
        Some(other) => Err(to_py_err(py, bad(format!("orbit: body must be 'earth' or a CentralBody(mu=..., radius=..., j2=...), got '{other}'")))),
        None => Err(to_py_err(py, bad(format!("orbit: body must be 'earth' or a CentralBody, got {}", type_name(body))))),
    }
}

/// An orbit: the central body, whether J2 acts on the point-mass motion, and the ECI state at
/// t = 0 (ECI's z is the body's pole). Built by `Orbit.circular`, `Orbit.from_elements` or
/// `Orbit.from_state`.
#[pyclass(module = "spacearm._core", name = "Orbit", frozen)]
pub struct PyOrbit {
    pub inner: Orbit,
}

pymethods_with_getters! {
#[pymethods]
impl PyOrbit {
    getters(self) {
        /// The central body.
        body: PyCentralBody = PyCentralBody { inner: self.inner.body };
        /// Whether J2 acts on the point-mass motion.
        j2: bool = self.inner.j2;
        /// Mean motion of the osculating orbit at t = 0, √(μ/a³), rad/s.
        mean_motion: f64 = self.inner.mean_motion();
        /// Period of the osculating orbit at t = 0, s.
        period: f64 = self.inner.period();
    }

    /// A circular orbit `altitude` (m) above the body's equatorial radius, inclination, RAAN
    /// and starting argument of latitude in rad; speed √(μ/a) (also with `j2=True`).
    #[staticmethod]
    #[pyo3(signature = (altitude, *, inclination=0.0, raan=0.0, arg_latitude=0.0, body=None, j2=false))]
    fn circular(py: Python<'_>, altitude: &Bound<'_, PyAny>, inclination: f64, raan: f64, arg_latitude: f64, body: Option<&Bound<'_, PyAny>>, j2: bool) -> PyResult<Self> {
        // A bool is not an altitude (Python would read True as 1 m).
        if altitude.is_instance_of::<PyBool>() || matches!(type_name(altitude).as_str(), "bool" | "bool_") {
            return Err(type_error(py, format!("orbit: the altitude must be a number of metres, got the bool {}", altitude.repr()?)));
        }
        let altitude: f64 = altitude
            .extract()
            .map_err(|_| type_error(py, format!("orbit: the altitude must be a number of metres, got {}", type_name(altitude))))?;
        let b = match body {
            Some(b) => central_body(py, b)?,
            None => EARTH,
        };
        Ok(PyOrbit { inner: Orbit::circular(b, altitude, inclination, raan, arg_latitude, j2).or_raise(py)? })
    }

    /// An orbit from its osculating elements at t = 0 (m, rad).
    #[staticmethod]
    #[pyo3(signature = (a, e, i, raan, argp, true_anomaly, *, body=None, j2=false))]
    #[allow(clippy::too_many_arguments)]
    fn from_elements(py: Python<'_>, a: f64, e: f64, i: f64, raan: f64, argp: f64, true_anomaly: f64, body: Option<&Bound<'_, PyAny>>, j2: bool) -> PyResult<Self> {
        let b = match body {
            Some(b) => central_body(py, b)?,
            None => EARTH,
        };
        let el = Elements { a, e, i, raan, argp, true_anomaly };
        Ok(PyOrbit { inner: Orbit::from_elements(b, &el, j2).or_raise(py)? })
    }

    /// An orbit from an ECI position (m) and velocity (m/s) at t = 0.
    #[staticmethod]
    #[pyo3(signature = (r, v, *, body=None, j2=false))]
    fn from_state(py: Python<'_>, r: &Bound<'_, PyAny>, v: &Bound<'_, PyAny>, body: Option<&Bound<'_, PyAny>>, j2: bool) -> PyResult<Self> {
        let b = match body {
            Some(b) => central_body(py, b)?,
            None => EARTH,
        };
        let r = finite3(r, "orbit 'r'")?;
        let v = finite3(v, "orbit 'v'")?;
        Ok(PyOrbit { inner: Orbit::from_state(b, r, v, j2).or_raise(py)? })
    }

    /// ECI position at t = 0, m, shape (3,).
    #[getter]
    fn r0<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array1(py, self.inner.r0.as_slice())
    }

    /// ECI velocity at t = 0, m/s, shape (3,).
    #[getter]
    fn v0<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array1(py, self.inner.v0.as_slice())
    }

    /// The osculating elements at t = 0.
    fn elements(&self) -> PyOrbitalElements {
        PyOrbitalElements { inner: self.inner.elements() }
    }

    /// The J2 secular rates (RAAN rate, argument-of-perigee rate), rad/s (Vallado eq. 9-41).
    fn j2_secular_rates(&self) -> (f64, f64) {
        self.inner.j2_secular_rates()
    }

    /// The point-mass ECI states at `times` (s, non-decreasing, >= 0): `(r, v)`, each (T, 3),
    /// by DOPRI5 with relative tolerance `rtol`.
    #[pyo3(signature = (times, *, rtol=1e-12))]
    fn propagate<'py>(&self, py: Python<'py>, times: &Bound<'py, PyAny>, rtol: f64) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>)> {
        let t = vec_arg(times, "times")?;
        let t = t.as_slice().to_vec();
        let orbit = self.inner;
        let states = py.detach(|| orbit.propagate(&t, rtol)).or_raise(py)?;
        let flat = |f: &dyn Fn(&(Vector3<f64>, Vector3<f64>)) -> Vector3<f64>| states.iter().flat_map(|s| f(s).iter().copied().collect::<Vec<_>>()).collect::<Vec<f64>>();
        let r = numpy::ndarray::Array2::from_shape_vec((states.len(), 3), flat(&|s| s.0)).expect("shape");
        let v = numpy::ndarray::Array2::from_shape_vec((states.len(), 3), flat(&|s| s.1)).expect("shape");
        Ok((r.into_pyarray(py), v.into_pyarray(py)))
    }

    /// The LVLH (Hill) frames of ECI states `r`, `v` (each (3,) or (T, 3)): the rotations LVLH →
    /// ECI, (3, 3) or (T, 3, 3), columns x̂ = r̂ (radial), ŷ = ẑ × x̂, ẑ = orbit normal.
    #[staticmethod]
    fn lvlh_to_eci<'py>(py: Python<'py>, r: &Bound<'py, PyAny>, v: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let ra = real_array(r, "r")?;
        let va = real_array(v, "v")?;
        if ra.shape() != va.shape() || ra.shape().last() != Some(&3) || ra.ndim() > 2 {
            return Err(shape_error(py, format!("r and v must both have shape (3,) or (T, 3), got {:?} and {:?}", ra.shape(), va.shape())));
        }
        let one = ra.ndim() == 1;
        // SAFETY: `real_array` returns C-contiguous float64 arrays.
        let rs = unsafe { ra.cast_unchecked::<numpy::PyArrayDyn<f64>>().as_slice() }.map_err(PyErr::from)?.to_vec();
        let vs = unsafe { va.cast_unchecked::<numpy::PyArrayDyn<f64>>().as_slice() }.map_err(PyErr::from)?.to_vec();
        check_finite(py, "r", &rs)?;
        check_finite(py, "v", &vs)?;
        let n = rs.len() / 3;
        let mut out = Array3::<f64>::zeros((n, 3, 3));
        for k in 0..n {
            let rk = Vector3::from_column_slice(&rs[3 * k..3 * k + 3]);
            let vk = Vector3::from_column_slice(&vs[3 * k..3 * k + 3]);
            if rk.cross(&vk).norm() == 0.0 {
                return Err(to_py_err(py, bad(format!("LVLH: row {k} has r parallel to v (no orbit plane)"))));
            }
            let m = lvlh_to_eci(&rk, &vk);
            for i in 0..3 {
                for j in 0..3 {
                    out[[k, i, j]] = m[(i, j)];
                }
            }
        }
        let arr: Bound<'py, PyArray3<f64>> = out.into_pyarray(py);
        if one {
            Ok(arr.call_method1("reshape", ((3, 3),))?)
        } else {
            Ok(arr.into_any())
        }
    }

    /// The exact relative motion in this orbit's LVLH of a point mass started at `rel0`
    /// (`[x, y, z, vx, vy, vz]`: LVLH position, m, and its rate in LVLH, m/s) and propagated on
    /// its own orbit: (T, 6) at `times`.
    #[pyo3(signature = (rel0, times, *, rtol=1e-12))]
    fn relative_motion<'py>(&self, py: Python<'py>, rel0: &Bound<'py, PyAny>, times: &Bound<'py, PyAny>, rtol: f64) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let rel = rel6(py, rel0)?;
        let t = owned_vec(times, "times")?;
        let orbit = self.inner;
        let states = py.detach(|| orbit.relative_motion(&rel, &t, rtol)).or_raise(py)?;
        Ok(rows(py, &states))
    }

    /// A run's state `(position, velocity)` (relative to this orbit's point `O` at time `t`,
    /// ECI axes; docs/orbit.md) of a point at relative state `rel` (`[x, y, z, vx, vy, vz]`, LVLH
    /// position and its rate in LVLH) about a centre at run state `center` (6: position,
    /// velocity; default `O` itself), the LVLH that of the centre's orbit.
    #[pyo3(signature = (rel, *, center=None, t=0.0))]
    fn lvlh_to_run<'py>(&self, py: Python<'py>, rel: &Bound<'py, PyAny>, center: Option<&Bound<'py, PyAny>>, t: f64) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let rel = rel6(py, rel)?;
        let c = match center {
            Some(c) => rel6(py, c)?,
            None => [0.0; 6],
        };
        let orbit = self.inner;
        let (ro, vo) = py.detach(|| orbit.state_at(t, 1e-13)).or_raise(py)?;
        let (p, v) = Orbit::lvlh_to_run(&ro, &vo, &Vector3::new(c[0], c[1], c[2]), &Vector3::new(c[3], c[4], c[5]), &rel);
        Ok(array1(py, &[p.x, p.y, p.z, v.x, v.y, v.z]))
    }

    /// The LVLH relative states (T, 6) about centres `center` (T, 6: run positions and
    /// velocities) of points `points` (T, 6), at the times `t` (T,) of a run of this orbit (run
    /// states relative to `O`, ECI axes): the inverse of `lvlh_to_run` sample by sample.
    fn run_to_lvlh<'py>(&self, py: Python<'py>, t: &Bound<'py, PyAny>, center: &Bound<'py, PyAny>, points: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let times = owned_vec(t, "t")?;
        let flat = |a: &Bound<'py, PyAny>, what: &str| -> PyResult<Vec<f64>> {
            Ok(match batch_arg(a, what)? {
                ArgValue::One(v) => v.as_slice().to_vec(),
                ArgValue::Many { values, .. } => values,
            })
        };
        let c = flat(center, "center")?;
        let p = flat(points, "points")?;
        if c.len() != 6 * times.len() || p.len() != 6 * times.len() {
            return Err(shape_error(py, format!("center and points must have shape ({}, 6) for {} times, got {} and {} numbers", times.len(), times.len(), c.len(), p.len())));
        }
        check_finite(py, "center", &c)?;
        check_finite(py, "points", &p)?;
        let orbit = self.inner;
        let states = py.detach(|| orbit.propagate(&times, 1e-13)).or_raise(py)?;
        let v3 = |s: &[f64]| Vector3::new(s[0], s[1], s[2]);
        let out: Vec<RelativeState> = states
            .iter()
            .enumerate()
            .map(|(k, (ro, vo))| {
                let (ck, pk) = (&c[6 * k..6 * k + 6], &p[6 * k..6 * k + 6]);
                Orbit::run_to_lvlh(ro, vo, &v3(ck), &v3(&ck[3..]), &v3(pk), &v3(&pk[3..]))
            })
            .collect();
        Ok(rows(py, &out))
    }

    /// The Clohessy–Wiltshire closed form about this orbit (its mean motion at t = 0) from
    /// `rel0` (LVLH): (T, 6) at `times`. Linear: for a target near a circular orbit.
    fn clohessy_wiltshire<'py>(&self, py: Python<'py>, rel0: &Bound<'py, PyAny>, times: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let rel = rel6(py, rel0)?;
        let t = vec_arg(times, "times")?;
        check_finite(py, "times", t.as_slice())?;
        let n = self.inner.mean_motion();
        let states: Vec<RelativeState> = t.as_slice().iter().map(|&t| clohessy_wiltshire(n, &rel, t)).collect();
        Ok(rows(py, &states))
    }

    /// The relative state (LVLH) of a drift-free safety ellipse about this orbit: radial
    /// half-axis `radial` (m; along-track half-axis twice it), cross-track amplitude
    /// `cross_track`, centred `along_track` m ahead.
    #[pyo3(signature = (radial, *, cross_track=0.0, along_track=0.0))]
    fn safety_ellipse<'py>(&self, py: Python<'py>, radial: f64, cross_track: f64, along_track: f64) -> PyResult<Bound<'py, PyArray1<f64>>> {
        check_finite(py, "safety ellipse", &[radial, cross_track, along_track])?;
        Ok(array1(py, &safety_ellipse(self.inner.mean_motion(), radial, cross_track, along_track)))
    }

    /// The gravity-gradient torques on `model` at configuration `x` (relative to this orbit's
    /// point at time `t`, s): `(wrenches, total, arm)` — per body `[force (N); torque about its CM
    /// (N·m)]` in ECI axes, shape (n_bodies, 6); the total torque about the system CM; the part of
    /// it from every body but the base.
    #[pyo3(signature = (model, x, *, t=0.0))]
    fn tidal_torques<'py>(
        &self,
        py: Python<'py>,
        model: &Bound<'py, PyAny>,
        x: &Bound<'py, PyAny>,
        t: f64,
    ) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>)> {
        let model = model_of(py, model)?;
        let x = owned_vec(x, "x")?;
        let orbit = self.inner;
        let m = model.borrow();
        let core = &m.model;
        let (rows_, total, arm) = py
            .detach(|| -> spacearm_core::Result<_> {
                let r = orbit.state_at(t, 1e-12)?.0;
                spacearm_core::sim::orbit::tidal_torques(core, &x, orbit.body.mu, &r)
            })
            .or_raise(py)?;
        let flat: Vec<f64> = rows_.iter().flatten().copied().collect();
        let w = numpy::ndarray::Array2::from_shape_vec((rows_.len(), 6), flat).expect("shape").into_pyarray(py);
        Ok((w, array1(py, total.as_slice()), array1(py, arm.as_slice())))
    }

    /// The orbit as plain data (`{body: {mu, radius, j2}, j2, r0, v0}`): the form a run's
    /// description carries it in (`spacearm_core::control::spec`).
    fn _data<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::controller_spec_py::to_data(py, &self.inner)
    }

    fn __repr__(&self) -> String {
        let e = self.inner.elements();
        format!(
            "<spacearm._core.Orbit a={:.1} m e={:.3e} i={:.6} rad raan={:.6} rad j2={} mu={:e}>",
            e.a, e.e, e.i, e.raan, self.inner.j2, self.inner.body.mu
        )
    }
}
}

/// A relative state argument (6 finite values).
fn rel6(py: Python<'_>, v: &Bound<'_, PyAny>) -> PyResult<RelativeState> {
    let v = vec6(v, "rel0")?;
    check_finite(py, "rel0", v.as_slice())?;
    Ok([v[0], v[1], v[2], v[3], v[4], v[5]])
}

/// Relative states as a (T, 6) array.
fn rows<'py>(py: Python<'py>, states: &[RelativeState]) -> Bound<'py, PyArray2<f64>> {
    let flat: Vec<f64> = states.iter().flatten().copied().collect();
    numpy::ndarray::Array2::from_shape_vec((states.len(), 6), flat).expect("shape").into_pyarray(py)
}

/// Register the orbit classes.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    add_to_module!(m, classes: [PyCentralBody, PyOrbitalElements, PyOrbit]);
    Ok(())
}
