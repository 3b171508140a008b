"""spacearm's CMGs against Basilisk's VSCMG effector (``vscmgStateEffector`` on a rigid
``spacecraft.Spacecraft`` hub; docs/cmg.md, "Against Basilisk's VSCMG"): the same hub and 4-CMG
pyramid, the same constant gimbal and wheel torques, 2 s, both with RK4 at the same step. Hub
attitude, rates and position, gimbal angles and rates and wheel speeds agree within the two
integrators' own step errors, estimated from each engine's runs at ``dt`` and ``dt/2``
(Richardson: a 4th-order method's error at ``dt/2`` is ``|x_dt − x_dt/2| / 15``). The conversion
of conventions is in one place, ``tests/bsk_runs.py``'s ``vscmg_run``."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("Basilisk.simulation.vscmgStateEffector",
                    reason="Basilisk (bsk) is not installed: scripts/test.sh installs it with --no-deps")

import spacearm  # noqa: E402
from bsk_runs import vscmg_run  # noqa: E402
from cmg_models import pyramid_sat  # noqa: E402
from scipy.spatial.transform import Rotation  # noqa: E402

T, DT = 2.0, 0.005


def _quantities(robot, x, u):
    """The compared quantities, each one array: attitude as a rotation vector of ``R0`` (the
    quaternion's sign is free), the hub's rates and position, the CMG states."""
    cmgs = robot.cmg_dofs.values()
    gimbal, rotor = (np.array([c[k] for c in cmgs]) for k in ("gimbal", "rotor"))
    return {
        "attitude": Rotation.from_quat(x[3:7]).as_rotvec(), "hub rate": u[3:6], "hub position": x[:3],
        "hub velocity": u[:3], "gimbal angle": x[7 + gimbal], "gimbal rate": u[6 + gimbal],
        "wheel speed": u[6 + rotor],
    }


def _spacearm(robot, x0, u0, tau, dt):
    sim = spacearm.Simulator(robot, dt=dt, integrator="rk4")
    sim.reset(x0, u0)
    sim.step(tau, n=int(round(T / dt)))
    return np.asarray(sim.x), np.asarray(sim.u)


@pytest.mark.parametrize("variable_speed", [True, False], ids=["vscmg", "sgcmg"])
def test_a_pyramid_on_a_rigid_hub_runs_as_basilisks_vscmg_effector(variable_speed):
    robot = pyramid_sat(arm=False, variable_speed=variable_speed)
    cmgs = robot.cmg_dofs.values()
    gimbal, rotor = (np.array([c[k] for c in cmgs]) for k in ("gimbal", "rotor"))
    x0 = robot.neutral_configuration(q=np.zeros(robot.n_dof))
    x0[3:7] = Rotation.from_rotvec([0.2, -0.4, 0.3]).as_quat()
    x0[7 + gimbal] = [0.3, -0.2, 0.5, -0.1]
    u0 = robot.cmg_velocity([500.0, -450.0, 520.0, -480.0])
    u0[3:6] = [0.01, -0.02, 0.015]
    u0[6 + gimbal] = [0.3, -0.2, 0.25, 0.1]
    tau = np.zeros(robot.n_dof)
    tau[gimbal] = [0.02, -0.01, 0.015, -0.02]
    if variable_speed:  # an SGCMG's rotor has no motor: a free wheel in Basilisk's effector
        tau[rotor] = [0.05, -0.03, 0.02, 0.04]
    start = _quantities(robot, x0, u0)
    runs = {}
    for dt in (DT, DT / 2):
        runs["basilisk", dt] = _quantities(robot, *vscmg_run(robot, x0, u0, tau, dt, T))
        runs["spacearm", dt] = _quantities(robot, *_spacearm(robot, x0, u0, tau, dt))
    fine = DT / 2
    for k in start:
        # Each engine's own step error at dt/2, from its two runs; the two engines may differ
        # by at most the sum (and a floor at rounding of the quantity's size).
        err = sum(np.abs(runs[e, DT][k] - runs[e, fine][k]).max() / 15 for e in ("basilisk", "spacearm"))
        scale = np.abs(runs["spacearm", fine][k]).max()
        diff = np.abs(runs["basilisk", fine][k] - runs["spacearm", fine][k]).max()
        print(f"{k:13s} |Basilisk − spacearm| {diff:.2e}, step error {err:.2e}, size {scale:.3g}")
        assert diff <= err + 1e-13 * scale, (k, diff, err)
        # The run moved every quantity, far beyond the tolerance.
        assert np.abs(runs["spacearm", fine][k] - start[k]).max() > 1e3 * (err + 1e-13 * scale), k
    if variable_speed:  # the wheel torques changed the wheel speeds by ~ τ T / J_s = 2 rad/s
        assert np.abs(runs["spacearm", fine]["wheel speed"] - start["wheel speed"]).min() > 0.5
