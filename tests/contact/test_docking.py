"""Probe and drogue (docs/contact.md, "Probe and drogue"; the core's model/docking.rs): the
geometry against its closed form, and a chaser's probe entering a free target's drogue under
compliant contact. The physics checked: a lateral misalignment within the mouth is corrected —
the cone's ribs turn the approach so that the probe's head reaches the throat's plate inside
the throat's circle — while one outside the mouth is not; robot + target momentum is kept
through the guidance."""

from __future__ import annotations

import math

import numpy as np
import pytest

import spacearm
from spacearm.contact import ContactModel, Pair
from spacearm.errors import ArgumentError, ModelError
from spacearm.rotations import quat_to_matrix

R_M, R_T, DEPTH, RHO, RIBS, HEAD = 0.2, 0.04, 0.3, 0.01, 24, 0.025


def models():
    c = spacearm.RobotBuilder("chaser", 500.0, np.diag([80.0, 90.0, 100.0]))
    c.add_probe("probe", position=(1.0, 0, 0), rpy=(0, np.pi / 2, 0), length=0.5, radius=0.02, head_radius=HEAD)
    t = spacearm.RobotBuilder("station", 100.0, np.diag([10.0, 12.0, 14.0]), base_name="port")
    t.add_drogue("cone", position=(-0.4, 0, 0), rpy=(0, -np.pi / 2, 0), mouth_radius=R_M, throat_radius=R_T,
                 depth=DEPTH, rib_radius=RHO, ribs=RIBS)
    return c.build(), t.build()


def test_the_drogue_is_a_cone_of_ribs_and_the_probe_a_capsule_with_a_head():
    chaser, station = models()
    ribs = [g for g in station.description.geometries if g.name.startswith("cone_rib")]
    assert len(ribs) == RIBS and all(g.shape == "capsule" and g.radius == RHO for g in ribs)
    axis = np.array([-1.0, 0, 0])  # rpy (0, −π/2, 0) turns +z to −x
    throat = np.array([-0.4, 0, 0])
    for i, g in enumerate(ribs):
        half = quat_to_matrix(np.asarray(g.rotation)) @ [0, 0, 0.5 * g.length]
        a, b = np.asarray(g.origin) - half, np.asarray(g.origin) + half
        # a on the throat's circle, b on the mouth's, both at angle 2πi/N about the axis
        for p, r, h in ((a, R_T, 0.0), (b, R_M, DEPTH)):
            d = p - throat
            assert abs(d @ axis - h) < 1e-14 and abs(np.linalg.norm(d - (d @ axis) * axis) - r) < 1e-14
        assert abs(math.atan2((a - throat)[1], (a - throat)[2]) % (2 * math.pi) - 2 * math.pi * i / RIBS) < 1e-12
    (plate,) = [g for g in station.description.geometries if g.name == "cone_throat_plate"]
    assert plate.shape == "cylinder" and plate.radius == R_T + RHO and plate.length == 2 * RHO
    x = station.neutral_configuration()
    np.testing.assert_allclose(station.point_position(x, "cone_mouth"), throat + DEPTH * axis, atol=1e-15)
    xc = chaser.neutral_configuration()
    np.testing.assert_allclose(chaser.point_position(xc, "probe_tip"), [1.5, 0, 0], atol=1e-15)
    (head,) = [g for g in chaser.description.geometries if g.name == "probe_head"]
    assert head.shape == "sphere" and head.radius == HEAD
    # the mouth's gaps are narrower than the head: it cannot slip between two ribs
    assert R_M * math.sin(math.pi / RIBS) - RHO < HEAD


def dock(y0: float):
    chaser, station = models()
    s0 = np.array([1.5 + DEPTH + 0.4 + 0.05, y0, 0.0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0])  # the head 5 cm out of the mouth
    u0 = chaser.zero_velocity()
    u0[0] = 0.1
    k, m_r = 1e4, 500.0 * 100.0 / 600.0
    contact = ContactModel(stiffness=k, damping=2 * 0.7 * math.sqrt(k * m_r), pairs=[Pair("probe_head", "target")])
    traj = spacearm.simulate(chaser, 5.0, dt=1e-3, record_every=10, u0=u0, target=station, target_state=s0, contact=contact)
    tips = chaser.point_position(np.ascontiguousarray(traj.x), "probe_tip")
    S = traj["target"]
    R = quat_to_matrix(S[:, 3:7])
    throat = S[:, :3] + R @ np.array([-0.4, 0, 0])
    axis = R @ np.array([-1.0, 0, 0])
    d = tips - throat
    axial = np.einsum("ki,ki->k", d, axis)
    lateral = np.linalg.norm(d - axial[:, None] * axis, axis=1)
    return traj, axial, lateral


@pytest.mark.parametrize("y0", [0.08, 0.15])
def test_a_misalignment_within_the_mouth_is_corrected(y0):
    traj, axial, lateral = dock(y0)
    assert y0 < R_M - RHO - HEAD  # inside the mouth's circle of free space
    k = int(np.argmin(axial))
    # the head reached the throat's plate (its face is the plane axial = 0) inside the throat
    assert axial[k] < HEAD and lateral[k] < R_T, (axial[k], lateral[k])
    assert traj.contact_count.max() >= 1
    P = traj["ledger_momentum"]
    assert np.abs(P[:, :3] - P[0, :3]).max() < 1e-12 * 500.0 * 0.1
    assert traj.meta["drift"]["L_origin"] < 1e-11


def test_a_misalignment_outside_the_mouth_is_not():
    traj, axial, lateral = dock(0.25)
    assert traj.contact_count.max() == 0 and lateral.min() > R_M


def test_bad_docking_parts_are_refused_naming_them():
    b = spacearm.RobotBuilder("t", 1.0, np.eye(3))
    with pytest.raises(ModelError, match="drogue 'cone': mouth_radius 0.03 m must exceed throat_radius"):
        b.add_drogue("cone", mouth_radius=0.03, throat_radius=0.04, depth=0.3, rib_radius=0.01)
    with pytest.raises(ModelError, match="ribs must be at least 3"):
        b.add_drogue("cone", mouth_radius=0.2, throat_radius=0.04, depth=0.3, rib_radius=0.01, ribs=2)
    with pytest.raises(ArgumentError, match="ribs must be an integer"):
        b.add_drogue("cone", mouth_radius=0.2, throat_radius=0.04, depth=0.3, rib_radius=0.01, ribs=2.5)
    with pytest.raises(ModelError, match="probe 'p': head_radius must be finite and > 0"):
        b.add_probe("p", length=0.5, radius=0.02, head_radius=-1.0)
