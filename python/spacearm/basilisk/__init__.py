"""spacearm inside Basilisk (``pip install "spacearm[basilisk]"``: ``bsk`` >= 2.12, whose
``MJScene`` runs MuJoCo multibody models in a spacecraft simulation). ``docs/basilisk.md``.

- [`to_mjscene`][spacearm.basilisk.to_mjscene]: a spacearm robot as an ``MJScene`` and its
  [`ActuatorMap`][spacearm.basilisk.ActuatorMap] (one actuator per actuated joint, wheel and base
  thruster axis, by name);
- [`state_from_scene`][spacearm.basilisk.state_from_scene] / [`state_to_scene`][spacearm.basilisk.state_to_scene]:
  the scene's state as spacearm's ``x, u`` and back (the one convention map);
- [`ControllerModule`][spacearm.basilisk.ControllerModule]: any native law of
  [`spacearm.control`][spacearm.control] as a flight-software module, sample and hold at its task rate;
- [`GravityGradientModule`][spacearm.basilisk.GravityGradientModule]: the core's per-body
  gravity-gradient torque on every body of a scene;
- [`scene_generalized_inertia`][spacearm.basilisk.scene_generalized_inertia],
  [`scene_generalized_jacobian`][spacearm.basilisk.scene_generalized_jacobian],
  [`scene_reaction_null_space`][spacearm.basilisk.scene_reaction_null_space],
  [`scene_singularities`][spacearm.basilisk.scene_singularities]: ``H*``, ``J*``, the reaction
  null space and the dynamic singularities at a scene's state;
- [`from_mjcf`][spacearm.basilisk.from_mjcf]: a Basilisk scenario's MJCF read into a spacearm robot.

Basilisk is imported only when a function or module needs it (the two module classes import it
on first access: ``spacearm.basilisk.ControllerModule``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .analysis import scene_generalized_inertia, scene_generalized_jacobian, scene_reaction_null_space, scene_singularities
from .mjcf import from_mjcf
from .scene import BASE_ACTUATORS, ActuatorMap, scene_qpos_qvel, state_from_scene, state_to_scene, to_mjscene

__all__ = [
    "to_mjscene", "ActuatorMap", "BASE_ACTUATORS", "state_from_scene", "state_to_scene", "scene_qpos_qvel",
    "ControllerModule", "GravityGradientModule",
    "scene_generalized_inertia", "scene_generalized_jacobian", "scene_reaction_null_space", "scene_singularities",
    "from_mjcf",
]

_MODULES = ("ControllerModule", "GravityGradientModule")

if TYPE_CHECKING:  # for type checkers and the API pages; at run time, imported on first access
    from .modules import ControllerModule, GravityGradientModule


def __getattr__(name):
    if name in _MODULES:  # subclasses of Basilisk's SysModel: Basilisk is imported here
        from . import modules

        return getattr(modules, name)
    raise AttributeError(f"module 'spacearm.basilisk' has no attribute {name!r}")
