//! A loop closure as the plant evaluates it ([`ClosureState`]): the constrained forward
//! dynamics with Baumgarte's stabilization; the closed-chain run is [`crate::sim::closed_chain`].

use nalgebra::{DVector, Vector6};

use crate::algorithms::constrained::{constrained_forward_dynamics_after_kinematics, LoopClosure};
use crate::derivatives::{loop_closure_bias, ClosureBiasWork};
use crate::error::Result;
use crate::model::data::Data;
use crate::model::Model;

/// A loop closure as the plant evaluates it: the weld, its stabilization and workspace, and the
/// values of the last evaluation.
#[derive(Debug, Clone)]
pub(crate) struct ClosureState {
    pub(crate) closure: LoopClosure,
    alpha: f64,
    work: ClosureBiasWork,
    /// `λ` of the last evaluation: the wrench on frame b at its origin (body a gets `−λ` there).
    pub(crate) lambda: Vector6<f64>,
    /// `e` of the last evaluation.
    pub(crate) error: Vector6<f64>,
}

impl ClosureState {
    pub(crate) fn new(model: &Model, closure: LoopClosure, alpha: f64) -> Self {
        ClosureState { closure, alpha, work: ClosureBiasWork::new(model), lambda: Vector6::zeros(), error: Vector6::zeros() }
    }

    /// The constrained forward dynamics at `(x, u)` under `f` (forward kinematics at `x` in
    /// `data`); `u̇` into `data.accel`.
    pub(crate) fn evaluate(&mut self, model: &Model, data: &mut Data, x: &[f64], u: &[f64], f: &[f64]) -> Result<()> {
        let j = self.closure.jacobian(model, data);
        self.error = self.closure.error(data);
        let jdot_u = loop_closure_bias(model, &mut self.work, x, u, &self.closure)?;
        let uv = DVector::from_column_slice(u);
        let ju = &j * &uv;
        let a = self.alpha;
        let gamma = DVector::from_fn(6, |r, _| jdot_u[r] + 2.0 * a * ju[r] + a * a * self.error[r]);
        let sol = constrained_forward_dynamics_after_kinematics(model, data, &x[7..], u, f, &j, &gamma)?;
        self.lambda = Vector6::from_column_slice(sol.lambda.as_slice());
        data.accel.copy_from(&sol.du);
        Ok(())
    }
}
