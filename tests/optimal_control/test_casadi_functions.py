"""spacearm.casadi against the Rust core: every Function equals the core's quantity at random
states (values to 1e-12 relative), CasADi's AD Jacobians of forward dynamics equal the core's
exact derivatives (compared in tangent coordinates through the quaternion's tangent map), and
one RK4 step equals one step of the native simulator.

Models: the presets planar4 and spatial6, the hand-built branched tree (prismatic and fixed
joints, branches), random trees from tests/random_models.py and a random URDF."""

import sys

import numpy as np
import pytest

import spacearm
from conftest import branched_tree
from random_models import assert_rel_close, random_model, random_state
from random_urdf import random_urdf

ca = pytest.importorskip("casadi")
import spacearm.casadi as sc  # noqa: E402


def _urdf_robot(tmp_path_factory):
    path = tmp_path_factory.mktemp("urdf") / "random3.urdf"
    path.write_text(random_urdf(3, n_links=6))
    return spacearm.io.load_urdf(path)


MODELS = {
    "planar4": lambda _: spacearm.presets.planar4(),
    "spatial6": lambda _: spacearm.presets.spatial6(),
    "branched": lambda _: branched_tree(),
    "random5": lambda _: random_model(5).robot,
    "random11": lambda _: random_model(11).robot,
    "urdf3": _urdf_robot,
}


@pytest.fixture(params=sorted(MODELS), scope="module")
def robot(request, tmp_path_factory):
    return MODELS[request.param](tmp_path_factory)


def _states(robot, n=3, seed=7):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        x, u = random_state(robot, rng)
        yield x, u, rng.normal(size=robot.n_dof), rng.normal(size=6), rng.normal(size=robot.nu)


def _np(value):
    return np.array(value, dtype=float)


def _point(robot):
    """The end effector if the model has one, else its last body."""
    return None if robot.end_effector is not None else robot.body_names[-1]


def test_values_equal_the_core(robot):
    fd, fid = sc.forward_dynamics(robot), sc.inverse_dynamics(robot)
    H, c = sc.mass_matrix(robot), sc.bias_forces(robot)
    Hs, cs = sc.generalized_inertia(robot), sc.generalized_bias(robot)
    point = _point(robot)
    Js, p = sc.generalized_jacobian(robot, point), sc.point_position(robot, point)
    mom, base_vel = sc.momentum(robot), sc.base_velocity_from_momentum(robot)
    for x, u, tau, wrench, du in _states(robot):
        assert_rel_close(_np(fd(x, u, tau, wrench)).ravel(), robot.forward_dynamics(x, u, tau=tau, base_wrench=wrench), "casadi fd", rtol=1e-12)
        assert_rel_close(_np(fid(x, u, du)).ravel(), robot.inverse_dynamics(x, u, du), "casadi id", rtol=1e-12)
        assert_rel_close(_np(H(x)), robot.mass_matrix(x), "casadi H", rtol=1e-12)
        assert_rel_close(_np(c(x, u)).ravel(), robot.bias_forces(x, u), "casadi c", rtol=1e-12)
        assert_rel_close(_np(Hs(x)), robot.generalized_inertia(x), "casadi H*", rtol=1e-12)
        assert_rel_close(_np(cs(x, u)).ravel(), robot.generalized_bias(x, u), "casadi c*", rtol=1e-12)
        assert_rel_close(_np(Js(x)), robot.generalized_jacobian(x, point), "casadi J*", rtol=1e-12)
        assert_rel_close(_np(p(x)).ravel(), robot.point_position(x, point), "casadi point", rtol=1e-12)
        P, L = mom(x, u)
        m = robot.momentum(x, u)
        assert_rel_close(_np(P).ravel(), m.P, "casadi P", rtol=1e-12)
        assert_rel_close(_np(L).ravel(), m.L_origin, "casadi L", rtol=1e-12)
        P_set, L_set = wrench[:3], wrench[3:]
        assert_rel_close(_np(base_vel(x, u[6:], P_set, L_set)).ravel(), robot.base_velocity_from_momentum(x, u[6:], P_set, L_set),
                         "casadi base velocity", rtol=1e-12)


def _quaternion_tangent_map(quat):
    """``d quat / d dtheta`` at ``dtheta = 0`` for ``quat <- exp(dtheta) ⊗ quat`` (4×3): the
    derivative of ``½ [dtheta; 0] ⊗ quat``, written out independently of the package."""
    qv, qw = quat[:3], quat[3]
    cross = np.array([[0.0, -qv[2], qv[1]], [qv[2], 0.0, -qv[0]], [-qv[1], qv[0], 0.0]])
    return 0.5 * np.vstack([qw * np.eye(3) - cross, -qv[None, :]])


def test_ad_jacobians_equal_the_core_derivatives(robot):
    n = robot.n_dof
    fd = sc.forward_dynamics(robot)
    X, U, T, W = ca.SX.sym("x", robot.nx), ca.SX.sym("u", robot.nu), ca.SX.sym("tau", n), ca.SX.sym("w", 6)
    du = fd(X, U, T, W)
    jac = ca.Function("fd_jacobians", [X, U, T, W], [ca.jacobian(du, X), ca.jacobian(du, U), ca.jacobian(du, T), ca.jacobian(du, W)])
    for x, u, tau, wrench, _ in _states(robot, n=2, seed=11):
        d_x, d_u, d_tau, d_wrench = (_np(a) for a in jac(x, u, tau, wrench))
        ref = robot.forward_dynamics_derivatives(x, u, tau=tau, base_wrench=wrench)
        # x -> tangent coordinates [dr0, dtheta, dq]: r0 and q directly, the quaternion through
        # its tangent map (the Function normalises the quaternion, so the map is exact).
        tangent = np.zeros((robot.nx, robot.nu))
        tangent[0:3, 0:3] = np.eye(3)
        tangent[3:7, 3:6] = _quaternion_tangent_map(x[3:7])
        tangent[7:, 6:] = np.eye(n)
        assert_rel_close(d_x @ tangent, ref.ddu_dx, "casadi ddu/dx", rtol=1e-10)
        assert_rel_close(d_u, ref.ddu_du, "casadi ddu/du", rtol=1e-10)
        assert_rel_close(d_tau, ref.ddu_df[:, 6:], "casadi ddu/dtau", rtol=1e-10)
        assert_rel_close(d_wrench, ref.ddu_df[:, :6], "casadi ddu/dwrench", rtol=1e-10)


def test_rk4_step_equals_the_native_rk4(robot):
    rng = np.random.default_rng(3)
    x0, u0 = random_state(robot, rng)
    dt, steps = 0.01, 25
    traj = spacearm.simulate(robot, dt * steps, x0=x0, u0=u0, integrator="rk4", dt=dt, joint_limits=False)
    step = sc.rk4_step(robot)
    x, u = x0, u0
    for _ in range(steps):
        x, u = (_np(v).ravel() for v in step(x, u, np.zeros(robot.n_dof), np.zeros(6), dt))
    assert abs(np.linalg.norm(x[3:7]) - 1.0) < 1e-14
    assert_rel_close(x, traj.x[-1], "casadi rk4 x", rtol=1e-12)
    assert_rel_close(u, traj.u[-1], "casadi rk4 u", rtol=1e-11)
    # It moved: the comparison is not between two initial states.
    assert np.linalg.norm(u - u0) > 1e-3 * np.linalg.norm(u0)


def test_thirty_joint_model_builds_quickly():
    """A 30-joint chain builds (the graph is linear in N for ABA); timing is in the docs, this
    only checks it builds and is right."""
    b = spacearm.Robot.builder("chain30", 500.0, np.diag([50.0, 60.0, 70.0]))
    for i in range(30):
        b.add_link(f"l{i}", parent="base" if i == 0 else f"l{i - 1}", axis=[(0, 0, 1), (0, 1, 0), (1, 0, 0)][i % 3],
                   origin=(0.3, 0, 0) if i else (1.0, 0, 0), com=(0.15, 0, 0), mass=2.0, inertia=[0.01, 0.02, 0.02])
    r30 = b.build()
    x, u = random_state(r30, np.random.default_rng(0))
    tau = np.linspace(-1, 1, 30)
    assert_rel_close(_np(sc.forward_dynamics(r30)(x, u, tau, np.zeros(6))).ravel(), r30.forward_dynamics(x, u, tau=tau), "casadi fd 30", rtol=1e-12)


def test_bad_input():
    with pytest.raises(spacearm.errors.SpacearmTypeError, match="spacearm.Robot"):
        sc.forward_dynamics("planar4")
    with pytest.raises(spacearm.errors.ArgumentError, match="substeps"):
        sc.rk4_step(spacearm.presets.planar4(), substeps=0)


def test_missing_casadi_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "casadi", None)
    with pytest.raises(spacearm.errors.MissingDependencyError, match=r"spacearm\[optimal-control\]"):
        sc.mass_matrix(spacearm.presets.planar4())


def test_rk4_step_with_linear_torque_equals_the_native_rk4_under_that_torque():
    """``torque="linear"``: each RK4 stage sees the torque of its time, as the native simulator
    does with a controller returning the same time-linear torque."""
    robot = spacearm.presets.spatial6()
    x0, u0 = random_state(robot, np.random.default_rng(5))
    tau_a, tau_b = np.linspace(-2.0, 1.0, 6), np.linspace(3.0, -1.0, 6)
    duration = 0.4
    torque = lambda t, x, u: tau_a + (tau_b - tau_a) * (t / duration)  # noqa: E731
    dt = 0.05
    traj = spacearm.simulate(robot, duration, x0=x0, u0=u0, integrator="rk4", dt=dt, joint_limits=False,
                             controller=spacearm.control.Callback(torque))
    step = sc.rk4_step(robot, substeps=8, torque="linear")
    x, u = (_np(v).ravel() for v in step(x0, u0, tau_a, tau_b, np.zeros(6), duration))
    assert_rel_close(x, traj.x[-1], "casadi rk4 linear x", rtol=1e-12)
    assert_rel_close(u, traj.u[-1], "casadi rk4 linear u", rtol=1e-11)
    constant = sc.rk4_step(robot, substeps=8)
    x_c, _ = (_np(v).ravel() for v in constant(x0, u0, tau_a, np.zeros(6), duration))
    assert np.linalg.norm(x_c - x) > 1e-6  # the torque's variation mattered


def test_values_on_both_sides_of_the_cores_branches(robot):
    """The Functions replay one recorded path of the core's code; its branches test structural
    zeros only (a joint exactly at zero skips its rotation in the f64 path, never on the tape),
    so states with every joint at zero, a negative quaternion scalar part, and a quaternion of
    any non-zero norm (normalised inside, as before) equal the core too."""
    fd, H, Js = sc.forward_dynamics(robot), sc.mass_matrix(robot), sc.generalized_jacobian(robot, _point(robot))
    rng = np.random.default_rng(21)
    for k in range(3):
        x, u = random_state(robot, rng)
        if k == 0:
            x[7:] = 0.0
        if k == 1:
            x[7::2] = 0.0
            x[3:7] = -x[3:7] if x[6] > 0 else x[3:7]
        tau, wrench = rng.normal(size=robot.n_dof), rng.normal(size=6)
        scaled = x.copy()
        scaled[3:7] *= [0.25, 1.0, 4.0][k]
        assert_rel_close(_np(fd(scaled, u, tau, wrench)).ravel(), robot.forward_dynamics(x, u, tau=tau, base_wrench=wrench), "casadi fd", rtol=1e-12)
        assert_rel_close(_np(H(scaled)), robot.mass_matrix(x), "casadi H", rtol=1e-12)
        assert_rel_close(_np(Js(scaled)), robot.generalized_jacobian(x, _point(robot)), "casadi J*", rtol=1e-12)


def test_numeric_inputs_are_checked_before_evaluation():
    """A zero quaternion has no direction (the normalised quaternion would be 0/0 = NaN): called
    with numbers, every Function refuses it, and NaN, a wrong size and complex numbers, with a
    spacearm error, in each calling style; called with symbols nothing is checked and the graph
    is unchanged (docs/optimal-control.md)."""
    robot = spacearm.presets.planar4()
    x, u = robot.neutral_configuration(), robot.zero_velocity()
    zero = x.copy()
    zero[3:7] = 0.0
    n = robot.n_dof
    builders = {
        "mass_matrix": (sc.mass_matrix, lambda x: (x,)),
        "forward_dynamics": (sc.forward_dynamics, lambda x: (x, u, np.zeros(n), np.zeros(6))),
        "generalized_jacobian": (sc.generalized_jacobian, lambda x: (x,)),
        "rk4_step": (sc.rk4_step, lambda x: (x, u, np.zeros(n), np.zeros(6), 0.01)),
    }
    for name, (build, args) in builders.items():
        f = build(robot)
        assert np.isfinite(_np(f(*args(x))[0] if name == "rk4_step" else f(*args(x)))).all()
        with pytest.raises(spacearm.QuaternionError, match="has no direction"):
            f(*args(zero))
        with pytest.raises(spacearm.QuaternionError):
            f(*args(ca.DM(zero)))
        with pytest.raises(spacearm.QuaternionError):
            f(**dict(zip(f.name_in(), args(list(zero)))))
        with pytest.raises(spacearm.QuaternionError):
            f.call(list(args(zero)))
        tiny = x.copy()
        tiny[3:7] = [0.0, 0.0, 0.0, 1e-200]  # its square underflows: no direction in floating point
        with pytest.raises(spacearm.QuaternionError):
            f(*args(tiny))
        bad = x.copy()
        bad[8] = np.nan
        with pytest.raises(spacearm.NonFiniteError, match=f"{name}: input 'x' must be finite, but entry 8 is nan"):
            f(*args(bad))
        with pytest.raises(spacearm.ShapeError, match=f"must have {robot.nx} entries, got {robot.nx - 1}"):
            f(*args(x[:-1]))
        with pytest.raises(spacearm.SpacearmTypeError, match="complex"):
            f(*args(x.astype(complex)))
    # Symbols pass unchecked: the graph of a zero quaternion is built, and evaluates to NaN.
    H = sc.mass_matrix(robot)
    xs = ca.MX.sym("x", robot.nx)
    g = ca.Function("g", [xs], [H(xs)])
    assert np.isnan(_np(g(zero))).any()


def test_the_graph_is_the_cores_tape():
    """The Function is the core's recorded arithmetic: one SX instruction per operation and
    constant of the tape (CasADi's simplification on the fly is off during the replay, and
    restored after it), so at these states it equals the core bit for bit; and no hand-written
    recursions are left in the package."""
    import importlib.util

    robot = spacearm.presets.spatial6()
    tape = robot.core_model.tape("forward_dynamics")
    operations = int(np.sum(tape.ops >= 2))
    assert ca.GlobalOptions.getSimplificationOnTheFly()
    f = sc.forward_dynamics(robot)
    assert ca.GlobalOptions.getSimplificationOnTheFly()
    assert f.n_instructions() - f.nnz_in() - f.nnz_out() == operations + len(tape.constants)
    x, u, tau, wrench, _ = next(_states(robot))
    assert np.array_equal(_np(f(x, u, tau, wrench)).ravel(), robot.forward_dynamics(x, u, tau=tau, base_wrench=wrench))
    assert importlib.util.find_spec("spacearm.casadi._recursions") is None
