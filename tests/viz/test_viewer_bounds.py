"""The viewer's bounds (issue 38): records and meshes it reads, the values it writes, the server
it starts. Each test fails on the behaviour before: a decompression bomb inflated in full, a
traceback for a bad ``__meta__``, NaN written into the page, a reversed ``t`` accepted, mesh
files read from anywhere, quadratic normals without scipy, an orphaned meshcat server."""

from __future__ import annotations

import os
import signal
import struct
import subprocess
import sys
import time
import zlib
from pathlib import Path

import numpy as np
import pytest

import spacearm
from spacearm.cli import main

pytest.importorskip("meshcat")
pytest.importorskip("trimesh")

ENV = dict(os.environ, PYTHONPATH=os.pathsep.join([str(Path(spacearm.__file__).parents[1])] + sys.path))


@pytest.fixture(scope="module")
def run_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("rec") / "run.npz"
    assert main(["simulate", "spatial6", "--duration", "0.2", "--out", str(path)]) == 0
    return path


def _zip_bomb(path: Path, gigabytes: float = 2.5) -> None:
    """A ~2.5 MB .npz whose one member, x.npy, inflates to ``gigabytes`` GB of zeros: raw deflate
    blocks made once and repeated (each ends with a full flush, so each is the same bytes),
    written into a zip by hand (the CRC is left 0: the reader must refuse before inflating)."""
    chunk_len = 1 << 24
    count = int(gigabytes * 1e9) // chunk_len
    c = zlib.compressobj(9, zlib.DEFLATED, -15)
    header = bytearray(b"\x93NUMPY\x01\x00")
    text = ("{'descr': '<f8', 'fortran_order': False, 'shape': (%d,), }" % (count * chunk_len // 8)).encode()
    text += b" " * (63 - (len(header) + 2 + len(text)) % 64) + b"\n"
    header += struct.pack("<H", len(text)) + text
    data = c.compress(bytes(header)) + c.flush(zlib.Z_FULL_FLUSH)
    block = c.compress(bytes(chunk_len)) + c.flush(zlib.Z_FULL_FLUSH)
    data += block * count + c.flush()
    size = len(header) + count * chunk_len
    name = b"x.npy"
    local = struct.pack("<IHHHHHIIIHH", 0x04034B50, 20, 0, 8, 0, 0x21, 0, len(data), size, len(name), 0) + name
    central = struct.pack("<IHHHHHHIIIHHHHHII", 0x02014B50, 20, 20, 0, 8, 0, 0x21, 0, len(data), size, len(name),
                          0, 0, 0, 0, 0, 0) + name
    end = struct.pack("<IHHHHIIH", 0x06054B50, 0, 0, 1, 1, len(central), len(local) + len(data), 0)
    path.write_bytes(local + data + central + end)


# ---- records -----------------------------------------------------------------------------------
def test_decompression_bomb_is_refused_before_inflating(tmp_path, capsys):
    bomb = tmp_path / "bomb.npz"
    _zip_bomb(bomb)
    assert bomb.stat().st_size < 3_000_000
    start = time.perf_counter()
    assert main(["view", str(bomb), "--out", str(tmp_path / "b.html")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("spacearm: error:") and "before decompressing" in err and "2.5 GB" in err, err
    assert time.perf_counter() - start < 5.0 and not (tmp_path / "b.html").exists()
    with pytest.raises(spacearm.ResourceLimitError, match="decompression bomb"):
        spacearm.Trajectory.load(bomb)


def test_npy_header_larger_than_its_member_is_refused(tmp_path, capsys):
    """A header declaring a shape its member does not hold: numpy allocated the declared array
    (10^12 float64) before reading a byte."""
    import io
    import zipfile

    member = io.BytesIO()
    np.lib.format.write_array_header_1_0(member, {"descr": "<f8", "fortran_order": False, "shape": (10**12,)})
    member.write(bytes(32))
    forged = tmp_path / "forged.npz"
    with zipfile.ZipFile(forged, "w") as zf:
        zf.writestr("x.npy", member.getvalue())
    assert main(["view", str(forged), "--out", str(tmp_path / "f.html")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("spacearm: error:") and "declares an array of shape (1000000000000)" in err, err


@pytest.mark.parametrize("meta, says", [
    ("{not json", "not valid JSON"),
    ("[1, 2]", "must be a JSON object"),
    ('{"conserved": 5}', "__meta__['conserved']"),
    ('{"wheel_dofs": ["a"]}', "__meta__['wheel_dofs']"),
    ("[" * 100_000, "not valid JSON"),
])
def test_bad_meta_is_an_error_not_a_traceback(run_file, tmp_path, capsys, meta, says):
    files = dict(np.load(run_file))
    files["__meta__"] = np.array(meta)
    bad = tmp_path / "bad.npz"
    np.savez(bad, **files)
    assert main(["view", str(bad), "--out", str(tmp_path / "b.html")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("spacearm: error:") and says in err and "Traceback" not in err, err
    with pytest.raises(spacearm.ArgumentError, match="__meta__"):
        spacearm.Trajectory.load(bad)


# ---- values written ----------------------------------------------------------------------------
def test_reversed_or_non_finite_times_and_overflowing_positions_are_refused(tmp_path):
    robot = spacearm.presets.spatial6()
    run = spacearm.simulate(robot, 0.2, dt=0.01)
    from spacearm.viz.viewer import trajectory_scene

    def traj(t=None, x=None):
        return spacearm.Trajectory(robot=robot, data={"t": run.t if t is None else t, "x": run.x if x is None else x,
                                                      "u": run.u}, meta=run.meta)

    with pytest.raises(spacearm.ArgumentError, match=r"times must increase .* t\[1\] = 0.19 s after t\[0\] = 0.2 s"):
        trajectory_scene(traj(t=run.t[::-1].copy()))
    t = run.t.copy()
    t[3] = np.nan
    with pytest.raises(spacearm.ArgumentError, match=r"times must be finite, got t\[3\] = nan"):
        trajectory_scene(traj(t=t))
    for value in (1e308, 1e20):
        x = run.x.copy()
        x[5:, 0] = value
        with pytest.raises(spacearm.ArgumentError, match="cannot be drawn.*not a finite number within 1e\\+15 m"):
            traj(x=x).view(tmp_path / "big.html")
    assert not (tmp_path / "big.html").exists()
    # equal times (an impact's jump) are still drawn
    t = run.t.copy()
    t[4] = t[3]
    trajectory_scene(traj(t=t))


# ---- meshes ------------------------------------------------------------------------------------
def _grid_mesh(n: int):
    """A wavy n × n grid: (n + 1)² vertices, 2 n² triangles."""
    i, j = np.meshgrid(np.arange(n + 1), np.arange(n + 1), indexing="ij")
    v = np.column_stack([i.ravel(), j.ravel(), 3 * np.sin(i.ravel() * 0.3) * np.cos(j.ravel() * 0.2)]) * 0.01
    k = lambda a, b: a * (n + 1) + b  # noqa: E731
    a, b = (m.ravel() for m in np.meshgrid(np.arange(n), np.arange(n), indexing="ij"))
    f = np.vstack([np.column_stack([k(a, b), k(a + 1, b), k(a + 1, b + 1)]), np.column_stack([k(a, b), k(a + 1, b + 1), k(a, b + 1)])])
    return v, f


def _robot_with_mesh(file):
    b = spacearm.Robot.builder("demo", base_mass=100.0, base_inertia=[10, 10, 10])
    b.add_link("arm", parent="base", joint="revolute", axis=(0, 0, 1), origin=(0.5, 0, 0), com=(0.5, 0, 0), mass=5.0,
               inertia=[0.01, 0.4, 0.4])
    b.add_geometry("base", "mesh", file=str(file), name="hull")
    return b.build()


def test_mesh_normals_are_the_area_weighted_reference(tmp_path):
    import trimesh

    v, f = _grid_mesh(12)
    stl = tmp_path / "grid.stl"
    trimesh.Trimesh(v, f, process=False).export(stl)
    from spacearm.viz.viewer import trajectory_scene

    scene = trajectory_scene(spacearm.simulate(_robot_with_mesh(stl), 0.05, dt=0.01))
    obj = {c.path.lower(): c.object.lower() for c in scene.commands() if type(c).__name__ == "SetObject"}
    geometry = obj["/spacearm/robot/bodies/0_base/geometry/hull"]["geometries"][0]["data"]
    pos = np.frombuffer(geometry["attributes"]["position"]["array"].data, dtype=np.float32).reshape(-1, 3).astype(float)
    faces = np.frombuffer(geometry["index"]["array"].data, dtype=np.uint32).reshape(-1, 3)
    normals = np.frombuffer(geometry["attributes"]["normal"]["array"].data, dtype=np.float32).reshape(-1, 3)
    ref = np.zeros_like(pos)  # a plain loop: each triangle's (b - a) x (c - a) added to its corners
    for tri in faces:
        a, b, c = pos[tri]
        for corner in tri:
            ref[corner] += np.cross(b - a, c - a)
    ref /= np.linalg.norm(ref, axis=1)[:, None]
    np.testing.assert_allclose(normals, ref, atol=2e-5)


def test_mesh_normals_are_linear_without_scipy(tmp_path):
    """trimesh's vertex normals fall back to a quadratic loop without scipy, which the view
    extra did not install: a 100k-triangle STL took 267 s. Run with scipy hidden."""
    import trimesh

    v, f = _grid_mesh(224)
    assert len(f) > 100_000
    stl = tmp_path / "big.stl"
    trimesh.Trimesh(v, f, process=False).export(stl)
    code = (
        "import sys, time; sys.modules['scipy'] = None\n"
        "import spacearm\n"
        "from spacearm.viz.viewer import trajectory_scene\n"
        "b = spacearm.Robot.builder('demo', base_mass=100.0, base_inertia=[10, 10, 10])\n"
        "b.add_link('arm', parent='base', joint='revolute', axis=(0, 0, 1), origin=(0.5, 0, 0), com=(0.5, 0, 0), "
        "mass=5.0, inertia=[0.01, 0.4, 0.4])\n"
        f"b.add_geometry('base', 'mesh', file={str(stl)!r}, name='hull')\n"
        "traj = spacearm.simulate(b.build(), 0.05, dt=0.01)\n"
        "start = time.perf_counter(); scene = trajectory_scene(traj); took = time.perf_counter() - start\n"
        "assert not scene.notes, scene.notes\n"
        "print('took', took)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=ENV, timeout=120)
    assert out.returncode == 0, out.stderr[-2000:]
    took = float(out.stdout.split("took")[-1])
    assert took < 20.0, took


def test_extras_install_scipy():
    import tomllib

    extras = tomllib.loads((Path(__file__).parents[2] / "pyproject.toml").read_text())["project"]["optional-dependencies"]
    for extra in ("mesh", "view"):
        assert any(dep.split(">")[0].split("=")[0].strip() == "scipy" for dep in extras[extra]), extras[extra]


def test_record_meshes_are_read_from_its_folder_only(tmp_path, capsys):
    import trimesh

    v, f = _grid_mesh(2)
    outside = tmp_path / "elsewhere"
    outside.mkdir()
    trimesh.Trimesh(v, f, process=False).export(outside / "hull.stl")
    rec = tmp_path / "rec"
    rec.mkdir()
    spacearm.simulate(_robot_with_mesh(outside / "hull.stl"), 0.05, dt=0.01).save(rec / "run.npz")
    out = tmp_path / "a.html"
    assert main(["view", str(rec / "run.npz"), "--out", str(out)]) == 0
    said = capsys.readouterr().out
    assert "outside the mesh folders" in said and "not read" in said
    from spacearm.viz.viewer import trajectory_scene

    def drawn(**options):
        with pytest.warns(UserWarning) if options.get("mesh_dirs") == [rec] else _nothing():
            scene = trajectory_scene(spacearm.Trajectory.load(rec / "run.npz"), **options)
        return any(c.path.lower().endswith("/geometry/hull") for c in scene.commands() if type(c).__name__ == "SetObject")

    assert not drawn(mesh_dirs=[rec])
    assert drawn(mesh_dirs=[rec, outside]) and drawn()
    # the CLI's options
    assert main(["view", str(rec / "run.npz"), "--mesh-dir", str(outside), "--out", str(out)]) == 0
    assert "not read" not in capsys.readouterr().out
    assert main(["view", str(rec / "run.npz"), "--allow-outside-meshes", "--out", str(out)]) == 0
    assert "not read" not in capsys.readouterr().out
    # a symbolic link inside the folder to a file outside is outside
    if hasattr(os, "symlink"):
        os.symlink(outside / "hull.stl", rec / "link.stl")
        spacearm.simulate(_robot_with_mesh(rec / "link.stl"), 0.05, dt=0.01).save(rec / "run2.npz")
        assert main(["view", str(rec / "run2.npz"), "--out", str(out)]) == 0
        assert "outside the mesh folders" in capsys.readouterr().out


class _nothing:
    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False


# ---- the live server ---------------------------------------------------------------------------
def _children(pid: int) -> list:
    kids = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                stat = Path(f"/proc/{entry}/stat").read_text()
            except OSError:
                continue
            if int(stat.rsplit(")", 1)[1].split()[1]) == pid:
                kids.append(int(entry))
    return kids


def _running(pid: int) -> bool:
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
@pytest.mark.parametrize("sig", ["SIGTERM", "SIGHUP", "SIGKILL"])
def test_live_server_ends_with_the_viewer(run_file, sig):
    proc = subprocess.Popen([sys.executable, "-m", "spacearm", "view", str(run_file), "--no-browser"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=ENV)
    servers = []
    try:
        for line in proc.stdout:
            if "serving the scene at" in line:
                break
        servers = _children(proc.pid)
        assert servers and all(_running(s) for s in servers)
        proc.send_signal(getattr(signal, sig))
        proc.wait(timeout=30)
        deadline = time.monotonic() + 5.0
        while any(_running(s) for s in servers) and time.monotonic() < deadline:
            time.sleep(0.1)
        assert not any(_running(s) for s in servers), f"meshcat server {servers} left running after {sig}"
        if sig != "SIGKILL":
            assert proc.returncode == 0
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        for s in servers:
            if _running(s):
                os.kill(s, signal.SIGKILL)
