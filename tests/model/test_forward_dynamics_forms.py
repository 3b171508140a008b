"""``forward_dynamics(x, u, tau=..., base_wrench=...)`` and ``forward_dynamics(x, u, f)`` are the
same computation: bit-identical results for every method, on random states of random trees
(fixed and prismatic joints, branches) and the presets, and errors that name the argument."""

from __future__ import annotations

import numpy as np
import pytest

import spacearm
from spacearm import presets
from spacearm.errors import ArgumentError, NonFiniteError, ShapeError
from random_models import random_model, random_state

MODELS = [f"random{s}" for s in range(0, 36, 5)] + list(presets.NAMES)
METHODS = ("aba", "mass_matrix", "reduced")


def model(name: str) -> spacearm.Robot:
    return random_model(int(name[6:])).robot if name.startswith("random") else presets.get(name)


@pytest.mark.parametrize("name", MODELS)
def test_tau_form_is_bit_identical_to_f_form(name):
    robot = model(name)
    rng = np.random.default_rng(abs(hash(name)) % 2**32)
    n = robot.n_dof
    for _ in range(4):
        x, u = random_state(robot, rng)
        tau = rng.normal(scale=5.0, size=n)
        fb = np.concatenate([rng.normal(scale=20.0, size=3), rng.normal(scale=5.0, size=3)])
        for method in METHODS:
            cases = [
                (dict(tau=tau), np.concatenate([np.zeros(6), tau])),
                (dict(tau=tau, base_wrench=fb), np.concatenate([fb, tau])),
                (dict(base_wrench=fb), np.concatenate([fb, np.zeros(n)])),
                (dict(), np.zeros(6 + n)),
                (dict(tau=list(tau), base_wrench=tuple(fb)), np.concatenate([fb, tau])),  # converted inputs
            ]
            for kwargs, f in cases:
                by_parts = robot.forward_dynamics(x, u, method=method, **kwargs)
                by_f = robot.forward_dynamics(x, u, f, method=method)
                assert np.array_equal(by_parts, by_f), (name, method, sorted(kwargs))
        # ... and the form does not change what the equations say: H du + c = f (eq. 36).
        f = np.concatenate([fb, tau])
        du = robot.forward_dynamics(x, u, tau=tau, base_wrench=fb)
        residual = robot.mass_matrix(x) @ du + robot.bias_forces(x, u) - f
        assert np.max(np.abs(residual)) <= 1e-9 * (1.0 + np.max(np.abs(f)))


def test_tau_form_with_external_wrenches_is_bit_identical():
    robot = presets.spatial6()
    rng = np.random.default_rng(7)
    x, u = random_state(robot, rng)
    tau, fb = rng.normal(size=robot.n_dof), rng.normal(size=6)
    w = [spacearm.ExternalWrench("link3", force=[1.0, -2.0, 0.5], torque=[0.1, 0.0, -0.3], offset=[0.1, 0.0, 0.0])]
    for method in ("aba", "mass_matrix"):
        by_parts = robot.forward_dynamics(x, u, tau=tau, base_wrench=fb, wrenches=w, method=method)
        by_f = robot.forward_dynamics(x, u, np.concatenate([fb, tau]), wrenches=w, method=method)
        assert np.array_equal(by_parts, by_f)
        assert not np.array_equal(by_parts, robot.forward_dynamics(x, u, tau=tau, base_wrench=fb, method=method))
    with pytest.raises(ArgumentError, match="no external wrenches"):
        robot.forward_dynamics(x, u, tau=tau, wrenches=w, method="reduced")


@pytest.mark.parametrize("method", METHODS)
def test_bad_parts_name_the_argument(method):
    robot = presets.planar4()
    x, u, n = robot.neutral_configuration(), robot.zero_velocity(), robot.n_dof
    with pytest.raises(ShapeError, match=r"^tau must have length 4, got 3"):
        robot.forward_dynamics(x, u, tau=np.zeros(3), method=method)
    with pytest.raises(ShapeError, match=r"^base_wrench must have length 6, got 5"):
        robot.forward_dynamics(x, u, tau=np.zeros(n), base_wrench=np.zeros(5), method=method)
    with pytest.raises(NonFiniteError, match=r"^tau must be finite, but entry 2 is NaN"):
        robot.forward_dynamics(x, u, tau=[0, 0, np.nan, 0], method=method)
    with pytest.raises(NonFiniteError, match=r"^base_wrench must be finite, but entry 5 is inf"):
        robot.forward_dynamics(x, u, base_wrench=[0, 0, 0, 0, 0, np.inf], method=method)
    with pytest.raises(ShapeError, match="tau"):
        robot.forward_dynamics(x, u, tau="strong", method=method)
    with pytest.raises(ShapeError, match=r"^x must have length"):
        robot.forward_dynamics(x[:-1], u, tau=np.zeros(n), method=method)
    with pytest.raises(ArgumentError, match="not both"):
        robot.forward_dynamics(x, u, np.zeros(6 + n), base_wrench=np.zeros(6), method=method)


def test_no_input_reaches_a_panic():
    # A Rust panic would surface as pyo3's PanicException (a BaseException, not caught here).
    from spacearm.errors import SpacearmError

    robot = presets.planar4()
    x, u, n = robot.neutral_configuration(), robot.zero_velocity(), robot.n_dof
    bad = [np.zeros((2, n)), np.zeros(0), [], [[1.0] * n], np.zeros(n, dtype=complex), np.zeros(2 * n)[::2] * np.nan,
           object(), {"a": 1}, np.zeros(10**6)]
    for value in bad:
        for kwargs in (dict(tau=value), dict(base_wrench=value), dict(tau=np.zeros(n), base_wrench=value)):
            for method in METHODS:
                with pytest.raises(SpacearmError):
                    robot.forward_dynamics(x, u, method=method, **kwargs)
    with pytest.raises(SpacearmError):
        robot.forward_dynamics(x, u, tau=np.zeros(n), wrenches=[spacearm.ExternalWrench(99)])
    # A model without joints: tau is empty.
    rigid = spacearm.RobotBuilder("rigid", 10.0, [1.0, 2.0, 3.0]).build()
    du = rigid.forward_dynamics(rigid.neutral_configuration(), rigid.zero_velocity(), tau=[], base_wrench=[10.0, 0, 0, 0, 0, 2.0])
    np.testing.assert_allclose(du, [1.0, 0, 0, 0, 0, 2.0 / 3.0], rtol=1e-15)
