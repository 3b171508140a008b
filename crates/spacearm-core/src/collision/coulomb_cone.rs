//! The Coulomb friction cone of a point contact and the residual of the rigid frictional contact
//! problem (docs/contact.md, "Rigid frictional impacts"), shared by the two solvers (admm.rs,
//! pgs.rs).
//!
//! Each point contributes three rows in its contact frame, `[t₁, t₂, n]` (two tangents, then the
//! normal from the first body towards the second). Its impulse `λ = [λ_t; λ_n]` lies in the cone
//! `K_μ = {‖λ_t‖ ≤ μ λ_n}`, whose dual is `K*_μ = {μ ‖σ_t‖ ≤ σ_n}`. With the contact velocity
//! `σ = G λ + g` (G the Delassus operator, g the free velocity), Coulomb's law with maximal
//! dissipation is the nonlinear complementarity problem (De Saxcé & Feng 1991; Carpentier et al.
//! 2024, eq. 12):
//!
//! `K_μ ∋ λ ⊥ σ + Γ(σ) ∈ K*_μ`,  `Γ(σ) = [0; 0; μ ‖σ_t‖]` (De Saxcé's correction),
//!
//! whose solutions are: apart (`λ = 0`, `σ_n ≥ 0`), sticking (`σ = 0`, `λ` in the cone) or
//! sliding (`σ_n = 0`, `λ_t = −μ λ_n σ_t / ‖σ_t‖`).

use nalgebra::{DVector, Vector2, Vector3};

/// The projection of `v = [v_t; v_n]` on the cone `‖v_t‖ ≤ μ v_n` (the second-order cone
/// scaled by `μ`; `μ = 0`: the normal half-line).
pub fn project_cone(v: &Vector3<f64>, mu: f64) -> Vector3<f64> {
    let t = Vector2::new(v[0], v[1]);
    let (nt, vn) = (t.norm(), v[2]);
    if nt <= mu * vn {
        return *v;
    }
    if mu * nt <= -vn {
        // In the polar cone: the apex.
        return Vector3::zeros();
    }
    // Onto the boundary ray [μ t̂; 1]: the scalar projection of (‖t‖, v_n) on (μ, 1).
    let a = (mu * nt + vn) / (1.0 + mu * mu);
    let dir = if nt > 0.0 { t / nt } else { Vector2::zeros() };
    Vector3::new(mu * a * dir[0], mu * a * dir[1], a)
}

/// The projection on the dual cone `μ ‖v_t‖ ≤ v_n` (the cone of `1/μ`; `μ = 0`: the half-space
/// `v_n ≥ 0`).
pub fn project_dual_cone(v: &Vector3<f64>, mu: f64) -> Vector3<f64> {
    if mu == 0.0 {
        return Vector3::new(v[0], v[1], v[2].max(0.0));
    }
    // K*_μ = {‖v_t‖ ≤ v_n / μ}: the cone of friction 1/μ.
    project_cone(v, 1.0 / mu)
}

/// De Saxcé's correction `Γ(σ)` of the contact velocities `sigma` (3 rows a point) added in place:
/// `σ_n += μ ‖σ_t‖`.
pub fn add_de_saxce(sigma: &mut DVector<f64>, friction: &[f64]) {
    for (i, mu) in friction.iter().enumerate() {
        let t = Vector2::new(sigma[3 * i], sigma[3 * i + 1]).norm();
        sigma[3 * i + 2] += mu * t;
    }
}

/// The block of point `i` of a stacked vector.
pub fn block(v: &DVector<f64>, i: usize) -> Vector3<f64> {
    Vector3::new(v[3 * i], v[3 * i + 1], v[3 * i + 2])
}

/// How far a candidate impulse is from solving the problem (all in m/s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConeResidual {
    /// `maxᵢ ‖sᵢ − P_{K*}(sᵢ)‖`, `s = σ + Γ(σ)`: the velocity outside the dual cone (a
    /// penetrating normal velocity, or a slip that the impulse does not oppose), m/s.
    pub dual_feasibility: f64,
    /// `maxᵢ |λᵢ · sᵢ| / ‖λᵢ‖` over the points that push: the velocity along the impulse (a
    /// separating or sliding point that the impulse still works against), m/s.
    pub complementarity: f64,
}

impl ConeResidual {
    /// The larger of the two, m/s: what a solver's tolerance bounds.
    pub fn max(&self) -> f64 {
        self.dual_feasibility.max(self.complementarity)
    }
}

/// The residual of the impulse `lambda` (each block in its cone, as the solvers return it) with
/// contact velocities `sigma = G λ + g`.
pub fn residual(lambda: &DVector<f64>, sigma: &DVector<f64>, friction: &[f64]) -> ConeResidual {
    let mut s = sigma.clone();
    add_de_saxce(&mut s, friction);
    let (mut dual, mut comp) = (0.0f64, 0.0f64);
    for (i, &mu) in friction.iter().enumerate() {
        let si = block(&s, i);
        dual = dual.max((si - project_dual_cone(&si, mu)).norm());
        let li = block(lambda, i);
        let nl = li.norm();
        if nl > 0.0 {
            comp = comp.max(li.dot(&si).abs() / nl);
        }
    }
    ConeResidual { dual_feasibility: dual, complementarity: comp }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projections_are_idempotent_land_in_their_cones_and_split_orthogonally() {
        let mut seed = 7u64;
        let mut next = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) * 4.0 - 2.0
        };
        for _ in 0..200 {
            let v = Vector3::new(next(), next(), next());
            let mu = 0.5 * (next() + 2.0);
            let p = project_cone(&v, mu);
            assert!(p.xy().norm() <= mu * p.z + 1e-12, "{v:?} -> {p:?}");
            assert!((project_cone(&p, mu) - p).norm() < 1e-12);
            // Moreau: v = P_K(v) + P_{K°}(v), the two orthogonal, and P_{K°}(v) = −P_{K*}(−v).
            let polar = -project_dual_cone(&-v, mu);
            assert!((p + polar - v).norm() < 1e-12, "{v:?} {p:?} {polar:?}");
            assert!(p.dot(&polar).abs() < 1e-12);
        }
        assert_eq!(project_cone(&Vector3::new(1.0, 0.0, -1.0), 0.0), Vector3::zeros());
        assert_eq!(project_cone(&Vector3::new(1.0, 2.0, 3.0), 0.0), Vector3::new(0.0, 0.0, 3.0));
    }

    #[test]
    fn the_residual_vanishes_on_the_three_regimes_of_coulombs_law() {
        let mu = [0.5];
        // Sticking: σ = 0, λ inside.
        let r = residual(&DVector::from_vec(vec![0.1, 0.0, 1.0]), &DVector::zeros(3), &mu);
        assert_eq!(r.max(), 0.0);
        // Sliding: σ_n = 0, λ_t = −μ λ_n σ_t/‖σ_t‖.
        let r = residual(&DVector::from_vec(vec![-0.3, -0.4, 1.0]), &DVector::from_vec(vec![0.6, 0.8, 0.0]), &mu);
        assert!(r.max() < 1e-15, "{r:?}");
        // Apart: λ = 0, σ_n > 0.
        assert_eq!(residual(&DVector::zeros(3), &DVector::from_vec(vec![3.0, 0.0, 1.0]), &mu).max(), 0.0);
        // Penetrating with no impulse, or sliding with friction that does not oppose it: not solutions.
        assert!(residual(&DVector::zeros(3), &DVector::from_vec(vec![0.0, 0.0, -1.0]), &mu).dual_feasibility > 0.99);
        assert!(residual(&DVector::from_vec(vec![0.3, 0.4, 1.0]), &DVector::from_vec(vec![0.6, 0.8, 0.0]), &mu).complementarity > 0.1);
    }
}
