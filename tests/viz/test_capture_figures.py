"""Figures of a capture: units on every axis, one label per joint in its line's colour, the phases
shaded and keyed,
the animation's frames, and the envelope's axes."""

from __future__ import annotations

import numpy as np
import pytest

import spacearm
from spacearm.capture import capture, capture_envelope

pytest.importorskip("matplotlib")


def _run():
    robot = spacearm.presets.spatial6()
    x = robot.neutral_configuration()
    target = spacearm.Target(50.0, [4.0, 5.0, 6.0], grasp_points={"handle": (-0.5, 0.0, 0.0)})
    s = target.state(position=robot.point_position(x) + np.array([0.6, 0.0, 0.0]), angular_velocity=(0.0, 0.0, 0.1))
    return robot, target, capture(robot, target, s, detumble_time=2.0, post_time=0.5, max_joint_torque=10.0)


def test_capture_figure_and_animation(tmp_path):
    from PIL import Image

    robot, _, res = _run()
    fig = res.plot(tmp_path / "cap.png")
    assert (tmp_path / "cap.png").stat().st_size > 10_000
    axes = [ax for ax in fig.axes if ax.get_visible()]
    assert len(axes) == 4
    for ax in axes:
        assert "[" in ax.get_ylabel(), f"no unit on '{ax.get_title()}'"
    assert all("[s]" in ax.get_xlabel() for ax in axes[2:])
    torques = next(ax for ax in axes if ax.get_title() == "joint torques")
    assert [t.get_text() for t in torques.texts] == robot.joint_names
    assert [t.get_color() for t in torques.texts] == [line.get_color() for line in torques.get_lines()]
    (key,) = fig.legends
    assert {t.get_text() for t in key.get_texts()} >= {"post-capture", "detumble"}
    from spacearm.viz.capture import animate_capture  # (res.animate draws 40 frames: slow for a test)

    path = animate_capture(res, tmp_path / "cap.gif", frames=3)
    with Image.open(path) as im:
        assert im.n_frames == 3


def test_envelope_figure(tmp_path):
    robot, target, _ = _run()
    env = capture_envelope(robot, target, spin_rates=(0.05, 0.1), inertia_errors=(0.0, 0.2), duration=3.0, dt=0.05)
    fig = env.plot(tmp_path / "env.png")
    ax = fig.axes[0]
    assert "[rad/s]" in ax.get_ylabel() and "error" in ax.get_xlabel()
    assert [t.get_text() for t in ax.get_yticklabels()] == ["0.05", "0.1"]
    assert (tmp_path / "env.png").stat().st_size > 5_000
