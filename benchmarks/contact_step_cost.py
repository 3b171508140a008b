#!/usr/bin/env python
"""The per-step cost of compliant contact (docs/contact.md, "Contact dynamics"): the same RK4 run
of an arm whose tip ball sweeps into an off-centre box on its floating base, without contact,
with contact but the pair apart (detection only: the arm folded away), and with the tip hitting
the box (forces, friction, the located onset); then with a free target in the loop of contact
(docs/contact.md, "Contact with a free target": its 13-state integrated with the robot's), a
ball far from the robot (detection against its shape, its Newton–Euler) and a ball hitting the
base's box (and flying on); and rigid contact (docs/contact.md, "Rigid contact in a run": each
step's cone problem on the Delassus operator, its impulses at the step's start), the pair apart
(detection once a step) and the tip striking the box under a joint torque that presses it there
(in contact in a few hundred of the steps); and a ball pressed on a plate and sliding on it,
in contact at every step: without contact, compliant, rigid.

Interleaved rounds; the figures are medians over ``--repeat`` rounds of the time per RK4 step
(four evaluations of the dynamics, each with detection when contact is on) and the ratio to the
run without contact. The machine's other load shows in the load average printed at the top.

    python benchmarks/contact_step_cost.py
    python benchmarks/contact_step_cost.py --steps 20000 --repeat 9
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path
import statistics
import time

import numpy as np

import spacearm
from spacearm.contact import ContactModel
from spacearm.control import JointPD, TorqueLimit

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "contact"))
from test_contact_dynamics import arm_and_box  # noqa: E402  (the robot of the momentum test)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--steps", type=int, default=10000)
    p.add_argument("--repeat", type=int, default=7)
    a = p.parse_args()
    print(f"load average {os.getloadavg()[0]:.2f}; {a.steps} RK4 steps per run, median of {a.repeat}")
    robot = arm_and_box()
    dt = 1e-4
    contact = ContactModel(stiffness=2e4, damping=30.0, friction=0.5, slip_velocity=0.01, pairs=[("base", "l2")])
    u0 = robot.zero_velocity()
    u0[6:] = [4.0, 1.0]
    hit = robot.neutral_configuration()
    hit[7:] = [0.3, 0.2]
    away = robot.neutral_configuration()
    away[7:] = [-1.0, 0.2]  # the tip turning about l2's axis only, clear of the box: detection, no contact
    u_away = robot.zero_velocity()
    u_away[7] = 4.0
    b = spacearm.RobotBuilder("ball", 2.0, np.diag([0.08, 0.1, 0.12]), base_name="ball")
    b.add_geometry("ball", "sphere", role="collision", radius=0.2)
    ball = b.build()
    target_contact = ContactModel(stiffness=2e4, damping=30.0, friction=0.5, slip_velocity=0.01, pairs=[("base", "target"), ("l2", "target")])
    # A ball 3 m out (apart), and one coming at the box's +y face (y = 1.1) at 1.5 m/s, touching at
    # t = 0.1 s, with spin: a contact of ~0.03 s and a flight back out.
    far = np.array([0.0, 3.0, 0.0, 0, 0, 0, 1, 0.0, 0.0, 0.0, 0.3, 0.2, 0.1])
    press = TorqueLimit(JointPD(kp=[1e6, 1e6], kd=[0.0, 0.0], reference=[3.0, 3.0]), limit=5.0)  # 5 N·m on each joint, towards the box
    rigid = ContactModel(kind="rigid", friction=0.5, margin=1e-3, pairs=[("base", "l2")])
    coming = np.array([0.0, 1.45, -0.2, 0, 0, 0, 1, 0.0, -1.5, 0.0, 0.3, 0.2, 0.1])
    cases = {
        "no contact": dict(x0=hit, u0=u0, contact=None),
        "contact, apart": dict(x0=away, u0=u_away, contact=contact),
        "contact, hitting": dict(x0=hit, u0=u0, contact=contact),
        "target, apart": dict(x0=away, u0=u_away, contact=target_contact, target=ball, target_state=far),
        "target, hitting": dict(x0=away, u0=u_away, contact=target_contact, target=ball, target_state=coming),
        "rigid, apart": dict(x0=away, u0=u_away, contact=rigid),
        "rigid, hitting": dict(x0=hit, u0=u0, contact=rigid, controller=press),
    }
    # Sustained contact, rigid against compliant: a ball on a slider pressed on a plate (a
    # 1e12 kg base) by a constant 5 N, in contact at every step.
    pb = spacearm.RobotBuilder("plate", 1e12, np.eye(3) * 1e12)
    pb.add_link("sx", parent="base", joint="prismatic", axis=(1, 0, 0), mass=2.0, inertia=np.eye(3) * 0.1)
    pb.add_link("sy", parent="sx", joint="prismatic", axis=(0, 1, 0), mass=1.0, inertia=np.eye(3) * 0.1)
    pb.add_geometry("base", "box", role="collision", size=(1.0, 4.0, 4.0))
    pb.add_geometry("sy", "sphere", role="collision", radius=0.1)
    plate = pb.build()
    xp = plate.neutral_configuration()
    xp[7:] = [0.6, 0.0]
    up = plate.zero_velocity()
    up[7] = 0.5  # sliding along the plate
    push = TorqueLimit(JointPD(kp=[1e6, 0.0], kd=[0.0, 0.0], reference=[-10.0, 0.0]), limit=5.0)
    pressed = dict(robot=plate, x0=xp, u0=up, controller=push)
    plate_cases = {
        "plate, no contact": dict(pressed, contact=None),
        "plate, compliant": dict(pressed, contact=ContactModel(stiffness=1e5, damping=200.0, friction=0.1, slip_velocity=0.01, pairs=[("base", "sy")])),
        "plate, rigid": dict(pressed, contact=ContactModel(kind="rigid", friction=0.1, margin=1e-3, pairs=[("base", "sy")])),
        "plate, rigid pgs": dict(pressed, contact=ContactModel(kind="rigid", friction=0.1, margin=1e-3, solver="pgs", pairs=[("base", "sy")])),
    }
    times: dict = {k: [] for k in [*cases, *plate_cases]}
    for _ in range(a.repeat):
        for name, kw in [*cases.items(), *plate_cases.items()]:
            kw = dict(kw)
            model = kw.pop("robot", robot)
            t0 = time.perf_counter()
            traj = spacearm.simulate(model, a.steps * dt, dt=dt, record_every=100, **kw)
            times[name].append((time.perf_counter() - t0) / a.steps)
            if name.startswith("rigid, hitting"):
                assert np.abs(traj.contact_impulse[-1]).max() > 0  # it struck (a step's count is sampled every 100)
            elif name.endswith("hitting") or name.startswith("plate, ") and kw["contact"] is not None:
                assert traj.contact_count.max() >= 1
            if name.endswith("apart"):
                assert traj.contact_count.max() == 0
    for group, ref in ((cases, "no contact"), (plate_cases, "plate, no contact")):
        base = statistics.median(times[ref])
        for name in group:
            m = statistics.median(times[name])
            print(f"{name:18s} {m * 1e6:8.2f} µs/step   ratio {m / base:5.2f}")


if __name__ == "__main__":
    main()
