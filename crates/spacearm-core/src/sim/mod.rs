//! The native simulation loop: the loop ([`simulate`]) with its records ([`record`]), the same loop one
//! RK4 step at a time ([`stepper`]), many steppers one step each in one call ([`batch_stepper`]), the longest RK4 step the fastest mode allows ([`step_limit`]), many runs on threads ([`rollout`]) and the soft capture of a
//! free target by a wrist impedance ([`soft_capture`]) and closed chains under a loop closure
//! ([`closed_chain`]); compliant contact between the system's bodies ([`contact`], its onset located in RK4 steps by [`contact_onset`]), rigid contact by time stepping ([`rigid_contact`]) and the outcome of a grasp on contact read from a run's records ([`grasp_outcome`]); the capture mission, one run of phases over one ledger ([`capture`],
//! described by [`capture_spec`], its ledger [`capture_ledger`]); the conditions that stop a run early ([`stop`], watched by [`events`]);
//! docs/simulation-core.md.
//!
//! Imports: everything below it (`math` with its time integrators, `model`, `algorithms`, `gjm`,
//! `derivatives`, the run's setting in [`crate::scenario`]) and the controllers of
//! [`crate::control`]. The modules re-exported here keep their former paths
//! (`sim::modes`, `sim::integrate`, ...) working for the bindings.

pub mod batch_stepper;
pub mod capture;
pub mod capture_ledger;
pub mod capture_spec;
pub mod closed_chain;
pub(crate) mod closure;
pub mod contact;
pub(crate) mod contact_onset;
pub mod events;
pub(crate) mod free_target;
pub mod grasp_outcome;
pub mod options;
pub mod plant;
pub mod record;
pub mod result;
pub(crate) mod rigid_contact;
pub mod rollout;
pub mod run;
pub mod simulate;
pub mod soft_capture;
pub mod step_limit;
pub mod stop;
pub mod topology;
pub mod topology_spec;
pub mod stepper;

pub use crate::math::integrate;
pub use crate::scenario::{actuators, free_body, modes, orbit, reference};
