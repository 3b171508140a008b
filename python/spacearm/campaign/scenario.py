"""One campaign sample: fly the perturbed plant under the controller built on the nominal model.

The scenario is a point-to-point manoeuvre (a joint-space quintic from the model's initial
angles to a goal, tracked by computed torque on the reduced EOM, eqs. 112–115, or by joint PD)
in a chosen maneuvering mode. The controller's model is always the *nominal* robot; the plant is
the nominal robot with the sample's inertia errors (:func:`spacearm.control.perturbed_model`).
With no error the computed-torque run tracks the reference to integration accuracy, so every
tracking error a campaign reports is caused by the sampled inertia error.

Metrics of a run (the result file's ``metrics`` columns, :data:`METRIC_NAMES`):

- ``tracking_error_max``, ``tracking_error_rms``, ``tracking_error_final``: norm of
  ``q_ref − q`` (rad), over the run and at its end;
- ``attitude_excursion_max``: the largest rotation of the base from its initial attitude (deg);
- ``base_displacement_max``: the largest distance of the base CM from its start (m);
- ``saturation_events``: actuator saturation events (wheel torque or speed, thruster limits).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Dict, Optional, Tuple

import numpy as np

from ..errors import ArgumentError, ShapeError, SimulationError

__all__ = ["Scenario", "METRIC_NAMES", "METRIC_UNITS", "evaluate", "with_payload"]

METRIC_NAMES = (
    "tracking_error_max",
    "tracking_error_rms",
    "tracking_error_final",
    "attitude_excursion_max",
    "base_displacement_max",
    "saturation_events",
)

#: The unit of each metric, for labels.
METRIC_UNITS = {
    "tracking_error_max": "rad",
    "tracking_error_rms": "rad",
    "tracking_error_final": "rad",
    "attitude_excursion_max": "deg",
    "base_displacement_max": "m",
    "saturation_events": "count",
}

_CONTROLLERS = ("computed-torque", "pd")


@dataclass(frozen=True)
class Scenario:
    """The manoeuvre every sample flies.

    ``mode``: a maneuvering mode (``"floating"`` … ``"flying"``, see :func:`spacearm.simulate`).
    ``controller``: ``"computed-torque"`` (reduced EOM on the nominal model) or ``"pd"``.
    The reference is a quintic from the model's initial ``q`` to ``q_goal`` (default: every
    joint ``q_offset`` rad further) over ``motion_fraction`` of ``duration``, then held.
    ``kp`` (1/s²) and ``kd`` (1/s) are the computed-torque gains; for PD they are joint
    stiffness (N·m/rad) and damping (N·m·s/rad). ``dt``: RK4 step (s).
    """

    mode: str = "floating"
    controller: str = "computed-torque"
    duration: float = 4.0
    dt: float = 2e-3
    q_offset: float = 0.5
    q_goal: Optional[Tuple[float, ...]] = None
    motion_fraction: float = 0.75
    kp: float = 100.0
    kd: float = 20.0

    def __post_init__(self):
        if self.controller not in _CONTROLLERS:
            raise ArgumentError(f"Scenario.controller must be one of {', '.join(_CONTROLLERS)}, got {self.controller!r}")
        for name in ("duration", "dt", "kp", "kd"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ArgumentError(f"Scenario.{name} must be a finite number > 0, got {value!r}")
        if not (0 < self.motion_fraction <= 1):
            raise ArgumentError(f"Scenario.motion_fraction must be in (0, 1], got {self.motion_fraction!r}")
        if self.dt > self.duration:
            raise ArgumentError(f"Scenario.dt ({self.dt} s) must not exceed the duration ({self.duration} s)")
        if self.q_goal is not None:
            goal = np.asarray(self.q_goal, dtype=float)
            if goal.ndim != 1 or not np.all(np.isfinite(goal)):
                raise ShapeError(f"Scenario.q_goal must be a finite 1-D sequence, got {self.q_goal!r}")
            object.__setattr__(self, "q_goal", tuple(float(v) for v in goal))

    def goal(self, robot) -> np.ndarray:
        q0 = np.asarray(robot.initial_q, dtype=float)
        if self.q_goal is None:
            return q0 + self.q_offset
        if len(self.q_goal) != robot.n_dof:
            raise ShapeError(f"Scenario.q_goal must have N = {robot.n_dof} values, got {len(self.q_goal)}")
        return np.asarray(self.q_goal)

    def to_dict(self) -> dict:
        return asdict(self)


def _attitude_angle_deg(quat0: np.ndarray, quats: np.ndarray) -> np.ndarray:
    """Rotation angle (deg) between the attitude ``quat0`` and each row of ``quats`` (xyzw)."""
    dots = np.clip(np.abs(quats @ quat0), 0.0, 1.0)
    return np.degrees(2.0 * np.arccos(dots))


def with_payload(robot, mass: float):
    """``robot`` holding a point payload of ``mass`` kg at its end effector.

    The payload is a point mass on a fixed joint at the end-effector point (so the joint space
    is unchanged and the end-effector body's mass properties merge by the model's own
    parallel-axis rules), attached with :meth:`spacearm.model.builder.RobotBuilder.attach_payload`.
    """
    if mass == 0:
        return robot
    if robot.end_effector is None:
        raise ArgumentError("a payload needs an end effector to hold it; the model defines none")
    ee = robot.description.point(robot.end_effector)
    builder = robot.to_builder()
    builder.attach_payload("campaign_payload", body=ee.body, mass=float(mass), origin=ee.offset.tolist())
    return builder.build()


def evaluate(nominal, scenario: Scenario, params: Dict[str, float]) -> Dict[str, float]:
    """Fly one sample: the metrics of :data:`METRIC_NAMES` for the plant drawn as ``params``."""
    from .. import control, simulate

    plant = control.perturbed_model(
        nominal,
        base_mass_scale=params["base_mass_scale"],
        base_inertia_scale=params["base_inertia_scale"],
        link_mass_scale=params["link_mass_scale"],
        slosh_fraction=params["slosh_fraction"],
        slosh_offset=(params["slosh_offset_x"], params["slosh_offset_y"], params["slosh_offset_z"]),
    )
    plant = with_payload(plant, params["payload_mass"])
    q0 = np.asarray(nominal.initial_q, dtype=float)
    reference = control.QuinticJoint(q0, scenario.goal(nominal), 0.0, scenario.motion_fraction * scenario.duration)
    if scenario.controller == "computed-torque":
        controller = control.ComputedTorque(scenario.kp, scenario.kd, reference, model=nominal)
    else:
        controller = control.JointPD(scenario.kp, scenario.kd, reference)
    traj = simulate(plant, scenario.duration, mode=scenario.mode, dt=scenario.dt, controller=controller)
    error = np.asarray(traj["tracking_error"], dtype=float)
    x = np.asarray(traj["x"], dtype=float)
    quats = x[:, 3:7]
    displacement = np.linalg.norm(x[:, 0:3] - x[0, 0:3], axis=1)
    metrics = {
        "tracking_error_max": float(np.max(error)),
        "tracking_error_rms": float(np.sqrt(np.mean(error**2))),
        "tracking_error_final": float(error[-1]),
        "attitude_excursion_max": float(np.max(_attitude_angle_deg(quats[0], quats))),
        "base_displacement_max": float(np.max(displacement)),
        "saturation_events": float(len(traj["saturation_t"]) if traj.has("saturation_t") else 0),
    }
    bad = [k for k, v in metrics.items() if not math.isfinite(v)]
    if bad:
        raise SimulationError(f"the simulation produced non-finite {', '.join(bad)}")
    return metrics
