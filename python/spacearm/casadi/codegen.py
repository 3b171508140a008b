"""C code of the equations of motion for embedded use (docs/c-api.md, "Embedded code"):
[`generate_c`][spacearm.casadi.generate_c] writes, with ``casadi.CodeGenerator``, one self-contained C file and its
header holding the forward dynamics, ``H*``, ``J*`` of a point and an RK4 step of a model (the
Functions of ``spacearm.casadi.functions``: the core's recursions recorded and replayed on
CasADi symbols). The code needs only a C compiler and ``libm``; no spacearm, no CasADi.

Each exported function follows CasADi's calling convention (``int f(const casadi_real** arg,
casadi_real** res, casadi_int* iw, casadi_real* w, int mem)``, with ``f_work`` giving the work
sizes); every matrix is **column-major** there (CasADi's layout, unlike the C ABI's row-major).
"""

from __future__ import annotations

import re
from pathlib import Path

from ..errors import ArgumentError
from .functions import _casadi_for, forward_dynamics, generalized_inertia, generalized_jacobian, rk4_step

__all__ = ["generate_c", "GENERATED"]

#: The functions [`generate_c`][spacearm.casadi.generate_c] writes, as ``<prefix>_<name>``.
GENERATED = ("forward_dynamics", "generalized_inertia", "generalized_jacobian", "rk4_step")


def generate_c(robot, directory, *, prefix: str = None, point=None, substeps: int = 1) -> Path:
    """Write ``<prefix>.c`` and ``<prefix>.h`` into ``directory`` and return the C file's path.

    The file defines ``<prefix>_forward_dynamics(x, u, tau, base_wrench) -> du``,
    ``<prefix>_generalized_inertia(x) -> H_star``, ``<prefix>_generalized_jacobian(x) ->
    J_star`` (of ``point``: a point or body name, ``(body, offset)``, or ``None`` for the end
    effector) and ``<prefix>_rk4_step(x, u, tau, base_wrench, dt) -> (x_next, u_next)``
    (``substeps`` RK4 steps, the native simulator's step). ``prefix`` defaults to the model
    name as a C identifier.
    """
    ca = _casadi_for(robot)
    prefix = prefix or re.sub(r"\W", "_", robot.name)
    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", prefix):
        raise ArgumentError(f"prefix must be a C identifier, got {prefix!r}")
    directory = Path(directory)
    if not directory.is_dir():
        raise ArgumentError(f"directory '{directory}' does not exist")
    sources = {"forward_dynamics": forward_dynamics(robot), "generalized_inertia": generalized_inertia(robot),
               "generalized_jacobian": generalized_jacobian(robot, point), "rk4_step": rk4_step(robot, substeps)}
    gen = ca.CodeGenerator(f"{prefix}.c", {"with_header": True})
    for name in GENERATED:
        f = sources[name]
        # A renamed wrapper: only the wrappers are exported; what they call stays static.
        args = f.mx_in()
        gen.add(ca.Function(f"{prefix}_{name}", args, f.call(args), f.name_in(), f.name_out()))
    gen.generate(str(directory) + "/")
    return directory / f"{prefix}.c"
