"""CasADi ``Function`` objects of a :class:`~spacearm.Robot`'s equations of motion.

Each builder takes a Robot and returns a ``casadi.Function`` on ``SX`` symbols, built from the
recursive algorithms in :mod:`._recursions` (RNEA, CRBA, ABA, kinematics) evaluated on the
model's typed description. The functions follow spacearm's conventions exactly
(docs/conventions.md): ``x = [r0, quat0 [x, y, z, w], q]`` (7+N), ``u = [v0, w0, qd]`` (6+N) with
``v0``, ``w0`` in 𝒥, ``f = [F0, N0, tau]``, ``EOM H du + c = f``. The quaternion input is
normalised inside each function (as the core normalises its input), so derivatives with
respect to it are tangent to the unit sphere.

Evaluated at a numeric state each function equals the core's result to rounding; its CasADi
derivatives are exact derivatives of the same recursions (docs/optimal-control.md).
"""

from __future__ import annotations

from typing import Tuple

from .._util.optional import require
from ..errors import ArgumentError, SpacearmTypeError
from . import _recursions as rec

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


def _symbols(robot) -> Tuple[object, object, object, "rec.Kinematics"]:
    """``(ca, x, u, kinematics)``: fresh SX symbols of a robot's state and its kinematics."""
    ca = _casadi_for(robot)
    x = ca.SX.sym("x", robot.nx)
    u = ca.SX.sym("u", robot.nu)
    return ca, x, u, rec.Kinematics(ca, robot.description, x)


def _function(ca, name: str, inputs: dict, outputs: dict):
    return ca.Function(name, list(inputs.values()), list(outputs.values()), list(inputs), list(outputs))


def _base_inverse_times(ca, H, rhs):
    """``H0⁻¹ rhs`` from the 6×6 base block of ``H``: CasADi's symbolic solve (a QR
    factorisation of the 6×6 block written into the graph, independent of N)."""
    return ca.solve(H[0:6, 0:6], rhs)


def forward_dynamics(robot):
    """``forward_dynamics(x, u, tau, base_wrench) -> du``: the state derivative
    ``du = [dv0/dt, dw0/dt, qdd]`` under joint torques ``tau`` (N) and the base wrench
    ``base_wrench = [F0, N0]`` (6, in 𝒥, about the base CM; zero for free floating), by the
    articulated-body algorithm (the core's ``Robot.forward_dynamics(method="aba")``)."""
    ca, x, u, kin = _symbols(robot)
    tau = ca.SX.sym("tau", robot.n_dof)
    wrench = ca.SX.sym("base_wrench", 6)
    du = rec.forward_dynamics(kin, u, ca.vertcat(wrench, tau))
    return _function(ca, "forward_dynamics", {"x": x, "u": u, "tau": tau, "base_wrench": wrench}, {"du": du})


def inverse_dynamics(robot):
    """``inverse_dynamics(x, u, du) -> f``: the generalized force ``f = [F0, N0, tau]`` with
    ``H du + c = f``, by RNEA (the core's ``Robot.inverse_dynamics``)."""
    ca, x, u, kin = _symbols(robot)
    du = ca.SX.sym("du", robot.nu)
    return _function(ca, "inverse_dynamics", {"x": x, "u": u, "du": du}, {"f": rec.inverse_dynamics(kin, u, du)})


def mass_matrix(robot):
    """``mass_matrix(x) -> H``: the generalized mass matrix ((6+N)², paper eq. 36), by CRBA."""
    ca, x, _, kin = _symbols(robot)
    return _function(ca, "mass_matrix", {"x": x}, {"H": rec.mass_matrix(kin)})


def bias_forces(robot):
    """``bias_forces(x, u) -> c``: the velocity-product terms of the EOM, RNEA with ``du = 0``."""
    ca, x, u, kin = _symbols(robot)
    return _function(ca, "bias_forces", {"x": x, "u": u}, {"c": rec.inverse_dynamics(kin, u, ca.DM.zeros(robot.nu))})


def generalized_inertia(robot):
    """``generalized_inertia(x) -> H_star``: ``H* = Hm − H0mᵀ H0⁻¹ H0m`` (N×N, paper eq. 45)."""
    ca, x, _, kin = _symbols(robot)
    H = rec.mass_matrix(kin)
    H0m, Hm = H[0:6, 6:], H[6:, 6:]
    return _function(ca, "generalized_inertia", {"x": x}, {"H_star": Hm - ca.mtimes(H0m.T, _base_inverse_times(ca, H, H0m))})


def generalized_bias(robot):
    """``generalized_bias(x, u) -> c_star``: ``c* = c_m − H0mᵀ H0⁻¹ c0`` (N)."""
    ca, x, u, kin = _symbols(robot)
    H = rec.mass_matrix(kin)
    c = rec.inverse_dynamics(kin, u, ca.DM.zeros(robot.nu))
    c_star = c[6:] - ca.mtimes(H[0:6, 6:].T, _base_inverse_times(ca, H, c[0:6]))
    return _function(ca, "generalized_bias", {"x": x, "u": u}, {"c_star": c_star})


def generalized_jacobian(robot, point=None):
    """``generalized_jacobian(x) -> J_star``: ``J* = J_mX − J_0X H0⁻¹ H0m`` (6×N, paper eq. 110)
    of a point (a point name, a body name, ``(body, offset)``, or ``None`` for the end
    effector): with zero momentum the point's twist ``[v_X; ω]`` in 𝒥 is ``J* qd``."""
    ca, x, _, kin = _symbols(robot)
    body, offset = robot.resolve_point(point)
    J0, Jm = kin.point_jacobians(body, offset)
    H = rec.mass_matrix(kin)
    J_star = Jm - ca.mtimes(J0, _base_inverse_times(ca, H, H[0:6, 6:]))
    return _function(ca, "generalized_jacobian", {"x": x}, {"J_star": J_star})


def point_position(robot, point=None):
    """``point_position(x) -> p``: position in 𝒥 of a point (default: the end effector)."""
    ca, x, _, kin = _symbols(robot)
    body, offset = robot.resolve_point(point)
    return _function(ca, "point_position", {"x": x}, {"p": kin.point_position(body, offset)})


def momentum(robot):
    """``momentum(x, u) -> (P, L_origin)``: the momentum map, linear momentum and angular
    momentum about the origin of 𝒥 (both conserved with no external wrench)."""
    ca, x, u, kin = _symbols(robot)
    h = rec.momentum_about_base(kin, u)
    P = h[0:3]
    return _function(ca, "momentum", {"x": x, "u": u}, {"P": P, "L_origin": h[3:6] + ca.cross(x[0:3], P)})


def base_velocity_from_momentum(robot):
    """``base_velocity_from_momentum(x, qd, P, L_origin) -> base_twist``: ``[v0; w0] =
    H0⁻¹ (M0 − H0m qd)`` (paper eqs. 43, 109), the base velocity that gives the system the
    momentum ``P``, ``L_origin`` while the joints move at ``qd``."""
    ca, x, _, kin = _symbols(robot)
    qd = ca.SX.sym("qd", robot.n_dof)
    P = ca.SX.sym("P", 3)
    L = ca.SX.sym("L_origin", 3)
    H = rec.mass_matrix(kin)
    M0 = ca.vertcat(P, L - ca.cross(x[0:3], P))  # momentum about the base CM
    twist = _base_inverse_times(ca, H, M0 - ca.mtimes(H[0:6, 6:], qd))
    return _function(ca, "base_velocity_from_momentum", {"x": x, "qd": qd, "P": P, "L_origin": L}, {"base_twist": twist})


def _quaternion_rate(ca, w, quat):
    """``quaṫ = ½ [ω; 0] ⊗ quat`` (Hamilton, ``[x, y, z, w]``, ``ω`` in 𝒥: a left product)."""
    qv, qw = quat[0:3], quat[3]
    return 0.5 * ca.vertcat(qw * w + ca.cross(w, qv), -ca.dot(w, qv))


def _project(ca, y):
    """Normalise the quaternion of a state ``y = [x; u]``."""
    quat = y[3:7]
    return ca.vertcat(y[0:3], quat / ca.norm_2(quat), y[7:])


def rk4_step(robot, substeps: int = 1, torque: str = "constant"):
    """``rk4_step(x, u, tau, base_wrench, dt) -> (x_next, u_next)``: ``substeps`` classical
    Runge–Kutta 4 steps of size ``dt / substeps`` with ``tau`` and ``base_wrench`` held.

    The quaternion is kept on the unit sphere by **renormalisation**, exactly as the native
    simulator's RK4 (``spacearm.simulate(integrator="rk4")``): it is integrated as four
    components of ``quaṫ = ½ [ω0; 0] ⊗ quat``, every stage value is normalised before the
    dynamics are evaluated, and the step result is normalised again (the projection method,
    which keeps the order 4). Chosen over an exponential-map (Lie-group) step so that one step
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
    fd = forward_dynamics(robot)
    # MX symbols calling the SX forward-dynamics Function: the graph holds 4·substeps calls
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
        xs, us = y[0:nx], y[nx:]
        xdot = ca.vertcat(us[0:3], _quaternion_rate(ca, us[3:6], xs[3:7]), us[6:])
        return ca.vertcat(xdot, fd(xs, us, tau + fraction * (tau_end - tau), wrench))

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
