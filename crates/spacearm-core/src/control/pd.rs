//! Joint-space PD control of the arm joints: `τ = K_p (q_ref − q) + K_d (q̇_ref − q̇)`
//! (diagonal gains), on the arm joints only (the wheels are left to a base controller).

use crate::error::{Result, SpacearmError};
use crate::sim::reference::JointReference;

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
    q_ref: Vec<f64>,
    qd_ref: Vec<f64>,
    qdd_ref: Vec<f64>,
}

impl JointPd {
    /// Gains: one value or one per arm joint (finite, ≥ 0); `reference`: one entry per arm
    /// joint.
    pub fn new(kp: Vec<f64>, kd: Vec<f64>, reference: JointReference) -> Self {
        JointPd { kp_given: kp, kd_given: kd, reference, kp: vec![], kd: vec![], arm: vec![], q_ref: vec![], qd_ref: vec![], qdd_ref: vec![] }
    }
}

/// Check that a joint reference has one entry per arm joint.
pub(crate) fn check_reference_len(reference: &JointReference, ctx: &ControlContext<'_>) -> Result<()> {
    check_len(reference, ctx.arm_dofs.len(), 0, ctx)
}

/// Check that a joint reference has `n_arm` entries: the arm joints less `n_passive` passive
/// ones (which a model-based controller does not command).
pub(crate) fn check_len(reference: &JointReference, n_arm: usize, n_passive: usize, ctx: &ControlContext<'_>) -> Result<()> {
    if reference.len() != n_arm {
        let mut less = vec![];
        if !ctx.wheel_dofs.is_empty() {
            less.push(format!("{} reaction wheels", ctx.wheel_dofs.len()));
        }
        if n_passive > 0 {
            less.push(format!("{n_passive} passive joints"));
        }
        let note = if less.is_empty() { String::new() } else { format!(" (N = {} minus {})", ctx.plant.n_dof(), less.join(" and ")) };
        let what = if n_passive > 0 { "actuated arm joints" } else { "arm joints" };
        return Err(SpacearmError::Dimension { what: "the joint reference".into(), expected: format!("the number of {what} {n_arm}{note}"), got: reference.len() });
    }
    Ok(())
}

impl Controller for JointPd {
    fn name(&self) -> &str {
        "joint_pd"
    }

    fn setup(&mut self, ctx: &ControlContext<'_>) -> Result<()> {
        check_reference_len(&self.reference, ctx)?;
        let n = ctx.arm_dofs.len();
        self.kp = broadcast_gains("kp", &self.kp_given, n)?;
        self.kd = broadcast_gains("kd", &self.kd_given, n)?;
        self.arm = ctx.arm_dofs.to_vec();
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
