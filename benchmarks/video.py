"""Time per video frame (docs/video.md): spacearm's MuJoCo frames (the export posed by
``to_mujoco_state``, ``mj_fwdPosition``, the trail, ``mujoco.Renderer``) against the bare
``mujoco.Renderer`` loop on the same exported model and poses (the peer: what spacearm adds),
spacearm's matplotlib frames, and the H.264 encoding alone; interleaved rounds, medians per
frame and the ratio spacearm / bare MuJoCo.

Usage: ``MUJOCO_GL=egl python benchmarks/video.py [--size 320x240] [--frames 20] [--rounds 3]``.
"""

from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time

os.environ.setdefault("MUJOCO_GL", "egl")

import mujoco  # noqa: E402
import numpy as np  # noqa: E402

import spacearm  # noqa: E402
from spacearm.interop import to_mujoco_state  # noqa: E402
from spacearm.viz import video as sv  # noqa: E402
from spacearm.viz.animation import trajectory_scene  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--size", default="320x240")
    ap.add_argument("--frames", type=int, default=20)
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args()
    w, h = (int(v) for v in args.size.split("x"))
    robot = spacearm.presets.spatial6()
    ref = spacearm.control.QuinticJoint(robot.initial_q, robot.initial_q + 0.8, 0.0, 2.0)
    traj = spacearm.simulate(robot, 2.0, controller=spacearm.control.ComputedTorque(kp=25.0, kd=10.0, reference=ref), dt=1e-2)
    idx = np.linspace(0, len(traj) - 1, args.frames).round().astype(int)
    qpos = np.array([to_mujoco_state(robot, traj.x[k], robot.zero_velocity())[0] for k in idx])
    ee = traj.ee_position[idx]

    def bare():
        model = sv._mujoco_model(robot)
        data = mujoco.MjData(model)
        cam = mujoco.MjvCamera()
        cam.lookat[:], cam.distance = [1.2, 0.0, -0.2], 4.0
        with mujoco.Renderer(model, h, w) as r:
            for q in qpos:
                data.qpos[:] = q
                mujoco.mj_fwdPosition(model, data)
                r.update_scene(data, cam)
                r.render()

    def ours_mujoco():
        model = sv._mujoco_model(robot)
        for _ in sv._mujoco_frames(mujoco, model, sv._open_renderer(mujoco, model, w, h), qpos, ee, None):
            pass

    def ours_matplotlib():
        for _ in sv._matplotlib_frames(lambda i, **kw: trajectory_scene(traj, i, **kw), idx, w, h):
            pass

    frames = [np.full((h, w, 3), 40 * (k % 6), dtype=np.uint8) for k in range(len(idx))]

    def encode():
        with tempfile.TemporaryDirectory() as d:
            sv._encode(os.path.join(d, "x.mp4"), iter(frames), len(frames), w, h, 30, False)

    cases = {"bare mujoco.Renderer": bare, "spacearm mujoco": ours_mujoco, "spacearm matplotlib": ours_matplotlib,
             "H.264 encoding only": encode}
    times = {k: [] for k in cases}
    for _ in range(args.rounds):
        for name, fn in cases.items():  # interleaved: each round runs every case once
            t = time.perf_counter()
            fn()
            times[name].append((time.perf_counter() - t) / len(idx))
    print(f"spatial6, {len(idx)} frames of {w}x{h}, {args.rounds} rounds (load {os.getloadavg()[0]:.1f}, {os.cpu_count()} CPUs)")
    for name, ts in times.items():
        print(f"  {name:24s} median {1e3 * statistics.median(ts):8.1f} ms/frame  (min {1e3 * min(ts):.1f})")
    ratio = [a / b for a, b in zip(times["spacearm mujoco"], times["bare mujoco.Renderer"])]
    print(f"  spacearm mujoco / bare mujoco.Renderer: median ratio {statistics.median(ratio):.2f}")


if __name__ == "__main__":
    main()
