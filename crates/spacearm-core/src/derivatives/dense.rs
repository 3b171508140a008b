//! The inverse of the mass matrix for the forward-dynamics Jacobians (`∂u̇/∂f = H⁻¹`, and the
//! factor of `∂u̇/∂x = −H⁻¹ ∂ID/∂x`): Cholesky `H = L Lᵀ`, `L⁻¹` by forward substitution, then
//! `H⁻¹ = L⁻ᵀ L⁻¹` — about `n³/2` multiply-adds, a third of solving `H X = E` column by column,
//! with every inner loop running down a contiguous column (the matrices are column-major).

use nalgebra::DMatrix;

/// `a · b` with four accumulators (a reduction the compiler does not vectorize by itself).
#[inline(always)]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let tail: f64 = ca.remainder().iter().zip(cb.remainder()).map(|(x, y)| x * y).sum();
    let mut acc = [0.0; 4];
    for (x, y) in ca.zip(cb) {
        for l in 0..4 {
            acc[l] += x[l] * y[l];
        }
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// `y -= alpha x`.
#[inline(always)]
fn axpy_neg(alpha: f64, x: &[f64], y: &mut [f64]) {
    for (yi, xi) in y.iter_mut().zip(x) {
        *yi -= alpha * xi;
    }
}

/// `out = H⁻¹` for a symmetric positive-definite `h` (its lower triangle is read), with
/// `scratch` (same size) for `L⁻¹`. Returns `false` if `h` is not positive definite (`out` is
/// then unspecified).
///
/// On x86-64 CPUs with AVX2 the same code runs compiled for AVX2 (4-wide vectors instead of
/// SSE2's 2): the operations and their order are the same, so are the results, bit for bit
/// (Rust fuses no multiply-add by itself).
pub(crate) fn spd_inverse(h: &DMatrix<f64>, scratch: &mut DMatrix<f64>, out: &mut DMatrix<f64>) -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2 (checked just above).
            return unsafe { spd_inverse_avx2(h, scratch, out) };
        }
    }
    spd_inverse_portable(h, scratch, out)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn spd_inverse_avx2(h: &DMatrix<f64>, scratch: &mut DMatrix<f64>, out: &mut DMatrix<f64>) -> bool {
    spd_inverse_portable(h, scratch, out)
}

#[inline(always)]
fn spd_inverse_portable(h: &DMatrix<f64>, scratch: &mut DMatrix<f64>, out: &mut DMatrix<f64>) -> bool {
    let n = h.nrows();
    // Cholesky, left-looking, into `out` (lower triangle): column j of L is
    // (h[j.., j] − Σ_{k<j} L[j, k] L[j.., k]) / L[j, j]. The diagonal is stored as 1 / L[j, j]
    // (the factorization never reads it; the substitution below multiplies by it instead of
    // dividing, a division being the latency that bounds that loop).
    out.copy_from(h);
    let l = out.as_mut_slice();
    for j in 0..n {
        for k in 0..j {
            let ljk = l[k * n + j];
            if ljk != 0.0 {
                let (left, right) = l.split_at_mut(j * n);
                axpy_neg(ljk, &left[k * n + j..k * n + n], &mut right[j..n]);
            }
        }
        let d = l[j * n + j];
        // Not positive (or NaN / infinite): not positive definite.
        if d.is_nan() || d <= 0.0 || d.is_infinite() {
            return false;
        }
        let ljj = d.sqrt();
        let inv = 1.0 / ljj;
        l[j * n + j] = inv;
        for v in &mut l[j * n + j + 1..j * n + n] {
            *v *= inv;
        }
    }
    // M = L⁻¹ (lower), column j by forward substitution of L m = e_j (diagonal: 1 / L[k, k]).
    let m = scratch.as_mut_slice();
    m.fill(0.0);
    for j in 0..n {
        let col = &mut m[j * n..j * n + n];
        col[j] = 1.0;
        for k in j..n {
            let xk = col[k] * l[k * n + k];
            col[k] = xk;
            if xk != 0.0 {
                axpy_neg(xk, &l[k * n + k + 1..k * n + n], &mut col[k + 1..n]);
            }
        }
    }
    // H⁻¹ = Mᵀ M: entry (i, j), i ≥ j, is the dot of columns i and j of M from row i down.
    let o = out.as_mut_slice();
    for j in 0..n {
        for i in j..n {
            let v = dot(&m[i * n + i..i * n + n], &m[j * n + i..j * n + n]);
            o[j * n + i] = v;
            o[i * n + j] = v;
        }
    }
    true
}

/// `out = −a b` for the products `∂u̇/∂(x, u) = −H⁻¹ ∂ID/∂(x, u)`. Small sizes column by column
/// (`out[:, c] = −Σ_k a[:, k] b[k, c]`, contiguous axpys, AVX2 where the CPU has it); from
/// [`BLOCKED_FROM`] rows on, nalgebra's blocked product (`matrixmultiply`), whose packing costs
/// more than it saves on small matrices.
pub(crate) fn neg_product(a: &DMatrix<f64>, b: nalgebra::DMatrixView<f64>, mut out: nalgebra::DMatrixViewMut<f64>) {
    if a.nrows() >= BLOCKED_FROM {
        out.gemm(-1.0, a, &b, 0.0);
        return;
    }
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2 (checked just above).
            unsafe { neg_product_avx2(a, b, out) };
            return;
        }
    }
    neg_product_columns(a, b, out)
}

/// Rows of `H` from which [`neg_product`] hands over to the blocked product.
const BLOCKED_FROM: usize = 24;

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn neg_product_avx2(a: &DMatrix<f64>, b: nalgebra::DMatrixView<f64>, out: nalgebra::DMatrixViewMut<f64>) {
    neg_product_columns(a, b, out)
}

#[inline(always)]
fn neg_product_columns(a: &DMatrix<f64>, b: nalgebra::DMatrixView<f64>, mut out: nalgebra::DMatrixViewMut<f64>) {
    let n = a.nrows();
    let a = a.as_slice();
    for c in 0..b.ncols() {
        let mut col = out.column_mut(c);
        let col = col.as_mut_slice();
        col.fill(0.0);
        for k in 0..b.nrows() {
            let bk = b[(k, c)];
            if bk != 0.0 {
                axpy_neg(bk, &a[k * n..k * n + n], col);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_of_a_random_spd_matrix() {
        for n in [1, 2, 5, 12, 31] {
            let a = DMatrix::from_fn(n, n, |i, j| ((i * 7 + j * 3) as f64 * 0.37).sin());
            let h = &a * a.transpose() + DMatrix::identity(n, n) * 0.5;
            let (mut s, mut inv) = (DMatrix::zeros(n, n), DMatrix::zeros(n, n));
            assert!(spd_inverse(&h, &mut s, &mut inv));
            let err = (&h * &inv - DMatrix::identity(n, n)).amax();
            assert!(err < 1e-12, "n = {n}: {err:e}");
            assert_eq!(inv, inv.transpose());
        }
    }

    #[test]
    fn negated_product_both_ways() {
        for n in [3, 12, 23, 24, 40] {
            let a = DMatrix::from_fn(n, n, |i, j| ((i * 5 + j * 11) as f64 * 0.13).cos());
            let b = DMatrix::from_fn(n, 2 * n + 3, |i, j| ((i * 3 + j * 7) as f64 * 0.29).sin());
            let mut out = DMatrix::zeros(n, 2 * n + 7);
            neg_product(&a, b.columns(1, 2 * n), out.columns_mut(4, 2 * n));
            let reference = -(&a * b.columns(1, 2 * n));
            assert!((out.columns(4, 2 * n) - reference).amax() < 1e-12);
            assert_eq!(out.columns(0, 4).amax(), 0.0);
        }
    }

    #[test]
    fn not_positive_definite_is_reported() {
        let h = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 1.0]);
        let (mut s, mut inv) = (DMatrix::zeros(2, 2), DMatrix::zeros(2, 2));
        assert!(!spd_inverse(&h, &mut s, &mut inv));
    }
}
