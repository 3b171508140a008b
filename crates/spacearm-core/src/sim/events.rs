//! Events in the simulation loop: conditions that stop a run before its duration
//! ([`StopCondition`], [`SimOptions::stop`](crate::sim::simulate::SimOptions::stop)), located
//! within the step in which they first hold (docs/simulation-core.md, "Events").
//!
//! A condition is a scalar event function `g(t, y)` that **holds** when `g ≤ 0`:
//!
//! - [`StopCondition::Time`]: `g = t − T`. Not root-found: the run's last step is cut to land on
//!   `T` exactly (as it lands on the duration), so the run is the run of duration `T`.
//! - [`StopCondition::Gap`]: `g = |p_ref(t) − p(x)| − tolerance`, the distance from a robot point
//!   `p(x)` (a body and an offset from its CM in its frame) to the controller's point reference
//!   `p_ref(t)` (the first three entries of its recorded reference: a controller that tracks a
//!   Cartesian point, the resolved-motion-rate control of a capture's approach) less a
//!   tolerance. Read from the plant's evaluation of `f(t, y)` (its kinematics and the command's
//!   reference), so it costs nothing at the end of a step where the integrator evaluated `f`
//!   anyway (DOPRI5's first-same-as-last stage).
//!
//! **Location.** `g` is evaluated at every step end and (DOPRI5) at every output sample within
//! the step, in time order — points where `f` is evaluated anyway, so a grid of `dt` watches at
//! least every `dt` even where the error control takes long steps; the first such point `t_b`
//! with `g(t_b) ≤ 0` after a point `t_a` with `g(t_a) > 0` brackets the event, and its time `t*`
//! is the root of `g(t, y(t)) = 0` in `[t_a, t_b]` found by the Illinois variant of regula falsi (every
//! fourth iterate a bisection), on the integrator's own continuation of the step: DOPRI5's
//! dense output of order 4 (Hairer et al. I, §II.6) projected onto the manifold; RK4's step
//! re-taken from `(t_n, y_n)` with the shorter step `t − t_n`. The bracket shrinks until its
//! ends are within four ulps of `t*`; the event time is the end where `g ≤ 0` (so the run's
//! last state satisfies the condition). Its accuracy is then that of the continuation: the
//! state at `t*` carries the step's local error (O(h⁵) for both), and `t*` the error of `g`
//! divided by `|ġ|`. A condition that holds at `t = 0` stops the run there (one sample); a
//! condition that holds only strictly between two watched points is not seen (the output
//! interval `dt` bounds their spacing for DOPRI5, the step for RK4).

use nalgebra::Vector3;

use crate::algorithms::kinematics::{check_body, point_position};
use crate::control::spec::PointSpec;
use crate::control::TrackingKind;
use crate::error::{Result, SpacearmError};
use crate::sim::plant::Plant;

/// The conditions as data, in their own file (`sim/stop.rs`), at their former paths too.
pub use crate::sim::stop::{validate, StopCondition, StopEvent};

/// The watch over a run's conditions: the earliest time condition (the run's end if within its
/// duration) and the gap conditions with their last values.
pub(crate) struct StopWatch {
    /// `(condition index, body, offset, tolerance)` of each gap condition.
    gaps: Vec<(usize, usize, Vector3<f64>, f64)>,
    /// The earliest time condition within the duration: `(index, T)`.
    pub(crate) time: Option<(usize, f64)>,
}

impl StopWatch {
    /// The watch of `stop` over a run of `duration` on `plant` (checked against its model and its
    /// controller: a gap needs a controller that tracks a Cartesian point).
    pub(crate) fn new(stop: &[StopCondition], duration: f64, plant: &Plant<'_>) -> Result<Self> {
        validate(stop)?;
        let mut gaps = Vec::new();
        let mut time: Option<(usize, f64)> = None;
        for (i, c) in stop.iter().enumerate() {
            match *c {
                StopCondition::Time { t } => {
                    if t <= duration && time.is_none_or(|(_, best)| t < best) {
                        time = Some((i, t));
                    }
                }
                StopCondition::Gap { ref point, tolerance } => {
                    let (body, offset) = PointSpec::resolve(point.as_ref(), plant.model())?;
                    check_body(plant.model(), body)?;
                    let c = &plant.controller;
                    if c.tracking() != Some(TrackingKind::Cartesian) || c.reference_len() < 3 {
                        return Err(SpacearmError::argument(format!(
                            "stop condition {i} (gap) measures the distance to the controller's point reference, and controller '{}' \
                             tracks no point; use a resolved-motion-rate controller (alone or as the arm of a combined one)",
                            c.name()
                        )));
                    }
                    gaps.push((i, body, offset, tolerance));
                }
            }
        }
        Ok(StopWatch { gaps, time })
    }

    /// The run's end: the earliest time condition within the duration, else the duration.
    pub(crate) fn end(&self, duration: f64) -> f64 {
        self.time.map_or(duration, |(_, t)| t)
    }

    /// Whether there are gap conditions to evaluate at every step.
    pub(crate) fn has_gaps(&self) -> bool {
        !self.gaps.is_empty()
    }

    /// The gap conditions' `g = gap − tolerance` after `plant` evaluated `f(t, y)`: the first
    /// (lowest index) that holds, `(condition index, g, gap)`, or `None`.
    pub(crate) fn holding(&self, plant: &Plant<'_>) -> Option<(usize, f64, f64)> {
        self.gaps.iter().find_map(|&(i, body, offset, tol)| {
            let gap = gap_of(plant, body, &offset);
            (gap - tol <= 0.0).then_some((i, gap - tol, gap))
        })
    }

    /// Every gap condition's `g` after `plant` evaluated `f(t, y)`, written at its condition
    /// index of `out` (one entry per condition of the run).
    pub(crate) fn values_into(&self, plant: &Plant<'_>, out: &mut [f64]) {
        for &(i, body, offset, tol) in &self.gaps {
            out[i] = gap_of(plant, body, &offset) - tol;
        }
    }

    /// Whether a gap condition holds in `values` (of [`StopWatch::values_into`]).
    pub(crate) fn any_holds(&self, values: &[f64]) -> bool {
        self.gaps.iter().any(|g| values[g.0] <= 0.0)
    }

    /// The indices of the gap conditions, in order.
    pub(crate) fn gap_conditions(&self) -> impl Iterator<Item = usize> + '_ {
        self.gaps.iter().map(|g| g.0)
    }

    /// The tolerance of gap condition `index`.
    pub(crate) fn tolerance(&self, index: usize) -> f64 {
        self.gaps.iter().find(|g| g.0 == index).expect("a gap condition of this watch").3
    }

    /// The `g` of gap condition `index` after `plant` evaluated `f(t, y)`.
    pub(crate) fn value(&self, plant: &Plant<'_>, index: usize) -> f64 {
        let &(_, body, offset, tol) = self.gaps.iter().find(|g| g.0 == index).expect("a gap condition of this watch");
        gap_of(plant, body, &offset) - tol
    }
}

/// `|p_ref − p|` after `plant` evaluated `f(t, y)`: its kinematics are at `x`, its command holds
/// the controller's reference at `t`.
fn gap_of(plant: &Plant<'_>, body: usize, offset: &Vector3<f64>) -> f64 {
    let p = point_position(plant.data(), body, offset);
    let r = &plant.cmd.reference;
    (Vector3::new(r[0], r[1], r[2]) - p).norm()
}

/// The first time in `(a, b]` where `g ≤ 0`, given `g(a) = ga > 0 ≥ g(b) = gb`: the Illinois
/// regula falsi with a bisection every fourth iterate, until the bracket is within four ulps;
/// returns the end where `g ≤ 0` and its value.
pub fn locate_root(g: &mut dyn FnMut(f64) -> Result<f64>, (mut a, mut ga): (f64, f64), (mut b, mut gb): (f64, f64)) -> Result<(f64, f64)> {
    debug_assert!(ga > 0.0 && gb <= 0.0 && a < b);
    // +1: the last iterate replaced a; −1: b.
    let mut side = 0i8;
    for it in 0..200 {
        if b - a <= 4.0 * f64::EPSILON * a.abs().max(b.abs()) {
            break;
        }
        let mut c = if it % 4 == 3 { 0.5 * (a + b) } else { (a * gb - b * ga) / (gb - ga) };
        if !(c > a && c < b) {
            c = 0.5 * (a + b);
        }
        let gc = g(c)?;
        if !gc.is_finite() {
            return Err(SpacearmError::Simulation(format!("the stop condition's value is not finite at t = {c} s")));
        }
        if gc <= 0.0 {
            (b, gb) = (c, gc);
            if side == -1 {
                ga *= 0.5;
            }
            side = -1;
        } else {
            (a, ga) = (c, gc);
            if side == 1 {
                gb *= 0.5;
            }
            side = 1;
        }
    }
    Ok((b, gb))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::spec::BodySpec;

    #[test]
    fn the_root_of_a_smooth_function_is_found_to_rounding() {
        // g = cos t − 0.3 falls through zero at acos(0.3).
        let mut n = 0;
        let (t, g) = locate_root(
            &mut |t| {
                n += 1;
                Ok(t.cos() - 0.3)
            },
            (1.0, 1f64.cos() - 0.3),
            (1.5, 1.5f64.cos() - 0.3),
        )
        .unwrap();
        assert!(g <= 0.0);
        assert!((t - 0.3f64.acos()).abs() < 1e-15, "{t} vs {}", 0.3f64.acos());
        assert!(n < 30, "{n} evaluations");
    }

    #[test]
    fn a_flat_then_steep_function_still_converges() {
        // g = 1 − t¹⁰ on [0, 2]: regula falsi alone creeps from one side.
        let (t, g) = locate_root(&mut |t| Ok(1.0 - t.powi(10)), (0.0, 1.0), (2.0, 1.0 - 1024.0)).unwrap();
        assert!(g <= 0.0 && (t - 1.0).abs() < 1e-15, "{t}");
    }

    #[test]
    fn conditions_round_trip_through_serde() {
        #[derive(Debug, PartialEq, serde::Serialize, serde::Deserialize)]
        struct Run {
            stop: Vec<StopCondition>,
        }
        let run = Run { stop: vec![StopCondition::Time { t: 1.5 }, StopCondition::Gap { point: Some(PointSpec::At(BodySpec::Index(6), [0.0, 0.1, 0.0])), tolerance: 0.02 }] };
        let text = toml::to_string(&run).unwrap();
        assert!(text.contains("kind = \"gap\""), "{text}");
        assert_eq!(toml::from_str::<Run>(&text).unwrap(), run);
        assert!(toml::from_str::<Run>("[[stop]]\nkind = \"gap\"\nbody = 1\noffset = [0, 0, 0]\ntolerance = 0.1\nextra = 1\n").is_err());
    }

    #[test]
    fn bad_values_are_refused() {
        assert!(validate(&[StopCondition::Time { t: 0.0 }]).is_err());
        assert!(validate(&[StopCondition::Time { t: f64::NAN }]).is_err());
        assert!(validate(&[StopCondition::Gap { point: None, tolerance: -1.0 }]).is_err());
    }
}
