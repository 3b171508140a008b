"""spacearm — equations of motion of spacecraft-manipulator systems.

The generalized inertia matrix ``H*`` and the Generalized Jacobian Matrix ``J*`` (Umetani &
Yoshida 1989; Wilde et al. 2018) and every quantity behind them, computed by a Rust core and
checked against Pinocchio and MuJoCo. Start with :class:`Robot` and :mod:`spacearm.presets`;
conventions are in ``docs/conventions.md``.
"""

import sys as _sys

from . import capture, control, presets
from .io import dh, model_file, urdf, urdf_export
from ._core import __version__
from .model.batch import batch_threads, set_batch_threads
from .model.builder import RobotBuilder
from .capture import Target
from .model.description import BaseDescription, JointLimits, LinkDescription, ModelDescription, PointDescription
from .errors import (
    ArgumentError,
    CampaignError,
    MissingDependencyError,
    ModelError,
    ModelFileError,
    NonFiniteError,
    NotFoundError,
    QuaternionError,
    ResourceLimitError,
    ShapeError,
    SimulationError,
    SingularError,
    SpacearmError,
    SpacearmTypeError,
)
from .model.robot import (
    ExternalWrench,
    ForwardDynamicsDerivatives,
    InertiaBlocks,
    InverseDynamicsPartials,
    Kinematics,
    Linearization,
    Momentum,
    Robot,
)
from .sim.rollout import Rollouts, rollout
from .sim.simulation import simulate
from .sim.simulator import Simulator
from .sim.trajectory import Trajectory

# The model-file modules moved into spacearm.io (docs/architecture.md); their old public paths
# (``import spacearm.dh``, ``from spacearm.urdf import load_urdf``) keep working.
for _name, _module in (("dh", dh), ("model_file", model_file), ("urdf", urdf), ("urdf_export", urdf_export)):
    _sys.modules[f"{__name__}.{_name}"] = _module
del _name, _module

__all__ = [
    "Robot",
    "RobotBuilder",
    "ExternalWrench",
    "Kinematics",
    "Momentum",
    "InertiaBlocks",
    "ForwardDynamicsDerivatives",
    "InverseDynamicsPartials",
    "Linearization",
    "ModelDescription",
    "BaseDescription",
    "LinkDescription",
    "PointDescription",
    "JointLimits",
    "presets",
    "capture",
    "Target",
    "simulate",
    "rollout",
    "Rollouts",
    "Simulator",
    "Trajectory",
    "set_batch_threads",
    "batch_threads",
    "control",
    "dh",
    "model_file",
    "SpacearmError",
    "ModelError",
    "ModelFileError",
    "ShapeError",
    "NonFiniteError",
    "QuaternionError",
    "NotFoundError",
    "SingularError",
    "ArgumentError",
    "SpacearmTypeError",
    "SimulationError",
    "ResourceLimitError",
    "CampaignError",
    "MissingDependencyError",
    "__version__",
]
