"""No campaign process outlives the process that started it, however that process dies.

Each test starts a campaign in a fresh interpreter in its own session, waits until samples are
running, kills the interpreter with SIGKILL (no clean-up runs) and then watches the session: every
process the campaign started (worker processes, multiprocessing's resource tracker, Dask's
nannies and workers) must be gone within a few seconds. Linux only (the session is read from
/proc).
"""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import spacearm

pytestmark = pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="reads processes from /proc (Linux)")

PYTHON_DIR = Path(spacearm.__file__).resolve().parent.parent
# Survivors are looked for this long after the kill (the workers poll or get a signal at once).
GRACE_SECONDS = 5.0


def _session_members(session: int):
    """Pids of the live (not zombie) processes of ``session``."""
    members = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:
            continue
        fields = stat.rsplit(")", 1)[1].split()
        state, sid = fields[0], int(fields[3])
        if sid == session and state != "Z":
            members.append(int(entry.name))
    return members


def _start(tmp_path: Path, argv) -> subprocess.Popen:
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(PYTHON_DIR), os.environ.get("PYTHONPATH", "")]))
    log = open(tmp_path / "log.txt", "w")
    return subprocess.Popen(argv, cwd=tmp_path, env=env, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)


def _wait_for(predicate, seconds: float, what: str):
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        if predicate():
            return
        time.sleep(0.1)
    raise AssertionError(f"timed out waiting for {what}")


def _kill_and_expect_no_survivor(proc: subprocess.Popen, expected_members: int, tmp_path: Path):
    session = proc.pid  # start_new_session: the session id is the leader's pid
    try:
        _wait_for(lambda: "running" in (tmp_path / "log.txt").read_text(), 120, "the first sample")
        members = _session_members(session)
        assert len(members) >= expected_members, (members, (tmp_path / "log.txt").read_text())
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(timeout=10)
        deadline = time.monotonic() + GRACE_SECONDS
        while _session_members(session) and time.monotonic() < deadline:
            time.sleep(0.1)
        survivors = _session_members(session)
        assert not survivors, f"processes alive {GRACE_SECONDS} s after the campaign was killed: {survivors}"
    finally:
        for pid in _session_members(session):  # never leave a survivor behind the test
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass


SCRIPT = """\
import sys
import spacearm
from spacearm.campaign import Scenario, run_campaign


def announce(done, total):
    if done == 1:
        print("running", flush=True)


def main():
    kind = sys.argv[1]
    robot = spacearm.presets.planar4()
    scenario = Scenario(duration=2.0, dt=1e-3)
    if kind == "dask":
        import distributed

        cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
        run_campaign(robot, 5000, scenario=scenario, scheduler=distributed.Client(cluster), progress=announce,
                     batch_size=1)
    else:
        run_campaign(robot, 5000, scenario=scenario, workers=2, backend=kind, progress=announce, batch_size=1)


if __name__ == "__main__":
    main()
"""


@pytest.mark.parametrize("backend, members", [("processes", 3), ("threads", 1)])
def test_local_workers_die_with_a_killed_campaign(tmp_path, backend, members):
    (tmp_path / "study.py").write_text(SCRIPT)
    proc = _start(tmp_path, [sys.executable, "study.py", backend])
    # processes: the campaign, its two workers (and the resource tracker); threads: one process.
    _kill_and_expect_no_survivor(proc, members, tmp_path)


def test_dask_local_cluster_dies_with_a_killed_campaign(tmp_path):
    pytest.importorskip("distributed")
    (tmp_path / "study.py").write_text(SCRIPT)
    proc = _start(tmp_path, [sys.executable, "study.py", "dask"])
    _kill_and_expect_no_survivor(proc, 3, tmp_path)  # the campaign (scheduler, nannies) and two workers


def test_cli_campaign_killed_leaves_nothing_running(tmp_path):
    # The reproduction of the bug report: `spacearm campaign planar4 --samples 2000 --out c.npz &
    # sleep 5; kill -9 $!`, with a progress line to know the samples are running.
    (tmp_path / "cli.py").write_text(
        "import sys\nfrom spacearm.cli import main\n"
        "print('running', flush=True)\n"
        "sys.exit(main(sys.argv[1:]))\n")
    proc = _start(tmp_path, [sys.executable, "cli.py", "campaign", "planar4", "--samples", "2000", "--workers", "2",
                             "--no-progress", "--out", "c.npz"])
    time.sleep(1.0)
    _kill_and_expect_no_survivor(proc, 1, tmp_path)
