//! The conditions that stop a run before its duration, as data ([`StopCondition`], checked by
//! [`validate`]) and the event that stopped one ([`StopEvent`]); watched and located by
//! [`crate::sim::events`] (its module docs define them). [`WatchedRecord`] is the one table of
//! the records a [`StopCondition::Record`] may watch.

use serde::{Deserialize, Serialize};

use crate::control::spec::PointSpec;
use crate::error::{Result, SpacearmError};

/// A condition that stops a run when it holds (module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum StopCondition {
    /// Stop at time `t`, s (> 0): the run ends there if `t` is within its duration.
    Time {
        /// The time, s.
        t: f64,
    },
    /// Stop when the robot's `point` comes within `tolerance` of the controller's point
    /// reference: `|p_ref − p| ≤ tolerance`.
    Gap {
        /// The robot point: a point or body name, or `[body, offset]` (offset from the body's CM
        /// in its frame, m); absent: the end effector. Resolved on the plant when the run starts.
        #[serde(default)]
        point: Option<PointSpec>,
        /// The distance at which the run stops, m (> 0).
        tolerance: f64,
    },
    /// Stop when a scalar record of the run crosses a threshold: `r ≥ above` or `r ≤ below`
    /// (exactly one of the two). The records that can be watched are those of
    /// [`WatchedRecord::NAMES`] (a CMG cluster's saturation, `cmg_envelope_fraction` above a
    /// value, and singularity, `cmg_measure` below one; docs/cmg.md, "Saturation and singularity
    /// events").
    Record {
        /// The record's name ([`WatchedRecord::NAMES`]).
        name: String,
        /// The run stops when the record reaches this value from below.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        above: Option<f64>,
        /// The run stops when the record reaches this value from above.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        below: Option<f64>,
    },
}

/// The records that a [`StopCondition::Record`] may watch: scalar records that the plant's
/// evaluation of `f(t, y)` gives at any time (the run's samples record the same values).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WatchedRecord {
    /// A base CMG cluster's singularity measure `det(A Aᵀ)/h̄⁶` (control/cmg_jacobian.rs).
    CmgMeasure,
    /// A base CMG cluster's momentum-envelope fraction `|H|/σ(Ĥ)` (analysis/cmg_envelope.rs).
    CmgEnvelopeFraction,
    /// The controller's tracking error (joint-space: rad or m; Cartesian: m).
    TrackingError,
    /// The controller's base attitude error angle, rad.
    AttitudeError,
}

impl WatchedRecord {
    /// Every watched record, in the order of [`WatchedRecord::NAMES`].
    pub const ALL: [WatchedRecord; 4] = [WatchedRecord::CmgMeasure, WatchedRecord::CmgEnvelopeFraction, WatchedRecord::TrackingError, WatchedRecord::AttitudeError];
    /// Their names: those of the run's records (`SimResult::records`, the Python `Trajectory`).
    pub const NAMES: [&'static str; 4] = ["cmg_measure", "cmg_envelope_fraction", "tracking_error", "attitude_error"];

    /// The record's name.
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    /// The watched record named `name`, or an error listing those that can be watched.
    pub fn from_name(name: &str) -> Result<Self> {
        Self::ALL.into_iter().find(|r| r.name() == name).ok_or_else(|| {
            SpacearmError::argument(format!("a record stop condition watches one of the records {:?}, got {name:?}", Self::NAMES))
        })
    }
}

impl StopCondition {
    /// The condition's kind: `"time"`, `"gap"` or `"record"`.
    pub fn kind(&self) -> &'static str {
        match self {
            StopCondition::Time { .. } => "time",
            StopCondition::Gap { .. } => "gap",
            StopCondition::Record { .. } => "record",
        }
    }

    /// A record condition's record, threshold and direction (`true`: it holds at `r ≥ above`),
    /// checked; `None` for the other kinds.
    pub fn record_threshold(&self) -> Result<Option<(WatchedRecord, f64, bool)>> {
        let StopCondition::Record { name, above, below } = self else { return Ok(None) };
        let record = WatchedRecord::from_name(name)?;
        let (value, rising) = match (above, below) {
            (Some(v), None) => (*v, true),
            (None, Some(v)) => (*v, false),
            _ => {
                return Err(SpacearmError::argument(format!(
                    "a record stop condition on {name:?} takes exactly one of above (stop when the record rises to it) and below \
                     (stop when it falls to it), got {}",
                    if above.is_some() { "both" } else { "neither" }
                )))
            }
        };
        if !value.is_finite() {
            return Err(SpacearmError::argument(format!("a record stop condition on {name:?}: the threshold must be finite, got {value}")));
        }
        Ok(Some((record, value, rising)))
    }
}

/// The event that stopped a run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct StopEvent {
    /// Index of the condition in [`SimOptions::stop`](crate::sim::simulate::SimOptions::stop).
    pub condition: usize,
    /// The time at which it held (the run's last sample), s.
    pub t: f64,
    /// The condition's quantity there: the time for a time condition, the gap (m, at most the
    /// tolerance) for a gap condition, the record's value (at or past the threshold) for a
    /// record condition.
    pub value: f64,
}

/// Check the conditions' values (those that need no plant).
pub fn validate(stop: &[StopCondition]) -> Result<()> {
    for (i, c) in stop.iter().enumerate() {
        match c {
            StopCondition::Time { t } => {
                if !(t.is_finite() && *t > 0.0) {
                    return Err(SpacearmError::argument(format!("stop condition {i} (time): t must be finite and > 0 s, got {t}")));
                }
            }
            StopCondition::Gap { tolerance, .. } => {
                if !(tolerance.is_finite() && *tolerance > 0.0) {
                    return Err(SpacearmError::argument(format!("stop condition {i} (gap): tolerance must be finite and > 0 m, got {tolerance}")));
                }
            }
            StopCondition::Record { .. } => {
                c.record_threshold().map_err(|e| SpacearmError::argument(format!("stop condition {i} (record): {e}")))?;
            }
        }
    }
    Ok(())
}
