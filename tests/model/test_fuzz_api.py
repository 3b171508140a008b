"""The API never crashes: hypothesis calls the Robot methods, the builder, the rotation helpers
and ``simulate`` with hostile arguments (wrong lengths, shapes and dtypes, NaN and infinities,
huge and tiny magnitudes, objects of the wrong kind, unit and non-unit quaternions) and every
call must either return finite numbers or raise a :class:`spacearm.SpacearmError` (whose
message says what was wrong). A Rust panic (``PanicException``), a bare builtin exception or a
crash of the interpreter fails the test.

Counts (calls tried, refused, returned finite, returned non-finite) are printed with
``pytest -s``. Non-finite results from *finite, physically plausible* inputs (every number
within 1e6 in magnitude) fail the test; those from astronomically large inputs (joint rates of
1e200, whose products overflow) are counted and printed: raising them as ``NonFiniteError`` is
the job of the output check at the array boundary.

Budget: ``SPACEARM_FUZZ_EXAMPLES`` (default 600), derandomized, so CI runs the same calls
every time.
"""

from __future__ import annotations

import collections
import math
import os

import numpy as np
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

import spacearm
from spacearm import rotations

FUZZ_EXAMPLES = int(os.environ.get("SPACEARM_FUZZ_EXAMPLES", "600"))
# No shrinking: a failure is reported as found (shrinking these calls can take minutes).
PHASES = [Phase.explicit, Phase.generate]
FUZZ = settings(max_examples=FUZZ_EXAMPLES, deadline=None, derandomize=True, database=None, phases=PHASES,
                suppress_health_check=list(HealthCheck), report_multiple_bugs=False)
COUNTS: collections.Counter = collections.Counter()
PLAUSIBLE = 1e6

ROBOTS = {"planar4": spacearm.presets.planar4(), "spatial6": spacearm.presets.spatial6()}

# Numbers: mostly ordinary, sometimes hostile.
ordinary = st.floats(min_value=-3.0, max_value=3.0, allow_nan=False)
hostile = st.sampled_from([0.0, -0.0, 1e-300, -1e-300, 1e6, -1e6, 1e20, 1e200, -1e200, 1e308, math.inf, -math.inf,
                           math.nan])
numbers = st.one_of(ordinary, ordinary, ordinary, hostile)


@st.composite
def arrays(draw, length):
    """A vector argument: usually of the right length and float, sometimes not."""
    n = draw(st.one_of(st.just(length), st.just(length), st.just(length), st.integers(0, length + 3)))
    values = draw(st.lists(numbers, min_size=n, max_size=n))
    kind = draw(st.sampled_from(["array", "array", "list", "int", "bool", "complex", "object", "str", "2d", "none",
                                 "datetime", "scalar"]))
    if kind == "array":
        return np.array(values, dtype=float)
    if kind == "list":
        return values
    if kind == "int":
        return np.array([int(v) if math.isfinite(v) and abs(v) < 1e18 else 0 for v in values], dtype=np.int64)
    if kind == "bool":
        return np.array([v > 0 for v in values])
    if kind == "complex":
        return np.array(values, dtype=complex) + 1j
    if kind == "object":
        return np.array(values, dtype=object)
    if kind == "str":
        return [str(v) for v in values]
    if kind == "2d":
        return np.array(values, dtype=float).reshape(1, -1)
    if kind == "datetime":
        return np.arange(n).astype("datetime64[s]")
    if kind == "scalar":
        return 1.0
    return None


@st.composite
def configurations(draw, robot):
    """A configuration: usually valid (unit quaternion), sometimes hostile."""
    if draw(st.booleans()):
        q = draw(st.lists(ordinary, min_size=robot.n_dof, max_size=robot.n_dof))
        quat = np.array(draw(st.lists(st.floats(-1, 1), min_size=4, max_size=4)))
        norm = np.linalg.norm(quat)
        quat = quat / norm if norm > 1e-3 else np.array([0.0, 0.0, 0.0, 1.0])
        r0 = draw(st.lists(ordinary, min_size=3, max_size=3))
        return np.concatenate([r0, quat, q])
    return draw(arrays(robot.nx))


def plausible(*args) -> bool:
    """Whether every number in the arguments is finite and within PLAUSIBLE in magnitude."""
    for a in args:
        try:
            arr = np.asarray(a, dtype=float)
        except (TypeError, ValueError):
            return False
        if not np.all(np.isfinite(arr)) or np.any(np.abs(arr) > PLAUSIBLE):
            return False
    return True


def finite_result(value) -> bool:
    if isinstance(value, spacearm.Robot):
        return True
    if isinstance(value, (tuple, list)):
        return all(finite_result(v) for v in value)
    if hasattr(value, "_asdict"):
        return all(finite_result(v) for v in value._asdict().values())
    if hasattr(value, "__dataclass_fields__"):
        return all(finite_result(getattr(value, f)) for f in value.__dataclass_fields__)
    if isinstance(value, (float, int, np.ndarray, np.floating)):
        arr = np.asarray(value)
        return arr.dtype.kind not in "fc" or bool(np.all(np.isfinite(arr)))
    return True


def attempt(name, call, *args):
    """Run one call and classify it; anything but a SpacearmError or a finite result fails."""
    COUNTS["tried"] += 1
    try:
        value = call()
    except spacearm.SpacearmError as exc:
        assert str(exc), f"{name}: a refusal without a message"
        COUNTS["refused"] += 1
        return
    except BaseException as exc:  # a Rust panic is a BaseException
        COUNTS["crashed"] += 1
        raise AssertionError(f"{name} crashed with {type(exc).__name__}: {exc}") from exc
    if finite_result(value):
        COUNTS["finite"] += 1
        return
    if plausible(*args):
        COUNTS["silent non-finite (plausible input)"] += 1
        raise AssertionError(f"{name} returned non-finite values from plausible input")
    COUNTS["non-finite from huge input"] += 1


METHODS = {
    "mass_matrix": lambda r, x, u, v: r.mass_matrix(x),
    "mass_matrix_paper": lambda r, x, u, v: r.mass_matrix(x, method="paper"),
    "generalized_inertia": lambda r, x, u, v: r.generalized_inertia(x),
    "generalized_jacobian": lambda r, x, u, v: r.generalized_jacobian(x),
    "generalized_bias": lambda r, x, u, v: r.generalized_bias(x, u),
    "bias_forces": lambda r, x, u, v: r.bias_forces(x, u),
    "inverse_dynamics": lambda r, x, u, v: r.inverse_dynamics(x, u, v),
    "forward_dynamics": lambda r, x, u, v: r.forward_dynamics(x, u, v),
    "forward_dynamics_mass_matrix": lambda r, x, u, v: r.forward_dynamics(x, u, v, method="mass_matrix"),
    "point_twist": lambda r, x, u, v: r.point_twist(x, v[: r.n_dof] if isinstance(v, np.ndarray) else v),
    "base_velocity_from_momentum": lambda r, x, u, v: r.base_velocity_from_momentum(
        x, v[: r.n_dof] if isinstance(v, np.ndarray) else v),
    "momentum": lambda r, x, u, v: r.momentum(x, u),
    "kinetic_energy": lambda r, x, u, v: r.kinetic_energy(x, u),
    "center_of_mass": lambda r, x, u, v: r.center_of_mass(x),
    "point_position": lambda r, x, u, v: r.point_position(x),
    "base_inertia_inverse": lambda r, x, u, v: r.base_inertia_inverse(x),
    "forward_kinematics": lambda r, x, u, v: r.forward_kinematics(x),
    "mass_matrix_derivative": lambda r, x, u, v: r.mass_matrix_derivative(x, u),
    "linearize": lambda r, x, u, v: r.linearize(x, u, v),
    "neutral_configuration": lambda r, x, u, v: r.neutral_configuration(
        q=v[: r.n_dof] if isinstance(v, np.ndarray) else v, quat0=x[3:7] if isinstance(x, np.ndarray) else x),
    "mass_matrix(robot)": lambda r, x, u, v: r.mass_matrix(r),
}


@FUZZ
@given(data=st.data(), robot_name=st.sampled_from(sorted(ROBOTS)), method=st.sampled_from(sorted(METHODS)))
def test_robot_methods(data, robot_name, method):
    robot = ROBOTS[robot_name]
    x = data.draw(configurations(robot))
    u = data.draw(arrays(robot.nu))
    v = data.draw(arrays(robot.nu))
    attempt(method, lambda: METHODS[method](robot, x, u, v), x, u, v)


@FUZZ
@given(mass=numbers, base_mass=numbers, origin=st.lists(numbers, min_size=3, max_size=3),
       com=st.lists(numbers, min_size=3, max_size=3), inertia=st.lists(numbers, min_size=3, max_size=3),
       axis=st.lists(numbers, min_size=3, max_size=3))
def test_builder(mass, base_mass, origin, com, inertia, axis):
    def build():
        b = spacearm.RobotBuilder("fuzz", abs(base_mass) * 100, [10.0, 12.0, 14.0])
        b.add_link("arm", parent="base", joint="revolute", axis=axis, origin=origin, com=com, mass=mass,
                   inertia=[abs(i) for i in inertia])
        b.add_point("tip", body="arm", offset=origin)
        robot = b.build()
        return robot.mass_matrix(robot.neutral_configuration())

    attempt("builder", build, mass, base_mass, origin, com, inertia, axis)


@FUZZ
@given(v=arrays(4), w=arrays(3), angle=numbers, m=st.lists(numbers, min_size=9, max_size=9))
def test_rotations(v, w, angle, m):
    attempt("quat_to_matrix", lambda: rotations.quat_to_matrix(v), v)
    attempt("quat_from_axis_angle", lambda: rotations.quat_from_axis_angle(w, angle), w, angle)
    attempt("quat_from_rpy", lambda: rotations.quat_from_rpy(angle, angle, angle), angle)
    attempt("quat_from_matrix", lambda: rotations.quat_from_matrix(np.reshape(m, (3, 3))), m)


@settings(max_examples=max(FUZZ_EXAMPLES // 20, 20), deadline=None, derandomize=True, database=None, phases=PHASES,
          suppress_health_check=list(HealthCheck), report_multiple_bugs=False)
@given(duration=numbers, dt=numbers, integrator=st.sampled_from(["rk4", "dopri5"]),
       record_every=st.integers(-1, 3), u0=arrays(12))
def test_simulate(duration, dt, integrator, record_every, u0):
    robot = ROBOTS["spatial6"]
    # Keep accepted runs short: at most 2000 output samples (longer ones are refused or capped).
    if math.isfinite(duration) and math.isfinite(dt) and dt > 0 and abs(duration) / dt > 2000:
        duration = math.copysign(2000 * dt, duration)
    attempt("simulate", lambda: spacearm.simulate(robot, duration, u0=u0, dt=dt, integrator=integrator,
                                                  record_every=record_every, progress=False), duration, dt, u0)


def test_report_counts():
    """Print the counts of the fuzz above (run with ``-s``); it ran if anything was tried."""
    print("\nAPI fuzz:", dict(COUNTS))
    assert COUNTS["crashed"] == 0
