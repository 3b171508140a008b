//! Collision detection on a model's geometry (docs/contact.md): which pairs of collision shapes
//! touch or come within a margin, with the contact points, the normal and the signed distance.
//! The narrow phase is parry's (the rapier project's collision crate, `parry3d-f64`), not
//! hand-written distance code: shapes.rs turns the model's geometries into parry shapes placed on
//! their bodies, detect.rs finds the contacts of a state. What contact does with them (forces,
//! impulses, events) is not here.

pub mod detect;
pub mod shapes;

pub use detect::{contacts, Contact, PairFilter};
pub use shapes::CollisionShapes;
