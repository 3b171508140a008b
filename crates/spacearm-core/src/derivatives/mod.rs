//! Exact derivatives of the equations of motion: `∂H/∂x`, `Ḣ`, `∂H*/∂q`, `Ḣ*`, `∂J*/∂x`,
//! `J̇*`, the Jacobians of forward dynamics and the linearization `(A, B)` of the state
//! equation (docs/derivatives.md).
//!
//! # Route: forward-mode automatic differentiation of the one generic implementation
//!
//! Forward kinematics, CRBA, RNEA and the GJM reduction are generic over the scalar
//! ([`crate::math::scalar::Real`]). Run on dual numbers `a + Σ_l b_l ε_l` (`ε_l ε_m = 0`, crate
//! `num-dual`) whose `ε` parts are seeded with a direction of the inputs, the very same code
//! returns, next to every value, its exact directional derivatives — no truncation error, no
//! step size, no second copy of an algorithm to keep in sync. Several directions travel
//! together in one pass ([`CHUNK`] lanes of `ε`); a directional derivative such as `Ḣ` needs a
//! single lane ([`num_dual::Dual64`]).
//!
//! # Tangent coordinates (conventions contract)
//!
//! The base attitude is a quasi-coordinate, so derivatives with respect to the configuration
//! are taken in the tangent space of dimension `6+N`:
//! `δx = [δr0 (3), δθ (3), δq (N)]`, where `δθ` is a rotation increment about the axes of the
//! inertial frame 𝒥: `R0 ← exp(δθ̃) R0` (a left, world-frame perturbation). With this choice
//! the time derivative of the configuration in tangent coordinates is exactly the generalized
//! velocity `u = [v0, ω0, q̇]` (because `Ṙ0 = ω̃0 R0` with `ω0` in 𝒥), so
//! `Ẋ = Σ_k ∂X/∂x_k u_k` for every quantity `X(x)`.
//!
//! Every quantity here is referred to the base CM, so it does not depend on `r0`: the partial
//! derivatives with respect to `δr0` are exactly zero (translation invariance; there is no
//! gravity in orbit) and are returned as zeros without being computed.
//!
//! In the dual evaluation the attitude increment enters as `R0 ← (E + δθ̃) R0`, which equals
//! `exp(δθ̃) R0` to first order — all that a first derivative sees — and avoids differentiating
//! the exponential at `δθ = 0`.
//!
//! The dual-number evaluation the files share (the seeding of directions, the workspaces) is
//! `dual.rs`; this file declares the files and re-exports the public names.
//!
//! Imports: `math`, `model`, `algorithms`, [`crate::gjm`], `error` and `admission`.

mod dense;
mod dual;
mod forward_dynamics;
mod generalized;
mod mass_matrix;
pub mod rnea_partials;

pub use dual::{loop_closure_bias, ClosureBiasWork, DerivativeData, DualChunk, CHUNK};
pub use forward_dynamics::{
    forward_dynamics_derivatives, forward_dynamics_derivatives_with, inverse_dynamics_partials, linearize, linearize_with, DerivativeMethod,
    LinearizationInputs,
};
pub use generalized::{
    generalized_inertia_derivative, generalized_inertia_partials, generalized_jacobian_derivative, generalized_jacobian_partials,
};
pub use mass_matrix::{mass_matrix_derivative, mass_matrix_partials};
