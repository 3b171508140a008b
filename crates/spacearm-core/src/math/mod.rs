//! Mathematics with no knowledge of the model: spatial (6-D) vectors and inertias, rotations
//! and quaternions, the scalar type the algorithms are generic over (and a recording scalar, [`tape`]), damped least squares, the Wilson interval of a success rate ([`wilson`]), and the time integrators
//! (RK4, DOPRI5) of the state on the quaternion manifold ([`integrate`]).
//!
//! Imports: [`crate::error`] only (the bottom folder). The allowed direction of imports across
//! the crate is `error ← admission ← math ← model ← io, algorithms ← gjm ← derivatives, taped ←
//! scenario ← analysis ← control ← sim` (docs/architecture.md, "The core's layers";
//! tests/test_core_module_graph.py).

pub mod dls;
pub mod integrate;
pub mod rotations;
pub mod scalar;
pub mod spatial;
pub mod tape;
pub mod wilson;
