"""Long native calls answer: batch inputs admitted before they are copied (a broadcast view is
not materialized first), Ctrl-C stops a rollout within a second, complex arrays are refused, the
thread count is bounded (issue 26, item 7)."""

from __future__ import annotations

import sys
import textwrap

import numpy as np
import pytest

import spacearm
from interrupt_child import interrupt_child


def test_a_batch_input_beyond_the_memory_limit_is_refused_before_it_is_copied():
    robot = spacearm.presets.spatial6()
    x = robot.neutral_configuration()
    # A 104-byte broadcast view of 3e7 rows: 3.1 GB once read into the call's buffer (the
    # output, 0.7 GB, alone would be admitted): refused, nothing copied.
    view = np.broadcast_to(x, (3 * 10**7, robot.nx))
    assert view.strides[0] == 0
    with pytest.raises(spacearm.ResourceLimitError, match=r"reading x \(30000000 rows of 13, 1 copy\)"):
        robot.center_of_mass(view)
    # integers count twice: numpy's float64 conversion, then the rows
    with pytest.raises(spacearm.ResourceLimitError, match="2 copies"):
        robot.center_of_mass(np.broadcast_to(np.zeros(robot.nx, dtype=np.int64), (2 * 10**7, robot.nx)))


def test_a_strided_float64_view_is_read_through_its_strides():
    robot = spacearm.presets.spatial6()
    rng = np.random.default_rng(3)
    xs = np.tile(robot.neutral_configuration(), (8, 1))
    xs[:, 7:] += rng.normal(scale=0.3, size=(8, robot.n_dof))
    wide = np.zeros((8, 2 * robot.nx))
    wide[:, ::2] = xs  # every other column: not contiguous
    np.testing.assert_array_equal(robot.center_of_mass(wide[:, ::2]), robot.center_of_mass(xs))
    np.testing.assert_array_equal(robot.center_of_mass(np.broadcast_to(xs[0], (5, robot.nx))), np.tile(robot.center_of_mass(xs[0]), (5, 1)))


def test_thread_counts_are_bounded():
    before = spacearm.batch_threads()
    with pytest.raises(spacearm.ArgumentError, match="at most 1024"):
        spacearm._core.set_batch_threads(10**6)
    assert spacearm.batch_threads() == before


def test_rollout_refuses_complex_states():
    robot = spacearm.presets.planar4()
    with pytest.raises(spacearm.SpacearmTypeError, match="x0 must hold real numbers"):
        spacearm.rollout(robot, 0.01, x0=np.tile(robot.neutral_configuration(), (2, 1)).astype(complex))


CHILD = textwrap.dedent("""
    import sys
    import spacearm
    robot = spacearm.presets.spatial6()
    print("started", flush=True)
    try:
        # 2 rollouts of 10^7 steps each, minutes of work, recording only their ends
        spacearm.rollout(robot, 1e4, x0=[robot.neutral_configuration()] * 2, dt=1e-3, record_every=10**8)
    except KeyboardInterrupt:
        print("interrupted", flush=True)
        sys.exit(130)
    print("finished", flush=True)
""")


@pytest.mark.skipif(sys.platform == "win32", reason="SIGINT to a child process")
def test_ctrl_c_stops_a_rollout_within_a_second():
    a = interrupt_child(CHILD, 0.5)
    assert a.out.strip() == "interrupted", a.out
    assert a.returncode == 130
    assert a.waited < 1.0, f"took {a.waited:.2f} s to answer Ctrl-C"


BATCH_CHILD = textwrap.dedent("""
    import sys
    import numpy as np
    import spacearm
    robot = spacearm.presets.spatial6()
    spacearm.set_batch_threads(1)
    B = 4_000_000  # seconds of work on one thread; the inputs are views (no copy), the output 380 MB
    x = np.broadcast_to(robot.neutral_configuration(), (B, robot.nx))
    u = np.broadcast_to(robot.zero_velocity(), (B, robot.nu))
    robot.forward_dynamics(x[:1000], u[:1000])
    print("started", flush=True)
    try:
        robot.forward_dynamics(x, u)
    except KeyboardInterrupt:
        print("interrupted", flush=True)
        sys.exit(130)
    print("finished", flush=True)
""")


@pytest.mark.skipif(sys.platform == "win32", reason="SIGINT to a child process")
def test_ctrl_c_stops_a_long_batch_call_within_a_second():
    # issue 26: "a long batch call stops only when it returns"
    a = interrupt_child(BATCH_CHILD, 0.5)
    assert a.out.strip() == "interrupted", (a.out, a.err[-500:])
    assert a.returncode == 130
    assert a.waited < 1.0, f"took {a.waited:.2f} s to answer Ctrl-C"
