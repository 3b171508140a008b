"""spacearm's FDDP against Crocoddyl's on the same problem (issue 36): (a) Crocoddyl's FDDP on
Pinocchio's free-flyer model of the robot (``DifferentialActionModelFreeFwdDynamics``,
``spacearm.interop.to_pinocchio``), (b) Crocoddyl's FDDP on spacearm's action model
(``spacearm.mpc.crocoddyl_action_model``, Python callbacks), (c) spacearm's native FDDP
(``spacearm.mpc.solve``). The optimum agreement (cost, joint trajectory, torques) and the time
per iteration, interleaved repeats, medians, ratios to (a). Robots: spatial6 (N = 6) and a
30-DOF chain (N = 30).

The problem: RK4 steps (Crocoddyl's ``IntegratedActionModelRK`` four, spacearm's simulator step),
running cost ``½ w_u |τ|²`` (constant over a step's RK stages, so Crocoddyl's RK quadrature of
the running cost equals spacearm's rectangle rule) and a terminal cost on the joint positions and
rates. The three discretize the same ODE in different coordinates (Pinocchio: base velocity in
the base frame; Crocoddyl's RK stages on the Lie group; spacearm: the quaternion in ambient
coordinates, renormalized), so their optima differ by the RK4 truncation's difference.

Crocoddyl downgrades example-robot-data, so run it in its own virtual environment:

    python3 -m venv /work/venvs/croc && /work/venvs/croc/bin/pip install crocoddyl numpy defusedxml tqdm
    PYTHONPATH=python /work/venvs/croc/bin/python benchmarks/mpc_crocoddyl.py [--repeat 5]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

import spacearm
import spacearm.mpc as mpc
from spacearm.interop import to_pinocchio, to_pinocchio_state
from spacearm.mpc.crocoddyl import crocoddyl_action_model, make_state

from _chain import chain

try:
    import crocoddyl
except ImportError as exc:  # pragma: no cover
    raise SystemExit(f"this benchmark needs crocoddyl (see its docstring): {exc}")

W_U, W_Q, W_QD = 1e-2, 100.0, 10.0


def goal_of(robot) -> np.ndarray:
    n = robot.n_dof
    return robot.initial_q + 0.1 * np.cos(np.arange(n))


def weighted(state, weights, residual):
    return crocoddyl.CostModelResidual(state, crocoddyl.ActivationModelWeightedQuad(np.asarray(weights, dtype=float)), residual)


def shooting(state, dam_of, x0, xref, nu, horizon, dt, discretization="rk4"):
    """Crocoddyl's problem: running ½ w_u |τ|², terminal ½ W_q |q − q_goal|² + ½ W_qd |q̇|²."""
    n = state.ndx // 2 - 6  # joints; nu: the controls (joint torques, then any base actuation)
    run_costs = crocoddyl.CostModelSum(state, nu)
    run_costs.addCost("u", weighted(state, np.full(nu, W_U), crocoddyl.ResidualModelControl(state, nu)), 1.0)
    term_costs = crocoddyl.CostModelSum(state, nu)
    w = np.zeros(state.ndx)
    w[6:6 + n], w[12 + n:] = W_Q, W_QD
    term_costs.addCost("x", weighted(state, w, crocoddyl.ResidualModelState(state, xref, nu)), 1.0)
    if discretization == "euler":  # semi-implicit Euler, spacearm's Problem(discretization="euler")
        run = crocoddyl.IntegratedActionModelEuler(dam_of(run_costs), dt)
        term = crocoddyl.IntegratedActionModelEuler(dam_of(term_costs), 0.0)
    else:
        run = crocoddyl.IntegratedActionModelRK(dam_of(run_costs), crocoddyl.RKType.four, dt)
        term = crocoddyl.IntegratedActionModelRK(dam_of(term_costs), crocoddyl.RKType.four, 0.0)
    return crocoddyl.ShootingProblem(x0, [run] * horizon, term)


def _skew(v):
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def _rotation(quat):
    """The rotation matrix of a unit ``[x, y, z, w]`` quaternion (body axes → 𝒥)."""
    x, y, z, w = quat
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def world_wrench_actuation(state, n: int, base: list):
    """Pinocchio's free flyer actuated by the joint torques, then the base wrench components
    ``base`` (indices into ``[F0; N0]``, in 𝒥, about the base CM: spacearm's controls,
    docs/conventions.md). Pinocchio's base generalized force is that wrench in the base frame,
    ``[Rᵀ F0; Rᵀ N0]``: it turns with the base, so ``dτ/dθ = [(Rᵀ F0)~; (Rᵀ N0)~]`` for the
    local rotation increment (R ← R exp(δθ)). Crocoddyl's ``ActuationModelFloatingBaseThrusters``
    models thrusters fixed to the base (a body-frame wrench), a different control."""

    class WorldWrench(crocoddyl.ActuationModelAbstract):
        def __init__(self):
            crocoddyl.ActuationModelAbstract.__init__(self, state, n + len(base))

        def _wrench(self, x, u):
            w = np.zeros(6)
            w[base] = u[n:]
            rt = _rotation(x[3:7]).T
            return rt, rt @ w[:3], rt @ w[3:]

        def calc(self, data, x, u=None):
            if u is None:
                return
            _, f, m = self._wrench(x, u)
            data.tau[:] = np.concatenate([f, m, u[:n]])

        def calcDiff(self, data, x, u=None):
            if u is None:
                return
            rt, f, m = self._wrench(x, u)
            data.dtau_dx[:] = 0.0
            data.dtau_dx[0:3, 3:6] = _skew(f)
            data.dtau_dx[3:6, 3:6] = _skew(m)
            data.dtau_du[:] = 0.0
            data.dtau_du[6:, :n] = np.eye(n)
            for i, c in enumerate(base):
                rows = slice(0, 3) if c < 3 else slice(3, 6)
                data.dtau_du[rows, n + i] = rt[:, c % 3]

        def commands(self, data, x, tau):
            raise NotImplementedError

        def torqueTransform(self, data, x, u):
            raise NotImplementedError

    return WorldWrench()


_BASE = {"floating": [], "rotation-flying": [3, 4, 5], "flying": [0, 1, 2, 3, 4, 5]}


class Case:
    def __init__(self, robot, horizon: int, dt: float, mode: str = "floating", discretization: str = "rk4"):
        self.robot, self.horizon, self.dt, self.mode = robot, horizon, dt, mode
        n = self.n = robot.n_dof
        self.nc = n + len(_BASE[mode])
        x0, u0 = robot.neutral_configuration(), robot.zero_velocity()
        goal = goal_of(robot)
        # (a) Pinocchio's free-flyer model (its q[:7] is spacearm's x[:7]; its base velocity is in the base frame).
        pin_model = to_pinocchio(robot)
        sp = crocoddyl.StateMultibody(pin_model)
        act = crocoddyl.ActuationModelFloatingBase(sp) if mode == "floating" else world_wrench_actuation(sp, n, _BASE[mode])
        q, v = to_pinocchio_state(robot, x0, u0)
        qref = q.copy()
        qref[7:] = goal
        self.pin = shooting(sp, lambda c: crocoddyl.DifferentialActionModelFreeFwdDynamics(sp, act, c), np.concatenate([q, v]),
                            np.concatenate([qref, np.zeros(sp.nv)]), act.nu, horizon, dt, discretization)
        # (b) spacearm's action model in Crocoddyl.
        ss = make_state(robot)
        z0 = np.concatenate([x0, u0])
        zref = z0.copy()
        zref[7:7 + n] = goal
        self.spa = shooting(ss, lambda c: crocoddyl_action_model(robot, c, state=ss, mode=mode), z0, zref, self.nc, horizon, dt, discretization)
        # (c) spacearm's native problem.
        self.native = mpc.Problem(horizon=horizon, dt=dt, running=[mpc.ControlCost(W_U)], terminal=[mpc.JointCost(W_Q, goal, weight_qd=W_QD)], mode=mode,
                                  discretization=discretization)

    def crocoddyl(self, problem, iterations: int = 200):
        solver = crocoddyl.SolverFDDP(problem)
        solver.th_stop = 1e-14
        us0 = [np.zeros(self.nc)] * self.horizon
        xs0 = problem.rollout(us0)
        t = time.perf_counter()
        solver.solve(xs0, us0, iterations)
        elapsed = time.perf_counter() - t
        return solver.cost, np.array(solver.xs)[:, 7:7 + self.n], np.array(solver.us), elapsed, max(solver.iter, 1)

    def spacearm(self):
        sol = mpc.solve(self.robot, self.native, max_iterations=200, tolerance=1e-14)
        return sol.cost, sol.x[:, 7:], sol.controls, sol.solve_time, max(sol.iterations, 1)


def compare(name: str, case: Case, repeat: int) -> None:
    runs = {"a": [], "b": [], "c": []}
    results = {}
    for _ in range(repeat):  # interleaved
        for key, fn in (("a", lambda: case.crocoddyl(case.pin)), ("b", lambda: case.crocoddyl(case.spa)), ("c", case.spacearm)):
            cost, qs, us, elapsed, iters = fn()
            runs[key].append(elapsed / iters)
            results[key] = (cost, qs, us, iters)
    print(f"\n{name}: N = {case.n}, T = {case.horizon} steps of {case.dt} s")
    labels = {"a": "Crocoddyl FDDP, Pinocchio free flyer", "b": "Crocoddyl FDDP, spacearm action model", "c": "spacearm FDDP (native)"}
    base = statistics.median(runs["a"])
    for key in "abc":
        cost, qs, us, iters = results[key]
        t = statistics.median(runs[key])
        print(f"  ({key}) {labels[key]:<40} cost {cost:.12g}  iterations {iters:3d}  {t * 1e3:9.3f} ms/iteration  ratio to (a) {t / base:7.3f}")
    for a, b in (("a", "c"), ("b", "c"), ("a", "b")):
        ca, qa, ua, _ = results[a]
        cb, qb, ub, _ = results[b]
        print(f"  ({a}) vs ({b}): |Δcost|/cost {abs(ca - cb) / abs(ca):.2e}  max|Δq| {np.abs(qa - qb).max():.2e} rad  max|Δτ| {np.abs(ua - ub).max():.2e}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--horizon", type=int, default=20)
    parser.add_argument("--dt", type=float, default=0.05)
    args = parser.parse_args()
    print(f"crocoddyl {crocoddyl.__version__}; spacearm {spacearm.__version__}; medians of {args.repeat} interleaved solves")
    compare("spatial6", Case(spacearm.presets.spatial6(), args.horizon, args.dt), args.repeat)
    compare("chain30", Case(chain(30), args.horizon, args.dt), args.repeat)
    for mode in ("rotation-flying", "flying"):
        compare(f"spatial6, {mode} (base torque{'' if mode == 'rotation-flying' else ' and force'} as controls)",
                Case(spacearm.presets.spatial6(), args.horizon, args.dt, mode), args.repeat)


if __name__ == "__main__":
    main()
