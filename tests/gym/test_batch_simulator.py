"""The core's batch stepper (spacearm._core.BatchSimulator over sim/batch_stepper.rs) against
one spacearm.Simulator per copy: bit for bit, whatever the thread count."""

import numpy as np
import pytest

import spacearm
from spacearm import _core, control
from spacearm.errors import ArgumentError, SpacearmError
from spacearm.sim.simulation import DEFAULTS, _options


def _opts(robot, dt):
    return _options(robot, mode="floating", integrator="rk4", dt=dt, rtol=DEFAULTS["rtol"], atol=DEFAULTS["atol"], wheels=None,
                    thrusters=None, record_every=1, joint_limits=False, max_steps=DEFAULTS["max_steps"], record_dtype="float64")


@pytest.mark.parametrize("threads", [1, 2, None])
def test_a_batch_step_equals_one_simulator_step_per_copy(threads):
    robot = spacearm.presets.spatial6()
    plants = [robot, control.perturbed_model(robot, base_mass_scale=1.3, link_mass_scale=0.8),
              control.perturbed_model(robot, base_inertia_scale=0.7, slosh_fraction=0.05, slosh_offset=(0.3, 0.1, 0.0))]
    rng = np.random.default_rng(3)
    b, dt, n = len(plants), 5e-3, robot.n_dof
    x0 = np.tile(robot.neutral_configuration(), (b, 1))
    x0[:, 7:] += rng.uniform(-0.3, 0.3, size=(b, n))
    u0 = np.zeros((b, robot.nu))
    u0[:, 3:] = rng.uniform(-0.05, 0.05, size=(b, 3 + n))
    batch = _core.BatchSimulator([p.core_model for p in plants], x0.ravel(), u0.ravel(), _opts(robot, dt), threads)
    sims = []
    for p, x, u in zip(plants, x0, u0):
        s = spacearm.Simulator(p, dt=dt, joint_limits=False)
        s.reset(x, u)
        sims.append(s)
    assert len(batch) == b
    for k in range(12):
        tau = rng.uniform(-5, 5, size=(b, n))
        wrench = rng.uniform(-1, 1, size=(b, 6)) if k % 2 else None
        steps = 1 + k % 3
        states = batch.step(tau.ravel(), None if wrench is None else wrench.ravel(), steps)
        assert states.shape == (b, 13 + 2 * n)
        for i, s in enumerate(sims):
            expected = s.step(tau[i], steps, None if wrench is None else wrench[i])
            assert np.array_equal(states[i], expected), (k, i)
    assert np.array_equal(batch.states, np.array([s.state for s in sims]))
    assert np.array_equal(batch.times, [s.time for s in sims])
    assert batch.n_steps == [s.n_steps for s in sims]
    # The state moved (a check that cannot pass on a frozen batch).
    assert np.max(np.abs(batch.states[:, 7:13] - x0[:, 7:])) > 1e-3


def test_a_reset_copy_starts_again_with_its_new_plant():
    robot = spacearm.presets.spatial6()
    dt = 1e-2
    heavy = control.perturbed_model(robot, link_mass_scale=2.0)
    x0, u0 = robot.neutral_configuration(), robot.zero_velocity()
    batch = _core.BatchSimulator([robot.core_model] * 2, np.tile(x0, 2), np.tile(u0, 2), _opts(robot, dt), 1)
    tau = np.full(2 * robot.n_dof, 3.0)
    batch.step(tau)
    batch.reset(1, x0, u0, heavy.core_model)
    assert batch.n_steps == [1, 0]
    states = batch.step(tau)
    sim = spacearm.Simulator(heavy, dt=dt, joint_limits=False)
    sim.reset(x0, u0)
    assert np.array_equal(states[1], sim.step(tau[: robot.n_dof]))


def test_wrong_arguments_are_spacearm_errors():
    robot = spacearm.presets.spatial6()
    x0, u0 = robot.neutral_configuration(), robot.zero_velocity()
    opts = _opts(robot, 1e-2)
    with pytest.raises(SpacearmError):
        _core.BatchSimulator([], x0, u0, opts)
    with pytest.raises(ArgumentError):
        _core.BatchSimulator([robot.core_model], x0, u0, opts, 0)
    batch = _core.BatchSimulator([robot.core_model] * 2, np.tile(x0, 2), np.tile(u0, 2), opts)
    with pytest.raises(SpacearmError):
        batch.step(np.zeros(robot.n_dof))
    with pytest.raises(SpacearmError):
        batch.step(np.full(2 * robot.n_dof, np.nan))
    with pytest.raises(ArgumentError):
        batch.reset(2, x0, u0)
    with pytest.raises(ArgumentError):
        batch.reset(0, x0, u0, spacearm.presets.planar4().core_model)
