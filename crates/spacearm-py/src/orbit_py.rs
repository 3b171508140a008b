//! The orbit of a run (`spacearm_core::sim::orbit`) as typed frozen classes: `CentralBody` (the
//! gravity constants), `OrbitalElements` (osculating two-body elements) and `Orbit` (the body,
//! J2 on or off, the ECI state at t = 0; propagation, elements, LVLH frames, J2 secular rates);
//! docs/orbit.md.

use nalgebra::Vector3;
use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArray3, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use spacearm_core::sim::orbit::{lvlh_to_eci, CentralBody, Elements, Orbit, EARTH};
use spacearm_core::SpacearmError;

use crate::convert::*;
use crate::sim_options_py::{refuse_unknown, type_name};

fn bad(msg: String) -> SpacearmError {
    SpacearmError::InvalidArgument(msg)
}

/// A central body's gravity constants: μ (m³/s²), the equatorial radius R (m) and J2.
#[pyclass(module = "spacearm._core", name = "CentralBody", frozen)]
#[derive(Clone)]
pub struct PyCentralBody {
    pub inner: CentralBody,
}

#[pymethods]
impl PyCentralBody {
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

    /// Gravitational parameter μ, m³/s².
    #[getter]
    fn mu(&self) -> f64 {
        self.inner.mu
    }

    /// Equatorial (J2 reference) radius, m.
    #[getter]
    fn radius(&self) -> f64 {
        self.inner.radius
    }

    /// Second zonal harmonic J2.
    #[getter]
    fn j2(&self) -> f64 {
        self.inner.j2
    }

    fn __repr__(&self) -> String {
        format!("<spacearm._core.CentralBody mu={:e} m^3/s^2 radius={} m j2={:e}>", self.inner.mu, self.inner.radius, self.inner.j2)
    }
}

/// Osculating classical elements (two-body, with the body's μ): a (m), e, i, raan, argp,
/// true_anomaly (rad). Circular orbits: argp = 0 and true_anomaly is the argument of latitude;
/// equatorial ones: raan = 0.
#[pyclass(module = "spacearm._core", name = "OrbitalElements", frozen)]
pub struct PyOrbitalElements {
    pub inner: Elements,
}

#[pymethods]
impl PyOrbitalElements {
    /// Semi-major axis, m.
    #[getter]
    fn a(&self) -> f64 {
        self.inner.a
    }
    /// Eccentricity.
    #[getter]
    fn e(&self) -> f64 {
        self.inner.e
    }
    /// Inclination, rad.
    #[getter]
    fn i(&self) -> f64 {
        self.inner.i
    }
    /// Right ascension of the ascending node, rad.
    #[getter]
    fn raan(&self) -> f64 {
        self.inner.raan
    }
    /// Argument of perigee, rad.
    #[getter]
    fn argp(&self) -> f64 {
        self.inner.argp
    }
    /// True anomaly, rad.
    #[getter]
    fn true_anomaly(&self) -> f64 {
        self.inner.true_anomaly
    }

    fn __repr__(&self) -> String {
        let e = &self.inner;
        format!(
            "<spacearm._core.OrbitalElements a={} m e={} i={} raan={} argp={} true_anomaly={} (rad)>",
            e.a, e.e, e.i, e.raan, e.argp, e.true_anomaly
        )
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

#[pymethods]
impl PyOrbit {
    /// A circular orbit `altitude` (m) above the body's equatorial radius, inclination, RAAN
    /// and starting argument of latitude in rad; speed √(μ/a) (also with `j2=True`).
    #[staticmethod]
    #[pyo3(signature = (altitude, *, inclination=0.0, raan=0.0, arg_latitude=0.0, body=None, j2=false))]
    fn circular(py: Python<'_>, altitude: f64, inclination: f64, raan: f64, arg_latitude: f64, body: Option<&Bound<'_, PyAny>>, j2: bool) -> PyResult<Self> {
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

    /// The central body.
    #[getter]
    fn body(&self) -> PyCentralBody {
        PyCentralBody { inner: self.inner.body }
    }

    /// Whether J2 acts on the point-mass motion.
    #[getter]
    fn j2(&self) -> bool {
        self.inner.j2
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

    /// Mean motion of the osculating orbit at t = 0, √(μ/a³), rad/s.
    #[getter]
    fn mean_motion(&self) -> f64 {
        self.inner.mean_motion()
    }

    /// Period of the osculating orbit at t = 0, s.
    #[getter]
    fn period(&self) -> f64 {
        self.inner.period()
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

    fn __repr__(&self) -> String {
        let e = self.inner.elements();
        format!(
            "<spacearm._core.Orbit a={:.1} m e={:.3e} i={:.6} rad raan={:.6} rad j2={} mu={:e}>",
            e.a, e.e, e.i, e.raan, self.inner.j2, self.inner.body.mu
        )
    }
}

/// Register the orbit classes.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyCentralBody>()?;
    m.add_class::<PyOrbitalElements>()?;
    m.add_class::<PyOrbit>()?;
    Ok(())
}
