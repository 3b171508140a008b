//! # spacearm-core
//!
//! Equations of motion of spacecraft-manipulator systems in the Generalized Jacobian Matrix
//! formulation (Umetani & Yoshida 1989; Wilde, Kwok Choon, Grompone & Romano 2018, "Equations
//! of Motion of Free-Floating Spacecraft-Manipulator Systems: An Engineer's Tutorial", Front.
//! Robot. AI 5:41 — "the paper" in these docs, cited by equation number).
//!
//! Conventions (docs/conventions.md, kept by every function): SI units; every vector in the
//! inertial frame 𝒥 unless its name says otherwise; configuration `x = [r0, quat0 [x,y,z,w], q]`;
//! generalized velocity `u = [v0, ω0, q̇]` with `v0` the base CM velocity and `ω0` the base
//! angular velocity, both in 𝒥; generalized force `f = [F0, N0, τ]`; spatial vectors linear
//! first. EOM: `H(x) u̇ + c(x, u) = f + Jᵀ w_ext`.
//!
//! Layout (docs/architecture.md, "The core's layers"), each folder importing only from its own
//! files and those before it (with [`error`] and [`admission`] below all; checked by
//! tests/test_core_module_graph.py):
//!
//! * [`math`] — spatial vectors, rotations and quaternions, the scalar type, the time integrators;
//! * [`model`] — [`Model`] (constant, validated, built only by [`ModelBuilder`]) and [`Data`]
//!   (workspace), as in Pinocchio; mass properties, joints, presets;
//! * [`io`] — TOML model files and Denavit–Hartenberg tables, both through the builder;
//! * [`algorithms`] — kinematics, CRBA, RNEA, ABA, the paper-form inertia, momentum: free
//!   functions `algo(&model, &mut data, x, ...)`;
//! * [`gjm`] and [`derivatives`] — the generalized (reduced) dynamics `H*`, `c*`, `J*`, and
//!   their exact derivatives; beside `gjm`, [`collision`] — the contacts of a state between the
//!   model's collision shapes (parry's narrow phase);
//! * [`taped`] — the same algorithms recorded on tapes ([`math::tape`]) for replay on other
//!   systems' symbols (the CasADi functions of `spacearm.casadi`);
//! * [`scenario`] — what a run is set in: maneuvering modes, actuator limits, references, the
//!   orbit and free bodies;
//! * [`analysis`] — the singularity, workspace and redundancy analyses, the resolved-motion-rate
//!   solver;
//! * [`optimal`] — optimal control (beside `analysis`): the box-constrained FDDP solver on the RK4
//!   step and its exact Jacobians, the cost terms, the run description `ProblemSpec`;
//! * [`control`] — the controllers and their interface;
//! * [`sim`] — the simulation loop, which runs the controllers.

#![deny(missing_docs)]

pub mod admission;
pub mod algorithms;
pub mod collision;
pub mod analysis;
pub mod control;
pub mod derivatives;
pub mod error;
pub mod gjm;
pub mod io;
pub mod math;
pub mod model;
pub mod optimal;
pub mod scenario;
pub mod sim;
pub mod taped;

pub use algorithms::wrench::ExternalWrench;
pub use error::{ErrorKind, Result, SpacearmError};
pub use model::joint::{JointDynamics, JointLimits, JointType};
pub use model::{Data, DataT, Geometry, GeometryRole, GeometrySpec, LinkSpec, Model, ModelBuilder, Mount, Shape};
