//! A torque-free rigid body (a capture target) and a point fixed to it, propagated natively:
//! the target's motion for [`crate::scenario::reference::PointReference::FreeBody`] (RMRC towards a
//! tumbling grasp point) and for the capture's records (docs/capture.md).
//!
//! State (13): `[r (3), quat [x, y, z, w] (4), v (3), ω (3)]`, the CM position and velocity and
//! the angular velocity in 𝒥, the attitude mapping body axes to 𝒥 (docs/conventions.md).
//!
//! Nothing acts on the body, so its linear momentum `m v` and its angular momentum about the CM
//! in 𝒥, `L = R I Rᵀ ω`, are constant: `r(t) = r₀ + t v`, and only the attitude is integrated,
//! `quaṫ = ½ [ω; 0] ⊗ quat` with `ω = R I⁻¹ Rᵀ L` ([`crate::math::rotations::quaternion_rate`]),
//! by classical RK4 with the quaternion re-normalized after each step. `P` and `L` are
//! therefore conserved exactly and only the attitude carries integration error (fourth order
//! in the step).
//!
//! **In orbit** ([`FreeBody::in_orbit`]): the state is relative to the orbit's point `O` of the
//! run (ECI axes, docs/orbit.md), and gravity's non-uniform part acts: the CM moves under the
//! exact relative acceleration `ρ̈ = g(r_O + ρ) − g(r_O)` (two-body, plus J2 if the orbit has it;
//! `r_O` from the run's [`OrbitTrack`], the same nodes as the simulation loop's), and the angular
//! momentum about the CM under the gravity-gradient torque `L̇ = axial(I_𝒥 G − G I_𝒥)` (`G` the
//! two-body gradient at `r_O`, [`crate::scenario::orbit::gravity_gradient_torque`]). Then the whole
//! state `[r, v, quat, L]` is integrated by classical RK4 on the grid (momenta are no longer
//! constant).
//!
//! Times are measured from the state the body was built with. The attitude is kept on a grid of
//! fixed steps `h` (extended as later times are asked for, so evaluating the body at the
//! integrator's stage times costs one RK4 step at most); a time between two grid points is
//! reached by one RK4 step of the remainder from the grid point below.

use nalgebra::{Matrix3, UnitQuaternion, Quaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::error::{check_finite, Result, SpacearmError};
use crate::math::rotations::{normalize_xyzw, quaternion_rate};
use crate::scenario::orbit::{gravity_gradient_tensor, gravity_gradient_torque, Orbit, OrbitTrack};

/// A body's inertia about its CM in its axes, kg·m²: three principal moments, a 3×3 matrix
/// (rows), or nine numbers row-major.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum InertiaSpec {
    /// Principal moments.
    Principal([f64; 3]),
    /// Rows of the matrix.
    Matrix([[f64; 3]; 3]),
    /// Nine numbers, row-major.
    Flat([f64; 9]),
}

impl InertiaSpec {
    /// The matrix.
    pub fn matrix(&self) -> Matrix3<f64> {
        match self {
            InertiaSpec::Principal(d) => Matrix3::from_diagonal(&Vector3::from(*d)),
            InertiaSpec::Matrix(m) => Matrix3::from_fn(|i, j| m[i][j]),
            InertiaSpec::Flat(v) => Matrix3::from_row_slice(v),
        }
    }
}

/// The description of a point fixed to a torque-free rigid body (a tumbling target's grasp
/// point), read by every door: the body of a free-body point reference
/// ([`crate::control::spec::PointReferenceSpec::FreeBody`]) and of an optimal-control point cost's
/// moving target ([`crate::optimal::costs::MovingPoint`]). [`FreeBodySpec::build`] checks it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FreeBodySpec {
    /// The body's inertia about its CM in its axes, kg·m².
    pub inertia: InertiaSpec,
    /// The body's 13-state `[r, quat xyzw, v, ω]` in 𝒥 at time 0 (of the simulation; for a
    /// cost, of the references' clock).
    pub state: Vec<f64>,
    /// The point from the body's CM, body axes, m.
    #[serde(default)]
    pub offset: [f64; 3],
    /// The attitude step of the body's propagation, s.
    #[serde(default = "default_free_body_step")]
    pub step: f64,
}

/// The default attitude step of a free body's propagation, s.
pub(crate) fn default_free_body_step() -> f64 {
    1e-3
}

impl FreeBodySpec {
    /// The body (checked by [`FreeBody::new`]).
    pub fn build(&self) -> Result<FreeBody> {
        FreeBody::new(self.inertia.matrix(), &self.state, Vector3::from(self.offset), self.step)
    }

    /// The body, in `orbit` when one is given (the orbit checked by [`Orbit::from_state`], the
    /// body by [`FreeBody::in_orbit`]): a free-body point reference's and a point cost's target.
    pub fn build_in(&self, orbit: Option<&Orbit>) -> Result<FreeBody> {
        let body = self.build()?;
        match orbit {
            Some(o) => body.in_orbit(&Orbit::from_state(o.body, o.r0, o.v0, o.j2)?),
            None => Ok(body),
        }
    }
}

/// A node of the grid: attitude `[x, y, z, w]`, and in orbit the CM position and velocity and
/// the angular momentum about the CM (in 𝒥); torque-free, only `q` evolves.
#[derive(Debug, Clone, Copy)]
struct Node {
    q: [f64; 4],
    r: Vector3<f64>,
    v: Vector3<f64>,
    l: Vector3<f64>,
}

/// A torque-free rigid body with a point fixed to it.
#[derive(Debug, Clone)]
pub struct FreeBody {
    inertia: Matrix3<f64>,
    inertia_inv: Matrix3<f64>,
    r0: Vector3<f64>,
    v: Vector3<f64>,
    /// Angular momentum about the CM, in 𝒥 (constant).
    l_world: Vector3<f64>,
    offset: Vector3<f64>,
    step: f64,
    grid: Vec<Node>,
    /// In orbit: the track of the run's point `O` (the tidal field's source).
    track: Option<Box<OrbitTrack>>,
}

fn rotation(q: &[f64; 4]) -> Matrix3<f64> {
    UnitQuaternion::from_quaternion(Quaternion::new(q[3], q[0], q[1], q[2])).to_rotation_matrix().into_inner()
}

impl FreeBody {
    /// A body of inertia `inertia` (about its CM, body axes; symmetric positive definite) in
    /// `state` (13, see the module docs; the quaternion need not be unit) with the point at
    /// `offset` from the CM (body axes, m); `step` h (s, > 0) of the attitude grid.
    pub fn new(inertia: Matrix3<f64>, state: &[f64], offset: Vector3<f64>, step: f64) -> Result<Self> {
        if state.len() != 13 {
            return Err(SpacearmError::Dimension { what: "free-body state".into(), expected: "13 ([r, quat xyzw, v, w])".into(), got: state.len() });
        }
        check_finite("free-body state", state)?;
        check_finite("free-body inertia", inertia.as_slice())?;
        check_finite("free-body point offset", offset.as_slice())?;
        if !(step.is_finite() && step > 0.0) {
            return Err(SpacearmError::argument(format!("free-body step must be finite and > 0, got {step}")));
        }
        if (inertia - inertia.transpose()).abs().max() > 1e-12 * inertia.abs().max() {
            return Err(SpacearmError::argument(format!("free-body inertia must be symmetric, got {inertia}")));
        }
        let inertia_inv = inertia
            .cholesky()
            .map(|c| c.inverse())
            .ok_or_else(|| SpacearmError::argument(format!("free-body inertia must be positive definite, got {inertia}")))?;
        let mut q = [state[3], state[4], state[5], state[6]];
        let norm = q.iter().map(|v| v * v).sum::<f64>().sqrt();
        if !(norm > 1e-12) {
            return Err(SpacearmError::argument(format!("free-body quaternion must be non-zero, got {q:?}")));
        }
        normalize_xyzw(&mut q);
        let r = rotation(&q);
        let w = Vector3::new(state[10], state[11], state[12]);
        let l_world = r * (inertia * (r.transpose() * w));
        Ok(FreeBody {
            inertia,
            inertia_inv,
            r0: Vector3::new(state[0], state[1], state[2]),
            v: Vector3::new(state[7], state[8], state[9]),
            l_world,
            offset,
            step,
            grid: vec![Node { q, r: Vector3::new(state[0], state[1], state[2]), v: Vector3::new(state[7], state[8], state[9]), l: l_world }],
            track: None,
        })
    }

    /// The same body in orbit (module docs): its state relative to the point `O` of `orbit` (the
    /// run's origin, ECI axes) at time 0, moving under gravity's tidal part and turning under
    /// its gravity-gradient torque.
    pub fn in_orbit(mut self, orbit: &Orbit) -> Result<Self> {
        let track = OrbitTrack::new(orbit, 16.0 * self.step)?;
        self.track = Some(Box::new(track));
        Ok(self)
    }

    /// Whether the body moves in orbit ([`FreeBody::in_orbit`]).
    pub fn is_in_orbit(&self) -> bool {
        self.track.is_some()
    }

    /// In orbit: the tidal acceleration of the CM and the gravity-gradient torque at time `t`
    /// for a node; torque-free: zeros.
    fn tidal(&mut self, t: f64, n: &Node) -> Result<(Vector3<f64>, Vector3<f64>)> {
        let Some(track) = self.track.as_mut() else {
            return Ok((Vector3::zeros(), Vector3::zeros()));
        };
        track.extend_to(t)?;
        let (ro, _) = track.state(t);
        let orbit = *track.orbit();
        let acc = orbit.acceleration(&(ro + n.r)) - orbit.acceleration(&ro);
        let g = gravity_gradient_tensor(orbit.body.mu, &ro);
        let rot = rotation(&n.q);
        let torque = gravity_gradient_torque(&g, &(rot * self.inertia * rot.transpose()));
        Ok((acc, torque))
    }

    /// The body's inertia about its CM, body axes.
    pub fn inertia(&self) -> &Matrix3<f64> {
        &self.inertia
    }

    /// The angular velocity in 𝒥 at attitude `q` with angular momentum `l` (𝒥, about the CM):
    /// `ω = R I⁻¹ Rᵀ L`.
    fn omega(&self, q: &[f64; 4], l: &Vector3<f64>) -> Vector3<f64> {
        let r = rotation(q);
        r * (self.inertia_inv * (r.transpose() * l))
    }

    /// The node's rates at `t`: `(q̇, ṙ, v̇, L̇)`.
    fn rates(&mut self, t: f64, n: &Node) -> Result<([f64; 4], Vector3<f64>, Vector3<f64>, Vector3<f64>)> {
        let qd = quaternion_rate(&n.q, &self.omega(&n.q, &n.l));
        let (acc, torque) = self.tidal(t, n)?;
        Ok((qd, n.v, acc, torque))
    }

    /// One classical RK4 step from node `n` at time `t` (the quaternion re-normalized; without
    /// an orbit `r`, `v`, `L` stay as they are: the CM's motion is in closed form).
    fn rk4(&mut self, n: &Node, t: f64, h: f64) -> Result<Node> {
        let shifted = |k: &([f64; 4], Vector3<f64>, Vector3<f64>, Vector3<f64>), c: f64| Node {
            q: [n.q[0] + c * k.0[0], n.q[1] + c * k.0[1], n.q[2] + c * k.0[2], n.q[3] + c * k.0[3]],
            r: n.r + k.1 * c,
            v: n.v + k.2 * c,
            l: n.l + k.3 * c,
        };
        let k1 = self.rates(t, n)?;
        let k2 = self.rates(t + 0.5 * h, &shifted(&k1, 0.5 * h))?;
        let k3 = self.rates(t + 0.5 * h, &shifted(&k2, 0.5 * h))?;
        let k4 = self.rates(t + h, &shifted(&k3, h))?;
        let mut q = [0.0; 4];
        for i in 0..4 {
            q[i] = n.q[i] + h / 6.0 * (k1.0[i] + 2.0 * k2.0[i] + 2.0 * k3.0[i] + k4.0[i]);
        }
        normalize_xyzw(&mut q);
        if self.track.is_none() {
            return Ok(Node { q, ..*n });
        }
        let comb = |a: Vector3<f64>, b: Vector3<f64>, c: Vector3<f64>, d: Vector3<f64>| (a + 2.0 * b + 2.0 * c + d) * (h / 6.0);
        Ok(Node {
            q,
            r: n.r + comb(k1.1, k2.1, k3.1, k4.1),
            v: n.v + comb(k1.2, k2.2, k3.2, k4.2),
            l: n.l + comb(k1.3, k2.3, k3.3, k4.3),
        })
    }

    /// The node (attitude; in orbit also the CM's state and `L`) at time `t ≥ 0`.
    fn node(&mut self, t: f64) -> Result<Node> {
        if !(t.is_finite() && t >= 0.0) {
            return Err(SpacearmError::argument(format!("a free body is propagated forward from its initial state: t must be finite and >= 0, got {t}")));
        }
        let steps = (t / self.step).floor();
        if steps > 1e8 {
            return Err(SpacearmError::argument(format!(
                "free-body propagation to t = {t} s with step {} s needs {steps:.3e} steps (more than 1e8); raise the step",
                self.step
            )));
        }
        let i = steps as usize;
        while self.grid.len() <= i {
            let k = self.grid.len() - 1;
            let last = self.grid[k];
            let next = self.rk4(&last, k as f64 * self.step, self.step)?;
            self.grid.push(next);
        }
        let rest = t - i as f64 * self.step;
        let n = self.grid[i];
        let mut out = if rest <= 1e-12 * self.step.max(1.0) { n } else { self.rk4(&n, i as f64 * self.step, rest)? };
        if self.track.is_none() {
            out.r = self.r0 + self.v * t;
            out.v = self.v;
            out.l = self.l_world;
        }
        // A finite state whose motion overflows the step (an angular velocity so large that
        // the RK4 stages leave the finite numbers) is refused, never returned as NaN.
        if out.q.iter().chain(out.r.iter()).chain(out.v.iter()).chain(out.l.iter()).any(|v| !v.is_finite()) {
            return Err(SpacearmError::Simulation(format!(
                "free-body propagation left the finite numbers before t = {t:.6e} s (step {:.6e} s, initial |L| = {:.6e} N m s): \
                 the body turns too fast for its numbers; check the state's angular velocity",
                self.step,
                self.l_world.norm()
            )));
        }
        Ok(out)
    }

    /// The attitude `[x, y, z, w]` at time `t ≥ 0` (s after the initial state).
    pub fn attitude(&mut self, t: f64) -> Result<[f64; 4]> {
        Ok(self.node(t)?.q)
    }

    /// The 13-state at time `t ≥ 0`.
    pub fn state(&mut self, t: f64) -> Result<[f64; 13]> {
        let n = self.node(t)?;
        let w = self.omega(&n.q, &n.l);
        Ok([n.r.x, n.r.y, n.r.z, n.q[0], n.q[1], n.q[2], n.q[3], n.v.x, n.v.y, n.v.z, w.x, w.y, w.z])
    }

    /// The external wrench on the body at time `t ≥ 0` if its mass is `mass` (kg): in orbit the
    /// tidal force `m (g(r_O + ρ) − g(r_O))` and its moment about the run's origin `ρ × f + N`
    /// (`N` the gravity-gradient torque about the CM); torque-free, zeros. What a momentum
    /// ledger integrates for the free target.
    pub fn external_wrench(&mut self, t: f64, mass: f64) -> Result<(Vector3<f64>, Vector3<f64>)> {
        let n = self.node(t)?;
        let (acc, torque) = self.tidal(t, &n)?;
        let f = acc * mass;
        Ok((f, n.r.cross(&f) + torque))
    }

    /// Position, velocity and acceleration (in 𝒥) of the body's point at time `t ≥ 0`:
    /// `p = r + R o`, `ṗ = v + ω × R o`, `p̈ = a + ω̇ × R o + ω × (ω × R o)` with the Euler rate
    /// `ω̇ = I_𝒥⁻¹ (N + L × ω)` (`a` and `N` the tidal acceleration and torque in orbit, else 0).
    pub fn point(&mut self, t: f64) -> Result<(Vector3<f64>, Vector3<f64>, Vector3<f64>)> {
        let n = self.node(t)?;
        let (acc, torque) = self.tidal(t, &n)?;
        let rot = rotation(&n.q);
        let arm = rot * self.offset;
        let w = self.omega(&n.q, &n.l);
        let wd = rot * (self.inertia_inv * (rot.transpose() * (torque + n.l.cross(&w))));
        let p = n.r + arm;
        let v = n.v + w.cross(&arm);
        let a = acc + wd.cross(&arm) + w.cross(&w.cross(&arm));
        Ok((p, v, a))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn body(step: f64) -> FreeBody {
        let inertia = Matrix3::new(4.0, 0.1, 0.0, 0.1, 5.0, -0.2, 0.0, -0.2, 6.0);
        let q = UnitQuaternion::from_euler_angles(0.3, -0.2, 0.5);
        let (qx, qy, qz, qw) = (q.i, q.j, q.k, q.w);
        let s = [1.0, -2.0, 0.5, qx, qy, qz, qw, 0.1, 0.0, -0.05, 0.2, -0.4, 0.7];
        FreeBody::new(inertia, &s, Vector3::new(0.3, 0.0, -0.2), step).unwrap()
    }

    #[test]
    fn momenta_are_conserved_and_euler_equations_hold() {
        let mut b = body(1e-3);
        let s0 = b.state(0.0).unwrap();
        let l0 = b.l_world;
        for &t in &[0.37, 1.0, 2.5] {
            let s = b.state(t).unwrap();
            let rot = rotation(&[s[3], s[4], s[5], s[6]]);
            let w = Vector3::new(s[10], s[11], s[12]);
            let l = rot * b.inertia * rot.transpose() * w;
            assert!((l - l0).norm() < 1e-13 * l0.norm());
            assert!((s[0] - s0[0] - t * s0[7]).abs() < 1e-15);
            // The body-axes angular velocity obeys Euler's equations I ω̇ + ω × I ω = 0: check by
            // central differences of the propagated state.
            let h = 1e-4;
            let wb = |s: [f64; 13]| rotation(&[s[3], s[4], s[5], s[6]]).transpose() * Vector3::new(s[10], s[11], s[12]);
            let (wp, wm, wc) = (wb(b.state(t + h).unwrap()), wb(b.state(t - h).unwrap()), wb(s));
            let wdot = (wp - wm) / (2.0 * h);
            let residual = b.inertia * wdot + wc.cross(&(b.inertia * wc));
            assert!(residual.norm() < 1e-6, "Euler residual {residual}");
        }
    }

    #[test]
    fn the_attitude_converges_at_fourth_order() {
        let t = 3.0;
        let fine = body(1e-4).attitude(t).unwrap();
        let err = |h: f64| {
            let q = body(h).attitude(t).unwrap();
            (0..4).map(|i| (q[i] - fine[i]).powi(2)).sum::<f64>().sqrt()
        };
        let (e1, e2) = (err(0.04), err(0.02));
        let order = (e1 / e2).log2();
        assert!(order > 3.7 && order < 4.4, "observed order {order} ({e1:.3e}, {e2:.3e})");
    }

    #[test]
    fn the_point_velocity_is_the_derivative_of_its_position() {
        let mut b = body(1e-3);
        let h = 1e-5;
        for &t in &[0.2, 1.3] {
            let (p, v, a) = b.point(t).unwrap();
            let (pp, vp, _) = b.point(t + h).unwrap();
            let (pm, vm, _) = b.point(t - h).unwrap();
            assert!(((pp - pm) / (2.0 * h) - v).norm() < 1e-8);
            assert!(((vp - vm) / (2.0 * h) - a).norm() < 1e-6);
            let _ = p;
        }
    }

    #[test]
    fn in_orbit_the_point_rates_are_consistent_and_the_torque_turns_l() {
        use crate::scenario::orbit::EARTH;
        let orbit = Orbit::circular(EARTH, 500e3, 0.9, 0.2, 0.1, true).unwrap();
        let mut b = body(1e-3).in_orbit(&orbit).unwrap();
        let h = 1e-5;
        for &t in &[0.5, 7.3] {
            let (_, v, a) = b.point(t).unwrap();
            let (pp, vp, _) = b.point(t + h).unwrap();
            let (pm, vm, _) = b.point(t - h).unwrap();
            assert!(((pp - pm) / (2.0 * h) - v).norm() < 1e-8, "velocity");
            // below the tidal acceleration (~5e-6 m/s² here): it is part of a
            assert!(((vp - vm) / (2.0 * h) - a).norm() < 1e-8, "acceleration");
        }
        // The tidal torque changes L (torque-free it is constant to round-off).
        let s0 = b.state(0.0).unwrap();
        let s1 = b.state(20.0).unwrap();
        let l = |s: [f64; 13]| {
            let rot = rotation(&[s[3], s[4], s[5], s[6]]);
            rot * b.inertia * rot.transpose() * Vector3::new(s[10], s[11], s[12])
        };
        assert!((l(s1) - l(s0)).norm() > 1e-9);
    }

    #[test]
    fn bad_inputs_are_refused() {
        let s = [0.0; 13];
        assert!(FreeBody::new(Matrix3::identity(), &s, Vector3::zeros(), 1e-3).is_err()); // zero quaternion
        let mut s = s;
        s[6] = 1.0;
        assert!(FreeBody::new(-Matrix3::identity(), &s, Vector3::zeros(), 1e-3).is_err());
        assert!(FreeBody::new(Matrix3::identity(), &s, Vector3::zeros(), 0.0).is_err());
        assert!(FreeBody::new(Matrix3::identity(), &s[..12], Vector3::zeros(), 1e-3).is_err());
        let mut b = FreeBody::new(Matrix3::identity(), &s, Vector3::zeros(), 1e-3).unwrap();
        assert!(b.state(-1.0).is_err());
        assert!(b.state(f64::NAN).is_err());
        assert!(b.state(1e9).is_err());
    }
}
