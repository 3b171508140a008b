"""Every valid array is read right, whatever its memory layout (issue 38, docs/batch.md "The
array boundary"): C or Fortran order, transposed and sliced views, negative and zero strides,
unaligned memory, big-endian bytes and read-only arrays holding the same values give
bit-identical results, on every method with a batch axis and on the other doors that take
arrays (rollouts, rotations, orbit frames, workspace scans, impulse dynamics).

Each batch row is compared with the one-state call on a C-ordered copy of that row, so a
layout read as row-major when it is not (the defect of ad1bc7a: a Fortran-ordered ``tau`` gave
forward dynamics off by 281) fails here.
"""

import numpy as np
import pytest

import spacearm
from spacearm import presets
from spacearm.errors import NonFiniteError, QuaternionError, ShapeError


def _unaligned(a):
    """A copy of ``a`` at an odd byte offset (numpy flags it unaligned)."""
    buf = np.zeros(a.nbytes + 1, dtype=np.uint8)
    out = np.frombuffer(buf.data, dtype=np.float64, count=a.size, offset=1).reshape(a.shape)
    out[...] = a
    assert not out.flags.aligned
    return out


def _read_only(a):
    out = np.array(a)
    out.setflags(write=False)
    return out


def _column_sliced(a):
    """Every other column of a wider array (inner stride 16 bytes)."""
    if a.ndim == 1:
        big = np.zeros(2 * a.size)
        big[::2] = a
        return big[::2]
    big = np.zeros((a.shape[0], 2 * a.shape[1]))
    big[:, ::2] = a
    return big[:, ::2]


def _row_sliced(a):
    if a.ndim == 1:
        return _column_sliced(a)
    big = np.zeros((2 * a.shape[0], a.shape[1]))
    big[::2] = a
    return big[::2]


def _negative(a):
    """The same values through negative strides on every axis."""
    flipped = np.ascontiguousarray(a[(slice(None, None, -1),) * a.ndim])
    return flipped[(slice(None, None, -1),) * a.ndim]


# Each layout holds exactly the values of its argument at the same indices.
LAYOUTS = {
    "C": np.ascontiguousarray,
    "Fortran": np.asfortranarray,
    "transposed view": lambda a: a.T.copy().T,
    "row-sliced": _row_sliced,
    "column-sliced": _column_sliced,
    "negative strides": _negative,
    "unaligned": _unaligned,
    "big-endian": lambda a: a.astype(">f8"),
    "read-only": _read_only,
    "Fortran unaligned": lambda a: np.asfortranarray(_unaligned(a)) if a.ndim == 1 else _unaligned(a.T.copy()).T,
}


def test_the_layouts_are_what_they_say():
    a = np.arange(12.0).reshape(3, 4)
    for name, make in LAYOUTS.items():
        b = make(a)
        assert np.array_equal(b, a), name
    assert LAYOUTS["Fortran"](a).flags.f_contiguous and not LAYOUTS["Fortran"](a).flags.c_contiguous
    assert LAYOUTS["transposed view"](a).flags.f_contiguous
    assert LAYOUTS["negative strides"](a).strides[0] < 0 and LAYOUTS["negative strides"](a).strides[1] < 0
    assert not LAYOUTS["unaligned"](a).flags.aligned
    assert LAYOUTS["big-endian"](a).dtype.byteorder == ">"
    assert not LAYOUTS["read-only"](a).flags.writeable
    fu = LAYOUTS["Fortran unaligned"](a)
    assert fu.flags.f_contiguous and not fu.flags.aligned


B = 3


@pytest.fixture(scope="module")
def robot():
    return presets.spatial6()


@pytest.fixture(scope="module")
def data(robot):
    rng = np.random.default_rng(38)
    n = robot.n_dof
    quat = rng.normal(size=(B, 4))
    quat /= np.linalg.norm(quat, axis=1, keepdims=True)
    return {
        "x": np.hstack([rng.normal(size=(B, 3)), quat, rng.uniform(-1, 1, (B, n))]),
        "u": rng.normal(scale=0.3, size=(B, robot.nu)),
        "du": rng.normal(size=(B, robot.nu)),
        "f": rng.normal(size=(B, robot.nu)),
        "tau": rng.normal(size=(B, n)),
        "base_wrench": rng.normal(size=(B, 6)),
        "qd": rng.normal(size=(B, n)),
        "P": rng.normal(size=(B, 3)),
        "L": rng.normal(size=(B, 3)),
        "dx": rng.normal(scale=0.1, size=(B, robot.nu)),
    }


# (method, the arguments it takes from `data`, keyword names among them)
METHODS = [
    ("mass_matrix", ["x"], []),
    ("bias_forces", ["x", "u"], []),
    ("forward_dynamics", ["x", "u", "tau", "base_wrench"], ["tau", "base_wrench"]),
    ("forward_dynamics", ["x", "u", "f"], []),
    ("inverse_dynamics", ["x", "u", "du"], []),
    ("generalized_inertia", ["x"], []),
    ("generalized_bias", ["x", "u"], []),
    ("generalized_jacobian", ["x"], []),
    ("inertia_blocks", ["x"], []),
    ("momentum", ["x", "u"], []),
    ("kinetic_energy", ["x", "u"], []),
    ("center_of_mass", ["x"], []),
    ("forward_kinematics", ["x"], []),
    ("point_position", ["x"], []),
    ("point_jacobian", ["x"], []),
    ("point_twist", ["x", "qd", "P", "L"], ["P", "L"]),
    ("base_inertia_inverse", ["x"], []),
    ("base_velocity_from_momentum", ["x", "qd", "P", "L"], ["P", "L"]),
    ("passive_forces", ["x", "u"], []),
    ("mass_matrix_derivative", ["x", "u"], []),
    ("generalized_inertia_derivative", ["x", "u"], []),
    ("generalized_jacobian_derivative", ["x", "u"], []),
    ("mass_matrix_partials", ["x"], []),
    ("forward_dynamics_derivatives", ["x", "u", "tau", "base_wrench"], ["tau", "base_wrench"]),
    ("forward_dynamics_derivatives", ["x", "u", "f"], []),
    ("linearize", ["x", "u", "tau"], ["tau"]),
    ("generalized_inertia_partials", ["x"], []),
    ("generalized_jacobian_partials", ["x"], []),
    ("inverse_dynamics_partials", ["x", "u", "du"], []),
    ("spring_energy", ["x"], []),
    ("momentum_scales", ["x", "u"], []),
]


def _call(robot, method, names, keywords, values):
    args = [values[k] for k in names if k not in keywords]
    kwargs = {k: values[k] for k in keywords}
    return getattr(robot, method)(*args, **kwargs)


def _parts(result):
    """A result as a list of arrays (named tuples and plain tuples split into their parts)."""
    if isinstance(result, tuple):
        return [np.asarray(p) for p in result]
    return [np.asarray(result)]


def _per_row(robot, method, names, keywords, data):
    rows = [_parts(_call(robot, method, names, keywords, {k: np.ascontiguousarray(data[k][i]) for k in names})) for i in range(B)]
    return [np.stack([r[p] for r in rows]) for p in range(len(rows[0]))]


def _method_id(m):
    return f"{m[0]}({', '.join(m[1])})"


@pytest.mark.parametrize("method, names, keywords", METHODS, ids=[_method_id(m) for m in METHODS])
def test_every_layout_of_every_batch_argument_gives_the_per_state_rows_bit_for_bit(robot, data, method, names, keywords):
    expected = _per_row(robot, method, names, keywords, data)
    for arg in names:
        for layout, make in LAYOUTS.items():
            values = {k: np.ascontiguousarray(data[k]) for k in names}
            values[arg] = make(data[arg])
            got = _parts(_call(robot, method, names, keywords, values))
            assert len(got) == len(expected)
            for g, e in zip(got, expected):
                assert g.shape == e.shape, (arg, layout)
                assert np.array_equal(g, e), f"{method}: {arg} {layout}: max difference {np.max(np.abs(g - e))}"


@pytest.mark.parametrize("method, names, keywords", METHODS, ids=[_method_id(m) for m in METHODS])
def test_every_layout_of_a_one_state_argument_gives_the_same_result(robot, data, method, names, keywords):
    row = {k: np.ascontiguousarray(data[k][1]) for k in names}
    expected = _parts(_call(robot, method, names, keywords, row))
    for arg in names:
        for layout, make in LAYOUTS.items():
            values = dict(row)
            values[arg] = make(row[arg])
            got = _parts(_call(robot, method, names, keywords, values))
            for g, e in zip(got, expected):
                assert np.array_equal(g, e), f"{method}: one-state {arg} {layout}"


def test_a_broadcast_row_is_every_row(robot, data):
    tau = np.broadcast_to(data["tau"][0], (B, robot.n_dof))
    assert tau.strides[0] == 0
    got = robot.forward_dynamics(data["x"], data["u"], tau=tau)
    for i in range(B):
        assert np.array_equal(got[i], robot.forward_dynamics(data["x"][i], data["u"][i], tau=data["tau"][0]))


def test_the_issue_example_is_read_right(robot):
    # The reproduction of issue 38: 281.2 off on ad1bc7a.
    rng = np.random.default_rng(1)
    X = np.stack([robot.neutral_configuration() for _ in range(4)])
    U = rng.normal(size=(4, 12)) * 0.1
    T = rng.normal(size=(4, 6))
    ref = np.array([robot.forward_dynamics(X[i], U[i], tau=T[i]) for i in range(4)])
    assert np.array_equal(robot.forward_dynamics(X, U, tau=np.asfortranarray(T)), ref)
    assert np.array_equal(robot.forward_dynamics(np.asfortranarray(X), U.T.copy().T, tau=T), ref)
    acc = rng.normal(size=(4, 12))
    ref_id = np.array([robot.inverse_dynamics(X[i], U[i], acc[i]) for i in range(4)])
    assert np.array_equal(robot.inverse_dynamics(X, U, np.asfortranarray(acc)), ref_id)


@pytest.mark.parametrize("layout", list(LAYOUTS))
def test_a_bad_row_is_named_by_its_index_in_every_layout(robot, data, layout):
    x = data["x"].copy()
    x[2, 3:7] = [0.0, 0.0, 0.0, 2.0]
    with pytest.raises(QuaternionError, match=r"^row 2 of the batch: the base quaternion"):
        robot.mass_matrix(LAYOUTS[layout](x))
    u = data["u"].copy()
    u[1, 4] = np.nan
    with pytest.raises(NonFiniteError, match=r"^row 1 of the batch: u must be finite, but entry 4 is NaN"):
        robot.bias_forces(data["x"], LAYOUTS[layout](u))


def test_an_empty_batch_checks_the_one_state_arguments(robot, data):
    x_empty = np.empty((0, robot.nx))
    bad_x = data["x"][0].copy()
    bad_x[3:7] = [0.0, 0.0, 0.0, 2.0]
    with pytest.raises(QuaternionError, match="base quaternion"):
        robot.forward_dynamics(bad_x, data["u"][0], tau=np.empty((0, robot.n_dof)))
    nan_u = data["u"][0].copy()
    nan_u[2] = np.nan
    with pytest.raises(NonFiniteError, match=r"^u must be finite, but entry 2 is NaN"):
        robot.bias_forces(x_empty, nan_u)
    with pytest.raises(ShapeError):
        robot.bias_forces(x_empty, np.zeros(robot.nu + 1))
    # A valid empty batch is an empty result of the right shape.
    assert robot.bias_forces(x_empty, data["u"][0]).shape == (0, robot.nu)
    assert robot.mass_matrix(x_empty).shape == (0, robot.nu, robot.nu)


def test_other_real_dtypes_are_converted_by_one_rule(robot, data):
    x = data["x"]
    q_int = np.round(x * 0)  # zeros: exactly representable in every dtype
    q_int[:, 6] = 1.0
    expected = robot.mass_matrix(q_int)
    for dtype in [np.float32, np.int32, np.int64, np.uint8, ">i4", np.float16]:
        for layout in ["C", "Fortran", "negative strides"]:
            arr = LAYOUTS[layout](q_int).astype(dtype)
            arr = LAYOUTS[layout](arr) if layout != "C" else arr
            assert np.array_equal(robot.mass_matrix(arr), expected), (dtype, layout)


# ---- the other doors that take arrays ----------------------------------------------------

def test_rotations_read_every_layout(data):
    from spacearm import rotations

    q = data["x"][:, 3:7]
    a, b = np.ascontiguousarray(q), np.ascontiguousarray(q[::-1])
    expected = rotations.quat_multiply(a, b)
    mats = rotations.quat_to_matrix(a)
    for layout, make in LAYOUTS.items():
        assert np.array_equal(rotations.quat_multiply(make(a), b), expected), layout
        assert np.array_equal(rotations.quat_multiply(a, make(b)), expected), layout
        assert np.array_equal(rotations.quat_to_matrix(make(a)), mats), layout
        m3 = np.ascontiguousarray(mats[1])
        assert np.array_equal(rotations.quat_from_matrix(make(m3)), rotations.quat_from_matrix(m3)), layout


def test_rollouts_read_every_layout(robot, data):
    x0 = np.ascontiguousarray(data["x"])
    u0 = np.ascontiguousarray(data["u"]) * 0.1
    expected = spacearm.rollout(robot, 0.05, x0, u0, dt=0.01)
    for layout in ["Fortran", "negative strides", "unaligned", "big-endian"]:
        got = spacearm.rollout(robot, 0.05, LAYOUTS[layout](x0), LAYOUTS[layout](u0), dt=0.01)
        assert np.array_equal(got.x, expected.x), layout
        assert np.array_equal(got.u, expected.u), layout


def test_orbit_frames_read_every_layout():
    from spacearm.orbit import Orbit

    rng = np.random.default_rng(3)
    r = rng.normal(size=(4, 3)) * 7e6
    v = np.cross(r, rng.normal(size=(4, 3))) * 1e-3
    expected = Orbit.lvlh_to_eci(r, v)
    for layout, make in LAYOUTS.items():
        assert np.array_equal(Orbit.lvlh_to_eci(make(r), make(v)), expected), layout


def test_workspace_scans_read_every_layout(robot):
    from spacearm import _core

    rng = np.random.default_rng(4)
    samples = rng.uniform(-1, 1, (5, robot.n_dof))
    m = robot.core_model
    body = robot.n_bodies - 1
    expected = _core.analysis_scan(m, samples, body, [0.0, 0.0, 0.0], [0, 1, 2])
    for layout, make in LAYOUTS.items():
        got = _core.analysis_scan(m, make(samples), body, [0.0, 0.0, 0.0], [0, 1, 2])
        assert np.array_equal(got.sigma_min_generalized, expected.sigma_min_generalized), layout
        assert np.array_equal(got.point_from_base, expected.point_from_base), layout


def test_simulator_reads_every_layout(robot, data):
    x0, u0 = np.ascontiguousarray(data["x"][0]), np.ascontiguousarray(data["u"][0]) * 0.1
    tau = np.ascontiguousarray(data["tau"][0])

    def run(x, u, t):
        sim = spacearm.Simulator(robot, dt=0.01)
        sim.reset(x, u)
        return sim.step(t, n=3)

    expected = run(x0, u0, tau)
    for layout, make in LAYOUTS.items():
        assert np.array_equal(run(make(x0), make(u0), make(tau)), expected), layout


def test_identification_reads_every_layout(robot):
    from spacearm.identify import identify_payload

    traj = spacearm.simulate(robot, 0.2, dt=0.01, u0=np.r_[np.zeros(6), 0.3 * np.ones(robot.n_dof)])
    x, u = np.ascontiguousarray(traj.x), np.ascontiguousarray(traj.u)
    body = robot.n_bodies - 1
    expected = identify_payload(robot, x=x, u=u, body=body)
    for layout in ["Fortran", "negative strides", "unaligned", "big-endian"]:
        got = identify_payload(robot, x=LAYOUTS[layout](x), u=LAYOUTS[layout](u), body=body)
        assert np.array_equal(got.parameters, expected.parameters), layout


def test_vector_env_actions_read_every_layout():
    pytest.importorskip("gymnasium")
    from spacearm import gym as sgym

    def run(make):
        env = sgym.make_vec(3)
        env.reset(seed=7)
        actions = np.random.default_rng(5).uniform(-1, 1, (3, env.task.robot.n_dof))
        obs, *_ = env.step(make(actions))
        return obs

    expected = run(np.ascontiguousarray)
    for layout in ["Fortran", "negative strides", "unaligned", "big-endian", "transposed view"]:
        assert np.array_equal(run(LAYOUTS[layout]), expected), layout


def _configurations(robot, rng, rows):
    quat = rng.normal(size=(rows, 4))
    quat /= np.linalg.norm(quat, axis=1, keepdims=True)
    return np.hstack([rng.normal(size=(rows, 3)), quat, rng.uniform(-1, 1, (rows, robot.n_dof))])


def test_configuration_algebra_reads_every_layout(robot, data):
    rng = np.random.default_rng(9)
    x0, x1 = _configurations(robot, rng, B), _configurations(robot, rng, B)
    dx = data["dx"]
    plus = np.stack([robot.configuration_plus(x0[i], dx[i]) for i in range(B)])
    diff = np.stack([robot.configuration_difference(x1[i], x0[i]) for i in range(B)])
    for layout, make in LAYOUTS.items():
        for i in range(B):
            assert np.array_equal(robot.configuration_plus(make(x0[i]), make(dx[i])), plus[i]), layout
            assert np.array_equal(robot.configuration_difference(make(x1[i]), make(x0[i])), diff[i]), layout


def test_sampled_references_read_every_layout():
    from spacearm import control

    t = np.linspace(0.0, 1.0, 6)
    rng = np.random.default_rng(2)
    q, qd, qdd = (rng.normal(size=(6, 3)) for _ in range(3))
    expected = control.SampledJoint(t=t, q=q, qd=qd, qdd=qdd).evaluate([0.1, 0.55, 0.9])
    for layout, make in LAYOUTS.items():
        got = control.SampledJoint(t=make(t), q=make(q), qd=make(qd), qdd=make(qdd)).evaluate([0.1, 0.55, 0.9])
        for g, e in zip(got, expected):
            assert np.array_equal(g, e), layout
