//! The description of a capture mission ([`CaptureSpec`]): what [`crate::sim::capture::run_capture`]
//! runs, as data every door reads (Python's `spacearm.capture.capture` writes it), with the one
//! validation of its values ([`CaptureSpec::validate`], and [`CaptureSpec::check_work_and_reach`]
//! once the robot and the target are known; docs/capture.md, "Grasps that are refused").

use serde::{Deserialize, Serialize};

use crate::algorithms::kinematics::forward_kinematics;
use crate::algorithms::momentum::{center_of_mass_from_data, momentum};
use crate::control::spec::PointSpec;
use crate::error::{Result, SpacearmError};
use crate::model::joint::JointType;
use crate::model::{Data, Model};
use crate::scenario::modes::Mode;
use crate::sim::options::RunOrbit;

/// The most samples a capture may record over its phases (`(approach + soft + post + detumble
/// time) / dt`): more is refused before anything runs.
pub const MAX_CAPTURE_SAMPLES: f64 = 1_000_000.0;

/// The largest angle, rad, the target may turn between two samples (`|ω| dt`).
pub const MAX_TURN_PER_SAMPLE: f64 = 1.0;

/// The grasp models ([`CaptureSpec::kind`]).
pub const CAPTURE_KINDS: &[&str] = &["rigid", "point", "soft"];

/// The modes a capture runs in ([`CaptureSpec::mode`]).
pub const CAPTURE_MODES: &[&str] = &["floating", "flying"];

/// The phases of a capture, in order (the index recorded per sample).
pub const PHASES: &[&str] = &["approach", "capture", "post-capture", "detumble"];

fn default_mode() -> String {
    "floating".into()
}
fn default_kind() -> String {
    "rigid".into()
}
fn approach_time() -> f64 {
    8.0
}
fn capture_tolerance() -> f64 {
    0.01
}
fn soft_time() -> f64 {
    2.0
}
fn post_time() -> f64 {
    1.0
}
fn detumble_time() -> f64 {
    30.0
}
fn dt() -> f64 {
    0.01
}
fn rmrc_gain() -> f64 {
    2.0
}
fn rmrc_damping() -> f64 {
    0.05
}
fn velocity_gain() -> f64 {
    5.0
}
fn one() -> f64 {
    1.0
}
fn rtol() -> f64 {
    1e-10
}
fn two() -> f64 {
    2.0
}
fn five() -> f64 {
    5.0
}
fn inf() -> f64 {
    f64::INFINITY
}
fn rate_tolerance() -> f64 {
    1e-3
}

/// A capture mission (docs/capture.md): a rigid target in `target_state` grasped at its point
/// `grasp` by the robot's `point`, in `mode`, with the grasp model `kind`, the phase durations,
/// the recording interval, the integrator's tolerance and the controllers' gains and limits.
/// The defaults are `spacearm.capture.capture`'s.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaptureSpec {
    /// The target's 13-state `[r, quat xyzw, v, ω]` in 𝒥 at time 0.
    pub target_state: Vec<f64>,
    /// The target's grasp point: a named point of the target's model (absent: its first).
    #[serde(default)]
    pub grasp: Option<String>,
    /// The name of the target's link in the captured system (absent: the target model's name).
    #[serde(default)]
    pub name: Option<String>,
    /// The robot's grasp point (absent: the end effector).
    #[serde(default)]
    pub point: Option<PointSpec>,
    /// `"floating"` or `"flying"` ([`CAPTURE_MODES`]).
    #[serde(default = "default_mode")]
    pub mode: String,
    /// `"rigid"`, `"point"` or `"soft"` ([`CAPTURE_KINDS`]).
    #[serde(default = "default_kind")]
    pub kind: String,
    /// Restitution of a point contact, in [0, 1] (0 for the other kinds).
    #[serde(default)]
    pub restitution: f64,
    /// Approach duration, s.
    #[serde(default = "approach_time")]
    pub approach_time: f64,
    /// The gap at which the grasp happens, m.
    #[serde(default = "capture_tolerance")]
    pub capture_tolerance: f64,
    /// Duration of the soft phase (`kind = "soft"`), s.
    #[serde(default = "soft_time")]
    pub soft_time: f64,
    /// Duration of the post-capture phase, s.
    #[serde(default = "post_time")]
    pub post_time: f64,
    /// Duration of the detumble phase, s.
    #[serde(default = "detumble_time")]
    pub detumble_time: f64,
    /// Recording interval, s (the soft phase records every `dt / 5`).
    #[serde(default = "dt")]
    pub dt: f64,
    /// Position gain of the approach's RMRC, 1/s.
    #[serde(default = "rmrc_gain")]
    pub rmrc_gain: f64,
    /// The largest damping λ_max of the approach's RMRC, m.
    #[serde(default = "rmrc_damping")]
    pub rmrc_damping: f64,
    /// Joint-rate tracking gain of the approach, 1/s.
    #[serde(default = "velocity_gain")]
    pub velocity_gain: f64,
    /// Cap on the approach's joint-rate command, rad/s.
    #[serde(default = "one")]
    pub max_joint_rate: f64,
    /// DOPRI5 relative tolerance of every phase (absolute: `rtol · 1e-2`).
    #[serde(default = "rtol")]
    pub rtol: f64,
    /// Hold-law stiffness, 1/s².
    #[serde(default = "one")]
    pub kp: f64,
    /// Hold-law damping, 1/s.
    #[serde(default = "two")]
    pub kd: f64,
    /// Momentum-damping time constant (flying mode), s.
    #[serde(default = "five")]
    pub time_constant: f64,
    /// Joint torque limit, N·m (inf: none).
    #[serde(default = "inf")]
    pub max_joint_torque: f64,
    /// Thruster force limit, N (inf: none).
    #[serde(default = "inf")]
    pub max_force: f64,
    /// Thruster torque limit, N·m (inf: none).
    #[serde(default = "inf")]
    pub max_torque: f64,
    /// Rates below which the system counts as detumbled, rad/s.
    #[serde(default = "rate_tolerance")]
    pub rate_tolerance: f64,
    /// The orbit of the run and whether gravity's tidal part acts (docs/orbit.md, "Capture in
    /// orbit"; the keys `orbit` and `gravity_gradient`, as a run's).
    #[serde(flatten)]
    pub in_orbit: RunOrbit,
}

/// `v` formatted as Python's `format(v, ".{precision}g")` (the messages the Python door wrote).
pub(crate) fn fmt_g(v: f64, precision: usize) -> String {
    if v.is_nan() {
        return "nan".into();
    }
    if v.is_infinite() {
        return if v > 0.0 { "inf".into() } else { "-inf".into() };
    }
    if v == 0.0 {
        return if v.is_sign_negative() { "-0".into() } else { "0".into() };
    }
    let p = precision.max(1);
    let sci = format!("{:.*e}", p - 1, v);
    let (mantissa, exp) = sci.split_once('e').unwrap_or((&sci, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    let strip = |s: String| -> String {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    };
    if exp < -4 || exp >= p as i32 {
        let m = strip(mantissa.to_string());
        format!("{m}e{}{:02}", if exp < 0 { '-' } else { '+' }, exp.abs())
    } else {
        strip(format!("{:.*}", (p as i32 - 1 - exp).max(0) as usize, v))
    }
}

/// `v` as Python's `str(float)` writes it for the usual magnitudes (`1.0`, `0.01`).
pub(crate) fn fmt_repr(v: f64) -> String {
    if v.is_finite() && v.fract() == 0.0 && v.abs() < 1e16 {
        format!("{v:.1}")
    } else {
        format!("{v}")
    }
}

/// `['a', 'b']`: a list of names as the Python door wrote it.
fn py_list(names: &[&str]) -> String {
    format!("[{}]", names.iter().map(|n| format!("'{n}'")).collect::<Vec<_>>().join(", "))
}

fn arg(msg: String) -> SpacearmError {
    SpacearmError::InvalidArgument(msg)
}

impl CaptureSpec {
    /// Whether the tidal wrenches act: in orbit, unless `gravity_gradient` is false.
    pub fn tidal(&self) -> bool {
        self.in_orbit.tidal()
    }

    /// The mode.
    pub fn run_mode(&self) -> Result<Mode> {
        Mode::from_name(&self.mode)
    }

    /// Every check that needs neither the robot nor the target (the rules of
    /// `spacearm.capture.capture`, with its messages).
    pub fn validate(&self) -> Result<()> {
        if !CAPTURE_MODES.contains(&self.mode.as_str()) {
            return Err(arg(format!("mode must be one of {}, got '{}'", py_list(CAPTURE_MODES), self.mode)));
        }
        if !CAPTURE_KINDS.contains(&self.kind.as_str()) {
            return Err(arg(format!("kind must be one of {}, got '{}'", py_list(CAPTURE_KINDS), self.kind)));
        }
        for (k, v) in self.times() {
            if !(v > 0.0) {
                return Err(arg(format!("{k} must be > 0, got {}", fmt_repr(v))));
            }
        }
        for (k, v) in [("max_joint_torque", self.max_joint_torque), ("max_force", self.max_force), ("max_torque", self.max_torque)] {
            if !(v > 0.0) {
                return Err(arg(format!("{k} must be > 0 (inf: no limit), got {}", fmt_repr(v))));
            }
        }
        let e = self.restitution;
        if !(0.0..=1.0).contains(&e) || (self.kind != "point" && e != 0.0) {
            return Err(arg(format!(
                "restitution must be in [0, 1] and is for kind='point' only (a grasp is plastic), got {} with kind='{}'",
                fmt_repr(e),
                self.kind
            )));
        }
        if self.in_orbit.options()?.is_some() && self.kind == "soft" {
            return Err(arg("kind='soft' is not implemented in orbit (the core's soft-capture plant runs in empty space); use kind='rigid' or kind='point' with orbit=".into()));
        }
        for (k, v) in [("rtol", self.rtol), ("time_constant", self.time_constant), ("rate_tolerance", self.rate_tolerance)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(arg(format!("{k} must be finite and > 0, got {}", fmt_repr(v))));
            }
        }
        for (k, v) in [("kp", self.kp), ("kd", self.kd), ("rmrc_gain", self.rmrc_gain), ("rmrc_damping", self.rmrc_damping), ("velocity_gain", self.velocity_gain)] {
            if !v.is_finite() {
                return Err(arg(format!("{k} must be finite, got {v}")));
            }
        }
        crate::error::check_finite("target_state", &self.target_state)?;
        let total: f64 = self.phase_total();
        if total / self.dt > MAX_CAPTURE_SAMPLES {
            return Err(arg(format!(
                "the capture would record {} samples ({} s of phases every dt = {} s), more than the {} allowed: raise dt or shorten the phases",
                fmt_g(total / self.dt, 3),
                fmt_g(total, 6),
                fmt_g(self.dt, 6),
                fmt_g(MAX_CAPTURE_SAMPLES, 6)
            )));
        }
        if self.target_state.len() != 13 {
            return Ok(()); // a jointed target's [x, u]: no spin rule (spacearm.capture.capture runs it)
        }
        let w = &self.target_state[10..13];
        let spin = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
        if spin * self.dt > MAX_TURN_PER_SAMPLE {
            return Err(arg(format!(
                "the target spins at {} rad/s: it turns {} rad between samples (dt = {} s), more than the {} rad the approach can follow; use dt <= {} s",
                fmt_g(spin, 4),
                fmt_g(spin * self.dt, 3),
                fmt_g(self.dt, 6),
                fmt_g(MAX_TURN_PER_SAMPLE, 6),
                fmt_g(MAX_TURN_PER_SAMPLE / spin, 3)
            )));
        }
        Ok(())
    }

    fn times(&self) -> [(&'static str, f64); 6] {
        [
            ("approach_time", self.approach_time),
            ("soft_time", self.soft_time),
            ("post_time", self.post_time),
            ("detumble_time", self.detumble_time),
            ("dt", self.dt),
            ("capture_tolerance", self.capture_tolerance),
        ]
    }

    /// The phases' total time, s (`approach + soft + post + detumble`, as the sample bound counts it).
    fn phase_total(&self) -> f64 {
        self.approach_time + self.soft_time + self.post_time + self.detumble_time
    }

    /// Refuse, before any run, a capture whose grasp point stays out of the arm's reach
    /// (floating mode: the system CM moves at constant velocity `P / m`). `body`, `offset`: the
    /// robot's grasp point; `handle`: the target's grasp point from its CM.
    pub fn check_work_and_reach(&self, robot: &Model, x0: &[f64], u0: &[f64], body: usize, offset: &nalgebra::Vector3<f64>, handle: f64) -> Result<()> {
        if self.mode != "floating" {
            return Ok(()); // the thrusters move the system CM: no bound from the momentum
        }
        let (point_reach, body_reach) = reach_bound(robot, body, offset);
        if !point_reach.is_finite() {
            return Ok(());
        }
        let mut data = Data::new(robot);
        forward_kinematics(robot, &mut data, x0)?;
        let cm0 = center_of_mass_from_data(robot, &data);
        let v_cm = momentum(robot, &mut data, x0, u0)?.linear / robot.total_mass();
        let s = &self.target_state;
        let p0 = nalgebra::Vector3::new(s[0], s[1], s[2]) - cm0;
        let v = nalgebra::Vector3::new(s[7], s[8], s[9]) - v_cm;
        let vv = v.dot(&v);
        let when = if vv == 0.0 { 0.0 } else { (-p0.dot(&v) / vv).clamp(0.0, self.approach_time) };
        let gap = (p0 + v * when).norm();
        if gap - handle > point_reach + body_reach {
            return Err(SpacearmError::Simulation(format!(
                "the approach cannot reach the target: its grasp point stays at least {} m from the robot's system CM (closest at t = {} s of the {} s approach), farther than the {} m that any configuration of '{}' reaches (its chain's lengths); place the target within reach",
                fmt_g(gap - handle, 4),
                fmt_g(when, 3),
                fmt_g(self.approach_time, 6),
                fmt_g(point_reach + body_reach, 4),
                robot.name()
            )));
        }
        Ok(())
    }
}

/// Upper bounds on how far the robot's point `(body, offset)` and any body's CM can be from the
/// base CM, m: the sums of the joint offsets, CM offsets and prismatic travels along the chain
/// (`inf` with an unbounded prismatic joint). The system CM is a mass-weighted mean of the
/// bodies' CMs, so `|p − r_cm| ≤ point bound + body bound` in every configuration.
fn reach_bound(robot: &Model, body: usize, offset: &nalgebra::Vector3<f64>) -> (f64, f64) {
    let mut reach = vec![0.0];
    for link in robot.links() {
        let travel = if link.joint.kind == JointType::Prismatic { link.joint.limits.lower.abs().max(link.joint.limits.upper.abs()) } else { 0.0 };
        reach.push(reach[link.parent] + link.joint.origin_in_parent.norm() + travel + link.com_from_joint.norm());
    }
    let most = reach.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (reach[body] + offset.norm(), most)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fmt_g_writes_what_python_writes() {
        for (v, p, want) in [(4.1e6, 3, "4.1e+06"), (1e6, 4, "1e+06"), (0.2, 6, "0.2"), (1e-5, 6, "1e-05"), (41.0, 6, "41"), (1000000.0, 6, "1e+06"), (0.000123456, 3, "0.000123"), (123.456, 4, "123.5")] {
            assert_eq!(fmt_g(v, p), want, "{v} .{p}g");
        }
    }

    #[test]
    fn defaults_are_the_python_defaults_and_bad_values_are_refused() {
        let mut spec: CaptureSpec = toml::from_str("target_state = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.2]").unwrap();
        assert_eq!((spec.approach_time, spec.dt, spec.kind.as_str(), spec.mode.as_str()), (8.0, 0.01, "rigid", "floating"));
        spec.validate().unwrap();
        spec.dt = 1e-5;
        assert!(spec.validate().unwrap_err().to_string().contains("would record 4.1e+06 samples"));
        spec.dt = 0.01;
        spec.restitution = 0.5;
        assert!(spec.validate().unwrap_err().to_string().contains("kind='point' only"));
    }
}
