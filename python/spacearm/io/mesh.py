"""Mesh files of a model's geometry (docs/geometry.md), through trimesh (the ``mesh`` extra):
`with_mesh_format` gives a copy of a model whose meshes
are all in one format (STL by default), converting the others (DAE, PLY, GLB, ...) into a
folder, for engines that read only some formats (MuJoCo reads STL and OBJ).

Why trimesh: it is the maintained Python mesh library that reads every format URDFs use
(COLLADA through pycollada, STL, OBJ, PLY, glTF) and writes STL and OBJ; spacearm reads no mesh
format itself. The converted mesh keeps the file's units as trimesh reads them (a COLLADA
``<unit meter>`` is applied), so a URDF's ``scale`` still applies on top.
"""

from __future__ import annotations

import os
from typing import Sequence

from .._util.atomic import atomic_open
from .._util.meshes import FORMATS, converted_bytes, converted_name
from ..errors import ArgumentError
from ..model.builder import RobotBuilder
from ..model.robot import Robot

__all__ = ["with_mesh_format", "converted_bytes", "FORMATS"]


def _convert(file: str, folder: str, fmt: str) -> str:
    out = os.path.join(folder, converted_name(file, fmt))
    if not os.path.isfile(out):
        data = converted_bytes(file, fmt)
        with atomic_open(out, "wb") as fh:
            fh.write(data)
    return out


def with_mesh_format(robot: Robot, folder, fmt: str = "stl", keep: Sequence[str] = ("stl", "obj")) -> Robot:
    """A copy of ``robot`` whose mesh geometries in a format not in ``keep`` are converted to
    ``fmt`` (``"stl"`` or ``"obj"``) as files in ``folder`` (created; a file already converted
    is reused). Everything else of the model is unchanged."""
    if fmt not in FORMATS:
        raise ArgumentError(f"fmt must be one of {FORMATS}, got {fmt!r}")
    folder = os.fspath(folder)
    os.makedirs(folder, exist_ok=True)
    b = RobotBuilder.from_robot(robot, geometry=False)
    for g in robot.description.geometries:
        dims = {key: getattr(g, key) for key in ("size", "radius", "length", "file", "scale") if getattr(g, key) is not None}
        if g.shape == "mesh" and os.path.splitext(g.file)[1].lower().lstrip(".") not in keep:
            dims["file"] = _convert(g.file, folder, fmt)
        b.add_geometry(g.body, g.shape, role=g.role, origin=g.origin, rotation=g.rotation, rgba=g.rgba, name=g.name, **dims)
    return b.build()
