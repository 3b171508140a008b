//! Forward dynamics through the mass matrix, `u̇ = H⁻¹ (f + Q_passive + Jᵀ w_ext − c)` (the O(N³) route,
//! independent of the articulated-body recursion in [`crate::algorithms::aba`]).

use nalgebra::{DMatrix, DVector};

use crate::algorithms::crba::crba_after_kinematics;
use crate::model::data::Data;
use crate::error::{named_by, Result, SpacearmError};
use crate::model::Model;
use crate::algorithms::passive::add_joint_passive_forces;
use crate::algorithms::rnea::rnea_after_kinematics;
use crate::algorithms::wrench::{kinematics_and_loads, ExternalWrench};

/// Forward dynamics by CRBA + RNEA + Cholesky: the state derivative `u̇` for the generalized
/// force `f = [F0; N0; τ]` and external wrenches, left in `data.accel` (no allocation: the
/// factorization reuses a workspace matrix of `data`).
pub fn compute_forward_dynamics_via_mass_matrix<'d>(
    model: &Model,
    data: &'d mut Data,
    x: &[f64],
    u: &[f64],
    f: &[f64],
    external: &[ExternalWrench],
) -> Result<&'d DVector<f64>> {
    kinematics_and_loads(model, data, x, u, "f", f, external)?;
    // c − Jᵀ w_ext is the inverse dynamics at zero acceleration (left in data.tau).
    rnea_after_kinematics(model, data, u, None, external);
    crba_after_kinematics(model, data, true)?;
    data.ensure_factor()?;
    let nu = model.nu();
    let mut factor = std::mem::take(&mut data.factor);
    factor.copy_from(&data.mass_matrix);
    let Some(chol) = factor.cholesky() else {
        data.factor = DMatrix::zeros(nu, nu);
        return Err(SpacearmError::Singular("the mass matrix H".into()));
    };
    for i in 0..nu {
        data.accel[i] = f[i] - data.tau[i];
    }
    add_joint_passive_forces(model, &x[7..], &u[6..], &mut data.accel.as_mut_slice()[6..]);
    chol.solve_mut(&mut data.accel);
    data.factor = chol.unpack_dirty();
    Ok(&data.accel)
}

/// Forward dynamics by CRBA + RNEA + Cholesky: the state derivative `u̇` for the generalized
/// force `f = [F0; N0; τ]` and external wrenches.
pub fn forward_dynamics_via_mass_matrix(
    model: &Model,
    data: &mut Data,
    x: &[f64],
    u: &[f64],
    f: &[f64],
    external: &[ExternalWrench],
) -> Result<DVector<f64>> {
    Ok(compute_forward_dynamics_via_mass_matrix(model, data, x, u, f, external)?.clone())
}

/// The routes of forward dynamics a door lets its caller name (`Robot.forward_dynamics(...,
/// method=...)`): the articulated-body recursion ([`crate::algorithms::aba`]), the mass matrix
/// (this file) or the paper's reduced equations of motion (`gjm::compute_reduced_forward_dynamics`,
/// eqs. 112–115).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ForwardDynamicsMethod {
    /// `"aba"`: the articulated-body recursion, O(N).
    Aba,
    /// `"mass_matrix"`: `H⁻¹ (f − c)` by Cholesky, O(N³).
    MassMatrix,
    /// `"reduced"`: the reduced equations of motion (no external wrenches).
    Reduced,
}

impl ForwardDynamicsMethod {
    /// Every method, in the order of [`ForwardDynamicsMethod::NAMES`].
    pub const ALL: [ForwardDynamicsMethod; 3] = [ForwardDynamicsMethod::Aba, ForwardDynamicsMethod::MassMatrix, ForwardDynamicsMethod::Reduced];
}

named_by!(ForwardDynamicsMethod, "method", [Aba = "aba", MassMatrix = "mass_matrix", Reduced = "reduced"]);

#[cfg(test)]
mod method_name_tests {
    use super::ForwardDynamicsMethod;

    #[test]
    fn every_method_reads_back_from_its_name_and_an_unknown_name_is_refused() {
        for (method, name) in ForwardDynamicsMethod::ALL.into_iter().zip(ForwardDynamicsMethod::NAMES) {
            assert_eq!(method.name(), name);
            assert_eq!(ForwardDynamicsMethod::from_name(name).unwrap(), method);
        }
        let err = ForwardDynamicsMethod::from_name("crba").unwrap_err().to_string();
        assert!(err.contains("method must be one of") && err.contains("'crba'"), "{err}");
    }
}
