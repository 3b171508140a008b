//! The continuous dynamics of an optimal-control problem, `ż = F(z, c)` on `z = [x; u]`, and
//! their Jacobian in ambient coordinates (the quaternion as four numbers), for the RK4 chain
//! rule of [`super::discretization`].
//!
//! The control `c` is what the mode lets an actuator apply ([`crate::scenario::modes`]): the
//! `N` joint torques (reaction wheels are joints), then the base torque `N0` (rotation-flying)
//! or the base force and torque `[F0; N0]` (flying); the generalized force is `f = S c`. The
//! right-hand side is the simulator's (`sim::plant`, without controller, limits or orbit):
//! `ṙ0 = v0`, `quaṫ = ½ [ω0; 0] ⊗ quat`, `q̇`, `u̇ = FD(x, u, f)` by ABA.
//!
//! Jacobian (`∂F/∂z` is `nz × nz`, `∂F/∂c` is `nz × m`): the kinematic rows are exact linear
//! maps (`∂quaṫ/∂quat = ½ L([ω0; 0])`, `∂quaṫ/∂ω0 = E(quat)`, [`super::state`]); the
//! dynamic rows are the core's forward-dynamics derivatives ([`crate::derivatives`],
//! Carpentier & Mansard 2018) in tangent coordinates, carried to the ambient quaternion by
//! `T(quat)`: `∂u̇/∂quat = ∂u̇/∂δθ · T(quat)`, `∂u̇/∂c = H⁻¹ S`.

use nalgebra::{DMatrix, Vector3};

use super::state::{quaternion_from_tangent, tangent_from_quaternion, StateSpace};
use crate::algorithms::aba::aba_after_kinematics;
use crate::algorithms::kinematics::forward_kinematics;
use crate::derivatives::{forward_dynamics_derivatives, DerivativeData};
use crate::error::{Result, SpacearmError};
use crate::math::rotations::quaternion_rate;
use crate::model::{Data, Model};
use crate::scenario::modes::Mode;

/// Which generalized-force components the control `c` drives in a mode.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ControlMap {
    /// `f[columns[i]] = c[i]`.
    pub columns: Vec<usize>,
}

impl ControlMap {
    /// The joint torques, then the base wrench components the mode allows (module docs).
    /// Translation-flying (a force through the moving system CM) is refused: its derivative
    /// with respect to the configuration is not implemented yet.
    pub fn new(model: &Model, mode: Mode) -> Result<ControlMap> {
        let mut columns: Vec<usize> = (6..model.nu()).collect();
        match mode {
            Mode::Floating | Mode::RotationFloating => {}
            Mode::RotationFlying => columns.extend(3..6),
            Mode::Flying => columns.extend(0..6),
            Mode::TranslationFlying => {
                return Err(SpacearmError::argument(
                    "optimal control in the translation-flying mode is not implemented yet (its force acts through the moving system CM); use \
                     'flying', 'rotation-flying', 'rotation-floating' or 'floating'",
                ))
            }
        }
        Ok(ControlMap { columns })
    }

    /// `m`, the length of `c`.
    pub fn len(&self) -> usize {
        self.columns.len()
    }

    /// Whether there is no control at all.
    pub fn is_empty(&self) -> bool {
        self.columns.is_empty()
    }

    /// `f = S c` into `f` (length `6+N`).
    pub fn force(&self, c: &[f64], f: &mut [f64]) {
        f.fill(0.0);
        for (col, v) in self.columns.iter().zip(c) {
            f[*col] = *v;
        }
    }
}

/// Workspaces of the continuous dynamics of one model.
pub struct Dynamics {
    /// The state's dimensions.
    pub space: StateSpace,
    /// The control map.
    pub controls: ControlMap,
    data: Data,
    work: DerivativeData,
    f: Vec<f64>,
}

impl Dynamics {
    /// Workspaces for `model` with the controls of `mode`.
    pub fn new(model: &Model, mode: Mode) -> Result<Dynamics> {
        Ok(Dynamics {
            space: StateSpace { n: model.n_dof() },
            controls: ControlMap::new(model, mode)?,
            data: Data::new(model),
            work: DerivativeData::new(model),
            f: vec![0.0; model.nu()],
        })
    }

    /// `ż = F(z, c)` into `dz` (the simulator's right-hand side, ABA).
    pub fn rhs(&mut self, model: &Model, z: &[f64], c: &[f64], dz: &mut [f64]) -> Result<()> {
        let nx = self.space.nx();
        let (x, u) = z.split_at(nx);
        self.controls.force(c, &mut self.f);
        forward_kinematics(model, &mut self.data, x)?;
        aba_after_kinematics(model, &mut self.data, &x[7..], u, &self.f)?;
        kinematic_rates(x, u, dz);
        dz[nx..].copy_from_slice(self.data.accel.as_slice());
        Ok(())
    }

    /// `ż` into `dz`, `∂F/∂z` into `jz` (`nz × nz`) and `∂F/∂c` into `jc` (`nz × m`) at a
    /// unit-quaternion `z` (module docs). The acceleration is the derivative routine's
    /// (`H⁻¹(f − c)`, equal to ABA's to rounding).
    pub fn rhs_jacobian(&mut self, model: &Model, z: &[f64], c: &[f64], dz: &mut [f64], jz: &mut DMatrix<f64>, jc: &mut DMatrix<f64>) -> Result<()> {
        let (nx, nu) = (self.space.nx(), self.space.nu());
        let (x, u) = z.split_at(nx);
        self.controls.force(c, &mut self.f);
        forward_dynamics_derivatives(model, &mut self.work, x, u, &self.f)?;
        let (dx, du, hinv) = (&self.work.accel_wrt_configuration, &self.work.accel_wrt_velocity, &self.work.accel_wrt_force);
        kinematic_rates(x, u, dz);
        dz[nx..].copy_from_slice(self.work.data.accel.as_slice());
        jz.fill(0.0);
        // ṙ0 = v0, q̇ rows.
        for i in 0..3 {
            jz[(i, nx + i)] = 1.0;
        }
        for i in 7..nx {
            jz[(i, nx + i - 1)] = 1.0;
        }
        // quaṫ = ½ [ω; 0] ⊗ [v; w]: ∂/∂v = ½ [ω̃; −ωᵀ], ∂/∂w = ½ [ω; 0], ∂/∂ω = E(quat).
        let w = Vector3::new(u[3], u[4], u[5]);
        let wx = crate::math::spatial::skew(&w) * 0.5;
        jz.view_mut((3, 3), (3, 3)).copy_from(&wx);
        for k in 0..3 {
            jz[(6, 3 + k)] = -0.5 * w[k];
            jz[(3 + k, 6)] = 0.5 * w[k];
        }
        jz.view_mut((3, nx + 3), (4, 3)).copy_from(&quaternion_from_tangent(&x[3..7]));
        // u̇ rows: ∂u̇/∂r0 = dx[:, 0..3] (zero), ∂u̇/∂quat = dx[:, 3..6] T(quat), ∂u̇/∂q, ∂u̇/∂u.
        let t = tangent_from_quaternion(&x[3..7]);
        jz.view_mut((nx, 0), (nu, 3)).copy_from(&dx.columns(0, 3));
        jz.view_mut((nx, 3), (nu, 4)).copy_from(&(dx.columns(3, 3) * t));
        jz.view_mut((nx, 7), (nu, nu - 6)).copy_from(&dx.columns(6, nu - 6));
        jz.view_mut((nx, nx), (nu, nu)).copy_from(du);
        jc.fill(0.0);
        for (i, col) in self.controls.columns.iter().enumerate() {
            jc.view_mut((nx, i), (nu, 1)).copy_from(&hinv.column(*col));
        }
        Ok(())
    }
}

/// The kinematic rows `[ṙ0; quaṫ; q̇] = [v0; ½ [ω0; 0] ⊗ quat; q̇]` into `dz[..nx]`.
fn kinematic_rates(x: &[f64], u: &[f64], dz: &mut [f64]) {
    let nx = x.len();
    dz[0..3].copy_from_slice(&u[0..3]);
    dz[3..7].copy_from_slice(&quaternion_rate(&x[3..7], &Vector3::new(u[3], u[4], u[5])));
    dz[7..nx].copy_from_slice(&u[6..]);
}
