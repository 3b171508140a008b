"""The task rows of a point's twist ``[vx, vy, vz, wx, wy, wz]`` (in the inertial frame) that
resolved-motion-rate control and the singularity analyses work on: the named tasks and their
resolution for a robot. One home, below ``control`` and ``analysis``, which both use it."""

from __future__ import annotations

from typing import Sequence, Union

from ..errors import ArgumentError

__all__ = ["TASKS", "TaskLike", "is_planar", "task_rows"]

TaskLike = Union[str, Sequence[int], None]

#: Named tasks: rows of the point twist [vx, vy, vz, wx, wy, wz] (in the inertial frame).
TASKS = {
    "position": (0, 1, 2),
    "planar": (0, 1),
    "planar_pose": (0, 1, 5),
    "orientation": (3, 4, 5),
    "full": (0, 1, 2, 3, 4, 5),
}


def is_planar(robot) -> bool:
    """True when every joint axis is along z at the initial configuration (a planar arm in x–y)."""
    k = robot.forward_kinematics(robot.neutral_configuration()).joint_axis_in_world
    axes = [k[b] for b in robot.body_of_dof]
    return len(axes) > 0 and all(abs(abs(a[2]) - 1.0) < 1e-12 for a in axes)


def task_rows(robot, task: TaskLike) -> list:
    """Rows of the twist for ``task``: a name of [`TASKS`][spacearm.model.tasks.TASKS], a sequence of row indices, or
    ``None``/``"auto"`` (``"planar"`` for a planar arm with every joint axis along z, else
    ``"position"``)."""
    if task is None or (isinstance(task, str) and task == "auto"):
        task = "planar" if is_planar(robot) else "position"
    if isinstance(task, str):
        if task not in TASKS:
            raise ArgumentError(f"unknown task '{task}': expected one of {', '.join(TASKS)} or a list of rows 0-5")
        return list(TASKS[task])
    rows = [int(r) for r in task]
    return rows


