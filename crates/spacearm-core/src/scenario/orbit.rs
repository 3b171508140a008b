//! The orbit of a system's centre of mass: a central body's constants, osculating two-body
//! elements and their state vectors, the point-mass equations of motion with the J2 zonal term,
//! their propagation, the J2 secular rates, the LVLH (Hill) frame and the gravity-gradient
//! (tidal) wrench on a rigid body (docs/orbit.md).
//!
//! Frames: ECI has its z axis along the central body's pole; LVLH (Hill) has x radial (along
//! `r`), z along the orbit normal `r × v`, y = z × x (along-track for a circular orbit).
//!
//! Equations (docs/orbit.md):
//! - point mass, two-body + J2 (Vallado, *Fundamentals of Astrodynamics and Applications*, 4th
//!   ed., 2013, eq. 8-30):
//!   `a = −μ r/|r|³ − (3/2) J2 μ R²/|r|⁵ [x(1 − 5z²/|r|²), y(1 − 5z²/|r|²), z(3 − 5z²/|r|²)]`;
//! - J2 secular rates (Vallado eq. 9-41): `Ω̇ = −(3/2) n J2 (R/p)² cos i`,
//!   `ω̇ = (3/4) n J2 (R/p)² (4 − 5 sin² i)`, with `n = √(μ/a³)`, `p = a(1 − e²)`;
//! - gravity gradient of the two-body field `G = μ/|r|³ (3 r̂ r̂ᵀ − 1)` (J2's own gradient, a
//!   relative `~J2 (R/r)²` ≈ 1e-3 correction, is not included), the tidal force on a body of
//!   mass `m` whose CM is `ρ` from the reference point `m G ρ`, and the torque about its CM
//!   `N = axial(I G − G I)`, which for the two-body `G` is `3 μ/|r|³ r̂ × (I r̂)` (Wie, *Space
//!   Vehicle Dynamics and Control*, 2nd ed., 2008, §6.3; Schaub & Junkins, *Analytical Mechanics
//!   of Space Systems*, 4th ed., 2018, §4.7). Both are first order in `|ρ|/|r|`.

use nalgebra::{Matrix3, Vector3};

use crate::algorithms::kinematics::forward_kinematics;
use crate::algorithms::momentum::center_of_mass_from_data;
use crate::algorithms::wrench::ExternalWrench;
use crate::error::{Result, SpacearmError};
use crate::model::data::Data;
use crate::model::Model;
use crate::math::integrate::{Dopri5, OdeSystem};

/// A central body's gravity constants.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CentralBody {
    /// Gravitational parameter μ, m³/s².
    pub mu: f64,
    /// Equatorial radius R (the reference radius of J2), m.
    pub radius: f64,
    /// Second zonal harmonic J2 (unnormalized).
    pub j2: f64,
}

/// The Earth: μ = 3.986004418e14 m³/s² (WGS 84 / EGM2008), R = 6378137 m (WGS 84),
/// J2 = 1.08262668e-3 (EGM2008, unnormalized; Vallado, Appendix D).
pub const EARTH: CentralBody = CentralBody { mu: 3.986_004_418e14, radius: 6_378_137.0, j2: 1.082_626_68e-3 };

impl CentralBody {
    /// Check the constants: μ > 0, R > 0, J2 finite.
    pub fn validate(&self) -> Result<()> {
        if !(self.mu.is_finite() && self.mu > 0.0) {
            return Err(SpacearmError::argument(format!("orbit: mu must be finite and > 0 m^3/s^2, got {}", self.mu)));
        }
        if !(self.radius.is_finite() && self.radius > 0.0) {
            return Err(SpacearmError::argument(format!("orbit: the body's radius must be finite and > 0 m, got {}", self.radius)));
        }
        if !self.j2.is_finite() {
            return Err(SpacearmError::argument(format!("orbit: j2 must be finite, got {}", self.j2)));
        }
        Ok(())
    }
}

/// Osculating classical elements (two-body, with the central body's μ); SI units and radians.
///
/// Singular orbits: for a circular orbit (`e` below [`CIRCULAR_TOL`]) the argument of perigee
/// is 0 and the true anomaly is the argument of latitude; for an equatorial one (`i` below
/// [`EQUATORIAL_TOL`] or above `π −` it) the RAAN is 0 and the angles are measured from ECI's x.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Elements {
    /// Semi-major axis, m (> 0: elliptic orbits only).
    pub a: f64,
    /// Eccentricity, 0 ≤ e < 1.
    pub e: f64,
    /// Inclination, rad, in [0, π].
    pub i: f64,
    /// Right ascension of the ascending node, rad.
    pub raan: f64,
    /// Argument of perigee, rad.
    pub argp: f64,
    /// True anomaly, rad.
    pub true_anomaly: f64,
}

/// Eccentricity below which an orbit counts as circular in [`Elements::from_state`].
pub const CIRCULAR_TOL: f64 = 1e-11;
/// Inclination (rad) below which an orbit counts as equatorial in [`Elements::from_state`].
pub const EQUATORIAL_TOL: f64 = 1e-11;

fn wrap_2pi(a: f64) -> f64 {
    let w = a.rem_euclid(std::f64::consts::TAU);
    if w >= std::f64::consts::TAU {
        0.0
    } else {
        w
    }
}

impl Elements {
    /// Check the values: finite, `a > 0`, `0 ≤ e < 1`, `0 ≤ i ≤ π`, perigee above the body's
    /// surface is not required (a caller may model any orbit).
    pub fn validate(&self) -> Result<()> {
        let all = [self.a, self.e, self.i, self.raan, self.argp, self.true_anomaly];
        let names = ["a", "e", "i", "raan", "argp", "true_anomaly"];
        if let Some(k) = all.iter().position(|v| !v.is_finite()) {
            return Err(SpacearmError::argument(format!("orbit elements: '{}' must be finite, got {}", names[k], all[k])));
        }
        if self.a <= 0.0 {
            return Err(SpacearmError::argument(format!("orbit elements: the semi-major axis a must be > 0 m (elliptic orbits), got {}", self.a)));
        }
        if !(0.0..1.0).contains(&self.e) {
            return Err(SpacearmError::argument(format!("orbit elements: the eccentricity e must be in [0, 1), got {}", self.e)));
        }
        if !(0.0..=std::f64::consts::PI).contains(&self.i) {
            return Err(SpacearmError::argument(format!("orbit elements: the inclination i must be in [0, pi] rad, got {}", self.i)));
        }
        Ok(())
    }

    /// The ECI position and velocity (Vallado, Algorithm 10, COE2RV): the perifocal state
    /// rotated by `R3(−Ω) R1(−i) R3(−ω)`.
    pub fn to_state(&self, mu: f64) -> (Vector3<f64>, Vector3<f64>) {
        let p = self.a * (1.0 - self.e * self.e);
        let (sn, cn) = self.true_anomaly.sin_cos();
        let r_pf = Vector3::new(p * cn / (1.0 + self.e * cn), p * sn / (1.0 + self.e * cn), 0.0);
        let k = (mu / p).sqrt();
        let v_pf = Vector3::new(-k * sn, k * (self.e + cn), 0.0);
        let rot = perifocal_to_eci(self.raan, self.i, self.argp);
        (rot * r_pf, rot * v_pf)
    }

    /// The osculating elements of an ECI state (Vallado, Algorithm 9, RV2COE), with the
    /// conventions of the type's docs for circular and equatorial orbits; angles in [0, 2π).
    pub fn from_state(mu: f64, r: &Vector3<f64>, v: &Vector3<f64>) -> Result<Elements> {
        let rn = r.norm();
        let h = r.cross(v);
        let hn = h.norm();
        if !(rn > 0.0 && hn > 0.0 && rn.is_finite() && hn.is_finite()) {
            return Err(SpacearmError::argument("orbit: the state is not an orbit (zero or non-finite position or angular momentum)"));
        }
        let energy = 0.5 * v.norm_squared() - mu / rn;
        if energy >= 0.0 {
            return Err(SpacearmError::argument(format!("orbit: the state is not bound (specific energy {energy} J/kg >= 0): only elliptic orbits")));
        }
        let a = -mu / (2.0 * energy);
        let e_vec = v.cross(&h) / mu - r / rn;
        let e = e_vec.norm();
        let i = (h.z / hn).clamp(-1.0, 1.0).acos();
        let z = Vector3::z();
        let node = z.cross(&h);
        let nn = node.norm();
        let equatorial = i < EQUATORIAL_TOL || i > std::f64::consts::PI - EQUATORIAL_TOL;
        let circular = e < CIRCULAR_TOL;
        // The reference direction in the orbit plane from which the argument of perigee (or of
        // latitude) is measured: the node, or ECI's x for an equatorial orbit.
        let (raan, node_dir) = if equatorial {
            (0.0, Vector3::x())
        } else {
            let raan = node.y.atan2(node.x);
            (wrap_2pi(raan), node / nn)
        };
        let h_hat = h / hn;
        // Signed angle from `from` to `to` about the orbit normal.
        let angle = |from: &Vector3<f64>, to: &Vector3<f64>| wrap_2pi(h_hat.dot(&from.cross(to)).atan2(from.dot(to)));
        let (argp, nu) = if circular { (0.0, angle(&node_dir, r)) } else { (angle(&node_dir, &e_vec), angle(&e_vec, r)) };
        Ok(Elements { a, e: if circular { 0.0 } else { e }, i, raan, argp, true_anomaly: nu })
    }
}

/// The rotation of the perifocal frame to ECI, `R3(−Ω) R1(−i) R3(−ω)`.
fn perifocal_to_eci(raan: f64, i: f64, argp: f64) -> Matrix3<f64> {
    let r3 = |a: f64| {
        let (s, c) = a.sin_cos();
        Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
    };
    let (s, c) = i.sin_cos();
    let r1 = Matrix3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c);
    r3(raan) * r1 * r3(argp)
}

/// An orbit: the central body, whether J2 acts, and the ECI state at `t = 0`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Orbit {
    /// The central body.
    pub body: CentralBody,
    /// Whether the J2 term acts on the point-mass motion.
    pub j2: bool,
    /// ECI position at `t = 0`, m.
    pub r0: Vector3<f64>,
    /// ECI velocity at `t = 0`, m/s.
    pub v0: Vector3<f64>,
}

/// The most DOPRI5 steps (accepted and rejected) one [`Orbit::propagate`] may take: beyond it
/// the propagation stops with a `SimulationError` naming the time reached and this budget
/// instead of running for minutes (a span of thousands of years, or a step that the error
/// control keeps shrinking). About 1.5 s of propagation, some years of a low orbit.
pub const ORBIT_MAX_STEPS: usize = 5_000_000;

impl Orbit {
    /// An orbit from its osculating elements at `t = 0`.
    pub fn from_elements(body: CentralBody, elements: &Elements, j2: bool) -> Result<Orbit> {
        body.validate()?;
        elements.validate()?;
        let (r0, v0) = elements.to_state(body.mu);
        Ok(Orbit { body, j2, r0, v0 })
    }

    /// A circular orbit of `altitude` above the body's equatorial radius, starting at the
    /// argument of latitude `arg_latitude`; the velocity is the two-body circular speed
    /// `√(μ/a)` (also with J2, whose osculating orbit from this state is then slightly
    /// eccentric; docs/orbit.md).
    ///
    /// The altitude must be finite and > 0: a circular orbit at or below the body's surface
    /// (`altitude <= 0`) runs through the body.
    pub fn circular(body: CentralBody, altitude: f64, inclination: f64, raan: f64, arg_latitude: f64, j2: bool) -> Result<Orbit> {
        if !(altitude.is_finite() && altitude > 0.0) {
            return Err(SpacearmError::argument(format!(
                "orbit: the altitude must be finite and > 0 m (above the central body's surface, radius {} m), got {altitude} m",
                body.radius
            )));
        }
        let el = Elements { a: body.radius + altitude, e: 0.0, i: inclination, raan, argp: 0.0, true_anomaly: arg_latitude };
        Orbit::from_elements(body, &el, j2)
    }

    /// An orbit from an ECI state at `t = 0` (checked: bound, finite).
    pub fn from_state(body: CentralBody, r0: Vector3<f64>, v0: Vector3<f64>, j2: bool) -> Result<Orbit> {
        body.validate()?;
        Elements::from_state(body.mu, &r0, &v0)?;
        Ok(Orbit { body, j2, r0, v0 })
    }

    /// The osculating elements at `t = 0`.
    pub fn elements(&self) -> Elements {
        Elements::from_state(self.body.mu, &self.r0, &self.v0).expect("an Orbit holds a bound state")
    }

    /// Mean motion of the osculating orbit at `t = 0`, `n = √(μ/a³)`, rad/s.
    pub fn mean_motion(&self) -> f64 {
        let a = self.elements().a;
        (self.body.mu / (a * a * a)).sqrt()
    }

    /// Period of the osculating orbit at `t = 0`, `2π/n`, s.
    pub fn period(&self) -> f64 {
        std::f64::consts::TAU / self.mean_motion()
    }

    /// The point-mass acceleration at ECI position `r`: two-body, plus J2 if enabled.
    pub fn acceleration(&self, r: &Vector3<f64>) -> Vector3<f64> {
        point_mass_acceleration(&self.body, self.j2, r)
    }

    /// The ECI state `(r, v)` at one time `t` (finite, ≥ 0, s) by [`Orbit::propagate`] with
    /// `rtol`: the one check of a single time every door makes.
    pub fn state_at(&self, t: f64, rtol: f64) -> Result<(Vector3<f64>, Vector3<f64>)> {
        if !(t.is_finite() && t >= 0.0) {
            return Err(SpacearmError::argument(format!("t must be finite and >= 0 s, got {t}")));
        }
        Ok(self.propagate(&[t], rtol)?[0])
    }

    /// The ECI states at `times` (non-decreasing, ≥ 0, s), by DOPRI5 on the point-mass equations
    /// with `rtol` (and an absolute tolerance of `rtol` times the orbit's radius and speed).
    pub fn propagate(&self, times: &[f64], rtol: f64) -> Result<Vec<(Vector3<f64>, Vector3<f64>)>> {
        if !(rtol.is_finite() && rtol > 0.0) {
            return Err(SpacearmError::argument(format!("orbit: rtol must be finite and > 0, got {rtol}")));
        }
        if let Some(k) = times.iter().position(|t| !(t.is_finite() && *t >= 0.0)) {
            return Err(SpacearmError::argument(format!("orbit: times must be finite and >= 0 s, but entry {k} is {}", times[k])));
        }
        if let Some(k) = times.windows(2).position(|w| w[1] < w[0]) {
            return Err(SpacearmError::argument(format!("orbit: times must be non-decreasing, but entry {} is less than entry {k}", k + 1)));
        }
        let mut sys = PointMass { orbit: *self, n_evals: 0 };
        let mut y = [self.r0.x, self.r0.y, self.r0.z, self.v0.x, self.v0.y, self.v0.z];
        // An absolute tolerance per component scaled by the orbit's size, so that a component
        // passing through zero does not force tiny steps.
        let atol = rtol * self.r0.norm().min(self.v0.norm() * self.period());
        let mut dp = Dopri5::new(6, rtol, atol);
        let end = times.last().copied().unwrap_or(0.0);
        let mut out = Vec::with_capacity(times.len());
        let mut k = 0;
        let mut t = 0.0;
        while k < times.len() && times[k] == 0.0 {
            out.push((self.r0, self.v0));
            k += 1;
        }
        if k == times.len() {
            return Ok(out);
        }
        let mut h = dp.initial_step(&mut sys, t, &y, end)?;
        let mut y_out = [0.0; 6];
        let mut steps = 0usize;
        while k < times.len() {
            steps += 1;
            if steps > ORBIT_MAX_STEPS {
                return Err(SpacearmError::Simulation(format!(
                    "orbit propagation used its budget of {ORBIT_MAX_STEPS} DOPRI5 steps (spacearm_core::scenario::orbit::ORBIT_MAX_STEPS) \
                     and reached only t = {t:.6e} s of {end:.6e} s; propagate over a shorter span or loosen rtol"
                )));
            }
            let remaining = end - t;
            if h >= remaining || remaining - h < 1e-12 * end {
                h = remaining;
            }
            let outcome = dp.try_step(&mut sys, t, h, &mut y)?;
            if outcome.accepted {
                let t_new = if h == remaining { end } else { t + h };
                while k < times.len() && times[k] <= t_new {
                    if times[k] == t_new {
                        y_out.copy_from_slice(&y);
                    } else {
                        dp.dense_output(times[k], &mut y_out);
                    }
                    out.push((Vector3::new(y_out[0], y_out[1], y_out[2]), Vector3::new(y_out[3], y_out[4], y_out[5])));
                    k += 1;
                }
                t = t_new;
            }
            h = outcome.next_h;
            if !(h.is_finite() && h > 1e-14 * end) {
                return Err(SpacearmError::Simulation(format!("orbit propagation: the step size fell to {h:e} s at t = {t} s (an orbit through the body's centre?)")));
            }
        }
        Ok(out)
    }

    /// The J2 secular rates of the orbit at `t = 0` (Vallado eq. 9-41), rad/s:
    /// `(Ω̇, ω̇)`. Computed with the body's J2 whether or not this orbit propagates with it.
    pub fn j2_secular_rates(&self) -> (f64, f64) {
        j2_secular_rates(&self.body, &self.elements())
    }
}

/// The J2 secular rates `(Ω̇, ω̇)` of orbit `el` about `body` (Vallado eq. 9-41), rad/s.
pub fn j2_secular_rates(body: &CentralBody, el: &Elements) -> (f64, f64) {
    let n = (body.mu / el.a.powi(3)).sqrt();
    let p = el.a * (1.0 - el.e * el.e);
    let k = n * body.j2 * (body.radius / p).powi(2);
    let (s, c) = el.i.sin_cos();
    (-1.5 * k * c, 0.75 * k * (4.0 - 5.0 * s * s))
}

/// The point-mass acceleration at ECI position `r` (Vallado eq. 8-30): two-body, plus the J2
/// term if `j2`.
pub fn point_mass_acceleration(body: &CentralBody, j2: bool, r: &Vector3<f64>) -> Vector3<f64> {
    let r2 = r.norm_squared();
    let rn = r2.sqrt();
    let mut a = -body.mu / (r2 * rn) * r;
    if j2 {
        let z2 = r.z * r.z / r2;
        let k = -1.5 * body.j2 * body.mu * body.radius * body.radius / (r2 * r2 * rn);
        a += k * Vector3::new(r.x * (1.0 - 5.0 * z2), r.y * (1.0 - 5.0 * z2), r.z * (3.0 - 5.0 * z2));
    }
    a
}

/// The gravity-gradient tensor of the two-body field at ECI position `r`,
/// `G = μ/|r|³ (3 r̂ r̂ᵀ − 1)`, 1/s² (the tidal acceleration at `ρ` from `r` is `G ρ` to first
/// order; J2's gradient is not included).
pub fn gravity_gradient_tensor(mu: f64, r: &Vector3<f64>) -> Matrix3<f64> {
    let rn = r.norm();
    let rh = r / rn;
    mu / (rn * rn * rn) * (3.0 * rh * rh.transpose() - Matrix3::identity())
}

/// The gravity-gradient torque about a body's CM, `N = axial(I G − G I)` with `I` its inertia
/// about the CM and `G` the gradient, both in the same axes (for the two-body `G`,
/// `3 μ/|r|³ r̂ × (I r̂)`).
pub fn gravity_gradient_torque(gradient: &Matrix3<f64>, inertia: &Matrix3<f64>) -> Vector3<f64> {
    let a = inertia * gradient - gradient * inertia;
    // axial(A) of a skew A = [w]×: w = (A32, A13, A21).
    Vector3::new(a[(2, 1)], a[(0, 2)], a[(1, 0)])
}

/// The LVLH (Hill) frame of an ECI state: the rotation LVLH → ECI, whose columns are
/// `x̂ = r̂` (radial), `ẑ = (r × v)/|r × v|` (orbit normal), `ŷ = ẑ × x̂`.
pub fn lvlh_to_eci(r: &Vector3<f64>, v: &Vector3<f64>) -> Matrix3<f64> {
    let x = r.normalize();
    let z = r.cross(v).normalize();
    let y = z.cross(&x);
    Matrix3::from_columns(&[x, y, z])
}

/// The angular velocity of the LVLH frame in ECI, `(r × v)/|r|²` (exact for the direction of
/// `r`; the frame's rotation about `r̂` from out-of-plane accelerations such as J2 is neglected).
pub fn lvlh_rate(r: &Vector3<f64>, v: &Vector3<f64>) -> Vector3<f64> {
    r.cross(v) / r.norm_squared()
}

/// A relative state in LVLH: position `[x radial, y along-track, z orbit normal]` (m) and its
/// rate of change seen in the rotating LVLH frame (m/s).
pub type RelativeState = [f64; 6];

/// The Clohessy–Wiltshire (Hill) closed-form solution at `t` (s) of the linearized relative
/// motion about a circular orbit of mean motion `n` (rad/s), from `rel0` at `t = 0` (Schaub &
/// Junkins, §14.4; Vallado eq. 6-66, with x radial, y along-track, z orbit normal):
/// `ẍ − 3n²x − 2nẏ = 0`, `ÿ + 2nẋ = 0`, `z̈ + n²z = 0`.
pub fn clohessy_wiltshire(n: f64, rel0: &RelativeState, t: f64) -> RelativeState {
    let [x0, y0, z0, vx0, vy0, vz0] = *rel0;
    let (s, c) = (n * t).sin_cos();
    let x = (4.0 - 3.0 * c) * x0 + s / n * vx0 + 2.0 / n * (1.0 - c) * vy0;
    let y = 6.0 * (s - n * t) * x0 + y0 - 2.0 / n * (1.0 - c) * vx0 + (4.0 * s - 3.0 * n * t) / n * vy0;
    let z = c * z0 + s / n * vz0;
    let vx = 3.0 * n * s * x0 + c * vx0 + 2.0 * s * vy0;
    let vy = -6.0 * n * (1.0 - c) * x0 - 2.0 * s * vx0 + (4.0 * c - 3.0) * vy0;
    let vz = -n * s * z0 + c * vz0;
    [x, y, z, vx, vy, vz]
}

/// The initial relative state of a drift-free CW "safety ellipse" about a point `along_track`
/// metres ahead (or behind): `x = a sin nt`, `y = y_c + 2a cos nt`, `z = b cos nt`, so the
/// target never crosses the chaser's along-track line inside the ellipse (a radial half-axis
/// `a`, along-track half-axis `2a`, cross-track amplitude `b`).
pub fn safety_ellipse(n: f64, radial: f64, cross_track: f64, along_track: f64) -> RelativeState {
    [0.0, along_track + 2.0 * radial, cross_track, radial * n, 0.0, 0.0]
}

impl Orbit {
    /// The ECI state of a point at relative state `rel` (LVLH of `(r, v)`) from `(r, v)`:
    /// position `r + C ρ`, velocity `v + C ρ̇ + ω × C ρ` with `C` LVLH → ECI and `ω` the LVLH rate.
    pub fn relative_to_eci(r: &Vector3<f64>, v: &Vector3<f64>, rel: &RelativeState) -> (Vector3<f64>, Vector3<f64>) {
        let c = lvlh_to_eci(r, v);
        let rho = c * Vector3::new(rel[0], rel[1], rel[2]);
        let rho_dot = c * Vector3::new(rel[3], rel[4], rel[5]);
        (r + rho, v + rho_dot + lvlh_rate(r, v).cross(&rho))
    }

    /// The relative state in the LVLH of `(r, v)` of a point at ECI `(r2, v2)`.
    pub fn eci_to_relative(r: &Vector3<f64>, v: &Vector3<f64>, r2: &Vector3<f64>, v2: &Vector3<f64>) -> RelativeState {
        let c = lvlh_to_eci(r, v);
        let rho = r2 - r;
        let rho_dot = v2 - v - lvlh_rate(r, v).cross(&rho);
        let p = c.transpose() * rho;
        let q = c.transpose() * rho_dot;
        [p.x, p.y, p.z, q.x, q.y, q.z]
    }

    /// A run's state (relative to the orbit's point `O`, ECI axes; docs/orbit.md) of a point at
    /// relative state `rel` in the LVLH of a centre at run state `(c, c_dot)`, `O` at ECI
    /// `(r_o, v_o)`: `ρ = c + C ρ_L`, `ρ̇ = ċ + C ρ̇_L + ω × C ρ_L` with `C` (LVLH → ECI) and `ω`
    /// the frame and rate of the centre's orbit (computed without forming ECI-sized differences).
    pub fn lvlh_to_run(r_o: &Vector3<f64>, v_o: &Vector3<f64>, c: &Vector3<f64>, c_dot: &Vector3<f64>, rel: &RelativeState) -> (Vector3<f64>, Vector3<f64>) {
        let (rc, vc) = (r_o + c, v_o + c_dot);
        let m = lvlh_to_eci(&rc, &vc);
        let rho = m * Vector3::new(rel[0], rel[1], rel[2]);
        (c + rho, c_dot + m * Vector3::new(rel[3], rel[4], rel[5]) + lvlh_rate(&rc, &vc).cross(&rho))
    }

    /// The inverse of [`Orbit::lvlh_to_run`]: the LVLH relative state about the centre `(c,
    /// c_dot)` of a point at run state `(p, p_dot)`, `O` at ECI `(r_o, v_o)`.
    pub fn run_to_lvlh(r_o: &Vector3<f64>, v_o: &Vector3<f64>, c: &Vector3<f64>, c_dot: &Vector3<f64>, p: &Vector3<f64>, p_dot: &Vector3<f64>) -> RelativeState {
        let (rc, vc) = (r_o + c, v_o + c_dot);
        let m = lvlh_to_eci(&rc, &vc);
        let rho = p - c;
        let rho_dot = p_dot - c_dot - lvlh_rate(&rc, &vc).cross(&rho);
        let (a, b) = (m.transpose() * rho, m.transpose() * rho_dot);
        [a.x, a.y, a.z, b.x, b.y, b.z]
    }

    /// The exact relative motion, in this orbit's LVLH, of a second point mass started at
    /// `rel0` (LVLH at `t = 0`) and propagated on its own orbit (the same body, J2 as this orbit):
    /// one relative state per time of `times`.
    pub fn relative_motion(&self, rel0: &RelativeState, times: &[f64], rtol: f64) -> Result<Vec<RelativeState>> {
        if let Some(k) = rel0.iter().position(|v| !v.is_finite()) {
            return Err(SpacearmError::argument(format!("relative state: entry {k} must be finite, got {}", rel0[k])));
        }
        let (r2, v2) = Orbit::relative_to_eci(&self.r0, &self.v0, rel0);
        let other = Orbit::from_state(self.body, r2, v2, self.j2)?;
        let mine = self.propagate(times, rtol)?;
        let theirs = other.propagate(times, rtol)?;
        Ok(mine.iter().zip(&theirs).map(|((r, v), (r2, v2))| Orbit::eci_to_relative(r, v, r2, v2)).collect())
    }
}

/// Each body's tidal wrench under gradient `g`, the kinematics in `data` current and the
/// positions measured from the point where `g` is taken: force `mᵢ G ρᵢ` at the CM and torque
/// `axial(Iᵢ G − G Iᵢ)` about it, in the frame of `data` (the one rule of the simulation loop and
/// of [`tidal_torques`]).
pub fn tidal_wrenches_into(model: &Model, data: &Data, g: &Matrix3<f64>, out: &mut Vec<ExternalWrench>) {
    for b in 0..model.n_bodies() {
        let force = model.mass_properties(b).mass * (g * data.com_in_world[b]);
        let torque = gravity_gradient_torque(g, &data.inertia_in_world[b]);
        out.push(ExternalWrench { body: b, offset: Vector3::zeros(), force, torque });
    }
}

/// The gravity-gradient torques on a system at configuration `x` (relative to the orbit's
/// point at ECI `r`, ECI axes): the per-body wrenches `[force; torque about the body's CM]`, the
/// total torque about the system CM, and the part of it from every body but the base (the arm's
/// disturbance of the attitude). An analysis quantity (docs/orbit.md).
pub fn tidal_torques(model: &Model, x: &[f64], mu: f64, r: &Vector3<f64>) -> Result<(Vec<[f64; 6]>, Vector3<f64>, Vector3<f64>)> {
    if !(r.iter().all(|v| v.is_finite()) && r.norm() > 0.0) {
        return Err(SpacearmError::argument("the orbit position must be finite and non-zero"));
    }
    let mut data = Data::new(model);
    forward_kinematics(model, &mut data, x)?;
    let g = gravity_gradient_tensor(mu, r);
    let mut w = Vec::with_capacity(model.n_bodies());
    tidal_wrenches_into(model, &data, &g, &mut w);
    let rg = center_of_mass_from_data(model, &data);
    let about = |e: &ExternalWrench| (data.com_in_world[e.body] - rg).cross(&e.force) + e.torque;
    let total: Vector3<f64> = w.iter().map(about).sum();
    let arm: Vector3<f64> = w.iter().skip(1).map(about).sum();
    let rows = w.iter().map(|e| [e.force.x, e.force.y, e.force.z, e.torque.x, e.torque.y, e.torque.z]).collect();
    Ok((rows, total, arm))
}

/// The point-mass equations as an ODE `y = [r; v]`.
struct PointMass {
    orbit: Orbit,
    n_evals: usize,
}

impl OdeSystem for PointMass {
    fn dim(&self) -> usize {
        6
    }
    fn project(&self, _y: &mut [f64]) {}
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<()> {
        self.n_evals += 1;
        let r = Vector3::new(y[0], y[1], y[2]);
        let a = self.orbit.acceleration(&r);
        dy[..3].copy_from_slice(&y[3..6]);
        dy[3..].copy_from_slice(a.as_slice());
        Ok(())
    }
}

/// A reference orbit propagated once over `[0, end]` and read at any time in between by quintic
/// Hermite interpolation of `(r, v, a)` at nodes a fixed fraction of the period apart: the
/// orbit the simulation loop reads at every stage.
#[derive(Debug, Clone)]
pub struct OrbitTrack {
    orbit: Orbit,
    h: f64,
    nodes: Vec<(Vector3<f64>, Vector3<f64>, Vector3<f64>)>,
}

/// Nodes per period of an [`OrbitTrack`] (interpolation error ~ `(2π/1000)⁶ |r| / 720`, below
/// a micrometre in low orbit).
pub const TRACK_NODES_PER_PERIOD: f64 = 1000.0;

/// Nodes per propagated chunk of an [`OrbitTrack`] (a tenth of a period).
pub const TRACK_CHUNK: usize = 100;

impl OrbitTrack {
    /// Propagate `orbit` over (at least) `[0, end]` (rtol 1e-13). The nodes are
    /// [`TRACK_NODES_PER_PERIOD`] per period whatever `end` is, propagated in chunks of
    /// [`TRACK_CHUNK`] nodes each from the last node of the one before: a track built for a
    /// long run and one extended step by step ([`OrbitTrack::extend_to`]) hold the same nodes, so
    /// stepping a run and simulating it give the same records.
    pub fn new(orbit: &Orbit, end: f64) -> Result<OrbitTrack> {
        let h = orbit.period() / TRACK_NODES_PER_PERIOD;
        let mut track = OrbitTrack { orbit: *orbit, h, nodes: vec![(orbit.r0, orbit.v0, orbit.acceleration(&orbit.r0))] };
        track.extend_to(end.max(h))?;
        Ok(track)
    }

    /// The orbit tracked.
    pub fn orbit(&self) -> &Orbit {
        &self.orbit
    }

    /// The end of the tracked span, s.
    pub fn end(&self) -> f64 {
        (self.nodes.len() - 1) as f64 * self.h
    }

    /// Extend the track by whole chunks so that it covers `[0, t]`: the orbit propagated on
    /// from its last node (a run stepped past the duration it was built for).
    pub fn extend_to(&mut self, t: f64) -> Result<()> {
        if t <= self.end() {
            return Ok(());
        }
        let chunks = ((t - self.end()) / (TRACK_CHUNK as f64 * self.h)).ceil().max(1.0) as usize;
        let total = self.nodes.len() + chunks * TRACK_CHUNK;
        crate::admission::admit(
            format_args!("an orbit track of {total} nodes"),
            crate::admission::bytes_of::<f64>(9.0 * total as f64),
            "simulate a shorter duration",
        )?;
        let times: Vec<f64> = (1..=TRACK_CHUNK).map(|k| k as f64 * self.h).collect();
        for _ in 0..chunks {
            let (r, v, _) = *self.nodes.last().expect("a track has nodes");
            let from = Orbit { r0: r, v0: v, ..self.orbit };
            for (r, v) in from.propagate(&times, 1e-13)? {
                let a = self.orbit.acceleration(&r);
                self.nodes.push((r, v, a));
            }
        }
        Ok(())
    }

    /// ECI position and velocity at `t` (clamped to the tracked span).
    pub fn state(&self, t: f64) -> (Vector3<f64>, Vector3<f64>) {
        let last = self.nodes.len() - 1;
        let k = ((t / self.h).floor().max(0.0) as usize).min(last.saturating_sub(1));
        if last == 0 {
            return (self.nodes[0].0, self.nodes[0].1);
        }
        let s = ((t - k as f64 * self.h) / self.h).clamp(0.0, 1.0);
        let (p0, v0, a0) = self.nodes[k];
        let (p1, v1, a1) = self.nodes[k + 1];
        let h = self.h;
        // Quintic Hermite basis on [0, 1] and its derivative.
        let s2 = s * s;
        let s3 = s2 * s;
        let s4 = s3 * s;
        let s5 = s4 * s;
        let h00 = 1.0 - 10.0 * s3 + 15.0 * s4 - 6.0 * s5;
        let h10 = s - 6.0 * s3 + 8.0 * s4 - 3.0 * s5;
        let h20 = 0.5 * s2 - 1.5 * s3 + 1.5 * s4 - 0.5 * s5;
        let h01 = 10.0 * s3 - 15.0 * s4 + 6.0 * s5;
        let h11 = -4.0 * s3 + 7.0 * s4 - 3.0 * s5;
        let h21 = 0.5 * s3 - s4 + 0.5 * s5;
        let d00 = -30.0 * s2 + 60.0 * s3 - 30.0 * s4;
        let d10 = 1.0 - 18.0 * s2 + 32.0 * s3 - 15.0 * s4;
        let d20 = s - 4.5 * s2 + 6.0 * s3 - 2.5 * s4;
        let d01 = 30.0 * s2 - 60.0 * s3 + 30.0 * s4;
        let d11 = -12.0 * s2 + 28.0 * s3 - 15.0 * s4;
        let d21 = 1.5 * s2 - 4.0 * s3 + 2.5 * s4;
        let r = h00 * p0 + h * h10 * v0 + h * h * h20 * a0 + h01 * p1 + h * h11 * v1 + h * h * h21 * a1;
        let v = (d00 * p0 + h * d10 * v0 + h * h * d20 * a0 + d01 * p1 + h * d11 * v1 + h * h * d21 * a1) / h;
        (r, v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_state_at_one_time_is_the_propagation_to_it_and_refuses_a_bad_time() {
        let o = Orbit::circular(EARTH, 500e3, 0.9, 0.3, 0.1, true).unwrap();
        for t in [0.0, 1.0, 1234.5] {
            assert_eq!(o.state_at(t, 1e-12).unwrap(), o.propagate(&[t], 1e-12).unwrap()[0]);
        }
        for t in [-1.0, f64::NAN, f64::INFINITY] {
            let e = o.state_at(t, 1e-12).unwrap_err();
            assert!(matches!(e, SpacearmError::InvalidArgument(_)) && e.to_string().contains("t must be finite and >= 0 s"), "{e}");
        }
    }

    #[test]
    fn a_circular_orbit_is_above_the_surface_and_a_propagation_has_a_budget() {
        for h in [0.0, -100e3, -EARTH.radius + 1.0, f64::NAN] {
            let err = Orbit::circular(EARTH, h, 0.0, 0.0, 0.0, false).unwrap_err().to_string();
            assert!(err.contains("above the central body's surface"), "{err}");
        }
        let o = Orbit::circular(EARTH, 1.0, 0.0, 0.0, 0.0, false).unwrap();
        let err = o.propagate(&[1e12], 1e-12).unwrap_err().to_string();
        assert!(err.contains(&format!("budget of {ORBIT_MAX_STEPS} DOPRI5 steps")) && err.contains("reached only t = "), "{err}");
    }

    #[test]
    fn elements_round_trip() {
        let el = Elements { a: 7.2e6, e: 0.05, i: 0.9, raan: 1.1, argp: 2.3, true_anomaly: 4.0 };
        let (r, v) = el.to_state(EARTH.mu);
        let back = Elements::from_state(EARTH.mu, &r, &v).unwrap();
        assert!((back.a - el.a).abs() < 1e-6);
        for (x, y) in [(back.e, el.e), (back.i, el.i), (back.raan, el.raan), (back.argp, el.argp), (back.true_anomaly, el.true_anomaly)] {
            assert!((x - y).abs() < 1e-10, "{x} vs {y}");
        }
        // Vis-viva, an independent check of the speed.
        assert!((v.norm_squared() - EARTH.mu * (2.0 / r.norm() - 1.0 / el.a)).abs() < 1e-6);
    }

    #[test]
    fn gradient_torque_is_the_closed_form() {
        let r = Vector3::new(3.0e6, -5.0e6, 2.0e6);
        let g = gravity_gradient_tensor(EARTH.mu, &r);
        let i = Matrix3::new(10.0, 1.0, -2.0, 1.0, 20.0, 0.5, -2.0, 0.5, 30.0);
        let rh = r.normalize();
        let closed = 3.0 * EARTH.mu / r.norm().powi(3) * rh.cross(&(i * rh));
        assert!((gravity_gradient_torque(&g, &i) - closed).norm() < 1e-12 * closed.norm());
    }

    #[test]
    fn lvlh_to_run_round_trips_and_agrees_with_eci() {
        let o = Orbit::circular(EARTH, 500e3, 0.9, 0.3, 0.2, false).unwrap();
        let (c, cd) = (Vector3::new(0.3, -0.1, 0.2), Vector3::new(1e-3, 2e-3, -1e-3));
        let rel = [1.0, -20.0, 3.0, 0.01, -0.02, 0.005];
        let (p, pd) = Orbit::lvlh_to_run(&o.r0, &o.v0, &c, &cd, &rel);
        let back = Orbit::run_to_lvlh(&o.r0, &o.v0, &c, &cd, &p, &pd);
        for k in 0..6 {
            assert!((back[k] - rel[k]).abs() < 1e-12, "{k}");
        }
        let (r2, v2) = Orbit::relative_to_eci(&(o.r0 + c), &(o.v0 + cd), &rel);
        assert!(((r2 - o.r0) - p).norm() < 1e-8 && ((v2 - o.v0) - pd).norm() < 1e-11);
    }

    #[test]
    fn track_matches_the_propagation() {
        let o = Orbit::circular(EARTH, 500e3, 0.9, 0.3, 0.2, true).unwrap();
        let track = OrbitTrack::new(&o, 1234.5).unwrap();
        let times = [0.0, 10.3, 600.7, 1234.5];
        let direct = o.propagate(&times, 1e-13).unwrap();
        for (t, (r, v)) in times.iter().zip(direct) {
            let (ri, vi) = track.state(*t);
            assert!((ri - r).norm() < 1e-5, "t {t}: {}", (ri - r).norm());
            assert!((vi - v).norm() < 1e-7, "t {t}: v {}", (vi - v).norm());
        }
    }
}
