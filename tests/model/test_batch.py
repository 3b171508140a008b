"""A batch of states (a leading axis) on every per-state Robot method: each row bit-identical to
the per-state call, independent of the thread count, computed safely from many Python threads;
a bad row is reported by its index. References: the per-state calls (one state at a time, on a
fresh model) and Pinocchio for a few rows."""

import concurrent.futures
import copy

import numpy as np
import pytest

import spacearm
from spacearm import _core, presets
from spacearm.errors import NonFiniteError, QuaternionError, ShapeError, SpacearmTypeError

from random_models import random_model, random_state

B = 24


def states(robot, seed, rows=B):
    rng = np.random.default_rng(seed)
    pairs = [random_state(robot, rng) for _ in range(rows)]
    xs = np.array([x for x, _ in pairs])
    us = np.array([u for _, u in pairs])
    taus = rng.normal(size=(rows, robot.n_dof))
    fs = rng.normal(size=(rows, robot.nu))
    return xs, us, taus, fs


def robots():
    return [presets.spatial6(), presets.planar4(), random_model(3).robot, random_model(11).robot]


# method name -> (call on a batch or one state: lambda robot, x, u, tau, f, fb)
CALLS = {
    "forward_kinematics": lambda r, x, u, tau, f, fb: r.forward_kinematics(x),
    "point_position": lambda r, x, u, tau, f, fb: r.point_position(x),
    "point_jacobian": lambda r, x, u, tau, f, fb: r.point_jacobian(x),
    "link_jacobians": lambda r, x, u, tau, f, fb: r.link_jacobians(x, r.n_bodies - 1),
    "inertia_blocks": lambda r, x, u, tau, f, fb: r.inertia_blocks(x),
    "mass_matrix": lambda r, x, u, tau, f, fb: r.mass_matrix(x),
    "mass_matrix_paper": lambda r, x, u, tau, f, fb: r.mass_matrix(x, method="paper"),
    "base_inertia_inverse": lambda r, x, u, tau, f, fb: r.base_inertia_inverse(x),
    "bias_forces": lambda r, x, u, tau, f, fb: r.bias_forces(x, u),
    "inverse_dynamics": lambda r, x, u, tau, f, fb: r.inverse_dynamics(x, u, f),
    "inverse_dynamics_wrench": lambda r, x, u, tau, f, fb: r.inverse_dynamics(
        x, u, f, wrenches=[spacearm.ExternalWrench(1, force=[1.0, 2.0, 3.0], offset=[0.1, 0, 0])]),
    "forward_dynamics_aba": lambda r, x, u, tau, f, fb: r.forward_dynamics(x, u, f),
    "forward_dynamics_mass_matrix": lambda r, x, u, tau, f, fb: r.forward_dynamics(x, u, f, method="mass_matrix"),
    "forward_dynamics_reduced": lambda r, x, u, tau, f, fb: r.forward_dynamics(x, u, f, method="reduced"),
    "forward_dynamics_tau": lambda r, x, u, tau, f, fb: r.forward_dynamics(x, u, tau=tau, base_wrench=fb),
    "forward_dynamics_tau_reduced": lambda r, x, u, tau, f, fb: r.forward_dynamics(x, u, tau=tau, method="reduced"),
    "generalized_inertia": lambda r, x, u, tau, f, fb: r.generalized_inertia(x),
    "generalized_bias": lambda r, x, u, tau, f, fb: r.generalized_bias(x, u),
    "generalized_jacobian": lambda r, x, u, tau, f, fb: r.generalized_jacobian(x),
    "point_twist": lambda r, x, u, tau, f, fb: r.point_twist(x, tau, P=fb[..., :3], L=fb[..., 3:]),
    "base_velocity_from_momentum": lambda r, x, u, tau, f, fb: r.base_velocity_from_momentum(x, tau, P=fb[..., :3]),
    "momentum": lambda r, x, u, tau, f, fb: r.momentum(x, u),
    "kinetic_energy": lambda r, x, u, tau, f, fb: r.kinetic_energy(x, u),
    "center_of_mass": lambda r, x, u, tau, f, fb: r.center_of_mass(x),
    "mass_matrix_partials": lambda r, x, u, tau, f, fb: r.mass_matrix_partials(x),
    "mass_matrix_derivative": lambda r, x, u, tau, f, fb: r.mass_matrix_derivative(x, u),
    "generalized_inertia_partials": lambda r, x, u, tau, f, fb: r.generalized_inertia_partials(x),
    "generalized_inertia_derivative": lambda r, x, u, tau, f, fb: r.generalized_inertia_derivative(x, u),
    "generalized_jacobian_partials": lambda r, x, u, tau, f, fb: r.generalized_jacobian_partials(x),
    "generalized_jacobian_derivative": lambda r, x, u, tau, f, fb: r.generalized_jacobian_derivative(x, u),
    "forward_dynamics_derivatives": lambda r, x, u, tau, f, fb: r.forward_dynamics_derivatives(x, u, f),
    "forward_dynamics_derivatives_tau": lambda r, x, u, tau, f, fb: r.forward_dynamics_derivatives(x, u, tau=tau, base_wrench=fb),
    "forward_dynamics_derivatives_tau_free": lambda r, x, u, tau, f, fb: r.forward_dynamics_derivatives(x, u, tau=tau),
    "linearize": lambda r, x, u, tau, f, fb: r.linearize(x, u, tau=tau),
    "linearize_all": lambda r, x, u, tau, f, fb: r.linearize(x, u, f, inputs="all"),
}


def parts(result):
    """A result as a list of arrays (tuples and NamedTuples flattened)."""
    if isinstance(result, tuple):
        return [np.asarray(p) for p in result]
    return [np.asarray(result)]


def assert_rows_equal(batch, per_state_results):
    batch_parts = parts(batch)
    for i, one in enumerate(per_state_results):
        for k, (b, o) in enumerate(zip(batch_parts, parts(one))):
            assert b.shape[0] == len(per_state_results)
            assert b[i].shape == o.shape, (k, b[i].shape, o.shape)
            # Bit for bit: the same kernel on the same inputs.
            assert np.array_equal(b[i], o), (i, k, np.max(np.abs(b[i] - o)))


@pytest.mark.parametrize("name", sorted(CALLS))
def test_every_row_is_the_per_state_call_bit_for_bit(name):
    call = CALLS[name]
    for seed, robot in enumerate(robots()):
        xs, us, taus, fs = states(robot, seed)
        fbs = fs[:, :6]
        batch = call(robot, xs, us, taus, fs, fbs)
        # Per-state reference on a fresh model, so no workspace is shared with the batch.
        fresh = copy.deepcopy(robot)
        singles = [call(fresh, xs[i], us[i], taus[i], fs[i], fbs[i]) for i in range(B)]
        assert_rows_equal(batch, singles)
        # The per-state results are themselves non-trivial (no all-zero pass).
        assert any(np.any(p != 0) for p in parts(singles[0]))


def test_a_single_row_broadcasts_against_a_batch():
    robot = presets.spatial6()
    xs, us, taus, fs = states(robot, 7)
    batch = robot.forward_dynamics(xs[0], us, tau=taus[0])  # x and tau: one row for all
    assert batch.shape == (B, robot.nu)
    for i in range(B):
        assert np.array_equal(batch[i], robot.forward_dynamics(xs[0], us[i], tau=taus[0]))
    e = robot.kinetic_energy(xs, us[3])
    assert e.shape == (B,) and e[5] == robot.kinetic_energy(xs[5], us[3])


def test_results_do_not_depend_on_the_thread_count():
    robot = random_model(5).robot
    xs, us, taus, fs = states(robot, 1, rows=301)
    results = {}
    try:
        for threads in (1, 2, 3):
            _core.set_batch_threads(threads)
            assert _core.batch_threads() == threads
            results[threads] = (robot.forward_dynamics(xs, us, fs), robot.mass_matrix(xs), robot.linearize(xs, us, fs).A)
    finally:
        _core.set_batch_threads(None)
    for threads in (2, 3):
        for a, b in zip(results[1], results[threads]):
            assert np.array_equal(a, b)


def test_an_empty_batch_gives_empty_results():
    robot = presets.planar4()
    out = robot.mass_matrix(np.zeros((0, robot.nx)))
    assert out.shape == (0, robot.nu, robot.nu)


@pytest.mark.parametrize("tau, error, match", [
    (np.ones(3), "ShapeError", "tau must have length 6, got 3"),
    (np.full(6, np.nan), "NonFiniteError", "tau must be finite, but entry 0 is NaN"),
])
def test_an_empty_batch_checks_the_shared_arguments_as_one_state_does(tau, error, match):
    """B = 0 runs no row, but a shared argument gets the verdict it gets with B = 1 (issue 26:
    an empty batch skipped the checks of the other arguments)."""
    robot = presets.spatial6()
    x, u = robot.neutral_configuration(), np.zeros(robot.nu)
    cls = getattr(spacearm.errors, error)
    with pytest.raises(cls, match=match):
        robot.forward_dynamics(x, u, tau=tau)  # the one-state verdict, from the kernel
    with pytest.raises(cls, match=match):
        robot.forward_dynamics(np.zeros((0, robot.nx)), np.zeros((0, robot.nu)), tau=tau)
    assert robot.forward_dynamics(np.zeros((0, robot.nx)), np.zeros((0, robot.nu)), tau=np.ones(6)).shape == (0, robot.nu)


def test_a_bad_row_is_reported_by_its_index():
    robot = presets.spatial6()
    xs, us, taus, fs = states(robot, 2)
    bad = xs.copy()
    bad[7, 8] = np.nan
    bad[12, 3:7] = [0, 0, 0, 2.0]
    with pytest.raises(NonFiniteError, match=r"^row 7 of the batch: x must be finite, but entry 8 is NaN"):
        robot.forward_dynamics(bad, us, fs)
    bad[7, 8] = 0.0
    with pytest.raises(QuaternionError, match=r"^row 12 of the batch: the base quaternion"):
        robot.mass_matrix(bad)
    badu = us.copy()
    badu[4, 0] = np.inf
    with pytest.raises(NonFiniteError, match=r"^row 4 of the batch: u must be finite"):
        robot.bias_forces(xs, badu)


def test_batch_shapes_are_checked():
    robot = presets.spatial6()
    xs, us, taus, fs = states(robot, 3)
    with pytest.raises(ShapeError, match=r"x has 24, u has 23"):
        robot.bias_forces(xs, us[:-1])
    with pytest.raises(ShapeError, match=r"u must have shape \(B, 12\).*got \(24, 11\)"):
        robot.bias_forces(xs, us[:, :-1])
    with pytest.raises(ShapeError, match=r"1-D array .* or a 2-D array"):
        robot.mass_matrix(xs[None])


def test_the_batch_matches_pinocchio_on_a_few_rows():
    pin = pytest.importorskip("pinocchio")
    from spacearm import interop

    robot = random_model(8).robot
    xs, us, taus, fs = states(robot, 4, rows=5)
    model = interop.to_pinocchio(robot)
    data = model.createData()
    batch = robot.forward_dynamics(xs, us, fs)
    for i in range(5):
        q, v = interop.to_pinocchio_state(robot, xs[i], us[i])
        a = pin.aba(model, data, q, v, interop.to_pinocchio_force(robot, xs[i], fs[i]))
        ref = interop.acceleration_from_pinocchio(robot, xs[i], us[i], a)
        np.testing.assert_allclose(batch[i], ref, rtol=1e-9, atol=1e-9 * np.max(np.abs(ref)))


# ---- thread safety ------------------------------------------------------------------------------
def test_concurrent_calls_on_one_robot_equal_serial_calls():
    robot = random_model(4).robot
    xs, us, taus, fs = states(robot, 5, rows=64)
    serial = [(robot.mass_matrix(xs[i]), robot.forward_dynamics(xs[i], us[i], fs[i]), robot.linearize(xs[i], us[i], fs[i]).A)
              for i in range(64)]

    def one(i):
        return robot.mass_matrix(xs[i]), robot.forward_dynamics(xs[i], us[i], fs[i]), robot.linearize(xs[i], us[i], fs[i]).A

    def batch(_):
        return robot.forward_dynamics(xs, us, fs)

    with concurrent.futures.ThreadPoolExecutor(8) as pool:
        for _ in range(5):
            threaded = list(pool.map(one, range(64)))
            batches = list(pool.map(batch, range(8)))
    for s, t in zip(serial, threaded):
        for a, b in zip(s, t):
            assert np.array_equal(a, b)
    for b in batches:
        assert np.array_equal(b, np.array([s[1] for s in serial]))


def test_a_robot_passed_as_a_state_is_a_type_error():
    robot = presets.spatial6()
    with pytest.raises(SpacearmTypeError, match="x must hold real numbers .*got a Robot"):
        robot.mass_matrix(robot)
    with pytest.raises(SpacearmTypeError, match="u must hold real numbers"):
        robot.bias_forces(robot.neutral_configuration(), robot)
