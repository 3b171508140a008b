"""The example model files shipped inside the package (docs/model-format.md).

Every tutorial, README block and CLI call can name them from any directory:
[`path`][spacearm.examples.path] gives the file of a shipped model by name, and the command line
takes the same names wherever it takes a model (``spacearm inspect spatial6_wheels``,
``--mount-on spacecraft_bus``).

| name | what |
| --- | --- |
| `spacecraft_bus` | a base-only 500 kg, 1.2 × 1.1 × 1.0 m bus to mount URDF arms on (no links) |
| `spatial6_wheels` | the spatial6 arm with three reaction wheels in the base (rotation-floating mode) |
| `gripper_servicer` | a 200 kg servicer with a boom and a parallel gripper (docs/contact.md, "A capture on contact") |
| `planar4`, `spatial6`, `dual_arm`, `spatial7`, `ets7` | the presets of [`spacearm.presets`][spacearm.presets], written as model files |

```python
import spacearm

robot = spacearm.io.load_toml(spacearm.examples.path("spatial6_wheels"))
print(robot.name, robot.n_dof, spacearm.examples.NAMES)
```
"""

from __future__ import annotations

from pathlib import Path

from ..errors import NotFoundError, SpacearmTypeError

__all__ = ["NAMES", "path"]

_HERE = Path(__file__).resolve().parent

#: The names of the shipped model files (without ``.toml``), as accepted by
#: [`path`][spacearm.examples.path] and by the CLI wherever it takes a model.
NAMES = tuple(sorted(p.stem for p in _HERE.glob("*.toml")))


def path(name: str) -> Path:
    """The file of the shipped example model ``name`` (``"spacecraft_bus"`` or
    ``"spacecraft_bus.toml"``), an existing ``.toml`` file inside the installed package.

    Raises [`NotFoundError`][spacearm.errors.NotFoundError] for a name that is not shipped (the
    message lists [`NAMES`][spacearm.examples.NAMES]).
    """
    if not isinstance(name, str):
        raise SpacearmTypeError(f"examples.path: the name must be a str, got {type(name).__name__}")
    stem = name[:-5] if name.endswith(".toml") else name
    if stem not in NAMES:
        shown = name if len(name) <= 80 else name[:80] + "..."
        raise NotFoundError(f"no shipped example model '{shown}': the shipped ones are {', '.join(NAMES)}")
    return _HERE / f"{stem}.toml"
