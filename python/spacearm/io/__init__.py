"""Models in and out of files: the constructors of [`Robot`][spacearm.Robot] from a source other
than Python code, and the writers.

- [`load_toml`][spacearm.io.load_toml] / [`loads_toml`][spacearm.io.loads_toml] (a model file or its text, ``docs/model-format.md``),
  [`save_toml`][spacearm.io.save_toml] / [`dumps_toml`][spacearm.io.dumps_toml] (write one back, bit-exact);
- [`load_urdf`][spacearm.io.load_urdf] / [`loads_urdf`][spacearm.io.loads_urdf] (URDF, free-flying or mounted on a spacecraft,
  ``docs/urdf.md``), [`to_urdf`][spacearm.io.to_urdf] / [`save_urdf`][spacearm.io.save_urdf] (URDF out);
- [`robot_from_dh`][spacearm.io.robot_from_dh] (a Denavit–Hartenberg table, ``docs/dh.md``).

They live here, not as ``Robot`` classmethods: ``io/`` builds Robots, so it sits a layer above
``model/``, which imports nothing from the layers above it (``docs/architecture.md``).
"""

from .dh import robot_from_dh
from .model_file import dumps_toml, load_toml, loads_toml, save_toml
from .urdf import load_urdf, loads_urdf
from .urdf_export import save_urdf, to_urdf



def __getattr__(name):
    # `spacearm.io.mesh` (the `mesh` extra's converters) is reachable without an import of its
    # own (issue 37 item 2: an error message named spacearm.io.mesh.with_mesh_format, which
    # failed as written); it is loaded on first use, so `import spacearm` needs no trimesh.
    if name == "mesh":
        import importlib

        # (`from . import mesh` would ask this function again for the attribute: recursion)
        return importlib.import_module(f"{__name__}.mesh")
    raise AttributeError(f"module 'spacearm.io' has no attribute {name!r}")


__all__ = ["load_toml", "loads_toml", "save_toml", "dumps_toml", "load_urdf", "loads_urdf", "to_urdf", "save_urdf", "robot_from_dh"]
