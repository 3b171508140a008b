"""Grippers (docs/contact.md, "Grippers"; the core's model/gripper.rs): RobotBuilder.add_gripper
and TOML ``[[gripper]]`` make the same model; the finger tips from the model's forward
kinematics against the closed forms of the opening (2 fingers: ``w − 2q``; 3 fingers: radius
``w/2 − ℓ sin q``); `spacearm inspect` shows it; bad input named; and a capture on contact:
fingers closed by a joint PD set point hold a slowly tumbling handle and let a fast one slip."""

from __future__ import annotations

import io

import numpy as np
import pytest

import spacearm
from spacearm.cli.inspect import inspect
from spacearm.contact import ContactModel, Pair
from spacearm.control import JointPD
from spacearm.errors import ArgumentError, ModelError
from spacearm.rotations import quat_to_matrix


def hub(fingers: int = 2, **kw) -> spacearm.Robot:
    b = spacearm.RobotBuilder("hub", 50.0, np.eye(3) * 5.0)
    b.add_gripper("hand", position=(0.4, 0.1, 0.0), rpy=(0.0, np.pi / 2, 0.0), fingers=fingers, finger_length=0.12,
                  finger_radius=0.01, opening=0.1, **kw)
    return b.build()


def test_two_finger_opening_is_the_closed_form_and_the_toml_table_makes_the_same_model():
    robot = hub(max_force=20.0)
    assert robot.n_dof == 2 and robot.actuated_dofs.all()
    for q in (0.0, 0.012, 0.04):
        x = robot.neutral_configuration([q, q])
        t0, t1 = robot.point_position(x, "hand_tip0"), robot.point_position(x, "hand_tip1")
        assert np.linalg.norm(t0 - t1) == pytest.approx(0.1 - 2 * q, abs=1e-15)
        # The palm turned by 90° about y: the fingers point along the base's +x from x = 0.4.
        np.testing.assert_allclose(0.5 * (t0 + t1), [0.4 + 0.12, 0.1, 0.0], atol=1e-15)
        np.testing.assert_allclose(robot.point_position(x, "hand_center"), [0.4 + 0.06, 0.1, 0.0], atol=1e-15)
    limits = robot.description.links[1].limits
    assert (limits.lower, limits.upper, limits.effort) == (0.0, pytest.approx(0.04), 20.0)
    # The capsules: the model's collision shapes, so the fingers touch what they close on.
    caps = [g for g in robot.description.geometries if g.role == "collision"]
    assert [g.name for g in caps] == ["hand_finger0_capsule", "hand_finger1_capsule"]
    text = ("[model]\nname = 'hub'\n[base]\nmass = 50.0\ninertia = [5.0, 5.0, 5.0]\n[[gripper]]\nname = 'hand'\n"
            f"position = [0.4, 0.1, 0.0]\nrotation = {list(map(float, spacearm.rotations.quat_from_rpy(0, np.pi / 2, 0)))}\n"
            "finger_length = 0.12\nfinger_radius = 0.01\nopening = 0.1\nmax_force = 20.0\n")
    again = spacearm.io.loads_toml(text)
    x = robot.neutral_configuration([0.01, 0.02])
    np.testing.assert_allclose(again.mass_matrix(x), robot.mass_matrix(x), rtol=0, atol=1e-15)
    np.testing.assert_allclose(again.point_position(x, "hand_tip1"), robot.point_position(x, "hand_tip1"), atol=1e-15)
    out = io.StringIO()
    inspect(robot, out=out)
    assert "hand: 2 prismatic fingers, dofs [0, 1]" in out.getvalue()


def test_three_fingers_tilt_inward_by_the_closed_form():
    robot = hub(fingers=3)
    assert robot.n_dof == 3
    for q in (0.0, 0.15, 0.33):
        x = robot.neutral_configuration([q, q, q])
        for i in range(3):
            tip = robot.point_position(x, f"hand_tip{i}")
            # The palm's axis is the base's x through (0.4, 0.1, 0): radius in the y–z plane.
            assert np.hypot(tip[1] - 0.1, tip[2]) == pytest.approx(0.05 - 0.12 * np.sin(q), abs=1e-15)
            assert tip[0] == pytest.approx(0.4 + 0.12 * np.cos(q), abs=1e-15)
    out = io.StringIO()
    inspect(robot, out=out)
    assert "hand: 3 revolute fingers" in out.getvalue()


def test_bad_grippers_are_refused_with_their_name():
    b = spacearm.RobotBuilder("hub", 50.0, np.eye(3) * 5.0)
    with pytest.raises(ModelError, match="gripper 'g': fingers must be 2"):
        b.add_gripper("g", fingers=4, finger_length=0.1, finger_radius=0.01, opening=0.1)
    with pytest.raises(ModelError, match="gripper 'g': opening .* must exceed twice the finger_radius"):
        b.add_gripper("g", finger_length=0.1, finger_radius=0.06, opening=0.1)
    with pytest.raises(ModelError, match="finger_length"):
        b.add_gripper("g", finger_length=float("nan"), finger_radius=0.01, opening=0.1)
    with pytest.raises(ModelError, match="unknown field"):
        spacearm.io.loads_toml("[model]\nname = 'h'\n[base]\nmass = 1.0\ninertia = [1.0, 1.0, 1.0]\n[[gripper]]\nname = 'g'\n"
                               "finger_length = 0.1\nfinger_radius = 0.01\nopening = 0.1\ngrip = 1\n")


def servicer() -> spacearm.Robot:
    """A 200 kg bus, a boom on a revolute joint, a parallel gripper at its tip pointing along +x."""
    b = spacearm.RobotBuilder("servicer", 200.0, np.eye(3) * 33.0)
    b.add_link("boom", parent="base", joint="revolute", axis=(0, 0, 1), origin=(0.5, 0, 0), com=(0.25, 0, 0), mass=5.0,
               inertia=np.diag([0.01, 0.11, 0.11]))
    b.add_gripper("hand", parent="boom", position=(0.25, 0, 0), rpy=(0, np.pi / 2, 0), finger_length=0.12, finger_radius=0.01,
                  opening=0.10)
    return b.build()


def handle_target() -> spacearm.Robot:
    """A 20 kg box with a cylinder handle along y, 0.29 m from its CM towards −x."""
    b = spacearm.RobotBuilder("target", 20.0, np.eye(3) * 0.53, base_name="target")
    b.add_geometry("target", "box", role="collision", size=(0.4, 0.4, 0.4), name="body")
    b.add_geometry("target", "cylinder", role="collision", radius=0.02, length=0.15, origin=(-0.29, 0, 0),
                   rpy=(np.pi / 2, 0, 0), name="handle")
    return b.build()


def grasp(spin: float, friction: float):
    robot, target = servicer(), handle_target()
    s0 = np.array([1.35, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, spin, 0.0])
    contact = ContactModel(stiffness=2e3, damping=20.0, friction=friction, slip_velocity=1e-3,
                           pairs=[Pair("hand_finger0", "target"), Pair("hand_finger1", "target")])
    pd = JointPD(kp=[500.0, 200.0, 200.0], kd=[100.0, 5.0, 5.0], reference=[0.0, 0.04, 0.04])
    traj = spacearm.simulate(robot, 3.0, dt=5e-4, record_every=2, controller=pd, contact=contact, target=target, target_state=s0)
    s = traj["target"]
    # The palm turns with the base and the boom's joint (about the base's z).
    boom_axis = np.array([quat_to_matrix(x[3:7])[:, 2] for x in traj.x])
    rel_w = np.linalg.norm(s[:, 10:13] - traj.u[:, 3:6] - traj.u[:, 6:7] * boom_axis, axis=1)
    handle = np.array([si[:3] + quat_to_matrix(si[3:7]) @ [-0.29, 0, 0] for si in s])
    centre = np.array([robot.point_position(x, "hand_center") for x in traj.x])
    return traj, rel_w, np.linalg.norm(handle - centre, axis=1)


def test_fingers_hold_a_slowly_tumbling_handle_and_a_fast_one_slips():
    traj, rel_w, off = grasp(0.05, 0.5)
    # Held: both fingers touch, the handle stays at the grasp centre, the relative spin dies.
    assert np.all(traj.contact_count[-500:] == 2)
    assert off[-1] < 2e-3 and rel_w[-1] < 0.05 * 0.05
    assert traj.meta["drift"]["P"] < 1e-6 and traj.meta["drift"]["L_origin"] < 1e-6
    fast, rel_fast, _ = grasp(2.0, 0.5)
    # Slips: after 3 s the handle still turns against the fingers at a good part of its spin.
    assert rel_fast[-1] > 0.1 * 2.0
