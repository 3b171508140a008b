"""Trees beyond one arm: the dual-arm preset and reaction wheels, against Pinocchio and MuJoCo.

Both engines get the model through :mod:`spacearm.interop` (which numbers joints depth-first:
the dual arm's two branches exercise ``engine_dof_order``); the quantities are mapped back with
its converters. ``H*`` and ``J*`` of both tools are computed with numpy from Pinocchio's ``M``
and frame Jacobians. The reaction-wheel model is also checked by hand (the base's reaction
to a wheel torque).
"""

from __future__ import annotations

import numpy as np
import pytest

pin = pytest.importorskip("pinocchio")
mujoco = pytest.importorskip("mujoco")

import spacearm  # noqa: E402
from spacearm import interop  # noqa: E402
from random_models import assert_rel_close, random_state  # noqa: E402


def wheeled_dual_arm() -> spacearm.Robot:
    """The dual-arm servicer's geometry plus three skewed reaction wheels."""
    d = spacearm.presets.dual_arm().describe()
    b = spacearm.RobotBuilder("wheeled", d["base"]["mass"], d["base"]["inertia"])
    for link in d["links"]:
        b.add_link(link["name"], parent=link["parent"], joint=link["type"], axis=link["axis"], origin=link["origin"],
                   rotation=link["rotation"], com=link["com"], mass=link["mass"], inertia=link["inertia"], joint_name=link["joint"])
    for point, body, offset in d["points"]:
        b.add_point(point, body=body, offset=offset)
    b.set_end_effector("left_tool")
    b.add_reaction_wheel([1, 0, 0], 0.08, position=(-0.3, 0.0, 0.2), max_torque=0.3, max_speed=600.0, mass=5.0)
    b.add_reaction_wheel([0, 1, 0.2], 0.08, position=(-0.3, 0.2, 0.0), max_torque=0.3, max_speed=600.0, mass=5.0)
    b.add_reaction_wheel([0.1, 0, 1], 0.08, position=(-0.3, -0.2, 0.0), max_torque=0.3, max_speed=600.0, mass=2.0)
    return b.build()


MODELS = {"dual_arm": spacearm.presets.dual_arm, "wheeled": wheeled_dual_arm}


@pytest.fixture(params=sorted(MODELS), scope="module")
def setup(request):
    r = MODELS[request.param]()
    rng = np.random.default_rng([3, len(request.param)])
    x, u = random_state(r, rng)
    f = np.concatenate([rng.normal(scale=20.0, size=3), rng.normal(scale=5.0, size=3), rng.normal(scale=2.0, size=r.n_dof)])
    return request.param, r, x, u, f


def test_dual_arm_preset_structure():
    r = spacearm.presets.dual_arm()
    assert r.n_dof == 12 and r.total_mass == pytest.approx(658.0)
    assert r.point_names == ["left_tool", "right_tool"] and r.end_effector == "left_tool"
    d = r.describe()["links"]
    assert d[0]["parent"] == "base" and d[6]["parent"] == "base" and d[6]["name"] == "right_link1"
    assert "dual_arm" in spacearm.presets.NAMES and spacearm.presets.get("dual_arm").n_dof == 12


def test_reaction_wheel_is_a_symmetric_rotor_on_the_base():
    r = wheeled_dual_arm()
    wheel = r.describe()["links"][-1]
    k = np.array([0.1, 0, 1]) / np.linalg.norm([0.1, 0, 1])
    assert wheel["name"] == "wheel3" and wheel["parent"] == "base" and wheel["type"] == "revolute"
    assert np.allclose(wheel["axis"], k)
    assert np.allclose(np.array(wheel["inertia"]) @ k, 0.08 * k)  # spin axis: the rotor inertia
    assert wheel["limits"][2:] == [600.0, 0.3]  # velocity, effort


def test_reaction_wheel_torque_turns_the_base_the_other_way():
    """A massless wheel at the base CM spinning up with torque τ about x: the base (Ixx = 10)
    gets ω̇ = −τ/Ixx about x and nothing else, whatever the rotor inertia."""
    b = spacearm.RobotBuilder("rw", 100.0, [10.0, 20.0, 30.0])
    b.add_reaction_wheel([1, 0, 0], 0.05, max_torque=0.2, max_speed=500.0)
    r = b.build()
    du = r.forward_dynamics(r.neutral_configuration(), r.zero_velocity(), tau=[0.2])
    assert np.allclose(du[:6], [0, 0, 0, -0.02, 0, 0], atol=1e-15)
    assert du[6] == pytest.approx(0.2 / 0.05 + 0.02)  # rotor relative to the base


def test_reaction_wheel_input_checks():
    b = spacearm.RobotBuilder("rw", 100.0, [10.0, 20.0, 30.0])
    for kwargs in ({"axis": [0, 0, 0], "rotor_inertia": 1.0}, {"axis": [1, 0, 0], "rotor_inertia": -1.0},
                   {"axis": [1, 0, 0], "rotor_inertia": 1.0, "max_speed": 0.0}):
        with pytest.raises(ValueError):
            b.add_reaction_wheel(**kwargs)


@pytest.mark.parametrize("axis", [[8e-10] * 3, [0.0, 0.0, 0.0]])
def test_reaction_wheel_axis_follows_the_joint_axis_rule(axis):
    """A wheel's axis is its joint's: add_link's verdict (the core's rule) for the same axis."""
    def link(b):
        b.add_link("l", parent="base", axis=axis, origin=(0, 0, 0), com=(0, 0, 0), mass=1.0, inertia=[1, 1, 1])

    def wheel(b):
        b.add_reaction_wheel(axis=axis, rotor_inertia=0.1)

    caught = []
    for add in (link, wheel):
        with pytest.raises(spacearm.SpacearmError) as info:
            add(spacearm.RobotBuilder("rw", 100.0, [10.0, 20.0, 30.0]))
        caught.append(info.value)
    assert type(caught[0]) is type(caught[1]) is spacearm.ModelError
    assert "joint axis must be a non-zero vector" in str(caught[0])
    assert "link 'wheel1': joint axis must be a non-zero vector" in str(caught[1])
    # A refused wheel takes no number: the next one is wheel1.
    b = spacearm.RobotBuilder("rw", 100.0, [10.0, 20.0, 30.0])
    with pytest.raises(spacearm.ModelError):
        wheel(b)
    b.add_reaction_wheel(axis=[0, 0, 2.0], rotor_inertia=0.1)
    assert b.build().body_names == ["base", "wheel1"]


def test_against_pinocchio(setup):
    name, r, x, u, f = setup
    model = interop.to_pinocchio(r)
    data = model.createData()
    q, v = interop.to_pinocchio_state(r, x, u)
    m = pin.crba(model, data, q)
    m = np.triu(m) + np.triu(m, 1).T
    assert_rel_close(r.mass_matrix(x), interop.mass_matrix_from_pinocchio(r, x, m), f"{name} pin H")
    nle = pin.nonLinearEffects(model, data, q, v)
    assert_rel_close(r.bias_forces(x, u), interop.bias_from_pinocchio(r, x, u, nle, m), f"{name} pin c")
    a = pin.aba(model, data, q, v, interop.to_pinocchio_force(r, x, f))
    assert_rel_close(r.forward_dynamics(x, u, f), interop.acceleration_from_pinocchio(r, x, u, a), f"{name} pin FD")
    order = interop.engine_dof_order(r)
    m_bb, m_bm, m_mm = m[:6, :6], m[:6, 6:], m[6:, 6:]
    h_star = np.empty((r.n_dof, r.n_dof))
    h_star[np.ix_(order, order)] = m_mm - m_bm.T @ np.linalg.solve(m_bb, m_bm)
    assert_rel_close(r.generalized_inertia(x), h_star, f"{name} pin H*")
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    for point in ("left_tool", "right_tool"):
        jac = pin.getFrameJacobian(model, data, model.getFrameId(point), pin.LOCAL_WORLD_ALIGNED)
        j_star = np.empty((6, r.n_dof))
        j_star[:, order] = jac[:, 6:] - jac[:, :6] @ np.linalg.solve(m_bb, m_bm)
        assert_rel_close(r.generalized_jacobian(x, point), j_star, f"{name} pin J*")


def test_against_mujoco(setup):
    name, r, x, u, f = setup
    model = interop.to_mujoco(r)
    data = mujoco.MjData(model)
    data.qpos[:], data.qvel[:] = interop.to_mujoco_state(r, x, u)
    data.qfrc_applied[:] = interop.to_mujoco_force(r, x, f)
    mujoco.mj_forward(model, data)
    m = np.zeros((model.nv, model.nv))
    mujoco.mj_fullM(model, data, m)
    assert_rel_close(r.mass_matrix(x), interop.mass_matrix_from_mujoco(r, x, m), f"{name} mj H")
    assert_rel_close(r.bias_forces(x, u), interop.bias_from_mujoco(r, x, data.qfrc_bias), f"{name} mj c")
    assert_rel_close(r.forward_dynamics(x, u, f), interop.acceleration_from_mujoco(r, x, data.qacc), f"{name} mj FD")
