"""Capture of a tumbling target: the target (:class:`Target`), the grasp impact
(:func:`grasp_impulse`, also ``Robot.grasp_impulse``) and its inverse-inertia quantities, the
captured system, detumbling and the whole capture sequence (``docs/capture.md``)."""

from .impact import GraspImpulse, MomentumSplit, grasp_impulse, impulse_momentum_split, inverse_inertia, virtual_mass
from .target import Target, TargetState

__all__ = [
    "Target",
    "TargetState",
    "GraspImpulse",
    "MomentumSplit",
    "grasp_impulse",
    "inverse_inertia",
    "virtual_mass",
    "impulse_momentum_split",
]
