"""The whole capture in one call ([`capture`][spacearm.capture.capture]): approach → capture → post-capture → detumble,
with phase markers and the momentum ledger of robot + target.

Where it runs: for a rigid target (in empty space or in orbit) the whole mission is **one core
run** (``spacearm_core::sim::capture::run_capture``; its description the core's ``CaptureSpec``,
``sim/capture_spec.rs``, with the one validation of every argument): this module reads the
arguments into that spec, makes the call, and wraps the binding's ``CaptureRun`` (``result.run``)
in [`CaptureResult`][spacearm.capture.CaptureResult], which adds the figures and the file. A
jointed target (``kind="point"`` only) still runs phase by phase here, each phase a core run
(``_capture_phases``; docs/capture.md, "Where the mission runs").

Phases (``PHASES``; ``result.phase`` holds the index at every sample):

0. **approach** — the native [`ResolvedMotionRate`][spacearm.control.ResolvedMotionRate] of the grasp point
   towards the *moving* grasp point of the tumbling target (a
   [`FreeBodyPoint`][spacearm.control.FreeBodyPoint], propagated by the core), through the generalized
   Jacobian: ``q̇_cmd = J*_vᵀ (J*_v J*_vᵀ + λ² E)⁻¹ (ṗ_t + k (p_t − p) − v_drift)`` over the arm
   joints (eq. 110; ``v_drift`` the point velocity the system momentum and the wheels make; ``λ``
   the damping law of docs/singularities.md with ``λ_max = rmrc_damping``), scaled as a whole to
   at most ``max_joint_rate``, followed through ``τ = H* k_v (q̇_cmd − q̇) + c*``. Reaction wheels
   are not arm joints: the approach gives them no torque. In the flying mode the native
   [`MomentumDamping`][spacearm.control.MomentumDamping] holds the system momentum at zero meanwhile. The
   approach ends at the grasp: the core stops the run when the two grasp points come within
   ``capture_tolerance`` ([`StopAtGap`][spacearm.sim.events.StopAtGap]), at the instant it
   locates within the step (docs/simulation-core.md, "Events"), not at the next sample (a
   jointed target, whose reference is a sampled path: at the first sample within the tolerance).
1. **capture** — ``rigid`` and ``point``: the impulse of [`grasp_impulse`][spacearm.capture.grasp_impulse] (one extra
   sample at the same instant, after the jump); ``soft``: the wrist impedance of
   [`soft_capture`][spacearm.capture.soft_capture] for ``soft_time``, then a rigid lock of what relative motion remains.
2. **post-capture** — the captured system (rigid, soft: the target attached as a payload, model
   edited at run time; point: the robot alone, the target flying off) with the joints braked.
   The thrusters act in the approach and the detumble only: the soft phase and this one are
   unactuated at the base in either mode.
3. **detumble** — [`detumble`][spacearm.capture.detumble] in ``mode``.

Momentum ledger: ``P`` and ``L`` (about the origin of 𝒥) of robot + target at every sample. In
floating mode nothing external acts, and their drift is the integration error
(``result.drift``): the core's drift (``max |v − v(0)|`` relative to the largest sum of the
bodies' own momentum magnitudes, robot and target; docs/simulation-core.md), the one definition
``Trajectory.drift`` and the simulator use.

**In orbit** (``orbit=``; docs/orbit.md, "Capture in orbit"): every phase runs in the orbit's
frame (states relative to the orbit's point ``O``, ECI axes), each phase's run starting from
``O``'s state at its start time; the free target is the core's free body in orbit (tidal drift,
its own gravity-gradient tumble), the approach's reference with it. Momentum is no longer
conserved, and the ledger reports the **balance** instead (``result.ledger == "balance"``):
``result.drift`` is ``max |c(t) − c(0) − ∫ w dt|`` over ``P`` and ``L_origin`` (``w`` the
external wrenches: the tidal wrenches of the robot, of the captured system and of the free
target, and in the flying mode the thrusters'; the integral by the trapezoid rule over the
samples), relative to the same scale as the drift. The result also holds ``r_cm_eci``,
``v_cm_eci`` (the chaser's system CM: the robot before the grasp, robot + target after),
``external_wrench`` (T, 6), ``target_lvlh`` (T, 6: the target's CM relative to the robot's own
CM, the same reference before and after the grasp, in the robot's LVLH) and ``attitude_lvlh()``. Not in orbit: ``kind="soft"`` and jointed targets
(an ``ArgumentError`` says so).
"""

from __future__ import annotations

import json
import math
import os
from typing import Optional

import numpy as np

from .. import _core
from .._util.arrays import number, vector
from ..control import Combined, MomentumDamping, ResolvedMotionRate, TorqueLimit
from ..errors import ArgumentError, SimulationError
from ..rotations import rotation_vector
from ..sim.simulation import simulate
from .captured import combined_model
from .detumbling import detumble
from .impact import CAPTURE_TOLERANCE, _check_target, grasp_impulse

__all__ = ["capture", "CaptureResult", "RecordedImpulse", "PHASES", "CAPTURE_KINDS", "MAX_CAPTURE_SAMPLES", "MAX_TURN_PER_SAMPLE"]

#: The most samples a capture may record over its phases (``(approach + soft + post +
#: detumble time) / dt``): more is refused before anything runs (docs/capture.md, "Grasps that
#: are refused"; the core's rule, ``sim/capture_spec.rs``).
MAX_CAPTURE_SAMPLES = _core.MAX_CAPTURE_SAMPLES

#: The largest angle, rad, the target may turn between two samples (``|ω| dt``): a faster spin
#: is not resolved by the recording nor by the free-body reference, and is refused (the core's rule).
MAX_TURN_PER_SAMPLE = _core.MAX_TURN_PER_SAMPLE


#: Format tag of the ``.npz`` that [`CaptureResult.save`][spacearm.capture.CaptureResult.save] writes
#: (``/2``: everything [`CaptureResult.load`][spacearm.capture.CaptureResult.load] needs; ``/1`` files
#: hold the arrays and models only, enough for ``spacearm view``).
FILE_FORMAT = "spacearm.CaptureResult/2"
#: The format tags ``spacearm view`` reads.
VIEWABLE_FORMATS = ("spacearm.CaptureResult/1", FILE_FORMAT)

#: The attributes of a [`GraspImpulse`][spacearm.capture.GraspImpulse] a capture file keeps
#: (``impact.<name>``; ``normal`` only where it is not None).
_IMPULSE_FIELDS = ("kind", "du", "target_dtwist", "impulse", "point", "gap", "u_after", "target_state_after",
                   "relative_twist_before", "relative_twist_after", "G_robot", "G_target", "energy_lost",
                   "locking_work", "target_u_after", "normal", "locking_impulse")
#: The scalars of a capture kept in the file's ``__meta__`` JSON.
_META_FIELDS = ("mode", "kind", "time_to_detumble", "residual_spin", "drift", "ledger", "gravity_gradient")


class RecordedImpulse:
    """A [`GraspImpulse`][spacearm.capture.GraspImpulse] read back from a capture file
    ([`CaptureResult.load`][spacearm.capture.CaptureResult.load]): the same attributes, the
    saved values (read-only arrays), nothing recomputed."""

    __slots__ = _IMPULSE_FIELDS

    def __init__(self, **fields):
        for name in _IMPULSE_FIELDS:
            value = fields[name]
            if isinstance(value, np.ndarray):
                value.setflags(write=False)
            object.__setattr__(self, name, value)

    def __setattr__(self, name, value):
        raise AttributeError(f"RecordedImpulse is read-only (attribute '{name}')")

    def __repr__(self) -> str:
        return (f"<RecordedImpulse {self.kind}: |f̂| {np.linalg.norm(self.impulse[:3]):.4e} N s, "
                f"|n̂| {np.linalg.norm(self.impulse[3:]):.4e} N m s, energy_lost {self.energy_lost:.4e} J, gap {self.gap:.3e} m>")

#: The phases of [`capture`][spacearm.capture.capture], in order (docs/capture.md).
PHASES = ("approach", "capture", "post-capture", "detumble")
#: The grasp models [`capture`][spacearm.capture.capture] accepts as ``kind``.
CAPTURE_KINDS = tuple(_core.CAPTURE_KINDS)


class CaptureResult:
    """The recorded capture: arrays over samples ``t`` (s), and the impact.

    Attributes: ``t`` (T,), ``phase`` (T,) indices into [`PHASES`][spacearm.capture.sequence.PHASES], ``x`` (T, 7+N) and ``u``
    (T, 6+N) of the robot (its own coordinates: the payload adds none), ``tau`` (T, N),
    ``base_wrench`` (T, 6), ``target`` (T, 13) target states, ``P`` and ``L`` (T, 3) robot +
    target momentum about the origin of 𝒥, ``grasp_wrench`` (T, 6) the wrench holding the
    target, ``[f; n]`` with the moment about the target's CM (zero while it is free), ``impact`` ([`GraspImpulse`][spacearm.capture.GraspImpulse]), ``robot`` (before
    capture), ``captured`` (the combined model, or ``None`` for a point contact), ``mode``,
    ``kind``, ``time_to_detumble`` (s after the detumble phase starts), ``residual_spin`` (rad/s),
    ``drift`` (relative, ``{"P": ..., "L": ...}``).
    """

    #: The names of the phases, indexed by ``phase``.
    phase_names = PHASES

    def __init__(self, **fields):
        self.__dict__.update(fields)

    @classmethod
    def _of_run(cls, run, robot, target, mode: str, kind: str, orbit=None, gravity_gradient=None) -> "CaptureResult":
        """The result of the core's mission (``_core.CaptureRun``, kept as ``run``): its arrays,
        impact, captured system and ledger, read as they are."""
        from .captured import CapturedSystem

        captured = None
        if run.captured is not None:
            (x, u), (payload, gripper) = run.captured_state, run.captured_names
            captured = CapturedSystem(robot._edited(run.captured), x, u, payload, gripper)
        return cls(t=run.t, phase=run.phase, x=run.x, u=run.u, tau=run.tau, base_wrench=run.base_wrench, target=run.target,
                   P=run.P, L=run.L, grasp_wrench=run.grasp_wrench, impact=run.impact,
                   soft_impact=run.impact if kind == "soft" else None, robot=robot, captured=captured, target_model=target, mode=mode,
                   kind=kind, time_to_detumble=run.time_to_detumble, residual_spin=run.residual_spin,
                   drift={"P": run.drift_p, "L": run.drift_l}, ledger=run.ledger, orbit=orbit, gravity_gradient=gravity_gradient, run=run,
                   **({} if orbit is None else {"external_wrench": run.external_wrench, "external_impulse": run.external_impulse,
                                               "r_cm_eci": run.r_cm_eci, "v_cm_eci": run.v_cm_eci, "target_lvlh": run.target_lvlh}))

    def __repr__(self) -> str:
        detumble = self.time_to_detumble
        return (f"<CaptureResult '{self.robot.name}' {self.kind} grasp, {self.mode}: {len(self.t)} samples, t = 0..{self.t[-1]:.4g} s, "
                f"grasp at {self.phase_start('capture'):.4g} s, detumbled "
                f"{'never' if not math.isfinite(detumble) else f'{detumble:.4g} s after the detumble starts'}>")

    @property
    def in_orbit(self) -> bool:
        """Whether the capture ran in orbit (``orbit=``)."""
        return getattr(self, "orbit", None) is not None

    def attitude_lvlh(self) -> np.ndarray:
        """The base attitude relative to the LVLH of the chaser's system CM, (T, 3, 3) base →
        LVLH (docs/orbit.md). Captures in orbit only."""
        if not self.in_orbit:
            raise ArgumentError("the capture did not run in orbit (capture(..., orbit=spacearm.Orbit...))")
        from ..orbit import attitude_lvlh

        return attitude_lvlh(self.r_cm_eci, self.v_cm_eci, self.x[:, 3:7])

    def balance_residual(self) -> np.ndarray:
        """In orbit: ``[P − P(0) − ∫F dt, L − L(0) − ∫N dt]`` (T, 6) of robot + target, the
        external wrench ``external_wrench`` integrated by the trapezoid rule (``external_impulse``;
        the ledger's balance, module docstring)."""
        if not self.in_orbit:
            raise ArgumentError("the capture did not run in orbit: its ledger is conservation (P - P(0), L - L(0))")
        return _balance_residual(self.P, self.L, self.external_impulse)

    def phase_start(self, name: str) -> float:
        """Time at which a phase starts."""
        idx = np.nonzero(self.phase == PHASES.index(name))[0]
        return float(self.t[idx[0]]) if idx.size else math.nan

    def summary(self) -> dict:
        """The figures of the capture (what the CLI prints)."""
        imp = self.impact
        post = self.phase >= 1
        return {
            "mode": self.mode,
            "kind": self.kind,
            "capture_time": self.phase_start("capture"),
            "gap": imp.gap,
            "impulse": imp.impulse.copy(),
            "impulse_force_norm": float(np.linalg.norm(imp.impulse[:3])),
            "impulse_moment_norm": float(np.linalg.norm(imp.impulse[3:])),
            "base_dv": imp.du[:3].copy(),
            "base_dw": imp.du[3:6].copy(),
            "energy_lost": imp.energy_lost,
            "peak_grasp_force": float(np.linalg.norm(self.grasp_wrench[post, :3], axis=1).max()),
            "peak_grasp_torque": float(np.linalg.norm(self.grasp_wrench[post, 3:], axis=1).max()),
            "peak_joint_torque": float(np.abs(self.tau).max()) if self.tau.size else 0.0,
            "time_to_detumble": self.time_to_detumble,
            "residual_spin": self.residual_spin,
            "drift_P": self.drift["P"],
            "drift_L": self.drift["L"],
            "ledger": self.ledger,
        } | (self._orbit_summary() if self.in_orbit else {})

    def _orbit_summary(self) -> dict:
        """The orbital figures of the summary: the orbit, the target's LVLH offset at the grasp,
        the tidal torque's integral, the final attitude relative to LVLH."""
        el = self.orbit.elements()
        k = int(np.nonzero(self.phase >= 1)[0][0])
        impulse = self.external_impulse[-1]
        # The base's rotation angle from LVLH at the start and at the end (the rotation vector's
        # norm, the core's rotations): the start is given too, since a run need not start in LVLH.
        r = self.attitude_lvlh()
        start, end = (np.degrees(np.linalg.norm(rotation_vector(r[k]))) for k in (0, -1))
        return {
            "orbit_altitude_km": (el.a - self.orbit.body.radius) / 1e3,
            "orbit_inclination_deg": float(np.degrees(el.i)),
            "gravity_gradient": self.gravity_gradient,
            "target_lvlh_at_grasp": self.target_lvlh[k, :3].copy(),
            "external_impulse_norm": float(np.linalg.norm(impulse[:3])),
            "external_angular_impulse_norm": float(np.linalg.norm(impulse[3:])),
            "initial_lvlh_angle_deg": float(start),
            "final_lvlh_angle_deg": float(end),
        }

    def arrays(self) -> dict:
        """The arrays saved by [`save`][spacearm.capture.CaptureResult.save]."""
        return {
            "t": self.t, "phase": self.phase, "P": self.P, "L": self.L, "x": self.x, "u": self.u, "tau": self.tau,
            "base_wrench": self.base_wrench, "target": self.target, "grasp_wrench": self.grasp_wrench,
            "impulse": self.impact.impulse, "du": self.impact.du, "target_dtwist": self.impact.target_dtwist,
            "impact_point": self.impact.point, "phase_names": np.array(PHASES),
        } | ({"r_cm_eci": self.r_cm_eci, "v_cm_eci": self.v_cm_eci, "target_lvlh": self.target_lvlh,
              "external_wrench": self.external_wrench, "external_impulse": self.external_impulse} if self.in_orbit else {})

    def save(self, path) -> None:
        """Write the arrays to an ``.npz`` file (atomically: no partial file), with the robot's
        and the target's models as TOML text (``__model_toml__``, ``__target_toml__``), the
        grasp and mode (``kind``, ``mode``) and the format tag ``__format__`` =
        ``FILE_FORMAT`` (``spacearm.CaptureResult/1``), so that ``spacearm view`` can
        draw the record."""
        from .._util.atomic import atomic_open
        from ..io.model_file import dumps_toml

        payload = dict(self.arrays())
        payload["__format__"] = np.array(FILE_FORMAT)
        payload["__model_toml__"] = np.array(dumps_toml(self.robot))
        payload["__target_toml__"] = np.array(dumps_toml(self.target_model.body))
        payload["__target_name__"] = np.array(self.target_model.name)
        payload["kind"], payload["mode"] = np.array(self.kind), np.array(self.mode)
        # What load() needs besides: the scalars, the impact(s), the captured system, the orbit.
        meta = {key: getattr(self, key) for key in _META_FIELDS}
        meta["soft_impact"] = self.soft_impact is not None
        meta["captured"] = None if self.captured is None else {"payload": self.captured.payload, "gripper": self.captured.gripper}
        if self.in_orbit:
            body = self.orbit.body
            meta["orbit"] = {"mu": body.mu, "radius": body.radius, "body_j2": body.j2, "j2": self.orbit.j2}
            payload["orbit.r0"], payload["orbit.v0"] = np.asarray(self.orbit.r0), np.asarray(self.orbit.v0)
        payload["__meta__"] = np.array(json.dumps(meta, allow_nan=True))
        for name in _IMPULSE_FIELDS:
            value = getattr(self.impact, name)
            if value is not None:
                payload[f"impact.{name}"] = np.asarray(value)
        if self.captured is not None:
            payload["__captured_toml__"] = np.array(dumps_toml(self.captured.robot))
            payload["captured.x"], payload["captured.u"] = np.asarray(self.captured.x), np.asarray(self.captured.u)
        with atomic_open(path, "wb") as fh:
            np.savez(fh, **payload)

    @classmethod
    def load(cls, path) -> "CaptureResult":
        """Read a capture written by [`save`][spacearm.capture.CaptureResult.save]: every array
        as saved (bit for bit), the robot, the target and the captured system rebuilt from their
        embedded models, the impact as a [`RecordedImpulse`][spacearm.capture.RecordedImpulse]
        (the same attributes), the orbit from its initial state. A damaged file, a file of
        another kind or of the older format ``spacearm.CaptureResult/1`` (the arrays only) raises
        [`ArgumentError`][spacearm.ArgumentError] naming what is wrong."""
        from .._util.npz import open_npz
        from ..io.model_file import loads_toml
        from .captured import CapturedSystem
        from .target import Target

        with open_npz(path, "spacearm capture") as files:
            files = dict(files)
        where = f"'{os.fspath(path)}'"
        fmt = str(files.get("__format__", ""))
        if fmt in VIEWABLE_FORMATS and fmt != FILE_FORMAT:
            raise ArgumentError(f"{where}: a capture file of an older spacearm ({fmt!r}: the arrays only, no impact or "
                                f"summary figures): 'spacearm view' draws it; run the capture again to load it into Python")
        if fmt != FILE_FORMAT:
            raise ArgumentError(f"{where}: not a spacearm capture file (format tag {fmt!r}, expected {FILE_FORMAT!r}: "
                                "what CaptureResult.save and 'spacearm capture --out' write)")

        def take(key):
            if key not in files:
                raise ArgumentError(f"{where}: the capture file has no '{key}' (damaged or edited; expected every "
                                    f"entry CaptureResult.save writes)")
            return files[key]

        try:
            meta = json.loads(str(take("__meta__")))
        except json.JSONDecodeError as exc:
            raise ArgumentError(f"{where}: the capture file's __meta__ is not JSON ({exc})") from None
        missing = [k for k in (*_META_FIELDS, "soft_impact", "captured") if not isinstance(meta, dict) or k not in meta]
        if missing:
            raise ArgumentError(f"{where}: the capture file's __meta__ lacks {', '.join(missing)}")
        robot = loads_toml(str(take("__model_toml__")), source=f"{path} (embedded model)")
        body = loads_toml(str(take("__target_toml__")), source=f"{path} (embedded target model)")
        target = Target.from_robot(body, name=str(take("__target_name__")))
        if target.is_rigid:  # a rigid target's inertia about its CM, as Target(mass, inertia) has it
            target.inertia = np.array(body.description.base.inertia, dtype=float).reshape(3, 3)
        impact = RecordedImpulse(**{name: _scalar(files[f"impact.{name}"]) if f"impact.{name}" in files
                                    else None if name == "normal" else take(f"impact.{name}") for name in _IMPULSE_FIELDS})
        captured = None
        if meta["captured"] is not None:
            plant = loads_toml(str(take("__captured_toml__")), source=f"{path} (embedded captured model)")
            captured = CapturedSystem(plant, take("captured.x"), take("captured.u"), str(meta["captured"]["payload"]),
                                      str(meta["captured"]["gripper"]))
        fields = {key: meta[key] for key in _META_FIELDS}
        fields["orbit"] = None
        if meta.get("orbit") is not None:
            from ..orbit import CentralBody, Orbit

            o = meta["orbit"]
            fields["orbit"] = Orbit.from_state(take("orbit.r0"), take("orbit.v0"), j2=bool(o["j2"]),
                                               body=CentralBody(mu=o["mu"], radius=o["radius"], j2=o["body_j2"]))
        arrays = {key: take(key) for key in ("t", "phase", "x", "u", "tau", "base_wrench", "target", "P", "L", "grasp_wrench")}
        if fields["orbit"] is not None:
            arrays.update({key: take(key) for key in ("r_cm_eci", "v_cm_eci", "target_lvlh", "external_wrench", "external_impulse")})
        T = len(arrays["t"])
        for key, value in arrays.items():
            if value.ndim == 0 or value.shape[0] != T:
                raise ArgumentError(f"{where}: '{key}' has shape {value.shape}, expected {T} rows (one per sample of 't')")
        return cls(**arrays, impact=impact, soft_impact=impact if meta["soft_impact"] else None, robot=robot,
                   captured=captured, target_model=target, **fields)

    def plot(self, path=None):
        """A figure of the capture; written to ``path`` if given. See ``spacearm.viz.capture``."""
        from ..viz.capture import plot_capture

        return plot_capture(self, path)

    def animate(self, path, fps: int = 20):
        """A GIF of the capture (robot, target, grasp point)."""
        from ..viz.capture import animate_capture

        return animate_capture(self, path, fps=fps)

    def video(self, path, *, width: int = 1280, height: int = 720, fps: int = 30, renderer: str = "auto", speed: float = 1.0,
              camera=None, progress=None):
        """Write an H.264 ``.mp4`` of the capture (robot and target, every phase), rendered
        offscreen, atomically; returns the ``spacearm.viz.video.Video``. The options are
        [`Trajectory.video`][spacearm.Trajectory.video]'s; MuJoCo draws the MJCF of the captured
        system (the target a free body at its recorded pose). docs/video.md."""
        from ..viz.video import capture_video

        system = None
        if self.captured is None and self.target_model.is_rigid:
            # a point contact: the target never rides; attached anywhere, it is only drawn (posed
            # by its recorded states), so MuJoCo has robot and target in one model
            system = (combined_model(self.robot, self.target_model, self.robot.body_names[0], np.zeros(3),
                                     np.array([0.0, 0.0, 0.0, 1.0])), self.target_model.name)
        return capture_video(self, path, width=width, height=height, fps=fps, renderer=renderer, speed=speed,
                             camera=camera, progress=progress, system=system)
    def view(self, path=None, *, fps: float = 30.0, open=None, **kwargs):
        """The capture in the 3-D browser viewer (meshcat, the ``view`` extra; docs/viewer.md):
        the robot, the target moving, the grasp point from the capture on, the momentum of robot
        + target. With ``path``: one self-contained ``.html`` file (returns the path); without:
        a live view (returns the ``meshcat.Visualizer``). Options: see
        ``spacearm.viz.viewer.capture_scene``."""
        from ..viz.viewer import capture_scene, view

        return view(capture_scene(self, fps=fps, **kwargs), path, open=open)


def _ledger(robot, target, xs, us, ss):
    """Total P, L about the origin of the robot and a free target over samples (batch calls)."""
    m = robot.momentum(xs, us)
    nx = target.body.nx
    mt = target.body.momentum(ss[:, :nx], ss[:, nx:])
    return m.P + mt.P, m.L_origin + mt.L_origin


def _target_states(target, state, t):
    """A jointed target's states at the times ``t`` from ``state`` at ``t[0]``: free-floating with
    zero joint torques, simulated by the core from sample to sample."""
    t = np.asarray(t, dtype=float) - float(t[0])
    out, cur, last = [], state, 0.0
    for tt in t:
        cur = target.propagate(cur, tt - last)
        last = tt
        out.append(cur)
    return np.array(out)


def capture(
    robot,
    target,
    target_state,
    *,
    x0=None,
    u0=None,
    mode: str = "floating",
    kind: str = "rigid",
    restitution: float = 0.0,
    point=None,
    grasp: Optional[str] = None,
    approach_time: float = 8.0,
    capture_tolerance: float = CAPTURE_TOLERANCE,
    soft_time: float = 2.0,
    post_time: float = 1.0,
    detumble_time: float = 30.0,
    dt: float = 0.01,
    rmrc_gain: float = 2.0,
    rmrc_damping: float = 0.05,
    velocity_gain: float = 5.0,
    max_joint_rate: float = 1.0,
    rtol: float = 1e-10,
    kp: float = 1.0,
    kd: float = 2.0,
    time_constant: float = 5.0,
    max_joint_torque: float = math.inf,
    max_force: float = math.inf,
    max_torque: float = math.inf,
    rate_tolerance: float = 1e-3,
    orbit=None,
    gravity_gradient: Optional[bool] = None,
) -> CaptureResult:
    """Simulate the capture of ``target`` (state ``target_state``) by ``robot`` (module docstring).

    ``mode``: ``"floating"`` or ``"flying"`` (base thrusters in the approach, holding the base
    momentum at zero, and in the detumble); ``kind``: ``"rigid"``, ``"point"`` (restitution
    ``restitution``) or ``"soft"``. Limits: ``max_joint_torque`` (N·m, every joint),
    ``max_force`` (N) and ``max_torque`` (N·m) of the base thrusters; the approach's joint-rate
    command is scaled down to at most ``max_joint_rate`` (rad/s). Times in s. Every phase is
    integrated by adaptive DOPRI5 with relative tolerance ``rtol`` and recorded every ``dt`` (the
    soft phase, in the core's soft-capture plant, every ``dt / 5``). Gains: ``rmrc_gain`` (1/s),
    ``rmrc_damping`` (m: ``λ_max`` of the damping law, docs/singularities.md), ``velocity_gain`` (1/s) of the approach; ``kp``, ``kd``,
    ``time_constant`` of [`detumble`][spacearm.capture.detumble].
    Raises ``SimulationError`` when the approach does not bring the grasp points within
    ``capture_tolerance`` (m). ``orbit`` (a [`spacearm.Orbit`][spacearm.Orbit]) and
    ``gravity_gradient`` (default ``True`` with an orbit): the capture in orbit (module
    docstring); ``x0``, ``u0`` and ``target_state`` are then relative to the orbit's point at
    time 0 ([`Target.state_in_orbit`][spacearm.capture.Target.state_in_orbit] places the target
    in LVLH).
    """
    _check_target(target)
    s0 = target.check_state(target_state)
    x0 = robot.neutral_configuration() if x0 is None else vector(x0, "x0", robot.nx)
    u0 = robot.zero_velocity() if u0 is None else vector(u0, "u0", robot.nu)
    body, offset = robot.resolve_point(point)
    target.point(grasp)  # an unknown grasp point fails here, before the approach runs
    # The run's description, the core's CaptureSpec (sim/capture_spec.rs): every rule of its
    # values (modes, kinds, times, limits, restitution, the work and the reach) is the core's.
    values = {k: number(v, k) for k, v in (
        ("approach_time", approach_time), ("soft_time", soft_time), ("post_time", post_time), ("detumble_time", detumble_time),
        ("dt", dt), ("capture_tolerance", capture_tolerance), ("restitution", restitution), ("rmrc_gain", rmrc_gain),
        ("rmrc_damping", rmrc_damping), ("velocity_gain", velocity_gain), ("max_joint_rate", max_joint_rate), ("rtol", rtol),
        ("kp", kp), ("kd", kd), ("time_constant", time_constant), ("max_joint_torque", max_joint_torque), ("max_force", max_force),
        ("max_torque", max_torque), ("rate_tolerance", rate_tolerance))}
    spec = {"target_state": s0.tolist(), "grasp": grasp, "name": target.name, "point": [int(body), np.asarray(offset, dtype=float).tolist()],
            "mode": mode, "kind": kind, **values}
    if spec["grasp"] is None:
        del spec["grasp"]
    if orbit is not None:
        from ..orbit import Orbit

        if not isinstance(orbit, Orbit):
            raise ArgumentError(f"orbit must be a spacearm.Orbit, got {type(orbit).__name__}")
        spec["orbit"] = orbit._data()
    if gravity_gradient is not None:
        spec["gravity_gradient"] = bool(gravity_gradient)
    _core.check_capture(robot.core_model, x0, u0, target.body.core_model, spec)
    gg = None if orbit is None else gravity_gradient is None or bool(gravity_gradient)
    if target.is_rigid:
        # The whole mission is one core run (sim/capture.rs): every phase, the grasp, the
        # attachment, the ledger (in orbit its balance).
        run = _core.run_capture(robot.core_model, x0, u0, target.body.core_model, spec)
        return CaptureResult._of_run(run, robot, target, mode, kind, orbit, gg)
    # A jointed target: the phases below, each a core run, put together here (not yet the
    # core's mission: docs/capture.md, "Where the mission runs").
    return _capture_phases(robot, target, s0, x0, u0, body, offset, mode=mode, kind=kind, point=point, grasp=grasp, **values)


def _capture_phases(robot, target, s0, x0, u0, body, offset, *, mode, kind, point, grasp, approach_time, dt, capture_tolerance,
                    restitution, rmrc_gain, rmrc_damping, velocity_gain, max_joint_rate, rtol, kp, kd, time_constant,
                    max_joint_torque, max_force, max_torque, rate_tolerance, post_time, detumble_time, **_):
    """The point-contact capture of a jointed target (empty space), phase by phase: each phase a
    core run, put together here (docs/capture.md, "Where the mission runs")."""
    # ---- 0. approach: the native RMRC towards the target's grasp point, its path sampled every
    # dt and interpolated in between, so only at the samples is the reference's gap the gap to
    # the target's own state: the approach runs whole and ends at the first sample within the
    # tolerance.
    reference = target.grasp_path(s0, approach_time, dt, grasp)
    rmrc = ResolvedMotionRate(reference, gain=rmrc_gain, max_damping=rmrc_damping, velocity_gain=velocity_gain, point=point,
                              max_joint_rate=max_joint_rate)
    ctrl = rmrc if mode == "floating" else Combined(arm=rmrc, base=MomentumDamping(time_constant, max_force=max_force, max_torque=max_torque))
    if math.isfinite(max_joint_torque):
        ctrl = TorqueLimit(ctrl, max_joint_torque)
    tr = simulate(robot, approach_time, x0=x0, u0=u0, mode=mode, dt=dt, controller=ctrl, integrator="dopri5", rtol=rtol,
                  atol=rtol * 1e-2)
    ta, xa, ua = tr.t, tr.x, tr.u
    sa = target.trajectory(s0, approach_time, dt)[1][: len(ta)]
    nxt = target.body.nx
    gaps = np.linalg.norm(robot.point_position(xa, (body, offset)) - target.body.point_position(sa[:, :nxt], target.point(grasp)), axis=1)
    within = np.nonzero(gaps < capture_tolerance)[0]
    if not len(within):
        raise SimulationError(
            f"the approach did not reach the grasp point: closest {gaps.min():.3g} m at t = {ta[gaps.argmin()]:.3g} s "
            f"(capture_tolerance {capture_tolerance} m); lengthen approach_time, place the target within reach or raise rmrc_gain")
    k = int(within[0])
    n = robot.n_dof
    seg = {"t": [ta[: k + 1]], "phase": [np.zeros(k + 1, dtype=int)], "x": [xa[: k + 1]], "u": [ua[: k + 1]], "target": [sa[: k + 1]],
           "tau": [tr.tau[: k + 1]], "base_wrench": [tr.base_wrench[: k + 1]]}
    t_cap, xc, uc, sc = float(ta[k]), xa[k], ua[k], sa[k]
    q_hold = xc[7:].copy()

    def add(**rows):
        for key, value in rows.items():
            seg[key].append(value)

    # ---- 1. capture: the point contact's impulse, one sample after the jump --------------------
    impact = grasp_impulse(robot, xc, uc, target, sc, point=point, grasp=grasp, kind=kind, restitution=restitution,
                           capture_tolerance=capture_tolerance)
    uc, sc = impact.u_after, impact.target_state_after
    add(t=np.array([t_cap]), phase=np.ones(1, dtype=int), x=xc[None], u=uc[None], target=sc[None], tau=np.zeros((1, n)),
        base_wrench=np.zeros((1, 6)))
    # ---- 2. post-capture, 3. detumble: the robot alone, the target flying off -----------------
    x_start, u_start = xc, uc
    for phase, duration, run_mode, gains in ((2, post_time, "floating", (0.0, kd)), (3, detumble_time, mode, (kp, kd))):
        run = detumble(robot, x_start, u_start, duration, mode=run_mode, q_hold=q_hold, kp=gains[0], kd=gains[1],
                       time_constant=time_constant, max_joint_torque=max_joint_torque, max_force=max_force, max_torque=max_torque,
                       rate_tolerance=rate_tolerance, dt=dt, rtol=rtol)
        tr = run.trajectory
        ss = _target_states(target, sc, tr.t)
        add(t=t_cap + tr.t[1:], phase=np.full(len(tr.t) - 1, phase), x=tr.x[1:], u=tr.u[1:], target=ss[1:], tau=tr.tau[1:],
            base_wrench=tr.base_wrench[1:])
        t_cap, x_start, u_start, sc = t_cap + float(tr.t[-1]), tr.x[-1], tr.u[-1], ss[-1]
    arrays = {key: np.concatenate(value) for key, value in seg.items()}
    # ---- the ledger: the robot's momentum and the free target's ---------------------------------
    X, U, S = arrays["x"], arrays["u"], arrays["target"]
    P, L = _ledger(robot, target, X, U, S)
    scales = robot.momentum_scales(X, U)[:, :2] + target.body.momentum_scales(S[:, :nxt], S[:, nxt:])[:, :2]
    drift = {"P": _core.conserved_drift(P, float(scales[:, 0].max())), "L": _core.conserved_drift(L, float(scales[:, 1].max()))}
    return CaptureResult(**arrays, P=P, L=L, grasp_wrench=np.zeros((len(arrays["t"]), 6)), impact=impact, soft_impact=None,
                         robot=robot, captured=None, target_model=target, mode=mode, kind=kind, time_to_detumble=run.time_to_detumble,
                         residual_spin=run.residual_spin, drift=drift, ledger="conservation", orbit=None, gravity_gradient=None)


def _scalar(value: np.ndarray):
    """A saved 0-d array as the Python scalar it was (a float, a bool or a str); arrays as they are."""
    return value.item() if value.ndim == 0 else value


def _balance_residual(P, L, impulse) -> np.ndarray:
    """``[P − P(0) − ∫F, L − L(0) − ∫N]`` at every sample (T, 6)."""
    return np.hstack([P - P[0] - impulse[:, :3], L - L[0] - impulse[:, 3:]])
