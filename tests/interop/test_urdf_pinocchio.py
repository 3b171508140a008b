"""Real, published URDFs (the ``example-robot-data`` package) loaded by spacearm and by
Pinocchio's own URDF parser (urdfdom), compared quantity by quantity.

Pinocchio's floating base is the URDF base link FRAME ``F``; spacearm's is the base CM frame
``B`` (docs/conventions.md). With ``F``'s pose in ``B`` known (free-flying: ``F`` is ``B``
shifted by minus the base CM, which this test reads from Pinocchio's own merged inertia of
joint 1; mounted: the inverse of the mounting pose), velocities map linearly,
``v_pin = T(x) u`` with

    v_pin[0:3] = R_Fᵀ (v0 + w0 × d),  v_pin[3:6] = R_Fᵀ w0,  joints permuted by name,

``d = R0 t_BF`` (base CM to ``F`` origin, in 𝒥). Then ``H = Tᵀ M T`` (same kinetic energy),
``f = Tᵀ τ_pin`` (same power), ``c = Tᵀ (nle + M Ṫu)`` and ``du = T⁻¹ (a_pin − Ṫu)``, where
``Ṫu = [−ω_F × v_lin + R_Fᵀ (w0 × (w0 × d)); 0]``. ``H*`` and ``J*`` do not depend on the base
parametrization and are computed with numpy from Pinocchio's ``M`` and frame Jacobian.

A mounted robot on the Pinocchio side is the same URDF with the spacecraft bus's inertia added
to the root body (``appendBodyToJoint``), so it too comes from urdfdom, not from spacearm.
"""

from __future__ import annotations

import os

import numpy as np
import pytest

pin = pytest.importorskip("pinocchio")

import spacearm  # noqa: E402
from spacearm.rotations import quat_from_matrix, quat_from_rpy, quat_to_matrix  # noqa: E402
from spacearm.io.urdf import load_urdf  # noqa: E402
from random_models import assert_rel_close  # noqa: E402
from random_urdf import random_urdf  # noqa: E402
from robot_data import robots_dir  # noqa: E402

RTOL = 1e-10


# name -> (path under robots/, load options). Baxter is a branched tree (two arms, grippers).
ROBOTS = {
    "ur5": ("ur_description/urdf/ur5_robot.urdf", {}),
    "panda": ("panda_description/urdf/panda.urdf", {"mimic": "independent"}),
    "xarm7": ("xarm_description/urdf/xarm7.urdf", {}),
    "z1": ("z1_description/urdf/z1.urdf", {}),
    "kinova": ("kinova_description/robots/kinova.urdf", {}),
    "baxter": ("baxter_description/urdf/baxter.urdf", {"mimic": "independent"}),
}
# A spacecraft bus to mount arms on: 900 kg, products of inertia, the arm 0.8 m out and tilted.
BUS_MASS = 900.0
BUS_INERTIA = np.array([[320.0, 4.0, -2.0], [4.0, 280.0, 3.0], [-2.0, 3.0, 350.0]])
MOUNT_AT = (0.8, -0.1, 0.5, 0.3, -0.2, 0.4)
RANDOM_SEEDS = range(6)  # random trees (random_urdf.py): prismatic joints, rotated inertials, fixed links
CASES = [(r, m) for r in list(ROBOTS) + [f"random{s}" for s in RANDOM_SEEDS] for m in ("free", "mounted")]


def skew(a):
    return np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])


def bus() -> spacearm.Robot:
    return spacearm.RobotBuilder("bus", BUS_MASS, BUS_INERTIA, base_name="bus").build()


class Case:
    def __init__(self, robot_name: str, mode: str, tmp_dir: str):
        if robot_name.startswith("random"):
            path, opts = os.path.join(tmp_dir, f"{robot_name}.urdf"), {}
            with open(path, "w") as fh:
                fh.write(random_urdf(int(robot_name[6:])))
        else:
            rel, opts = ROBOTS[robot_name]
            path = os.path.join(robots_dir(), rel)
        if mode == "free":
            self.robot = load_urdf(path, **opts)
        else:
            self.robot = load_urdf(path, mount_on=bus(), at=MOUNT_AT, **opts)
        self.model = pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer())  # mimic joints as ordinary joints
        self.model.gravity.setZero()
        if mode == "free":
            # B in F: the CM of everything welded to the root, as Pinocchio merged it.
            self.R_FB, self.t_FB = np.eye(3), np.array(self.model.inertias[1].lever)
        else:
            r_at = quat_to_matrix(quat_from_rpy(*MOUNT_AT[3:]))
            self.R_FB, self.t_FB = r_at.T, -r_at.T @ np.array(MOUNT_AT[:3])
            bus_in_f = pin.Inertia(BUS_MASS, self.t_FB, self.R_FB @ BUS_INERTIA @ self.R_FB.T)
            self.model.appendBodyToJoint(1, bus_in_f, pin.SE3.Identity())
        self.data = self.model.createData()
        r = self.robot
        assert self.model.nv == r.nu, (self.model.nv, r.nu)  # (nq differs: continuous joints are (cos, sin))
        # spacearm dof k is Pinocchio velocity index perm[k] (joints matched by URDF name)
        dof_joints = [link["joint"] for link in r.describe()["links"] if link["type"] != "fixed"]
        self.perm = np.array([self.model.joints[self.model.getJointId(j)].idx_v for j in dof_joints])
        self.joints_pin = [self.model.joints[self.model.getJointId(j)] for j in dof_joints]
        rng = np.random.default_rng(abs(hash((robot_name, mode))) % 2**32)
        quat = rng.normal(size=4)
        quat /= np.linalg.norm(quat)
        q = rng.uniform(-1.0, 1.0, size=r.n_dof)
        self.x = np.concatenate([[3.0, -2.0, 1.5], quat, q])
        self.u = np.concatenate([rng.normal(scale=0.3, size=3), rng.normal(scale=0.5, size=3), rng.normal(size=r.n_dof)])
        self.f = np.concatenate([rng.normal(scale=20.0, size=3), rng.normal(scale=5.0, size=3), rng.normal(scale=5.0, size=r.n_dof)])
        self._pin_state()

    def _pin_state(self):
        n = self.robot.n_dof
        x, u = self.x, self.u
        R0 = quat_to_matrix(x[3:7])
        R_BF, t_BF = self.R_FB.T, -self.R_FB.T @ self.t_FB
        R_F = R0 @ R_BF
        d = R0 @ t_BF
        q = np.zeros(self.model.nq)
        q[:3] = x[:3] + d
        q[3:7] = quat_from_matrix(R_F)
        for joint, angle in zip(self.joints_pin, x[7:]):
            if joint.nq == 2:  # a continuous joint is Pinocchio's unbounded revolute: q = (cos, sin)
                q[joint.idx_q:joint.idx_q + 2] = np.cos(angle), np.sin(angle)
            else:
                q[joint.idx_q] = angle
        T = np.zeros((6 + n, 6 + n))
        T[:3, :3] = R_F.T
        T[:3, 3:6] = -R_F.T @ skew(d)
        T[3:6, 3:6] = R_F.T
        T[self.perm, 6 + np.arange(n)] = 1.0
        v = T @ u
        w0 = u[3:6]
        tdot_u = np.zeros(6 + n)
        tdot_u[:3] = -np.cross(v[3:6], v[:3]) + R_F.T @ np.cross(w0, np.cross(w0, d))
        self.q, self.v, self.T, self.tdot_u = q, v, T, tdot_u

    def mass_matrix_pin(self):
        m = pin.crba(self.model, self.data, self.q)
        return np.triu(m) + np.triu(m, 1).T

    def reduced_pin(self, M):
        """(H*, a function giving J* of a frame) in spacearm's joint order, from Pinocchio's M."""
        p = self.perm
        mbb, mbj, mjj = M[:6, :6], M[:6, p], M[np.ix_(p, p)]
        return mjj - mbj.T @ np.linalg.solve(mbb, mbj), np.linalg.solve(mbb, mbj)

    def gjm_pin(self, frame: str):
        M = self.mass_matrix_pin()
        _, mbb_inv_mbj = self.reduced_pin(M)
        pin.computeJointJacobians(self.model, self.data, self.q)
        pin.updateFramePlacements(self.model, self.data)
        J = pin.getFrameJacobian(self.model, self.data, self.model.getFrameId(frame, pin.BODY), pin.LOCAL_WORLD_ALIGNED)
        return J[:, self.perm] - J[:, :6] @ mbb_inv_mbj


_CASES = {}


@pytest.fixture
def case(tmp_path_factory):
    def get(robot_name: str, mode: str) -> Case:
        if (robot_name, mode) not in _CASES:
            _CASES[robot_name, mode] = Case(robot_name, mode, str(tmp_path_factory.mktemp("urdf")))
        return _CASES[robot_name, mode]

    return get


@pytest.mark.parametrize("robot_name,mode", CASES)
def test_mass_matrix(case, robot_name, mode):
    c = case(robot_name, mode)
    H = c.T.T @ c.mass_matrix_pin() @ c.T
    assert_rel_close(c.robot.mass_matrix(c.x), H, f"urdf {robot_name} {mode} H")


@pytest.mark.parametrize("robot_name,mode", CASES)
def test_bias(case, robot_name, mode):
    c = case(robot_name, mode)
    nle = pin.nonLinearEffects(c.model, c.data, c.q, c.v)
    ref = c.T.T @ (nle + c.mass_matrix_pin() @ c.tdot_u)
    assert_rel_close(c.robot.bias_forces(c.x, c.u), ref, f"urdf {robot_name} {mode} c")


@pytest.mark.parametrize("robot_name,mode", CASES)
def test_forward_dynamics(case, robot_name, mode):
    c = case(robot_name, mode)
    # f = Tᵀ τ_pin; the URDF's <dynamics damping> is a passive force −c q̇ in spacearm's dynamics,
    # which Pinocchio's ABA leaves to the caller (its parser keeps the coefficients in model.damping).
    tau = np.linalg.solve(c.T.T, c.f) - c.model.damping * c.v
    a = pin.aba(c.model, c.data, c.q, c.v, tau)
    ref = np.linalg.solve(c.T, a - c.tdot_u)
    assert_rel_close(c.robot.forward_dynamics(c.x, c.u, c.f), ref, f"urdf {robot_name} {mode} forward dynamics")


@pytest.mark.parametrize("robot_name,mode", CASES)
def test_generalized_inertia(case, robot_name, mode):
    c = case(robot_name, mode)
    ref, _ = c.reduced_pin(c.mass_matrix_pin())
    assert_rel_close(c.robot.generalized_inertia(c.x), ref, f"urdf {robot_name} {mode} H*")


@pytest.mark.parametrize("robot_name,mode", CASES)
def test_generalized_jacobians(case, robot_name, mode):
    c = case(robot_name, mode)
    r = c.robot
    # every merged URDF link is a point of spacearm and a frame of Pinocchio
    points = [p for p in r.point_names if not p.endswith("_frame")]
    if not robot_name.startswith("random"):
        assert points, "the URDF should have fixed-joint links (end-effector frames)"
    for p in points:
        ref = c.gjm_pin(p)
        if np.linalg.norm(ref) < 1e-6:  # a frame on the base does not move with the joints
            assert np.linalg.norm(r.generalized_jacobian(c.x, p)) < 1e-9
            continue
        assert_rel_close(r.generalized_jacobian(c.x, p), ref, f"urdf {robot_name} {mode} J*")
