"""Two-arm grasps: a closed kinematic chain (:func:`simulate_closed_chain`).

When a second gripper also holds the captured target, the captured model (the target a payload
of the first gripper, :func:`~spacearm.capture.attach_target`) gains a loop: the frame of the
second gripper must keep its pose relative to the target. With ``J_c = J_b − J_a`` the difference
of the two frames' point Jacobians (6×(6+N), eqs. 104–108), the loop-closure constraint is
``J_c u = 0`` (both Jacobians taken at frame b's origin) and the dynamics become the index-1 system

    [ H    −J_cᵀ ] [ du ]   [ f − c                              ]
    [ J_c    0   ] [ λ  ] = [ −J̇_c u − 2α J_c u − α² e            ]

(``λ`` the constraint wrench, ``e = [p_a − p_b − d; θ]`` the pose error against the grasp, the
last two terms Baumgarte's drift stabilisation with rate ``α``). ``J̇_c u`` is the frames'
relative acceleration at zero ``du``, taken by a central difference of ``J_c`` along ``u``
(step 1e-6 s: error ~1e-12 relative). ``simulate`` takes no constraint, so this is integrated
here by classical fixed-step RK4 (:mod:`spacearm.capture._rk4`).
"""

from __future__ import annotations

from typing import Callable, NamedTuple, Optional

import numpy as np

from .._util.arrays import number, vector
from ..errors import ArgumentError, SimulationError, SingularError
from ..rotations import rotation_vector
from ._rk4 import rk4_step

__all__ = ["ClosedChainRun", "simulate_closed_chain"]


class ClosedChainRun(NamedTuple):
    t: np.ndarray  #: (T,)
    x: np.ndarray  #: (T, 7+N)
    u: np.ndarray  #: (T, 6+N)
    constraint_wrench: np.ndarray  #: (T, 6) λ: the wrench on frame b at its origin, [force; torque] in 𝒥 (body a gets −λ there)
    pose_error: np.ndarray  #: (T, 6) e = [position error (m); rotation error (rad)]


def simulate_closed_chain(robot, x0, u0, duration: float, point_a, point_b, *, dt: float = 1e-3, stabilization: float = 20.0,
                          torque: Optional[Callable[[float, np.ndarray, np.ndarray], np.ndarray]] = None) -> ClosedChainRun:
    """Integrate ``robot`` with the frames at ``point_a`` and ``point_b`` (each a point name, a
    body, or ``(body, offset)``) welded at their relative pose at ``x0``.

    ``u0`` must satisfy the velocity constraint (``J_c u0 = 0`` to 1e-9 of ``|u0|``; an
    ``ArgumentError`` otherwise). ``torque(t, x, u)`` gives the joint torques (default zero);
    the base is free. ``stabilization``: Baumgarte's rate ``α`` (1/s). RK4 with step ``dt``.
    """
    x0, u0 = vector(x0, "x0", robot.nx), vector(u0, "u0", robot.nu)
    duration, dt, alpha = number(duration, "duration"), number(dt, "dt"), number(stabilization, "stabilization")
    if not (duration > 0 and dt > 0 and alpha >= 0):
        raise ArgumentError(f"duration and dt must be > 0 and stabilization >= 0, got {duration}, {dt}, {alpha}")
    ba, oa = robot.resolve_point(point_a)
    bb, ob = robot.resolve_point(point_b)
    if ba == bb:
        raise ArgumentError("the two grasp frames are on the same body: no loop to close")
    n = robot.n_dof

    def frames(x):
        kin = robot.forward_kinematics(x)
        return (robot.point_position(x, (ba, oa)), kin.body_to_world[ba], robot.point_position(x, (bb, ob)), kin.body_to_world[bb])

    pa, Ra, pb, Rb = frames(x0)
    d0 = Ra.T @ (pb - pa)  # b's origin in a's frame, and b's attitude relative to a, at the grasp
    rel0 = Ra.T @ Rb

    def error(x):
        pa, Ra, pb, Rb = frames(x)
        return np.r_[pb - pa - Ra @ d0, rotation_vector(Rb @ (Ra @ rel0).T)]

    # Frame b moves with a: its velocity constraint is written at b's origin for both frames,
    # i.e. a's point Jacobian is taken at the material point of body a that coincides with b.
    def jc_at_b(x):
        kin = robot.forward_kinematics(x)
        pb = robot.point_position(x, (bb, ob))
        oa_b = kin.body_to_world[ba].T @ (pb - kin.com_in_world[ba])
        ja0, jam = robot.point_jacobian(x, (ba, oa_b))
        jb0, jbm = robot.point_jacobian(x, (bb, ob))
        return np.hstack([jb0 - ja0, jbm - jam])

    if np.linalg.norm(jc_at_b(x0) @ u0) > 1e-9 * max(np.linalg.norm(u0), 1e-300):
        raise ArgumentError("u0 violates the loop closure (the two grasp frames move apart); project it onto the null space of J_c")

    def accel(t, x, u):
        J = jc_at_b(x)
        h = 1e-6
        jdot_u = (jc_at_b(robot.configuration_plus(x, h * u)) - jc_at_b(robot.configuration_plus(x, -h * u))) @ u / (2 * h)
        H = robot.mass_matrix(x)
        tau = np.zeros(n) if torque is None else vector(torque(t, x, u), "closed-chain torque", n)
        rhs_f = np.r_[np.zeros(6), tau] - robot.bias_forces(x, u)
        rhs_c = -jdot_u - 2 * alpha * (J @ u) - alpha**2 * error(x)
        k = np.block([[H, -J.T], [J, np.zeros((6, 6))]])
        try:
            sol = np.linalg.solve(k, np.r_[rhs_f, rhs_c])
        except np.linalg.LinAlgError:
            raise SingularError("the closed chain's constraint Jacobian lost rank (a singular two-arm posture)") from None
        return sol[: robot.nu], sol[robot.nu:]

    steps = max(1, int(np.ceil(duration / dt)))
    h = duration / steps
    x, u = x0.copy(), u0.copy()
    T, X, U, LAM, E = [], [], [], [], []
    for i in range(steps + 1):
        t = i * h
        _, lam = accel(t, x, u)
        T.append(t), X.append(x.copy()), U.append(u.copy()), LAM.append(lam), E.append(error(x))
        if i == steps:
            break
        (x,), (u,) = rk4_step(t, h, [x], [u], lambda tt, xx, uu: [accel(tt, xx[0], uu[0])[0]])
        if not np.all(np.isfinite(u)):
            raise SimulationError(f"the closed chain diverged at t = {t + h:.4g} s")
    return ClosedChainRun(np.array(T), np.array(X), np.array(U), np.array(LAM), np.array(E))
