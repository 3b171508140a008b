//! The discrete dynamics `z_{k+1} = Φ(z_k, c_k)`: one classical Runge–Kutta 4 step of length
//! `h` with `c` held, the quaternion renormalised at every stage and at the end — the step of
//! the native simulator (`math::integrate::Rk4` on `sim::plant`, `integrator = "rk4"`) and of
//! `spacearm.casadi.rk4_step`, so that a solution re-simulates without a discretisation
//! mismatch.
//!
//! Jacobians by the chain rule through the stages, in ambient coordinates (docs/mpc.md):
//! with `Z_i = ∂s_i/∂(δz, c)` the sensitivity of stage value `s_i` and `K_i = ∂k_i/∂(δz, c)`,
//!
//! `Z_1 = [E(z) | 0]`, `K_i = ∂F/∂z(s_i) Z_i + [0 | ∂F/∂c(s_i)]`,
//! `Z_2 = N(p_2)(Z_1 + h/2 K_1)`, `Z_3 = N(p_3)(Z_1 + h/2 K_2)`, `Z_4 = N(p_4)(Z_1 + h K_3)`,
//! `∂z⁺ = N(p⁺)(Z_1 + h/6 (K_1 + 2K_2 + 2K_3 + K_4))`,
//!
//! where `N(p) = (E₄ − p̂ p̂ᵀ)/|p|` on the quaternion rows (the derivative of the
//! renormalisation `p ↦ p/|p|` at the pre-normalised value `p`, identity elsewhere) and
//! `E(z)` maps the tangent increment to the ambient one ([`super::state`]). The tangent
//! Jacobians are then `A = T(z⁺) ∂z⁺/∂δz` and `B = T(z⁺) ∂z⁺/∂c`.

use nalgebra::{DMatrix, Vector4};
use serde::{Deserialize, Serialize};

use super::dynamics::Dynamics;
use super::euler::EulerDiscretization;
use crate::error::Result;
use crate::model::Model;

/// Which step a problem's knots take (serde data of the run description, `ProblemSpec`'s
/// `discretization`): `"rk4"` (the simulator's step, the default; this module) or `"euler"`
/// (the semi-implicit Euler step, [`super::euler`]: one derivative evaluation per knot instead
/// of four, a model that differs from the RK4 plant by `O(h)`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(try_from = "String", into = "&'static str")]
pub enum DiscretizationKind {
    /// Classical RK4 with the quaternion renormalised (the simulator's `integrator = "rk4"`).
    #[default]
    Rk4,
    /// Semi-implicit Euler on the state manifold (Crocoddyl's `IntegratedActionModelEuler`).
    Euler,
}

crate::error::named_by!(DiscretizationKind, "discretization", [Rk4 = "rk4", Euler = "euler"]);

/// The step of a problem's knots, one of [`DiscretizationKind`].
pub enum Discretization {
    /// RK4 (this module).
    Rk4(Rk4Discretization),
    /// Semi-implicit Euler ([`super::euler`]).
    Euler(EulerDiscretization),
}

impl Discretization {
    /// Workspaces for steps of `h` seconds of `dynamics` of the `kind`.
    pub fn new(kind: DiscretizationKind, dynamics: Dynamics, h: f64) -> Self {
        match kind {
            DiscretizationKind::Rk4 => Discretization::Rk4(Rk4Discretization::new(dynamics, h)),
            DiscretizationKind::Euler => Discretization::Euler(EulerDiscretization::new(dynamics, h)),
        }
    }

    /// The step, s.
    pub fn h(&self) -> f64 {
        match self {
            Discretization::Rk4(d) => d.h,
            Discretization::Euler(d) => d.h,
        }
    }

    /// The continuous dynamics.
    pub fn dynamics(&self) -> &Dynamics {
        match self {
            Discretization::Rk4(d) => &d.dynamics,
            Discretization::Euler(d) => &d.dynamics,
        }
    }

    /// `z⁺ = Φ(z, c)` into `next`.
    pub fn step(&mut self, model: &Model, z: &[f64], c: &[f64], next: &mut [f64]) -> Result<()> {
        match self {
            Discretization::Rk4(d) => d.step(model, z, c, next),
            Discretization::Euler(d) => d.step(model, z, c, next),
        }
    }

    /// `z⁺ = Φ(z, c)` into `next` with the tangent Jacobians `A` and `B`.
    pub fn step_derivatives(&mut self, model: &Model, z: &[f64], c: &[f64], next: &mut [f64], a: &mut DMatrix<f64>, b: &mut DMatrix<f64>) -> Result<()> {
        match self {
            Discretization::Rk4(d) => d.step_derivatives(model, z, c, next, a, b),
            Discretization::Euler(d) => d.step_derivatives(model, z, c, next, a, b),
        }
    }
}

/// Workspaces of the RK4 step and its Jacobians.
pub struct Rk4Discretization {
    /// The continuous dynamics.
    pub dynamics: Dynamics,
    /// The step, s.
    pub h: f64,
    k: [Vec<f64>; 4],
    stage: Vec<f64>,
    z1: DMatrix<f64>,
    zi: DMatrix<f64>,
    ki: [DMatrix<f64>; 4],
    acc: DMatrix<f64>,
}

impl Rk4Discretization {
    /// Workspaces for steps of `h` seconds of `dynamics`.
    pub fn new(dynamics: Dynamics, h: f64) -> Self {
        let (nz, nd, m) = (dynamics.space.nz(), dynamics.space.nd(), dynamics.controls.len());
        let mat = || DMatrix::zeros(nz, nd + m);
        Rk4Discretization {
            h,
            k: std::array::from_fn(|_| vec![0.0; nz]),
            stage: vec![0.0; nz],
            z1: {
                let mut z1 = mat();
                let mut e = DMatrix::zeros(nz, nd);
                let mut unit = vec![0.0; nz];
                unit[6] = 1.0;
                dynamics.space.ambient_from_tangent(&unit, &mut e);
                z1.columns_mut(0, nd).copy_from(&e);
                z1
            },
            zi: mat(),
            ki: std::array::from_fn(|_| mat()),
            acc: mat(),
            dynamics,
        }
    }

    /// `z⁺ = Φ(z, c)` into `next`.
    pub fn step(&mut self, model: &Model, z: &[f64], c: &[f64], next: &mut [f64]) -> Result<()> {
        let h = self.h;
        self.dynamics.rhs(model, z, c, &mut self.k[0])?;
        for (i, a) in [(1usize, 0.5 * h), (2, 0.5 * h), (3, h)] {
            combine(&mut self.stage, z, a, &self.k[i - 1]);
            normalize_quaternion(&mut self.stage);
            self.dynamics.rhs(model, &self.stage, c, &mut self.k[i])?;
        }
        for j in 0..z.len() {
            next[j] = z[j] + h / 6.0 * (self.k[0][j] + 2.0 * self.k[1][j] + 2.0 * self.k[2][j] + self.k[3][j]);
        }
        normalize_quaternion(next);
        Ok(())
    }

    /// `z⁺ = Φ(z, c)` into `next` and the tangent Jacobians `A = ∂z⁺/∂δz` into `a` (`nd × nd`)
    /// and `B = ∂z⁺/∂c` into `b` (`nd × m`) (module docs). `z` has a unit quaternion.
    pub fn step_derivatives(&mut self, model: &Model, z: &[f64], c: &[f64], next: &mut [f64], a: &mut DMatrix<f64>, b: &mut DMatrix<f64>) -> Result<()> {
        let h = self.h;
        let space = self.dynamics.space;
        let (nd, m) = (space.nd(), self.dynamics.controls.len());
        // Z_1 = [E(z) | 0]: the identity but on the quaternion's rows (set in `new`); E's block here.
        self.z1.view_mut((3, 3), (4, 3)).copy_from(&super::state::quaternion_from_tangent(&z[3..7]));
        self.stage.copy_from_slice(z);
        for i in 0..4 {
            if i > 0 {
                let coef = if i == 3 { h } else { 0.5 * h };
                combine(&mut self.stage, z, coef, &self.k[i - 1]);
                // Z_i = N(p_i) (Z_1 + coef K_{i-1}), p_i the stage before renormalisation.
                self.zi.copy_from(&self.z1);
                add_scaled(&mut self.zi, coef, &self.ki[i - 1]);
                normalization_jacobian_rows(&self.stage, &mut self.zi);
                normalize_quaternion(&mut self.stage);
            }
            self.dynamics.rhs_derivatives(model, &self.stage, c, &mut self.k[i])?;
            // K_i = ∂F/∂z(s_i) Z_i + [0 | ∂F/∂c(s_i)] (the first stage's Z_1 is [E | 0]).
            let s = if i == 0 { &self.z1 } else { &self.zi };
            self.dynamics.sensitivity(&self.stage, s, i == 0, &mut self.ki[i]);
        }
        for j in 0..z.len() {
            next[j] = z[j] + h / 6.0 * (self.k[0][j] + 2.0 * self.k[1][j] + 2.0 * self.k[2][j] + self.k[3][j]);
        }
        self.acc.copy_from(&self.z1);
        for (i, w) in [1.0, 2.0, 2.0, 1.0].iter().enumerate() {
            add_scaled(&mut self.acc, h / 6.0 * w, &self.ki[i]);
        }
        normalization_jacobian_rows(next, &mut self.acc);
        normalize_quaternion(next);
        // A = T(z⁺) ∂z⁺/∂δz, B = T(z⁺) ∂z⁺/∂c: T is the identity but on the quaternion's rows
        // (StateSpace::tangent_from_ambient), so only those rows are a product.
        let t = super::state::tangent_from_quaternion(&next[3..7]);
        let nz = space.nz();
        for (out, from, cols) in [(a, 0, nd), (b, nd, m)] {
            for c in 0..cols {
                let col = from + c;
                for r in 0..3 {
                    out[(r, c)] = self.acc[(r, col)];
                }
                for r in 0..3 {
                    out[(3 + r, c)] = (0..4).map(|j| t[(r, j)] * self.acc[(3 + j, col)]).sum();
                }
                for i in 7..nz {
                    out[(i - 1, c)] = self.acc[(i, col)];
                }
            }
        }
        Ok(())
    }
}

/// `m += a k` (no temporary).
fn add_scaled(m: &mut DMatrix<f64>, a: f64, k: &DMatrix<f64>) {
    for (v, x) in m.as_mut_slice().iter_mut().zip(k.as_slice()) {
        *v += a * x;
    }
}

/// `out = z + a k`.
fn combine(out: &mut [f64], z: &[f64], a: f64, k: &[f64]) {
    for ((o, zi), ki) in out.iter_mut().zip(z).zip(k) {
        *o = zi + a * ki;
    }
}

/// The quaternion `z[3..7]` divided by its norm.
fn normalize_quaternion(z: &mut [f64]) {
    crate::math::rotations::normalize_xyzw(&mut z[3..7]);
}

/// Rows 3..7 of `m` ← `N(p) m[3..7, :]` with `N(p) = (E₄ − p̂ p̂ᵀ)/|p|`, `p = z[3..7]` (before
/// the renormalisation).
fn normalization_jacobian_rows(z: &[f64], m: &mut DMatrix<f64>) {
    let p = Vector4::new(z[3], z[4], z[5], z[6]);
    let norm = p.norm();
    let ph = p / norm;
    let proj = (nalgebra::Matrix4::identity() - ph * ph.transpose()) / norm;
    for c in 0..m.ncols() {
        let col = Vector4::new(m[(3, c)], m[(4, c)], m[(5, c)], m[(6, c)]);
        let v = proj * col;
        for r in 0..4 {
            m[(3 + r, c)] = v[r];
        }
    }
}

/// Test support: the largest relative difference `|fd − an| / (1 + |an|)` between a step's
/// tangent Jacobians `A`, `B` at `(z, c)` (whose step end is `next`) and central differences of
/// the step in tangent coordinates, Richardson-extrapolated (`(4 D(ε/2) − D(ε)) / 3`), with
/// where it is (row, column, difference, analytic).
#[cfg(test)]
#[allow(clippy::too_many_arguments)]
fn jacobian_fd_error(
    space: super::state::StateSpace,
    z: &[f64],
    c: &[f64],
    next: &[f64],
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    eps: f64,
    mut step: impl FnMut(&[f64], &[f64], &mut [f64]),
) -> (f64, (usize, usize, f64, f64)) {
    let (nz, nd, m) = (space.nz(), space.nd(), c.len());
    let (mut zp, mut zm, mut np, mut nm) = (vec![0.0; nz], vec![0.0; nz], vec![0.0; nz], vec![0.0; nz]);
    let (mut dp, mut dm) = (vec![0.0; nd], vec![0.0; nd]);
    let mut column = |j: usize, eps: f64| -> Vec<f64> {
        let mut d = vec![0.0; nd];
        let (mut cp, mut cm) = (c.to_vec(), c.to_vec());
        if j < nd {
            d[j] = eps;
            space.integrate(z, &d, &mut zp);
            d[j] = -eps;
            space.integrate(z, &d, &mut zm);
        } else {
            zp.copy_from_slice(z);
            zm.copy_from_slice(z);
            cp[j - nd] += eps;
            cm[j - nd] -= eps;
        }
        step(&zp, &cp, &mut np);
        step(&zm, &cm, &mut nm);
        space.diff(next, &np, &mut dp);
        space.diff(next, &nm, &mut dm);
        (0..nd).map(|i| (dp[i] - dm[i]) / (2.0 * eps)).collect()
    };
    let (mut worst, mut at) = (0.0, (0, 0, 0.0, 0.0));
    for j in 0..nd + m {
        let (coarse, fine) = (column(j, eps), column(j, eps / 2.0));
        for i in 0..nd {
            let fd = (4.0 * fine[i] - coarse[i]) / 3.0;
            let an = if j < nd { a[(i, j)] } else { b[(i, j - nd)] };
            let e = (fd - an).abs() / (1.0 + an.abs());
            if e > worst {
                worst = e;
                at = (i, j, fd, an);
            }
        }
    }
    (worst, at)
}

/// Test support, the check of both steps: at every tumbling case
/// ([`super::dynamics::tumbling_cases`]) the step of `kind` with its Jacobians agrees with the
/// plain step (ABA and `H⁻¹(f − c)` to rounding, ~1e-12 here: `H` is ill-conditioned), and
/// its `A`, `B` with central differences ([`jacobian_fd_error`]); then `more(model, mode, z, c,
/// plain step, A, B)` checks what is the kind's own.
#[cfg(test)]
pub(crate) fn check_step_jacobians(
    kind: DiscretizationKind,
    h: f64,
    mut more: impl FnMut(&Model, crate::scenario::modes::Mode, &[f64], &[f64], &[f64], &DMatrix<f64>, &DMatrix<f64>),
) {
    let (model, cases) = super::dynamics::tumbling_cases();
    for (mode, dynamics, z, c) in cases {
        let space = dynamics.space;
        let (nz, nd, m) = (space.nz(), space.nd(), c.len());
        let mut disc = Discretization::new(kind, dynamics, h);
        let (mut a, mut b) = (DMatrix::zeros(nd, nd), DMatrix::zeros(nd, m));
        let mut next = vec![0.0; nz];
        disc.step_derivatives(&model, &z, &c, &mut next, &mut a, &mut b).unwrap();
        let mut plain = vec![0.0; nz];
        disc.step(&model, &z, &c, &mut plain).unwrap();
        for (p, n) in plain.iter().zip(&next) {
            assert!((p - n).abs() < 1e-9 * (1.0 + p.abs()), "{kind:?} {mode:?}: the two steps differ: {p} vs {n}");
        }
        // The accelerations carry rounding noise of ~1e-12 (ill-conditioned H) that the
        // differences divide by eps: with eps = 1e-4 that noise and the truncation error eps²
        // are both ~1e-8, against O(h²) ~ 1e-3 for a missing term.
        let (worst, at) = jacobian_fd_error(space, &z, &c, &next, &a, &b, 1e-4, |z, c, out| disc.step(&model, z, c, out).unwrap());
        assert!(worst < 1e-6, "{kind:?} {mode:?}: largest relative difference {worst:e} at {at:?}");
        more(&model, mode, &z, &c, &plain, &a, &b);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// As data the kind is its name; another name is refused naming the table.
    #[test]
    fn the_kind_is_read_and_written_by_its_name() {
        #[derive(Debug, Serialize, Deserialize)]
        struct Spec {
            discretization: DiscretizationKind,
        }
        let read = |s: &str| toml::from_str::<Spec>(s).map(|s| s.discretization).map_err(|e| e.to_string());
        assert_eq!(read("discretization = 'euler'"), Ok(DiscretizationKind::Euler));
        assert_eq!(read("discretization = 'rk4'"), Ok(DiscretizationKind::Rk4));
        let e = read("discretization = 'rk5'").unwrap_err();
        assert!(e.contains(r#"discretization must be one of ["rk4", "euler"], got 'rk5'"#), "{e}");
        let text = toml::to_string(&Spec { discretization: DiscretizationKind::Euler }).unwrap();
        assert_eq!(text.trim(), r#"discretization = "euler""#);
    }

    /// `A` and `B` against central differences of the step in tangent coordinates, for a
    /// spatial arm in every mode with controls, at a tumbling, moving state.
    #[test]
    fn step_jacobians_match_finite_differences() {
        check_step_jacobians(DiscretizationKind::Rk4, 0.05, |_, mode, _, _, _, a, b| {
            assert!(a.norm() > 1.0 && b.norm() > 1e-3, "{mode:?}: a trivial Jacobian");
        });
    }
}
