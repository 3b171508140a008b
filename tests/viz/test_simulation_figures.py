"""Figures of a run: the PNG's panels carry the trajectory's own numbers, the GIF has the
requested frames, and the drawn geometry matches the presets' documented dimensions."""

import os

import numpy as np
import pytest
from PIL import Image

import spacearm
from spacearm.viz.animation import arm_segments, box_faces, equivalent_box
from spacearm.errors import SpacearmError
from spacearm.sim.trajectory import Trajectory

from sim_samples import synthetic


def _axes_by_title(fig):
    return {ax.get_title(): ax for ax in fig.axes if ax.get_visible() and ax.get_title()}


def test_plot_writes_png_with_the_run_in_its_panels(tmp_path):
    robot, data, meta = synthetic(k=61)
    tr = Trajectory(robot=robot, data=data, meta=meta)
    path = tmp_path / "run.png"
    fig = tr.plot(path)
    with Image.open(path) as im:
        assert im.format == "PNG" and im.size[0] > 800 and im.size[1] > 600
    axes = _axes_by_title(fig)
    joints = axes["joint angles (dashed: reference)"]
    # Every joint's solid line is q_j(t); its dashed twin is the reference.
    solid = [l for l in joints.get_lines() if l.get_linestyle() == "-"]
    dashed = [l for l in joints.get_lines() if l.get_linestyle() == "--"]
    assert len(solid) == 6 and len(dashed) == 6
    for j, line in enumerate(solid):
        np.testing.assert_array_equal(line.get_ydata(), tr.q[:, j])
        np.testing.assert_array_equal(dashed[j].get_ydata(), data["reference"][:, j])
    # The attitude panel shows degrees of the unwrapped roll-pitch-yaw, its sequence named.
    att = axes["base attitude, Z-Y-X Euler angles (R0 = Rz(yaw) Ry(pitch) Rx(roll))"].get_lines()
    np.testing.assert_allclose(att[2].get_ydata(), np.degrees(tr.base_euler[:, 2]))
    # Conservation: the change of P in N s from sample 1 on, the unit on the axis and the label.
    cons = axes["momentum: change from the initial value"]
    p_line = [l for l in cons.get_lines() if l.get_label() == "P [N s] (conserved)"][0]
    change = np.linalg.norm(data["P"] - data["P"][0], axis=1)
    np.testing.assert_allclose(p_line.get_ydata(), np.maximum(change[1:], 1e-17))
    assert cons.get_ylabel() == "|v(t) − v(0)| [N s (P), N m s (L)]"
    assert "scale" not in cons.get_ylabel()
    assert "tracking error (joint)" in axes
    assert not any("wheel" in t for t in axes)  # no wheels recorded
    assert not any("base wrench" in t for t in axes)  # zero wrench
    assert os.listdir(tmp_path) == ["run.png"]


def test_plot_shows_wheels_wrench_and_cartesian_reference():
    robot, data, meta = synthetic(k=31)
    meta["wheel_dofs"] = [5]
    data["wheel_speed"] = data["u"][:, 11:12]
    data["base_wrench"][:, 2] = 7.0
    meta["tracking_error_kind"] = "cartesian"
    data["reference"] = data["ee_position"] + 0.01
    fig = Trajectory(robot=robot, data=data, meta=meta).plot()
    axes = _axes_by_title(fig)
    wheels = axes["reaction-wheel speeds (dotted: torque, right axis)"]
    np.testing.assert_array_equal(wheels.get_lines()[0].get_ydata(), data["u"][:, 11])
    wrench = axes["base wrench (thrusters) in the inertial frame"]
    np.testing.assert_array_equal(wrench.get_lines()[2].get_ydata(), np.full(31, 7.0))
    ee = axes["end-effector position (dashed: reference)"]
    np.testing.assert_array_equal(ee.get_lines()[1].get_ydata(), data["reference"][:, 0])
    # The wheel is not among the arm's joints.
    joints = axes["joint angles"]
    assert len(joints.get_lines()) == 5


def test_equivalent_box_recovers_the_presets_documented_sides():
    # spatial6: 500 kg, 1.2 x 1.0 x 0.8 m; planar4: 100 kg, 0.5 m cube (presets docstrings).
    for robot, sides in ((spacearm.presets.spatial6(), [1.2, 1.0, 0.8]), (spacearm.presets.planar4(), [0.5, 0.5, 0.5])):
        base = robot.describe()["base"]
        got, axes = equivalent_box(base["mass"], base["inertia"])
        along = np.abs(axes) @ got  # sides along the body x, y, z axes (diagonal inertia)
        np.testing.assert_allclose(along, sides, rtol=1e-3)


def test_box_faces_enclose_the_box():
    faces = box_faces(np.array([1.0, 2.0, 3.0]), np.eye(3), np.array([2.0, 4.0, 6.0]), np.eye(3))
    corners = np.unique(np.vstack(faces).round(12), axis=0)
    assert corners.shape == (8, 3)
    np.testing.assert_allclose(corners.min(axis=0), [0.0, 0.0, 0.0])
    np.testing.assert_allclose(corners.max(axis=0), [2.0, 4.0, 6.0])
    for f in faces:  # each face is planar: one coordinate constant
        assert np.sum(np.ptp(f, axis=0) < 1e-12) == 1


def test_arm_segments_form_the_documented_chain():
    robot = spacearm.presets.spatial6()
    rng = np.random.default_rng(1)
    x = robot.neutral_configuration(rng.uniform(-2, 2, 6), r0=(3.0, -1.0, 2.0), quat0=(0.1, 0.2, 0.3, np.sqrt(0.86)))
    segs = arm_segments(robot, x)
    assert len(segs) == 6
    # Joint to joint to the end effector: a connected chain of the documented link lengths.
    for (a0, b0), (a1, _) in zip(segs, segs[1:]):
        np.testing.assert_allclose(b0, a1, atol=1e-12)
    lengths = [np.linalg.norm(b - a) for a, b in segs]
    np.testing.assert_allclose(lengths, [0.2, 1.0, 1.0, 0.15, 0.15, 0.2], atol=1e-12)
    np.testing.assert_allclose(segs[-1][1], robot.point_position(x), atol=1e-12)
    # Wheels (skipped dofs) are not drawn.
    assert len(arm_segments(robot, x, skip_dofs=[5])) == 5


def test_animate_writes_a_small_gif(tmp_path):
    robot, data, meta = synthetic(k=41)
    tr = Trajectory(robot=robot, data=data, meta=meta)
    path = tmp_path / "run.gif"
    tr.animate(path, frames=4, fps=10)
    with Image.open(path) as im:
        assert im.format == "GIF" and im.n_frames == 4 and im.size == (360, 360)
    assert os.listdir(tmp_path) == ["run.gif"]
    with pytest.raises(SpacearmError, match="animate needs the robot"):
        Trajectory(data={k: data[k] for k in ("t", "x", "u")}).animate(tmp_path / "x.gif")
    with pytest.raises(ValueError, match="frames must be >= 1"):
        tr.animate(tmp_path / "y.gif", frames=0)
    assert os.listdir(tmp_path) == ["run.gif"]


def test_torque_free_run_has_no_torque_panel():
    robot, data, meta = synthetic(k=11)
    data["tau"] = np.zeros_like(data["tau"])
    data["tau_cmd"] = np.zeros_like(data["tau_cmd"])
    titles = _axes_by_title(Trajectory(robot=robot, data=data, meta=meta).plot())
    assert not any("joint torques" in t for t in titles)
    data["tau_cmd"][3, 2] = 1.0  # commanded but fully clipped: still shown
    titles = _axes_by_title(Trajectory(robot=robot, data=data, meta=meta).plot())
    assert any("joint torques" in t for t in titles)


def _empty_axes(fig):
    """Axes a reader sees as an empty panel: hidden slots of the grid, or visible axes with
    nothing drawn."""
    return [ax for ax in fig.axes if not ax.get_visible() or not (ax.lines or ax.collections or ax.patches or ax.images)]


@pytest.mark.parametrize("controller", ["computed_torque", None])
def test_no_panel_of_the_figure_is_empty(controller):
    # Issue 37 item 7a: an odd number of panels left the 2-column grid's last slot empty. A
    # computed-torque run has 7 panels (odd), a torque-free one 5 (odd): the last spans the row.
    robot = spacearm.presets.spatial6()
    ctrl = spacearm.control.ComputedTorque(kp=50.0, kd=10.0, reference=[0.1] * 6) if controller else None
    tr = spacearm.simulate(robot, 0.2, dt=1e-2, controller=ctrl)
    fig = tr.plot()
    assert _empty_axes(fig) == []
    main = [ax for ax in fig.axes if ax.get_title()]
    assert len(main) % 2 == 1
    # The last panel is as wide as a row of two; every other one is half of it.
    fig.canvas.draw()
    widths = [ax.get_position().width for ax in main]
    assert widths[-1] > 1.8 * max(widths[:-1])
    # Every panel carries a line of the run's samples (the momentum's from sample 1 on).
    assert all(any(len(l.get_xdata()) >= len(tr.t) - 1 for l in ax.lines) for ax in main)
