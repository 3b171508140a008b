"""slosh_parameters(tank="sphere"): the spherical tank's lateral slosh modes (a Ritz–Trefftz
solution in the core, crates/spacearm-core/src/model/slosh_sphere.rs), against the published
half-full value, the shallow and near-full limits and the model's mass and CM properties
(docs/flexibility.md, "From a tank to the slosh parameters")."""

import math

import pytest

import spacearm
from spacearm import errors


def sphere(**kw):
    args = dict(radius=0.8, axial_acceleration=0.4, propellant_mass=120.0)
    args.update(kw)
    return spacearm.slosh_parameters("sphere", **args)


def test_half_full_matches_mciver():
    # McIver, J. Fluid Mech. 201 (1989) 243-257: omega^2 R / g = 1.5602 for the first
    # antisymmetric mode of a half-full sphere (Faltinsen & Timokha, Sloshing, 2009: 1.5601).
    r, a = 0.8, 0.4
    p = sphere(fill_fraction=0.5)
    assert p.fill_height == pytest.approx(r, rel=1e-12)
    w2 = p.modes[0].frequency ** 2 * r / a
    assert w2 == pytest.approx(1.5602, abs=1e-4)
    # The frequency scales as sqrt(a); the masses and heights do not depend on it.
    q = sphere(fill_fraction=0.5, axial_acceleration=1.6)
    assert q.modes[0].frequency == pytest.approx(2.0 * p.modes[0].frequency, rel=1e-12)
    assert q.modes[0].mass == pytest.approx(p.modes[0].mass, rel=1e-12)
    assert p.modes[0].length == pytest.approx(a / p.modes[0].frequency ** 2, rel=1e-12)
    assert p.modes[0].stiffness == pytest.approx(p.modes[0].mass * p.modes[0].frequency ** 2, rel=1e-12)


def test_shallow_limit_is_a_pendulum_about_the_centre():
    # A thin layer at the bottom swings as a whole like a pendulum of length R hinged at the
    # sphere's centre: omega^2 R/a -> 1, m1 -> m_L, hinge height -> R above the bottom pole.
    r, a = 0.8, 0.4
    p = sphere(fill_height=1e-3 * r)
    m = p.modes[0]
    assert m.frequency ** 2 * r / a == pytest.approx(1.0, abs=1e-3)
    assert m.mass / p.liquid_mass == pytest.approx(1.0, abs=1e-3)
    cm = p.fill_height * (8 * r - 3 * p.fill_height) / (4 * (3 * r - p.fill_height))  # cap centroid above the pole
    assert cm + m.height + m.length == pytest.approx(r, rel=1e-5)


def test_toward_full_the_frequency_rises_and_the_mass_vanishes():
    fills = [0.1, 0.3, 0.5, 0.7, 0.9, 0.97]
    ps = [sphere(fill_fraction=f) for f in fills]
    w = [p.modes[0].frequency for p in ps]
    m = [p.modes[0].mass / p.liquid_mass for p in ps]
    assert all(b > a for a, b in zip(w, w[1:])) and all(b < a for a, b in zip(m, m[1:]))
    assert m[-1] < 0.1 and w[-1] ** 2 * 0.8 / 0.4 > 3.5  # half full: 0.58 and 1.56


@pytest.mark.parametrize("fraction", [0.05, 0.5, 0.85])
def test_the_model_keeps_the_mass_and_the_centre(fraction):
    p = sphere(fill_fraction=fraction, modes=3)
    total = p.fixed_mass + sum(m.mass for m in p.modes)
    assert total == pytest.approx(p.liquid_mass, rel=1e-12)
    assert p.fixed_mass * p.fixed_height + sum(m.mass * m.height for m in p.modes) == pytest.approx(0.0, abs=1e-10)
    assert all(m.mass > 0 for m in p.modes) and p.fixed_mass > 0
    assert all(b.frequency > a.frequency for a, b in zip(p.modes, p.modes[1:]))
    # The wall pressure is normal to the sphere, so its resultant passes through the centre: every
    # mode's pendulum hinge (height + length above the liquid's CM) lies at the sphere's centre.
    r, h = p.radius, p.fill_height
    cm = h * (8 * r - 3 * h) / (4 * (3 * r - h))
    for m in p.modes:
        assert cm + m.height + m.length == pytest.approx(r, abs=1e-9 * r)


def test_fill_fraction_and_density_use_the_cap_volume():
    r = 0.8
    p = sphere(fill_fraction=0.3, propellant_mass=None, density=1000.0)
    h = p.fill_height
    cap = math.pi * h * h * (3 * r - h) / 3
    assert cap / (4 / 3 * math.pi * r ** 3) == pytest.approx(0.3, rel=1e-12)
    assert p.liquid_mass == pytest.approx(1000.0 * cap, rel=1e-12)
    same = sphere(fill_height=h, propellant_mass=None, density=1000.0)
    assert same.modes[0].frequency == pytest.approx(p.modes[0].frequency, rel=1e-12)
    # tank_height is redundant for a sphere: accepted only when it is the diameter.
    assert sphere(fill_fraction=0.3, tank_height=2 * r).fill_height == pytest.approx(h, rel=1e-12)


@pytest.mark.parametrize(
    "kw, match",
    [
        (dict(fill_fraction=0.0), r"fill_fraction must be in \(0, 1\]"),
        (dict(fill_fraction=1.2), r"fill_fraction must be in \(0, 1\]"),
        (dict(fill_fraction=1.0), "does not slosh"),
        (dict(fill_height=1.6), "does not slosh"),
        (dict(fill_height=-0.1), "fill height"),
        (dict(fill_fraction=0.5, radius=0.0), "radius"),
        (dict(fill_fraction=0.5, radius=-1.0), "radius"),
        (dict(fill_fraction=0.5, tank_height=1.0), "diameter"),
        (dict(fill_fraction=0.5, modes=4), "1 to 3"),
        (dict(fill_fraction=0.5, axial_acceleration=0.0), "surface tension"),
        (dict(), "one of them"),
    ],
)
def test_bad_input(kw, match):
    with pytest.raises(errors.ArgumentError, match=match):
        sphere(**kw)


def test_add_to_a_builder():
    p = sphere(fill_fraction=0.5, modes=2, damping_ratio=0.01)
    b = spacearm.Robot.builder("sat", base_mass=300.0, base_inertia=[40.0, 40.0, 50.0])
    p.add_to(b, "tank", center=(0.0, 0.0, 0.2), axis=(0.0, 0.0, 1.0))
    robot = b.build()
    assert len([n for n in robot.joint_names if n.startswith("tank_")]) == 2
