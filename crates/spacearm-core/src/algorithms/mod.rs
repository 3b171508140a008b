//! The rigid-body algorithms on one [`crate::model::Model`], each a free function
//! `algo(&model, &mut data, x, ...)` leaving its results in [`crate::model::Data`]:
//! forward kinematics and Jacobians ([`kinematics`]), impulse dynamics ([`impulse`]), forward
//! dynamics under constraints and the loop closure ([`constrained`]), the paper-form inertia blocks
//! ([`inertia`], eqs. 27–36), CRBA ([`crba`]), RNEA ([`rnea`]), ABA ([`aba`]), forward
//! dynamics through `H` ([`dynamics`]), momentum and energy ([`momentum`]), the joints' springs and dampers ([`passive`]) and external
//! wrenches ([`wrench`]).
//!
//! Imports: [`crate::math`], [`crate::model`], [`crate::error`] and [`crate::admission`].

pub mod aba;
pub mod constrained;
pub mod crba;
pub mod dynamics;
pub mod impulse;
pub mod inertia;
pub mod kinematics;
pub mod momentum;
pub mod passive;
pub mod rnea;
pub mod wrench;
