//! Computed-torque control on the reduced (generalized) equations of motion, paper eqs.
//! 112–115: `τ = H̃* (q̈_ref + K_d ė + K_p e) + c̃*`, `e = q_ref − q`, where `H̃*`, `c̃*` come from
//! the controller's own model (by default the plant's; [`super::mismatch::perturbed_model`]
//! builds a mismatched one — mass and inertia errors, fuel slosh).
//!
//! The reduced EOM with a base wrench and the joints' passive force (docs/physics.md,
//! docs/flexibility.md) is `H* q̈ + c* + H0mᵀ H0⁻¹ F_b = τ + Q`, so when a base controller
//! commands a wrench `F_b` (in [`super::Combined`]) its effect is compensated by the extra term,
//! with `F_b` as the mode applies it, and the springs and dampers `Q` of the controller's model
//! are compensated too. Write `g = c* + H0mᵀ H0⁻¹ F_b − Q`.
//!
//! Only the **actuated** arm joints `A` are commanded. The other joints are *given*: the
//! reaction wheels `W` with the torques the base controller commanded, and the passive joints
//! `P` (no motor) with zero torque — their coordinates are measured drift. The actuated joints
//! get the torques that produce the desired `q̈_A` exactly (collocated partial feedback
//! linearization, Spong 1994): from the rows of the given joints `G = W ∪ P`,
//! `q̈_G = H*_GG⁻¹ (τ_G − g_G − H*_GA q̈_A)`, and then `τ_A = H*_AA q̈_A + H*_AG q̈_G + g_A`, which is
//! `τ_A = (H*_AA − H*_AG H*_GG⁻¹ H*_GA) q̈_A + g_A + H*_AG H*_GG⁻¹ (τ_G − g_G)`.
//!
//! [`PassiveTreatment::Frozen`] designs the controller on the rigid model instead: the passive
//! joints are taken as locked at their spring's rest position with zero rate (the model with
//! those joints fixed: `q̈_P = 0`, `H*`, `c*` evaluated there), so the controller ignores the
//! motion of the fuel and panels it cannot see — the model error the flexibility risk study
//! (docs/flexibility-risk.md) measures.

use crate::model::data::Data;
use crate::error::{Result, SpacearmError};
use crate::gjm::{compute_generalized_bias, compute_generalized_inertia};
use crate::algorithms::inertia::BaseInverse;
use crate::algorithms::passive::subtract_joint_passive_forces;
use crate::model::Model;
use crate::scenario::modes::Mode;
use crate::scenario::reference::JointReference;

use super::controller::{check_model_dofs, split_passive};
use super::joint_tracking::{JointLaw, JointTracker, JointTracking};
use super::{cholesky_solve_in_place, Command, ControlContext};

/// How a model-based arm controller treats the passive joints (no motor) of the plant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PassiveTreatment {
    /// Measured drift: the passive coordinates and rates are taken from the state, their
    /// accelerations follow from the dynamics (collocated partial feedback linearization).
    #[default]
    Drift,
    /// Frozen: the controller's model has the passive joints locked at their rest position
    /// with zero rate (a rigid model; the passive coordinates are not measured).
    Frozen,
}

crate::error::named_by!(PassiveTreatment, "computed_torque 'passive'", [Drift = "drift", Frozen = "frozen"]);

/// Joint torques from the reduced EOM of a (controller's) model for desired accelerations of
/// the actuated arm joints, given the wheel torques and the base wrench already in a
/// [`Command`] and zero torque on the passive joints (module docs).
#[derive(Debug, Clone)]
pub struct ReducedInverseDynamics {
    model: Model,
    data: Data,
    mode: Mode,
    treatment: PassiveTreatment,
    arm: Vec<usize>,
    passive: Vec<usize>,
    given: Vec<usize>,
    g: Vec<f64>,
    h_gg: Vec<f64>,
    qdd_g: Vec<f64>,
    x_eval: Vec<f64>,
    u_eval: Vec<f64>,
}

impl ReducedInverseDynamics {
    /// For `model`, which must have the plant's degrees of freedom; passive joints as drift.
    pub fn new(model: Model, ctx: &ControlContext<'_>) -> Result<Self> {
        Self::with_passive(model, ctx, PassiveTreatment::Drift)
    }

    /// For `model` with the plant's degrees of freedom, the passive joints treated as `treatment`.
    pub fn with_passive(model: Model, ctx: &ControlContext<'_>, treatment: PassiveTreatment) -> Result<Self> {
        check_model_dofs("the controller's model", &model, ctx)?;
        let n = model.n_dof();
        let (arm, passive) = split_passive(ctx);
        let mut given = ctx.wheel_dofs.to_vec();
        if treatment == PassiveTreatment::Drift {
            given.extend_from_slice(&passive);
        }
        let ng = given.len();
        let data = Data::new(&model);
        Ok(ReducedInverseDynamics {
            model,
            data,
            mode: ctx.mode,
            treatment,
            arm,
            passive,
            given,
            g: vec![0.0; n],
            h_gg: vec![0.0; ng * ng],
            qdd_g: vec![0.0; ng],
            x_eval: vec![],
            u_eval: vec![],
        })
    }

    /// The model the torques are computed with.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// The actuated arm dofs (ascending): the ones [`ReducedInverseDynamics::arm_torques`] commands.
    pub fn actuated_arm(&self) -> &[usize] {
        &self.arm
    }

    /// The passive arm dofs (ascending): zero torque.
    pub fn passive(&self) -> &[usize] {
        &self.passive
    }

    /// Write into `out.tau` the torques of the actuated arm joints that give them the
    /// accelerations `qdd_arm` (one per actuated arm joint, [`ReducedInverseDynamics::actuated_arm`]),
    /// with the wheel torques and base wrench of `out` taken as given; the passive joints get
    /// zero torque.
    pub fn arm_torques(&mut self, x: &[f64], u: &[f64], qdd_arm: &[f64], out: &mut Command) -> Result<()> {
        let (x, u) = if self.treatment == PassiveTreatment::Frozen && !self.passive.is_empty() {
            self.x_eval.clear();
            self.x_eval.extend_from_slice(x);
            self.u_eval.clear();
            self.u_eval.extend_from_slice(u);
            let dynamics = self.model.dof_dynamics();
            for &p in &self.passive {
                self.x_eval[7 + p] = dynamics[p].rest;
                self.u_eval[6 + p] = 0.0;
            }
            (&self.x_eval[..], &self.u_eval[..])
        } else {
            (x, u)
        };
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
        // g − Q: the springs and dampers of the controller's model (nothing on a rigid one).
        subtract_joint_passive_forces(&self.model, &x[7..], &u[6..], &mut self.g);
        for &p in &self.passive {
            out.tau[p] = 0.0;
        }
        let hs = &self.data.generalized_inertia;
        let ng = self.given.len();
        if ng > 0 {
            for (a, &ga) in self.given.iter().enumerate() {
                let mut r = out.tau[ga] - self.g[ga];
                for (i, &d) in self.arm.iter().enumerate() {
                    r -= hs[(ga, d)] * qdd_arm[i];
                }
                self.qdd_g[a] = r;
                for (b, &gb) in self.given.iter().enumerate() {
                    self.h_gg[a + b * ng] = hs[(ga, gb)];
                }
            }
            if !cholesky_solve_in_place(&mut self.h_gg, ng, &mut self.qdd_g) {
                let what = if self.passive.is_empty() || self.treatment == PassiveTreatment::Frozen { "wheel" } else { "wheel and passive" };
                return Err(SpacearmError::Singular(format!("the {what} block of the generalized inertia H*")));
            }
        }
        for &d in &self.arm {
            let mut t = self.g[d];
            for (k, &dk) in self.arm.iter().enumerate() {
                t += hs[(d, dk)] * qdd_arm[k];
            }
            for (k, &gk) in self.given.iter().enumerate() {
                t += hs[(d, gk)] * self.qdd_g[k];
            }
            out.tau[d] = t;
        }
        Ok(())
    }
}

/// Computed-torque tracking of a joint reference (paper eqs. 112–115).
pub type ComputedTorque = JointTracker<ComputedTorqueLaw>;

/// The law of [`ComputedTorque`]: `q̈_cmd = q̈_ref + K_d ė + K_p e` on the actuated arm joints,
/// realized through the reduced EOM of the controller's model ([`ReducedInverseDynamics`]).
#[derive(Debug, Clone)]
pub struct ComputedTorqueLaw {
    model: Option<Model>,
    passive: PassiveTreatment,
    inner: Option<ReducedInverseDynamics>,
    qdd_cmd: Vec<f64>,
}

impl ComputedTorque {
    /// Gains: one value or one per actuated arm joint; `reference`: one entry per actuated arm
    /// joint (the passive joints are not commanded); `model`: the controller's model (`None`:
    /// the plant's). Passive joints as measured drift ([`ComputedTorque::with_passive`]).
    pub fn new(kp: Vec<f64>, kd: Vec<f64>, reference: JointReference, model: Option<Model>) -> Self {
        JointTracker::with_law(kp, kd, reference, ComputedTorqueLaw { model, passive: PassiveTreatment::Drift, inner: None, qdd_cmd: vec![] })
    }

    /// How the controller treats the plant's passive joints (default [`PassiveTreatment::Drift`]).
    pub fn with_passive(mut self, passive: PassiveTreatment) -> Self {
        self.law.passive = passive;
        self
    }
}

impl JointLaw for ComputedTorqueLaw {
    const NAME: &'static str = "computed_torque";

    fn setup(&mut self, ctx: &ControlContext<'_>, tracking: &JointTracking, _passive: Vec<usize>) -> Result<()> {
        let model = self.model.clone().unwrap_or_else(|| ctx.plant.clone());
        self.inner = Some(ReducedInverseDynamics::with_passive(model, ctx, self.passive)?);
        self.qdd_cmd = vec![0.0; tracking.arm.len()];
        Ok(())
    }

    fn command(&mut self, j: &JointTracking, x: &[f64], u: &[f64], out: &mut Command) -> Result<()> {
        for (i, q) in self.qdd_cmd.iter_mut().enumerate() {
            *q = j.qdd_ref[i] + j.kd[i] * j.ed[i] + j.kp[i] * j.e[i];
        }
        let inner = self.inner.as_mut().ok_or_else(|| SpacearmError::Simulation("computed torque used before setup".into()))?;
        inner.arm_torques(x, u, &self.qdd_cmd, out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algorithms::dynamics::forward_dynamics_via_mass_matrix;
    use crate::control::coordinated::tests::{fuel_pendulum, revolute_links};
    use crate::model::builder::ModelBuilder;
    use crate::model::joint::JointDynamics;
    use crate::scenario::actuators::Actuators;

    /// Two actuated links on a base carrying a slosh pendulum and a hinged panel (passive, with
    /// a torsional spring), the passive joints between and after the actuated ones.
    fn flexible_arm() -> Model {
        let mut b = ModelBuilder::new("flex", "base", 200.0, [[20.0, 0.0, 0.0], [0.0, 25.0, 0.0], [0.0, 0.0, 30.0]]).unwrap();
        let link = revolute_links([0.05, 0.4, 0.4]);
        b.add_link(link("l1", "base", [0.6, 0.0, 0.2], [0.0, 0.0, 1.0], [0.5, 0.0, 0.0], 8.0)).unwrap();
        b.add_slosh(fuel_pendulum(30.0)).unwrap();
        b.add_link(link("panel", "base", [0.0, -0.7, 0.0], [1.0, 0.0, 0.0], [0.0, -0.8, 0.0], 12.0)).unwrap();
        b.set_joint_dynamics("panel", JointDynamics { actuated: false, stiffness: 40.0, damping: 0.5, rest: 0.1 }).unwrap();
        b.add_link(link("l2", "l1", [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.4, 0.0, 0.0], 5.0)).unwrap();
        b.build().unwrap()
    }

    #[test]
    fn actuated_joints_get_the_commanded_acceleration_and_passive_ones_no_torque() {
        let m = flexible_arm();
        assert_eq!(m.actuated_dofs(), vec![true, false, false, true]);
        let mut x = vec![0.0; m.nx()];
        x[6] = 1.0;
        x[0..3].copy_from_slice(&[0.1, -0.2, 0.05]);
        x[3..6].copy_from_slice(&[0.05, -0.02, 0.1]);
        let norm = (x[3..7].iter().map(|v| v * v).sum::<f64>()).sqrt();
        x[3..7].iter_mut().for_each(|v| *v /= norm);
        x[7..].copy_from_slice(&[0.4, 0.3, -0.25, -0.6]);
        let u: Vec<f64> = (0..m.nu()).map(|i| 0.1 * ((i as f64) * 1.3).sin()).collect();
        let arm = vec![0, 1, 2, 3];
        let actuators = Actuators::new(&m, false, None);
        for mode in [Mode::Floating, Mode::Flying] {
            let ctx = ControlContext { plant: &m, mode, wheel_dofs: &[], arm_dofs: &arm, actuators: &actuators };
            let mut rid = ReducedInverseDynamics::new(m.clone(), &ctx).unwrap();
            assert_eq!(rid.actuated_arm(), &[0, 3]);
            assert_eq!(rid.passive(), &[1, 2]);
            let want = [0.7, -1.1];
            let mut out = Command::new(m.n_dof(), 0);
            out.tau.fill(99.0);
            rid.arm_torques(&x, &u, &want, &mut out).unwrap();
            assert_eq!(out.tau[1], 0.0);
            assert_eq!(out.tau[2], 0.0);
            // The plant's forward dynamics (mass matrix route: H u̇ + c = f + Q_passive, the
            // base free) under these torques.
            let mut f = vec![0.0; m.nu()];
            f[6..].copy_from_slice(&out.tau);
            let mut d = Data::new(&m);
            let ud = forward_dynamics_via_mass_matrix(&m, &mut d, &x, &u, &f, &[]).unwrap();
            assert!((ud[6] - want[0]).abs() < 1e-10, "{mode:?}: {} vs {}", ud[6], want[0]);
            assert!((ud[9] - want[1]).abs() < 1e-10, "{mode:?}: {} vs {}", ud[9], want[1]);
            // The passive joints drift (they are not held).
            assert!(ud[7].abs() > 1e-3 && ud[8].abs() > 1e-3);
            // Frozen (a rigid model): the passive coordinates at rest, not realized exactly.
            let mut frozen = ReducedInverseDynamics::with_passive(m.clone(), &ctx, PassiveTreatment::Frozen).unwrap();
            let mut out2 = Command::new(m.n_dof(), 0);
            frozen.arm_torques(&x, &u, &want, &mut out2).unwrap();
            assert_eq!((out2.tau[1], out2.tau[2]), (0.0, 0.0));
            f[6..].copy_from_slice(&out2.tau);
            let ud2 = forward_dynamics_via_mass_matrix(&m, &mut d, &x, &u, &f, &[]).unwrap();
            assert!((ud2[6] - want[0]).abs() > 1e-4);
        }
    }
}
