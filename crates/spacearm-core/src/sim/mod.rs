//! The native simulation loop: time integrators on the quaternion manifold ([`integrate`]),
//! maneuvering modes ([`modes`]), actuator limits ([`actuators`]), reference trajectories
//! ([`reference`]), the loop ([`simulate`]) with its records ([`record`]), the same loop one
//! RK4 step at a time ([`stepper`]), many steppers one step each in one call ([`batch_stepper`]), the longest RK4 step the fastest mode allows ([`step_limit`]), many runs on threads ([`rollout`]) and the soft capture of a
//! free target by a wrist impedance ([`soft_capture`]) and closed chains under a loop closure
//! ([`closed_chain`]); the conditions that stop a run early ([`events`]);
//! docs/simulation-core.md.
//!
//! Imports: everything below it (`math`, `model`, `algorithms`, `gjm`) and the controllers of
//! [`crate::control`], which in turn use [`modes`], [`actuators`] and [`reference`].

pub mod actuators;
pub mod batch_stepper;
pub mod closed_chain;
pub mod events;
pub mod free_body;
pub mod integrate;
pub mod modes;
pub mod orbit;
pub mod record;
pub mod reference;
pub mod rollout;
pub mod simulate;
pub mod soft_capture;
pub mod step_limit;
pub mod stepper;
