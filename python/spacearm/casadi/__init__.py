"""CasADi functions of the equations of motion, for optimal control (optional extra
``optimal-control``: ``pip install "spacearm[optimal-control]"``).

Every builder takes a [`Robot`][spacearm.Robot] and returns a ``casadi.Function`` on ``SX``
symbols whose graph is the Rust core's own recursions (ABA, RNEA, CRBA, the GJM reduction,
kinematics), recorded by the core on a tape and replayed on ``SX`` (``._tape``), in
spacearm's conventions (docs/conventions.md):

>>> import spacearm, spacearm.casadi as sc
>>> robot = spacearm.presets.planar4()
>>> fd = sc.forward_dynamics(robot)            # (x, u, tau, base_wrench) -> du
>>> x, u = robot.neutral_configuration(), robot.zero_velocity()
>>> du = fd(x, u, [1.0, 0, 0, 0], [0.0] * 6)

See docs/optimal-control.md for the equations and the planner [`spacearm.plan`][spacearm.plan] built on them,
and docs/c-api.md ("Embedded code") for [`generate_c`][spacearm.casadi.generate_c], their C code.
"""

from .functions import (
    base_velocity_from_momentum,
    bias_forces,
    forward_dynamics,
    generalized_bias,
    generalized_inertia,
    generalized_jacobian,
    inverse_dynamics,
    mass_matrix,
    momentum,
    point_position,
    rk4_step,
)

from .codegen import GENERATED, generate_c  # noqa: E402
from . import codegen as _codegen, functions as _functions  # noqa: E402

__all__ = [*_functions.__all__, *_codegen.__all__]  # each module's list, once
