"""The capture envelope ([`capture_envelope`][spacearm.capture.capture_envelope]): which target spin rates and which errors in
the target's inertia still give a successful capture.

Every sample starts at the grasp — the robot's grasp point on the target's, the gripper at rest,
the target spinning at the sample's rate about ``spin_axis`` — applies the rigid grasp impulse,
attaches the target and runs [`detumble`][spacearm.capture.detumble] for ``duration`` s. The
controller's model of the captured system carries the target with mass and inertia scaled by
``1 + error`` (the plant has the true target). A sample succeeds when the system is detumbled
within ``duration`` and the peak grasp force and torque stay within ``max_grasp_force`` and
``max_grasp_torque`` (joint torques and thrusts are clamped to their limits, so they are always
respected). The approach is left out: it is the same for every sample up to the target's motion,
and leaving it out keeps a sample to about a second.
"""

from __future__ import annotations

import math
from typing import NamedTuple, Optional, Sequence

import numpy as np

from .._util.arrays import vector
from ..errors import ArgumentError, SimulationError
from .captured import attach_target
from .impact import grasp_impulse
from .detumbling import detumble, grasp_wrench
from .target import Target

__all__ = ["CaptureEnvelope", "capture_envelope"]


class CaptureEnvelope(NamedTuple):
    """Results on the grid ``spin_rates × inertia_errors`` (rows: spin rates)."""

    spin_rates: np.ndarray  #: rad/s
    inertia_errors: np.ndarray  #: relative error of the controller's target mass and inertia
    success: np.ndarray  #: bool
    time_to_detumble: np.ndarray  #: s (inf: not within the run)
    peak_grasp_force: np.ndarray  #: N
    peak_grasp_torque: np.ndarray  #: N·m
    peak_joint_torque: np.ndarray  #: N·m
    mode: str

    def plot(self, path=None):
        """The envelope figure (success map with detumble times); written to ``path`` if given."""
        from ..viz.capture import plot_envelope

        return plot_envelope(self, path)


def capture_envelope(robot, target, *, spin_rates: Sequence[float] = (0.05, 0.1, 0.2, 0.4),
                     inertia_errors: Sequence[float] = (-0.3, 0.0, 0.3), spin_axis=(0.0, 0.0, 1.0), x=None,
                     grasp: Optional[str] = None, mode: str = "floating", duration: float = 20.0, dt: float = 0.02,
                     max_joint_torque: float = math.inf, max_force: float = math.inf, max_torque: float = math.inf,
                     max_grasp_force: float = math.inf, max_grasp_torque: float = math.inf,
                     kp: float = 1.0, kd: float = 2.0, time_constant: float = 5.0, rate_tolerance: float = 1e-3) -> CaptureEnvelope:
    """Sweep the grid (module docstring) and return a [`CaptureEnvelope`][spacearm.capture.CaptureEnvelope]."""
    rates = np.asarray(spin_rates, dtype=float).ravel()
    errors = np.asarray(inertia_errors, dtype=float).ravel()
    if rates.size == 0 or errors.size == 0 or not np.all(np.isfinite(rates)) or not np.all(np.isfinite(errors)):
        raise ArgumentError("spin_rates and inertia_errors must be non-empty lists of finite numbers")
    if np.any(errors <= -1.0):
        raise ArgumentError(f"inertia errors must be > -1 (a scale 1 + error > 0), got {errors}")
    axis = vector(spin_axis, "spin_axis", 3)
    if not np.linalg.norm(axis) > 0:
        raise ArgumentError("spin_axis must be non-zero")
    axis = axis / np.linalg.norm(axis)
    x = robot.neutral_configuration() if x is None else vector(x, "x", robot.nx)
    u = robot.zero_velocity()
    X = robot.point_position(x)
    offset = target.point(grasp)[1]
    shape = (rates.size, errors.size)
    success = np.zeros(shape, dtype=bool)
    t_rest, f_peak, n_peak, tau_peak = (np.full(shape, np.nan) for _ in range(4))
    for i, rate in enumerate(rates):
        s = target.state(X - offset, velocity=rate * np.cross(axis, offset), angular_velocity=rate * axis)
        imp = grasp_impulse(robot, x, u, target, s, grasp=grasp)
        cap = attach_target(robot, x, imp.u_after, target, imp.target_state_after)
        for j, err in enumerate(errors):
            guess = Target(target.mass * (1 + err), target.inertia * (1 + err), name=target.name,
                           grasp_points=target.grasp_points)
            model = attach_target(robot, x, imp.u_after, guess, imp.target_state_after).robot
            try:
                run = detumble(cap.robot, cap.x, cap.u, duration, mode=mode, kp=kp, kd=kd, time_constant=time_constant,
                               max_joint_torque=max_joint_torque, max_force=max_force, max_torque=max_torque,
                               rate_tolerance=rate_tolerance, dt=dt, model=model)
            except SimulationError:  # a diverging sample is a failed sample, not a failed sweep
                continue
            tr = run.trajectory
            w = grasp_wrench(cap, tr)
            f_peak[i, j] = float(np.linalg.norm(w[:, :3], axis=1).max())
            n_peak[i, j] = float(np.linalg.norm(w[:, 3:], axis=1).max())
            tau_peak[i, j] = run.peak_joint_torque
            t_rest[i, j] = run.time_to_detumble
            success[i, j] = run.time_to_detumble <= duration and f_peak[i, j] <= max_grasp_force and n_peak[i, j] <= max_grasp_torque
    return CaptureEnvelope(rates, errors, success, t_rest, f_peak, n_peak, tau_peak, mode)
