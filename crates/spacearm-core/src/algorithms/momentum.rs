//! Momentum, kinetic energy and the system centre of mass, summed body by body from the body
//! velocities (independent of the mass matrix, which the tests compare against:
//! `[P; L_base] = H0 ẋ0 + H0m q̇`, `T = ½ uᵀ H u`, paper eqs. 27 and 42).

use nalgebra::Vector3;

use crate::model::data::{Data, DataT};
use crate::math::scalar::Real;
use crate::error::Result;
use crate::algorithms::kinematics::{check_velocity, forward_kinematics};
use crate::model::Model;
use crate::algorithms::rnea::velocity_pass;
use crate::math::spatial::{angular, linear};

/// Linear momentum and angular momentum about three points (docs/conventions.md).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Momentum {
    /// `P = Σ mᵢ vᵢ`, N·s.
    pub linear: Vector3<f64>,
    /// Angular momentum about the origin of 𝒥 (conserved with no external wrench).
    pub angular_about_origin: Vector3<f64>,
    /// Angular momentum about the base CM (the lower half of `H0 ẋ0 + H0m q̇`).
    pub angular_about_base: Vector3<f64>,
    /// Angular momentum about the system CM.
    pub angular_about_com: Vector3<f64>,
}

/// System centre of mass `r_g` in 𝒥. Requires forward kinematics.
pub fn center_of_mass_from_data(model: &Model, data: &Data) -> Vector3<f64> {
    let mut first = Vector3::zeros();
    for b in 0..model.n_bodies() {
        first += model.mass_properties(b).mass * data.com_in_world[b];
    }
    first / model.total_mass()
}

/// System centre of mass `r_g` in 𝒥 at configuration `x`.
pub fn center_of_mass(model: &Model, data: &mut Data, x: &[f64]) -> Result<Vector3<f64>> {
    forward_kinematics(model, data, x)?;
    Ok(center_of_mass_from_data(model, data))
}

/// Momentum of the system at `(x, u)`.
pub fn momentum(model: &Model, data: &mut Data, x: &[f64], u: &[f64]) -> Result<Momentum> {
    forward_kinematics(model, data, x)?;
    check_velocity(model, "u", u)?;
    velocity_pass(model, data, u);
    Ok(momentum_from_data(model, data))
}

/// Momentum from the body velocities already in `data` (after forward kinematics and the
/// velocity pass): `[P; L_base] = Σ Iᵢ vᵢ` with the spatial inertias and velocities at the base
/// CM, then moved to the origin of 𝒥 and to the system CM. The one momentum sum of the crate
/// (the simulator records it with this function too).
pub fn momentum_from_data(model: &Model, data: &Data) -> Momentum {
    let (p, l_base) = momentum_about_base(model, data);
    let r0 = data.base_position;
    let rg = center_of_mass_from_data(model, data);
    Momentum {
        linear: p,
        angular_about_origin: l_base + r0.cross(&p),
        angular_about_base: l_base,
        angular_about_com: l_base + (r0 - rg).cross(&p),
    }
}

/// The magnitudes against which the drift of a conserved quantity is measured
/// ([`conserved_drift`]): the sums over the bodies of their own contributions' norms,
/// `Σ mᵢ (|v_{0i}| + |ωᵢ × (rᵢ − r0)|)` (the two terms of `pᵢ`, `v_{0i}` the velocity of body i's
/// point at the base CM `r0`: a rotor spinning about its own CM has `pᵢ = 0` from two terms that
/// cancel, and P's rounding is relative to them), `Σ (|rᵢ × pᵢ| + |Iᵢ ωᵢ|)` about the origin and
/// about the system CM, and the
/// mechanical energy, kinetic plus the joint springs' (a sum of non-negative terms). A sum of norms bounds the norm of the sum and does not
/// cancel when the total is zero, so the relative drift stays meaningful for a system at zero
/// momentum (docs/simulation-core.md, "Records and meta").
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct MomentumScales {
    /// `Σ mᵢ (|v_{0i}| + |ωᵢ × (rᵢ − r0)|)`, N·s.
    pub linear: f64,
    /// `Σ (|rᵢ × pᵢ| + |Iᵢ ωᵢ|)`, about the origin of 𝒥, N·m·s.
    pub angular_about_origin: f64,
    /// The same about the system CM, N·m·s.
    pub angular_about_com: f64,
    /// Mechanical energy: kinetic plus the joint springs' potential energy
    /// ([`crate::algorithms::passive`]; [`momentum_scales_from_data`] has no `q` and gives the
    /// kinetic part alone), J.
    pub energy: f64,
}

impl MomentumScales {
    /// The larger of each pair of entries (a running maximum over samples).
    pub fn max(self, other: MomentumScales) -> MomentumScales {
        MomentumScales {
            linear: self.linear.max(other.linear),
            angular_about_origin: self.angular_about_origin.max(other.angular_about_origin),
            angular_about_com: self.angular_about_com.max(other.angular_about_com),
            energy: self.energy.max(other.energy),
        }
    }
}

/// [`MomentumScales`] from the body velocities already in `data` (after forward kinematics and
/// the velocity pass), body by body; the energy is the kinetic energy alone (the caller adds the
/// springs', which need `q`).
pub fn momentum_scales_from_data(model: &Model, data: &Data) -> MomentumScales {
    let r0 = data.base_position;
    let rg = center_of_mass_from_data(model, data);
    let mut s = MomentumScales::default();
    for b in 0..model.n_bodies() {
        let v = data.body_velocity[b];
        s.energy += 0.5 * v.dot(&(data.spatial_inertia[b] * v));
        let w = angular(&v);
        let rb = data.com_in_world[b];
        // pᵢ = mᵢ (v_{0i} + ωᵢ × (rᵢ − r0)), v_{0i} the velocity of body i's point at r0: the
        // two terms cancel for a rotor spinning about its own CM (a wheel or CMG on a base at
        // rest), and their sizes, not |pᵢ|, are what the rounding of P is relative to.
        let m = model.mass_properties(b).mass;
        let lever = w.cross(&(rb - r0));
        let p_b = (linear(&v) + lever) * m;
        let spin = (data.inertia_in_world[b] * w).norm();
        s.linear += (linear(&v).norm() + lever.norm()) * m;
        s.angular_about_origin += rb.cross(&p_b).norm() + spin;
        s.angular_about_com += (rb - rg).cross(&p_b).norm() + spin;
    }
    s
}

/// [`MomentumScales`] at `(x, u)`.
pub fn momentum_scales(model: &Model, data: &mut Data, x: &[f64], u: &[f64]) -> Result<MomentumScales> {
    forward_kinematics(model, data, x)?;
    check_velocity(model, "u", u)?;
    velocity_pass(model, data, u);
    let mut s = momentum_scales_from_data(model, data);
    s.energy += crate::algorithms::passive::spring_energy_of_q(model, &x[7..]);
    Ok(s)
}

/// The drift of a conserved quantity over samples: `max_k |v_k − v_0| / max(|v_0|, scale)`,
/// `values` row-major with `dim` entries per sample and `scale` the largest
/// [`MomentumScales`] entry of the run (the smallest positive double keeps an all-zero quantity
/// at drift 0). The one definition of drift: the simulator's records, `Trajectory.drift` and the
/// capture's momentum ledger use it.
pub fn conserved_drift(values: &[f64], dim: usize, scale: f64) -> f64 {
    if values.is_empty() || dim == 0 {
        return 0.0;
    }
    let first = &values[..dim];
    let norm = |c: &[f64]| c.iter().zip(first).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt();
    let denom = first.iter().map(|v| v * v).sum::<f64>().sqrt().max(scale).max(f64::MIN_POSITIVE);
    values.chunks_exact(dim).map(norm).fold(0.0, f64::max) / denom
}

/// `(P, L_base)` from the body velocities already in `data`, any scalar: `[P; L_base] =
/// Σ Iᵢ vᵢ` (the angular momentum about the base CM).
pub(crate) fn momentum_about_base<T: Real>(model: &Model, data: &DataT<T>) -> (Vector3<T>, Vector3<T>) {
    let mut total = nalgebra::Vector6::zeros();
    for b in 0..model.n_bodies() {
        total += data.spatial_inertia[b] * data.body_velocity[b];
    }
    (linear(&total), angular(&total))
}

/// Kinetic energy `T = ½ Σ (mᵢ |vᵢ|² + ωᵢᵀ Iᵢ ωᵢ)` at `(x, u)`, J.
pub fn kinetic_energy(model: &Model, data: &mut Data, x: &[f64], u: &[f64]) -> Result<f64> {
    forward_kinematics(model, data, x)?;
    check_velocity(model, "u", u)?;
    velocity_pass(model, data, u);
    let r0 = data.base_position;
    let mut t = 0.0;
    for b in 0..model.n_bodies() {
        let v = data.body_velocity[b];
        let w = angular(&v);
        // Velocity of the body CM from the twist at the base CM.
        let v_com = linear(&v) + w.cross(&(data.com_in_world[b] - r0));
        let m = model.mass_properties(b).mass;
        t += 0.5 * (m * v_com.norm_squared() + w.dot(&(data.inertia_in_world[b] * w)));
    }
    Ok(t)
}
