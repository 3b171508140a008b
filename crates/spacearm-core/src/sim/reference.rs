//! Reference trajectories for the controllers: a joint-space quintic and a straight-line
//! Cartesian path with quintic timing.
//!
//! Both use the rest-to-rest quintic time scaling `s(τ) = 10τ³ − 15τ⁴ + 6τ⁵`,
//! `τ = (t − t_start)/(t_end − t_start)` clamped to `[0, 1]`: zero velocity and acceleration at
//! both ends (Siciliano et al., *Robotics: Modelling, Planning and Control*, 2009, §4.2.1).
//! Before `t_start` the reference holds the start, after `t_end` the goal.

use nalgebra::Vector3;

use crate::error::{check_finite, Result, SpacearmError};

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

fn check_times(t_start: f64, t_end: f64) -> Result<()> {
    if !(t_start.is_finite() && t_end.is_finite() && t_end > t_start) {
        return Err(SpacearmError::argument(format!(
            "a reference needs finite times with t_end > t_start, got t_start = {t_start}, t_end = {t_end}"
        )));
    }
    Ok(())
}

/// A joint-space reference: a constant set point or a rest-to-rest quintic.
#[derive(Debug, Clone, PartialEq)]
pub enum JointReference {
    /// Hold `q` (zero velocity and acceleration).
    Constant(Vec<f64>),
    /// `q(t) = q_start + s(t) (q_goal − q_start)`.
    Quintic {
        /// Joint coordinates at and before `t_start`.
        q_start: Vec<f64>,
        /// Joint coordinates at and after `t_end`.
        q_goal: Vec<f64>,
        /// Start of the motion, s.
        t_start: f64,
        /// End of the motion, s.
        t_end: f64,
    },
}

impl JointReference {
    /// A quintic from `q_start` to `q_goal` (same length, finite) over `[t_start, t_end]`.
    pub fn quintic(q_start: Vec<f64>, q_goal: Vec<f64>, t_start: f64, t_end: f64) -> Result<Self> {
        check_finite("q_start", &q_start)?;
        check_finite("q_goal", &q_goal)?;
        if q_start.len() != q_goal.len() {
            return Err(SpacearmError::Dimension { what: "q_goal".into(), expected: format!("len(q_start) = {}", q_start.len()), got: q_goal.len() });
        }
        check_times(t_start, t_end)?;
        Ok(JointReference::Quintic { q_start, q_goal, t_start, t_end })
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
            JointReference::Quintic { q_start, .. } => q_start.len(),
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
            JointReference::Quintic { q_start, q_goal, t_start, t_end } => {
                let (s, sd, sdd) = quintic_scaling(t, *t_start, *t_end);
                for i in 0..q.len() {
                    let delta = q_goal[i] - q_start[i];
                    q[i] = q_start[i] + s * delta;
                    qd[i] = sd * delta;
                    qdd[i] = sdd * delta;
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
}
