"""A [`Derivation`][spacearm.symbolic.Derivation]: every closed-form quantity of one model, derived once and cached.

>>> import spacearm
>>> from spacearm.symbolic import derive
>>> d = derive(spacearm.presets.planar4())
>>> d.Hm.shape
(4, 4)

Everything is derived in the base frame (base CM at the origin, ``R0 = E``; see
``spacearm.symbolic.frames`` for why that loses nothing and how the world form follows) as
functions of the joint coordinates ``q``, the parameters chosen to be symbols, and — for
velocity-dependent quantities — ``u_b = [v_b; ω_b; q̇]``, the base velocities in base axes.
[`Derivation.world`][spacearm.symbolic.Derivation.world] gives the world form with the base attitude as a DCM or a quaternion;
[`Derivation.evaluate`][spacearm.symbolic.Derivation.evaluate] evaluates any quantity numerically at a world state ``(x, u)``.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from functools import cached_property
from typing import Callable, Dict, List

import numpy as np
import sympy as sp

from .bias import bias_from_lagrangian
from .derivatives import partial, time_derivative
from .frames import quat_to_dcm, rotate, to_base_velocity
from .generalized import generalized_bias, generalized_inertia, generalized_jacobian
from .inertia import SymbolicInertia, assemble, inertia_blocks
from .jacobians import point_jacobians, rotational_jacobian, translational_jacobian
from .kinematics import Kinematics, quaternion_dcm, quaternion_symbols, dcm_symbols
from .parameters import Parameters
from ..errors import NotFoundError

__all__ = ["Derivation", "Quantity", "derive", "fast_cse"]


def fast_cse(exprs):
    """Common-subexpression elimination without canonical reordering (``order="none"``):
    the default ordering costs ~40× more on spatial6's ``H*`` for the same result."""
    return sp.cse(exprs, symbols=sp.numbered_symbols("_t"), order="none")


@dataclass(frozen=True)
class Quantity:
    """One derived matrix, in base-frame form, with how it maps to the world frame."""

    name: str
    expr: sp.Matrix  #: base-frame expression
    row_groups: int  #: leading 3-row groups that rotate with R0
    col_groups: int  #: leading 3-column groups that rotate with R0
    needs_u: bool  #: depends on the velocity u
    doc: str  #: one line, with the paper's equation


def derive(robot, symbols=None) -> "Derivation":
    """The [`Derivation`][spacearm.symbolic.Derivation] of ``robot`` (a [`spacearm.Robot`][spacearm.Robot]). ``symbols``: which
    parameters become symbols (``spacearm.symbolic.parameters``; default none)."""
    return Derivation(robot, symbols)


class Derivation:
    """Closed-form quantities of one model; each is derived on first access and cached."""

    def __init__(self, robot, symbols=None):
        self.robot = robot
        self.description = robot.description
        self.name = self.description.name
        self.timings: Dict[str, float] = {}
        t = time.perf_counter()
        self.params = Parameters(self.description, symbols)
        self.kin = Kinematics(self.params)
        self.timings["kinematics"] = time.perf_counter() - t
        self.n_dof = self.kin.n_dof
        self.q: List[sp.Symbol] = self.kin.q
        self.qd: List[sp.Symbol] = list(sp.symbols(f"qd1:{self.n_dof + 1}", real=True)) if self.n_dof else []
        self.v_b = sp.Matrix(sp.symbols("v_x v_y v_z", real=True))
        self.w_b = sp.Matrix(sp.symbols("omega_x omega_y omega_z", real=True))
        self.u_b = sp.Matrix.vstack(self.v_b, self.w_b, sp.Matrix(self.qd)) if self.n_dof else sp.Matrix.vstack(self.v_b, self.w_b)
        self.points = {p.name: (self.robot.body_index(p.body), p.offset.tolist()) for p in self.description.points}
        self._lambdas: Dict[str, Callable] = {}

    def _timed(self, key: str, fn):
        t = time.perf_counter()
        out = fn()
        self.timings[key] = self.timings.get(key, 0.0) + time.perf_counter() - t
        return out

    # ---- the paper's matrices (base frame) -------------------------------------------------
    @cached_property
    def blocks(self) -> SymbolicInertia:
        """``M, r_0g, H_S, J_TS, H_Sq, H0, H0m, Hm`` (eqs. 27–36)."""
        return self._timed("inertia blocks", lambda: inertia_blocks(self.kin))

    M = property(lambda self: self.blocks.M)
    r_0g = property(lambda self: self.blocks.r_0g)
    H_S = property(lambda self: self.blocks.H_S)
    J_TS = property(lambda self: self.blocks.J_TS)
    H_Sq = property(lambda self: self.blocks.H_Sq)
    H0 = property(lambda self: self.blocks.H0)
    H0m = property(lambda self: self.blocks.H0m)
    Hm = property(lambda self: self.blocks.Hm)

    @cached_property
    def H(self) -> sp.Matrix:
        """``H = [[H0, H0m], [H0mᵀ, Hm]]`` (eq. 36)."""
        return assemble(self.blocks)

    def J_T(self, body) -> sp.Matrix:
        """``J_Ti`` (eq. 20) of a body (name or index)."""
        return translational_jacobian(self.kin, self.robot.body_index(body))

    def J_R(self, body) -> sp.Matrix:
        """``J_Ri`` (eq. 21) of a body (name or index)."""
        return rotational_jacobian(self.kin, self.robot.body_index(body))

    @cached_property
    def schur(self):
        """``S``, ``det S``, ``adj S``, ``S⁻¹`` and ``H0⁻¹`` (eqs. 52–61)."""
        from .schur import schur_inverse

        return self._timed("H0 inverse (Schur)", lambda: schur_inverse(self.blocks))

    @property
    def H0_inv(self) -> sp.Matrix:
        return self.schur.H0_inv

    @cached_property
    def H_star(self) -> sp.Matrix:
        """``H*`` (eq. 45)."""
        return self._timed("H*", lambda: generalized_inertia(self.blocks, self.schur))

    def J_star(self, point=None) -> sp.Matrix:
        """``J*`` (eq. 110) of a point: a point name (default: the end effector) or ``(body, offset)``."""
        body, off = self._point(point)
        J0, Jm = point_jacobians(self.kin, body, off)
        return generalized_jacobian(self.blocks, self.schur, self.kin.point(body, off), Jm)

    def point_jacobians(self, point=None):
        """``(J_0X, J_mX)`` (eqs. 104–108) of a point."""
        body, off = self._point(point)
        return point_jacobians(self.kin, body, off)

    def _point(self, point):
        if point is None:
            point = self.description.end_effector
            if point is None:
                raise NotFoundError("the model has no end effector; pass a point name or (body, offset)")
        if isinstance(point, str):
            if point in self.points:
                return self.points[point]
            return self.robot.body_index(point), [0.0, 0.0, 0.0]
        body, off = point
        return self.robot.body_index(body), list(off)

    # ---- derivatives ------------------------------------------------------------------------
    @cached_property
    def dH_dq(self) -> List[sp.Matrix]:
        """``[∂H/∂q_1, …, ∂H/∂q_N]`` (base frame; the blocks are ``∂H0/∂q_k`` etc.)."""
        return self._timed("dH/dq", lambda: [partial(self.H, qk) for qk in self.q])

    @cached_property
    def H_dot(self) -> sp.Matrix:
        """``Ḣ`` (base-frame form; blocks ``Ḣ0``, ``Ḣ0m``, ``Ḣm``) as a function of ``q``, ``q̇``, ``ω_b``."""
        return self._timed("H dot", lambda: time_derivative(self.H, self.dH_dq, self.qd, self.w_b, 2, 2))

    def partial_block(self, block: str, k: int) -> sp.Matrix:
        """``∂X/∂q_k`` for ``X`` in ``H0``, ``H0m``, ``Hm`` (``k`` from 1)."""
        return self._slice(self.dH_dq[k - 1], block)

    def dot_block(self, block: str) -> sp.Matrix:
        """``Ẋ`` for ``X`` in ``H0``, ``H0m``, ``Hm`` (base-frame form)."""
        return self._slice(self.H_dot, block)

    @staticmethod
    def _slice(X: sp.Matrix, block: str) -> sp.Matrix:
        return {"H0": X[0:6, 0:6], "H0m": X[0:6, 6:], "Hm": X[6:, 6:]}[block]

    # ---- velocity terms -------------------------------------------------------------------
    @cached_property
    def c(self) -> sp.Matrix:
        """Bias ``c`` (base-frame form, a function of ``q`` and ``u_b``) from ``Ḣ`` and ``∂H/∂q``
        with the quasi-coordinate correction (``spacearm.symbolic.bias``)."""
        return self._timed("c", lambda: bias_from_lagrangian(self.H, self.dH_dq, self.u_b))

    @cached_property
    def c_star(self) -> sp.Matrix:
        """``c* = c_m − H0mᵀ H0⁻¹ c0`` (N)."""
        return self._timed("c*", lambda: generalized_bias(self.blocks, self.schur, self.c))

    # ---- catalogue, world form, evaluation ------------------------------------------------
    def _catalogue(self):
        """``(group, name, thunk)`` for every quantity; the thunk derives it on demand."""
        Q = Quantity
        b = lambda: self.blocks  # noqa: E731
        cat = [
            ("blocks", "r_0g", lambda: Q("r_0g", b().r_0g, 1, 0, False, "base CM to system CM r_0g")),
            ("blocks", "H_S", lambda: Q("H_S", b().H_S, 1, 1, False, "H_S, eq. 29")),
            ("blocks", "J_TS", lambda: Q("J_TS", b().J_TS, 1, 0, False, "J_TS, eq. 32")),
            ("blocks", "H_Sq", lambda: Q("H_Sq", b().H_Sq, 1, 0, False, "H_Sq, eq. 33")),
            ("blocks", "H0", lambda: Q("H0", b().H0, 2, 2, False, "base inertia H0, eq. 30")),
            ("blocks", "H0m", lambda: Q("H0m", b().H0m, 2, 0, False, "coupling inertia H0m, eq. 31")),
            ("blocks", "Hm", lambda: Q("Hm", b().Hm, 0, 0, False, "manipulator inertia Hm, eq. 34")),
            ("blocks", "H", lambda: Q("H", self.H, 2, 2, False, "mass matrix H, eq. 36")),
        ]
        for i, name in enumerate(self.robot.body_names[1:], start=1):
            cat.append(("jacobians", f"J_T_{name}", lambda i=i, name=name: Q(f"J_T_{name}", translational_jacobian(self.kin, i), 1, 0, False, f"J_T of body {name}, eq. 20")))
            cat.append(("jacobians", f"J_R_{name}", lambda i=i, name=name: Q(f"J_R_{name}", rotational_jacobian(self.kin, i), 1, 0, False, f"J_R of body {name}, eq. 21")))
        cat.append(("H0_inv", "H0_inv", lambda: Q("H0_inv", self.H0_inv, 2, 2, False, "closed-form H0 inverse, eqs. 52-61")))
        if self.n_dof:
            cat.append(("H_star", "H_star", lambda: Q("H_star", self.H_star, 0, 0, False, "generalized inertia H*, eq. 45")))
            for name in self.points:
                cat.append(("J_star", f"J_star_{name}", lambda name=name: Q(f"J_star_{name}", self.J_star(name), 2, 0, False, f"generalized Jacobian J* of point {name}, eq. 110")))
            for k in range(self.n_dof):
                cat.append(("dH_dq", f"dH_dq{k + 1}", lambda k=k: Q(f"dH_dq{k + 1}", self.dH_dq[k], 2, 2, False, f"dH/dq{k + 1} (blocks dH0, dH0m, dHm)")))
            cat.append(("H_dot", "H_dot", lambda: Q("H_dot", self.H_dot, 2, 2, True, "time derivative of H (blocks H0dot, H0mdot, Hmdot)")))
        cat.append(("c", "c", lambda: Q("c", self.c, 2, 0, True, "bias c(x, u) from the Lagrangian (Hdot, dH/dq, quasi-coordinate term)")))
        if self.n_dof:
            cat.append(("c_star", "c_star", lambda: Q("c_star", self.c_star, 0, 0, True, "generalized bias c* = c_m - H0m^T H0^-1 c0")))
        return cat

    #: The groups of [`quantities`][spacearm.symbolic.Derivation.quantities].
    GROUPS = ("blocks", "jacobians", "H0_inv", "H_star", "J_star", "dH_dq", "H_dot", "c", "c_star")

    def quantities(self, include=None) -> List[Quantity]:
        """The quantities the code generators emit. ``include``: groups or names to keep
        (default everything); groups are [`GROUPS`][spacearm.symbolic.derivation.Derivation.GROUPS]."""
        want = None if include is None else set(include)
        if want is not None:
            known = set(self.GROUPS) | {n for _, n, _ in self._catalogue()}
            if want - known:
                raise NotFoundError(f"unknown quantities {sorted(want - known)}; groups are {', '.join(self.GROUPS)}")
        return [f() for g, n, f in self._catalogue() if want is None or g in want or n in want]

    def quantity(self, name: str) -> Quantity:
        """One quantity of [`quantities`][spacearm.symbolic.Derivation.quantities] by name."""
        for _, n, f in self._catalogue():
            if n == name:
                return f()
        raise NotFoundError(f"no quantity named {name!r}")

    def world(self, expr: sp.Matrix, row_groups: int, col_groups: int, attitude: str = "quaternion") -> sp.Matrix:
        """World form ``Tr X Tcᵀ`` of a base-frame expression, with ``R0`` as nine DCM symbols
        (``attitude="dcm"``) or from the quaternion ``[eta0_x, eta0_y, eta0_z, eta0_w]``."""
        R0 = dcm_symbols() if attitude == "dcm" else quaternion_dcm(quaternion_symbols())
        X = sp.Matrix(expr)
        for g in range(row_groups):
            X[3 * g:3 * g + 3, :] = R0 * X[3 * g:3 * g + 3, :]
        for g in range(col_groups):
            X[:, 3 * g:3 * g + 3] = X[:, 3 * g:3 * g + 3] * R0.T
        return X

    def _lambda(self, qs) -> Callable:
        """A numeric function ``f(q, u_b, p)`` returning the flattened base-frame values of the
        quantities ``qs``, reduced together by one CSE and printed by SymPy's NumPy printer
        (``sympy.lambdify`` walks the expression as a tree without sharing before any CSE,
        which takes minutes for spatial6's ``H*``)."""
        key = tuple(q.name for q in qs)
        f = self._lambdas.get(key)
        if f is None:
            from sympy.printing.numpy import NumPyPrinter

            pr = NumPyPrinter({"fully_qualified_modules": True})
            flat = [e for q in qs for e in q.expr]
            reps, red = fast_cse(flat)
            lines = ["def f(q, ub, p):"]
            for syms, vec in ((self.q, "q"), (list(self.u_b), "ub"), (self.params.symbols, "p")):
                if syms:
                    lines.append(f"    {', '.join(str(s) for s in syms)}, = {vec}")
            lines += [f"    {s} = {pr.doprint(e)}" for s, e in reps]
            lines.append(f"    out = numpy.empty({len(flat)})")
            lines += [f"    out[{i}] = {pr.doprint(e)}" for i, e in enumerate(red)]
            lines.append("    return out")
            namespace = {"numpy": np}
            exec(compile("\n".join(lines), f"<spacearm.symbolic {self.name} {' '.join(key)}>", "exec"), namespace)
            f = self._lambdas[key] = namespace["f"]
        return f

    def evaluate(self, quantity, x, u=None, p=None) -> np.ndarray:
        """Numeric value at the world state ``(x, u)`` (and parameters ``p``, default the
        model's) of a [`Quantity`][spacearm.symbolic.Quantity] or a quantity name from [`quantities`][spacearm.symbolic.Derivation.quantities]. Column
        quantities (``c``, ``c_star``, ``r_0g``) come back as 1-D arrays."""
        return self.evaluate_many([quantity], x, u, p)[0]

    def evaluate_many(self, quantities, x, u=None, p=None) -> List[np.ndarray]:
        """[`evaluate`][spacearm.symbolic.Derivation.evaluate] for several quantities at once, sharing one CSE (much cheaper than
        one call each, since ``H*``, ``J*``, ``H0⁻¹`` share most of their subexpressions)."""
        qs = [self.quantity(q) if isinstance(q, str) else q for q in quantities]
        x = np.asarray(x, dtype=float)
        R0 = quat_to_dcm(x[3:7])
        ub = np.zeros(6 + self.n_dof) if u is None else to_base_velocity(u, R0)
        pv = self.params.defaults if p is None else list(p)
        flat = np.asarray(self._lambda(qs)(x[7:], ub, pv), dtype=float)
        out, at = [], 0
        for q in qs:
            rows, cols = q.expr.shape
            val = rotate(flat[at:at + rows * cols].reshape(rows, cols), R0, q.row_groups, q.col_groups)
            at += rows * cols
            out.append(val[:, 0] if cols == 1 else val)
        return out
