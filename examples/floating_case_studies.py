#!/usr/bin/env python
"""Two floating-mode case studies in the manner of the paper's §6 (Wilde et al. 2018), on the
presets planar4 (4 links on a 100 kg cube, a planar arm; SPART's ResolvedMotion values) and
spatial6 (6 links on a 500 kg box; project-defined) — not the paper's own parameters, which are
not available:

1. computed torque on the reduced EOM (paper eqs. 112–115) drives the arm along a quintic
   joint maneuver: the base reacts equal and opposite (it turns and moves), the system CM
   stays where it was, the tracking error stays at the integration level;
2. joint PD to the same goal as a set point: the same physics, a looser tracking;
3. zero torques, the joints released with velocities and the base with the velocity that
   gives zero momentum (eq. 109): P, L and the kinetic energy are conserved, the CM stays put.

Writes <model>_<run>.png (the run's panels) and <model>_<run>_paths.png (paths and momenta)
to --out-dir. Runs in a few seconds.

    python examples/floating_case_studies.py --out-dir out/examples
"""

import numpy as np

import spacearm
from spacearm import control

from _common import case_figure, out_dir

CASES = {
    # model, joint goal offset, plane of the path figure
    "planar4": (spacearm.presets.planar4, np.array([0.6, 0.5, 0.4, 0.3]), (0, 1)),
    "spatial6": (spacearm.presets.spatial6, np.array([0.8, 0.5, 0.6, 0.5, 0.6, 0.5]), (0, 2)),
}


def zero_momentum_velocity(robot, qd):
    """``u = [v0, w0, qd]`` with the base velocity that makes P = 0 and L = 0 (eq. 109): the
    joints move, the base reacts, the system CM stays put."""
    x0 = robot.neutral_configuration()
    return np.concatenate([robot.base_velocity_from_momentum(x0, qd), qd])


def main():
    out = out_dir(__doc__.split("\n\n")[0])
    for name, (make, offset, plane) in CASES.items():
        robot = make()
        q0 = robot.initial_q
        goal = q0 + offset
        # PD gains per joint: 3 rad/s, critically damped, on the diagonal of H* (eq. 45) — the
        # inertia each joint drives, so the light wrist joints do not make the loop stiff.
        h = np.diag(robot.generalized_inertia(robot.neutral_configuration()))
        kp, kd = 9.0 * h, 6.0 * h
        runs = {
            "computed_torque": dict(controller=control.ComputedTorque(kp=25.0, kd=10.0,
                                                                      reference=control.QuinticJoint(q0, goal, 0.0, 4.0))),
            "pd": dict(controller=control.JointPD(kp=kp, kd=kd, reference=goal)),
            "torque_free": dict(u0=zero_momentum_velocity(robot, 0.4 * np.cos(np.arange(robot.n_dof)))),
        }
        for run, kwargs in runs.items():
            traj = spacearm.simulate(robot, 5.0, dt=1e-3, record_every=10, **kwargs)
            print(f"--- {name} / {run}\n{traj.summary()}\n")
            traj.plot(out / f"{name}_{run}.png")
            case_figure(traj, out / f"{name}_{run}_paths.png", f"{name}, floating, {run.replace('_', ' ')}", plane=plane)
    print(f"figures in {out}/")


if __name__ == "__main__":
    main()
