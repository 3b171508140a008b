"""Draw docs/figures/dh_conventions.png: the two DH conventions of docs/dh.md on the planar
3-link worked example (joint axes out of the page).

Run from anywhere: ``python docs/figures/make_dh_figure.py`` (needs numpy and matplotlib only).
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import FancyArrowPatch, Rectangle  # noqa: E402

OUT = Path(__file__).with_name("dh_conventions.png")

# The worked example of docs/dh.md: base 0.5 m cube, joint 1 at 0.25 m on +x, links 1.0, 0.8,
# 0.5 m with the CM at mid-length, drawn at q = (35°, -60°, 50°).
LENGTHS = [1.0, 0.8, 0.5]
Q = np.radians([35.0, -60.0, 50.0])
J1 = np.array([0.25, 0.0])


def geometry():
    """Joint positions p_1..p_3, the tip, link CMs and the link angles."""
    joints, coms, angles = [J1], [], []
    angle = 0.0
    for length, q in zip(LENGTHS, Q):
        angle += q
        u = np.array([np.cos(angle), np.sin(angle)])
        coms.append(joints[-1] + 0.5 * length * u)
        joints.append(joints[-1] + length * u)
        angles.append(angle)
    return joints, coms, angles


def arrow(ax, start, end, color, lw=1.6, style="-|>", ls="-", z=3):
    ax.add_patch(FancyArrowPatch(start, end, arrowstyle=style, mutation_scale=11, color=color, lw=lw, linestyle=ls,
                                 zorder=z, shrinkA=0, shrinkB=0))


def frame(ax, origin, angle, label, color, size=0.28, y_axis=True, labels=True):
    ux = np.array([np.cos(angle), np.sin(angle)])
    uy = np.array([-np.sin(angle), np.cos(angle)])
    arrow(ax, origin, origin + size * ux, color, lw=2.0, z=5)
    if labels:
        ax.text(*(origin + (size + 0.05) * ux), f"$x_{{{label}}}$", color=color, fontsize=9, ha="center", va="center")
    if y_axis:
        arrow(ax, origin, origin + size * uy, color, lw=2.0, z=5)
        if labels:
            ax.text(*(origin + (size + 0.06) * uy), f"$y_{{{label}}}$", color=color, fontsize=9, ha="center", va="center")


def normal(a, b):
    """Unit normal (+90°) of the segment a -> b, and its direction."""
    u = (b - a) / np.linalg.norm(b - a)
    return np.array([-u[1], u[0]]), u


def arm(ax, joints, coms):
    ax.add_patch(Rectangle((-0.25, -0.25), 0.5, 0.5, facecolor="#d9d9d9", edgecolor="#555555", zorder=1))
    ax.text(0.0, -0.33, "base (link 0)", ha="center", va="top", fontsize=9, color="#333333")
    for a, b in zip(joints[:-1], joints[1:]):
        ax.plot(*np.transpose([a, b]), color="#8c8c8c", lw=9, solid_capstyle="round", zorder=2, alpha=0.55)
    for k, p in enumerate(joints[:-1], start=1):
        ax.plot(*p, "o", ms=11, mfc="white", mec="black", zorder=6)
        ax.plot(*p, ".", ms=4, color="black", zorder=7)  # z axis out of the page
        ax.text(p[0] + (0.03 if k == 1 else 0.0), p[1] - 0.09, f"joint {k}", fontsize=8, ha="left" if k == 1 else "center",
                va="top", zorder=8)
    for k, (c, a, b) in enumerate(zip(coms, joints[:-1], joints[1:]), start=1):
        n, u = normal(a, b)
        ax.plot(*c, marker="o", ms=7, mfc="#ffcc00", mec="black", zorder=6)
        ax.text(*(c + 0.13 * n - 0.11 * u), f"CM$_{k}$", fontsize=8, ha="center", va="center")
    ax.plot(0.0, 0.0, marker="o", ms=7, mfc="#ffcc00", mec="black", zorder=6)
    ax.text(-0.04, 0.06, "CM$_0$", fontsize=8, ha="right")
    ax.plot(*joints[-1], marker="*", ms=12, color="#2ca02c", zorder=6)
    ax.text(joints[-1][0] + 0.02, joints[-1][1] + 0.09, "tip", fontsize=9, color="#2ca02c")


def main():
    joints, coms, angles = geometry()
    fig, axes = plt.subplots(1, 2, figsize=(12.5, 4.4))
    for ax in axes:
        arm(ax, joints, coms)
        ax.set_aspect("equal")
        ax.set_xlim(-0.45, 2.55)
        ax.set_ylim(-0.45, 1.12)
        ax.set_xticks([])
        ax.set_yticks([])

    # (a) classic DH: frame i at the distal joint of link i (on joint i+1's axis).
    ax = axes[0]
    ax.set_title("(a) classic DH: frame $i$ on joint $i{+}1$ (blue: $x_i$), CM $c_i$ given in frame $i$", fontsize=11)
    blue, red = "#1f77b4", "#d62728"
    frame(ax, J1, 0.0, "0", blue, y_axis=False)
    for i, (p, ang) in enumerate(zip(joints[1:], angles), start=1):
        frame(ax, p, ang, str(i), blue, y_axis=False)
    for i, (c, a, b) in enumerate(zip(coms, joints[:-1], joints[1:]), start=1):
        n, _ = normal(a, b)
        arrow(ax, b + 0.035 * n, c + 0.035 * n, red, lw=1.4, ls="--")
        ax.text(*((b + c) / 2 + 0.12 * n), f"$c_{i}$", color=red, fontsize=11, ha="center", va="center")
        ax.text(*((a + b) / 2 - 0.15 * n), f"$a_{i}$", color="#555555", fontsize=11, ha="center", va="center")
    ax.text(-0.42, 1.09, r"$^{i-1}T_i=\mathrm{Rot}_z(\theta_i{+}q_i)\,\mathrm{Trans}_z(d_i)\,\mathrm{Trans}_x(a_i)\,\mathrm{Rot}_x(\alpha_i)$"
            "\nhere $d_i=\\alpha_i=0$; $z$ axes out of the page", fontsize=9, va="top")

    # (b) the paper's convention = spacearm's link frames: origin at the CM.
    ax = axes[1]
    ax.set_title(r"(b) Wilde et al. (2018): frame $\mathcal{L}_i$ at CM$_i$, vectors $\mathbf{a}_i$, $\mathbf{b}_i$", fontsize=11)
    green, purple = "#2ca02c", "#9467bd"
    frame(ax, np.zeros(2), 0.0, r"\mathcal{L}_0", purple, size=0.16, labels=False)
    ax.text(-0.02, 0.2, r"$\mathcal{L}_0$", color=purple, fontsize=10, ha="right")
    for i, (c, ang) in enumerate(zip(coms, angles), start=1):
        frame(ax, c, ang, rf"\mathcal{{L}}_{i}", purple, size=0.2, labels=False)
    arrow(ax, np.array([0.0, -0.05]), J1 + [0.0, -0.05], green, lw=1.4)
    ax.text(0.1, -0.1, r"$\mathbf{b}_0$", color=green, fontsize=11, ha="center", va="top")
    for i, (p, c, nxt) in enumerate(zip(joints[:-1], coms, joints[1:]), start=1):
        n = np.array([-(nxt - p)[1], (nxt - p)[0]]) / np.linalg.norm(nxt - p)
        arrow(ax, p - 0.04 * n, c - 0.04 * n, red, lw=1.4)
        arrow(ax, c - 0.04 * n, nxt - 0.04 * n, green, lw=1.4)
        ax.text(*((p + c) / 2 - 0.16 * n), rf"$\mathbf{{a}}_{i}$", color=red, fontsize=11, ha="center", va="center")
        ax.text(*((c + nxt) / 2 - 0.16 * n), rf"$\mathbf{{b}}_{i}$", color=green, fontsize=11, ha="center", va="center")
    ax.text(-0.42, 1.09, r"$\mathcal{L}_i$ aligned with joint frame $i{+}1$; "
            r"$^{i-1}R_i=\mathrm{Rot}_z(\theta_i{+}q_i)\,\mathrm{Rot}_x(\alpha_i)$"
            "\n" r"$\mathbf{a}_i$: joint $i$ → CM$_i$, $\mathbf{b}_i$: CM$_i$ → joint $i{+}1$, both in $\mathcal{L}_i$"
            "\nspacearm's link frames are these (purple: $x$ along, $y$ across the link)", fontsize=9, va="top")

    fig.tight_layout()
    fig.savefig(OUT, dpi=130, bbox_inches="tight")
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
