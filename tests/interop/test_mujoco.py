"""spacearm against MuJoCo, an independent engine, on random trees and the presets.

Every quantity is computed by MuJoCo on the model compiled from
:func:`spacearm.interop.to_mjcf`, mapped to spacearm's conventions with the converters of
:mod:`spacearm.interop` (free joint: linear velocity in the world, angular in the base frame,
quaternion scalar first; docs/conventions.md), and compared norm-wise:
``‖spacearm − mujoco‖ / ‖mujoco‖ ≤ 1e-10`` with ``‖mujoco‖`` asserted to be non-negligible.
``H*``, ``J*`` and ``c*`` are computed with numpy from MuJoCo's own dense mass matrix
(``mj_fullM``) and site Jacobian (``mj_jacSite``, world axes) in MuJoCo's coordinates.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco")

import spacearm  # noqa: E402
from spacearm import interop  # noqa: E402
from random_models import SEEDS, assert_rel_close, random_model, random_state  # noqa: E402

CASES = [f"seed{s}" for s in SEEDS] + ["planar4", "spatial6"]


class Case:
    """A model, its MuJoCo twin, a random state and random inputs."""

    def __init__(self, name: str):
        if name.startswith("seed"):
            seed = int(name[4:])
            self.robot = random_model(seed).robot
        else:
            seed = 1000 + CASES.index(name)
            self.robot = spacearm.presets.get(name)
        # a different stream from test_pinocchio's: other states, other inputs
        rng = np.random.default_rng([11, seed])
        r = self.robot
        self.x, self.u = random_state(r, rng)
        self.f = np.concatenate([rng.normal(scale=20.0, size=3), rng.normal(scale=5.0, size=3), rng.normal(scale=5.0, size=r.n_dof)])
        self.du = rng.normal(size=r.nu)
        self.point = "probe" if "probe" in r.point_names else r.end_effector
        body, offset = r._point(self.point)
        self.wrench = spacearm.ExternalWrench(body=body, force=rng.normal(scale=10.0, size=3),
                                              torque=rng.normal(scale=3.0, size=3), offset=offset)
        self.model = interop.to_mujoco(r)
        self.data = mujoco.MjData(self.model)
        self.qpos, self.qvel = interop.to_mujoco_state(r, self.x, self.u)
        self.order = interop.engine_dof_order(r)

    # MuJoCo-side helpers -----------------------------------------------------------------
    def forward(self, qfrc_applied=None, xfrc_applied=None):
        """``mj_forward`` at the case's state with the given applied forces (others zero)."""
        d = self.data
        d.qpos[:], d.qvel[:] = self.qpos, self.qvel
        d.qfrc_applied[:] = 0.0 if qfrc_applied is None else qfrc_applied
        d.xfrc_applied[:] = 0.0 if xfrc_applied is None else xfrc_applied
        d.ctrl[:] = 0.0
        mujoco.mj_forward(self.model, d)
        return d

    def mass_matrix_mj(self) -> np.ndarray:
        self.forward()
        m = np.zeros((self.model.nv, self.model.nv))
        mujoco.mj_fullM(self.model, self.data, m)
        return m

    def wrench_site(self):
        """Body id, application point (MuJoCo's own kinematics) and world force/couple."""
        d = self.forward()
        site = self.model.site(self.point)
        point = d.site_xpos[site.id].copy()
        return int(site.bodyid[0]), point, np.asarray(self.wrench.force, float), np.asarray(self.wrench.torque, float)

    def xfrc(self) -> np.ndarray:
        """The case's wrench as ``xfrc_applied``: world force and torque about the body's CM
        (``xipos``)."""
        body, point, force, couple = self.wrench_site()
        out = np.zeros((self.model.nbody, 6))
        out[body, :3] = force
        out[body, 3:] = couple + np.cross(point - self.data.xipos[body], force)
        return out

    def to_sa_joint_cols(self, mat: np.ndarray) -> np.ndarray:
        out = np.empty_like(mat)
        out[..., self.order] = mat
        return out


@functools.lru_cache(maxsize=None)
def case(name: str) -> Case:
    return Case(name)


# ---- the exported model --------------------------------------------------------------------
def test_mjcf_model_has_no_extra_physics():
    c = case("seed7")
    m = c.model
    assert m.nq == c.robot.nx and m.nv == c.robot.nu
    assert np.all(m.opt.gravity == 0.0)
    assert m.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_CONTACT
    # Geoms carry no mass and make no contacts; the motors act only through ctrl (zero here).
    assert m.neq == 0 and m.nu == sum(1 for link in c.robot.description.links if link.dof is not None and link.actuated)
    assert not np.any(m.geom_contype) and not np.any(m.geom_conaffinity)
    assert np.all(m.dof_damping == 0) and np.all(m.dof_armature == 0) and np.all(m.dof_frictionloss == 0)
    assert np.all(m.jnt_stiffness == 0) and not np.any(m.jnt_limited)
    assert m.opt.density == 0 and m.opt.viscosity == 0
    # body i of the MJCF is spacearm body i in depth-first order, its frame at the CM
    assert np.allclose(m.body_ipos[1:], 0.0)
    assert [m.body(i).name for i in range(1, m.nbody)][0] == c.robot.body_names[0]
    assert np.isclose(m.body_subtreemass[1], c.robot.total_mass, rtol=1e-14)
    # joints are numbered depth-first; their names say which spacearm dof each one is
    joint_names = [link["joint"] for link in c.robot.describe()["links"] if link["type"] != "fixed"]
    assert [m.joint(j).name for j in range(1, m.njnt)] == [joint_names[k] for k in c.order]


# ---- kinematics ------------------------------------------------------------------------------
@pytest.mark.parametrize("name", CASES)
def test_frames_and_points(name):
    c = case(name)
    r = c.robot
    d = c.forward()
    kin = r.forward_kinematics(c.x)
    r0 = c.x[:3]
    for b, body in enumerate(r.body_names):
        i = c.model.body(body).id
        assert_rel_close(kin.body_to_world[b], d.xmat[i].reshape(3, 3), "mj body rotation", min_norm=1.0)
        if b > 0:
            assert_rel_close(kin.com_in_world[b] - r0, d.xipos[i] - r0, "mj body position", min_norm=1e-6)
    for p in r.point_names:
        ref = d.site_xpos[c.model.site(p).id]
        assert_rel_close(r.point_position(c.x, p) - r0, ref - r0, "mj point position", min_norm=1e-6)


# ---- inertia and bias --------------------------------------------------------------------------
@pytest.mark.parametrize("method", ["crba", "paper"])
@pytest.mark.parametrize("name", CASES)
def test_mass_matrix(name, method):
    c = case(name)
    ref = interop.mass_matrix_from_mujoco(c.robot, c.x, c.mass_matrix_mj())
    assert_rel_close(c.robot.mass_matrix(c.x, method=method), ref, f"mj H ({method})")


@pytest.mark.parametrize("name", CASES)
def test_bias_forces(name):
    c = case(name)
    r = c.robot
    c_sa = r.bias_forces(c.x, c.u)
    d = c.forward()
    assert_rel_close(c_sa, interop.bias_from_mujoco(r, c.x, d.qfrc_bias), "mj c")
    # second route: inverse dynamics at qacc = 0 (which is u̇ = 0 for MuJoCo's free joint)
    d.qacc[:] = interop.to_mujoco_acceleration(r, c.x, np.zeros(r.nu))
    mujoco.mj_inverse(c.model, d)
    assert_rel_close(c_sa, interop.from_mujoco_force(r, c.x, d.qfrc_inverse), "mj c")


# ---- dynamics ------------------------------------------------------------------------------------
@pytest.mark.parametrize("method", ["aba", "mass_matrix", "reduced"])
@pytest.mark.parametrize("name", CASES)
def test_forward_dynamics(name, method):
    c = case(name)
    r = c.robot
    d = c.forward(qfrc_applied=interop.to_mujoco_force(r, c.x, c.f))
    ref = interop.acceleration_from_mujoco(r, c.x, d.qacc)
    assert_rel_close(r.forward_dynamics(c.x, c.u, c.f, method=method), ref, f"mj forward dynamics ({method})")


@pytest.mark.parametrize("method", ["aba", "mass_matrix"])
@pytest.mark.parametrize("name", CASES)
def test_forward_dynamics_with_external_wrench(name, method):
    c = case(name)
    r = c.robot
    d = c.forward(qfrc_applied=interop.to_mujoco_force(r, c.x, c.f), xfrc_applied=c.xfrc())
    ref = interop.acceleration_from_mujoco(r, c.x, d.qacc)
    got = r.forward_dynamics(c.x, c.u, c.f, wrenches=[c.wrench], method=method)
    assert_rel_close(got, ref, f"mj forward dynamics + wrench ({method})")


@pytest.mark.parametrize("name", CASES)
def test_inverse_dynamics(name):
    c = case(name)
    r = c.robot
    d = c.forward()
    d.qacc[:] = interop.to_mujoco_acceleration(r, c.x, c.du)
    mujoco.mj_inverse(c.model, d)
    ref = interop.from_mujoco_force(r, c.x, d.qfrc_inverse)
    assert_rel_close(r.inverse_dynamics(c.x, c.u, c.du), ref, "mj inverse dynamics")
    # the wrench's generalized force J_Xᵀ w by mj_applyFT at MuJoCo's own site position
    body, point, force, couple = c.wrench_site()
    qfrc = np.zeros(c.model.nv)
    mujoco.mj_applyFT(c.model, c.data, force, couple, point, body, qfrc)
    jw = interop.from_mujoco_force(r, c.x, qfrc)
    assert_rel_close(r.inverse_dynamics(c.x, c.u, c.du) - r.inverse_dynamics(c.x, c.u, c.du, wrenches=[c.wrench]),
                     jw, "mj wrench generalized force")
    assert_rel_close(r.inverse_dynamics(c.x, c.u, c.du, wrenches=[c.wrench]), ref - jw, "mj inverse dynamics + wrench")


# ---- GJM quantities, from MuJoCo's outputs in MuJoCo's own coordinates -----------------------
def _h_star_mj(m: np.ndarray) -> np.ndarray:
    m_bb, m_bm, m_mm = m[:6, :6], m[:6, 6:], m[6:, 6:]
    return m_mm - m_bm.T @ np.linalg.solve(m_bb, m_bm)


@pytest.mark.parametrize("name", CASES)
def test_generalized_inertia(name):
    c = case(name)
    h_star = _h_star_mj(c.mass_matrix_mj())
    ref = np.empty_like(h_star)
    ref[np.ix_(c.order, c.order)] = h_star
    assert_rel_close(c.robot.generalized_inertia(c.x), ref, "mj H*")


@pytest.mark.parametrize("name", CASES)
def test_generalized_jacobian(name):
    c = case(name)
    r = c.robot
    m = c.mass_matrix_mj()  # also runs mj_forward at the case's state
    m_bb, m_bm = m[:6, :6], m[:6, 6:]
    for point in sorted(set(r.point_names)):
        jacp = np.zeros((3, c.model.nv))
        jacr = np.zeros((3, c.model.nv))
        mujoco.mj_jacSite(c.model, c.data, jacp, jacr, c.model.site(point).id)
        jac = np.vstack([jacp, jacr])  # [v_X; ω] in world axes per unit of qvel
        j_star = jac[:, 6:] - jac[:, :6] @ np.linalg.solve(m_bb, m_bm)
        floor = 1e-3 if point == r.end_effector else 1e-7
        assert_rel_close(r.generalized_jacobian(c.x, point), c.to_sa_joint_cols(j_star), "mj J*", min_norm=floor)


@pytest.mark.parametrize("name", CASES)
def test_generalized_bias(name):
    c = case(name)
    r = c.robot
    h_star = _h_star_mj(c.mass_matrix_mj())
    d = c.forward()  # free floating, τ = 0: H* q̈ + c* = 0
    ref = np.empty(r.n_dof)
    ref[c.order] = -h_star @ d.qacc[6:]
    assert_rel_close(r.generalized_bias(c.x, c.u), ref, "mj c*")


# ---- momentum and energy ---------------------------------------------------------------------
@pytest.mark.parametrize("name", CASES)
def test_momentum(name):
    c = case(name)
    r = c.robot
    d = c.forward()
    mujoco.mj_subtreeVel(c.model, d)
    # subtree of the base body (id 1) = the whole system
    com = d.subtree_com[1].copy()
    p = c.model.body_subtreemass[1] * d.subtree_linvel[1]
    l_com = d.subtree_angmom[1].copy()  # about the subtree CM, world axes
    mom = r.momentum(c.x, c.u)
    assert_rel_close(r.center_of_mass(c.x) - c.x[:3], com - c.x[:3], "mj system CM", min_norm=1e-6)
    assert_rel_close(mom.P, p, "mj P")
    assert_rel_close(mom.L_com, l_com, "mj L_com")
    assert_rel_close(mom.L_origin, l_com + np.cross(com, p), "mj L_origin")
    assert_rel_close(mom.L_base, l_com + np.cross(com - c.x[:3], p), "mj L_base")


@pytest.mark.parametrize("name", CASES)
def test_kinetic_energy(name):
    c = case(name)
    d = c.forward()
    mujoco.mj_energyVel(c.model, d)
    assert_rel_close(c.robot.kinetic_energy(c.x, c.u), d.energy[1], "mj kinetic energy")


# ---- converters ----------------------------------------------------------------------------------
@pytest.mark.parametrize("name", ["seed0", "seed5", "seed11", "planar4", "spatial6"])
def test_converters_round_trip(name):
    c = case(name)
    r = c.robot
    rng = np.random.default_rng(5)
    x2, u2 = interop.from_mujoco_state(r, *interop.to_mujoco_state(r, c.x, c.u))
    np.testing.assert_allclose(x2, c.x, rtol=0, atol=1e-15)
    np.testing.assert_allclose(u2, c.u, rtol=0, atol=1e-14)
    f2 = interop.from_mujoco_force(r, c.x, interop.to_mujoco_force(r, c.x, c.f))
    np.testing.assert_allclose(f2, c.f, rtol=0, atol=1e-13)
    du2 = interop.acceleration_from_mujoco(r, c.x, interop.to_mujoco_acceleration(r, c.x, c.du))
    np.testing.assert_allclose(du2, c.du, rtol=0, atol=1e-14)
    # quaternion scalar first on MuJoCo's side
    qpos, _ = interop.to_mujoco_state(r, c.x, c.u)
    np.testing.assert_array_equal(qpos[3:7], np.r_[c.x[6], c.x[3:6]])
    # from MuJoCo's side: a random MuJoCo state survives the round trip
    quat = rng.normal(size=4)
    qpos = np.concatenate([rng.normal(size=3), quat / np.linalg.norm(quat), rng.normal(size=r.n_dof)])
    qvel = rng.normal(size=r.nu)
    qpos2, qvel2 = interop.to_mujoco_state(r, *interop.from_mujoco_state(r, qpos, qvel))
    np.testing.assert_allclose(qpos2, qpos, rtol=0, atol=1e-15)
    np.testing.assert_allclose(qvel2, qvel, rtol=0, atol=1e-14)
    # the mappings preserve power fᵀu and kinetic energy
    assert np.isclose(interop.to_mujoco_force(r, c.x, c.f) @ c.qvel, c.f @ c.u, rtol=1e-13, atol=0)
    m = c.mass_matrix_mj()
    h = interop.mass_matrix_from_mujoco(r, c.x, m)
    assert np.isclose(c.u @ h @ c.u, c.qvel @ m @ c.qvel, rtol=1e-13, atol=0)


def test_mujoco_simulation_conserves_what_spacearm_predicts():
    """A short free-floating MuJoCo rollout (RK4) keeps spacearm's momentum: the exported model
    adds no damping or other dissipation."""
    c = case("spatial6")
    r = c.robot
    d = mujoco.MjData(c.model)
    d.qpos[:], d.qvel[:] = c.qpos, c.qvel
    c.model.opt.timestep = 1e-3
    p0 = r.momentum(c.x, c.u)
    for _ in range(200):
        mujoco.mj_step(c.model, d)
    x1, u1 = interop.from_mujoco_state(r, d.qpos, d.qvel)
    x1[3:7] /= np.linalg.norm(x1[3:7])
    p1 = r.momentum(x1, u1)
    assert_rel_close(p1.P, p0.P, "mj rollout P", rtol=1e-9)
    assert_rel_close(p1.L_origin, p0.L_origin, "mj rollout L_origin", rtol=1e-7)
    assert_rel_close(np.array([r.kinetic_energy(x1, u1)]), np.array([r.kinetic_energy(c.x, c.u)]), "mj rollout energy", rtol=1e-7)
