"""spacearm — equations of motion of spacecraft-manipulator systems.

The generalized inertia matrix ``H*`` and the Generalized Jacobian Matrix ``J*`` (Umetani &
Yoshida 1989; Wilde et al. 2018) and every quantity behind them, computed by a Rust core and
checked against Pinocchio and MuJoCo. Start with [`Robot`][spacearm.Robot] and [`spacearm.presets`][spacearm.presets];
conventions are in ``docs/conventions.md``.
"""

from . import capture, control, io, presets
from ._core import __version__
from .model.batch import batch_threads, set_batch_threads
from .model.builder import RobotBuilder
from .model.slosh import SloshMode, SloshParameters, slosh_parameters
from .capture import Target
from .orbit import CentralBody, Orbit, OrbitalElements
from .model.description import (BaseDescription, GeometryDescription, JointLimits, LinkDescription, ModelDescription,
                                PointDescription)
from . import errors
from .errors import *  # noqa: F403 -- the exceptions and warnings of spacearm.errors, its __all__
from .model.robot import (
    ExternalWrench,
    ForwardDynamicsDerivatives,
    InertiaBlocks,
    InverseDynamicsPartials,
    Kinematics,
    Linearization,
    Momentum,
    PassiveModes,
    Robot,
)
from .sim.rollout import Rollouts, rollout
from .sim.simulation import simulate
from .sim.simulator import Simulator
from .sim.trajectory import Trajectory

#: The subpackages imported on first use (PEP 562): ``spacearm.plan`` after ``import spacearm``
#: imports ``spacearm.plan`` then, so ``import spacearm`` does not pay for them (CasADi, SymPy,
#: Dask and the engines load only with the subpackage that needs them).
_LAZY_SUBPACKAGES = ("analysis", "basilisk", "c", "campaign", "casadi", "examples", "fmi", "gym", "identify", "interop", "mpc", "plan", "symbolic")


def __getattr__(name: str):
    if name in _LAZY_SUBPACKAGES:
        import importlib

        module = importlib.import_module(f"{__name__}.{name}")
        globals()[name] = module
        return module
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_LAZY_SUBPACKAGES))

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
    "PassiveModes",
    "slosh_parameters",
    "SloshParameters",
    "SloshMode",
    "ModelDescription",
    "BaseDescription",
    "LinkDescription",
    "PointDescription",
    "GeometryDescription",
    "JointLimits",
    "presets",
    "capture",
    "Target",
    "Orbit",
    "CentralBody",
    "OrbitalElements",
    "simulate",
    "rollout",
    "Rollouts",
    "Simulator",
    "Trajectory",
    "set_batch_threads",
    "batch_threads",
    "control",
    "io",
    "__version__",
]
__all__ += errors.__all__  # the exceptions and warnings (one list: spacearm.errors.__all__)
