"""The 3-D viewer in the browser: a run as a meshcat scene (three.js), saved as one
self-contained HTML file or served live (the ``view`` extra; docs/viewer.md).

A [`Scene`][spacearm.viz.viewer.Scene] is the list of meshcat commands that draw one run: the bodies of
the robot (and of a capture's target) with their geometry, the base and end-effector frames, the
named points, the end-effector path as a line, the momentum vectors as arrows, and one animation
that moves them, played with meshcat's own controls (play, pause, reset, the time slider, the
speed). The same commands go to a file ([`Scene.save`][spacearm.viz.viewer.Scene.save]: meshcat's
viewer bundle and the commands inline, opened from ``file://`` with no server and no network) or
to a live meshcat server ([`Scene.show`][spacearm.viz.viewer.Scene.show]).

Every pose comes from the core: each body's node is placed at its frame's pose
``(r_i, R_i)`` of [`Robot.forward_kinematics`][spacearm.Robot.forward_kinematics] at the recorded
configurations (the quaternion of ``R_i`` from [`spacearm.rotations.quat_from_matrix`][spacearm.rotations.quat_from_matrix]),
and the shapes, frames and points hang below it at their fixed placement in the body frame
(docs/geometry.md): ``x = r_i + R_i (p_g + R_g s)``, the composition three.js does. Nothing of
the kinematics is recomputed here.

Scene tree (meshcat paths; a body's name has its ``/`` replaced):

- ``/spacearm/robot/bodies/<i>_<name>``: body ``i``, animated; below it ``geometry/<name>``
  (the shapes), ``frame`` (the base's and the end-effector body's triads), ``points/<name>``.
  A control-moment gyro's gimbal and rotor (docs/cmg.md) without shapes of their own get
  ``cmg/frame`` (the gimbal frame: a rectangle in the plane of the gimbal and spin axes, with the
  gimbal axle) and ``cmg/disc`` (the rotor disc about its spin axis, with its axle) below their
  body nodes, so the disc turns with the recorded gimbal angle.
- ``/spacearm/robot/ee_path``: the end-effector path over the whole run (a line).
- ``/spacearm/momentum/P`` and ``/spacearm/momentum/L``: the arrows (``shaft``, ``head``).
- ``/spacearm/contacts/<j>``: a contact run's contact slot ``j`` (``point``, and the arrows
  ``normal`` and ``friction``: the forces on the pair's second body; ``contact_slots``).
- ``/spacearm/target/bodies/...``: a capture's target, or a contact run's free target; ``/spacearm/grasp``: the grasp point,
  shown from the capture instant on.

Below ``/spacearm`` the coordinates are 𝒥's; ``/spacearm`` itself is shifted by minus the centre
of the drawn scene (``Scene.extent``), so that the camera turns about the scene.
"""

from __future__ import annotations

import base64
import html as _html
import json
import math
import os
import warnings
import webbrowser
from typing import Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

from .._util.summary import controller_label
from .._util.atomic import write_text
from .._util.optional import require
from .._util.paths import inside
from .._util.show import shown as _shown
from ..errors import ArgumentError, MissingDependencyError
from ..rotations import quat_exp, quat_from_matrix, quat_to_matrix

__all__ = ["Scene", "trajectory_scene", "capture_scene", "view", "contact_slots", "GEOMETRY_ROLES", "MAX_COORDINATE",
           "ROBOT_PREFIX", "TARGET_PREFIX"]

PathLike = Union[str, "os.PathLike[str]"]

#: Which shapes are drawn (``geometry=``): a body with none of the chosen role shows its others.
GEOMETRY_ROLES = ("visual", "collision")
#: Root of the robot's nodes in the scene tree.
ROBOT_PREFIX = "/spacearm/robot"
#: Root of a capture target's nodes in the scene tree.
TARGET_PREFIX = "/spacearm/target"

_STICK_COLOR = (0.12, 0.47, 0.71, 1.0)  # links without geometry
_BASE_COLOR = (0.75, 0.75, 0.78, 1.0)  # a base without geometry: its equivalent box
_P_COLOR = (0.1, 0.75, 0.2, 1.0)  # linear momentum arrow
_L_COLOR = (0.85, 0.15, 0.75, 1.0)  # angular momentum arrow
_PATH_COLOR = (0.85, 0.1, 0.1, 1.0)
_GRASP_COLOR = (1.0, 0.45, 0.0, 1.0)
_GIMBAL_COLOR = (0.93, 0.62, 0.12, 1.0)  # a CMG's gimbal frame
_ROTOR_COLOR = (0.35, 0.37, 0.45, 1.0)  # a CMG's rotor disc
_CONTACT_COLOR = (0.95, 0.85, 0.1, 1.0)  # contact points
_NORMAL_COLOR = (0.1, 0.55, 0.95, 1.0)  # contact normal forces
_FRICTION_COLOR = (0.95, 0.2, 0.2, 1.0)  # contact friction forces
_TINY = 1e-6  # the scale of a hidden node (three.js needs an invertible matrix)
#: The largest coordinate the viewer draws, m (three.js computes in 32-bit floats, which end at
#: 3.4e38; a scene wider than this shows nothing anyway): a larger or non-finite one is refused.
MAX_COORDINATE = 1e15


def _meshcat():
    """meshcat's modules (the ``view`` extra)."""
    require("meshcat", "the 3-D viewer")
    import meshcat.animation
    import meshcat.commands
    import meshcat.geometry
    import meshcat.path

    return meshcat


def _hex(rgba) -> int:
    r, g, b = (int(round(255 * float(np.clip(c, 0.0, 1.0)))) for c in tuple(rgba)[:3])
    return (r << 16) | (g << 8) | b


def _material(mc, rgba):
    alpha = float(rgba[3]) if len(rgba) > 3 else 1.0
    return mc.geometry.MeshPhongMaterial(color=_hex(rgba), opacity=alpha, transparent=alpha < 1.0)


def _node(name: str) -> str:
    return str(name).replace("/", "_") or "_"


def _transform(position=(0.0, 0.0, 0.0), quaternion=None, scale=None) -> np.ndarray:
    """The 4×4 matrix of a placement (rotation from the core's quaternion-to-matrix)."""
    m = np.eye(4)
    if quaternion is not None:
        m[:3, :3] = quat_to_matrix(np.asarray(quaternion, dtype=float))
    if scale is not None:
        m[:3, :3] = m[:3, :3] @ np.diag(np.asarray(scale, dtype=float))
    m[:3, 3] = np.asarray(position, dtype=float)
    return m


def _y_to(direction) -> np.ndarray:
    """The quaternion ``[x, y, z, w]`` turning three.js's cylinder axis ``y`` onto ``direction``
    (the rotation about ``y × d`` by the angle between them; ``spacearm.rotations.quat_exp``)."""
    d = np.asarray(direction, dtype=float)
    n = float(np.linalg.norm(d))
    if n == 0.0:
        return np.array([0.0, 0.0, 0.0, 1.0])
    d = d / n
    axis = np.array([d[2], 0.0, -d[0]])  # y × d
    s, c = float(np.linalg.norm(axis)), float(d[1])
    if s < 1e-12:
        return np.array([0.0, 0.0, 0.0, 1.0]) if c > 0 else np.array([1.0, 0.0, 0.0, 0.0])
    return quat_exp(axis / s * math.atan2(s, c))


def _vertex_normals(vertices, faces) -> np.ndarray:
    """Unit vertex normals of a triangle mesh, in O(faces): each vertex's is the sum of the
    (unnormalized) normals ``(b - a) × (c - a)`` of the triangles that use it, so weighted by
    their areas, then normalized; a vertex with none (unused, or only degenerate triangles)
    gets ``+z``. (trimesh's ``vertex_normals`` is quadratic in the faces without scipy: a
    100k-triangle STL took 267 s.)"""
    v = np.asarray(vertices, dtype=float).reshape(-1, 3)
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    cross = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    acc = np.zeros_like(v)
    for c in range(3):
        for k in range(3):
            acc[:, c] += np.bincount(f[:, k], weights=cross[:, c], minlength=len(v))
    norms = np.linalg.norm(acc, axis=1)
    out = np.tile([0.0, 0.0, 1.0], (len(v), 1))
    ok = np.isfinite(norms) & (norms > 0)
    out[ok] = acc[ok] / norms[ok, None]
    return out


class _MeshData:
    """A triangle mesh with vertex normals for meshcat (its ``TriangularMeshGeometry`` sends no
    normals, and three.js shades a mesh without them black)."""

    def __init__(self, mc, vertices, faces, normals):
        self._geometry = mc.geometry.TriangularMeshGeometry(vertices, faces)
        self._pack = mc.geometry.pack_numpy_array
        self._normals = np.asarray(normals, dtype=np.float32)

    def build(self):
        geometry, pack, normals = self._geometry, self._pack, self._normals
        lower = geometry.lower

        def lower_with_normals(object_data):
            data = lower(object_data)
            data["data"]["attributes"]["normal"] = pack(normals.T)
            return data

        geometry.lower = lower_with_normals
        return geometry


# ---------------------------------------------------------------------------------------------
# the scene
# ---------------------------------------------------------------------------------------------
#: What the page says where the browser cannot start WebGL (the 3-D view needs it).
NO_WEBGL = ("This 3-D view needs WebGL, which this browser could not start: enable hardware acceleration or "
            "WebGL in its settings, or open the page in another browser.")


class Scene:
    """The meshcat commands of one scene and its animation.

    Built by [`trajectory_scene`][spacearm.viz.viewer.trajectory_scene] and
    [`capture_scene`][spacearm.viz.viewer.capture_scene] (through ``Trajectory.view`` and
    ``CaptureResult.view``). ``times`` are the sample times (s, from the run's start) of the
    animation's key frames and ``samples`` their indices into the run; ``notes`` says what the
    drawing left out or stood in for (a mesh file that could not be read, a momentum arrow not
    drawn because it is zero), each also issued as a warning.
    """

    def __init__(self, title: str, fps: float):
        self._mc = _meshcat()
        self.title = str(title)
        self.fps = float(fps)
        self._objects: List = []  # (path, object), in order
        self._transforms: Dict[str, np.ndarray] = {}
        self._properties: List[Tuple[str, str, object]] = []
        self._tracks: Dict[str, Dict[str, Tuple[np.ndarray, np.ndarray]]] = {}
        self.times = np.zeros(0)
        self.samples = np.zeros(0, dtype=int)
        self.legend: List[Tuple[Tuple[float, ...], str]] = []
        self.notes: List[str] = []
        self.extent = (np.zeros(3), 1.0)  # centre, radius of what is drawn
        self.mesh_dirs: Optional[List[str]] = None  # the folders mesh files are read from (None: any)

    # ---- building --------------------------------------------------------------------------
    def _drawable(self, path: str, what: str, values) -> np.ndarray:
        """``values`` as floats, each finite and within ``MAX_COORDINATE`` m, or an
        [`ArgumentError`][spacearm.ArgumentError] naming the node and the key frame (a NaN or an
        overflow written into the page draws nothing, silently)."""
        v = np.asarray(values, dtype=float)
        with np.errstate(invalid="ignore"):
            ok = np.isfinite(v) & (np.abs(v) <= MAX_COORDINATE)
        if not ok.all():
            bad = np.argwhere(~ok)[0]
            frame = ""
            if v.ndim == 2 and what != "line" and len(self.times) == len(v):
                frame = f" at key frame {int(bad[0])} (t = {float(self.times[bad[0]]):.6g} s)"
            raise ArgumentError(f"the run cannot be drawn: the {what} of '{path}'{frame} is {float(v[tuple(bad)]):.6g}, "
                                f"not a finite number within {MAX_COORDINATE:.0e} m (non-finite or overflowing states?)")
        return v

    def _add(self, path: str, obj, transform: Optional[np.ndarray] = None) -> None:
        self._objects.append((path, obj))
        if transform is not None:
            self._transforms[path] = self._drawable(path, "placement", transform)

    def _set_transform(self, path: str, transform: np.ndarray) -> None:
        self._transforms[path] = self._drawable(path, "placement", transform)

    def _animate(self, path: str, prop: str, values: np.ndarray) -> None:
        """A track of ``prop`` (``position``, ``quaternion`` or ``scale``) at the key frames."""
        self._tracks.setdefault(path, {})[prop] = self._drawable(path, prop, values)

    def _note(self, message: str) -> None:
        self.notes.append(message)
        warnings.warn(message, UserWarning, stacklevel=4)

    # ---- the commands -----------------------------------------------------------------------
    def commands(self) -> list:
        """The meshcat commands (``meshcat.commands`` objects), in the order they are sent:
        objects, static transforms, properties, then the animation."""
        mc = self._mc
        P = mc.path.Path
        split = lambda p: P(tuple(s for s in p.split("/") if s))  # noqa: E731
        out = [mc.commands.SetObject(obj, path=split(path)) for path, obj in self._objects]
        out += [mc.commands.SetTransform(m, split(path)) for path, m in self._transforms.items()]
        out += [mc.commands.SetProperty(key, value, split(path)) for path, key, value in self._properties]
        if len(self.times) > 1 and self._tracks:
            anim = mc.animation.Animation(default_framerate=self.fps)
            keys = [float(t) * self.fps for t in self.times]  # frames; three.js divides by the clip's fps
            jstype = {"position": "vector3", "quaternion": "quaternion", "scale": "vector3"}
            for path, tracks in self._tracks.items():
                clip = mc.animation.AnimationClip(fps=self.fps)
                for prop, values in tracks.items():
                    clip.tracks[prop] = mc.animation.AnimationTrack(prop, jstype[prop], list(keys),
                                                                    [[float(v) for v in row] for row in values])
                anim.clips[split(path)] = clip
            out.append(mc.commands.SetAnimation(anim, play=self._play, repetitions=self._repetitions))
        return out

    _play = True
    _repetitions = 1

    def _packed(self) -> List[str]:
        import umsgpack  # meshcat's own encoder (u-msgpack-python, a meshcat dependency)

        return [base64.b64encode(umsgpack.packb(c.lower())).decode("ascii") for c in self.commands()]

    def html(self, *, controls: bool = True) -> str:
        """The scene as one self-contained HTML page: meshcat's viewer (its JavaScript bundle
        inline) and the commands (msgpack, base64), no request to any server or network.
        ``controls`` opens meshcat's control panel with the animation folder."""
        mc = self._mc
        bundle = os.path.join(os.path.dirname(mc.__file__), "viewer", "dist", "main.min.js")
        if not os.path.isfile(bundle):
            raise MissingDependencyError(f"meshcat's viewer bundle is missing ({bundle}): reinstall meshcat "
                                         '(pip install "spacearm[view]")', package="meshcat", extra="view")
        with open(bundle, encoding="utf-8") as fh:
            js = fh.read()
        legend = "".join(f'<div><span style="color:#{_hex(c):06x}">&#9632;</span> {_html.escape(text)}</div>'
                         for c, text in self.legend)
        opener = ("try { viewer.gui.open(); viewer.animator.folder.open(); } catch (e) {}" if controls else "")
        # Breaking "</script" inside the embedded strings keeps the HTML parser out of them.
        commands = json.dumps(self._packed()).replace("</", "<\\/")
        return (
            "<!DOCTYPE html>\n<html>\n<head><meta charset=\"utf-8\"><title>" + _html.escape(self.title) + "</title>\n"
            "<style>body { margin: 0; } #meshcat-pane { width: 100vw; height: 100vh; overflow: hidden; }\n"
            "#spacearm-legend { position: absolute; left: 8px; top: 8px; font: 13px sans-serif; color: #fff;"
            " background: rgba(0, 0, 0, 0.35); padding: 6px 9px; border-radius: 4px; pointer-events: none; }</style>\n"
            "</head>\n<body>\n<div id=\"meshcat-pane\"></div>\n"
            "<div id=\"spacearm-legend\"><b>" + _html.escape(self.title) + "</b>" + legend + "</div>\n"
            "<script>\n" + js.replace("</script", "<\\/script") + "\n</script>\n"
            # Without WebGL meshcat draws nothing and the page stayed blank: say so on the page.
            "<script>\n(function () {\n"
            "  var gl = null;\n"
            "  try { var c = document.createElement(\"canvas\"); gl = c.getContext(\"webgl2\") || c.getContext(\"webgl\"); } catch (e) {}\n"
            "  if (!gl) {\n"
            "    var note = document.createElement(\"div\");\n"
            "    note.id = \"spacearm-no-webgl\";\n"
            "    note.style.cssText = \"position:absolute;left:0;right:0;top:40%;text-align:center;font:16px sans-serif;color:#222\";\n"
            "    note.textContent = \"" + NO_WEBGL + "\";\n"
            "    document.body.appendChild(note);\n"
            "  }\n"
            "})();\n</script>\n"
            "<script>\nvar viewer = new MeshCat.Viewer(document.getElementById(\"meshcat-pane\"));\n"
            "var spacearm_commands = " + commands + ";\n"
            "spacearm_commands.forEach(function (b64) {\n"
            "  var s = atob(b64), bytes = new Uint8Array(s.length);\n"
            "  for (var i = 0; i < s.length; i++) bytes[i] = s.charCodeAt(i);\n"
            "  viewer.handle_command_bytearray(bytes);\n"
            "});\n" + opener + "\n</script>\n</body>\n</html>\n"
        )

    def save(self, path: PathLike, *, controls: bool = True) -> str:
        """Write [`html`][spacearm.viz.viewer.Scene.html] to ``path`` (atomically). Returns the path."""
        write_text(path, self.html(controls=controls), suffix=".html")
        return str(path)

    def show(self, *, open: bool = True, zmq_url: Optional[str] = None):
        """Send the scene to a live meshcat viewer and return its ``meshcat.Visualizer``:
        a new server (a subprocess serving http://127.0.0.1:7000/static/ or the next free port,
        ``vis.window.server_proc``, which ends when this process ends, however it ends: it
        watches its parent) unless ``zmq_url`` names a running one. ``open`` opens it in the
        web browser."""
        mc = self._mc
        if zmq_url is None:
            proc, zmq_url = _start_server()
            try:
                vis = mc.Visualizer(zmq_url=zmq_url)
            except BaseException:
                _stop_server(proc)
                raise
            vis.window.server_proc = proc
        else:
            vis = mc.Visualizer(zmq_url=zmq_url)
        for command in self.commands():
            vis.window.send(command)
        if open:
            vis.open()
        return vis


# The live server: meshcat's own, run by a small wrapper that ends it when its parent process is
# gone (its parent id changes when the parent dies, whatever killed it: SIGTERM, SIGHUP, SIGKILL).
# meshcat's start_zmq_server_as_subprocess only kills it at a normal exit (atexit), so a viewer
# killed by a signal left its server running, holding its ports, for ever.
_SERVER_WRAPPER = """
import os, sys, threading, time
parent = int(sys.argv[1])
def watch():
    while os.getppid() == parent:
        time.sleep(0.2)
    os._exit(0)
if os.getppid() != parent:
    os._exit(0)
threading.Thread(target=watch, daemon=True).start()
sys.argv = ["meshcat-server"] + sys.argv[2:]
import runpy
runpy.run_module("meshcat.servers.zmqserver", run_name="__main__", alter_sys=True)
"""


def _stop_server(proc) -> None:
    if proc.poll() is None:
        proc.kill()
    proc.wait()


def _start_server():
    """A meshcat server subprocess that ends with this process: ``(process, zmq_url)``."""
    import atexit
    import subprocess
    import sys

    from meshcat.servers.zmqserver import match_zmq_url

    env = dict(os.environ)
    meshcat_root = os.path.dirname(os.path.dirname(os.path.abspath(_meshcat().__file__)))
    env["PYTHONPATH"] = os.pathsep.join([meshcat_root] + ([env["PYTHONPATH"]] if env.get("PYTHONPATH") else []))
    proc = subprocess.Popen([sys.executable, "-u", "-c", _SERVER_WRAPPER, str(os.getpid())], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, env=env, start_new_session=True)
    atexit.register(_stop_server, proc)
    try:
        line = ""
        while "zmq_url" not in line:
            raw = proc.stdout.readline()
            if not raw and proc.poll() is not None:
                err = proc.stderr.read().decode("utf-8", "replace").strip().splitlines()
                raise MissingDependencyError(f"the meshcat server ended at its start (exit code {proc.returncode}): "
                                             f"{err[-1] if err else 'no message'}", package="meshcat", extra="view")
            line = raw.decode("utf-8", "replace").strip()
        proc.stdout.readline()  # the web URL, asked of the server by the Visualizer
    except BaseException:
        _stop_server(proc)
        raise
    return proc, match_zmq_url(line)


# ---------------------------------------------------------------------------------------------
# drawing a model
# ---------------------------------------------------------------------------------------------
def _mesh_object(scene: Scene, g, material):
    """A mesh geometry as a meshcat mesh (through trimesh), or ``None`` with a note."""
    mc = scene._mc
    file = g.file
    roots = scene.mesh_dirs
    if roots is not None and file:  # confined: a model from a file (spacearm view of a record)
        if "://" in file:
            scene._note(f"mesh '{file[:200]}' of geometry '{g.name}' is a URL, not a file: not read, not drawn")
            return None
        if not os.path.isabs(file):
            file = os.path.join(roots[0], file)
        if not inside(file, roots):
            scene._note(f"mesh '{file[:200]}' of geometry '{g.name}' (body '{g.body}') is outside the mesh folders "
                        f"({', '.join(str(r)[:120] for r in roots)}): not read, not drawn (CLI --allow-outside-meshes reads it, "
                        "--mesh-dir DIR adds a folder; in Python mesh_dirs=None or [...])")
            return None
    if not file or not os.path.isfile(file):
        scene._note(f"mesh '{g.file}' of geometry '{g.name}' (body '{g.body}') does not exist: not drawn")
        return None
    try:
        trimesh = require("trimesh", "drawing mesh geometry in the viewer")
    except MissingDependencyError as exc:
        scene._note(f"geometry '{g.name}' (body '{g.body}') not drawn: {exc}")
        return None
    try:
        mesh = trimesh.load(file, force="mesh")
        vertices, faces = np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces, dtype=np.int64)
    except Exception as exc:  # trimesh raises many kinds; the note names the file
        scene._note(f"mesh '{g.file}' of geometry '{g.name}' could not be read ({type(exc).__name__}: {exc}): not drawn")
        return None
    if len(faces) == 0:
        scene._note(f"mesh '{g.file}' of geometry '{g.name}' has no faces: not drawn")
        return None
    normals = _vertex_normals(vertices, faces)
    return mc.geometry.Mesh(_MeshData(mc, vertices, faces, normals).build(), material)


def _shape(scene: Scene, path: str, g) -> bool:
    """Draw one geometry below ``path`` (its body's node), at its placement in the body frame.
    Returns whether anything was drawn."""
    mc = scene._mc
    G = mc.geometry
    mat = _material(mc, g.rgba)
    node = f"{path}/geometry/{_node(g.name)}"
    place = _transform(g.origin, g.rotation)
    # three.js's cylinder lies along y, spacearm's along the geometry frame's z: a quarter turn about x.
    y_to_z = _transform(quaternion=(math.sqrt(0.5), 0.0, 0.0, math.sqrt(0.5)))
    if g.shape == "box":
        scene._add(node, G.Mesh(G.Box([float(v) for v in g.size]), mat), place)
    elif g.shape == "sphere":
        scene._add(node, G.Mesh(G.Sphere(float(g.radius)), mat), place)
    elif g.shape == "cylinder":
        scene._add(node, G.Mesh(G.Cylinder(float(g.length), float(g.radius)), mat), place @ y_to_z)
    elif g.shape == "capsule":
        r, h = float(g.radius), float(g.length)
        scene._add(node + "/cylinder", G.Mesh(G.Cylinder(h, r), mat), place @ y_to_z)
        for end, z in (("cap_top", 0.5 * h), ("cap_bottom", -0.5 * h)):
            scene._add(f"{node}/{end}", G.Mesh(G.Sphere(r), mat), place @ _transform((0.0, 0.0, z)))
    elif g.shape == "mesh":
        obj = _mesh_object(scene, g, mat)
        if obj is None:
            return False
        scene._add(node, obj, place @ _transform(scale=g.scale))
    else:  # a shape kind this viewer does not know (the model gained one): said, not hidden
        scene._note(f"geometry '{g.name}' has shape '{g.shape}', which the viewer cannot draw")
        return False
    return True


def _stick(scene: Scene, path: str, a, b, radius: float, color) -> None:
    """A cylinder from ``a`` to ``b`` (body frame) below ``path``."""
    mc = scene._mc
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    d = b - a
    n = float(np.linalg.norm(d))
    if n < 1e-9:
        return
    scene._add(path, mc.geometry.Mesh(mc.geometry.Cylinder(n, radius), _material(mc, color)),
               _transform(0.5 * (a + b), _y_to(d)))


def _base_radius(robot) -> float:
    """Half the diagonal of the base's box of moments (m): how far the base reaches from its CM."""
    from .. import _core

    base = robot.description.base
    moments = np.linalg.eigvalsh(np.asarray(base.inertia, dtype=float))
    return 0.5 * float(np.linalg.norm(_core.box_of_moments(float(base.mass), [float(m) for m in moments])))


def _model_size(robot) -> float:
    """A length for markers and sticks: the model's largest joint or CM offset (m)."""
    lengths = [float(np.linalg.norm(link.origin)) for link in robot.description.links]
    lengths += [float(np.linalg.norm(link.com)) for link in robot.description.links]
    base = robot.description.base
    lengths.append(math.sqrt(1.5 * float(np.trace(np.asarray(base.inertia))) / float(base.mass)))
    return max(max(lengths), 1e-3)


def _cmg_bodies(robot) -> Dict[int, Tuple[str, np.ndarray, np.ndarray, float]]:
    """The bodies of the model's CMGs ([`Robot.cmg_dofs`][spacearm.Robot.cmg_dofs]), body index →
    (``"gimbal"`` or ``"rotor"``, the gimbal axis and the spin axis in that body's frame, the rotor
    radius drawn). The axes are the joints' own (``description``): the gimbal's in the gimbal
    frame, the spin axis in the rotor frame (and carried into the gimbal frame at the spin joint's
    zero by its rotation). The radius is the uniform disc's, ``J_s = m r² / 2``, or a twentieth of
    the model's size for a massless rotor, at most a quarter of the model's size."""
    desc = robot.description
    out: Dict[int, Tuple[str, np.ndarray, np.ndarray, float]] = {}
    size = _model_size(robot)
    for c in robot.cmg_dofs.values():
        g_body, r_body = robot.body_of_dof[c["gimbal"]], robot.body_of_dof[c["rotor"]]
        gimbal, rotor = desc.links[g_body - 1], desc.links[r_body - 1]
        g = np.asarray(gimbal.axis, dtype=float)
        s_rotor = np.asarray(rotor.axis, dtype=float)
        to_gimbal = quat_to_matrix(np.asarray(rotor.rotation, dtype=float))  # rotor frame → gimbal frame at zero spin
        s_gimbal = to_gimbal @ s_rotor
        g_rotor = to_gimbal.T @ g
        radius = math.sqrt(2.0 * c["rotor_inertia"] / rotor.mass) if rotor.mass > 0 else 0.05 * size
        radius = min(radius, 0.25 * size)  # a light rotor of large J_s stays inside the picture
        out[g_body] = ("gimbal", g, s_gimbal, radius)
        out[r_body] = ("rotor", g_rotor, s_rotor, radius)
    return out


def _draw_cmg_part(scene: Scene, node: str, kind: str, g: np.ndarray, s: np.ndarray, radius: float, joint: np.ndarray) -> None:
    """A CMG's gimbal frame or rotor disc below body ``node`` (``_cmg_bodies``), centred on the
    gimbal joint ``joint`` (body frame)."""
    mc = scene._mc
    g, s = g / np.linalg.norm(g), s / np.linalg.norm(s)
    thin = 0.06 * radius
    if kind == "rotor":
        scene._add(f"{node}/cmg/disc", mc.geometry.Mesh(mc.geometry.Cylinder(0.3 * radius, radius), _material(mc, _ROTOR_COLOR)),
                   _transform(joint, _y_to(s)))
        _stick(scene, f"{node}/cmg/axle", joint - 0.75 * radius * s, joint + 0.75 * radius * s, thin, _ROTOR_COLOR)
        return
    a, b = 1.2 * radius * g, 0.75 * radius * s  # the frame's half-sides: along the gimbal axis, along the spin axis
    corners = [joint + a + b, joint - a + b, joint - a - b, joint + a - b]
    for k in range(4):
        _stick(scene, f"{node}/cmg/frame/side{k}", corners[k], corners[(k + 1) % 4], thin, _GIMBAL_COLOR)
    for sign, end in ((1.0, "axle_plus"), (-1.0, "axle_minus")):
        _stick(scene, f"{node}/cmg/frame/{end}", joint + sign * a, joint + sign * 1.6 * radius * g, 1.5 * thin, _GIMBAL_COLOR)


def _draw_model(scene: Scene, robot, prefix: str, geometry: str, *, ee_frame: bool, frames: bool, points: bool) -> List[str]:
    """The nodes of every body of ``robot`` below ``prefix``/bodies, with their shapes (or a
    stand-in), frames and points. Returns the body nodes' paths (index = body index)."""
    mc = scene._mc
    desc = robot.description
    names = [desc.base.name] + [link.name for link in desc.links]
    nodes = [f"{prefix}/bodies/{i}_{_node(n)}" for i, n in enumerate(names)]
    size = _model_size(robot)
    other = [r for r in GEOMETRY_ROLES if r != geometry][0]
    shapes: Dict[int, list] = {}
    for g in desc.geometries:
        shapes.setdefault(g.body_index, []).append(g)
    children: Dict[int, List[int]] = {}
    for i, link in enumerate(desc.links):
        children.setdefault(link.parent_index, []).append(i + 1)
    body_points: Dict[int, list] = {}
    for p in desc.points:
        body_points.setdefault(p.body_index, []).append(p)
    cmgs = _cmg_bodies(robot)
    if cmgs:
        scene.legend.append((_ROTOR_COLOR, f"CMGs ({len(cmgs) // 2}): gimbal frame and rotor disc"))
    for b, node in enumerate(nodes):
        mine = shapes.get(b, [])
        chosen = [g for g in mine if g.role == geometry] or [g for g in mine if g.role == other]
        drawn = sum(_shape(scene, node, g) for g in chosen)
        if drawn:
            continue
        if b in cmgs:
            kind, g_axis, s_axis, radius = cmgs[b]
            _draw_cmg_part(scene, node, kind, g_axis, s_axis, radius, -np.asarray(desc.links[b - 1].com, dtype=float))
            continue
        # No shape: a stand-in, like the GIF's (docs/viewer.md).
        if b == 0:
            moments, axes = np.linalg.eigh(np.asarray(desc.base.inertia, dtype=float))
            if np.linalg.det(axes) < 0:
                axes[:, 2] = -axes[:, 2]
            from .. import _core

            sides = _core.box_of_moments(float(desc.base.mass), [float(m) for m in moments])
            scene._add(f"{node}/geometry/box_of_moments", mc.geometry.Mesh(mc.geometry.Box([float(s) for s in sides]),
                                                                            _material(mc, _BASE_COLOR)),
                       _transform(quaternion=quat_from_matrix(axes)))
            continue
        link = desc.links[b - 1]
        joint = -np.asarray(link.com, dtype=float)  # the joint, in the link frame (origin at the CM)
        ends = [np.asarray(desc.links[c - 1].origin, dtype=float) for c in children.get(b, [])]
        if not ends:
            pts = body_points.get(b, [])
            ends = [np.asarray(pts[0].offset, dtype=float)] if pts else [np.asarray(link.com, dtype=float)]
        for j, end in enumerate(ends):
            _stick(scene, f"{node}/geometry/stick{j}", joint, end, 0.04 * size, _STICK_COLOR)
    if frames:
        scene._add(f"{nodes[0]}/frame", mc.geometry.triad(0.5 * size))
    if ee_frame and robot.end_effector is not None:
        b, off = robot.resolve_point(robot.end_effector)
        scene._add(f"{nodes[b]}/ee_frame", mc.geometry.triad(0.3 * size), _transform(off))
    if points:
        for b, pts in body_points.items():
            for p in pts:
                scene._add(f"{nodes[b]}/points/{_node(p.name)}",
                           mc.geometry.Mesh(mc.geometry.Sphere(0.03 * size), _material(mc, (1.0, 1.0, 1.0, 1.0))),
                           _transform(p.offset))
    return nodes


def _pose_model(scene: Scene, robot, nodes: List[str], xs: np.ndarray) -> np.ndarray:
    """Animate every body node at the core's poses of ``xs`` (K, nx); the first one also as the
    static transform. Returns the CM positions (K, nb, 3) for the view's extent."""
    kin = robot.forward_kinematics(np.ascontiguousarray(xs))
    rot, pos = np.asarray(kin.body_to_world), np.asarray(kin.com_in_world)
    if rot.ndim == 3:  # one state
        rot, pos = rot[None], pos[None]
    k, nb = pos.shape[:2]
    quats = quat_from_matrix(rot.reshape(k * nb, 3, 3)).reshape(k, nb, 4)
    for b, node in enumerate(nodes):
        m = np.eye(4)
        m[:3, :3], m[:3, 3] = rot[0, b], pos[0, b]
        scene._set_transform(node, m)
        scene._animate(node, "position", pos[:, b])
        scene._animate(node, "quaternion", quats[:, b])
    return pos


def _line(scene: Scene, path: str, points: np.ndarray, color) -> None:
    mc = scene._mc
    pts = scene._drawable(path, "line", points).astype(np.float32)
    if len(pts) < 2:
        return
    scene._add(path, mc.geometry.Line(mc.geometry.PointsGeometry(pts.T),
                                      mc.geometry.LineBasicMaterial(color=_hex(color), linewidth=2)))


def _arrow(scene: Scene, name: str, origins: np.ndarray, vectors: np.ndarray, length: float, color, label: str,
           unit: str, floor: float) -> None:
    """An animated arrow ``/spacearm/momentum/<name>`` from ``origins`` along ``vectors``
    (K, 3), the largest ``length`` m long. A vector that stays below ``floor`` (its numerical
    zero: a millionth of the bodies' own momentum scale, ``Robot.momentum_scales``, above the
    drift of a conserving run's integration) is not drawn, and the legend says so."""
    norms = np.linalg.norm(vectors, axis=1)
    peak = float(norms.max()) if norms.size else 0.0
    if not peak > floor:
        bound = "0" if floor < 1e-200 else f"{floor:.2g} {unit}"
        scene.legend.append((color, f"{label}: zero over the run (|{name}| ≤ {bound}), no arrow"))
        return
    per_m = peak / length
    scene.legend.append((color, f"{label}: 1 m of arrow = {per_m:.4g} {unit}"))
    _arrow_nodes(scene, f"/spacearm/momentum/{name}", origins, vectors, per_m, length, color)


def _arrow_nodes(scene: Scene, root: str, origins: np.ndarray, vectors: np.ndarray, per_m: float, length: float, color) -> None:
    """The animated arrow ``root/shaft`` and ``root/head`` from ``origins`` along ``vectors``
    (K, 3), ``|v| / per_m`` m long (shaft plus head), its head and thickness those of an arrow
    ``length`` m long; a zero vector hides it (scale ~0)."""
    mc = scene._mc
    norms = np.linalg.norm(vectors, axis=1)
    lengths = norms / per_m
    head = 0.12 * length
    shaft_len = np.maximum(lengths - head, 0.0)
    quats = np.array([_y_to(v) for v in vectors])
    radius = 0.012 * length
    mat = _material(mc, color)
    scene._add(f"{root}/shaft/body", mc.geometry.Mesh(mc.geometry.Cylinder(1.0, radius), mat), _transform((0.0, 0.5, 0.0)))
    scene._add(f"{root}/head/body", mc.geometry.Mesh(mc.geometry.Cylinder(head, radiusTop=0.0, radiusBottom=2.5 * radius), mat),
               _transform((0.0, 0.5 * head, 0.0)))
    visible = lengths > 0.0
    shaft_scale = np.column_stack([np.ones_like(lengths), np.where(shaft_len > 0, shaft_len, _TINY), np.ones_like(lengths)])
    head_scale = np.where(visible[:, None], np.minimum(lengths / head, 1.0)[:, None], _TINY) * np.ones((1, 3))
    head_scale = np.maximum(head_scale, _TINY)
    dirs = np.where(visible[:, None], vectors / np.where(norms > 0, norms, 1.0)[:, None], 0.0)
    head_pos = origins + dirs * (shaft_len[:, None])
    for part, pos, scale in (("shaft", origins, shaft_scale), ("head", head_pos, head_scale)):
        node = f"{root}/{part}"
        scene._set_transform(node, _transform(pos[0], quats[0], scale[0]))
        scene._animate(node, "position", pos)
        scene._animate(node, "quaternion", quats)
        scene._animate(node, "scale", scale)


def contact_slots(traj, samples: np.ndarray) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The contacts of a run at the key frames ``samples``, slot by slot, from its record
    ``contact_forces`` (one row per acting contact per sample, docs/contact.md): ``present``
    (K, S) whether slot ``j`` holds a contact at key frame ``k`` (the ``j``-th row of that
    sample, in the core's order), ``points`` (K, S, 3), ``normal`` (K, S, 3) the normal force
    ``f_n n̂`` and ``friction`` (K, S, 3) the friction ``f − f_n n̂``, each on the second body of
    the pair, in 𝒥; zeros where a slot is empty. ``S`` is the most contacts at one key frame."""
    rows = np.asarray(traj.contact_forces, dtype=float)
    samples = np.asarray(samples, dtype=int)
    per = [rows[rows[:, 0] == k] for k in samples]
    s = max((len(r) for r in per), default=0)
    k = len(samples)
    present = np.zeros((k, s), dtype=bool)
    points, normal, friction = (np.zeros((k, s, 3)) for _ in range(3))
    for i, r in enumerate(per):
        n = len(r)
        present[i, :n] = True
        points[i, :n] = r[:, 3:6]
        normal[i, :n] = r[:, 9:10] * r[:, 6:9]
        friction[i, :n] = r[:, 10:13] - normal[i, :n]
    return present, points, normal, friction


def _draw_contacts(scene: Scene, traj, samples: np.ndarray, length: float) -> List[np.ndarray]:
    """The contacts of a contact run at the key frames: slot ``j`` (``contact_slots``) is
    ``/spacearm/contacts/<j>/point`` (a ball at the point, hidden where the slot is empty) and the
    arrows ``/spacearm/contacts/<j>/normal`` and ``.../friction`` of the force on the second body
    from the point, both on one scale, the largest normal force ``length`` m. Returns the points
    drawn (for the view's extent)."""
    mc = scene._mc
    present, points, normal, friction = contact_slots(traj, samples)
    if present.size == 0 or not present.any():
        scene.legend.append((_CONTACT_COLOR, "contacts: none at the key frames"))
        return []
    peak = float(np.linalg.norm(normal, axis=2).max())
    per_m = peak / length if peak > 0 else 1.0
    scene.legend.append((_CONTACT_COLOR, f"contact points ({present.shape[1]} at most at once)"))
    scene.legend.append((_NORMAL_COLOR, f"contact normal force on the second body: 1 m of arrow = {per_m:.4g} N"))
    scene.legend.append((_FRICTION_COLOR, "contact friction force, same scale"))
    ball = 0.04 * length
    for j in range(present.shape[1]):
        root = f"/spacearm/contacts/{j}"
        # an empty slot: hidden, kept where it was last (or will first be) shown
        shown = present[:, j]
        first = int(np.argmax(shown))
        pos = points[:, j].copy()
        pos[: first] = pos[first]
        for i in range(first + 1, len(pos)):
            if not shown[i]:
                pos[i] = pos[i - 1]
        scale = np.where(shown, 1.0, _TINY)[:, None] * np.ones((1, 3))
        scene._add(f"{root}/point", mc.geometry.Mesh(mc.geometry.Sphere(ball), _material(mc, _CONTACT_COLOR)))
        scene._set_transform(f"{root}/point", _transform(pos[0], scale=scale[0]))
        scene._animate(f"{root}/point", "position", pos)
        scene._animate(f"{root}/point", "scale", scale)
        _arrow_nodes(scene, f"{root}/normal", pos, normal[:, j], per_m, length, _NORMAL_COLOR)
        _arrow_nodes(scene, f"{root}/friction", pos, friction[:, j], per_m, length, _FRICTION_COLOR)
    return [points[present]]


def _draw_free_target(scene: Scene, traj, target, samples: np.ndarray, geometry: str, frames: bool, points: bool) -> np.ndarray:
    """A contact run's free target (``target``: its model, a ``spacearm.Target`` or a rigid
    ``Robot``) under ``TARGET_PREFIX``, its body at the recorded 13-states' ``[r, quat]`` (its
    model's configuration: the CM and the attitude). Returns its CM positions."""
    from ..model.robot import Robot

    body = target.body if not isinstance(target, Robot) and isinstance(getattr(target, "body", None), Robot) else target
    if not isinstance(body, Robot) or body.n_dof != 0:
        raise ArgumentError(f"target must be the run's free target: a spacearm.Target or a rigid spacearm.Robot, got {type(target).__name__}")
    if not traj.has("target"):
        raise ArgumentError("target= draws a free target, but this run has none (simulate(..., target=, target_state=, contact=))")
    xs = np.ascontiguousarray(np.asarray(traj["target"], dtype=float)[samples, :7])
    nodes = _draw_model(scene, body, TARGET_PREFIX, geometry, ee_frame=False, frames=frames, points=points)
    return _pose_model(scene, body, nodes, xs).reshape(-1, 3)


def _key_samples(t: np.ndarray, fps: float, max_frames: int) -> np.ndarray:
    """Indices of the samples shown as key frames: the sample at or after each tick of ``fps``
    per second of the run (at most ``max_frames``), the last sample always; of samples at one
    instant (an impact's jump) the later."""
    t = np.asarray(t, dtype=float)
    if len(t) == 1:
        return np.zeros(1, dtype=int)
    span = float(t[-1] - t[0])
    n = int(min(max_frames, math.floor(span * fps + 1e-9) + 1))
    ticks = t[0] + np.linspace(0.0, span, max(n, 2))
    idx = np.unique(np.concatenate([np.searchsorted(t, ticks, side="left").clip(0, len(t) - 1), [len(t) - 1]]))
    # of equal times keep the later sample
    same_as_next = np.concatenate([t[idx[:-1]] == t[idx[1:]], [False]])
    idx = idx[~same_as_next]
    later = np.searchsorted(t, t[idx], side="right") - 1  # the last sample at each kept instant
    return np.unique(later)


def _mesh_dirs(dirs) -> Optional[List[str]]:
    if dirs is None:
        return None
    if isinstance(dirs, (str, os.PathLike)):
        dirs = [dirs]
    out = [os.path.abspath(os.fspath(d)) for d in dirs]
    if not out:
        raise ArgumentError("mesh_dirs must name at least one folder (None reads meshes from anywhere)")
    return out


def _check_times(t) -> np.ndarray:
    """The run's sample times: finite and never decreasing (equal at an impact's jump), else an
    [`ArgumentError`][spacearm.ArgumentError] naming the first sample at fault."""
    t = np.asarray(t, dtype=float).reshape(-1)
    if t.size == 0:
        raise ArgumentError("the run has no samples to draw")
    bad = np.flatnonzero(~np.isfinite(t))
    if bad.size:
        raise ArgumentError(f"the run's times must be finite, got t[{bad[0]}] = {t[bad[0]]}")
    back = np.flatnonzero(np.diff(t) < 0)
    if back.size:
        k = int(back[0]) + 1
        raise ArgumentError(f"the run's times must increase (equal only at an impact's jump), got t[{k}] = {t[k]:.6g} s "
                            f"after t[{k - 1}] = {t[k - 1]:.6g} s")
    return t


def _check_options(fps, max_frames, geometry) -> Tuple[float, int]:
    try:
        fps = float(fps)
        max_frames = int(max_frames)
    except (TypeError, ValueError):
        raise ArgumentError(f"fps must be a number > 0 and max_frames an integer >= 2, got {_shown(fps)} and "
                            f"{_shown(max_frames)}") from None
    if not (math.isfinite(fps) and fps > 0):
        raise ArgumentError(f"fps must be a finite number > 0 (key frames per second of the run), got {_shown(fps)}")
    if max_frames < 2:
        raise ArgumentError(f"max_frames must be >= 2, got {_shown(max_frames)}")
    if geometry not in GEOMETRY_ROLES:
        raise ArgumentError(f"geometry must be one of {list(GEOMETRY_ROLES)}, got {geometry!r}")
    return fps, max_frames


def _finish(scene: Scene, points: np.ndarray, play: bool, repetitions: int, pad: float = 0.0) -> None:
    """The extent and the camera. The ``/spacearm`` node is shifted by minus the centre of every
    drawn point, so that meshcat's camera, which orbits the viewer's origin, turns about the
    scene; it looks from a fixed direction, far enough to hold the scene. The grid and meshcat's
    axes are hidden (space has no floor)."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    pts = pts[np.all(np.isfinite(pts), axis=1)]
    centre = 0.5 * (pts.min(axis=0) + pts.max(axis=0)) if len(pts) else np.zeros(3)
    radius = (float(np.max(np.linalg.norm(pts - centre, axis=1))) if len(pts) else 1.0) + float(pad)  # pad: the bases' size
    scene.extent = (centre, max(radius, 1e-3))
    scene._set_transform("/spacearm", _transform(-centre))
    distance = 1.45 * max(radius, 0.25)
    direction = np.array([0.9, 1.2, 0.75]) / np.linalg.norm([0.9, 1.2, 0.75])  # +x to the left, away from the controls
    eye = distance * direction  # in 𝒥's axes (z up); meshcat's camera node is y up: (x, z, -y)
    scene._properties.append(("/Cameras/default/rotated/<object>", "position", [float(eye[0]), float(eye[2]), float(-eye[1])]))
    scene._properties.append(("/Grid", "visible", False))
    scene._properties.append(("/Axes", "visible", False))
    scene._play = bool(play)
    scene._repetitions = int(repetitions)


# ---------------------------------------------------------------------------------------------
# runs
# ---------------------------------------------------------------------------------------------
def _robot_scene(robot, t, x, heading: str, fps, max_frames, geometry, mesh_dirs, frames, points):
    """The scene of a run's robot at its key samples (the options checked first): ``(scene, idx,
    xs, cms)``, ``idx`` the key samples of ``t``, ``xs`` their states, ``cms`` the bodies' CMs
    there (what a run's scene draws before its own parts)."""
    fps, max_frames = _check_options(fps, max_frames, geometry)
    idx = _key_samples(_check_times(t), fps, max_frames)
    scene = Scene(heading, fps)
    scene.mesh_dirs = _mesh_dirs(mesh_dirs)
    scene.samples = idx
    scene.times = np.asarray(t[idx] - t[0], dtype=float)
    xs = np.ascontiguousarray(x[idx])
    nodes = _draw_model(scene, robot, ROBOT_PREFIX, geometry, ee_frame=frames, frames=frames, points=points)
    return scene, idx, xs, _pose_model(scene, robot, nodes, xs)


def _ee_path(scene, robot, x, path: bool) -> list:
    """The end-effector path over every sample of ``x`` as a line (when ``path`` and the robot
    has an end effector on an arm): ``[its points]`` for the scene's extent, else ``[]``."""
    if not (path and robot.end_effector is not None and robot.n_dof > 0):
        return []
    ee = robot.point_position(np.ascontiguousarray(x))
    _line(scene, f"{ROBOT_PREFIX}/ee_path", ee, _PATH_COLOR)
    scene.legend.append((_PATH_COLOR, f"end-effector path ({robot.end_effector})"))
    return [ee]


def trajectory_scene(
    traj,
    *,
    fps: float = 30.0,
    max_frames: int = 3000,
    geometry: str = "visual",
    momentum: bool = True,
    path: bool = True,
    frames: bool = True,
    points: bool = True,
    play: bool = True,
    repetitions: int = 1,
    title: Optional[str] = None,
    mesh_dirs: Optional[Sequence[PathLike]] = None,
    contacts: bool = True,
    target=None,
) -> Scene:
    """The [`Scene`][spacearm.viz.viewer.Scene] of a [`Trajectory`][spacearm.Trajectory] (it needs its robot).

    Key frames: the recorded sample at each ``1 / fps`` s of the run (at most ``max_frames``),
    played in real time (meshcat's speed control changes that). ``geometry``: the ``"visual"`` or
    ``"collision"`` shapes. ``momentum``: the linear momentum ``P`` and the angular momentum about
    the system CM ``L_com`` as arrows from the system CM, each scaled so that its largest value
    reaches out of the base (1.6 times the half-diagonal of the base's box of moments, plus a
    fifth of the arm's size; the legend gives the scale). ``path``: the end-effector path;
    ``frames``: the base and end-effector triads; ``points``: the named points. ``mesh_dirs``:
    the folders mesh files may be read from (a relative mesh path is taken from the first), for
    a model that came from a file not trusted (``spacearm view`` passes the record's folder); a
    mesh outside them is not read (a note says so). ``None`` (the default): any path, as the
    caller's own model gives it. ``contacts``: a contact run's contacts (its record
    ``contact_forces``, docs/contact.md) at each key frame, a ball at each point with the arrows
    of its normal and friction forces on the pair's second body (``/spacearm/contacts/<j>``).
    ``target``: a contact run's free target model (the ``target=`` of ``simulate``), drawn at
    its recorded states; without it the target is not drawn (a note says so).
    """
    robot = traj.robot
    if robot is None:
        raise ArgumentError("view needs the robot: build the Trajectory with robot=..., or load() a file saved with one")
    heading = title or f"{robot.name}: {traj.meta.get('mode', '')} ({controller_label(traj.meta.get('controller'))})"
    scene, idx, xs, cms = _robot_scene(robot, traj.t, traj.x, heading, fps, max_frames, geometry, mesh_dirs, frames, points)
    extent = [cms.reshape(-1, 3)] + _ee_path(scene, robot, traj.x, path)
    size = 2.0 * float(np.max(np.linalg.norm(cms.reshape(-1, 3) - cms.reshape(-1, 3).mean(axis=0), axis=1)))
    size = max(size, _model_size(robot))
    span = 1.6 * _base_radius(robot) + 0.2 * size  # out of the base, which holds the system CM
    if target is not None:
        extent.append(_draw_free_target(scene, traj, target, idx, geometry, frames, points))
    elif traj.has("target") and traj.has("contact_count"):
        scene._note("the run's free target is not drawn: pass its model, view(..., target=...)")
    if contacts and traj.has("contact_forces"):
        extent += _draw_contacts(scene, traj, idx, 0.25 * size)
    if momentum:
        us = np.ascontiguousarray(traj.u[idx])
        m = robot.momentum(xs, us)
        com = np.asarray(traj.com[idx]) if traj.has("com") else robot.center_of_mass(xs)
        scales = robot.momentum_scales(xs, us)
        _arrow(scene, "P", com, np.asarray(m.P), span, _P_COLOR, "P, linear momentum", "N s",
               1e-6 * max(float(scales[:, 0].max()), 1e-300))
        _arrow(scene, "L", com, np.asarray(m.L_com), span, _L_COLOR, "L, angular momentum about the CM", "N m s",
               1e-6 * max(float(scales[:, 2].max()), 1e-300))
    _finish(scene, np.vstack(extent), play, repetitions, pad=_base_radius(robot))
    return scene


def capture_scene(
    result,
    *,
    fps: float = 30.0,
    max_frames: int = 3000,
    geometry: str = "visual",
    momentum: bool = True,
    path: bool = True,
    frames: bool = True,
    points: bool = True,
    play: bool = True,
    repetitions: int = 1,
    title: Optional[str] = None,
    mesh_dirs: Optional[Sequence[PathLike]] = None,
) -> Scene:
    """The [`Scene`][spacearm.viz.viewer.Scene] of a [`CaptureResult`][spacearm.capture.CaptureResult]: the robot, the target moving
    (its bodies at the core's poses of its recorded states), the grasp point (a marker from the
    capture instant on, at the impact point), the end-effector path and the momentum of robot +
    target (``P`` and ``L`` about 𝒥's origin, drawn from the origin). Options as
    [`trajectory_scene`][spacearm.viz.viewer.trajectory_scene]."""
    robot, target = result.robot, result.target_model
    heading = title or f"{robot.name} capturing {target.name} ({result.kind} grasp, {result.mode})"
    scene, idx, xs, cms = _robot_scene(robot, result.t, result.x, heading, fps, max_frames, geometry, mesh_dirs, frames, points)
    body = target.body
    txs = np.ascontiguousarray(np.asarray(result.target)[idx, : body.nx])
    tnodes = _draw_model(scene, body, TARGET_PREFIX, geometry, ee_frame=False, frames=frames, points=points)
    tcms = _pose_model(scene, body, tnodes, txs)
    extent = [cms.reshape(-1, 3), tcms.reshape(-1, 3)] + _ee_path(scene, robot, result.x, path)
    size = max(_model_size(robot), _model_size(body))
    # the grasp: a marker at the impact point, hidden (scale ~0) until the capture instant
    mc = scene._mc
    point = np.asarray(result.impact.point, dtype=float)
    t_grasp = result.phase_start("capture") - float(result.t[0])
    shown = np.where(scene.times >= t_grasp - 1e-12, 1.0, _TINY)[:, None] * np.ones((1, 3))
    scene._add("/spacearm/grasp", mc.geometry.Mesh(mc.geometry.Sphere(0.06 * size), _material(mc, _GRASP_COLOR)))
    scene._set_transform("/spacearm/grasp", _transform(point, scale=shown[0]))
    scene._animate("/spacearm/grasp", "position", np.tile(point, (len(idx), 1)))
    scene._animate("/spacearm/grasp", "scale", shown)
    scene.legend.append((_GRASP_COLOR, f"grasp point (from t = {t_grasp:.3g} s)"))
    extent.append(point[None])
    if momentum:
        P, L = np.asarray(result.P)[idx], np.asarray(result.L)[idx]
        origin = np.zeros((len(idx), 3))
        scales = robot.momentum_scales(xs, np.ascontiguousarray(result.u[idx]))
        span = 1.6 * _base_radius(robot) + 0.2 * size
        _arrow(scene, "P", origin, P, span, _P_COLOR, "P, robot + target", "N s", 1e-6 * max(float(scales[:, 0].max()), 1e-300))
        _arrow(scene, "L", origin, L, span, _L_COLOR, "L about the origin, robot + target", "N m s",
               1e-6 * max(float(scales[:, 1].max()), 1e-300))
    _finish(scene, np.vstack(extent), play, repetitions, pad=max(_base_radius(robot), _base_radius(body)))
    return scene


def view(scene: Scene, path: Optional[PathLike] = None, *, open: Optional[bool] = None):
    """Write ``scene`` to ``path`` (a self-contained ``.html``; returns the path; ``open=True``
    also opens it in the web browser) or, without a path, serve it live
    ([`Scene.show`][spacearm.viz.viewer.Scene.show]; returns the ``meshcat.Visualizer``; opened unless ``open=False``)."""
    if path is not None:
        written = scene.save(path)
        if open:
            webbrowser.open(os.path.abspath(written))
        return written
    return scene.show(open=True if open is None else bool(open))
