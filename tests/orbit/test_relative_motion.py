"""Relative motion in LVLH (docs/orbit.md): the Clohessy–Wiltshire closed form against scipy's
integration of Hill's equations, the exact two-body relative motion against it (agreement in the
linear regime, divergence growing as the square of the separation), the safety ellipse, and a
free body in an orbital run following Hill's equations."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import spacearm


def _hill(n):
    def f(t, s):
        x, y, z, vx, vy, vz = s
        return [vx, vy, vz, 3 * n * n * x + 2 * n * vy, -2 * n * vx, -n * n * z]
    return f


def test_cw_closed_form_matches_scipy_integration_of_hills_equations():
    orbit = spacearm.Orbit.circular(500e3)
    n = orbit.mean_motion
    rel0 = np.array([12.0, -30.0, 5.0, 0.01, -0.02, 0.005])
    times = np.linspace(0.0, 1.5 * orbit.period, 41)
    ref = solve_ivp(_hill(n), (0, times[-1]), rel0, t_eval=times, method="DOP853", rtol=1e-12, atol=1e-12).y.T
    cw = orbit.clohessy_wiltshire(rel0, times)
    np.testing.assert_allclose(cw, ref, rtol=0, atol=1e-7 * np.max(np.abs(ref)))


def _divergence(orbit, d):
    rel0 = np.array([0.0, d, 0.0, 0.0, 0.0, 0.0])  # V-bar, at rest: stationary under CW
    times = np.linspace(0.0, orbit.period, 21)
    exact = orbit.relative_motion(rel0, times)
    cw = orbit.clohessy_wiltshire(rel0, times)
    return np.max(np.linalg.norm(exact[:, :3] - cw[:, :3], axis=1))


def test_exact_relative_motion_agrees_in_the_linear_regime_and_diverges_quadratically():
    orbit = spacearm.Orbit.circular(500e3)
    rel0 = np.array([5.0, 10.0, -3.0, 0.002, -0.01, 0.001])
    times = np.linspace(0.0, orbit.period, 21)
    exact = orbit.relative_motion(rel0, times)
    cw = orbit.clohessy_wiltshire(rel0, times)
    assert np.max(np.abs(exact[:, :3] - cw[:, :3])) < 1e-3  # m, over one orbit at ~10 m
    e1, e10 = _divergence(orbit, 1e3), _divergence(orbit, 1e4)
    assert e10 > 10.0  # m: at 10 km V-bar the linear model is tens of metres off after one orbit
    assert e10 / e1 == pytest.approx(100.0, rel=0.1)  # second order in the separation


def test_safety_ellipse_is_closed_and_has_the_stated_axes():
    orbit = spacearm.Orbit.circular(500e3)
    rel0 = orbit.safety_ellipse(50.0, cross_track=20.0, along_track=-200.0)
    times = np.linspace(0.0, orbit.period, 401)
    cw = orbit.clohessy_wiltshire(rel0, times)
    np.testing.assert_allclose(cw[-1], rel0, atol=1e-9)
    assert np.ptp(cw[:, 0]) == pytest.approx(100.0, rel=1e-4)
    assert np.ptp(cw[:, 1]) == pytest.approx(200.0, rel=1e-4)
    assert np.mean(cw[:, 1]) == pytest.approx(-200.0, abs=1.0)
    assert np.max(np.abs(cw[:, 2])) == pytest.approx(20.0, rel=1e-4)
    exact = orbit.relative_motion(rel0, times)
    assert np.max(np.linalg.norm(exact[:, :3] - cw[:, :3], axis=1)) < 0.05  # m: nearly closed in truth too


def test_a_free_body_in_an_orbital_run_follows_hills_equations():
    """The loop's tidal force on a body away from the orbit's point is Hill's linearized
    gravity: its relative path, seen in LVLH, is the CW closed form."""
    target = spacearm.Target(500.0, np.diag([50.0, 60.0, 70.0]))
    orbit = spacearm.Orbit.circular(500e3, inclination=0.7, raan=0.2)
    n = orbit.mean_motion
    rel0 = np.array([10.0, -20.0, 4.0, 0.003, 0.01, -0.002])
    c = spacearm.Orbit.lvlh_to_eci(orbit.r0, orbit.v0)
    rho = c @ rel0[:3]
    x0 = np.concatenate([rho, [0.0, 0.0, 0.0, 1.0]])
    u0 = np.concatenate([c @ rel0[3:] + np.cross(n * c[:, 2], rho), np.zeros(3)])
    period = orbit.period
    traj = spacearm.simulate(target.body, 0.5 * period, x0=x0, u0=u0, orbit=orbit, integrator="dopri5", dt=60.0,
                             rtol=1e-11, atol=1e-12)
    r_o, v_o = orbit.propagate(traj.t)
    lvlh = spacearm.Orbit.lvlh_to_eci(r_o, v_o)
    seen = np.einsum("kji,kj->ki", lvlh, traj.com)
    cw = orbit.clohessy_wiltshire(rel0, traj.t)
    assert np.max(np.abs(cw[:, :3] - rel0[:3])) > 10.0  # it moved
    np.testing.assert_allclose(seen, cw[:, :3], rtol=0, atol=1e-4)
