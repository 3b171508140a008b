"""Independent numpy forms of the capture module's native laws, for the tests to hold the core
against (the package itself runs the native controllers: spacearm.capture.detumble)."""

from __future__ import annotations

import numpy as np


def hold_torque(robot, x, u, q_hold, kp: float, kd: float, max_joint_torque: float) -> np.ndarray:
    """``clip(H* (kp (q_hold − q) − kd q̇) + c*, ±max_joint_torque)`` from the robot's ``H*`` and
    ``c*`` (paper eqs. 45 and 112–115 with a constant reference)."""
    if robot.n_dof == 0:
        return np.zeros(0)
    q, qd = x[7:], u[6:]
    tau = robot.generalized_inertia(x) @ (kp * (q_hold - q) - kd * qd) + robot.generalized_bias(x, u)
    return np.clip(tau, -max_joint_torque, max_joint_torque)
