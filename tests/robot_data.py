"""Where the robots of ``example-robot-data`` (a test extra) are installed: one place for every
test that loads a real arm's URDF. The package ships no Python module; its files sit under
``cmeel.prefix/share/example-robot-data/robots`` in site-packages."""

from importlib import metadata
from pathlib import Path

import pytest

_ROBOTS = "cmeel.prefix/share/example-robot-data/robots"


def robots_dir() -> str:
    """The ``robots`` folder, or skip the test when the package is not installed."""
    try:
        root = Path(str(metadata.distribution("example-robot-data").locate_file(_ROBOTS)))
    except metadata.PackageNotFoundError:
        pytest.skip("example-robot-data (a test extra) is not installed")
    if not root.is_dir():
        pytest.skip(f"example-robot-data has no {_ROBOTS}")
    return str(root)


def robot_urdf(relative: str) -> str:
    """The path of ``relative`` (e.g. ``"ur_description/urdf/ur5_robot.urdf"``) under ``robots``."""
    path = Path(robots_dir()) / relative
    if not path.is_file():
        pytest.skip(f"example-robot-data has no {relative}")
    return str(path)
