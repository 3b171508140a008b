"""``spacearm view RESULT.npz [--out scene.html]``: a recorded run in the 3-D browser viewer
(``spacearm.viz.viewer``, the ``view`` extra; docs/viewer.md).

RESULT is what ``simulate --out`` (a trajectory, ``spacearm.Trajectory/1``) or ``capture --out``
(``spacearm.CaptureResult/2``, or the older ``/1``) wrote; both embed their models as TOML. With ``--out`` the scene is
written as one self-contained HTML file; without it, it is served live (meshcat's server, the
browser opened unless ``--no-browser``) until Ctrl-C. A trajectory written without its model
(``Trajectory.save`` of a run with no robot) needs ``--model MODEL``; a capture record of an older
spacearm, which stored no models, is refused with the way to re-record it.
"""

from __future__ import annotations

import os
import signal
import sys
import threading
import time
import warnings

import numpy as np

from .model_options import MODEL_HELP, load_model
from ..errors import ArgumentError

__all__ = ["add_parser", "run"]


def add_parser(sub) -> None:
    p = sub.add_parser("view", help="a recorded run (simulate --out, capture --out) in the 3-D browser viewer",
                       description="Draws the run of RESULT.npz in the browser (meshcat): the bodies with their "
                                   "geometry, frames, the end-effector path, the momentum arrows, a time slider and "
                                   "play/pause. --out writes one self-contained HTML file; without it the scene is "
                                   "served live until Ctrl-C.")
    p.add_argument("result", metavar="RESULT.npz", help="a record written by 'spacearm simulate --out' or 'spacearm capture --out'")
    p.add_argument("--out", default=None, help="write the scene as a self-contained .html file (no server)")
    p.add_argument("--model", default=None, help="the model, for a trajectory saved without one: " + MODEL_HELP)
    p.add_argument("--fps", type=float, default=30.0, help="key frames per second of the run (default 30)")
    p.add_argument("--geometry", choices=("visual", "collision"), default="visual",
                   help="which shapes to draw (default visual; a body with none shows its others)")
    p.add_argument("--no-momentum", action="store_true", help="leave out the momentum arrows")
    p.add_argument("--open", action="store_true", help="with --out: open the file in the web browser")
    p.add_argument("--no-browser", action="store_true", help="live view: do not open the web browser")
    p.add_argument("--mesh-dir", action="append", default=[], metavar="DIR",
                   help="a folder mesh files of the record's models may be read from, besides the record's own "
                        "folder (repeatable); a mesh elsewhere is not read")
    p.add_argument("--allow-outside-meshes", action="store_true",
                   help="read the record's mesh files wherever they are (only for records you trust)")


class _SavedCapture:
    """What the viewer draws of a capture record (``CaptureResult.save``): the arrays, the
    robot and the target rebuilt from their embedded models."""

    def __init__(self, path, files):
        from ..capture.sequence import PHASES
        from ..capture.target import Target
        from ..io.model_file import loads_toml

        self.t, self.phase, self.x, self.u = files["t"], files["phase"], files["x"], files["u"]
        self.target, self.P, self.L = files["target"], files["P"], files["L"]
        self.kind, self.mode = str(files["kind"]), str(files["mode"])
        self.robot = loads_toml(str(files["__model_toml__"]), source=f"{path} (embedded model)")
        body = loads_toml(str(files["__target_toml__"]), source=f"{path} (embedded target model)")
        self.target_model = Target.from_robot(body, name=str(files["__target_name__"]))

        class _Impact:
            point = np.asarray(files["impact_point"], dtype=float)

        self.impact = _Impact()
        self._phases = PHASES

    def phase_start(self, name: str) -> float:
        idx = np.nonzero(self.phase == self._phases.index(name))[0]
        return float(self.t[idx[0]]) if idx.size else float("nan")


def _read(path, model):
    """The Trajectory or saved capture in ``path``."""
    from .._util.npz import open_npz
    from ..capture.sequence import VIEWABLE_FORMATS
    from ..sim.trajectory import FILE_FORMAT as TRAJECTORY_FORMAT, Trajectory

    with open_npz(path, "spacearm record") as files:
        files = dict(files)
    fmt = str(files.get("__format__", ""))
    if fmt == TRAJECTORY_FORMAT:
        robot = load_model(model) if model is not None else None
        traj = Trajectory.load(path, robot=robot)
        if traj.robot is None:
            raise ArgumentError(f"{path}: this trajectory was saved without its model: pass --model MODEL (the model it "
                                "was simulated with: a preset, a shipped model, a .toml or .urdf file)")
        return traj
    if fmt in VIEWABLE_FORMATS:
        if model is not None:
            raise ArgumentError(f"{path}: a capture record embeds the robot and the target; --model is for trajectories")
        return _SavedCapture(path, files)
    if {"phase", "target", "impact_point"} <= set(files):
        raise ArgumentError(f"{path}: a capture record of an older spacearm, without the robot's and the target's models: "
                            "run 'spacearm capture ... --out' again to record them")
    raise ArgumentError(f"{path}: not a record of 'spacearm simulate --out' ({TRAJECTORY_FORMAT!r}) or 'spacearm capture "
                        f"--out' ({VIEWABLE_FORMATS[-1]!r}); its format tag is {fmt!r}")


def run(args, out=None) -> int:
    from ..viz.viewer import capture_scene, trajectory_scene

    out = sys.stdout if out is None else out
    record = _read(args.result, args.model)
    # The record's models name their mesh files: read only those in its folder or a --mesh-dir.
    mesh_dirs = None if args.allow_outside_meshes else [os.path.dirname(os.path.abspath(args.result))] + list(args.mesh_dir)
    options = dict(fps=args.fps, geometry=args.geometry, momentum=not args.no_momentum, mesh_dirs=mesh_dirs)
    with warnings.catch_warnings():  # the scene's notes are printed below, once
        warnings.simplefilter("ignore", UserWarning)
        scene = capture_scene(record, **options) if isinstance(record, _SavedCapture) else trajectory_scene(record, **options)
    for note in scene.notes:
        out.write(f"note: {note}\n")
    if args.out:
        scene.save(args.out)
        out.write(f"wrote scene: {args.out} ({len(scene.times)} key frames over {scene.times[-1]:.4g} s)\n")
        if args.open:
            import webbrowser

            webbrowser.open(os.path.abspath(args.out))
        return 0
    # SIGTERM and SIGHUP (a closed terminal) stop the server as Ctrl-C does; the server also
    # ends by itself when this process is gone however it ends (SIGKILL: viz/viewer.py).
    handled = [getattr(signal, name) for name in ("SIGTERM", "SIGHUP") if hasattr(signal, name)]
    previous = {}
    if threading.current_thread() is threading.main_thread():
        previous = {sig: signal.signal(sig, _stop) for sig in handled}
    vis = None
    try:  # the announcement inside: a Ctrl-C right after it is the stop asked for, not an error
        vis = scene.show(open=not args.no_browser)
        out.write(f"serving the scene at {vis.window.web_url} (Ctrl-C to stop)\n")
        out.flush()
        while True:
            time.sleep(1.0)
    except (KeyboardInterrupt, _Stopped):
        out.write("stopped\n")
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        proc = getattr(getattr(vis, "window", None), "server_proc", None)
        if proc is not None and proc.poll() is None:
            proc.kill()
            proc.wait()
    return 0


class _Stopped(Exception):
    """A SIGTERM or SIGHUP asked the live view to stop."""


def _stop(signum, frame):
    raise _Stopped(signum)
