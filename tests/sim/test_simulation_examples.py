"""The example scripts run and write the figures they promise (a smoke test: their physics is
checked by test_simulation_validation.py and test_simulation_cli.py)."""

import subprocess
import sys
from pathlib import Path

import pytest
from PIL import Image

import spacearm

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

CASES = {
    "floating_case_studies.py": [f"{m}_{r}{s}.png" for m in ("planar4", "spatial6")
                                 for r in ("computed_torque", "pd", "torque_free") for s in ("", "_paths")],
    "rotation_floating_wheels.py": [f"spatial6_rw_{r}{s}.png" for r in ("floating_wheels_idle", "rotation_floating_attitude_hold")
                                    for s in ("", "_paths")],
    "flying_modes.py": [f"spatial6_{m}{s}.png" for m in ("rotation-flying", "translation-flying", "flying")
                        + (("flying_coordinated",) if hasattr(spacearm.control, "CoordinatedFlying") else ())
                        for s in ("", "_paths")],
}


@pytest.mark.parametrize("script", sorted(CASES))
def test_example_writes_its_figures(script, tmp_path):
    out = subprocess.run([sys.executable, str(EXAMPLES / script), "--out-dir", str(tmp_path)],
                         capture_output=True, text=True, cwd=EXAMPLES, timeout=300)
    assert out.returncode == 0, out.stderr
    assert "simulation of" in out.stdout and "Traceback" not in out.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(CASES[script])
    for name in CASES[script]:
        with Image.open(tmp_path / name) as im:
            assert im.format == "PNG" and im.size[0] >= 1000
