r"""The transcription: point-to-point maneuvers of a free-floating system by direct multiple
shooting, solved by IPOPT through CasADi (docs/optimal-control.md).

Unknowns: the state ``y_k = [x_k; u_k]`` and the joint torques ``tau_k`` at the knots
``t_k = k T / K`` (``k = 0..K``); the torque is linear between knots (a first-order hold), so
it is continuous and any fixed-step integrator reproduces the plan to its own order.
Constraints:

- ``y_0`` is the given initial state;
- continuity ``y_k+1 = Φ(y_k, tau_k, tau_k+1, T/K)``, ``Φ`` being ``substeps`` RK4 steps of the
  free-floating dynamics (no base wrench) with the quaternion renormalised
  ([`spacearm.casadi.rk4_step`][spacearm.casadi.rk4_step] with ``torque="linear"``);
- the point reaches ``target`` at ``t_K``;
- joint positions, speeds and torques within their bounds at every knot;
- optionally zero joint speeds at ``t_K`` (``rest_at_end``) and zero base angular velocity at
  ``t_K`` (``reactionless_end``: the arm ends moving, if at all, inside the reaction null space).

Objectives (both divided by ``T`` so that their size does not depend on the duration):

- ``"attitude"``: $\frac1T \sum_{k=1}^K \lVert\theta_k\rVert^2 \Delta t$ with $\theta_k = 2 \operatorname{vec}(\mathrm{quat}_k \otimes \mathrm{quat}_0^*)$ (for small
  angles the base rotation vector since $t_0$), plus ``effort_weight`` $\cdot \frac1T \sum_k \lVert\tau_k\rVert^2 \Delta t$
  so that the torques are defined where the attitude does not decide them;
- ``"effort"``: $\frac1T \sum_k \tfrac12 (\lVert\tau_k\rVert^2 + \lVert\tau_{k+1}\rVert^2) \Delta t$ (trapezoidal rule);

and with either, the torque-rate term ``smoothness_weight`` $\cdot \frac1T \sum_k \lVert\tau_{k+1} - \tau_k\rVert^2 / \Delta t$.

The K intervals share one shooting map: ``rk4_step`` expanded to ``SX`` (its RK4 stages
inlined) and mapped over the knots, so its derivatives are built once for one interval.
"""

from __future__ import annotations

import signal
import threading
import time

import numpy as np

from .._util.optional import require
from ..casadi import point_position, rk4_step
from ..errors import ArgumentError

#: The objectives of [`point_to_point`][spacearm.plan.point_to_point]: the base attitude excursion, or the
#: control effort (docs/optimal-control.md).
OBJECTIVES = ("attitude", "effort")
#: How IPOPT gets the Hessian of the Lagrangian: the objective's only, or the exact one.
HESSIANS = ("objective", "exact")


def _attitude_error(ca, quat, quat0: np.ndarray):
    """``2 vec(quat ⊗ quat0*)`` (3): the base rotation since ``quat0`` (≈ rotation vector)."""
    c = np.array([-quat0[0], -quat0[1], -quat0[2], quat0[3]])
    qv, qw = quat[0:3], quat[3]
    return 2.0 * (qw * c[:3] + c[3] * qv + ca.cross(qv, c[:3]))


class _Interrupts:
    """Ctrl-C during the solve: CasADi turns a ``KeyboardInterrupt`` raised inside IPOPT into a
    stop of the solver and a normal return (status ``NonIpopt_Exception_Thrown`` or
    ``User_Requested_Stop``). In the main thread, with Python's default SIGINT handler, this
    records the signal (and still raises inside, so that IPOPT stops at once), so that the solve
    can raise ``KeyboardInterrupt`` afterwards instead of returning a plan."""

    caught = False

    def __enter__(self):
        self._previous = None
        if threading.current_thread() is threading.main_thread() and signal.getsignal(signal.SIGINT) is signal.default_int_handler:
            self._previous = signal.signal(signal.SIGINT, self._handler)
        return self

    def _handler(self, signum, frame):
        self.caught = True
        raise KeyboardInterrupt

    def __exit__(self, *exc):
        if self._previous is not None:
            signal.signal(signal.SIGINT, self._previous)
        return False


def solve(robot, x0, u0, target, point, duration, nodes, substeps, objective, bounds, guess, rest_at_end, reactionless_end,
          effort_weight, max_iter, progress, hessian="objective", smoothness_weight=0.0):
    """Build and solve the NLP; returns a dict of the plan arrays and the solver's report."""
    if objective not in OBJECTIVES:
        raise ArgumentError(f"objective must be one of {OBJECTIVES}, got {objective!r}")
    if hessian not in HESSIANS:
        raise ArgumentError(f"hessian must be one of {HESSIANS}, got {hessian!r}")
    ca = require("casadi", "the planner (spacearm.plan)")
    n, nx, nu = robot.n_dof, robot.nx, robot.nu
    K = nodes
    dt = duration / K
    # One interval's shooting map on SX (the RK4 stages inlined), mapped over the K intervals:
    # its derivatives, and the Hessian of the Lagrangian, are built once for one interval.
    step = rk4_step(robot, substeps, torque="linear").expand().map(K)
    position = point_position(robot, point)

    opti = ca.Opti()
    X = opti.variable(nx, K + 1)
    U = opti.variable(nu, K + 1)
    TAU = opti.variable(n, K + 1)
    opti.subject_to(X[:, 0] == x0)
    opti.subject_to(U[:, 0] == u0)
    x_next, u_next = step(X[:, :K], U[:, :K], TAU[:, :K], TAU[:, 1:], ca.DM.zeros(6, K), ca.DM.ones(1, K) * dt)
    opti.subject_to(X[:, 1:] == x_next)
    opti.subject_to(U[:, 1:] == u_next)
    sq = ca.sum1(TAU ** 2)
    effort = ca.sum2(0.5 * (sq[:, :K] + sq[:, 1:])) * dt / duration
    if objective == "effort":
        cost = effort
    else:
        theta = ca.horzcat(*[_attitude_error(ca, X[3:7, k], x0[3:7]) for k in range(1, K + 1)])
        cost = ca.sumsqr(theta) * dt / duration + effort_weight * effort
    if smoothness_weight:
        cost += smoothness_weight * ca.sumsqr(TAU[:, 1:] - TAU[:, :K]) / (dt * duration)
    opti.minimize(cost)
    opti.subject_to(position(X[:, K]) == target)
    for j in range(n):
        q, qd = X[7 + j, 1:], U[6 + j, 1:]
        if np.isfinite(bounds.lower[j]):
            opti.subject_to(q >= bounds.lower[j])
        if np.isfinite(bounds.upper[j]):
            opti.subject_to(q <= bounds.upper[j])
        if np.isfinite(bounds.velocity[j]):
            opti.subject_to(opti.bounded(-bounds.velocity[j], qd, bounds.velocity[j]))
        if np.isfinite(bounds.effort[j]):
            opti.subject_to(opti.bounded(-bounds.effort[j], TAU[j, :], bounds.effort[j]))
    if rest_at_end:
        opti.subject_to(U[6:, K] == 0)
    if reactionless_end:
        opti.subject_to(U[3:6, K] == 0)

    x_guess, u_guess, tau_guess = guess
    opti.set_initial(X, x_guess.T)
    opti.set_initial(U, u_guess.T)
    opti.set_initial(TAU, tau_guess.T)
    options = {}
    if hessian == "objective":
        # The objective's exact Hessian, without the curvature of the shooting constraints (a
        # Gauss-Newton-type approximation; the objective is a sum of squares). The exact
        # Hessian of the constraints costs about twenty Jacobians per iteration through the
        # second derivatives of every RK4 stage, and buys no fewer iterations from the warm start.
        lam_f, lam_g = ca.MX.sym("lam_f"), ca.MX.sym("lam_g", opti.ng)
        hess = ca.triu(lam_f * ca.hessian(cost, opti.x)[0])
        options["hess_lag"] = ca.Function("nlp_hess_l", [opti.x, opti.p, lam_f, lam_g], [hess], ["x", "p", "lam_f", "lam_g"], ["hess_gamma_x_x"])
    opti.solver("ipopt", {**options, "print_time": False, "ipopt.print_level": 0, "ipopt.sb": "yes", "ipopt.max_iter": int(max_iter),
                          "ipopt.tol": 1e-9, "ipopt.constr_viol_tol": 1e-10})
    raised = []  # an exception of the progress callback, re-raised once IPOPT has stopped

    def callback(i):
        try:
            progress(int(i), float(opti.debug.value(cost)))
        except BaseException as exc:
            raised.append(exc)
            raise

    if progress is not None:
        opti.callback(callback)
    start = time.perf_counter()
    with _Interrupts() as interrupts:
        try:
            sol = opti.solve()
            value, stats = sol.value, sol.stats()
        except RuntimeError:  # IPOPT stopped without success: keep its last iterate and report it
            value, stats = opti.debug.value, opti.debug.stats()
    if interrupts.caught:
        raise KeyboardInterrupt("the plan was interrupted during the IPOPT solve")
    if raised:
        raise raised[0]
    elapsed = time.perf_counter() - start
    x = np.ascontiguousarray(np.atleast_2d(np.array(value(X))).T)
    # Unit quaternions at the knots: exact to the constraint tolerance after a successful
    # solve; for an unconverged iterate this keeps every state a valid configuration.
    x[:, 3:7] /= np.linalg.norm(x[:, 3:7], axis=1, keepdims=True)
    u = np.ascontiguousarray(np.atleast_2d(np.array(value(U))).T)
    tau = np.ascontiguousarray(np.array(value(TAU)).reshape(n, K + 1).T)
    return {
        "x": x,
        "u": u,
        "tau": tau,
        "status": str(stats.get("return_status", "unknown")),
        "solver_success": bool(stats.get("success", False)),
        "iterations": int(stats.get("iter_count", -1)),
        "cost": float(value(cost)),
        "solve_time": elapsed,
    }
