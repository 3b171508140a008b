//! Damped least squares: the one damping law and the one damped inverse, used by the controllers
//! that run in the simulation loop (control/rmrc.rs, control/coordinated.rs) and by the analyses
//! (analysis/singularity.rs, analysis/rmrc_solver.rs).
//!
//! The damped least-squares inverse of an m×n Jacobian `J = Σ σᵢ uᵢ vᵢᵀ` (Nakamura & Hanafusa
//! 1986; Wampler 1986) is `J⁺_λ = Σ σᵢ / (σᵢ² + λᵢ²) vᵢ uᵢᵀ`. The damping is applied per
//! singular direction (Maciejewski & Klein 1988; Chiaverini 1997): each direction gets the
//! damping of its own singular value, `λᵢ = λ(σᵢ)` of [`DampingLaw`], so a direction that is far
//! from singular (`σᵢ ≥ ε`) is inverted exactly and only the weak directions are damped — a single
//! `λ(σ_min)` for every direction would also distort the well-conditioned ones.
//!
//! Two factorisations realise the same inverse: [`damped_inverse`] from an SVD of `J` (analysis,
//! where the inverse is needed as a matrix), and [`RowSvd`], a one-sided Jacobi SVD of a Jacobian
//! of at most six rows in a workspace allocated once: no allocation per evaluation, for the
//! controllers in the simulation loop (the resolved-motion-rate solver of
//! `analysis/rmrc_solver.rs`, which the analyses run too, and the acceleration-level task of
//! control/coordinated.rs), with the accuracy of an SVD, which the projectors onto null spaces
//! need. A test holds the two together.

use nalgebra::{DMatrix, DVector, Matrix6};

use crate::error::{Result, SpacearmError};

/// The damping law near singularities (Nakamura & Hanafusa 1986):
/// `λ²(σ) = λ_max² (1 − (σ/ε)²)` inside the singular region `σ < ε`, `λ = 0` outside. The damping
/// rises smoothly from 0 at `σ = ε` to `λ_max` at `σ = 0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DampingLaw {
    /// Size `ε > 0` of the singular region, in the units of `σ` (m/rad for position rows).
    pub threshold: f64,
    /// Damping `λ_max ≥ 0` at the singularity itself, in the units of `σ`.
    pub max_damping: f64,
}

impl Default for DampingLaw {
    /// The library's default law, `ε = λ_max = 0.05` (m for position rows): every controller and
    /// analysis that damps takes it unless told otherwise (Python reads it as `_core.DLS_DEFAULTS`).
    fn default() -> Self {
        DampingLaw { threshold: 0.05, max_damping: 0.05 }
    }
}

impl DampingLaw {
    /// A law, checked: `threshold` finite and > 0, `max_damping` finite and ≥ 0.
    pub fn new(threshold: f64, max_damping: f64) -> Result<Self> {
        if !(threshold.is_finite() && threshold > 0.0) {
            return Err(SpacearmError::InvalidArgument(format!("the damping threshold ε must be finite and > 0, got {threshold}")));
        }
        if !(max_damping.is_finite() && max_damping >= 0.0) {
            return Err(SpacearmError::InvalidArgument(format!("the maximum damping λ_max must be finite and >= 0, got {max_damping}")));
        }
        Ok(DampingLaw { threshold, max_damping })
    }

    /// No damping at all (the Moore–Penrose inverse).
    pub fn none() -> Self {
        DampingLaw { threshold: 1.0, max_damping: 0.0 }
    }

    /// `λ²(σ)`.
    pub fn damping_sq(&self, sigma: f64) -> f64 {
        if sigma >= self.threshold {
            return 0.0;
        }
        let r = (sigma.max(0.0) / self.threshold).min(1.0);
        self.max_damping * self.max_damping * (1.0 - r * r)
    }

    /// `λ(σ)`.
    pub fn damping(&self, sigma: f64) -> f64 {
        self.damping_sq(sigma).sqrt()
    }

    /// The weight `σ / (σ² + λ²(σ))` of one singular direction in the damped inverse. A direction
    /// with `σ ≤ cut` (numerically outside the range of `J`) gets 0: there the undamped weight
    /// `1/σ` would amplify rounding, and the damped one is ≈ `σ/λ²`, below rounding too.
    pub fn weight(&self, sigma: f64, cut: f64) -> f64 {
        if !(sigma > cut) {
            return 0.0;
        }
        sigma / (sigma * sigma + self.damping_sq(sigma))
    }
}

/// Relative size below which a singular value counts as zero in [`damped_inverse`]:
/// `cut = RANK_TOLERANCE · σ_max`.
pub const RANK_TOLERANCE: f64 = 1e-12;

/// The damped inverse `J⁺_λ = Σ wᵢ vᵢ uᵢᵀ` (n×m) of an m×n matrix from its SVD: `u` (m×k) and
/// `v` (n×k, or more columns: those past `k` are not used) with orthonormal columns and the `k` singular values `sigma`, weights
/// [`DampingLaw::weight`] with `cut = RANK_TOLERANCE · σ_max`. With [`DampingLaw::none`] it is
/// the Moore–Penrose inverse.
pub fn damped_inverse(u: &DMatrix<f64>, sigma: &DVector<f64>, v: &DMatrix<f64>, law: &DampingLaw) -> DMatrix<f64> {
    let cut = RANK_TOLERANCE * sigma.iter().fold(0.0_f64, |a, &s| a.max(s));
    let mut out = DMatrix::zeros(v.nrows(), u.nrows());
    for (i, &s) in sigma.iter().enumerate() {
        let w = law.weight(s, cut);
        if w != 0.0 {
            out += w * v.column(i) * u.column(i).transpose();
        }
    }
    out
}

/// Most rows a [`RowSvd`] factors (a point twist has six).
pub const MAX_ROWS: usize = 6;

/// One-sided Jacobi SVD (Hestenes 1958; Demmel & Veselić 1992) of an m×k matrix `A` with
/// `m ≤ 6` rows, in a workspace allocated once for up to `max_cols` columns: nothing is
/// allocated per factorisation.
///
/// The columns of `B = Aᵀ` (k×m) are rotated pairwise, `B ← B V` with `V` orthogonal (m×m),
/// until they are mutually orthogonal to rounding. Then `A = Σⱼ vⱼ bⱼᵀ` with `σⱼ = |bⱼ|`:
/// `vⱼ` are the left singular vectors and `bⱼ = Aᵀ vⱼ = σⱼ qⱼ` the right ones scaled by the
/// singular values. The damped inverse of [`damped_inverse`] applied to `b` is then
/// `J⁺_λ b = Σⱼ (vⱼ·b) / (σⱼ² + λ²(σⱼ)) bⱼ` (directions with `σⱼ ≤ RANK_TOLERANCE · σ_max` dropped),
/// and the projector onto the row space is `Σ qⱼ qⱼᵀ` over the directions above a rank cut. The
/// `qⱼ` are orthonormal to rounding whatever their `σⱼ` (the stopping rule). (An eigen-decomposition
/// of the Gram matrix `J Jᵀ`, used before, gives small singular values that carry the rounding
/// of `σ_max²`: at `σ ≈ 1e-8 σ_max` they were off by 1 %.)
#[derive(Debug, Clone)]
pub struct RowSvd {
    m: usize,
    k: usize,
    /// `B V`, k×MAX_ROWS (the first `m` columns used).
    b: DMatrix<f64>,
    v: Matrix6<f64>,
    sigma: [f64; MAX_ROWS],
}

impl RowSvd {
    /// A workspace for matrices of up to six rows and `max_cols` columns.
    pub fn new(max_cols: usize) -> Self {
        RowSvd { m: 0, k: 0, b: DMatrix::zeros(max_cols, MAX_ROWS), v: Matrix6::identity(), sigma: [0.0; MAX_ROWS] }
    }

    /// Factor the m×k matrix `a` (m ≤ 6, k ≤ `max_cols`; checked by the caller's shapes: a
    /// larger matrix is a programming error and panics).
    pub fn factor(&mut self, a: &DMatrix<f64>) {
        let (m, k) = a.shape();
        assert!(m <= MAX_ROWS && k <= self.b.nrows(), "RowSvd: {m}×{k} matrix for a {MAX_ROWS}×{} workspace", self.b.nrows());
        self.m = m;
        self.k = k;
        for r in 0..m {
            for c in 0..k {
                self.b[(c, r)] = a[(r, c)];
            }
        }
        self.v = Matrix6::identity();
        for _sweep in 0..60 {
            let mut rotated = false;
            for p in 0..m {
                for q in p + 1..m {
                    let (mut alpha, mut beta, mut gamma) = (0.0, 0.0, 0.0);
                    for i in 0..k {
                        let (x, y) = (self.b[(i, p)], self.b[(i, q)]);
                        alpha += x * x;
                        beta += y * y;
                        gamma += x * y;
                    }
                    if gamma == 0.0 || gamma.abs() <= f64::EPSILON * (alpha * beta).sqrt() {
                        continue;
                    }
                    rotated = true;
                    let zeta = (beta - alpha) / (2.0 * gamma);
                    let t = zeta.signum() / (zeta.abs() + (1.0 + zeta * zeta).sqrt());
                    let c = 1.0 / (1.0 + t * t).sqrt();
                    let s = c * t;
                    for i in 0..k {
                        let (x, y) = (self.b[(i, p)], self.b[(i, q)]);
                        self.b[(i, p)] = c * x - s * y;
                        self.b[(i, q)] = s * x + c * y;
                    }
                    for i in 0..m {
                        let (x, y) = (self.v[(i, p)], self.v[(i, q)]);
                        self.v[(i, p)] = c * x - s * y;
                        self.v[(i, q)] = s * x + c * y;
                    }
                }
            }
            if !rotated {
                break;
            }
        }
        for j in 0..m {
            self.sigma[j] = (0..k).map(|i| self.b[(i, j)] * self.b[(i, j)]).sum::<f64>().sqrt();
        }
    }

    /// The `m` column norms `σⱼ` (unsorted; when `m > k`, `m − k` of them are zero to rounding).
    pub fn sigmas(&self) -> &[f64] {
        &self.sigma[..self.m]
    }

    /// Largest singular value.
    pub fn sigma_max(&self) -> f64 {
        self.sigmas().iter().fold(0.0_f64, |a, &s| a.max(s))
    }

    /// The smallest of the `min(m, k)` largest singular values (the matrix's `σ_min`).
    pub fn sigma_min(&self) -> f64 {
        let mut s = self.sigma;
        let s = &mut s[..self.m];
        s.sort_unstable_by(|a, b| b.partial_cmp(a).unwrap_or(std::cmp::Ordering::Equal));
        let r = self.m.min(self.k);
        if r == 0 { 0.0 } else { s[r - 1] }
    }

    /// The product of the `min(m, k)` largest singular values (manipulability).
    pub fn product(&self) -> f64 {
        let mut s = self.sigma;
        let s = &mut s[..self.m];
        s.sort_unstable_by(|a, b| b.partial_cmp(a).unwrap_or(std::cmp::Ordering::Equal));
        s[..self.m.min(self.k)].iter().product()
    }

    /// `out = J⁺_λ b` (k entries) for `b` of `m` entries, each direction damped by `law`.
    pub fn solve(&self, b: &[f64], law: &DampingLaw, out: &mut DVector<f64>) {
        let cut = RANK_TOLERANCE * self.sigma_max();
        out.fill(0.0);
        for j in 0..self.m {
            let sigma = self.sigma[j];
            // weight/σ = 1/(σ² + λ²): bⱼ carries the factor σⱼ of qⱼ.
            let w = law.weight(sigma, cut);
            if w == 0.0 {
                continue;
            }
            let vb: f64 = (0..self.m).map(|i| self.v[(i, j)] * b[i]).sum();
            let f = vb * w / sigma;
            for i in 0..self.k {
                out[i] += f * self.b[(i, j)];
            }
        }
    }

    /// Number of singular values above `relative_tolerance · σ_max` (and above 0).
    pub fn rank(&self, relative_tolerance: f64) -> usize {
        let cut = relative_tolerance * self.sigma_max();
        self.sigmas().iter().filter(|&&s| s > cut && s > 0.0).count()
    }

    /// `target −= Σ qⱼ qⱼᵀ` (k×k) over the directions with `σⱼ > relative_tolerance · σ_max`:
    /// removes the projector onto the row space of `A` (`A⁺A`, undamped).
    pub fn subtract_row_space(&self, relative_tolerance: f64, target: &mut DMatrix<f64>) {
        let cut = relative_tolerance * self.sigma_max();
        for j in 0..self.m {
            let sigma = self.sigma[j];
            if !(sigma > cut && sigma > 0.0) {
                continue;
            }
            let inv = 1.0 / (sigma * sigma);
            for c in 0..self.k {
                let f = self.b[(c, j)] * inv;
                for r in 0..self.k {
                    target[(r, c)] -= self.b[(r, j)] * f;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn law_shape() {
        let law = DampingLaw::new(0.1, 0.05).unwrap();
        assert_eq!(law.damping(0.2), 0.0);
        assert_eq!(law.damping(0.1), 0.0);
        assert!((law.damping(0.0) - 0.05).abs() < 1e-15);
        let l = law.damping(0.05);
        assert!((l * l - 0.05f64.powi(2) * (1.0 - 0.25)).abs() < 1e-15);
        assert!(DampingLaw::new(0.0, 1.0).is_err());
        assert!(DampingLaw::new(1.0, -1.0).is_err());
        assert!(DampingLaw::new(f64::NAN, 1.0).is_err());
    }

    fn svd(j: &DMatrix<f64>) -> (DMatrix<f64>, DVector<f64>, DMatrix<f64>) {
        let s = j.clone().svd(true, true);
        (s.u.unwrap(), s.singular_values, s.v_t.unwrap().transpose())
    }

    #[test]
    fn undamped_inverse_is_the_moore_penrose_inverse() {
        let j = DMatrix::from_row_slice(3, 5, &[0.3, -1.0, 0.2, 0.7, 0.1, 1.1, 0.4, -0.6, 0.0, 0.9, -0.2, 0.5, 0.8, 0.3, -0.4]);
        let (u, s, v) = svd(&j);
        let p = damped_inverse(&u, &s, &v, &DampingLaw::none());
        // The Penrose conditions, and Jᵀ(JJᵀ)⁻¹ for a full-row-rank J.
        assert!((&j * &p * &j - &j).norm() < 1e-13);
        assert!((&p * &j * &p - &p).norm() < 1e-13);
        let normal = j.transpose() * (&j * j.transpose()).try_inverse().unwrap();
        assert!((p - normal).norm() < 1e-12);
    }

    #[test]
    fn per_direction_damping_leaves_strong_directions_exact() {
        // σ = 2, 1, 0.01: with ε = 0.1 only the weakest direction is damped.
        let j = DMatrix::from_row_slice(3, 3, &[2.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.01]);
        let law = DampingLaw::new(0.1, 0.05).unwrap();
        let (u, s, v) = svd(&j);
        let p = damped_inverse(&u, &s, &v, &law);
        assert!((p[(0, 0)] - 0.5).abs() < 1e-15 && (p[(1, 1)] - 1.0).abs() < 1e-15);
        let lam_sq = law.damping_sq(0.01);
        assert!((p[(2, 2)] - 0.01 / (1e-4 + lam_sq)).abs() < 1e-12);
    }

    #[test]
    fn damped_inverse_is_the_normal_equations_with_per_direction_damping() {
        // Aᵀ(AAᵀ + Λ)⁻¹ with Λ = U diag(λ²(σᵢ)) Uᵀ from nalgebra's own SVD, for both forms.
        let a = DMatrix::from_row_slice(2, 3, &[1.0, 2.0, 0.0, 0.0, 1.0, 1.0]);
        let law = DampingLaw::new(10.0, 0.3).unwrap();
        let svd = a.clone().svd(true, false);
        let u = svd.u.clone().unwrap();
        let lambda_sq = DMatrix::from_diagonal(&svd.singular_values.map(|s| law.damping_sq(s)));
        let direct = a.transpose() * (&a * a.transpose() + &u * lambda_sq * u.transpose()).try_inverse().unwrap();
        let (u, s, v) = self::svd(&a);
        assert!((damped_inverse(&u, &s, &v, &law) - &direct).norm() < 1e-12);
        let mut ws = RowSvd::new(3);
        ws.factor(&a);
        for (c, b) in [[1.0, 0.0], [0.0, 1.0]].iter().enumerate() {
            let mut col = DVector::zeros(3);
            ws.solve(b, &law, &mut col);
            assert!((col - direct.column(c)).norm() < 1e-12);
        }
    }

    #[test]
    fn jacobi_svd_equals_the_svd_form() {
        let law = DampingLaw::new(0.5, 0.1).unwrap();
        let mut ws = RowSvd::new(7);
        for j in [
            DMatrix::from_row_slice(3, 4, &[0.3, -1.0, 0.2, 0.7, 1.1, 0.4, -0.6, 0.0, -0.2, 0.5, 0.8, 0.3]),
            DMatrix::from_row_slice(3, 4, &[0.3, -1.0, 0.2, 0.7, 1.1, 0.4, -0.6, 0.0, 0.0, 0.0, 0.0, 0.0]),
            DMatrix::from_row_slice(3, 4, &[0.3, -1.0, 0.2, 0.7, 1.1, 0.4, -0.6, 0.0, 0.3, -1.0, 0.2, 0.71]),
            // More rows than columns (a whole twist over two joints).
            DMatrix::from_row_slice(6, 2, &[0.3, -1.0, 0.2, 0.7, 1.1, 0.4, -0.6, 0.0, 0.3, -1.0, 0.2, 0.71]),
        ] {
            let (m, k) = j.shape();
            let b: Vec<f64> = (0..m).map(|i| 0.4 - 0.3 * i as f64).collect();
            let (u, s, v) = svd(&j);
            ws.factor(&j);
            for l in [law, DampingLaw::none()] {
                let expected = damped_inverse(&u, &s, &v, &l) * DVector::from_column_slice(&b);
                let mut got = DVector::zeros(k);
                ws.solve(&b, &l, &mut got);
                assert!((&got - &expected).norm() < 1e-12 * expected.norm().max(1.0), "Jacobi and SVD forms differ: {} {m}x{k} {:?}", (got - &expected).norm(), l);
            }
            let mut sorted = s.as_slice().to_vec();
            sorted.sort_by(|a, b| b.partial_cmp(a).unwrap());
            assert!((ws.sigma_min() - sorted[m.min(k) - 1]).abs() < 1e-12);
            assert!((ws.product() - sorted.iter().take(m.min(k)).product::<f64>()).abs() < 1e-12);
            // E − A⁺A is the projector onto the null space.
            let mut p = DMatrix::identity(k, k);
            ws.subtract_row_space(1e-12, &mut p);
            let pinv = damped_inverse(&u, &s, &v, &DampingLaw::none());
            assert!((&p - (DMatrix::identity(k, k) - &pinv * &j)).norm() < 1e-12);
            assert!((&j * &p).norm() < 1e-12 && (&p * &p - &p).norm() < 1e-12);
        }
    }
}
