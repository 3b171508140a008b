"""The Gym doors (issue 38): a batch too large for memory is refused before it is allocated,
actions of the wrong dtype or shape and non-finite ones are spacearm errors naming the action
(the copy and the entry of a vector env), render modes the env does not have are refused at
construction, one env stepped from two threads says so, and BatchSimulator.step answers Ctrl-C."""

from __future__ import annotations

import os
import signal
import threading
import time

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

import spacearm  # noqa: E402
import spacearm.gym as sgym  # noqa: E402
from spacearm import _core, errors  # noqa: E402
from spacearm.sim.simulation import DEFAULTS, _options  # noqa: E402


def _opts(robot, dt=1e-2):
    return _options(robot, mode="floating", integrator="rk4", dt=dt, rtol=DEFAULTS["rtol"], atol=DEFAULTS["atol"], wheels=None,
                    thrusters=None, record_every=1, joint_limits=False, max_steps=DEFAULTS["max_steps"], record_dtype="float64")


def test_a_million_copies_are_refused_before_anything_is_allocated():
    # Before: make_vec(10**6) allocated about 3 GB unadmitted and died with SIGABRT.
    with pytest.raises(errors.ResourceLimitError, match="a batch of 1000000 copies"):
        sgym.make_vec(10**6)
    robot = spacearm.presets.spatial6()
    with pytest.raises(errors.ResourceLimitError, match="more than the"):
        _core.BatchSimulator.admit(robot.core_model, 10**6)
    b = 10**6
    with pytest.raises(errors.ResourceLimitError):
        _core.BatchSimulator([robot.core_model] * b, np.tile(robot.neutral_configuration(), b), np.tile(robot.zero_velocity(), b),
                             _opts(robot))
    _core.BatchSimulator.admit(robot.core_model, 1000)


@pytest.mark.parametrize("action, error, match", [
    (lambda n: "abc", errors.SpacearmTypeError, r"action must be real numbers .*shape \(N,\)"),
    (lambda n: np.zeros(n, dtype=complex), errors.SpacearmTypeError, "complex"),
    (lambda n: np.zeros((n, 1)), errors.ArgumentError, r"shape \(N, 1\)"),
    (lambda n: np.zeros((1, n)), errors.ArgumentError, r"shape \(1, N\)"),
    (lambda n: np.r_[np.zeros(n - 1), np.nan], errors.NonFiniteError, "entry N-1 is nan"),
])
@pytest.mark.parametrize("env_id", ["spacearm/Reach-v0", "spacearm/Capture-v0", "spacearm/Detumble-v0"])
def test_single_env_actions_are_checked(env_id, action, error, match):
    # Before: step('abc') raised a plain ValueError; complex and (N, 1) actions were accepted.
    env = gymnasium.make(env_id, disable_env_checker=True).unwrapped
    env.reset(seed=0)
    n = env.action_space.shape[0]
    with pytest.raises(error, match=match.replace("N-1", str(n - 1)).replace("N", str(n))):
        env.step(action(n))


def test_vector_env_actions_name_the_copy_and_the_entry():
    env = sgym.ReachVectorEnv(4)
    env.reset(seed=0)
    a = np.zeros((4, 6))
    a[3, 0] = np.nan
    # Before: "tau must be finite, but entry 18 is nan".
    with pytest.raises(errors.NonFiniteError, match="actions of copy 3 must be finite, but entry 0 is nan"):
        env.step(a)
    with pytest.raises(errors.SpacearmTypeError, match="actions"):
        env.step(np.zeros((4, 6), dtype=complex))
    with pytest.raises(errors.ArgumentError, match=r"shape \(4, 6\)"):
        env.step(np.zeros(24))


def test_the_batch_simulator_names_the_copy_and_the_entry():
    robot = spacearm.presets.spatial6()
    b, n = 4, robot.n_dof
    batch = _core.BatchSimulator([robot.core_model] * b, np.tile(robot.neutral_configuration(), b), np.tile(robot.zero_velocity(), b),
                                 _opts(robot))
    tau = np.zeros(b * n)
    tau[3 * n + 2] = np.inf
    with pytest.raises(errors.NonFiniteError, match="tau of copy 3 must be finite, but entry 2 is inf"):
        batch.step(tau)


@pytest.mark.parametrize("make", [
    lambda: sgym.ReachVectorEnv(2, render_mode="human"),
    lambda: sgym.make_vec(2, render_mode="rgb_array"),
    lambda: sgym.ReachEnv(render_mode="human"),
    lambda: sgym.CaptureEnv(render_mode="human"),
    lambda: sgym.DetumbleEnv(render_mode="human"),
])
def test_render_modes_the_env_does_not_have_are_refused_at_construction(make):
    # Before: the vector env raised a builtin TypeError from deep inside ReachTask.
    with pytest.raises(errors.ArgumentError, match="render_mode"):
        make()


def _two_threads(call, repeats):
    """Run ``call`` from two threads at once, ``repeats`` times each: the messages of the
    SimulationErrors raised, and the reprs of any other exception (the defect)."""
    start = threading.Barrier(2)
    seen, others = [], []

    def worker():
        start.wait()
        for _ in range(repeats):
            try:
                call()
            except errors.SimulationError as exc:
                seen.append(str(exc))
            except Exception as exc:  # noqa: BLE001 - anything else is the defect
                others.append(repr(exc))

    threads = [threading.Thread(target=worker) for _ in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    return seen, others


def test_one_vector_env_stepped_from_two_threads_says_so():
    # Before: RuntimeError: Already borrowed (PyO3's), or a torn episode.
    env = sgym.ReachVectorEnv(256, threads=1)
    env.reset(seed=0)
    zeros = np.zeros(env.action_space.shape)
    seen, others = _two_threads(lambda: env.step(zeros), 40)
    assert others == []
    assert seen, "the two threads never overlapped"
    assert all("in use by another thread" in e for e in seen)


def test_the_batch_simulator_from_two_threads_says_so():
    robot = spacearm.presets.spatial6()
    b = 512
    batch = _core.BatchSimulator([robot.core_model] * b, np.tile(robot.neutral_configuration(), b), np.tile(robot.zero_velocity(), b),
                                 _opts(robot), 1)
    tau = np.zeros(b * robot.n_dof)
    seen, others = _two_threads(lambda: batch.step(tau, None, 5), 20)
    assert others == [] and seen and all("in use by another thread" in s for s in seen)


@pytest.mark.skipif(os.name != "posix", reason="SIGINT delivery")
def test_batch_simulator_step_answers_ctrl_c():
    # Before: a long step ran to its end, whatever SIGINT said.
    robot = spacearm.presets.spatial6()
    b = 64
    batch = _core.BatchSimulator([robot.core_model] * b, np.tile(robot.neutral_configuration(), b), np.tile(robot.zero_velocity(), b),
                                 _opts(robot), 1)
    tau = np.zeros(b * robot.n_dof)
    t0 = time.perf_counter()
    batch.step(tau, None, 20)
    per_step = (time.perf_counter() - t0) / 20
    steps = int(30.0 / per_step)  # about 30 s of stepping
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    t0 = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        batch.step(tau, None, steps)
    assert time.perf_counter() - t0 < 10.0
    timer.cancel()
