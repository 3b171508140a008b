#!/usr/bin/env python
"""Regenerate the figures of docs/singularities.md, docs/workspace.md, docs/reactionless.md and
docs/redundancy.md (about a minute):

    python docs/figures/make_analysis_figures.py
"""

import os
import sys

import numpy as np

import spacearm
from spacearm import analysis

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tests"))
from analysis_refs import two_link_planar  # noqa: E402


def out(name):
    return os.path.join(HERE, name)


def main():
    two = two_link_planar()
    analysis.singularity_map(two, joints=(0, 1), resolution=201, task="planar").plot(out("analysis_singularities_two_link.png"))
    s6 = spacearm.presets.spatial6()
    analysis.singularity_map(s6, joints=(2, 4), resolution=121, task="full").plot(out("analysis_singularities_spatial6.png"))
    analysis.workspace(two, resolution=181, task="planar").plot(out("analysis_workspace_two_link.png"))
    analysis.workspace(spacearm.presets.planar4(), resolution=15).plot(out("analysis_workspace_planar4.png"))
    analysis.workspace(s6, random_samples=100000, task="full").plot(out("analysis_workspace_spatial6_xz.png"), plane="xz")
    p4 = spacearm.presets.planar4()
    x0 = p4.neutral_configuration()
    target = p4.point_position(x0) + np.array([-0.5, 0.6, 0.0])
    ms = [analysis.move_to(p4, target, strategy=s) for s in ("reactionless", "minimum_disturbance", "naive")]
    ms[0].plot(out("analysis_reactionless_planar4.png"), others=ms[1:])
    s7 = spacearm.presets.spatial7()
    x0 = s7.neutral_configuration()
    target = s7.point_position(x0) + np.array([-0.5, 0.4, 0.4])
    kw = dict(task="position", strategy="naive", duration=4.0, settle=1.0, dt=0.02)
    plain = analysis.move_to(s7, target, **kw)
    plain.strategy = "naive (no null-space term)"
    lim = analysis.move_to(s7, target, joint_limit_gain=50.0, **kw)
    lim.strategy = "joint-limit avoidance"
    man = analysis.move_to(s7, target, manipulability_gain=20.0, **kw)
    man.strategy = "manipulability ascent"
    md = analysis.move_to(s7, target, task="position", strategy="minimum_disturbance", duration=4.0, settle=1.0, dt=0.02)
    md.strategy = "minimum base disturbance"
    plain.plot(out("analysis_redundancy_spatial7.png"), others=[lim, man, md],
               title="spatial7: RMRC through J* with null-space objectives (x–y projection of the path)")


if __name__ == "__main__":
    main()
