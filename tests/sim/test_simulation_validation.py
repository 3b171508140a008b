"""Validation of spacearm.simulate against independent solutions.

(a) spatial6 floating under prescribed joint torques against MuJoCo's RK4 on the same model;
(b) torque-free axisymmetric rigid body against its closed-form solution (body-frame precession,
    attitude as precession about the fixed angular momentum composed with a body spin);
(c) the intermediate-axis (Dzhanibekov) flip against the Jacobi-elliptic solution (mpmath);
(d) zero-torque spatial6 with non-zero velocities: P, L_origin and energy, recomputed from the
    recorded states through the mass matrix, drift < 1e-9 relative over 10 s at 1 ms RK4;
(e) the system CM, computed from the bodies' positions, stays fixed to 1e-9 m in floating mode
    with zero initial momentum under a non-trivial torque history.

Every tolerance is stated with its reason next to the assertion. The observed errors are
printed (``pytest -s``) so the report quotes them.
"""

import math

import mpmath
import numpy as np
import pytest

import spacearm
from spacearm.rotations import quat_from_axis_angle, quat_to_matrix


# ---------------------------------------------------------------------------------------------
# helpers
# ---------------------------------------------------------------------------------------------
def rotation_about(axis, angle):
    """Rodrigues' formula: rotation by ``angle`` about the unit vector ``axis``."""
    k = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(angle) * kx + (1 - math.cos(angle)) * kx @ kx


def rotation_angle_between(ra, rb):
    """Angle (rad) of ``ra rbᵀ``, from ``|ra − rb|_F = 2√2 sin(θ/2)`` (accurate for small
    angles, unlike the arccos of the trace, which cannot resolve angles below ~1e-8)."""
    return 2.0 * math.asin(min(1.0, np.linalg.norm(ra - rb) / (2.0 * math.sqrt(2.0))))


def rigid_body(inertia_diag, mass=10.0):
    return spacearm.Robot.builder("rigid", base_mass=mass, base_inertia=list(inertia_diag)).build()


def body_masses(robot):
    d = robot.describe()
    return np.array([d["base"]["mass"]] + [link["mass"] for link in d["links"]])


# ---------------------------------------------------------------------------------------------
# (b) torque-free axisymmetric body
# ---------------------------------------------------------------------------------------------
I_T, I_A = 2.0, 3.2  # transverse and axial moments, kg m^2 (axis = body z)


def axisymmetric_reference(r_init, w_body0, v0, r0, t):
    """Closed form of the torque-free axisymmetric top (e.g. Landau & Lifshitz §33).

    Body rates: ``ω_b(t) = Rz(λ t) ω_b(0)`` with ``λ = (I_A − I_T)/I_T ω_3`` (Euler's
    equations: ``d/dt (ω1 + i ω2) = i λ (ω1 + i ω2)``, ``ω3`` constant). Attitude:
    ``R(t) = exp(Ω_p t l̂×) R(0) Rz(−λ t)`` with ``L = R(0) I ω_b(0)`` fixed in space and
    ``Ω_p = |L| / I_T`` (its angular velocity is ``Ω_p l̂ − λ R e3``, whose body components are
    ``I ω_b / I_T − λ e3 = ω_b``). The CM moves uniformly.
    """
    inertia = np.diag([I_T, I_T, I_A])
    lam = (I_A - I_T) / I_T * w_body0[2]
    ell = r_init @ inertia @ w_body0
    omega_p = np.linalg.norm(ell) / I_T
    w_b = rotation_about([0, 0, 1], lam * t) @ w_body0
    rot = rotation_about(ell, omega_p * t) @ r_init @ rotation_about([0, 0, 1], -lam * t)
    return w_b, rot, r0 + v0 * t, ell


def run_axisymmetric(dt, duration, record_every=1):
    robot = rigid_body([I_T, I_T, I_A])
    quat0 = quat_from_axis_angle([0.3, -0.5, 0.8], 1.1)
    r_init = quat_to_matrix(quat0)
    w_body0 = np.array([0.4, -0.3, 1.5])
    v0, r0 = np.array([0.1, 0.2, -0.05]), np.array([1.0, 2.0, 3.0])
    x0 = np.concatenate([r0, quat0])
    u0 = np.concatenate([v0, r_init @ w_body0])
    traj = spacearm.simulate(robot, duration, x0=x0, u0=u0, dt=dt, integrator="rk4", record_every=record_every)
    err_w = err_rot = err_pos = err_l = 0.0
    for k in range(len(traj)):
        w_b, rot, pos, ell = axisymmetric_reference(r_init, w_body0, v0, r0, traj.t[k])
        err_w = max(err_w, np.linalg.norm(traj.base_angular_velocity_in_base[k] - w_b))
        err_rot = max(err_rot, rotation_angle_between(traj.base_rotation[k], rot))
        err_pos = max(err_pos, np.linalg.norm(traj.base_position[k] - pos))
        err_l = max(err_l, np.linalg.norm(traj.L_com[k] - ell))
    return traj, err_w, err_rot, err_pos, err_l


def test_b_axisymmetric_body_matches_closed_form():
    traj, err_w, err_rot, err_pos, err_l = run_axisymmetric(1e-3, 10.0, record_every=20)
    print(f"\n(b) axisymmetric, 10 s at dt = 1 ms: |w_b err| {err_w:.2e} rad/s, attitude err {err_rot:.2e} rad, "
          f"position err {err_pos:.2e} m, |L err| {err_l:.2e} N m s")
    # Not trivial: the body rates precess through several turns (λ = 0.9 rad/s over 10 s) and
    # the attitude sweeps large angles.
    lam = (I_A - I_T) / I_T * 1.5
    assert lam * 10.0 > 2 * np.pi
    assert np.max(traj.base_rotation_angle) > 2.0
    # RK4's global error is about T (ω dt)^4 ω ~ 10 · (1.6e-3)^4 · 1.6 ≈ 1e-10; 1e-8 leaves
    # room for the rounding of 10^4 steps while a wrong model or formula gives errors of O(1).
    assert err_w < 1e-8
    assert err_rot < 1e-8
    assert err_pos < 1e-10  # uniform motion: RK4 is exact up to rounding
    assert err_l < 1e-8


def test_b_axisymmetric_error_is_fourth_order():
    """With steps large enough for truncation to dominate rounding, halving dt divides the
    error by 2^4 = 16: the simulator converges to the closed form at RK4's order."""
    _, ew1, er1, _, _ = run_axisymmetric(0.04, 8.0)
    _, ew2, er2, _, _ = run_axisymmetric(0.02, 8.0)
    print(f"\n(b) order: dt 0.04 -> 0.02: w_b err {ew1:.2e} -> {ew2:.2e} (ratio {ew1 / ew2:.1f}), "
          f"attitude err {er1:.2e} -> {er2:.2e} (ratio {er1 / er2:.1f})")
    assert ew1 > 1e-7  # truncation, not rounding, at the coarse step
    assert 12.0 < ew1 / ew2 < 20.0
    assert 12.0 < er1 / er2 < 20.0


# ---------------------------------------------------------------------------------------------
# (c) intermediate-axis flip
# ---------------------------------------------------------------------------------------------
I_ASYM = (1.0, 2.0, 2.5)  # I1 < I2 < I3, kg m^2


def intermediate_axis_reference(w0, t_values):
    """Body rates of a torque-free body with ``I1 < I2 < I3`` started at ``ω = (0, Ω, ε)``,
    ``ε > 0`` (so ``M² > 2E I2``: Landau & Lifshitz §37):

    ``ω = (A1 cn τ, A2 sn τ, A3 dn τ)``, ``τ = s t + K(m)``
    with ``s = sqrt((I3 − I2)(M² − 2E I1)/(I1 I2 I3))``,
    ``m = k² = (I2 − I1)(2E I3 − M²)/((I3 − I2)(M² − 2E I1))``,
    ``A1² = (2E I3 − M²)/(I1 (I3 − I1))``, ``A2² = (2E I3 − M²)/(I2 (I3 − I2))``,
    ``A3² = (M² − 2E I1)/(I3 (I3 − I1))``. The offset K(m) puts t = 0 at ``sn = 1, cn = 0``.
    ``ω2 = A2 sn τ`` changes sign at ``τ = 2jK``: ``t_j = (2j − 1) K / s``.
    Returns the rates ``(len(t), 3)`` and the function giving ``t_j``.
    """
    i1, i2, i3 = I_ASYM
    e2 = i1 * w0[0] ** 2 + i2 * w0[1] ** 2 + i3 * w0[2] ** 2
    m2 = (i1 * w0[0]) ** 2 + (i2 * w0[1]) ** 2 + (i3 * w0[2]) ** 2
    s = math.sqrt((i3 - i2) * (m2 - e2 * i1) / (i1 * i2 * i3))
    m = (i2 - i1) * (e2 * i3 - m2) / ((i3 - i2) * (m2 - e2 * i1))
    a1 = math.sqrt((e2 * i3 - m2) / (i1 * (i3 - i1)))
    a2 = math.sqrt((e2 * i3 - m2) / (i2 * (i3 - i2)))
    a3 = math.sqrt((m2 - e2 * i1) / (i3 * (i3 - i1)))
    with mpmath.workdps(30):
        kk = mpmath.ellipk(m)
        out = np.array([[float(a1 * mpmath.ellipfun("cn", s * t + kk, m=m)),
                         float(a2 * mpmath.ellipfun("sn", s * t + kk, m=m)),
                         float(a3 * mpmath.ellipfun("dn", s * t + kk, m=m))] for t in t_values])
        k_float = float(kk)
    return out, (lambda j: (2 * j - 1) * k_float / s), m


def sign_changes(t, y):
    """Times where ``y`` changes sign, by linear interpolation between samples."""
    idx = np.nonzero(np.sign(y[:-1]) * np.sign(y[1:]) < 0)[0]
    return t[idx] - y[idx] * (t[idx + 1] - t[idx]) / (y[idx + 1] - y[idx])


def test_c_intermediate_axis_flip_matches_elliptic_solution():
    robot = rigid_body(I_ASYM)
    w0 = np.array([0.0, 2.0, 0.15])  # 4° from the intermediate axis
    quat0 = quat_from_axis_angle([1.0, 1.0, 0.0], 0.4)
    r_init = quat_to_matrix(quat0)
    x0 = np.concatenate([[0.0, 0.0, 0.0], quat0])
    u0 = np.concatenate([[0.0, 0.0, 0.0], r_init @ w0])
    duration = 24.0
    traj = spacearm.simulate(robot, duration, x0=x0, u0=u0, dt=1e-3, integrator="rk4", record_every=10)
    w_sim = traj.base_angular_velocity_in_base
    ref, flip_time, m = intermediate_axis_reference(w0, traj.t[::10])
    # Self-check of the formula at t = 0 (amplitudes and phase) before using it.
    np.testing.assert_allclose(ref[0], w0, atol=1e-12)
    flips = sign_changes(traj.t, w_sim[:, 1])
    predicted = np.array([flip_time(j) for j in range(1, len(flips) + 1)])
    err_w = float(np.max(np.linalg.norm(w_sim[::10] - ref, axis=1)))
    print(f"\n(c) Dzhanibekov, m = k^2 = {m:.6f}: {len(flips)} flips at {np.round(flips, 4)} s, predicted "
          f"{np.round(predicted, 4)} s; max |flip time err| {np.max(np.abs(flips - predicted)):.2e} s; "
          f"max |w_b err| {err_w:.2e} rad/s")
    # Not trivial: omega_2 reverses (from +2 to -2 rad/s) at least 3 times.
    assert len(flips) >= 3
    assert np.min(w_sim[:, 1]) < -1.9 and np.max(w_sim[:, 1]) > 1.9
    # The flip times (8 s apart, 2K(m)/s with m = 0.9896) agree to 1e-6 s: RK4's phase error
    # is ~1e-10 s, and ω2 has an inflection at its zeros, so the linear interpolation across
    # the 10 ms samples errs by O(Δt³ |ω2‴/ω2′|) ≈ 1e-7 s.
    np.testing.assert_allclose(flips, predicted, atol=1e-6)
    # The whole history: RK4's global error is about T (ω dt)^4 ω ≈ 24 · (2e-3)^4 · 2 ≈ 1e-9,
    # times a modest growth through the unstable flips; a wrong inertia or sign gives O(1).
    assert err_w < 1e-8


# ---------------------------------------------------------------------------------------------
# (d) zero-torque spatial6: conservation recomputed from the recorded states
# ---------------------------------------------------------------------------------------------
def test_d_zero_torque_spatial6_conserves_momentum_and_energy():
    robot = spacearm.presets.spatial6()
    rng = np.random.default_rng(7)
    x0 = robot.neutral_configuration(robot.initial_q + rng.uniform(-0.3, 0.3, 6), r0=(2.0, -1.0, 0.5),
                                     quat0=quat_from_axis_angle([0.2, 1.0, -0.4], 0.7))
    u0 = np.concatenate([[0.05, -0.02, 0.03], [0.02, -0.03, 0.04], rng.uniform(-0.8, 0.8, 6)])
    traj = spacearm.simulate(robot, 10.0, x0=x0, u0=u0, dt=1e-3, integrator="rk4", record_every=50)
    assert traj.t[-1] == pytest.approx(10.0)
    # Independent of the simulator's momentum bookkeeping: [P; L_base] = (H u)[:6] (eqs.
    # 38-42, CRBA), L_origin = L_base + r0 × P, T = ½ uᵀ H u, at every recorded sample.
    p, l_o, e = [], [], []
    for x, u in zip(traj.x, traj.u):
        h = robot.mass_matrix(x)
        hu = h @ u
        p.append(hu[:3])
        l_o.append(hu[3:6] + np.cross(x[:3], hu[:3]))
        e.append(0.5 * u @ hu)
    p, l_o, e = np.array(p), np.array(l_o), np.array(e)
    drift = {name: float(np.max(np.linalg.norm((v - v[0]).reshape(len(v), -1), axis=1)) / np.linalg.norm(v[0]))
             for name, v in (("P", p), ("L_origin", l_o), ("energy", e))}
    print(f"\n(d) spatial6 zero torque, 10 s at 1 ms: relative drift {', '.join(f'{k} {v:.2e}' for k, v in drift.items())}; "
          f"Trajectory.drift() {traj.drift(['P', 'L_origin', 'energy'])}")
    # Not trivial: the initial values are far from zero and the system really moves.
    assert np.linalg.norm(p[0]) > 10.0 and np.linalg.norm(l_o[0]) > 10.0 and e[0] > 1.0
    assert np.max(np.abs(traj.q - traj.q[0])) > 1.0  # the joints swing by more than a radian
    assert traj.base_rotation_angle.max() > 0.05
    # The contract: < 1e-9 relative over 10 s at 1 ms RK4.
    for name, v in drift.items():
        assert v < 1e-9, name
    # The recorded momenta (the simulator's own) agree with the recomputation.
    np.testing.assert_allclose(traj.P, p, rtol=0, atol=1e-10 * np.linalg.norm(p[0]))
    np.testing.assert_allclose(traj.L_origin, l_o, rtol=0, atol=1e-10 * np.linalg.norm(l_o[0]))
    np.testing.assert_allclose(traj.energy, e, rtol=1e-10)


# ---------------------------------------------------------------------------------------------
# (e) the system CM stays put under internal torques
# ---------------------------------------------------------------------------------------------
def prescribed_torque(t, x, u):
    """Smooth joint torques (N m), different on every joint: a non-trivial internal history."""
    amp = np.array([4.0, 7.0, 5.0, 1.0, 0.8, 0.5])
    freq = np.array([0.7, 1.1, 0.9, 1.7, 2.3, 1.3])
    return amp * np.sin(freq * t + np.arange(6))


def test_e_system_cm_fixed_under_internal_torques():
    robot = spacearm.presets.spatial6()
    x0 = robot.neutral_configuration(r0=(0.5, -0.2, 0.1), quat0=quat_from_axis_angle([0, 0, 1], 0.3))
    traj = spacearm.simulate(robot, 5.0, x0=x0, dt=1e-3, integrator="rk4",
                             controller=spacearm.control.Callback(prescribed_torque), record_every=10)
    # CM from the bodies' positions: r_g = Σ m_i r_i / Σ m_i (forward kinematics + masses).
    masses = body_masses(robot)
    cm = np.array([masses @ robot.forward_kinematics(x).com_in_world / masses.sum() for x in traj.x])
    moved = float(np.max(np.linalg.norm(cm - cm[0], axis=1)))
    base_moved = float(np.max(np.linalg.norm(traj.base_position - traj.base_position[0], axis=1)))
    ee = np.array([robot.point_position(x) for x in traj.x])
    ee_moved = float(np.max(np.linalg.norm(ee - ee[0], axis=1)))
    print(f"\n(e) spatial6 under prescribed torques, 5 s: system CM moved {moved:.2e} m while the base "
          f"moved {base_moved:.3f} m and the end effector {ee_moved:.3f} m")
    # Not trivial: the torques swing the arm and push the base around.
    assert base_moved > 0.01 and ee_moved > 0.3
    assert np.max(np.abs(traj.tau)) > 5.0
    # Zero initial momentum and internal torques only: r_g is constant (paper §3). 1e-9 m is
    # the contract. RK4 does not keep r_g exactly (it is a nonlinear function of the
    # configuration): ~8e-11 m here, falling 16x per halving of dt (truncation, not rounding).
    assert moved < 1e-9


# ---------------------------------------------------------------------------------------------
# (a) against MuJoCo: same model, same RK4 step, same torque history
# ---------------------------------------------------------------------------------------------
def mujoco_run(robot, x0, u0, torque, dt, duration, every):
    """MuJoCo's RK4 (``mj_step``) on ``interop.to_mujoco(robot)`` (zero gravity, no contacts),
    joint torques from ``torque(t)`` set in a control callback, which MuJoCo calls at every RK4
    stage with the stage's time: the same continuous-time input as spacearm's controller, which
    is also evaluated per stage. Returns the spacearm-layout states every ``every`` steps."""
    mujoco = pytest.importorskip("mujoco")
    from spacearm import interop

    model = interop.to_mujoco(robot)
    model.opt.timestep = dt
    model.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
    assert np.all(model.opt.gravity == 0)
    data = mujoco.MjData(model)
    data.qpos[:], data.qvel[:] = interop.to_mujoco_state(robot, x0, u0)
    order = interop.engine_dof_order(robot)

    def control(m, d):
        # Joint torques only (the free joint gets none): qfrc = T_mjᵀ [0; 0; τ] = [0; 0; τ[order]].
        d.qfrc_applied[:6] = 0.0
        d.qfrc_applied[6:] = torque(d.time, None, None)[order]

    xs, us, ts = [], [], []
    mujoco.set_mjcb_control(control)
    try:
        steps = int(round(duration / dt))
        for s in range(steps + 1):
            if s % every == 0:
                x, u = interop.from_mujoco_state(robot, data.qpos, data.qvel)
                xs.append(x), us.append(u), ts.append(data.time)
            if s < steps:
                mujoco.mj_step(model, data)
    finally:
        mujoco.set_mjcb_control(None)
    return np.array(ts), np.array(xs), np.array(us)


def state_difference(traj, t_mj, x_mj, u_mj):
    """Largest differences over the samples: base position (m), base attitude (rad), joint
    angles (rad), generalized velocity (m/s, rad/s)."""
    np.testing.assert_allclose(traj.t, t_mj, atol=1e-9)
    d_pos = np.max(np.linalg.norm(traj.base_position - x_mj[:, :3], axis=1))
    d_att = max(rotation_angle_between(quat_to_matrix(a), quat_to_matrix(b)) for a, b in zip(traj.base_quat, x_mj[:, 3:7]))
    d_q = np.max(np.abs(traj.q - x_mj[:, 7:]))
    d_u = np.max(np.abs(traj.u - u_mj))
    return d_pos, d_att, d_q, d_u


def test_a_spatial6_under_prescribed_torques_matches_mujoco():
    robot = spacearm.presets.spatial6()
    rng = np.random.default_rng(11)
    x0 = robot.neutral_configuration(robot.initial_q + rng.uniform(-0.3, 0.3, 6), r0=(0.3, 0.1, -0.2),
                                     quat0=quat_from_axis_angle([1.0, -0.5, 0.3], 0.6))
    u0 = np.concatenate([[0.02, -0.01, 0.03], [0.01, 0.02, -0.015], rng.uniform(-0.3, 0.3, 6)])
    duration, dt = 3.0, 1e-3
    torque = spacearm.control.Callback(prescribed_torque)
    traj = spacearm.simulate(robot, duration, x0=x0, u0=u0, dt=dt, integrator="rk4", controller=torque, record_every=20)
    t_mj, x_mj, u_mj = mujoco_run(robot, x0, u0, prescribed_torque, dt, duration, 20)
    d_pos, d_att, d_q, d_u = state_difference(traj, t_mj, x_mj, u_mj)
    # The integration error of either at this step, against spacearm at dt/10 (same samples).
    fine = spacearm.simulate(robot, duration, x0=x0, u0=u0, dt=dt / 10, integrator="rk4", controller=torque, record_every=200)
    e_q = np.max(np.abs(traj.q - fine.q))
    e_u = np.max(np.abs(traj.u - fine.u))
    print(f"\n(a) spatial6 vs MuJoCo RK4, 3 s at dt = 1 ms: max |Δr0| {d_pos:.2e} m, max base attitude "
          f"Δ {d_att:.2e} rad, max |Δq| {d_q:.2e} rad, max |Δu| {d_u:.2e}; integration error of either "
          f"(vs dt/10): |q| {e_q:.2e} rad, |u| {e_u:.2e}")
    # Not trivial: the joints swing and the base turns and moves under the torques.
    assert np.max(np.abs(traj.q - traj.q[0])) > 0.5
    assert traj.base_rotation_angle.max() > 0.02
    assert e_u > 1e-8  # the step is coarse enough for truncation to show
    # Both are RK4 at the same step on the same ODE (MuJoCo integrates the base attitude with
    # the exponential map, spacearm the quaternion's components then renormalizes: the same
    # to O(dt^5) per step). So they agree (i) to 1e-9 in absolute terms and (ii) over a
    # hundred times more closely than either agrees with the exact solution: they compute the
    # same discrete trajectory. A modelling or convention error would give O(1e-3) or more.
    assert d_pos < 1e-9 and d_att < 1e-9 and d_q < 1e-9 and d_u < 1e-9
    assert d_q < 1e-2 * e_q and d_u < 1e-2 * e_u
