"""Every figure is written in the format its file name asks for (docs: spacearm.viz.figures):
the bytes of the file say so, and a format matplotlib cannot write is refused before any file
appears."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("matplotlib")

import spacearm  # noqa: E402
from spacearm.capture import capture  # noqa: E402

MAGIC = {".png": b"\x89PNG", ".pdf": b"%PDF", ".svg": b"<?xml"}


def _traj():
    robot = spacearm.presets.planar4()
    return spacearm.simulate(robot, 0.2, dt=0.01)


@pytest.mark.parametrize("suffix", [".png", ".pdf", ".svg"])
def test_trajectory_plot_follows_the_suffix(tmp_path, suffix):
    path = tmp_path / f"run{suffix}"
    _traj().plot(path)
    assert path.read_bytes()[:5].startswith(MAGIC[suffix])


def test_an_unwritable_format_is_refused_before_writing(tmp_path):
    path = tmp_path / "run.xyz"
    with pytest.raises(spacearm.ArgumentError, match=r"\.xyz.*\.pdf"):
        _traj().plot(path)
    assert list(tmp_path.iterdir()) == []


def test_capture_figure_follows_the_suffix(tmp_path):
    robot = spacearm.presets.spatial6()
    x = robot.neutral_configuration()
    target = spacearm.Target(50.0, [4.0, 5.0, 6.0], grasp_points={"handle": (-0.5, 0.0, 0.0)})
    s = target.state(position=robot.point_position(x) + np.array([0.6, 0.0, 0.0]), angular_velocity=(0.0, 0.0, 0.1))
    res = capture(robot, target, s, detumble_time=1.0, post_time=0.2)
    res.plot(tmp_path / "cap.pdf")
    assert (tmp_path / "cap.pdf").read_bytes().startswith(b"%PDF")
    with pytest.raises(spacearm.ArgumentError, match="cannot write a figure"):
        res.plot(tmp_path / "cap.doc")
