"""from_mjcf on Basilisk's own MuJoCo scenarios (the XMLs of its repository's examples/mujoco;
the bsk wheel ships none, so CI checks the Basilisk-style model of test_mjcf_reader.py instead):
H* and J* of each importable file against MuJoCo's, what is refused and why.

    PYTHONPATH=python python3 tests/basilisk/check_basilisk_examples.py /path/to/basilisk/examples/mujoco
"""

from __future__ import annotations

import sys
from pathlib import Path

import mujoco
import numpy as np

sys.path[:0] = [str(Path(__file__).resolve().parent), str(Path(__file__).resolve().parents[1])]
from test_mjcf_reader import _mujoco_h_star_j_star  # noqa: E402

from spacearm import basilisk as sb  # noqa: E402
from spacearm.errors import ModelError  # noqa: E402


def main(folder: str) -> None:
    for path in sorted(Path(folder).glob("*.xml")):
        try:
            robot = sb.from_mjcf(path)
        except ModelError as exc:
            print(f"{path.name}: not imported: {exc}")
            continue
        m = mujoco.MjModel.from_xml_path(str(path))
        if robot.n_dof == 0:
            print(f"{path.name}: {robot.total_mass:.1f} kg, no joints")
            continue
        site = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_SITE, m.nsite - 1) if m.nsite else None
        rng = np.random.default_rng(0)
        worst_h = worst_j = 0.0
        for _ in range(5):
            quat = rng.normal(size=4)
            quat /= np.linalg.norm(quat)
            q = rng.uniform(-1, 1, m.nq - 7)
            h_mj, j_mj = _mujoco_h_star_j_star(m, np.concatenate([[0, 0, 0], quat, q]), site)
            x = np.concatenate([[0, 0, 0], quat[[1, 2, 3, 0]], q])
            worst_h = max(worst_h, np.abs(robot.generalized_inertia(x) - h_mj).max() / np.abs(h_mj).max())
            if site is not None:
                worst_j = max(worst_j, np.abs(robot.generalized_jacobian(x, site) - j_mj).max() / np.abs(j_mj).max())
        print(f"{path.name}: {robot.n_dof} dof, {robot.total_mass:.1f} kg; H* off MuJoCo's by {worst_h:.1e}"
              + (f", J* of site '{site}' by {worst_j:.1e}" if site else ""))


if __name__ == "__main__":
    main(sys.argv[1])
