"""One campaign sample: fly the perturbed plant under the controller built on the nominal model.

The scenario is a point-to-point manoeuvre (a joint-space quintic from the model's initial
angles to a goal, tracked by computed torque on the reduced EOM, eqs. 112–115, or by joint PD)
in a chosen maneuvering mode. The controller's model is always the *nominal* robot; the plant is
the nominal robot with the sample's inertia errors ([`spacearm.control.perturbed_model`][spacearm.control.perturbed_model]).
With no error the computed-torque run tracks the reference to integration accuracy, so every
tracking error a campaign reports is caused by the sampled inertia error.

Metrics of a run (the result file's ``metrics`` columns, [`METRIC_NAMES`][spacearm.campaign.scenario.METRIC_NAMES]):

- ``tracking_error_max``, ``tracking_error_rms``, ``tracking_error_final``: norm of
  ``q_ref − q`` (rad), over the run and at its end;
- ``attitude_excursion_max``: the largest rotation of the base from its initial attitude (deg);
- ``base_displacement_max``: the largest distance of the base CM from its start (m);
- ``base_rate_max``: the largest base angular rate ``|w0|`` over the run (rad/s), the base
  disturbance of the manoeuvre;
- ``saturation_events``: actuator saturation events (wheel torque or speed, thruster limits).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Dict, Optional, Tuple

import numpy as np

from .. import _core, control
from ..errors import ArgumentError, ShapeError, SimulationError
from ..sim.simulation import simulate
from .cmg import CmgUncertainty
from .flexibility import Flexibility
from .._util.pickling import reduce_through_constructor as _reduce_through_constructor

__all__ = ["Scenario", "METRIC_NAMES", "METRIC_UNITS", "evaluate", "plant", "control_model", "controller", "with_payload",
           "metrics_from_records", "non_finite_message", "attitude_angle_deg", "reference", "shaping_frequency"]

#: The metrics of each campaign sample, in the order of the result's columns (docs/campaigns.md).
METRIC_NAMES = (
    "tracking_error_max",
    "tracking_error_rms",
    "tracking_error_final",
    "attitude_excursion_max",
    "base_displacement_max",
    "base_rate_max",
    "saturation_events",
)

#: The unit of each metric, for labels.
METRIC_UNITS = {
    "tracking_error_max": "rad",
    "tracking_error_rms": "rad",
    "tracking_error_final": "rad",
    "attitude_excursion_max": "deg",
    "base_displacement_max": "m",
    "base_rate_max": "rad/s",
    "saturation_events": "count",
}

#: The control laws a campaign flies, as the core's kinds (control/spec.rs); the names a user
#: gives ("computed-torque", "pd", ...) resolve through the core's table (_core.controller_kind).
_CONTROLLERS = ("computed_torque", "joint_pd")


def _kind(name) -> "str | None":
    """The core's kind of a controller name, or None if it names none."""
    try:
        return _core.controller_kind(name) if isinstance(name, str) else None
    except ArgumentError:
        return None
_SHAPERS = ("zv", "zvd")


@dataclass(frozen=True)
class Scenario:
    """The manoeuvre every sample flies.

    ``mode``: a maneuvering mode (``"floating"`` … ``"flying"``, see [`spacearm.simulate`][spacearm.simulate]).
    ``controller``: ``"computed-torque"`` (reduced EOM on the nominal model) or ``"pd"``.
    The reference is a quintic from the model's initial ``q`` to ``q_goal`` (default: every
    joint ``q_offset`` rad further) over ``motion_fraction`` of ``duration``, then held.
    ``kp`` (1/s²) and ``kd`` (1/s) are the computed-torque gains; for PD they are joint
    stiffness (N·m/rad) and damping (N·m·s/rad). ``dt``: RK4 step (s).
    ``orbit``: a [`spacearm.Orbit`][spacearm.Orbit] to fly every sample in (docs/orbit.md; each
    plant's system CM put on it), kept as plain numbers (``r0``, ``v0``, μ, R, J2, whether J2
    acts) so that the spec travels as JSON; ``gravity_gradient``: whether the tidal wrenches act.
    ``flexibility``: a [`Flexibility`][spacearm.campaign.Flexibility] recipe: every plant gets a sloshing tank and/or a
    hinged panel with parameters drawn per sample, and computed torque is designed on the nominal
    flexible model with its passive joints frozen (the rigid lumped model, docs/campaigns.md).
    ``passive``: how that controller treats the passive joints, ``"frozen"`` (default: locked at
    rest in its model) or ``"drift"`` (measured from the plant's state, collocated partial
    feedback linearization; [`spacearm.control.ComputedTorque`][spacearm.control.ComputedTorque]); only with a flexibility recipe.
    ``shaping``: ``"zv"`` or ``"zvd"`` to fly the quintic convolved with that input shaper
    ([`spacearm.control.input_shaper`][spacearm.control.input_shaper]; the shaped move is longer by
    the shaper's duration) designed for ``shaping_frequency`` (rad/s) and ``shaping_damping``;
    without a frequency, the first mode of the controller's model
    ([`Robot.natural_frequencies`][spacearm.Robot.natural_frequencies] at its neutral
    configuration, the actuated joints held), which needs a flexibility recipe.
    ``cmg``: a [`CmgUncertainty`][spacearm.campaign.CmgUncertainty]: the wheel speed, rotor inertia and
    gimbal-axis misalignment of the nominal model's CMGs drawn per sample (docs/campaigns.md).
    """

    __reduce__ = _reduce_through_constructor  # unpickled through the validating constructor

    mode: str = "floating"
    controller: str = "computed-torque"
    duration: float = 4.0
    dt: float = 2e-3
    q_offset: float = 0.5
    q_goal: Optional[Tuple[float, ...]] = None
    motion_fraction: float = 0.75
    kp: float = 100.0
    kd: float = 20.0
    orbit: Optional[Tuple[float, ...]] = None
    gravity_gradient: bool = True
    flexibility: Optional[Flexibility] = None
    passive: str = "frozen"
    shaping: Optional[str] = None
    shaping_frequency: Optional[float] = None
    shaping_damping: float = 0.0
    cmg: Optional[CmgUncertainty] = None

    def __post_init__(self):
        from ..orbit import Orbit

        if isinstance(self.cmg, dict):
            object.__setattr__(self, "cmg", CmgUncertainty.from_dict(self.cmg))
        if self.cmg is not None and not isinstance(self.cmg, CmgUncertainty):
            raise ArgumentError(f"Scenario.cmg must be a spacearm.campaign.CmgUncertainty, got {type(self.cmg).__name__}")

        if isinstance(self.flexibility, dict):
            object.__setattr__(self, "flexibility", Flexibility.from_dict(self.flexibility))
        if self.flexibility is not None and not isinstance(self.flexibility, Flexibility):
            raise ArgumentError("Scenario.flexibility must be a spacearm.campaign.Flexibility, "
                                f"got {type(self.flexibility).__name__}")
        if self.flexibility is not None and _kind(self.controller) != "computed_torque":
            raise ArgumentError("Scenario.flexibility needs controller='computed-torque' (the flexible-plant study "
                                f"designs computed torque on the rigid model, docs/flexibility.md), got {self.controller!r}")

        if self.passive not in _core.PASSIVE_TREATMENTS:
            raise ArgumentError(f"Scenario.passive must be one of {_core.PASSIVE_TREATMENTS}, got {self.passive!r}")
        if self.passive != "frozen" and self.flexibility is None:
            raise ArgumentError("Scenario.passive='drift' needs a flexibility recipe (a rigid plant has no passive joints)")

        if isinstance(self.orbit, Orbit):
            o = self.orbit
            object.__setattr__(self, "orbit", tuple(float(v) for v in (*o.r0, *o.v0, o.body.mu, o.body.radius, o.body.j2,
                                                                       1.0 if o.j2 else 0.0)))
        elif self.orbit is not None:
            values = np.asarray(self.orbit, dtype=float)
            if values.shape != (10,) or not np.all(np.isfinite(values)):
                raise ArgumentError(f"Scenario.orbit must be a spacearm.Orbit (or its 10 numbers r0, v0, mu, R, J2, j2), got {self.orbit!r}")
            object.__setattr__(self, "orbit", tuple(float(v) for v in values))
        if self.shaping is not None and self.shaping not in _SHAPERS:
            raise ArgumentError(f"Scenario.shaping must be None, 'zv' or 'zvd', got {self.shaping!r}")
        if self.shaping_frequency is not None:
            f = self.shaping_frequency
            if isinstance(f, bool) or not isinstance(f, (int, float)) or not (math.isfinite(f) and f > 0):
                raise ArgumentError(f"Scenario.shaping_frequency must be None or a finite number > 0 (rad/s), got {f!r}")
            object.__setattr__(self, "shaping_frequency", float(f))
        z = self.shaping_damping
        if isinstance(z, bool) or not isinstance(z, (int, float)) or not (0.0 <= z < 1.0):
            raise ArgumentError(f"Scenario.shaping_damping must be a number in [0, 1), got {z!r}")
        object.__setattr__(self, "shaping_damping", float(z))
        if self.shaping is None and (self.shaping_frequency is not None or self.shaping_damping != 0.0):
            raise ArgumentError("Scenario.shaping_frequency and shaping_damping need shaping='zv' or 'zvd'")
        if self.shaping is not None and self.shaping_frequency is None and self.flexibility is None:
            raise ArgumentError("Scenario.shaping without shaping_frequency takes the first flexible mode of the "
                                "controller's model, which needs a flexibility recipe; give shaping_frequency (rad/s)")
        if not isinstance(self.gravity_gradient, bool):
            raise ArgumentError(f"Scenario.gravity_gradient must be True or False, got {self.gravity_gradient!r}")
        if _kind(self.controller) not in _CONTROLLERS:
            raise ArgumentError(f"Scenario.controller must be 'computed-torque' or 'pd' (the core's {' or '.join(_CONTROLLERS)}), "
                                f"got {self.controller!r}")
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
        """Plain data for the JSON spec (no ``flexibility`` or ``passive`` key without a recipe and
        no ``shaping*`` keys without shaping, so a rigid campaign's spec is what it was before
        flexible plants and shaped references existed)."""
        optional = ("flexibility", "passive", "shaping", "shaping_frequency", "shaping_damping", "cmg")
        d = {k: getattr(self, k) for k in self.__dataclass_fields__ if k not in optional}
        if self.flexibility is not None:
            d["flexibility"] = self.flexibility.to_dict()
            d["passive"] = self.passive
        if self.shaping is not None:
            d.update(shaping=self.shaping, shaping_frequency=self.shaping_frequency, shaping_damping=self.shaping_damping)
        if self.cmg is not None:
            d["cmg"] = self.cmg.to_dict()
        return d

    def orbit_model(self):
        """The scenario's [`spacearm.Orbit`][spacearm.Orbit] (``None`` in empty space)."""
        if self.orbit is None:
            return None
        from ..orbit import CentralBody, Orbit

        o = self.orbit
        return Orbit.from_state(o[0:3], o[3:6], body=CentralBody(mu=o[6], radius=o[7], j2=o[8]), j2=bool(o[9]))

    def run_options(self) -> dict:
        """The orbit keywords of the runs (``orbit``, ``gravity_gradient``), empty in empty space."""
        orbit = self.orbit_model()
        return {} if orbit is None else {"orbit": orbit, "gravity_gradient": self.gravity_gradient}

    def initial_configuration(self, robot) -> np.ndarray:
        """The sample's initial configuration: the neutral one, in orbit shifted so that the
        system CM is on the orbit (docs/orbit.md)."""
        x0 = np.array(robot.neutral_configuration(), dtype=float)
        if self.orbit is not None:
            x0[:3] -= robot.center_of_mass(x0)
        return x0

    def initial_velocity(self, robot, params: Dict[str, float]) -> np.ndarray:
        """The sample's initial ``u``: at rest, or with a CMG recipe every rotor at the drawn
        ``cmg_wheel_speed`` ([`Robot.cmg_velocity`][spacearm.Robot.cmg_velocity])."""
        if self.cmg is None:
            return np.zeros(robot.nu)
        return self.cmg.initial_velocity(robot, params)


def attitude_angle_deg(quat0: np.ndarray, quats: np.ndarray) -> np.ndarray:
    """Rotation angle (deg) between the attitude ``quat0`` (``(..., 4)``, xyzw) and each
    ``quats[..., k, :]``: ``2 acos |q0 · q|``. The dot product is written out term by term so
    that a batch of runs and one run give the same bits (a matrix product may sum in another
    order)."""
    q0 = quat0[..., None, :]
    dots = (quats[..., 0] * q0[..., 0] + quats[..., 1] * q0[..., 1]) + (quats[..., 2] * q0[..., 2]
                                                                        + quats[..., 3] * q0[..., 3])
    return np.degrees(2.0 * np.arccos(np.clip(np.abs(dots), 0.0, 1.0)))


def metrics_from_records(tracking_error: np.ndarray, x: np.ndarray, saturation_events: np.ndarray,
                         u: np.ndarray) -> np.ndarray:
    """The metrics (columns [`METRIC_NAMES`][spacearm.campaign.scenario.METRIC_NAMES]) of ``B`` runs from their records.

    ``tracking_error`` ``(B, K)`` (rad), ``x`` ``(B, K, 7+N)``, ``saturation_events`` ``(B,)`` and
    ``u`` ``(B, K, 6+N)`` (``[v0, w0, qd]``), every step recorded. Each row of the result
    depends on its own run only, computed with the
    same operations whatever ``B`` (so one run alone and the same run in a batch agree bit for
    bit); a row with a non-finite metric is the caller's to report.
    """
    error = np.asarray(tracking_error, dtype=float)
    x = np.asarray(x, dtype=float)
    displacement = np.linalg.norm(x[:, :, 0:3] - x[:, :1, 0:3], axis=-1)
    quats = x[:, :, 3:7]
    u = np.asarray(u, dtype=float)
    # |w0| written out term by term, like the attitude angle: the same bits for one run or many.
    w = u[:, :, 3:6]
    rate = np.sqrt((w[..., 0] * w[..., 0] + w[..., 1] * w[..., 1]) + w[..., 2] * w[..., 2])
    columns = {
        "tracking_error_max": np.max(error, axis=1),
        "tracking_error_rms": np.sqrt(np.mean(error**2, axis=1)),
        "tracking_error_final": error[:, -1],
        "attitude_excursion_max": np.max(attitude_angle_deg(quats[:, 0, :], quats), axis=1),
        "base_displacement_max": np.max(displacement, axis=1),
        "base_rate_max": np.max(rate, axis=1),
        "saturation_events": np.asarray(saturation_events, dtype=float),
    }
    return np.stack([columns[name] for name in METRIC_NAMES], axis=1)


def non_finite_message(metrics_row: np.ndarray) -> str:
    """The failure message of a run whose metrics are not all finite ('' if they are)."""
    bad = [name for name, v in zip(METRIC_NAMES, metrics_row) if not math.isfinite(v)]
    return f"the simulation produced non-finite {', '.join(bad)}" if bad else ""


def with_payload(robot, mass: float):
    """``robot`` holding a point payload of ``mass`` kg at its end effector.

    The payload is a point mass on a fixed joint at the end-effector point (so the joint space
    is unchanged and the end-effector body's mass properties merge by the model's own
    parallel-axis rules), attached by the core's model edit ([`Robot.attach_body`][spacearm.Robot.attach_body],
    ``model/edit.rs``: the rest of the model bit for bit, no builder replay).
    """
    if mass == 0:
        return robot
    if robot.end_effector is None:
        raise ArgumentError("a payload needs an end effector to hold it; the model defines none")
    body, offset = robot.resolve_point(robot.end_effector)
    return robot.attach_body("campaign_payload", body=robot.body_names[body], mass=float(mass), origin=list(offset))


def plant(nominal, params: Dict[str, float], flexibility: Optional[Flexibility] = None, cmg: Optional[CmgUncertainty] = None):
    """The plant of a sample: ``nominal`` with the inertia errors ``params`` (the
    [`PARAMETER_NAMES`][spacearm.campaign.perturbation.PARAMETER_NAMES]) and its payload, then the flexible parts of
    ``flexibility`` with the drawn values in ``params``, then its CMGs perturbed as ``cmg`` says."""
    perturbed = control.perturbed_model(
        nominal,
        base_mass_scale=params["base_mass_scale"],
        base_inertia_scale=params["base_inertia_scale"],
        link_mass_scale=params["link_mass_scale"],
        slosh_fraction=params["slosh_fraction"],
        slosh_offset=(params["slosh_offset_x"], params["slosh_offset_y"], params["slosh_offset_z"]),
    )
    rigid = with_payload(perturbed, params["payload_mass"])
    flexible = rigid if flexibility is None else flexibility.apply(rigid, params)
    return flexible if cmg is None else cmg.apply(flexible, params)


def control_model(nominal, scenario: Scenario):
    """The model the controller is designed on and the rollouts are keyed by: ``nominal``, or with
    a flexibility recipe the nominal robot with its flexible parts at their nominal values."""
    if scenario.flexibility is None:
        return nominal
    return scenario.flexibility.apply(nominal, scenario.flexibility.nominal())


def shaping_frequency(nominal, scenario: Scenario) -> float:
    """The frequency (rad/s) the scenario's input shaper is designed for: ``shaping_frequency``, or
    the first mode of [`control_model`][spacearm.campaign.scenario.control_model] at its neutral
    configuration with the actuated joints held ([`Robot.natural_frequencies`][spacearm.Robot.natural_frequencies])."""
    if scenario.shaping_frequency is not None:
        return scenario.shaping_frequency
    model = control_model(nominal, scenario)
    modes = model.natural_frequencies(model.neutral_configuration()).frequencies
    if len(modes) == 0 or not (math.isfinite(modes[0]) and modes[0] > 0):
        raise ArgumentError("Scenario.shaping: the controller's model has no flexible mode to shape against "
                            f"(natural frequencies {list(modes)}); give shaping_frequency (rad/s)")
    return float(modes[0])


def reference(nominal, scenario: Scenario):
    """The joint reference every sample tracks: the quintic from ``nominal``'s initial ``q`` to the
    goal over ``motion_fraction · duration``, convolved with the scenario's input shaper if it has one."""
    q0 = np.asarray(nominal.initial_q, dtype=float)
    goal = np.asarray(scenario.goal(nominal), dtype=float)
    # The arm laws' joints (Robot.actuated_arm_dofs): the passive joints of the nominal model,
    # its reaction wheels and its CMGs' gimbals and rotors take no reference.
    arm = np.asarray(nominal.actuated_arm_dofs, dtype=int)
    if len(arm) != len(q0):
        q0, goal = q0[arm], goal[arm]
    move = control.QuinticJoint(q0, goal, 0.0, scenario.motion_fraction * scenario.duration)
    if scenario.shaping is None:
        return move
    shaper = control.input_shaper(scenario.shaping, frequency=shaping_frequency(nominal, scenario),
                                  damping=scenario.shaping_damping)
    return shaper.shape(move)


def controller(nominal, scenario: Scenario):
    """The controller every sample flies with, built on the *nominal* model: the
    [`reference`][spacearm.campaign.scenario.reference] tracked by computed torque or joint PD.
    With a flexibility recipe, computed torque uses
    [`control_model`][spacearm.campaign.scenario.control_model] with its passive joints treated as
    ``scenario.passive`` says (frozen at rest, or measured drift); the reference is over
    ``nominal``'s joints (the plant's actuated ones)."""
    reference_ = reference(nominal, scenario)
    if _kind(scenario.controller) == "computed_torque":
        if scenario.flexibility is not None:
            return control.ComputedTorque(scenario.kp, scenario.kd, reference_, model=control_model(nominal, scenario),
                                          passive=scenario.passive)
        return control.ComputedTorque(scenario.kp, scenario.kd, reference_, model=nominal)
    return control.JointPD(scenario.kp, scenario.kd, reference_)


def evaluate(nominal, scenario: Scenario, params: Dict[str, float]) -> Dict[str, float]:
    """Fly one sample with [`spacearm.simulate`][spacearm.simulate]: the metrics of [`METRIC_NAMES`][spacearm.campaign.scenario.METRIC_NAMES] for the
    plant drawn as ``params``. The reference every batched run is checked against."""
    p = plant(nominal, params, scenario.flexibility, scenario.cmg)
    traj = simulate(p, scenario.duration, x0=scenario.initial_configuration(p), u0=scenario.initial_velocity(p, params),
                    mode=scenario.mode, dt=scenario.dt,
                    controller=controller(nominal, scenario), **scenario.run_options())
    saturation = len(traj["saturation_t"]) if traj.has("saturation_t") else 0
    row = metrics_from_records(traj["tracking_error"][None], traj["x"][None], np.array([saturation]), traj["u"][None])[0]
    message = non_finite_message(row)
    if message:
        raise SimulationError(message)
    return {name: float(v) for name, v in zip(METRIC_NAMES, row)}
