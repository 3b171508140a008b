//! The native simulation loop: time integrators on the quaternion manifold ([`integrate`]),
//! maneuvering modes ([`modes`]), actuator limits ([`actuators`]), reference trajectories
//! ([`reference`]) and the loop with its records ([`simulate`]); docs/simulation-core.md.
//!
//! Imports: everything below it (`math`, `model`, `algorithms`, `gjm`) and the controllers of
//! [`crate::control`], which in turn use [`modes`], [`actuators`] and [`reference`].

pub mod actuators;
pub mod integrate;
pub mod modes;
pub mod reference;
pub mod simulate;
