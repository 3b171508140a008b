"""spacearm's compliant contact against MuJoCo's soft contact (docs/contact.md, "In MuJoCo"):
the model and its contact exported by ``to_mjcf(..., contact=, target=, effective_mass=)``, the
law mapped to ``solref = (−k/m_eff, −d/m_eff)`` at impedance ``D = IMPEDANCE``, both run with
RK4 at one step. Compared: the contact onset time (both against the closed form of the
approach) and the twists after the impact, to the tolerance the two laws allow (derived in each
test from where they differ, docs/contact.md): MuJoCo's law is spacearm's with the stiffness and
damping scaled by ``s = 1 / (1 + (1 − D)(Â/A − 1))`` (``Â``: MuJoCo's approximation of the
contact's inverse effective mass ``A``, read back from its regularizer ``efc_R``), and MuJoCo does not
locate the onset inside a step, where the Kelvin–Voigt force jumps by ``d δ̇``."""

from __future__ import annotations

import math

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco")

import spacearm  # noqa: E402
from spacearm.contact import ContactModel, Pair  # noqa: E402
from spacearm.errors import ArgumentError  # noqa: E402
from spacearm.interop import from_mujoco_state, to_mjcf, to_mujoco_state  # noqa: E402
from spacearm.interop.mujoco_contact import IMPEDANCE, mujoco_contact_parameters, target_qpos_qvel  # noqa: E402
from spacearm.rotations import quat_to_matrix  # noqa: E402

M_BUS, M_T, R_BUS, R_T = 100.0, 2.0, 0.3, 0.2
M_R = M_BUS * M_T / (M_BUS + M_T)


def restitution(zeta: float) -> float:
    """The Kelvin–Voigt impact's coefficient of restitution (docs/contact.md, closed form)."""
    return math.exp(-zeta * (math.pi - 2 * math.asin(zeta)) / math.sqrt(1 - zeta ** 2))


def balls():
    b = spacearm.RobotBuilder("bus", M_BUS, np.eye(3) * 3.6)
    b.add_geometry("base", "sphere", role="collision", radius=R_BUS, name="hull")
    t = spacearm.RobotBuilder("rock", M_T, np.diag([0.08, 0.1, 0.12]), base_name="rock")
    t.add_geometry("rock", "sphere", role="collision", radius=R_T, name="shell")
    return b.build(), t.build()


def run_mujoco(robot, target, contact, m_eff, x0, u0, s0, duration, dt):
    """MuJoCo's run of the exported model: (final robot x, u, target 13-state, onset time, Â of
    the first contact row)."""
    model = mujoco.MjModel.from_xml_string(to_mjcf(robot, geometry=("collision",), contact=contact, target=target,
                                                   effective_mass=m_eff))
    model.opt.timestep = dt
    data = mujoco.MjData(model)
    qp, qv = to_mujoco_state(robot, x0, u0)
    tq, tv = target_qpos_qvel(s0)
    data.qpos[:], data.qvel[:] = np.concatenate([qp, tq]), np.concatenate([qv, tv])
    onset, diag = None, None
    for _ in range(int(round(duration / dt))):
        mujoco.mj_step(model, data)
        if onset is None and data.ncon > 0:
            onset = data.time
            mujoco.mj_forward(model, data)
            imp = float(data.efc_KBIP[0, 2])  # MuJoCo's impedance D of the row; its R = (1 − D)/D · Â
            diag = float(data.efc_R[0]) * imp / (1.0 - imp)
    nq, nv = robot.nx, robot.nu
    x, u = from_mujoco_state(robot, data.qpos[:nq], data.qvel[:nv])
    q = data.qpos[nq:nq + 7]
    quat = np.array([q[4], q[5], q[6], q[3]])  # [x, y, z, w]
    R = quat_to_matrix(quat / np.linalg.norm(quat))
    s = np.concatenate([q[:3], quat, data.qvel[nv:nv + 3], R @ data.qvel[nv + 3:nv + 6]])
    return x, u, s, onset, diag


def test_the_map_and_what_it_refuses():
    c = ContactModel(stiffness=1e4, damping=40.0, friction=0.3)
    p = mujoco_contact_parameters(c, 2.0)
    assert [float(v) for v in p["solref"].split()] == [-5e3, -20.0]
    assert [float(v) for v in p["solimp"].split()][:2] == [IMPEDANCE, IMPEDANCE]
    assert p["condim"] == "3" and p["friction"].split()[:2] == ["0.3", "0.3"]
    assert mujoco_contact_parameters(ContactModel(stiffness=1e4), 1.0)["condim"] == "1"
    with pytest.raises(ArgumentError, match="Kelvin–Voigt law with exponent 1 only"):
        mujoco_contact_parameters(ContactModel(stiffness=1e4, damping=0.1, law="hunt_crossley"), 1.0)
    with pytest.raises(ArgumentError, match="exponent"):
        mujoco_contact_parameters(ContactModel(stiffness=1e4, exponent=1.5), 1.0)
    with pytest.raises(ArgumentError, match="effective_mass"):
        mujoco_contact_parameters(c, 0.0)
    bus, rock = balls()
    with pytest.raises(ArgumentError, match="needs effective_mass"):
        to_mjcf(bus, contact=c, target=rock)
    xml = to_mjcf(bus, geometry=("collision",), contact=ContactModel(stiffness=1e4, pairs=[Pair("base", "target")]),
                  target=rock, effective_mass=M_R)
    model = mujoco.MjModel.from_xml_string(xml)
    assert model.npair == 1 and model.nq == 14 and model.opt.cone == mujoco.mjtCone.mjCONE_ELLIPTIC
    np.testing.assert_allclose(model.pair_solref[0], [-1e4 / M_R, 0.0])


@pytest.mark.parametrize("offset", [0.0, 0.25])
def test_a_ball_on_a_ball_matches_mujoco(offset):
    """A spinning ball target meets the bus's ball, centrally or 0.25 of the way off the line of
    centres (frictionless: the normal passes through both centres, so the effective mass is the
    reduced mass at every instant). Onset: both within one step after the closed form. Twists
    after: the change of the normal velocity is (1 + e) times the approach's, MuJoCo's with ζ
    scaled by √s; plus the impulse of the unlocated onset jump, at most d δ̇₀ dt."""
    bus, rock = balls()
    k, zeta, v0, dt = 1e4, 0.2, 0.5, 1e-5
    d = 2 * zeta * math.sqrt(k * M_R)
    gap = 0.0500037  # the onset inside a step: t = gap / v0 = 0.1000074 s
    y = offset * (R_BUS + R_T)
    s0 = np.array([math.sqrt((R_BUS + R_T) ** 2 - y ** 2) + gap, y, 0.0, 0, 0, 0, 1, -v0, 0.0, 0.0, 0.0, 0.0, 2.0])
    contact = ContactModel(stiffness=k, damping=d, pairs=[Pair("base", "target")])
    T = 0.16
    traj = spacearm.simulate(bus, T, dt=dt, target=rock, target_state=s0, contact=contact)
    x0, u0 = bus.neutral_configuration(), bus.zero_velocity()
    x, u, s, onset, diag = run_mujoco(bus, rock, contact, M_R, x0, u0, s0, T, dt)
    # onset: the approach closes the gap at v0 · (the normal's share of it)
    n0 = np.array([s0[0], y, 0.0]) / (R_BUS + R_T)
    v_n = v0 * n0[0]
    t_on = gap * n0[0] / v_n if offset == 0 else None
    if t_on is None:  # off-centre: the distance of the centres along the straight approach
        xs = s0[0] - v0 * np.linspace(0, T, 200001)
        t_on = np.linspace(0, T, 200001)[np.argmax(np.hypot(xs, y) <= R_BUS + R_T)]
        n0 = np.array([s0[0] - v0 * t_on, y, 0.0]) / (R_BUS + R_T)
        v_n = v0 * n0[0]
    first = traj.t[np.argmax(traj.contact_count > 0)]
    assert t_on <= first <= t_on + dt + 1e-6 and t_on <= onset <= t_on + dt + 1e-6
    # the tolerance: the law scaled by s (ζ by √s), and the onset jump's impulse
    A = 1.0 / M_R
    scale = 1.0 / (1.0 + (1.0 - IMPEDANCE) * (diag / A - 1.0))
    h = 1e-6
    de_dzeta = (restitution(zeta + h) - restitution(zeta - h)) / (2 * h)
    tol = (M_R / M_T) * v_n * abs(de_dzeta) * zeta * abs(math.sqrt(scale) - 1.0) + d * v_n * dt / M_T + 1e-9
    s_sa = traj["target"][-1]
    if offset == 0:  # spacearm against its closed form (off-centre the normal turns during the contact)
        dv_closed = (1 + restitution(zeta)) * v_n * M_R / M_T
        assert abs(np.dot(s_sa[7:10] - s0[7:10], n0) - dv_closed) < 1e-6 * dv_closed
    err_v = np.abs(s[7:10] - s_sa[7:10]).max()
    err_w = np.abs(s[10:13] - s_sa[10:13]).max()
    err_bus = np.abs(u - traj.u[-1]).max() * M_BUS / M_T
    print(f"offset {offset}: onset closed form {t_on:.7f}, spacearm {first:.7f}, MuJoCo {onset:.7f}; "
          f"Â/A = {diag / A:.4f}, s − 1 = {scale - 1:.2e}; target v {err_v:.2e}, ω {err_w:.2e}, "
          f"bus (× M/m) {err_bus:.2e} m/s against {tol:.2e}")
    assert err_v <= tol and err_w <= tol and err_bus <= tol
    assert np.abs(s[10:13] - s0[10:13]).max() < 1e-9  # no turning through the centres
