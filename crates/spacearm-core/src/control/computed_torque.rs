//! Computed-torque control on the reduced (generalized) equations of motion, paper eqs.
//! 112–115: `τ = H̃* (q̈_ref + K_d ė + K_p e) + c̃*`, `e = q_ref − q`, where `H̃*`, `c̃*` come from
//! the controller's own model (by default the plant's; [`super::mismatch::perturbed_model`]
//! builds a mismatched one — mass and inertia errors, fuel slosh).
//!
//! The reduced EOM with a base wrench (docs/physics.md) is `H* q̈ + c* + H0mᵀ H0⁻¹ F_b = τ`, so when a
//! base controller commands a wrench `F_b` (in [`super::Combined`]) its effect is compensated
//! by the extra term, with `F_b` as the mode applies it. With reaction wheels the wheels' torques
//! `τ_W` are given (by the base controller, or zero) and the arm joints `A` get the torques
//! that produce the desired `q̈_A` exactly: from the wheel rows
//! `q̈_W = H*_WW⁻¹ (τ_W − g_W − H*_WA q̈_A)` and then `τ_A = H*_AA q̈_A + H*_AW q̈_W + g_A`, with
//! `g = c* + H0mᵀ H0⁻¹ F_b`.

use crate::model::data::Data;
use crate::error::{Result, SpacearmError};
use crate::gjm::{compute_generalized_bias, compute_generalized_inertia};
use crate::algorithms::inertia::BaseInverse;
use crate::model::Model;
use crate::sim::modes::Mode;
use crate::sim::reference::JointReference;

use super::pd::check_reference_len;
use super::{broadcast_gains, cholesky_solve_in_place, Command, ControlContext, Controller, TrackingKind};

/// Joint torques from the reduced EOM of a (controller's) model for desired arm accelerations,
/// given the wheel torques and the base wrench already in a [`Command`].
#[derive(Debug, Clone)]
pub struct ReducedInverseDynamics {
    model: Model,
    data: Data,
    mode: Mode,
    arm: Vec<usize>,
    wheels: Vec<usize>,
    g: Vec<f64>,
    h_ww: Vec<f64>,
    qdd_w: Vec<f64>,
}

impl ReducedInverseDynamics {
    /// For `model`, which must have the plant's degrees of freedom.
    pub fn new(model: Model, ctx: &ControlContext<'_>) -> Result<Self> {
        if model.n_dof() != ctx.plant.n_dof() {
            return Err(SpacearmError::argument(format!(
                "the controller's model '{}' has {} joint dofs but the plant '{}' has {}",
                model.name(),
                model.n_dof(),
                ctx.plant.name(),
                ctx.plant.n_dof()
            )));
        }
        let n = model.n_dof();
        let w = ctx.wheel_dofs.len();
        let data = Data::new(&model);
        Ok(ReducedInverseDynamics {
            model,
            data,
            mode: ctx.mode,
            arm: ctx.arm_dofs.to_vec(),
            wheels: ctx.wheel_dofs.to_vec(),
            g: vec![0.0; n],
            h_ww: vec![0.0; w * w],
            qdd_w: vec![0.0; w],
        })
    }

    /// The model the torques are computed with.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// Write into `out.tau` the arm torques that give the arm joints the accelerations
    /// `qdd_arm` (one per arm joint), with the wheel torques and base wrench of `out` taken as
    /// given.
    pub fn arm_torques(&mut self, x: &[f64], u: &[f64], qdd_arm: &[f64], out: &mut Command) -> Result<()> {
        compute_generalized_inertia(&self.model, &mut self.data, x)?;
        compute_generalized_bias(&self.model, &mut self.data, x, u)?;
        let n = self.model.n_dof();
        self.g.copy_from_slice(&self.data.generalized_bias.as_slice()[..n]);
        if out.base_wrench.iter().any(|v| *v != 0.0) {
            // After the bias, the base rows of the mass matrix and H0 (the base's composite
            // inertia) are current.
            let inv = BaseInverse::new(&self.data.subtree_inertia[0])?;
            let (applied, _) = self.mode.applied_wrench(&out.base_wrench, &inv.base_to_com);
            let w = inv.apply(&applied);
            for j in 0..n {
                self.g[j] += self.data.mass_matrix.fixed_view::<6, 1>(0, 6 + j).dot(&w);
            }
        }
        let hs = &self.data.generalized_inertia;
        let nw = self.wheels.len();
        if nw > 0 {
            for (a, &wa) in self.wheels.iter().enumerate() {
                let mut r = out.tau[wa] - self.g[wa];
                for (i, &d) in self.arm.iter().enumerate() {
                    r -= hs[(wa, d)] * qdd_arm[i];
                }
                self.qdd_w[a] = r;
                for (b, &wb) in self.wheels.iter().enumerate() {
                    self.h_ww[a + b * nw] = hs[(wa, wb)];
                }
            }
            if !cholesky_solve_in_place(&mut self.h_ww, nw, &mut self.qdd_w) {
                return Err(SpacearmError::Singular("the wheel block of the generalized inertia H*".into()));
            }
        }
        for &d in &self.arm {
            let mut t = self.g[d];
            for (k, &dk) in self.arm.iter().enumerate() {
                t += hs[(d, dk)] * qdd_arm[k];
            }
            for (k, &wk) in self.wheels.iter().enumerate() {
                t += hs[(d, wk)] * self.qdd_w[k];
            }
            out.tau[d] = t;
        }
        Ok(())
    }
}

/// Computed-torque tracking of a joint reference (paper eqs. 112–115).
#[derive(Debug, Clone)]
pub struct ComputedTorque {
    kp_given: Vec<f64>,
    kd_given: Vec<f64>,
    reference: JointReference,
    model: Option<Model>,
    inner: Option<ReducedInverseDynamics>,
    kp: Vec<f64>,
    kd: Vec<f64>,
    arm: Vec<usize>,
    q_ref: Vec<f64>,
    qd_ref: Vec<f64>,
    qdd_ref: Vec<f64>,
    qdd_cmd: Vec<f64>,
}

impl ComputedTorque {
    /// Gains: one value or one per arm joint; `model`: the controller's model (`None`: the
    /// plant's).
    pub fn new(kp: Vec<f64>, kd: Vec<f64>, reference: JointReference, model: Option<Model>) -> Self {
        ComputedTorque {
            kp_given: kp,
            kd_given: kd,
            reference,
            model,
            inner: None,
            kp: vec![],
            kd: vec![],
            arm: vec![],
            q_ref: vec![],
            qd_ref: vec![],
            qdd_ref: vec![],
            qdd_cmd: vec![],
        }
    }
}

impl Controller for ComputedTorque {
    fn name(&self) -> &str {
        "computed_torque"
    }

    fn setup(&mut self, ctx: &ControlContext<'_>) -> Result<()> {
        check_reference_len(&self.reference, ctx)?;
        let n = ctx.arm_dofs.len();
        self.kp = broadcast_gains("kp", &self.kp_given, n)?;
        self.kd = broadcast_gains("kd", &self.kd_given, n)?;
        let model = self.model.clone().unwrap_or_else(|| ctx.plant.clone());
        self.inner = Some(ReducedInverseDynamics::new(model, ctx)?);
        self.arm = ctx.arm_dofs.to_vec();
        self.q_ref = vec![0.0; n];
        self.qd_ref = vec![0.0; n];
        self.qdd_ref = vec![0.0; n];
        self.qdd_cmd = vec![0.0; n];
        Ok(())
    }

    fn command(&mut self, t: f64, x: &[f64], u: &[f64], out: &mut Command) -> Result<()> {
        self.reference.eval(t, &mut self.q_ref, &mut self.qd_ref, &mut self.qdd_ref);
        let mut err2 = 0.0;
        for (i, &d) in self.arm.iter().enumerate() {
            let e = self.q_ref[i] - x[7 + d];
            let ed = self.qd_ref[i] - u[6 + d];
            self.qdd_cmd[i] = self.qdd_ref[i] + self.kd[i] * ed + self.kp[i] * e;
            err2 += e * e;
        }
        let inner = self.inner.as_mut().ok_or_else(|| SpacearmError::Simulation("computed torque used before setup".into()))?;
        inner.arm_torques(x, u, &self.qdd_cmd, out)?;
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
