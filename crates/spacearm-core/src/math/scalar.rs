//! The scalar type of the recursive algorithms.
//!
//! Forward kinematics, ABA, CRBA, RNEA, the GJM reduction, the point Jacobians and the momentum
//! sum are written once, generic over a scalar `T: Real`. With `T = f64` they are the ordinary
//! algorithms (the `Data` workspace is `DataT<f64>`); with `T` a dual number of the `num-dual`
//! crate they carry, alongside every value, its exact directional derivatives — which is how
//! [`crate::derivatives`] obtains `∂H/∂x`, `Ḣ`, `∂H*/∂q`, `J̇*` and the forward-dynamics
//! Jacobians to machine precision from the same code (forward-mode automatic differentiation);
//! with `T` the recording scalar [`crate::math::tape::Var`] they write the operations they
//! perform onto a tape, which `spacearm.casadi` replays on CasADi symbols ([`crate::taped`]).
//!
//! The model's constants stay `f64` and are converted with [`Real::c`] where they meet the
//! state; for `f64` that conversion is the identity and compiles away.

use nalgebra::RealField;
use num_dual::{Dual64, DualSVec64};

/// A real scalar the algorithms can run on: `f64`, or a dual number whose comparisons and
/// error messages use its real part.
pub trait Real: RealField + Copy {
    /// The `f64` constant `x` as this scalar (no derivative part).
    #[inline(always)]
    fn c(x: f64) -> Self {
        nalgebra::convert(x)
    }

    /// The value as `f64` (the real part of a dual number).
    fn value(self) -> f64;

    /// `true` if the value and every derivative part are exactly zero (so that a computation
    /// may take a shortcut without losing derivatives). For the recording scalar: only the
    /// constant zero (a structural zero), so that a shortcut never depends on the state.
    fn is_exactly_zero(self) -> bool;
}

impl Real for f64 {
    #[inline(always)]
    fn c(x: f64) -> Self {
        x
    }

    #[inline(always)]
    fn value(self) -> f64 {
        self
    }

    #[inline(always)]
    fn is_exactly_zero(self) -> bool {
        self == 0.0
    }
}

impl Real for Dual64 {
    #[inline(always)]
    fn value(self) -> f64 {
        self.re
    }

    #[inline]
    fn is_exactly_zero(self) -> bool {
        self.re == 0.0 && self.eps == 0.0
    }
}

impl<const K: usize> Real for DualSVec64<K> {
    #[inline(always)]
    fn value(self) -> f64 {
        self.re
    }

    #[inline]
    fn is_exactly_zero(self) -> bool {
        self.re == 0.0 && self.eps.unwrap_generic(nalgebra::Const::<K>, nalgebra::U1).iter().all(|e| *e == 0.0)
    }
}

/// A model's `f64` 3-vector as a vector of `T`.
#[inline(always)]
pub fn vector3<T: Real>(v: &nalgebra::Vector3<f64>) -> nalgebra::Vector3<T> {
    nalgebra::Vector3::new(T::c(v.x), T::c(v.y), T::c(v.z))
}

/// A model's `f64` 3×3 matrix as a matrix of `T`.
#[inline(always)]
pub fn matrix3<T: Real>(m: &nalgebra::Matrix3<f64>) -> nalgebra::Matrix3<T> {
    m.map(T::c)
}
