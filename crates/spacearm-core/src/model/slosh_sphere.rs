//! The lateral slosh modes of a spherical tank, computed by a Ritz–Trefftz method, and their
//! equivalent mechanical model (docs/flexibility.md, "From a tank to the slosh parameters").
//!
//! No closed form exists for a sphere. The liquid fills a spherical cap of depth `h` in a sphere
//! of radius `R`; its free surface `S` is the disk at the height `h` above the bottom, its wetted
//! wall `W` the rest of the cap's boundary. The linear sloshing problem in the axial acceleration
//! `a` is
//!
//! `∇²φ = 0` in the liquid, `∂φ/∂n = 0` on `W`, `∂φ/∂z = λ φ` on `S`, `ω² = a λ`.
//!
//! Its eigenvalues are the stationary values of the Rayleigh quotient
//! `λ = ∫|∇φ|² dV / ∫_S φ² dA` over all `φ` (the wall condition is natural), so a Ritz method on
//! a subspace gives upper bounds that decrease to the true values as the subspace grows. The
//! lateral (`m = 1`) modes are sought in the span of the solid harmonics
//! `φ_l = ρ^l P_l¹(cos ϑ) cos ϕ = x g_l(z, r²)`, `l = 1 … N`, which satisfy Laplace's equation
//! exactly (a Trefftz basis), in coordinates centred on the liquid's bounding box and scaled by
//! its size. The `g_l` follow from the recurrence of the associated Legendre functions,
//! `l g_{l+1} = (2l+1) z g_l − (l+1)(r² + z²) g_{l−1}`, `g_0 = 0`, `g_1 = 1`. Green's identity
//! turns every volume integral into one over the meridian boundary (the `ϕ` integrals of
//! `cos² ϕ` give `π`):
//!
//! - `K_ij = ∫ ∇φ_i·∇φ_j dV = π ∫_{W∪S} f_i ∂_n f_j r ds`, `M_ij = π ∫_S f_i f_j r dr`
//!   (`f_l = r g_l`, the meridian part of `φ_l`);
//! - the momentum amplitude `P = ∫ ∂_x φ dV = π ∫ f n_r r ds`;
//! - the angular momentum about the lateral axis through the liquid's centre of mass,
//!   `H_y = ∫ ((z − z_cm) ∂_x φ − x ∂_z φ) dV = π ∫ f ((z − z_cm) n_r − r n_z) r ds`.
//!
//! Gauss–Legendre quadrature integrates these polynomial (disk) and trigonometric-polynomial
//! (wall, in `ϑ`) integrands to rounding. `M` is singular (on the disk the `N` harmonics span
//! only about `N/2` functions), so the problem is solved as `M a = (1/λ) K a`: `K` (positive
//! definite) is diagonally scaled and orthonormalized by its eigen-decomposition (directions of
//! relative size below `1e-13` are dropped: near-dependent harmonics), and the largest
//! eigenvalues `1/λ` of the reduced `M` give the lowest modes.
//!
//! For mode `n` with its eigenvector normalized so that `∫|∇φ|² = 1`, matching the momentum
//! (`m ω X = ρP`) and the kinetic energy (`½ m ω² X² = ½ρ`) of a point mass `m` oscillating
//! laterally with amplitude `X`, and then its angular momentum, gives the equivalent mechanical
//! model's
//!
//! `mₙ = ρ P² / ∫|∇φ|²`, `ℓₙ = H_y / P` (height above the liquid's centre of mass),
//!
//! `ωₙ² = a λₙ`, `kₙ = mₙ ωₙ²`, `Lₙ = a/ωₙ²`, `m₀ = m_L − Σ mₙ` at `ℓ₀ = −Σ mₙ ℓₙ / m₀`, as for
//! any tank. The same solver run on a flat-bottomed cylinder ([`AxisymmetricDomain::flat_cylinder`])
//! reproduces the closed-form `ωₙ` and `mₙ` of `slosh_tank::cylinder_slosh` (Abramson 1966) and
//! its `ℓₙ = H_y/P = h/2 − (2R/ξₙ) tanh(ξₙh/2R)` (the unit tests). For the sphere, every mode's pendulum
//! hinge (`ℓₙ + Lₙ` above the liquid's CM) falls on the sphere's centre: the wall pressure is
//! normal to the sphere, so its resultant passes through the centre. The contact line where the free
//! surface meets the wall above the equator (`h > R`) makes the potential singular there and the
//! convergence algebraic instead of exponential, so [`sphere_slosh`] solves at two basis sizes
//! and refuses a result whose modes differ by more than its tolerances.

use nalgebra::{DMatrix, SymmetricEigen};

use super::slosh_tank::{positive, tank_inputs, SloshMode, TankSlosh};
use crate::error::{Result, SpacearmError};

/// The most slosh modes [`sphere_slosh`] returns (higher ones converge slowly near full).
pub const SPHERE_MAX_MODES: usize = 3;

/// The basis sizes [`sphere_slosh`] solves at (the smaller one estimates the error).
const N_BASIS: usize = 48;
const N_BASIS_CHECK: usize = 32;
/// Gauss–Legendre points per boundary piece (each solve) and for the check solve.
const N_QUAD: usize = 160;
const N_QUAD_CHECK: usize = 120;
/// The convergence tolerances between the two solves: relative on `λₙ`, relative on `mₙ`, and
/// on `ℓₙ / R`.
const TOL_LAMBDA: f64 = 1e-3;
const TOL_MASS: f64 = 1e-2;
const TOL_HEIGHT: f64 = 1e-3;

/// The nodes and weights of the `n`-point Gauss–Legendre rule on `[-1, 1]` (Newton's iteration
/// on `P_n` from the asymptotic guess `cos(π(i − ¼)/(n + ½))`).
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let (mut x, mut w) = (vec![0.0; n], vec![0.0; n]);
    let nf = n as f64;
    for i in 0..n.div_ceil(2) {
        let mut t = (std::f64::consts::PI * (i as f64 + 0.75) / (nf + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, t);
            for k in 2..=n {
                let kf = k as f64;
                let p2 = ((2.0 * kf - 1.0) * t * p1 - (kf - 1.0) * p0) / kf;
                p0 = p1;
                p1 = p2;
            }
            let pn = if n == 0 { 1.0 } else { p1 };
            let pm = if n <= 1 { 1.0 } else { p0 };
            dp = nf * (t * pn - pm) / (t * t - 1.0);
            let step = pn / dp;
            t -= step;
            if step.abs() < 1e-16 {
                break;
            }
        }
        x[i] = t;
        x[n - 1 - i] = -t;
        w[i] = 2.0 / ((1.0 - t * t) * dp * dp);
        w[n - 1 - i] = w[i];
    }
    (x, w)
}

/// One quadrature node on the meridian boundary: the point `(r, z)`, the outward normal
/// `(n_r, n_z)` and the arc-length weight `w` (so that `∫ F ds ≈ Σ w F`).
#[derive(Debug, Clone, Copy)]
struct Node {
    r: f64,
    z: f64,
    nr: f64,
    nz: f64,
    w: f64,
}

/// An axisymmetric liquid domain, dimensionless (the tank radius is 1): its wetted wall and its
/// free surface (the disk `z = surface_z`, `r ≤ surface_radius`), as Gauss–Legendre nodes on the
/// meridian, and its volume and centre-of-mass height.
#[derive(Debug, Clone)]
pub struct AxisymmetricDomain {
    wall: Vec<Node>,
    surface: Vec<Node>,
    /// The free surface's height (in the domain's coordinates).
    pub surface_z: f64,
    /// The liquid's volume.
    pub volume: f64,
    /// The liquid's centre-of-mass height (in the domain's coordinates).
    pub cm_z: f64,
    z_min: f64,
    r_max: f64,
}

/// Map `n` Gauss–Legendre nodes onto `[a, b]`: `(t, weight)` pairs.
fn mapped(n: usize, a: f64, b: f64) -> Vec<(f64, f64)> {
    let (x, w) = gauss_legendre(n);
    x.iter().zip(&w).map(|(&xi, &wi)| (a + 0.5 * (b - a) * (xi + 1.0), 0.5 * (b - a) * wi)).collect()
}

fn surface_nodes(z: f64, radius: f64, n: usize) -> Vec<Node> {
    mapped(n, 0.0, radius).into_iter().map(|(r, w)| Node { r, z, nr: 0.0, nz: 1.0, w }).collect()
}

impl AxisymmetricDomain {
    /// The liquid in a sphere of radius 1 centred at the origin, filled to the depth `depth`
    /// (`h/R`, in (0, 2)) from the bottom pole; `n_quad` nodes on the wall and on the surface.
    pub fn sphere_cap(depth: f64, n_quad: usize) -> Self {
        let zs = depth - 1.0;
        let theta_h = zs.clamp(-1.0, 1.0).acos();
        let wall = mapped(n_quad, theta_h, std::f64::consts::PI)
            .into_iter()
            .map(|(t, w)| {
                let (s, c) = t.sin_cos();
                Node { r: s, z: c, nr: s, nz: c, w }
            })
            .collect();
        let rs = (1.0 - zs * zs).max(0.0).sqrt();
        AxisymmetricDomain {
            wall,
            surface: surface_nodes(zs, rs, n_quad),
            surface_z: zs,
            volume: std::f64::consts::PI * depth * depth * (3.0 - depth) / 3.0,
            cm_z: sphere_cap_cm_height(depth) - 1.0,
            z_min: -1.0,
            r_max: if zs > 0.0 { 1.0 } else { rs },
        }
    }

    /// The liquid in an upright flat-bottomed cylinder of radius 1, filled to `depth` (`h/R`)
    /// from its bottom at `z = 0` (to check the solver against the closed form).
    pub fn flat_cylinder(depth: f64, n_quad: usize) -> Self {
        let mut wall: Vec<Node> = mapped(n_quad, 0.0, 1.0).into_iter().map(|(r, w)| Node { r, z: 0.0, nr: 0.0, nz: -1.0, w }).collect();
        wall.extend(mapped(n_quad, 0.0, depth).into_iter().map(|(z, w)| Node { r: 1.0, z, nr: 1.0, nz: 0.0, w }));
        AxisymmetricDomain {
            wall,
            surface: surface_nodes(depth, 1.0, n_quad),
            surface_z: depth,
            volume: std::f64::consts::PI * depth,
            cm_z: 0.5 * depth,
            z_min: 0.0,
            r_max: 1.0,
        }
    }
}

/// The centre-of-mass height above the bottom pole of a spherical cap of depth `h` in a sphere
/// of radius 1: `h (8 − 3h) / (4 (3 − h))`.
fn sphere_cap_cm_height(h: f64) -> f64 {
    h * (8.0 - 3.0 * h) / (4.0 * (3.0 - h))
}

/// The meridian parts `f_l = r g_l` of the `m = 1` solid harmonics `l = 1 … n` at `(r, z)` in
/// the coordinates centred at `(0, zc)` and scaled by `s`, with their derivatives `∂f/∂r`,
/// `∂f/∂z` in the domain's coordinates (module docs: the recurrence).
fn harmonics(r: f64, z: f64, n: usize, zc: f64, s: f64, f: &mut [f64], fr: &mut [f64], fz: &mut [f64]) {
    let (rr, zz) = (r / s, (z - zc) / s);
    let w = rr * rr;
    let rho2 = w + zz * zz;
    // (g, ∂g/∂z, ∂g/∂(r²)) of l − 1 and l, starting at l = 1 (g_0 = 0, g_1 = 1).
    let (mut g0, mut gz0, mut gw0) = (0.0, 0.0, 0.0);
    let (mut g1, mut gz1, mut gw1) = (1.0, 0.0, 0.0);
    for l in 1..=n {
        f[l - 1] = rr * g1;
        fr[l - 1] = (g1 + 2.0 * w * gw1) / s;
        fz[l - 1] = rr * gz1 / s;
        let lf = l as f64;
        let (a, b) = ((2.0 * lf + 1.0) / lf, (lf + 1.0) / lf);
        let g2 = a * zz * g1 - b * rho2 * g0;
        let gz2 = a * (g1 + zz * gz1) - b * (2.0 * zz * g0 + rho2 * gz0);
        let gw2 = a * zz * gw1 - b * (g0 + rho2 * gw0);
        (g0, gz0, gw0) = (g1, gz1, gw1);
        (g1, gz1, gw1) = (g2, gz2, gw2);
    }
}

/// One lateral slosh mode from [`ritz_lateral_modes`], dimensionless (lengths in the tank
/// radius).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RitzMode {
    /// The eigenvalue `λ = ω² R / a`.
    pub lambda: f64,
    /// The sloshing mass over the liquid's, `mₙ / m_L`.
    pub mass_fraction: f64,
    /// The equivalent mass's height above the liquid's centre of mass, `ℓₙ / R`.
    pub height: f64,
}

/// The Ritz–Trefftz lateral slosh modes of `domain` (module docs) with `n_basis` harmonics: the
/// lowest `n_modes`, the first first. An error if the basis cannot resolve that many.
pub fn ritz_lateral_modes(domain: &AxisymmetricDomain, n_basis: usize, n_modes: usize) -> Result<Vec<RitzMode>> {
    let n = n_basis;
    if n < 2 || n_modes == 0 {
        return Err(SpacearmError::argument(format!("the Ritz slosh solver needs at least 2 basis functions and 1 mode, got {n} and {n_modes}")));
    }
    let zc = 0.5 * (domain.z_min + domain.surface_z);
    let s = domain.r_max.hypot(0.5 * (domain.surface_z - domain.z_min));
    let pi = std::f64::consts::PI;
    let (mut k, mut m) = (DMatrix::<f64>::zeros(n, n), DMatrix::<f64>::zeros(n, n));
    let (mut p, mut hy) = (vec![0.0; n], vec![0.0; n]);
    let (mut f, mut fr, mut fz) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    for (nodes, on_surface) in [(&domain.wall, false), (&domain.surface, true)] {
        for q in nodes.iter() {
            harmonics(q.r, q.z, n, zc, s, &mut f, &mut fr, &mut fz);
            let wr = pi * q.w * q.r;
            let lever = (q.z - domain.cm_z) * q.nr - q.r * q.nz;
            for i in 0..n {
                p[i] += wr * f[i] * q.nr;
                hy[i] += wr * f[i] * lever;
                for j in 0..n {
                    k[(i, j)] += wr * f[i] * (fr[j] * q.nr + fz[j] * q.nz);
                    if on_surface {
                        m[(i, j)] += wr * f[i] * f[j];
                    }
                }
            }
        }
    }
    let k = 0.5 * (&k + k.transpose());
    let mut d = vec![0.0; n];
    for i in 0..n {
        if !(k[(i, i)].is_finite() && k[(i, i)] > 0.0) {
            return Err(SpacearmError::argument(format!("the Ritz slosh solver's stiffness matrix is not positive (basis function {}): the domain is degenerate", i + 1)));
        }
        d[i] = 1.0 / k[(i, i)].sqrt();
    }
    let scaled = DMatrix::from_fn(n, n, |i, j| d[i] * k[(i, j)] * d[j]);
    let eig = SymmetricEigen::new(scaled);
    let top = eig.eigenvalues.max();
    let keep: Vec<usize> = (0..n).filter(|&i| eig.eigenvalues[i] > 1e-13 * top).collect();
    // T = D V_k Λ_k^{-1/2}: Tᵀ K T = 1.
    let t = DMatrix::from_fn(n, keep.len(), |i, c| d[i] * eig.eigenvectors[(i, keep[c])] / eig.eigenvalues[keep[c]].sqrt());
    let c = t.transpose() * &m * &t;
    let c = 0.5 * (&c + c.transpose());
    let ce = SymmetricEigen::new(c);
    let mut order: Vec<usize> = (0..keep.len()).collect();
    order.sort_by(|&a, &b| ce.eigenvalues[b].total_cmp(&ce.eigenvalues[a]));
    let mu_max = ce.eigenvalues[order[0]];
    let mut modes = Vec::with_capacity(n_modes);
    for &idx in order.iter().take(n_modes) {
        let mu = ce.eigenvalues[idx];
        if !(mu.is_finite() && mu > 1e-12 * mu_max && mu_max > 0.0) {
            return Err(SpacearmError::argument(format!("the Ritz slosh solver resolves only {} lateral modes with {n} basis functions, {n_modes} asked", modes.len())));
        }
        let a = &t * ce.eigenvectors.column(idx);
        let energy = (a.transpose() * &k * &a)[(0, 0)];
        let pn: f64 = (0..n).map(|i| p[i] * a[i]).sum();
        let hn: f64 = (0..n).map(|i| hy[i] * a[i]).sum();
        modes.push(RitzMode { lambda: 1.0 / mu, mass_fraction: pn * pn / (energy * domain.volume), height: hn / pn });
    }
    Ok(modes)
}

/// The fill height `h` of a sphere of `radius` R holding the `fill_fraction` f of its volume:
/// the root in `(0, 2R]` of `(h/R)² (3 − h/R) / 4 = f` (the cap volume `π h² (3R − h)/3`), by a
/// Newton iteration safeguarded by bisection.
pub fn sphere_fill_height(radius: f64, fill_fraction: f64) -> Result<f64> {
    let r = positive("the tank radius (m)", radius)?;
    if !(fill_fraction.is_finite() && fill_fraction > 0.0 && fill_fraction <= 1.0) {
        return Err(SpacearmError::argument(format!("the fill fraction of a spherical tank must be in (0, 1] (the liquid's volume over the tank's), got {fill_fraction}")));
    }
    let vol = |t: f64| t * t * (3.0 - t) / 4.0;
    let (mut lo, mut hi) = (0.0_f64, 2.0_f64);
    // The half-fill root is 1; start from the cubic's small-f or near-full asymptote.
    let mut t = if fill_fraction < 0.5 { (4.0 * fill_fraction / 3.0).sqrt() } else { 2.0 - (4.0 * (1.0 - fill_fraction) / 3.0).sqrt() };
    for _ in 0..200 {
        let g = vol(t) - fill_fraction;
        if g > 0.0 {
            hi = t;
        } else {
            lo = t;
        }
        let dg = 0.75 * t * (2.0 - t);
        let next = t - g / dg;
        let next = if dg > 0.0 && next > lo && next < hi { next } else { 0.5 * (lo + hi) };
        if (next - t).abs() < 1e-15 * t.max(1e-300) || hi - lo < 1e-16 {
            t = next;
            break;
        }
        t = next;
    }
    Ok(t * r)
}

/// The equivalent mechanical model of the liquid in a spherical tank of `radius` R filled to
/// `fill_height` h (from the bottom, in (0, 2R)) with `liquid_mass` m_L, in the axial
/// acceleration `a`, with `n_modes` lateral modes (1 to 3; module docs). The returned
/// `liquid_cm_height` is above the tank's bottom pole; the heights of the modes and of the fixed
/// mass are above the liquid's centre of mass, along the tank axis.
pub fn sphere_slosh(radius: f64, fill_height: f64, liquid_mass: f64, axial_acceleration: f64, n_modes: usize) -> Result<TankSlosh> {
    let (r, h, m_l) = tank_inputs(radius, fill_height, liquid_mass, axial_acceleration)?;
    if !(1..=SPHERE_MAX_MODES).contains(&n_modes) {
        return Err(SpacearmError::argument(format!(
            "the number of slosh modes of a spherical tank must be 1 to {SPHERE_MAX_MODES} (higher modes converge too slowly near full), got {n_modes}"
        )));
    }
    let depth = h / r;
    if depth >= 2.0 {
        return Err(SpacearmError::argument(format!(
            "the fill height of a spherical tank must be below its diameter 2R = {} m (a full tank has no free surface and does not slosh), got {h}",
            2.0 * r
        )));
    }
    let fine = ritz_lateral_modes(&AxisymmetricDomain::sphere_cap(depth, N_QUAD), N_BASIS, n_modes)?;
    let coarse = ritz_lateral_modes(&AxisymmetricDomain::sphere_cap(depth, N_QUAD_CHECK), N_BASIS_CHECK, n_modes)?;
    for (i, (a, b)) in fine.iter().zip(&coarse).enumerate() {
        let dl = (a.lambda - b.lambda).abs() / a.lambda;
        let dm = (a.mass_fraction - b.mass_fraction).abs() / a.mass_fraction;
        let dh = (a.height - b.height).abs();
        if !(dl <= TOL_LAMBDA && dm <= TOL_MASS && dh <= TOL_HEIGHT) {
            return Err(SpacearmError::argument(format!(
                "the spherical tank's slosh mode {} is not converged at the fill h/R = {depth} (between {N_BASIS_CHECK} and {N_BASIS} \
                 harmonics: relative change {dl:.1e} in the frequency squared, {dm:.1e} in the mass, {dh:.1e} R in the height; \
                 tolerances {TOL_LAMBDA:.0e}, {TOL_MASS:.0e}, {TOL_HEIGHT:.0e}): ask for fewer modes, or use a lower fill (near full \
                 the sloshing mass is small)",
                i + 1
            )));
        }
    }
    let a = axial_acceleration;
    let modes: Vec<SloshMode> = fine
        .iter()
        .map(|md| {
            let mass = m_l * md.mass_fraction;
            let w2 = a * md.lambda / r;
            SloshMode::from_frequency_squared(mass, r * md.height, w2, a)
        })
        .collect();
    TankSlosh::from_modes(m_l, h, r, a, r * sphere_cap_cm_height(depth), modes)
}

#[cfg(test)]
mod tests {
    use super::super::slosh_tank::{cylinder_slosh, BESSEL_J1_PRIME_ZEROS};
    use super::*;

    #[test]
    fn gauss_legendre_integrates_polynomials_and_a_closed_form() {
        let (x, w) = gauss_legendre(10);
        // Exact for degree ≤ 19: ∫ x^18 = 2/19.
        let s: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(18)).sum();
        assert!((s - 2.0 / 19.0).abs() < 1e-14, "{s}");
        let (x, w) = gauss_legendre(40);
        let s: f64 = x.iter().zip(&w).map(|(x, w)| w * x.exp()).sum();
        assert!((s - (1f64.exp() - (-1f64).exp())).abs() < 1e-13, "{s}");
    }

    #[test]
    fn the_basis_is_harmonic() {
        // φ = x g(z, r²): a central second difference of the 3-D Laplacian at a point.
        let n = 9;
        let phi = |x: f64, y: f64, z: f64| {
            let (mut f, mut fr, mut fz) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
            let r = x.hypot(y);
            harmonics(r, z, n, 0.1, 0.8, &mut f, &mut fr, &mut fz);
            f.iter().map(|fl| fl * x / r).collect::<Vec<_>>()
        };
        let (x, y, z, e) = (0.3, 0.2, -0.4, 1e-3);
        let c = phi(x, y, z);
        let sum = |dx: f64, dy: f64, dz: f64| phi(x + dx, y + dy, z + dz);
        let lap: Vec<f64> = (0..n)
            .map(|l| {
                (sum(e, 0.0, 0.0)[l] + sum(-e, 0.0, 0.0)[l] + sum(0.0, e, 0.0)[l] + sum(0.0, -e, 0.0)[l] + sum(0.0, 0.0, e)[l] + sum(0.0, 0.0, -e)[l]
                    - 6.0 * c[l])
                    / (e * e)
            })
            .collect();
        for (l, v) in lap.iter().enumerate() {
            // The functions are O(1)..O(10) here; the difference's truncation error is ~e².
            assert!(v.abs() < 1e-4 * (1.0 + c[l].abs()) * 10f64.powi(l as i32 / 3), "l = {}: ∇²φ = {v}", l + 1);
        }
        // And the derivatives by differences.
        let (mut f, mut fr, mut fz) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let (mut fp, mut fm, mut d1, mut d2) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        harmonics(0.5, -0.2, n, 0.1, 0.8, &mut f, &mut fr, &mut fz);
        harmonics(0.5 + 1e-6, -0.2, n, 0.1, 0.8, &mut fp, &mut d1, &mut d2);
        harmonics(0.5 - 1e-6, -0.2, n, 0.1, 0.8, &mut fm, &mut d1, &mut d2);
        for l in 0..n {
            assert!(((fp[l] - fm[l]) / 2e-6 - fr[l]).abs() < 1e-6 * (1.0 + fr[l].abs()));
        }
        harmonics(0.5, -0.2 + 1e-6, n, 0.1, 0.8, &mut fp, &mut d1, &mut d2);
        harmonics(0.5, -0.2 - 1e-6, n, 0.1, 0.8, &mut fm, &mut d1, &mut d2);
        for l in 0..n {
            assert!(((fp[l] - fm[l]) / 2e-6 - fz[l]).abs() < 1e-6 * (1.0 + fz[l].abs()));
        }
    }

    /// The momentum-matched height of the cylinder's mode (module docs: `ℓ = H_y/P` with the
    /// exact potential `J₁(ξr) cosh(ξz) cos ϕ` integrates to this; `R = 1`).
    fn cylinder_height_closed_form(xi: f64, h: f64) -> f64 {
        0.5 * h - 2.0 / xi * (0.5 * xi * h).tanh()
    }

    #[test]
    fn the_solver_reproduces_the_cylinder_closed_form() {
        for &h in &[0.3, 1.0, 2.0] {
            let modes = ritz_lateral_modes(&AxisymmetricDomain::flat_cylinder(h, 80), 28, 3).unwrap();
            let closed = cylinder_slosh(1.0, h, 1.0, 1.0, 3).unwrap();
            for (n, (md, c)) in modes.iter().zip(&closed.modes).enumerate() {
                let xi = BESSEL_J1_PRIME_ZEROS[n];
                let tol = [1e-10, 1e-8, 1e-5][n];
                assert!((md.lambda - c.frequency.powi(2)).abs() < tol * md.lambda, "h = {h}, mode {}: λ {} vs {}", n + 1, md.lambda, c.frequency.powi(2));
                assert!((md.mass_fraction - c.mass).abs() < tol * c.mass * 10.0, "h = {h}, mode {}: m {} vs {}", n + 1, md.mass_fraction, c.mass);
                assert!((md.height - cylinder_height_closed_form(xi, h)).abs() < tol * 100.0, "h = {h}, mode {}: ℓ {}", n + 1, md.height);
                assert!((md.height - c.height).abs() < tol * 100.0, "h = {h}, mode {}: ℓ {} vs cylinder_slosh {}", n + 1, md.height, c.height);
            }
        }
    }

    #[test]
    fn the_half_full_sphere_matches_mciver() {
        // McIver (J. Fluid Mech. 201, 1989): ω²R/g = 1.5602 for the first antisymmetric mode at h = R.
        let t = sphere_slosh(1.0, 1.0, 1.0, 1.0, 1).unwrap();
        assert!((t.modes[0].frequency.powi(2) - 1.5602).abs() < 5e-5, "{}", t.modes[0].frequency.powi(2));
        // Convergence in N: the Ritz values are upper bounds that decrease.
        let dom = AxisymmetricDomain::sphere_cap(1.0, 120);
        let lam: Vec<f64> = [4, 8, 12, 16, 24].iter().map(|&n| ritz_lateral_modes(&dom, n, 1).unwrap()[0].lambda).collect();
        for w in lam.windows(2) {
            assert!(w[1] <= w[0] + 1e-12, "{lam:?}");
        }
        assert!((lam[3] - lam[4]).abs() < 1e-6, "{lam:?}");
    }

    #[test]
    fn limits_of_the_sphere() {
        // Shallow: the liquid swings like a pendulum of length R about the centre: ω²R/a → 1,
        // all of it sloshes, and the pendulum's hinge is at the centre.
        let (r, a, m) = (0.7, 0.3, 50.0);
        let t = sphere_slosh(r, 1e-3 * r, m, a, 1).unwrap();
        let md = &t.modes[0];
        assert!((md.frequency.powi(2) * r / a - 1.0).abs() < 1e-3, "{}", md.frequency.powi(2) * r / a);
        assert!((md.mass / m - 1.0).abs() < 1e-3, "{}", md.mass / m);
        let hinge = t.liquid_cm_height + md.height + md.length;
        assert!((hinge - r).abs() < 1e-5 * r, "hinge {hinge} vs centre {r}");
        // Toward full: the frequency rises without bound and the sloshing mass vanishes.
        let fills = [0.5, 1.0, 1.5, 1.8, 1.9];
        let ts: Vec<TankSlosh> = fills.iter().map(|&f| sphere_slosh(r, f * r, m, a, 1).unwrap()).collect();
        for w in ts.windows(2) {
            assert!(w[1].modes[0].frequency > w[0].modes[0].frequency);
            assert!(w[1].modes[0].mass < w[0].modes[0].mass);
        }
        assert!(ts[4].modes[0].mass / m < 0.05 && ts[4].modes[0].frequency.powi(2) * r / a > 5.0);
        assert!(sphere_slosh(r, 2.0 * r, m, a, 1).is_err());
        assert!(sphere_slosh(r, 0.5, m, 0.0, 1).is_err());
        assert!(sphere_slosh(-1.0, 0.5, m, a, 1).is_err());
        assert!(sphere_slosh(r, 0.5, m, a, 4).is_err());
    }

    #[test]
    fn the_model_keeps_the_liquid_mass_and_centre() {
        for &f in &[0.05, 0.4, 1.0, 1.3, 1.7] {
            let t = sphere_slosh(1.2, f * 1.2, 80.0, 0.5, 3).unwrap();
            let total = t.fixed_mass + t.modes.iter().map(|m| m.mass).sum::<f64>();
            assert!((total - 80.0).abs() < 1e-10);
            let moment = t.fixed_mass * t.fixed_height + t.modes.iter().map(|m| m.mass * m.height).sum::<f64>();
            assert!(moment.abs() < 1e-10);
            assert!(t.modes.iter().all(|m| m.mass > 0.0) && t.fixed_mass > 0.0);
            assert!(t.modes.windows(2).all(|w| w[1].frequency > w[0].frequency));
            // The wall pressure is normal to the sphere: its resultant passes through the centre,
            // so each mode's pendulum hinge (ℓₙ + Lₙ above the liquid's CM) is at the centre.
            for m in &t.modes {
                let hinge = t.liquid_cm_height + m.height + m.length;
                assert!((hinge - 1.2).abs() < 1e-9, "fill {f}: hinge {hinge}");
            }
        }
    }

    #[test]
    fn converged_in_the_quadrature_and_the_basis() {
        // A second quadrature resolution and basis size give the same modes.
        for &h in &[0.3, 1.0, 1.6] {
            let a = ritz_lateral_modes(&AxisymmetricDomain::sphere_cap(h, 200), 56, 2).unwrap();
            let b = ritz_lateral_modes(&AxisymmetricDomain::sphere_cap(h, N_QUAD), N_BASIS, 2).unwrap();
            for (x, y) in a.iter().zip(&b) {
                assert!((x.lambda - y.lambda).abs() < 2e-5 * x.lambda, "h = {h}: {x:?} {y:?}");
                assert!((x.mass_fraction - y.mass_fraction).abs() < 2e-4 * x.mass_fraction, "h = {h}: {x:?} {y:?}");
            }
        }
    }

    #[test]
    fn the_fill_height_inverts_the_cap_volume() {
        for &f in &[1e-6, 0.01, 0.3, 0.5, 0.8, 0.999, 1.0] {
            let h = sphere_fill_height(2.0, f).unwrap();
            let vol = std::f64::consts::PI * h * h * (6.0 - h) / 3.0;
            let full = 4.0 / 3.0 * std::f64::consts::PI * 8.0;
            assert!((vol / full - f).abs() < 1e-13, "f = {f}: {}", vol / full);
        }
        assert!((sphere_fill_height(2.0, 0.5).unwrap() - 2.0).abs() < 1e-14);
        assert!(sphere_fill_height(2.0, 0.0).is_err() && sphere_fill_height(2.0, 1.2).is_err() && sphere_fill_height(0.0, 0.5).is_err());
    }
}
