"""Analysis of free-floating spacecraft-manipulator systems, on top of the Rust core's
``analysis`` module:

- ``singularities`` — dynamic singularities of ``J*`` vs kinematic ones of
  ``J_m``, the DLS singularity detector, ``σ_min`` maps (``docs/singularities.md``);
- ``workspaces`` — reachable, path-dependent and path-independent
  workspaces, fixed-base workspace (``docs/workspace.md``);
- ``reactionless`` — reaction null space, reactionless and
  minimum-disturbance motion, RMRC with null-space objectives (``docs/reactionless.md``,
  ``docs/redundancy.md``);
- ``free_floating`` — base motion under prescribed joint motion with
  conserved momentum.

Result objects have a ``.plot(path)`` method (needs matplotlib) that writes the figure atomically.
"""

from .cmg import CmgEnvelope, CmgSingularSurfaces, cmg_envelope, cmg_singular_surfaces
from .free_floating import attitude_change, integrate_prescribed
from .reactionless import STRATEGIES, Motion, ReactionNullSpace, move_to, reaction_null_space, rmrc_rates
from .singularities import Detection, JacobianMeasures, SingularityMap, SingularityReport, analyze, damping, detect, scan, singularity_map
from .workspaces import Workspace, workspace
from ._common import TASKS, task_rows

__all__ = [
    "analyze", "detect", "damping", "scan", "singularity_map", "SingularityReport", "JacobianMeasures", "Detection", "SingularityMap",
    "workspace", "Workspace",
    "cmg_envelope", "CmgEnvelope", "cmg_singular_surfaces", "CmgSingularSurfaces",
    "reaction_null_space", "ReactionNullSpace", "move_to", "rmrc_rates", "Motion", "STRATEGIES",
    "integrate_prescribed", "attitude_change",
    "TASKS", "task_rows",
]
