"""Every native control law through the three doors of the core's loop (issue 32): the same
controller spec run by ``spacearm.simulate`` (RK4), by the C stepper (``libspacearm_c`` through
ctypes, the options' ``[controller]`` table written by ``spacearm_options_with_controller``
from ``ControllerSpec.to_toml()``) and by an exported FMU under FMPy gives the **same states,
bit for bit**, at every communication point, for FMI 3 and FMI 2.

The three runs share nothing but the spec and the core: a law the C stepper or the FMU builds
differently from ``spacearm.simulate`` (another default, a gain broadcast otherwise, a point
resolved elsewhere, a reference evaluated at another time) shows as a difference. The step is a
power of two and every time a multiple of it, so no door rounds a time its own way. Each run
must also move the state (a frozen or empty run would pass the equality trivially).
"""

from __future__ import annotations

import ctypes

import numpy as np
import pytest

import spacearm
import spacearm.fmi
from spacearm import _core
from spacearm._util.spec import controller_spec
from spacearm.control import (MPC, AttitudeControl, BaseThrusterControl, CartesianLine, CmgSteering, Combined, ComputedTorque,
                              CoordinatedFlying, JointPD, MomentumDamping, QuinticJoint, ResolvedMotionRate, TorqueLimit)
from spacearm.fmi import library

fmpy = pytest.importorskip("fmpy", reason="FMPy (a test extra) runs the FMUs")
from fmpy.validation import validate_fmu  # noqa: E402

DT = 2.0**-9  # the RK4 step, s (exact in binary)
EVERY = 8  # RK4 steps per communication step
POINTS = 40  # communication steps per run
H = EVERY * DT
DURATION = POINTS * H
D = ctypes.POINTER(ctypes.c_double)


def wheels_robot() -> spacearm.Robot:
    return spacearm.io.load_toml(spacearm.examples.path("spatial6_wheels"))


def cmg_robot() -> spacearm.Robot:
    from cmg_models import pyramid_sat
    return pyramid_sat()


def vscmg_robot() -> spacearm.Robot:
    """The pyramid of VSCMGs with the two-joint arm, written as URDF and read back (docs/urdf.md)."""
    from cmg_models import pyramid_sat
    from spacearm.io.urdf import loads_urdf
    from spacearm.io.urdf_export import to_urdf
    return loads_urdf(to_urdf(pyramid_sat(variable_speed=True)))


def _line(robot, delta, t_end=0.05) -> CartesianLine:
    """A line of the end effector from where it starts, by ``delta`` (m) over ``[0, t_end]``."""
    p0 = robot.point_position(robot.neutral_configuration())
    return CartesianLine(p0, p0 + np.asarray(delta), 0.0, t_end)


def _laws():
    """(name, robot, mode, controller, u0) of every native law."""
    s6 = spacearm.presets.spatial6
    q0 = s6().initial_q
    d = np.array([0.2, -0.1, 0.15, 0.1, -0.2, 0.3])
    quat = [0.0, 0.0, np.sin(0.05), np.cos(0.05)]
    u_flying = np.concatenate([[0.1, 0.05, -0.02, 0.01, -0.02, 0.03], [0.2, -0.1, 0.1, 0.0, 0.1, 0.0]])
    return [
        ("none", s6, "floating", lambda r: None, np.concatenate([np.zeros(6), np.full(6, 0.05)])),
        ("joint_pd", s6, "floating", lambda r: JointPD(kp=[60.0, 60.0, 60.0, 5.0, 5.0, 5.0], kd=4.0, reference=q0 + d), None),
        ("computed_torque", s6, "floating", lambda r: ComputedTorque(kp=25.0, kd=10.0, reference=QuinticJoint(q0, q0 + d, 0.0, 0.05)), None),
        ("resolved_motion_rate", s6, "floating", lambda r: ResolvedMotionRate(_line(r, [0.05, 0.05, -0.05]), gain=5.0), None),
        ("attitude", wheels_robot, "rotation-floating", lambda r: AttitudeControl(quat, kp=20.0, kd=80.0), None),
        ("cmg_steering", cmg_robot, "rotation-floating", lambda r: CmgSteering(quat, kp=200.0, kd=400.0, dither=0.05, null_gain=0.5),
         cmg_robot().cmg_velocity(500.0) + np.r_[np.zeros(6), np.tile([0.1, 0.0], 4), 0.0, 0.0]),
        ("cmg_steering_unloading", cmg_robot, "rotation-flying",
         lambda r: CmgSteering(quat, kp=200.0, kd=400.0, unload_gain=2.0, unload_above=0.004, unload_below=0.002),
         cmg_robot().cmg_velocity(500.0) + np.r_[np.zeros(6), np.tile([0.1, 0.0], 4), 0.0, 0.0]),
        ("cmg_steering_vscmg", vscmg_robot, "rotation-floating", lambda r: CmgSteering(quat, kp=200.0, kd=400.0, wheel_weight=1.0, wheel_mu=1.0),
         vscmg_robot().cmg_velocity(500.0) + np.r_[np.zeros(6), np.tile([0.1, 0.0], 4), 0.0, 0.0]),
        # The coordinated arm + cluster law on VSCMGs (spin motors, no torque asked of them) read
        # back from URDF: the arm's PD and the cluster's steering in one run description.
        ("combined_cmg", vscmg_robot, "rotation-floating",
         lambda r: Combined(arm=JointPD(kp=60.0, kd=20.0, reference=[0.3, -0.2]), base=CmgSteering(quat, kp=200.0, kd=400.0)),
         vscmg_robot().cmg_velocity(400.0) + np.r_[np.zeros(6), np.tile([0.1, 0.0], 4), 0.0, 0.0]),
        ("base_thrusters", s6, "flying",
         lambda r: BaseThrusterControl(com_ref=[0.05, -0.02, 0.01], quat_ref=quat, kp_attitude=200.0, kd_attitude=400.0), u_flying),
        ("coordinated_flying", s6, "flying", lambda r: CoordinatedFlying(_line(r, [-0.05, 0.05, 0.05])), None),
        ("momentum_damping", s6, "flying", lambda r: MomentumDamping(0.05), u_flying),
        ("combined", wheels_robot, "rotation-floating",
         lambda r: Combined(arm=JointPD(kp=60.0, kd=[20.0, 20.0, 20.0, 4.0, 4.0, 4.0], reference=r.initial_q[:6] + 0.1),
                            base=AttitudeControl(quat, kp=20.0, kd=80.0)), None),
        ("torque_limit", s6, "floating", lambda r: TorqueLimit(JointPD(kp=1000.0, kd=1.0, reference=q0 + d), limit=0.5), None),
        ("mpc", s6, "floating", lambda r: MPC(_mpc_problem(q0 + d), max_iterations=3), None),
        ("mpc_moving_target", s6, "floating", lambda r: MPC(_mpc_tracking(r), max_iterations=3), None),
        ("mpc_euler_orbiting_target", s6, "floating",
         lambda r: MPC(_mpc_tracking(r, orbit=spacearm.Orbit.circular(500e3), discretization="euler"), max_iterations=3), None),
    ]


def _mpc_problem(goal):
    """Joint tracking over 5 knots of the communication step H (the law samples every 8 RK4 steps)."""
    import spacearm.mpc as mpc
    return mpc.Problem(horizon=5, dt=H, running=[mpc.JointCost(10.0, goal, weight_qd=0.1), mpc.ControlCost(1e-2)],
                       terminal=[mpc.JointCost(100.0, goal, weight_qd=1.0)], control_limit=5.0)


def _mpc_tracking(robot, orbit=None, discretization="rk4"):
    """The end effector after a tumbling target's grasp point (a moving reference of the point
    cost, docs/mpc.md): the run description carries the target as data, every door propagates it
    (with ``orbit``: under the tidal motion; ``discretization``: the plan's step)."""
    import spacearm.mpc as mpc
    from spacearm.control import FreeBodyPoint
    body, offset = robot.resolve_point(None)
    cm = robot.point_position(robot.neutral_configuration()) + np.array([0.01, 0.0, 0.0]) - np.array([0.3, 0.0, 0.0])
    target = FreeBodyPoint([3.0, 4.0, 5.0], np.r_[cm, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.05, 0.0, 0.1], offset=(0.3, 0.0, 0.0), orbit=orbit)
    return mpc.Problem(horizon=5, dt=H, running=[mpc.PointCost(body, target, weight=1e3, offset=offset), mpc.ControlCost(1e-2)],
                       control_limit=5.0, discretization=discretization)


LAWS = {law[0]: law[1:] for law in _laws()}


def options_toml(mode: str, controller) -> str:
    run = f'mode = "{mode}"\ndt = {DT!r}\n'
    if controller is None:
        return run
    return library.load().options_with_controller(run, controller_spec(controller).to_toml())


def c_stepper_states(robot, options: str, x0, u0) -> tuple[np.ndarray, np.ndarray]:
    """The C stepper's states at t = 0, H, 2H, ... (ctypes on libspacearm_c)."""
    lib = ctypes.CDLL(str(library.path()))
    lib.spacearm_last_error.restype = ctypes.c_char_p
    lib.spacearm_model_from_toml.argtypes = [ctypes.c_char_p, ctypes.POINTER(ctypes.c_void_p)]
    lib.spacearm_model_free.argtypes = [ctypes.c_void_p]
    lib.spacearm_stepper_new.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.POINTER(ctypes.c_void_p)]
    lib.spacearm_stepper_reset.argtypes = [ctypes.c_void_p, D, D]
    lib.spacearm_stepper_step.argtypes = [ctypes.c_void_p, D, D, ctypes.c_size_t]
    lib.spacearm_stepper_state.argtypes = [ctypes.c_void_p, D, D]
    lib.spacearm_stepper_free.argtypes = [ctypes.c_void_p]

    def ok(status):
        assert status == 0, lib.spacearm_last_error().decode()

    model, stepper = ctypes.c_void_p(), ctypes.c_void_p()
    ok(lib.spacearm_model_from_toml(_core.model_to_toml(robot.core_model).encode(), ctypes.byref(model)))
    try:
        ok(lib.spacearm_stepper_new(model, options.encode(), ctypes.byref(stepper)))
        x0, u0 = np.ascontiguousarray(x0, dtype=float), np.ascontiguousarray(u0, dtype=float)
        ok(lib.spacearm_stepper_reset(stepper, x0.ctypes.data_as(D), u0.ctypes.data_as(D)))
        xs, us = [x0.copy()], [u0.copy()]
        for _ in range(POINTS):
            ok(lib.spacearm_stepper_step(stepper, None, None, EVERY))
            x, u = np.empty_like(x0), np.empty_like(u0)
            ok(lib.spacearm_stepper_state(stepper, x.ctypes.data_as(D), u.ctypes.data_as(D)))
            xs.append(x)
            us.append(u)
        return np.array(xs), np.array(us)
    finally:
        lib.spacearm_stepper_free(stepper)
        lib.spacearm_model_free(model)


def fmu_states(path, robot, u0) -> tuple[np.ndarray, np.ndarray]:
    n = robot.n_dof
    start = {f"u0[{k + 1}]": v for k, v in enumerate(u0)}
    result = fmpy.simulate_fmu(str(path), stop_time=DURATION, step_size=H, output_interval=H, start_values=start,
                               fmi_type="CoSimulation")
    assert np.array_equal(result["time"], np.arange(POINTS + 1) * H), result["time"]

    def columns(group, k):
        return np.column_stack([result[f"{group}[{i}]"] for i in range(1, k + 1)])

    x = np.hstack([columns("r0", 3), columns("quat0", 4), columns("q", n)])
    u = np.hstack([columns("v0", 3), columns("w0", 3), columns("qd", n)])
    return x, u


@pytest.mark.parametrize("law", list(LAWS))
def test_every_native_law_runs_bit_for_bit_alike_in_simulate_the_c_stepper_and_the_fmu(tmp_path, law):
    make_robot, mode, make_controller, u0 = LAWS[law]
    robot = make_robot()
    controller = make_controller(robot)
    x0 = robot.neutral_configuration()
    u0 = robot.zero_velocity() if u0 is None else np.asarray(u0, dtype=float)
    traj = spacearm.simulate(robot, DURATION, dt=DT, mode=mode, controller=controller, x0=x0, u0=u0)
    keep = slice(None, None, EVERY)
    want_x, want_u = traj.x[keep], traj.u[keep]
    assert want_x.shape[0] == POINTS + 1
    # The run moved (the equality below would hold of two frozen runs).
    assert max(np.abs(want_x[-1] - want_x[0]).max(), np.abs(want_u[-1] - want_u[0]).max()) > 1e-2, law

    options = options_toml(mode, controller)
    got_x, got_u = c_stepper_states(robot, options, x0, u0)
    assert np.array_equal(got_x, want_x) and np.array_equal(got_u, want_u), \
        f"C stepper: max |dx| {np.abs(got_x - want_x).max():.3g}, |du| {np.abs(got_u - want_u).max():.3g}"

    for version in (3, 2):
        path = spacearm.fmi.export(robot, tmp_path / f"{law}_{version}.fmu", mode=mode, controller=controller, dt=DT,
                                   fmi_version=version, joint_limits=True)
        assert validate_fmu(str(path)) == []
        fx, fu = fmu_states(path, robot, u0)
        assert np.array_equal(fx, want_x) and np.array_equal(fu, want_u), \
            f"FMI {version}: max |dx| {np.abs(fx - want_x).max():.3g}, |du| {np.abs(fu - want_u).max():.3g}"


def test_the_numbers_of_a_law_are_fmu_parameters_and_checked_by_the_core(tmp_path):
    """An attitude law's FMU, its parameters set before initialization: the run equals
    ``spacearm.simulate`` of the law with those values (bit for bit); a ``quat_ref`` that is not a
    unit quaternion is refused at the end of initialization with the core's message."""
    from fmpy.fmi1 import FMICallException

    robot = wheels_robot()
    exported = AttitudeControl([0.0, 0.0, 0.0, 1.0], kp=5.0, kd=30.0)
    path = spacearm.fmi.export(robot, tmp_path / "att.fmu", mode="rotation-floating", controller=exported, dt=DT)
    md = fmpy.read_model_description(str(path))
    params = {v.name: v for v in md.modelVariables if v.causality == "parameter"}
    assert {"quat_ref[1]", "quat_ref[2]", "quat_ref[3]", "quat_ref[4]", "kp", "kd"} <= set(params)
    assert float(params["kd"].start) == 30.0 and float(params["quat_ref[4]"].start) == 1.0
    quat = [0.0, np.sin(0.05), 0.0, np.cos(0.05)]
    start = {"kp": 20.0, "kd": 80.0, **{f"quat_ref[{k + 1}]": v for k, v in enumerate(quat)}}
    result = fmpy.simulate_fmu(str(path), stop_time=DURATION, step_size=H, output_interval=H, start_values=start, fmi_type="CoSimulation")
    traj = spacearm.simulate(robot, DURATION, dt=DT, mode="rotation-floating", controller=AttitudeControl(quat, kp=20.0, kd=80.0))
    got = np.column_stack([result[f"quat0[{k}]"] for k in range(1, 5)])
    assert np.array_equal(got, traj.x[::EVERY, 3:7])
    assert np.abs(got[-1] - got[0]).max() > 1e-3
    messages: list = []
    with pytest.raises(FMICallException):
        fmpy.simulate_fmu(str(path), stop_time=DURATION, step_size=H, start_values={"quat_ref[4]": 2.0}, fmi_type="CoSimulation",
                          logger=lambda *args: messages.append(str(args)))
    assert any("quat_ref" in m and "unit" in m for m in messages), messages


def _toml_value(v) -> str:
    """A plain-data value as TOML (inline tables; floats in shortest round-trip form)."""
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{k} = {_toml_value(x)}" for k, x in v.items()) + " }"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, bool):
        return "true" if v else "false"
    return repr(float(v))


def test_the_c_stepper_reads_simulates_run_description_an_orbit_with_its_tidal_torques():
    """The stepper's options are the core's run description (sim/options.rs ``RunSpec``), so an
    orbit with the gravity gradient, which the C crate never had an option for, runs from C the
    way ``spacearm.simulate`` runs it (bit for bit), and differs from the same run in empty space
    (the tidal torques act)."""
    robot = spacearm.presets.spatial6()
    orbit = spacearm.Orbit.circular(400e3, inclination=0.9, raan=0.3, arg_latitude=0.2, j2=True)
    x0 = robot.neutral_configuration()
    x0[3:7] = [np.sin(0.3), 0.0, 0.0, np.cos(0.3)]  # tilted: the gradient torque is not zero
    u0 = robot.zero_velocity()
    controller = JointPD(kp=30.0, kd=5.0, reference=robot.initial_q + 0.1)
    traj = spacearm.simulate(robot, DURATION, dt=DT, controller=controller, x0=x0, u0=u0, orbit=orbit, gravity_gradient=True)
    empty = spacearm.simulate(robot, DURATION, dt=DT, controller=controller, x0=x0, u0=u0)
    run = f'dt = {DT!r}\norbit = {_toml_value(orbit._data())}\ngravity_gradient = true\n'
    options = library.load().options_with_controller(run, controller_spec(controller).to_toml())
    got_x, got_u = c_stepper_states(robot, options, x0, u0)
    assert np.array_equal(got_x, traj.x[::EVERY]) and np.array_equal(got_u, traj.u[::EVERY])
    assert np.abs(traj.u[-1, :6] - empty.u[-1, :6]).max() > 0  # the orbit changed the run
    # What the stepper cannot do is refused with the core's reasons, not ignored.
    lib = library.load()
    for text, why in ((f"dt = {DT!r}\nintegrator = \"dopri5\"\n", "RK4"), (f"dt = {DT!r}\ngravity_gradient = true\n", "needs an orbit"),
                      (f"dt = {DT!r}\nstop = [{{ kind = \"time\", t = 0.5 }}]\n", "stop")):
        with pytest.raises(Exception, match=why):
            c_stepper_states(robot, text, x0, u0)
