"""Capture of a tumbling target (``docs/capture.md``).

- [`Target`][spacearm.Target]: a free rigid body with grasp points (state ``[position, quaternion [x, y, z,
  w], velocity, angular velocity]``, all in 𝒥);
- [`grasp_impulse`][spacearm.capture.grasp_impulse]: the impact, rigid lock or frictionless
  point contact, and its pieces [`inverse_inertia`][spacearm.capture.inverse_inertia], [`virtual_mass`][spacearm.capture.virtual_mass],
  [`impulse_momentum_split`][spacearm.capture.impulse_momentum_split];
- [`attach_target`][spacearm.capture.attach_target] (the captured system as one model) and [`soft_capture`][spacearm.capture.soft_capture] (a wrist
  impedance between two free bodies);
- [`simulate_closed_chain`][spacearm.capture.simulate_closed_chain]: a two-arm grasp as a closed chain;
- [`detumble`][spacearm.capture.detumble]; [`capture`][spacearm.capture.capture], the whole sequence with phases and the momentum ledger;
- [`capture_envelope`][spacearm.capture.capture_envelope]: success over target spin rates and inertia errors;
- [`ContactCapture`][spacearm.capture.ContactCapture]: a gripper closing on a tumbling handle by contact, judged held, slipped or missed;
- [`compare_in_orbit`][spacearm.capture.compare_in_orbit]: the same capture in empty space and in orbit (docs/orbit.md).
"""

from .closed_chain import ClosedChainRun, simulate_closed_chain
from ..sim.contact_capture import ContactCapture, ContactCaptureRun
from .captured import CapturedSystem, SoftCaptureRun, attach_target, relative_twist, soft_capture
from .detumbling import DetumbleRun, detumble
from .envelope import CaptureEnvelope, capture_envelope
from .in_orbit import OrbitComparison, compare_in_orbit
from .impact import CAPTURE_TOLERANCE, MAX_HANDLE_RATIO, GraspImpulse, MomentumSplit, grasp_impulse, impulse_momentum_split, inverse_inertia, virtual_mass
from .sequence import MAX_CAPTURE_SAMPLES, MAX_TURN_PER_SAMPLE, PHASES, CaptureResult, RecordedImpulse, capture
from .target import Target, TargetState

__all__ = [
    "ContactCapture",
    "ContactCaptureRun",
    "Target",
    "TargetState",
    "GraspImpulse",
    "CAPTURE_TOLERANCE",
    "MAX_HANDLE_RATIO",
    "MAX_CAPTURE_SAMPLES",
    "MAX_TURN_PER_SAMPLE",
    "MomentumSplit",
    "grasp_impulse",
    "inverse_inertia",
    "virtual_mass",
    "impulse_momentum_split",
    "CapturedSystem",
    "attach_target",
    "relative_twist",
    "SoftCaptureRun",
    "soft_capture",
    "ClosedChainRun",
    "simulate_closed_chain",
    "DetumbleRun",
    "detumble",
    "PHASES",
    "CaptureResult",
    "RecordedImpulse",
    "capture",
    "CaptureEnvelope",
    "capture_envelope",
    "OrbitComparison",
    "compare_in_orbit",
]
