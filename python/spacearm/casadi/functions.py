"""CasADi ``Function`` objects of a [`Robot`][spacearm.Robot]'s equations of motion.

Each builder takes a Robot and returns a ``casadi.Function`` on ``SX`` symbols whose graph is
the Rust core's own recursions (ABA, RNEA, CRBA, the GJM reduction, kinematics), recorded by
the core on a recording scalar and replayed on ``SX`` by ``._tape`` — the same arithmetic,
operation for operation, as the core's numbers. The functions follow spacearm's conventions
exactly (docs/conventions.md): ``x = [r0, quat0 [x, y, z, w], q]`` (7+N), ``u = [v0, w0, qd]``
(6+N) with ``v0``, ``w0`` in 𝒥, ``f = [F0, N0, tau]``, ``EOM H du + c = f``. The quaternion
input is normalised inside each function (as the core normalises its input), so derivatives
with respect to it are tangent to the unit sphere.

Called with numbers, each function checks them before CasADi evaluates (a CasADi function cannot
raise once it runs): a wrong size is a [`ShapeError`][spacearm.errors.ShapeError], NaN or an
infinity a [`NonFiniteError`][spacearm.errors.NonFiniteError], and a zero base quaternion, which
has no direction to normalise to, a [`QuaternionError`][spacearm.errors.QuaternionError].
Called with symbols (``SX``/``MX``, in a graph or an NLP) nothing can be checked: a zero
quaternion there evaluates to NaN, so a problem must keep it away from zero itself (a start on
the unit sphere propagated by [`rk4_step`][spacearm.casadi.rk4_step], which renormalises, or a
unit-norm constraint).

Evaluated at a numeric state each function equals the core's result to rounding; its CasADi
derivatives are exact derivatives of the same recursions (docs/optimal-control.md).
"""

from __future__ import annotations

from .._util.optional import require
from ..errors import ArgumentError, SpacearmTypeError
from . import _tape
from ._checked import checked_function

__all__ = [
    "forward_dynamics",
    "inverse_dynamics",
    "mass_matrix",
    "bias_forces",
    "generalized_inertia",
    "generalized_bias",
    "generalized_jacobian",
    "point_position",
    "momentum",
    "base_velocity_from_momentum",
    "rk4_step",
]


def _casadi():
    return require("casadi", "spacearm.casadi (CasADi functions of the equations of motion)")


def _casadi_for(robot):
    """The casadi module, once ``robot`` is checked to be a Robot."""
    from ..model.robot import Robot

    if not isinstance(robot, Robot):
        raise SpacearmTypeError(f"spacearm.casadi functions take a spacearm.Robot, got {type(robot).__name__}")
    return _casadi()


def _function(ca, name: str, inputs: dict, outputs: dict):
    return checked_function(ca, name, inputs.values(), outputs.values(), inputs, outputs)


def _taped(robot, name: str, point=None, with_point: bool = False):
    """The core's function ``name`` of ``robot`` as a ``casadi.Function`` (of a point if
    ``with_point``: a point name, a body name, ``(body, offset)`` or ``None``)."""
    ca = _casadi_for(robot)
    if with_point:
        body, offset = robot.resolve_point(point)
        return _tape.function(ca, robot, name, body, offset)
    return _tape.function(ca, robot, name)


def forward_dynamics(robot):
    """``forward_dynamics(x, u, tau, base_wrench) -> du``: the state derivative
    ``du = [dv0/dt, dw0/dt, qdd]`` under joint torques ``tau`` (N) and the base wrench
    ``base_wrench = [F0, N0]`` (6, in 𝒥, about the base CM; zero for free floating), by the
    articulated-body algorithm (the core's ``Robot.forward_dynamics(method="aba")``), the joints'
    springs and dampers included (docs/flexibility.md)."""
    return _taped(robot, "forward_dynamics")


def inverse_dynamics(robot):
    """``inverse_dynamics(x, u, du) -> f``: the generalized force ``f = [F0, N0, tau]`` with
    ``H du + c = f + Q_passive``, by RNEA (the core's ``Robot.inverse_dynamics``; ``Q_passive``
    the joints' springs and dampers, docs/flexibility.md)."""
    return _taped(robot, "inverse_dynamics")


def mass_matrix(robot):
    """``mass_matrix(x) -> H``: the generalized mass matrix ((6+N)², paper eq. 36), by CRBA."""
    return _taped(robot, "mass_matrix")


def bias_forces(robot):
    """``bias_forces(x, u) -> c``: the velocity-product terms of the EOM, RNEA with ``du = 0``."""
    return _taped(robot, "bias_forces")


def generalized_inertia(robot):
    """``generalized_inertia(x) -> H_star``: $H^* = H_m - H_{0m}^T H_0^{-1} H_{0m}$ (N×N, paper eq. 45),
    with the core's closed-form $H_0^{-1}$ (eqs. 52–61)."""
    return _taped(robot, "generalized_inertia")


def generalized_bias(robot):
    """``generalized_bias(x, u) -> c_star``: $c^* = c_m - H_{0m}^T H_0^{-1} c_0$ (N)."""
    return _taped(robot, "generalized_bias")


def generalized_jacobian(robot, point=None):
    r"""``generalized_jacobian(x) -> J_star``: $J^* = J_{mX} - J_{0X} H_0^{-1} H_{0m}$ (6×N, paper eq. 110)
    of a point (a point name, a body name, ``(body, offset)``, or ``None`` for the end
    effector): with zero momentum the point's twist $[v_X; \omega]$ in 𝒥 is $J^* \dot q$."""
    return _taped(robot, "generalized_jacobian", point, with_point=True)


def point_position(robot, point=None):
    """``point_position(x) -> p``: position in 𝒥 of a point (default: the end effector)."""
    return _taped(robot, "point_position", point, with_point=True)


def momentum(robot):
    """``momentum(x, u) -> (P, L_origin)``: the momentum map, linear momentum and angular
    momentum about the origin of 𝒥 (both conserved with no external wrench)."""
    return _taped(robot, "momentum")


def base_velocity_from_momentum(robot):
    r"""``base_velocity_from_momentum(x, qd, P, L_origin) -> base_twist``: $[v_0; \omega_0] =
    H_0^{-1} (M_0 - H_{0m} \dot q)$ (paper eqs. 43, 109), the base velocity that gives the system the
    momentum ``P``, ``L_origin`` while the joints move at ``qd``."""
    return _taped(robot, "base_velocity_from_momentum")


def _project(ca, y):
    """Normalise the quaternion of a state ``y = [x; u]``."""
    quat = y[3:7]
    return ca.vertcat(y[0:3], quat / ca.norm_2(quat), y[7:])


def rk4_step(robot, substeps: int = 1, torque: str = "constant"):
    r"""``rk4_step(x, u, tau, base_wrench, dt) -> (x_next, u_next)``: ``substeps`` classical
    Runge–Kutta 4 steps of size ``dt / substeps`` with ``tau`` and ``base_wrench`` held.

    The quaternion is kept on the unit sphere by **renormalisation**, exactly as the native
    simulator's RK4 (``spacearm.simulate(integrator="rk4")``): it is integrated as four
    components of $\dot{\mathrm{quat}} = \tfrac12 [\omega_0; 0] \otimes \mathrm{quat}$, every stage value is normalised before the
    dynamics are evaluated, and the step result is normalised again (the projection method,
    which keeps the order 4). The state derivative of each stage is the core's, recorded like
    the other functions (``[v0, quaṫ, qd, du]``, ``du`` by ABA: the simulator's
    ``sim::simulate`` right-hand side); only the Runge–Kutta weights and the projection are
    written here. Chosen over an exponential-map (Lie-group) step so that one step
    of this function and one step of the native simulation are the same map to rounding: a plan
    built on it re-simulates without a discretisation mismatch.

    ``torque="linear"`` adds an input ``tau_end`` after ``tau``: the joint torque then varies
    linearly from ``tau`` at the start to ``tau_end`` at ``t + dt`` (a first-order hold; each
    RK4 stage sees the torque of its own time), so a sequence of steps applies a continuous
    torque, which a fixed-step integrator with any step reproduces to its order.
    """
    if isinstance(substeps, bool) or not isinstance(substeps, int) or substeps < 1:
        raise ArgumentError(f"substeps must be a positive integer, got {substeps!r}")
    if torque not in ("constant", "linear"):
        raise ArgumentError(f"torque must be 'constant' or 'linear', got {torque!r}")
    ca = _casadi_for(robot)
    state_derivative = _taped(robot, "state_derivative")
    # MX symbols calling the SX state-derivative Function: the graph holds 4·substeps calls
    # of one compiled function instead of as many inlined copies, so its derivatives (and an
    # optimiser's Hessian) are built once per model rather than once per stage.
    x = ca.MX.sym("x", robot.nx)
    u = ca.MX.sym("u", robot.nu)
    tau = ca.MX.sym("tau", robot.n_dof)
    tau_end = ca.MX.sym("tau_end", robot.n_dof) if torque == "linear" else tau
    wrench = ca.MX.sym("base_wrench", 6)
    dt = ca.MX.sym("dt")
    nx = robot.nx

    def rhs(y, fraction):
        """The state rate at the fraction ``fraction`` of the step (for the torque)."""
        return state_derivative(y[0:nx], y[nx:], tau + fraction * (tau_end - tau), wrench)

    h = dt / substeps
    y = ca.vertcat(x, u)
    for m in range(substeps):
        a, mid, b = m / substeps, (m + 0.5) / substeps, (m + 1) / substeps
        k1 = rhs(y, a)
        k2 = rhs(_project(ca, y + 0.5 * h * k1), mid)
        k3 = rhs(_project(ca, y + 0.5 * h * k2), mid)
        k4 = rhs(_project(ca, y + h * k3), b)
        y = _project(ca, y + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4))
    inputs = {"x": x, "u": u, "tau": tau}
    if torque == "linear":
        inputs["tau_end"] = tau_end
    inputs.update({"base_wrench": wrench, "dt": dt})
    return _function(ca, "rk4_step", inputs, {"x_next": y[0:nx], "u_next": y[nx:]})
