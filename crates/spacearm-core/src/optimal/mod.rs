//! Optimal control on the core's dynamics and derivatives (docs/mpc.md): the feasibility-driven
//! differential dynamic programming (FDDP) solver of Mastalli et al. (2020, "Crocoddyl: An
//! Efficient and Versatile Framework for Multi-Contact Optimal Control", ICRA) with box
//! constraints on the controls (Tassa, Mansard & Todorov 2014, "Control-limited differential
//! dynamic programming", ICRA), on the RK4 step of the simulator and its exact Jacobians.
//!
//! One algorithm per file:
//!
//! * [`state`] — the state manifold `z = [x; u]`, its tangent space (the error state of the
//!   Riccati recursion), `⊕` and `⊖`;
//! * [`dynamics`] — the continuous dynamics `ż = F(z, c)` of a mode's controls and their Jacobian;
//! * [`discretization`] — the RK4 step and its Jacobians by the chain rule through the stages
//!   (and the choice of a problem's step, [`discretization::DiscretizationKind`]);
//! * [`euler`] — the semi-implicit Euler step and its Jacobians (one derivative evaluation);
//! * [`costs`] — the cost terms (state and joint tracking, base attitude, a point's position,
//!   control regularization) with their gradients and Gauss–Newton Hessians;
//! * [`shooting`] — the multiple-shooting problem the solver sees ([`shooting::ShootingProblem`]);
//! * [`problem`] — the run description [`problem::ProblemSpec`] and the robot's shooting problem;
//! * [`box_qp`] — the box-constrained QP of each knot (projected Newton);
//! * [`backward`] — the backward (Riccati) pass with the gaps;
//! * [`forward`] — the nonlinear forward rollout that closes the gaps;
//! * [`fddp`] — the solver loop: regularization, line search, stopping, the result.
//!
//! Imports: `error`, `math`, `model`, `algorithms`, `derivatives`, `scenario` (a layer above
//! `scenario`, below `control`, beside `analysis`; docs/architecture.md).

pub mod backward;
pub mod box_qp;
pub mod costs;
pub mod discretization;
pub mod dynamics;
pub mod euler;
pub mod fddp;
pub mod forward;
pub mod problem;
pub mod shooting;
pub mod state;

pub use fddp::{solve, SolverOptions, Solution, StopReason};
pub use problem::{ProblemSpec, RobotProblem};
