//! Topology events as data ([`TopologyEvent`], checked once by [`validate`]): the attach of the
//! run's free target to a robot body (a weld, at a commanded time or when the gap and the
//! relative twist fall below thresholds) and the release of a rigid link (with or without a
//! separation impulse); run by [`crate::sim::topology`] (its module docs and docs/events.md give
//! the equations). One serde type read by every door (the `events` list of a run's
//! description, [`crate::sim::options::RunSpec`]'s neighbour in the entry points).

use serde::{Deserialize, Serialize};

use crate::control::spec::PointSpec;
use crate::error::{Result, SpacearmError};

/// A change of the simulated system's topology mid-run (module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum TopologyEvent {
    /// Weld the free target to the robot: the rigid 6-D grasp impulse at the robot's `point`
    /// (docs/capture.md, "The grasp impact", restitution 0), then the target a link of the robot
    /// on a fixed joint at its relative pose ([`crate::model::edit`]'s `attach_model`).
    /// Happens at time `at` when given, else when every given threshold holds (located within
    /// the step, [`crate::sim::events`]); at least one of `at`, `gap` must be given.
    Attach {
        /// The commanded time, s (> 0); absent: when the thresholds hold.
        #[serde(default)]
        at: Option<f64>,
        /// The robot point: a point or body name, or `[body, offset]`; absent: the end effector.
        #[serde(default)]
        point: Option<PointSpec>,
        /// The target's grasp point (a named point of the target); absent: its first point,
        /// else its CM.
        #[serde(default)]
        grasp: Option<String>,
        /// Threshold on the distance between the two points, m (> 0).
        #[serde(default)]
        gap: Option<f64>,
        /// Threshold on the relative linear velocity at the robot's point, m/s (> 0).
        #[serde(default)]
        speed: Option<f64>,
        /// Threshold on the relative angular velocity, rad/s (> 0).
        #[serde(default)]
        rate: Option<f64>,
    },
    /// Release the rigid link `body` (a link on a fixed joint with no link below it; absent:
    /// the attached target) at time `at`: the model loses the link, which flies on as the free
    /// target, with the separation impulse `impulse` (N·s, ≥ 0) pushing it along `direction`
    /// (in 𝒥; absent: from its parent's CM to its CM) and the robot back.
    Detach {
        /// The time, s (> 0).
        at: f64,
        /// The released link's name; absent: the attached target.
        #[serde(default)]
        body: Option<String>,
        /// The separation impulse, N·s (≥ 0; 0: a plain split).
        #[serde(default)]
        impulse: f64,
        /// Its direction in 𝒥 (normalized here); absent: parent CM → link CM.
        #[serde(default)]
        direction: Option<[f64; 3]>,
    },
}

impl TopologyEvent {
    /// `"attach"` or `"detach"`.
    pub fn kind(&self) -> &'static str {
        match self {
            TopologyEvent::Attach { .. } => "attach",
            TopologyEvent::Detach { .. } => "detach",
        }
    }

    /// The commanded time, if any.
    pub fn at(&self) -> Option<f64> {
        match self {
            TopologyEvent::Attach { at, .. } => *at,
            TopologyEvent::Detach { at, .. } => Some(*at),
        }
    }
}

/// Check the events' values (what needs no model): positive finite times, thresholds and
/// impulse, a non-zero finite direction, an attach with a time or a gap, commanded times in
/// increasing order with the threshold events between them.
pub fn validate(events: &[TopologyEvent]) -> Result<()> {
    let positive = |i: usize, kind: &str, what: &str, v: f64, unit: &str| -> Result<()> {
        if v.is_finite() && v > 0.0 {
            Ok(())
        } else {
            Err(SpacearmError::argument(format!("event {i} ({kind}): {what} must be finite and > 0 {unit}, got {v}")))
        }
    };
    let mut last_t = 0.0;
    for (i, e) in events.iter().enumerate() {
        let kind = e.kind();
        match e {
            TopologyEvent::Attach { at, gap, speed, rate, .. } => {
                for (what, v, unit) in [("at", at, "s"), ("gap", gap, "m"), ("speed", speed, "m/s"), ("rate", rate, "rad/s")] {
                    if let Some(v) = v {
                        positive(i, kind, what, *v, unit)?;
                    }
                }
                if at.is_none() && gap.is_none() {
                    return Err(SpacearmError::argument(format!(
                        "event {i} (attach): give a commanded time at= (s) or a gap threshold gap= (m, with speed= and rate= if wanted)"
                    )));
                }
                if at.is_some() && (gap.is_some() || speed.is_some() || rate.is_some()) {
                    return Err(SpacearmError::argument(format!(
                        "event {i} (attach): give either a commanded time at= or thresholds (gap=, speed=, rate=), not both"
                    )));
                }
            }
            TopologyEvent::Detach { at, impulse, direction, .. } => {
                positive(i, kind, "at", *at, "s")?;
                if !(impulse.is_finite() && *impulse >= 0.0) {
                    return Err(SpacearmError::argument(format!("event {i} (detach): impulse must be finite and >= 0 N·s, got {impulse}")));
                }
                if let Some(d) = direction {
                    let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                    if !(n.is_finite() && n > 0.0) {
                        return Err(SpacearmError::argument(format!("event {i} (detach): direction must be a finite non-zero vector, got {d:?}")));
                    }
                }
            }
        }
        if let Some(t) = e.at() {
            if t <= last_t {
                return Err(SpacearmError::argument(format!(
                    "event {i} ({kind}): the events happen in their order, so its time must be later than the previous commanded time \
                     {last_t} s, got {t} s"
                )));
            }
            last_t = t;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn events_round_trip_through_serde_and_unknown_keys_are_refused() {
        #[derive(Debug, PartialEq, Serialize, Deserialize)]
        struct Run {
            events: Vec<TopologyEvent>,
        }
        let run = Run {
            events: vec![
                TopologyEvent::Attach { at: None, point: Some(PointSpec::Named("hand".into())), grasp: Some("handle".into()), gap: Some(0.01), speed: Some(0.1), rate: None },
                TopologyEvent::Detach { at: 2.0, body: None, impulse: 0.5, direction: Some([1.0, 0.0, 0.0]) },
            ],
        };
        let text = toml::to_string(&run).unwrap();
        assert!(text.contains("kind = \"attach\"") && text.contains("kind = \"detach\""), "{text}");
        assert_eq!(toml::from_str::<Run>(&text).unwrap(), run);
        assert!(toml::from_str::<Run>("[[events]]\nkind = \"detach\"\nat = 1.0\nimpuls = 2.0\n").is_err());
        assert!(toml::from_str::<Run>("[[events]]\nkind = \"glue\"\nat = 1.0\n").is_err());
    }

    #[test]
    fn bad_values_are_refused_with_their_names() {
        let attach = |at, gap| TopologyEvent::Attach { at, point: None, grasp: None, gap, speed: None, rate: None };
        let detach = |at, impulse, direction| TopologyEvent::Detach { at, body: None, impulse, direction };
        let msg = |e: &[TopologyEvent]| validate(e).unwrap_err().to_string();
        assert!(msg(&[attach(None, None)]).contains("give a commanded time"));
        assert!(msg(&[attach(Some(1.0), Some(0.1))]).contains("not both"));
        assert!(msg(&[attach(None, Some(-0.1))]).contains("gap must be finite and > 0 m"));
        assert!(msg(&[detach(f64::NAN, 0.0, None)]).contains("at must be finite"));
        assert!(msg(&[detach(1.0, -1.0, None)]).contains("impulse must be finite and >= 0"));
        assert!(msg(&[detach(1.0, 1.0, Some([0.0; 3]))]).contains("non-zero"));
        assert!(msg(&[attach(Some(2.0), None), detach(1.0, 0.0, None)]).contains("later than the previous commanded time 2 s"));
        assert!(validate(&[attach(None, Some(0.1)), detach(1.0, 0.0, None), attach(Some(1.5), None)]).is_ok());
    }
}
