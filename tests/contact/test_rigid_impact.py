"""The rigid frictional impact (spacearm.contact.solve_impact; the core's collision/impact.rs,
delassus.rs, admm.rs, pgs.rs; docs/contact.md "Rigid frictional impacts"): against Pinocchio 4's
own Delassus operator and ADMM/PGS contact solvers on the same robot, contact points, normals and
friction; against the closed forms of a central frictionless impact of two free bodies and of a
block that sticks or slides; momentum kept; bad input refused."""

from __future__ import annotations

import numpy as np
import pytest

import spacearm
from spacearm.contact import Pair, contacts, solve_impact
from spacearm.errors import ArgumentError, SpacearmTypeError


def _arm_contacts(robot, x, u, rng, k):
    """``k`` contacts between random bodies of ``robot`` near the second's CM, each normal turned
    so that the point approaches; drawn again until the Delassus operator is well conditioned
    (each point free to move in all directions relative to its other body: one solution to
    compare, which a spherical wrist or a short path between the bodies would not give)."""
    kin = robot.forward_kinematics(x)
    names = robot.body_names
    while True:
        out = []
        while len(out) < k:
            a, b = sorted(rng.choice(len(names), 2, replace=False))
            p = kin.com_in_world[b] + rng.uniform(-0.1, 0.1, 3)
            n = rng.normal(size=3)
            n /= np.linalg.norm(n)
            if solve_impact(robot, x, u, [(names[a], names[b], p, n)]).velocity_before[0, 2] > 0:
                n = -n
            out.append((names[a], names[b], p, n))
        eig = np.linalg.eigvalsh(solve_impact(robot, x, u, out).delassus)
        if eig[0] > 1e-3 * eig[-1]:
            return out


def _pinocchio_problem(robot, x, u, points, mu):
    """Pinocchio's Delassus operator, free velocity and constraint models for ``points``: the same
    world point on both bodies, the contact frame of spacearm's result."""
    pin = pytest.importorskip("pinocchio")
    from spacearm import interop

    model = interop.to_pinocchio(robot)
    data = model.createData()
    q, v = interop.to_pinocchio_state(robot, x, u)
    pin.forwardKinematics(model, data, q, v)
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    frames = solve_impact(robot, x, u, points).frames
    models = pin.StdVec_ConstraintModel()
    rows = []
    for (a, b, p, _), R in zip(points, frames):
        joints = [model.frames[model.getFrameId(name)].parentJoint for name in (a, b)]
        world = pin.SE3(R, np.asarray(p, float))
        cm = pin.PointContactConstraintModel(model, joints[0], data.oMi[joints[0]].inverse() * world, joints[1], data.oMi[joints[1]].inverse() * world)
        cm.setFriction(mu)
        cd = cm.createData()
        cm.calc(model, data, cd)
        rows.append(cm.jacobian(model, data, cd))
        models.append(pin.ConstraintModel(cm))
    J = np.vstack(rows)
    M = pin.crba(model, data, q)
    M = np.triu(M) + np.triu(M, 1).T
    G = J @ np.linalg.solve(M, J.T)
    datas = pin.StdVec_ConstraintData()
    for cm in models:
        datas.append(cm.createData())
    return pin, model, q, v, J, M, G, models, datas


def _pinocchio_solve(pin, kind, G, g, models, datas):
    """Pinocchio's solution of the cone problem by its ADMM or PGS solver. Pinocchio 4.1's PGS
    evaluates each point's residual right after that point's own projection, before the later
    points change its velocity, and can report convergence early (frictionless: residuals of 0
    after its first sweep); its sweeps are run here, warm-started one after the other, until the
    impulses stop changing (its fixed point, which the comparison needs)."""
    if kind == "admm":
        settings, result, solver = pin.ADMMSolverSettings(), pin.ADMMSolverResult(), pin.ADMMConstraintSolver(len(g))
    else:
        settings, result, solver = pin.PGSSolverSettings(), pin.PGSSolverResult(), pin.PGSConstraintSolver(len(g))
    settings.absolute_feasibility_tol = settings.absolute_complementarity_tol = 1e-15
    settings.relative_feasibility_tol = settings.relative_complementarity_tol = 0.0
    settings.max_iterations = 100000
    delassus = pin.DelassusOperatorDense(G)
    solver.solve(delassus, g, models, datas, settings, result)
    assert result.converged, f"Pinocchio's {kind} did not converge"
    lam = np.asarray(result.retrieveConstraintImpulses()).copy()
    for _ in range(100000 if kind == "pgs" else 0):
        result.setConstraintImpulseGuess(lam)
        solver.solve(delassus, g, models, datas, settings, result)
        new = np.asarray(result.retrieveConstraintImpulses()).copy()
        if np.abs(new - lam).max() <= 1e-15 * max(1.0, np.abs(lam).max()):
            return new
        lam = new
    assert kind == "admm", "Pinocchio's PGS sweeps did not reach a fixed point"
    return lam


@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize("mu", [0.0, 0.3, 1.2])
def test_delassus_impulses_and_velocities_equal_pinocchio_admm_and_pgs(seed, mu):
    from spacearm import interop

    robot = spacearm.presets.spatial7()
    rng = np.random.default_rng([53, seed])
    x = robot.neutral_configuration()
    x[7:] = rng.uniform(-1.5, 1.5, robot.n_dof)
    u = rng.normal(scale=0.3, size=robot.nu)
    points = _arm_contacts(robot, x, u, rng, 1 + seed % 2)
    pin, model, q, v, J, M, G, models, datas = _pinocchio_problem(robot, x, u, points, mu)
    eig = np.linalg.eigvalsh(G)
    assert eig[0] > 1e-6 * eig[-1], "a positive definite Delassus operator: one solution"
    for solver in ("admm", "pgs"):
        r = solve_impact(robot, x, u, points, friction=mu, solver=solver, tolerance=1e-13, max_iterations=20000)
        assert r.converged, r
        # The Delassus operator: J H⁻¹ Jᵀ is the same in both layouts (u = T v, M = Tᵀ H T).
        np.testing.assert_allclose(r.delassus, G, rtol=0, atol=1e-10 * np.abs(G).max())
        # The free velocity J u⁻ = J_pin v.
        np.testing.assert_allclose(r.velocity_before.ravel(), J @ v, rtol=0, atol=1e-12)
        lam_ref = _pinocchio_solve(pin, solver, G, J @ v, models, datas)
        assert np.linalg.norm(lam_ref) > 1e-2
        np.testing.assert_allclose(r.impulse.ravel(), lam_ref, rtol=0, atol=1e-8 * np.abs(lam_ref).max())
        v_after = v + np.linalg.solve(M, J.T @ lam_ref)
        _, u_ref = interop.from_pinocchio_state(robot, q, v_after)
        np.testing.assert_allclose(r.u_after, u_ref, rtol=0, atol=1e-8 * max(1.0, np.abs(u_ref).max()))
        # Internal impulses: the momenta do not change.
        m0, m1 = robot.momentum(x, u), robot.momentum(x, r.u_after)
        assert np.abs(m1.P - m0.P).max() < 1e-11 and np.abs(m1.L_origin - m0.L_origin).max() < 1e-11


def _balls():
    """The two balls of docs/contact.md: a 100 kg base with a ball of 0.3 m, a 1 kg slider along
    x with a ball of 0.2 m; they touch at q = 0.5."""
    b = spacearm.RobotBuilder("balls", 100.0, np.eye(3) * 10.0)
    b.add_link("slider", parent="base", joint="prismatic", axis=(1, 0, 0), mass=1.0, inertia=np.eye(3) * 0.1)
    b.add_geometry("base", "sphere", role="collision", radius=0.3)
    b.add_geometry("slider", "sphere", role="collision", radius=0.2)
    return b.build()


@pytest.mark.parametrize("restitution", [0.0, 0.7])
@pytest.mark.parametrize("solver", ["admm", "pgs"])
def test_two_free_bodies_central_frictionless_impact_closed_form(restitution, solver):
    robot = _balls()
    x = robot.neutral_configuration()
    x[7] = 0.5
    u = robot.zero_velocity()
    u[:3] = [0.1, -0.2, 0.05]  # the pair drifts: no effect on the relative impact
    u[6] = -0.8
    r = solve_impact(robot, x, u, restitution=restitution, solver=solver, friction=0.4, margin=1e-9, pairs=[("base", "slider")], tolerance=1e-13)
    m_r = 100.0 / 101.0
    # λ_n = (1 + e) m_r v_n; the slider rebounds at e v; the base takes the opposite impulse.
    np.testing.assert_allclose(r.impulse_world, [[(1 + restitution) * m_r * 0.8, 0, 0]], atol=1e-12)
    assert abs(r.u_after[6] - restitution * 0.8) < 1e-12
    assert abs(r.u_after[0] - (0.1 - (1 + restitution) * m_r * 0.8 / 100.0)) < 1e-12
    assert r.converged and r.residual <= 1e-10


def _block_on_wall(mu):
    """A 1e12 kg base with a box face at x = 0.5 (a wall) and a 2 kg x-slider carrying a 1 kg
    y-slider with a ball of 0.1 m touching it."""
    big = 1e12
    b = spacearm.RobotBuilder("wall", big, np.eye(3) * big)
    b.add_link("sx", parent="base", joint="prismatic", axis=(1, 0, 0), mass=2.0, inertia=np.eye(3) * 0.1)
    b.add_link("sy", parent="sx", joint="prismatic", axis=(0, 1, 0), mass=1.0, inertia=np.eye(3) * 0.1)
    b.add_geometry("base", "box", role="collision", size=(1.0, 4.0, 4.0))
    b.add_geometry("sy", "sphere", role="collision", radius=0.1)
    return b.build()


@pytest.mark.parametrize("solver", ["admm", "pgs"])
@pytest.mark.parametrize("vy", [0.2, -1.0])
def test_a_block_hitting_a_wall_sticks_or_slides_as_coulomb_says(solver, vy):
    mu, vx = 0.5, -0.4
    robot = _block_on_wall(mu)
    x = robot.neutral_configuration()
    x[7:] = [0.6, 0.3]  # the ball's centre 0.1 m from the face
    u = robot.zero_velocity()
    u[6:] = [vx, vy]
    (c,) = contacts(robot, x, pairs=[("base", "sy")])
    r = solve_impact(robot, x, u, [c], friction=mu, solver=solver, tolerance=1e-12)
    ln = 3.0 * -vx  # both sliders stop along x
    stick = abs(vy) * 1.0 <= mu * ln
    lt = abs(vy) if stick else mu * ln
    np.testing.assert_allclose(r.impulse_world[0], [ln, -np.sign(vy) * lt, 0.0], atol=1e-9)
    vy_after = 0.0 if stick else vy - np.sign(vy) * mu * ln
    np.testing.assert_allclose(r.u_after[6:], [0.0, vy_after], atol=1e-9)
    assert stick == (vy == 0.2)


def test_not_converging_is_reported_and_bad_input_is_refused():
    robot = _balls()
    x = robot.neutral_configuration()
    x[7] = 0.5
    u = robot.zero_velocity()
    u[6] = -0.8
    r = solve_impact(robot, x, u, friction=0.3, max_iterations=1, tolerance=1e-15, margin=1e-9, pairs=[("base", "slider")])
    assert not r.converged and r.iterations == 1 and r.residual > 1e-15
    assert "converged false in 1 iterations" in repr(r)
    with pytest.raises(ArgumentError, match="restitution"):
        solve_impact(robot, x, u, restitution=2.0, margin=1e-9, pairs=[("base", "slider")])
    with pytest.raises(ArgumentError, match="solver"):
        solve_impact(robot, x, u, solver="lemke", margin=1e-9, pairs=[("base", "slider")])
    with pytest.raises(ArgumentError, match="friction coefficient of contact 0"):
        solve_impact(robot, x, u, friction=-0.1, margin=1e-9, pairs=[("base", "slider")])
    with pytest.raises(ArgumentError, match="friction has 2 values for 1 contacts"):
        solve_impact(robot, x, u, friction=[0.1, 0.2], margin=1e-9, pairs=[("base", "slider")])
    with pytest.raises(ArgumentError, match="unit vector"):
        solve_impact(robot, x, u, [("base", "slider", [0.3, 0, 0], [2.0, 0, 0])])
    with pytest.raises(ArgumentError, match="itself"):
        solve_impact(robot, x, u, [("base", "base", [0.3, 0, 0], [1.0, 0, 0])])
    with pytest.raises(spacearm.errors.SpacearmError, match="no body named 'hand'"):
        solve_impact(robot, x, u, [("base", "hand", [0.3, 0, 0], [1.0, 0, 0])])
    with pytest.raises(ArgumentError, match="no contact point"):
        solve_impact(robot, x, u, [])
    with pytest.raises(SpacearmTypeError, match="contact 0 must be"):
        solve_impact(robot, x, u, ["base"])


def test_the_compliant_law_without_stiffness_is_refused():
    # (rigid contact in a run: tests/contact/test_rigid_contact_run.py)
    from spacearm.contact import ContactModel

    robot = _balls()
    with pytest.raises(ArgumentError, match="stiffness is required by the compliant law"):
        spacearm.simulate(robot, 0.01, contact=ContactModel(pairs=[Pair("base", "slider")]))
