"""Exact derivatives against independent references.

The core computes every derivative by dual numbers through the same algorithms; the references
here are independent of that:

- central finite differences (step 1e-6) of the ``f64`` quantities, with the attitude perturbed
  on the manifold by the exponential map (built here from rotation matrices, not with the
  package's tangent helpers): relative error ≤ 1e-6 on random trees with N ≤ 12 (branches at
  the base and mid-chain, prismatic and fixed joints) and on the conftest branched tree;
- SymPy (:mod:`spacearm.symbolic`): ``∂H/∂q_k`` and ``Ḣ`` on planar4 and a random N = 3 model,
  and ``∂H*/∂q_k``, ``∂J*/∂q_k`` differentiated symbolically here on planar4 (1e-10);
- closed forms: the attitude slices ``∂H/∂θ_i = Ω_i H − H Ω_i`` and
  ``∂J*/∂θ_i = blkdiag(ẽ_i, ẽ_i) J*``;
- Pinocchio's ``computeABADerivatives`` mapped to spacearm's conventions by the chain rule of
  the state, force and acceleration maps of :mod:`spacearm.interop` (1e-9);
- the nonlinear simulation: one RK4 step forward and one backward of a perturbed and a nominal
  trajectory, whose central difference in time must equal ``A δz + B δf``.

Every comparison asserts the reference is non-negligible (``assert_rel_close``).
"""

from __future__ import annotations

import functools

import numpy as np
import pytest

import spacearm
from spacearm.rotations import quat_from_matrix, quat_to_matrix
from conftest import branched_tree
from random_models import assert_rel_close, random_model, random_state

H_STEP = 1e-6
RTOL_FD = 1e-6

#: Random models covering the tree features (N = 3, 7, 10, 12, 11, 1, 12; branches at the base
#: and mid-chain, prismatic joints, fixed links with children).
FD_SEEDS = [0, 2, 6, 14, 22, 28, 29]
FD_CASES = [f"seed{s}" for s in FD_SEEDS] + ["branched", "spatial6"]


def robot_of(name: str) -> spacearm.Robot:
    if name.startswith("seed"):
        return random_model(int(name[4:])).robot
    if name == "branched":
        return branched_tree()
    return spacearm.presets.get(name)


@functools.lru_cache(maxsize=None)
def case(name: str):
    """A robot, a random state with the base near the origin of 𝒥 (finite differences of
    quantities computed relative to a base kilometres away lose digits to rounding: see
    :func:`test_derivatives_do_not_depend_on_the_base_position` for far bases) and a random
    generalized force (with a base wrench)."""
    robot = robot_of(name)
    rng = np.random.default_rng([11, sum(map(ord, name))])
    x, u = random_state(robot, rng)
    x[:3] = rng.uniform(-2.0, 2.0, size=3)
    f = np.concatenate([rng.normal(scale=20.0, size=3), rng.normal(scale=5.0, size=3), rng.normal(scale=5.0, size=robot.n_dof)])
    return robot, x, u, f


def test_cases_cover_the_tree_features():
    feats = [random_model(s).features for s in FD_SEEDS]
    for key in ("base_branch", "mid_chain_branch", "prismatic", "fixed_with_children"):
        assert any(f[key] for f in feats), key
    assert max(random_model(s).robot.n_dof for s in FD_SEEDS) == 12


# ---------------------------------------------------------------------------------------------
# tangent perturbations, built independently of spacearm.model.tangent
# ---------------------------------------------------------------------------------------------
def _rotvec_matrix(w) -> np.ndarray:
    """exp(w̃) by Rodrigues' formula."""
    w = np.asarray(w, dtype=float)
    angle = np.linalg.norm(w)
    if angle == 0.0:
        return np.eye(3)
    k = w / angle
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def perturb(x, k: int, h: float) -> np.ndarray:
    """``x ⊕ h e_k`` in the tangent coordinates [δr0, δθ (world, left), δq]."""
    y = np.array(x, dtype=float)
    if k < 3:
        y[k] += h
    elif k < 6:
        w = np.zeros(3)
        w[k - 3] = h
        y[3:7] = quat_from_matrix(_rotvec_matrix(w) @ quat_to_matrix(x[3:7]))
    else:
        y[7 + k - 6] += h
    return y


def tangent_fd(fun, x, nu: int, h: float = H_STEP) -> np.ndarray:
    """Central differences of ``fun(x)`` along every tangent coordinate, stacked LAST."""
    return np.stack([(fun(perturb(x, k, h)) - fun(perturb(x, k, -h))) / (2 * h) for k in range(nu)], axis=-1)


def test_configuration_plus_and_difference():
    robot, x, _, _ = case("seed2")
    rng = np.random.default_rng(3)
    dx = rng.normal(scale=0.3, size=robot.nu)
    y = robot.configuration_plus(x, dx)
    # Independent construction: rotation matrices.
    R = _rotvec_matrix(dx[3:6]) @ quat_to_matrix(x[3:7])
    assert np.allclose(quat_to_matrix(y[3:7]), R, atol=1e-14)
    assert np.allclose(y[:3], x[:3] + dx[:3]) and np.allclose(y[7:], x[7:] + dx[6:])
    assert_rel_close(robot.configuration_difference(y, x), dx, "configuration_difference", rtol=1e-12)
    with pytest.raises(spacearm.ShapeError):
        robot.configuration_plus(x, dx[1:])
    with pytest.raises(spacearm.NonFiniteError):
        robot.configuration_plus(x, np.full(robot.nu, np.nan))
    # finite inputs whose sum overflows: an error naming the components, not a silent inf/NaN (issue 26)
    huge_x, huge_dx = x.copy(), np.zeros(robot.nu)
    huge_x[0], huge_dx[0], huge_dx[-1] = 1.5e308, 1.5e308, 1.7e308
    huge_x[-1] = 1.7e308
    with pytest.raises(spacearm.NonFiniteError, match=r"overflows: components \[0, %d\]" % (robot.nu)):
        robot.configuration_plus(huge_x, huge_dx)
    # a finite attitude increment whose norm (the angle) overflows: named, not "a must be finite, got [nan ...]"
    huge_turn = np.zeros(robot.nu)
    huge_turn[3:6] = 1e200
    with pytest.raises(spacearm.NonFiniteError, match=r"dx\[3:6\] \(the attitude increment\) = .*rotation angle, overflows"):
        robot.configuration_plus(x, huge_turn)
    with pytest.raises(spacearm.NonFiniteError, match=r"theta = .*rotation angle, overflows"):
        spacearm.rotations.quat_exp([1e308, 0.0, 1e308])
    huge_turn[3:6] = 1e150  # large but finite: a unit quaternion
    assert np.isclose(np.linalg.norm(robot.configuration_plus(x, huge_turn)[3:7]), 1.0)
    bad = x.copy()
    bad[3:7] *= 1.1
    with pytest.raises(spacearm.QuaternionError):
        robot.configuration_difference(bad, x)


# ---------------------------------------------------------------------------------------------
# finite differences
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", FD_CASES)
def test_mass_matrix_partials_and_derivative(name):
    robot, x, u, _ = case(name)
    dH = robot.mass_matrix_partials(x)
    assert dH.shape == (robot.nu,) * 3
    fd = tangent_fd(robot.mass_matrix, x, robot.nu)
    assert_rel_close(dH, fd, "dH/dx vs central differences", rtol=RTOL_FD)
    assert np.all(dH[:, :, :3] == 0.0)
    assert np.linalg.norm(fd[:, :, :3]) <= 1e-6 * np.linalg.norm(fd)
    # Hdot = Σ_k ∂H/∂x_k u_k (u is the tangent velocity of x); and Hdot is symmetric.
    hdot = robot.mass_matrix_derivative(x, u)
    assert_rel_close(hdot, dH @ u, "Hdot vs sum of partials", rtol=1e-12)
    assert np.array_equal(hdot, hdot.T)


@pytest.mark.parametrize("name", FD_CASES)
def test_generalized_inertia_partials_and_derivative(name):
    robot, x, u, _ = case(name)
    n = robot.n_dof
    dHs = robot.generalized_inertia_partials(x)
    assert dHs.shape == (n, n, n)
    fd = tangent_fd(robot.generalized_inertia, x, robot.nu)
    assert_rel_close(dHs, fd[:, :, 6:], "dH*/dq vs central differences", rtol=RTOL_FD)
    # H* does not depend on the base pose.
    assert np.linalg.norm(fd[:, :, :6]) <= 1e-6 * np.linalg.norm(fd)
    assert_rel_close(robot.generalized_inertia_derivative(x, u), dHs @ u[6:], "H*dot vs sum of partials", rtol=1e-12)


@pytest.mark.parametrize("name", FD_CASES)
def test_generalized_jacobian_partials_and_derivative(name):
    robot, x, u, _ = case(name)
    point = "tip" if "tip" in robot.point_names else robot.end_effector
    dJ = robot.generalized_jacobian_partials(x, point)
    assert dJ.shape == (6, robot.n_dof, robot.nu)
    fd = tangent_fd(lambda y: robot.generalized_jacobian(y, point), x, robot.nu)
    assert_rel_close(dJ, fd, "dJ*/dx vs central differences", rtol=RTOL_FD)
    assert np.all(dJ[:, :, :3] == 0.0)
    assert_rel_close(robot.generalized_jacobian_derivative(x, u, point), dJ @ u, "J*dot vs sum of partials", rtol=1e-12)


@pytest.mark.parametrize("name", FD_CASES)
def test_forward_dynamics_derivatives(name):
    robot, x, u, f = case(name)
    nu = robot.nu
    d = robot.forward_dynamics_derivatives(x, u, f)
    fd_x = tangent_fd(lambda y: robot.forward_dynamics(y, u, f), x, nu)
    eye = np.eye(nu)
    fd_u = np.stack([(robot.forward_dynamics(x, u + H_STEP * e, f) - robot.forward_dynamics(x, u - H_STEP * e, f)) / (2 * H_STEP) for e in eye], axis=-1)
    fd_f = np.stack([(robot.forward_dynamics(x, u, f + H_STEP * e) - robot.forward_dynamics(x, u, f - H_STEP * e)) / (2 * H_STEP) for e in eye], axis=-1)
    assert_rel_close(d.ddu_dx, fd_x, "d(du)/dx vs central differences", rtol=RTOL_FD)
    assert_rel_close(d.ddu_du, fd_u, "d(du)/du vs central differences", rtol=RTOL_FD)
    assert_rel_close(d.ddu_df, fd_f, "d(du)/df vs central differences", rtol=RTOL_FD)
    assert np.all(d.ddu_dx[:, :3] == 0.0)
    # ∂u̇/∂f is the inverse of the mass matrix.
    assert_rel_close(d.ddu_df @ robot.mass_matrix(x), eye, "H^-1 H", rtol=1e-10)
    # The tau/base_wrench form gives the same.
    d2 = robot.forward_dynamics_derivatives(x, u, tau=f[6:], base_wrench=f[:6])
    assert np.array_equal(d2.ddu_dx, d.ddu_dx)


@pytest.mark.parametrize("name", ["seed14", "branched", "spatial6"])
def test_forward_dynamics_derivatives_tau_form_is_the_f_form_bit_for_bit(name):
    """The tau/base_wrench form (one native call that assembles f) returns exactly the arrays of
    the f form, with and without a base wrench, for one state and for a batch (either part one
    row for all), on both routes and with external wrenches; bad parts are refused under their
    own names."""
    robot, x, u, f = case(name)
    n = robot.n_dof
    tau, fb = f[6:].copy(), f[:6].copy()
    assert np.any(fb != 0) and np.any(tau != 0)

    def same(a, b):
        assert all(np.array_equal(p, q) for p, q in zip(a, b))
        assert any(np.any(p != 0) for p in a)

    same(robot.forward_dynamics_derivatives(x, u, tau=tau, base_wrench=fb), robot.forward_dynamics_derivatives(x, u, f))
    free = np.concatenate([np.zeros(6), tau])
    same(robot.forward_dynamics_derivatives(x, u, tau=tau), robot.forward_dynamics_derivatives(x, u, free))
    same(robot.forward_dynamics_derivatives(x, u, base_wrench=fb), robot.forward_dynamics_derivatives(x, u, np.concatenate([fb, np.zeros(n)])))
    same(robot.forward_dynamics_derivatives(x, u, tau=list(tau), base_wrench=list(fb)), robot.forward_dynamics_derivatives(x, u, f))
    # The base wrench changes the result (so the equalities above see it).
    assert not np.array_equal(robot.forward_dynamics_derivatives(x, u, f).ddu_dx, robot.forward_dynamics_derivatives(x, u, free).ddu_dx)
    ext = [spacearm.ExternalWrench(robot.n_bodies - 1, force=[1.0, -2.0, 0.5], torque=[0.1, 0.0, -0.3], offset=[0.1, 0.0, 0.0])]
    same(robot.forward_dynamics_derivatives(x, u, tau=tau, base_wrench=fb, wrenches=ext), robot.forward_dynamics_derivatives(x, u, f, wrenches=ext))
    same(robot.forward_dynamics_derivatives(x, u, tau=tau, method="dual"), robot.forward_dynamics_derivatives(x, u, free, method="dual"))
    # A batch: x, u and tau with B rows, the base wrench one row for all, or B rows too.
    rng = np.random.default_rng(5)
    rows = 4
    xs, us = np.tile(x, (rows, 1)), u + 0.1 * rng.normal(size=(rows, robot.nu))
    taus, fbs = tau + rng.normal(size=(rows, n)), fb + rng.normal(size=(rows, 6))
    same(robot.forward_dynamics_derivatives(xs, us, tau=taus, base_wrench=fb),
         robot.forward_dynamics_derivatives(xs, us, np.concatenate([np.tile(fb, (rows, 1)), taus], axis=1)))
    same(robot.forward_dynamics_derivatives(xs, us, tau=taus, base_wrench=fbs),
         robot.forward_dynamics_derivatives(xs, us, np.concatenate([fbs, taus], axis=1)))
    same(robot.forward_dynamics_derivatives(xs, us, tau=tau), robot.forward_dynamics_derivatives(xs, us, free))
    # Refusals name the part at fault, not the assembled f.
    with pytest.raises(spacearm.NonFiniteError, match="^tau must be finite"):
        robot.forward_dynamics_derivatives(x, u, tau=np.full(n, np.nan), base_wrench=fb)
    with pytest.raises(spacearm.NonFiniteError, match="^base_wrench must be finite, but entry 2"):
        robot.forward_dynamics_derivatives(x, u, tau=tau, base_wrench=[0, 0, np.inf, 0, 0, 0])
    bad = taus.copy()
    bad[2, 1] = np.nan
    with pytest.raises(spacearm.NonFiniteError, match="tau must be finite") as info:
        robot.forward_dynamics_derivatives(xs, us, tau=bad)
    assert "row 2" in str(info.value) or "state 2" in str(info.value), str(info.value)
    with pytest.raises(spacearm.ShapeError, match=f"tau must have length {n}, got {n - 1}"):
        robot.forward_dynamics_derivatives(x, u, tau=tau[:-1])
    with pytest.raises(spacearm.ShapeError, match="base_wrench must have length 6, got 5"):
        robot.forward_dynamics_derivatives(x, u, tau=tau, base_wrench=fb[:5])
    with pytest.raises(spacearm.ShapeError, match="tau has 4, base_wrench has 3"):
        robot.forward_dynamics_derivatives(xs, us, tau=taus, base_wrench=fbs[:3])
    with pytest.raises(ValueError, match="either f or tau"):
        robot.forward_dynamics_derivatives(x, u, f, tau=tau)
    with pytest.raises(ValueError, match="either f or tau"):
        robot.forward_dynamics_derivatives(x, u, f, base_wrench=fb, method="dual")
    with pytest.raises(ValueError, match="method must be"):
        robot.forward_dynamics_derivatives(x, u, tau=tau, method="numeric")


@pytest.mark.parametrize("name", ["seed14", "seed28", "branched"])
def test_derivatives_do_not_depend_on_the_base_position(name):
    """Everything is referred to the base CM: moving the base 4 km away changes no derivative
    (the dual parts do not suffer the cancellation in r_i − r0 that finite differences do)."""
    robot, x, u, f = case(name)
    far = x.copy()
    far[:3] = [4000.0, -2500.0, 3000.0]
    pairs = [
        (robot.mass_matrix_partials(far), robot.mass_matrix_partials(x), "dH/dx far vs near"),
        (robot.generalized_inertia_partials(far), robot.generalized_inertia_partials(x), "dH*/dq far vs near"),
        (robot.generalized_jacobian_partials(far), robot.generalized_jacobian_partials(x), "dJ*/dx far vs near"),
    ]
    pairs += [(a, b, f"d(du) far vs near {i}") for i, (a, b) in enumerate(zip(robot.forward_dynamics_derivatives(far, u, f), robot.forward_dynamics_derivatives(x, u, f)))]
    for a, b, what in pairs:
        assert_rel_close(a, b, what, rtol=1e-9)


# ---------------------------------------------------------------------------------------------
# SymPy and closed forms
# ---------------------------------------------------------------------------------------------
#: planar4 and random seed 31 (N = 3, a revolute and a prismatic joint; its SymPy derivation
#: takes seconds, unlike some other N = 3 models whose random rotations make dense expressions).
SYMBOLIC_CASES = ["planar4", "seed31"]


def test_symbolic_random_case_is_n3():
    assert random_model(31).robot.n_dof == 3


@functools.lru_cache(maxsize=None)
def derivation(name):
    from spacearm.symbolic import derive

    return derive(robot_of(name))


@pytest.mark.parametrize("name", SYMBOLIC_CASES)
def test_mass_matrix_derivatives_equal_sympy(name):
    pytest.importorskip("sympy")
    d = derivation(name)
    robot = d.robot
    rng = np.random.default_rng(5)
    for _ in range(2):
        x, u = random_state(robot, rng)
        dH = robot.mass_matrix_partials(x)
        sym = d.evaluate_many([f"dH_dq{k + 1}" for k in range(robot.n_dof)], x)
        for k in range(robot.n_dof):
            if np.linalg.norm(sym[k]) > 1e-8:
                assert_rel_close(dH[:, :, 6 + k], sym[k], "dH/dq vs SymPy", rtol=1e-10)
            else:
                assert np.linalg.norm(dH[:, :, 6 + k]) < 1e-10
        assert_rel_close(robot.mass_matrix_derivative(x, u), d.evaluate("H_dot", x, u), "Hdot vs SymPy", rtol=1e-10)


def _skew(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


@pytest.mark.parametrize("name", ["seed14", "branched"])
def test_attitude_partials_closed_form(name):
    """``H = T H_b Tᵀ`` and ``J* = blkdiag(R0, R0) J*_b`` with ``T = blkdiag(R0, R0, E)``, so
    ``∂/∂θ_i`` (R0 ← exp(θ̃) R0) gives ``Ω_i H − H Ω_i`` and ``blkdiag(ẽ_i, ẽ_i) J*``."""
    robot, x, _, _ = case(name)
    H = robot.mass_matrix(x)
    J = robot.generalized_jacobian(x)
    dH = robot.mass_matrix_partials(x)
    dJ = robot.generalized_jacobian_partials(x)
    for i in range(3):
        e = _skew(np.eye(3)[i])
        om = np.zeros((robot.nu, robot.nu))
        om[:3, :3] = om[3:6, 3:6] = e
        assert_rel_close(dH[:, :, 3 + i], om @ H - H @ om, "dH/dtheta closed form", rtol=1e-12)
        assert_rel_close(dJ[:, :, 3 + i], om[:6, :6] @ J, "dJ*/dtheta closed form", rtol=1e-12)


def test_generalized_partials_equal_sympy():
    """``∂H*/∂q_k`` and ``∂J*/∂q_k`` by symbolic differentiation of the closed-form ``H*`` and
    ``J*`` of :mod:`spacearm.symbolic`, on random seed 28 (one revolute joint and fixed links
    with children; differentiating the reduced matrices of larger models takes SymPy minutes)."""
    sp = pytest.importorskip("sympy")
    from spacearm.symbolic.derivation import Quantity

    d = derivation("seed28")
    robot = d.robot
    hs = d.H_star
    js = d.J_star()
    quantities = [Quantity(f"dHs{k}", hs.diff(q), 0, 0, False, "") for k, q in enumerate(d.q)]
    quantities += [Quantity(f"dJs{k}", js.diff(q), 2, 0, False, "") for k, q in enumerate(d.q)]
    assert isinstance(hs, sp.Matrix)
    rng = np.random.default_rng(9)
    x, _ = random_state(robot, rng)
    # (evaluate returns single-column quantities as 1-D arrays)
    values = [np.reshape(v, q.expr.shape) for v, q in zip(d.evaluate_many(quantities, x), quantities)]
    n = robot.n_dof
    assert_rel_close(robot.generalized_inertia_partials(x), np.stack(values[:n], axis=-1), "dH*/dq vs SymPy", rtol=1e-10)
    assert_rel_close(robot.generalized_jacobian_partials(x)[:, :, 6:], np.stack(values[n:], axis=-1), "dJ*/dq vs SymPy", rtol=1e-10)


# ---------------------------------------------------------------------------------------------
# Pinocchio computeABADerivatives, through the chain rule of the convention maps
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", ["seed2", "seed14", "seed22", "branched", "spatial6"])
def test_forward_dynamics_derivatives_equal_pinocchio(name):
    """Pinocchio: ``a = ABA(q, v, τ_p)`` with ``v = Tᵀ u``, ``τ_p = Tᵀ f`` and
    ``u̇ = T a + [ω0 × v0; 0]``, ``T = blkdiag(R0, R0, P)``; its configuration tangent is the
    local increment ``δ_p = Tᵀ δx``. With ``R0 ← exp(δθ̃) R0``: ``δ(Tᵀ w) = Tᵀ [w̃_lin; w̃_ang; 0] δθ``
    and ``δT a = −[(R0 a_lin)~; (R0 a_ang)~; 0] δθ``, hence

    ``∂u̇/∂x = T (A_q + A_v Tᵀ C(u) + M⁻¹ Tᵀ C(f)) − C(T a)``-wise (``C(w)`` the map
    ``δx ↦ [w̃_lin; w̃_ang; 0] δθ``; :func:`spacearm.interop.aba_derivatives_from_pinocchio`),
    ``∂u̇/∂u = T A_v Tᵀ + ∂(ω0 × v0)/∂u``, ``∂u̇/∂f = T M⁻¹ Tᵀ``.
    """
    pin = pytest.importorskip("pinocchio")
    from spacearm import interop

    robot, x, u, f = case(name)
    nu = robot.nu
    model = interop.to_pinocchio(robot)
    data = model.createData()
    q, v = interop.to_pinocchio_state(robot, x, u)
    tau = interop.to_pinocchio_force(robot, x, f)
    T = interop.pinocchio_transform(robot, x)
    pin.computeABADerivatives(model, data, q, v, tau)
    ref_x, ref_u, ref_f = interop.aba_derivatives_from_pinocchio(robot, x, u, f, data.ddq_dq, data.ddq_dv, data.Minv, data.ddq)
    # The chain rule written out here once more, independently of interop's implementation.
    T = interop.pinocchio_transform(robot, x)
    minv = np.triu(data.Minv) + np.triu(data.Minv, 1).T

    def cross_columns(w):
        """Columns 3:6 of δx ↦ [w_lin × δθ; w_ang × δθ; 0]."""
        out = np.zeros((nu, nu))
        out[0:3, 3:6] = _skew(w[0:3])
        out[3:6, 3:6] = _skew(w[3:6])
        return out

    Ta = T @ np.array(data.ddq)
    manual = T @ (data.ddq_dq @ T.T + data.ddq_dv @ T.T @ cross_columns(u) + minv @ T.T @ cross_columns(f)) - cross_columns(Ta)
    assert_rel_close(ref_x, manual, "interop chain rule vs written out", rtol=1e-13)
    d = robot.forward_dynamics_derivatives(x, u, f)
    assert_rel_close(d.ddu_dx, ref_x, "d(du)/dx vs pinocchio", rtol=1e-9)
    assert_rel_close(d.ddu_du, ref_u, "d(du)/du vs pinocchio", rtol=1e-9)
    assert_rel_close(d.ddu_df, ref_f, "d(du)/df vs pinocchio", rtol=1e-9)


# ---------------------------------------------------------------------------------------------
# the linearization against the nonlinear simulation
# ---------------------------------------------------------------------------------------------
def _rk4(robot, x, u, f, h):
    """One RK4 step of ``ẋ = u`` (tangent), ``u̇ = FD(x, u, f)``, stages on the manifold."""

    def deriv(xs, us):
        return us, robot.forward_dynamics(xs, us, f)

    k1x, k1u = deriv(x, u)
    k2x, k2u = deriv(perturb_vec(x, 0.5 * h * k1x), u + 0.5 * h * k1u)
    k3x, k3u = deriv(perturb_vec(x, 0.5 * h * k2x), u + 0.5 * h * k2u)
    k4x, k4u = deriv(perturb_vec(x, h * k3x), u + h * k3u)
    return perturb_vec(x, h * (k1x + 2 * k2x + 2 * k3x + k4x) / 6), u + h * (k1u + 2 * k2u + 2 * k3u + k4u) / 6


def perturb_vec(x, dx) -> np.ndarray:
    """``x ⊕ dx`` (whole tangent vector), built from rotation matrices."""
    y = np.array(x, dtype=float)
    y[:3] += dx[:3]
    y[3:7] = quat_from_matrix(_rotvec_matrix(dx[3:6]) @ quat_to_matrix(x[3:7]))
    y[7:] += dx[6:]
    return y


def _log_diff(x1, x0):
    """Tangent difference ``x1 ⊖ x0`` from rotation matrices (small angles)."""
    R = quat_to_matrix(x1[3:7]) @ quat_to_matrix(x0[3:7]).T
    angle = np.arccos(np.clip((np.trace(R) - 1) / 2, -1, 1))
    w = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    w = w * (0.5 if angle < 1e-12 else angle / (2 * np.sin(angle)))
    return np.concatenate([x1[:3] - x0[:3], w, x1[7:] - x0[7:]])


@pytest.mark.parametrize("name", ["seed14", "branched", "spatial6"])
@pytest.mark.parametrize("inputs", ["joints", "all"])
def test_linearization_reproduces_the_simulation(name, inputs):
    robot, x, u, f = case(name)
    x = x.copy()
    x[:3] = [0.3, -0.2, 0.1]  # near the origin: the differences below are ~1e-9
    nu = robot.nu
    A, B = robot.linearize(x, u, f, inputs=inputs)
    assert A.shape == (2 * nu, 2 * nu) and B.shape == (2 * nu, robot.n_dof if inputs == "joints" else nu)
    rng = np.random.default_rng(2)
    eps, h = 1e-6, 2e-4
    dz = eps * rng.normal(size=2 * nu)
    dtau = eps * rng.normal(size=B.shape[1]) * 10
    df = np.zeros(nu)
    df[nu - B.shape[1]:] = dtau
    xp, up = perturb_vec(x, dz[:nu]), u + dz[nu:]
    steps = {}
    for s in (h, -h):
        xn, un = _rk4(robot, x, u, f, s)
        xq, uq = _rk4(robot, xp, up, f + df, s)
        steps[s] = np.concatenate([_log_diff(xq, xn), uq - un])
    # Central difference in time of the perturbation: its rate at t = 0, O(h²) + O(eps).
    rate = (steps[h] - steps[-h]) / (2 * h)
    predicted = A @ dz + B @ dtau
    # Configuration rows (δẋ = Ω δx + δu) and velocity rows (δu̇) separately.
    assert_rel_close(rate[:nu], predicted[:nu], "linearization vs RK4 simulation, configuration rows", rtol=1e-4, min_norm=1e-7)
    assert_rel_close(rate[nu:], predicted[nu:], "linearization vs RK4 simulation, velocity rows", rtol=1e-4, min_norm=1e-7)
    # The test can fail: without the attitude term Ω (δθ̇ = δω0 + ω0 × δθ) the attitude rows
    # are wrong by the size of ω0 × δθ.
    A_wrong = A.copy()
    A_wrong[3:6, 3:6] = 0.0
    wrong = A_wrong @ dz + B @ dtau
    assert np.linalg.norm(wrong[3:6] - rate[3:6]) > 0.05 * np.linalg.norm(rate[3:6])


# ---------------------------------------------------------------------------------------------
# bad input
# ---------------------------------------------------------------------------------------------
def test_bad_input_raises_spacearm_errors():
    robot, x, u, f = case("spatial6")
    with pytest.raises(spacearm.ShapeError, match="x must have length"):
        robot.mass_matrix_partials(x[:-1])
    with pytest.raises(spacearm.ShapeError, match="u must have length"):
        robot.mass_matrix_derivative(x, u[:-1])
    with pytest.raises(spacearm.NonFiniteError):
        robot.forward_dynamics_derivatives(x, u, np.full(robot.nu, np.nan))
    bad = x.copy()
    bad[3:7] = [0, 0, 0, 2.0]
    with pytest.raises(spacearm.QuaternionError):
        robot.generalized_inertia_partials(bad)
    with pytest.raises(spacearm.NotFoundError):
        robot.generalized_jacobian_partials(x, "no_such_point")
    with pytest.raises(ValueError, match="inputs must be"):
        robot.linearize(x, u, f, inputs="base")
    with pytest.raises(ValueError, match="either f or tau"):
        robot.linearize(x, u, f, tau=f[6:])
    with pytest.raises(spacearm.ShapeError):
        robot.linearize(x, u, tau=f[:3])
