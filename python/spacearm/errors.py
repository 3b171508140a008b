"""The exceptions spacearm raises.

Every error spacearm raises on bad input (an argument, a model, a file) or on a computation
that cannot go on is an instance of [`SpacearmError`][spacearm.SpacearmError], so ``except spacearm.SpacearmError``
catches all of them and nothing else. Each class also derives from the builtin exception a
Python programmer would expect for that kind of error, so ``except ValueError`` (or
``TypeError``, ``KeyError``...) keeps working around spacearm calls. The Rust core has one error
kind per class below (the bindings map each onto its class).

| class | builtin bases | raised when |
| --- | --- | --- |
| `ModelError` | `ValueError` | a model breaks a physical or structural rule (the message names the body or joint) |
| `ModelFileError` | `ValueError` (a `ModelError`) | a model file (TOML, URDF) cannot be read; the message gives the line and column |
| `ShapeError` | `ValueError` | an array has the wrong length or shape, or is not an array of numbers |
| `NonFiniteError` | `ValueError` | an argument holds NaN or an infinity, or a result computed from finite arguments overflowed |
| `QuaternionError` | `ValueError` | a quaternion is not of unit norm |
| `ArgumentError` | `ValueError` | an option or number is outside its valid range (an unknown method or mode name, a negative duration, gain, tolerance...) |
| `SpacearmTypeError` | `TypeError` | an argument is an object of the wrong kind (not a `Robot`, not an `ExternalWrench`, bytes where text is expected, an array that is not real numbers: complex, object, datetime, strings) |
| `NotFoundError` | `KeyError` (so `LookupError`) and `ValueError` | a body, joint, point, preset, metric or quantity name (or index) does not exist |
| `SingularError` | `ArithmeticError` | a matrix that must be inverted is singular at this configuration |
| `SimulationError` | `RuntimeError` | a simulation cannot go on (it diverged, the step size collapsed, the step budget ran out) |
| `ResourceLimitError` | `MemoryError` | a request would allocate more than the memory limit of one request (2 GiB): a simulation recording too many samples, a dense matrix or tensor of a very large model; refused before anything is allocated, the message gives the size and the way out |
| `CampaignError` | `RuntimeError` | a campaign cannot run, go on or report for reasons outside its samples (a script without a main guard under the spawn start method, an unreachable Dask scheduler, lost workers, nothing that ran to plot) |
| `MissingDependencyError` | `ImportError` | an optional package is not installed (the message names the extra to install) |

Two warning classes (both ``UserWarning``): [`NonPhysicalInertiaWarning`][spacearm.errors.NonPhysicalInertiaWarning], issued when a
model is loaded with ``allow_nonphysical_inertia=True`` and a body's inertia breaks the triangle
inequality, and [`PlanCheckWarning`][spacearm.errors.PlanCheckWarning], issued when a planned maneuver fails its check
(``spacearm.plan``: IPOPT did not solve it, or its defect or re-simulation is beyond tolerance).

``NotFoundError`` is a lookup failure (``robot.body_index("nope")``, ``results.metric("x")``),
hence a ``KeyError``; a name that does not exist is also an invalid argument value, hence a
``ValueError`` too, so that ``except ValueError`` catches every bad-input error of this table
except a wrong type (``TypeError``), a missing package (``ImportError``), a singular matrix
and a failed simulation or campaign. Its message
prints as written (a plain ``KeyError`` would print it in quotes).
"""

__all__ = [
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
    "NonPhysicalInertiaWarning",
    "PlanCheckWarning",
]


# The classes the extension raises are defined by the extension itself (so that it never
# imports this package); they are re-exported here, where users import them from, with their
# documentation. Their bases are those of the table above.
from ._core import (  # noqa: E402
    ArgumentError,
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

SpacearmError.__doc__ = """Base class of every spacearm error."""
ModelError.__doc__ = """The model description violates a physical or structural rule (names the body/joint)."""
ModelFileError.__doc__ = """A model file (TOML, URDF) could not be read; the message gives the line and column."""
ShapeError.__doc__ = """An array argument has the wrong length or shape (the message gives the expected one)."""
NonFiniteError.__doc__ = """An argument contains NaN or infinity, or a computation from finite arguments overflowed
(the message names the call and the likely cause)."""
QuaternionError.__doc__ = """A quaternion is not of unit norm within the stated tolerance."""
NotFoundError.__doc__ = """A body, joint, point, preset, metric or quantity name (or index) does not exist.

A ``KeyError`` (so a ``LookupError``) and a ``ValueError``: see the module docstring. Its message
prints as written (a plain ``KeyError`` prints it in quotes)."""
SingularError.__doc__ = """A matrix that must be inverted is singular at this configuration."""
ArgumentError.__doc__ = """An option or numerical argument is outside its valid range (a negative duration, an unknown
mode, a tolerance, gain, time step or resolution out of range)."""
SpacearmTypeError.__doc__ = """An argument is an object of the wrong kind (e.g. not a ``Robot``, not an
``ExternalWrench``, bytes where a string is expected, an array of complex numbers or strings); the
message names what was expected."""
SimulationError.__doc__ = """A simulation could not continue (the state diverged, the adaptive step size collapsed,
the step budget ran out); the message says when and what to change."""


ResourceLimitError.__doc__ = """A request would allocate more than the memory limit of one request
(``spacearm._core.MEMORY_LIMIT_BYTES``, 2 GiB): refused before anything is allocated. The
message names the request, its size and the way out (``record_every``, a coarser output
grid, a shorter run, an O(N) algorithm, a smaller model)."""


def _reduce_from_args(self):
    # MemoryError's own pickling goes through MemoryError.__new__, which refuses subclasses;
    # rebuild from the message instead (campaign workers send errors between processes).
    return (type(self), self.args)


ResourceLimitError.__reduce__ = _reduce_from_args


class CampaignError(SpacearmError, RuntimeError):
    """A campaign cannot run, or cannot go on, for reasons outside its samples (a script
    without an ``if __name__ == "__main__":`` guard under the spawn start method, an unreachable
    Dask scheduler, lost worker processes); the message says what to change."""


class MissingDependencyError(SpacearmError, ImportError):
    """An optional package that this feature needs is not installed; the message names the extra
    to install (``pip install "spacearm[plot]"``, ``[symbolic]``, ``[campaign]`` or ``[all]``)."""

    def __init__(self, message: str, package: str = "", extra=None):
        super().__init__(message, name=package or None)
        self.package = package
        self.extra = extra



class NonPhysicalInertiaWarning(UserWarning):
    """A body's inertia breaks the triangle inequality ``I1 + I2 >= I3`` (no real mass
    distribution has such moments) and was loaded because ``allow_nonphysical_inertia=True``
    (command line: ``--allow-nonphysical-inertia``) asked for it; the message names the body.
    Published identified inertias of flown robots can be of this kind (ETS-VII)."""


class PlanCheckWarning(UserWarning):
    """A maneuver planned by [`point_to_point`][spacearm.plan.point_to_point] is not a plan: IPOPT did not
    solve it, or its shooting defect or its re-simulation in the native simulator is beyond the
    tolerance of docs/optimal-control.md ("Checks"), whatever IPOPT's status. The plan returned
    has ``success`` False and ``failure`` saying why."""
