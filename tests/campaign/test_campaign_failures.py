"""Campaign failures that are not the sample's: scripts without a main guard under ``spawn``,
worker processes lost mid-run, files from earlier versions, and a figure with nothing to plot.

The rule under test (docs/campaigns.md, "Resuming and failures"): a sample that fails for its
own reasons is recorded as failed; a sample the back end loses is not recorded, stays pending,
and a rerun runs it. The main-guard tests run real scripts in a fresh interpreter, as a user
would.
"""

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

import spacearm
from spacearm.campaign import FAILED, PENDING, CampaignResult, CampaignSpec, Perturbations, Scenario, run_campaign
from spacearm.campaign._main_guard import line_is_guarded
from spacearm.errors import CampaignError
from spacearm.io.model_file import dumps_toml

PYTHON_DIR = Path(spacearm.__file__).resolve().parent.parent
QUICK = Scenario(duration=0.6, dt=5e-3, q_offset=0.4)

CAMPAIGN_CALL = """\
result = run_campaign(spacearm.presets.planar4(), samples=3, workers=2, progress=False, out="c.npz",
                      scenario=Scenario(duration=0.3, dt=0.01))
print("samples ok:", result.n_ok)
"""


def _run_script(tmp_path: Path, body: str) -> subprocess.CompletedProcess:
    script = tmp_path / "study.py"
    script.write_text("import spacearm\nfrom spacearm.campaign import Scenario, run_campaign\n" + body)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(PYTHON_DIR), os.environ.get("PYTHONPATH", "")]))
    return subprocess.run([sys.executable, str(script)], cwd=tmp_path, env=env, capture_output=True, text=True,
                          timeout=120)


def test_unguarded_script_fails_once_before_any_sample(tmp_path):
    proc = _run_script(tmp_path, CAMPAIGN_CALL)
    assert proc.returncode != 0
    assert proc.stderr.count("Traceback") == 1, proc.stderr
    assert "spacearm.errors.CampaignError" in proc.stderr
    assert 'if __name__ == "__main__":' in proc.stderr and "workers=0" in proc.stderr
    assert "BrokenProcessPool" not in proc.stderr and "samples ok" not in proc.stdout
    assert not (tmp_path / "c.npz").exists()


def test_guarded_script_runs(tmp_path):
    body = "def main():\n" + textwrap.indent(CAMPAIGN_CALL, "    ") + '\n\nif __name__ == "__main__":\n    main()\n'
    proc = _run_script(tmp_path, body)
    assert proc.returncode == 0, proc.stderr
    assert "samples ok: 3" in proc.stdout
    assert CampaignResult.load(tmp_path / "c.npz").n_ok == 3


def test_unguarded_script_fails_once_even_when_the_source_check_is_inconclusive(tmp_path):
    # As if the script's source could not be read: the workers then re-run it, stop quietly,
    # and the parent reports the broken pool once, with the same advice.
    body = "import spacearm.campaign.executor as executor\nexecutor.check_caller_is_guarded = lambda: None\n" + CAMPAIGN_CALL
    proc = _run_script(tmp_path, body)
    assert proc.returncode != 0
    assert proc.stderr.count("Traceback") == 1, proc.stderr
    assert "no worker process returned a sample" in proc.stderr
    assert 'if __name__ == "__main__":' in proc.stderr
    assert not (tmp_path / "c.npz").exists()


@pytest.mark.parametrize("source, line, guarded", [
    ("x = 1\nrun()\n", 2, False),
    ('if __name__ == "__main__":\n    run()\n', 2, True),
    ('if "__main__" == __name__:\n    run()\n', 2, True),
    ('if __name__ != "__main__":\n    pass\nelse:\n    run()\n', 4, True),
    ('if __name__ == "__main__":\n    pass\nelse:\n    run()\n', 4, False),
    ('if __name__ == "__mp_main__":\n    run()\n', 2, False),
    ('try:\n    if __name__ == "__main__":\n        run()\nexcept KeyError:\n    pass\n', 3, True),
])
def test_main_guard_detection(source, line, guarded):
    assert line_is_guarded(source, line) is guarded


def test_lost_workers_leave_their_samples_pending_and_a_rerun_runs_them(tmp_path):
    import multiprocessing

    planar4 = spacearm.presets.planar4()
    slow = Scenario(duration=2.0, dt=1e-3, q_offset=0.4)  # ~30 ms a sample: the pool cannot finish first
    out = tmp_path / "lost.npz"

    def kill_the_workers(done, total):
        if done == 1:
            for child in multiprocessing.active_children():  # this test's pool workers
                child.kill()

    with pytest.raises(CampaignError, match=r"did not run because the processes back end failed") as info:
        run_campaign(planar4, 40, seed=2, scenario=slow, workers=1, out=out, progress=kill_the_workers)
    assert "stay pending" in str(info.value) and str(out) in str(info.value)
    saved = CampaignResult.load(out)
    assert saved.n_failed == 0 and saved.n_ok >= 1 and saved.n_pending > 0
    assert saved.run["samples_lost"] == saved.n_pending and "BrokenProcessPool" in saved.run["lost_reason"]
    ran_before = saved.status != PENDING

    resumed = run_campaign(planar4, 40, seed=2, scenario=slow, workers=0, out=out, progress=False)
    assert resumed.n_ok == 40 and resumed.run["samples_run"] == saved.n_pending
    # Bit for bit what one uninterrupted run in this process gives.
    reference = run_campaign(planar4, 40, seed=2, scenario=slow, workers=0, progress=False)
    np.testing.assert_array_equal(resumed.metrics, reference.metrics)
    assert ran_before.sum() == 40 - saved.n_pending


def test_files_with_lost_samples_recorded_as_failed_are_rerun(tmp_path):
    planar4 = spacearm.presets.planar4()
    out = tmp_path / "old.npz"
    full = run_campaign(planar4, 4, seed=1, scenario=QUICK, workers=0, progress=False, out=out)
    # What an earlier version wrote after a broken pool, next to a sample that failed on its own.
    old = CampaignResult.load(out)
    old.status[[0, 1, 2]] = FAILED
    old.metrics[[0, 1, 2]] = np.nan
    old.error[0] = "worker failed: BrokenProcessPool: A process in the process pool was terminated abruptly"
    old.error[1] = "dask task failed: KilledWorker: attempted to run task 3 times"
    old.error[2] = "FloatingPointError: the simulation produced non-finite tracking_error_max"
    old.save(out)
    loaded = CampaignResult.load(out)
    np.testing.assert_array_equal(loaded.status, [PENDING, PENDING, FAILED, 1])
    resumed = run_campaign(planar4, 4, seed=1, scenario=QUICK, workers=0, progress=False, out=out)
    assert resumed.run["samples_run"] == 2 and resumed.n_failed == 1
    np.testing.assert_array_equal(resumed.metrics[:2], full.metrics[:2])
    retried = run_campaign(planar4, 4, seed=1, scenario=QUICK, workers=0, progress=False, out=out, retry_failed=True)
    assert retried.n_ok == 4


def test_plot_with_no_successful_sample_is_a_clear_error(tmp_path):
    planar4 = spacearm.presets.planar4()
    bad_goal = CampaignSpec(dumps_toml(planar4), 3, 0, Perturbations(), Scenario(duration=0.2, dt=0.01, q_goal=(0.1,)))
    result = run_campaign(bad_goal, workers=0, progress=False)
    assert result.n_failed == 3
    with pytest.raises(CampaignError, match="no sample of this campaign ran successfully"):
        result.plot(tmp_path / "empty.png")
    assert not (tmp_path / "empty.png").exists()
    assert list(tmp_path.iterdir()) == []


def test_ctrl_c_keeps_what_ran_and_a_rerun_runs_the_rest(tmp_path):
    planar4 = spacearm.presets.planar4()
    out = tmp_path / "interrupted.npz"

    def interrupt(done, total):
        if done == 2:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_campaign(planar4, 5, seed=4, scenario=QUICK, workers=0, out=out, progress=interrupt)
    saved = CampaignResult.load(out)
    assert (saved.n_ok, saved.n_failed, saved.n_pending) == (2, 0, 3)
    resumed = run_campaign(planar4, 5, seed=4, scenario=QUICK, workers=0, out=out, progress=False)
    assert resumed.run["samples_run"] == 3 and resumed.n_ok == 5


def test_dask_tasks_lost_to_a_restart_stay_pending(tmp_path):
    distributed = pytest.importorskip("distributed")
    planar4 = spacearm.presets.planar4()
    slow = Scenario(duration=2.0, dt=1e-3, q_offset=0.4)
    out = tmp_path / "dask.npz"
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:

            def restart_the_cluster(done, total):
                if done == 1:
                    client.restart()  # every task not yet finished is cancelled: not the samples' doing

            with pytest.raises(CampaignError, match="did not run because the dask back end failed"):
                run_campaign(planar4, 30, seed=2, scenario=slow, scheduler=client, out=out, progress=restart_the_cluster)
    saved = CampaignResult.load(out)
    assert saved.n_failed == 0 and saved.n_ok >= 1 and saved.n_pending == saved.run["samples_lost"] > 0
    assert "cancelled" in saved.run["lost_reason"].lower()
    resumed = run_campaign(planar4, 30, seed=2, scenario=slow, workers=0, out=out, progress=False)
    assert resumed.n_ok == 30 and resumed.run["samples_run"] == saved.n_pending
