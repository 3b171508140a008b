"""Preset models (defined once, in the Rust core's ``presets`` module).

Provenance: [`planar4`][spacearm.presets.planar4] carries exactly the planar values of SPART's ``ResolvedMotion``
example (100 kg, 0.5 m base; four 10 kg, 1 m links; initial angles [π/4, −π/4, −π/4, π/4]).
[`spatial6`][spacearm.presets.spatial6], [`dual_arm`][spacearm.presets.dual_arm] and [`spatial7`][spacearm.presets.spatial7] are defined by this project.
[`ets7`][spacearm.presets.ets7] is the flown ETS-VII robot, from published parameters (its docstring gives the
sources). None of them is the case study of Wilde et al. (2018): the paper's own case-study
parameters are not available.

The project-defined ones follow the paper's link convention: every link frame aligns with the base frame at
``q = 0``, links extend along their x axis with the CM at mid-length, joint ``i+1`` sits at the
tip of link ``i``, and the end effector is the tip of the last link.
"""

from __future__ import annotations

from . import _core
from .model.robot import Robot, warn_nonphysical_inertia

__all__ = ["planar4", "spatial6", "dual_arm", "spatial7", "ets7", "NAMES", "get"]

#: Preset names, as accepted by [`get`][spacearm.presets.get] and the CLI.
NAMES = ("planar4", "spatial6", "dual_arm", "spatial7", "ets7")


def planar4() -> Robot:
    """Planar 4-link arm on a 100 kg cube: the planar values of SPART's ``ResolvedMotion`` example.

    Base: 100 kg, 0.5 m cube (4.1667 kg·m² about each axis). Four revolute joints about +z;
    joint 1 at (0.25, 0, 0) m from the base CM; links 10 kg, 1 m long, 0.05 m square bars
    (Ixx = m w²/6, Iyy = Izz = m (L² + w²)/12), CM at mid-length; initial angles
    [π/4, −π/4, −π/4, π/4].
    """
    return Robot(_core.preset("planar4"))


def spatial6() -> Robot:
    """Spatial 6-link arm on a 500 kg box (defined by this project).

    Base: 500 kg, 1.2 × 1.0 × 0.8 m (Ixx 68.33, Iyy 86.67, Izz 101.67 kg·m²); joint 1 at
    (0.6, 0, 0) m; axes x, y, y, x, y, x; lengths 0.2, 1.0, 1.0, 0.15, 0.15, 0.2 m; masses 8,
    15, 12, 4, 3, 3 kg; 0.1 m square bars; initial angles [0, π/4, −π/2, 0, π/4, 0].
    """
    return Robot(_core.preset("spatial6"))


def dual_arm() -> Robot:
    """Dual-arm servicer: two 6-DOF arms on a 600 kg, 1.2 × 1.0 × 1.0 m box (a branched tree).

    Base: Ixx 100, Iyy = Izz 122 kg·m². First joints at (0.6, ±0.35, 0) m; axes z, y, y, x, y, x;
    lengths 0.2, 0.8, 0.8, 0.15, 0.15, 0.2 m; masses 6, 10, 8, 2, 1.5, 1.5 kg; 0.08 m square
    bars. ``q[0:6]`` moves the left arm (``left_joint1..6``), ``q[6:12]`` the right one; points
    ``left_tool`` (the end effector) and ``right_tool`` at the tips: pass either to
    [`generalized_jacobian`][spacearm.Robot.generalized_jacobian].
    """
    return Robot(_core.preset("dual_arm"))


def spatial7() -> Robot:
    """Redundant 7-DOF arm on the spatial6 base: the redundancy-resolution example.

    Base: 500 kg, 1.2 × 1.0 × 0.8 m (Ixx 68.33, Iyy 86.67, Izz 101.67 kg·m²); joint 1 at
    (0.6, 0, 0) m; axes x, y, x, y, x, y, x (shoulder roll-pitch-roll, elbow pitch, wrist
    roll-pitch-roll); lengths 0.2, 0.1, 0.9, 0.1, 0.9, 0.1, 0.15 m; masses 8, 4, 12, 4, 10, 3,
    3 kg; 0.1 m square bars. Limits: roll joints ±2.97 rad, pitch joints 2 and 6 ±2.09 rad, elbow
    −2.9…0.1 rad; 1.5 rad/s and 100 N·m each. Initial angles [0, π/4, 0, −π/2, 0, π/4, 0].
    """
    return Robot(_core.preset("spatial7"))


def ets7(allow_nonphysical_inertia: bool = False) -> Robot:
    """ETS-VII (Engineering Test Satellite VII, flown 1997–1999): a 6-DOF arm on a 2.55 t satellite.

    Sources: kinematics from K. Yoshida, "Engineering test satellite VII flight experiments for
    space robot dynamics and control", Int. J. Robotics Research 22(5):321–335, 2003; inertial
    parameters from K. Yoshida and S. Abiko, "Inertia parameter identification for a free-flying
    space robot", AIAA GNC Conference, 2002; as transcribed in S. Vyas's public URDF
    ("TraceableRobotModels", 2020). These are the transcribed values of the papers, with the
    transcription's simplification that each link's CM is at its joint frame origin — not a
    flight dataset.

    Base (the satellite): 2550 kg; inertia about its CM (Ixx, Iyy, Izz; Ixy, Ixz, Iyz) =
    (6200, 3540, 7090; 48.2, 78.5, −29.2) kg·m². Six revolute joints, each about its frame's z
    (links ``link1..6``, joints ``joint1..6``, no limits); joint origins (m) and roll-pitch-yaw
    (rad) in the parent frame: (−0.79, −0.29, 1.0), (0, 0, π); (0, −0.275, 0.35), (−π/2, 0, 0);
    (0, −0.87, 0), 0; (−0.63, 0, 0), 0; (0, 0, 0.26), (π/2, 0, 0); (0, 0, 0.28), (0, −π/2, 0)
    (the transcription's 3.1416 and 1.5708 read as π and π/2). Masses 35, 22.5, 21.9, 16.5, 26,
    18.5 kg; principal moments (Ixx, Iyy, Izz) 0.25, 0.25, 1.69; 0.1, 1.31, 3.75; 0.1, 0.71,
    2.53; 0.15, 0.15, 0.073; 0.15, 0.15, 0.13; 0.97, 0.97, 0.26 kg·m². End effector
    ``end_effector`` 0.53 m along link 6's z axis. Initial angles zero (a non-singular pose,
    the end effector 2.5 m above the base CM).

    The published moments of links 1, 2 and 3 break the triangle inequality ``Ixx + Iyy >= Izz``
    (no real mass distribution has them). By default they are corrected minimally: the moments
    imply a negative second moment of mass ``Szz = ∫z² dm = (Ixx + Iyy − Izz)/2``; it is set to
    zero, keeping ``Sxx`` and ``Syy`` — Ixx and Iyy both rise by ``(Izz − Ixx − Iyy)/2`` and Izz,
    the moment about the joint axis, is kept: link 1 (0.845, 0.845, 1.69), link 2 (1.27, 2.48,
    3.75), link 3 (0.96, 1.57, 2.53) kg·m². ``allow_nonphysical_inertia=True`` keeps the published
    values instead, with one [`NonPhysicalInertiaWarning`][spacearm.errors.NonPhysicalInertiaWarning] per link.
    """
    return warn_nonphysical_inertia(Robot(_core.preset("ets7", allow_nonphysical_inertia=bool(allow_nonphysical_inertia))))


def get(name: str, allow_nonphysical_inertia: bool = False) -> Robot:
    """A preset by name (raises [`NotFoundError`][spacearm.NotFoundError] for an unknown name).
    ``allow_nonphysical_inertia`` only changes [`ets7`][spacearm.presets.ets7] (the published inertias)."""
    robot = Robot(_core.preset(name, allow_nonphysical_inertia=bool(allow_nonphysical_inertia)))
    return warn_nonphysical_inertia(robot)
