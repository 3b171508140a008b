"""Dask campaigns when the cluster fails: batches lost with a scheduler, and the watchdog that stops
a campaign left without workers.

The rule under test (docs/campaigns.md, "Resuming and failures"): samples the infrastructure loses
are not recorded, stay pending, and a plain rerun (no ``retry_failed``) runs them, giving what one
uninterrupted in-process run gives, bit for bit. Each test runs on a LocalCluster of one worker
process, bounded by the watchdog's and the client's short timeouts.
"""

import numpy as np
import pytest

import spacearm
from spacearm.campaign import CampaignResult, Scenario, run_campaign
from spacearm.errors import CampaignError

distributed = pytest.importorskip("distributed")

# ~30 ms a sample, one sample per task: the cluster cannot finish before it is broken.
SLOW = Scenario(duration=2.0, dt=1e-3, q_offset=0.4)
SAMPLES = 24


@pytest.fixture(scope="module")
def reference():
    return run_campaign(spacearm.presets.planar4(), SAMPLES, seed=2, scenario=SLOW, workers=0, progress=False)


def _cluster():
    return distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None)


def _rerun_completes_it(out, saved, reference):
    resumed = run_campaign(spacearm.presets.planar4(), SAMPLES, seed=2, scenario=SLOW, workers=0, out=out,
                           progress=False)
    assert resumed.n_ok == SAMPLES and resumed.run["samples_run"] == saved.n_pending
    np.testing.assert_array_equal(resumed.metrics, reference.metrics)


def test_watchdog_stops_a_campaign_whose_cluster_has_no_worker_left(tmp_path, reference):
    out = tmp_path / "watchdog.npz"
    with _cluster() as cluster, distributed.Client(cluster) as client:

        def lose_every_worker(done, total):
            if done == 1:
                cluster.scale(0)  # the cluster stays up, with nobody to run the tasks

        with pytest.raises(CampaignError, match=r"no live Dask worker for 2 s \(worker_timeout\)") as info:
            run_campaign(spacearm.presets.planar4(), SAMPLES, seed=2, scenario=SLOW, scheduler=client, batch_size=1,
                         worker_timeout=2, out=out, progress=lose_every_worker)
    assert "stay pending" in str(info.value) and str(out) in str(info.value)
    saved = CampaignResult.load(out)
    assert saved.n_failed == 0 and saved.n_ok >= 1 and saved.n_pending == saved.run["samples_lost"] > 0
    _rerun_completes_it(out, saved, reference)


def test_samples_lost_with_the_scheduler_stay_pending(tmp_path, reference):
    import multiprocessing

    out = tmp_path / "scheduler.npz"
    cluster = _cluster()
    try:
        with distributed.Client(cluster, timeout="2s") as client:

            def lose_the_scheduler(done, total):
                if done == 1:
                    cluster.sync(cluster.scheduler.close)

            with pytest.raises(CampaignError, match="did not run because the dask back end failed"):
                run_campaign(spacearm.presets.planar4(), SAMPLES, seed=2, scenario=SLOW, scheduler=client,
                             batch_size=1, worker_timeout=30, out=out, progress=lose_the_scheduler)
    finally:
        # A cluster whose scheduler is gone cannot close its workers through it: give it a few
        # seconds, then end this test's worker processes directly.
        try:
            cluster.close(timeout=3)
        except Exception:  # noqa: BLE001 — the close is expected to time out
            pass
        for child in multiprocessing.active_children():
            child.kill()
    saved = CampaignResult.load(out)
    assert saved.n_failed == 0 and saved.n_ok >= 1 and saved.n_pending == saved.run["samples_lost"] > 0
    assert "scheduler-connection-lost" in saved.run["lost_reason"]
    _rerun_completes_it(out, saved, reference)


def test_a_cluster_without_workers_stops_after_the_timeout():
    with distributed.LocalCluster(n_workers=0, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            with pytest.raises(CampaignError, match=r"4 sample\(s\) did not run .*no live Dask worker for 1 s"):
                run_campaign(spacearm.presets.planar4(), 4, scenario=SLOW, scheduler=client, worker_timeout=1,
                             progress=False)
