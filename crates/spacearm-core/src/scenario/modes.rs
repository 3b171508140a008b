//! The five maneuvering modes (paper Table 1; docs/physics.md): which components of the base
//! wrench `F_b = [F0; N0]` an actuator may apply, and which momenta therefore stay constant.
//!
//! | mode | base wrench applied | conserved |
//! | --- | --- | --- |
//! | floating | none | `P`, `L_origin` (and the energy with zero joint torques) |
//! | rotation-floating | none (reaction wheels are internal joints) | `P`, `L_origin` |
//! | rotation-flying | torque only: `[0; N0]` | `P` |
//! | translation-flying | force through the system CM: `[F0; (r_g − r0) × F0]` | `L_com` |
//! | flying | full `[F0; N0]` | none |
//!
//! In translation-flying the force is applied along a line through the system CM, so it has no
//! moment about the system CM and the angular momentum about the system CM is conserved; as a
//! wrench at the base CM (the reference point of `F_b`) that is the force `F0` plus the couple
//! `(r_g − r0) × F0`. Components a mode does not allow are dropped before the wrench reaches
//! the dynamics; the simulator reports how much was dropped.

use nalgebra::{Vector3, Vector6};

/// A maneuvering mode. As data (a run description, [`crate::sim::options::RunSpec`]) it is its
/// name ([`Mode::NAMES`]), read through [`Mode::from_name`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "String", into = "&'static str")]
pub enum Mode {
    /// No base actuation: `F_b = 0`; `P` and `L` conserved.
    Floating,
    /// No external base actuation; the attitude is held by reaction wheels (internal joint
    /// torques), so `P` and `L` (including the wheels) are conserved.
    RotationFloating,
    /// External torque only (thruster couples): `F_b = [0; N0]`; `P` conserved.
    RotationFlying,
    /// External force only, through the system CM: `F_b = [F0; (r_g − r0) × F0]`; the angular
    /// momentum about the system CM is conserved.
    TranslationFlying,
    /// Full base wrench: nothing conserved.
    Flying,
}

/// A quantity a mode conserves (names as in the simulation records).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Conserved {
    /// Linear momentum `P`.
    LinearMomentum,
    /// Angular momentum about the origin of 𝒥.
    AngularMomentumOrigin,
    /// Angular momentum about the system CM.
    AngularMomentumCom,
    /// Mechanical energy, kinetic plus the joint springs' (only with zero joint torques, no base
    /// wrench and no joint damper).
    Energy,
}

impl Conserved {
    /// Record name: `"P"`, `"L_origin"`, `"L_com"`, `"energy"`.
    pub fn name(self) -> &'static str {
        match self {
            Conserved::LinearMomentum => "P",
            Conserved::AngularMomentumOrigin => "L_origin",
            Conserved::AngularMomentumCom => "L_com",
            Conserved::Energy => "energy",
        }
    }
}

crate::error::named_by!(
    Mode,
    "mode",
    [
        Floating = "floating",
        RotationFloating = "rotation-floating",
        RotationFlying = "rotation-flying",
        TranslationFlying = "translation-flying",
        Flying = "flying",
    ]
);

impl Mode {
    /// Whether an external base force `F0` may be applied.
    pub fn allows_force(self) -> bool {
        matches!(self, Mode::TranslationFlying | Mode::Flying)
    }

    /// Whether an external base torque `N0` may be commanded (in translation-flying the couple
    /// `(r_g − r0) × F0` follows from the force and is not commanded).
    pub fn allows_torque(self) -> bool {
        matches!(self, Mode::RotationFlying | Mode::Flying)
    }

    /// The quantities the mode conserves; `torque_free` (no joint torques, no base wrench at
    /// all) adds the kinetic energy in the floating modes.
    pub fn conserved(self, torque_free: bool) -> Vec<Conserved> {
        use Conserved::*;
        match self {
            Mode::Floating | Mode::RotationFloating if torque_free => vec![LinearMomentum, AngularMomentumOrigin, Energy],
            Mode::Floating | Mode::RotationFloating => vec![LinearMomentum, AngularMomentumOrigin],
            Mode::RotationFlying => vec![LinearMomentum],
            Mode::TranslationFlying => vec![AngularMomentumCom],
            Mode::Flying => vec![],
        }
    }

    /// Keep the components of a commanded base wrench `[F0; N0]` the mode allows; returns
    /// `(kept, dropped)` with `kept + dropped = commanded`. The kept force of translation-flying
    /// still has to be moved to the system CM by [`Mode::wrench_at_base`].
    pub fn mask(self, commanded: &Vector6<f64>) -> (Vector6<f64>, Vector6<f64>) {
        let mut kept = *commanded;
        if !self.allows_force() {
            kept.fixed_rows_mut::<3>(0).fill(0.0);
        }
        if !self.allows_torque() {
            kept.fixed_rows_mut::<3>(3).fill(0.0);
        }
        (kept, commanded - kept)
    }

    /// The wrench at the base CM (the reference point of `F_b`) that an allowed wrench `kept`
    /// amounts to: unchanged, except in translation-flying where the force acts through the
    /// system CM at `r_g = r0 + base_to_com`, adding the couple `(r_g − r0) × F0`.
    pub fn wrench_at_base(self, kept: &Vector6<f64>, base_to_com: &Vector3<f64>) -> Vector6<f64> {
        match self {
            Mode::TranslationFlying => {
                let f = kept.fixed_rows::<3>(0).into_owned();
                let n = base_to_com.cross(&f);
                Vector6::new(f.x, f.y, f.z, n.x, n.y, n.z)
            }
            _ => *kept,
        }
    }

    /// [`Mode::mask`] then [`Mode::wrench_at_base`]: `(applied at the base CM, dropped)`.
    pub fn applied_wrench(self, commanded: &Vector6<f64>, base_to_com: &Vector3<f64>) -> (Vector6<f64>, Vector6<f64>) {
        let (kept, dropped) = self.mask(commanded);
        (self.wrench_at_base(&kept, base_to_com), dropped)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::SpacearmError;

    #[test]
    fn names_round_trip_and_bad_names_are_argument_errors() {
        for name in Mode::NAMES {
            assert_eq!(Mode::from_name(name).unwrap().name(), name);
        }
        assert!(matches!(Mode::from_name("hovering"), Err(SpacearmError::InvalidArgument(_))));
    }

    #[test]
    fn masks_keep_exactly_the_allowed_components() {
        let w = Vector6::new(1.0, 2.0, 3.0, 4.0, 5.0, 6.0);
        let r = Vector3::new(0.3, -0.2, 0.5);
        let expect = |m: Mode, f: bool, n: bool| {
            let (applied, dropped) = m.applied_wrench(&w, &r);
            for i in 0..3 {
                assert_eq!(dropped[i], if f { 0.0 } else { w[i] }, "{m:?} force {i}");
                assert_eq!(dropped[3 + i], if n { 0.0 } else { w[3 + i] }, "{m:?} torque {i}");
                assert_eq!(applied[i], if f { w[i] } else { 0.0 });
            }
            applied
        };
        assert_eq!(expect(Mode::Floating, false, false), Vector6::zeros());
        assert_eq!(expect(Mode::RotationFloating, false, false), Vector6::zeros());
        let rf = expect(Mode::RotationFlying, false, true);
        assert_eq!(rf.fixed_rows::<3>(3).into_owned(), Vector3::new(4.0, 5.0, 6.0));
        assert_eq!(expect(Mode::Flying, true, true), w);
        // Translation-flying: the couple is r_0g × F, so the moment about the system CM,
        // N − r_0g × F, vanishes.
        let tf = expect(Mode::TranslationFlying, true, false);
        let f = Vector3::new(1.0, 2.0, 3.0);
        let n = tf.fixed_rows::<3>(3).into_owned();
        assert!((n - r.cross(&f)).norm() < 1e-15);
        assert!(n.norm() > 0.1);
    }
}
