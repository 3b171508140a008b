"""spacearm's analysis on a Basilisk scene's state (flight software or post-processing): the
generalized inertia ``H*``, the generalized Jacobian ``J*``, the reaction null space and the
dynamic singularities, each the core's, at the state [`state_from_scene`][spacearm.basilisk.state_from_scene] reads (one convention
map). Basilisk has none of them."""

from __future__ import annotations

import numpy as np

from ..analysis.reactionless import reaction_null_space as _rns
from ..analysis.singularities import analyze as _analyze
from .scene import state_from_scene

__all__ = ["scene_generalized_inertia", "scene_generalized_jacobian", "scene_reaction_null_space", "scene_singularities"]


def scene_generalized_inertia(robot, scene) -> np.ndarray:
    """``H*`` (N×N, paper eq. 46) at the scene's state."""
    x, _ = state_from_scene(robot, scene)
    return robot.generalized_inertia(x)


def scene_generalized_jacobian(robot, scene, point=None) -> np.ndarray:
    """``J*`` (6×N, paper eq. 48) of ``point`` (default: the end effector) at the scene's state,
    for the momentum the scene has (``J*`` maps joint rates to the point's twist at zero momentum;
    the drift the momentum adds is ``Robot.point_twist``'s)."""
    x, _ = state_from_scene(robot, scene)
    return robot.generalized_jacobian(x, point)


def scene_reaction_null_space(robot, scene, base_motion: str = "angular", tolerance: float = 1e-9):
    """The reaction null space ([`spacearm.analysis.reaction_null_space`][spacearm.analysis.reaction_null_space])
    at the scene's state: joint rates that leave the base attitude (``"angular"``) or its whole
    motion (``"full"``) unchanged."""
    x, _ = state_from_scene(robot, scene)
    return _rns(robot, x, base_motion=base_motion, tolerance=tolerance)


def scene_singularities(robot, scene, point=None, task=None):
    """The dynamic singularities at the scene's state
    ([`spacearm.analysis.analyze`][spacearm.analysis.analyze],
    Papadopoulos & Dubowsky): the singular values, condition and manipulability of the task rows
    of ``J*`` (free floating) beside those of the fixed-base ``J_m`` (docs/singularities.md), for
    ``point`` (default: the end effector). A flight-software check before an arm command: a small
    ``report.generalized.sigma_min`` where ``report.fixed_base.sigma_min`` is not is a singularity
    that only a free-floating base has."""
    x, _ = state_from_scene(robot, scene)
    return _analyze(robot, x, point=point, task=task)
