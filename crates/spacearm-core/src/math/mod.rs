//! Mathematics with no knowledge of the model: spatial (6-D) vectors and inertias, rotations
//! and quaternions, the scalar type the algorithms are generic over (and a recording scalar, [`tape`]), damped least squares, and the time integrators
//! (RK4, DOPRI5) of the state on the quaternion manifold ([`integrate`]).
//!
//! Imports: nothing else from this crate (the bottom layer). The allowed direction of imports
//! across the crate is `math ← model ← io, algorithms ← gjm, derivatives ← sim, control,
//! analysis` (docs/architecture.md).

pub mod dls;
pub mod integrate;
pub mod rotations;
pub mod scalar;
pub mod spatial;
pub mod tape;
