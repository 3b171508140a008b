"""TOML model files: read and write a [`Robot`][spacearm.Robot].

The schema (units, frames, every key and every validation rule) is in
``docs/model-format.md``. In brief:

    [model]
    name = "demo"
    end_effector = "tip"            # optional: names a [[point]]
    initial_q = [0.3]               # optional: one entry per moving joint

    [base]
    mass = 100.0                    # kg
    inertia = [10.0, 10.0, 10.0]    # about the base CM; or 3x3, or {ixx = .., ixy = ..}

    [[link]]
    name = "arm"
    parent = "base"
    com = [0.5, 0.0, 0.0]           # CM from the joint, link frame
    mass = 5.0
    inertia = [0.01, 0.4, 0.4]      # about the CM, link axes
    joint = { type = "revolute", origin = [0.5, 0.0, 0.0], axis = [0.0, 0.0, 1.0] }

    [[point]]
    name = "tip"
    body = "arm"
    offset = [0.5, 0.0, 0.0]

Every problem with a file raises [`ModelFileError`][spacearm.ModelFileError] (a
[`ModelError`][spacearm.ModelError], hence a ``ValueError``) whose message starts with
``file:line:column:`` and names the link, joint or point concerned.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Union

from .. import _core
from .._util.atomic import write_text
from ..errors import ModelFileError, SpacearmTypeError
from ..model.robot import Robot, warn_nonphysical_inertia

__all__ = ["load_toml", "loads_toml", "save_toml", "dumps_toml"]

PathLike = Union[str, "os.PathLike[str]"]


def loads_toml(text: str, source: str = "<string>", *, allow_nonphysical_inertia: bool = False) -> Robot:
    """Parse a model from TOML text. ``source`` names the text in error messages.

    ``allow_nonphysical_inertia``: accept inertias whose principal moments break the triangle
    inequality ``I1 + I2 >= I3`` (refused by default: no real body has them), with a
    [`NonPhysicalInertiaWarning`][spacearm.errors.NonPhysicalInertiaWarning] per body; published identified datasets
    can need it. Symmetry and positive semi-definiteness are still required.
    """
    if isinstance(text, (bytes, bytearray)):
        try:
            text = bytes(text).decode("utf-8")
        except UnicodeDecodeError as exc:
            raise ModelFileError(f"{source}: the model file is not valid UTF-8 (byte {exc.start})") from None
    if not isinstance(text, str):
        raise SpacearmTypeError(f"loads_toml expects the TOML text as a str, got {type(text).__name__}")
    robot = Robot(_core.model_from_toml(text, str(source), allow_nonphysical_inertia=bool(allow_nonphysical_inertia)))
    return warn_nonphysical_inertia(robot)


def load_toml(path: PathLike, *, allow_nonphysical_inertia: bool = False) -> Robot:
    """Read a model file (UTF-8 TOML). A missing file raises ``FileNotFoundError``; anything
    wrong inside it raises [`ModelFileError`][spacearm.ModelFileError] with the line and column.
    ``allow_nonphysical_inertia``: see [`loads_toml`][spacearm.io.loads_toml]."""
    try:
        path = Path(path)
    except TypeError:
        raise SpacearmTypeError(f"load_toml expects a path (str or os.PathLike), got {type(path).__name__}") from None
    data = path.read_bytes()
    return loads_toml(data, source=str(path), allow_nonphysical_inertia=allow_nonphysical_inertia)


def dumps_toml(robot: Robot) -> str:
    """The model as TOML text. ``loads_toml(dumps_toml(robot))`` gives back exactly the same
    model (every number is written in its shortest exact form)."""
    if not isinstance(robot, Robot):
        raise SpacearmTypeError(f"dumps_toml expects a spacearm.Robot, got {type(robot).__name__}")
    return _core.model_to_toml(robot.core_model)


def save_toml(robot: Robot, path: PathLike) -> Path:
    """Write the model to ``path`` atomically: the text goes to a temporary file in the same
    directory, is flushed to disk, and then replaces ``path`` in one step, so an interrupted
    run never leaves a truncated file (``spacearm._util.atomic``). Returns the path written."""
    return write_text(path, dumps_toml(robot))
