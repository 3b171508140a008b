//! The equations of motion recorded on tapes ([`crate::math::tape`]): the very algorithms of
//! the `f64` functions — forward kinematics, ABA, RNEA, CRBA, the GJM reduction, point
//! positions and the momentum sum — run once on [`Var`] inputs, for another system to replay
//! on its own symbols (`spacearm.casadi` builds its CasADi `Function`s from these tapes).
//!
//! Each [`TapedFunction`] names its inputs and outputs ([`TapedFunction::inputs`],
//! [`TapedFunction::outputs`]); the tape's inputs are those inputs concatenated in order, its
//! outputs the outputs concatenated, each matrix in column-major order.
//!
//! The configuration `x = [r0, quat0, q]` enters as the `f64` path uses it after its checks: the
//! quaternion is normalized (`nalgebra`'s `UnitQuaternion::from_quaternion`, the same
//! operations) before its rotation matrix is formed, so the recorded functions accept a
//! quaternion of any non-zero norm and their derivatives with respect to it are tangent to the
//! unit sphere. A zero quaternion has no direction: the replayed functions return NaN there
//! (a tape cannot raise an error at evaluation).
//!
//! The recording is made at the nominal state `x = [0, 0, 0, 0, 0, 0, 1, 0…]` with every other
//! input zero; the branches the algorithms take do not depend on the state (module docs of
//! [`crate::math::tape`]), and the tests replay every tape at random states.
//!
//! Imports: `math`, `model`, `algorithms` and [`crate::gjm`].

use nalgebra::{Quaternion, UnitQuaternion, Vector3, Vector6};

use crate::algorithms::aba::aba_after_kinematics;
use crate::algorithms::crba::crba_after_kinematics;
use crate::algorithms::kinematics::{check_body, forward_kinematics_at, point_position};
use crate::algorithms::momentum::momentum_about_base;
use crate::algorithms::passive::subtract_joint_passive_forces;
use crate::algorithms::rnea::{rnea_after_kinematics, velocity_pass};
use crate::error::{Result, SpacearmError};
use crate::gjm::{
    base_velocity_after_reduction, fill_generalized_inertia, generalized_bias_after_reduction, generalized_jacobian_after_reduction,
    reduce_after_kinematics, reduction_columns,
};
use crate::math::rotations::quaternion_rate;
use crate::math::tape::{Recording, Tape, Var};
use crate::model::data::DataT;
use crate::model::Model;

/// A function of the equations of motion that can be recorded.
#[derive(Debug, Clone, PartialEq)]
pub enum TapedFunction {
    /// `(x, u, tau, base_wrench) → du`: ABA with `f = [base_wrench; tau]`.
    ForwardDynamics,
    /// `(x, u, tau, base_wrench) → dy`: the simulator's state derivative `dy = [ṙ0 = v0,
    /// quaṫ = ½ [ω0; 0] ⊗ quat, q̇, u̇]` (7+N then 6+N; the quaternion rate of `x`'s quaternion
    /// as given), `u̇` by ABA.
    StateDerivative,
    /// `(x, u, du) → f`: RNEA.
    InverseDynamics,
    /// `x → H`: CRBA.
    MassMatrix,
    /// `(x, u) → c`: RNEA at `u̇ = 0`.
    BiasForces,
    /// `x → H_star`: `H* = H_m − H0mᵀ H0⁻¹ H0m`.
    GeneralizedInertia,
    /// `(x, u) → c_star`: `c* = c_m − H0mᵀ H0⁻¹ c0`.
    GeneralizedBias,
    /// `x → J_star` of the point at `offset` (body frame, from its CM) on `body`.
    GeneralizedJacobian {
        /// Body index (0 = base).
        body: usize,
        /// Offset from the body's CM in its frame.
        offset: Vector3<f64>,
    },
    /// `x → p`: position in 𝒥 of the point at `offset` on `body`.
    PointPosition {
        /// Body index (0 = base).
        body: usize,
        /// Offset from the body's CM in its frame.
        offset: Vector3<f64>,
    },
    /// `(x, u) → (P, L_origin)`: linear momentum and angular momentum about the origin of 𝒥.
    Momentum,
    /// `(x, qd, P, L_origin) → base_twist`: `[v0; ω0] = H0⁻¹ (M0 − H0m q̇)`.
    BaseVelocityFromMomentum,
}

impl TapedFunction {
    /// The function of a name (`"forward_dynamics"`, ...; the names of `spacearm.casadi`), with
    /// the point `(body, offset)` for the two functions of a point.
    pub fn from_name(name: &str, point: Option<(usize, Vector3<f64>)>) -> Result<TapedFunction> {
        let needs_point = matches!(name, "generalized_jacobian" | "point_position");
        let (body, offset) = match (needs_point, point) {
            (true, Some(p)) => p,
            (true, None) => return Err(SpacearmError::InvalidArgument(format!("the taped function '{name}' needs a point"))),
            (false, Some(_)) => return Err(SpacearmError::InvalidArgument(format!("the taped function '{name}' takes no point"))),
            (false, None) => (0, Vector3::zeros()),
        };
        Ok(match name {
            "forward_dynamics" => TapedFunction::ForwardDynamics,
            "state_derivative" => TapedFunction::StateDerivative,
            "inverse_dynamics" => TapedFunction::InverseDynamics,
            "mass_matrix" => TapedFunction::MassMatrix,
            "bias_forces" => TapedFunction::BiasForces,
            "generalized_inertia" => TapedFunction::GeneralizedInertia,
            "generalized_bias" => TapedFunction::GeneralizedBias,
            "generalized_jacobian" => TapedFunction::GeneralizedJacobian { body, offset },
            "point_position" => TapedFunction::PointPosition { body, offset },
            "momentum" => TapedFunction::Momentum,
            "base_velocity_from_momentum" => TapedFunction::BaseVelocityFromMomentum,
            _ => {
                return Err(SpacearmError::InvalidArgument(format!(
                    "no taped function named '{name}'; the names are {:?}",
                    TapedFunction::NAMES
                )))
            }
        })
    }

    /// The names [`TapedFunction::from_name`] knows.
    pub const NAMES: [&'static str; 11] = [
        "forward_dynamics",
        "state_derivative",
        "inverse_dynamics",
        "mass_matrix",
        "bias_forces",
        "generalized_inertia",
        "generalized_bias",
        "generalized_jacobian",
        "point_position",
        "momentum",
        "base_velocity_from_momentum",
    ];

    /// The name (as in [`TapedFunction::NAMES`]).
    pub fn name(&self) -> &'static str {
        match self {
            TapedFunction::ForwardDynamics => "forward_dynamics",
            TapedFunction::StateDerivative => "state_derivative",
            TapedFunction::InverseDynamics => "inverse_dynamics",
            TapedFunction::MassMatrix => "mass_matrix",
            TapedFunction::BiasForces => "bias_forces",
            TapedFunction::GeneralizedInertia => "generalized_inertia",
            TapedFunction::GeneralizedBias => "generalized_bias",
            TapedFunction::GeneralizedJacobian { .. } => "generalized_jacobian",
            TapedFunction::PointPosition { .. } => "point_position",
            TapedFunction::Momentum => "momentum",
            TapedFunction::BaseVelocityFromMomentum => "base_velocity_from_momentum",
        }
    }

    /// Names and lengths of the inputs, in order.
    pub fn inputs(&self, model: &Model) -> Vec<(&'static str, usize)> {
        let (nx, nu, n) = (model.nx(), model.nu(), model.n_dof());
        match self {
            TapedFunction::ForwardDynamics | TapedFunction::StateDerivative => vec![("x", nx), ("u", nu), ("tau", n), ("base_wrench", 6)],
            TapedFunction::InverseDynamics => vec![("x", nx), ("u", nu), ("du", nu)],
            TapedFunction::MassMatrix
            | TapedFunction::GeneralizedInertia
            | TapedFunction::GeneralizedJacobian { .. }
            | TapedFunction::PointPosition { .. } => vec![("x", nx)],
            TapedFunction::BiasForces | TapedFunction::GeneralizedBias | TapedFunction::Momentum => vec![("x", nx), ("u", nu)],
            TapedFunction::BaseVelocityFromMomentum => vec![("x", nx), ("qd", n), ("P", 3), ("L_origin", 3)],
        }
    }

    /// Names and shapes `(rows, columns)` of the outputs, in order.
    pub fn outputs(&self, model: &Model) -> Vec<(&'static str, usize, usize)> {
        let (nu, n) = (model.nu(), model.n_dof());
        match self {
            TapedFunction::ForwardDynamics => vec![("du", nu, 1)],
            TapedFunction::StateDerivative => vec![("dy", model.nx() + nu, 1)],
            TapedFunction::InverseDynamics => vec![("f", nu, 1)],
            TapedFunction::MassMatrix => vec![("H", nu, nu)],
            TapedFunction::BiasForces => vec![("c", nu, 1)],
            TapedFunction::GeneralizedInertia => vec![("H_star", n, n)],
            TapedFunction::GeneralizedBias => vec![("c_star", n, 1)],
            TapedFunction::GeneralizedJacobian { .. } => vec![("J_star", 6, n)],
            TapedFunction::PointPosition { .. } => vec![("p", 3, 1)],
            TapedFunction::Momentum => vec![("P", 3, 1), ("L_origin", 3, 1)],
            TapedFunction::BaseVelocityFromMomentum => vec![("base_twist", 6, 1)],
        }
    }
}

/// The nominal configuration of a recording: base at the origin, identity attitude, `q = 0`.
fn nominal_configuration(model: &Model) -> Vec<f64> {
    let mut x = vec![0.0; model.nx()];
    x[6] = 1.0;
    x
}

/// Forward kinematics of the recorded configuration `x` (quaternion normalized first).
fn kinematics(model: &Model, data: &mut DataT<Var>, x: &[Var]) {
    let r0 = Vector3::new(x[0], x[1], x[2]);
    let rot = UnitQuaternion::from_quaternion(Quaternion::new(x[6], x[3], x[4], x[5])).to_rotation_matrix().into_inner();
    forward_kinematics_at(model, data, &r0, &rot, &x[7..]);
}

/// Record `function` of `model`: its [`Tape`], whose inputs and outputs are those of
/// [`TapedFunction::inputs`] and [`TapedFunction::outputs`] concatenated (matrices
/// column-major).
pub fn record(model: &Model, function: &TapedFunction) -> Result<Tape> {
    if let TapedFunction::GeneralizedJacobian { body, .. } | TapedFunction::PointPosition { body, .. } = function {
        check_body(model, *body)?;
    }
    let (nx, nu, n) = (model.nx(), model.nu(), model.n_dof());
    let mut rec = Recording::start();
    let x = rec.inputs(&nominal_configuration(model));
    debug_assert_eq!(x.len(), nx);
    let mut data = DataT::<Var>::new(model);
    kinematics(model, &mut data, &x);
    let outputs: Vec<Var> = match function {
        TapedFunction::ForwardDynamics | TapedFunction::StateDerivative => {
            let u = rec.inputs(&vec![0.0; nu]);
            let tau = rec.inputs(&vec![0.0; n]);
            let wrench = rec.inputs(&[0.0; 6]);
            let f: Vec<Var> = wrench.iter().chain(tau.iter()).copied().collect();
            aba_after_kinematics(model, &mut data, &x[7..], &u, &f)?;
            if *function == TapedFunction::ForwardDynamics {
                data.accel.iter().copied().collect()
            } else {
                // As the simulator's state derivative (sim::simulate): ṙ0, quaṫ, q̇, u̇.
                let quat_rate = quaternion_rate(&x[3..7], &Vector3::new(u[3], u[4], u[5]));
                u[0..3].iter().chain(quat_rate.iter()).chain(u[6..].iter()).chain(data.accel.iter()).copied().collect()
            }
        }
        TapedFunction::InverseDynamics => {
            let u = rec.inputs(&vec![0.0; nu]);
            let du = rec.inputs(&vec![0.0; nu]);
            rnea_after_kinematics(model, &mut data, &u, Some(&du), &[]);
            subtract_joint_passive_forces(model, &x[7..], &u[6..], &mut data.tau.as_mut_slice()[6..]);
            data.tau.iter().copied().collect()
        }
        TapedFunction::BiasForces => {
            let u = rec.inputs(&vec![0.0; nu]);
            rnea_after_kinematics(model, &mut data, &u, None, &[]);
            data.tau.iter().copied().collect()
        }
        TapedFunction::MassMatrix => {
            crba_after_kinematics(model, &mut data, true)?;
            data.mass_matrix.iter().copied().collect()
        }
        TapedFunction::GeneralizedInertia => {
            let inv = reduce_after_kinematics(model, &mut data, true)?;
            reduction_columns(model, &mut data, &inv);
            fill_generalized_inertia(model, &mut data, &inv, false)?;
            data.generalized_inertia.iter().copied().collect()
        }
        TapedFunction::GeneralizedBias => {
            let u = rec.inputs(&vec![0.0; nu]);
            let inv = reduce_after_kinematics(model, &mut data, false)?;
            generalized_bias_after_reduction(model, &mut data, &inv, &u);
            data.generalized_bias.iter().copied().collect()
        }
        TapedFunction::GeneralizedJacobian { body, offset } => {
            let inv = reduce_after_kinematics(model, &mut data, false)?;
            generalized_jacobian_after_reduction(model, &mut data, &inv, *body, offset)?;
            data.generalized_jacobian.iter().copied().collect()
        }
        TapedFunction::PointPosition { body, offset } => point_position(&data, *body, offset).iter().copied().collect(),
        TapedFunction::Momentum => {
            let u = rec.inputs(&vec![0.0; nu]);
            velocity_pass(model, &mut data, &u);
            let (p, l_base) = momentum_about_base(model, &data);
            let l_origin = l_base + data.base_position.cross(&p);
            p.iter().chain(l_origin.iter()).copied().collect()
        }
        TapedFunction::BaseVelocityFromMomentum => {
            let qd = rec.inputs(&vec![0.0; n]);
            let p = rec.inputs(&[0.0; 3]);
            let l = rec.inputs(&[0.0; 3]);
            let inv = reduce_after_kinematics(model, &mut data, false)?;
            let twist: Vector6<Var> =
                base_velocity_after_reduction(&data, &inv, &qd, &Vector3::new(p[0], p[1], p[2]), &Vector3::new(l[0], l[1], l[2]));
            twist.iter().copied().collect()
        }
    };
    Ok(rec.finish(&outputs))
}
