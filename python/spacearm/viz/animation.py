"""3-D animation of a simulation run as a GIF: the base as a box, the arm as segments from
joint to joint, the end-effector trail and the system CM.

The model carries no geometry, only mass properties, so the base is drawn as its *equivalent
box*: the uniform box with the base's mass and principal moments of inertia (for a box of
sides a, b, c: ``I_x = m (b² + c²) / 12`` …, hence ``a² = 6 (I_y + I_z − I_x) / m``), oriented
along the principal axes. Each link is drawn from its joint to the joints of its children; a
link without children ends at the end-effector point if it carries one, else at the mirror
image of its joint through its CM (the tip of a uniform bar). Reaction wheels (rotors inside
the base) are not drawn.

Frames are drawn with matplotlib (Agg canvas, no ``pyplot``) and written with its
``PillowWriter``; the file is written atomically.
"""

from __future__ import annotations

import os
from typing import List, Optional, Sequence, Tuple, Union

import numpy as np

from .._util.summary import controller_label
from .._util.atomic import atomic_path
from ..errors import ArgumentError

__all__ = ["animate_trajectory", "trajectory_scene", "write_gif", "equivalent_box", "arm_segments", "box_faces"]

PathLike = Union[str, "os.PathLike[str]"]


def equivalent_box(mass: float, inertia) -> Tuple[np.ndarray, np.ndarray]:
    """Side lengths ``(3,)`` and axes ``(3, 3)`` (columns, in the body frame) of the uniform
    box with the given mass and inertia about its CM. Moments that violate the box relation
    (a flat or thin body) give a side of at least 2 % of the largest one, so it stays visible."""
    inertia = 0.5 * (np.asarray(inertia, dtype=float) + np.asarray(inertia, dtype=float).T)
    moments, axes = np.linalg.eigh(inertia)
    total = moments.sum()
    sides_sq = 6.0 * (total - 2.0 * moments) / float(mass)  # a² = 6 (I_y + I_z − I_x) / m
    sides = np.sqrt(np.maximum(sides_sq, 0.0))
    sides = np.maximum(sides, 0.02 * max(float(sides.max()), 1e-9))
    return sides, axes


def box_faces(center, rotation, sides, axes) -> List[np.ndarray]:
    """The six faces ``(4, 3)`` in 𝒥 of a box with the given side lengths along ``axes``
    (body frame), its centre at ``center`` and body-to-world ``rotation``."""
    half = 0.5 * np.asarray(sides)
    signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float)
    corners = center + (signs * half) @ (rotation @ axes).T  # (8, 3)
    # Corner index = 4*ix + 2*iy + iz; each face fixes one coordinate, corners in cyclic order.
    quads = [(0, 1, 3, 2), (4, 5, 7, 6), (0, 1, 5, 4), (2, 3, 7, 6), (0, 2, 6, 4), (1, 3, 7, 5)]
    return [corners[list(q)] for q in quads]


def arm_segments(robot, x, skip_dofs: Sequence[int] = ()) -> List[Tuple[np.ndarray, np.ndarray]]:
    """The segments ``(start, end)`` in 𝒥 that draw every link at configuration ``x``
    (joint to child joint; a leaf ends at its end-effector point or the mirror of its joint
    through its CM). Links moved by a dof in ``skip_dofs`` (reaction wheels) are left out."""
    desc = robot.description
    kin = robot.forward_kinematics(x)
    links = desc.links
    children = {b: [] for b in range(len(links) + 1)}
    for i, link in enumerate(links):
        children[link.parent_index].append(i + 1)
    point_on = {}
    for p in desc.points:
        point_on.setdefault(robot.body_index(p.body), []).append(p.name)
    skip = {int(d) for d in skip_dofs}
    segments = []
    for i, link in enumerate(links):
        b = i + 1
        if link.dof is not None and link.dof in skip:
            continue
        start = kin.joint_position_in_world[b]
        ends = [kin.joint_position_in_world[c] for c in children[b]]
        if not ends:
            names = point_on.get(b, [])
            ee = robot.end_effector
            if ee in names:
                ends = [robot.point_position(x, ee)]
            elif names:
                ends = [robot.point_position(x, names[0])]
            else:
                ends = [2.0 * kin.com_in_world[b] - start]
        for end in ends:
            if np.linalg.norm(end - start) > 1e-12:
                segments.append((np.array(start), np.array(end)))
    return segments


def trajectory_scene(traj, idx, *, figsize: Tuple[float, float], dpi: float = 100.0, trail: bool = True,
                     elev: float = 25.0, azim: float = -60.0, title: Optional[str] = None):
    """The figure of ``traj`` and ``draw(j)``, which poses it at sample ``idx[j]`` and returns
    the artists it moved: the base box, the arm, the end-effector trail so far and the system
    CM, in a fixed view box that holds every frame at equal scale (so the rest of the figure
    is the same in every frame). The one drawing of a run, shared by the GIF
    ([`animate_trajectory`][spacearm.viz.animation.animate_trajectory]) and the video
    (``spacearm.viz.video``)."""
    from .._util.optional import require

    FigureCanvasAgg = require("matplotlib.backends.backend_agg", "animations").FigureCanvasAgg
    Figure = require("matplotlib.figure", "animations").Figure
    Poly3DCollection = require("mpl_toolkits.mplot3d.art3d", "animations").Poly3DCollection

    robot = traj.robot
    idx = np.asarray(idx, dtype=int)
    wheel_dofs = [int(d) for d in (traj.meta.get("wheel_dofs") or [])]
    base = robot.description.base
    sides, axes = equivalent_box(base.mass, base.inertia)
    rotations = traj.base_rotation
    has_ee = robot.end_effector is not None and robot.n_dof > 0
    ee = traj.ee_position if traj.has("ee_position") else (
        np.array([robot.point_position(x) for x in traj.x[idx]]) if has_ee else None)
    ee_at = (lambda j: ee[idx[: j + 1]]) if traj.has("ee_position") else (lambda j: ee[: j + 1])
    com = traj.com if traj.has("com") else None

    # Geometry of every frame first: the fixed view box must hold all of it.
    geo = []
    for k in idx:
        x = traj.x[k]
        geo.append((box_faces(x[:3], rotations[k], sides, axes), arm_segments(robot, x, wheel_dofs)))
    pts = [np.vstack(f) for f, _ in geo] + [np.vstack([np.vstack(s) for s in segs]) for _, segs in geo if segs]
    if ee is not None:
        pts.append(ee.reshape(-1, 3))
    allpts = np.vstack(pts)
    lo, hi = allpts.min(axis=0), allpts.max(axis=0)
    centre, half = 0.5 * (lo + hi), 0.5 * float(np.max(hi - lo)) * 1.08 + 1e-6

    fig = Figure(figsize=figsize, dpi=dpi)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(projection="3d")
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)
    ax.set_box_aspect((1, 1, 1))
    ax.view_init(elev=elev, azim=azim)
    ax.set_xlabel("x [m]", fontsize=7)
    ax.set_ylabel("y [m]", fontsize=7)
    ax.set_zlabel("z [m]", fontsize=7)
    ax.tick_params(labelsize=6)
    fig.subplots_adjust(left=0.0, right=1.0, bottom=0.02, top=0.92)

    box = Poly3DCollection(geo[0][0], facecolor="silver", edgecolor="dimgray", alpha=0.35, linewidths=0.6)
    ax.add_collection3d(box)
    n_seg = len(geo[0][1])
    links = [ax.plot([], [], [], "-o", color="C0", lw=2.5, ms=3)[0] for _ in range(n_seg)]
    trail_line = ax.plot([], [], [], "-", color="C3", lw=1.0, alpha=0.8)[0] if (trail and ee is not None) else None
    com_dot = ax.plot([], [], [], "x", color="k", ms=6)[0] if com is not None else None
    name = robot.name
    heading = title or f"{name}: {traj.meta.get('mode', '')} ({controller_label(traj.meta.get('controller'))})"
    text = ax.set_title("", fontsize=8)

    def draw(j):
        faces, segs = geo[j]
        box.set_verts(faces)
        for line, (a, b) in zip(links, segs):
            line.set_data_3d([a[0], b[0]], [a[1], b[1]], [a[2], b[2]])
        if trail_line is not None:
            p = ee_at(j)
            trail_line.set_data_3d(p[:, 0], p[:, 1], p[:, 2])
        if com_dot is not None:
            g = com[idx[j]]
            com_dot.set_data_3d([g[0]], [g[1]], [g[2]])
        text.set_text(f"{heading}\nt = {traj.t[idx[j]]:.2f} s")
        return moving

    moving = [box, *links] + [a for a in (trail_line, com_dot) if a is not None] + [text]
    return fig, draw


def animate_trajectory(
    traj,
    path: PathLike,
    *,
    frames: int = 100,
    fps: int = 20,
    dpi: int = 80,
    size: float = 4.5,
    trail: bool = True,
    elev: float = 25.0,
    azim: float = -60.0,
    title: Optional[str] = None,
) -> str:
    """Write a GIF of ``traj`` to ``path`` (atomically) and return the path.

    ``frames`` (≤ the number of samples) are spread evenly over the run and played at ``fps``;
    the image is ``size`` inches square at ``dpi`` (default 360 × 360 pixels). ``trail``
    draws the end-effector path so far. The view is fixed (``elev``, ``azim`` in degrees) and
    its box holds the whole run at equal scale on the three axes.
    """
    robot = traj.robot
    if robot is None:
        raise ArgumentError("animate needs the robot: build the Trajectory with robot=..., or load() a file saved with one")
    return write_gif(path, len(traj), frames, fps, dpi,
                     lambda idx: trajectory_scene(traj, idx, figsize=(size, size), trail=trail, elev=elev, azim=azim, title=title))


def write_gif(path: PathLike, samples: int, frames, fps, dpi, scene) -> str:
    """Write a GIF to ``path`` (atomically) and return the path: ``frames`` key samples spread
    evenly over a run's ``samples`` (at most all of them), played at ``fps``; ``scene(idx)``
    gives the figure and its ``draw(j)`` of key frame ``j``."""
    if int(frames) < 1:
        raise ArgumentError(f"frames must be >= 1, got {frames}")
    if int(fps) < 1:
        raise ArgumentError(f"fps must be >= 1, got {fps}")
    from .._util.optional import require

    PillowWriter = require("matplotlib.animation", "animations").PillowWriter
    idx = np.unique(np.linspace(0, samples - 1, min(int(frames), samples)).round().astype(int))
    fig, draw = scene(idx)
    # The writer is driven directly rather than through FuncAnimation.save, which draws every
    # frame twice on a non-interactive canvas (once to "show" it, once to grab it).
    writer = PillowWriter(fps=int(fps))
    with atomic_path(path, suffix=".gif") as tmp:
        with writer.saving(fig, str(tmp), dpi=dpi):
            for j in range(len(idx)):
                draw(j)
                writer.grab_frame()
    return str(path)
