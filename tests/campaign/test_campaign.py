"""Inertia-uncertainty campaigns: sampling, execution back ends, files, CLI.

References used here are independent of the campaign code: the closed-form statistics of the
log-normal scales, a hand-built perturbed plant's total mass and CM, the computed-torque
property that an exact model tracks to integration accuracy, and reruns of the same samples by
other back ends (in-process vs processes vs a Dask LocalCluster), which must agree bit for bit.
"""

import json

import numpy as np
import pytest

import spacearm
from spacearm.campaign import (
    FAILED,
    METRIC_NAMES,
    OK,
    PARAMETER_NAMES,
    PENDING,
    CampaignResult,
    CampaignSpec,
    Perturbations,
    Scenario,
    run_campaign,
)
from spacearm.io.model_file import dumps_toml

QUICK = Scenario(duration=0.6, dt=5e-3, q_offset=0.4)


@pytest.fixture(scope="module")
def planar4():
    return spacearm.presets.planar4()


# -- sampling ------------------------------------------------------------------------------

def test_draws_are_reproducible_and_per_index():
    p = Perturbations(payload_mass_max=10.0)
    a = p.draw(7, 3)
    assert a == p.draw(7, 3)
    assert a != p.draw(7, 4) and a != p.draw(8, 3)
    assert set(a) == set(PARAMETER_NAMES)


def test_draw_statistics_match_the_stated_distributions():
    p = Perturbations(base_mass_sigma=0.05, base_inertia_sigma=0.2, link_mass_sigma=0.0,
                      slosh_fraction_max=0.1, slosh_offset=0.4, payload_mass_max=5.0)
    draws = [p.draw(1, i) for i in range(4000)]
    log_mass = np.log([d["base_mass_scale"] for d in draws])
    log_inertia = np.log([d["base_inertia_scale"] for d in draws])
    # log of a log-normal scale is N(0, σ²): mean within 4 standard errors, std within 5 %.
    assert abs(log_mass.mean()) < 4 * 0.05 / np.sqrt(4000)
    assert abs(log_mass.std() / 0.05 - 1) < 0.05
    assert abs(log_inertia.std() / 0.2 - 1) < 0.05
    assert all(d["link_mass_scale"] == 1.0 for d in draws)
    offsets = np.array([[d["slosh_offset_x"], d["slosh_offset_y"], d["slosh_offset_z"]] for d in draws])
    np.testing.assert_allclose(np.linalg.norm(offsets, axis=1), 0.4, rtol=1e-12)
    assert np.all(np.abs(offsets.mean(axis=0)) < 0.03)  # uniform on the sphere: zero mean
    fractions = np.array([d["slosh_fraction"] for d in draws])
    payloads = np.array([d["payload_mass"] for d in draws])
    assert 0 <= fractions.min() and fractions.max() < 0.1 and abs(fractions.mean() - 0.05) < 0.003
    assert 0 <= payloads.min() and payloads.max() < 5.0 and abs(payloads.mean() - 2.5) < 0.15


@pytest.mark.parametrize("kwargs", [
    {"base_mass_sigma": -0.1}, {"slosh_fraction_max": 1.0}, {"payload_mass_max": float("nan")},
    {"slosh_offset": float("inf")},
])
def test_bad_perturbations_are_refused(kwargs):
    with pytest.raises(ValueError, match="Perturbations"):
        Perturbations(**kwargs)


@pytest.mark.parametrize("kwargs", [
    {"controller": "lqr"}, {"duration": 0.0}, {"dt": -1e-3}, {"dt": 5.0, "duration": 1.0},
    {"motion_fraction": 1.5}, {"q_goal": (0.1, float("nan"))},
])
def test_bad_scenarios_are_refused(kwargs):
    with pytest.raises(ValueError, match="Scenario"):
        Scenario(**kwargs)


def test_bad_campaign_arguments(planar4, tmp_path):
    with pytest.raises(ValueError, match="samples"):
        run_campaign(planar4, 0, workers=0, progress=False)
    with pytest.raises(ValueError, match="samples"):
        run_campaign(planar4, workers=0, progress=False)
    with pytest.raises(ValueError, match="workers"):
        run_campaign(planar4, 2, workers=-1, progress=False)
    with pytest.raises(ValueError, match=".npz"):
        run_campaign(planar4, 2, workers=0, out=tmp_path / "r.csv", progress=False)
    with pytest.raises(ValueError, match="q_goal must have N = 4"):
        run_campaign(planar4, 2, workers=0, scenario=Scenario(q_goal=(0.1, 0.2)), progress=False)
    with pytest.raises(ValueError, match="backend must be one of"):
        run_campaign(planar4, 2, backend="gpu", progress=False)
    with pytest.raises(ValueError, match="needs a scheduler"):
        run_campaign(planar4, 2, backend="dask", progress=False)
    with pytest.raises(ValueError, match="needs workers >= 1"):
        run_campaign(planar4, 2, workers=0, backend="threads", progress=False)
    with pytest.raises(ValueError, match="batch_size"):
        run_campaign(planar4, 2, batch_size=0, progress=False)
    with pytest.raises(ValueError, match="worker_timeout is the Dask watchdog"):
        run_campaign(planar4, 2, worker_timeout=5, progress=False)


# -- the perturbed plant ---------------------------------------------------------------------

def test_perturbed_plant_mass_and_cm_against_a_hand_sum(planar4):
    from spacearm import control
    from spacearm.campaign.scenario import with_payload

    d = planar4.describe()
    base_mass = d["base"]["mass"]
    link_mass = sum(link["mass"] for link in d["links"])
    plant = with_payload(control.perturbed_model(planar4, base_mass_scale=1.1, base_inertia_scale=0.9,
                                                 link_mass_scale=1.05, slosh_fraction=0.05,
                                                 slosh_offset=(0.3, -0.2, 0.1)), 4.0)
    assert plant.n_dof == planar4.n_dof
    assert plant.total_mass == pytest.approx(1.1 * base_mass + 1.05 * link_mass + 4.0, rel=1e-12)
    # The CM of the plant at the same configuration, from the hand sum of its parts: the nominal
    # links scaled, the base mass (of which 5 % sits 0.3,-0.2,0.1 from the nominal base CM) and the
    # payload at the end effector. Both plants are placed with the nominal base CM at the origin.
    x = planar4.neutral_configuration()
    kin = planar4.forward_kinematics(x)
    link_cm = sum(link["mass"] * 1.05 * kin.com_in_world[i + 1] for i, link in enumerate(d["links"]))
    base_cm = 1.1 * base_mass * 0.05 * np.array([0.3, -0.2, 0.1])
    payload_cm = 4.0 * planar4.point_position(x)
    expected = (link_cm + base_cm + payload_cm) / plant.total_mass
    xp = plant.neutral_configuration()
    shift = 0.05 * np.array([0.3, -0.2, 0.1])  # the plant's base CM sits here in nominal base axes
    xp[0:3] = shift
    np.testing.assert_allclose(plant.center_of_mass(xp), expected, atol=1e-12)


# -- running ---------------------------------------------------------------------------------

def test_exact_model_tracks_and_errors_cost_tracking(planar4):
    from spacearm.campaign import evaluate

    exact = {name: 0.0 for name in PARAMETER_NAMES}
    exact.update(base_mass_scale=1.0, base_inertia_scale=1.0, link_mass_scale=1.0)
    m_exact = evaluate(planar4, QUICK, exact)
    wrong = dict(exact, base_mass_scale=1.3, base_inertia_scale=0.7, link_mass_scale=1.2)
    m_wrong = evaluate(planar4, QUICK, wrong)
    # Computed torque on an exact model tracks to integration accuracy; a 20-30 % error does not.
    assert m_exact["tracking_error_max"] < 1e-6
    assert m_wrong["tracking_error_max"] > 1e3 * max(m_exact["tracking_error_max"], 1e-9)
    # The base turns in reaction to the arm either way (floating mode, no wheels).
    assert m_exact["attitude_excursion_max"] > 0.1


def test_backends_agree_bit_for_bit_and_files_round_trip(planar4, tmp_path):
    serial = run_campaign(planar4, 4, seed=3, scenario=QUICK, workers=0, progress=False)
    assert serial.n_ok == 4 and serial.n_failed == 0
    assert np.all(np.isfinite(serial.metrics))
    # Every sample is a different plant: the tracking errors differ.
    assert np.unique(serial.metric("tracking_error_max")).size == 4
    threads = run_campaign(planar4, 4, seed=3, scenario=QUICK, workers=2, batch_size=3, progress=False,
                           out=tmp_path / "c.npz")
    procs = run_campaign(planar4, 4, seed=3, scenario=QUICK, workers=2, backend="processes", progress=False)
    for other in (threads, procs):
        np.testing.assert_array_equal(other.metrics, serial.metrics)
        np.testing.assert_array_equal(other.params, serial.params)
    assert procs.run["backend"] == "processes"
    loaded = CampaignResult.load(tmp_path / "c.npz")
    np.testing.assert_array_equal(loaded.metrics, serial.metrics)
    assert loaded.run["backend"] == "threads" and loaded.run["samples_run"] == 4
    raw = np.load(tmp_path / "c.npz")  # readable without spacearm
    assert list(raw["metric_names"]) == list(METRIC_NAMES)
    assert json.loads(str(raw["spec_json"]))["samples"] == 4


def test_resume_runs_only_the_missing_samples(planar4, tmp_path):
    out = tmp_path / "r.npz"
    full = run_campaign(planar4, 5, seed=1, scenario=QUICK, workers=0, progress=False, out=out)
    partial = CampaignResult.load(out)
    partial.status[[1, 3]] = PENDING
    partial.metrics[[1, 3]] = np.nan
    partial.save(out)
    seen = []
    resumed = run_campaign(planar4, 5, seed=1, scenario=QUICK, workers=0, out=out,
                           progress=lambda done, total: seen.append((done, total)))
    assert resumed.run["samples_run"] == 2
    assert seen == [(4, 5), (5, 5)]
    np.testing.assert_array_equal(resumed.metrics, full.metrics)
    # A different campaign refuses to resume this file ...
    with pytest.raises(spacearm.SpacearmError, match="different campaign"):
        run_campaign(planar4, 5, seed=2, scenario=QUICK, workers=0, progress=False, out=out)
    # ... unless told to overwrite it.
    other = run_campaign(planar4, 2, seed=2, scenario=QUICK, workers=0, progress=False, out=out, resume=False)
    assert CampaignResult.load(out).n_samples == 2 and other.n_ok == 2


def test_failed_samples_are_recorded_not_fatal(planar4, tmp_path, monkeypatch):
    import spacearm.campaign.scenario as scenario_module

    real = scenario_module.evaluate

    def flaky(nominal, scenario, params):
        if params["base_mass_scale"] > 1.0:
            raise spacearm.SingularError("synthetic failure of a heavy plant")
        return real(nominal, scenario, params)

    monkeypatch.setattr(scenario_module, "evaluate", flaky)
    result = run_campaign(planar4, 6, seed=0, scenario=QUICK, workers=0, progress=False, out=tmp_path / "f.npz")
    heavy = result.parameter("base_mass_scale", ok_only=False) > 1.0
    assert 0 < heavy.sum() < 6  # the seed gives both kinds
    np.testing.assert_array_equal(result.status, np.where(heavy, FAILED, OK))
    assert all("synthetic failure" in msg and "SingularError" in msg for msg in result.failures().values())
    assert np.all(np.isnan(result.metrics[heavy])) and np.all(np.isfinite(result.metrics[~heavy]))
    assert "failed" in result.table()
    # Every metric row carries its unit (issue 37 item 7: the table had none).
    from spacearm.campaign.scenario import METRIC_UNITS

    rows = [line for line in result.table().splitlines() if line.startswith("| ") and "---" not in line][1:]
    assert len(rows) == len(result.metric_names)
    for name, row in zip(result.metric_names, rows):
        assert row.startswith(f"| {name} [{METRIC_UNITS[name]}] |"), row


def test_failures_in_worker_processes_are_recorded(planar4):
    # A spec whose goal has the wrong length (bypassing run_campaign's early check) makes every
    # sample fail inside the worker; the campaign still completes and says why.
    spec = CampaignSpec(dumps_toml(planar4), 2, 0, Perturbations(), Scenario(duration=0.2, dt=0.01, q_goal=(0.1,)))
    for backend in ("threads", "processes"):
        result = run_campaign(spec, workers=2, backend=backend, progress=False)
        assert result.n_failed == 2
        assert all("q_goal must have N = 4" in m for m in result.failures().values())


def test_dask_local_cluster_matches_in_process(planar4):
    distributed = pytest.importorskip("distributed")
    serial = run_campaign(planar4, 4, seed=5, scenario=QUICK, workers=0, progress=False)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            by_client = run_campaign(planar4, 4, seed=5, scenario=QUICK, scheduler=client, progress=False)
        by_address = run_campaign(planar4, 4, seed=5, scenario=QUICK, scheduler=cluster.scheduler_address,
                                  progress=False)
    for result in (by_client, by_address):
        assert result.run["backend"] == "dask"
        np.testing.assert_array_equal(result.metrics, serial.metrics)
    assert by_client.run["workers"] == 2


def test_cli_campaign_writes_results_and_figure(tmp_path, capsys):
    from spacearm.cli import main

    out, fig = tmp_path / "cli.npz", tmp_path / "cli.png"
    code = main(["campaign", "planar4", "--samples", "3", "--workers", "0", "--duration", "0.4", "--dt", "0.01",
                 "--out", str(out), "--plot", str(fig), "--no-progress"])
    text = capsys.readouterr().out
    assert code == 0
    assert CampaignResult.load(out).n_ok == 3
    assert fig.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "tracking_error_max" in text and "3 samples ran" in text
    assert main(["campaign", "planar4", "--samples", "0", "--workers", "0", "--out", str(out)]) == 2
    # The watchdog's timeout is for a Dask cluster only: a clear error, not a silently ignored option.
    assert main(["campaign", "planar4", "--samples", "2", "--worker-timeout", "5", "--out", str(out)]) == 2
    assert "worker_timeout is the Dask watchdog's" in capsys.readouterr().err


def test_a_campaign_whose_every_sample_fails_exits_2(tmp_path, monkeypatch, capsys):
    import spacearm.campaign.scenario as scenario_module

    def failing(nominal, scenario, params):
        raise spacearm.SingularError("synthetic failure of every plant")

    from spacearm.cli import main

    monkeypatch.setattr(scenario_module, "evaluate", failing)
    out = tmp_path / "all_failed.npz"
    code = main(["campaign", "planar4", "--samples", "3", "--workers", "0", "--duration", "0.4", "--dt", "0.01",
                 "--no-progress", "--out", str(out)])
    assert code == 2
    err = capsys.readouterr().err
    assert "every sample of the campaign failed (3 of 3" in err and "synthetic failure" in err
    assert out.exists()  # the record of the failures is kept
    # a campaign that resumes into a file of another campaign names the CLI's option
    code = main(["campaign", "planar4", "--samples", "4", "--workers", "0", "--no-progress", "--out", str(out)])
    assert code == 2 and "--no-resume" in capsys.readouterr().err
