//! Momentum unloading of a CMG cluster with the base's thrusters (docs/cmg.md, "Momentum
//! unloading"; Wie, *Space Vehicle Dynamics and Control*, 2nd ed., 2008, ch. 7: momentum
//! management of momentum-exchange actuators by external torques).
//!
//! A cluster that holds the attitude against a persistent disturbance (an arm's reaction, an
//! initial spin) stores the momentum in its rotors until it reaches its envelope. The thrusters
//! then apply an external torque on the base,
//!
//! `N_u = −k (H − H_goal)`,
//!
//! `H = Σ h_i ŝ_i` the cluster's momentum (in 𝒥, as the envelope fraction measures it), `k`
//! the unloading gain (1/s), while the steering law keeps holding the attitude with that torque
//! fed forward (the cluster is steered to give the base `N − N_u`, so the base feels the PD's
//! `N`). The total angular momentum then changes by the thrusters' angular impulse,
//! `L̇ = N_u`; with the base held (`ω₀ ≈ 0`, the arm still) `L ≈ H`, so the cluster's momentum
//! decays to the goal as the first-order closed form `H(t) = H_goal + (H(0) − H_goal) e^{−k t}`.
//!
//! The unloading switches with hysteresis on the envelope fraction `f = |H| / σ(Ĥ)`
//! ([`crate::analysis::cmg_envelope::envelope_fraction`]): on when `f ≥ above`, off when
//! `f ≤ below` (`below < above`), decided at the start of each integrator step
//! ([`super::Controller::sample`]), so the law is smooth within a step.

use nalgebra::Vector3;

use crate::error::{Result, SpacearmError};

/// The unloading law's parameters and its on/off state (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct MomentumUnloading {
    /// `k`, 1/s (> 0).
    pub gain: f64,
    /// The fraction at which unloading starts.
    pub above: f64,
    /// The fraction at which it stops.
    pub below: f64,
    /// `H_goal` in 𝒥, N·m·s.
    pub goal: Vector3<f64>,
    on: bool,
}

impl MomentumUnloading {
    /// The law of gain `k` (1/s), thresholds `below < above` on the envelope fraction and goal
    /// momentum (N·m·s, in 𝒥), off; checked.
    pub fn new(gain: f64, above: f64, below: f64, goal: [f64; 3]) -> Result<Self> {
        check(gain, above, below, goal)?;
        Ok(MomentumUnloading { gain, above, below, goal: Vector3::from(goal), on: false })
    }

    /// Whether the thrusters unload now.
    pub fn is_on(&self) -> bool {
        self.on
    }

    /// Switch at the envelope fraction `fraction` (hysteresis: on at `≥ above`, off at `≤ below`).
    pub fn update(&mut self, fraction: f64) {
        if fraction >= self.above {
            self.on = true;
        } else if fraction <= self.below {
            self.on = false;
        }
    }

    /// The unloading torque on the base at the cluster momentum `h` (zero when off).
    pub fn torque(&self, h: &Vector3<f64>) -> Vector3<f64> {
        if self.on {
            -(h - self.goal) * self.gain
        } else {
            Vector3::zeros()
        }
    }
}

/// The checks of the unloading options (the run description's and the law's): `gain > 0`,
/// `0 ≤ below < above`, a finite goal.
pub fn check(gain: f64, above: f64, below: f64, goal: [f64; 3]) -> Result<()> {
    if !(gain.is_finite() && gain > 0.0) {
        return Err(SpacearmError::argument(format!("cmg_steering unload_gain must be finite and > 0 1/s (0: no unloading), got {gain}")));
    }
    if !(below.is_finite() && above.is_finite() && 0.0 <= below && below < above) {
        return Err(SpacearmError::argument(format!(
            "cmg_steering unloading needs 0 <= unload_below < unload_above (envelope fractions: on at unload_above, off at unload_below), \
             got unload_above = {above}, unload_below = {below}"
        )));
    }
    if goal.iter().any(|v| !v.is_finite()) {
        return Err(SpacearmError::argument(format!("cmg_steering unload_goal must be finite, got {goal:?}")));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_switch_has_hysteresis_and_the_torque_drives_h_to_the_goal() {
        let mut u = MomentumUnloading::new(0.5, 0.8, 0.3, [0.0, 0.0, 1.0]).unwrap();
        let h = Vector3::new(2.0, 0.0, 3.0);
        assert_eq!(u.torque(&h), Vector3::zeros());
        let states: Vec<bool> = [0.5, 0.79, 0.8, 0.5, 0.31, 0.3, 0.5, 0.9]
            .iter()
            .map(|&f| {
                u.update(f);
                u.is_on()
            })
            .collect();
        assert_eq!(states, [false, false, true, true, true, false, false, true]);
        // −k (H − H_goal), along −(H − H_goal): it shrinks the difference at the rate k.
        assert_eq!(u.torque(&h), Vector3::new(-1.0, 0.0, -1.0));
    }

    #[test]
    fn bad_options_are_refused() {
        assert!(MomentumUnloading::new(0.0, 0.8, 0.3, [0.0; 3]).is_err());
        assert!(MomentumUnloading::new(1.0, 0.3, 0.3, [0.0; 3]).unwrap_err().to_string().contains("unload_below < unload_above"));
        assert!(MomentumUnloading::new(1.0, 0.8, -0.1, [0.0; 3]).is_err());
        assert!(MomentumUnloading::new(1.0, 0.8, 0.3, [f64::NAN, 0.0, 0.0]).is_err());
    }
}
