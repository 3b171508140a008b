"""Rigid frictional contact inside a run (docs/contact.md, "Rigid contact in a run";
crates/spacearm-core/src/sim/rigid_contact.rs): each step's cone problem on the Delassus operator,
its impulses applied at the step's start, the smooth motion after them by RK4.

Each quantity two ways: the closed forms of a ball on a very heavy plate (rebound at ``e v``;
resting under a push at the gap ``½ h² F / m`` with the mean normal force ``F``), of a ball pressed
on a plate and sliding with Coulomb friction (stop time ``m v₀ / (μ F_n)``, distance
``m v₀² / (2 μ F_n)``), against the recorded impulses and the recorded momentum; one step's
impulses against ``solve_impact`` (itself checked against Pinocchio 4's solvers in
test_rigid_impact.py) and, where Pinocchio 4 is installed, against its ADMM solver directly.
"""

import numpy as np
import pytest

import spacearm
from spacearm.contact import ContactModel, Pair, solve_impact
from spacearm.control import Callback
from spacearm.sim.events import StopAtRecord, StopAtTime

BIG = 1e12  # the heaviest base the model rules allow: a plate that does not move


def plate(two_axes: bool):
    """A 1e12 kg base with a box (its face x = 0.5 m) and a ball of radius 0.1 m on a slider along x
    (mass 2 kg) and, with ``two_axes``, a second slider along y (1 kg) carrying it: the ball touches
    the face at q_x = 0.6 m."""
    b = spacearm.RobotBuilder("plate", BIG, np.eye(3) * BIG)
    b.add_link("sx", parent="base", joint="prismatic", axis=(1, 0, 0), mass=2.0, inertia=np.eye(3) * 0.1)
    last = "sx"
    if two_axes:
        b.add_link("sy", parent="sx", joint="prismatic", axis=(0, 1, 0), mass=1.0, inertia=np.eye(3) * 0.1)
        last = "sy"
    b.add_geometry("base", "box", role="collision", size=(1.0, 4.0, 4.0))
    b.add_geometry(last, "sphere", role="collision", radius=0.1)
    return b.build(), last


def run(robot, T, q0, qd0, contact, dt=1e-4, controller=None, **kw):
    x0 = robot.neutral_configuration()
    x0[7:] = q0
    u0 = robot.zero_velocity()
    u0[6:] = qd0
    return spacearm.simulate(robot, T, x0=x0, u0=u0, dt=dt, controller=controller, contact=contact, **kw)


@pytest.mark.parametrize("margin", [1e-3, 0.0])
def test_a_ball_rebounds_from_a_heavy_plate_at_the_closed_form_speed(margin):
    robot, ball = plate(False)
    v0, m, dt = 0.4, 2.0, 1e-4
    for e in (1.0, 0.5):
        traj = run(robot, 0.3, [0.65], [-v0], ContactModel(kind="rigid", restitution=e, margin=margin, pairs=[Pair("base", ball)]), dt=dt)
        # Newton's restitution against a plate that does not move: q̇⁺ = e v0.
        assert abs(traj.u[-1, 6] - e * v0) < 1e-9
        # The impulse the ball received: its momentum's change, m (1 + e) v0, recorded and closed form.
        imp = traj.contact_impulse[-1]
        assert abs(imp[0] - m * (1 + e) * v0) < 1e-9 * m * v0 and np.abs(imp[1:]).max() < 1e-15
        v_ball = traj.u[:, 0] + traj.u[:, 6]  # in 𝒥: the plate recoils by 1e-12 m/s, which counts here
        assert abs(imp[0] - m * (v_ball[-1] - v_ball[0])) < 1e-12 * m * v0
        # The impulses' work is the ball's lost kinetic energy ½ m v0² (1 − e²).
        assert abs(traj.contact_work[-1] + 0.5 * m * v0**2 * (1 - e * e)) < 1e-9
        # The ball turns within one step's approach of the face (apart with a margin: it turns at
        # a gap below v0 dt; without one it is found interpenetrating by less than v0 dt).
        q = traj.x[:, 7]
        assert q.min() > 0.6 - (0 if margin else v0 * dt) - 1e-15
        assert q.min() < 0.6 + v0 * dt
        # After the rebound it moves at e v0 from where it turned: the closed-form line to v0 dt.
        t_c = 0.05 / v0
        assert abs(q[-1] - (0.6 + e * v0 * (0.3 - t_c))) < 2 * v0 * dt


def test_a_pushed_ball_comes_to_rest_on_the_plate_with_the_push_as_normal_force():
    robot, ball = plate(False)
    v0, m, dt, F = 0.4, 2.0, 1e-4, 3.0
    push = Callback(lambda t, x, u: np.array([-F]))
    traj = run(robot, 0.4, [0.65], [-v0], ContactModel(kind="rigid", margin=1e-3, pairs=[Pair("base", ball)]), dt=dt, controller=push)
    late = traj.t > 0.3
    # At rest each step's impulse is h F (the step's push), the mean normal force F; the ball
    # sits on the face (its mean velocity over each step 0), its velocity sampled at a step's
    # start −½ h F / m (after the previous step's push, before this step's impulse).
    assert np.abs(traj.contact_normal_force[late] / F - 1).max() < 1e-9
    assert np.abs(traj.x[late, 7] - 0.6).max() < 1e-12
    assert np.abs(traj.u[late, 6] + 0.5 * dt * F / m).max() < 1e-9
    # The impulses: the ball's momentum at impact plus the push's impulse since (its velocity
    # at the end is the sampled −½ h F / m).
    expected = m * v0 + F * traj.t[-1] + m * traj.u[-1, 6]
    assert abs(traj.contact_impulse[-1, 0] - expected) < 1e-9 * expected
    assert traj.contact_count[late].min() == 1


@pytest.mark.parametrize("solver", ["admm", "pgs"])
def test_a_ball_sliding_on_the_plate_stops_by_coulomb_friction_at_the_closed_form_time(solver):
    robot, ball = plate(True)
    mu, Fn, m_y, v0, dt = 0.4, 5.0, 1.0, 1.0, 1e-4
    press = Callback(lambda t, x, u: np.array([-Fn, 0.0]))
    contact = ContactModel(kind="rigid", friction=mu, margin=1e-3, solver=solver, tolerance=1e-13, pairs=[Pair("base", ball)])
    traj = run(robot, 0.8, [0.6, 0.0], [0.0, v0], contact, dt=dt, controller=press)
    a = mu * Fn / m_y  # the friction's deceleration: μ times the normal force, over the sliding mass
    t_stop, distance = v0 / a, v0**2 / (2 * a)
    vy = traj.u[:, 7]
    sliding = traj.t < t_stop - dt
    # While it slides its velocity falls linearly, each step's friction impulse μ h F_n, but for
    # the start: the ball set touching at rest takes half the press's impulse in the second step
    # (it settles at the gap ½ h² F_n / m_x it keeps under a steady press), an offset of ½ a h.
    assert np.abs(vy[sliding] - (v0 - a * traj.t[sliding])).max() < 0.5 * a * dt * (1 + 1e-5)
    assert np.abs(np.diff(vy[sliding][3:]) + a * dt).max() < 1e-12
    # It sticks within a step of the closed-form time, and stays stuck.
    t_stuck = traj.t[np.argmax(np.abs(vy) < 1e-12)]
    assert abs(t_stuck - t_stop) <= dt + 1e-12
    assert np.abs(vy[traj.t > t_stop + dt]).max() < 1e-12
    # The slide: v0² / (2a) (measured to 4e-13 m: the cone problem holds each step's mean
    # velocity, which moves the ball).
    assert abs(traj.x[-1, 8] - distance) < 1e-9
    # The normal impulse per step is h F_n (the press; ½ h F_n in the first step, the start-up),
    # the friction impulse the ball's lost momentum: the recorded impulse's tangential part is −m_y v0.
    assert abs(traj.contact_normal_force[1] / Fn - 0.5) < 1e-8
    assert np.abs(traj.contact_normal_force[2:] / Fn - 1).max() < 1e-8
    assert abs(traj.contact_impulse[-1, 1] + m_y * v0) < 1e-9


def test_a_tangential_push_below_the_cone_sticks_and_above_it_slides_at_the_closed_form_rate():
    robot, ball = plate(True)
    mu, Fn, m_y, dt = 0.4, 5.0, 1.0, 1e-4
    contact = ContactModel(kind="rigid", friction=mu, margin=1e-3, pairs=[Pair("base", ball)])
    for ratio in (0.5, 0.99, 2.0):
        Ft = ratio * mu * Fn
        push = Callback(lambda t, x, u, Ft=Ft: np.array([-Fn, Ft]))
        traj = run(robot, 0.2, [0.6, 0.0], [0.0, 0.0], contact, dt=dt, controller=push)
        if ratio < 1:
            # stuck: it does not move; its velocity sampled at a step's start is the push's
            # ½ h F_t / m_y (its mean over each step 0)
            assert np.abs(traj.x[:, 8]).max() < 1e-12
            assert np.abs(traj.u[1:, 7] - 0.5 * dt * Ft / m_y).max() < 1e-9
        else:
            # sliding at (F_t − μ F_n) / m_y, to the start-up step (see the sliding stop above)
            a = (Ft - mu * Fn) / m_y
            assert np.abs(traj.u[:, 7] - a * traj.t).max() < mu * Fn / m_y * dt
            assert abs(traj.u[-1, 7] - traj.u[-2, 7] - a * dt) < 1e-12


def floating_arm():
    """A floating base of 100 kg with a two-link arm whose tip ball can strike the base's box off
    its centre."""
    b = spacearm.RobotBuilder("arm", 100.0, np.diag([8.0, 9.0, 10.0]))
    b.add_link("l1", parent="base", joint="revolute", axis=(0, 0, 1), origin=(0.6, 0.2, 0), com=(0.4, 0, 0), mass=4.0,
               inertia=np.diag([0.01, 0.2, 0.2]))
    b.add_link("l2", parent="l1", joint="revolute", axis=(0, 0, 1), origin=(0.4, 0, 0), com=(0.3, 0, 0), mass=2.0,
               inertia=np.diag([0.01, 0.06, 0.06]))
    b.add_geometry("base", "box", role="collision", size=(1.0, 1.0, 1.0))
    b.add_geometry("l2", "sphere", role="collision", radius=0.08, origin=(0.3, 0, 0))
    robot = b.build()
    x0 = robot.neutral_configuration()
    x0[7:] = [1.2, 2.0]
    u0 = robot.zero_velocity()
    u0[:6] = [0.01, -0.02, 0.0, 0.0, 0.0, 0.03]
    u0[6:] = [1.5, 2.0]
    return robot, x0, u0


def test_a_floating_arm_striking_its_base_keeps_its_momentum_through_the_impulses():
    # No external force: P and L are kept through the impacts (friction and restitution); the
    # impulses' work closes the energy ledger.
    robot, x0, u0 = floating_arm()
    traj = spacearm.simulate(robot, 1.0, x0=x0, u0=u0, dt=2e-4,
                             contact=ContactModel(kind="rigid", friction=0.3, restitution=0.5, margin=2e-3, pairs=[Pair("base", "l2")]))
    assert traj.contact_count.max() >= 1 and np.abs(traj.contact_impulse[-1]).max() > 0.1  # the arm did strike
    P, L = traj.P, traj.L_origin
    scale_p = 6.0 * np.abs(u0[6:]).max()
    assert np.abs(P - P[0]).max() < 1e-12 * scale_p
    assert traj.meta["drift"]["P"] < 1e-12 and traj.meta["drift"]["L_origin"] < 1e-11
    # The kinetic energy lost in the impacts is the impulses' work (to RK4's accuracy between).
    assert traj.contact_work[-1] < -1e-3
    assert traj.meta["drift"]["energy"] < 1e-9


def test_a_planar_arm_pressed_on_a_face_with_high_friction_keeps_a_solvable_cone_problem():
    # The planar arm of test_contact_dynamics (its joints about the base's z): its tip's contact
    # velocity cannot leave the arm's plane, so G is singular (rank 2), and the face's normal
    # leaves that plane; the gap's bias enters by its part in G's range, without which the
    # problem has no solution (PGS stopped at a residual of 7e-6 m/s at the second step).
    from test_contact_dynamics import arm_and_box
    from spacearm.control import JointPD, TorqueLimit

    robot = arm_and_box()
    x0 = robot.neutral_configuration()
    x0[7:] = [0.3, 0.2]
    u0 = robot.zero_velocity()
    u0[6:] = [4.0, 1.0]
    press = TorqueLimit(JointPD(kp=[1e6, 1e6], kd=[0.0, 0.0], reference=[3.0, 3.0]), limit=5.0)
    contact = ContactModel(kind="rigid", friction=2.0, margin=1e-3, solver="pgs", pairs=[Pair("base", "l2")])
    traj = spacearm.simulate(robot, 1.2, x0=x0, u0=u0, dt=1e-4, record_every=1, controller=press, contact=contact)
    assert (traj.contact_count > 0).sum() > 100  # pressed on the face for many steps
    assert traj.meta["drift"]["P"] < 1e-11 and traj.meta["drift"]["L_origin"] < 1e-10


def test_the_step_by_step_simulator_takes_the_same_steps():
    # spacearm.Simulator steps the same core stepper: the same rebound, bit for bit.
    robot, ball = plate(False)
    contact = ContactModel(kind="rigid", restitution=0.5, margin=1e-3, pairs=[Pair("base", ball)])
    traj = run(robot, 0.2, [0.65], [-0.4], contact)
    sim = spacearm.Simulator(robot, dt=1e-4, contact=contact, record_every=1)
    x0 = robot.neutral_configuration()
    x0[7] = 0.65
    u0 = robot.zero_velocity()
    u0[6] = -0.4
    sim.reset(x0, u0)
    sim.step(n=2000)
    assert abs(sim.time - 0.2) < 1e-12
    np.testing.assert_array_equal(sim.u, traj.u[-1])
    np.testing.assert_array_equal(sim.trajectory().contact_impulse[-1], traj.contact_impulse[-1])


def test_one_step_takes_the_impulses_of_solve_impact():
    # The ball touching the plate (d = 0), approaching and slipping, no force: the first step's
    # cone problem is solve_impact's at (x0, u0) — free velocity J u0, Newton's restitution.
    robot, ball = plate(True)
    for vy, solver in ((0.2, "admm"), (1.0, "admm"), (1.0, "pgs")):
        contact = ContactModel(kind="rigid", friction=0.5, restitution=0.3, solver=solver, pairs=[Pair("base", ball)])
        traj = run(robot, 2e-4, [0.6, 0.3], [-0.4, vy], contact, dt=1e-4)
        r = solve_impact(robot, traj.x[0], traj.u[0], friction=0.5, restitution=0.3, solver=solver, pairs=[("base", ball)], margin=1e-12)
        assert r.converged
        assert np.abs(traj.contact_impulse[1] - r.impulse_world.sum(axis=0)).max() < 1e-10
        assert np.abs(traj.u[1] - r.u_after).max() < 1e-10


def test_one_step_takes_pinocchios_admm_impulses():
    # The first step in which the arm's tip strikes the base: its cone problem rebuilt with
    # Pinocchio's constraint Jacobian and Delassus operator (the free velocity u + ½ h u̇ from the
    # recorded u̇ at the step's start, the gap's bias d / h) and solved by Pinocchio's ADMM.
    pytest.importorskip("pinocchio")
    from test_rigid_impact import _pinocchio_problem, _pinocchio_solve

    from spacearm import interop
    from spacearm.contact import contacts

    robot, x0, u0 = floating_arm()
    h, mu = 2e-4, 0.3
    contact = ContactModel(kind="rigid", friction=mu, margin=2e-3, tolerance=1e-13, max_iterations=100000, pairs=[Pair("base", "l2")])
    traj = spacearm.simulate(robot, 0.6, x0=x0, u0=u0, dt=h, contact=contact)
    k = int(np.argmax(traj.contact_count > 0)) - 1  # the sample at the start of the first step with an impulse
    assert k >= 0
    x, u = traj.x[k], traj.u[k]
    u_free = u + 0.5 * h * traj.du[k]
    (c,) = contacts(robot, x, pairs=[("base", "l2")], margin=2e-3)
    point = ("base", "l2", 0.5 * (np.asarray(c.point_a) + np.asarray(c.point_b)), c.normal)
    pin, model, q, v, J, M, G, models, datas = _pinocchio_problem(robot, x, u_free, [point], mu)
    g = J @ v + np.array([0.0, 0.0, max(c.distance, 0.0) / h + min(c.distance, 0.0) * 0.2 / h])
    lam = _pinocchio_solve(pin, "admm", G, g, models, datas)
    R = solve_impact(robot, x, u, [point]).frames[0]
    step = traj.contact_impulse[k + 1] - traj.contact_impulse[k]
    assert np.linalg.norm(lam) > 1e-3
    np.testing.assert_allclose(step, R @ lam, rtol=0, atol=1e-8 * np.abs(lam).max())


def test_bad_combinations_are_refused():
    robot, ball = plate(False)
    rigid = ContactModel(kind="rigid", pairs=[Pair("base", ball)])
    with pytest.raises(spacearm.ArgumentError, match="integrator=\"rk4\""):
        run(robot, 0.01, [0.65], [0.0], rigid, integrator="dopri5")
    with pytest.raises(spacearm.ArgumentError, match="no stiffness or damping"):
        run(robot, 0.01, [0.65], [0.0], ContactModel(kind="rigid", stiffness=1e4))
    with pytest.raises(spacearm.ArgumentError, match="restitution is a setting of the rigid contact"):
        run(robot, 0.01, [0.65], [0.0], ContactModel(stiffness=1e4, restitution=0.5))
    with pytest.raises(spacearm.ArgumentError, match="restitution must be in"):
        run(robot, 0.01, [0.65], [0.0], ContactModel(kind="rigid", restitution=1.5))
    with pytest.raises(spacearm.ArgumentError, match="solver"):
        run(robot, 0.01, [0.65], [0.0], ContactModel(kind="rigid", solver="lcp"))
    with pytest.raises(spacearm.ArgumentError, match="time stop conditions only"):
        run(robot, 0.01, [0.65], [0.0], rigid, stop=StopAtRecord("tracking_error", above=1.0))
    run(robot, 0.01, [0.65], [0.0], rigid, stop=StopAtTime(0.005))  # a time condition is taken
    t = spacearm.RobotBuilder("rock", 2.0, np.eye(3) * 0.1, base_name="rock")
    t.add_geometry("rock", "sphere", role="collision", radius=0.2)
    s0 = np.array([2.0, 0, 0, 0, 0, 0, 1, -0.5, 0, 0, 0, 0, 0])
    with pytest.raises(spacearm.ArgumentError, match="rigid contact .* with a free target is not implemented yet"):
        spacearm.simulate(robot, 0.01, contact=ContactModel(kind="rigid"), target=t.build(), target_state=s0)
    # nor with a target flying in the loop of contact in a run with topology events
    from target_scene import scene
    from spacearm.events import Attach

    arm, rock, s_rock, u_arm, _ = scene()
    with pytest.raises(spacearm.ArgumentError, match="rigid contact .* with a free target is not implemented yet"):
        spacearm.simulate(arm, 0.01, u0=u_arm, dt=1e-3, contact=ContactModel(kind="rigid"), target=rock, target_state=s_rock,
                          events=[Attach(point="tip", grasp="handle", gap=0.01, speed=0.01)])
