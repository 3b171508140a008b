//! A closed kinematic chain in the simulation loop: a [`Plant`] whose forward dynamics are
//! those under a loop closure (two frames welded), with Baumgarte's drift stabilization
//! (docs/capture.md, "Two arms: a closed chain").
//!
//! At every evaluation, after the controller and the actuator limits have given `f`:
//!
//! `[H  −J_cᵀ; J_c  0] [u̇; λ] = [f − c; −J̇_c u − 2α J_c u − α² e]`
//!
//! ([`crate::algorithms::constrained`]; `J̇_c u` exact, [`crate::derivatives::loop_closure_bias`];
//! `e` the pose error, `α` the stabilization rate). The run is the simulation's own
//! ([`crate::sim::simulate`]: RK4 or DOPRI5, the records), with the constraint wrench `λ` and
//! the pose error `e` recorded at every sample ([`crate::sim::simulate::Records::constraint_wrench`],
//! [`crate::sim::simulate::Records::constraint_error`]).

use nalgebra::DVector;

use crate::algorithms::constrained::LoopClosure;
use crate::algorithms::kinematics::BodyPoint;
use crate::control::Controller;
use crate::error::{Result, SpacearmError};
use crate::model::data::Data;
use crate::model::Model;
use crate::sim::closure::ClosureState;
use crate::sim::simulate::{check_initial_state, run_plant, Plant, Progress, SimOptions, SimResult};

/// Simulate `model` from `(x0, u0)` with the frames at `a` and `b` welded at their relative
/// pose at `x0` (module docs), under `controller`, for `opts.duration` s. `u0` must satisfy the
/// velocity constraint (`|J_c u0| ≤ 1e-9 |u0|`); `stabilization` is Baumgarte's rate `α` (1/s,
/// ≥ 0).
#[allow(clippy::too_many_arguments)]
pub fn simulate_closed_chain(
    model: &Model,
    x0: &[f64],
    u0: &[f64],
    a: BodyPoint,
    b: BodyPoint,
    stabilization: f64,
    opts: &SimOptions,
    controller: &mut dyn Controller,
    progress: Progress<'_>,
) -> Result<SimResult> {
    opts.validate()?;
    opts.refuse_contact("a closed-chain run")?;
    check_initial_state(model, x0, u0)?;
    if !(stabilization.is_finite() && stabilization >= 0.0) {
        return Err(SpacearmError::argument(format!("stabilization must be finite and >= 0, got {stabilization}")));
    }
    let mut data = Data::new(model);
    let closure = LoopClosure::at(model, &mut data, x0, a, b)?;
    let ju = &closure.jacobian(model, &data) * DVector::from_column_slice(u0);
    let scale = u0.iter().map(|v| v * v).sum::<f64>().sqrt().max(1e-300);
    if ju.norm() > 1e-9 * scale {
        return Err(SpacearmError::argument(format!(
            "u0 violates the loop closure (the two grasp frames move apart at {:.3e}); project it onto the null space of J_c",
            ju.norm()
        )));
    }
    let mut plant = Plant::new(model, opts, controller)?;
    plant.closure = Some(Box::new(ClosureState::new(model, closure, stabilization)));
    run_plant(plant, x0, u0, opts, progress)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::derivatives::{loop_closure_bias, ClosureBiasWork};
    use crate::algorithms::kinematics::forward_kinematics;
    use crate::control::ZeroTorque;
    use crate::math::rotations::{quaternion_from_xyzw, xyzw};
    use crate::model::presets::{dual_arm, initial_configuration};
    use crate::math::integrate::IntegratorKind;
    use nalgebra::{DMatrix, UnitQuaternion, Vector3};

    /// `x ⊕ h u`: the base moved by `h v0`, turned by `exp(h ω0)` (in 𝒥), the joints by `h q̇`.
    fn plus(x: &[f64], u: &[f64], h: f64) -> Vec<f64> {
        let mut out = x.to_vec();
        for i in 0..3 {
            out[i] += h * u[i];
        }
        let q = UnitQuaternion::from_quaternion(quaternion_from_xyzw(&x[3..7]));
        let turned = UnitQuaternion::from_scaled_axis(Vector3::new(u[3], u[4], u[5]) * h) * q;
        out[3..7].copy_from_slice(&xyzw(&turned));
        for j in 7..x.len() {
            out[j] += h * u[j - 1];
        }
        out
    }

    /// A dual-arm posture, the two wrists welded, and a velocity in the null space of `J_c`.
    fn scene() -> (Model, Vec<f64>, Vec<f64>, BodyPoint, BodyPoint) {
        let model = dual_arm();
        let mut x = initial_configuration(&model);
        x[7..].iter_mut().enumerate().for_each(|(j, q)| *q += 0.2 * (0.7 * j as f64).sin());
        let n = model.n_dof();
        let (a, b) = (BodyPoint { body: n / 2, offset: Vector3::new(0.05, 0.0, 0.0) }, BodyPoint { body: n, offset: Vector3::zeros() });
        let mut data = Data::new(&model);
        let closure = LoopClosure::at(&model, &mut data, &x, a, b).unwrap();
        let j = closure.jacobian(&model, &data);
        let raw = DVector::from_fn(model.nu(), |k, _| 0.1 * ((k as f64) * 1.3 + 0.2).cos());
        // project onto the null space of J: u = raw − Jᵀ (J Jᵀ)⁻¹ J raw
        let jjt = &j * j.transpose();
        let u = &raw - j.transpose() * jjt.lu().solve(&(&j * &raw)).unwrap();
        (model, x, u.as_slice().to_vec(), a, b)
    }

    #[test]
    fn jdot_u_matches_a_central_difference_of_the_constraint_jacobian() {
        let (model, x, u, a, b) = scene();
        let mut data = Data::new(&model);
        let closure = LoopClosure::at(&model, &mut data, &x, a, b).unwrap();
        let exact = loop_closure_bias(&model, &mut ClosureBiasWork::new(&model), &x, &u, &closure).unwrap();
        let jc = |xx: &[f64]| -> DMatrix<f64> {
            let mut d = Data::new(&model);
            forward_kinematics(&model, &mut d, xx).unwrap();
            closure.jacobian(&model, &d)
        };
        let h = 1e-6;
        let uv = DVector::from_column_slice(&u);
        let fd = (jc(&plus(&x, &u, h)) - jc(&plus(&x, &u, -h))) * &uv / (2.0 * h);
        assert!(exact.norm() > 1e-4, "a measurable J̇u: {exact:?}");
        assert!((DVector::from_column_slice(exact.as_slice()) - &fd).norm() < 1e-8 * exact.norm(), "{exact:?} vs {fd:?}");
    }

    #[test]
    fn the_loop_stays_closed_and_momentum_is_conserved() {
        let (model, x, u, a, b) = scene();
        for integrator in [IntegratorKind::Rk4, IntegratorKind::Dopri5] {
            let opts = SimOptions { integrator, duration: 1.0, dt: 1e-3, rtol: 1e-10, atol: 1e-12, ..SimOptions::default() };
            let r = simulate_closed_chain(&model, &x, &u, a, b, 20.0, &opts, &mut ZeroTorque, &mut |_| Ok(())).unwrap();
            let e = r.records.constraint_error.as_ref().unwrap();
            let worst = e.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            assert!(worst < 1e-9, "{integrator:?}: pose error {worst:e}");
            let lam = r.records.constraint_wrench.as_ref().unwrap();
            assert!(lam.iter().any(|v| v.abs() > 1e-3), "the loop carries a wrench");
            for (c, d) in &r.drift {
                assert!(*d < 1e-9, "{integrator:?}: drift of {c:?} {d:e}");
            }
            // the joints moved
            let n = model.nx();
            let last = &r.records.x[(r.records.n_samples - 1) * n..];
            assert!(last.iter().zip(&x).map(|(p, q)| (p - q).abs()).fold(0.0, f64::max) > 1e-3);
        }
        let bad: Vec<f64> = (0..model.nu()).map(|k| 0.1 * (k as f64).sin()).collect();
        let err = simulate_closed_chain(&model, &x, &bad, a, b, 20.0, &SimOptions::default(), &mut ZeroTorque, &mut |_| Ok(())).unwrap_err();
        assert!(err.to_string().contains("loop closure"), "{err}");
    }
}
