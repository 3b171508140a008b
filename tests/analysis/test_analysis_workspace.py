"""Workspaces: reachable shell about the system CM against a hand-derived closed
form and Pinocchio's CM and frame placements; path-dependent workspace against the radii of the
dynamic singularities located by the SymPy determinant."""

import numpy as np
import pytest

import spacearm
from spacearm import analysis, interop
from spacearm.errors import ArgumentError, ShapeError

from analysis_refs import bisect, sympy_two_link, two_link_planar


def test_planar4_reach_closed_form():
    robot = spacearm.presets.planar4()
    w = analysis.workspace(robot, resolution=9)  # odd: the grid contains q = 0
    # Straight arm along the base x axis: tip 0.25 + 4 × 1 m from the base CM; system CM
    # 10 kg × (0.75 + 1.75 + 2.75 + 3.75) m / 140 kg = 9/14 m; the virtual manipulator's links are
    # all aligned there, so this is the largest barycentric distance.
    assert w.fixed_base[1] == pytest.approx(4.25, abs=1e-12)
    assert w.reachable[1] == pytest.approx(4.25 - 9.0 / 14.0, abs=1e-12)
    assert 0 <= w.reachable[0] < 0.1
    assert w.samples.shape == (9**4, 4) and "grid 9^4" in w.resolution


def test_barycentric_positions_match_pinocchio():
    pin = pytest.importorskip("pinocchio")
    robot = spacearm.presets.spatial7()
    model = interop.to_pinocchio(robot)
    data = model.createData()
    w = analysis.workspace(robot, random_samples=200, seed=3)
    for k in range(0, 200, 37):
        x = robot.neutral_configuration(q=w.samples[k])
        q_pin, _ = interop.to_pinocchio_state(robot, x, np.zeros(robot.nu))
        com = pin.centerOfMass(model, data, q_pin)
        pin.framesForwardKinematics(model, data, q_pin)
        tip = data.oMf[model.getFrameId(robot.end_effector)].translation
        assert np.linalg.norm(tip - com) > 0.3
        np.testing.assert_allclose(w.point_from_com[k], tip - com, atol=1e-12)
        np.testing.assert_allclose(w.point_from_base[k], tip, atol=1e-12)


def test_two_link_path_dependent_workspace_contains_the_sympy_singular_radii(tmp_path):
    robot = two_link_planar()
    w = analysis.workspace(robot, resolution=181, task="planar")
    _, f_det = sympy_two_link()
    radii = []
    for q1 in np.linspace(-np.pi, np.pi, 25):
        g = np.linspace(-np.pi + 1e-4, np.pi - 1e-4, 241)
        v = np.array([f_det(q1, s) for s in g])
        for i in np.nonzero(np.sign(v[:-1]) * np.sign(v[1:]) < 0)[0]:
            q2 = bisect(lambda s: f_det(q1, s), g[i], g[i + 1])
            x = robot.neutral_configuration(q=[q1, q2])
            radii.append(np.linalg.norm(robot.point_position(x) - robot.center_of_mass(x)))
    assert len(radii) > 20
    tol = 2 * w.radial_resolution
    for r in radii:
        assert any(a - tol <= r <= b + tol for a, b in w.path_dependent), (r, w.path_dependent)
    # the PDW does not swallow everything: a path-independent shell remains, and it holds no
    # singular radius
    assert sum(b - a for a, b in w.path_independent) > 0.3
    for r in radii:
        assert not any(a + tol < r < b - tol for a, b in w.path_independent)
    # the outermost PDW shell ends at the stretched arm (a singular configuration) = R_max
    assert w.path_dependent[-1][1] == pytest.approx(w.reachable[1], abs=1e-9)
    print(f"\ntwo-link: W_R = {w.reachable}, PDW = {w.path_dependent}, PIW = {w.path_independent}, "
          f"{w.samples.shape[0]} samples at {w.samples_per_second:.0f} samples/s")
    w.plot(tmp_path / "ws.png")
    assert (tmp_path / "ws.png").stat().st_size > 10_000


def test_spatial_slice_figure(tmp_path):
    robot = spacearm.presets.spatial6()
    w = analysis.workspace(robot, random_samples=20000, task="full", seed=1)
    assert w.reachable[0] < w.reachable[1] and w.fixed_base[1] > w.reachable[1]
    w.plot(tmp_path / "slice.png", plane="xz")
    assert (tmp_path / "slice.png").stat().st_size > 10_000
    with pytest.raises(spacearm.SpacearmError, match="plane"):
        w.plot(tmp_path / "bad.png", plane="xq")


def test_bad_input():
    robot = spacearm.presets.planar4()
    with pytest.raises(ShapeError):
        analysis.workspace(robot, samples=np.zeros((4, 3)))
    with pytest.raises(ArgumentError, match="radial resolution"):
        analysis.workspace(robot, resolution=3, radial_resolution=-1.0)
    with pytest.raises(ArgumentError, match="too large"):
        analysis.workspace(spacearm.presets.dual_arm(), resolution=10)
