//! The conditions that stop a run before its duration, as data ([`StopCondition`], checked by
//! [`validate`]) and the event that stopped one ([`StopEvent`]); watched and located by
//! [`crate::sim::events`] (its module docs define them).

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
}

impl StopCondition {
    /// The condition's kind: `"time"` or `"gap"`.
    pub fn kind(&self) -> &'static str {
        match self {
            StopCondition::Time { .. } => "time",
            StopCondition::Gap { .. } => "gap",
        }
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
    /// tolerance) for a gap condition.
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
        }
    }
    Ok(())
}
