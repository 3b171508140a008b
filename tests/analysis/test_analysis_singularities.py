"""Dynamic singularities against independent references: a SymPy determinant of
the two-link planar free-floating J* derived here from the momentum conditions, and NumPy SVDs of
Pinocchio-built J* and J_m."""

import numpy as np
import pytest

import spacearm
from spacearm import analysis
from spacearm.errors import ArgumentError, NonFiniteError, ShapeError

from analysis_refs import PinRef, bisect, sympy_two_link, two_link_planar

pytest.importorskip("sympy")


def test_two_link_jstar_and_det_match_sympy():
    robot = two_link_planar()
    f_j, f_det = sympy_two_link()
    rng = np.random.default_rng(3)
    worst = 0.0
    for q1, q2 in rng.uniform(-np.pi, np.pi, size=(40, 2)):
        ref = f_j(q1, q2)
        assert np.linalg.norm(ref) > 0.1
        rep = analysis.analyze(robot, robot.neutral_configuration(q=[q1, q2]), task="planar")
        j = rep.generalized.jacobian
        worst = max(worst, np.linalg.norm(j - ref) / np.linalg.norm(ref))
        # |det| = product of the singular values.
        assert rep.generalized.manipulability == pytest.approx(abs(f_det(q1, q2)), rel=1e-9, abs=1e-12)
    assert worst < 1e-12, worst


def test_dynamic_singularity_is_where_sympy_det_vanishes_and_not_a_kinematic_one():
    robot = two_link_planar()
    _, f_det = sympy_two_link()
    # det J*(q2) at q1 = 0.3 changes sign between samples: bracket the root and bisect.
    q1 = 0.3
    grid = np.linspace(-np.pi + 1e-3, np.pi - 1e-3, 721)
    vals = np.array([f_det(q1, v) for v in grid])
    brackets = np.nonzero(np.sign(vals[:-1]) * np.sign(vals[1:]) < 0)[0]
    assert len(brackets) >= 2
    for i in brackets:
        q2 = bisect(lambda v: f_det(q1, v), grid[i], grid[i + 1])
        rep = analysis.analyze(robot, robot.neutral_configuration(q=[q1, q2]), task="planar")
        s = rep.generalized.singular_values
        assert s[-1] < 1e-10 * s[0], (q2, s)
        if abs(np.sin(q2)) > 0.1:
            # the fixed-base Jacobian is far from singular there: a purely dynamic singularity
            assert rep.fixed_base.sigma_min > 0.05
        # the worst task direction is the left singular vector of the zero singular value
        u = rep.generalized.task_directions[:, -1]
        assert np.linalg.norm(u @ rep.generalized.jacobian) < 1e-9
        det = analysis.detect(robot, robot.neutral_configuration(q=[q1, q2]), task="planar", threshold=0.05, max_damping=0.04)
        assert det.near_singular and det.damping == pytest.approx(0.04, rel=1e-6)


@pytest.mark.parametrize("name,task", [("spatial6", "full"), ("spatial7", "position"), ("planar4", "planar"), ("dual_arm", "full")])
def test_measures_match_numpy_svd_of_pinocchio_jacobians(name, task):
    robot = spacearm.presets.get(name)
    ref = PinRef(robot)
    rows = analysis.task_rows(robot, task)
    rng = np.random.default_rng(5)
    for _ in range(6):
        quat = rng.normal(size=4)
        x = robot.neutral_configuration(q=rng.uniform(-np.pi, np.pi, robot.n_dof), r0=rng.normal(size=3), quat0=quat / np.linalg.norm(quat))
        jstar, jm, _ = ref.maps(x)
        rep = analysis.analyze(robot, x, task=task)
        for meas, j in ((rep.generalized, jstar[rows]), (rep.fixed_base, jm[rows])):
            s = np.linalg.svd(j, compute_uv=False)
            assert s[0] > 1e-2
            np.testing.assert_allclose(meas.singular_values, s, rtol=1e-9, atol=1e-12 * s[0])
            assert meas.condition == pytest.approx(s[0] / s[-1], rel=1e-8)
            assert meas.manipulability == pytest.approx(np.prod(s), rel=1e-8)
            np.testing.assert_allclose(meas.jacobian, j, atol=1e-10 * s[0])
            # singular directions: J v_i = σ_i u_i
            k = len(s)
            np.testing.assert_allclose(meas.jacobian @ meas.joint_directions[:, :k], meas.task_directions * meas.singular_values, atol=1e-10 * s[0])
        # the dynamic and kinematic Jacobians differ (the base reacts)
        assert np.linalg.norm(jstar[rows] - jm[rows]) > 1e-3 * np.linalg.norm(jm[rows])


def test_damping_law():
    eps, lmax = 0.1, 0.05
    assert analysis.damping(0.2, eps, lmax) == 0.0
    for s in (0.0, 0.01, 0.05, 0.099):
        assert analysis.damping(s, eps, lmax) ** 2 == pytest.approx(lmax**2 * (1 - (s / eps) ** 2), rel=1e-12)
    with pytest.raises(ArgumentError, match="threshold"):
        analysis.damping(0.1, 0.0, 0.1)
    with pytest.raises(ArgumentError, match="damping"):
        analysis.damping(0.1, 0.1, -1.0)


def test_scan_equals_per_sample_analysis_and_is_chunk_independent():
    robot = spacearm.presets.spatial6()
    rng = np.random.default_rng(9)
    q = rng.uniform(-np.pi, np.pi, size=(3000, 6))
    whole = analysis.scan(robot, q, task="full")
    chunks = analysis.scan(robot, q, task="full", progress=True)  # progress bar: chunked
    for k in whole:
        np.testing.assert_array_equal(whole[k], chunks[k])
    for i in (0, 1234, 2999):
        rep = analysis.analyze(robot, robot.neutral_configuration(q=q[i]), task="full")
        assert whole["sigma_min_generalized"][i] == pytest.approx(rep.generalized.sigma_min, rel=1e-12)
        assert whole["sigma_min_fixed"][i] == pytest.approx(rep.fixed_base.sigma_min, rel=1e-12)
        assert whole["det_generalized"][i] == pytest.approx(np.linalg.det(rep.generalized.jacobian), rel=1e-9)
        com = robot.center_of_mass(robot.neutral_configuration(q=q[i]))
        p = robot.point_position(robot.neutral_configuration(q=q[i]))
        np.testing.assert_allclose(whole["point_from_com"][i], p - com, atol=1e-12)
        np.testing.assert_allclose(whole["point_from_base"][i], p, atol=1e-12)


def test_scan_is_independent_of_the_thread_count():
    import hashlib
    import os
    import subprocess
    import sys

    code = ("import numpy as np, spacearm, hashlib; from spacearm import analysis; r = spacearm.presets.spatial7(); "
            "q = np.random.default_rng(1).uniform(-3, 3, (5000, 7)); s = analysis.scan(r, q); "
            "print(hashlib.sha256(b''.join(np.ascontiguousarray(s[k]).tobytes() for k in sorted(s))).hexdigest())")
    digests = set()
    for threads in ("1", "2", "3"):
        env = dict(os.environ, RAYON_NUM_THREADS=threads)
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
        assert out.returncode == 0, out.stderr
        digests.add(out.stdout.strip())
    assert len(digests) == 1 and len(hashlib.sha256().hexdigest()) == len(digests.pop())


def test_singularity_map_and_figure(tmp_path):
    robot = two_link_planar()
    m = analysis.singularity_map(robot, joints=(0, 1), resolution=81, task="planar")
    assert m.sigma_min_generalized.shape == (81, 81)
    # the det sign changes (the singular locus) exist for J* along q2 for every q1 row
    assert np.all(np.any(np.diff(np.sign(m.det_generalized), axis=1) != 0, axis=1))
    print(f"\nsigma_min map: {m.sigma_min_generalized.size} samples in {m.seconds:.4f} s = {m.samples_per_second:.0f} samples/s")
    out = m.plot(tmp_path / "map.png")
    assert (tmp_path / "map.png").stat().st_size > 10_000 and out.endswith("map.png")
    assert [p.name for p in tmp_path.iterdir()] == ["map.png"]


def test_bad_input():
    robot = spacearm.presets.planar4()
    x = robot.neutral_configuration()
    with pytest.raises(ShapeError, match="task rows"):
        analysis.analyze(robot, x, task=[0, 0])
    with pytest.raises(ShapeError, match="task rows"):
        analysis.analyze(robot, x, task=[7])
    with pytest.raises(spacearm.SpacearmError, match="unknown task"):
        analysis.analyze(robot, x, task="sideways")
    with pytest.raises(ShapeError, match="N = 4"):
        analysis.scan(robot, np.zeros((3, 5)))
    with pytest.raises(NonFiniteError):
        analysis.scan(robot, np.full((2, 4), np.nan))
    with pytest.raises(ShapeError):
        analysis.singularity_map(robot, joints=(1, 1))
    with pytest.raises(ArgumentError, match="resolution"):
        analysis.singularity_map(robot, resolution=1)
    with pytest.raises(spacearm.QuaternionError):
        analysis.detect(robot, np.r_[0, 0, 0, 0, 0, 0, 2.0, robot.initial_q])


def test_planar4_measures_match_the_symbolic_jstar():
    """planar4: the singular values of J* from spacearm.symbolic (closed form, SymPy) and the
    minors of its planar rows: σ₁σ₂ = √(Σ of the squared 2×2 minors) (Cauchy–Binet)."""
    from itertools import combinations

    from spacearm.symbolic import derive

    robot = spacearm.presets.planar4()
    d = derive(robot)
    rng = np.random.default_rng(21)
    for _ in range(3):
        x = robot.neutral_configuration(q=rng.uniform(-np.pi, np.pi, 4))
        (jsym,) = d.evaluate_many([f"J_star_{robot.end_effector}"], x)
        j = np.asarray(jsym, dtype=float)[:2]
        rep = analysis.analyze(robot, x, task="planar").generalized
        minors = [np.linalg.det(j[:, [a, b]]) for a, b in combinations(range(4), 2)]
        assert rep.manipulability == pytest.approx(np.sqrt(np.sum(np.square(minors))), rel=1e-9)
        np.testing.assert_allclose(rep.singular_values, np.linalg.svd(j, compute_uv=False), rtol=1e-9)
