//! The joint-space trackers [`super::JointPd`] and [`super::ComputedTorque`]: one
//! [`Controller`] ([`JointTracker`]) that holds the gains (one value or one per **actuated**
//! arm joint) and the joint reference, evaluates the errors `e = q_ref − q`, `ė = q̇_ref − q̇`
//! over the actuated arm joints and reports the reference and `|e|`; its [`JointLaw`] turns the
//! errors into torques (PD: `τ = K_p e + K_d ė`, pd.rs; computed torque: `q̈_cmd = q̈_ref + K_d ė
//! + K_p e` through the reduced EOM, paper eqs. 112–115, computed_torque.rs).

use crate::error::Result;
use crate::scenario::reference::JointReference;

use super::controller::{check_len, split_passive};
use super::{broadcast_gains, Command, ControlContext, Controller, TrackingKind};

/// Gains, reference and errors of a joint-space tracker (module docs).
#[derive(Debug, Clone)]
pub struct JointTracking {
    kp_given: Vec<f64>,
    kd_given: Vec<f64>,
    reference: JointReference,
    /// `K_p`, one per actuated arm joint (after [`JointTracking::setup`]).
    pub(crate) kp: Vec<f64>,
    /// `K_d`, one per actuated arm joint.
    pub(crate) kd: Vec<f64>,
    /// The actuated arm dofs, ascending.
    pub(crate) arm: Vec<usize>,
    /// `q_ref`, `q̇_ref`, `q̈_ref` at the last [`JointTracking::errors`].
    pub(crate) q_ref: Vec<f64>,
    pub(crate) qd_ref: Vec<f64>,
    pub(crate) qdd_ref: Vec<f64>,
    /// `e = q_ref − q` and `ė = q̇_ref − q̇` at the last [`JointTracking::errors`].
    pub(crate) e: Vec<f64>,
    pub(crate) ed: Vec<f64>,
}

impl JointTracking {
    /// Gains: one value or one per actuated arm joint (finite, ≥ 0); `reference`: one entry per
    /// actuated arm joint.
    pub(crate) fn new(kp: Vec<f64>, kd: Vec<f64>, reference: JointReference) -> Self {
        JointTracking { kp_given: kp, kd_given: kd, reference, kp: vec![], kd: vec![], arm: vec![], q_ref: vec![], qd_ref: vec![], qdd_ref: vec![], e: vec![], ed: vec![] }
    }

    /// Check the reference and the gains against the plant's actuated arm joints and size the
    /// work vectors; returns the passive arm dofs (ascending), which the tracker does not see.
    pub(crate) fn setup(&mut self, ctx: &ControlContext<'_>) -> Result<Vec<usize>> {
        let (arm, passive) = split_passive(ctx);
        check_len(&self.reference, arm.len(), passive.len(), ctx)?;
        let n = arm.len();
        self.kp = broadcast_gains("kp", &self.kp_given, n)?;
        self.kd = broadcast_gains("kd", &self.kd_given, n)?;
        self.arm = arm;
        for v in [&mut self.q_ref, &mut self.qd_ref, &mut self.qdd_ref, &mut self.e, &mut self.ed] {
            *v = vec![0.0; n];
        }
        Ok(passive)
    }

    /// Evaluate the reference at `t` and the errors at `(x, u)`; returns `|e|`.
    pub(crate) fn errors(&mut self, t: f64, x: &[f64], u: &[f64]) -> f64 {
        self.reference.eval(t, &mut self.q_ref, &mut self.qd_ref, &mut self.qdd_ref);
        let mut err2 = 0.0;
        for (i, &d) in self.arm.iter().enumerate() {
            self.e[i] = self.q_ref[i] - x[7 + d];
            self.ed[i] = self.qd_ref[i] - u[6 + d];
            err2 += self.e[i] * self.e[i];
        }
        err2.sqrt()
    }

    /// Report the reference and the tracking error `error` in `out`.
    pub(crate) fn report(&self, error: f64, out: &mut Command) {
        out.reference[..self.arm.len()].copy_from_slice(&self.q_ref);
        out.tracking_error = error;
    }
}

/// What a [`JointTracker`] makes of the tracking errors: its control law.
pub trait JointLaw: Send {
    /// The controller's name ([`Controller::name`]).
    const NAME: &'static str;

    /// Check the law against the plant and allocate its workspaces, after `tracking` is set up;
    /// `passive`: the passive arm dofs (ascending), which the tracker does not see.
    fn setup(&mut self, ctx: &ControlContext<'_>, tracking: &JointTracking, passive: Vec<usize>) -> Result<()>;

    /// Write the torques into `out` from the errors `tracking` holds at `(x, u)`.
    fn command(&mut self, tracking: &JointTracking, x: &[f64], u: &[f64], out: &mut Command) -> Result<()>;
}

/// A joint-space tracker: the reference, gains and errors of [`JointTracking`] and the law `L`.
#[derive(Debug, Clone)]
pub struct JointTracker<L> {
    pub(crate) tracking: JointTracking,
    pub(crate) law: L,
}

impl<L> JointTracker<L> {
    /// Gains: one value or one per actuated arm joint (finite, ≥ 0); `reference`: one entry per
    /// actuated arm joint (the passive joints are not commanded).
    pub(crate) fn with_law(kp: Vec<f64>, kd: Vec<f64>, reference: JointReference, law: L) -> Self {
        JointTracker { tracking: JointTracking::new(kp, kd, reference), law }
    }
}

impl<L: JointLaw> Controller for JointTracker<L> {
    fn name(&self) -> &str {
        L::NAME
    }

    fn setup(&mut self, ctx: &ControlContext<'_>) -> Result<()> {
        let passive = self.tracking.setup(ctx)?;
        self.law.setup(ctx, &self.tracking, passive)
    }

    fn command(&mut self, t: f64, x: &[f64], u: &[f64], out: &mut Command) -> Result<()> {
        let error = self.tracking.errors(t, x, u);
        self.law.command(&self.tracking, x, u, out)?;
        self.tracking.report(error, out);
        Ok(())
    }

    fn reference_len(&self) -> usize {
        self.tracking.reference.len()
    }

    fn tracking(&self) -> Option<TrackingKind> {
        Some(TrackingKind::Joint)
    }
}
