"""The 3-D browser viewer (spacearm.viz.viewer, docs/viewer.md).

The scene is read back from the written HTML the way the browser reads it (the base64 msgpack
commands decoded with u-msgpack-python, independently of the writer) and checked against the
core's kinematics and the recorded states, with quaternions turned into matrices by scipy; the
page is loaded in headless Chromium (tests/browser.py) and its screenshot must show the robot.
"""

from __future__ import annotations

import base64
import json
import re
from pathlib import Path

import numpy as np
import pytest

import spacearm
from spacearm.cli import main

pytest.importorskip("meshcat")
umsgpack = pytest.importorskip("umsgpack")
Rotation = pytest.importorskip("scipy.spatial.transform").Rotation

from browser import dump_dom, screenshot  # noqa: E402  (tests/browser.py)


# ---- reading a saved scene back --------------------------------------------------------------
def _commands(html: str) -> list:
    match = re.search(r"var spacearm_commands = (\[.*?\]);\n", html, re.S)
    assert match, "the page holds no command list"
    return [umsgpack.unpackb(base64.b64decode(b)) for b in json.loads(match.group(1).replace("<\\/", "</"))]


def _objects(cmds) -> dict:
    return {c["path"]: c["object"] for c in cmds if c["type"] == "set_object"}


def _transforms(cmds) -> dict:
    return {c["path"]: np.array(c["matrix"], dtype=float).reshape(4, 4).T for c in cmds if c["type"] == "set_transform"}


def _tracks(cmds) -> dict:
    """{node path: {"position": (times s, values), ...}} of the one animation."""
    anims = [c for c in cmds if c["type"] == "set_animation"]
    assert len(anims) == 1
    out = {}
    for a in anims[0]["animations"]:
        fps = a["clip"]["fps"]
        out[a["path"]] = {t["name"].lstrip("."): (np.array([k["time"] for k in t["keys"]], dtype=float) / fps,
                                                  np.array([k["value"] for k in t["keys"]], dtype=float))
                          for t in a["clip"]["tracks"]}
    return out


def _matrix(q) -> np.ndarray:
    return Rotation.from_quat(np.asarray(q, dtype=float)).as_matrix()  # scipy: [x, y, z, w]


def _moving_run(robot, duration=1.0, seed=3):
    rng = np.random.default_rng(seed)
    u0 = robot.zero_velocity()
    u0[:6] = rng.normal(scale=0.05, size=6)
    u0[6:] = rng.normal(scale=0.6, size=robot.n_dof)
    return spacearm.simulate(robot, duration, u0=u0, dt=0.01)


def _ur5_on_bus():
    from robot_data import robot_urdf

    ur5 = robot_urdf("ur_description/urdf/ur5_robot.urdf")
    bus = spacearm.io.load_toml(spacearm.examples.path("spacecraft_bus"))
    return spacearm.io.load_urdf(ur5, mount_on=bus, at=(0.6, 0, 0, 0, 0, 0), end_effector="tool0")


@pytest.fixture(scope="module")
def spatial6_run():
    return _moving_run(spacearm.presets.spatial6())


@pytest.fixture(scope="module")
def spatial6_html(spatial6_run, tmp_path_factory):
    path = tmp_path_factory.mktemp("viewer") / "spatial6.html"
    spatial6_run.view(path, fps=25)
    return path


# ---- the scene against the core ----------------------------------------------------------------
def test_body_poses_are_the_core_kinematics(spatial6_run, spatial6_html):
    traj, robot = spatial6_run, spatial6_run.robot
    cmds = _commands(spatial6_html.read_text())
    tracks = _tracks(cmds)
    static = _transforms(cmds)
    names = [robot.description.base.name] + [link.name for link in robot.description.links]
    rel = traj.t - traj.t[0]
    for b, name in enumerate(names):
        node = f"/spacearm/robot/bodies/{b}_{name}"
        times, pos = tracks[node]["position"]
        qtimes, quat = tracks[node]["quaternion"]
        np.testing.assert_array_equal(times, qtimes)
        assert len(times) >= 25  # one second at 25 key frames per second
        # each key frame is a recorded sample; its pose is the core's of that sample
        k = np.array([int(np.argmin(np.abs(rel - t))) for t in times])
        np.testing.assert_allclose(rel[k], times, rtol=0, atol=1e-12)
        kin = robot.forward_kinematics(np.ascontiguousarray(traj.x[k]))
        np.testing.assert_allclose(pos, kin.com_in_world[:, b], rtol=0, atol=1e-12)
        np.testing.assert_allclose(_matrix(quat), kin.body_to_world[:, b], rtol=0, atol=1e-12)
        # the static transform is the first key frame's pose
        np.testing.assert_allclose(static[node][:3, 3], kin.com_in_world[0, b], atol=1e-12)
        np.testing.assert_allclose(static[node][:3, :3], kin.body_to_world[0, b], atol=1e-12)
    # below /spacearm the coordinates are 𝒥's; /spacearm itself is only shifted (the camera's centre)
    np.testing.assert_array_equal(static["/spacearm"][:3, :3], np.eye(3))
    # the base's pose is the recorded configuration itself
    times, pos = tracks[f"/spacearm/robot/bodies/0_{names[0]}"]["position"]
    k = np.array([int(np.argmin(np.abs(rel - t))) for t in times])
    np.testing.assert_allclose(pos, traj.x[k, :3], atol=1e-12)
    assert np.ptp(pos, axis=0).max() > 1e-4  # the run moves: a test on a still scene proves little


def test_shapes_sit_at_their_placement_in_the_body_frame(spatial6_run, spatial6_html):
    robot = spatial6_run.robot
    cmds = _commands(spatial6_html.read_text())
    objects, static = _objects(cmds), _transforms(cmds)
    names = [robot.description.base.name] + [link.name for link in robot.description.links]
    geoms = robot.description.geometries
    assert geoms
    for g in geoms:
        node = f"/spacearm/robot/bodies/{g.body_index}_{names[g.body_index]}/geometry/{g.name}"
        geometry = objects[node]["geometries"][0]
        assert geometry["type"] == "BoxGeometry"
        np.testing.assert_allclose([geometry["width"], geometry["height"], geometry["depth"]], g.size, rtol=0, atol=1e-12)
        np.testing.assert_allclose(static[node][:3, 3], g.origin, atol=1e-12)
        np.testing.assert_allclose(static[node][:3, :3], _matrix(g.rotation), atol=1e-12)
        colour = objects[node]["materials"][0]["color"]
        assert colour == sum(int(round(255 * c)) << s for c, s in zip(g.rgba[:3], (16, 8, 0)))
    # a shape's corner in 𝒥 at a key frame: x = r_i + R_i (p_g + R_g s) (docs/geometry.md)
    g = geoms[-1]
    node = f"/spacearm/robot/bodies/{g.body_index}_{names[g.body_index]}"
    times, pos = _tracks(cmds)[node]["position"]
    _, quat = _tracks(cmds)[node]["quaternion"]
    corner = 0.5 * np.asarray(g.size)
    world = pos[-1] + _matrix(quat[-1]) @ (np.asarray(g.origin) + _matrix(g.rotation) @ corner)
    x_last = spatial6_run.x[-1]
    kin = robot.forward_kinematics(x_last)
    expected = kin.com_in_world[g.body_index] + kin.body_to_world[g.body_index] @ (np.asarray(g.origin) + _matrix(g.rotation) @ corner)
    np.testing.assert_allclose(world, expected, atol=1e-12)


def test_end_effector_path_and_momentum_arrows(spatial6_run, spatial6_html):
    traj, robot = spatial6_run, spatial6_run.robot
    cmds = _commands(spatial6_html.read_text())
    objects, tracks = _objects(cmds), _tracks(cmds)
    # the path: every recorded sample's end-effector position (float32 in the page)
    line = objects["/spacearm/robot/ee_path"]["geometries"][0]["data"]["attributes"]["position"]
    pts = np.frombuffer(line["array"].data, dtype=np.float32).reshape(-1, 3)
    np.testing.assert_allclose(pts, robot.point_position(np.ascontiguousarray(traj.x)), atol=1e-6)
    # the arrows: from the system CM along P and L_com, lengths proportional to the norms
    rel = traj.t - traj.t[0]
    for name, column in (("P", "P"), ("L", "L_com")):
        times, origin = tracks[f"/spacearm/momentum/{name}/shaft"]["position"]
        _, quat = tracks[f"/spacearm/momentum/{name}/shaft"]["quaternion"]
        _, head = tracks[f"/spacearm/momentum/{name}/head"]["position"]
        _, scale = tracks[f"/spacearm/momentum/{name}/head"]["scale"]
        k = np.array([int(np.argmin(np.abs(rel - t))) for t in times])
        xs, us = np.ascontiguousarray(traj.x[k]), np.ascontiguousarray(traj.u[k])
        np.testing.assert_allclose(origin, robot.center_of_mass(xs), atol=1e-9)
        v = np.asarray(getattr(robot.momentum(xs, us), column))
        assert np.linalg.norm(v, axis=1).min() > 1e-3  # a run with momentum
        direction = np.einsum("kij,j->ki", _matrix(quat), [0.0, 1.0, 0.0])  # the arrow's y axis
        np.testing.assert_allclose(direction, v / np.linalg.norm(v, axis=1, keepdims=True), atol=1e-9)
        # the head's base lies on the arrow; the arrow's length (shaft + head) is proportional to |v|
        along = np.einsum("ki,ki->k", head - origin, direction)
        np.testing.assert_allclose(np.linalg.norm(head - origin, axis=1), along, atol=1e-9)
        _, shaft_scale = tracks[f"/spacearm/momentum/{name}/shaft"]["scale"]
        np.testing.assert_allclose(shaft_scale[:, 1], along, atol=1e-9)
        head_height = objects[f"/spacearm/momentum/{name}/head/body"]["geometries"][0]["height"]
        total = along + head_height * scale[:, 1]
        norms = np.linalg.norm(v, axis=1)
        np.testing.assert_allclose(total / total.max(), norms / norms.max(), rtol=1e-9)


def test_zero_momentum_draws_no_arrow():
    robot = spacearm.presets.spatial6()
    traj = spacearm.simulate(robot, 0.5, controller=spacearm.control.JointPD(kp=20.0, kd=5.0, reference=list(robot.initial_q + 0.2)), dt=0.002)
    from spacearm.viz.viewer import trajectory_scene

    scene = trajectory_scene(traj)
    cmds = scene.commands()
    paths = {c.path.lower() for c in cmds if type(c).__name__ == "SetObject"}
    assert not any("/momentum/" in p for p in paths)
    assert any("zero over the run" in text for _, text in scene.legend)


def test_page_is_self_contained(spatial6_html):
    text = spatial6_html.read_text()
    urls = set(re.findall(r"https?://[^\s\"'<>)]+", text))
    assert urls <= {"http://www.w3.org/1999/xhtml"}, urls  # an XML namespace name, never fetched
    assert not re.search(r"<(script|link|img|iframe)[^>]*\s(src|href)\s*=", text, re.I)
    assert "fetch(" not in text.split("var spacearm_commands")[1]
    assert text.count("<script>") == 3 and "MeshCat.Viewer" in text  # meshcat, the WebGL check, the scene


def test_capture_scene_moves_the_target_and_shows_the_grasp(tmp_path):
    from spacearm.capture import Target, capture

    robot = spacearm.presets.spatial6()
    x0 = robot.neutral_configuration()
    ee = robot.point_position(x0)
    target = Target(40.0, [3.0, 4.0, 5.0], grasp_points={"handle": [-0.3, 0.0, 0.0]})
    s0 = target.state(position=ee + [0.4, 0.0, 0.0], angular_velocity=[0.0, 0.0, 0.2])
    res = capture(robot, target, s0, x0=x0, approach_time=6.0, detumble_time=1.0, post_time=0.3)
    path = tmp_path / "capture.html"
    assert res.view(path) == str(path)
    cmds = _commands(path.read_text())
    tracks = _tracks(cmds)
    node = f"/spacearm/target/bodies/0_{target.name}"
    times, pos = tracks[node]["position"]
    _, quat = tracks[node]["quaternion"]
    rel = res.t - res.t[0]
    k = np.array([int(np.argmax(np.where(np.abs(rel - t) < 1e-12, np.arange(len(rel)), -1))) for t in times])
    np.testing.assert_allclose(rel[k], times, atol=1e-12)
    np.testing.assert_allclose(pos, res.target[k, :3], atol=1e-12)  # the recorded target states
    np.testing.assert_allclose(_matrix(quat), _matrix(res.target[k, 3:7]), atol=1e-12)
    assert np.ptp(pos, axis=0).max() > 1e-3
    # its shape: the box of its moments; the grasp marker appears at the capture instant
    assert _objects(cmds)[f"{node}/geometry/{target.body.description.geometries[0].name}"]["geometries"][0]["type"] == "BoxGeometry"
    gt, gscale = tracks["/spacearm/grasp"]["scale"]
    _, gpos = tracks["/spacearm/grasp"]["position"]
    t_grasp = res.phase_start("capture")
    assert np.all(gscale[gt < t_grasp - 1e-9] < 1e-3) and np.all(gscale[gt >= t_grasp] == 1.0)
    np.testing.assert_allclose(gpos, np.tile(res.impact.point, (len(gt), 1)), atol=1e-12)
    # the CLI draws the saved record the same way (the models travel in the .npz)
    rec = tmp_path / "capture.npz"
    res.save(rec)
    out = tmp_path / "from_cli.html"
    assert main(["view", str(rec), "--out", str(out)]) == 0
    cli_tracks = _tracks(_commands(out.read_text()))
    np.testing.assert_allclose(cli_tracks[node]["position"][1], pos, atol=1e-12)


def test_live_view_serves_the_same_scene(spatial6_run):
    from spacearm.viz.viewer import trajectory_scene

    scene = trajectory_scene(spatial6_run)
    vis = scene.show(open=False)
    try:
        page = vis.static_html()  # the server's own copy of the scene (meshcat's get_scene)
    finally:
        vis.window.server_proc.kill()
        vis.window.server_proc.wait()
    served = [umsgpack.unpackb(base64.b64decode(b)) for b in re.findall(r"data:application/octet-binary;base64,([A-Za-z0-9+/=]+)", page)]
    ours = {c["path"] for c in _commands(scene.html()) if c["type"] == "set_object"}
    assert {c["path"] for c in served if c["type"] == "set_object"} == ours
    assert any(c["type"] == "set_animation" for c in served)


# ---- errors ------------------------------------------------------------------------------------
def test_bad_options_are_spacearm_errors(spatial6_run, tmp_path):
    with pytest.raises(spacearm.ArgumentError, match="fps"):
        spatial6_run.view(tmp_path / "a.html", fps=0)
    with pytest.raises(spacearm.ArgumentError, match="geometry"):
        spatial6_run.view(tmp_path / "a.html", geometry="wire")
    bare = spacearm.Trajectory(data={"t": spatial6_run.t, "x": spatial6_run.x, "u": spatial6_run.u})
    with pytest.raises(spacearm.ArgumentError, match="needs the robot"):
        bare.view(tmp_path / "a.html")
    assert not (tmp_path / "a.html").exists()


def test_missing_mesh_is_said_and_the_rest_drawn(tmp_path):
    b = spacearm.Robot.builder("demo", base_mass=100.0, base_inertia=[10, 10, 10])
    b.add_link("arm", parent="base", joint="revolute", axis=(0, 0, 1), origin=(0.5, 0, 0), com=(0.5, 0, 0), mass=5.0,
               inertia=[0.01, 0.4, 0.4])
    b.add_geometry("base", "mesh", file=str(tmp_path / "gone.stl"))
    b.add_geometry("arm", "capsule", radius=0.04, length=1.0, rpy=(0, 1.5707963267948966, 0))
    robot = b.build()
    traj = spacearm.simulate(robot, 0.2, dt=0.01)
    from spacearm.viz.viewer import trajectory_scene

    with pytest.warns(UserWarning, match="gone.stl"):
        scene = trajectory_scene(traj)
    assert any("gone.stl" in n for n in scene.notes)
    paths = {c.path.lower() for c in scene.commands() if type(c).__name__ == "SetObject"}
    assert "/spacearm/robot/bodies/0_base/geometry/box_of_moments" in paths  # the stand-in
    capsule = [p for p in paths if p.startswith("/spacearm/robot/bodies/1_arm/geometry/")]
    assert sorted(p.rsplit("/", 1)[1] for p in capsule) == ["cap_bottom", "cap_top", "cylinder"]


def test_cli_view(tmp_path, capsys):
    run = tmp_path / "run.npz"
    assert main(["simulate", "spatial6", "--duration", "0.3", "--out", str(run)]) == 0
    out = tmp_path / "scene.html"
    assert main(["view", str(run), "--out", str(out)]) == 0
    assert "wrote scene" in capsys.readouterr().out and out.stat().st_size > 100_000
    # a trajectory saved without its model needs --model
    traj = spacearm.Trajectory.load(run)
    bare = tmp_path / "bare.npz"
    spacearm.Trajectory(data={k: traj[k] for k in traj.keys}, meta=traj.meta).save(bare)
    assert main(["view", str(bare), "--out", str(tmp_path / "b.html")]) == 2
    assert "--model" in capsys.readouterr().err and not (tmp_path / "b.html").exists()
    assert main(["view", str(bare), "--model", "spatial6", "--out", str(tmp_path / "b.html")]) == 0
    # not a record; an old capture record without models
    junk = tmp_path / "junk.npz"
    np.savez(junk, a=np.zeros(3))
    assert main(["view", str(junk), "--out", str(tmp_path / "c.html")]) == 2
    assert "spacearm: error:" in capsys.readouterr().err
    old = tmp_path / "old.npz"
    np.savez(old, t=np.zeros(2), phase=np.zeros(2), target=np.zeros((2, 13)), impact_point=np.zeros(3))
    assert main(["view", str(old), "--out", str(tmp_path / "c.html")]) == 2
    assert "capture ... --out" in capsys.readouterr().err
    assert main(["view", str(tmp_path / "none.npz")]) == 2


# ---- in a real browser -------------------------------------------------------------------------
def _pixels(png):
    Image = pytest.importorskip("PIL.Image")
    return np.asarray(Image.open(png).convert("RGB"), dtype=int)


def _warm(img):
    """Pixels of the robot's colours in the middle of the view: not the sky-blue gradient of
    meshcat's background (blue well above red everywhere) — the gold bus, the grey links."""
    h, w, _ = img.shape
    mid = img[h // 5: 4 * h // 5, w // 5: 7 * w // 10]
    r, g, b = mid[..., 0], mid[..., 1], mid[..., 2]
    return int(np.count_nonzero(r >= b - 10)), int(np.count_nonzero((r > b + 40) & (g > b)))


@pytest.mark.parametrize("which", ["ur5_on_bus", "spatial6"])
def test_chromium_draws_the_robot(which, tmp_path):
    robot = _ur5_on_bus() if which == "ur5_on_bus" else spacearm.presets.spatial6()
    page = tmp_path / f"{which}.html"
    _moving_run(robot, duration=0.5).view(page, fps=20, geometry="collision")  # the light meshes: SwiftShader is slow
    from spacearm.viz.viewer import Scene

    empty = tmp_path / "empty.html"
    Scene("empty", 20).save(empty)
    dom = dump_dom(page, budget_ms=3000)
    assert "<canvas" in dom
    for control in ("play", "pause", "reset", "time", "Animations"):
        assert f">{control}<" in dom, control
    shot, blank = screenshot(page, tmp_path / f"{which}.png", width=1000, height=700), screenshot(empty, tmp_path / "empty.png", width=1000, height=700)
    img, bg = _pixels(shot), _pixels(blank)
    assert img.std() > 10  # not a uniform page
    robot_like, gold = _warm(img)
    assert robot_like > 2000 and gold > 500, (robot_like, gold)  # the bus (gold) and the arm are drawn
    bg_like, bg_gold = _warm(bg)  # meshcat's grid and axes only
    assert robot_like > 2 * bg_like and gold > 10 * max(bg_gold, 10), (robot_like, gold, bg_like, bg_gold)
    assert np.abs(img - bg).sum(axis=2).astype(bool).mean() > 0.02  # and differs from an empty scene


def test_ur5_meshes_are_sent_with_normals():
    robot = _ur5_on_bus()
    traj = spacearm.simulate(robot, 0.05, dt=0.01)
    from spacearm.viz.viewer import trajectory_scene

    scene = trajectory_scene(traj, geometry="collision")
    assert not scene.notes
    objects = {c.path.lower(): c.object.lower() for c in scene.commands() if type(c).__name__ == "SetObject"}
    names = [robot.description.base.name] + [link.name for link in robot.description.links]
    meshes = [g for g in robot.description.geometries if g.role == "collision" and g.shape == "mesh"]
    assert len(meshes) == 7
    for g in meshes:
        geometry = objects[f"/spacearm/robot/bodies/{g.body_index}_{names[g.body_index]}/geometry/{g.name}"]["geometries"][0]
        attrs = geometry["data"]["attributes"]
        n_vertices = len(attrs["position"]["array"].data) // 12
        assert n_vertices > 100 and len(attrs["normal"]["array"].data) // 12 == n_vertices
        faces = np.frombuffer(geometry["data"]["index"]["array"].data, dtype=np.uint32)
        assert faces.size % 3 == 0 and faces.max() < n_vertices
        normals = np.frombuffer(attrs["normal"]["array"].data, dtype=np.float32).reshape(-1, 3)
        np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-5)


def test_cli_live_view_serves_until_interrupted(tmp_path):
    import os
    import signal
    import subprocess
    import sys

    run = tmp_path / "run.npz"
    assert main(["simulate", "spatial6", "--duration", "0.2", "--out", str(run)]) == 0
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(Path(spacearm.__file__).parents[1])] + sys.path))
    proc = subprocess.Popen([sys.executable, "-m", "spacearm", "view", str(run), "--no-browser"], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=env)
    try:
        lines = []
        for line in proc.stdout:
            lines.append(line)
            if "serving the scene at" in line:
                break
        assert any("serving the scene at http://" in line for line in lines), lines
        proc.send_signal(signal.SIGINT)
        out, _ = proc.communicate(timeout=60)
        assert proc.returncode == 0 and "stopped" in out
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()


def test_without_webgl_the_page_says_so(tmp_path):
    # Issue 37 item 7: where WebGL cannot start the page stayed blank, with no message.
    from spacearm.viz.viewer import NO_WEBGL, Scene

    page = tmp_path / "empty.html"
    Scene("empty", 20).save(page)
    without = dump_dom(page, budget_ms=2000, extra=["--disable-webgl", "--disable-3d-apis"])
    assert 'id="spacearm-no-webgl"' in without and NO_WEBGL in without
    with_gl = dump_dom(page, budget_ms=2000)
    assert "spacearm-no-webgl" not in with_gl.split("</script>")[-1]  # drawn: no message element added


# ---- control-moment gyros (docs/cmg.md) --------------------------------------------------------
def test_cmg_gimbal_frame_and_rotor_disc_turn_with_the_gimbal_angle(tmp_path):
    """Each CMG's rotor disc, read back from the page, points at every key frame along
    R0(t) ŝ(δ(t)), ŝ(δ) = cos δ ŝ₀ + sin δ (ĝ × ŝ₀), the spin axis turned by the recorded gimbal
    angle about the gimbal axis (the closed form of docs/cmg.md, not the core's kinematics), and the
    gimbal frame's axle along R0(t) ĝ."""
    from cmg_models import pyramid_axes, pyramid_sat

    robot = pyramid_sat(arm=False)
    cmgs = robot.cmg_dofs
    u0 = robot.cmg_velocity(200.0)
    for rate, c in zip((0.9, -0.6, 0.4, 1.2), cmgs.values()):
        u0[6 + c["gimbal"]] = rate  # the gimbals turn freely, the rotors spin: the base tumbles
    traj = spacearm.simulate(robot, 1.5, u0=u0, dt=5e-3)
    path = tmp_path / "cmg.html"
    traj.view(path, fps=10)
    cmds = _commands(path.read_text())
    tracks, static, objects = _tracks(cmds), _transforms(cmds), _objects(cmds)
    rel = traj.t - traj.t[0]
    names = [robot.description.base.name] + [link.name for link in robot.description.links]
    gimbal_axes, spin_axes = pyramid_axes()
    y = np.array([0.0, 1.0, 0.0])  # three.js's cylinder axis
    for i, (name, c) in enumerate(cmgs.items()):
        g_body, r_body = robot.body_of_dof[c["gimbal"]], robot.body_of_dof[c["rotor"]]
        disc = f"/spacearm/robot/bodies/{r_body}_{names[r_body]}/cmg/disc"
        axle = f"/spacearm/robot/bodies/{g_body}_{names[g_body]}/cmg/frame/axle_plus"
        assert objects[disc]["geometries"][0]["type"] == "CylinderGeometry" and disc + "" in static
        sides = [p for p in objects if p.startswith(f"/spacearm/robot/bodies/{g_body}_{names[g_body]}/cmg/frame/side")]
        assert len(sides) == 4
        times, quat_r = tracks[f"/spacearm/robot/bodies/{r_body}_{names[r_body]}"]["quaternion"]
        _, quat_g = tracks[f"/spacearm/robot/bodies/{g_body}_{names[g_body]}"]["quaternion"]
        k = np.array([int(np.argmin(np.abs(rel - t))) for t in times])
        np.testing.assert_allclose(rel[k], times, rtol=0, atol=1e-12)
        delta = traj.q[k, c["gimbal"]]
        assert np.ptp(delta) > 0.3  # the gimbal turns: a still one would prove little
        g, s0 = gimbal_axes[i], spin_axes[i]
        spin = np.cos(delta)[:, None] * s0 + np.sin(delta)[:, None] * np.cross(g, s0)
        base = _matrix(traj.x[k, 3:7])
        expected = np.einsum("kij,kj->ki", base, spin)
        drawn = np.einsum("kij,j->ki", _matrix(quat_r), static[disc][:3, :3] @ y)
        np.testing.assert_allclose(drawn, expected, rtol=0, atol=1e-9)
        drawn_g = np.einsum("kij,j->ki", _matrix(quat_g), static[axle][:3, :3] @ y)
        np.testing.assert_allclose(drawn_g, base @ g, rtol=0, atol=1e-9)
        # the disc is the rotor's: J_s = m r² / 2
        assert objects[disc]["geometries"][0]["radiusTop"] == pytest.approx(np.sqrt(2 * 0.05 / 3.0), rel=1e-6)
