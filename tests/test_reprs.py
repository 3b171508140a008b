"""Results print a summary, not their arrays (issue 26, item 8): each repr is short, names its
class, and holds no array's numbers."""

from __future__ import annotations

import numpy as np
import pytest

import spacearm
from spacearm import analysis
from spacearm.capture import Target, capture, detumble, soft_capture

LIMIT = 600  # characters


def _check(obj):
    text = repr(obj)
    assert len(text) < LIMIT, text
    assert type(obj).__name__ in text
    assert "array([" not in text and "\n" not in text, text
    return text


@pytest.fixture(scope="module")
def scene():
    robot = spacearm.presets.spatial6()
    x, u = robot.neutral_configuration(), robot.zero_velocity()
    target = Target(50.0, [4.0, 5.0, 6.0], grasp_points={"h": (-0.3, 0.0, 0.0)})
    s = target.state(position=robot.point_position(x) + [0.3, 0.0, 0.0], angular_velocity=[0.0, 0.0, 0.1])
    return robot, x, u, target, s


def test_capture_results(scene):
    robot, x, u, target, s = scene
    u = u.copy()
    u[6:] = 0.05
    text = _check(detumble(robot, x, u, 0.2, dt=0.01))
    assert "time_to_detumble=" in text and "trajectory=<Trajectory" in text
    _check(soft_capture(robot, x, robot.zero_velocity(), target, s, 0.05, dt=0.01))
    res = capture(robot, target, s, detumble_time=0.2, post_time=0.1)
    assert "rigid grasp, floating" in _check(res)


def test_analysis_and_identification_results():
    robot = spacearm.presets.planar4()
    m = analysis.singularity_map(robot, resolution=5)
    assert "sigma_min_generalized=array(5, 5) float64" in _check(m)
    from spacearm.identify import identify_payload

    traj = spacearm.simulate(robot, 0.2, dt=0.01, u0=np.r_[np.zeros(6), 0.3 * np.ones(robot.n_dof)])
    est = identify_payload(robot, traj, body=robot.body_names[-1])
    assert "parameters=array(10,) float64" in _check(est)



def test_simulator():
    # It had the default repr (issue 37 item 7).
    robot = spacearm.presets.spatial6()
    sim = spacearm.Simulator(robot, dt=0.01)
    assert "not reset yet" in _check(sim)
    sim.reset()
    sim.step(None, n=3)
    text = _check(sim)
    assert "'spatial6'" in text and "floating mode" in text and "dt = 0.01 s" in text and "after 3 steps" in text
    assert "t = 0.03 s" in text
