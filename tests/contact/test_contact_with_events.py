"""A free target under contact AND topology events in one run (docs/events.md, "Events with
contact"; the core's sim/topology.rs): the rock comes at the arm's tip, the contact stops it,
the grasp fires when the tip–handle gap and the relative speed fall below their thresholds (the
grasp on contact), and a release later lets it go, the contact pushing the two apart again.
Checked here from what the run did not compute: robot + rock momentum summed from the robot's
recorded momentum and the rock's rows, mass and inertia, continuous across the grasp and the
release to 1e-12 relative; the kinetic energy (the robot's recorded energy plus the rock's) the
same just before and after the release (no separation impulse) to 1e-12; and each sample's
phase against the events' times."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import spacearm
from spacearm.events import Attach, Detach

from target_scene import I_ROCK, M_ROCK, scene


def rock_momentum(s):
    R = Rotation.from_quat(s[:, 3:7]).as_matrix()
    spin = np.einsum("kij,jl,kml,km->ki", R, I_ROCK, R, s[:, 10:13])
    p = M_ROCK * s[:, 7:10]
    return p, np.cross(s[:, 0:3], p) + spin, 0.5 * (M_ROCK * (s[:, 7:10] ** 2).sum(1) + (s[:, 10:13] * spin).sum(1))


def test_a_grasp_on_contact_and_a_release_keep_the_momentum_and_the_energy():
    robot, rock, s0, u0, contact = scene()
    events = [Attach(point="tip", grasp="handle", gap=0.01, speed=0.01), Detach(at=0.9)]
    traj = spacearm.simulate(robot, 1.2, u0=u0, dt=1e-3, contact=contact, target=rock, target_state=s0, events=events)
    ev = traj.meta["events"]
    assert [e["kind"] for e in ev] == ["attach", "detach"]
    t_a, t_d = ev[0]["t"], ev[1]["t"]
    t, s, attached, phase = traj.t, traj["target"], traj["attached"].astype(bool), traj["phase"]
    n = t.size
    assert s.shape == (n, 13) and attached.shape == phase.shape == (n,)
    # the contact acted before the grasp (phase 0), none while welded, again after the release
    touching = traj.contact_count > 0
    assert touching[phase == 0].any() and t[touching][0] < t_a
    assert not touching[phase == 1].any() and touching[phase == 2].any()
    # each sample's phase: the events' instants are recorded twice, once in each phase
    k_a, k_d = np.flatnonzero(t == t_a), np.flatnonzero(t == t_d)
    assert k_a.size == 2 and k_d.size == 2
    expected = np.where(np.arange(n) <= k_a[0], 0, np.where(np.arange(n) <= k_d[0], 1, 2))
    np.testing.assert_array_equal(phase, expected)
    np.testing.assert_array_equal(attached, phase == 1)
    assert ev[0]["body"] == "rock" and traj["event_gap"][0] < 0.01
    # robot + rock momentum, summed here: the rock's own momentum only where it flies free (while
    # attached it is a link of the robot, inside the robot's records)
    p_t, l_t, e_t = rock_momentum(s)
    free = ~attached
    P = traj.P + p_t * free[:, None]
    L = traj.L_origin + l_t * free[:, None]
    H = np.hstack([P, L])
    np.testing.assert_allclose(traj["ledger_momentum"], H, rtol=0, atol=1e-13 * np.abs(H).max())
    for k in (k_a, k_d):
        jump = np.abs(H[k[1]] - H[k[0]]).max() / np.abs(H[k[0]]).max()
        assert jump < 1e-12, f"momentum across the event at {t[k[0]]}: {jump:.3g}"
        # while the rock's own momentum jumps (the grasp) or the robot's records do (both)
        assert np.abs(traj.P[k[1]] - traj.P[k[0]]).max() > 1e-3
    # the grasp's impulse is the jump of the rock's momentum
    np.testing.assert_allclose(M_ROCK * (s[k_a[1], 7:10] - s[k_a[0], 7:10]), -traj["event_impulse"][0, :3], rtol=1e-9)
    # the release, without a separation impulse, keeps the kinetic energy
    E = traj.energy + e_t * free
    assert abs(E[k_d[1]] - E[k_d[0]]) < 1e-12 * E[k_d[0]]
    assert abs(traj["event_energy_after"][1] - traj["event_energy_before"][1]) < 1e-12 * traj["event_energy_before"][1]
    # over the run the contact forces are internal: the ledger drifts by the integration error only
    assert np.abs(H - H[0]).max() < 1e-8 * np.abs(H).max()


def test_a_free_target_without_events_runs_through_the_same_entry():
    """The one entry (issue 32): a free target under contact without events is the run it was —
    the target's rows, the ledger, all in phase 0, no events."""
    robot, rock, s0, u0, contact = scene()
    traj = spacearm.simulate(robot, 0.3, u0=u0, dt=1e-3, contact=contact, target=rock, target_state=s0)
    assert traj.meta["events"] == []
    assert (traj["phase"] == 0).all() and not traj["attached"].any()
    p_t, l_t, _ = rock_momentum(traj["target"])
    np.testing.assert_allclose(traj["ledger_momentum"][:, :3], traj.P + p_t, rtol=0, atol=1e-14)


def test_a_target_without_contact_or_events_is_refused():
    robot, rock, s0, u0, _ = scene()
    with pytest.raises(spacearm.errors.ArgumentError, match=r"give contact=.*or events="):
        spacearm.simulate(robot, 0.1, u0=u0, target=rock, target_state=s0)
    with pytest.raises(spacearm.errors.ArgumentError, match="go together"):
        spacearm.simulate(robot, 0.1, u0=u0, target=rock)
