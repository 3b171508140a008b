"""Generated NumPy module and C source against the Rust core, and the
``spacearm derive`` command. C tests skip cleanly without a C compiler."""

import ctypes
import importlib.util
import shutil
import subprocess

import numpy as np
import pytest

pytest.importorskip("sympy")

import spacearm  # noqa: E402
from spacearm.cli import main  # noqa: E402
from spacearm.symbolic.c_source import c_source  # noqa: E402
from spacearm.symbolic.numpy_module import numpy_module  # noqa: E402

from random_models import random_state  # noqa: E402
from test_symbolic import RANDOM3, derivation, r0g_tolerance, rel_close  # noqa: E402

INCLUDE = ["blocks", "H0_inv", "H_star", "J_star", "c", "c_star"]
MODELS = ["planar4", f"random{RANDOM3[0]}"]


def load_module(path, name):
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def check_against_core(robot, call, seed):
    rng = np.random.default_rng(seed)
    for _ in range(3):
        x, u = random_state(robot, rng)
        b = robot.inertia_blocks(x)
        rel_close(call("r_0g", x), b.r_0g, "r_0g", rtol=r0g_tolerance(x))
        for q in ("H_S", "J_TS", "H_Sq", "H0", "H0m", "Hm"):
            rel_close(call(q, x), getattr(b, q), q)
        rel_close(call("H", x), robot.mass_matrix(x), "H")
        rel_close(call("H0_inv", x), robot.base_inertia_inverse(x), "H0_inv")
        rel_close(call("H_star", x), robot.generalized_inertia(x), "H_star")
        rel_close(call("J_star_" + robot.end_effector, x), robot.generalized_jacobian(x), "J_star")
        rel_close(call("c", x, u), robot.bias_forces(x, u), "c", rtol=1e-11)
        rel_close(call("c_star", x, u), robot.generalized_bias(x, u), "c_star", rtol=1e-11)


@pytest.mark.parametrize("name", MODELS)
def test_generated_numpy_module_equals_core(name, tmp_path):
    d = derivation(name)
    path = tmp_path / f"{name}_eom.py"
    path.write_text(numpy_module(d, INCLUDE))
    mod = load_module(path, f"{name}_eom")
    assert mod.N == d.n_dof

    def call(q, x, u=None):
        f = getattr(mod, q)
        return f(x) if u is None else f(x, u)

    check_against_core(d.robot, call, seed=11)
    with pytest.raises(ValueError, match="7\\+N"):
        mod.H0(np.zeros(3))


@pytest.mark.skipif(shutil.which("gcc") is None and shutil.which("cc") is None, reason="no C compiler")
@pytest.mark.parametrize("name", MODELS)
def test_generated_c_compiles_and_equals_core(name, tmp_path):
    d = derivation(name)
    src = tmp_path / f"{name}.c"
    lib = tmp_path / f"lib{name}.so"
    src.write_text(c_source(d, INCLUDE, prefix="m"))
    cc = shutil.which("gcc") or shutil.which("cc")
    subprocess.run([cc, "-std=c99", "-O1", "-Wall", "-Werror", "-Wno-unused-variable", "-shared", "-fPIC",
                    "-o", str(lib), str(src), "-lm"], check=True, capture_output=True)
    so = ctypes.CDLL(str(lib))
    P = ctypes.POINTER(ctypes.c_double)
    shapes = {q.name: q.expr.shape for q in d.quantities(INCLUDE)}

    def call(q, x, u=None):
        rows, cols = shapes[q]
        out = np.zeros(rows * cols)
        x = np.ascontiguousarray(x, dtype=float)
        uu = None if u is None else np.ascontiguousarray(u, dtype=float).ctypes.data_as(P)
        getattr(so, f"m_{q}")(x.ctypes.data_as(P), uu, None, out.ctypes.data_as(P))
        return out if cols == 1 else out.reshape(rows, cols)

    check_against_core(d.robot, call, seed=12)


def test_cli_derive_writes_all_three_outputs(tmp_path, capsys):
    tex, py, c = tmp_path / "p4.tex", tmp_path / "p4.py", tmp_path / "p4.c"
    rc = main(["derive", "planar4", "--latex", str(tex), "--python", str(py), "--c", str(c), "--include", "blocks,H_star"])
    assert rc == 0
    out = capsys.readouterr().out
    assert "total" in out and "LaTeX" in out
    text = tex.read_text()
    assert text.startswith("\\documentclass") and text.rstrip().endswith("\\end{document}")
    for name in ("H_S", "J_{TS}", "H_{Sq}", "H_m", "H^*", "det S"):
        assert name in text, name
    assert "cos{\\left(q_{2} + q_{3} \\right)}" in text  # tidied trig sums, readable
    mod = load_module(py, "p4_cli")
    robot = spacearm.presets.planar4()
    x = robot.neutral_configuration()
    rel_close(mod.H_star(x), robot.generalized_inertia(x), "CLI NumPy H*")
    assert "void planar4_H_star(" in c.read_text()
    assert not list(tmp_path.glob(".tmp-*")), "temporary files left behind"


def test_cli_derive_reports_bad_input(capsys):
    assert main(["derive", "no_such_model", "--python", "x.py"]) == 2
    assert "neither a preset" in capsys.readouterr().err
    assert main(["derive", "planar4", "--symbols", "bogus", "--python", "x.py"]) == 2
    assert "unknown parameter" in capsys.readouterr().err
