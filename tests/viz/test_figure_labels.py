"""Structure of the figures: units on every axis that has one, a legend (or a colour bar) for
any number of joints, energy apart from the momenta, one colour scale per singularity map,
no label over a neighbouring panel, and campaign axes with units.

Expected units and joint kinds come from outside the plotting code: the Panda's URDF read with
xml.etree, the SI units of each physical quantity, and the maps' own data ranges.
"""

import os
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import spacearm
from spacearm import analysis, control
from spacearm.io.urdf import load_urdf
from spacearm.campaign import Perturbations, Scenario, run_campaign

from robot_data import robot_urdf  # noqa: E402

pytest.importorskip("matplotlib")


def _axes_by_title(fig):
    return {ax.get_title(): ax for ax in fig.axes if ax.get_visible() and ax.get_title()}


def _legend_texts(ax):
    legend = ax.get_legend()
    return [t.get_text() for t in legend.get_texts()] if legend is not None else []


def _colorbars(fig):
    return [ax for ax in fig.axes if ax.get_label() == "<colorbar>"]


def _quintic_run(robot, offset, duration=0.5):
    q0 = robot.initial_q
    ref = control.QuinticJoint(q0, q0 + offset, 0.0, 0.8 * duration)
    return spacearm.simulate(robot, duration, dt=1e-3, record_every=10,
                             controller=control.ComputedTorque(kp=25.0, kd=10.0, reference=ref))


def _chain(n: int):
    """A serial chain of ``n`` revolute joints (alternating z and y axes) on a 200 kg base."""
    b = spacearm.RobotBuilder(f"chain{n}", 200.0, [50.0, 50.0, 50.0])
    parent = "base"
    for i in range(n):
        b.add_link(f"l{i + 1}", parent=parent, axis=(0, 0, 1) if i % 2 == 0 else (0, 1, 0),
                   origin=(0.5 if i == 0 else 0.2, 0, 0), com=(0.1, 0, 0), mass=1.0, inertia=[0.01, 0.01, 0.01],
                   joint_name=f"j{i + 1}")
        parent = f"l{i + 1}"
    return b.build()


@pytest.fixture(scope="module")
def panda_run():
    path = robot_urdf("panda_description/urdf/panda.urdf")
    panda = load_urdf(path, mimic="independent")
    kinds = {j.get("name"): j.get("type") for j in ET.parse(path).getroot().iter("joint")}
    return _quintic_run(panda, np.r_[0.4 * np.ones(7), 0.01, 0.01]), kinds


def test_panda_with_fingers_names_every_joint_with_its_unit(panda_run, tmp_path):
    traj, urdf_kinds = panda_run
    assert traj.n_dof == 9
    revolute = [n for n in traj.joint_names() if urdf_kinds[n] == "revolute"]
    prismatic = [n for n in traj.joint_names() if urdf_kinds[n] == "prismatic"]
    assert len(revolute) == 7 and len(prismatic) == 2
    fig = traj.plot(tmp_path / "panda.png")
    assert (tmp_path / "panda.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    axes = _axes_by_title(fig)
    angles = axes["joint angles (dashed: reference)"]
    positions = axes["prismatic joint positions (dashed: reference)"]
    torques = axes["joint torques applied"]
    forces = axes["prismatic joint forces applied"]
    # Every joint named in the legend of its kind's panels, with that kind's SI unit.
    assert _legend_texts(angles) == revolute and _legend_texts(torques) == revolute
    assert _legend_texts(positions) == prismatic and _legend_texts(forces) == prismatic
    assert angles.get_ylabel().endswith("[rad]") and positions.get_ylabel().endswith("[m]")
    assert torques.get_ylabel().endswith("[N m]") and forces.get_ylabel().endswith("[N]")
    # A joint keeps its colour from the coordinate panel to the force panel.
    for coord_ax, force_ax in ((angles, torques), (positions, forces)):
        solid = [line for line in coord_ax.get_lines() if line.get_linestyle() == "-"]
        assert [line.get_color() for line in solid] == [line.get_color() for line in force_ax.get_lines()]
        assert len({str(line.get_color()) for line in solid}) == len(solid)
    # The tracking error is a norm over rad and m alike: the label says so.
    assert "rad and m" in axes["tracking error (joint)"].get_ylabel()
    assert not any("N m or N" in ax.get_ylabel() for ax in fig.axes)


def test_energy_has_its_own_linear_panel(panda_run):
    traj, _ = panda_run
    axes = _axes_by_title(traj.plot())
    momentum = axes["momentum: change from the initial value"]
    assert momentum.get_yscale() == "log"
    assert not any("energy" in t for t in _legend_texts(momentum))
    energy_ax = axes["kinetic energy: change from T(0)"]  # a controlled run: not conserved
    assert energy_ax.get_yscale() == "linear"
    assert energy_ax.get_ylabel() == "T(t) − T(0) [J]"
    # T - T(0) in J, against the energy computed here from the states (½ uᵀ H u, eq. 27).
    robot = traj.robot
    energy = np.array([0.5 * u @ robot.mass_matrix(x) @ u for x, u in zip(traj.x, traj.u)])
    np.testing.assert_allclose(energy_ax.get_lines()[0].get_ydata(), energy - energy[0], rtol=1e-9, atol=1e-12 * energy.max())
    assert energy.max() > 0


@pytest.mark.parametrize("n", [14, 24])
def test_joint_legend_or_colour_bar_for_many_joints(n):
    traj = _quintic_run(_chain(n), 0.2, duration=0.3)
    fig = traj.plot()
    axes = _axes_by_title(fig)
    angles, torques = axes["joint angles (dashed: reference)"], axes["joint torques applied"]
    if n <= 20:  # every joint named, in a legend outside the axes, each its own colour
        names = [f"j{i + 1}" for i in range(n)]
        for ax in (angles, torques):
            assert _legend_texts(ax) == names
            legend_box = ax.get_legend().get_window_extent(fig.canvas.get_renderer())
            assert legend_box.x0 >= ax.get_window_extent().x1
        colours = {tuple(np.round(np.atleast_1d(line.get_color()), 6)) for line in torques.get_lines()}
        assert len(colours) == n
        assert not _colorbars(fig)
    else:  # too many to name: coloured along a colormap, a colour bar of the joint number per panel
        assert _legend_texts(angles) == [] and _legend_texts(torques) == []
        bars = _colorbars(fig)
        assert len(bars) == 2 and all(b.get_ylabel() == "joint number" for b in bars)


def test_singularity_maps_have_one_colour_scale_each():
    m = analysis.singularity_map(spacearm.presets.spatial6(), joints=(2, 4), resolution=21, task="full")
    fig = m.figure()
    images = [ax.get_images()[0] for ax in fig.axes if ax.get_images()]
    assert len(images) == 2 and len(_colorbars(fig)) == 2
    assert images[0].get_clim() == (0.0, np.nanmax(m.sigma_min_generalized))
    assert images[1].get_clim() == (0.0, np.nanmax(m.sigma_min_fixed))
    assert np.nanmax(m.sigma_min_generalized) != np.nanmax(m.sigma_min_fixed)
    labels = sorted(b.get_ylabel() for b in _colorbars(fig))
    assert labels[0].startswith("σ_min(J*)") and labels[1].startswith("σ_min(J_m)")
    assert all(ax.get_xlabel().endswith("[rad]") for ax in fig.axes if ax.get_images())


def _overlaps(a, b) -> bool:
    return a.x0 < b.x1 and b.x0 < a.x1 and a.y0 < b.y1 and b.y0 < a.y1


def _assert_no_label_over_another_panel(fig):
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    panels = [ax for ax in fig.axes if ax.get_visible() and ax.get_label() != "<colorbar>"]
    for ax in panels:
        for label in (ax.yaxis.label, ax.xaxis.label):
            if not label.get_text():
                continue
            box = label.get_window_extent(renderer)
            for other in panels:
                if other is not ax and not (other.bbox.bounds == ax.bbox.bounds):
                    assert not _overlaps(box, other.get_window_extent(renderer)), (label.get_text(), other.get_title())


def test_motion_figure_sigma_label_clears_the_neighbouring_panel(tmp_path):
    s7 = spacearm.presets.spatial7()
    target = s7.point_position(s7.neutral_configuration()) + np.array([-0.5, 0.4, 0.4])
    kw = dict(task="position", duration=1.0, settle=0.2, dt=0.02)
    naive = analysis.move_to(s7, target, strategy="naive", **kw)
    other = analysis.move_to(s7, target, strategy="minimum_disturbance", **kw)
    path = naive.plot(tmp_path / "motion.png", others=[other])
    assert os.path.isfile(path)
    _assert_no_label_over_another_panel(naive.figure(others=[other]))


def test_trajectory_figure_labels_clear_the_neighbouring_panels(panda_run):
    traj, _ = panda_run
    _assert_no_label_over_another_panel(traj.plot())


def test_campaign_axes_carry_units():
    robot = spacearm.presets.planar4()
    result = run_campaign(robot, 12, seed=0, workers=0, progress=False,
                          perturbations=Perturbations(payload_mass_max=5.0),
                          scenario=Scenario(duration=0.6, dt=5e-3, q_offset=0.4))
    fig = result.figure()
    # SI units of the drawn quantities: masses in kg, offsets in m, scales and fractions unitless,
    # joint errors in rad, attitude in deg, displacement in m.
    units = {"payload_mass": "kg", "slosh_offset_x": "m", "slosh_offset_y": "m", "slosh_offset_z": "m",
             "base_mass_scale": "-", "base_inertia_scale": "-", "link_mass_scale": "-", "slosh_fraction": "-",
             "tracking_error_max": "rad", "tracking_error_rms": "rad", "tracking_error_final": "rad",
             "attitude_excursion_max": "deg", "base_displacement_max": "m", "base_rate_max": "rad/s"}
    # Every parameter and metric has its unit in the tables the figure reads.
    from spacearm.campaign import METRIC_NAMES, METRIC_UNITS, PARAMETER_NAMES, PARAMETER_UNITS

    assert PARAMETER_UNITS == {name: units[name] for name in PARAMETER_NAMES}
    assert {k: v for k, v in METRIC_UNITS.items() if k != "saturation_events"} == \
        {name: units[name] for name in METRIC_NAMES if name != "saturation_events"}
    labels = [ax.get_xlabel() for ax in fig.axes if ax.get_visible() and ax.get_xlabel()]
    labels += [ax.get_ylabel() for ax in fig.axes if ax.get_visible() and ax.get_ylabel() not in ("", "samples")]
    assert len(labels) >= 4
    for label in labels:
        name, unit = label.split(" [")
        assert unit == units[name] + "]", label
    assert any(label.split(" [")[0] in {"payload_mass", "base_inertia_scale", "base_mass_scale", "link_mass_scale",
                                        "slosh_fraction"} for label in labels)


def test_without_a_robot_the_joint_units_say_they_are_unknown():
    from sim_samples import synthetic

    from spacearm.sim.trajectory import Trajectory

    _, data, meta = synthetic(k=21)
    axes = _axes_by_title(Trajectory(data=data, meta=meta).plot())  # joint kinds unknown
    assert axes["joint coordinates (dashed: reference)"].get_ylabel() == "q [rad or m]"
    assert axes["joint torques and forces applied (dashed: commanded)"].get_ylabel() == "τ [N m or N]"
    assert axes["tracking error (joint)"].get_ylabel() == "‖e‖ [rad or m]"


def test_in_orbit_the_momenta_are_not_labelled_conserved():
    # With the gravity gradient the tidal wrench changes P and L (issue 37 item 4: the legend said
    # "P (conserved)" while L changed by 0.1 N m s). The change is measured here from the states.
    robot = spacearm.presets.planar4()
    orbit = spacearm.Orbit.circular(400e3, inclination=0.5)
    q = np.array([0.3, 0.1, 0.2, 0.927]) / np.linalg.norm([0.3, 0.1, 0.2, 0.927])
    traj = spacearm.simulate(robot, 20.0, x0=robot.neutral_configuration(quat0=q), orbit=orbit, dt=0.05)
    momentum = _axes_by_title(traj.plot())["momentum: change from the initial value"]
    texts = _legend_texts(momentum)
    assert not any("conserved" in t for t in texts), texts
    assert "L_origin [N m s] (changed by the tidal wrench)" in texts
    m = robot.momentum(traj.x, traj.u)
    assert np.linalg.norm(m.L_origin[-1] - m.L_origin[0]) > 1e3 * max(traj.meta["drift"].values()) * np.linalg.norm(m.L_origin[0]) + 1e-12
    # Off orbit the same run conserves them and says so.
    free = spacearm.simulate(robot, 1.0, x0=robot.neutral_configuration(quat0=q), dt=0.05)
    assert "L_origin [N m s] (conserved)" in _legend_texts(_axes_by_title(free.plot())["momentum: change from the initial value"])


def test_passive_coordinates_have_a_panel_of_their_own():
    # Issue 37 item 5: a panel's and a beam's coordinates (~1e-2 rad) were drawn in the arm's
    # ±1.5 rad panel with their names in its legend.
    from random_models import flexible_sat

    robot = flexible_sat()
    names = robot.joint_names
    active = [names[j] for j in range(robot.n_dof) if robot.actuated_dofs[j]]
    passive = [names[j] for j in range(robot.n_dof) if not robot.actuated_dofs[j]]
    assert active and len(passive) >= 2
    ref = control.QuinticJoint([0.0], [1.0], t_start=0.0, t_end=0.4)
    traj = spacearm.simulate(robot, 0.5, dt=0.01, controller=control.JointPD(kp=20.0, kd=5.0, reference=ref))
    axes = _axes_by_title(traj.plot())
    arm_ax = next(ax for title, ax in axes.items() if title.startswith("joint angles"))
    passive_ax = axes["passive coordinates (no motor: slosh, panels, beams, compliant links)"]
    assert sorted(_legend_texts(arm_ax)) == sorted(active)
    assert sorted(_legend_texts(passive_ax)) == sorted(passive)
    assert passive_ax.get_ylabel() == "q [rad]"


def test_titles_name_the_controller_in_words():
    # Issue 37 item 7: titles read "controller computed_torque" and "(none)".
    from spacearm import _core

    robot = spacearm.presets.planar4()
    q0 = robot.initial_q
    ref = control.QuinticJoint(q0, q0 + 0.2, 0.0, 0.05)
    for ctrl, words in ((control.ComputedTorque(kp=25.0, kd=10.0, reference=ref), "computed torque"), (None, "no control")):
        traj = spacearm.simulate(robot, 0.05, dt=0.01, controller=ctrl)
        title = traj.plot()._suptitle.get_text()
        assert words in title and "_" not in title.split(":", 1)[1], title
        assert words == _core.CONTROLLER_LABELS[traj.meta["controller"]]
        assert f"controller: {words}" in traj.summary()
