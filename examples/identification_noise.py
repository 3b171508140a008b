"""Accuracy of payload identification against measurement noise (docs/identification.md).

For spatial6 and ETS-VII, a payload is attached to link 6 (RobotBuilder.attach_payload), the
combined system floats torque-free for 6 s from a state with nonzero linear and angular
momentum and moving joints (spacearm.simulate, DOPRI5, samples every 0.03 s), and
spacearm.identify.identify_payload estimates the payload from the recorded motion with
Gaussian noise of standard deviation sigma added to every measured velocity (u: base linear
and angular velocity and joint rates; the configurations are exact). For each sigma, TRIALS
noise draws; the table gives the median relative errors of the mass, the CM (|dc| / |c|) and the
inertia about the payload's CM (Frobenius norm), the median standard deviation of the mass
that the estimate itself reports (its noise model), to compare with the mass error, and how
many draws gave no physical estimate (a mass that is not positive).

    python examples/identification_noise.py            # the table in docs/identification.md
    python examples/identification_noise.py --trials 3  # quicker
"""

from __future__ import annotations

import argparse

import numpy as np

import spacearm
from spacearm.identify import identify_payload

SIGMAS = (0.0, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2)  # m/s and rad/s

#: (preset, payload mass kg, CM from link 6's CM in its axes m, principal moments kg·m², rpy of its axes)
CASES = (
    ("spatial6", 40.0, (0.35, 0.05, -0.02), (2.0, 3.0, 4.5), (0.3, -0.2, 0.5)),
    ("ets7", 100.0, (0.05, -0.03, 0.6), (12.0, 15.0, 10.0), (0.2, 0.1, -0.3)),
)


def run_case(preset, mass, com, moments, rpy, trials, rng):
    robot = spacearm.presets.get(preset)
    combined = robot.to_builder().attach_payload("target", body="link6", mass=mass, inertia=moments, origin=com, rpy=rpy).build()
    # The payload's inertia about its CM in link 6's axes: R diag(moments) R^T.
    frame = combined.description.links[-1]
    rot = spacearm.rotations.quat_to_matrix(frame.rotation)
    inertia = rot @ np.diag(moments) @ rot.T
    u0 = combined.zero_velocity()
    u0[:6] = [0.01, 0.02, -0.01, 0.02, -0.01, 0.03]
    u0[6:] = [0.3, -0.25, 0.35, 0.4, -0.3, 0.5]
    traj = spacearm.simulate(combined, 6.0, u0=u0, integrator="dopri5", rtol=1e-12, atol=1e-12, dt=0.03)
    rows = []
    for sigma in SIGMAS:
        errors, mass_std, cond, failed = [], [], [], 0
        for _ in range(trials if sigma > 0 else 1):
            u = traj.u + rng.normal(scale=sigma, size=traj.u.shape)
            est = identify_payload(robot, x=traj.x, u=u, body="link6")
            cond.append(est.condition_number)
            if est.parameters[0] <= 0.0:  # no CM or inertia about it: counted, left out of the medians
                failed += 1
                continue
            errors.append((abs(est.mass - mass) / mass, np.linalg.norm(est.com - com) / np.linalg.norm(com),
                           np.linalg.norm(est.inertia - inertia) / np.linalg.norm(inertia)))
            mass_std.append(est.physical_std[0] / mass)
        e = np.median(np.array(errors), axis=0) if errors else np.full(3, np.nan)
        rows.append((preset, sigma, *e, float(np.median(mass_std)) if mass_std else np.nan, float(np.median(cond)),
                     failed, len(cond), len(traj.t)))
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=10, help="noise draws per sigma (default 10)")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    rng = np.random.default_rng(args.seed)
    print("| robot | sigma (m/s, rad/s) | mass error | CM error | inertia error | reported mass std | condition number "
          "| no physical estimate | samples |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for case in CASES:
        for preset, sigma, em, ec, ei, sm, cond, failed, draws, k in run_case(*case, args.trials, rng):
            print(f"| {preset} | {sigma:.0e} | {em:.1e} | {ec:.1e} | {ei:.1e} | {sm:.1e} | {cond:.1f} | {failed}/{draws} | {k} |")


if __name__ == "__main__":
    main()
