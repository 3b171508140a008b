"""The typed results of the analysis bindings (``spacearm._core``): each extension function
returns its frozen class, the stub declares exactly the attributes the class has, and the
attributes agree with independent computations: NumPy SVDs of Pinocchio-built J* and J_m, the
base map from Pinocchio's mass matrix, the damping law's closed form, quaternion algebra, and
workspace shells worked out by hand from the definitions."""

import ast
import pathlib

import numpy as np
import pytest

import spacearm
from spacearm import _core

from analysis_refs import PinRef

CLASSES = ("JacobianMeasures", "SingularityReport", "Detection", "ScanResult", "WorkspaceShells", "ReactionNullSpace", "RmrcRates",
           "RmrcMotion")
STUB = pathlib.Path(spacearm.__file__).with_name("_core.pyi")


def _stub_attributes():
    """Attribute names declared for each class of the stub."""
    out = {}
    for node in ast.parse(STUB.read_text(encoding="utf-8")).body:
        if isinstance(node, ast.ClassDef):
            out[node.name] = {n.name for n in node.body if isinstance(n, ast.FunctionDef) and not n.name.startswith("_")}
    return out


def _stub_returns():
    return {n.name: ast.unparse(n.returns) for n in ast.parse(STUB.read_text(encoding="utf-8")).body if isinstance(n, ast.FunctionDef)}


@pytest.mark.parametrize("name", CLASSES)
def test_stub_declares_exactly_the_class_attributes(name):
    cls = getattr(_core, name)
    assert cls.__module__ == "spacearm._core"
    public = {a for a in dir(cls) if not a.startswith("_")}
    assert _stub_attributes()[name] == public
    for a in public:
        assert getattr(cls, a).__doc__, f"{name}.{a} has no docstring"


def test_stub_names_the_classes_as_return_types():
    returns = _stub_returns()
    expected = {"analysis_singularity": "SingularityReport", "analysis_detect": "Detection", "analysis_scan": "ScanResult",
                "analysis_reaction_null_space": "ReactionNullSpace", "analysis_rmrc_rates": "RmrcRates"}
    for fn, cls in expected.items():
        assert returns[fn] == cls
    assert not [f for f, r in returns.items() if f.startswith("analysis_") and "dict" in r]


def _random_state(robot, rng):
    quat = rng.normal(size=4)
    return robot.neutral_configuration(q=rng.uniform(-2, 2, robot.n_dof), r0=rng.normal(size=3), quat0=quat / np.linalg.norm(quat))


def _check_measures(m, jacobian):
    assert isinstance(m, _core.JacobianMeasures)
    np.testing.assert_allclose(m.jacobian, jacobian, atol=1e-10 * np.abs(jacobian).max())
    s = np.linalg.svd(jacobian, compute_uv=False)
    np.testing.assert_allclose(m.singular_values, s, rtol=1e-9, atol=1e-12 * s[0])
    assert m.condition == pytest.approx(s[0] / s[-1], rel=1e-8)
    assert m.manipulability == pytest.approx(np.prod(s), rel=1e-8)
    k, n = len(s), jacobian.shape[1]
    u, v = m.task_directions, m.joint_directions
    assert u.shape == (jacobian.shape[0], k) and v.shape == (n, n)
    np.testing.assert_allclose(v.T @ v, np.eye(n), atol=1e-12)
    # J v_i = σ_i u_i for every singular pair (the directions belong to the values).
    np.testing.assert_allclose(jacobian @ v[:, :k], u * s, atol=1e-9 * s[0])


@pytest.mark.parametrize("name,rows", [("spatial6", [0, 1, 2]), ("planar4", [0, 1]), ("spatial7", [0, 1, 2, 3, 4, 5])])
def test_singularity_analysis_matches_pinocchio_svd(name, rows):
    robot = spacearm.presets.get(name)
    ref = PinRef(robot)
    x = _random_state(robot, np.random.default_rng(5))
    body, off = robot._point(None)
    a = _core.analysis_singularity(robot.core_model, x, body, off, rows)
    assert isinstance(a, _core.SingularityReport) and a.task == tuple(rows)
    assert a.generalized.sigma_min == a.generalized.singular_values[-1]
    jstar, jm, _ = ref.maps(x)
    _check_measures(a.generalized, jstar[rows])
    _check_measures(a.fixed_base, jm[rows])
    # Read-only: the result carries what the core computed.
    with pytest.raises(AttributeError):
        a.generalized.condition = 1.0
    with pytest.raises(AttributeError):
        a.fixed_base = a.generalized
    assert "JacobianMeasures" in repr(a.generalized) and f"jacobian=({len(rows)}, {robot.n_dof})" in repr(a.generalized)


def test_detection_matches_svd_and_the_damping_closed_form():
    robot = spacearm.presets.spatial6()
    ref = PinRef(robot)
    x = _random_state(robot, np.random.default_rng(6))
    body, off = robot._point(None)
    s = np.linalg.svd(ref.maps(x)[0][:3], compute_uv=False)
    for eps, lam_max in ((2.0 * s[-1], 0.1), (0.5 * s[-1], 0.1)):
        d = _core.analysis_detect(robot.core_model, x, body, off, [0, 1, 2], eps, lam_max)
        assert isinstance(d, _core.Detection)
        assert d.sigma_min == pytest.approx(s[-1], rel=1e-9)
        assert d.condition == pytest.approx(s[0] / s[-1], rel=1e-8)
        near = s[-1] < eps
        assert d.near_singular is bool(near)
        # λ² = λ_max² (1 − (σ/ε)²) inside the singular region, 0 outside.
        assert d.damping == pytest.approx(lam_max * np.sqrt(1 - (s[-1] / eps) ** 2) if near else 0.0, rel=1e-9, abs=1e-15)
        assert d.damping > 0.0 if near else d.damping == 0.0


@pytest.mark.parametrize("name,rows", [("spatial6", [0, 1, 2, 3, 4, 5]), ("planar4", [0, 1])])
def test_scan_result_columns_match_per_sample_references(name, rows):
    robot = spacearm.presets.get(name)
    ref = PinRef(robot)
    q = np.random.default_rng(7).uniform(-2.5, 2.5, (5, robot.n_dof))
    body, off = robot._point(None)
    r = _core.analysis_scan(robot.core_model, q, body, off, rows)
    assert isinstance(r, _core.ScanResult)
    for col in ("sigma_min_generalized", "sigma_max_generalized", "manipulability_generalized", "det_generalized", "sigma_min_fixed",
                "manipulability_fixed", "det_fixed"):
        assert getattr(r, col).shape == (5,)
    assert r.point_from_base.shape == r.point_from_com.shape == (5, 3)
    square = len(rows) == robot.n_dof
    for i, qi in enumerate(q):
        x = robot.neutral_configuration(q=qi)  # base at the origin, aligned with 𝒥: base frame = 𝒥
        jstar, jm, _ = ref.maps(x)
        sg, sf = (np.linalg.svd(j[rows], compute_uv=False) for j in (jstar, jm))
        assert r.sigma_min_generalized[i] == pytest.approx(sg[-1], rel=1e-8, abs=1e-12)
        assert r.sigma_max_generalized[i] == pytest.approx(sg[0], rel=1e-9)
        assert r.manipulability_generalized[i] == pytest.approx(np.prod(sg), rel=1e-8, abs=1e-14)
        assert r.sigma_min_fixed[i] == pytest.approx(sf[-1], rel=1e-8, abs=1e-12)
        assert r.manipulability_fixed[i] == pytest.approx(np.prod(sf), rel=1e-8, abs=1e-14)
        if square:
            assert r.det_generalized[i] == pytest.approx(np.linalg.det(jstar[rows]), rel=1e-8, abs=1e-12)
            assert r.det_fixed[i] == pytest.approx(np.linalg.det(jm[rows]), rel=1e-8, abs=1e-12)
        else:
            assert np.isnan(r.det_generalized[i]) and np.isnan(r.det_fixed[i])
        p = robot.point_position(x)
        np.testing.assert_allclose(r.point_from_base[i], p, atol=1e-12)
        np.testing.assert_allclose(r.point_from_com[i], p - robot.center_of_mass(x), atol=1e-12)


def test_workspace_shells_from_hand_worked_samples():
    # Barycentric radii 1.0, 1.2, 1.25, 2.0, 3.0 in assorted directions; the samples at 1.2 and
    # 1.25 are singular (σ below 0.01) and 0.05 apart, within the 0.1 m resolution: one PDW
    # shell [1.2, 1.25]; the PIW shells are the rest of [1.0, 3.0].
    dirs = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1], [0.6, 0.8, 0], [0, 0.6, -0.8]])
    com = dirs * np.array([1.0, 1.2, 1.25, 2.0, 3.0])[:, None]
    base = dirs[::-1] * np.array([0.5, 0.7, 0.4, 2.5, 1.5])[:, None]
    sigma = [1.0, 1e-3, 5e-3, 1.0, 0.5]
    w = _core.WorkspaceShells(sigma, [np.nan] * 5, com, base, 0.01, 0.1)
    assert isinstance(w, _core.WorkspaceShells)
    assert w.reachable == pytest.approx((1.0, 3.0), rel=1e-15)
    assert w.fixed_base == pytest.approx((0.4, 2.5), rel=1e-15)
    np.testing.assert_allclose(w.singular_radii, [1.2, 1.25], rtol=1e-15)
    assert len(w.path_dependent) == 1 and w.path_dependent[0] == pytest.approx((1.2, 1.25), rel=1e-15)
    assert len(w.path_independent) == 2
    assert w.path_independent[0] == pytest.approx((1.0, 1.2), rel=1e-15)
    assert w.path_independent[1] == pytest.approx((1.25, 3.0), rel=1e-15)
    assert w.radial_resolution == 0.1
    # A finer resolution than the gap splits the PDW shell in two.
    w2 = _core.WorkspaceShells(sigma, [np.nan] * 5, com, base, 0.01, 0.01)
    np.testing.assert_allclose(w2.path_dependent, [(1.2, 1.2), (1.25, 1.25)], rtol=1e-15)


@pytest.mark.parametrize("which,rows", [("angular", slice(3, 6)), ("full", slice(0, 6))])
def test_reaction_null_space_matches_pinocchio_base_map(which, rows):
    robot = spacearm.presets.spatial7()
    ref = PinRef(robot)
    x = _random_state(robot, np.random.default_rng(8))
    r = _core.analysis_reaction_null_space(robot.core_model, x, which, 1e-9)
    assert isinstance(r, _core.ReactionNullSpace)
    base = ref.maps(x)[2][rows]
    np.testing.assert_allclose(r.base_motion_map, base, atol=1e-10 * np.abs(base).max())
    s = np.linalg.svd(base, compute_uv=False)
    np.testing.assert_allclose(r.singular_values, s, rtol=1e-9)
    rank = int(np.sum(s > 1e-9 * s[0]))
    assert isinstance(r.rank, int) and r.rank == rank and r.dimension == robot.n_dof - rank
    n = robot.n_dof
    assert r.basis.shape == (n, n - rank)
    np.testing.assert_allclose(r.basis.T @ r.basis, np.eye(n - rank), atol=1e-12)
    np.testing.assert_allclose(base @ r.basis, 0.0, atol=1e-10 * s[0])
    np.testing.assert_allclose(r.projector, r.basis @ r.basis.T, atol=1e-12)


def test_rmrc_rates_realise_the_twist_and_match_the_base_map():
    robot = spacearm.presets.spatial6()
    ref = PinRef(robot)
    x = _random_state(robot, np.random.default_rng(9))
    body, off = robot._point(None)
    desired = np.array([0.01, -0.02, 0.015, 0.0, 0.0, 0.0])
    options = _core.RmrcOptions(rows=[0, 1, 2], threshold=1e-6, max_damping=1e-3)
    r = _core.analysis_rmrc_rates(robot.core_model, x, body, off, desired, options)
    assert isinstance(r, _core.RmrcRates)
    jstar, _, base = ref.maps(x)
    np.testing.assert_allclose(r.qd, np.linalg.pinv(jstar[:3]) @ desired[:3], rtol=1e-8, atol=1e-14)
    np.testing.assert_allclose(jstar[:3] @ r.qd, desired[:3], atol=1e-12)
    np.testing.assert_allclose(r.base_angular_velocity, base[3:] @ r.qd, atol=1e-12)
    assert r.sigma_min == pytest.approx(np.linalg.svd(jstar[:3], compute_uv=False)[-1], rel=1e-9)
    assert r.damping == 0.0


def test_rmrc_motion_rows_are_consistent_records():
    robot = spacearm.presets.planar4()
    x0 = robot.neutral_configuration()
    body, off = robot._point(None)
    p0 = robot.point_position(x0)
    target = p0 + np.array([-0.1, 0.05, 0.0])
    dt = 0.02
    options = _core.RmrcOptions(rows=[0, 1], threshold=1e-3, max_damping=1e-2, gain=5.0, strategy="naive")
    m = _core.RmrcMotion(robot.core_model, x0, body, off, target, 1.0, 0.2, dt, options)
    assert isinstance(m, _core.RmrcMotion)
    assert (m.robot_name, m.strategy) == (robot.name, "naive") and np.array_equal(m.target, target)
    assert m.max_attitude_change == m.attitude_change.max()
    k = m.times.shape[0]
    n = robot.n_dof
    assert m.x.shape == (k, 7 + n) and m.qd.shape == (k, n) and m.point_position.shape == (k, 3)
    assert m.sigma_min.shape == m.damping.shape == m.attitude_change.shape == (k,)
    np.testing.assert_allclose(m.times, dt * np.arange(k), atol=1e-12)
    np.testing.assert_allclose(m.x[0], x0, atol=1e-15)
    for i in (0, k // 2, k - 1):
        np.testing.assert_allclose(m.point_position[i], robot.point_position(m.x[i]), atol=1e-12)
        # rotation angle between the start and current base quaternions
        c = abs(float(m.x[0, 3:7] @ m.x[i, 3:7]))
        assert m.attitude_change[i] == pytest.approx(2.0 * np.arccos(min(c, 1.0)), abs=1e-7)
    assert m.final_position_error == pytest.approx(np.linalg.norm(m.point_position[-1, :2] - target[:2]), rel=1e-9, abs=1e-15)
    assert m.final_position_error < 1e-3


def test_public_scan_dict_has_every_scan_column_in_chunks_and_whole():
    from spacearm.analysis.singularities import SCAN_COLUMNS

    assert set(SCAN_COLUMNS) == {a for a in dir(_core.ScanResult) if not a.startswith("_")}
    robot = spacearm.presets.planar4()
    q = np.random.default_rng(10).uniform(-3, 3, (2500, robot.n_dof))  # two chunks
    s = spacearm.analysis.scan(robot, q)
    assert tuple(s) == SCAN_COLUMNS
    body, off = robot._point(None)
    last = _core.analysis_scan(robot.core_model, q[-3:], body, off, [0, 1])
    for k in SCAN_COLUMNS:
        assert len(s[k]) == 2500
        np.testing.assert_array_equal(s[k][-3:], getattr(last, k))


def test_public_results_are_the_extension_classes():
    """Each type once: the public analysis results are the extension's classes (Motion a
    subclass adding the figure only, no fields of its own), returned as the core made them."""
    from spacearm import analysis

    for public, core in (("JacobianMeasures", "JacobianMeasures"), ("SingularityReport", "SingularityReport"),
                         ("Detection", "Detection"), ("ReactionNullSpace", "ReactionNullSpace")):
        assert getattr(analysis, public) is getattr(_core, core)
    assert issubclass(analysis.Motion, _core.RmrcMotion) and analysis.Motion.__slots__ == ()
    assert issubclass(analysis.Workspace, _core.WorkspaceShells)
    shell_fields = {a for a in dir(_core.WorkspaceShells) if not a.startswith("_")}
    assert not shell_fields & set(analysis.Workspace.__slots__)  # no copy of the extension's fields
    robot = spacearm.presets.planar4()
    rep = analysis.analyze(robot, task="planar")
    assert type(rep) is analysis.SingularityReport and rep.task == (0, 1)
    assert rep.generalized.sigma_min == rep.generalized.singular_values[-1]
    assert type(analysis.detect(robot, robot.neutral_configuration(), task="planar")) is analysis.Detection
    rns = analysis.reaction_null_space(robot)
    assert rns.dimension == rns.basis.shape[1] == robot.n_dof - rns.rank
    r = analysis.rmrc_rates(robot, robot.neutral_configuration(), [0.01, 0, 0, 0, 0, 0], task="planar")
    assert type(r) is _core.RmrcRates
    m = analysis.move_to(robot, robot.point_position(robot.neutral_configuration()) + [-0.05, 0.02, 0.0], task="planar",
                         duration=0.5, settle=0.1, dt=0.02)
    assert type(m) is analysis.Motion and m.robot_name == robot.name and m.strategy == "reactionless"
    assert m.max_attitude_change == float(np.max(m.attitude_change))
    with pytest.raises(AttributeError):
        m.strategy = "naive"
