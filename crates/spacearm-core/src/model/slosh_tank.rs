//! From a tank to the parameters of its slosh modes' equivalent mechanical model
//! (docs/flexibility.md, "From a tank to the slosh parameters").
//!
//! An upright circular cylinder of radius `R` with a flat bottom, filled to the height `h` with a
//! liquid of mass `m_L`, in an axial acceleration `a` (the thrust's, toward the bottom): the
//! linear potential-flow solution of its lateral sloshing (Abramson, *The Dynamic Behavior of
//! Liquids in Moving Containers*, NASA SP-106, 1966, Table 6.1; Dodge, *The New "Dynamic Behavior
//! of Liquids in Moving Containers"*, SwRI, 2000, §3.2 and Fig. 3.3) gives, for the antisymmetric
//! modes `n = 1, 2, …` with `ξₙ` the zeros of `J₁′` (1.8412, 5.3314, 8.5363, …):
//!
//! - frequency `ωₙ² = (a/R) ξₙ tanh(ξₙ h/R)`;
//! - sloshing mass `mₙ/m_L = 2 tanh(ξₙ h/R) / (ξₙ (ξₙ² − 1) h/R)`;
//! - the spring–mass model's mass at `ℓₙ = h/2 − (2R/ξₙ) tanh(ξₙ h/(2R))` above the liquid's
//!   centre of mass (along the tank axis, toward the free surface), spring `kₙ = mₙ ωₙ²`. This is
//!   the mode's angular momentum over its momentum, `ℓₙ = H_y/P`: the height at which one mass
//!   has the mode's coupling to the tank's rotation as well as its translation, so that the
//!   model reproduces the moment on the tank of the wall *and* bottom pressures. The wall
//!   pressure alone acts at `h/2 − (R/ξₙ) tanh(ξₙ h/(2R))` (the height some tables quote,
//!   "excluding bottom pressure"); a rigid tank feels both. Checked against the mode's
//!   potential flow integrated by quadrature in `tests/model/test_slosh_potential_flow.py`
//!   (docs/flexibility.md);
//! - the pendulum model's bob at the same place, on a rod of `Lₙ = a/ωₙ² = R/(ξₙ tanh(ξₙ h/R))`
//!   from a hinge at `ℓₙ + Lₙ` (the moment of the pendulum's rod force about the tank then equals
//!   the spring–mass model's, its force and its displaced weight);
//! - the fixed (non-sloshing) mass `m₀ = m_L − Σ mₙ` at `ℓ₀ = −Σ mₙ ℓₙ / m₀`, so that the model's
//!   centre of mass is the liquid's;
//! - the fixed mass's moment of inertia about a lateral axis through its CM,
//!   `I₀ = J − m₀ ℓ₀² − Σ mₙ ℓₙ²`, with `J` the pitching inertia of the liquid under a rigid lid
//!   about its CM (the Stokes–Zhukovsky potential `Ψ = x z + χ` of the closed cylinder; `χ` a
//!   Dini series in `J₁(ξₙ r/R) sinh(ξₙ z/R)`):
//!   `J = m_L [h²/12 − 3R²/4 + (16R³/h) Σₙ tanh(ξₙ h/2R) / (ξₙ³ (ξₙ² − 1))]`, the sum over all
//!   the zeros of `J₁′`. With the liquid's velocity split into the lid flow and the sloshing
//!   modes, the model then has the liquid's kinetic energy in any motion of the tank: the modes'
//!   coupling to the lid flow is `mₙ ℓₙ` (their `H_y`), the modes not in the model move with the
//!   fixed mass. `J → m_L (R²/4 + h²/12)` (the rigid liquid's) for a deep or a shallow fill, and
//!   dips to about `0.16` of it near `h = 2R`. About the tank axis the ideal liquid does not turn
//!   with an axisymmetric tank: no axial moment. Checked against a Ritz solution by quadrature in
//!   `tests/model/test_slosh_potential_flow.py`.
//!
//! In weightless coasting (`a → 0`) the restoring force vanishes: `ω → 0` and the liquid's
//! position is set by surface tension (a low-Bond-number regime this model does not describe),
//! so `a` must be > 0: the axial acceleration of the phase being studied (thrust / vehicle mass
//! during a burn or a settling burn). The frequency scales as `√a`; the masses and positions do
//! not depend on `a`. Damping is not part of the inviscid solution: the caller gives a damping
//! ratio `ζ` (from tests or the viscous estimates of Dodge 2000, §3.2; of the order of 0.001–0.01
//! for a smooth-walled tank, more with baffles), and the damper is `cₙ = 2 ζ mₙ ωₙ`.

use crate::error::{Result, SpacearmError};

/// The first zeros of `J₁′(ξ)` (the antisymmetric slosh modes of a circular cylinder).
pub const BESSEL_J1_PRIME_ZEROS: [f64; 5] = [1.841_183_781_340_659, 5.331_442_773_525_033, 8.536_316_366_346_286, 11.706_004_902_592_063, 14.863_588_633_909_034];

/// One slosh mode of a tank (serialized as the doors' plain data: `{mass, height, frequency,
/// stiffness, length}`).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct SloshMode {
    /// The sloshing mass `mₙ`, kg.
    pub mass: f64,
    /// Its height above the liquid's centre of mass along the tank axis, m (`ℓₙ`).
    pub height: f64,
    /// The natural frequency `ωₙ` in the acceleration `a`, rad/s.
    pub frequency: f64,
    /// The spring–mass model's stiffness `mₙ ωₙ²`, N/m.
    pub stiffness: f64,
    /// The pendulum model's rod length `a/ωₙ²`, m (the hinge is at `height + length`).
    pub length: f64,
}

impl SloshMode {
    /// The mode of `mass` at `height` whose squared frequency is `w2` in the acceleration `a`:
    /// the spring `mₙ ωₙ²` and the pendulum rod `a/ωₙ²` follow (module docs).
    pub fn from_frequency_squared(mass: f64, height: f64, w2: f64, a: f64) -> Self {
        SloshMode { mass, height, frequency: w2.sqrt(), stiffness: mass * w2, length: a / w2 }
    }
}

/// The equivalent mechanical model of a tank's liquid (module docs); serialized field by field
/// (the Python door's dict).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct TankSlosh {
    /// The liquid's mass `m_L`, kg.
    pub liquid_mass: f64,
    /// The fill height `h`, m.
    pub fill_height: f64,
    /// The tank radius `R`, m.
    pub radius: f64,
    /// The axial acceleration `a`, m/s².
    pub axial_acceleration: f64,
    /// The liquid's centre of mass above the tank bottom, m (`h/2`).
    pub liquid_cm_height: f64,
    /// The slosh modes, the first first.
    pub modes: Vec<SloshMode>,
    /// The fixed mass `m₀`, kg.
    pub fixed_mass: f64,
    /// Its height above the liquid's centre of mass, m (`ℓ₀`).
    pub fixed_height: f64,
    /// Its moment of inertia about a lateral axis through its CM, kg·m² (`I₀`, module docs), where
    /// the model defines it (the cylinder); `None` where it does not (the sphere).
    pub fixed_inertia: Option<f64>,
}

impl TankSlosh {
    /// The model of the liquid (`liquid_mass`, `fill_height`, `radius`, `axial_acceleration`,
    /// its CM `liquid_cm_height` above the bottom) with these `modes`: the rest of the liquid is
    /// the fixed mass `m₀ = m_L − Σ mₙ`, at the height `ℓ₀ = −Σ mₙ ℓₙ / m₀` that keeps the model's
    /// CM at the liquid's. An error if the modes hold all the liquid or more.
    pub fn from_modes(liquid_mass: f64, fill_height: f64, radius: f64, axial_acceleration: f64, liquid_cm_height: f64,
                      modes: Vec<SloshMode>) -> Result<Self> {
        let sloshing: f64 = modes.iter().map(|m| m.mass).sum();
        let fixed_mass = liquid_mass - sloshing;
        if !(fixed_mass > 0.0) {
            return Err(SpacearmError::argument(format!("the slosh masses ({sloshing} kg) exceed the liquid's ({liquid_mass} kg)")));
        }
        let fixed_height = -modes.iter().map(|m| m.mass * m.height).sum::<f64>() / fixed_mass;
        Ok(TankSlosh { liquid_mass, fill_height, radius, axial_acceleration, liquid_cm_height, modes, fixed_mass, fixed_height, fixed_inertia: None })
    }

    /// This model with the fixed mass's moment of inertia `I₀ = J − m₀ ℓ₀² − Σ mₙ ℓₙ²` for the
    /// liquid's pitching inertia `J` under a rigid lid about its CM (module docs). An error if
    /// it is negative (a `J` below the masses' own: not this model's liquid).
    pub fn with_lid_inertia(mut self, lid_inertia: f64) -> Result<Self> {
        let i0 = lid_inertia - self.fixed_mass * self.fixed_height.powi(2) - self.modes.iter().map(|m| m.mass * m.height.powi(2)).sum::<f64>();
        if !(i0.is_finite() && i0 >= 0.0) {
            return Err(SpacearmError::argument(format!("the fixed liquid's moment of inertia came out as {i0} kg m^2 (from the lid inertia {lid_inertia})")));
        }
        self.fixed_inertia = Some(i0);
        Ok(self)
    }
}

/// The `n`-th zero of `J₁′` (from 1): the table, then McMahon's expansion
/// `β − 7/(8β) − 4·431/(3 (8β)³)`, `β = (n − 1/4) π` (Abramowitz & Stegun 9.5.13 with μ = 4; its
/// error is 2.7e-6 at n = 5, 1.0e-6 at n = 6, and falls about as n⁻⁵; in the sum it moves `J` by
/// under 1e-10 of itself).
fn j1_prime_zero(n: usize) -> f64 {
    if n <= BESSEL_J1_PRIME_ZEROS.len() {
        return BESSEL_J1_PRIME_ZEROS[n - 1];
    }
    let beta = (n as f64 - 0.25) * std::f64::consts::PI;
    let b8 = 8.0 * beta;
    beta - 7.0 / b8 - 4.0 * 431.0 / (3.0 * b8.powi(3))
}

/// The pitching moment of inertia about its CM of the liquid filling a closed upright cylinder
/// of radius `R` and height `h` (a rigid lid at the free surface), kg·m² (module docs).
pub fn cylinder_lid_inertia(radius: f64, fill_height: f64, liquid_mass: f64) -> f64 {
    let (r, h) = (radius, fill_height);
    // Σ tanh(ξ h/2R)/(ξ³ (ξ² − 1)): terms fall as ξ⁻⁵ (≈ (π n)⁻⁵); 400 terms leave < 1e-14.
    let sum: f64 = (1..=400).map(j1_prime_zero).map(|xi| (0.5 * xi * h / r).tanh() / (xi.powi(3) * (xi * xi - 1.0))).sum();
    liquid_mass * (h * h / 12.0 - 0.75 * r * r + 16.0 * r.powi(3) / h * sum)
}

/// `v`, when finite and > 0; else an argument error naming `what`.
pub(crate) fn positive(what: &str, v: f64) -> Result<f64> {
    if !(v.is_finite() && v > 0.0) {
        return Err(SpacearmError::argument(format!("{what} must be finite and > 0, got {v}")));
    }
    Ok(v)
}

/// Check the axial acceleration of a slosh model (> 0: at 0 the model does not apply; module docs).
pub(crate) fn axial(axial_acceleration: f64) -> Result<f64> {
    if !(axial_acceleration.is_finite() && axial_acceleration > 0.0) {
        return Err(SpacearmError::argument(format!(
            "the axial acceleration must be finite and > 0 m/s^2 (the thrust's; at 0 the liquid has no restoring force and \
             surface tension sets it, which this model does not describe), got {axial_acceleration}"
        )));
    }
    Ok(axial_acceleration)
}

/// The shallowest fill a slosh model describes, as the fill height over the tank radius `h/R`:
/// a layer thinner than this is a film whose motion viscosity and surface tension set (its
/// boundary layer and meniscus are as deep as the layer), not the inviscid potential flow of
/// these models, whose cylinder pendulum would grow without bound (`Lₙ → R²/(ξₙ² h)`; at this
/// bound about 3000 R). Shallower fills are refused (docs/flexibility.md).
pub const MIN_FILL_DEPTH_RATIO: f64 = 1e-4;

/// Check a fill height `h` (m, finite and > 0) against [`MIN_FILL_DEPTH_RATIO`] of `radius`.
pub(crate) fn fill_depth(radius: f64, fill_height: f64) -> Result<f64> {
    let h = positive("the fill height (m)", fill_height)?;
    if h < MIN_FILL_DEPTH_RATIO * radius {
        return Err(SpacearmError::argument(format!(
            "the fill height {h:e} m is below {MIN_FILL_DEPTH_RATIO:e} of the tank radius {radius} m: a layer that thin has no slosh \
             modes this model describes (viscosity and surface tension hold it); model the liquid as a fixed mass"
        )));
    }
    Ok(h)
}

/// Check the inputs every tank model shares, in this order: `radius` R and `liquid_mass` m_L
/// finite and > 0, the fill height ([`fill_depth`]) and the axial acceleration ([`axial`]);
/// returns `(R, h, m_L)`.
pub(crate) fn tank_inputs(radius: f64, fill_height: f64, liquid_mass: f64, axial_acceleration: f64) -> Result<(f64, f64, f64)> {
    let r = positive("the tank radius (m)", radius)?;
    let h = fill_depth(r, fill_height)?;
    let m_l = positive("the liquid mass (kg)", liquid_mass)?;
    axial(axial_acceleration)?;
    Ok((r, h, m_l))
}

/// The fill height `h = f H` (m) of an upright cylinder of height `tank_height` H holding the
/// `fill_fraction` f of its height, f in (0, 1): a full tank (f = 1) has no free surface and
/// does not slosh (its liquid moves with the tank: a fixed mass), so it is refused, as the
/// sphere's ([`crate::model::slosh_sphere::sphere_slosh`]).
pub fn cylinder_fill_height(tank_height: f64, fill_fraction: f64) -> Result<f64> {
    let big_h = positive("the tank height (m)", tank_height)?;
    if !(fill_fraction.is_finite() && fill_fraction > 0.0 && fill_fraction <= 1.0) {
        return Err(SpacearmError::argument(format!("the fill fraction of a cylindrical tank must be in (0, 1) (of its height), got {fill_fraction}")));
    }
    if fill_fraction == 1.0 {
        return Err(SpacearmError::argument(
            "the fill fraction of a cylindrical tank must be below 1: a full tank has no free surface and does not slosh (model its \
             liquid as a fixed mass)"
                .to_string(),
        ));
    }
    Ok(fill_fraction * big_h)
}

/// The equivalent mechanical model of the liquid in an upright flat-bottomed cylinder of
/// `radius` R, filled to `fill_height` h with `liquid_mass` m_L, in the axial acceleration `a`,
/// with `n_modes` modes (1 to 5; module docs).
pub fn cylinder_slosh(radius: f64, fill_height: f64, liquid_mass: f64, axial_acceleration: f64, n_modes: usize) -> Result<TankSlosh> {
    let (r, h, m_l) = tank_inputs(radius, fill_height, liquid_mass, axial_acceleration)?;
    if !(1..=BESSEL_J1_PRIME_ZEROS.len()).contains(&n_modes) {
        return Err(SpacearmError::argument(format!("the number of slosh modes must be 1 to {}, got {n_modes}", BESSEL_J1_PRIME_ZEROS.len())));
    }
    let a = axial_acceleration;
    let modes: Vec<SloshMode> = BESSEL_J1_PRIME_ZEROS[..n_modes]
        .iter()
        .map(|&xi| {
            let t = (xi * h / r).tanh();
            let mass = m_l * 2.0 * t / (xi * (xi * xi - 1.0) * h / r);
            let w2 = a / r * xi * t;
            SloshMode::from_frequency_squared(mass, 0.5 * h - 2.0 * r / xi * (0.5 * xi * h / r).tanh(), w2, a)
        })
        .collect();
    TankSlosh::from_modes(m_l, h, r, a, 0.5 * h, modes)?.with_lid_inertia(cylinder_lid_inertia(r, h, m_l))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_zero_is_that_of_j1_prime() {
        // J1'(x) = J0(x) − J1(x)/x; J0, J1 by their power series (converges fast for x < 3).
        let series = |x: f64, n: i32| {
            let (mut term, mut sum) = ((x / 2.0).powi(n) / (1..=n).map(f64::from).product::<f64>(), 0.0);
            for k in 0..40 {
                sum += term;
                term *= -(x * x / 4.0) / (f64::from(k + 1) * f64::from(k + 1 + n));
            }
            sum
        };
        let x = BESSEL_J1_PRIME_ZEROS[0];
        assert!((series(x, 0) - series(x, 1) / x).abs() < 1e-13);
    }

    #[test]
    fn deep_and_shallow_limits() {
        // Deep: m1/mL → 2R/(ξ(ξ²−1)h), ω² → a ξ/R, the mass 2R/ξ below the surface (H_y/P of
        // a mode decaying as e^{ξ(z−h)/R}: the wall's lever R/ξ below the surface, and as much
        // again from the bottom and surface terms).
        let (r, a, m) = (0.5, 0.2, 100.0);
        let deep = cylinder_slosh(r, 20.0, m, a, 1).unwrap();
        let xi = BESSEL_J1_PRIME_ZEROS[0];
        let md = &deep.modes[0];
        assert!((md.mass / m - 2.0 * r / (xi * (xi * xi - 1.0) * 20.0)).abs() < 1e-12);
        assert!((md.frequency.powi(2) - a * xi / r).abs() < 1e-12);
        assert!((md.height - (10.0 - 2.0 * r / xi)).abs() < 1e-12);
        // Shallow: tanh(x) → x, the first mode's mass fraction → 2/(ξ²−1) = 0.837 (Σₙ 2/(ξₙ²−1) = 1:
        // all of a shallow layer sloshes).
        let shallow = cylinder_slosh(r, 1e-4, m, a, 1).unwrap();
        assert!((shallow.modes[0].mass / m - 2.0 / (xi * xi - 1.0)).abs() < 1e-6);
        // ... at the bottom (ℓ → −h/2: the bottom pressure's moment dominates a thin layer's).
        assert!((shallow.modes[0].height + 0.5e-4).abs() < 1e-10);
        for t in [&deep, &shallow] {
            let total = t.fixed_mass + t.modes.iter().map(|m| m.mass).sum::<f64>();
            assert!((total - m).abs() < 1e-12);
            let moment = t.fixed_mass * t.fixed_height + t.modes.iter().map(|m| m.mass * m.height).sum::<f64>();
            assert!(moment.abs() < 1e-12);
        }
        assert!(cylinder_slosh(r, 1.0, m, 0.0, 1).is_err());
    }

    #[test]
    fn lid_inertia_limits_and_mcmahon_zeros() {
        // McMahon's expansion continues the table: at n = 5 it is within 3e-6 of the zero.
        let beta = 4.75 * std::f64::consts::PI;
        let b8 = 8.0 * beta;
        assert!((beta - 7.0 / b8 - 4.0 * 431.0 / (3.0 * b8.powi(3)) - BESSEL_J1_PRIME_ZEROS[4]).abs() < 3e-6);
        // Deep and shallow fills: the rigid liquid's m (R²/4 + h²/12), to O(R/h) and O(h²).
        let rigid = |r: f64, h: f64| r * r / 4.0 + h * h / 12.0;
        assert!((cylinder_lid_inertia(1.0, 200.0, 1.0) / rigid(1.0, 200.0) - 1.0).abs() < 1e-3);
        let shallow = cylinder_lid_inertia(1.0, 1e-3, 1.0);
        assert!((shallow - (0.25 - 0.25e-6)).abs() < 1e-9, "{shallow}");
        // The cylinder model has it, non-negative; the modes and m₀ hold less than J.
        let t = cylinder_slosh(0.5, 0.5, 100.0, 0.2, 3).unwrap();
        assert!(t.fixed_inertia.unwrap() > 0.0);
    }
}
