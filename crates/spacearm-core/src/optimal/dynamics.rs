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
    /// `[∂u̇/∂(δθ, q) | ∂u̇/∂u]` (`(6+N) × (9+2N)`) and the stacked factor of [`Dynamics::sensitivity`].
    partials: DMatrix<f64>,
    stacked: DMatrix<f64>,
}

impl Dynamics {
    /// Workspaces for `model` with the controls of `mode`.
    pub fn new(model: &Model, mode: Mode) -> Result<Dynamics> {
        let controls = ControlMap::new(model, mode)?;
        let (nu, nd) = (model.nu(), 12 + 2 * model.n_dof());
        Ok(Dynamics {
            space: StateSpace { n: model.n_dof() },
            partials: DMatrix::zeros(nu, 2 * nu - 3),
            stacked: DMatrix::zeros(2 * nu - 3, nd + controls.len()),
            controls,
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

    /// `ż = F(z, c)` into `dz` at a unit-quaternion `z`, by the derivative routine (its
    /// acceleration `H⁻¹(f − c)`, equal to ABA's to rounding), keeping the partials of the
    /// acceleration for [`Dynamics::sensitivity`].
    pub fn rhs_derivatives(&mut self, model: &Model, z: &[f64], c: &[f64], dz: &mut [f64]) -> Result<()> {
        let nx = self.space.nx();
        let (x, u) = z.split_at(nx);
        self.controls.force(c, &mut self.f);
        forward_dynamics_derivatives(model, &mut self.work, x, u, &self.f)?;
        kinematic_rates(x, u, dz);
        dz[nx..].copy_from_slice(self.work.data.accel.as_slice());
        Ok(())
    }

    /// The partials of the acceleration at the `z` of the last [`Dynamics::rhs_derivatives`]:
    /// `∂u̇/∂δx` (tangent configuration columns `[δr0, δθ, δq]`), `∂u̇/∂u` and `∂u̇/∂f = H⁻¹`
    /// (each `(6+N) × (6+N)`).
    pub fn partials(&self) -> (&DMatrix<f64>, &DMatrix<f64>, &DMatrix<f64>) {
        let w = &self.work;
        (&w.accel_wrt_configuration, &w.accel_wrt_velocity, &w.accel_wrt_force)
    }

    /// `out = ∂F/∂z(z) S + [0 | ∂F/∂c(z)]` for a sensitivity `S` (`nz × (nd + m)`, the last `m`
    /// columns those of the controls) at the `z` of the last [`Dynamics::rhs_derivatives`]
    /// (the product [`Dynamics::rhs_jacobian`] would give, without forming `∂F/∂z`): the
    /// kinematic rows pick rows of `S` (`ṙ0 = v0`, `q̇`) or mix the quaternion's and `ω0`'s
    /// (`quaṫ`); the `6+N` acceleration rows are `∂u̇/∂x · (T S_x) + ∂u̇/∂u · S_u`, where
    /// `T S_x` is the configuration rows of `S` in tangent coordinates (`δθ = T dquat`;
    /// `∂u̇/∂r0 = 0`: no column for it). `start`: `S` is `[E(z) | 0]` (the first RK4 stage,
    /// [`super::discretization`]), whose acceleration rows are `[∂u̇/∂x | ∂u̇/∂u | H⁻¹ S]`
    /// exactly (`T E = I`): copied, not multiplied.
    pub fn sensitivity(&mut self, z: &[f64], s: &DMatrix<f64>, start: bool, out: &mut DMatrix<f64>) {
        let space = self.space;
        let (nx, nu, nz, nd) = (space.nx(), space.nu(), space.nz(), space.nd());
        let w = &self.work;
        let (dx, du, hinv) = (&w.accel_wrt_configuration, &w.accel_wrt_velocity, &w.accel_wrt_force);
        let e = quaternion_from_tangent(&z[3..7]);
        let t = tangent_from_quaternion(&z[3..7]);
        let om = [z[nx + 3], z[nx + 4], z[nx + 5]];
        let p = s.ncols();
        for j in 0..p {
            let sc = &s.as_slice()[j * nz..(j + 1) * nz];
            let oc = &mut out.as_mut_slice()[j * nz..(j + 1) * nz];
            oc[0..3].copy_from_slice(&sc[nx..nx + 3]);
            // quaṫ = ½ [ω; 0] ⊗ [v; w]: ½ (ω × dv + ω dw), −½ ω·dv; + E(quat) dω.
            let (a, b, o) = ([sc[3], sc[4], sc[5]], sc[6], [sc[nx + 3], sc[nx + 4], sc[nx + 5]]);
            let cross = [om[1] * a[2] - om[2] * a[1], om[2] * a[0] - om[0] * a[2], om[0] * a[1] - om[1] * a[0]];
            for r in 0..3 {
                oc[3 + r] = 0.5 * cross[r] + 0.5 * om[r] * b + e[(r, 0)] * o[0] + e[(r, 1)] * o[1] + e[(r, 2)] * o[2];
            }
            oc[6] = -0.5 * (om[0] * a[0] + om[1] * a[1] + om[2] * a[2]) + e[(3, 0)] * o[0] + e[(3, 1)] * o[1] + e[(3, 2)] * o[2];
            oc[7..nx].copy_from_slice(&sc[nx + 6..nz]);
            if start {
                let acc = &mut oc[nx..nz];
                match j {
                    _ if j < nu => acc.copy_from_slice(dx.column(j).as_slice()),
                    _ if j < nd => acc.copy_from_slice(du.column(j - nu).as_slice()),
                    _ => acc.fill(0.0),
                }
            } else {
                // The stacked right factor [T S_quat; S_q; S_u] of column j.
                let vc = &mut self.stacked.as_mut_slice()[j * (2 * nu - 3)..(j + 1) * (2 * nu - 3)];
                for r in 0..3 {
                    vc[r] = t[(r, 0)] * sc[3] + t[(r, 1)] * sc[4] + t[(r, 2)] * sc[5] + t[(r, 3)] * sc[6];
                }
                vc[3..nu - 3].copy_from_slice(&sc[7..nx]);
                vc[nu - 3..].copy_from_slice(&sc[nx..nz]);
            }
        }
        if !start {
            // [∂u̇/∂(δθ, q) | ∂u̇/∂u], then one product for the acceleration rows.
            self.partials.columns_mut(0, nu - 3).copy_from(&dx.columns(3, nu - 3));
            self.partials.columns_mut(nu - 3, nu).copy_from(du);
            out.rows_mut(nx, nu).gemm(1.0, &self.partials, &self.stacked, 0.0);
        }
        for (i, col) in self.controls.columns.iter().enumerate() {
            let mut oc = out.view_mut((nx, nd + i), (nu, 1));
            oc += hinv.column(*col);
        }
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

/// The point of the optimal-control derivative checks (this module's, the RK4 and the Euler
/// steps'): the spatial arm, and for each mode with controls its dynamics and a tumbling, moving
/// state `z` (base off the origin, a unit quaternion far from the identity, every rate non-zero)
/// with non-zero controls `c`.
#[cfg(test)]
pub(crate) fn tumbling_cases() -> (Model, Vec<(Mode, Dynamics, Vec<f64>, Vec<f64>)>) {
    let model = crate::model::presets::spatial6();
    let cases = [Mode::Floating, Mode::RotationFlying, Mode::Flying]
        .into_iter()
        .map(|mode| {
            let dynamics = Dynamics::new(&model, mode).unwrap();
            let mut z = vec![0.0; dynamics.space.nz()];
            z[0..3].copy_from_slice(&[0.1, -0.2, 0.3]);
            z[3..7].copy_from_slice(&[0.2, -0.1, 0.3, 0.9]);
            crate::math::rotations::normalize_xyzw(&mut z[3..7]);
            for (i, zi) in z.iter_mut().enumerate().skip(7) {
                *zi = 0.3 * ((i * 7) as f64).sin();
            }
            let c: Vec<f64> = (0..dynamics.controls.len()).map(|i| 2.0 * ((i * 3 + 1) as f64).cos()).collect();
            (mode, dynamics, z, c)
        })
        .collect();
    (model, cases)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ops::AddAssign;

    /// The structured product equals the dense Jacobian's, in every mode with controls, at a
    /// tumbling, moving state, for a dense sensitivity and for the first stage's `[E | 0]`.
    #[test]
    fn sensitivity_equals_the_dense_jacobian_product() {
        let (model, cases) = tumbling_cases();
        for (mode, mut dynamics, z, c) in cases {
            let space = dynamics.space;
            let (nz, nd, m) = (space.nz(), space.nd(), c.len());
            let (mut jz, mut jc) = (DMatrix::zeros(nz, nz), DMatrix::zeros(nz, m));
            let (mut d1, mut d2) = (vec![0.0; nz], vec![0.0; nz]);
            dynamics.rhs_jacobian(&model, &z, &c, &mut d1, &mut jz, &mut jc).unwrap();
            dynamics.rhs_derivatives(&model, &z, &c, &mut d2).unwrap();
            assert_eq!(d1, d2);
            let mut e = DMatrix::zeros(nz, nd);
            space.ambient_from_tangent(&z, &mut e);
            let mut start = DMatrix::zeros(nz, nd + m);
            start.columns_mut(0, nd).copy_from(&e);
            let dense = DMatrix::from_fn(nz, nd + m, |i, j| ((i * 7 + j * 13) as f64 * 0.1).sin());
            for (s, first) in [(&dense, false), (&start, true)] {
                let mut expected = &jz * s;
                expected.columns_mut(nd, m).add_assign(&jc);
                let mut out = DMatrix::from_element(nz, nd + m, f64::NAN);
                dynamics.sensitivity(&z, s, first, &mut out);
                let err = (&out - &expected).amax();
                assert!(err < 1e-12 * (1.0 + expected.amax()), "{mode:?} start {first}: {err:e}");
                assert!(expected.rows(space.nx(), space.nu()).amax() > 1e-2, "a trivial product");
            }
        }
    }
}
