"""Reaction null space and reactionless motion (Nenchev, Umetani & Yoshida 1992; Nenchev et al.
1999), and the resolved-motion-rate planner shared with redundancy resolution
(``docs/reactionless.md``, ``docs/redundancy.md``).

[`ReactionNullSpace`][spacearm.analysis.ReactionNullSpace] and the rates of [`rmrc_rates`][spacearm.analysis.rmrc_rates] (``RmrcRates``) are the
extension's own frozen classes; [`Motion`][spacearm.analysis.Motion] is a subclass of the extension's ``RmrcMotion``
that adds the figure only (constructing it runs the motion in the core).
"""

from __future__ import annotations

from typing import Optional


from .. import _core
from .._core import ReactionNullSpace
from .._util.arrays import number, vector
from ..errors import ArgumentError, SpacearmTypeError
from ._common import TaskLike, task_rows

__all__ = ["ReactionNullSpace", "reaction_null_space", "Motion", "move_to", "rmrc_rates", "STRATEGIES"]

#: Strategies of the planner: how the base is treated.
STRATEGIES = ("naive", "reactionless", "minimum_disturbance")


def reaction_null_space(robot, x=None, base_motion: str = "angular", tolerance: float = 1e-9) -> ReactionNullSpace:
    r"""The reaction null space at ``x`` (default: initial configuration): the null space of the
    angular rows (``base_motion="angular"``, Nenchev's RNS: null space of the coupling inertia
    about the system CM) or of all rows (``"full"``) of $-H_0^{-1} H_{0m}$; rank at
    ``tolerance`` $\cdot\, \sigma_\text{max}$."""
    x = robot.neutral_configuration() if x is None else x
    if not isinstance(base_motion, str):
        raise SpacearmTypeError(f"base_motion must be 'angular' or 'full', got {type(base_motion).__name__} {base_motion!r}")
    return _core.analysis_reaction_null_space(robot.core_model, x, base_motion, number(tolerance, "tolerance"))


def _check_strategy(strategy: str) -> str:
    if strategy not in STRATEGIES:
        raise ArgumentError(f"strategy must be one of {', '.join(STRATEGIES)}, got {strategy!r}")
    return strategy


def rmrc_rates(robot, x, desired_twist, point=None, task: TaskLike = None, strategy: str = "naive", threshold: float = _core.DLS_DEFAULTS.threshold,
               max_damping: float = _core.DLS_DEFAULTS.max_damping, manipulability_gain: float = 0.0, joint_limit_gain: float = 0.0) -> _core.RmrcRates:
    """One evaluation of the resolved-motion-rate law: joint rates realising the task rows of
    ``desired_twist`` (6 values ``[v; w]`` in 𝒥) through ``J*`` (DLS with the damping law of
    [`spacearm.analysis.damping`][spacearm.analysis.damping]), with the null-space objectives. Returns the extension's
    frozen ``RmrcRates``: ``qd``, ``sigma_min``, ``damping`` and ``base_angular_velocity``."""
    body, off = robot.resolve_point(point)
    options = _core.RmrcOptions(rows=task_rows(robot, task), threshold=number(threshold, "threshold"),
                                max_damping=number(max_damping, "max_damping"), strategy=_check_strategy(strategy),
                                manipulability_gain=number(manipulability_gain, "manipulability_gain"),
                                joint_limit_gain=number(joint_limit_gain, "joint_limit_gain"))
    return _core.analysis_rmrc_rates(robot.core_model, x, body, off, vector(desired_twist, "desired_twist", 6), options)


class Motion(_core.RmrcMotion):
    """A closed-loop point-to-point motion of a free-floating system (zero momentum), what
    [`move_to`][spacearm.analysis.move_to] returns: the extension's ``RmrcMotion`` (``robot_name``, ``strategy``,
    ``target``, ``times`` (K+1,), ``x`` (K+1, 7+N), ``qd`` (K+1, N), ``point_position`` (K+1, 3)
    in 𝒥, ``sigma_min`` and ``damping`` of the (projected) task Jacobian, ``attitude_change``
    (rad from the start), ``max_attitude_change``, ``final_position_error`` (m)) with its figure."""

    __slots__ = ()

    def plot(self, path, others=(), title: Optional[str] = None) -> str:
        """Write [`figure`][spacearm.analysis.Motion.figure] to ``path`` in the format its suffix names (atomically); returns the path."""
        from ..viz.figures import plot_to

        return plot_to(path, lambda: self.figure(others, title), bbox_inches="tight")

    def figure(self, others=(), title: Optional[str] = None):
        """Point path (x–y), base attitude change and σ_min against time, for this motion and
        any ``others`` (``spacearm.viz.analysis.motion_figure``). Returns the matplotlib ``Figure``."""
        from ..viz.analysis import motion_figure

        return motion_figure(self, others, title)


def move_to(robot, target, x0=None, point=None, task: TaskLike = None, strategy: str = "reactionless", duration: float = 5.0,
            settle: float = 1.0, dt: float = 0.01, gain: float = 5.0, threshold: float = _core.DLS_DEFAULTS.threshold, max_damping: float = _core.DLS_DEFAULTS.max_damping,
            manipulability_gain: float = 0.0, joint_limit_gain: float = 0.0) -> Motion:
    """Move a point (default: the end effector) to ``target`` (3 values in 𝒥; only the task's
    linear rows are controlled; angular rows hold the initial orientation) along a straight line
    with quintic timing over ``duration`` s, then ``settle`` s more, by resolved-motion-rate
    control through ``J*`` integrated with the free-floating kinematics (RK4, step ``dt``).

    ``strategy``: ``"naive"`` (DLS pseudo-inverse of ``J*``), ``"reactionless"`` (task in the
    reaction null space: base attitude undisturbed), ``"minimum_disturbance"`` (task first, base
    angular velocity minimized in its null space). ``manipulability_gain`` and
    ``joint_limit_gain`` add singularity- and joint-limit-avoidance in the remaining null space.
    """
    x0 = robot.neutral_configuration() if x0 is None else x0
    body, off = robot.resolve_point(point)
    tgt = vector(target, "target", 3)
    options = _core.RmrcOptions(rows=task_rows(robot, task), threshold=number(threshold, "threshold"),
                                max_damping=number(max_damping, "max_damping"), gain=number(gain, "gain"),
                                strategy=_check_strategy(strategy), manipulability_gain=number(manipulability_gain, "manipulability_gain"),
                                joint_limit_gain=number(joint_limit_gain, "joint_limit_gain"))
    return Motion(robot.core_model, x0, body, off, tgt, number(duration, "duration"), number(settle, "settle"), number(dt, "dt"), options)
