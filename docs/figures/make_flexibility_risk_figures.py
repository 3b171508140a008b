"""Draw the figures of docs/flexibility-risk.md (about a minute):

    python docs/figures/make_flexibility_risk_figures.py

A 400 kg bus with a two-joint arm, a cylindrical propellant tank (R = 0.3 m, 0.8 m tall,
1000 kg/m³, the slosh model of spacearm.slosh_parameters in an axial acceleration of 0.1 m/s²)
and a hinged solar panel (a passive revolute joint with a torsional spring). A computed-torque
maneuver of the arm (a quintic over 8 s) is designed on the rigid lumped model (the fuel and the
panel frozen at rest, ``passive="frozen"``) and run on the flexible plant, against the fill
fraction, with and without a ZVD input shaper at the first flexible mode; it is compared with
the lumped-inertia Monte Carlo of today (a rigid plant with the fuel lumped at the liquid's CM,
the controller's model with that mass displaced anywhere in the tank, ``perturbed_model``), and
with the partial-feedback-linearizing controller (``passive="drift"``) that measures the passive
coordinates. Prints the table the page quotes.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import spacearm  # noqa: E402
from spacearm.control import ComputedTorque, QuinticJoint, input_shaper, perturbed_model  # noqa: E402

OUT = Path(__file__).with_name("flexibility_risk.png")
R, TANK_H, RHO, ACCEL = 0.3, 0.8, 1000.0, 0.1
CENTER_BOTTOM = np.array([0.0, 0.0, -0.35])  # tank bottom centre in the bus frame
PANEL_K, PANEL_C = 25.0, 0.2
Q0 = np.array([0.2, -0.3])
DQ = np.array([0.9, -0.7])
T_MOVE, T_END = 8.0, 30.0
KP, KD = 4.0, 4.0
FILLS = np.array([0.1, 0.25, 0.4, 0.55, 0.7, 0.85])


def plant(fill: float, *, flexible: bool = True) -> spacearm.Robot:
    b = spacearm.Robot.builder("bus", base_mass=400.0, base_inertia=[60.0, 70.0, 80.0])
    b.add_link("l1", joint="revolute", axis=(0, 0, 1), origin=(0.7, 0, 0.3), com=(0.5, 0, 0), mass=8.0, inertia=[0.02, 0.7, 0.7])
    b.add_link("l2", joint="revolute", axis=(0, 1, 0), parent="l1", origin=(1.0, 0, 0), com=(0.5, 0, 0), mass=6.0, inertia=[0.02, 0.5, 0.5])
    b.add_point("tip", body="l2", offset=(0.5, 0, 0))
    tank = spacearm.slosh_parameters(radius=R, fill_fraction=fill, tank_height=TANK_H, density=RHO, axial_acceleration=ACCEL,
                                     damping_ratio=0.005)
    center = CENTER_BOTTOM + [0.0, 0.0, tank.fill_height / 2]
    if flexible:
        tank.add_to(b, "fuel", center=center, axis=(0, 0, 1), lateral=(0, 1, 0), model="pendulum")
        b.add_link("panel", joint="revolute", axis=(1, 0, 0), origin=(0, 0.9, 0), com=(0, 1.0, 0), mass=15.0,
                   inertia=[5.0, 0.05, 5.0], actuated=False, stiffness=PANEL_K, damping=PANEL_C)
    else:
        b.attach_payload("fuel", body="base", mass=tank.liquid_mass, origin=center)
        b.attach_payload("panel", body="base", mass=15.0, inertia=[5.0, 0.05, 5.0], origin=(0, 1.9, 0))
    return b.build(), tank


def metrics(robot, traj, ref):
    q_ref, _, _ = ref.evaluate(traj.t)
    act = np.flatnonzero(robot.actuated_dofs)
    err = np.abs(traj.x[:, 7 + act] - q_ref).max()
    w0 = np.linalg.norm(traj.u[:, 3:6], axis=1).max()
    return err, w0


def run(robot, ref, **ct):
    traj = spacearm.simulate(robot, T_END, x0=robot.neutral_configuration(q=_q0(robot)),
                             controller=ComputedTorque(kp=KP, kd=KD, reference=ref, **ct), rtol=1e-9, atol=1e-11)
    return metrics(robot, traj, ref), traj


def _q0(robot):
    q = np.zeros(robot.n_dof)
    act = np.flatnonzero(robot.actuated_dofs)
    q[act] = Q0
    return q


def main() -> None:
    rng = np.random.default_rng(2018)
    move = QuinticJoint(Q0, Q0 + DQ, t_start=0.0, t_end=T_MOVE)
    rows = []
    for f in FILLS:
        robot, tank = plant(f)
        w1 = robot.natural_frequencies(robot.neutral_configuration(q=_q0(robot))).frequencies[0]
        shaped = input_shaper("zvd", frequency=w1).shape(move)
        (frozen, _) = run(robot, move, passive="frozen")
        (frozen_shaped, _) = run(robot, shaped, passive="frozen")
        (drift, _) = run(robot, move, passive="drift")
        rigid, _ = plant(f, flexible=False)
        lumped = []
        for _ in range(8):
            d = rng.normal(size=3)
            d *= rng.uniform(0, 1) ** (1 / 3) * R / np.linalg.norm(d)
            frac = tank.liquid_mass / rigid.total_mass
            model = perturbed_model(rigid, slosh_fraction=min(frac, 0.99), slosh_offset=d)
            traj = spacearm.simulate(rigid, T_END, x0=rigid.neutral_configuration(q=Q0),
                                     controller=ComputedTorque(kp=KP, kd=KD, reference=move, model=model), rtol=1e-9, atol=1e-11)
            lumped.append(metrics(rigid, traj, move))
        lumped = np.array(lumped)
        rows.append((f, tank.liquid_mass, tank.modes[0].frequency, w1, *frozen, *frozen_shaped, *drift, *lumped.max(axis=0)))
        print(f"fill {f:.2f}: m_L {tank.liquid_mass:6.1f} kg, slosh w1 {tank.modes[0].frequency:.3f}, first mode {w1:.3f} rad/s | "
              f"frozen err {frozen[0]:.2e} w0 {frozen[1]:.2e} | shaped err {frozen_shaped[0]:.2e} w0 {frozen_shaped[1]:.2e} | "
              f"drift err {drift[0]:.2e} w0 {drift[1]:.2e} | lumped MC max err {lumped[:, 0].max():.2e} w0 {lumped[:, 1].max():.2e}")
    a = np.array(rows)
    fig, ax = plt.subplots(1, 2, figsize=(10, 3.8))
    for col, label, style in [(4, "rigid-model CT on the flexible plant", "o-"), (6, "same, ZVD-shaped reference", "s-"),
                              (8, "partial feedback linearization (drift)", "^-"), (10, "lumped-inertia Monte Carlo (max of 8)", "x--")]:
        ax[0].semilogy(a[:, 0], a[:, col], style, label=label)
        ax[1].semilogy(a[:, 0], a[:, col + 1], style, label=label)
    ax[0].set(xlabel="fill fraction", ylabel="max joint tracking error (rad)")
    ax[1].set(xlabel="fill fraction", ylabel="max base angular rate (rad/s)")
    ax[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(OUT, dpi=110)
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
