//! Controllers that run natively inside the integration loop (no call into Python per step).
//!
//! A [`Controller`] is evaluated at every stage of the integrator (a continuous-time control
//! law, so the right-hand side stays smooth and the integrators keep their order). It receives
//! the plant's state `(t, x, u)` and writes a [`Command`]: joint torques `τ` (N) and a base
//! wrench `[F0; N0]` (in 𝒥, at the base CM). The simulator then applies the maneuvering mode's
//! mask and the actuator limits ([`crate::scenario::modes`], [`crate::scenario::actuators`]).
//!
//! Joint degrees of freedom are split into the **arm** joints and the **reaction wheels**
//! ([`ControlContext`]): arm controllers (joint PD, computed torque, resolved motion rate) act
//! on the arm joints only, and their references have one entry per arm joint; base controllers
//! (attitude control) drive the wheels or the base wrench. [`Combined`] runs a base controller
//! first and then an arm controller, which sees (and, for computed torque, compensates) what the
//! base controller commanded.
//!
//! Each controller keeps its own [`Model`](crate::model::Model) and [`Data`](crate::model::Data) (a computed-torque controller may use a
//! model that differs from the plant), so controllers never disturb the plant's workspace.
//!
//! The interface (the trait, the command, the context and the helpers) is [`controller`]; this
//! file only declares the controllers' files and re-exports their public types.
//!
//! Imports: everything below it (`math`, `model`, `algorithms`, `gjm`), the maneuvering
//! modes, actuator limits and references of [`crate::scenario`], the resolved-motion-rate solver
//! and task rows of [`crate::analysis`] (`analysis/rmrc_solver.rs`, [`crate::analysis::Task`]) and
//! the optimal-control problems and solver of [`crate::optimal`] (the [`mpc`] law);
//! nothing of [`crate::sim`], which runs the controllers.

pub mod attitude;
pub mod cmg_dither;
pub mod cmg_jacobian;
pub mod cmg_null_motion;
pub mod cmg_sr_inverse;
pub mod cmg_steering;
pub mod cmg_unloading;
pub mod computed_torque;
pub mod controller;
pub mod coordinated;
pub mod joint_tracking;
pub mod mismatch;
pub mod momentum_damping;
pub mod mpc;
pub mod pd;
pub mod rmrc;
pub mod shaping;
pub mod spec;
pub mod thrusters;
pub mod vscmg_steering;

pub use attitude::{AttitudeControl, LvlhReference};
pub use cmg_steering::CmgSteering;
pub use computed_torque::{ComputedTorque, PassiveTreatment};
pub use controller::{
    arm_dofs, broadcast_gains, cholesky_solve_in_place, positive, Combined, Command, ControlContext, Controller, GoalReport, SolveReport,
    TrackingKind, ZeroTorque, CONTROLLER_LABELS, GOAL_TOLERANCE,
};
pub use coordinated::{CoordinatedFlying, CoordinatedGains};
pub use momentum_damping::{JointTorqueLimit, MomentumDamping};
pub use mpc::ModelPredictive;
pub use joint_tracking::{JointLaw, JointTracker};
pub use pd::JointPd;
pub use rmrc::ResolvedMotionRate;
pub use shaping::{InputShaper, ShaperKind};
pub use thrusters::BaseThrusterControl;
