"""Mesh files in another format (trimesh, the ``mesh`` extra): one converter for the model
writers (``spacearm.io.mesh.with_mesh_format``) and the MuJoCo export
(``spacearm.interop.mujoco``), which sit side by side a layer above this one
(docs/architecture.md)."""

from __future__ import annotations

import hashlib
import os

from ..errors import ArgumentError, ModelFileError
from .optional import require

#: The formats a model's meshes can be converted to.
FORMATS = ("stl", "obj")


def converted_bytes(file: str, fmt: str = "stl") -> bytes:
    """The mesh file ``file`` in format ``fmt`` (``"stl"`` or ``"obj"``), as bytes: read by
    trimesh (COLLADA through pycollada), in the file's own units."""
    if fmt not in FORMATS:
        raise ArgumentError(f"fmt must be one of {FORMATS}, got {fmt!r}")
    trimesh = require("trimesh", "converting mesh files")
    if not os.path.isfile(file):
        raise ModelFileError(f"mesh '{file}' does not exist (a package:// file not found when the URDF was read? "
                             "pass package_dirs=[...] to load_urdf)")
    try:
        mesh = trimesh.load(file, force="mesh")
    except Exception as exc:  # trimesh raises many kinds; the message names the file
        raise ModelFileError(f"mesh '{file}' could not be read: {type(exc).__name__}: {exc}") from None
    data = mesh.export(file_type=fmt)
    return data if isinstance(data, bytes) else data.encode()


def converted_name(file: str, fmt: str) -> str:
    """The file name a converted ``file`` gets: its stem, a digest of its path (two meshes of one
    name in different folders stay apart), the new suffix."""
    digest = hashlib.sha1(os.path.abspath(file).encode()).hexdigest()[:8]
    return f"{os.path.splitext(os.path.basename(file))[0]}_{digest}.{fmt}"
