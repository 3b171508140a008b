"""Video of a run or a capture: an H.264 ``.mp4`` rendered offscreen
([`Trajectory.video`][spacearm.Trajectory.video], ``CaptureResult.video``, ``spacearm simulate
... --video run.mp4``).

**Frames.** The video lasts the run's duration divided by ``speed`` (``speed=2``: twice as
fast as real time). Frame ``k`` shows the recorded sample nearest to the time
``t0 + k · speed / fps``: no interpolation, every pose drawn is one the core computed. There are
``floor(duration · fps / speed) + 1`` frames (a sample recorded more sparsely than that shows in
several frames).

**Renderers** (``RENDERERS``):

- ``"mujoco"``: MuJoCo's offscreen renderer (``mujoco.Renderer``) of the complete MJCF export
  ([`to_mujoco`][spacearm.interop.to_mujoco]: the model's visual geometry, or its collision
  geometry where it has no visual one), each frame posed by setting ``qpos`` from the state with
  the export's own map ([`to_mujoco_state`][spacearm.interop.to_mujoco_state]). A capture is
  rendered from the MJCF of the captured system, the target a free body
  (``weld``, docs/geometry.md), its pose the recorded target state. The camera looks at the
  bounding sphere of the geometry over the whole run (or ``camera``: MuJoCo's free-camera
  ``lookat``, ``distance``, ``azimuth``, ``elevation``); the end-effector path so far is drawn
  as a line. It needs ``mujoco`` and an offscreen OpenGL: EGL or OSMesa (Debian:
  ``apt-get install libegl1 libgl1-mesa-dri``). ``MUJOCO_GL=egl`` is set where MuJoCo is not
  imported yet, ``MUJOCO_GL`` is unset and there is no display.
- ``"matplotlib"``: the 3-D drawing of the GIF animation (``spacearm.viz.animation``, the
  capture's in ``spacearm.viz.capture``): the base's equivalent box, the arm as segments, the
  end-effector trail, the time in the title.
- ``"auto"`` (default): MuJoCo where it can render this model here, else matplotlib; when
  MuJoCo is installed but cannot (no offscreen OpenGL, a mesh format it does not read or a mesh
  file not found, a model without geometry) a ``RuntimeWarning`` says why. The result's ``renderer`` says which one drew.

**Encoding.** The ffmpeg binary that the pip package ``imageio-ffmpeg`` ships (extra ``video``):
raw RGB frames piped into ``libx264`` (CRF 18), ``yuv420p`` so that every player opens the file
(hence even ``width`` and ``height``), ``+faststart``. The file is written atomically: ffmpeg writes
a temporary beside the target that is renamed onto it when the encoder succeeded, so an error
or Ctrl-C leaves no partial file. A progress bar (tqdm) is shown for renders of at least
``PROGRESS_FRAMES`` frames (``progress=True``/``False`` forces it).
"""

from __future__ import annotations

import errno
import math
import os
import subprocess
import sys
import tempfile
import warnings
from typing import Callable, Iterator, NamedTuple, Optional, Tuple

import numpy as np

from .._util.arrays import positive_number
from .._util.atomic import atomic_path
from .._util.optional import require
from ..errors import ArgumentError, MissingDependencyError, ModelFileError, SpacearmTypeError

__all__ = ["Video", "RENDERERS", "VIDEO_SUFFIX", "check_video_options", "frame_samples", "trajectory_video", "capture_video",
           "PROGRESS_FRAMES", "MAX_FRAMES", "MAX_WIDTH", "MAX_HEIGHT", "MAX_FPS"]

#: The renderers a video can be drawn with.
RENDERERS = ("auto", "mujoco", "matplotlib")
#: The file type written.
VIDEO_SUFFIX = ".mp4"
#: Limits of the options (``yuv420p`` needs even sizes; H.264 level 6.2 holds 8K at these rates).
MIN_SIZE = 16
MAX_WIDTH, MAX_HEIGHT = 7680, 4320
MAX_FPS = 240
#: The most frames one video may have (an hour at 30 fps, 2 hours at 15 fps).
MAX_FRAMES = 108_000
#: A progress bar is shown (``progress=None``) for renders of at least this many frames.
PROGRESS_FRAMES = 100
#: libx264's constant rate factor (0 lossless, 51 worst; 18 is visually lossless).
CRF = 18
#: The default MuJoCo camera direction (deg; MuJoCo's conventions: azimuth about z, elevation
#: negative looking down).
AZIMUTH, ELEVATION = 135.0, -25.0


class Video(NamedTuple):
    """A video written by [`Trajectory.video`][spacearm.Trajectory.video] or ``CaptureResult.video``."""

    path: str  #: the file
    renderer: str  #: ``"mujoco"`` or ``"matplotlib"``: the one that drew it
    frames: int  #: number of frames
    width: int  #: pixels
    height: int  #: pixels
    fps: int  #: frames per second

    def __fspath__(self) -> str:
        return self.path

    def __str__(self) -> str:
        return self.path


def _integer(value, name: str) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        if isinstance(value, (float, np.floating)) and float(value).is_integer():
            return int(value)
        raise ArgumentError(f"{name} must be a whole number, got {value!r}")
    return int(value)


def check_video_options(path, *, width=1280, height=720, fps=30, speed=1.0, renderer="auto") -> dict:
    """The video options checked (before any work): ``path`` ends in ``.mp4``; ``width`` and
    ``height`` are even whole numbers of pixels in ``[16, 7680]`` × ``[16, 4320]`` (``yuv420p``
    halves the colour planes); ``fps`` a whole number in ``[1, 240]``; ``speed`` finite and > 0;
    ``renderer`` one of ``RENDERERS``. Raises [`ArgumentError`][spacearm.ArgumentError]; returns
    the values."""
    p = os.fspath(path)
    suffix = os.path.splitext(p)[1]
    if suffix.lower() != VIDEO_SUFFIX:
        raise ArgumentError(f"a video is written as an H.264 {VIDEO_SUFFIX} file; '{p}' has the suffix "
                            f"'{suffix or '(none)'}': name it '{os.path.splitext(p)[0]}{VIDEO_SUFFIX}'")
    w, h = _integer(width, "video width"), _integer(height, "video height")
    for name, v, top in (("width", w, MAX_WIDTH), ("height", h, MAX_HEIGHT)):
        if not MIN_SIZE <= v <= top:
            raise ArgumentError(f"video {name} must be in [{MIN_SIZE}, {top}] pixels, got {v}")
        if v % 2:
            raise ArgumentError(f"video {name} must be even (H.264 in yuv420p halves the colour planes), got {v}; "
                                f"use {v + 1 if v + 1 <= top else v - 1}")
    f = _integer(fps, "fps")
    if not 1 <= f <= MAX_FPS:
        raise ArgumentError(f"fps must be in [1, {MAX_FPS}] frames per second, got {f}")
    s = positive_number(speed, "speed (the playback speed, 1 = real time)")
    if renderer not in RENDERERS:
        raise ArgumentError(f"renderer must be one of {', '.join(map(repr, RENDERERS))}, got {renderer!r}")
    return {"width": w, "height": h, "fps": f, "speed": s, "renderer": renderer}


def frame_samples(t, fps: int, speed: float) -> Tuple[np.ndarray, np.ndarray]:
    """``(times, samples)`` of the frames of a run recorded at times ``t`` (module docstring):
    frame ``k`` at ``t[0] + k · speed / fps``, showing the sample nearest to it."""
    t = np.asarray(t, dtype=float)
    duration = float(t[-1] - t[0])
    n = int(math.floor(duration * fps / speed + 1e-9)) + 1
    if n > MAX_FRAMES:
        raise ArgumentError(f"the video would have {n} frames ({duration:g} s at {fps} fps, speed {speed:g}), more than the "
                            f"{MAX_FRAMES} allowed: raise speed or lower fps")
    times = t[0] + np.arange(n) * (speed / fps)
    right = np.clip(np.searchsorted(t, times), 1, len(t) - 1) if len(t) > 1 else np.zeros(n, dtype=int)
    if len(t) == 1:
        return times, right
    left = right - 1
    samples = np.where(np.abs(t[left] - times) <= np.abs(t[right] - times), left, right)
    return times, samples


# ---------------------------------------------------------------------------------------------
# the encoder
# ---------------------------------------------------------------------------------------------
def _ffmpeg() -> str:
    return require("imageio_ffmpeg", "videos").get_ffmpeg_exe()


def _encode(path, frames: Iterator[np.ndarray], n: int, width: int, height: int, fps: int, progress) -> None:
    """Pipe ``n`` RGB frames ``(height, width, 3)`` uint8 into ffmpeg (libx264, yuv420p),
    writing ``path`` atomically."""
    exe = _ffmpeg()
    show = n >= PROGRESS_FRAMES if progress is None else bool(progress)
    bar = None
    with atomic_path(path, suffix=VIDEO_SUFFIX) as tmp, tempfile.TemporaryFile() as log:
        if show:
            from tqdm.auto import tqdm

            bar = tqdm(total=n, desc="video", unit="frame", leave=False)
        cmd = [exe, "-y", "-loglevel", "error", "-f", "rawvideo", "-vcodec", "rawvideo", "-pix_fmt", "rgb24",
               "-s", f"{width}x{height}", "-r", str(fps), "-i", "-", "-an", "-c:v", "libx264", "-preset", "medium",
               "-crf", str(CRF), "-pix_fmt", "yuv420p", "-movflags", "+faststart", "-f", "mp4", str(tmp)]
        proc = subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.DEVNULL, stderr=log)
        try:
            written = 0
            for frame in frames:
                if frame.shape != (height, width, 3) or frame.dtype != np.uint8:
                    raise ArgumentError(f"internal: a frame of shape {frame.shape} {frame.dtype}, expected ({height}, {width}, 3) uint8")
                try:
                    proc.stdin.write(np.ascontiguousarray(frame).tobytes())
                except BrokenPipeError:
                    break  # ffmpeg stopped: its log says why (below)
                written += 1
                if bar is not None:
                    bar.update(1)
            try:
                proc.stdin.close()
            except BrokenPipeError:
                pass
            code = proc.wait()
        except BaseException:
            proc.kill()
            proc.wait()
            raise
        finally:
            if bar is not None:
                bar.close()
        if code != 0 or written != n:
            log.seek(0)
            text = log.read().decode("utf-8", "replace").strip().splitlines()
            reason = text[-1] if text else f"exit status {code}"
            err = errno.ENOSPC if "No space left" in reason else errno.EIO
            raise OSError(err, f"ffmpeg could not write the video ({written} of {n} frames): {reason}", os.fspath(path))


# ---------------------------------------------------------------------------------------------
# matplotlib frames
# ---------------------------------------------------------------------------------------------
def _matplotlib_frames(make_scene: Callable, idx, width: int, height: int) -> Iterator[np.ndarray]:
    """Frames of a matplotlib scene (``make_scene(idx, figsize, dpi) -> (fig, draw)``, ``draw(j)``
    returning the artists it moved), the figure 4.5 in tall whatever the resolution (the GIF's
    text size in proportion). The view is fixed, so the figure without its moving artists (axes,
    panes, ticks: most of the drawing time) is drawn once and each frame draws only the moving
    artists over a copy of it."""
    dpi = height / 4.5
    # a quarter pixel more: Agg truncates the figure's size in pixels
    fig, draw = make_scene(idx, figsize=((width + 0.25) / dpi, (height + 0.25) / dpi), dpi=dpi)
    canvas = fig.canvas
    moving = draw(0)
    for a in moving:  # a text stays visible, empty, so that its axes place it where it belongs
        a.set_text("") if hasattr(a, "set_text") else a.set_visible(False)
    canvas.draw()
    background = canvas.copy_from_bbox(fig.bbox)
    for a in moving:
        a.set_visible(True)
    for j in range(len(idx)):
        moving = draw(j)
        canvas.restore_region(background)
        for a in moving:
            if hasattr(a, "do_3d_projection"):  # a 3-D collection is projected by its axes' draw
                a.do_3d_projection()
            fig.draw_artist(a)
        yield np.asarray(canvas.buffer_rgba())[:height, :width, :3]


# ---------------------------------------------------------------------------------------------
# MuJoCo frames
# ---------------------------------------------------------------------------------------------
class _Unavailable(Exception):
    """MuJoCo cannot render this video here (the message says why)."""


def _import_mujoco_offscreen():
    """``mujoco``, with ``MUJOCO_GL=egl`` chosen first on Linux where it is unset, MuJoCo not
    imported yet and there is no display."""
    if ("mujoco" not in sys.modules and sys.platform.startswith("linux") and not os.environ.get("MUJOCO_GL")
            and not os.environ.get("DISPLAY") and not os.environ.get("WAYLAND_DISPLAY")):
        os.environ["MUJOCO_GL"] = "egl"
    try:
        import mujoco
    except ImportError:
        raise _Unavailable("mujoco is not installed (pip install mujoco)") from None
    return mujoco


def _render_roles(robot) -> tuple:
    roles = {g.role for g in robot.description.geometries}
    if "visual" in roles:
        return ("visual",)
    if "collision" in roles:
        return ("collision",)
    raise _Unavailable(f"model '{robot.name}' has no geometry for MuJoCo to draw (docs/geometry.md)")


def _mujoco_model(robot, weld=()):
    from ..interop.mujoco import to_mujoco

    try:
        return to_mujoco(robot, geometry=_render_roles(robot), actuators=False, weld=weld)
    except (ArgumentError, SpacearmTypeError, ModelFileError) as exc:  # a mesh MuJoCo does not read, or not found
        raise _Unavailable(str(exc)) from None


def _open_renderer(mujoco, model, width: int, height: int):
    model.vis.global_.offwidth = max(int(model.vis.global_.offwidth), width)
    model.vis.global_.offheight = max(int(model.vis.global_.offheight), height)
    try:
        return mujoco.Renderer(model, height, width)
    except Exception as exc:  # the GL context could not be made: no EGL/OSMesa, no display
        gl = os.environ.get("MUJOCO_GL", "(unset: glfw, needs a display)")
        raise _Unavailable(f"MuJoCo's offscreen renderer did not start with MUJOCO_GL={gl} ({type(exc).__name__}: "
                           f"{str(exc).strip().splitlines()[0] if str(exc).strip() else 'no message'}); it needs EGL or "
                           "OSMesa (Debian: apt-get install libegl1 libgl1-mesa-dri) and MUJOCO_GL=egl") from None


def _camera(mujoco, model, data, qpos_frames, camera):
    """MuJoCo's free camera: ``camera`` (a mapping of lookat, distance, azimuth, elevation), its
    missing entries from the bounding sphere of the drawn geometry over every frame."""
    cam = mujoco.MjvCamera()
    cam.type = mujoco.mjtCamera.mjCAMERA_FREE
    camera = dict(camera or {})
    unknown = set(camera) - {"lookat", "distance", "azimuth", "elevation"}
    if unknown:
        raise ArgumentError(f"camera: unknown keys {sorted(unknown)}; the keys are lookat, distance, azimuth, elevation")
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
    rbound = model.geom_rbound[:, None]
    for qpos in qpos_frames:
        data.qpos[:] = qpos
        mujoco.mj_kinematics(model, data)
        lo = np.minimum(lo, (data.geom_xpos - rbound).min(axis=0))
        hi = np.maximum(hi, (data.geom_xpos + rbound).max(axis=0))
    centre, radius = 0.5 * (lo + hi), 0.5 * float(np.linalg.norm(hi - lo))
    half_fov = math.radians(float(model.vis.global_.fovy)) / 2
    try:
        cam.lookat[:] = np.asarray(camera.get("lookat", centre), dtype=float).reshape(3)
        cam.distance = float(camera.get("distance", 1.05 * max(radius, 1e-3) / math.sin(half_fov)))
        cam.azimuth = float(camera.get("azimuth", AZIMUTH))
        cam.elevation = float(camera.get("elevation", ELEVATION))
    except (TypeError, ValueError) as exc:
        raise ArgumentError(f"camera: {exc}") from None
    return cam


def _add_trail(mujoco, scene, points) -> None:
    """The path ``points`` (k, 3) as line segments added to ``scene`` (red, 2 px)."""
    rgba = np.array([0.85, 0.15, 0.1, 1.0], dtype=np.float32)
    for a, b in zip(points[:-1], points[1:]):
        if scene.ngeom >= scene.maxgeom:
            return
        if np.linalg.norm(b - a) < 1e-9:
            continue
        g = scene.geoms[scene.ngeom]
        mujoco.mjv_initGeom(g, mujoco.mjtGeom.mjGEOM_LINE, np.zeros(3), np.zeros(3), np.eye(3).ravel(), rgba)
        mujoco.mjv_connector(g, mujoco.mjtGeom.mjGEOM_LINE, 2.0, a, b)
        scene.ngeom += 1


def _mujoco_frames(mujoco, model, renderer, qpos_frames, trail, camera) -> Iterator[np.ndarray]:
    data = mujoco.MjData(model)
    option = mujoco.MjvOption()
    option.geomgroup[:] = 1  # the one geometry role exported is drawn, whatever its group
    option.sitegroup[:] = 0
    cam = _camera(mujoco, model, data, qpos_frames, camera)
    try:
        for j, qpos in enumerate(qpos_frames):
            data.qpos[:] = qpos
            mujoco.mj_fwdPosition(model, data)  # the poses, and the lights' (mj_camlight)
            renderer.update_scene(data, cam, option)
            if trail is not None and j > 0:
                step = max(1, j // 300)  # at most ~300 segments
                _add_trail(mujoco, renderer.scene, trail[np.r_[0:j:step, j]])
            yield renderer.render().copy()
    finally:
        renderer.close()


def caption_size(height: int) -> int:
    """The caption's text height in pixels for a frame ``height`` pixels high; the caption sits
    in a band of ``caption_band(height)`` pixels at the top (what) and at the bottom (when)."""
    return max(8, height // 30)


def caption_band(height: int) -> int:
    return caption_size(height) + 2 * (2 + max(1, height // 240)) + 2


def _captioned(frames: Iterator[np.ndarray], caption: str, times) -> Iterator[np.ndarray]:
    """MuJoCo's frames with what they show (``caption``, top left) and the run's time of each
    recorded sample (``t = … s``, bottom left), white with a dark outline, drawn by Pillow (matplotlib's
    dependency, so in the ``video`` extra)."""
    from PIL import Image, ImageDraw, ImageFont

    font = None
    for frame, t in zip(frames, times):
        h = frame.shape[0]
        size, pad, stroke = caption_size(h), 2 + max(1, h // 240), max(1, h // 240)
        if font is None:
            try:
                font = ImageFont.load_default(size=size)  # Pillow >= 10.1: a scalable font
            except TypeError:  # an older Pillow: its one bitmap font
                font = ImageFont.load_default()
        img = Image.fromarray(frame)
        draw = ImageDraw.Draw(img)
        style = dict(font=font, fill=(255, 255, 255), stroke_width=stroke, stroke_fill=(0, 0, 0))
        draw.text((pad, pad), caption, **style)
        draw.text((pad, h - caption_band(h) + pad), f"t = {t:.2f} s", **style)
        yield np.asarray(img)


# ---------------------------------------------------------------------------------------------
# the two entry points
# ---------------------------------------------------------------------------------------------
def _choose(renderer: str, try_mujoco: Callable):
    """``(name, mujoco setup or None)``: MuJoCo's setup, or matplotlib where ``auto`` allows it."""
    if renderer == "matplotlib":
        return "matplotlib", None
    try:
        return "mujoco", try_mujoco()
    except _Unavailable as exc:
        if renderer == "mujoco":
            raise MissingDependencyError(f"renderer='mujoco' cannot render here: {exc}; or use renderer='matplotlib'",
                                         package="mujoco", extra="video") from None
        if "mujoco" in sys.modules:  # installed but unable: say why the picture is matplotlib's
            warnings.warn(f"video: MuJoCo cannot render this ({exc}); rendering with matplotlib", RuntimeWarning, stacklevel=4)
        return "matplotlib", None


def trajectory_video(traj, path, *, width: int = 1280, height: int = 720, fps: int = 30, renderer: str = "auto",
                     speed: float = 1.0, camera=None, trail: bool = True, progress: Optional[bool] = None) -> Video:
    """Write the video of ``traj`` (a [`Trajectory`][spacearm.Trajectory] with its robot) to
    ``path`` (module docstring); returns the [`Video`][spacearm.viz.video.Video]."""
    opts = check_video_options(path, width=width, height=height, fps=fps, speed=speed, renderer=renderer)
    robot = traj.robot
    if robot is None:
        raise ArgumentError("video needs the robot: build the Trajectory with robot=..., or load() a file saved with one")
    if camera is not None and renderer == "matplotlib":
        raise ArgumentError("camera sets MuJoCo's camera; the matplotlib renderer takes none")
    _ffmpeg()  # the encoder first: a missing extra costs no render
    w, h, f = opts["width"], opts["height"], opts["fps"]
    _, idx = frame_samples(traj.t, f, opts["speed"])

    def setup():
        mujoco = _import_mujoco_offscreen()
        model = _mujoco_model(robot)
        from ..interop.mujoco import to_mujoco_state

        zero = np.zeros(robot.nu)
        qpos = np.array([to_mujoco_state(robot, traj.x[k], zero)[0] for k in idx])
        return mujoco, model, _open_renderer(mujoco, model, w, h), qpos

    name, mj = _choose(renderer, setup)
    if name == "mujoco":
        mujoco, model, rend, qpos = mj
        ee = None
        if trail and robot.end_effector is not None and robot.n_dof > 0:
            ee = traj.ee_position[idx] if traj.has("ee_position") else np.asarray(robot.point_position(traj.x[idx]))
        from .._util.summary import controller_label

        caption = f"{robot.name}: {traj.meta.get('mode', '')} mode, {controller_label(traj.meta.get('controller'))}"
        frames = _captioned(_mujoco_frames(mujoco, model, rend, qpos, ee, camera), caption, traj.t[idx])
    else:
        from .animation import trajectory_scene

        frames = _matplotlib_frames(lambda i, **kw: trajectory_scene(traj, i, trail=trail, **kw), idx, w, h)
    _encode(path, frames, len(idx), w, h, f, progress)
    return Video(os.fspath(path), name, len(idx), w, h, f)


def _capture_render_model(result, system):
    """The MJCF model of robot + target (the target a free body) and the combined model."""
    target = result.target_model
    if not target.is_rigid:
        raise _Unavailable(f"target '{target.name}' is a jointed model; MuJoCo draws a rigid target only")
    if system is None:
        if result.captured is None:
            raise _Unavailable("a point-contact capture has no captured system; pass system=(combined model, payload name)")
        system = (result.captured.robot, result.captured.payload)
    combined, payload = system
    return _mujoco_model(combined, weld=(payload,)), combined


def capture_video(result, path, *, width: int = 1280, height: int = 720, fps: int = 30, renderer: str = "auto",
                  speed: float = 1.0, camera=None, progress: Optional[bool] = None, system=None) -> Video:
    """Write the video of a capture (a ``CaptureResult``) to ``path``: the robot and the target,
    every phase (module docstring); returns the [`Video`][spacearm.viz.video.Video].
    ``system``: ``(combined model, payload name)``, robot and target in one model, the target
    the payload link that MuJoCo draws as a free body at its recorded pose (default: the
    captured system; ``CaptureResult.video`` passes one for a point contact too)."""
    opts = check_video_options(path, width=width, height=height, fps=fps, speed=speed, renderer=renderer)
    if camera is not None and renderer == "matplotlib":
        raise ArgumentError("camera sets MuJoCo's camera; the matplotlib renderer takes none")
    _ffmpeg()
    w, h, f = opts["width"], opts["height"], opts["fps"]
    _, idx = frame_samples(result.t, f, opts["speed"])
    robot = result.robot

    def setup():
        mujoco = _import_mujoco_offscreen()
        model, combined = _capture_render_model(result, system)
        from ..interop.mujoco import to_mujoco_state

        zero = np.zeros(combined.nu)
        qpos = []
        for k in idx:
            q_robot = to_mujoco_state(combined, result.x[k], zero)[0]
            s = result.target[k]
            qpos.append(np.concatenate([q_robot, s[:3], [s[6]], s[3:6]]))  # the target's free joint: [r, w, x, y, z]
        return mujoco, model, _open_renderer(mujoco, model, w, h), np.array(qpos)

    name, mj = _choose(renderer, setup)
    if name == "mujoco":
        mujoco, model, rend, qpos = mj
        grip = np.asarray(robot.point_position(result.x[idx])) if robot.end_effector is not None else None
        caption = f"{robot.name} captures {result.target_model.name}: {result.kind} grasp, {result.mode} mode"
        frames = _captioned(_mujoco_frames(mujoco, model, rend, qpos, grip, camera), caption, result.t[idx])
    else:
        from .capture import capture_scene

        frames = _matplotlib_frames(lambda i, **kw: capture_scene(result, i, **kw), idx, w, h)
    _encode(path, frames, len(idx), w, h, f, progress)
    return Video(os.fspath(path), name, len(idx), w, h, f)
