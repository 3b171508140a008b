"""The analytic dynamics Jacobians (Carpentier & Mansard's recursions carried into spacearm's
frames; docs/derivatives.md) against the dual-number route (``method="dual"``) and against
central finite differences, on random trees with branches, prismatic and fixed joints, with and
without external wrenches.

The default route of ``forward_dynamics_derivatives``/``linearize`` is the analytic one, so the
finite-difference, Pinocchio and simulation checks of tests/model/test_derivatives.py hold it
too; this file adds the oracle comparison and the external wrenches.
"""

from __future__ import annotations

import numpy as np
import pytest

import spacearm
from test_derivatives import FD_CASES, H_STEP, RTOL_FD, case, tangent_fd
from random_models import assert_rel_close


def wrenches_for(robot, seed: int):
    """Two wrenches with random force, torque and point: one on the last body, one on the base."""
    rng = np.random.default_rng(seed)
    return [
        spacearm.ExternalWrench(body=robot.n_bodies - 1, force=rng.normal(scale=10.0, size=3),
                                torque=rng.normal(scale=2.0, size=3), offset=rng.uniform(-0.3, 0.3, 3)),
        spacearm.ExternalWrench(body=0, force=rng.normal(scale=10.0, size=3), offset=rng.uniform(-0.5, 0.5, 3)),
    ]


@pytest.mark.parametrize("name", FD_CASES)
def test_analytic_equals_dual_numbers(name):
    robot, x, u, f = case(name)
    du = robot.forward_dynamics(x, u, f) + 0.3
    for ext in (None, wrenches_for(robot, len(name))):
        a = robot.inverse_dynamics_partials(x, u, du, ext)
        d = robot.inverse_dynamics_partials(x, u, du, ext, method="dual")
        assert_rel_close(a.df_dx, d.df_dx, "dID/dx analytic vs dual", rtol=1e-12)
        assert_rel_close(a.df_du, d.df_du, "dID/du analytic vs dual", rtol=1e-12)
        assert np.all(a.df_dx[:, :3] == 0.0)
        a = robot.forward_dynamics_derivatives(x, u, f, wrenches=ext)
        d = robot.forward_dynamics_derivatives(x, u, f, wrenches=ext, method="dual")
        for got, ref, what in zip(a, d, ("ddu_dx", "ddu_du", "ddu_df")):
            assert_rel_close(got, ref, f"{what} analytic vs dual", rtol=1e-11)
    for inputs in ("joints", "all"):
        a = robot.linearize(x, u, f, inputs=inputs)
        d = robot.linearize(x, u, f, inputs=inputs, method="dual")
        assert_rel_close(a.A, d.A, "A analytic vs dual", rtol=1e-11)
        assert_rel_close(a.B, d.B, "B analytic vs dual", rtol=1e-11)


@pytest.mark.parametrize("name", ["seed2", "seed14", "seed28", "branched", "spatial6"])
def test_inverse_dynamics_partials_match_finite_differences(name):
    robot, x, u, f = case(name)
    nu = robot.nu
    du = robot.forward_dynamics(x, u, f)
    ext = wrenches_for(robot, 3)
    p = robot.inverse_dynamics_partials(x, u, du, ext)
    fd_x = tangent_fd(lambda y: robot.inverse_dynamics(y, u, du, ext), x, nu)
    fd_u = np.stack([(robot.inverse_dynamics(x, u + H_STEP * e, du, ext) - robot.inverse_dynamics(x, u - H_STEP * e, du, ext))
                     / (2 * H_STEP) for e in np.eye(nu)], axis=-1)
    assert_rel_close(p.df_dx, fd_x, "dID/dx vs central differences", rtol=RTOL_FD)
    assert_rel_close(p.df_du, fd_u, "dID/du vs central differences", rtol=RTOL_FD)


@pytest.mark.parametrize("name", ["seed6", "seed22", "branched"])
def test_forward_dynamics_derivatives_with_wrenches_match_finite_differences(name):
    robot, x, u, f = case(name)
    nu = robot.nu
    ext = wrenches_for(robot, 5)
    d = robot.forward_dynamics_derivatives(x, u, f, wrenches=ext)
    fd_x = tangent_fd(lambda y: robot.forward_dynamics(y, u, f, wrenches=ext), x, nu)
    fd_u = np.stack([(robot.forward_dynamics(x, u + H_STEP * e, f, wrenches=ext) - robot.forward_dynamics(x, u - H_STEP * e, f, wrenches=ext))
                     / (2 * H_STEP) for e in np.eye(nu)], axis=-1)
    assert_rel_close(d.ddu_dx, fd_x, "d(du)/dx with wrenches vs central differences", rtol=RTOL_FD)
    assert_rel_close(d.ddu_du, fd_u, "d(du)/du with wrenches vs central differences", rtol=RTOL_FD)
    # The wrenches change the point of linearization, not H⁻¹.
    assert_rel_close(d.ddu_df @ robot.mass_matrix(x), np.eye(nu), "H^-1 H", rtol=1e-10)


def test_bad_method_and_wrench_raise_spacearm_errors():
    robot, x, u, f = case("spatial6")
    with pytest.raises(spacearm.ArgumentError, match="method must be 'analytic' or 'dual'"):
        robot.forward_dynamics_derivatives(x, u, f, method="numeric")
    with pytest.raises(spacearm.ArgumentError, match="method must be"):
        robot.linearize(x, u, f, method="fd")
    with pytest.raises(spacearm.NotFoundError):
        robot.inverse_dynamics_partials(x, u, u, [spacearm.ExternalWrench(body="no_such_body")])
    with pytest.raises(spacearm.SpacearmTypeError):
        robot.forward_dynamics_derivatives(x, u, f, wrenches=[(1, 2, 3)])
    with pytest.raises(spacearm.ShapeError):
        robot.inverse_dynamics_partials(x, u, u[:-1])
