//! Collision detection on a model's geometry (docs/contact.md): which pairs of collision shapes
//! touch or come within a margin, with the contact points, the normal and the signed distance.
//! The narrow phase is parry's (the rapier project's collision crate, `parry3d-f64`), not
//! hand-written distance code: shapes.rs turns the model's geometries into parry shapes placed on
//! their bodies, detect.rs finds the contacts of a state, compliant.rs is the compliant contact
//! law that turns a contact into forces on its two bodies (the simulation's plant applies them:
//! sim/contact.rs). Impulses and topology events are not here.

pub mod compliant;
pub mod detect;
pub mod shapes;

pub use compliant::{ContactForce, ContactLaw, NormalLaw};
pub use detect::{contacts, Contact, PairFilter};
pub use shapes::CollisionShapes;
