"""Seeded random spacecraft-manipulator models and states, for the cross-engine tests.

Every model is built through the public :class:`spacearm.RobotBuilder` (so the tests exercise
the same path as users) from a ``numpy.random.Generator`` seeded with the case's seed: a failing
seed reproduces exactly.

What a model can contain (docs/conventions.md frames: every body frame at its CM):

- N = 1..12 joint degrees of freedom, revolute or prismatic, plus 0..3 fixed links;
- a tree, not only a chain: each new link hangs from the previous link (a chain), from the base
  (a branch at the base) or from any earlier link (a branch mid-chain, also below fixed links);
  :func:`tree_features` says which of these a model has;
- joint placements ``origin`` and CM offsets ``com`` up to 0.8 m per axis, random orientations
  ``rotation`` (some identity), random unit axes (some along a coordinate axis);
- masses 0.5–20 kg (base 20–800 kg) and physical inertias: principal moments built from random
  non-negative second moments ``s`` as ``(s_y + s_z, s_x + s_z, s_x + s_y)``, which always obey
  the triangle inequality, rotated by a random rotation;
- a named point ``tip`` on a leaf link (the end effector) and a point ``probe`` on a random body.

States: the base sometimes far from the origin (up to ~5 km), random attitude, random joint
coordinates and velocities of order one.
"""

from __future__ import annotations

import atexit
import json
import os
from dataclasses import dataclass, field
from typing import Dict, List

import numpy as np

import spacearm
from spacearm.rotations import quat_to_matrix

__all__ = [
    "SEEDS",
    "RandomModel",
    "random_model",
    "with_joint_springs",
    "random_state",
    "random_quaternion",
    "random_inertia",
    "tree_features",
    "assert_rel_close",
    "MAX_ERRORS",
]


#: Seeds of the random models every cross-engine test runs on.
SEEDS = list(range(36))


def random_quaternion(rng: np.random.Generator) -> np.ndarray:
    """Uniformly distributed unit quaternion ``[x, y, z, w]`` (normalized Gaussian)."""
    q = rng.normal(size=4)
    return q / np.linalg.norm(q)


def random_inertia(rng: np.random.Generator, mass: float, size=(0.03, 0.5)) -> np.ndarray:
    """A physical inertia tensor (3×3, about the CM) of a body of ``mass``.

    Second moments ``s_k = m d_k²`` with ``d_k`` uniform in ``size`` give principal moments
    ``I_x = s_y + s_z`` (etc.), which obey the triangle inequality by construction (a body whose
    mass lies in a box of half-widths ~d). A random rotation makes the tensor full.
    """
    s = mass * rng.uniform(*size, size=3) ** 2
    principal = np.array([s[1] + s[2], s[0] + s[2], s[0] + s[1]])
    a, b, c = principal
    assert a + b >= c and a + c >= b and b + c >= a, "triangle inequality"
    r = quat_to_matrix(random_quaternion(rng))
    inertia = r @ np.diag(principal) @ r.T
    return 0.5 * (inertia + inertia.T)


def _random_axis(rng: np.random.Generator) -> np.ndarray:
    if rng.random() < 0.3:  # along a coordinate axis, either sign
        axis = np.zeros(3)
        axis[rng.integers(3)] = rng.choice([-1.0, 1.0])
        return axis
    a = rng.normal(size=3)
    return a / np.linalg.norm(a)


@dataclass
class RandomModel:
    """A random model with the facts the tests assert about the generator."""

    seed: int
    robot: spacearm.Robot
    parents: List[int]  # parent body index of each link (link k is body k+1)
    kinds: List[str]  # joint type of each link
    specs: List[dict]  # the keyword arguments given to RobotBuilder.add_link, in order
    features: Dict[str, bool] = field(default_factory=dict)


def tree_features(parents: List[int], kinds: List[str]) -> Dict[str, bool]:
    """Which structures a tree (parent body of each link, body 0 = base) contains."""
    n_children: Dict[int, int] = {}
    for p in parents:
        n_children[p] = n_children.get(p, 0) + 1
    return {
        "base_branch": n_children.get(0, 0) >= 2,
        "mid_chain_branch": any(p != 0 and n >= 2 for p, n in n_children.items()),
        "fixed": "fixed" in kinds,
        "fixed_with_children": any(kinds[p - 1] == "fixed" for p in parents if p != 0),
        "prismatic": "prismatic" in kinds,
        "revolute": "revolute" in kinds,
    }


def random_model(seed: int) -> RandomModel:
    """The random model of ``seed`` (deterministic)."""
    rng = np.random.default_rng([20180541, seed])
    n_dof = int(rng.integers(1, 13))
    n_fixed = int(rng.integers(0, 4))
    kinds = ["revolute" if rng.random() < 0.7 else "prismatic" for _ in range(n_dof)] + ["fixed"] * n_fixed
    rng.shuffle(kinds)

    base_mass = float(rng.uniform(20.0, 800.0))
    b = spacearm.Robot.builder(f"random{seed}", base_mass, random_inertia(rng, base_mass, (0.3, 1.2)))
    parents: List[int] = []
    specs: List[dict] = []
    for k, kind in enumerate(kinds):
        body = k + 1
        u = rng.random()
        if body == 1 or u < 0.2:
            parent = 0  # a branch at the base (or the first link)
        elif u < 0.7:
            parent = body - 1  # continue the chain
        else:
            parent = int(rng.integers(1, body))  # hang from any earlier link: mid-chain branch
        parents.append(parent)
        mass = float(rng.uniform(0.5, 20.0))
        rotation = np.array([0.0, 0.0, 0.0, 1.0]) if rng.random() < 0.2 else random_quaternion(rng)
        spec = dict(
            parent="base" if parent == 0 else f"link{parent}",
            joint=kind,
            axis=_random_axis(rng),
            origin=rng.uniform(-0.8, 0.8, size=3),
            rotation=rotation,
            com=rng.uniform(-0.6, 0.6, size=3),
            mass=mass,
            inertia=random_inertia(rng, mass),
        )
        specs.append(spec)
        b.add_link(f"link{body}", **spec)
    leaves = [body for body in range(1, len(kinds) + 1) if body not in parents]
    tip_body = int(rng.choice(leaves))
    b.add_point("tip", body=f"link{tip_body}", offset=rng.uniform(-0.5, 0.5, size=3))
    b.set_end_effector("tip")
    probe_body = int(rng.integers(0, len(kinds) + 1))
    b.add_point("probe", body="base" if probe_body == 0 else f"link{probe_body}", offset=rng.uniform(-0.5, 0.5, size=3))
    robot = b.build()
    assert robot.n_dof == n_dof
    return RandomModel(seed, robot, parents, kinds, specs, tree_features(parents, kinds))


def with_joint_springs(robot: spacearm.Robot, rng: np.random.Generator) -> tuple:
    """``robot`` rebuilt with a random spring–damper (``stiffness`` 0–50, ``damping`` 0–5),
    ``rest`` (±1) and actuation on every moving joint (docs/flexibility.md), and the list of
    those joints' keyword arguments in ``q`` order."""
    d = robot.description
    b = spacearm.Robot.builder(d.name, base_mass=d.base.mass, base_inertia=d.base.inertia, base_name=d.base.name)
    dynamics = []
    for link in d.links:
        extra = {}
        if link.type != "fixed":
            extra = dict(actuated=bool(rng.random() < 0.5), stiffness=float(rng.uniform(0, 50)),
                         damping=float(rng.uniform(0, 5)), rest=float(rng.uniform(-1, 1)))
            dynamics.append(extra)
        b.add_link(link.name, parent=link.parent, joint=link.type, axis=link.axis, origin=link.origin,
                   rotation=link.rotation, com=link.com, mass=link.mass, inertia=link.inertia, joint_name=link.joint, **extra)
    for p in d.points:
        b.add_point(p.name, body=p.body, offset=p.offset)
    if d.end_effector is not None:
        b.set_end_effector(d.end_effector)
    return b.build(), dynamics


def flexible_sat() -> spacearm.Robot:
    """A 40 kg bus with a flexible panel, a three-segment beam and one motorized arm link."""
    b = spacearm.Robot.builder("flex-sat", base_mass=40.0, base_inertia=[3.0, 3.5, 4.0])
    b.add_panel("wing", hinge_position=(0.5, 0, 0), hinge_axis=(0, 1, 0), direction=(1, 0, 0), size=(1.2, 0.8, 0.02),
                mass=4.0, frequency=2.0, damping=0.05)
    b.add_beam("boom", root_position=(0, 0.4, 0), axis=(0, 1, 0), length=2.0, segments=3, EI=40.0,
               bending_axes=[(1, 0, 0)], rho_A=0.6, rho_J=0.002, damping_ratio=0.01)
    b.add_link("arm", joint="revolute", axis=(0, 0, 1), origin=(-0.4, 0, 0), com=(-0.3, 0, 0), mass=2.0,
               inertia=[0.01, 0.06, 0.06])
    return b.build()


def random_state(robot: spacearm.Robot, rng: np.random.Generator):
    """A random state ``(x, u)``: base sometimes far from the origin (1–5 km), random attitude,
    joint coordinates (revolute ±π rad, prismatic ±0.5 m) and velocities of order one."""
    far = rng.random() < 0.35
    r0 = rng.uniform(-5000.0, 5000.0, size=3) if far else rng.uniform(-2.0, 2.0, size=3)
    types = robot.dof_types
    q = np.array([rng.uniform(-np.pi, np.pi) if t == "revolute" else rng.uniform(-0.5, 0.5) for t in types])
    x = robot.neutral_configuration(q=q, r0=r0, quat0=random_quaternion(rng))
    u = np.concatenate([rng.normal(scale=0.5, size=3), rng.normal(scale=0.5, size=3), rng.normal(size=robot.n_dof)])
    return x, u


# ---------------------------------------------------------------------------------------------
# comparisons
# ---------------------------------------------------------------------------------------------
#: Largest relative error seen per quantity name in this process.
MAX_ERRORS: Dict[str, float] = {}


def assert_rel_close(actual, reference, what: str, rtol: float = 1e-10, min_norm: float = 1e-3) -> float:
    """Assert ``‖actual − reference‖ / ‖reference‖ ≤ rtol`` (Frobenius/2-norm).

    ``‖reference‖ ≥ min_norm`` is asserted first, so a comparison cannot pass on zeros (both
    engines returning nothing). The error is recorded in :data:`MAX_ERRORS` under ``what``.
    """
    a = np.asarray(actual, dtype=float)
    b = np.asarray(reference, dtype=float)
    assert a.shape == b.shape, f"{what}: shape {a.shape} != reference shape {b.shape}"
    assert np.all(np.isfinite(a)), f"{what}: non-finite values {a}"
    nb = float(np.linalg.norm(b))
    assert nb >= min_norm, f"{what}: reference norm {nb:.3g} < {min_norm:g}: the comparison would be vacuous"
    err = float(np.linalg.norm(a - b)) / nb
    MAX_ERRORS[what] = max(err, MAX_ERRORS.get(what, 0.0))
    assert err <= rtol, f"{what}: relative error {err:.3e} > {rtol:.0e}\nactual    {a}\nreference {b}"
    return err


def _dump_errors() -> None:  # pragma: no cover - diagnostics only
    path = os.environ.get("SPACEARM_INTEROP_ERRORS")
    if path and MAX_ERRORS:
        old = {}
        if os.path.exists(path):
            with open(path) as fh:
                old = json.load(fh)
        for k, v in MAX_ERRORS.items():
            old[k] = max(v, old.get(k, 0.0))
        with open(path, "w") as fh:
            json.dump(old, fh, indent=1, sort_keys=True)


atexit.register(_dump_errors)
