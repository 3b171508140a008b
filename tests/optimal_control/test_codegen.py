"""The generated C code of the equations of motion ([`spacearm.casadi.generate_c`][spacearm.casadi.generate_c],
docs/c-api.md "Embedded code"), compiled with the system C compiler and run, against the core:
the forward dynamics, ``H*`` and ``J*`` against the Robot's (the core's own recursions in
float64, not the taped graph), and the RK4 step against one step of the native simulator
(``spacearm.Simulator``) with the same held torque and base wrench.
"""

from __future__ import annotations

import shutil
import subprocess

import numpy as np
import pytest

import spacearm

ca = pytest.importorskip("casadi", reason="the optimal-control extra (casadi) generates the code")
import spacearm.casadi as sc  # noqa: E402


@pytest.fixture(scope="module")
def compiled(tmp_path_factory):
    cc = shutil.which("cc") or shutil.which("gcc") or shutil.which("clang")
    if cc is None:
        pytest.fail("no C compiler (cc) on PATH: the generated code cannot be checked")
    robot = spacearm.presets.spatial6()
    directory = tmp_path_factory.mktemp("gen")
    source = sc.generate_c(robot, directory, prefix="s6")
    assert source.name == "s6.c" and (directory / "s6.h").is_file()
    header = (directory / "s6.h").read_text()
    for name in sc.GENERATED:
        assert f"int s6_{name}(" in header
    library = directory / "libs6.so"
    subprocess.run([cc, "-O1", "-shared", "-fPIC", "-Wall", "-Werror=implicit-function-declaration", str(source), "-o", str(library), "-lm"],
                   check=True, capture_output=True)
    return robot, {name: ca.external(f"s6_{name}", str(library)) for name in sc.GENERATED}


def states(robot, k):
    rng = np.random.default_rng(11)
    for _ in range(k):
        quat = rng.normal(size=4)
        x = robot.neutral_configuration(robot.initial_q + rng.uniform(-0.6, 0.6, robot.n_dof), r0=rng.normal(size=3), quat0=quat / np.linalg.norm(quat))
        yield x, rng.normal(size=robot.nu) * 0.4, rng.normal(size=robot.n_dof), rng.normal(size=6)


def test_the_compiled_code_equals_the_core(compiled):
    robot, f = compiled
    for x, u, tau, w in states(robot, 5):
        du = np.array(f["forward_dynamics"](x, u, tau, w)).ravel()
        assert np.allclose(du, robot.forward_dynamics(x, u, tau=tau, base_wrench=w), rtol=1e-9, atol=1e-9)
        assert np.allclose(np.array(f["generalized_inertia"](x)), robot.generalized_inertia(x), rtol=1e-10, atol=1e-12)
        assert np.allclose(np.array(f["generalized_jacobian"](x)), robot.generalized_jacobian(x), rtol=1e-10, atol=1e-12)


def test_the_compiled_rk4_step_is_the_native_simulators_step(compiled):
    robot, f = compiled
    dt = 0.01
    sim = spacearm.Simulator(robot, mode="flying", dt=dt, joint_limits=False)
    for x, u, tau, w in states(robot, 3):
        sim.reset(x, u)
        sim.step(tau, n=1, base_wrench=w)
        x1, u1 = (np.array(v).ravel() for v in f["rk4_step"](x, u, tau, w, dt))
        assert np.allclose(x1, sim.x, rtol=0, atol=1e-11) and np.allclose(u1, sim.u, rtol=0, atol=1e-10)
        assert np.abs(u1 - u).max() > 1e-3  # the step moved


def test_the_mpc_example_runs_and_reports_its_solve_times():
    import os
    import sys

    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    run = subprocess.run([sys.executable, os.path.join(root, "examples", "mpc_receding_horizon.py"), "--steps", "2", "--horizon", "3"],
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert "solve time per step (CPU): median" in run.stdout and "final joint error" in run.stdout
