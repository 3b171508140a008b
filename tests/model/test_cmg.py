"""Control-moment gyros as two ordinary links (docs/cmg.md, the core's model/cmg.rs): the builder
and TOML ``[[cmg]]`` make the same model, the gyroscopic torque of one CMG on a free hub is the
closed form, the total angular momentum of a pyramid cluster with an arm is conserved in free
floating, and MuJoCo's mass matrix of the exported MJCF is spacearm's."""

from __future__ import annotations

import io

import numpy as np
import pytest

import spacearm
from spacearm.errors import ModelError, SpacearmError
from spacearm.cli.inspect import inspect

from cmg_models import BETA, J_S, pyramid_axes, pyramid_sat, rodrigues  # noqa: E402


def test_builder_and_toml_make_the_same_cmgs_and_inspect_shows_them():
    robot = pyramid_sat(arm=False, variable_speed=True)
    cmgs = robot.cmg_dofs
    assert list(cmgs) == ["cmg1", "cmg2", "cmg3", "cmg4"]
    assert [(c["gimbal"], c["rotor"]) for c in cmgs.values()] == [(0, 1), (2, 3), (4, 5), (6, 7)]
    assert all(c["variable_speed"] for c in cmgs.values()) and robot.actuated_dofs.all()
    assert robot.wheel_dofs == []  # neither link is a reaction wheel
    again = spacearm.io.loads_toml(spacearm.io.dumps_toml(robot))
    assert again.cmg_dofs.keys() == cmgs.keys()
    x = robot.neutral_configuration(q=np.linspace(-1, 1, robot.n_dof))
    np.testing.assert_array_equal(again.mass_matrix(x), robot.mass_matrix(x))
    g, s = pyramid_axes()
    fmt = (lambda v: "[" + ", ".join(repr(float(c)) for c in v) + "]")
    rows = "\n".join(
        f"[[cmg]]\nname = 'cmg{i + 1}'\nposition = {fmt(0.3 * np.cross(g[i], s[i]))}\ngimbal_axis = {fmt(g[i])}\n"
        f"spin_axis = {fmt(s[i])}\nrotor_inertia = {J_S}\ngimbal_inertia = [0.02, 0.015, 0.018]\nrotor_mass = 3.0\n"
        f"gimbal_mass = 1.5\nvariable_speed = true\nmax_wheel_speed = 800.0\n" for i in range(4))
    text = f"[model]\nname = 'cmg-sat'\n[base]\nmass = 200.0\ninertia = [30.0, 34.0, 38.0]\n{rows}"
    from_toml = spacearm.io.loads_toml(text)
    np.testing.assert_allclose(from_toml.mass_matrix(x), robot.mass_matrix(x), rtol=0, atol=1e-15)
    out = io.StringIO()
    inspect(robot, out=out)
    assert "cmg3: VSCMG (spin motor), gimbal dof 4" in out.getvalue()
    # SGCMG: the rotor has no motor; the initial wheel speed goes into u0.
    sg = pyramid_sat(arm=False)
    assert not any(sg.actuated_dofs[[c["rotor"] for c in sg.cmg_dofs.values()]])
    u0 = sg.cmg_velocity(600.0)
    assert np.count_nonzero(u0) == 4 and u0[6 + 1] == 600.0
    with pytest.raises(SpacearmError, match="max_wheel_speed"):
        sg.cmg_velocity(900.0)


def test_bad_cmgs_are_refused_with_their_name():
    b = spacearm.Robot.builder("hub", base_mass=10.0, base_inertia=[1, 1, 1])
    with pytest.raises(ModelError, match="cmg 'c'.*perpendicular"):
        b.add_cmg("c", gimbal_axis=(0, 0, 1), spin_axis=(1, 0, 1), rotor_inertia=0.1)
    with pytest.raises(ModelError, match="max_wheel_torque needs variable_speed"):
        b.add_cmg("c", gimbal_axis=(0, 0, 1), spin_axis=(1, 0, 0), rotor_inertia=0.1, max_wheel_torque=1.0)
    with pytest.raises(ModelError, match="rotor_inertia"):
        b.add_cmg("c", gimbal_axis=(0, 0, 1), spin_axis=(1, 0, 0), rotor_inertia=-0.1)
    with pytest.raises(ModelError, match="parent"):
        b.add_cmg("c", parent="nowhere", gimbal_axis=(0, 0, 1), spin_axis=(1, 0, 0), rotor_inertia=0.1)


@pytest.mark.parametrize("delta", [0.0, 0.7, -2.1])
def test_gyroscopic_torque_of_one_cmg_on_a_free_hub_is_the_closed_form(delta):
    """A hub at rest, one CMG at its CM with the rotor spinning at Ω and the gimbal turning at a
    held rate δ̇ (δ̈ = 0, free rotor): the hub feels h × δ̇ĝ, so
    (I_lock − J_s ŝŝᵀ) ω̇ = −J_s Ω δ̇ (ĝ × ŝ) (docs/cmg.md), with ŝ = R(ĝ, δ) ŝ₀, and the gimbal
    motor's torque is (I_g + J_t) ĝ·ω̇."""
    g, s0 = np.array([0.0, 0.6, 0.8]), np.array([1.0, 0.0, 0.0])
    hub = np.diag([30.0, 34.0, 38.0])
    gim = [0.02, 0.015, 0.018]
    b = spacearm.Robot.builder("hub", base_mass=200.0, base_inertia=hub)
    b.add_cmg("c", gimbal_axis=g, spin_axis=s0, rotor_inertia=J_S, rotor_transverse_inertia=0.03, gimbal_inertia=gim,
              rotor_mass=3.0, gimbal_mass=1.5)
    robot = b.build()
    omega, rate = 600.0, 0.4
    x = robot.neutral_configuration(q=[delta, 0.3])
    u = np.zeros(robot.nu)
    u[6:] = [rate, omega]
    # Forward dynamics is affine in the gimbal torque: pick the torque that holds δ̈ = 0.
    a0 = robot.forward_dynamics(x, u, tau=[0.0, 0.0])
    a1 = robot.forward_dynamics(x, u, tau=[1.0, 0.0]) - a0
    tau_g = -a0[6] / a1[6]
    acc = a0 + tau_g * a1
    s = rodrigues(g, delta) @ s0
    t = np.cross(g, s)
    gimbal_inertia = sum(m * np.outer(a, a) for m, a in zip(gim, (g, rodrigues(g, delta) @ s0, t)))
    rotor_inertia = J_S * np.outer(s, s) + 0.03 * (np.eye(3) - np.outer(s, s))
    lock = hub + gimbal_inertia + rotor_inertia
    wdot = np.linalg.solve(lock - J_S * np.outer(s, s), -J_S * omega * rate * np.cross(g, s))
    assert np.linalg.norm(wdot) > 0.1  # the effect is there
    np.testing.assert_allclose(acc[3:6], wdot, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(acc[:3], 0.0, atol=1e-13)  # every CM at the hub's
    # The free rotor keeps its absolute spin: Ω̇ = −ŝ·ω̇. The rotor inertia's rounding (ε|I|, not
    # exactly symmetric once turned onto a tilted axis) meets Ω² = 3.6e5 rad²/s²: compared at ε Ω².
    eps = np.finfo(float).eps
    np.testing.assert_allclose(acc[7], -s @ wdot, rtol=0, atol=2 * eps * omega**2)
    # τ_g is read off a difference of two forward dynamics: compared at the gyroscopic scale.
    assert abs(tau_g - (gim[0] + 0.03) * g @ wdot) <= 1e-12 * J_S * omega * rate


def test_total_angular_momentum_is_conserved_in_free_floating_with_gimbal_motion():
    robot = pyramid_sat()
    u0 = robot.cmg_velocity([500.0, -450.0, 520.0, -480.0])
    u0[6 + np.array([c["gimbal"] for c in robot.cmg_dofs.values()])] = [0.3, -0.2, 0.25, 0.1]
    u0[6 + robot.n_dof - 2:] = [0.2, -0.3]  # the arm moves too
    x0 = robot.neutral_configuration(q=np.r_[np.zeros(8), 0.3, -0.5])
    traj = spacearm.simulate(robot, 2.0, x0=x0, u0=u0, integrator="dopri5", dt=0.01, rtol=1e-12, atol=1e-12)
    gimbals = traj.x[:, 7 + np.array([0, 2, 4, 6])]
    assert np.ptp(gimbals, axis=0).min() > 0.05  # the gimbals did turn
    L = traj.L_origin
    drift = np.linalg.norm(L - L[0], axis=1).max() / np.linalg.norm(L[0])
    assert drift < 1e-12, drift
    assert np.linalg.norm(L[0]) > 3.0  # the rotors' momenta (25 N m s each) nearly cancel in a pyramid
    print(f"angular momentum drift over 2 s: {drift:.3g} relative")


def test_mujoco_mass_matrix_of_the_exported_cmgs_is_spacearms():
    mujoco = pytest.importorskip("mujoco")
    from spacearm import interop

    robot = pyramid_sat()
    model = interop.to_mujoco(robot)
    data = mujoco.MjData(model)
    rng = np.random.default_rng(3)
    for _ in range(3):
        x = robot.neutral_configuration(q=rng.uniform(-1.5, 1.5, robot.n_dof))
        u = rng.normal(size=robot.nu)
        data.qpos[:], data.qvel[:] = interop.to_mujoco_state(robot, x, u)
        mujoco.mj_forward(model, data)
        full = np.zeros((model.nv, model.nv))
        mujoco.mj_fullM(model, data, full)
        h = interop.mass_matrix_from_mujoco(robot, x, full)
        ref = robot.mass_matrix(x)
        assert np.abs(h - ref).max() <= 1e-12 * np.abs(ref).max()


def test_cmg_steering_holds_the_base_while_the_arm_moves():
    """The pyramid holds the base (rotation-floating) while a joint PD swings the arm: the
    attitude excursion is below the free base's and returns to zero; the arm law sees only the
    arm joints (the gimbals and rotors are momentum devices)."""
    from spacearm.control import CmgSteering, Combined, JointPD

    robot = pyramid_sat()
    assert robot.arm_dofs == [8, 9]
    x0, u0 = robot.neutral_configuration(), robot.cmg_velocity(500.0)
    arm = JointPD(kp=200.0, kd=60.0, reference=[0.8, -0.6])
    run = (lambda c: spacearm.simulate(robot, 4.0, x0=x0, u0=u0, mode="rotation-floating", controller=c, dt=2e-3))
    free, held = run(arm), run(Combined(arm=arm, base=CmgSteering([0, 0, 0, 1], kp=200.0, kd=400.0)))
    angle = (lambda t: 2 * np.arccos(np.clip(np.abs(t.x[:, 6]), 0, 1)))
    assert angle(free).max() > 0.07 and angle(free)[-1] > 0.06  # the arm turns a free base by ~4°
    assert angle(held).max() < 0.75 * angle(free).max() and angle(held)[-1] < 0.005
    np.testing.assert_allclose(held.x[-1, -2:], [0.8, -0.6], atol=1e-3)  # the arm got there
    gimbals = held.x[:, 7 + np.array([0, 2, 4, 6])]
    assert np.ptp(gimbals, axis=0).min() > 0.1  # the cluster did the work
    # Without CMGs, or in another mode, the law refuses with the reason.
    with pytest.raises(SpacearmError, match="control-moment gyros"):
        spacearm.simulate(spacearm.presets.spatial6(), 0.01, mode="rotation-floating",
                          controller=CmgSteering([0, 0, 0, 1], kp=1.0, kd=1.0))
    with pytest.raises(SpacearmError, match="rotation-floating"):
        spacearm.simulate(robot, 0.01, u0=u0, controller=CmgSteering([0, 0, 0, 1], kp=1.0, kd=1.0))
    with pytest.raises(SpacearmError, match="rate_gain"):
        spacearm.simulate(robot, 0.01, u0=u0, mode="rotation-floating", controller=CmgSteering([0, 0, 0, 1], kp=1.0, kd=1.0, rate_gain=0.0))


def test_the_pyramid_momentum_envelope_has_its_closed_forms():
    """Along z each rotor gives h sin β; along x the two gimbals in the xz plane give h cos β and
    the two perpendicular to x give h (docs/cmg.md); a robot's cluster gives the same envelope
    as its axes and momenta."""
    from spacearm.analysis import cmg_envelope

    robot = pyramid_sat(arm=False)
    env = cmg_envelope(robot, wheel_speed=500.0, n=5)
    h = J_S * 500.0
    top, side = env.points[-1, 0], env.points[2, 5]  # elevation +90°; elevation 0, azimuth 0
    np.testing.assert_allclose(env.directions[2, 5], [1, 0, 0], atol=1e-15)
    np.testing.assert_allclose(top, [0, 0, 4 * h * np.sin(BETA)], atol=1e-12)
    np.testing.assert_allclose(side, [h * (2 + 2 * np.cos(BETA)), 0, 0], atol=1e-12)
    again = cmg_envelope(gimbal_axes=pyramid_axes()[0], h=[h] * 4, n=5)
    np.testing.assert_array_equal(again.points, env.points)
    assert env.magnitude.max() <= 4 * h + 1e-12 and env.magnitude.min() > 2 * h  # within Σ h_i, nowhere thin


def test_mujoco_runs_the_exported_cmg_cluster_and_arm_as_spacearm_does_for_2_s():
    """The exported MJCF of a VSCMG pyramid and a two-joint arm under constant gimbal, wheel and
    arm torques, 2 s of RK4 at 2 ms in both (issue 34's validation): every coordinate and rate
    to 1e-8, while either's own step error (against spacearm at dt/2) is far larger."""
    pytest.importorskip("mujoco")
    from sim.test_simulation_validation import mujoco_run

    robot = pyramid_sat(variable_speed=True)
    gimbal, rotor = (np.array([c[k] for c in robot.cmg_dofs.values()]) for k in ("gimbal", "rotor"))
    x0 = robot.neutral_configuration(q=np.r_[np.zeros(8), 0.3, -0.5])
    x0[7 + gimbal] = [0.3, -0.2, 0.5, -0.1]
    u0 = robot.cmg_velocity([500.0, -450.0, 520.0, -480.0])
    u0[3:6], u0[6 + gimbal], u0[-2:] = [0.01, -0.02, 0.015], [0.3, -0.2, 0.25, 0.1], [0.2, -0.3]
    tau = np.zeros(robot.n_dof)
    tau[gimbal], tau[rotor], tau[-2:] = [0.02, -0.01, 0.015, -0.02], [0.05, -0.03, 0.02, 0.04], [0.5, -0.3]
    torque = (lambda t, x, u: tau)
    dt, every = 2e-3, 50
    run = (lambda h: spacearm.simulate(robot, 2.0, x0=x0, u0=u0, dt=h, integrator="rk4",
                                       controller=spacearm.control.Callback(torque), record_every=round(every * dt / h)))
    traj = run(dt)
    t_mj, x_mj, u_mj = mujoco_run(robot, x0, u0, torque, dt, 2.0, every)
    np.testing.assert_allclose(traj.t, t_mj, atol=1e-12)
    quat_gap = np.abs(np.abs(np.einsum("ij,ij->i", traj.x[:, 3:7], x_mj[:, 3:7])) - 1).max()
    d_x = np.abs(np.delete(traj.x - x_mj, [3, 4, 5, 6], axis=1)).max()
    d_u = np.abs(traj.u - u_mj).max()
    step = np.abs(traj.u - run(dt / 2).u).max()
    print(f"spacearm vs MuJoCo, 2 s: |Δx| {d_x:.2e}, |Δu| {d_u:.2e}, 1 − |q·q_mj| {quat_gap:.1e}; step error |u| {step:.2e}")
    assert d_x < 1e-8 and d_u < 1e-8 and quat_gap < 1e-12
    assert step > 100 * d_u  # the two integrate the same ODE: they agree far below its step error
    # Not trivial: the gimbals, wheels, arm and base all moved.
    assert np.abs(traj.u[-1, 6 + rotor] - u0[6 + rotor]).min() > 0.5
    assert np.ptp(traj.x[:, 7 + gimbal], axis=0).min() > 0.1 and np.ptp(traj.x[:, -2:], axis=0).min() > 0.1
    assert np.abs(traj.x[-1, 3:6] - x0[3:6]).max() > 1e-3


def test_the_gsr_dither_and_null_motion_options_hold_the_base_too_and_bad_values_are_refused():
    """The steering law with Wie's dithered GSR inverse and null motion (docs/cmg.md,
    "Steering") holds the base as the SR inverse does; the options change the gimbal motion
    (null motion turns the gimbals without torque, so their angles differ) and the run's
    description carries them; bad values name the option."""
    from spacearm.control import CmgSteering, Combined, JointPD

    robot = pyramid_sat()
    x0, u0 = robot.neutral_configuration(), robot.cmg_velocity(500.0)
    arm = JointPD(kp=200.0, kd=60.0, reference=[0.8, -0.6])
    run = (lambda **o: spacearm.simulate(robot, 3.0, x0=x0, u0=u0, mode="rotation-floating", dt=2e-3,
                                         controller=Combined(arm=arm, base=CmgSteering([0, 0, 0, 1], kp=200.0, kd=400.0, **o))))
    plain, options = run(), run(dither=0.05, null_gain=0.5)
    angle = (lambda t: 2 * np.arccos(np.clip(np.abs(t.x[:, 6]), 0, 1)))
    assert angle(options).max() < 1.05 * angle(plain).max() and angle(options)[-1] < 0.005
    gimbals = 7 + np.array([c["gimbal"] for c in robot.cmg_dofs.values()])
    assert np.abs(options.x[-1, gimbals] - plain.x[-1, gimbals]).max() > 1e-3  # the options did act
    assert np.isfinite(options.x).all()
    for bad, match in [(dict(dither=0.5), "dither must be in"), (dict(dither=0.1, lambda0=0.0), "dither needs lambda0"),
                       (dict(null_gain=-1.0), "null_gain"), (dict(dither_frequency=float("nan")), "dither_frequency")]:
        with pytest.raises(SpacearmError, match=match):
            CmgSteering([0, 0, 0, 1], kp=1.0, kd=1.0, **bad)


def test_the_run_records_the_clusters_singularity_measure_and_envelope_fraction():
    """Every sample of a run with CMGs on the base records the measure det(A Aᵀ)/h̄⁶ and the
    fraction |H|/σ(Ĥ) of the momentum envelope, recomputed here from the recorded states with
    the kinematics and the envelope's closed form (docs/cmg.md)."""
    from scipy.spatial.transform import Rotation

    from spacearm.control import CmgSteering, Combined, JointPD

    robot = pyramid_sat()
    x0, u0 = robot.neutral_configuration(), robot.cmg_velocity(500.0)
    law = Combined(arm=JointPD(kp=200.0, kd=60.0, reference=[0.8, -0.6]), base=CmgSteering([0, 0, 0, 1], kp=200.0, kd=400.0))
    traj = spacearm.simulate(robot, 2.0, x0=x0, u0=u0, mode="rotation-floating", controller=law, dt=2e-3, record_every=25)
    g0, s0 = pyramid_axes()
    cmgs = list(robot.cmg_dofs.values())
    for x, u, m, frac in zip(traj.x, traj.u, traj.cmg_measure, traj.cmg_envelope_fraction):
        r0 = Rotation.from_quat(x[3:7]).as_matrix()
        g = [r0 @ gi for gi in g0]
        s = [r0 @ rodrigues(gi, x[7 + c["gimbal"]]) @ si for gi, si, c in zip(g0, s0, cmgs)]
        h = [J_S * (si @ u[3:6] + u[6 + c["rotor"]]) for si, c in zip(s, cmgs)]
        a = np.column_stack([hi * np.cross(gi, si) for gi, si, hi in zip(g, s, h)])
        hbar = np.mean(np.abs(h))
        assert abs(m - np.linalg.det(a @ a.T) / hbar**6) <= 1e-12 * max(m, 1.0)
        big_h = sum(hi * si for hi, si in zip(h, s))
        if np.linalg.norm(big_h) < 1e-12:  # zero momentum (the start): no direction, fraction 0
            assert frac <= 1e-12
            continue
        e = big_h / np.linalg.norm(big_h)
        extent = sum(abs(hi) * np.linalg.norm(e - (e @ gi) * gi) for gi, hi in zip(g, h))
        assert abs(frac - np.linalg.norm(big_h) / extent) <= 1e-12
    assert traj.cmg_measure[0] == pytest.approx(32 / 27, rel=1e-9)  # the pyramid at δ = 0 (docs/cmg.md)
    assert traj.cmg_envelope_fraction[0] < 1e-12 and traj.cmg_envelope_fraction.max() > 0.01  # zero momentum, then used
    assert np.ptp(traj.cmg_measure) > 0.01
    assert "cmg_measure" in [c[0] for c in traj.columns()]
    assert not spacearm.simulate(spacearm.presets.spatial6(), 0.1).has("cmg_measure")


def test_every_singular_surface_point_is_singular_in_the_core_record_and_the_outer_one_is_the_envelope():
    """cmg_singular_surfaces (docs/cmg.md, "The singular surfaces"): the outer surface (every
    ε_i = +1) is cmg_envelope's; every point of every surface, set as gimbal angles on the robot,
    has the run record's singularity measure (sim/record.rs, through control/cmg_jacobian.rs) 0 to
    1e-10, while the same angles turned by 0.2 rad have it above 1e-5; the pyramid's internal
    elliptic singular state δ = (−90°, 0, 90°, 0) holds H = 2h cos β x̂ on the surface ε = (+, −, +, +)."""
    from spacearm.analysis import cmg_envelope, cmg_singular_surfaces

    robot = pyramid_sat(arm=False)
    surf = cmg_singular_surfaces(robot, wheel_speed=500.0, n=5)
    h = J_S * 500.0
    assert surf.points.shape == (8, 5, 11, 3) and surf.spin_axes.shape == (8, 5, 11, 4, 3)
    np.testing.assert_array_equal(surf.negatives, [0, 1, 1, 1, 2, 2, 2, 3])
    np.testing.assert_allclose(surf.points[0], cmg_envelope(robot, wheel_speed=500.0, n=5).points, atol=1e-12)
    assert np.all(np.linalg.norm(surf.points[1:], axis=-1) < np.linalg.norm(surf.points[0], axis=-1) + 1e-12)
    side = surf.points[list(map(tuple, surf.signs)).index((1, -1, 1, 1)), 2, 5]  # u = x
    np.testing.assert_allclose(side, [2 * h * np.cos(BETA), 0, 0], atol=1e-12)

    g0, s0 = pyramid_axes()
    cmgs = list(robot.cmg_dofs.values())
    u0 = robot.cmg_velocity(500.0)
    # A drifting base: with P = 0 exactly, the run's drift check divides rounding by zero.
    u0[0] = 0.01
    rng = np.random.default_rng(3)
    measures = []
    for k in range(len(surf.signs)):
        for i, j in zip(rng.integers(1, 4, 3), rng.integers(0, 11, 3)):
            s = surf.spin_axes[k, i, j]
            delta = np.array([np.arctan2(si @ np.cross(gi, s0i), si @ s0i) for gi, s0i, si in zip(g0, s0, s)])
            for gi, s0i, si, d in zip(g0, s0, s, delta):  # the spin axes are the gimbals' own
                np.testing.assert_allclose(rodrigues(gi, d) @ s0i, si, atol=1e-14)
            for shift, store in ((0.0, measures), (0.2, None)):
                x0 = robot.neutral_configuration()
                x0[7 + np.array([c["gimbal"] for c in cmgs])] = delta + shift
                m = spacearm.simulate(robot, 1e-3, x0=x0, u0=u0, dt=1e-3).cmg_measure[0]
                if store is None:
                    assert m > 1e-5, (surf.signs[k], delta)
                else:
                    store.append(m)
    assert max(measures) < 1e-10, max(measures)

    with pytest.raises(spacearm.errors.ArgumentError, match=r"\+1 or -1"):
        cmg_singular_surfaces(robot, wheel_speed=500.0, signs=[1, 0.5, 1, 1])
    with pytest.raises(spacearm.errors.ArgumentError, match="no CMG"):
        cmg_singular_surfaces(spacearm.presets.spatial6(), wheel_speed=500.0)


def _zero_crossings(t, y):
    """The times where ``y`` changes sign, each by linear interpolation between its two samples."""
    i = np.nonzero(np.sign(y[:-1]) * np.sign(y[1:]) < 0)[0]
    return t[i] - y[i] * (t[i + 1] - t[i]) / (y[i + 1] - y[i])


@pytest.mark.parametrize("rotor", ["wheel", "cmg"])
def test_a_spinning_rotor_nutates_at_its_closed_form_frequency(rotor):
    """Issue 34's nutation closed form (docs/cmg.md, "Nutation"), against the base rate's zero
    crossings over ~10 periods of a free-floating run. "wheel": a gyrostat, a hub with a free
    wheel of momentum h about z (its CM at the hub's), ω_n = h/√(A B), A and B the system's
    transverse moments (the rotor's J_t included). "cmg": a single-gimbal CMG with a free gimbal
    about x, spin along z: the gimbal and the hub's y rate exchange h, ω_n = h/√(B J_g), J_g the
    gimbal's and rotor's moment about the gimbal axis. The frequency is the mean over all
    crossings; RK4 at 1 ms and linear interpolation of the crossings leave it within 1e-8
    relative (the run at 2 ms differs from the 1 ms one by less than that; the rates of 1e-4
    rad/s keep the nonlinear terms, relative size of the squared amplitude, below it too), far
    below the 0.9 % (wheel) and 58 % (cmg) by which the closed form moves without the rotor's J_t."""
    b = spacearm.Robot.builder("gyro", base_mass=100.0, base_inertia=[30.0, 40.0, 50.0])
    j_t = 0.6 * {"wheel": 0.5, "cmg": 0.05}[rotor]  # the default transverse moment
    if rotor == "wheel":
        b.add_reaction_wheel([0, 0, 1], rotor_inertia=0.5)
        robot = b.build()
        u0 = robot.zero_velocity()
        u0[6], u0[3] = 600.0, 1e-4  # wheel speed; a small x rate to start the nutation
        h, duration = 0.5 * 600.0, 8.0
        expected = h / np.sqrt((30.0 + j_t) * (40.0 + j_t))
    else:
        b.add_cmg("cmg", gimbal_axis=[1, 0, 0], spin_axis=[0, 0, 1], rotor_inertia=0.05,
                  gimbal_inertia=[0.02, 0.015, 0.018], rotor_mass=3.0, gimbal_mass=1.5)
        robot = b.build()
        u0 = robot.cmg_velocity(300.0)
        u0[4] = 1e-4  # a small y rate (the gimbal then swings by ±5e-4 rad)
        h, duration = 0.05 * 300.0, 6.0
        # (ĝ, ŝ0, ĝ × ŝ0) = (x, z, −y): the gimbal's moments 0.02 about x, 0.018 about y.
        expected = h / np.sqrt((40.0 + 0.018 + j_t) * (0.02 + j_t))
    found = []
    for dt in (2e-3, 1e-3):
        traj = spacearm.simulate(robot, duration, u0=u0, dt=dt)
        rate = traj.base_angular_velocity_in_base
        tc = _zero_crossings(traj.t, rate[:, 1])
        assert len(tc) >= 19
        found.append(np.pi * (len(tc) - 1) / (tc[-1] - tc[0]))
        if rotor == "cmg":  # the free gimbal passes no torque about x: the hub's x rate stays 0
            assert np.abs(rate[:, 0]).max() < 1e-9 and np.ptp(traj.q[:, robot.cmg_dofs["cmg"]["gimbal"]]) > 5e-4
    assert abs(found[1] - found[0]) < 1e-8 * expected
    assert found[1] == pytest.approx(expected, rel=1e-8), (found, expected)
