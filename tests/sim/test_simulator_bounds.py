"""Simulator.step: n typed and checked, the records admitted before the steps, Ctrl-C within a
second of a long call (issue 26, item 7)."""

from __future__ import annotations

import sys
import textwrap

import numpy as np
import pytest

import spacearm
from interrupt_child import interrupt_child


@pytest.fixture
def sim():
    s = spacearm.Simulator(spacearm.presets.planar4(), dt=1e-3, record_every=1)
    s.reset()
    return s


@pytest.mark.parametrize("n, error", [(-1, spacearm.ArgumentError), (0, spacearm.ArgumentError), ("3", spacearm.SpacearmTypeError),
                                      (1.5, spacearm.SpacearmTypeError), (True, spacearm.SpacearmTypeError),
                                      ([2], spacearm.SpacearmTypeError), (2**80, spacearm.ArgumentError)])
def test_a_bad_step_count_is_a_spacearm_error(sim, n, error):
    with pytest.raises(error, match="n must be|n must"):
        sim.step(n=n)
    assert sim.n_steps == 0


def test_good_step_counts(sim):
    sim.step(n=np.int64(3))
    sim.step(n=None)  # None: one step
    sim.step()
    assert sim.n_steps == 5


def test_the_records_of_a_long_call_are_refused_before_it_runs(sim):
    with pytest.raises(spacearm.ResourceLimitError, match="recording"):
        sim.step(n=10**9)
    assert sim.n_steps == 0
    sim.step(n=2)  # the simulator goes on
    assert sim.n_steps == 2


CHILD = textwrap.dedent("""
    import sys
    import spacearm
    sim = spacearm.Simulator(spacearm.presets.spatial6(), dt=1e-3)  # nothing recorded: no admission limit
    sim.reset()
    print("started", flush=True)
    try:
        sim.step(n=10**9)  # hours of steps
    except KeyboardInterrupt:
        print("interrupted", sim.n_steps > 0, flush=True)
        sys.exit(130)
    print("finished", flush=True)
""")


@pytest.mark.skipif(sys.platform == "win32", reason="SIGINT to a child process")
def test_ctrl_c_stops_a_long_step_call_within_a_second():
    a = interrupt_child(CHILD, 0.3)
    assert a.out.strip() == "interrupted True", a.out
    assert a.returncode == 130
    assert a.waited < 1.0, f"took {a.waited:.2f} s to answer Ctrl-C"


def test_counts_beyond_what_the_core_takes_are_argument_errors():
    # Issue 38: Simulator(record_every=10**130) and gym.make_vec(10**130) raised a builtin
    # OverflowError from the conversion to the core's usize; one count rule now answers.
    import spacearm
    from spacearm.errors import ArgumentError

    robot = spacearm.presets.planar4()
    with pytest.raises(ArgumentError, match=r"record_every must be an integer from 1 to 2\*\*63 - 1, got ~1e\+130 \(131 digits\)"):
        spacearm.Simulator(robot, record_every=10**130)
    with pytest.raises(ArgumentError, match="max_steps must be an integer from 1 to"):
        spacearm.simulate(robot, 0.1, max_steps=2**64)
    gym = pytest.importorskip("spacearm.gym")
    pytest.importorskip("gymnasium")
    with pytest.raises(ArgumentError, match="num_envs must be an integer from 1 to"):
        gym.make_vec(10**130)
