//! Joint-space PD control of the arm joints: `τ = K_p (q_ref − q) + K_d (q̇_ref − q̇)`
//! (diagonal gains), on the **actuated** arm joints only: the wheels are left to a base
//! controller, and the passive joints (no motor: slosh, panels, the deflection of a compliant
//! joint; docs/flexibility.md) get exactly zero torque and no reference — their coordinates are
//! drift the law does not see, and the tracking error is over the actuated joints.

use crate::error::Result;
use crate::scenario::reference::JointReference;

use super::controller::{check_len, split_passive};
use super::{broadcast_gains, Command, ControlContext, Controller, TrackingKind};

/// Joint PD with a constant or quintic reference.
#[derive(Debug, Clone)]
pub struct JointPd {
    kp_given: Vec<f64>,
    kd_given: Vec<f64>,
    reference: JointReference,
    kp: Vec<f64>,
    kd: Vec<f64>,
    arm: Vec<usize>,
    passive: Vec<usize>,
    q_ref: Vec<f64>,
    qd_ref: Vec<f64>,
    qdd_ref: Vec<f64>,
}

impl JointPd {
    /// Gains: one value or one per actuated arm joint (finite, ≥ 0); `reference`: one entry per
    /// actuated arm joint (the passive joints are not commanded).
    pub fn new(kp: Vec<f64>, kd: Vec<f64>, reference: JointReference) -> Self {
        JointPd { kp_given: kp, kd_given: kd, reference, kp: vec![], kd: vec![], arm: vec![], passive: vec![], q_ref: vec![], qd_ref: vec![], qdd_ref: vec![] }
    }
}

impl Controller for JointPd {
    fn name(&self) -> &str {
        "joint_pd"
    }

    fn setup(&mut self, ctx: &ControlContext<'_>) -> Result<()> {
        let (arm, passive) = split_passive(ctx);
        check_len(&self.reference, arm.len(), passive.len(), ctx)?;
        let n = arm.len();
        self.kp = broadcast_gains("kp", &self.kp_given, n)?;
        self.kd = broadcast_gains("kd", &self.kd_given, n)?;
        self.arm = arm;
        self.passive = passive;
        self.q_ref = vec![0.0; n];
        self.qd_ref = vec![0.0; n];
        self.qdd_ref = vec![0.0; n];
        Ok(())
    }

    fn command(&mut self, t: f64, x: &[f64], u: &[f64], out: &mut Command) -> Result<()> {
        self.reference.eval(t, &mut self.q_ref, &mut self.qd_ref, &mut self.qdd_ref);
        let mut err2 = 0.0;
        for (i, &d) in self.arm.iter().enumerate() {
            let e = self.q_ref[i] - x[7 + d];
            let ed = self.qd_ref[i] - u[6 + d];
            out.tau[d] = self.kp[i] * e + self.kd[i] * ed;
            err2 += e * e;
        }
        for &d in &self.passive {
            out.tau[d] = 0.0;
        }
        out.reference[..self.arm.len()].copy_from_slice(&self.q_ref);
        out.tracking_error = err2.sqrt();
        Ok(())
    }

    fn reference_len(&self) -> usize {
        self.reference.len()
    }

    fn tracking(&self) -> Option<TrackingKind> {
        Some(TrackingKind::Joint)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::coordinated::tests::flexible_spatial3;
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
