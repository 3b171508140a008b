"""spacearm against Pinocchio, an independent engine, on random trees and the presets.

Every quantity is computed by Pinocchio on the model exported by
:func:`spacearm.interop.to_pinocchio`, mapped to spacearm's conventions with the converters of
:mod:`spacearm.interop` (formulas in its docstring, docs/conventions.md), and compared norm-wise:
``‖spacearm − pinocchio‖ / ‖pinocchio‖ ≤ 1e-10`` with ``‖pinocchio‖`` asserted to be
non-negligible. ``H*``, ``J*`` and ``c*`` are computed with numpy from Pinocchio's own mass
matrix and frame Jacobian in Pinocchio's coordinates (they do not depend on the base-velocity
convention), so they check spacearm's GJM without going through the converters.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest

pin = pytest.importorskip("pinocchio")

import spacearm  # noqa: E402
from spacearm import interop  # noqa: E402
from random_models import SEEDS, assert_rel_close, random_model, random_state  # noqa: E402

CASES = [f"seed{s}" for s in SEEDS] + ["planar4", "spatial6"]
RTOL = 1e-10


class Case:
    """A model, its Pinocchio twin, a random state and random inputs."""

    def __init__(self, name: str):
        if name.startswith("seed"):
            seed = int(name[4:])
            self.robot = random_model(seed).robot
        else:
            seed = 1000 + CASES.index(name)
            self.robot = spacearm.presets.get(name)
        rng = np.random.default_rng([7, seed])
        r = self.robot
        self.x, self.u = random_state(r, rng)
        # generalized force with a non-zero base wrench (the flying regime) and joint torques
        self.f = np.concatenate([rng.normal(scale=20.0, size=3), rng.normal(scale=5.0, size=3), rng.normal(scale=5.0, size=r.n_dof)])
        self.du = rng.normal(size=r.nu)
        # an external wrench (world force + couple) at a named point
        self.point = "probe" if "probe" in r.point_names else r.end_effector
        body, offset = r._point(self.point)
        self.wrench = spacearm.ExternalWrench(body=body, force=rng.normal(scale=10.0, size=3),
                                              torque=rng.normal(scale=3.0, size=3), offset=offset)
        self.model = interop.to_pinocchio(r)
        self.data = self.model.createData()
        self.q, self.v = interop.to_pinocchio_state(r, self.x, self.u)
        self.order = interop.engine_dof_order(r)
        self.R0 = interop.pinocchio_transform(r, self.x)[:3, :3]

    # Pinocchio-side helpers ---------------------------------------------------------------
    def mass_matrix_pin(self) -> np.ndarray:
        m = pin.crba(self.model, self.data, self.q)
        return np.triu(m) + np.triu(m, 1).T  # pin's crba fills the upper triangle

    def fext(self):
        """The case's wrench as Pinocchio per-joint forces: in the support joint's LOCAL frame,
        about the joint origin, using Pinocchio's own kinematics for the application point."""
        model, data = self.model, self.data
        pin.forwardKinematics(model, data, self.q)
        pin.updateFramePlacements(model, data)
        fid = model.getFrameId(self.point)
        joint = model.frames[fid].parentJoint
        point = data.oMf[fid].translation
        oMi = data.oMi[joint]
        force = np.asarray(self.wrench.force, dtype=float)
        moment = np.asarray(self.wrench.torque, dtype=float) + np.cross(point - oMi.translation, force)
        fext = [pin.Force.Zero() for _ in range(model.njoints)]
        fext[joint] = pin.Force(oMi.rotation.T @ force, oMi.rotation.T @ moment)
        return fext

    def to_sa_joint_cols(self, mat_pin_joint_cols: np.ndarray) -> np.ndarray:
        """Reorder the joint columns of a matrix from Pinocchio's order to spacearm's."""
        out = np.empty_like(mat_pin_joint_cols)
        out[..., self.order] = mat_pin_joint_cols
        return out


@functools.lru_cache(maxsize=None)
def case(name: str) -> Case:
    return Case(name)


# ---- the exported model ----------------------------------------------------------------------
def test_exported_model_structure():
    c = case("seed3")
    r, model = c.robot, c.model
    assert model.nq == r.nx and model.nv == r.nu
    assert np.all(model.gravity.vector == 0.0)
    for name in r.body_names + r.point_names:
        assert model.existFrame(name), name
    # joints are numbered depth-first; their names say which spacearm dof each one is
    joint_names = [link["joint"] for link in r.describe()["links"] if link["type"] != "fixed"]
    assert [model.names[j] for j in range(2, model.njoints)] == [joint_names[k] for k in c.order]


# ---- kinematics ------------------------------------------------------------------------------
@pytest.mark.parametrize("name", CASES)
def test_frames_and_points(name):
    c = case(name)
    r = c.robot
    pin.forwardKinematics(c.model, c.data, c.q)
    pin.updateFramePlacements(c.model, c.data)
    kin = r.forward_kinematics(c.x)
    r0 = c.x[:3]
    for b, body in enumerate(r.body_names):
        pose = c.data.oMf[c.model.getFrameId(body)]
        assert_rel_close(pose.rotation, kin.body_to_world[b], "pin body rotation", min_norm=1.0)
        if b > 0:  # positions relative to the base CM: the base may be kilometres away
            assert_rel_close(kin.com_in_world[b] - r0, pose.translation - r0, "pin body position", min_norm=1e-6)
    for p in r.point_names:
        ref = c.data.oMf[c.model.getFrameId(p)].translation
        assert_rel_close(r.point_position(c.x, p) - r0, ref - r0, "pin point position", min_norm=1e-6)


# ---- inertia and bias --------------------------------------------------------------------------
@pytest.mark.parametrize("method", ["crba", "paper"])
@pytest.mark.parametrize("name", CASES)
def test_mass_matrix(name, method):
    c = case(name)
    ref = interop.mass_matrix_from_pinocchio(c.robot, c.x, pin.crba(c.model, c.data, c.q))
    assert_rel_close(c.robot.mass_matrix(c.x, method=method), ref, f"pin H ({method})")


@pytest.mark.parametrize("name", CASES)
def test_bias_forces(name):
    c = case(name)
    r = c.robot
    c_sa = r.bias_forces(c.x, c.u)
    # route 1: nle with the -H[:, :3](ω0 × v0) correction
    nle = pin.nonLinearEffects(c.model, c.data, c.q, c.v)
    ref = interop.bias_from_pinocchio(r, c.x, c.u, nle, c.mass_matrix_pin())
    assert_rel_close(c_sa, ref, "pin c")
    # route 2: RNEA at the Pinocchio acceleration that is u̇ = 0 in spacearm's coordinates
    a0 = interop.to_pinocchio_acceleration(r, c.x, c.u, np.zeros(r.nu))
    ref2 = interop.from_pinocchio_force(r, c.x, pin.rnea(c.model, c.data, c.q, c.v, a0))
    assert_rel_close(c_sa, ref2, "pin c")


# ---- dynamics ------------------------------------------------------------------------------------
@pytest.mark.parametrize("method", ["aba", "mass_matrix", "reduced"])
@pytest.mark.parametrize("name", CASES)
def test_forward_dynamics(name, method):
    c = case(name)
    r = c.robot
    tau_pin = interop.to_pinocchio_force(r, c.x, c.f)
    a = pin.aba(c.model, c.data, c.q, c.v, tau_pin)
    ref = interop.acceleration_from_pinocchio(r, c.x, c.u, a)
    assert_rel_close(r.forward_dynamics(c.x, c.u, c.f, method=method), ref, f"pin forward dynamics ({method})")


@pytest.mark.parametrize("method", ["aba", "mass_matrix"])
@pytest.mark.parametrize("name", CASES)
def test_forward_dynamics_with_external_wrench(name, method):
    c = case(name)
    r = c.robot
    tau_pin = interop.to_pinocchio_force(r, c.x, c.f)
    a = pin.aba(c.model, c.data, c.q, c.v, tau_pin, c.fext())
    ref = interop.acceleration_from_pinocchio(r, c.x, c.u, a)
    got = r.forward_dynamics(c.x, c.u, c.f, wrenches=[c.wrench], method=method)
    assert_rel_close(got, ref, f"pin forward dynamics + wrench ({method})")


@pytest.mark.parametrize("name", CASES)
def test_inverse_dynamics(name):
    c = case(name)
    r = c.robot
    a = interop.to_pinocchio_acceleration(r, c.x, c.u, c.du)
    ref = interop.from_pinocchio_force(r, c.x, pin.rnea(c.model, c.data, c.q, c.v, a))
    assert_rel_close(r.inverse_dynamics(c.x, c.u, c.du), ref, "pin inverse dynamics")
    ref_w = interop.from_pinocchio_force(r, c.x, pin.rnea(c.model, c.data, c.q, c.v, a, c.fext()))
    assert_rel_close(r.inverse_dynamics(c.x, c.u, c.du, wrenches=[c.wrench]), ref_w, "pin inverse dynamics + wrench")
    # the wrench's generalized force J_Xᵀ w on its own (f(no wrench) − f(wrench))
    assert_rel_close(r.inverse_dynamics(c.x, c.u, c.du) - r.inverse_dynamics(c.x, c.u, c.du, wrenches=[c.wrench]),
                     ref - ref_w, "pin wrench generalized force")


# ---- GJM quantities, from Pinocchio's outputs in Pinocchio's own coordinates ------------------
def _pin_reduction(c: Case):
    m = c.mass_matrix_pin()
    m_bb, m_bm, m_mm = m[:6, :6], m[:6, 6:], m[6:, 6:]
    return m, m_bb, m_bm, m_mm


@pytest.mark.parametrize("name", CASES)
def test_generalized_inertia(name):
    c = case(name)
    _, m_bb, m_bm, m_mm = _pin_reduction(c)
    h_star_pin = m_mm - m_bm.T @ np.linalg.solve(m_bb, m_bm)  # eq. 45 in Pinocchio's coordinates
    ref = np.empty_like(h_star_pin)
    ref[np.ix_(c.order, c.order)] = h_star_pin
    assert_rel_close(c.robot.generalized_inertia(c.x), ref, "pin H*")


@pytest.mark.parametrize("name", CASES)
def test_generalized_jacobian(name):
    c = case(name)
    r = c.robot
    _, m_bb, m_bm, _ = _pin_reduction(c)
    pin.computeJointJacobians(c.model, c.data, c.q)
    pin.updateFramePlacements(c.model, c.data)
    for point in sorted(set(r.point_names)):
        # [v_X; ω] in world axes per unit of Pinocchio velocity, then zero-momentum base motion
        jac = pin.getFrameJacobian(c.model, c.data, c.model.getFrameId(point), pin.LOCAL_WORLD_ALIGNED)
        j_star_pin = jac[:, 6:] - jac[:, :6] @ np.linalg.solve(m_bb, m_bm)
        # a point on a heavy base barely moves: its J* can be small, but never zero
        floor = 1e-3 if point == r.end_effector else 1e-7
        assert_rel_close(r.generalized_jacobian(c.x, point), c.to_sa_joint_cols(j_star_pin), "pin J*", min_norm=floor)


@pytest.mark.parametrize("name", CASES)
def test_generalized_bias(name):
    c = case(name)
    r = c.robot
    # free floating, τ = 0: H* q̈ + c* = 0, and q̈ is the physical joint acceleration
    _, m_bb, m_bm, m_mm = _pin_reduction(c)
    h_star_pin = m_mm - m_bm.T @ np.linalg.solve(m_bb, m_bm)
    qdd_pin = pin.aba(c.model, c.data, c.q, c.v, np.zeros(r.nu))[6:]
    ref = np.empty(r.n_dof)
    ref[c.order] = -h_star_pin @ qdd_pin
    assert_rel_close(r.generalized_bias(c.x, c.u), ref, "pin c*")


# ---- momentum and energy ---------------------------------------------------------------------
@pytest.mark.parametrize("name", CASES)
def test_momentum(name):
    c = case(name)
    r = c.robot
    hg = pin.computeCentroidalMomentum(c.model, c.data, c.q, c.v)  # about the system CM, world axes
    com = pin.centerOfMass(c.model, c.data, c.q)
    p, l_com = hg.linear, hg.angular
    mom = r.momentum(c.x, c.u)
    assert_rel_close(r.center_of_mass(c.x) - c.x[:3], com - c.x[:3], "pin system CM", min_norm=1e-6)
    assert_rel_close(mom.P, p, "pin P")
    assert_rel_close(mom.L_com, l_com, "pin L_com")
    assert_rel_close(mom.L_origin, l_com + np.cross(com, p), "pin L_origin")
    assert_rel_close(mom.L_base, l_com + np.cross(com - c.x[:3], p), "pin L_base")


@pytest.mark.parametrize("name", CASES)
def test_kinetic_energy(name):
    c = case(name)
    ref = pin.computeKineticEnergy(c.model, c.data, c.q, c.v)
    assert_rel_close(c.robot.kinetic_energy(c.x, c.u), ref, "pin kinetic energy")


# ---- converters ----------------------------------------------------------------------------------
@pytest.mark.parametrize("name", ["seed0", "seed5", "seed11", "planar4", "spatial6"])
def test_converters_round_trip(name):
    c = case(name)
    r = c.robot
    rng = np.random.default_rng(3)
    x2, u2 = interop.from_pinocchio_state(r, *interop.to_pinocchio_state(r, c.x, c.u))
    np.testing.assert_allclose(x2, c.x, rtol=0, atol=1e-15)
    np.testing.assert_allclose(u2, c.u, rtol=0, atol=1e-14)
    f2 = interop.from_pinocchio_force(r, c.x, interop.to_pinocchio_force(r, c.x, c.f))
    np.testing.assert_allclose(f2, c.f, rtol=0, atol=1e-13)
    du2 = interop.acceleration_from_pinocchio(r, c.x, c.u, interop.to_pinocchio_acceleration(r, c.x, c.u, c.du))
    np.testing.assert_allclose(du2, c.du, rtol=0, atol=1e-14)
    # and from Pinocchio's side: a random Pinocchio state survives the round trip
    q = pin.randomConfiguration(c.model, -np.ones(c.model.nq), np.ones(c.model.nq))
    v = rng.normal(size=r.nu)
    q2, v2 = interop.to_pinocchio_state(r, *interop.from_pinocchio_state(r, q, v))
    np.testing.assert_allclose(q2, q, rtol=0, atol=1e-15)
    np.testing.assert_allclose(v2, v, rtol=0, atol=1e-14)
    # the mappings preserve power fᵀu and kinetic energy
    tau_pin = interop.to_pinocchio_force(r, c.x, c.f)
    assert np.isclose(tau_pin @ c.v, c.f @ c.u, rtol=1e-13, atol=0)
    h = interop.mass_matrix_from_pinocchio(r, c.x, c.mass_matrix_pin())
    assert np.isclose(c.u @ h @ c.u, c.v @ c.mass_matrix_pin() @ c.v, rtol=1e-13, atol=0)


def test_converters_check_shapes():
    r = spacearm.presets.planar4()
    x = r.neutral_configuration()
    with pytest.raises(ValueError, match="length"):
        interop.to_pinocchio_state(r, x[:-1], np.zeros(r.nu))
    with pytest.raises(ValueError, match="10×10"):
        interop.mass_matrix_from_pinocchio(r, x, np.zeros((9, 9)))
