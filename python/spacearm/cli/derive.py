"""``spacearm derive MODEL [--latex OUT.tex] [--python OUT.py] [--c OUT.c] [--symbols ...]``.

Derives the model's closed-form matrices and writes the requested outputs atomically; prints the
derivation time of each stage. Registered in ``spacearm.cli``. SymPy (the ``symbolic`` extra)
is imported only when the command runs, so the parser builds without it.
"""

from __future__ import annotations

import sys
import time

from .model_options import add_model_arguments

__all__ = ["add_parser", "run"]


def add_parser(sub) -> None:

    p = sub.add_parser("derive", help="derive the closed-form matrices (SymPy) and write LaTeX, NumPy and C")
    add_model_arguments(p)
    p.add_argument("--latex", metavar="OUT.tex", help="write a LaTeX document of the matrices")
    p.add_argument("--python", metavar="OUT.py", help="write a NumPy module")
    p.add_argument("--c", metavar="OUT.c", help="write C99 source")
    p.add_argument("--symbols", default=None,
                   help="comma-separated parameters or categories to keep symbolic (masses, inertias, lengths, all, or names like m1,o2_x)")
    p.add_argument("--include", default=None,
                   help="comma-separated quantity groups for --python/--c (default all: blocks, jacobians, H0_inv, H_star, J_star, dH_dq, H_dot, c, c_star)")


def run(args, model_from_args, out=None) -> None:
    # Resolve the stream at call time so that redirections of sys.stdout (pytest, callers) count.
    out = sys.stdout if out is None else out
    from ..errors import SpacearmError
    from ..symbolic.codegen import write_atomic
    from ..symbolic.derivation import derive

    if not (args.latex or args.python or args.c):
        from .numbers import CliError

        raise CliError("nothing to write: give --latex, --python and/or --c")
    robot = model_from_args(args)
    symbols = None
    if args.symbols:
        symbols = "all" if args.symbols == "all" else [s.strip() for s in args.symbols.split(",") if s.strip()]
    include = None if not args.include else [s.strip() for s in args.include.split(",") if s.strip()]
    t0 = time.perf_counter()
    try:
        d = derive(robot, symbols)
    except ValueError as exc:
        raise SpacearmError(str(exc)) from None
    jobs = []
    if args.latex:
        from ..symbolic.latex import latex_document

        jobs.append(("LaTeX", args.latex, lambda: latex_document(d)))
    if args.python:
        from ..symbolic.numpy_module import numpy_module

        jobs.append(("NumPy", args.python, lambda: numpy_module(d, include)))
    if args.c:
        from ..symbolic.c_source import c_source

        jobs.append(("C", args.c, lambda: c_source(d, include)))
    for what, path, make in jobs:
        t = time.perf_counter()
        try:
            text = make()
        except ValueError as exc:
            raise SpacearmError(str(exc)) from None
        write_atomic(path, text)
        out.write(f"{what:6s} {path}  ({len(text)} characters, {time.perf_counter() - t:.2f} s)\n")
    out.write("derivation stages: " + ", ".join(f"{k} {v:.2f} s" for k, v in d.timings.items()) + "\n")
    out.write(f"total {time.perf_counter() - t0:.2f} s\n")
