"""Draw the figure of docs/flexibility.md (a few seconds):

    python docs/figures/make_flexibility_figures.py

Left: a 5 kg slosh mass on a spring (k = 200 N/m, c = 3 N s/m) on a free 100 kg base, released
0.02 m from rest: spacearm's simulation against the closed form of ``μ q̈ + c q̇ + k q = 0``
(``μ`` the reduced mass) and against the same spring on a clamped base (``μ = m``). Right: the
frequency of a hinged panel (10 kg, k = 30 N m/rad) on a free hub, relative to the clamped
panel's, against the hub's size: spacearm's ``Robot.natural_frequencies`` (dots) and the
closed form ``√(k / I_red)`` (line).
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import spacearm  # noqa: E402

OUT = Path(__file__).with_name("flexibility_closed_forms.png")


def spring_mass(k: float, c: float) -> spacearm.Robot:
    b = spacearm.Robot.builder("spring-mass", base_mass=100.0, base_inertia=[8.0, 9.0, 10.0])
    b.add_link("slug", joint="prismatic", axis=(1, 0, 0), origin=(0.5, 0, 0), mass=5.0, inertia=[1e-3] * 3,
               actuated=False, stiffness=k, damping=c)
    return b.build()


def panel(base_mass: float, base_izz: float, k: float = 30.0) -> spacearm.Robot:
    b = spacearm.Robot.builder("hinged", base_mass=base_mass, base_inertia=[0.8 * base_izz, 0.9 * base_izz, base_izz])
    b.add_link("panel", joint="revolute", axis=(0, 0, 1), origin=(1.0, 0, 0), com=(0.5, 0, 0), mass=10.0,
               inertia=[0.1, 0.75, 0.8], actuated=False, stiffness=k)
    return b.build()


def reduced_inertia(base_mass, base_izz, m=10.0, i1=0.8, a=1.0, b=0.5):
    mu = base_mass * m / (base_mass + m)
    m11, m12, m22 = mu * a * a + base_izz, mu * a * b, mu * b * b + i1
    return (m11 * m22 - m12 * m12) / (m11 + 2 * m12 + m22)


def damped(t, amp, k, c, mass):
    w = np.sqrt(k / mass)
    z = c / (2 * np.sqrt(k * mass))
    wd = w * np.sqrt(1 - z * z)
    return amp * np.exp(-z * w * t) * (np.cos(wd * t) + z * w / wd * np.sin(wd * t))


def main() -> None:
    k, c, amp = 200.0, 3.0, 0.02
    robot = spring_mass(k, c)
    traj = spacearm.simulate(robot, 3.0, x0=robot.neutral_configuration(q=[amp]), dt=1e-3, record_every=10)
    mu = 100.0 * 5.0 / 105.0
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4))
    ax1.plot(traj.t, 1e3 * traj.x[:, 7], lw=2.5, color="tab:blue", label="spacearm simulation (free base)")
    ax1.plot(traj.t, 1e3 * damped(traj.t, amp, k, c, mu), "k--", lw=1, label="closed form, reduced mass μ")
    ax1.plot(traj.t, 1e3 * damped(traj.t, amp, k, c, 5.0), ":", color="tab:red", lw=1.2, label="clamped base (μ = m)")
    ax1.set_xlabel("time [s]")
    ax1.set_ylabel("slosh mass displacement q [mm]")
    ax1.set_title("spring–mass on a free 100 kg base")
    ax1.legend(loc="upper right", fontsize=8)
    ratios = np.logspace(-1, 3, 9)  # hub inertia / clamped panel inertia (hub mass 10 kg per kg m² of it)
    clamped = 0.8 + 10.0 * 0.25
    line = np.logspace(-1, 3, 200)
    ax2.semilogx(line, np.sqrt(clamped / reduced_inertia(10.0 * line * clamped, line * clamped)), "k-", lw=1,
                 label="closed form √(k / I_red)")
    dots = [panel(10.0 * r * clamped, r * clamped).natural_frequencies().frequencies[0] / np.sqrt(30.0 / clamped) for r in ratios]
    ax2.semilogx(ratios, dots, "o", color="tab:blue", label="spacearm natural_frequencies")
    ax2.axhline(1.0, color="tab:red", ls=":", lw=1.2, label="clamped panel")
    ax2.set_xlabel("hub inertia / panel inertia about the hinge")
    ax2.set_ylabel("ω (free hub) / ω (clamped)")
    ax2.set_title("hinged panel on a free hub")
    ax2.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(OUT, dpi=130)
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
