r"""Crocoddyl interop: a ``crocoddyl.DifferentialActionModelAbstract`` backed by spacearm's
forward dynamics and its analytic derivatives (docs/mpc.md, "Crocoddyl").

Crocoddyl (``pip install crocoddyl``) is imported only when a model is made. The state is
spacearm's $z = [x; u]$ (``nq = 7 + N``, ``nv = 6 + N``) on its own manifold
(`make_state`): the tangent $\delta z = [\delta r_0,
\delta\theta, \delta q, \delta v_0, \delta\omega_0, \delta\dot q]$ with $\delta\theta$ a world-frame
rotation increment, $\mathrm{quat} \leftarrow \exp(\delta\theta) \otimes \mathrm{quat}$ — the tangent of
the core's derivatives, in which $\delta\dot x = u$ (so Crocoddyl's integrators, which advance the
configuration by the velocity half of the state, integrate spacearm's kinematics). The model's
``xout`` is $\dot u = \mathrm{FD}(x, u, S c)$ (the controls $c$: the joint torques, then the base
torque or wrench the mode allows, `control_columns`)
and ``Fx``, ``Fu`` its exact Jacobians (``Robot.forward_dynamics_derivatives``, docs/derivatives.md).

The cost is a ``crocoddyl.CostModelSum`` on that state (residuals that use only the state's
``diff`` and the controls, e.g. ``ResidualModelState`` and ``ResidualModelControl``).
"""

from __future__ import annotations

import numpy as np

from ..errors import ArgumentError, MissingDependencyError, NonFiniteError

__all__ = ["control_columns", "crocoddyl_action_model", "make_state"]


def _import_crocoddyl():
    try:
        import crocoddyl
    except ImportError as exc:  # depends on the environment
        raise MissingDependencyError(
            "spacearm.mpc.crocoddyl_action_model needs Crocoddyl: install it with `pip install crocoddyl` "
            "(in a separate virtual environment if your example-robot-data must stay at version 6: "
            "crocoddyl pins it to 5)") from exc
    return crocoddyl


def _skew(v):
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def _quat_mul(a, b):
    """Hamilton product of ``[x, y, z, w]`` quaternions."""
    av, aw, bv, bw = a[:3], a[3], b[:3], b[3]
    return np.concatenate([aw * bv + bw * av + np.cross(av, bv), [aw * bw - av @ bv]])


def _exp(phi):
    t = np.linalg.norm(phi)
    if t < 1e-8:
        q = np.concatenate([0.5 * phi, [1.0]])
        return q / np.linalg.norm(q)
    return np.concatenate([np.sin(0.5 * t) / t * phi, [np.cos(0.5 * t)]])


def _log(q):
    q = q / np.linalg.norm(q)
    if q[3] < 0:
        q = -q
    s = np.linalg.norm(q[:3])
    if s < 1e-8:
        return 2.0 * q[:3] / q[3]
    return 2.0 * np.arctan2(s, q[3]) / s * q[:3]


def _left_jacobian(phi):
    r"""$J_l(\phi) = I + \frac{1 - \cos t}{t^2} \tilde\phi + \frac{t - \sin t}{t^3} \tilde\phi^2$."""
    t, k = np.linalg.norm(phi), _skew(phi)
    if t < 1e-5:
        return np.eye(3) + 0.5 * k + k @ k / 6.0
    return np.eye(3) + (1.0 - np.cos(t)) / t**2 * k + (t - np.sin(t)) / t**3 * (k @ k)


def _left_jacobian_inverse(phi):
    r"""$J_l^{-1}(\phi) = I - \tfrac12 \tilde\phi + \big(\frac{1}{t^2} - \frac{1 + \cos t}{2 t \sin t}\big) \tilde\phi^2$."""
    t, k = np.linalg.norm(phi), _skew(phi)
    if t < 1e-5:
        return np.eye(3) - 0.5 * k + k @ k / 12.0
    return np.eye(3) - 0.5 * k + (1.0 / t**2 - (1.0 + np.cos(t)) / (2.0 * t * np.sin(t))) * (k @ k)


def _rotation(phi):
    t, k = np.linalg.norm(phi), _skew(phi)
    if t < 1e-8:
        return np.eye(3) + k
    return np.eye(3) + np.sin(t) / t * k + (1.0 - np.cos(t)) / t**2 * (k @ k)


def make_state(robot):
    """The Crocoddyl state of ``robot``'s ``[x; u]`` on spacearm's manifold (module docs): a
    ``crocoddyl.StateAbstract`` with ``diff``, ``integrate`` and their Jacobians."""
    crocoddyl = _import_crocoddyl()
    n = robot.n_dof
    nq, nv = 7 + n, 6 + n
    first, second, both = crocoddyl.Jcomponent.first, crocoddyl.Jcomponent.second, crocoddyl.Jcomponent.both

    def blocks(m):
        """``blockdiag(I, m, I)`` of size ``2 nv`` (the attitude rows 3:6)."""
        j = np.eye(2 * nv)
        j[3:6, 3:6] = m
        return j

    class SpacearmState(crocoddyl.StateAbstract):
        def __init__(self):
            crocoddyl.StateAbstract.__init__(self, nq + nv, 2 * nv)
            self.robot = robot

        def zero(self):
            return np.concatenate([robot.neutral_configuration(), robot.zero_velocity()])

        def rand(self):
            z = self.zero()
            z[7:nq] += np.random.uniform(-1.0, 1.0, n)
            z[3:7] = _exp(np.random.uniform(-1.0, 1.0, 3))
            return z

        def diff(self, x0, x1):
            d = np.empty(2 * nv)
            d[:3] = x1[:3] - x0[:3]
            d[3:6] = _log(_quat_mul(x1[3:7], x0[3:7] * np.array([-1.0, -1.0, -1.0, 1.0])))
            d[6:] = x1[7:] - x0[7:]
            return d

        def integrate(self, x, dx):
            out = np.array(x, dtype=float)
            out[:3] += dx[:3]
            out[3:7] = _quat_mul(_exp(dx[3:6]), x[3:7])
            out[7:] += dx[6:]
            return out

        def Jdiff(self, x0, x1, firstsecond=both):
            if firstsecond == both:
                return [self.Jdiff(x0, x1, first), self.Jdiff(x0, x1, second)]
            theta = self.diff(x0, x1)[3:6]
            inv = _left_jacobian_inverse(theta)
            # θ = log(q1 q0*): δθ/δ1 = J_l⁻¹(θ), δθ/δ0 = −J_r⁻¹(θ) = −J_l⁻¹(θ)ᵀ.
            return -blocks(inv.T) if firstsecond == first else blocks(inv)

        def Jintegrate(self, x, dx, firstsecond=both):
            if firstsecond == both:
                return [self.Jintegrate(x, dx, first), self.Jintegrate(x, dx, second)]
            # exp(dθ) exp(δ) q = exp(R(dθ) δ) exp(dθ) q;  exp(dθ + ε) q ≈ exp(J_l(dθ) ε) exp(dθ) q.
            return blocks(_rotation(dx[3:6]) if firstsecond == first else _left_jacobian(dx[3:6]))

        def JintegrateTransport(self, x, dx, Jin, firstsecond):
            return self.Jintegrate(x, dx, firstsecond) @ Jin

    return SpacearmState()


_BASE_COLUMNS = {"floating": [], "rotation-floating": [], "rotation-flying": [3, 4, 5], "flying": [0, 1, 2, 3, 4, 5]}


def control_columns(robot, mode: str = "floating") -> list:
    """The generalized-force components ``f[columns[i]] = c[i]`` the controls of ``mode`` drive:
    the joint torques, then the base torque ``N0`` (rotation-flying) or the base wrench
    ``[F0; N0]`` (flying), in 𝒥 about the base CM (docs/conventions.md) — the core's
    ``optimal::dynamics::ControlMap``."""
    if mode not in _BASE_COLUMNS:
        raise ArgumentError(f"crocoddyl_action_model: mode {mode!r} is not implemented (one of {', '.join(map(repr, _BASE_COLUMNS))} is; "
                            "translation-flying's force acts through the moving system CM)")
    return [6 + j for j in range(robot.n_dof)] + _BASE_COLUMNS[mode]


def crocoddyl_action_model(robot, costs=None, *, mode: str = "floating", state=None):
    r"""A ``crocoddyl.DifferentialActionModelAbstract`` of ``robot`` (module docs): ``xout`` the
    forward dynamics $\dot u = \mathrm{FD}(x, u, S c)$ of spacearm's state, ``Fx``/``Fu`` its
    analytic derivatives, the cost ``costs`` (a ``crocoddyl.CostModelSum`` on ``state``;
    ``None``: no cost). ``state``: the model's state (`make_state`; made when absent — pass the
    one the costs were built on). The controls ``c`` are the mode's (`control_columns`): the
    joint torques (``"floating"``, ``"rotation-floating"``), then the base torque $N_0$
    (``"rotation-flying"``) or the base wrench $[F_0; N_0]$ (``"flying"``), in 𝒥."""
    crocoddyl = _import_crocoddyl()
    columns = control_columns(robot, mode)
    state = make_state(robot) if state is None else state
    n = robot.n_dof
    nq, nc = 7 + n, len(columns)
    if nc == 0:
        raise ArgumentError(f"crocoddyl_action_model: the robot has no control in the {mode!r} mode (no joint, no base actuation)")
    if costs is not None and not isinstance(costs, crocoddyl.CostModelSum):
        raise ArgumentError(f"crocoddyl_action_model: costs must be a crocoddyl.CostModelSum, got {type(costs).__name__}")

    def force(c):
        f = np.zeros(6 + n)
        if c is not None:
            f[columns] = c
        return f

    class SpacearmDifferentialActionModel(crocoddyl.DifferentialActionModelAbstract):
        def __init__(self):
            crocoddyl.DifferentialActionModelAbstract.__init__(self, state, nc, 0 if costs is None else costs.nr)
            self.robot, self.costs = robot, costs

        def calc(self, data, x, u=None):
            try:
                data.xout[:] = robot.forward_dynamics(x[:nq], x[nq:], force(u))
            except NonFiniteError:
                # A trial step of the line search that overflows: NaN, which Crocoddyl's solvers
                # refuse as a failed step (a Python exception would abort the solve instead).
                data.xout[:] = np.nan
                data.cost = np.nan
                return
            if costs is not None:
                if u is None:
                    costs.calc(data.costs, x)
                else:
                    costs.calc(data.costs, x, u)
                data.cost = data.costs.cost

        def calcDiff(self, data, x, u=None):
            d = robot.forward_dynamics_derivatives(x[:nq], x[nq:], force(u))
            data.Fx[:, : 6 + n] = d.ddu_dx
            data.Fx[:, 6 + n:] = d.ddu_du
            data.Fu[:, :] = d.ddu_df[:, columns]
            if costs is not None:
                if u is None:
                    costs.calcDiff(data.costs, x)
                else:
                    costs.calcDiff(data.costs, x, u)

        def createData(self):
            return SpacearmDifferentialActionData(self)

    class SpacearmDifferentialActionData(crocoddyl.DifferentialActionDataAbstract):
        def __init__(self, model):
            crocoddyl.DifferentialActionDataAbstract.__init__(self, model)
            if costs is not None:
                self.collector = crocoddyl.DataCollectorAbstract()
                self.costs = costs.createData(self.collector)
                self.costs.shareMemory(self)

    return SpacearmDifferentialActionModel()
