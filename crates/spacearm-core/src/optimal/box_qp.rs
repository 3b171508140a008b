//! The box-constrained QP of one knot of box-DDP (Tassa, Mansard & Todorov 2014, Algorithm 1):
//! `min ½ δcᵀ Q δc + gᵀ δc` subject to `lower ≤ δc ≤ upper`, `Q` positive definite, by the
//! projected Newton method — at each iterate the clamped set (variables at a bound whose
//! gradient pushes outward), a Newton step on the free variables, and a projected
//! backtracking (Armijo) line search — warm started from a guess.
//!
//! The result keeps the Cholesky factor of the free block `Q_ff`, which gives the feedback
//! gains of the free controls, `K_f = −Q_ff⁻¹ Q_cz,f`; the clamped ones get no feedback.

use nalgebra::{Cholesky, DMatrix, DVector, Dyn};

/// The solution of a box QP.
pub struct BoxQpSolution {
    /// The minimizer.
    pub x: DVector<f64>,
    /// Which variables are free (not clamped) at the solution.
    pub free: Vec<bool>,
    /// The Cholesky factor of the free block of `Q`; `None` when every variable is clamped.
    pub free_factor: Option<Cholesky<f64, Dyn>>,
}

fn clamp(x: &mut DVector<f64>, lower: &[f64], upper: &[f64]) {
    for i in 0..x.len() {
        x[i] = x[i].max(lower[i]).min(upper[i]);
    }
}

fn value(q: &DMatrix<f64>, g: &DVector<f64>, x: &DVector<f64>) -> f64 {
    0.5 * x.dot(&(q * x)) + g.dot(x)
}

/// The free block `Q_ff` of `q` for the mask `free`.
fn free_block(q: &DMatrix<f64>, free: &[bool]) -> DMatrix<f64> {
    let idx: Vec<usize> = (0..free.len()).filter(|i| free[*i]).collect();
    DMatrix::from_fn(idx.len(), idx.len(), |a, b| q[(idx[a], idx[b])])
}

/// Solve the box QP (module docs) from `guess`; `None` when a free block is not positive
/// definite (the caller raises the regularization).
pub fn solve_box_qp(q: &DMatrix<f64>, g: &DVector<f64>, lower: &[f64], upper: &[f64], guess: &DVector<f64>) -> Option<BoxQpSolution> {
    let m = g.len();
    let mut x = guess.clone();
    clamp(&mut x, lower, upper);
    let mut free = vec![true; m];
    let mut factor = None;
    let mut fx = value(q, g, &x);
    for _ in 0..100 {
        let grad = q * &x + g;
        let mut changed = factor.is_none();
        for i in 0..m {
            let clamped = (x[i] <= lower[i] && grad[i] > 0.0) || (x[i] >= upper[i] && grad[i] < 0.0);
            if free[i] == clamped {
                changed = true;
            }
            free[i] = !clamped;
        }
        if free.iter().all(|f| !f) {
            return Some(BoxQpSolution { x, free, free_factor: None });
        }
        if changed {
            factor = Some(Cholesky::new(free_block(q, &free))?);
        }
        let chol = factor.as_ref().expect("factored above");
        let idx: Vec<usize> = (0..m).filter(|i| free[*i]).collect();
        let gf = DVector::from_iterator(idx.len(), idx.iter().map(|i| grad[*i]));
        if gf.norm() < 1e-13 * (1.0 + g.norm()) {
            break;
        }
        let stepf = -chol.solve(&gf);
        let mut step = DVector::zeros(m);
        for (a, i) in idx.iter().enumerate() {
            step[*i] = stepf[a];
        }
        // Projected Armijo backtracking.
        let mut alpha = 1.0;
        let mut accepted = false;
        while alpha > 1e-10 {
            let mut trial = &x + &step * alpha;
            clamp(&mut trial, lower, upper);
            let ft = value(q, g, &trial);
            if fx - ft >= 0.1 * grad.dot(&(&x - &trial)) {
                let improvement = fx - ft;
                x = trial;
                fx = ft;
                accepted = true;
                if improvement <= 1e-15 * (1.0 + fx.abs()) {
                    alpha = 0.0;
                }
                break;
            }
            alpha *= 0.5;
        }
        if !accepted || alpha == 0.0 {
            break;
        }
    }
    // The free set and factor at the final point.
    let grad = q * &x + g;
    let mut final_free = vec![true; m];
    for i in 0..m {
        final_free[i] = !((x[i] <= lower[i] && grad[i] > 0.0) || (x[i] >= upper[i] && grad[i] < 0.0));
    }
    if final_free != free || factor.is_none() {
        free = final_free;
        factor = if free.iter().any(|f| *f) { Some(Cholesky::new(free_block(q, &free))?) } else { None };
    }
    Some(BoxQpSolution { x, free, free_factor: factor })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The KKT conditions at the solution: a free variable has zero gradient, a clamped one a
    /// gradient pointing out of the box; the unconstrained case is `−Q⁻¹ g`.
    #[test]
    fn solutions_satisfy_the_kkt_conditions() {
        let q = DMatrix::from_row_slice(3, 3, &[4.0, 1.0, 0.5, 1.0, 3.0, -0.2, 0.5, -0.2, 2.0]);
        let g = DVector::from_row_slice(&[-8.0, 3.0, 1.0]);
        let inf = f64::INFINITY;
        let s = solve_box_qp(&q, &g, &[-inf; 3], &[inf; 3], &DVector::zeros(3)).unwrap();
        let exact = -q.clone().cholesky().unwrap().solve(&g);
        assert!((s.x - exact).norm() < 1e-12);
        let (lo, hi) = ([-0.5, -0.5, -0.5], [0.5, 0.5, 0.5]);
        let s = solve_box_qp(&q, &g, &lo, &hi, &DVector::zeros(3)).unwrap();
        let grad = &q * &s.x + &g;
        let mut clamped = 0;
        for i in 0..3 {
            assert!(s.x[i] >= lo[i] && s.x[i] <= hi[i]);
            if s.free[i] {
                assert!(grad[i].abs() < 1e-10, "free {i}: gradient {}", grad[i]);
            } else {
                clamped += 1;
                assert!((s.x[i] == lo[i] && grad[i] > 0.0) || (s.x[i] == hi[i] && grad[i] < 0.0));
            }
        }
        assert!(clamped >= 1, "the bounds bind in this case");
    }
}
