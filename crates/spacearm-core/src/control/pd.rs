//! Joint-space PD control of the arm joints: `τ = K_p (q_ref − q) + K_d (q̇_ref − q̇)`
//! (diagonal gains), on the **actuated** arm joints only: the wheels are left to a base
//! controller, and the passive joints (no motor: slosh, panels, the deflection of a compliant
//! joint; docs/flexibility.md) get exactly zero torque and no reference — their coordinates are
//! drift the law does not see, and the tracking error is over the actuated joints.

use crate::error::Result;
use crate::scenario::reference::JointReference;

use super::joint_tracking::{JointLaw, JointTracker, JointTracking};
use super::{Command, ControlContext};

/// Joint PD with a constant or quintic reference.
pub type JointPd = JointTracker<PdLaw>;

/// The law of [`JointPd`]: `τ = K_p e + K_d ė` on the actuated arm joints, zero on the passive ones.
#[derive(Debug, Clone)]
pub struct PdLaw {
    passive: Vec<usize>,
}

impl JointPd {
    /// Gains: one value or one per actuated arm joint (finite, ≥ 0); `reference`: one entry per
    /// actuated arm joint (the passive joints are not commanded).
    pub fn new(kp: Vec<f64>, kd: Vec<f64>, reference: JointReference) -> Self {
        JointTracker::with_law(kp, kd, reference, PdLaw { passive: vec![] })
    }
}

impl JointLaw for PdLaw {
    const NAME: &'static str = "joint_pd";

    fn setup(&mut self, _ctx: &ControlContext<'_>, _tracking: &JointTracking, passive: Vec<usize>) -> Result<()> {
        self.passive = passive;
        Ok(())
    }

    fn command(&mut self, j: &JointTracking, _x: &[f64], _u: &[f64], out: &mut Command) -> Result<()> {
        for (i, &d) in j.arm.iter().enumerate() {
            out.tau[d] = j.kp[i] * j.e[i] + j.kd[i] * j.ed[i];
        }
        for &d in &self.passive {
            out.tau[d] = 0.0;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::coordinated::tests::flexible_spatial3;
    use crate::control::Controller;
    use crate::scenario::actuators::Actuators;
    use crate::scenario::modes::Mode;

    #[test]
    fn passive_joints_get_no_reference_no_torque_and_no_error() {
        let m = flexible_spatial3();
        let act: Vec<usize> = (0..m.n_dof()).filter(|&d| m.dof_dynamics()[d].actuated).collect();
        assert_eq!(act, vec![0, 2, 4]);
        let arm: Vec<usize> = (0..m.n_dof()).collect();
        let actuators = Actuators::new(&m, false, None);
        let ctx = ControlContext { plant: &m, mode: Mode::Floating, wheel_dofs: &[], arm_dofs: &arm, actuators: &actuators };
        // A reference over every arm joint (passive ones included) is refused, naming the count.
        let mut all = JointPd::new(vec![1.0], vec![1.0], JointReference::constant(vec![0.0; 5]).unwrap());
        let err = all.setup(&ctx).unwrap_err().to_string();
        assert!(err.contains("actuated arm joints 3") && err.contains("2 passive joints"), "{err}");
        let (kp, kd, q_ref) = ([3.0, 5.0, 7.0], [0.5, 0.25, 2.0], [0.2, -0.4, 0.9]);
        let mut pd = JointPd::new(kp.to_vec(), kd.to_vec(), JointReference::constant(q_ref.to_vec()).unwrap());
        pd.setup(&ctx).unwrap();
        let mut x = vec![0.0; m.nx()];
        x[6] = 1.0;
        x[7..].copy_from_slice(&[0.1, 0.5, -0.3, 0.7, 0.4]);
        let mut u = vec![0.0; m.nu()];
        u[6..].copy_from_slice(&[0.3, -1.0, 0.2, 2.0, -0.1]);
        let mut out = Command::new(m.n_dof(), 3);
        out.tau.fill(99.0);
        pd.command(0.0, &x, &u, &mut out).unwrap();
        let mut err2 = 0.0;
        for (i, &d) in act.iter().enumerate() {
            assert_eq!(out.tau[d], kp[i] * (q_ref[i] - x[7 + d]) + kd[i] * (0.0 - u[6 + d]));
            err2 += (q_ref[i] - x[7 + d]).powi(2);
        }
        assert_eq!((out.tau[1], out.tau[3]), (0.0, 0.0));
        assert_eq!(out.reference, q_ref.to_vec());
        assert!((out.tracking_error - err2.sqrt()).abs() < 1e-15);
    }
}
