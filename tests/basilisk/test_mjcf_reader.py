"""Basilisk's models into spacearm (spacearm.basilisk.from_mjcf): an MJCF in the style of
Basilisk's MuJoCo scenarios (mass from geom densities, xyaxes / axisangle frames, ranges in
degrees, a reaction wheel, a deployable panel chain, a slide joint) read into a Robot, whose H* and
J* are checked against MuJoCo's own mass matrix and site Jacobian of the same file; and the round
trip spacearm → MJCF → spacearm."""

from __future__ import annotations

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco")

import spacearm  # noqa: E402
from spacearm import basilisk as sb  # noqa: E402
from spacearm.errors import ModelError  # noqa: E402
from random_models import SEEDS, random_model  # noqa: E402

SAT = """
<mujoco model="sat_with_arm_and_panels">
  <compiler angle="degree"/>
  <option gravity="0 0 0"><flag contact="disable"/></option>
  <worldbody>
    <body name="hub">
      <freejoint/>
      <geom name="hub_box" type="box" size="0.8 0.6 0.5" density="600"/>
      <geom name="hub_tank" type="sphere" pos="0.2 0.1 -0.1" size="0.3" density="900"/>
      <body name="wheel" pos="0.1 -0.2 0.3" xyaxes="0 1 0 0 0 1">
        <joint name="wheel_spin" type="hinge" axis="0 0 1"/>
        <geom type="cylinder" size="0.15 0.04" density="7800"/>
      </body>
      <body name="panel_a" pos="0.8 0 -0.5" xyaxes="0 -1 0 0 0 -1">
        <joint name="panel_a_deploy" axis="1 0 0" range="0 90"/>
        <geom type="box" pos="0 0 0.9" size="0.7 0.03 0.8" density="400"/>
        <body name="panel_b" pos="0.7 0 1.7" axisangle="0 1 0 90">
          <joint name="panel_b_deploy" axis="1 0 0" range="0 180"/>
          <geom type="box" pos="0 0 0.8" size="0.6 0.03 0.7" density="400"/>
        </body>
      </body>
      <body name="boom" pos="-0.8 0 0.2" axisangle="0 0 1 30">
        <joint name="boom_extend" type="slide" axis="-1 0 0"/>
        <geom type="capsule" fromto="0 0 0 -1.2 0 0" size="0.05" density="2700"/>
        <body name="arm" pos="-1.2 0 0">
          <joint name="arm_yaw" axis="0 0 1"/>
          <geom type="capsule" fromto="0 0 0 -0.6 0.2 0" size="0.04" density="2700"/>
          <site name="tip" pos="-0.6 0.2 0"/>
        </body>
      </body>
      <body name="thruster_arm" pos="0 0.6 0.5" xyaxes="1 0 0 0 0 1">
        <joint name="arm_pitch" axis="1 0 0" pos="0 0 -0.1"/>
        <joint name="arm_roll" axis="0 1 0" pos="0 0.05 0"/>
        <geom type="box" pos="0 0 0.4" size="0.05 0.05 0.4" density="2000"/>
        <site name="nozzle" pos="0 0 0.8"/>
      </body>
    </body>
  </worldbody>
  <actuator>
    <motor name="wheel_spin" joint="wheel_spin"/>
    <motor name="arm_yaw" joint="arm_yaw"/>
    <motor name="boom_extend" joint="boom_extend"/>
    <motor name="arm_pitch" joint="arm_pitch"/>
    <motor name="arm_roll" joint="arm_roll"/>
  </actuator>
</mujoco>
"""


def _beam_robot():
    b = spacearm.Robot.builder("beam_sat", 300.0, [40.0, 50.0, 60.0])
    b.add_link("mast", joint="revolute", axis=[0, 0, 1], origin=[0.6, 0, 0], com=[0.3, 0, 0], mass=8.0, inertia=[0.2, 0.3, 0.3])
    b.add_beam("boom", parent="mast", root_position=[0.3, 0, 0], axis=[1, 0, 0], length=2.0, segments=2, EI=400.0, rho_A=3.0)
    return b.build()


def _mujoco_h_star_j_star(m, qpos, site):
    """H* and J* of MuJoCo's own mass matrix and site Jacobian at qpos: the Schur complement of
    the base block (invariant to the base's velocity coordinates: free-joint origin and axes)."""
    d = mujoco.MjData(m)
    d.qpos[:] = qpos
    mujoco.mj_forward(m, d)
    full = np.zeros((m.nv, m.nv))
    mujoco.mj_fullM(m, d, full)  # MuJoCo 4: (model, data, dense)
    h0, h0m, hm = full[:6, :6], full[:6, 6:], full[6:, 6:]
    h_star = hm - h0m.T @ np.linalg.solve(h0, h0m)
    if site is None:
        return h_star, None
    jp, jr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
    mujoco.mj_jacSite(m, d, jp, jr, mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, site))
    jac = np.vstack([jp, jr])
    j_star = jac[:, 6:] - jac[:, :6] @ np.linalg.solve(h0, h0m)
    return h_star, j_star


def test_basilisk_style_satellite_h_star_and_j_star_match_mujoco():
    robot = sb.from_mjcf(SAT)
    m = mujoco.MjModel.from_xml_string(SAT)
    assert robot.name == "sat_with_arm_and_panels"
    # the two-joint body: a massless link on its first joint, then the body on its second
    assert robot.n_dof == 7 and robot.body_names == ["hub", "wheel", "panel_a", "panel_b", "boom", "arm",
                                                     "thruster_arm__arm_pitch", "thruster_arm"]
    assert abs(robot.total_mass - float(np.sum(m.body_mass))) < 1e-9 * robot.total_mass
    links = {link.name: link for link in robot.description.links}
    assert links["panel_a"].actuated is False and links["arm"].actuated is True
    assert links["panel_b"].limits.upper == pytest.approx(np.pi)  # degrees read by MuJoCo
    rng = np.random.default_rng(5)
    for _ in range(3):
        q = rng.uniform(-1, 1, robot.n_dof)
        quat = rng.normal(size=4)
        quat /= np.linalg.norm(quat)
        qpos = np.concatenate([rng.uniform(-2, 2, 3), quat, q])
        x = np.concatenate([qpos[:3], quat[[1, 2, 3, 0]], q])  # base position: H*, J* do not depend on it
        for site in ("tip", "nozzle"):
            h_mj, j_mj = _mujoco_h_star_j_star(m, qpos, site)
            h_sa, j_sa = robot.generalized_inertia(x), robot.generalized_jacobian(x, site)
            assert np.max(np.abs(h_sa - h_mj)) < 1e-10 * np.max(np.abs(h_mj))
            assert np.max(np.abs(j_sa - j_mj)) < 1e-10 * np.max(np.abs(j_mj))


@pytest.mark.parametrize("seed", SEEDS[:3] + ["beam"])
def test_round_trip_spacearm_mjcf_spacearm(seed):
    """spacearm → to_mjcf → from_mjcf: the same mass matrix, H* and J* at random states, to
    1e-12 relative (MuJoCo's compiler diagonalizes each inertia: its eigen-solver's round-off).
    ``beam``: a flexible beam's massless links, merged by to_mjcf into bodies of several joints,
    come back as massless links."""
    robot = _beam_robot() if seed == "beam" else random_model(seed).robot
    if seed == "beam":
        assert any(link.mass == 0.0 for link in robot.description.links)  # merged by to_mjcf
    back = sb.from_mjcf(spacearm.interop.to_mjcf(robot, geometry=()))
    assert back.n_dof == robot.n_dof
    rng = np.random.default_rng([7, 99 if seed == "beam" else seed])
    tip = (robot.body_names[-1], [0.1, -0.2, 0.05])  # a point on the last body, by name in both
    for _ in range(3):
        x = np.asarray(robot.neutral_configuration(rng.uniform(-1, 1, robot.n_dof)), float)
        q = rng.normal(size=4)
        x[3:7] = q / np.linalg.norm(q)
        order = spacearm.interop.engine_dof_order(robot)  # from_mjcf numbers joints depth-first
        xb = np.concatenate([x[:7], x[7:][order]])
        for a, b in ((robot.mass_matrix(x)[6:, 6:][np.ix_(order, order)], back.mass_matrix(xb)[6:, 6:]),
                     (robot.generalized_inertia(x)[np.ix_(order, order)], back.generalized_inertia(xb)),
                     (robot.generalized_jacobian(x, tip)[:, order], back.generalized_jacobian(xb, tip))):
            assert np.max(np.abs(a - b)) < 1e-12 * np.max(np.abs(a))


@pytest.mark.parametrize("xml, match", [
    ("<mujoco><worldbody><body name='a'><freejoint/><geom size='1'/><body name='b'><joint type='ball'/>"
     "<geom size='0.1'/></body></body></worldbody></mujoco>", "ball joint"),
    ("<mujoco><worldbody><body name='a'><freejoint/><geom size='1'/></body><body name='c'><freejoint/>"
     "<geom size='1'/></body></worldbody></mujoco>", "root="),
    ("<mujoco><worldbody><body name='a'><geom size='1'/></body></worldbody></mujoco>", "freejoint"),
    ("<mujoco><worldbody><body name='a'><freejoint/><geom size='1'/><body name='b'><joint name='j' axis='1 0 0'/>"
     "<geom size='0.1'/><site name='s1'/></body><site name='s0'/></body></worldbody><tendon><spatial name='t'>"
     "<site site='s0'/><site site='s1'/></spatial></tendon></mujoco>", "tendons"),
    ("<mujoco><worldbody><body name='a'><freejoint/><geom size='1'/><body name='b'><joint name='j' armature='0.1'/>"
     "<geom size='0.1'/></body></body></worldbody></mujoco>", "armature"),
    ("<mujoco><worldbody><body name='a'><freejoint/><geom size='1'/><body name='b'><joint name='j'/>"
     "<geom size='0.1'/></body></body></worldbody><equality><joint joint1='j'/></equality></mujoco>", "equality"),
    ("<mujoco><worldbody><body name='a'><freejoint/></worldbody></mujoco>", "cannot compile"),
])
def test_what_cannot_be_imported_is_named(xml, match):
    with pytest.raises(ModelError, match=match):
        sb.from_mjcf(xml)
