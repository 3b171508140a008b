"""The record of the contacts' points and forces (docs/contact.md, "Records"; the core's
sim/record.rs): one row per acting contact per sample, ``[k, body_a, body_b, p, n̂, f_n, f]``.

Checked two ways against what the record did not compute: at every sample, the forces on the
bus (a single rigid body) against Newton–Euler on its recorded accelerations ``du`` (the core's
forward dynamics); over the run, the impulse of the recorded forces (trapezoidal quadrature over
the samples) against the change of the target's and the bus's momentum, to the quadrature's own
error bound. And the rows against the contact law they come from: ``f · n̂ = f_n``, the friction
tangential and within Coulomb's cone, and against the summary records ``contact_count`` and
``contact_normal_force``."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import spacearm
from spacearm.contact import ContactModel, Pair
from spacearm.errors import ArgumentError, NotFoundError

M_BUS, I_BUS = 100.0, np.diag([3.0, 3.6, 4.2])
M_T, I_T = 2.0, np.diag([0.05, 0.08, 0.1])
MU = 0.3


def bus_and_rock():
    """A bus with two balls on its +x face and a box target: the box's face meets both balls."""
    b = spacearm.RobotBuilder("bus", M_BUS, I_BUS)
    b.add_geometry("base", "sphere", role="collision", radius=0.1, origin=(0.4, 0.2, 0.0), name="knob_a")
    b.add_geometry("base", "sphere", role="collision", radius=0.1, origin=(0.4, -0.2, 0.0), name="knob_b")
    bus = b.build()
    t = spacearm.RobotBuilder("rock", M_T, I_T, base_name="rock")
    t.add_geometry("rock", "box", role="collision", size=(0.3, 0.8, 0.3), name="slab")
    return bus, t.build()


@pytest.fixture(scope="module")
def run():
    bus, rock = bus_and_rock()
    # The slab comes along −x, turned a little about z so one ball is met before the other,
    # sliding along y and spinning towards the second ball: both contacts with friction, onsets apart.
    q = Rotation.from_euler("z", 0.02).as_quat()
    s0 = np.concatenate([[0.67, 0.0, 0.0], q, [-0.4, 0.15, 0.0], [0.0, 0.3, -0.5]])
    contact = ContactModel(stiffness=2e4, damping=0.5, law="hunt_crossley", friction=MU, slip_velocity=1e-2,
                           pairs=[Pair("base", "target")])
    traj = spacearm.simulate(bus, 0.25, dt=2e-5, record_every=1, target=rock, target_state=s0, contact=contact)
    return bus, rock, traj


def _per_body(traj, body: int) -> tuple:
    """The recorded contact force (K, 3) on ``body`` and its moment about ``centres`` (K, 3) per
    sample, summed from the rows (the first body of a row feels −f, the second +f)."""
    rows = traj.contact_forces
    k = len(traj)
    force, moment_origin = np.zeros((k, 3)), np.zeros((k, 3))
    for sign, col in ((-1.0, 1), (1.0, 2)):
        sel = rows[:, col] == body
        f = sign * rows[sel, 10:13]
        idx = rows[sel, 0].astype(int)
        np.add.at(force, idx, f)
        np.add.at(moment_origin, idx, np.cross(rows[sel, 3:6], f))
    return force, moment_origin


def test_rows_follow_the_law_and_the_summary_records(run):
    _, _, traj = run
    rows = traj.contact_forces
    assert rows.shape[1] == 13 and len(rows) > 100
    counts = np.bincount(rows[:, 0].astype(int), minlength=len(traj))
    np.testing.assert_array_equal(counts, traj.contact_count)
    assert counts.max() == 2 and (counts == 1).any()  # one ball, then both
    fn_sum = np.bincount(rows[:, 0].astype(int), weights=rows[:, 9], minlength=len(traj))
    np.testing.assert_allclose(fn_sum, traj.contact_normal_force, rtol=0, atol=1e-12 * fn_sum.max())
    n, fn, f = rows[:, 6:9], rows[:, 9], rows[:, 10:13]
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1.0, atol=1e-14)
    assert (fn >= 0).all() and fn.max() > 10.0
    np.testing.assert_allclose(np.einsum("ij,ij->i", f, n), fn, atol=1e-12 * fn.max())
    friction = f - fn[:, None] * n
    assert (np.linalg.norm(friction, axis=1) <= MU * fn * (1 + 1e-12) + 1e-12).all()
    assert np.linalg.norm(friction, axis=1).max() > 0.1 * MU * fn.max()  # friction acts
    # the bus is body 0, the target one past the robot's bodies
    assert set(rows[:, 1]) == {0.0} and set(rows[:, 2]) == {1.0}
    k = int(rows[len(rows) // 2, 0])
    np.testing.assert_array_equal(traj.contacts_at(k), rows[rows[:, 0] == k])
    with pytest.raises(ArgumentError, match="out of range"):
        traj.contacts_at(len(traj))


def test_recorded_forces_are_newton_euler_of_the_recorded_accelerations(run):
    """The bus is one rigid body: Σ f = M v̇ and Σ (p − r) × f = I_J ω̇ + ω × I_J ω with the
    recorded ``du`` (the core's forward dynamics at the sample, not the rows)."""
    _, _, traj = run
    force, moment_origin = _per_body(traj, 0)
    r = traj.x[:, :3]
    moment = moment_origin - np.cross(r, force)
    R = Rotation.from_quat(traj.x[:, 3:7]).as_matrix()
    I_J = R @ I_BUS @ R.transpose(0, 2, 1)
    w, dw = traj.u[:, 3:6], traj.du[:, 3:6]
    euler = np.einsum("kij,kj->ki", I_J, dw) + np.cross(w, np.einsum("kij,kj->ki", I_J, w))
    peak = np.linalg.norm(force, axis=1).max()
    assert peak > 10.0
    np.testing.assert_allclose(force, M_BUS * traj.du[:, :3], rtol=0, atol=1e-10 * peak)
    np.testing.assert_allclose(moment, euler, rtol=0, atol=1e-10 * peak * 0.5)


def _trapezoid_with_bound(t: np.ndarray, f: np.ndarray) -> tuple:
    """∫ f dt by the trapezoidal rule over the samples and its error bound
    Σ h³/12 |f''| over the intervals, |f''| from the samples' second differences; twice that,
    for the kinks of f at contact onset and separation (there the second difference sees the
    jump of f' spread over one step, and the rule's error on a kink is up to h²|Δf'|/8 against
    the h²|Δf'|/12 the formula gives)."""
    h = np.diff(t)
    integral = np.sum(0.5 * h[:, None] * (f[1:] + f[:-1]), axis=0)
    d2 = np.abs(f[2:] - 2 * f[1:-1] + f[:-2]) / h[1:, None] ** 2
    d2 = np.vstack([d2[:1], d2, d2[-1:]])  # at the ends, the neighbours'
    per_interval = np.maximum(d2[1:], d2[:-1]) * (h ** 3 / 12.0)[:, None]
    return integral, 2.0 * per_interval.sum(axis=0)


def test_the_impulse_of_the_recorded_forces_is_the_change_of_momentum(run):
    """Σ contact impulses = Δ momentum: the target's (from its recorded 13-state, m v and
    r × m v + I_J ω) and the bus's, each the impulse of the recorded forces on it (trapezoid
    over the samples, to its error bound); robot + target's total stays put."""
    _, _, traj = run
    t = traj.t
    s = traj["target"]
    f_t, m_t = _per_body(traj, 1)
    f_b, _ = _per_body(traj, 0)
    J_t, bound_t = _trapezoid_with_bound(t, f_t)
    H_t, bound_h = _trapezoid_with_bound(t, m_t)
    J_b, bound_b = _trapezoid_with_bound(t, f_b)
    P_t = M_T * s[:, 7:10]
    R = Rotation.from_quat(s[:, 3:7]).as_matrix()
    L_t = np.cross(s[:, :3], P_t) + np.einsum("kij,kj->ki", R @ I_T @ R.transpose(0, 2, 1), s[:, 10:13])
    dP_t, dL_t = P_t[-1] - P_t[0], L_t[-1] - L_t[0]
    dP_b = traj.P[-1] - traj.P[0]
    assert np.linalg.norm(dP_t) > 0.5 * M_T * 0.4  # the contact turns the target's momentum round
    assert bound_t.max() < 1e-4 * np.linalg.norm(dP_t)  # a bound that can tell
    np.testing.assert_array_less(np.abs(J_t - dP_t), bound_t + 1e-12)
    np.testing.assert_array_less(np.abs(H_t - dL_t), bound_h + 1e-12)
    np.testing.assert_array_less(np.abs(J_b - dP_b), bound_b + 1e-12)
    total = traj["ledger_momentum"]
    assert np.abs(total - total[0]).max() < 1e-12 * M_T * 0.5


def test_a_run_without_contact_has_no_contact_rows():
    traj = spacearm.simulate(spacearm.presets.spatial6(), 0.01, dt=0.01)
    assert not traj.has("contact_forces")
    with pytest.raises(NotFoundError, match="no contact"):
        traj.contact_forces


def test_the_rows_of_a_run_with_events_count_as_its_samples():
    """A run with topology events is recorded segment by segment (sim/topology.rs): the rows'
    sample indices continue across the grasp and the release, so each sample's rows are still
    its ``contact_count`` and its ``contact_normal_force``."""
    from spacearm.events import Attach, Detach
    from target_scene import scene

    robot, rock, s0, u0, contact = scene()
    events = [Attach(point="tip", grasp="handle", gap=0.01, speed=0.01), Detach(at=0.9)]
    traj = spacearm.simulate(robot, 1.2, u0=u0, dt=1e-3, contact=contact, target=rock, target_state=s0, events=events)
    rows = traj.contact_forces
    phase = traj["phase"]
    k = rows[:, 0].astype(int)
    counts = np.bincount(k, minlength=len(traj))
    np.testing.assert_array_equal(counts, traj.contact_count)
    assert (counts[phase == 0] > 0).any() and (counts[phase == 2] > 0).any()  # before the grasp and after the release
    fn_sum = np.bincount(k, weights=rows[:, 9], minlength=len(traj))
    np.testing.assert_allclose(fn_sum, traj.contact_normal_force, rtol=0, atol=1e-12 * fn_sum.max())
