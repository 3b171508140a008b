"""Without Gymnasium, ``import spacearm`` works and ``spacearm.gym`` answers in one line which
extra to install."""

import subprocess
import sys

CODE = r"""
import sys
sys.modules["gymnasium"] = None  # as if it were not installed
import spacearm
from spacearm.errors import MissingDependencyError
try:
    import spacearm.gym
except MissingDependencyError as e:
    assert e.extra == "rl" and 'pip install "spacearm[rl]"' in str(e), str(e)
    print("ok")
else:
    raise SystemExit("no MissingDependencyError")
"""


def test_a_missing_gymnasium_names_the_rl_extra(tmp_path):
    out = subprocess.run([sys.executable, "-c", CODE], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0 and out.stdout.strip() == "ok", out.stderr
