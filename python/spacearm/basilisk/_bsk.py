"""The one import of Basilisk (``pip install "spacearm[basilisk]"``: ``bsk``), made only when a
function of ``spacearm.basilisk`` needs it, so that ``import spacearm.basilisk`` is free."""

from __future__ import annotations

from .._util.optional import require


def mujoco():
    """Basilisk's ``Basilisk.simulation.mujoco`` (MJScene and its actuators, states, messages)."""
    return require("Basilisk.simulation.mujoco", "Basilisk scenes (spacearm.basilisk)")


def messaging():
    """Basilisk's ``Basilisk.architecture.messaging``."""
    return require("Basilisk.architecture.messaging", "Basilisk modules (spacearm.basilisk)")


def sys_model():
    """Basilisk's ``Basilisk.architecture.sysModel`` (the base class of Python modules)."""
    return require("Basilisk.architecture.sysModel", "Basilisk modules (spacearm.basilisk)")
