"""Regenerate the viewer's pictures and 3-D gallery (docs/viewer.md) in a real browser.

Runs the UR5 on the spacecraft bus (the README's resolved-motion-rate run) and a spatial6
capture of a tumbling target, saves each run's scene as a self-contained HTML file under
``docs/scenes/`` (the collision meshes for the UR5, to keep the file small) and screenshots it
with headless Chromium through ``tests/browser.py`` into ``docs/figures/viewer_*.png`` (the UR5
with its visual meshes).

Usage: ``python scripts/viewer_screenshots.py`` (needs the ``view`` and ``test`` extras and
Chromium; about a minute).
"""

from __future__ import annotations

import sys
import tempfile
from importlib import metadata
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

import numpy as np  # noqa: E402

import spacearm  # noqa: E402
from spacearm.cli import main  # noqa: E402

from browser import screenshot  # noqa: E402  (tests/browser.py: the one Chromium helper)

FIGURES = ROOT / "docs" / "figures"
GALLERY = ROOT / "docs" / "scenes"
WIDTH, HEIGHT = 1200, 760


def ur5_run(tmp: Path):
    ur5 = metadata.distribution("example-robot-data").locate_file(
        "cmeel.prefix/share/example-robot-data/robots/ur_description/urdf/ur5_robot.urdf")
    out = tmp / "ur5.npz"
    assert main(["simulate", str(ur5), "--mount-on", "spacecraft_bus", "--at", "0.6,0,0,0,0,0", "--end-effector", "tool0",
                 "--q0", "-0.4,-1.1,1.3,-0.7,0.5,0.3", "--controller", "rmrc", "--target", "1.25,0.15,0.55",
                 "--duration", "5", "--out", str(out)]) == 0
    return spacearm.Trajectory.load(out)


def capture_run():
    from spacearm.capture import Target, capture

    robot = spacearm.presets.spatial6()
    x0 = robot.neutral_configuration()
    ee = robot.point_position(x0)
    target = Target(50.0, [4.0, 5.0, 6.0], grasp_points={"handle": [-0.35, 0.0, 0.0]})
    state = target.state(position=ee + [0.5, 0.0, 0.0], angular_velocity=[0.05, -0.1, 0.2])
    return capture(robot, target, state, x0=x0, approach_time=8.0, detumble_time=6.0)


def main_() -> None:
    FIGURES.mkdir(exist_ok=True)
    GALLERY.mkdir(exist_ok=True)
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        ur5 = ur5_run(tmp)
        ur5.view(GALLERY / "ur5_on_bus.html", fps=20, geometry="collision")
        ur5.view(tmp / "ur5_visual.html", fps=20, play=False)  # the first pose, still: SwiftShader renders the 95k triangles slowly
        screenshot(tmp / "ur5_visual.html", FIGURES / "viewer_ur5_on_bus.png", width=WIDTH, height=HEIGHT, budget_ms=2500, timeout=400)
        cap = capture_run()
        cap.view(GALLERY / "spatial6_capture.html", fps=15)
        screenshot(GALLERY / "spatial6_capture.html", FIGURES / "viewer_spatial6_capture.png", width=WIDTH, height=HEIGHT,
                   budget_ms=4000, timeout=400)
    for f in sorted(GALLERY.glob("*.html")) + sorted(FIGURES.glob("viewer_*.png")):
        print(f"{f.relative_to(ROOT)}: {f.stat().st_size / 1e6:.2f} MB")
    print(f"capture: grasp at {cap.phase_start('capture'):.3f} s, final sample t = {cap.t[-1]:.3f} s, "
          f"UR5 end-effector final position {np.round(ur5.ee_position[-1], 4).tolist()} m")


if __name__ == "__main__":
    main_()
