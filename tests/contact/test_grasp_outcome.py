"""The grasp's outcome (docs/contact.md, "The grasp's outcome"; the core's sim/grasp_outcome.rs):
held / slipped / missed judged from a run's records, on runs whose outcome physics fixes — a slow
tumble about the handle squeezed with friction holds; without friction the fingers' normal forces
cannot stop the handle sliding along its own axis (it slips at its initial speed); a target
drifting away from the gripper is missed — and at the thresholds' edges on states placed by hand."""

from __future__ import annotations

import numpy as np
import pytest

import spacearm
from spacearm.contact import ContactModel, GraspOutcome, Pair, grasp_outcome
from spacearm.control import JointPD
from spacearm.errors import ArgumentError, NotFoundError
from spacearm.rotations import quat_to_matrix


def scene():
    """docs/contact.md's servicer with a parallel gripper, and a 20 kg box with a handle."""
    b = spacearm.RobotBuilder("servicer", 200.0, np.eye(3) * 33.0)
    b.add_link("boom", parent="base", joint="revolute", axis=(0, 0, 1), origin=(0.5, 0, 0), com=(0.25, 0, 0), mass=5.0,
               inertia=np.diag([0.01, 0.11, 0.11]))
    b.add_gripper("hand", parent="boom", position=(0.25, 0, 0), rpy=(0, np.pi / 2, 0), fingers=2,
                  finger_length=0.12, finger_radius=0.01, opening=0.10)
    t = spacearm.RobotBuilder("target", 20.0, np.eye(3) * 0.53, base_name="target")
    t.add_geometry("target", "box", role="collision", size=(0.4, 0.4, 0.4), name="body")
    t.add_geometry("target", "cylinder", role="collision", radius=0.02, length=0.15, origin=(-0.29, 0, 0),
                   rpy=(np.pi / 2, 0, 0), name="handle")
    return b.build(), t.build()


ROBOT, TARGET = scene()
CLOSE = JointPD(kp=[500.0, 200.0, 200.0], kd=[100.0, 5.0, 5.0], reference=[0.0, 0.04, 0.04])


def fly(s0, friction: float, duration: float):
    contact = ContactModel(stiffness=2e3, damping=20.0, friction=friction, slip_velocity=1e-3,
                           pairs=[Pair("hand_finger0", "target"), Pair("hand_finger1", "target")])
    return spacearm.simulate(ROBOT, duration, dt=5e-4, record_every=2, controller=CLOSE, contact=contact, target=TARGET,
                             target_state=np.array(s0, float))


def test_a_slow_tumble_squeezed_with_friction_is_held():
    traj = fly([1.35, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0.05, 0], 0.5, 3.0)
    o = grasp_outcome(ROBOT, TARGET, traj)
    assert isinstance(o, GraspOutcome) and o.outcome == "held" and o.held, o.reason
    assert o.fingers_touching == o.fingers == 2 and o.first_touch < 0.5
    # The window's numbers, recomputed here from the records by the model's kinematics.
    k = traj.t >= traj.t[-1] - 0.5
    s, x, u = traj["target"][k], traj.x[k], traj.u[k]
    palm_w = u[:, 3:6] + u[:, 6:7] * np.array([quat_to_matrix(q)[:, 2] for q in x[:, 3:7]])  # boom axis z
    spin = np.linalg.norm(s[:, 10:13] - palm_w, axis=1).max()
    handle = s[:, :3] + np.einsum("kij,j->ki", np.array([quat_to_matrix(q) for q in s[:, 3:7]]), [-0.29, 0, 0])
    off = max(np.linalg.norm(h - ROBOT.point_position(xi, "hand_center")) for h, xi in zip(handle, x))
    assert abs(o.relative_spin - spin) < 1e-12 and abs(o.offset - off) < 1e-12
    assert o.window_samples == k.sum() and o.window_start == traj.t[k][0]


def test_without_friction_the_handle_slides_out_along_its_axis():
    # The handle's axis is 𝒥's y; the fingers' normals are perpendicular to it: with μ = 0 no
    # force acts along y, and the handle keeps its 0.02 m/s relative to the (still) fingers.
    v, T = 0.02, 2.0
    traj = fly([1.35, 0, 0, 0, 0, 0, 1, 0, v, 0, 0, 0, 0], 0.0, T)
    assert np.abs(traj["target"][:, 8] - v).max() < 1e-6 * v
    o = grasp_outcome(ROBOT, TARGET, traj)
    assert o.outcome == "slipped" and not o.held, o.reason
    assert o.fingers_touching == 2 and "relative speed" in o.reason and "grasp centre" in o.reason
    assert abs(o.relative_speed - v) < 1e-4 * v and abs(o.offset - v * T) < 1e-4, (o.relative_speed, o.offset)
    # With friction the same run's slide stops (the handle may still pivot in a two-point pinch).
    o = grasp_outcome(ROBOT, TARGET, fly([1.35, 0, 0, 0, 0, 0, 1, 0, v, 0, 0, 0, 0], 0.5, T))
    assert o.relative_speed < 0.005 and o.offset < 0.005


def test_a_target_drifting_away_is_missed():
    traj = fly([1.35, 0.3, 0, 0, 0, 0, 1, 0, 0.05, 0, 0, 0, 0], 0.5, 1.0)
    o = grasp_outcome(ROBOT, TARGET, traj)
    assert (o.outcome, o.first_touch, o.touching_samples, o.fingers_touching) == ("missed", None, 0, 0), o.reason
    # The handle's centre: 0.3 m aside of the grasp centre at t = 0, then 0.05 m/s further.
    assert abs(o.offset - (0.3 + 0.05 * 1.0)) < 1e-3


def held_records(q: float, handle_at, w=(0.0, 0.0, 0.0), n: int = 11):
    """1 s of the robot at rest with its fingers at q, the target's handle centre at handle_at
    (its axis along y), spinning at w: built by hand, no run."""
    x = ROBOT.neutral_configuration()
    x[8:] = q
    R = quat_to_matrix([0, 0, 0, 1])
    s = np.concatenate([np.asarray(handle_at) - R @ [-0.29, 0, 0], [0, 0, 0, 1], [0, 0, 0], w])
    t = np.linspace(0.0, 1.0, n)
    return spacearm.Trajectory(ROBOT, {"t": t, "x": np.tile(x, (n, 1)), "u": np.zeros((n, ROBOT.nu)), "target": np.tile(s, (n, 1))})


def test_thresholds_decide_at_their_bounds():
    x = ROBOT.neutral_configuration()
    c = ROBOT.point_position(x, "hand_center")
    # Closed on the 0.02 m handle: the finger axes 0.1 − 2q apart, surfaces on it at q = 0.02 m.
    o = grasp_outcome(ROBOT, TARGET, held_records(0.02, c))
    assert o.held and o.offset < 1e-12 and o.fingers_touching == 2, o.reason
    # Open (q = 0): each finger 0.05 − 0.01 − 0.02 = 0.02 m from the handle.
    assert grasp_outcome(ROBOT, TARGET, held_records(0.0, c)).outcome == "missed"
    assert grasp_outcome(ROBOT, TARGET, held_records(0.0, c), touch_margin=0.0201).held
    assert grasp_outcome(ROBOT, TARGET, held_records(0.0, c), touch_margin=0.0199).outcome == "missed"
    # Spinning about the handle's axis (y) through the CM at w: relative spin w, handle speed 0.29 w.
    w = 0.004
    traj = held_records(0.02, c, w=(0, w, 0))
    o = grasp_outcome(ROBOT, TARGET, traj)
    assert o.held and abs(o.relative_spin - w) < 1e-15 and abs(o.relative_speed - 0.29 * w) < 1e-15
    o = grasp_outcome(ROBOT, TARGET, traj, max_relative_spin=0.999 * w)
    assert o.outcome == "slipped" and "relative spin" in o.reason
    assert grasp_outcome(ROBOT, TARGET, traj, max_relative_speed=0.999 * 0.29 * w).outcome == "slipped"
    # 3 mm along the handle's axis: still between the fingers, 3 mm from the grasp centre.
    traj = held_records(0.02, c + [0, 0.003, 0])
    assert abs(grasp_outcome(ROBOT, TARGET, traj).offset - 0.003) < 1e-12
    assert grasp_outcome(ROBOT, TARGET, traj, max_offset=0.0031).held
    assert grasp_outcome(ROBOT, TARGET, traj, max_offset=0.0029).outcome == "slipped"


def test_bad_input_is_named():
    x = ROBOT.neutral_configuration()
    traj = held_records(0.02, ROBOT.point_position(x, "hand_center"))
    with pytest.raises(NotFoundError, match="no gripper 'claw'"):
        grasp_outcome(ROBOT, TARGET, traj, gripper="claw")
    with pytest.raises(NotFoundError, match="'knob'"):
        grasp_outcome(ROBOT, TARGET, traj, handle="knob")
    with pytest.raises(ArgumentError, match="shorter than the run"):
        grasp_outcome(ROBOT, TARGET, traj, window=1.0)
    with pytest.raises(ArgumentError, match="max_offset"):
        grasp_outcome(ROBOT, TARGET, traj, max_offset=0.0)
    with pytest.raises(ArgumentError, match="free target"):
        grasp_outcome(ROBOT, TARGET, spacearm.Trajectory(ROBOT, {"t": traj.t, "x": traj.x, "u": traj.u}))
