"""Identification of a captured payload's inertial parameters from momentum conservation.

After a rigid grasp, the target is a payload of the gripper link. Its ten inertial parameters
(mass, first moment, inertia) enter the combined system's momentum linearly, ``h = h_robot +
Y π`` (Yoshida & Abiko 2002), and that momentum is constant while no external wrench acts; so a
recorded free-floating motion determines them by least squares, with the identifiable
combinations, the condition number and a covariance (``docs/identification.md``).

>>> import numpy as np, spacearm
>>> from spacearm.identify import identify_payload
>>> robot = spacearm.presets.spatial6()
>>> combined = robot.attach_body("target", body="link6", mass=40.0, inertia=[2.0, 3.0, 4.0],
...     origin=(0.4, 0.05, -0.02))
>>> u0 = combined.zero_velocity(); u0[3:6] = [0.02, -0.01, 0.03]; u0[6:] = 0.3
>>> traj = spacearm.simulate(combined, 4.0, u0=u0, integrator="dopri5", rtol=1e-12, atol=1e-12, dt=0.02)
>>> est = identify_payload(robot, traj, body="link6")
>>> est.rank, round(est.mass, 6)
(10, 40.0)
"""

from .estimate import DEFAULT_RCOND, PayloadEstimate, identify_payload
from .parameters import PARAMETER_NAMES, from_parameters, to_parameters
from .regressor import momentum_regressor, robot_momentum

__all__ = [
    "identify_payload",
    "PayloadEstimate",
    "DEFAULT_RCOND",
    "PARAMETER_NAMES",
    "to_parameters",
    "from_parameters",
    "momentum_regressor",
    "robot_momentum",
]
