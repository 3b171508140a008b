"""Redundancy resolution on the 7-DOF preset: the task is met exactly through
Pinocchio-built J*, the null-space objectives improve what they target, damped least squares
keeps motions toward unreachable targets finite."""

import numpy as np
import pytest

import spacearm
from spacearm import analysis

from analysis_refs import PinRef

pytest.importorskip("pinocchio")


def _limits(robot):
    lim = np.array([link["limits"][:2] for link in robot.describe()["links"]])
    return lim.mean(axis=1), lim[:, 1] - lim[:, 0]


@pytest.mark.parametrize("strategy", ["naive", "minimum_disturbance", "reactionless"])
@pytest.mark.parametrize("gains", [(0.0, 0.0), (5.0, 50.0)])
def test_rates_meet_the_task_through_pinocchio_jstar(strategy, gains):
    robot = spacearm.presets.spatial7()
    ref = PinRef(robot)
    rng = np.random.default_rng(12)
    mid, _ = _limits(robot)
    for _ in range(3):
        x = robot.neutral_configuration(q=mid + rng.uniform(-0.8, 0.8, 7))
        jstar, _, base = ref.maps(x)
        desired = np.r_[rng.normal(scale=0.05, size=3), 0, 0, 0]
        r = analysis.rmrc_rates(robot, x, desired, task="position", strategy=strategy, manipulability_gain=gains[0],
                                joint_limit_gain=gains[1], threshold=1e-3)
        assert r.damping == 0.0 and np.all(np.isfinite(r.qd))
        v = jstar[:3] @ r.qd
        # the preset's 1.5 rad/s limits may scale the whole q̇ down (direction kept)
        scale = v @ desired[:3] / (desired[:3] @ desired[:3])
        np.testing.assert_allclose(v, scale * desired[:3], atol=1e-9)
        assert 0 < scale <= 1 + 1e-9
        if np.abs(r.qd).max() < 1.5 - 1e-9:
            assert scale == pytest.approx(1.0, abs=1e-9)
        else:
            assert np.abs(r.qd).max() == pytest.approx(1.5)
        w0 = base[3:] @ r.qd
        np.testing.assert_allclose(r.base_angular_velocity, w0, atol=1e-12)
        naive = analysis.rmrc_rates(robot, x, desired, task="position", strategy="naive", threshold=1e-3)
        w_naive = np.linalg.norm(base[3:] @ naive.qd)
        assert w_naive > 1e-4
        if strategy == "reactionless":
            # the task itself is solved in the reaction null space: no base rotation at all
            assert np.linalg.norm(w0) < 1e-9
        elif strategy == "minimum_disturbance":
            # the null space (dimension 4) absorbs as much of the 3 base rotations as the damping
            # of Ω N₁ and the velocity limits let it
            assert np.linalg.norm(w0) < 0.5 * w_naive


def test_null_space_objectives_improve_their_measure():
    robot = spacearm.presets.spatial7()
    x0 = robot.neutral_configuration()
    target = robot.point_position(x0) + np.array([-0.5, 0.4, 0.4])
    mid, span = _limits(robot)
    kw = dict(task="position", strategy="naive", duration=4.0, settle=1.0, dt=0.02)
    plain = analysis.move_to(robot, target, **kw)
    limits = analysis.move_to(robot, target, joint_limit_gain=50.0, **kw)
    manip = analysis.move_to(robot, target, manipulability_gain=20.0, **kw)
    for m in (plain, limits, manip):
        assert m.final_position_error < 1e-8
    cost = lambda m: float(np.mean((2 * (m.x[-1, 7:] - mid) / span) ** 2))  # noqa: E731
    w = lambda m: analysis.analyze(robot, m.x[-1], task="position").generalized.manipulability  # noqa: E731
    print(f"\njoint-limit cost {cost(plain):.4f} -> {cost(limits):.4f}; manipulability {w(plain):.4f} -> {w(manip):.4f}")
    assert cost(limits) < 0.8 * cost(plain)
    assert w(manip) > 1.05 * w(plain)


def test_dls_keeps_motion_to_an_unreachable_target_finite():
    robot = spacearm.presets.spatial7()
    x0 = robot.neutral_configuration()
    target = robot.point_position(x0) + np.array([0.6, 0.0, -0.2])  # beyond the stretched arm
    m = analysis.move_to(robot, target, task="position", strategy="naive", threshold=0.05, max_damping=0.05, duration=4.0, settle=1.0, dt=0.02)
    assert np.all(np.isfinite(m.x)) and np.all(np.isfinite(m.qd))
    assert m.damping.max() > 0.04 and m.sigma_min.min() < 0.01  # it went into the singular region
    assert np.abs(m.qd).max() <= 1.5 + 1e-12  # the velocity limits of the preset
    assert 0.0 < m.final_position_error < 0.1


def test_spatial7_preset():
    robot = spacearm.presets.spatial7()
    d = robot.describe()
    assert robot.n_dof == 7 and robot.total_mass == pytest.approx(544.0)
    assert [link["axis"] for link in d["links"]] == [[1, 0, 0], [0, 1, 0], [1, 0, 0], [0, 1, 0], [1, 0, 0], [0, 1, 0], [1, 0, 0]]
    assert d["links"][3]["limits"][:2] == [-2.9, 0.1]
    assert analysis.reaction_null_space(robot).dimension == 4
