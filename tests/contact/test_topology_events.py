"""Topology events (docs/events.md; the core's sim/topology.rs): attach, release and re-dock of
two free systems in one run. Each quantity is checked against something the event code did not
compute: the robot's own momentum function, the target's mass times its recorded velocity jump,
a closed-form crossing time."""

from __future__ import annotations

import numpy as np
import pytest

import spacearm
from spacearm.errors import ArgumentError
from spacearm.events import Attach, Detach


def _scene(v_target=(-0.05, 0.01, 0.0), w_target=(0.0, 0.05, 0.1), offset=0.6):
    robot = spacearm.presets.spatial6()
    x0 = robot.neutral_configuration()
    u0 = robot.zero_velocity()
    u0[0], u0[5] = 0.02, 0.01
    u0[6:] = 0.05 * np.arange(1, 7) * (-1.0) ** np.arange(6)
    target = spacearm.Target(50.0, [4.0, 5.0, 6.0], grasp_points={"handle": (-0.5, 0.0, 0.0)})
    s0 = target.state(position=robot.point_position(x0) + np.array([offset, 0.0, 0.0]), velocity=v_target,
                      angular_velocity=w_target)
    return robot, x0, u0, target, s0


def _rel(a, b):
    return np.linalg.norm(np.asarray(a) - np.asarray(b)) / np.linalg.norm(a)


def test_attach_release_and_redock_keep_the_momentum_and_each_impulse_is_its_jump():
    robot, x0, u0, target, s0 = _scene()
    traj = spacearm.simulate(robot, 1.2, x0=x0, u0=u0, dt=0.01, target=target, target_state=s0,
                             events=[Attach(at=0.3), Detach(at=0.6, impulse=2.0, direction=(1.0, 0.5, 0.0)),
                                     Attach(at=0.9, grasp="handle")])
    assert [e["kind"] for e in traj.meta["events"]] == ["attach", "detach", "attach"]
    t, u, s = traj.t, traj.u, traj["target"]
    for i, te in enumerate(traj["event_t"]):
        k = int(np.flatnonzero(t == te)[0])
        assert t[k + 1] == te
        before, after = traj["event_momentum_before"][i], traj["event_momentum_after"][i]
        assert np.linalg.norm(before) > 1.0
        assert _rel(before, after) < 1e-12
        assert _rel(traj["ledger_momentum"][k], traj["ledger_momentum"][k + 1]) < 1e-12
        f = traj["event_impulse"][i, :3]
        assert np.linalg.norm(f) > 0.1
        # the target's momentum jumps by the impulse (−f at an attach, +f at a release)
        dp = 50.0 * (s[k + 1, 7:10] - s[k, 7:10])
        assert _rel(f if traj["event_kind"][i] == 1 else -f, dp) < 1e-9
    # at the first attach the robot (its own model, its own momentum function) took +f at X:
    # ΔP = f, ΔL_O = X × f + n
    k = int(np.flatnonzero(t == traj["event_t"][0])[0])
    m_b, m_a = robot.momentum(traj.x[k], u[k]), robot.momentum(traj.x[k], u[k + 1])
    lam, x_pt = traj["event_impulse"][0], traj["event_point"][0]
    assert _rel(lam[:3], m_a.P - m_b.P) < 1e-9
    assert _rel(np.cross(x_pt, lam[:3]) + lam[3:], m_a.L_origin - m_b.L_origin) < 1e-9
    # the separation impulse as asked: 2 N·s along (1, 0.5, 0)
    f = traj["event_impulse"][1, :3]
    assert abs(np.linalg.norm(f) - 2.0) < 1e-12 and abs(f[1] / f[0] - 0.5) < 1e-12 and f[2] == 0.0
    np.testing.assert_array_equal(traj["attached"][[0, -1]], [0.0, 1.0])


def test_a_release_without_impulse_keeps_the_energy():
    robot = spacearm.presets.spatial6().attach_body("pod", body="link6", mass=8.0, inertia=[0.2, 0.3, 0.25],
                                                    origin=(0.1, 0.05, 0.0))
    u0 = robot.zero_velocity()
    u0[3:6] = (0.01, -0.02, 0.03)
    u0[6:] = 0.1
    traj = spacearm.simulate(robot, 0.5, u0=u0, dt=0.01, events=[Detach(at=0.25, body="pod")])
    k = int(np.flatnonzero(traj.t == 0.25)[0])
    eb, ea = traj["event_energy_before"][0], traj["event_energy_after"][0]
    # the robot with the pod, by the robot's own kinetic energy, is the energy before
    assert abs(robot.kinetic_energy(traj.x[k], traj.u[k]) - eb) < 1e-12 * eb
    assert abs(ea - eb) < 1e-12 * eb and eb > 1e-3
    assert abs(traj["ledger_energy"][k + 1] - traj["ledger_energy"][k]) < 1e-12 * eb
    # the robot's own energy record drops by the pod's kinetic energy: ½ m v² + ½ ωᵀ I ω
    s = traj["target"][k + 1]
    r = spacearm.rotations.quat_to_matrix(s[3:7])
    t_pod = 0.5 * 8.0 * s[7:10] @ s[7:10] + 0.5 * s[10:] @ (r @ np.diag([0.2, 0.3, 0.25]) @ r.T) @ s[10:]
    assert abs((traj.energy[k] - traj.energy[k + 1]) - t_pod) < 1e-12 * eb


def test_a_threshold_attach_lands_on_the_closed_form_time():
    robot, x0, _, target, _ = _scene()
    u0 = robot.zero_velocity()
    u0[0] = 0.01
    d0, v, g0 = 0.3, -0.07, 0.02
    s0 = target.state(position=robot.point_position(x0) + np.array([0.5 + d0, 0.0, 0.0]), velocity=(v, 0.0, 0.0))
    t_star = (d0 - g0) / (0.01 - v)
    for dt in (0.05, 0.013):
        traj = spacearm.simulate(robot, 6.0, x0=x0, u0=u0, dt=dt, target=target, target_state=s0, events=Attach(gap=g0))
        assert abs(traj["event_t"][0] - t_star) < 1e-12
        assert abs(traj["event_gap"][0] - g0) < 1e-12


def test_bad_events_are_refused_by_the_core_with_their_names():
    robot, x0, u0, target, s0 = _scene()
    run = dict(x0=x0, u0=u0, dt=0.01, target=target, target_state=s0)
    with pytest.raises(ArgumentError, match="gap must be finite and > 0 m"):
        spacearm.simulate(robot, 0.5, events=[Attach(gap=-1.0)], **run)
    with pytest.raises(ArgumentError, match="attach located by thresholds is not implemented with integrator=.dopri5."):
        spacearm.simulate(robot, 0.5, events=[Attach(gap=0.1)], integrator="dopri5", **run)
    with pytest.raises(ArgumentError, match="events takes"):
        spacearm.simulate(robot, 0.5, events=["attach"], **run)
    with pytest.raises(ArgumentError, match=r"give contact=.*or events="):
        spacearm.simulate(robot, 0.5, x0=x0, u0=u0, target=target, target_state=s0)


def test_a_run_with_events_saves_and_loads_with_its_records(tmp_path):
    robot, x0, u0, target, s0 = _scene()
    traj = spacearm.simulate(robot, 0.4, x0=x0, u0=u0, dt=0.02, target=target, target_state=s0,
                             events=[Attach(at=0.1), Detach(at=0.3)])
    back = spacearm.Trajectory.load(traj.save(tmp_path / "events.npz"))
    assert back.meta["events"] == traj.meta["events"]
    for key in ("target", "attached", "ledger_momentum", "event_t", "event_impulse", "event_momentum_after"):
        np.testing.assert_array_equal(back[key], traj[key])
    assert "saturation: none" in back.summary()
