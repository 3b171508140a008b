//! Collision detection on a model's geometry (docs/contact.md): which pairs of collision shapes
//! touch or come within a margin, with the contact points, the normal and the signed distance.
//! The narrow phase is parry's (the rapier project's collision crate, `parry3d-f64`), not
//! hand-written distance code: shapes.rs turns the model's geometries into parry shapes placed on
//! their bodies, detect.rs finds the contacts of a state, compliant.rs is the compliant contact
//! law that turns a contact into forces on its two bodies (the simulation's plant applies them:
//! sim/contact.rs). The rigid frictional impact: delassus.rs builds the contact Jacobian and the
//! Delassus operator of a set of point contacts, coulomb_cone.rs states the Coulomb cone problem,
//! admm.rs and pgs.rs solve it, impact.rs turns the impulses into the velocity jump. Topology
//! events are not here.

pub mod admm;
pub mod compliant;
pub mod coulomb_cone;
pub mod delassus;
pub mod detect;
pub mod impact;
pub mod pgs;
pub mod shapes;

pub use admm::{ConeSolution, SolverSettings};
pub use compliant::{ContactForce, ContactLaw, NormalLaw};
pub use delassus::{contact_frame, ContactPoint, Delassus};
pub use detect::{contacts, Contact, PairFilter};
pub use impact::{rigid_impact, ImpactSolver, ImpactSpec, RigidImpact};
pub use shapes::CollisionShapes;
