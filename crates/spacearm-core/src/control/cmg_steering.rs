//! Base attitude control with a CMG cluster (rotation-floating mode; docs/cmg.md).
//!
//! The base torque wanted is the attitude PD of [`super::attitude`] (Wie 2008, §7.3):
//! `N = −K_p e − K_d ω0`. The cluster gives the base `−Ḣ = −A(δ) δ̇`
//! ([`super::cmg_jacobian`]), so the gimbal rates commanded are `δ̇_c = A# (−N)` with the
//! singularity-robust inverse `A# = Aᵀ (A Aᵀ + λE)⁻¹`, `λ = λ₀ h̄² exp(−μ m)`
//! ([`super::cmg_sr_inverse`]; `λ₀ = 0`: the pseudo-inverse). `A` is read from the plant's
//! kinematics at each call: `ĝ_i`, `ŝ_i` in 𝒥 and `h_i = J_s,i (ŝ_i · ω0 + Ω_i)` (the rotor's
//! absolute spin; `ĝ_i ⟂ ŝ_i`, so the gimbal rate adds none). `δ̇_c` is scaled down as one
//! vector (its direction kept) until every gimbal is within its rate limit, and each gimbal
//! motor follows it with the rate loop `τ_i = k (I_i) (δ̇_c,i − δ̇_i)`, `I_i = ĝ_i·(I_G + I_R) ĝ_i`
//! the gimbal's and rotor's moment about the gimbal axis and `k` (1/s) the loop's bandwidth.
//! Two options (both off by default): `dither = ε₀ > 0` replaces `E` by the dithered weight
//! `W(t)` of [`super::cmg_dither`] (Wie's generalized SR inverse, which leaves even a singular
//! state commanded along its singular direction), and `null_gain = k_n > 0` adds the null
//! motion `k_n (E − A⁺A) ∇√m` of [`super::cmg_null_motion`] before the rates are scaled.
//! `wheel_weight = W_s0 > 0` (a cluster of VSCMGs) steers the gimbal rates and the wheel
//! accelerations together by the weighted minimum-norm law of [`super::vscmg_steering`]
//! (Schaub, Vadali & Junkins 1998) in place of the SR inverse, each wheel motor given
//! `τ_i = J_s,i Ω̇_c,i`. Otherwise the rotors get no torque (an SGCMG's has no motor); the arm
//! joints get none either: combine with an arm law through [`super::Combined`].
//! With momentum unloading ([`super::cmg_unloading`], mode rotation-flying or flying) the
//! thrusters apply `N_u = −k (H − H_goal)` on the base while the cluster is on, and the cluster is
//! steered to give `N − N_u` (the unloading torque fed forward), so the base still feels `N`.

use nalgebra::{Matrix3xX, Vector3};

use crate::algorithms::kinematics::forward_kinematics;
use crate::error::{Result, SpacearmError};
use crate::model::cmg::{detect_cmgs, Cmg};
use crate::model::data::Data;
use crate::model::Model;
use crate::scenario::modes::Mode;

use super::attitude::AttitudeControl;
use super::cmg_dither::dither_weight;
use super::cmg_jacobian::{cluster_from_kinematics, cmg_jacobian_from_axes, singularity_measure};
use super::cmg_null_motion::{null_motion, root_measure_gradient};
use super::cmg_sr_inverse::{sr_weight, steering_rates_weighted};
use super::cmg_unloading::MomentumUnloading;
use super::vscmg_steering::{vscmg_rates, wheel_matrix, wheel_weight};
use crate::analysis::cmg_envelope::envelope_fraction;
use super::{Command, ControlContext, Controller};

/// The steering law's options beyond the SR inverse (module docs): the GSR dither's amplitude
/// `ε₀` (dimensionless, `< 1/2`; 0: none) and frequency (rad/s), and the null-motion gain
/// (rad/s; 0: none).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SteeringOptions {
    /// `ε₀` of [`dither_weight`].
    pub dither: f64,
    /// `ω` of [`dither_weight`], rad/s.
    pub dither_frequency: f64,
    /// `k_n` of the null motion, rad/s.
    pub null_gain: f64,
    /// `W_s0` of the VSCMG steering ([`super::vscmg_steering`]; 0: the gimbals alone).
    pub wheel_weight: f64,
    /// `μ` of the wheel weight `W_s = W_s0 exp(−μ m)`.
    pub wheel_mu: f64,
}

impl Default for SteeringOptions {
    fn default() -> Self {
        SteeringOptions { dither: 0.0, dither_frequency: std::f64::consts::FRAC_PI_2, null_gain: 0.0, wheel_weight: 0.0, wheel_mu: 10.0 }
    }
}

impl SteeringOptions {
    /// The options' checks (the run description's and the law's).
    pub fn check(&self, lambda0: f64) -> Result<()> {
        let o = self;
        if !(o.dither.is_finite() && (0.0..0.5).contains(&o.dither)) {
            return Err(SpacearmError::argument(format!("cmg_steering dither must be in [0, 0.5) (the weight W must stay positive definite), got {}", o.dither)));
        }
        if o.dither > 0.0 && lambda0 <= 0.0 {
            return Err(SpacearmError::argument("cmg_steering dither needs lambda0 > 0: the dither weights the SR term λW, which the pseudo-inverse (lambda0 = 0) has not"));
        }
        if o.wheel_weight > 0.0 && o.dither > 0.0 {
            return Err(SpacearmError::argument(
                "cmg_steering wheel_weight > 0 steers the wheels with the gimbals (the VSCMG law, which replaces the SR inverse): it takes no dither",
            ));
        }
        for (what, v) in [("dither_frequency", o.dither_frequency), ("null_gain", o.null_gain), ("wheel_weight", o.wheel_weight), ("wheel_mu", o.wheel_mu)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(SpacearmError::argument(format!("cmg_steering {what} must be finite and >= 0, got {v}")));
            }
        }
        Ok(())
    }
}

/// Attitude hold with the plant's CMGs (module docs).
#[derive(Debug, Clone)]
pub struct CmgSteering {
    attitude: AttitudeControl,
    quat_ref: [f64; 4],
    kp: f64,
    kd: f64,
    lambda0: f64,
    mu: f64,
    rate_gain: f64,
    options: SteeringOptions,
    model: Option<Model>,
    data: Option<Data>,
    cmgs: Vec<Cmg>,
    /// Each gimbal's moment about its axis (gimbal and rotor), kg·m².
    gimbal_moments: Vec<f64>,
    /// The last singularity measure met.
    measure: f64,
    /// Momentum unloading by the thrusters, if on ([`super::cmg_unloading`]).
    unloading: Option<MomentumUnloading>,
}

impl CmgSteering {
    /// `quat_ref` `[x, y, z, w]`, `kp` (N·m/rad), `kd` (N·m·s/rad), the SR weight `lambda0`
    /// (dimensionless; 0: the pseudo-inverse) and `mu`, the gimbal rate loop's `rate_gain` (1/s).
    pub fn new(quat_ref: [f64; 4], kp: f64, kd: f64, lambda0: f64, mu: f64, rate_gain: f64) -> Self {
        CmgSteering {
            attitude: AttitudeControl::new(quat_ref, kp, kd),
            quat_ref,
            kp,
            kd,
            lambda0,
            mu,
            rate_gain,
            options: SteeringOptions::default(),
            model: None,
            data: None,
            cmgs: Vec::new(),
            gimbal_moments: Vec::new(),
            measure: f64::NAN,
            unloading: None,
        }
    }

    /// The law with the GSR dither and null-motion options (module docs).
    pub fn with_options(mut self, options: SteeringOptions) -> Self {
        self.options = options;
        self
    }

    /// The law with momentum unloading by the thrusters (module docs).
    pub fn with_unloading(mut self, unloading: MomentumUnloading) -> Self {
        self.unloading = Some(unloading);
        self
    }

    /// Whether the thrusters unload the cluster now (false without unloading).
    pub fn unloading(&self) -> bool {
        self.unloading.as_ref().is_some_and(MomentumUnloading::is_on)
    }

    /// The singularity measure `m` at the last command (NaN before the first).
    pub fn last_measure(&self) -> f64 {
        self.measure
    }
}

impl Controller for CmgSteering {
    fn name(&self) -> &str {
        "cmg_steering"
    }

    fn setup(&mut self, ctx: &ControlContext<'_>) -> Result<()> {
        if self.unloading.is_some() {
            if !ctx.mode.allows_torque() {
                return Err(SpacearmError::argument(format!(
                    "CMG steering with momentum unloading (unload_gain > 0) needs the thrusters' torque on the base: mode \
                     'rotation-flying' or 'flying', but the simulation mode is '{}'",
                    ctx.mode.name()
                )));
            }
        } else if ctx.mode != Mode::RotationFloating {
            return Err(SpacearmError::argument(format!(
                "CMG steering holds the attitude in the 'rotation-floating' mode (or, with momentum unloading, 'rotation-flying' or \
                 'flying'), but the simulation mode is '{}'",
                ctx.mode.name()
            )));
        }
        for (what, v) in [("kp", self.kp), ("kd", self.kd), ("lambda0", self.lambda0), ("mu", self.mu)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(SpacearmError::argument(format!("cmg_steering {what} must be finite and >= 0, got {v}")));
            }
        }
        if !(self.rate_gain.is_finite() && self.rate_gain > 0.0) {
            return Err(SpacearmError::argument(format!("cmg_steering rate_gain must be finite and > 0 1/s, got {}", self.rate_gain)));
        }
        self.options.check(self.lambda0)?;
        let cmgs = detect_cmgs(ctx.plant);
        if cmgs.is_empty() {
            return Err(SpacearmError::argument("CMG steering needs control-moment gyros: add them with RobotBuilder.add_cmg or [[cmg]] tables"));
        }
        if let Some(c) = cmgs.iter().find(|c| c.parent_body != 0) {
            return Err(SpacearmError::argument(format!("cmg '{}' is not on the base: CMG steering of a cluster on another body is not implemented", c.name)));
        }
        if let Some(c) = cmgs.iter().find(|c| !ctx.plant.dof_dynamics()[c.gimbal_dof].actuated) {
            return Err(SpacearmError::argument(format!("cmg '{}': its gimbal joint has no motor (actuated = false)", c.name)));
        }
        if self.options.wheel_weight > 0.0 {
            if let Some(c) = cmgs.iter().find(|c| !c.variable_speed || !ctx.plant.dof_dynamics()[c.rotor_dof].actuated) {
                return Err(SpacearmError::argument(format!(
                    "cmg_steering wheel_weight > 0 steers the wheels too, and cmg '{}' is not a variable-speed CMG (add_cmg(..., variable_speed=True))",
                    c.name
                )));
            }
        }
        self.attitude.set_reference(self.quat_ref)?;
        let model = ctx.plant.clone();
        self.gimbal_moments = cmgs
            .iter()
            .map(|c| {
                let gl = &model.links()[model.body_of_dof(c.gimbal_dof) - 1];
                let rl = &model.links()[model.body_of_dof(c.rotor_dof) - 1];
                let gi = gl.joint.axis.into_inner();
                let ri = rl.joint.rotation_in_parent.inverse() * gi;
                gi.dot(&(gl.mass.inertia * gi)) + ri.dot(&(rl.mass.inertia * ri))
            })
            .collect();
        self.data = Some(Data::new(&model));
        self.model = Some(model);
        self.cmgs = cmgs;
        Ok(())
    }

    fn command(&mut self, t: f64, x: &[f64], u: &[f64], out: &mut Command) -> Result<()> {
        let (e, angle) = self.attitude.error(&x[3..7]);
        let (Some(model), Some(data)) = (self.model.as_ref(), self.data.as_mut()) else {
            return Err(SpacearmError::Simulation("CMG steering used before setup".into()));
        };
        forward_kinematics(model, data, x)?;
        let w0 = Vector3::new(u[3], u[4], u[5]);
        let torque = -e * self.kp - w0 * self.kd;
        let (g, s, h) = cluster_from_kinematics(model, data, &self.cmgs, u);
        // The unloading torque on the base (thrusters), fed forward into the cluster's.
        let cluster: Vector3<f64> = s.iter().zip(&h).map(|(s, h)| s * *h).sum();
        let unload = self.unloading.as_ref().map_or_else(Vector3::zeros, |un| un.torque(&cluster));
        let torque = torque - unload;
        let a: Matrix3xX<f64> = cmg_jacobian_from_axes(&g, &s, &h);
        let m = singularity_measure(&a, &h);
        self.measure = m;
        let hbar = h.iter().map(|v| v.abs()).sum::<f64>() / h.len() as f64;
        let mut accel = None;
        let mut rates = if self.options.wheel_weight > 0.0 {
            // The VSCMG law: gimbal rates and wheel accelerations together.
            let js: Vec<f64> = self.cmgs.iter().map(|c| c.rotor_inertia).collect();
            let w_s = wheel_weight(self.options.wheel_weight, self.options.wheel_mu, m);
            let (rates, wheels) = vscmg_rates(&a, &wheel_matrix(&s, &js), &(-torque), w_s)?;
            accel = Some(wheels);
            rates
        } else {
            let weight = dither_weight(self.options.dither, self.options.dither_frequency, t);
            steering_rates_weighted(&a, &(-torque), sr_weight(self.lambda0, self.mu, m, hbar), &weight)?
        };
        if self.options.null_gain > 0.0 {
            rates += null_motion(&a, &root_measure_gradient(&a, &s, &h), self.options.null_gain);
        }
        let over = self.cmgs.iter().zip(rates.iter()).map(|(c, r)| r.abs() / c.max_gimbal_rate).fold(0.0f64, f64::max);
        if over > 1.0 {
            rates /= over;
            if let Some(w) = accel.as_mut() {
                *w /= over;
            }
        }
        // The wheel motors: τ_i = J_s,i Ω̇_c,i gives the absolute spin momentum the rate
        // J_s,i Ω̇_c,i exactly (the spin joint's equation, ĝ_i ⟂ ŝ_i).
        if let Some(w) = &accel {
            for (c, wi) in self.cmgs.iter().zip(w.iter()) {
                out.tau[c.rotor_dof] = c.rotor_inertia * wi;
            }
        }
        for ((c, r), inertia) in self.cmgs.iter().zip(rates.iter()).zip(&self.gimbal_moments) {
            out.tau[c.gimbal_dof] = self.rate_gain * inertia * (r - u[6 + c.gimbal_dof]);
        }
        out.attitude_error = angle;
        out.base_wrench[3] += unload.x;
        out.base_wrench[4] += unload.y;
        out.base_wrench[5] += unload.z;
        Ok(())
    }

    /// The unloading's switch, at the step's start: the envelope fraction of `(x, u)`.
    fn sample(&mut self, _t: f64, x: &[f64], u: &[f64]) -> Result<()> {
        let (Some(un), Some(model), Some(data)) = (self.unloading.as_mut(), self.model.as_ref(), self.data.as_mut()) else { return Ok(()) };
        forward_kinematics(model, data, x)?;
        let (g, s, h) = cluster_from_kinematics(model, data, &self.cmgs, u);
        un.update(envelope_fraction(&g, &s, &h));
        Ok(())
    }

    fn reports_attitude_error(&self) -> bool {
        true
    }
}
