"""The grasp impact against independent references: conservation and the lock condition, the
closed forms of two free rigid bodies (arm locked), and Pinocchio's impulseDynamics for the
robot-side jump against a fixed contact."""

from __future__ import annotations

import numpy as np
import pytest

import spacearm
from spacearm.capture import grasp_impulse, impulse_momentum_split, inverse_inertia, virtual_mass
from spacearm.rotations import quat_to_matrix
from random_models import random_model, random_quaternion, random_state

SEEDS = (3, 11, 42)


def _scene(robot, rng, *, target_mass=80.0, spin=0.5, near_origin=True):
    """A robot state and a target whose grasp point sits at the robot's end effector."""
    x, u = random_state(robot, rng)
    if near_origin:
        x[:3] = rng.normal(scale=0.5, size=3)
    target = spacearm.Target(target_mass, [6.0, 8.0, 9.0], grasp_points={"handle": (0.2, -0.4, 0.3)})
    quat = random_quaternion(rng)
    X = robot.point_position(x)
    cm = X - quat_to_matrix(quat) @ target.grasp_points["handle"]
    s = target.state(cm, quat, rng.normal(scale=0.3, size=3), rng.normal(scale=spin, size=3))
    return x, u, target, s


def _robots():
    return [spacearm.presets.spatial6()] + [random_model(s).robot for s in SEEDS]


def _rigid_body(robot, x):
    """The robot frozen as one rigid body, from its bodies' own mass properties (independent of
    the mass matrix): total mass, CM, inertia about the CM in 𝒥."""
    desc = robot.description
    kin = robot.forward_kinematics(x)
    masses = [desc.base.mass] + [link.mass for link in desc.links]
    inertias = [np.asarray(desc.base.inertia).reshape(3, 3)] + [np.asarray(link.inertia).reshape(3, 3) for link in desc.links]
    m = sum(masses)
    c = sum(mi * ri for mi, ri in zip(masses, kin.com_in_world)) / m
    inertia = np.zeros((3, 3))
    for mi, Ii, Ri, ri in zip(masses, inertias, kin.body_to_world, kin.com_in_world):
        d = ri - c
        inertia += Ri @ Ii @ Ri.T + mi * (d @ d * np.eye(3) - np.outer(d, d))
    return m, c, inertia


@pytest.mark.parametrize("index", range(4))
def test_rigid_grasp_conserves_momentum_and_locks(index):
    robot = _robots()[index]
    x, u, target, s = _scene(robot, np.random.default_rng([14, index]))
    res = grasp_impulse(robot, x, u, target, s, grasp="handle")
    assert res.gap < 1e-12
    # the lock: no relative twist at the grasp point after, a clear one before
    assert np.linalg.norm(res.relative_twist_before) > 0.1
    assert np.linalg.norm(res.relative_twist_after) < 1e-12 * np.linalg.norm(res.relative_twist_before) * 1e3
    before_r, before_t = robot.momentum(x, u), target.momentum(s)
    after_r, after_t = robot.momentum(x, res.u_after), target.momentum(res.target_state_after)
    scale_p = np.linalg.norm(before_r.P) + np.linalg.norm(before_t.P) + np.linalg.norm(res.impulse[:3])
    scale_l = np.linalg.norm(before_r.L_origin) + np.linalg.norm(before_t.L_origin) + np.linalg.norm(res.impulse[3:])
    assert np.linalg.norm(before_r.P + before_t.P - after_r.P - after_t.P) < 1e-12 * scale_p
    assert np.linalg.norm(before_r.L_origin + before_t.L_origin - after_r.L_origin - after_t.L_origin) < 1e-12 * scale_l
    # the impulse the robot receives is the momentum it gains (about the origin of 𝒥)
    np.testing.assert_allclose(after_r.P - before_r.P, res.impulse[:3], atol=1e-12 * scale_p)
    np.testing.assert_allclose(after_r.L_origin - before_r.L_origin, res.impulse[3:] + np.cross(res.point, res.impulse[:3]),
                               atol=1e-11 * scale_l)
    assert res.energy_lost > 0.0


@pytest.mark.parametrize("index", range(4))
def test_inverse_inertia_forms_agree(index):
    robot = _robots()[index]
    x, _ = random_state(robot, np.random.default_rng([15, index]))
    g1 = inverse_inertia(robot, x)
    g2 = inverse_inertia(robot, x, form="generalized")
    np.testing.assert_allclose(g2, g1, atol=1e-10 * np.abs(g1).max())
    assert np.all(np.linalg.eigvalsh(0.5 * (g1 + g1.T)) > 0)
    # Locking the arm stiffens the point: G_locked <= G_free in the PSD order.
    gl = inverse_inertia(robot, x, arm="locked")
    assert np.linalg.eigvalsh(0.5 * ((g1 - gl) + (g1 - gl).T)).min() > -1e-10 * np.abs(g1).max()
    n = np.array([0.3, -0.5, 0.8])
    assert virtual_mass(robot, x, n) <= virtual_mass(robot, x, n, arm="locked") * (1 + 1e-12)


@pytest.mark.parametrize("index", range(4))
def test_two_free_bodies_point_impact_closed_form(index):
    """Arm locked: the robot is one rigid body; the classical two-body impulse
    λ = (1 + e) m_eff v_n with 1/m_eff = 1/m1 + 1/m2 + (r1×n)ᵀI1⁻¹(r1×n) + (r2×n)ᵀI2⁻¹(r2×n)."""
    robot = _robots()[index]
    rng = np.random.default_rng([16, index])
    x, u, target, s = _scene(robot, rng)
    u[6:] = 0.0  # the arm at rest relative to the base: the robot is one rigid body
    m1, c1, I1 = _rigid_body(robot, x)
    X = robot.point_position(x)
    n = rng.normal(size=3)
    n /= np.linalg.norm(n)
    # the robot's point velocity and the target's material point velocity
    j0, jm = robot.point_jacobian(x)
    v_robot = (j0 @ u[:6] + jm @ u[6:])[:3]
    st = target.split(s)
    v_target = st.velocity + np.cross(st.angular_velocity, X - st.position)
    vn = n @ (v_robot - v_target)
    if vn > 0:
        n, vn = -n, -vn
    m2 = target.mass
    R2 = quat_to_matrix(st.quaternion)
    I2 = R2 @ target.inertia @ R2.T
    r1, r2 = X - c1, X - st.position
    inv_meff = 1 / m1 + 1 / m2 + np.cross(r1, n) @ np.linalg.solve(I1, np.cross(r1, n)) + np.cross(r2, n) @ np.linalg.solve(I2, np.cross(r2, n))
    meff = 1 / inv_meff
    for e in (0.0, 1.0, 0.4):
        res = grasp_impulse(robot, x, u, target, s, kind="point", restitution=e, normal=n, arm="locked")
        lam = (1 + e) * meff * (-vn)
        np.testing.assert_allclose(res.impulse, np.r_[lam * n, 0, 0, 0], rtol=1e-10, atol=1e-12 * abs(lam))
        # the target's jump from Newton–Euler on its own
        np.testing.assert_allclose(res.target_dtwist[:3], -lam * n / m2, rtol=1e-10, atol=1e-13)
        np.testing.assert_allclose(res.target_dtwist[3:], -np.linalg.solve(I2, np.cross(r2, lam * n)), rtol=1e-9, atol=1e-13)
        # the robot's base jump: the rigid composite's CM and spin jump, moved to the base CM
        dv_c = lam * n / m1
        dw = np.linalg.solve(I1, np.cross(r1, lam * n))
        np.testing.assert_allclose(res.du[3:6], dw, rtol=1e-9, atol=1e-13)
        np.testing.assert_allclose(res.du[:3], dv_c + np.cross(dw, x[:3] - c1), rtol=1e-9, atol=1e-13)
        assert np.all(res.du[6:] == 0.0)
        # normal relative velocity: -e times before; energy: lost (1 - e²)/2 m_eff v_n²
        assert n @ res.relative_twist_after[:3] == pytest.approx(-e * vn, rel=1e-9, abs=1e-13)
        assert res.energy_lost == pytest.approx(0.5 * meff * (1 - e * e) * vn * vn, rel=1e-8, abs=1e-10 * meff * vn * vn)


@pytest.mark.parametrize("index", range(4))
def test_two_free_bodies_rigid_grasp_closed_form(index):
    """Arm locked, rigid lock: both bodies end moving as one rigid body with v = P/M and
    ω = I_c⁻¹ L_c (momentum about the combined CM)."""
    robot = _robots()[index]
    x, u, target, s = _scene(robot, np.random.default_rng([17, index]))
    u[6:] = 0.0  # the arm at rest relative to the base: a rigid body before the impact too
    res = grasp_impulse(robot, x, u, target, s, arm="locked")
    m1, c1, I1 = _rigid_body(robot, x)
    st = target.split(s)
    R2 = quat_to_matrix(st.quaternion)
    I2 = R2 @ target.inertia @ R2.T
    v1 = u[:3] + np.cross(u[3:6], c1 - x[:3])
    M = m1 + target.mass
    c = (m1 * c1 + target.mass * st.position) / M
    P = m1 * v1 + target.mass * st.velocity
    L = I1 @ u[3:6] + m1 * np.cross(c1 - c, v1) + I2 @ st.angular_velocity + target.mass * np.cross(st.position - c, st.velocity)
    Ic = (I1 + m1 * ((c1 - c) @ (c1 - c) * np.eye(3) - np.outer(c1 - c, c1 - c))
          + I2 + target.mass * ((st.position - c) @ (st.position - c) * np.eye(3) - np.outer(st.position - c, st.position - c)))
    v, w = P / M, np.linalg.solve(Ic, L)
    scale = np.linalg.norm(v) + np.linalg.norm(w)
    after = target.split(res.target_state_after)
    np.testing.assert_allclose(after.angular_velocity, w, atol=1e-10 * scale)
    np.testing.assert_allclose(after.velocity, v + np.cross(w, st.position - c), atol=1e-10 * scale)
    np.testing.assert_allclose(res.u_after[3:6], w, atol=1e-10 * scale)
    np.testing.assert_allclose(res.u_after[:3], v + np.cross(w, x[:3] - c), atol=1e-10 * scale)


def test_momentum_split_adds_up():
    robot = spacearm.presets.spatial6()
    x, _ = random_state(robot, np.random.default_rng(18))
    lam = np.array([3.0, -1.0, 2.0, 0.5, 0.2, -0.4])
    split = impulse_momentum_split(robot, x, lam)
    X = robot.point_position(x)
    # the impulse's momentum about the base CM, from its definition
    total = np.r_[lam[:3], lam[3:] + np.cross(X - x[:3], lam[:3])]
    np.testing.assert_allclose(split.total, total, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(split.base + split.arm, total, rtol=1e-9, atol=1e-10)
    assert np.linalg.norm(split.arm) > 1e-3 * np.linalg.norm(total)
    assert split.base_jump_singular_values.shape == (6,)
    # B Λ is the base's jump H⁻¹ Jᵀ Λ (from the mass matrix, independently of the core's solve)
    J = np.hstack(robot.point_jacobian(x))
    np.testing.assert_allclose(split.base_jump_map @ lam, np.linalg.solve(robot.mass_matrix(x), J.T @ lam)[:6], rtol=1e-10, atol=1e-12)
    # one type: the extension's class, read-only
    assert type(split) is spacearm._core.MomentumSplit and not split.base.flags.writeable



@pytest.mark.parametrize("index", range(4))
@pytest.mark.parametrize("kind", ["rigid", "point"])
def test_robot_jump_against_pinocchio_impulse_dynamics(index, kind):
    """A target far heavier than the robot, at rest, is a fixed contact: the robot-side jump
    must equal Pinocchio's impulseDynamics with the gripper frame's Jacobian as constraint."""
    from spacearm import interop

    pin = pytest.importorskip("pinocchio")
    robot = _robots()[index]
    rng = np.random.default_rng([19, index])
    x, u = random_state(robot, rng)
    X = robot.point_position(x)
    big = 1e12  # the heaviest body the model rules allow (docs/model-format.md): a fixed contact to ~1e-10
    target = spacearm.Target(big, [big, big, big])
    s = target.state(X + np.array([0.3, 0.1, -0.2]))
    model = interop.to_pinocchio(robot)
    data = model.createData()
    q, v = interop.to_pinocchio_state(robot, x, u)
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    J = pin.getFrameJacobian(model, data, model.getFrameId(robot.end_effector), pin.LOCAL_WORLD_ALIGNED)
    if kind == "rigid":
        # the target's CM 0.37 m from X: the lock acts at the robot's point X (no gap allowed for)
        res = grasp_impulse(robot, x, u, target, s, capture_tolerance=np.inf)
        v_after = pin.impulseDynamics(model, data, q, v, J, 0.0, 0.0)
    else:
        j0, jm = robot.point_jacobian(x)
        vX = (j0 @ u[:6] + jm @ u[6:])[:3]
        n = -vX / np.linalg.norm(vX)  # the gripper moves into the contact
        e = 0.6
        res = grasp_impulse(robot, x, u, target, s, kind="point", restitution=e, normal=n, capture_tolerance=np.inf)
        v_after = pin.impulseDynamics(model, data, q, v, (n @ J[:3])[None, :], e, 0.0)
    _, u_ref = interop.from_pinocchio_state(robot, q, np.asarray(v_after))
    du_ref = u_ref - u
    assert np.linalg.norm(du_ref) > 1e-2
    np.testing.assert_allclose(res.du, du_ref, atol=1e-9 * np.linalg.norm(du_ref))


def test_bad_input():
    robot = spacearm.presets.spatial6()
    x, u = robot.neutral_configuration(), robot.zero_velocity()
    target = spacearm.Target(10.0, [1, 1, 1])
    s = target.state(robot.point_position(x))
    with pytest.raises(spacearm.ArgumentError, match="restitution"):
        grasp_impulse(robot, x, u, target, s, kind="point", restitution=1.5)
    with pytest.raises(spacearm.ArgumentError, match="kind"):
        grasp_impulse(robot, x, u, target, s, kind="glue")
    with pytest.raises(spacearm.ArgumentError, match="plastic"):
        grasp_impulse(robot, x, u, target, s, restitution=0.5)
    with pytest.raises(spacearm.ShapeError, match="target_state"):
        grasp_impulse(robot, x, u, target, s[:12])
    with pytest.raises(spacearm.SpacearmTypeError, match="Target"):
        grasp_impulse(robot, x, u, "box", s)
    with pytest.raises(spacearm.ModelError, match="target 'box'.*triangle"):
        spacearm.Target(10.0, [1, 1, 5], name="box")
    with pytest.raises(spacearm.NotFoundError, match="grasp point"):
        target.grasp_position(s, "nope")


# ---- a whole model as the target ---------------------------------------------------------------
def test_jointless_model_target_equals_target():
    robot = spacearm.presets.spatial6()
    rng = np.random.default_rng(20)
    x, u, target, s = _scene(robot, rng)
    twin = spacearm.Target.from_robot(target.body)
    a = grasp_impulse(robot, x, u, target, s, grasp="handle")
    b = grasp_impulse(robot, x, u, twin, s, grasp="handle")
    np.testing.assert_array_equal(a.impulse, b.impulse)
    np.testing.assert_array_equal(a.target_dtwist, b.target_dtwist)


@pytest.mark.parametrize("seed", SEEDS)
def test_jointed_target_conserves_momentum_and_locks(seed):
    robot = spacearm.presets.spatial6()
    model = random_model(seed).robot
    target = spacearm.Target.from_robot(model)
    rng = np.random.default_rng([21, seed])
    x, u = random_state(robot, rng)
    x[:3] = 0.0
    xt, ut = random_state(model, rng)
    # move the target so that its probe point is at the gripper
    xt[:3] += robot.point_position(x) - model.point_position(xt, "probe")
    s = np.concatenate([xt, ut])
    res = grasp_impulse(robot, x, u, target, s, grasp="probe")
    assert res.gap < 1e-9 and res.target_dtwist.shape == (model.nu,)
    assert np.linalg.norm(res.relative_twist_after) < 1e-9 * np.linalg.norm(res.relative_twist_before)
    m0 = [robot.momentum(x, u), target.momentum(s)]
    m1 = [robot.momentum(x, res.u_after), target.momentum(res.target_state_after)]
    scale = sum(np.linalg.norm(m.L_origin) for m in m0 + m1) + sum(np.linalg.norm(m.P) for m in m0 + m1)
    np.testing.assert_allclose(m0[0].P + m0[1].P, m1[0].P + m1[1].P, atol=1e-12 * scale)
    np.testing.assert_allclose(m0[0].L_origin + m0[1].L_origin, m1[0].L_origin + m1[1].L_origin, atol=1e-11 * scale)
    with pytest.raises(spacearm.ArgumentError, match="jointed"):
        from spacearm.capture import attach_target

        attach_target(robot, x, res.u_after, target, res.target_state_after)


@pytest.mark.parametrize("seed", SEEDS)
def test_jointed_target_jump_against_pinocchio(seed):
    """A jointless 'robot' of 1e12 kg, at rest, is a fixed contact for a jointed target:
    the target's jump must equal Pinocchio's impulseDynamics of the target's model."""
    from spacearm import interop

    pin = pytest.importorskip("pinocchio")
    model = random_model(seed).robot
    target = spacearm.Target.from_robot(model)
    rng = np.random.default_rng([22, seed])
    xt, ut = random_state(model, rng)
    big = 1e12  # the heaviest body the model rules allow (docs/model-format.md): a fixed contact to ~1e-10
    wall = spacearm.Robot.builder("wall", base_mass=big, base_inertia=[big, big, big])
    wall.add_point("pad", body="base", offset=(0.0, 0.0, 0.0))
    wall.set_end_effector("pad")
    wall = wall.build()
    xw = wall.neutral_configuration(r0=model.point_position(xt, "probe"))
    res = grasp_impulse(wall, xw, wall.zero_velocity(), target, np.concatenate([xt, ut]), grasp="probe")
    pmodel = interop.to_pinocchio(model)
    data = pmodel.createData()
    q, v = interop.to_pinocchio_state(model, xt, ut)
    pin.computeJointJacobians(pmodel, data, q)
    pin.updateFramePlacements(pmodel, data)
    J = pin.getFrameJacobian(pmodel, data, pmodel.getFrameId("probe"), pin.LOCAL_WORLD_ALIGNED)
    v_after = pin.impulseDynamics(pmodel, data, q, v, J, 0.0, 0.0)
    _, u_ref = interop.from_pinocchio_state(model, q, np.asarray(v_after))
    du_ref = u_ref - ut
    assert np.linalg.norm(du_ref) > 1e-2
    np.testing.assert_allclose(res.target_dtwist, du_ref, atol=1e-9 * np.linalg.norm(du_ref))


def test_analysis_quantities_bad_input_and_grasp_point_forms():
    robot = spacearm.presets.spatial6()
    x = robot.neutral_configuration()
    with pytest.raises(spacearm.ArgumentError, match="form"):
        inverse_inertia(robot, x, form="schur")
    with pytest.raises(spacearm.ArgumentError, match="arm"):
        inverse_inertia(robot, x, arm="floppy")
    with pytest.raises(spacearm.ArgumentError, match="direction"):
        virtual_mass(robot, x, (0.0, 0.0, 0.0))
    with pytest.raises(spacearm.ShapeError):
        impulse_momentum_split(robot, x, [1.0, 2.0])
    # grasp points: a mapping, a list of offsets, one flat offset
    assert list(spacearm.Target(1.0, [1, 1, 1], grasp_points=[(0.1, 0, 0), (0, 0.2, 0)]).grasp_points) == ["grasp0", "grasp1"]
    one = spacearm.Target(1.0, [1, 1, 1], grasp_points=(0.1, 0.0, 0.0))
    np.testing.assert_array_equal(one.grasp_points["grasp0"], [0.1, 0.0, 0.0])
    with pytest.raises(spacearm.ArgumentError, match="at least one grasp point"):
        spacearm.Target(1.0, [1, 1, 1], grasp_points={})
    with pytest.raises(spacearm.ArgumentError, match="jointed model"):
        spacearm.Target.from_robot(robot).state()


def _rigid_target_energy(target, state):
    """½ m |v|² + ½ ωᵀ (R I Rᵀ) ω of a rigid target, from its split state alone."""
    st = target.split(state)
    R = quat_to_matrix(st.quaternion)
    w = st.angular_velocity
    return 0.5 * target.mass * st.velocity @ st.velocity + 0.5 * w @ (R @ target.inertia @ R.T) @ w


def _energy_ledger(robot, x, u, target, s, res):
    """``(T_before, T_after, locking_work)``: the kinetic energies from the paper-form mass matrix
    (½ uᵀ H u) and the target's own mass properties, and the locking impulses' work from the
    joint rows of H Δu = Jᵀ Λ + [0; τ̂] with the paper's inertia blocks (τ̂ = H0mᵀ Δẋ0 − J_mᵀ Λ)."""
    h = robot.mass_matrix(x, method="paper")
    blocks = robot.inertia_blocks(x)
    _, jm = robot.point_jacobian(x)
    tau_lock = blocks.H0m.T @ res.du[:6] + blocks.Hm @ res.du[6:] - jm.T @ res.impulse
    before = 0.5 * u @ h @ u + _rigid_target_energy(target, s)
    after = 0.5 * res.u_after @ h @ res.u_after + _rigid_target_energy(target, res.target_state_after)
    return before, after, float(tau_lock @ u[6:]), tau_lock


@pytest.mark.parametrize("index", range(4))
@pytest.mark.parametrize("kind", ["rigid", "point"])
def test_locked_arm_with_moving_joints_energy_ledger(index, kind):
    """arm="locked" holds the joint rates (Δq̇ = 0) by locking impulses τ̂ that work on the moving
    joints: energy_lost is the grasp's own dissipation (>= 0), locking_work that work, and the
    kinetic energy changes by locking_work − energy_lost (ledger from the mass matrix)."""
    robot = _robots()[index]
    rng = np.random.default_rng([21, index])
    x, u, target, s = _scene(robot, rng)
    u[6:] = rng.normal(scale=0.5, size=robot.n_dof)  # the joints move
    n = None
    if kind == "point":
        j0, jm = robot.point_jacobian(x)
        st = target.split(s)
        v_rel = (j0 @ u[:6] + jm @ u[6:])[:3] - (st.velocity + np.cross(st.angular_velocity, robot.point_position(x) - st.position))
        n = -v_rel / np.linalg.norm(v_rel)  # approaching along n
    kw = {} if kind == "rigid" else {"kind": "point", "normal": n, "restitution": 0.3}
    res = grasp_impulse(robot, x, u, target, s, grasp="handle", arm="locked", **kw)
    free = grasp_impulse(robot, x, u, target, s, grasp="handle", arm="free", **kw)
    before, after, locking, tau_lock = _energy_ledger(robot, x, u, target, s, res)
    scale = before + abs(locking)
    assert np.all(res.du[6:] == 0.0)
    assert np.linalg.norm(tau_lock) > 1e-3 * np.linalg.norm(res.impulse)  # the lock does act
    assert res.locking_work == pytest.approx(locking, rel=1e-9, abs=1e-12 * scale)
    assert res.energy_lost >= 0.0
    assert before - after == pytest.approx(res.energy_lost - res.locking_work, rel=1e-9, abs=1e-11 * scale)
    # The grasp's dissipation in closed form, from G = J_0 H0⁻¹ J_0ᵀ (arm locked) + the target's.
    h0 = robot.inertia_blocks(x).H0
    j0, _ = robot.point_jacobian(x)
    g = j0 @ np.linalg.solve(h0, j0.T) + res.G_target
    if kind == "rigid":
        expected = 0.5 * res.relative_twist_before @ np.linalg.solve(g, res.relative_twist_before)
    else:
        vn = n @ res.relative_twist_before[:3]
        expected = 0.5 * (1 - 0.3**2) * vn * vn / (n @ g[:3, :3] @ n)
    assert res.energy_lost == pytest.approx(expected, rel=1e-9)
    # arm="free": no locking impulse, the whole change is the grasp's.
    fb, fa, f_locking, f_tau = _energy_ledger(robot, x, u, target, s, free)
    assert free.locking_work == 0.0
    _, jm = robot.point_jacobian(x)
    assert np.abs(f_tau).max() < 1e-10 * np.abs(jm.T @ free.impulse).max()  # the joint rows balance
    assert fb - fa == pytest.approx(free.energy_lost, rel=1e-9, abs=1e-11 * fb)


def test_locked_arm_spatial6_target_at_rest():
    """The reported case: spatial6 with its joints at 0.3 rad/s grasping a 50 kg target at rest.
    The kinetic energy rises (the locking impulses put energy in), yet the grasp dissipates."""
    robot = spacearm.presets.spatial6()
    x, u = robot.neutral_configuration(), robot.zero_velocity()
    u[6:] = 0.3
    target = spacearm.Target(50.0, [4.0, 5.0, 6.0], grasp_points={"handle": (-0.5, 0.0, 0.0)})
    s = target.state(position=robot.point_position(x) + np.array([0.5, 0.0, 0.0]))
    res = grasp_impulse(robot, x, u, target, s, grasp="handle", arm="locked")
    before, after, locking, _ = _energy_ledger(robot, x, u, target, s, res)
    assert after > before  # what the old energy_lost (before − after) reported as a negative loss
    assert res.locking_work == pytest.approx(locking, rel=1e-9) and locking > after - before
    assert res.energy_lost == pytest.approx(locking - (after - before), rel=1e-9) and res.energy_lost > 0


# ---- the previous numpy implementation of grasp_impulse, kept as an independent oracle of the
# core's algorithms/impulse.rs (robot methods: point Jacobians and mass matrices, numpy solves).
def _numpy_grasp_impulse(robot, x, u, target, s, *, grasp=None, kind="rigid", restitution=0.0, normal=None, arm="free"):
    e = restitution
    body, offset = robot.resolve_point(None)
    X = robot.point_position(x, (body, offset))
    grasp_world = target.grasp_position(s, grasp)
    tx, tu = target.xu(s)
    t_body, t_offset = target.material_point(s, X, grasp)
    j_t = np.hstack(target.body.point_jacobian(tx, (t_body, t_offset)))
    h_t = target.body.mass_matrix(tx)
    g_t = j_t @ np.linalg.solve(h_t, j_t.T)
    j_full = np.hstack(robot.point_jacobian(x, (body, offset)))
    h_full = robot.mass_matrix(x)
    j_r, h_r = (j_full[:, :6], h_full[:6, :6]) if arm == "locked" else (j_full, h_full)
    g_r = j_r @ np.linalg.solve(h_r, j_r.T)
    v_rel = j_full @ u - j_t @ tu
    g = g_r + g_t
    if kind == "rigid":
        lam = -np.linalg.solve(g, v_rel)
    else:
        if normal is None:
            n = grasp_world - target.body.forward_kinematics(tx).com_in_world[t_body]
        else:
            n = np.asarray(normal, dtype=float)
        n = n / np.linalg.norm(n)
        vn = float(n @ v_rel[:3])
        lam = np.zeros(6)
        if vn < 0.0:
            lam[:3] = -(1.0 + e) * vn / float(n @ g[:3, :3] @ n) * n
    du = np.zeros(robot.nu)
    du[: j_r.shape[1]] = np.linalg.solve(h_r, j_r.T @ lam)
    dtw = -np.linalg.solve(h_t, j_t.T @ lam)
    u_after = u + du
    s_after = s.copy()
    s_after[tx.size:] += dtw
    v_rel_after = j_full @ u_after - j_t @ target.xu(s_after)[1]
    lost = -float(lam @ (v_rel + v_rel_after)) / 2.0
    locking = 0.0
    if arm == "locked" and robot.n_dof:
        locking = float((h_full @ du - j_full.T @ lam)[6:] @ u[6:])
    return dict(du=du, target_dtwist=dtw, impulse=lam, point=X, gap=float(np.linalg.norm(X - grasp_world)), u_after=u_after,
                target_state_after=s_after, relative_twist_before=v_rel, relative_twist_after=v_rel_after, G_robot=g_r, G_target=g_t,
                energy_lost=lost, locking_work=locking)


@pytest.mark.parametrize("index", range(4))
@pytest.mark.parametrize("kind, restitution, normal", [("rigid", 0.0, None), ("point", 0.0, None), ("point", 0.6, None),
                                                       ("point", 1.0, (0.3, -0.8, 0.5))])
@pytest.mark.parametrize("arm", ["free", "locked"])
def test_core_grasp_impulse_equals_the_numpy_formulas(index, kind, restitution, normal, arm):
    """grasp_impulse (the core's algorithms/impulse.rs) against the numpy implementation it replaced."""
    robot = _robots()[index]
    x, u, target, s = _scene(robot, np.random.default_rng([31, index]))
    if kind == "point":  # make the bodies approach along the normal: n·v_rel = −0.2 m/s
        n = np.asarray(normal if normal is not None else target.grasp_position(s, "handle") - s[:3], dtype=float)
        n = n / np.linalg.norm(n)
        v_rel = grasp_impulse(robot, x, u, target, s, grasp="handle").relative_twist_before
        s[7:10] += (v_rel[:3] @ n + 0.2) * n
    got = grasp_impulse(robot, x, u, target, s, grasp="handle", kind=kind, restitution=restitution, normal=normal, arm=arm)
    want = _numpy_grasp_impulse(robot, x, u, target, s, grasp="handle", kind=kind, restitution=restitution, normal=normal, arm=arm)
    assert np.linalg.norm(want["impulse"]) > 1e-3, "the fixture must collide"
    for name, value in want.items():
        g = np.asarray(getattr(got, name))
        scale = max(np.abs(value).max(), 1e-300)
        if name in ("energy_lost", "locking_work"):  # energies: relative to the kinetic energy in play
            scale = robot.kinetic_energy(x, u) + target.kinetic_energy(s)
        if name == "gap":
            scale = 1.0
        if name == "relative_twist_after":  # zero for a rigid lock: rounding of the twist before
            scale = np.abs(want["relative_twist_before"]).max()
        np.testing.assert_allclose(g, value, rtol=0, atol=1e-12 * scale, err_msg=name)


def test_core_impulse_dynamics_of_one_model():
    """_core.impulse_dynamics: Newton's restitution law on the contact rows and the Schur form
    against a dense KKT solve (numpy), free and locked."""
    from spacearm import _core

    robot = random_model(11).robot
    x, u = random_state(robot, np.random.default_rng(5))
    j = np.hstack(robot.point_jacobian(x))
    h = robot.mass_matrix(x)
    for e in (0.0, 0.5):
        r = _core.impulse_dynamics(robot.core_model, x, u, j, restitution=e)
        k = np.block([[h, -j.T], [j, np.zeros((6, 6))]])
        sol = np.linalg.solve(k, np.r_[h @ u, -e * (j @ u)])
        np.testing.assert_allclose(r.u_after, sol[: robot.nu], atol=1e-11 * np.abs(sol[: robot.nu]).max())
        np.testing.assert_allclose(r.impulse, sol[robot.nu:], atol=1e-11 * np.abs(sol[robot.nu:]).max())
        np.testing.assert_allclose(j @ r.u_after, -e * (j @ u), atol=1e-12 * np.abs(j @ u).max())
        locked = _core.impulse_dynamics(robot.core_model, x, u, j[:1], restitution=e, arm="locked")
        assert np.all(locked.du[6:] == 0.0)
        np.testing.assert_allclose(j[:1] @ locked.u_after, -e * (j[:1] @ u), atol=1e-12 * np.abs(j @ u).max())
        np.testing.assert_allclose(locked.locking_impulse, (h @ locked.du - j[:1].T @ locked.impulse)[6:], atol=1e-10)


def test_grasp_impulse_is_the_extensions_frozen_class():
    """One type: ``capture.GraspImpulse`` is ``_core.GraspImpulse``, frozen, its arrays read-only,
    ``target_state_after`` the target's x then its u after, and a one-line repr."""
    from spacearm import _core

    robot = _robots()[1]
    x, u, target, s = _scene(robot, np.random.default_rng([7, 1]))
    res = grasp_impulse(robot, x, u, target, s, grasp="handle", kind="point", normal=(0.0, 0.0, 1.0), restitution=0.3)
    assert spacearm.capture.GraspImpulse is _core.GraspImpulse and type(res) is _core.GraspImpulse
    assert res.kind == "point" and res.normal is not None and res.locking_impulse.shape == (robot.n_dof,)
    tx, _ = target.xu(target.check_state(s))
    np.testing.assert_array_equal(res.target_state_after[: tx.size], tx)
    np.testing.assert_array_equal(res.target_state_after[tx.size:], res.target_u_after)
    assert res.G_robot.shape == res.G_target.shape == (6, 6)
    for name in ("du", "target_dtwist", "impulse", "point", "u_after", "target_state_after", "relative_twist_before",
                 "relative_twist_after", "G_robot", "G_target", "target_u_after", "normal", "locking_impulse"):
        a = getattr(res, name)
        assert not a.flags.writeable, name
        with pytest.raises(ValueError):
            a[...] = 0.0
    with pytest.raises(AttributeError):
        res.gap = 1.0  # frozen
    text = repr(res)
    assert text.startswith("<spacearm._core.GraspImpulse point:") and "energy_lost" in text and len(text) < 200
    assert grasp_impulse(robot, x, u, target, s, grasp="handle").normal is None
