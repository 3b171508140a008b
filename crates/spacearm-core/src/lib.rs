//! # spacearm-core
//!
//! Equations of motion of spacecraft-manipulator systems in the Generalized Jacobian Matrix
//! formulation (Umetani & Yoshida 1989; Wilde, Kwok Choon, Grompone & Romano 2018, "Equations
//! of Motion of Free-Floating Spacecraft-Manipulator Systems: An Engineer's Tutorial", Front.
//! Robot. AI 5:41 — "the paper" in these docs, cited by equation number).
//!
//! Conventions (DESIGN.md §1, kept by every function): SI units; every vector in the inertial
//! frame 𝒥 unless its name says otherwise; configuration `x = [r0, quat0 [x,y,z,w], q]`;
//! generalized velocity `u = [v0, ω0, q̇]` with `v0` the base CM velocity and `ω0` the base
//! angular velocity, both in 𝒥; generalized force `f = [F0, N0, τ]`; spatial vectors linear
//! first. EOM: `H(x) u̇ + c(x, u) = f + Jᵀ w_ext`.
//!
//! Layout: [`Model`] (constant) and [`Data`] (workspace) as in Pinocchio; one algorithm per
//! module: [`kinematics`], [`inertia`] (paper form), [`crba`], [`rnea`], [`aba`], [`gjm`],
//! [`momentum`], [`dynamics`]; model input in [`model`]. Simulation: [`simulate`] (loop and
//! records), [`integrate`] (RK4, DOPRI5 on the quaternion manifold), [`modes`], [`actuators`],
//! [`control`], [`reference`].

pub mod aba;
pub mod analysis;
pub mod actuators;
pub mod body;
pub mod control;
pub mod crba;
pub mod data;
pub mod derivatives;
pub mod dh;
pub mod dynamics;
pub mod error;
pub mod gjm;
pub mod inertia;
pub mod integrate;
pub mod joint;
pub mod kinematics;
pub mod model;
pub mod model_file;
pub mod modes;
pub mod momentum;
pub mod presets;
pub mod reference;
pub mod rnea;
pub mod simulate;
pub mod scalar;
pub mod spatial;
pub mod wrench;

pub use data::{Data, DataT};
pub use error::{Result, SpacearmError};
pub use joint::{JointLimits, JointType};
pub use model::{LinkSpec, Model, ModelBuilder};
pub use wrench::ExternalWrench;
