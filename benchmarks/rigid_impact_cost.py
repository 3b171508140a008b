#!/usr/bin/env python
"""The cost of one rigid frictional impact (docs/contact.md, "Rigid frictional impacts"):
``spacearm.contact.solve_impact`` on the 7-joint arm ``spatial7`` with one and two contacts
(μ = 0.3) by ADMM and by PGS — the whole call: Jacobian, mass matrix, Delassus operator, solve
and velocity jump — next to Pinocchio 4's ``ADMMConstraintSolver`` / ``PGSConstraintSolver``
solving the same problem given its Delassus matrix (the solve alone), both to the tolerance
1e-10 (spacearm's residual in m/s; Pinocchio's absolute feasibility and complementarity).

Interleaved rounds; medians over ``--repeat`` rounds of ``--calls`` calls each, with the
iterations each solver took. The machine's load shows in the load average printed at the top.

    python benchmarks/rigid_impact_cost.py
    python benchmarks/rigid_impact_cost.py --calls 2000 --repeat 9
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

import spacearm
from spacearm.contact import solve_impact

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "contact"))
from test_rigid_impact import _arm_contacts, _pinocchio_problem  # noqa: E402


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--calls", type=int, default=500)
    p.add_argument("--repeat", type=int, default=7)
    a = p.parse_args()
    print(f"load average {os.getloadavg()[0]:.2f}; {a.calls} calls per round, median of {a.repeat}")
    robot = spacearm.presets.spatial7()
    rng = np.random.default_rng(5)
    x = robot.neutral_configuration()
    x[7:] = rng.uniform(-1.5, 1.5, robot.n_dof)
    u = rng.normal(scale=0.3, size=robot.nu)
    mu, tol = 0.3, 1e-10
    cases, pin = {}, None
    for k in (1, 2):
        points = _arm_contacts(robot, x, u, rng, k)
        for solver in ("admm", "pgs"):
            cases[f"spacearm {solver}, {k} contact(s)"] = (lambda pts=points, s=solver: solve_impact(robot, x, u, pts, friction=mu, solver=s, tolerance=tol))
        try:
            pin, _, _, v, J, _, G, models, datas = _pinocchio_problem(robot, x, u, points, mu)
        except BaseException:  # pytest's skip when Pinocchio is missing
            continue
        for solver in ("admm", "pgs"):
            def solve(s=solver, G=G, g=J @ v, models=models, datas=datas):
                if s == "admm":
                    st, res, so = pin.ADMMSolverSettings(), pin.ADMMSolverResult(), pin.ADMMConstraintSolver(len(g))
                else:
                    st, res, so = pin.PGSSolverSettings(), pin.PGSSolverResult(), pin.PGSConstraintSolver(len(g))
                st.absolute_feasibility_tol = st.absolute_complementarity_tol = tol
                st.relative_feasibility_tol = st.relative_complementarity_tol = 0.0
                st.max_iterations = 1000
                so.solve(pin.DelassusOperatorDense(G), g, models, datas, st, res)
                return res
            cases[f"pinocchio {solver} solve, {k} contact(s)"] = solve
    times: dict = {k: [] for k in cases}
    for _ in range(a.repeat):
        for name, f in cases.items():
            t0 = time.perf_counter()
            for _ in range(a.calls):
                r = f()
            times[name].append((time.perf_counter() - t0) / a.calls)
    for name, ts in times.items():
        r = cases[name]()
        its = r.iterations
        print(f"{name:34s} {statistics.median(ts) * 1e6:9.2f} µs/call   {its:5d} iterations")


if __name__ == "__main__":
    main()
