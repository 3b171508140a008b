"""Saturation and singularity events of a CMG cluster (docs/cmg.md, "Saturation and singularity
events"; the core's record stop condition, sim/stop.rs and sim/events.rs): the time the core
locates within the step where ``cmg_envelope_fraction`` rises to a value, or ``cmg_measure`` falls
to one, equals the crossing found independently on a 1e-5 s output grid of the same run without
the condition (linear interpolation between the samples), under DOPRI5 (dense output) and RK4
(the step re-taken); bad conditions are refused with what was expected."""

from __future__ import annotations

import numpy as np
import pytest

import spacearm
from spacearm.control import CmgSteering
from spacearm.errors import ArgumentError
from spacearm.sim.events import StopAtRecord

from cmg_models import pyramid_sat  # noqa: E402

# The base spins at 2.5 rad/s about z and the attitude law stops it, the cluster taking its
# momentum (I_z ω > 38 · 2.5 = 95 N m s, more than the pyramid's 4 h sin β = 81.6 N m s along z with
# h = 25 N m s): the envelope fraction rises to 1 (saturation) and the measure falls to 0 (the
# saturation singularity) within 0.6 s.
W0 = [0.0, 0.0, 2.5]
DURATION = 0.6


def _run(robot, **kw):
    u0 = robot.cmg_velocity(500.0)
    u0[3:6] = W0
    return spacearm.simulate(robot, DURATION, u0=u0, mode="rotation-floating", controller=CmgSteering([0, 0, 0, 1], kp=20.0, kd=40.0), **kw)


@pytest.fixture(scope="module")
def robot():
    return pyramid_sat(arm=False)


@pytest.fixture(scope="module")
def fine(robot):
    """The run without conditions, sampled every 1e-5 s on DOPRI5's dense output."""
    return _run(robot, dt=1e-5, integrator="dopri5")


def _crossing(traj, name, value, rising):
    """The first time where the record reaches ``value``, by linear interpolation between the
    two samples around it."""
    r = getattr(traj, name)
    g = value - r if rising else r - value
    k = int(np.argmax(g <= 0))
    assert k > 0 and g[k] <= 0 < g[k - 1]
    return traj.t[k - 1] + (traj.t[k] - traj.t[k - 1]) * g[k - 1] / (g[k - 1] - g[k])


@pytest.mark.parametrize("name, value, rising", [("cmg_envelope_fraction", 0.9, True), ("cmg_measure", 0.1, False)])
def test_the_event_is_located_where_a_fine_scan_of_the_same_run_finds_the_crossing(robot, fine, name, value, rising):
    t_scan = _crossing(fine, name, value, rising)
    cond = StopAtRecord(name, above=value) if rising else StopAtRecord(name, below=value)
    located = {}
    for integrator, dt in (("dopri5", 0.05), ("rk4", 1e-3)):
        traj = _run(robot, dt=dt, integrator=integrator, stop=cond)
        stop = traj.meta["stop"]
        assert stop["condition"] == 0 and stop["kind"] == "record"
        # The last sample is the event's; the record there is the threshold (reached, not passed
        # by more than the located time's rounding), as the meta says.
        assert traj.t[-1] == stop["t"] and 0.0 < stop["t"] < DURATION
        r_end = getattr(traj, name)[-1]
        assert r_end == pytest.approx(value, abs=1e-12) and r_end == pytest.approx(stop["value"], abs=1e-15)
        assert (r_end >= value) if rising else (r_end <= value)
        # Before it, the record had not reached the threshold.
        before = getattr(traj, name)[:-1]
        assert np.all(before < value) if rising else np.all(before > value)
        located[integrator] = stop["t"]
        # Off the sample grid: located within the step, not at a sample.
        assert abs(stop["t"] / dt - round(stop["t"] / dt)) > 1e-6
    # DOPRI5's dense output (rtol 1e-9) and RK4's re-taken 1 ms step both carry the step error;
    # the scan's linear interpolation over 1e-5 s errs by ~(1e-5)² |r''|/|r'| ~ 1e-10 s.
    assert located["dopri5"] == pytest.approx(t_scan, abs=1e-8)
    assert located["rk4"] == pytest.approx(t_scan, abs=1e-8)


def test_the_first_of_two_events_wins_and_the_samples_before_it_are_the_runs_without_it(robot, fine):
    """Saturation (fraction ≥ 0.9) comes before the singularity (measure ≤ 0.1) in this run, as
    the scan says; listed second, it still ends the run."""
    t_sat, t_sing = _crossing(fine, "cmg_envelope_fraction", 0.9, True), _crossing(fine, "cmg_measure", 0.1, False)
    assert t_sat < t_sing
    free = _run(robot, dt=0.01, integrator="dopri5")
    traj = _run(robot, dt=0.01, integrator="dopri5",
                stop=[StopAtRecord("cmg_measure", below=0.1), StopAtRecord("cmg_envelope_fraction", above=0.9)])
    assert traj.meta["stop"]["condition"] == 1 and traj.meta["stop"]["t"] == pytest.approx(t_sat, abs=1e-8)
    n = len(traj.t) - 1
    np.testing.assert_array_equal(traj.x[:n], free.x[:n])
    np.testing.assert_array_equal(traj.cmg_measure[:n], free.cmg_measure[:n])


def test_a_condition_that_holds_at_the_start_stops_the_run_there(robot):
    traj = _run(robot, dt=0.01, integrator="rk4", stop=StopAtRecord("cmg_measure", below=2.0))
    assert len(traj.t) == 1 and traj.meta["stop"]["t"] == 0.0
    assert traj.meta["stop"]["value"] == pytest.approx(32 / 27, rel=1e-12)  # the pyramid at δ = 0 (docs/cmg.md)


def test_bad_record_conditions_are_refused_with_what_was_expected(robot):
    with pytest.raises(ArgumentError, match=r"one of the records .*cmg_envelope_fraction.*got \"cmg_torque\""):
        StopAtRecord("cmg_torque", above=0.5)
    with pytest.raises(ArgumentError, match="exactly one of above"):
        StopAtRecord("cmg_measure", above=0.5, below=0.1)
    with pytest.raises(ArgumentError, match="neither"):
        StopAtRecord("cmg_measure")
    with pytest.raises(ArgumentError, match="finite"):
        StopAtRecord("cmg_measure", below=float("nan"))
    # A model with no CMGs: the run refuses the condition before its first step.
    with pytest.raises(ArgumentError, match=r"stop condition 0 \(record\) watches \"cmg_measure\".*no control-moment gyros"):
        spacearm.simulate(spacearm.presets.spatial6(), 0.1, stop=StopAtRecord("cmg_measure", below=0.1))
    # A record the controller does not give.
    with pytest.raises(ArgumentError, match="attitude_error.*reports no attitude error"):
        spacearm.simulate(robot, 0.1, stop=StopAtRecord("attitude_error", above=0.1))
    with pytest.raises(ArgumentError, match="takes StopAtTime, StopAtGap, StopAtRecord"):
        spacearm.simulate(robot, 0.1, stop=["cmg_measure"])
