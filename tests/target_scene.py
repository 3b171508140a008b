"""The scene of the free-target-with-contact tests (tests/contact/test_contact_with_events.py,
tests/fmi/test_target_doors.py; the core's test in sim/topology.rs and the C test's
crates/spacearm-c/tests/c/target/ are the same): a floating bus with one hinged link whose tip
ball points along x, and a 2 kg ball rock coming at the tip, its handle facing it."""

from __future__ import annotations

import numpy as np

import spacearm
from spacearm.contact import ContactModel, Pair

M_ROCK, I_ROCK = 2.0, np.diag([0.08, 0.1, 0.12])


def scene():
    b = spacearm.RobotBuilder("bus", 100.0, np.eye(3) * 3.6)
    b.add_geometry("base", "sphere", role="collision", radius=0.3)
    b.add_link("l1", parent="base", joint="revolute", axis=(0, 0, 1), origin=(0.5, 0, 0), com=(0.3, 0, 0), mass=3.0,
               inertia=np.diag([0.02, 0.1, 0.1]))
    b.add_geometry("l1", "sphere", role="collision", radius=0.1, origin=(0.3, 0.0, 0.0))
    b.add_point("tip", body="l1", offset=(0.4, 0.0, 0.0))
    robot = b.build()
    t = spacearm.RobotBuilder("rock", M_ROCK, I_ROCK, base_name="rock")
    t.add_geometry("rock", "sphere", role="collision", radius=0.2)
    t.add_point("handle", body="rock", offset=(-0.2, 0.0, 0.0))
    rock = t.build()
    # the tip's surface is at x = 1.2; the rock's handle 5 cm beyond, coming at 0.1 m/s, spinning
    # about the line of approach; the robot drifts and turns slowly
    s0 = np.array([1.45, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, -0.1, 0.0, 0.0, 0.05, 0.0, 0.0])
    u0 = np.array([0.01, 0.0, 0.0, 0.0, 0.0, 0.005, 0.0])
    contact = ContactModel(stiffness=2e4, damping=30.0, friction=0.4, slip_velocity=1e-2, pairs=[Pair("l1", "target")])
    return robot, rock, s0, u0, contact
