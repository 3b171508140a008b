//! What a run is set in, shared by the simulation loop and the controllers: the maneuvering
//! modes ([`modes`]), the actuator limits ([`actuators`]), the reference trajectories
//! ([`reference`](mod@reference)), the orbit and its gravity gradient ([`orbit`]) and free rigid bodies such as
//! a capture target ([`free_body`]); docs/simulation-core.md, docs/orbit.md.
//!
//! Imports: everything below it (`math`, `model`, `algorithms`); nothing of `analysis`,
//! `control` or `sim`, which all use it.

pub mod actuators;
pub mod free_body;
pub mod modes;
pub mod orbit;
pub mod reference;
