"""Draw docs/figures/mujoco_ur5_bus.png: the UR5 mounted on the shipped bus, exported by
spacearm.interop.to_mujoco (visual meshes converted from COLLADA by spacearm.io.mesh), rendered
by MuJoCo's own offscreen renderer (EGL, no display).

Run from anywhere: ``MUJOCO_GL=egl python docs/figures/make_mujoco_frame.py`` (needs mujoco,
trimesh, pycollada and example-robot-data).
"""

from __future__ import annotations

import os
import tempfile
from importlib import metadata
from pathlib import Path

os.environ.setdefault("MUJOCO_GL", "egl")

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import mujoco  # noqa: E402
import numpy as np  # noqa: E402

import spacearm  # noqa: E402
from spacearm.interop import mujoco as smj  # noqa: E402
from spacearm.io.mesh import with_mesh_format  # noqa: E402

OUT = Path(__file__).with_name("mujoco_ur5_bus.png")
URDF = Path(str(metadata.distribution("example-robot-data").locate_file(
    "cmeel.prefix/share/example-robot-data/robots/ur_description/urdf/ur5_robot.urdf")))


def main() -> None:
    bus = spacearm.io.load_toml(spacearm.examples.path("spacecraft_bus"))
    robot = spacearm.io.load_urdf(URDF, mount_on=bus, at=(0.6, 0, 0, 0, 0, 0))
    robot = with_mesh_format(robot, Path(tempfile.gettempdir()) / "spacearm_ur5_meshes")
    model = smj.to_mujoco(robot, geometry=("visual",))
    data = mujoco.MjData(model)
    x = robot.neutral_configuration([0.3, -1.1, 1.4, -0.4, 1.2, 0.0])
    data.qpos[:], data.qvel[:] = smj.to_mujoco_state(robot, x, robot.zero_velocity())
    mujoco.mj_forward(model, data)
    camera = mujoco.MjvCamera()
    camera.lookat[:] = [0.6, 0.0, 0.2]
    camera.distance, camera.azimuth, camera.elevation = 3.2, 135.0, -25.0
    with mujoco.Renderer(model, 480, 640) as renderer:
        renderer.update_scene(data, camera)
        image = renderer.render()
    fig = plt.figure(figsize=(6.4, 4.8), dpi=100)
    ax = fig.add_axes([0, 0, 1, 1])
    ax.imshow(image)
    ax.set_axis_off()
    fig.savefig(OUT)
    print(f"wrote {OUT}: {image.shape[1]}×{image.shape[0]}, {model.ngeom} geoms, mean intensity {image.mean():.1f}")


if __name__ == "__main__":
    main()
