#!/usr/bin/env python
"""A receding-horizon (MPC) joint controller on planar4 on spacearm's CasADi model, with the
solve time of every step (docs/c-api.md, "Embedded code").

The solve times depend on the machine; the wall time also on its load (the CPU time less so).

At every control period the controller solves, with IPOPT (CasADi's own NLP solver; warm
started from the previous solution), a multiple-shooting problem over a horizon of ``--horizon``
periods: the free-floating dynamics are the RK4 step of [`spacearm.casadi.rk4_step`][spacearm.casadi.rk4_step] (the
same map as the C code of [`spacearm.casadi.generate_c`][spacearm.casadi.generate_c]), the cost the joint error to the
goal plus a small effort term, the torques bounded by the model's effort limits. The first
torque is applied to the plant, the native simulator (``spacearm.Simulator``, RK4 at a tenth of
the period), and the horizon moves on.

Prints the median, 95th-percentile and largest solve time per step (wall and CPU), how many
solves stopped at the iteration limit (their last iterate is applied), and the final joint error.

    python examples/mpc_receding_horizon.py --steps 30
"""

import argparse
import time

import numpy as np

import spacearm
import spacearm.casadi as sc


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=30, help="control periods to run (default 30)")
    parser.add_argument("--horizon", type=int, default=10, help="periods in the horizon (default 10)")
    parser.add_argument("--period", type=float, default=0.1, help="control period, s (default 0.1)")
    args = parser.parse_args()
    import casadi as ca

    robot = spacearm.presets.planar4()
    n, nx, nu, horizon, period = robot.n_dof, robot.nx, robot.nu, args.horizon, args.period
    q_goal = robot.initial_q + np.array([0.4, -0.3, 0.3, -0.2])
    # The model's effort limits where it has them, else 20 N·m (planar4's joints are unlimited).
    limit = np.array([min(link.limits.effort, 20.0) for link in robot.description.links if link.dof is not None])
    step = sc.rk4_step(robot)

    opti = ca.Opti()
    taus = opti.variable(n, horizon)
    x0, u0 = opti.parameter(nx), opti.parameter(nu)
    cost, xk, uk = 0, x0, u0
    for k in range(horizon):  # single shooting: the states are the RK4 steps of the torques
        xk, uk = step(xk, uk, taus[:, k], ca.DM.zeros(6), period)
        cost += ca.sumsqr(xk[7:] - q_goal) + 1e-2 * ca.sumsqr(uk[6:]) + 1e-4 * ca.sumsqr(taus[:, k])
    opti.subject_to(opti.bounded(np.tile(-limit, (horizon, 1)).T, taus, np.tile(limit, (horizon, 1)).T))
    opti.minimize(cost)
    opti.solver("ipopt", {"print_time": False}, {"print_level": 0, "sb": "yes", "max_iter": 100, "tol": 1e-8, "hessian_approximation": "limited-memory"})

    plant = spacearm.Simulator(robot, dt=period / 10)
    x, u = robot.neutral_configuration(), robot.zero_velocity()
    plant.reset(x, u)
    wall, cpu, unsolved, guess = [], [], 0, None
    for _ in range(args.steps):
        opti.set_value(x0, x)
        opti.set_value(u0, u)
        if guess is not None:
            opti.set_initial(taus, guess)
        start, start_cpu = time.perf_counter(), time.process_time()
        try:
            plan = np.asarray(opti.solve().value(taus)).reshape(n, horizon)
        except RuntimeError:  # not converged in max_iter: apply the last iterate, and say so below
            plan = np.asarray(opti.debug.value(taus)).reshape(n, horizon)
            unsolved += 1
        wall.append(time.perf_counter() - start)
        cpu.append(time.process_time() - start_cpu)
        guess = np.hstack([plan[:, 1:], plan[:, -1:]])  # the plan shifted by one period
        plant.step(plan[:, 0], n=10)
        x, u = plant.x, plant.u
    print(f"MPC on planar4: horizon {horizon} x {period:g} s, {args.steps} steps, single shooting, IPOPT "
          f"(limited-memory Hessian); {unsolved} of {args.steps} solves stopped at the iteration limit")
    for what, t in (("wall", np.array(wall) * 1e3), ("CPU", np.array(cpu) * 1e3)):
        print(f"solve time per step ({what}): median {np.median(t):.1f} ms, 95th percentile {np.percentile(t, 95):.1f} ms, "
              f"max {t.max():.1f} ms (the first, cold: {t[0]:.1f} ms)")
    print(f"final joint error {np.abs(x[7:] - q_goal).max():.3g} rad after {args.steps * period:g} s")


if __name__ == "__main__":
    main()
