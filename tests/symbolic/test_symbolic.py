"""spacearm.symbolic: the closed-form matrices against the Rust core.

Every symbolic quantity is evaluated at random world states and compared to an independent
numeric computation of the core (paper-form Jacobian sums, CRBA, RNEA, the Schur inverse):
relative error ≤ 1e-12 on planar4, spatial6 and random models with N ≤ 4. Derivations are
cached per model for the session; the heavy ones (dH/dq, c) run on small models only.
"""

import numpy as np
import pytest

sp = pytest.importorskip("sympy")

import spacearm  # noqa: E402
from spacearm.rotations import quat_from_matrix  # noqa: E402
from spacearm.symbolic import derive  # noqa: E402

from random_models import random_model, random_state  # noqa: E402

RTOL = 1e-12
_CACHE = {}


def small_seeds(max_dof, count, max_bodies=99):
    """The first ``count`` seeds of random models with N <= max_dof (and few bodies: random
    rotations make dense expressions, and lambdify's CSE grows quickly with them)."""
    out = []
    for seed in range(200):
        r = random_model(seed).robot
        if r.n_dof <= max_dof and r.n_bodies <= max_bodies:
            out.append(seed)
            if len(out) == count:
                return out
    return out


#: Random models for the configuration quantities: N <= 4 with few bodies (random rotations make
#: dense expressions and lambdify's CSE grows quickly with them). At this writing: seed 25 (a
#: 3-dof tree) and seed 93 (4 dof).
RANDOM4 = small_seeds(4, 1, 4) + [s for s in range(200) if random_model(s).robot.n_dof == 4 and random_model(s).robot.n_bodies <= 5][:1]
#: Smaller random models for the velocity terms (dH/dq, c) and code generation.
RANDOM3 = small_seeds(3, 1, 4) + small_seeds(1, 1, 4)


def model(name):
    if name.startswith("random"):
        return random_model(int(name[6:])).robot
    return spacearm.presets.get(name)


def derivation(name, symbols=None):
    key = (name, symbols)
    if key not in _CACHE:
        _CACHE[key] = derive(model(name), symbols)
    return _CACHE[key]


def rel_close(actual, reference, what, rtol=RTOL):
    a = np.asarray(actual, dtype=float)
    b = np.asarray(reference, dtype=float)
    assert a.shape == b.shape, f"{what}: shape {a.shape} != {b.shape}"
    nb = np.linalg.norm(b)
    err = np.linalg.norm(a - b) / nb if nb > 0 else np.linalg.norm(a)
    assert err <= rtol, f"{what}: relative error {err:.3e} > {rtol:.0e}"
    return err


def states(robot, n=3, seed=0):
    rng = np.random.default_rng(seed)
    return [random_state(robot, rng) for _ in range(n)]


#: One random model (the 4-dof one) for the configuration quantities: the 3-dof one's H0⁻¹, H* and
#: J* cost CI 40 s more and add no structure the 4-dof tree lacks; its H, Jacobians, velocity terms
#: and generated code are still checked (below and in test_symbolic_codegen.py).
CONFIG_MODELS = ["planar4", "spatial6"] + [f"random{s}" for s in RANDOM4[1:]]


def r0g_tolerance(x):
    """The core computes r_0g as r_g − r0, which loses the digits of |r0| (up to 5 km in the
    random states); the symbolic r_0g = Σ m_i r_0i / M does not. Scale the tolerance."""
    return RTOL * max(1.0, float(np.linalg.norm(x[0:3])))


@pytest.mark.parametrize("name", CONFIG_MODELS)
def test_inertia_matrices_equal_core(name):
    d = derivation(name)
    robot = d.robot
    names = ["r_0g", "H_S", "J_TS", "H_Sq", "H0", "H0m", "Hm", "H", "H0_inv", "H_star"] + [f"J_star_{p}" for p in d.points]
    for x, _ in states(robot):
        val = dict(zip(names, d.evaluate_many(names, x)))
        b = robot.inertia_blocks(x)
        rel_close(val["r_0g"], b.r_0g, f"{name} r_0g", rtol=r0g_tolerance(x))
        for q in ("H_S", "J_TS", "H_Sq", "H0", "H0m", "Hm"):
            rel_close(val[q], getattr(b, q), f"{name} {q}")
        rel_close(val["H"], robot.mass_matrix(x, method="crba"), f"{name} H vs CRBA")
        rel_close(val["H0_inv"], robot.base_inertia_inverse(x), f"{name} H0^-1")
        rel_close(val["H_star"], robot.generalized_inertia(x), f"{name} H*")
        for point in d.points:
            rel_close(val[f"J_star_{point}"], robot.generalized_jacobian(x, point), f"{name} J* {point}")


@pytest.mark.parametrize("name", ["planar4", f"random{RANDOM4[0]}"])
def test_link_and_point_jacobians_equal_core(name):
    d = derivation(name)
    robot = d.robot
    for x, _ in states(robot, 2, seed=1):
        for i, body in enumerate(robot.body_names[1:], start=1):
            JT, JR = robot.link_jacobians(x, i)
            rel_close(d.evaluate(f"J_T_{body}", x), JT, f"{name} J_T{i}")
            rel_close(d.evaluate(f"J_R_{body}", x), JR, f"{name} J_R{i}")


def test_world_forms_dcm_and_quaternion():
    d = derivation("planar4")
    robot = d.robot
    x, _ = states(robot, 1, seed=2)[0]
    from spacearm.symbolic.kinematics import dcm_symbols, quaternion_symbols

    R0 = spacearm.rotations.quat_to_matrix(x[3:7])
    qsub = dict(zip(d.q, x[7:]))
    Hq = d.world(d.H0, 2, 2, attitude="quaternion").xreplace({**qsub, **dict(zip(quaternion_symbols(), x[3:7]))})
    Hd = d.world(d.H0, 2, 2, attitude="dcm").xreplace({**qsub, **dict(zip(dcm_symbols(), R0.ravel()))})
    ref = robot.inertia_blocks(x).H0
    rel_close(np.array(Hq.evalf(), dtype=float), ref, "H0 quaternion form")
    rel_close(np.array(Hd.evalf(), dtype=float), ref, "H0 DCM form")
    r0, _, R, r, p, k = d.kin.world("quaternion")
    sub = {**qsub, **dict(zip(quaternion_symbols(), x[3:7])), **dict(zip(r0, x[0:3]))}
    fk = robot.forward_kinematics(x)
    for i in range(robot.n_bodies):
        rel_close(np.array(r[i].xreplace(sub).evalf(), dtype=float)[:, 0], fk.com_in_world[i], f"r_{i}")
        rel_close(np.array(R[i].xreplace(sub).evalf(), dtype=float), fk.body_to_world[i], f"R_{i}")


def test_symbolic_parameters_evaluate_to_the_model():
    d = derivation("planar4", "all")
    assert "m1" in d.params.names and "I1_zz" in d.params.names and "c1_x" in d.params.names
    assert d.Hm.free_symbols & set(d.params.symbols)
    robot = d.robot
    for x, _ in states(robot, 2, seed=3):
        rel_close(d.evaluate("H_star", x), robot.generalized_inertia(x), "H* with symbolic parameters")
    # Changing a parameter changes the result like rebuilding the model would: doubling every
    # mass and inertia doubles H*.
    p = np.array(d.params.defaults)
    scale = np.array([2.0 if n[0] in "mI" else 1.0 for n in d.params.names])
    x, _ = states(robot, 1, seed=4)[0]
    rel_close(d.evaluate("H_star", x, p=p * scale), 2 * robot.generalized_inertia(x), "H*(2m, 2I)")


def test_unknown_parameter_name_is_rejected():
    with pytest.raises(ValueError, match="unknown parameter"):
        derive(spacearm.presets.planar4(), ["mass_of_link_1"])


# ---- velocity terms: the Lagrangian identity -------------------------------------------------
BIAS_MODELS = ["planar4"] + [f"random{s}" for s in RANDOM3]


@pytest.mark.parametrize("name", BIAS_MODELS)
def test_lagrangian_bias_equals_rnea(name):
    """c rebuilt from Ḣ and ∂H/∂q with the quasi-coordinate term v0 × P equals RNEA's bias."""
    d = derivation(name)
    robot = d.robot
    for x, u in states(robot, 3, seed=5):
        c, cs = d.evaluate_many(["c", "c_star"], x, u)
        rel_close(c, robot.bias_forces(x, u), f"{name} c (Lagrangian) vs RNEA", rtol=1e-11)
        rel_close(cs, robot.generalized_bias(x, u), f"{name} c*", rtol=1e-11)


def _rotvec_matrix(w, t):
    th = np.linalg.norm(w) * t
    if th == 0:
        return np.eye(3)
    a = w / np.linalg.norm(w)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(th) * K + (1 - np.cos(th)) * K @ K


def _advance(x, u, t):
    """The state at time t moving at constant u (world angular velocity w0)."""
    xt = x.copy()
    xt[0:3] = x[0:3] + u[0:3] * t
    R = _rotvec_matrix(u[3:6], t) @ spacearm.rotations.quat_to_matrix(x[3:7])
    xt[3:7] = quat_from_matrix(R)
    xt[7:] = x[7:] + u[6:] * t
    return xt


@pytest.mark.parametrize("name", BIAS_MODELS)
def test_time_and_joint_derivatives_against_finite_differences(name):
    d = derivation(name)
    robot = d.robot
    h = 1e-5
    for x, u in states(robot, 2, seed=6):
        Hdot = d.evaluate("H_dot", x, u)
        fd = (robot.mass_matrix(_advance(x, u, h)) - robot.mass_matrix(_advance(x, u, -h))) / (2 * h)
        rel_close(Hdot, fd, f"{name} Hdot vs central differences", rtol=1e-6)
        for k in range(robot.n_dof):
            e = np.zeros_like(x)
            e[7 + k] = h
            fdk = (robot.mass_matrix(x + e) - robot.mass_matrix(x - e)) / (2 * h)
            dk = d.evaluate_many([f"dH_dq{k + 1}" for k in range(robot.n_dof)], x)[k]
            if np.linalg.norm(fdk) > 1e-8:
                rel_close(dk, fdk, f"{name} dH/dq{k + 1}", rtol=1e-6)
            else:
                assert np.linalg.norm(dk) < 1e-8
        # The blocks: Ḣ0, Ḣ0m, Ḣm are slices of Ḣ.
        assert d.dot_block("Hm", ).shape == (robot.n_dof, robot.n_dof)


def test_single_rigid_body_check_of_the_quasi_coordinate_term():
    """A prismatic joint of zero travel mass barely matters; the base terms must give Euler's
    equation c_w = w × I w and c_v = 0 at zero joint rates."""
    d = derivation("planar4")
    robot = d.robot
    x, u = states(robot, 1, seed=7)[0]
    u[6:] = 0.0
    c = d.evaluate("c", x, u)
    rel_close(c, robot.bias_forces(x, u), "c at zero joint rates")
