"""Models in and out of files: the constructors of :class:`~spacearm.Robot` from a source other
than Python code, and the writers.

- :func:`load_toml` / :func:`loads_toml` (a model file or its text, ``docs/model-format.md``),
  :func:`save_toml` / :func:`dumps_toml` (write one back, bit-exact);
- :func:`load_urdf` / :func:`loads_urdf` (URDF, free-flying or mounted on a spacecraft,
  ``docs/urdf.md``), :func:`to_urdf` / :func:`save_urdf` (URDF out);
- :func:`robot_from_dh` (a Denavit–Hartenberg table, ``docs/dh.md``).

They live here, not as ``Robot`` classmethods: ``io/`` builds Robots, so it sits a layer above
``model/``, which imports nothing from the layers above it (``docs/architecture.md``).
"""

from .dh import robot_from_dh
from .model_file import dumps_toml, load_toml, loads_toml, save_toml
from .urdf import load_urdf, loads_urdf
from .urdf_export import save_urdf, to_urdf

__all__ = ["load_toml", "loads_toml", "save_toml", "dumps_toml", "load_urdf", "loads_urdf", "to_urdf", "save_urdf", "robot_from_dh"]
