"""spacearm — equations of motion of spacecraft-manipulator systems.

The generalized inertia matrix ``H*`` and the Generalized Jacobian Matrix ``J*`` (Umetani &
Yoshida 1989; Wilde et al. 2018) and every quantity behind them, computed by a Rust core and
checked against Pinocchio and MuJoCo. Start with :class:`Robot` and :mod:`spacearm.presets`;
conventions are in ``docs/conventions.md``.
"""

from . import control, dh, model_file, presets
from ._core import __version__
from .builder import RobotBuilder
from .description import BaseDescription, JointLimits, LinkDescription, ModelDescription, PointDescription
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
from .robot import ExternalWrench, ForwardDynamicsDerivatives, InertiaBlocks, Kinematics, Linearization, Momentum, Robot
from .simulation import simulate
from .trajectory import Trajectory

__all__ = [
    "Robot",
    "RobotBuilder",
    "ExternalWrench",
    "Kinematics",
    "Momentum",
    "InertiaBlocks",
    "ForwardDynamicsDerivatives",
    "Linearization",
    "ModelDescription",
    "BaseDescription",
    "LinkDescription",
    "PointDescription",
    "JointLimits",
    "presets",
    "simulate",
    "Trajectory",
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
