//! The options of a run ([`SimOptions`]: mode, integrator, duration, steps, records, actuators,
//! orbit), checked by [`SimOptions::validate`]; the loop is [`crate::sim::simulate`].

use crate::error::{Result, SpacearmError};
use crate::math::integrate::IntegratorKind;
use crate::scenario::actuators::ThrusterLimits;
use crate::scenario::modes::Mode;
use crate::scenario::orbit::Orbit;
use crate::sim::stop::StopCondition;

/// Options of a simulation.
#[derive(Debug, Clone, PartialEq)]
pub struct SimOptions {
    /// Maneuvering mode.
    pub mode: Mode,
    /// Integrator.
    pub integrator: IntegratorKind,
    /// Simulated time, s (> 0).
    pub duration: f64,
    /// RK4: the step; DOPRI5: the output (recording) interval. s, > 0.
    pub dt: f64,
    /// DOPRI5 relative tolerance (> 0).
    pub rtol: f64,
    /// DOPRI5 absolute tolerance (≥ 0).
    pub atol: f64,
    /// RK4: keep every k-th step (≥ 1); the final state is always kept.
    pub record_every: usize,
    /// Wheel degrees of freedom; `None`: [`detect_reaction_wheels`](crate::scenario::actuators::detect_reaction_wheels).
    pub wheels: Option<Vec<usize>>,
    /// Thruster limits (flying modes); `None`: unlimited.
    pub thrusters: Option<ThrusterLimits>,
    /// Whether the joints' effort and velocity limits apply (they always do to nothing else).
    pub joint_limits: bool,
    /// Largest number of attempted steps (DOPRI5) before giving up.
    pub max_steps: usize,
    /// The orbit of the run ([`OrbitOptions`]); `None`: empty, inertial space.
    pub orbit: Option<OrbitOptions>,
    /// Conditions that stop the run before its duration, the first to hold wins
    /// ([`crate::sim::events`]; [`SimResult::stop`](crate::sim::result::SimResult::stop) says which and when); empty: none. Honoured
    /// by [`simulate`](crate::sim::simulate::simulate) (both integrators); the entry points that stack equal-length runs or step
    /// a plant refuse them ([`SimOptions::refuse_stop`]).
    pub stop: Vec<StopCondition>,
}

/// A run in orbit (docs/orbit.md): the origin of 𝒥 is the orbit's point `O`, propagated on its
/// own (point mass, two-body + J2, [`OrbitTrack`](crate::scenario::orbit::OrbitTrack)), with 𝒥's axes those of ECI; the states stay
/// relative to `O`. With `gravity_gradient`, every body feels the tidal force `mᵢ G ρᵢ` at its CM
/// (`ρᵢ` its CM from `O`) and the torque `axial(Iᵢ G − G Iᵢ)` about it, `G` the gradient at `O`
/// ([`crate::scenario::orbit`]); the uniform part of gravity moves `O` and with it everything. The
/// conserved quantities of the mode are then monitored as balances: the change of each equals
/// the integral of the tidal wrenches (trapezoid over the samples), the energy is dropped.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrbitOptions {
    /// The orbit of `O` (at `t = 0`).
    pub orbit: Orbit,
    /// Whether the tidal wrenches act on the bodies.
    pub gravity_gradient: bool,
}

/// The default step budget of a DOPRI5 run ([`SimOptions::max_steps`], accepted and rejected
/// steps): spent, the run stops with a `SimulationError` naming the time reached and the
/// budget. About two minutes of spatial6 (a run of 10⁶ s at rtol 1e-12 reaches t = 1.2·10⁴ s).
pub const DEFAULT_MAX_STEPS: usize = 10_000_000;

impl Default for SimOptions {
    fn default() -> Self {
        SimOptions {
            mode: Mode::Floating,
            integrator: IntegratorKind::Rk4,
            duration: 1.0,
            dt: 1e-3,
            rtol: 1e-9,
            atol: 1e-12,
            record_every: 1,
            wheels: None,
            thrusters: None,
            joint_limits: true,
            max_steps: DEFAULT_MAX_STEPS,
            orbit: None,
            stop: Vec::new(),
        }
    }
}

impl SimOptions {
    /// Check every value (positive duration and step, tolerances, counts).
    pub fn validate(&self) -> Result<()> {
        let arg = |msg: String| Err(SpacearmError::argument(msg));
        if !(self.duration.is_finite() && self.duration > 0.0) {
            return arg(format!("duration must be finite and > 0 s, got {}", self.duration));
        }
        if !(self.dt.is_finite() && self.dt > 0.0) {
            return arg(format!("dt must be finite and > 0 s, got {}", self.dt));
        }
        if self.duration / self.dt > 1e9 {
            return arg(format!("duration / dt = {:e} steps or samples is more than the 1e9 allowed", self.duration / self.dt));
        }
        if !(self.rtol.is_finite() && self.rtol > 0.0) {
            return arg(format!("rtol must be finite and > 0, got {}", self.rtol));
        }
        if !(self.atol.is_finite() && self.atol >= 0.0) {
            return arg(format!("atol must be finite and >= 0, got {}", self.atol));
        }
        if self.record_every == 0 {
            return arg("record_every must be >= 1".into());
        }
        if self.max_steps == 0 {
            return arg("max_steps must be >= 1".into());
        }
        crate::sim::stop::validate(&self.stop)
    }

    /// Refuse stop conditions where `entry` (a run that is not [`simulate`](crate::sim::simulate::simulate)'s) cannot honour them.
    pub fn refuse_stop(&self, entry: &str) -> Result<()> {
        if self.stop.is_empty() {
            return Ok(());
        }
        Err(SpacearmError::argument(format!(
            "{entry} does not take stop conditions (a run that stops early has its own length): use simulate for a run with stop="
        )))
    }
}
