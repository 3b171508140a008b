//! Reference trajectories for the controllers: joint-space references (a set point, a
//! rest-to-rest quintic, a sampled trajectory) and point references (a straight-line Cartesian
//! path with quintic timing, a point on a tumbling free body).
//!
//! The quintic and the line use the rest-to-rest quintic time scaling `s(τ) = 10τ³ − 15τ⁴ + 6τ⁵`,
//! `τ = (t − t_start)/(t_end − t_start)` clamped to `[0, 1]`: zero velocity and acceleration at
//! both ends (Siciliano et al., *Robotics: Modelling, Planning and Control*, 2009, §4.2.1).
//! Before `t_start` the reference holds the start, after `t_end` the goal.
//!
//! A sampled reference is the piecewise quintic Hermite interpolant of knots `(tₖ, qₖ, q̇ₖ, q̈ₖ)`
//! ([`quintic_hermite`]): on each interval the quintic that matches position, velocity and
//! acceleration at both ends, so `q`, `q̇` and `q̈` are continuous. The rest-to-rest quintic is
//! the special case with zero end derivatives (its polynomial is the Hermite basis function of
//! the end value).

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::error::{check_finite, Result, SpacearmError};
use crate::scenario::free_body::FreeBody;

/// Quintic time scaling: `(s, ṡ, s̈)` at time `t`.
pub fn quintic_scaling(t: f64, t_start: f64, t_end: f64) -> (f64, f64, f64) {
    let duration = t_end - t_start;
    if t <= t_start {
        return (0.0, 0.0, 0.0);
    }
    if t >= t_end {
        return (1.0, 0.0, 0.0);
    }
    let tau = (t - t_start) / duration;
    let (t2, t3) = (tau * tau, tau * tau * tau);
    let s = t3 * (10.0 - 15.0 * tau + 6.0 * t2);
    let sd = 30.0 * t2 * (1.0 - 2.0 * tau + t2) / duration;
    let sdd = 60.0 * tau * (1.0 - 3.0 * tau + 2.0 * t2) / (duration * duration);
    (s, sd, sdd)
}

/// The quintic Hermite interpolant on one interval of length `h`: from the end values
/// `(p0, v0, a0)` at `s = 0` and `(p1, v1, a1)` at `s = 1` (`s = (t − t₀)/h`), the position,
/// velocity and acceleration at `s`. The polynomial is `Σ cₖ sᵏ` with `c0 = p0`, `c1 = V0`,
/// `c2 = A0/2`, `c3 = 10Δ − 6V0 − 4V1 − (3A0 − A1)/2`, `c4 = −15Δ + 8V0 + 7V1 + (3A0 − 2A1)/2`,
/// `c5 = 6Δ − 3V0 − 3V1 − (A0 − A1)/2`, where `Δ = p1 − p0`, `V = v h`, `A = a h²`.
#[inline]
pub fn quintic_hermite(s: f64, h: f64, start: (f64, f64, f64), end: (f64, f64, f64)) -> (f64, f64, f64) {
    let (p0, v0, a0) = start;
    let (p1, v1, a1) = end;
    let (vv0, vv1, aa0, aa1) = (v0 * h, v1 * h, a0 * h * h, a1 * h * h);
    let d = p1 - p0;
    let c = [
        p0,
        vv0,
        0.5 * aa0,
        10.0 * d - 6.0 * vv0 - 4.0 * vv1 - 0.5 * (3.0 * aa0 - aa1),
        -15.0 * d + 8.0 * vv0 + 7.0 * vv1 + 0.5 * (3.0 * aa0 - 2.0 * aa1),
        6.0 * d - 3.0 * vv0 - 3.0 * vv1 - 0.5 * (aa0 - aa1),
    ];
    let p = c[0] + s * (c[1] + s * (c[2] + s * (c[3] + s * (c[4] + s * c[5]))));
    let dp = c[1] + s * (2.0 * c[2] + s * (3.0 * c[3] + s * (4.0 * c[4] + s * 5.0 * c[5])));
    let ddp = 2.0 * c[2] + s * (6.0 * c[3] + s * (12.0 * c[4] + s * 20.0 * c[5]));
    (p, dp / h, ddp / (h * h))
}

fn check_times(t_start: f64, t_end: f64) -> Result<()> {
    if !(t_start.is_finite() && t_end.is_finite() && t_end > t_start) {
        return Err(SpacearmError::argument(format!(
            "a reference needs finite times with t_end > t_start, got t_start = {t_start}, t_end = {t_end}"
        )));
    }
    Ok(())
}

/// A rest-to-rest quintic from `q_start` to `q_goal` over `[t_start, t_end]` (module docs): the
/// data of [`JointReference::Quintic`], and as it is the description of one
/// ([`crate::control::spec::JointReferenceSpec::Quintic`]), with its one check ([`Quintic::check`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Quintic {
    /// Joint coordinates at and before `t_start`, one entry per arm joint.
    pub q_start: Vec<f64>,
    /// Joint coordinates at and after `t_end`, one entry per arm joint.
    pub q_goal: Vec<f64>,
    /// Start of the motion, s.
    pub t_start: f64,
    /// End of the motion, s.
    pub t_end: f64,
}

impl Quintic {
    /// `q_start` and `q_goal` finite and of one length, the times finite with `t_end > t_start`.
    pub fn check(&self) -> Result<()> {
        check_finite("q_start", &self.q_start)?;
        check_finite("q_goal", &self.q_goal)?;
        if self.q_start.len() != self.q_goal.len() {
            return Err(SpacearmError::Dimension { what: "q_goal".into(), expected: format!("len(q_start) = {}", self.q_start.len()), got: self.q_goal.len() });
        }
        check_times(self.t_start, self.t_end)
    }
}

/// A joint-space reference: a constant set point or a rest-to-rest quintic.
#[derive(Debug, Clone, PartialEq)]
pub enum JointReference {
    /// Hold `q` (zero velocity and acceleration).
    Constant(Vec<f64>),
    /// `q(t) = q_start + s(t) (q_goal − q_start)`.
    Quintic(Quintic),
    /// The piecewise quintic Hermite interpolant of knots (module docs); outside
    /// `[t₀, t_last]` the values at the nearer end knot (its position, velocity and
    /// acceleration).
    Sampled {
        /// Knot times, strictly increasing, s (at least two).
        t: Vec<f64>,
        /// Positions at the knots, row-major (knot, joint).
        q: Vec<f64>,
        /// Velocities at the knots, row-major.
        qd: Vec<f64>,
        /// Accelerations at the knots, row-major.
        qdd: Vec<f64>,
        /// Number of joints.
        n: usize,
    },
    /// An input-shaped reference (`crate::control::shaping`): `Σ Aᵢ base(t − tᵢ)`.
    Shaped {
        /// The reference being shaped (any joint reference).
        base: Box<JointReference>,
        /// Impulse amplitudes (sum 1).
        amplitudes: Vec<f64>,
        /// Impulse times (delays), s, ≥ 0.
        delays: Vec<f64>,
    },
}

impl JointReference {
    /// A quintic from `q_start` to `q_goal` (same length, finite) over `[t_start, t_end]`.
    pub fn quintic(q_start: Vec<f64>, q_goal: Vec<f64>, t_start: f64, t_end: f64) -> Result<Self> {
        Self::from_quintic(Quintic { q_start, q_goal, t_start, t_end })
    }

    /// The quintic `motion`, checked ([`Quintic::check`]).
    pub fn from_quintic(motion: Quintic) -> Result<Self> {
        motion.check()?;
        Ok(JointReference::Quintic(motion))
    }

    /// A sampled trajectory: knot times `t` (K ≥ 2, finite, strictly increasing) and the
    /// positions, velocities and accelerations at the knots, each K×n row-major.
    pub fn sampled(t: Vec<f64>, q: Vec<f64>, qd: Vec<f64>, qdd: Vec<f64>, n: usize) -> Result<Self> {
        let k = t.len();
        if k < 2 {
            return Err(SpacearmError::argument(format!("a sampled joint reference needs at least two knots, got {k}")));
        }
        check_finite("sampled reference knot times", &t)?;
        if let Some(i) = (1..k).find(|&i| !(t[i] > t[i - 1])) {
            return Err(SpacearmError::argument(format!(
                "sampled reference knot times must be strictly increasing, got t[{}] = {} after t[{}] = {}",
                i,
                t[i],
                i - 1,
                t[i - 1]
            )));
        }
        for (what, v) in [("q", &q), ("qd", &qd), ("qdd", &qdd)] {
            if v.len() != k * n {
                return Err(SpacearmError::Dimension { what: format!("sampled reference {what}"), expected: format!("{k} knots × {n} joints = {}", k * n), got: v.len() });
            }
            check_finite(&format!("sampled reference {what}"), v)?;
        }
        Ok(JointReference::Sampled { t, q, qd, qdd, n })
    }

    /// A constant set point.
    pub fn constant(q: Vec<f64>) -> Result<Self> {
        check_finite("reference q", &q)?;
        Ok(JointReference::Constant(q))
    }

    /// Number of joints the reference covers.
    pub fn len(&self) -> usize {
        match self {
            JointReference::Constant(q) => q.len(),
            JointReference::Quintic(m) => m.q_start.len(),
            JointReference::Sampled { n, .. } => *n,
            JointReference::Shaped { base, .. } => base.len(),
        }
    }

    /// The coordinates where the reference starts and ends (a constant: its set point twice;
    /// a sampled reference: its first and last knot; a shaped one: its base's).
    pub fn end_values(&self) -> (&[f64], &[f64]) {
        match self {
            JointReference::Constant(q) => (q, q),
            JointReference::Quintic(m) => (&m.q_start, &m.q_goal),
            JointReference::Sampled { q, n, .. } => (&q[..*n], &q[q.len() - *n..]),
            JointReference::Shaped { base, .. } => base.end_values(),
        }
    }

    /// When the motion starts and ends, s (`None` for a constant; a shaped reference ends its
    /// last delay after its base).
    pub fn time_span(&self) -> Option<(f64, f64)> {
        match self {
            JointReference::Constant(_) => None,
            JointReference::Quintic(m) => Some((m.t_start, m.t_end)),
            JointReference::Sampled { t, .. } => Some((t[0], t[t.len() - 1])),
            JointReference::Shaped { base, delays, .. } => {
                let last = delays.iter().copied().fold(0.0, f64::max);
                base.time_span().map(|(a, b)| (a, b + last))
            }
        }
    }

    /// Whether the reference covers no joint.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Position, velocity and acceleration at `t` into the three slices (each `len()`).
    pub fn eval(&self, t: f64, q: &mut [f64], qd: &mut [f64], qdd: &mut [f64]) {
        match self {
            JointReference::Constant(q_set) => {
                q.copy_from_slice(q_set);
                qd.fill(0.0);
                qdd.fill(0.0);
            }
            JointReference::Quintic(Quintic { q_start, q_goal, t_start, t_end }) => {
                let (s, sd, sdd) = quintic_scaling(t, *t_start, *t_end);
                for i in 0..q.len() {
                    let delta = q_goal[i] - q_start[i];
                    q[i] = q_start[i] + s * delta;
                    qd[i] = sd * delta;
                    qdd[i] = sdd * delta;
                }
            }
            JointReference::Sampled { t: knots, q: kq, qd: kqd, qdd: kqdd, n } => {
                let last = knots.len() - 1;
                let n = *n;
                let at_knot = |k: usize, q: &mut [f64], qd: &mut [f64], qdd: &mut [f64]| {
                    q.copy_from_slice(&kq[k * n..(k + 1) * n]);
                    qd.copy_from_slice(&kqd[k * n..(k + 1) * n]);
                    qdd.copy_from_slice(&kqdd[k * n..(k + 1) * n]);
                };
                if !(t > knots[0]) {
                    return at_knot(0, q, qd, qdd);
                }
                if t >= knots[last] {
                    return at_knot(last, q, qd, qdd);
                }
                // The interval [t_i, t_{i+1}) holding t.
                let i = knots.partition_point(|&tk| tk <= t) - 1;
                let h = knots[i + 1] - knots[i];
                let s = (t - knots[i]) / h;
                for j in 0..n {
                    let (a, b) = (i * n + j, (i + 1) * n + j);
                    let (p, v, acc) = quintic_hermite(s, h, (kq[a], kqd[a], kqdd[a]), (kq[b], kqd[b], kqdd[b]));
                    q[j] = p;
                    qd[j] = v;
                    qdd[j] = acc;
                }
            }
            JointReference::Shaped { base, amplitudes, delays } => {
                let n = q.len();
                let (mut bq, mut bqd, mut bqdd) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
                q.fill(0.0);
                qd.fill(0.0);
                qdd.fill(0.0);
                for (&a, &d) in amplitudes.iter().zip(delays) {
                    base.eval(t - d, &mut bq, &mut bqd, &mut bqdd);
                    for j in 0..n {
                        q[j] += a * bq[j];
                        qd[j] += a * bqd[j];
                        qdd[j] += a * bqdd[j];
                    }
                }
            }
        }
    }
}

/// A straight-line Cartesian path of a point, `p(t) = p_start + s(t) (p_goal − p_start)` with
/// quintic timing (a constant point when `p_goal = p_start`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CartesianLine {
    /// Start point in 𝒥, m.
    pub p_start: Vector3<f64>,
    /// Goal point in 𝒥, m.
    pub p_goal: Vector3<f64>,
    /// Time the motion starts, s (the point is at `p_start` before).
    pub t_start: f64,
    /// Time the motion ends, s (the point is at `p_goal` after).
    pub t_end: f64,
}

impl CartesianLine {
    /// Validate and build.
    pub fn new(p_start: Vector3<f64>, p_goal: Vector3<f64>, t_start: f64, t_end: f64) -> Result<Self> {
        check_finite("p_start", p_start.as_slice())?;
        check_finite("p_goal", p_goal.as_slice())?;
        check_times(t_start, t_end)?;
        Ok(CartesianLine { p_start, p_goal, t_start, t_end })
    }

    /// Position, velocity and acceleration at `t`.
    pub fn eval(&self, t: f64) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
        let (s, sd, sdd) = quintic_scaling(t, self.t_start, self.t_end);
        let d = self.p_goal - self.p_start;
        (self.p_start + d * s, d * sd, d * sdd)
    }
}

/// A reference for a point: where it should be, and its velocity and acceleration, at `t`.
#[derive(Debug, Clone)]
pub enum PointReference {
    /// A straight line with quintic timing.
    Line(CartesianLine),
    /// A point fixed to a torque-free rigid body ([`crate::scenario::free_body`]), e.g. the grasp
    /// point of a tumbling target; the body's state is the one at simulation time 0.
    FreeBody(Box<FreeBody>),
    /// A sampled path: a [`JointReference::Sampled`] of the point's three coordinates in 𝒥
    /// (e.g. the recorded motion of a jointed target's grasp point).
    Sampled(JointReference),
}

impl From<CartesianLine> for PointReference {
    fn from(line: CartesianLine) -> Self {
        PointReference::Line(line)
    }
}

impl PointReference {
    /// Position, velocity and acceleration at `t` (in 𝒥).
    pub fn eval(&mut self, t: f64) -> Result<(Vector3<f64>, Vector3<f64>, Vector3<f64>)> {
        match self {
            PointReference::Line(line) => Ok(line.eval(t)),
            PointReference::FreeBody(body) => body.point(t),
            PointReference::Sampled(path) => {
                let (mut p, mut v, mut a) = (Vector3::zeros(), Vector3::zeros(), Vector3::zeros());
                path.eval(t, p.as_mut_slice(), v.as_mut_slice(), a.as_mut_slice());
                Ok((p, v, a))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quintic_scaling_matches_finite_differences_and_boundary_conditions() {
        let (t0, t1) = (0.5, 2.5);
        assert_eq!(quintic_scaling(t0, t0, t1), (0.0, 0.0, 0.0));
        assert_eq!(quintic_scaling(t1, t0, t1), (1.0, 0.0, 0.0));
        let h = 1e-5;
        for &t in &[0.7, 1.1, 1.5, 2.2] {
            let (s, sd, sdd) = quintic_scaling(t, t0, t1);
            let (sp, sdp, _) = quintic_scaling(t + h, t0, t1);
            let (sm, sdm, _) = quintic_scaling(t - h, t0, t1);
            assert!(((sp - sm) / (2.0 * h) - sd).abs() < 1e-8);
            assert!(((sdp - sdm) / (2.0 * h) - sdd).abs() < 1e-7);
            assert!(s > 0.0 && s < 1.0 && sd > 0.0);
        }
        // Symmetric about the midpoint.
        let (s_mid, _, sdd_mid) = quintic_scaling(1.5, t0, t1);
        assert!((s_mid - 0.5).abs() < 1e-15 && sdd_mid.abs() < 1e-14);
    }

    #[test]
    fn bad_times_are_rejected() {
        assert!(JointReference::quintic(vec![0.0], vec![1.0], 1.0, 1.0).is_err());
        assert!(CartesianLine::new(Vector3::zeros(), Vector3::x(), 0.0, f64::NAN).is_err());
        assert!(JointReference::quintic(vec![0.0], vec![1.0, 2.0], 0.0, 1.0).is_err());
    }

    #[test]
    fn sampled_reference_interpolates_a_polynomial_exactly() {
        // q(t) = 1 + 2t − t³ + 0.5 t⁵ is a quintic: its Hermite interpolant on any knots is exact.
        let f = |t: f64| (1.0 + 2.0 * t - t.powi(3) + 0.5 * t.powi(5), 2.0 - 3.0 * t * t + 2.5 * t.powi(4), -6.0 * t + 10.0 * t.powi(3));
        let knots = vec![0.0, 0.3, 0.9, 1.0, 1.7];
        let (mut q, mut qd, mut qdd) = (vec![], vec![], vec![]);
        for &t in &knots {
            let (a, b, c) = f(t);
            q.push(a);
            qd.push(b);
            qdd.push(c);
        }
        // The end knot's values as stored (recomputing f(1.7) in the assertion may round
        // differently: LLVM may fold `powi` of a constant by another algorithm in release).
        let end = (q[4], qd[4], qdd[4]);
        let r = JointReference::sampled(knots, q, qd, qdd, 1).unwrap();
        let (mut a, mut b, mut c) = ([0.0], [0.0], [0.0]);
        for &t in &[0.0, 0.1, 0.3, 0.55, 0.95, 1.2, 1.7] {
            r.eval(t, &mut a, &mut b, &mut c);
            let (ea, eb, ec) = f(t);
            assert!((a[0] - ea).abs() < 1e-13 && (b[0] - eb).abs() < 1e-12 && (c[0] - ec).abs() < 1e-11, "t = {t}");
        }
        // Outside the knots: the end knots' values.
        r.eval(5.0, &mut a, &mut b, &mut c);
        assert_eq!((a[0], b[0], c[0]), end);
    }

    #[test]
    fn the_rest_to_rest_quintic_is_the_hermite_with_zero_end_derivatives() {
        for &tau in &[0.0, 0.2, 0.5, 0.81, 1.0] {
            let (s, sd, sdd) = quintic_scaling(tau * 2.0, 0.0, 2.0);
            let (p, v, a) = quintic_hermite(tau, 2.0, (0.0, 0.0, 0.0), (1.0, 0.0, 0.0));
            assert!((s - p).abs() < 1e-14 && (sd - v).abs() < 1e-14 && (sdd - a).abs() < 1e-13, "tau = {tau}: {s} {p}, {sd} {v}, {sdd} {a}");
        }
    }

    #[test]
    fn bad_sampled_references_are_rejected() {
        assert!(JointReference::sampled(vec![0.0], vec![0.0], vec![0.0], vec![0.0], 1).is_err());
        assert!(JointReference::sampled(vec![0.0, 0.0], vec![0.0; 2], vec![0.0; 2], vec![0.0; 2], 1).is_err());
        assert!(JointReference::sampled(vec![0.0, 1.0], vec![0.0; 3], vec![0.0; 2], vec![0.0; 2], 1).is_err());
        assert!(JointReference::sampled(vec![0.0, 1.0], vec![0.0, f64::NAN], vec![0.0; 2], vec![0.0; 2], 1).is_err());
    }
}
