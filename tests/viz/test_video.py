"""Videos (spacearm.viz.video): the mp4 is H.264 yuv420p with the requested size, frame rate and
frame count (read back by ffmpeg, through imageio-ffmpeg's reader); its frames show the robot
(not uniform, and a different configuration gives a different picture); MuJoCo's first frame
is mujoco.Renderer's own picture of the exported model at x[0]; bad options are spacearm errors
before any work, the CLI answers them with exit status 2, and a failed render leaves no file."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest

import spacearm
from spacearm.errors import ArgumentError
from spacearm.viz import video as sv

imageio_ffmpeg = pytest.importorskip("imageio_ffmpeg")
pytest.importorskip("matplotlib")

W, H, FPS = 96, 64, 10


def _read(path):
    """``(meta, frames)`` decoded by ffmpeg: meta has the codec, pixel format, size and fps."""
    gen = imageio_ffmpeg.read_frames(str(path))
    meta = next(gen)
    w, h = meta["size"]
    frames = np.array([np.frombuffer(b, dtype=np.uint8).reshape(h, w, 3) for b in gen])
    return meta, frames


def _probe(path) -> str:
    """ffmpeg's own description of the file (``ffmpeg -i``)."""
    out = subprocess.run([imageio_ffmpeg.get_ffmpeg_exe(), "-hide_banner", "-i", str(path)], capture_output=True, text=True)
    return out.stderr


@pytest.fixture(scope="module")
def run():
    """spatial6 moving every joint by 0.8 rad in 1 s (the picture changes), recorded every 10 ms."""
    robot = spacearm.presets.spatial6()
    ref = spacearm.control.QuinticJoint(robot.initial_q, robot.initial_q + 0.8, 0.0, 1.0)
    return spacearm.simulate(robot, 1.0, controller=spacearm.control.ComputedTorque(kp=25.0, kd=10.0, reference=ref), dt=1e-2)


def _mujoco_or_skip():
    """mujoco with a working offscreen context, or a skip (a failure under SPACEARM_REQUIRE_GL=1, as in CI)."""
    mujoco = pytest.importorskip("mujoco")
    try:
        with mujoco.Renderer(mujoco.MjModel.from_xml_string("<mujoco/>"), 16, 16):
            pass
    except Exception as exc:  # no EGL / OSMesa here
        if os.environ.get("SPACEARM_REQUIRE_GL") == "1":
            pytest.fail(f"MuJoCo's offscreen renderer does not start (MUJOCO_GL={os.environ.get('MUJOCO_GL')}): {exc}")
        pytest.skip(f"no offscreen OpenGL for MuJoCo here: {exc}")
    return mujoco


def test_matplotlib_video_is_h264_with_the_size_rate_and_frames_asked(run, tmp_path):
    path = tmp_path / "run.mp4"
    v = run.video(path, width=W, height=H, fps=FPS, renderer="matplotlib", speed=0.5)
    assert (v.path, v.renderer, v.width, v.height, v.fps) == (str(path), "matplotlib", W, H, FPS)
    meta, frames = _read(path)
    assert meta["codec"].startswith("h264") and meta["pix_fmt"].startswith("yuv420p")
    assert tuple(meta["size"]) == (W, H) and meta["fps"] == FPS
    info = _probe(path)
    assert "Video: h264" in info and "yuv420p" in info and f"{W}x{H}" in info and f"{FPS} fps" in info
    # 1 s at half speed: 2 s of video, floor(1 * 10 / 0.5) + 1 frames
    assert v.frames == len(frames) == 21
    # the robot is drawn (not a uniform picture) and it moves: the last frame is another picture
    assert frames[0].std() > 10
    assert np.abs(frames[-1].astype(int) - frames[0]).mean() > 1.0


def test_frames_are_the_nearest_samples():
    t = np.linspace(0.0, 1.0, 11)  # samples every 0.1 s
    times, idx = sv.frame_samples(t, fps=4, speed=1.0)
    np.testing.assert_allclose(times, [0.0, 0.25, 0.5, 0.75, 1.0])
    assert list(idx) == [0, 2, 5, 7, 10]  # 0.25 is nearer 0.2 than 0.3 (ties go to the earlier sample)
    _, idx = sv.frame_samples(t, fps=30, speed=2.0)
    assert len(idx) == 16 and idx[-1] == 10


@pytest.mark.parametrize("kwargs, match", [
    ({"width": 97}, "even"), ({"height": 8}, r"\[16, 4320\]"), ({"width": 1280.5}, "whole number"),
    ({"fps": 0}, r"\[1, 240\]"), ({"speed": -1.0}, "speed"), ({"speed": float("nan")}, "speed"),
    ({"renderer": "blender"}, "renderer"),
])
def test_bad_options_are_refused_before_any_work(run, tmp_path, kwargs, match):
    opts = {"width": W, "height": H, "fps": FPS, **kwargs}
    with pytest.raises(ArgumentError, match=match):
        run.video(tmp_path / "x.mp4", **opts)
    assert not list(tmp_path.iterdir())


def test_a_bad_suffix_is_refused(run, tmp_path):
    for name in ("x.gif", "x"):
        with pytest.raises(ArgumentError, match=r"\.mp4"):
            run.video(tmp_path / name)
    assert not list(tmp_path.iterdir())


def test_a_failed_render_leaves_no_file(run, tmp_path, monkeypatch):
    path = tmp_path / "run.mp4"
    path.write_bytes(b"the previous video")

    def broken(*args, **kwargs):
        yield np.zeros((H, W, 3), dtype=np.uint8)
        raise KeyboardInterrupt  # Ctrl-C in the middle of the render

    monkeypatch.setattr(sv, "_matplotlib_frames", broken)
    with pytest.raises(KeyboardInterrupt):
        run.video(path, width=W, height=H, fps=FPS, renderer="matplotlib")
    assert path.read_bytes() == b"the previous video"
    assert [p.name for p in tmp_path.iterdir()] == ["run.mp4"]  # no temporary left


def test_mujoco_first_frame_is_mujocos_own_render(run, tmp_path):
    mujoco = _mujoco_or_skip()
    from spacearm.interop import mujoco as smj

    camera = {"lookat": [1.2, 0.0, -0.2], "distance": 4.0, "azimuth": 120.0, "elevation": -20.0}
    w, h = 160, 120
    v = run.video(tmp_path / "mj.mp4", width=w, height=h, fps=FPS, renderer="mujoco", camera=camera)
    assert v.renderer == "mujoco"
    meta, frames = _read(v.path)
    assert tuple(meta["size"]) == (w, h) and meta["codec"].startswith("h264") and len(frames) == 11

    # The independent picture: MuJoCo's renderer of the exported model posed at x[0] and at x[-1].
    robot = run.robot
    model = smj.to_mujoco(robot, geometry=("visual",), actuators=False)
    data = mujoco.MjData(model)
    cam = mujoco.MjvCamera()
    cam.lookat[:], cam.distance, cam.azimuth, cam.elevation = camera["lookat"], camera["distance"], camera["azimuth"], camera["elevation"]
    option = mujoco.MjvOption()
    option.sitegroup[:] = 0  # the video hides the sites (the named points)

    def picture(x):
        data.qpos[:] = smj.to_mujoco_state(robot, x, robot.zero_velocity())[0]
        mujoco.mj_forward(model, data)
        with mujoco.Renderer(model, h, w) as r:
            r.update_scene(data, cam, option)
            return r.render().astype(int)

    first, last = picture(run.x[0]), picture(run.x[-1])
    assert first.std() > 5  # the robot is in the picture
    # Between the caption bands (what, at the top; the time, at the bottom) the frame is MuJoCo's.
    from spacearm.viz.video import caption_band

    band = caption_band(h)
    inside = slice(band, h - band)
    same = np.abs(frames[0][inside] - first[inside]).mean()  # H.264 at CRF 18 and yuv420p: a few grey levels at most
    other = np.abs(frames[0][inside] - last[inside]).mean()
    assert same < 1.0 and other > 4 * same, (same, other)
    # The caption and the time stamp are drawn (issue 37 item 7: the video had neither): the top
    # band differs from MuJoCo's picture, and the bottom band differs between two frames whose
    # recorded times differ while showing the same pose.
    assert np.abs(frames[0][:band] - first[:band]).mean() > 4 * same
    assert np.abs(frames[0][h - band:] - first[h - band:]).mean() > 4 * same


def test_cli_simulate_video(tmp_path):
    path = tmp_path / "cli.mp4"
    cmd = [sys.executable, "-m", "spacearm", "simulate", "planar4", "--duration", "0.5", "--dt", "0.01", "--controller", "pd",
           "--video", str(path), "--video-size", f"{W}x{H}", "--fps", str(FPS), "--renderer", "matplotlib"]
    out = subprocess.run(cmd, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert f"wrote video: {path} ({W}x{H}, 6 frames at {FPS} fps, matplotlib renderer)" in out.stdout
    meta, frames = _read(path)
    assert tuple(meta["size"]) == (W, H) and len(frames) == 6
    for bad, message in ((["--video", str(tmp_path / "x.avi")], ".mp4"), (["--video", str(tmp_path / "y.mp4"), "--video-size", "95x64"], "even"),
                         (["--video", str(tmp_path / "z.mp4"), "--video-size", "big"], "WIDTHxHEIGHT")):
        out = subprocess.run([sys.executable, "-m", "spacearm", "simulate", "planar4", "--duration", "0.1", *bad],
                             capture_output=True, text=True)
        assert out.returncode == 2 and out.stderr.startswith("spacearm: error:") and message in out.stderr, out.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cli.mp4"]


@pytest.fixture(scope="module")
def captured():
    robot = spacearm.presets.spatial6()
    x = robot.neutral_configuration()
    target = spacearm.Target(50.0, [4.0, 5.0, 6.0], grasp_points={"handle": (-0.5, 0.0, 0.0)})
    s = target.state(position=robot.point_position(x) + np.array([0.6, 0.0, 0.0]), angular_velocity=(0.0, 0.0, 0.1))
    return spacearm.capture.capture(robot, target, s, detumble_time=0.5, post_time=0.2)


def test_capture_video_matplotlib(captured, tmp_path):
    v = captured.video(tmp_path / "cap.mp4", width=W, height=H, fps=FPS, renderer="matplotlib", speed=4.0)
    meta, frames = _read(v.path)
    n = int(np.floor((captured.t[-1] - captured.t[0]) * FPS / 4.0 + 1e-9)) + 1
    assert v.frames == len(frames) == n and tuple(meta["size"]) == (W, H)
    assert frames[0].std() > 10 and np.abs(frames[-1].astype(int) - frames[0]).mean() > 0.5


def test_capture_video_mujoco_draws_robot_and_target(captured, tmp_path):
    mujoco = _mujoco_or_skip()
    from spacearm.interop import mujoco as smj

    camera = {"lookat": [1.8, 0.0, -0.2], "distance": 5.0, "azimuth": 120.0, "elevation": -20.0}
    w, h = 160, 120
    v = captured.video(tmp_path / "cap.mp4", width=w, height=h, fps=FPS, renderer="mujoco", speed=4.0, camera=camera)
    _, frames = _read(v.path)
    # MuJoCo's own picture of the captured system's MJCF (the target a welded free body), posed by
    # the first recorded robot and target states; and the same without the target.
    cs = captured.captured
    model = smj.to_mujoco(cs.robot, geometry=("visual",), actuators=False, weld=[cs.payload])
    data = mujoco.MjData(model)
    cam = mujoco.MjvCamera()
    cam.lookat[:], cam.distance, cam.azimuth, cam.elevation = camera["lookat"], camera["distance"], camera["azimuth"], camera["elevation"]
    option = mujoco.MjvOption()
    option.sitegroup[:] = 0

    def picture(target_on: bool):
        s = captured.target[0]
        qpos = smj.to_mujoco_state(cs.robot, captured.x[0], cs.robot.zero_velocity())[0]
        far = [0.0, 0.0, 1e3] if not target_on else s[:3]  # the target out of the view
        data.qpos[:] = np.concatenate([qpos, far, [s[6]], s[3:6]])
        mujoco.mj_forward(model, data)
        with mujoco.Renderer(model, h, w) as r:
            r.update_scene(data, cam, option)
            return r.render().astype(int)

    with_target, without = picture(True), picture(False)
    from spacearm.viz.video import caption_band

    inside = slice(caption_band(h), h - caption_band(h))  # between the caption bands
    same = np.abs(frames[0][inside] - with_target[inside]).mean()
    assert same < 1.0 and np.abs(frames[0][inside] - without[inside]).mean() > 4 * same, same


def test_auto_falls_back_to_matplotlib_with_a_warning(run, tmp_path, monkeypatch):
    pytest.importorskip("mujoco")

    def no_gl(*args, **kwargs):
        raise sv._Unavailable("no offscreen OpenGL (test)")

    monkeypatch.setattr(sv, "_open_renderer", no_gl)
    with pytest.warns(RuntimeWarning, match="no offscreen OpenGL"):
        v = run.video(tmp_path / "auto.mp4", width=W, height=H, fps=FPS, speed=4.0)
    assert v.renderer == "matplotlib" and _read(v.path)[1].shape == (3, H, W, 3)
    with pytest.raises(spacearm.MissingDependencyError, match="no offscreen OpenGL"):
        run.video(tmp_path / "mj.mp4", width=W, height=H, fps=FPS, renderer="mujoco")
    assert not (tmp_path / "mj.mp4").exists()


def test_point_capture_video_mujoco(tmp_path):
    _mujoco_or_skip()
    robot = spacearm.presets.spatial6()
    x = robot.neutral_configuration()
    target = spacearm.Target(50.0, [4.0, 5.0, 6.0], grasp_points={"handle": (-0.5, 0.0, 0.0)})
    s = target.state(position=robot.point_position(x) + np.array([0.6, 0.0, 0.0]), angular_velocity=(0.0, 0.0, 0.1))
    res = spacearm.capture.capture(robot, target, s, kind="point", restitution=0.5, detumble_time=0.5, post_time=0.2)
    assert res.captured is None
    v = res.video(tmp_path / "point.mp4", width=W, height=H, fps=FPS, renderer="mujoco", speed=4.0)
    _, frames = _read(v.path)
    assert v.renderer == "mujoco" and len(frames) == v.frames and frames[0].std() > 5


def test_mujoco_renders_beyond_its_default_framebuffer(tmp_path):
    _mujoco_or_skip()
    robot = spacearm.presets.spatial6()
    traj = spacearm.simulate(robot, 0.02, dt=1e-2)  # one frame at 30 fps
    v = traj.video(tmp_path / "hd.mp4", renderer="mujoco")  # the defaults: 1280x720, wider than MuJoCo's 640x480 buffer
    meta, frames = _read(v.path)
    assert (v.width, v.height, v.frames) == (1280, 720, 1) and tuple(meta["size"]) == (1280, 720) and meta["fps"] == 30
    assert frames.shape == (1, 720, 1280, 3) and frames[0].std() > 5


def test_an_encoder_failure_is_an_os_error_naming_the_file(run, tmp_path, monkeypatch):
    monkeypatch.setattr(sv, "_ffmpeg", lambda: "/bin/false")  # an encoder that fails at once
    path = tmp_path / "run.mp4"
    with pytest.raises(OSError, match="ffmpeg could not write the video") as info:
        run.video(path, width=W, height=H, fps=FPS, renderer="matplotlib", speed=4.0)
    assert info.value.filename == str(path)
    assert not list(tmp_path.iterdir())
