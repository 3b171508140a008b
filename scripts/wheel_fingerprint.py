"""Numerical fingerprint of an installed spacearm, to show that two builds compute the same bits.

Two builds of the extension (say the manylinux2014 wheel linked through zig and a local
``maturin develop``) should give bit-identical results: same Rust code, same optimisation flags,
and a libm ``hypot``/``sqrt`` that is correctly rounded on both. This script evaluates the
dynamics quantities on fixed-seed random states of every preset and of a few seeded random trees,
plus a short simulation, and saves every array; ``--compare`` requires two such files to be
bit-identical (``numpy.array_equal`` after checking that the NaN pattern is the same).

Run it from the repository root, once in each environment, then compare::

    python scripts/wheel_fingerprint.py /tmp/fp-local.npz
    /tmp/venv-wheel/bin/python scripts/wheel_fingerprint.py /tmp/fp-wheel.npz
    python scripts/wheel_fingerprint.py --compare /tmp/fp-local.npz /tmp/fp-wheel.npz

Exit status: 0 identical (or fingerprint written), 1 a difference, 2 bad input. The inputs
(states, torques) are saved with the outputs and compared first, so a difference in the random
inputs (another numpy) is told apart from a difference in the build.
"""

from __future__ import annotations

import argparse
import os
import sys
from typing import Dict

import numpy as np

#: Random states per model.
STATES_PER_MODEL = 3
#: Seeds of tests/random_models.random_model used (trees with 1-12 DOF, branches, prismatic joints).
RANDOM_MODEL_SEEDS = (0, 1, 2, 3, 5, 8)
#: Keys that hold the inputs of the evaluation, not results.
INPUT_TAG = "input"


def _random_state(robot, rng: np.random.Generator):
    """A state ``(x, u)`` and a joint torque: base off the origin, random attitude, random joints."""
    r0 = rng.uniform(-3.0, 3.0, size=3)
    quat = rng.normal(size=4)
    quat /= np.linalg.norm(quat)
    q = rng.uniform(-np.pi, np.pi, size=robot.n_dof)
    x = robot.neutral_configuration(q=q, r0=r0, quat0=quat)
    u = rng.normal(scale=0.5, size=robot.nu)
    tau = rng.normal(size=robot.n_dof)
    return x, u, tau


def _quantities(robot, x, u, tau) -> Dict[str, np.ndarray]:
    """Every quantity compared, evaluated at one state (end effector as the default point)."""
    base_wrench = np.array([1.0, -2.0, 0.5, 0.3, 0.1, -0.2])
    momentum = robot.momentum(x, u)
    fd_derivatives = robot.forward_dynamics_derivatives(x, u, tau=tau)
    linearization = robot.linearize(x, u, tau=tau)
    blocks = robot.inertia_blocks(x)
    return {
        "mass_matrix": robot.mass_matrix(x),
        "mass_matrix_paper": robot.mass_matrix(x, method="paper"),
        "H0": blocks.H0,
        "H0m": blocks.H0m,
        "Hm": blocks.Hm,
        "bias_forces": robot.bias_forces(x, u),
        "forward_dynamics_aba": robot.forward_dynamics(x, u, tau=tau),
        "forward_dynamics_mass_matrix": robot.forward_dynamics(x, u, tau=tau, method="mass_matrix"),
        "forward_dynamics_flying": robot.forward_dynamics(x, u, tau=tau, base_wrench=base_wrench),
        "inverse_dynamics": robot.inverse_dynamics(x, u, np.linspace(-1.0, 1.0, robot.nu)),
        "generalized_inertia": robot.generalized_inertia(x),
        "generalized_bias": robot.generalized_bias(x, u),
        "generalized_jacobian": robot.generalized_jacobian(x),
        "point_jacobian": np.hstack(robot.point_jacobian(x)),
        "base_velocity_from_momentum": robot.base_velocity_from_momentum(x, u[6:], P=(0.1, 0.0, -0.1), L=(0.0, 0.2, 0.0)),
        "momentum": np.concatenate([momentum.P, momentum.L_origin, momentum.L_base, momentum.L_com]),
        "kinetic_energy": np.array([robot.kinetic_energy(x, u)]),
        "center_of_mass": robot.center_of_mass(x),
        "mass_matrix_partials": robot.mass_matrix_partials(x),
        "generalized_jacobian_derivative": robot.generalized_jacobian_derivative(x, u),
        "forward_dynamics_ddu_dx": fd_derivatives.ddu_dx,
        "forward_dynamics_ddu_du": fd_derivatives.ddu_du,
        "linearize_A": linearization.A,
        "linearize_B": linearization.B,
    }


def _models():
    """(label, robot) for every preset and the seeded random trees of the test suite."""
    import spacearm

    for name in ("planar4", "spatial6", "dual_arm", "spatial7"):
        yield name, spacearm.presets.get(name)
    tests_dir = os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "tests")
    sys.path.insert(0, os.path.normpath(tests_dir))
    from random_models import random_model

    for seed in RANDOM_MODEL_SEEDS:
        yield f"random{seed}", random_model(seed).robot


def fingerprint() -> Dict[str, np.ndarray]:
    """Every array of the fingerprint, keyed ``model/state/quantity`` (inputs tagged ``input``)."""
    import spacearm

    arrays: Dict[str, np.ndarray] = {}
    for model_index, (label, robot) in enumerate(_models()):
        rng = np.random.default_rng([2026, 11, model_index])
        for k in range(STATES_PER_MODEL):
            x, u, tau = _random_state(robot, rng)
            prefix = f"{label}/state{k}"
            arrays[f"{prefix}/{INPUT_TAG}_x"] = x
            arrays[f"{prefix}/{INPUT_TAG}_u"] = u
            arrays[f"{prefix}/{INPUT_TAG}_tau"] = tau
            for name, value in _quantities(robot, x, u, tau).items():
                arrays[f"{prefix}/{name}"] = np.asarray(value, dtype=float)
    # A short torque-free simulation: thousands of chained evaluations, so a last-bit difference
    # anywhere in the step would grow and show.
    robot = spacearm.presets.spatial6()
    x0 = robot.neutral_configuration()
    u0 = np.concatenate([np.zeros(6), np.full(robot.n_dof, 0.3)])
    trajectory = spacearm.simulate(robot, 0.5, x0=x0, u0=u0, dt=1e-3)
    arrays["simulate_spatial6/x"] = trajectory.x
    arrays["simulate_spatial6/u"] = trajectory.u
    arrays["meta/version"] = np.array(spacearm.__version__)
    arrays["meta/extension"] = np.array(os.path.abspath(spacearm._core.__file__))
    return arrays


def _load(path: str) -> Dict[str, np.ndarray]:
    """Every array of a fingerprint file; exit 2 with one line if it is not one."""
    try:
        with np.load(path) as file:
            return {key: file[key] for key in file.files}
    except (OSError, ValueError) as exc:
        print(f"wheel_fingerprint.py: error: {path} is not a fingerprint .npz file ({exc})", file=sys.stderr)
        raise SystemExit(2)


def compare(path_a: str, path_b: str) -> int:
    """0 when every array of the two fingerprints is bit-identical, 1 otherwise (with a report)."""
    a, b = _load(path_a), _load(path_b)
    print(f"A: {path_a}: spacearm {a.get('meta/version')} from {a.get('meta/extension')}")
    print(f"B: {path_b}: spacearm {b.get('meta/version')} from {b.get('meta/extension')}")
    keys_a = {key for key in a if not key.startswith("meta/")}
    keys_b = {key for key in b if not key.startswith("meta/")}
    if keys_a != keys_b:
        print(f"DIFFERENT: the fingerprints hold different arrays (only in A: {sorted(keys_a - keys_b)[:5]}, "
              f"only in B: {sorted(keys_b - keys_a)[:5]}); were they made by the same script?")
        return 1
    inputs = sorted(key for key in keys_a if f"/{INPUT_TAG}_" in key)
    if not all(np.array_equal(a[key], b[key]) for key in inputs):
        print("DIFFERENT INPUTS: the random states differ (another numpy random stream?); "
              "the outputs cannot be compared")
        return 1
    outputs = sorted(keys_a - set(inputs))
    differing = []
    n_values = 0
    for key in outputs:
        va, vb = a[key], b[key]
        n_values += va.size
        if va.shape != vb.shape:
            differing.append((key, f"shape {va.shape} vs {vb.shape}"))
            continue
        nan_a, nan_b = np.isnan(va), np.isnan(vb)
        if not np.array_equal(nan_a, nan_b):
            differing.append((key, f"NaN pattern differs ({nan_a.sum()} vs {nan_b.sum()} NaNs)"))
            continue
        if not np.array_equal(va, vb, equal_nan=True):
            finite = ~nan_a
            abs_diff = np.abs(va[finite] - vb[finite])
            scale = np.maximum(np.abs(va[finite]), np.abs(vb[finite]))
            rel = np.max(abs_diff / np.where(scale > 0, scale, 1.0))
            differing.append((key, f"max |A-B| = {abs_diff.max():.3e}, max relative {rel:.3e}, "
                                   f"{np.count_nonzero(abs_diff)} of {va.size} values differ"))
    if differing:
        print(f"DIFFERENT: {len(differing)} of {len(outputs)} arrays are not bit-identical:")
        for key, why in differing:
            print(f"  {key}: {why}")
        return 1
    print(f"IDENTICAL: {len(outputs)} arrays ({n_values} values) bit-identical, NaN patterns equal, "
          f"on {len(inputs) // 3} identical input states")
    return 0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="wheel_fingerprint.py", description=__doc__.split("\n\n")[0])
    parser.add_argument("paths", nargs="+", metavar="FILE.npz",
                        help="where to write the fingerprint; with --compare, the two fingerprints")
    parser.add_argument("--compare", action="store_true", help="compare two fingerprints bit for bit")
    args = parser.parse_args(argv)
    if args.compare:
        if len(args.paths) != 2:
            parser.error(f"--compare takes two fingerprint files, got {len(args.paths)}")
        for path in args.paths:
            if not os.path.isfile(path):
                parser.error(f"no such fingerprint file: {path}")
        return compare(*args.paths)
    if len(args.paths) != 1:
        parser.error(f"expected one output file, got {len(args.paths)} (did you mean --compare A B?)")
    (path,) = args.paths
    if not path.endswith(".npz"):
        parser.error(f"the output file must end in .npz, got {path}")
    arrays = fingerprint()
    # Written beside the target and renamed, so an interrupted run leaves no partial file.
    partial = path[: -len(".npz")] + ".partial.npz"
    np.savez(partial, **arrays)
    os.replace(partial, path)
    print(f"wrote {len(arrays)} arrays to {path} (spacearm {arrays['meta/version']} from {arrays['meta/extension']})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
