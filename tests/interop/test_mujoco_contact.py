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


def gripper_and_handle():
    """The servicer of docs/contact.md ("A capture on contact") with its parallel gripper on the
    bus, and the 20 kg box target with its handle (a cylinder along y)."""
    b = spacearm.RobotBuilder("servicer", 200.0, np.eye(3) * 33.0)
    b.add_gripper("hand", position=(0.5, 0, 0), rpy=(0, np.pi / 2, 0), fingers=2, finger_length=0.12,
                  finger_radius=0.01, opening=0.10)
    t = spacearm.RobotBuilder("target", 20.0, np.eye(3) * 0.53, base_name="target")
    t.add_geometry("target", "box", role="collision", size=(0.4, 0.4, 0.4), name="body")
    t.add_geometry("target", "capsule", role="collision", radius=0.02, length=0.15, origin=(-0.29, 0, 0),
                   rpy=(np.pi / 2, 0, 0), name="handle")
    return b.build(), t.build()


def inverse_mass(robot, x, body, s, p, n, target_inertia, target_mass):
    """``A = n̂ᵀ G n̂`` of a contact at ``p`` between the robot's ``body`` and the free target at
    13-state ``s``: the robot's ``n̂ᵀ J_v H⁻¹ J_vᵀ n̂`` (its point Jacobian and mass matrix) plus
    the target's ``1/m + (ρ × n̂)ᵀ I_J⁻¹ (ρ × n̂)``. Also ``H⁻¹ J_vᵀ n̂``: the robot's velocity
    change per unit impulse."""
    kin = robot.forward_kinematics(x)
    off = kin.body_to_world[body].T @ (p - kin.com_in_world[body])
    j0, jm = robot.point_jacobian(x, (body, off))
    J = np.hstack([j0, jm])[:3]
    du = np.linalg.solve(robot.mass_matrix(x), J.T @ n)
    R = quat_to_matrix(s[3:7])
    rho = np.cross(p - s[:3], n)
    return n @ J @ du + 1.0 / target_mass + rho @ np.linalg.solve(R @ target_inertia @ R.T, rho), du, J


def test_a_handle_knocking_a_finger_matches_mujoco():
    """The target's handle, drifting and tumbling, meets the outside of the open gripper's finger
    (free on its slide: no controller) and knocks it inward: a contact of the articulated
    servicer, mapped at the effective mass of the onset (``1 / n̂ᵀ G n̂``, from spacearm's point
    Jacobian and mass matrix and the target's inertia). Onset within one step of each other.
    Twists after (the target's v and ω, the finger's rate): within the impulse
    error ``ΔJ`` mapped to each (``ΔJ / m``, ``I⁻¹ (ρ × n̂) ΔJ``, ``(H⁻¹ J_vᵀ n̂)_q̇ ΔJ``), ``ΔJ`` the
    unlocated onset jump's ``d v_n dt`` plus the linear impact's impulse change
    ``|e′(ζ)| ζ |√σ − 1| m_eff v_n`` for the law's scaling σ: MuJoCo's ``s`` times the drift
    ``A(onset)/A(t)`` of the effective mass over the contact (from the recorded rows)."""
    robot, target = gripper_and_handle()
    I_t, m_t = np.eye(3) * 0.53, 20.0
    zh = 0.05 + 0.01 + 0.02 + 0.0031  # the handle 3.1 mm above finger 1's capsule
    s0 = np.array([0.87, 0, zh, 0, 0, 0, 1, 0, 0, -0.3, 0, -1.0, 0])  # down at 0.3 m/s, tumbling about y
    k, zeta0, dt, T = 2e3, 0.2, 1e-5, 0.05
    d = 2 * zeta0 * math.sqrt(k * 0.1)
    contact = ContactModel(stiffness=k, damping=d, pairs=[Pair("hand_finger1", "handle")])
    traj = spacearm.simulate(robot, T, dt=dt, target=target, target_state=s0, contact=contact)
    rows, S = traj.contact_forces, traj["target"]
    finger = robot.body_names.index("hand_finger1")
    k0, kl = int(rows[0, 0]), int(rows[-1, 0])
    assert kl < len(traj) - 100  # the contact is over before the end
    A0, du0, J0 = inverse_mass(robot, traj.x[k0], finger, S[k0], rows[0, 3:6], rows[0, 6:9], I_t, m_t)
    m_eff = 1.0 / A0
    drift = [inverse_mass(robot, traj.x[int(r[0])], finger, S[int(r[0])], r[3:6], r[6:9], I_t, m_t)[0] / A0
             for r in rows[:: max(1, len(rows) // 50)]]
    # compared just after the contact (20 steps), before the finger's sliding turns the bus further
    after = kl + 20
    x, u, s, onset, diag = run_mujoco(robot, target, contact, m_eff, robot.neutral_configuration(), robot.zero_velocity(),
                                      s0, traj.t[after], dt)
    assert abs(onset - traj.t[k0]) <= dt + 1e-9
    # the approach speed at onset: the handle's point against the finger's
    n, p, sk, xk = rows[0, 6:9], rows[0, 3:6], S[k0 - 1], traj.x[k0 - 1]
    v_n = -n @ ((sk[7:10] + np.cross(sk[10:13], p - sk[:3])) - J0 @ traj.u[k0 - 1])
    assert v_n > 0.5
    scale = 1.0 / (1.0 + (1.0 - IMPEDANCE) * (diag / A0 - 1.0))
    sigma = [scale / g for g in (min(drift), max(drift))]
    zeta = d / (2 * math.sqrt(k * m_eff))
    h = 1e-6
    de_dzeta = (restitution(zeta + h) - restitution(zeta - h)) / (2 * h)
    dJ = d * v_n * dt + abs(de_dzeta) * zeta * max(abs(math.sqrt(sg) - 1) for sg in sigma) * m_eff * v_n + 1e-12
    s_sa, u_sa = S[after], traj.u[after]
    R = quat_to_matrix(s_sa[3:7])
    lever = np.abs(np.linalg.solve(R @ I_t @ R.T, np.cross(rows[-1, 3:6] - s_sa[:3], n)))
    # the two sides of the contact: the target's twist and the knocked finger's rate (the bus's
    # twist is compared in the report only: docs/contact.md, "In MuJoCo")
    err = {"v": np.abs(s[7:10] - s_sa[7:10]), "w": np.abs(s[10:13] - s_sa[10:13]), "finger": np.abs(u[-1] - u_sa[-1])}
    # (plus 1e-10 m/s or rad/s: the rounding of the components the impact leaves at zero)
    tol = {"v": dJ / m_t + 1e-10, "w": lever * dJ + 1e-10, "finger": abs(du0[-1]) * dJ + 1e-10}
    print(f"onset spacearm {traj.t[k0]:.6f} s, MuJoCo {onset:.6f} s; m_eff {m_eff:.6f} kg, v_n {v_n:.4f} m/s, "
          f"Â/A {diag / A0:.3f}, A drift {min(drift) - 1:.1e}..{max(drift) - 1:.1e}; ΔJ {dJ:.2e} N s; finger rate "
          f"{u_sa[-1]:.6f} vs {u[-1]:.6f} m/s; errors / tolerances: "
          + ", ".join(f"{key} {err[key].max():.1e}/{tol[key][np.argmax(err[key])] if np.ndim(tol[key]) else tol[key]:.1e}"
                      for key in err) + f"; bus twist {np.abs(u[:6] - u_sa[:6]).max():.1e} of {np.abs(u_sa[:6]).max():.1e}")
    assert u_sa[-1] > 0.5  # the finger was knocked inward
    assert np.abs(s_sa[7:13] - s0[7:13]).max() > 1e-2  # and the target's twist changed
    for key in err:
        assert (err[key] <= tol[key]).all(), key
