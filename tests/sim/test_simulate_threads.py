"""simulate and rollout release the GIL: while one Python thread simulates, another thread runs
Python code (with the GIL held it could not run at all until the call returned), and runs on two
threads at once give the same records as one after the other."""

import threading
import time

import numpy as np

import spacearm


def longest_pause_of_python_while(call) -> tuple:
    """Run ``call`` on a thread while this thread ticks; return the longest gap between ticks
    during the call and the call's duration."""
    done = threading.Event()
    result = {}

    def worker():
        t0 = time.perf_counter()
        result["value"] = call()
        result["duration"] = time.perf_counter() - t0
        done.set()

    thread = threading.Thread(target=worker)
    ticks = [time.perf_counter()]
    thread.start()
    while not done.is_set():
        ticks.append(time.perf_counter())
    thread.join()
    return float(np.max(np.diff(ticks))), result["duration"], result["value"]


def test_python_runs_while_another_thread_simulates():
    robot = spacearm.presets.spatial6()
    u0 = robot.zero_velocity()
    u0[6:] = 0.3
    # Long enough (tenths of a second) to tell a released GIL from a held one.
    gap, duration, _ = longest_pause_of_python_while(lambda: spacearm.simulate(robot, 40.0, u0=u0, dt=1e-3, record_every=1000))
    assert duration > 0.1
    assert gap < 0.5 * duration, (gap, duration)
    x0 = np.tile(robot.neutral_configuration(), (4, 1))
    gap, duration, _ = longest_pause_of_python_while(lambda: spacearm.rollout(robot, 10.0, x0, u0, dt=1e-3, record_every=1000, threads=1))
    assert gap < 0.5 * duration, (gap, duration)


def test_two_threads_simulating_give_the_serial_records():
    robot = spacearm.presets.spatial6()
    states = []
    for k in range(2):
        u0 = robot.zero_velocity()
        u0[6:] = 0.1 * (k + 1)
        states.append(u0)
    serial = [spacearm.simulate(robot, 2.0, u0=u0, record_every=50) for u0 in states]
    out = [None, None]

    def run(k):
        out[k] = spacearm.simulate(robot, 2.0, u0=states[k], record_every=50)

    threads = [threading.Thread(target=run, args=(k,)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for a, b in zip(out, serial):
        np.testing.assert_array_equal(a.x, b.x)
        np.testing.assert_array_equal(a.energy, b.energy)
