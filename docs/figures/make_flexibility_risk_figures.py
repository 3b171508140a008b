"""Draw the figure of docs/flexibility-risk.md and print its tables (one to two minutes on two cores):

    python docs/figures/make_flexibility_risk_figures.py

Three campaigns ([`spacearm.campaign.run_campaign`]) of the same arm manoeuvre on a 400 kg bus with
a two-joint arm (a quintic of (0.9, -0.7) rad over 8 s, computed torque with kp = kd = 4,
30 s flown):

A. the flexible plant: a cylindrical propellant tank (R = 0.3 m, 0.8 m tall, 1000 kg/m³, a
   pendulum slosh model in an axial acceleration of 0.1 m/s²) whose fill fraction is drawn
   U(0.05, 0.95) and slosh damping ratio U(0.001, 0.01), and a 15 kg hinged panel whose stiffness
   is drawn LogNormal(25 N·m/rad, 0.2); the controller is designed on the nominal rigid lumped
   model (fill 0.5, ζ = 0.0055, 25 N·m/rad, passive joints frozen: ``passive="frozen"``);
B. the same with the reference ZVD-shaped (``Scenario(shaping="zvd")``) at the first mode of the
   controller's model (the slosh); B' (printed, not drawn): ZVD at its second mode (the panel);
   D (printed, not drawn): A's controller with the passive coordinates measured
   (``Scenario(passive="drift")``, collocated partial feedback linearization on the nominal model);
C. the lumped-inertia Monte Carlo of today: a rigid plant (the nominal fuel a point mass at its
   CM, the panel welded) with a mass U(0, m_L(0.95)) of the base moved 0.3 m (the tank's radius)
   from the base CM in a random direction (``Perturbations(slosh_fraction_max, slosh_offset)``);
   it has no fill fraction, so it is plotted against the displaced mass as a fill fraction
   (m_s / m_L(1), the fill whose liquid that mass is).
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy import stats  # noqa: E402

import spacearm  # noqa: E402
from spacearm.campaign import Flexibility, LogNormal, Panel, Perturbations, Scenario, Tank, Uniform, run_campaign  # noqa: E402

OUT = Path(__file__).with_name("flexibility_risk.png")
SAMPLES, SEED = 200, 24
R, TANK_H, RHO, ACCEL = 0.3, 0.8, 1000.0, 0.1
BOTTOM = (0.0, 0.0, -0.35)  # the tank's bottom centre in the bus frame
BASE_MASS = 400.0
Q0 = np.array([0.2, -0.3])
DQ = np.array([0.9, -0.7])
T_MOVE, T_END, DT = 8.0, 30.0, 5e-3
KP, KD = 4.0, 4.0
PANEL = Panel(hinge_position=(0.0, 0.9, 0.0), hinge_axis=(1.0, 0.0, 0.0), direction=(0.0, 1.0, 0.0), mass=15.0,
              size=(2.0, 1.0, 0.02), damping=0.2)
TANK = Tank(radius=R, height=TANK_H, density=RHO, axial_acceleration=ACCEL, bottom=BOTTOM, lateral=(0.0, 1.0, 0.0),
            model="pendulum")
FLEX = Flexibility(tank=TANK, fill_fraction=Uniform(0.05, 0.95), slosh_damping_ratio=Uniform(0.001, 0.01),
                   panel=PANEL, panel_stiffness=LogNormal(25.0, 0.2))
NO_ERRORS = Perturbations(0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
FULL_TANK = np.pi * R**2 * TANK_H * RHO  # kg of liquid at fill 1
BINS = np.array([0.05, 0.275, 0.5, 0.725, 0.95])


def bus_builder() -> spacearm.RobotBuilder:
    """The rigid bus and arm, without fuel or panel (campaigns A and B add them per sample)."""
    b = spacearm.Robot.builder("bus", base_mass=BASE_MASS, base_inertia=[60.0, 70.0, 80.0])
    b.add_link("l1", joint="revolute", axis=(0, 0, 1), origin=(0.7, 0, 0.3), com=(0.5, 0, 0), mass=8.0,
               inertia=[0.02, 0.7, 0.7])
    b.add_link("l2", joint="revolute", axis=(0, 1, 0), parent="l1", origin=(1.0, 0, 0), com=(0.5, 0, 0), mass=6.0,
               inertia=[0.02, 0.5, 0.5])
    b.add_point("tip", body="l2", offset=(0.5, 0, 0))
    b.set_initial_q(Q0)
    return b


def rigid_lumped() -> spacearm.Robot:
    """Campaign C's nominal plant: the nominal fuel (fill 0.5) a point mass at the liquid's CM, the
    panel welded (a uniform plate's inertia about its CM, hinge axis x, length along y)."""
    b = bus_builder()
    tank = spacearm.slosh_parameters("cylinder", radius=R, fill_fraction=0.5, tank_height=TANK_H, density=RHO,
                                     axial_acceleration=ACCEL)
    b.attach_payload("fuel", body="base", mass=tank.liquid_mass, origin=(0.0, 0.0, BOTTOM[2] + tank.fill_height / 2))
    (length, width, thick), m = PANEL.size, PANEL.mass
    inertia = [m * (length**2 + thick**2) / 12, m * (width**2 + thick**2) / 12, m * (length**2 + width**2) / 12]
    b.attach_payload("panel", body="base", mass=m, inertia=inertia, origin=(0.0, 0.9 + length / 2, 0.0))
    return b.build()


def scenario(**kw) -> Scenario:
    return Scenario(duration=T_END, dt=DT, kp=KP, kd=KD, q_goal=tuple(Q0 + DQ), motion_fraction=T_MOVE / T_END, **kw)


def binned(x, y):
    """(median, max) of y in each fill bin."""
    out = []
    for lo, hi in zip(BINS[:-1], BINS[1:]):
        sel = (x >= lo) & (x <= hi)
        out.append((np.median(y[sel]), y[sel].max(), int(sel.sum())))
    return out


def main() -> None:
    bus = bus_builder().build()
    a = run_campaign(bus, samples=SAMPLES, seed=SEED, perturbations=NO_ERRORS, scenario=scenario(flexibility=FLEX),
                     progress=False)
    b = run_campaign(bus, samples=SAMPLES, seed=SEED, perturbations=NO_ERRORS,
                     scenario=scenario(flexibility=FLEX, shaping="zvd"), progress=False)
    lumped = rigid_lumped()
    c = run_campaign(lumped, samples=SAMPLES, seed=SEED, scenario=scenario(),
                     perturbations=Perturbations(0.0, 0.0, 0.0, slosh_fraction_max=0.95 * FULL_TANK / BASE_MASS,
                                                 slosh_offset=R), progress=False)
    for name, r in (("A", a), ("B", b), ("C", c)):
        if r.n_ok != SAMPLES:
            raise SystemExit(f"campaign {name}: {r.n_failed} samples failed: {r.failures()}")
    series = {
        "A: rigid-model CT on the flexible plant": (a.parameter("fill_fraction"), a, "o"),
        "B: the same, ZVD-shaped reference": (b.parameter("fill_fraction"), b, "s"),
        "C: lumped-inertia Monte Carlo (rigid plant)": (c.parameter("slosh_fraction") * BASE_MASS / FULL_TANK, c, "x"),
    }

    # What the numbers rest on: the modes of the nominal model and of the extreme plants.
    from spacearm.campaign.scenario import control_model, shaping_frequency

    nominal = control_model(bus, scenario(flexibility=FLEX))
    print(f"controller's model (fill 0.5, 25 N·m/rad): modes {nominal.natural_frequencies().frequencies.round(3)} rad/s; "
          f"ZVD designed at {shaping_frequency(bus, scenario(flexibility=FLEX, shaping='zvd')):.3f} rad/s")
    for fill in (0.05, 0.95):
        for k in (25.0 * np.exp(-0.4), 25.0 * np.exp(0.4)):
            p = FLEX.apply(bus, {"fill_fraction": fill, "slosh_frequency_scale": 1.0, "slosh_damping_ratio": 0.0055,
                                 "panel_stiffness": k})
            print(f"  plant fill {fill:.2f}, panel {k:4.1f} N·m/rad: modes {p.natural_frequencies().frequencies.round(3)} rad/s")
    # B at the panel's mode (the second of the controller's model) instead: printed, not drawn.
    panel_mode = float(nominal.natural_frequencies().frequencies[1])
    b2 = run_campaign(bus, samples=SAMPLES, seed=SEED, perturbations=NO_ERRORS, progress=False,
                      scenario=scenario(flexibility=FLEX, shaping="zvd", shaping_frequency=panel_mode))
    print(f"campaign B': ZVD at the panel mode of the controller's model, {panel_mode:.3f} rad/s")
    # D: A's controller measuring the fuel and the panel (partial feedback linearization): printed, not drawn.
    d = run_campaign(bus, samples=SAMPLES, seed=SEED, perturbations=NO_ERRORS, progress=False,
                     scenario=scenario(flexibility=FLEX, passive="drift"))
    for name, r in (("B'", b2), ("D", d)):
        if r.n_ok != SAMPLES:
            raise SystemExit(f"campaign {name}: {r.n_failed} samples failed: {r.failures()}")
    for name, r in (("A", a), ("B", b), ("B'", b2), ("D", d)):
        e = r.metric("tracking_error_max")
        for param in ("fill_fraction", "panel_stiffness", "slosh_damping_ratio"):
            rho = stats.spearmanr(r.parameter(param), e).statistic
            print(f"campaign {name}: Spearman rank correlation of tracking_error_max with {param}: {rho:+.2f}")
    e_a, e_d = a.metric("tracking_error_max"), d.metric("tracking_error_max")
    mismatch = np.abs(np.log(d.parameter("panel_stiffness") / FLEX.panel_stiffness.nominal))
    print(f"campaign D: below A's error in {int(np.sum(e_d < e_a))} of {SAMPLES} samples (same draws); Spearman rank "
          f"correlation with the panel stiffness's mismatch |ln(k / k_nominal)|: "
          f"{stats.spearmanr(mismatch, e_d).statistic:+.2f}")
    for name, r in (("A", a), ("B", b), ("B'", b2), ("C", c), ("D", d)):
        e, w = r.metric("tracking_error_max"), r.metric("base_rate_max")
        print(f"campaign {name}: {r.n_ok} samples in {r.run['elapsed_s']:.1f} s; tracking error median {np.median(e):.2e} "
              f"max {e.max():.2e} rad; base rate median {np.median(w):.3e} max {w.max():.3e} rad/s")

    print("\n| fill | A error median / max (rad) | B (ZVD) error median / max (rad) | C (lumped MC) error median / max (rad) "
          "| A base rate median / max (rad/s) | B base rate median / max | C base rate median / max |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    cells = {name: (binned(x, r.metric("tracking_error_max")), binned(x, r.metric("base_rate_max")))
             for name, (x, r, _) in series.items()}
    for i, (lo, hi) in enumerate(zip(BINS[:-1], BINS[1:])):
        errs = " | ".join(f"{cells[n][0][i][0]:.2e} / {cells[n][0][i][1]:.2e} ({cells[n][0][i][2]})" for n in series)
        rates = " | ".join(f"{cells[n][1][i][0]:.4f} / {cells[n][1][i][1]:.4f}" for n in series)
        print(f"| {lo:.2f}–{hi:.2f} | {errs} | {rates} |")

    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    centers = 0.5 * (BINS[:-1] + BINS[1:])
    for (label, (x, r, marker)), color in zip(series.items(), ("C0", "C1", "C2")):
        for k, metric in enumerate(("tracking_error_max", "base_rate_max")):
            y = r.metric(metric)
            ax[k].plot(x, y, marker, ms=3.5, color=color, alpha=0.55, mfc="none" if marker != "x" else None, label=label)
            ax[k].plot(centers, [m for m, _, _ in binned(x, y)], "-", color=color, lw=1.5)
    for k in range(2):
        y = c.metric(("tracking_error_max", "base_rate_max")[k])
        ax[k].axhspan(np.percentile(y, 5), np.percentile(y, 95), color="C2", alpha=0.12, lw=0,
                      label="C: 5–95 % spread" if k == 0 else None)
        ax[k].set_xlim(0, 1)
    ax[0].set_yscale("log")  # the errors span decades; the base rates two levels near 0.02 and 0.04 rad/s
    ax[0].set(xlabel="fill fraction (C: displaced mass as a fill)", ylabel="max joint tracking error (rad)")
    ax[1].set(xlabel="fill fraction (C: displaced mass as a fill)", ylabel="max base angular rate (rad/s)")
    ax[0].legend(fontsize=7, loc="lower right")
    fig.suptitle(f"{SAMPLES} samples per campaign; lines: medians in fill bins", fontsize=9)
    fig.tight_layout()
    fig.savefig(OUT, dpi=110)
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
