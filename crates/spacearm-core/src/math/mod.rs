//! Mathematics with no knowledge of the model: spatial (6-D) vectors and inertias, rotations
//! and quaternions, and the scalar type the algorithms are generic over.
//!
//! Imports: nothing else from this crate (the bottom layer). The allowed direction of imports
//! across the crate is `math ← model ← io, algorithms ← gjm, derivatives ← sim, control,
//! analysis` (docs/architecture.md).

pub mod rotations;
pub mod scalar;
pub mod spatial;
