"""Figures of a capture: the run (``plot_capture``), its animation (``animate_capture``)
and the capture envelope (``plot_envelope``). matplotlib (extra ``plot``) on its Agg canvas,
files written atomically."""

from __future__ import annotations

import numpy as np

from .._util.optional import require
from .animation import arm_segments, box_faces, equivalent_box, write_gif
from .figures import new_figure, save_figure

__all__ = ["plot_capture", "animate_capture", "capture_scene", "plot_envelope"]

_PHASE_COLOURS = ("#ffffff", "#fde0c5", "#e3f0d6", "#dbe7f5")


def _figure(width, height, layout="constrained"):
    return new_figure(figsize=(width, height), layout=layout)


def _save(fig, path):
    if path is not None:
        save_figure(fig, path, dpi=110)
    return fig


def _shade(ax, result):
    """Background colour per phase (after the approach); returns the phases shaded, for the key."""
    t, phase = result.t, result.phase
    shaded = []
    for k, name in enumerate(result.phase_names):
        idx = np.nonzero(phase == k)[0]
        if idx.size and k > 0:
            ax.axvspan(t[idx[0]], t[idx[-1]], color=_PHASE_COLOURS[k], alpha=0.8, lw=0)
            shaded.append(k)
    return shaded


def _name_lines(ax, fontsize=7):
    """Each line's label in its colour, stacked in the axes' upper right corner (direct labels:
    a legend's box packing cost more than the rest of the panel, benchmarks/README.md)."""
    for k, line in enumerate(ax.get_lines()):
        ax.annotate(line.get_label(), xy=(1.0, 1.0), xycoords="axes fraction", xytext=(-4, -3 - 1.2 * fontsize * k),
                    textcoords="offset points", ha="right", va="top", color=line.get_color(), fontsize=fontsize)


def plot_capture(result, path=None):
    """Four panels against time, phases shaded (capture orange, post-capture green, detumble
    blue; the key above the panels): the momentum ledger's change ``P − P(0)`` and ``L − L(0)``
    of robot + target; the base angular velocity; the joint torques; the grasp force and moment.
    Each line is named in its colour in the panel's upper right corner. A capture in orbit adds a
    row: the base attitude relative to LVLH (roll, pitch, yaw) and the target's CM relative to the
    chaser's CM in LVLH (radial x, along-track y, orbit-normal z), and its ledger panel is the
    momentum balance's residual."""
    # What the figure's time goes to is matplotlib's per-artist work (benchmarks/README.md,
    # "Profiler history"): a fixed layout and title positions (y=1.0), direct labels instead of
    # legends, at most 5 y ticks, no x axis on the upper panels (they share the lower ones'),
    # plain log tick labels, and one figure-level key of the phases.
    ticker = require("matplotlib.ticker", "figures")
    Patch = require("matplotlib.patches", "figures").Patch
    orbital = getattr(result, "in_orbit", False)
    fig = _figure(9.0, 9.6 if orbital else 7.0, layout=None)
    fig.subplots_adjust(left=0.09, right=0.98, bottom=0.06 if orbital else 0.08, top=0.94 if orbital else 0.93, wspace=0.25,
                        hspace=0.18)
    axes = fig.subplots(3 if orbital else 2, 2, sharex=True)
    t = result.t
    (a0, a1), (a2, a3) = axes[:2]
    for ax in axes[:-1].ravel():
        ax.xaxis.set_visible(False)
    for ax in axes.ravel():
        shaded = _shade(ax, result)
        ax.yaxis.set_major_locator(ticker.MaxNLocator(4))
    dP = np.linalg.norm(result.P - result.P[0], axis=1)
    dL = np.linalg.norm(result.L - result.L[0], axis=1)
    if orbital:  # the balance: the change less the integral of the external wrenches
        res = result.balance_residual()
        dP, dL = np.linalg.norm(res[:, :3], axis=1), np.linalg.norm(res[:, 3:], axis=1)
    a0.semilogy(t, np.maximum(dP, 1e-18), label="|P − P(0) − ∫F| [N s]" if orbital else "|P − P(0)| [N s]")
    a0.semilogy(t, np.maximum(dL, 1e-18), label="|L − L(0) − ∫N| [N m s]" if orbital else "|L − L(0)| [N m s]")
    # Plain "1e-10" tick labels on the log axis (mathtext labels cost a parse each).
    a0.yaxis.set_major_locator(ticker.LogLocator(numticks=5))
    a0.yaxis.set_major_formatter(ticker.LogFormatter(labelOnlyBase=True))
    a0.yaxis.set_minor_locator(ticker.NullLocator())
    a0.set_title(f"momentum {'balance' if orbital else 'ledger'}, robot + target ({result.mode})", fontsize=9, y=1.0)
    a0.set_ylabel("change [N s], [N m s]")
    w0 = result.u[:, 3:6]
    for k, c in enumerate("xyz"):
        a1.plot(t, w0[:, k], label=f"ω0{c}")
    a1.set_title("base angular velocity", fontsize=9, y=1.0)
    a1.set_ylabel("ω0 [rad/s]")
    if result.tau.size:
        for k, name in enumerate(result.robot.joint_names):
            a2.plot(t, result.tau[:, k], lw=0.8, label=name)
    a2.set_title("joint torques", fontsize=9, y=1.0)
    a2.set_ylabel("τ [N m]")
    a3.plot(t, np.linalg.norm(result.grasp_wrench[:, :3], axis=1), label="|f| [N]")
    a3.plot(t, np.linalg.norm(result.grasp_wrench[:, 3:], axis=1), label="|n| [N m]")
    a3.set_title("wrench holding the target", fontsize=9, y=1.0)
    a3.set_ylabel("|f| [N], |n| [N m]")
    if orbital:
        from .orbit import lvlh_angles

        a4, a5 = axes[2]
        ang = np.degrees(lvlh_angles(result.attitude_lvlh()))
        for k, name in enumerate(("roll", "pitch", "yaw")):
            a4.plot(t, ang[:, k], label=name)
        a4.set_title("base attitude relative to LVLH", fontsize=9, y=1.0)
        a4.set_ylabel("[deg]")
        rel = result.target_lvlh
        for k, name in enumerate(("x radial", "y along-track", "z normal")):
            a5.plot(t, rel[:, k] - rel[0, k], label=name)
        a5.set_title("target CM relative to the robot's CM (LVLH), change from start", fontsize=9, y=1.0)
        a5.set_ylabel("[m]")
    for ax in axes[-1]:
        ax.set_xlabel("t [s]")
    for ax in axes.ravel():
        _name_lines(ax, fontsize=6 if ax is a2 else 7)
    if shaded:
        fig.legend([Patch(color=_PHASE_COLOURS[k]) for k in shaded], [result.phase_names[k] for k in shaded],
                   loc="upper center", bbox_to_anchor=(0.5, 1.0), ncol=len(shaded), fontsize=7, frameon=False)
    return _save(fig, path)


def capture_scene(result, idx, *, figsize, dpi: float = 100.0):
    """The figure of a capture and ``draw(j)``, which poses it at sample ``idx[j]`` and returns
    the artists it moved (the rest of the figure is the same in every frame): the base
    (its equivalent box), the arm, the target (its equivalent box; a jointed target's links as
    segments) in a fixed view box; the title gives the phase and time. The one drawing of a
    capture, shared by the GIF ([`animate_capture`][spacearm.viz.capture.animate_capture]) and
    the video (``spacearm.viz.video``)."""
    Poly3DCollection = require("mpl_toolkits.mplot3d.art3d", "animations").Poly3DCollection
    robot, target = result.robot, result.target_model
    idx = np.asarray(idx, dtype=int)
    base = robot.description.base
    b_sides, b_axes = equivalent_box(base.mass, base.inertia)
    # a jointed target: its base as a box and its links as segments
    t_base = target.body.description.base
    t_sides, t_axes = equivalent_box(t_base.mass, t_base.inertia)
    geo = []
    from ..rotations import quat_to_matrix

    for k in idx:
        x, s = result.x[k], result.target[k]
        tx = target.xu(s)[0]
        segs = arm_segments(robot, x) + (arm_segments(target.body, tx) if not target.is_rigid else [])
        geo.append((box_faces(x[:3], quat_to_matrix(x[3:7]), b_sides, b_axes), segs,
                    box_faces(s[:3], quat_to_matrix(s[3:7]), t_sides, t_axes)))
    pts = np.vstack([np.vstack(b) for b, _, _ in geo] + [np.vstack(tb) for _, _, tb in geo]
                    + [np.vstack([np.vstack(seg) for seg in segs]) for _, segs, _ in geo if segs])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    centre, half = 0.5 * (lo + hi), 0.5 * float(np.max(hi - lo)) * 1.08 + 1e-6
    fig = new_figure(figsize=figsize, dpi=dpi, layout=None)
    fig.subplots_adjust(left=0.0, right=1.0, bottom=0.02, top=0.9)
    ax = fig.add_subplot(projection="3d")
    for setter, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), centre):
        setter(c - half, c + half)
    ax.set_box_aspect((1, 1, 1))
    ax.tick_params(labelsize=6)
    base_box = Poly3DCollection(geo[0][0], facecolor="silver", edgecolor="dimgray", alpha=0.35, linewidths=0.6)
    target_box = Poly3DCollection(geo[0][2], facecolor="tab:orange", edgecolor="saddlebrown", alpha=0.35, linewidths=0.6)
    ax.add_collection3d(base_box)
    ax.add_collection3d(target_box)
    links = [ax.plot([], [], [], "-o", color="C0", lw=2.5, ms=3)[0] for _ in geo[0][1]]
    title = ax.set_title("", fontsize=8)

    def draw(j):
        k = idx[j]
        faces, segs, tfaces = geo[j]
        base_box.set_verts(faces)
        target_box.set_verts(tfaces)
        for line, (a, b) in zip(links, segs):
            line.set_data_3d([a[0], b[0]], [a[1], b[1]], [a[2], b[2]])
        title.set_text(f"{robot.name} capturing {target.name} ({result.kind}, {result.mode})\n"
                       f"{result.phase_names[result.phase[k]]}, t = {result.t[k]:.2f} s")
        return moving

    moving = [base_box, target_box, *links, title]
    return fig, draw


def animate_capture(result, path, *, frames: int = 40, fps: int = 10, dpi: int = 72, size: float = 4.5) -> str:
    """A GIF: the base (its equivalent box), the arm, the target (its equivalent box) and the
    grasp point's path; the title gives the phase and time."""
    return write_gif(path, len(result.t), frames, fps, dpi, lambda idx: capture_scene(result, idx, figsize=(size, size)))


def plot_envelope(envelope, path=None):
    """Success (green) or failure (red) over spin rate × inertia error, each cell labelled with
    the time to detumble ("not detumbled" when the run ended first; "limit" when it detumbled but a
    grasp-wrench limit was exceeded)."""
    fig = _figure(6.0, 4.0)
    ax = fig.subplots()
    colors = np.where(envelope.success, 1.0, 0.0)
    ax.imshow(colors, cmap="RdYlGn", vmin=-0.2, vmax=1.2, origin="lower", aspect="auto")
    for i in range(envelope.success.shape[0]):
        for j in range(envelope.success.shape[1]):
            t = envelope.time_to_detumble[i, j]
            if not np.isfinite(t):
                label = "not\ndetumbled"
            else:
                label = f"{t:.1f} s" + ("" if envelope.success[i, j] else "\nlimit")
            ax.text(j, i, label, ha="center", va="center", fontsize=8)
    ax.set_xticks(range(len(envelope.inertia_errors)), [f"{e:+.0%}" for e in envelope.inertia_errors])
    ax.set_yticks(range(len(envelope.spin_rates)), [f"{r:g}" for r in envelope.spin_rates])
    ax.set_xlabel("error of the controller's target mass and inertia")
    ax.set_ylabel("target spin rate [rad/s]")
    ax.set_title(f"capture envelope ({envelope.mode}): time to detumble", fontsize=9)
    return _save(fig, path)
