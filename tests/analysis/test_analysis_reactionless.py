"""Reaction null space, free-floating kinematics and reactionless motion,
against Pinocchio-built base maps, an independent NumPy RK4 of the base driven by Pinocchio's mass
matrix, and a closed form."""

import numpy as np
import pytest

import spacearm
from spacearm import analysis
from spacearm.errors import ArgumentError, ShapeError

from analysis_refs import PinRef, pin_integrate_base


@pytest.mark.parametrize("name,dim_angular,dim_full", [("planar4", 3, 1), ("spatial6", 3, 0), ("spatial7", 4, 1), ("dual_arm", 9, 6)])
def test_reaction_null_space_matches_pinocchio(name, dim_angular, dim_full):
    robot = spacearm.presets.get(name)
    ref = PinRef(robot)
    rng = np.random.default_rng(2)
    for _ in range(4):
        quat = rng.normal(size=4)
        x = robot.neutral_configuration(q=rng.uniform(-2, 2, robot.n_dof), r0=rng.normal(size=3), quat0=quat / np.linalg.norm(quat))
        _, _, base = ref.maps(x)
        for which, rows, dim in (("angular", slice(3, 6), dim_angular), ("full", slice(0, 6), dim_full)):
            rns = analysis.reaction_null_space(robot, x, base_motion=which)
            np.testing.assert_allclose(rns.base_motion_map, base[rows], atol=1e-10 * np.abs(base).max())
            assert rns.dimension == dim
            # independent null space: SVD of the Pinocchio map, rank from its own singular values
            _, s, vt = np.linalg.svd(base[rows])
            rank = int(np.sum(s > 1e-9 * s[0]))
            null_ref = vt[rank:].T
            assert null_ref.shape[1] == dim
            np.testing.assert_allclose(rns.projector, null_ref @ null_ref.T, atol=1e-9)
            if dim:
                # the base does not rotate (angular) or move (full) under these joint rates
                qd = rns.basis @ rng.normal(size=dim)
                xd0 = robot.base_velocity_from_momentum(x, qd)
                moved = xd0[3:] if which == "angular" else xd0
                assert np.linalg.norm(moved) < 1e-12 * np.linalg.norm(qd) * np.abs(base).max() + 1e-15
                # while a generic joint rate does move it
                assert np.linalg.norm(robot.base_velocity_from_momentum(x, rng.normal(size=robot.n_dof))[3:]) > 1e-4


def _trajectory(robot, seed=4):
    rng = np.random.default_rng(seed)
    q0 = robot.initial_q
    amp, freq = rng.uniform(0.3, 0.8, robot.n_dof), rng.uniform(0.5, 1.5, robot.n_dof)
    q = lambda t: q0 + amp * np.sin(freq * t)  # noqa: E731
    qd = lambda t: amp * freq * np.cos(freq * t)  # noqa: E731
    return q, qd


@pytest.mark.parametrize("name", ["spatial6", "planar4"])
def test_prescribed_motion_matches_pinocchio_rk4(name):
    robot = spacearm.presets.get(name)
    q, qd = _trajectory(robot)
    x0 = robot.neutral_configuration(r0=[0.5, -0.2, 0.1], quat0=[0.1, -0.2, 0.3, np.sqrt(1 - 0.14)])
    t, xs = analysis.integrate_prescribed(robot, q, qd, t_end=3.0, dt=0.02, x0=x0)
    assert xs.shape == (151, robot.nx) and t[-1] == pytest.approx(3.0)
    ref = pin_integrate_base(robot, x0, q, qd, 3.0, 150)
    turned = analysis.attitude_change(x0[3:7], xs[-1, 3:7])
    assert turned > 1e-2  # the reference is not trivial: the base rotates
    assert np.linalg.norm(xs[-1, :3] - ref[:3]) < 1e-10
    assert analysis.attitude_change(xs[-1, 3:7], ref[3:7]) < 1e-10
    np.testing.assert_allclose(xs[:, 7:], np.array([q(s) for s in t]), atol=1e-14)
    # zero momentum: the system CM stays put (independent check through body sums)
    com = np.array([robot.center_of_mass(x) for x in xs[::25]])
    assert np.abs(com - com[0]).max() < 1e-8  # RK4 truncation at dt = 0.02 s


def test_nonzero_momentum_is_conserved():
    robot = spacearm.presets.spatial6()
    q, qd = _trajectory(robot, seed=8)
    P, L = np.array([1.0, -2.0, 0.5]), np.array([0.3, 0.1, -0.4])
    t, xs = analysis.integrate_prescribed(robot, q, qd, t_end=2.0, dt=0.01, P=P, L=L)
    for k in (0, 100, 200):
        u = np.r_[robot.base_velocity_from_momentum(xs[k], qd(t[k]), P=P, L=L), qd(t[k])]
        mom = robot.momentum(xs[k], u)  # body sums, independent of the mass matrix
        np.testing.assert_allclose(mom.P, P, atol=1e-10)
        np.testing.assert_allclose(mom.L_origin, L, atol=1e-10)
    # the system CM drifts at P/M
    drift = robot.center_of_mass(xs[-1]) - robot.center_of_mass(xs[0])
    np.testing.assert_allclose(drift, P / robot.total_mass * 2.0, atol=1e-9)


def _hermite(times, qs, qds):
    """Cubic Hermite interpolation of a sampled joint trajectory (position and rate)."""
    dt = times[1] - times[0]

    def at(t):
        k = min(int(t / dt), len(times) - 2)
        s = (t - times[k]) / dt
        h00, h10, h01, h11 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s, -2 * s**3 + 3 * s**2, s**3 - s**2
        return h00 * qs[k] + h10 * dt * qds[k] + h01 * qs[k + 1] + h11 * dt * qds[k + 1]

    def rate(t):
        k = min(int(t / dt), len(times) - 2)
        s = (t - times[k]) / dt
        d00, d10, d01, d11 = 6 * s**2 - 6 * s, 3 * s**2 - 4 * s + 1, -6 * s**2 + 6 * s, 3 * s**2 - 2 * s
        return (d00 * qs[k] + d01 * qs[k + 1]) / dt + d10 * qds[k] + d11 * qds[k + 1]

    return at, rate


@pytest.mark.parametrize("name,offset,task", [("planar4", [-0.5, 0.6, 0.0], "planar"), ("spatial7", [-0.3, 0.0, 0.2], "position"),
                                               ("spatial6", [-0.3, 0.0, 0.2], "position")])
def test_reactionless_motion_keeps_attitude_and_naive_does_not(name, offset, task, tmp_path):
    robot = spacearm.presets.get(name)
    x0 = robot.neutral_configuration()
    target = robot.point_position(x0) + np.array(offset)
    kw = dict(task=task, duration=4.0, settle=1.0, dt=0.01)
    rl = analysis.move_to(robot, target, strategy="reactionless", **kw)
    nv = analysis.move_to(robot, target, strategy="naive", **kw)
    md = analysis.move_to(robot, target, strategy="minimum_disturbance", **kw)
    print(f"\n{name}: attitude change reactionless {rl.max_attitude_change:.3e} rad, minimum-disturbance "
          f"{md.max_attitude_change:.3e} rad, naive {nv.max_attitude_change:.3e} rad; final errors "
          f"{rl.final_position_error:.2e} / {md.final_position_error:.2e} / {nv.final_position_error:.2e} m")
    for m in (rl, nv, md):
        assert m.final_position_error < 1e-4
    assert rl.max_attitude_change < 1e-9
    assert nv.max_attitude_change > 1e-2
    assert md.max_attitude_change <= nv.max_attitude_change
    # Independent check: re-integrate the planned joint motion with the Pinocchio-driven RK4.
    q_of_t, qd_of_t = _hermite(rl.times, rl.x[:, 7:], rl.qd)
    ref = pin_integrate_base(robot, x0, q_of_t, qd_of_t, rl.times[-1], 250)
    assert analysis.attitude_change(x0[3:7], ref[3:7]) < 1e-6
    q_of_t, qd_of_t = _hermite(nv.times, nv.x[:, 7:], nv.qd)
    ref_n = pin_integrate_base(robot, x0, q_of_t, qd_of_t, nv.times[-1], 250)
    assert analysis.attitude_change(ref_n[3:7], nv.x[-1, 3:7]) < 1e-5
    assert analysis.attitude_change(x0[3:7], ref_n[3:7]) > 1e-2
    if name == "planar4":
        rl.plot(tmp_path / "motion.png", others=[md, nv])
        assert (tmp_path / "motion.png").stat().st_size > 10_000


def test_bad_input():
    robot = spacearm.presets.planar4()
    x = robot.neutral_configuration()
    with pytest.raises(spacearm.SpacearmError, match="strategy"):
        analysis.move_to(robot, [1, 1, 0], strategy="sideways")
    with pytest.raises(ArgumentError, match="time step"):
        analysis.move_to(robot, [1, 1, 0], dt=0.0)
    with pytest.raises(ArgumentError, match="feedback gain"):
        analysis.move_to(robot, [1, 1, 0], gain=-1.0)
    with pytest.raises(ShapeError):
        analysis.move_to(robot, [1, 1])
    with pytest.raises(ArgumentError, match="angular"):
        analysis.reaction_null_space(robot, x, base_motion="twist")
    with pytest.raises(ArgumentError, match="tolerance"):
        analysis.reaction_null_space(robot, x, tolerance=0.0)
    with pytest.raises(spacearm.SpacearmError):
        analysis.integrate_prescribed(robot, lambda t: np.zeros(4), lambda t: np.zeros(4), t_end=-1.0, dt=0.1)
    with pytest.raises(ShapeError, match="length 4"):
        analysis.integrate_prescribed(robot, lambda t: np.zeros(3), lambda t: np.zeros(3), t_end=1.0, dt=0.1)
