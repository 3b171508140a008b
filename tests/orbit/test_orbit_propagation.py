"""spacearm.Orbit against independent sources (docs/orbit.md): the two-body + J2 point-mass
equations integrated by scipy, the textbook element-to-state formulas written out here, and the
J2 secular rates of RAAN and argument of perigee (Vallado eq. 9-41) fitted over many orbits."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import spacearm
from spacearm.errors import ArgumentError

MU, RE, J2 = 3.986004418e14, 6378137.0, 1.08262668e-3


def _accel(r, j2):
    rn = np.linalg.norm(r)
    a = -MU * r / rn**3
    if j2:
        z2 = (r[2] / rn) ** 2
        k = -1.5 * J2 * MU * RE**2 / rn**5
        a = a + k * np.array([r[0] * (1 - 5 * z2), r[1] * (1 - 5 * z2), r[2] * (3 - 5 * z2)])
    return a


def _scipy(orbit, times, j2):
    sol = solve_ivp(lambda t, y: np.concatenate([y[3:], _accel(y[:3], j2)]), (0.0, times[-1]),
                    np.concatenate([orbit.r0, orbit.v0]), method="DOP853", t_eval=times, rtol=1e-13, atol=1e-6)
    assert sol.success
    return sol.y[:3].T, sol.y[3:].T


def _coe2rv(a, e, i, raan, argp, nu):
    """Vallado's COE2RV, written here from the formulas (perifocal state, then 3-1-3 rotation)."""
    p = a * (1 - e * e)
    r_pf = np.array([p * math.cos(nu) / (1 + e * math.cos(nu)), p * math.sin(nu) / (1 + e * math.cos(nu)), 0.0])
    v_pf = math.sqrt(MU / p) * np.array([-math.sin(nu), e + math.cos(nu), 0.0])
    cO, sO, ci, si, cw, sw = math.cos(raan), math.sin(raan), math.cos(i), math.sin(i), math.cos(argp), math.sin(argp)
    rot = np.array([
        [cO * cw - sO * sw * ci, -cO * sw - sO * cw * ci, sO * si],
        [sO * cw + cO * sw * ci, -sO * sw + cO * cw * ci, -cO * si],
        [sw * si, cw * si, ci],
    ])
    return rot @ r_pf, rot @ v_pf


@pytest.mark.parametrize("j2", [False, True])
def test_propagation_matches_scipy_integration_of_the_point_mass_equations(j2):
    orbit = spacearm.Orbit.from_elements(7.0e6, 0.02, 0.9, 0.4, 1.0, 0.3, j2=j2)
    times = np.linspace(0.0, 3 * orbit.period, 31)
    r, v = orbit.propagate(times)
    r_ref, v_ref = _scipy(orbit, times, j2)
    assert np.max(np.linalg.norm(r - r_ref, axis=1)) < 0.05  # m, over 3 orbits (17,500 s)
    assert np.max(np.linalg.norm(v - v_ref, axis=1)) < 5e-5  # m/s
    if j2:  # J2 matters at this level: without it the orbits part by kilometres
        r_kepler, _ = _scipy(orbit, times, False)
        assert np.max(np.linalg.norm(r_kepler - r_ref, axis=1)) > 1e3


def test_elements_give_the_textbook_state_and_come_back():
    el = (7.2e6, 0.05, 0.9, 1.1, 2.3, 4.0)
    orbit = spacearm.Orbit.from_elements(*el)
    r, v = _coe2rv(*el)
    np.testing.assert_allclose(orbit.r0, r, rtol=0, atol=1e-6)
    np.testing.assert_allclose(orbit.v0, v, rtol=0, atol=1e-9)
    back = orbit.elements()
    np.testing.assert_allclose([back.a, back.e, back.i, back.raan, back.argp, back.true_anomaly], el, rtol=1e-10, atol=1e-10)
    # Elements in and out through a state: from_state gives the same orbit.
    again = spacearm.Orbit.from_state(orbit.r0, orbit.v0)
    assert again.elements().a == pytest.approx(7.2e6, rel=1e-12)


def test_circular_orbit_speed_period_and_argument_of_latitude():
    orbit = spacearm.Orbit.circular(500e3, inclination=math.radians(51.6), raan=0.2, arg_latitude=0.7)
    a = RE + 500e3
    assert np.linalg.norm(orbit.r0) == pytest.approx(a, rel=1e-14)
    assert np.linalg.norm(orbit.v0) == pytest.approx(math.sqrt(MU / a), rel=1e-14)
    assert orbit.period == pytest.approx(2 * math.pi * math.sqrt(a**3 / MU), rel=1e-12)
    assert float(np.dot(orbit.r0, orbit.v0)) == pytest.approx(0.0, abs=1e-15 * a * 8e3 * 10)
    # Argument of latitude: the angle from the ascending node to r, in the orbit plane.
    node = np.array([math.cos(0.2), math.sin(0.2), 0.0])
    assert math.acos(np.dot(node, orbit.r0) / a) == pytest.approx(0.7, abs=1e-12)
    el = orbit.elements()
    assert el.e == 0.0 and el.argp == 0.0 and el.true_anomaly == pytest.approx(0.7, abs=1e-12)


def test_j2_secular_rates_of_raan_and_perigee_over_many_orbits():
    a, e, i = 7.0e6, 0.05, math.radians(50.0)
    orbit = spacearm.Orbit.from_elements(a, e, i, 0.3, 1.0, 0.0, j2=True)
    n = math.sqrt(MU / a**3)
    p = a * (1 - e * e)
    raan_dot = -1.5 * n * J2 * (RE / p) ** 2 * math.cos(i)
    argp_dot = 0.75 * n * J2 * (RE / p) ** 2 * (4 - 5 * math.sin(i) ** 2)
    assert orbit.j2_secular_rates() == pytest.approx((raan_dot, argp_dot), rel=1e-12)
    # The osculating RAAN and argument of perigee of the propagated states, once per orbit for
    # 40 orbits (short-period terms then average out), fitted by a line.
    times = np.arange(41) * orbit.period
    r, v = orbit.propagate(times)
    h = np.cross(r, v)
    raan = np.unwrap(np.arctan2(h[:, 0], -h[:, 1]))
    ecc = np.cross(v, h) / MU - r / np.linalg.norm(r, axis=1)[:, None]
    node = np.stack([np.cos(raan), np.sin(raan), np.zeros_like(raan)], axis=1)
    hhat = h / np.linalg.norm(h, axis=1)[:, None]
    argp = np.unwrap(np.arctan2(np.einsum("ij,ij->i", hhat, np.cross(node, ecc)), np.einsum("ij,ij->i", node, ecc)))
    assert np.polyfit(times, raan, 1)[0] == pytest.approx(raan_dot, rel=0.01)
    assert np.polyfit(times, argp, 1)[0] == pytest.approx(argp_dot, rel=0.01)
    # Over 40 orbits the node has moved by degrees: the check is not of a tiny number.
    assert abs(raan[-1] - raan[0]) > math.radians(5)


def test_lvlh_axes_radial_along_track_orbit_normal():
    orbit = spacearm.Orbit.from_elements(7.0e6, 0.1, 0.5, 0.2, 0.1, 1.0)
    m = spacearm.Orbit.lvlh_to_eci(orbit.r0, orbit.v0)
    h = np.cross(orbit.r0, orbit.v0)
    np.testing.assert_allclose(m[:, 0], orbit.r0 / np.linalg.norm(orbit.r0), atol=1e-15)
    np.testing.assert_allclose(m[:, 2], h / np.linalg.norm(h), atol=1e-15)
    np.testing.assert_allclose(m.T @ m, np.eye(3), atol=1e-15)
    assert np.linalg.det(m) == pytest.approx(1.0, abs=1e-14)
    assert float(np.dot(m[:, 1], orbit.v0)) > 0  # y points along the motion
    r, v = orbit.propagate([0.0, 100.0])
    assert spacearm.Orbit.lvlh_to_eci(r, v).shape == (2, 3, 3)


def test_other_central_body_by_its_constants():
    moon = spacearm.CentralBody(mu=4.9028e12, radius=1737.4e3, j2=2.03e-4)
    orbit = spacearm.Orbit.circular(100e3, body=moon)
    assert orbit.period == pytest.approx(2 * math.pi * math.sqrt((1837.4e3) ** 3 / 4.9028e12), rel=1e-12)
    assert spacearm.CentralBody.earth().mu == MU


@pytest.mark.parametrize("call", [
    lambda: spacearm.Orbit.from_elements(7e6, 1.2, 0, 0, 0, 0),
    lambda: spacearm.Orbit.from_elements(-7e6, 0.0, 0, 0, 0, 0),
    lambda: spacearm.Orbit.from_elements(7e6, 0.0, 4.0, 0, 0, 0),
    lambda: spacearm.Orbit.circular(500e3, body="mars"),
    lambda: spacearm.Orbit.from_state([7e6, 0, 0], [0, 20e3, 0]),
    lambda: spacearm.CentralBody(mu=-1.0, radius=1.0, j2=0.0),
    lambda: spacearm.Orbit.circular(500e3).propagate([10.0, 5.0]),
])
def test_bad_orbits_are_argument_errors(call):
    with pytest.raises(ArgumentError):
        call()
