"""The capture's approach ends at the grasp located by the core (a gap stop condition,
docs/simulation-core.md "Events"), with no warning, and equals an independent reference: the
same approach without events on a 100x finer output grid, the gap crossing located by bisection
on its records (linear interpolation between samples), then a run of exactly that duration for
the state at the grasp."""

import warnings

import numpy as np
import pytest

import spacearm
from spacearm import presets
from spacearm.capture import Target, capture, grasp_impulse
from spacearm.capture.impact import CAPTURE_TOLERANCE
from spacearm.control import ResolvedMotionRate
from spacearm.sim.events import StopAtGap, StopAtTime


def _readme_capture():
    """The README's capture (spatial6, 50 kg target, inertia 4,5,6, spin 0,0,0.2, floating), as
    cli/capture.py builds it."""
    robot = presets.spatial6()
    x0 = robot.neutral_configuration()
    ee = robot.point_position(x0)
    outward = (ee - x0[:3]) / np.linalg.norm(ee - x0[:3])
    at = ee + 0.6 * outward
    to_ee = ee - at
    grasp = to_ee * (np.linalg.norm(to_ee) - 0.1) / np.linalg.norm(to_ee)
    target = Target(50.0, np.array([4.0, 5.0, 6.0]), grasp_points={"grasp": grasp})
    return robot, x0, target, target.state(position=at, angular_velocity=np.array([0.0, 0.0, 0.2]))


@pytest.fixture(scope="module")
def readme():
    robot, x0, target, s0 = _readme_capture()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = capture(robot, target, s0, x0=x0, mode="floating", detumble_time=20.0)
    return robot, x0, target, s0, res, caught


def test_the_approach_ends_at_the_grasp_without_a_warning(readme):
    robot, x0, target, s0, res, caught = readme
    assert [str(w.message) for w in caught] == []
    approach = res.t[res.phase == 0]
    t_grasp = res.phase_start("capture")
    # The approach's last sample is the grasp, off the dt grid, within one dt of the sample
    # where the grasp points were first within the tolerance.
    assert approach[-1] == t_grasp
    assert 1.0 < t_grasp < 1.1 and abs(t_grasp / 0.01 - round(t_grasp / 0.01)) > 1e-6
    assert np.all(np.diff(approach) > 0) and approach[-1] - approach[-2] <= 0.01
    # The gap there is the tolerance (the event's value), from the records and the target's states.
    body, offset = robot.resolve_point(None)
    k = len(approach) - 1
    gap = np.linalg.norm(robot.point_position(res.x[k], (body, offset)) - target.body.point_position(res.target[k, :7], target.point("grasp")))
    assert gap <= CAPTURE_TOLERANCE and gap == pytest.approx(CAPTURE_TOLERANCE, rel=1e-9)
    assert res.impact.gap == pytest.approx(gap, abs=1e-15)


def test_the_grasp_equals_a_fine_grid_reference_without_events(readme):
    robot, x0, target, s0, res, _ = readme
    body, offset = robot.resolve_point(None)
    dt, rtol = 0.01, 1e-10
    # The approach's controller exactly as capture() builds it (defaults of capture()).
    reference = target.free_body(s0, "grasp", step=0.5 * dt, point=None)
    rmrc = lambda: ResolvedMotionRate(reference, gain=2.0, max_damping=0.05, velocity_gain=5.0, point=None, max_joint_rate=1.0)  # noqa: E731
    kw = dict(x0=x0, mode="floating", integrator="dopri5", rtol=rtol, atol=rtol * 1e-2)
    fine_dt = dt / 100
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # no stop: the run may end far from its goal
        fine = spacearm.simulate(robot, 1.2, dt=fine_dt, controller=rmrc(), **kw)
    gaps = np.linalg.norm(robot.point_position(fine.x, (body, offset))
                          - target.body.point_position(reference.states(fine.t)[:, :7], target.point("grasp")), axis=1)
    j = int(np.nonzero(gaps <= CAPTURE_TOLERANCE)[0][0])
    # Bisection on the records: the crossing between samples j-1 and j, the gap linear between them.
    lo, hi = fine.t[j - 1], fine.t[j]
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        g = np.interp(mid, fine.t[j - 1:j + 1], gaps[j - 1:j + 1])
        lo, hi = (mid, hi) if g > CAPTURE_TOLERANCE else (lo, mid)
    t_ref = hi
    t_grasp = res.phase_start("capture")
    # Linear interpolation over 1e-4 s: its error is ~ g'' h² / 8 / |g'| ~ 1e-9 s.
    assert t_grasp == pytest.approx(t_ref, abs=1e-8)
    assert t_grasp < fine.t[j] + 1e-12 and t_grasp <= round(t_grasp / dt + 0.5) * dt  # before the old grid sample
    # The state at the reference's grasp time: a run of exactly that duration; its impulse.
    at = spacearm.simulate(robot, t_ref, dt=dt, controller=rmrc(), **kw)
    s_ref = reference.states(np.array([t_ref]))[0]
    imp = grasp_impulse(robot, at.x[-1], at.u[-1], target, s_ref, grasp="grasp", kind="rigid", capture_tolerance=2 * CAPTURE_TOLERANCE)
    scale = np.abs(imp.impulse).max()
    assert np.abs(res.impact.impulse - imp.impulse).max() <= 1e-6 * scale


def test_stop_conditions_through_simulate():
    robot, x0, target, s0 = _readme_capture()
    reference = target.free_body(s0, "grasp", step=0.005)
    c = ResolvedMotionRate(reference, gain=2.0, max_damping=0.05, velocity_gain=5.0, max_joint_rate=1.0)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        tr = spacearm.simulate(robot, 8.0, x0=x0, dt=0.01, integrator="dopri5", rtol=1e-10, controller=c,
                               stop=[StopAtTime(5.0), StopAtGap(None, 0.05)])
    assert [str(w.message) for w in caught] == []
    stop = tr.meta["stop"]
    assert stop["condition"] == 1 and stop["kind"] == "gap" and stop["t"] == tr.t[-1] < 1.04
    assert stop["value"] == pytest.approx(0.05, rel=1e-9) and stop["value"] <= 0.05
    # Without the stop, the same run warns at its natural end (its goal judged there).
    with pytest.warns(RuntimeWarning, match="out of reach"):
        full = spacearm.simulate(robot, 8.0, x0=x0, dt=0.01, integrator="dopri5", rtol=1e-10, controller=c)
    assert full.meta["stop"] is None
    # The samples before the stop are the full run's (the same steps, the same dense output).
    n = len(tr.t) - 1
    np.testing.assert_array_equal(tr.t[:n], full.t[:n])
    np.testing.assert_allclose(tr.x[:n], full.x[:n], rtol=0, atol=1e-13)


def test_bad_stop_arguments_are_refused():
    robot = presets.spatial6()
    with pytest.raises(spacearm.ArgumentError, match="stop takes"):
        spacearm.simulate(robot, 0.1, stop=[1.0])
    with pytest.raises(spacearm.ArgumentError, match="t must be finite and > 0"):
        StopAtTime(-1.0)
    with pytest.raises(spacearm.ArgumentError, match="tracks no point"):
        spacearm.simulate(robot, 0.1, stop=StopAtGap(None, 0.01))
    # The step-by-step simulator cannot stop early: its door refuses the options.
    from spacearm import _core

    options = _core.RunOptions(integrator="rk4", stop=[_core.StopCondition.time(0.5)])
    with pytest.raises(spacearm.ArgumentError, match="the Simulator does not take stop conditions"):
        _core.Simulator(robot.core_model, options)
