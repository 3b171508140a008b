"""The exceptions spacearm raises.

Every error spacearm raises on bad input derives from :class:`SpacearmError`; those caused by
an invalid argument or model also derive from :class:`ValueError`, so ``except ValueError``
keeps working. The Rust core maps each of its error kinds onto one class here.
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
    "SimulationError",
    "MissingDependencyError",
]


class SpacearmError(Exception):
    """Base class of every spacearm error."""


class ModelError(SpacearmError, ValueError):
    """The model description violates a physical or structural rule (names the body/joint)."""


class ModelFileError(ModelError):
    """A model file (TOML, URDF) could not be read; the message gives the line and column."""


class ShapeError(SpacearmError, ValueError):
    """An array argument has the wrong length or shape (the message gives the expected one)."""


class NonFiniteError(SpacearmError, ValueError):
    """An argument contains NaN or infinity."""


class QuaternionError(SpacearmError, ValueError):
    """A quaternion is not of unit norm within the stated tolerance."""


class NotFoundError(SpacearmError, LookupError):
    """A body, joint or point name (or index) does not exist in the model."""


class SingularError(SpacearmError, ArithmeticError):
    """A matrix that must be inverted is singular at this configuration."""


class ArgumentError(SpacearmError, ValueError):
    """An option or numerical argument is outside its valid range (a negative duration, an unknown mode, a
    tolerance, gain, time step or resolution out of range)."""


class SimulationError(SpacearmError, RuntimeError):
    """A simulation could not continue (the state diverged, the adaptive step size collapsed,
    the step budget ran out); the message says when and what to change."""


class MissingDependencyError(SpacearmError, ImportError):
    """An optional package that this feature needs is not installed; the message names the extra
    to install (``pip install "spacearm[plot]"``, ``[symbolic]``, ``[campaign]`` or ``[all]``)."""

    def __init__(self, message: str, package: str = "", extra=None):
        super().__init__(message, name=package or None)
        self.package = package
        self.extra = extra
