"""Campaigns on native threads: batches of rollouts against the per-sample reference.

The reference is the in-process path (``workers=0``): one :func:`spacearm.simulate` per sample
and its metrics. The thread back end flies the same samples as batched rollouts on several
threads; every metric must agree bit for bit whatever the thread count and batch size, failures
must land on the same samples, and what the back end loses (a batch that fails outside its
samples, Ctrl-C) must stay pending for a plain rerun.
"""

import numpy as np
import pytest

import spacearm
from spacearm.campaign import FAILED, OK, PENDING, CampaignResult, Perturbations, Scenario, run_campaign
from spacearm.errors import CampaignError

QUICK = Scenario(duration=0.6, dt=5e-3, q_offset=0.4)
ERRORS = Perturbations(payload_mass_max=5.0)


@pytest.fixture(scope="module")
def spatial6():
    return spacearm.presets.spatial6()


@pytest.fixture(scope="module")
def reference(spatial6):
    return run_campaign(spatial6, 12, seed=9, perturbations=ERRORS, scenario=QUICK, workers=0, progress=False)


@pytest.mark.parametrize("workers, batch_size", [(1, None), (2, None), (2, 5), (3, 1)])
def test_threads_match_the_per_sample_reference_bit_for_bit(spatial6, reference, workers, batch_size):
    result = run_campaign(spatial6, 12, seed=9, perturbations=ERRORS, scenario=QUICK, workers=workers,
                          batch_size=batch_size, progress=False)
    assert result.run["backend"] == "threads" and result.run["workers"] == workers
    assert reference.n_ok == 12 and np.unique(reference.metric("tracking_error_max")).size == 12
    np.testing.assert_array_equal(result.status, reference.status)
    np.testing.assert_array_equal(result.params, reference.params)
    np.testing.assert_array_equal(result.metrics, reference.metrics)
    assert np.all(result.seconds > 0)


def test_diverging_samples_fail_on_the_same_samples_with_the_same_reason(spatial6):
    # Gains too stiff for the step (dt·sqrt(kp) = 2.8, at RK4's stability limit): whether a plant's
    # tracking diverges depends on its inertia errors (the reference run decides which; this seed
    # gives both kinds).
    stiff = Scenario(duration=1.0, dt=0.02, kp=20000.0, kd=10.0)
    errors = Perturbations(base_mass_sigma=0.3, base_inertia_sigma=0.3, link_mass_sigma=0.5)
    kwargs = dict(seed=1, perturbations=errors, scenario=stiff, progress=False)
    serial = run_campaign(spatial6, 8, workers=0, **kwargs)
    threads = run_campaign(spatial6, 8, workers=2, **kwargs)
    np.testing.assert_array_equal(threads.status, serial.status)
    np.testing.assert_array_equal(threads.metrics, serial.metrics)
    assert 0 < serial.n_failed < 8, serial.failures()
    for index, message in threads.failures().items():
        # The per-sample path adds where it was raised; the failure itself is the same.
        assert message.split(" (at ")[0] in serial.failures()[index]


def test_a_plant_that_cannot_be_built_fails_alone(spatial6, monkeypatch):
    import spacearm.campaign.batch as batch

    real = batch.plant

    def fragile(nominal, params, *rest):
        if params["payload_mass"] > 2.5:
            raise spacearm.errors.ModelError("synthetic: this payload breaks the model")
        return real(nominal, params, *rest)

    monkeypatch.setattr(batch, "plant", fragile)
    result = run_campaign(spatial6, 8, seed=3, perturbations=ERRORS, scenario=QUICK, workers=2, progress=False)
    heavy = result.parameter("payload_mass", ok_only=False) > 2.5
    assert 0 < heavy.sum() < 8
    np.testing.assert_array_equal(result.status, np.where(heavy, FAILED, OK))
    assert all("ModelError: synthetic" in m for m in result.failures().values())


def test_a_batch_lost_outside_its_samples_stays_pending(spatial6, reference, tmp_path, monkeypatch):
    import spacearm.campaign.local as local

    real, calls = local.fly, []

    def second_batch_breaks(prepared, threads, stop=None):
        calls.append(len(prepared.flying))
        if len(calls) == 2:
            raise MemoryError("synthetic: no memory for the records")
        return real(prepared, threads, stop)

    monkeypatch.setattr(local, "fly", second_batch_breaks)
    out = tmp_path / "lost.npz"
    with pytest.raises(CampaignError, match="4 sample.*did not run.*MemoryError: synthetic") as info:
        run_campaign(spatial6, 12, seed=9, perturbations=ERRORS, scenario=QUICK, workers=2, batch_size=4, out=out,
                     progress=False)
    assert "stay pending" in str(info.value)
    saved = CampaignResult.load(out)
    np.testing.assert_array_equal(saved.status, [OK] * 4 + [PENDING] * 4 + [OK] * 4)
    monkeypatch.setattr(local, "fly", real)
    resumed = run_campaign(spatial6, 12, seed=9, perturbations=ERRORS, scenario=QUICK, workers=2, out=out,
                           progress=False)
    assert resumed.run["samples_run"] == 4
    np.testing.assert_array_equal(resumed.metrics, reference.metrics)


def test_ctrl_c_keeps_the_batches_recorded_and_a_rerun_completes(spatial6, reference, tmp_path):
    out = tmp_path / "interrupted.npz"

    def interrupt(done, total):
        if done == 5:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_campaign(spatial6, 12, seed=9, perturbations=ERRORS, scenario=QUICK, workers=2, batch_size=2, out=out,
                     progress=interrupt)
    saved = CampaignResult.load(out)
    assert saved.n_ok == 5 and saved.n_failed == 0 and saved.n_pending == 7
    resumed = run_campaign(spatial6, 12, seed=9, perturbations=ERRORS, scenario=QUICK, workers=2, out=out,
                           progress=False)
    assert resumed.run["samples_run"] == 7
    np.testing.assert_array_equal(resumed.metrics, reference.metrics)


def test_checkpoints_are_written_while_the_threads_run(spatial6, tmp_path):
    out = tmp_path / "checkpoint.npz"
    seen = []

    def look_at_the_file(done, total):
        if out.exists():
            seen.append((done, CampaignResult.load(out).n_ok))

    run_campaign(spatial6, 8, seed=9, perturbations=ERRORS, scenario=QUICK, workers=2, batch_size=2, out=out,
                 checkpoint_seconds=1e-6, progress=look_at_the_file)
    # Every checkpoint holds the samples recorded before it, and the first one is written long
    # before the end.
    assert seen and seen[0][0] < 8
    assert all(ok <= done for done, ok in seen)
    assert CampaignResult.load(out).n_ok == 8


def test_batches_cover_every_sample_once_in_order():
    from spacearm.campaign.batch import split_into_batches

    assert [len(b) for b in split_into_batches(list(range(20)), 8)] == [8, 8, 4]
    ramped = split_into_batches(list(range(20)), 8, first=2)
    assert [len(b) for b in ramped] == [2, 4, 8, 6]
    assert sum(ramped, []) == list(range(20))
