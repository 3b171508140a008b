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
use crate::model::cmg::Cmg;
use crate::sim::plant::Plant;
use crate::sim::record::{cmg_records, Recorder};

/// The conditions as data, in their own file (`sim/stop.rs`), at their former paths too.
pub use crate::sim::stop::{validate, StopCondition, StopEvent, WatchedRecord};

/// A condition watched at every step (module docs): its event function's parts.
enum Watched {
    /// `g = |p_ref − p| − tolerance`, the point `p` of `body` at `offset`.
    Gap { body: usize, offset: Vector3<f64>, tolerance: f64 },
    /// `g = threshold − r` (`rising`: it holds at `r ≥ threshold`) or `g = r − threshold`.
    Record { record: WatchedRecord, threshold: f64, rising: bool },
}

/// The watch over a run's conditions: the earliest time condition (the run's end if within its
/// duration) and the conditions located within the step (gap and record conditions).
pub(crate) struct StopWatch {
    /// `(condition index, its event function)` of each gap and record condition.
    watched: Vec<(usize, Watched)>,
    /// The base CMG cluster a CMG record condition reads ([`Recorder::base_cmgs`]).
    cmgs: Vec<Cmg>,
    /// The earliest time condition within the duration: `(index, T)`.
    pub(crate) time: Option<(usize, f64)>,
}

impl StopWatch {
    /// The watch of `stop` over a run of `duration` on `plant` (checked against its model and its
    /// controller: a gap needs a controller that tracks a Cartesian point, a record condition a
    /// plant that records it).
    pub(crate) fn new(stop: &[StopCondition], duration: f64, plant: &Plant<'_>) -> Result<Self> {
        validate(stop)?;
        let mut watched = Vec::new();
        let mut time: Option<(usize, f64)> = None;
        let cmgs = Recorder::base_cmgs(plant.model());
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
                    watched.push((i, Watched::Gap { body, offset, tolerance }));
                }
                StopCondition::Record { .. } => {
                    let (record, threshold, rising) = c.record_threshold()?.expect("a record condition");
                    let c = &plant.controller;
                    let missing = match record {
                        WatchedRecord::CmgMeasure | WatchedRecord::CmgEnvelopeFraction if cmgs.is_empty() => Some(
                            "the model has no control-moment gyros on its base (a CMG record needs a cluster whose every gimbal is on the base; docs/cmg.md)"
                                .to_string(),
                        ),
                        WatchedRecord::TrackingError if c.tracking().is_none() => Some(format!("controller '{}' tracks no reference", c.name())),
                        WatchedRecord::AttitudeError if !c.reports_attitude_error() => Some(format!("controller '{}' reports no attitude error", c.name())),
                        _ => None,
                    };
                    if let Some(why) = missing {
                        return Err(SpacearmError::argument(format!("stop condition {i} (record) watches {:?}, which this run does not record: {why}", record.name())));
                    }
                    watched.push((i, Watched::Record { record, threshold, rising }));
                }
            }
        }
        Ok(StopWatch { watched, cmgs, time })
    }

    /// The run's end: the earliest time condition within the duration, else the duration.
    pub(crate) fn end(&self, duration: f64) -> f64 {
        self.time.map_or(duration, |(_, t)| t)
    }

    /// Whether there are conditions to evaluate at every step.
    pub(crate) fn has_watched(&self) -> bool {
        !self.watched.is_empty()
    }

    /// The `g` of one watched condition after `plant` evaluated `f(t, y)` (`y` its state).
    fn g(&self, w: &Watched, plant: &Plant<'_>, y: &[f64]) -> f64 {
        match *w {
            Watched::Gap { body, ref offset, tolerance } => gap_of(plant, body, offset) - tolerance,
            Watched::Record { record, threshold, rising } => {
                let r = match record {
                    WatchedRecord::CmgMeasure => cmg_records(plant.model(), plant.data(), &self.cmgs, &y[plant.nx..]).0,
                    WatchedRecord::CmgEnvelopeFraction => cmg_records(plant.model(), plant.data(), &self.cmgs, &y[plant.nx..]).1,
                    WatchedRecord::TrackingError => plant.cmd.tracking_error,
                    WatchedRecord::AttitudeError => plant.cmd.attitude_error,
                };
                if rising {
                    threshold - r
                } else {
                    r - threshold
                }
            }
        }
    }

    /// The watched conditions' `g` after `plant` evaluated `f(t, y)`: the first (lowest index)
    /// that holds, `(condition index, g, its quantity)`, or `None`.
    pub(crate) fn holding(&self, plant: &Plant<'_>, y: &[f64]) -> Option<(usize, f64, f64)> {
        self.watched.iter().find_map(|(i, w)| {
            let g = self.g(w, plant, y);
            (g <= 0.0).then(|| (*i, g, self.quantity(*i, g)))
        })
    }

    /// Every watched condition's `g` after `plant` evaluated `f(t, y)`, written at its
    /// condition index of `out` (one entry per condition of the run).
    pub(crate) fn values_into(&self, plant: &Plant<'_>, y: &[f64], out: &mut [f64]) {
        for (i, w) in &self.watched {
            out[*i] = self.g(w, plant, y);
        }
    }

    /// Whether a watched condition holds in `values` (of [`StopWatch::values_into`]).
    pub(crate) fn any_holds(&self, values: &[f64]) -> bool {
        self.watched.iter().any(|w| values[w.0] <= 0.0)
    }

    /// The indices of the watched conditions, in order.
    pub(crate) fn watched_conditions(&self) -> impl Iterator<Item = usize> + '_ {
        self.watched.iter().map(|w| w.0)
    }

    /// The quantity of watched condition `index` whose `g` is `g`: the gap (m) of a gap
    /// condition, the record's value of a record condition ([`StopEvent::value`]).
    pub(crate) fn quantity(&self, index: usize, g: f64) -> f64 {
        match self.watched.iter().find(|w| w.0 == index).expect("a watched condition of this watch").1 {
            Watched::Gap { tolerance, .. } => g + tolerance,
            Watched::Record { threshold, rising: true, .. } => threshold - g,
            Watched::Record { threshold, rising: false, .. } => g + threshold,
        }
    }

    /// The `g` of watched condition `index` after `plant` evaluated `f(t, y)`.
    pub(crate) fn value(&self, plant: &Plant<'_>, y: &[f64], index: usize) -> f64 {
        let (_, w) = self.watched.iter().find(|w| w.0 == index).expect("a watched condition of this watch");
        self.g(w, plant, y)
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
    fn record_conditions_round_trip_and_bad_ones_are_refused_with_what_was_expected() {
        #[derive(Debug, PartialEq, serde::Serialize, serde::Deserialize)]
        struct Run {
            stop: Vec<StopCondition>,
        }
        let text = "[[stop]]\nkind = \"record\"\nname = \"cmg_envelope_fraction\"\nabove = 0.8\n\n[[stop]]\nkind = \"record\"\nname = \"cmg_measure\"\nbelow = 0.05\n";
        let run: Run = toml::from_str(text).unwrap();
        assert_eq!(run.stop[0], StopCondition::Record { name: "cmg_envelope_fraction".into(), above: Some(0.8), below: None });
        assert_eq!(run.stop[0].record_threshold().unwrap(), Some((WatchedRecord::CmgEnvelopeFraction, 0.8, true)));
        assert_eq!(run.stop[1].record_threshold().unwrap(), Some((WatchedRecord::CmgMeasure, 0.05, false)));
        assert_eq!(toml::from_str::<Run>(&toml::to_string(&run).unwrap()).unwrap(), run);
        validate(&run.stop).unwrap();
        // In the one run description (the TOML of the C stepper's and FMU's options), checked
        // when the options are made.
        let spec: crate::sim::options::RunSpec = toml::from_str(&format!("mode = \"rotation-floating\"\n{text}")).unwrap();
        assert_eq!(spec.options(1.0).unwrap().stop, run.stop);
        let bad: crate::sim::options::RunSpec = toml::from_str("[[stop]]\nkind = \"record\"\nname = \"energy\"\nbelow = 1.0\n").unwrap();
        assert!(bad.options(1.0).unwrap_err().to_string().contains("\"energy\""));
        for r in WatchedRecord::ALL {
            assert_eq!(WatchedRecord::from_name(r.name()).unwrap(), r);
        }
        let rec = |name: &str, above: Option<f64>, below: Option<f64>| StopCondition::Record { name: name.into(), above, below };
        let msg = |c: StopCondition| validate(&[StopCondition::Time { t: 1.0 }, c]).unwrap_err().to_string();
        let m = msg(rec("cmg_torque", Some(1.0), None));
        assert!(m.contains("stop condition 1 (record)") && m.contains("\"cmg_torque\"") && m.contains("cmg_envelope_fraction"), "{m}");
        assert!(msg(rec("cmg_measure", Some(1.0), Some(0.5))).contains("exactly one of above"));
        assert!(msg(rec("cmg_measure", None, None)).contains("neither"));
        assert!(msg(rec("cmg_measure", None, Some(f64::NAN))).contains("finite"));
    }

    #[test]
    fn bad_values_are_refused() {
        assert!(validate(&[StopCondition::Time { t: 0.0 }]).is_err());
        assert!(validate(&[StopCondition::Time { t: f64::NAN }]).is_err());
        assert!(validate(&[StopCondition::Gap { point: None, tolerance: -1.0 }]).is_err());
    }
}
