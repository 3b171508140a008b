"""The per-body gravity-gradient torque in a Basilisk MJScene (spacearm.basilisk.GravityGradientModule):
against the closed form, and an orbital run (Basilisk's point-mass gravity on every body plus the
module) against spacearm's own orbital simulation (docs/orbit.md)."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("Basilisk.simulation.mujoco")

import spacearm  # noqa: E402
from spacearm import basilisk as sb  # noqa: E402
from bsk_runs import scene_run  # noqa: E402

MU = spacearm.CentralBody.earth().mu
DT, T = 0.01, 10.0


@pytest.fixture(scope="module")
def orbital_runs():
    """spatial6 tumbling slowly on a 500 km circular orbit: Basilisk (NBodyGravity point-mass
    Earth on every body, with and without the module) and spacearm (orbit, gravity gradient)."""
    from Basilisk.simulation import NBodyGravity, pointMassGravityModel

    robot = spacearm.presets.spatial6()
    orbit = spacearm.Orbit.circular(500e3, inclination=0.9)
    (r_o,), (v_o,) = orbit.propagate([0.0])
    x0 = np.asarray(robot.neutral_configuration(), float)
    x0[3:7] = [0.3, -0.2, 0.4, 0.8] / np.linalg.norm([0.3, -0.2, 0.4, 0.8])
    x0[:3] -= robot.center_of_mass(x0)  # the system CM on the orbit's point O
    u0 = np.zeros(robot.nu)
    u0[3:6] = [1e-3, -2e-3, 1.5e-3]
    u0[6:] = 0.02
    u0[:3] = -robot.momentum(x0, u0).P / robot.total_mass  # zero momentum relative to O
    x_eci, u_eci = x0.copy(), u0.copy()
    x_eci[:3] += r_o
    u_eci[:3] += v_o

    def gravity(with_gradient):
        def setup(scene, acts):
            keep = {"dynamics": []}
            nbody = NBodyGravity.NBodyGravity()
            point_mass = pointMassGravityModel.PointMassGravityModel()
            point_mass.muBody = MU
            nbody.addGravitySource("earth", point_mass, True)
            for _, name in acts.bodies:
                nbody.addGravityTarget(name, scene.getBody(name))
            keep["dynamics"].append(nbody)
            keep["models"] = point_mass
            if with_gradient:
                module = sb.GravityGradientModule(robot, scene, acts, mu=MU)
                keep["dynamics"].append(module)
                keep["gg"] = module
            return keep
        return setup

    runs = {}
    for gg in (True, False):
        x, u, scene, acts, extras = scene_run(robot, x_eci, u_eci, DT, T, setup=gravity(gg))
        runs[gg] = (x, u, scene, acts, extras)
    traj = spacearm.simulate(robot, T, x0=x0, u0=u0, dt=DT, integrator="rk4", orbit=orbit, gravity_gradient=True)
    (r_end,), (v_end,) = orbit.propagate([T])
    return robot, runs, traj, (r_end, v_end)


def test_module_torques_are_the_closed_form(orbital_runs):
    """Each body's torque from the module (the core's tidal_torques) against the closed form
    3μ/|r|⁵ (r × I r) evaluated at the body's own CM: they differ by the field's variation over
    the body's distance from the system CM (ρ/|r| ≈ 4e-7 here), asserted at 1e-5 of the largest."""
    robot, runs, _, _ = orbital_runs
    x, u, _, _, extras = runs[True]
    module = extras["gg"]
    torques = module.torques_at(x, u)
    kin = robot.forward_kinematics(x)
    closed = []
    for b in range(len(robot.body_names)):
        inertia = robot.description.base.inertia if b == 0 else robot.description.links[b - 1].inertia
        i_world = kin.body_to_world[b] @ np.asarray(inertia) @ kin.body_to_world[b].T
        r = kin.com_in_world[b]
        closed.append(3 * MU / np.linalg.norm(r) ** 5 * np.cross(r, i_world @ r))
    closed = np.array(closed)
    assert np.max(np.abs(closed)) > 1e-5  # N·m: the base's torque is not negligible
    np.testing.assert_allclose(torques, closed, rtol=0, atol=1e-5 * np.max(np.abs(closed)))
    # The formula the module states (docs/basilisk.md): r the system CM's position, for every body.
    r_cm = robot.center_of_mass(x)
    at_cm = np.array([3 * MU / np.linalg.norm(r_cm) ** 5 * np.cross(r_cm, (kin.body_to_world[b] @ np.asarray(
        robot.description.base.inertia if b == 0 else robot.description.links[b - 1].inertia) @ kin.body_to_world[b].T) @ r_cm)
        for b in range(len(robot.body_names))])
    np.testing.assert_allclose(torques, at_cm, rtol=0, atol=1e-12 * np.max(np.abs(at_cm)))
    assert np.max(np.abs(module.torques)) > 0  # the module ran inside the dynamics task


def test_orbital_run_agrees_with_spacearm(orbital_runs):
    """10 s in orbit: Basilisk (exact point-mass gravity at each body's CM + the module's torques)
    against spacearm's orbital run (linearized tidal wrenches about O, docs/orbit.md).

    Measured: base attitude 6e-9, ω0 6e-10 rad/s, base position relative to O 5e-9 m; without
    the module the attitude is off by 4e-6 (the gravity-gradient torque's effect, 600 times the
    agreement). The joints agree to 1e-6 rad only: Basilisk's MJScene holds the state in ECI
    (positions of 7e6 m, velocities of 7.6 km/s), and MuJoCo's dynamics round off at
    ε|v|² per unit mass — the same scene with no gravity at all, moved to the ECI state, drifts
    1.4e-6 rad from the exact free motion in 10 s (and 3e-13 at a thousandth of the offset), the
    reason spacearm keeps an orbital run's state relative to O (docs/orbit.md). Asserted: the
    base to the issue's 1e-7, the joints to 1e-5."""
    robot, runs, traj, (r_end, v_end) = orbital_runs
    x, u = runs[True][0], runs[True][1]
    xs, us = traj.x[-1], traj.u[-1]
    attitude = np.max(np.abs(x[3:7] - xs[3:7]))
    assert attitude < 1e-7
    assert np.max(np.abs(u[3:6] - us[3:6])) < 1e-8  # rad/s, ω0 ≈ 6e-4
    assert np.max(np.abs(x[:3] - r_end - xs[:3])) < 1e-7  # the base CM relative to O (m)
    assert np.max(np.abs(u[:3] - v_end - us[:3])) < 1e-7  # m/s
    assert np.max(np.abs(x[7:] - xs[7:])) < 1e-5  # the ECI round-off floor of MJScene, above
    without = np.max(np.abs(runs[False][0][3:7] - xs[3:7]))
    assert without > 100 * attitude
