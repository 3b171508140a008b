#!/usr/bin/env python
"""Rotation-floating: three reaction wheels hold the base attitude while the arm moves.

A spatial6-like servicer (the project-defined spatial6 preset with three orthogonal reaction wheels in the
base, built with ``RobotBuilder.add_reaction_wheel``) performs the same computed-torque arm
maneuver twice:

1. floating, wheels idle: the base turns by ~17° in reaction to the arm;
2. rotation-floating, ``AttitudeControl`` (PD on the attitude error, wheel torques through the
   pseudo-inverse of the wheel axes) combined with the arm's computed torque: the wheels absorb
   the arm's angular momentum and the base attitude stays within a fraction of a degree.

In both runs the wheels' torques are internal: P and L_origin are conserved (the summaries
print their drift), and the angular momentum ends up stored in the wheels (their speeds are
plotted). Writes spatial6_rw_<run>.png to --out-dir (a few seconds).

    python examples/rotation_floating_wheels.py --out-dir out/examples
"""

import numpy as np

import spacearm
from spacearm import control

from _common import case_figure, out_dir


def spatial6_with_wheels(rotor_inertia=0.2, max_torque=40.0, max_speed=400.0):
    """spatial6 (same base, links and end effector) plus reaction wheels along the base axes."""
    d = spacearm.presets.spatial6().describe()
    b = spacearm.Robot.builder("spatial6_rw", base_mass=d["base"]["mass"], base_inertia=d["base"]["inertia"])
    for link in d["links"]:
        b.add_link(link["name"], parent=link["parent"], joint=link["type"], axis=link["axis"], origin=link["origin"],
                   rotation=link["rotation"], com=link["com"], mass=link["mass"], inertia=link["inertia"],
                   joint_name=link["joint"])
    for axis in np.eye(3):
        b.add_reaction_wheel(axis, rotor_inertia=rotor_inertia, max_torque=max_torque, max_speed=max_speed)
    point, body, offset = d["points"][0]
    b.add_point(point, body=body, offset=offset)
    b.set_end_effector(point)
    b.set_initial_q(list(d["initial_q"]) + [0.0, 0.0, 0.0])
    return b.build()


def main():
    out = out_dir(__doc__.split("\n\n")[0])
    robot = spatial6_with_wheels()
    x0 = robot.neutral_configuration()
    q_arm0 = robot.initial_q[:6]
    ref = control.QuinticJoint(q_arm0, q_arm0 + np.array([0.8, 0.5, 0.6, 0.5, 0.6, 0.5]), 0.0, 4.0)
    arm = control.ComputedTorque(kp=25.0, kd=10.0, reference=ref)
    # Attitude gains: about 3 rad/s, critically damped, on the ~100 kg m^2 of the base.
    hold = control.AttitudeControl(quat_ref=x0[3:7], kp=900.0, kd=600.0)
    runs = {
        "floating_wheels_idle": dict(mode="floating", controller=arm),
        "rotation_floating_attitude_hold": dict(mode="rotation-floating", controller=control.Combined(arm=arm, base=hold)),
    }
    for run, kwargs in runs.items():
        traj = spacearm.simulate(robot, 6.0, dt=1e-3, record_every=10, **kwargs)
        print(f"--- spatial6_rw / {run}\n{traj.summary()}\n  base turned at most "
              f"{np.degrees(traj.base_rotation_angle.max()):.3g} deg\n")
        traj.plot(out / f"spatial6_rw_{run}.png")
        case_figure(traj, out / f"spatial6_rw_{run}_paths.png", f"spatial6 + 3 wheels, {run.replace('_', ' ')}", plane=(0, 2))
    print(f"figures in {out}/")


if __name__ == "__main__":
    main()
