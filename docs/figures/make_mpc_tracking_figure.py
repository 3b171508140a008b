"""Draw docs/figures/mpc_tracking_spatial6.png: the tutorial of docs/mpc.md ("Tracking a tumbling
target") — spacearm.control.MPC on spatial6 following the grasp point of a target tumbling at
0.1 rad/s (a moving reference of the point cost), the rigid grasp, then the MPC detumbling the
captured system with the base torque (rotation-flying). Tracking error, base attitude
disturbance, the system's angular rate and momentum, and the solve time per sample (wall clock,
so it depends on the machine and its load).

    PYTHONPATH=python python3 docs/figures/make_mpc_tracking_figure.py
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import spacearm  # noqa: E402
import spacearm.mpc as mpc  # noqa: E402
from spacearm.capture import attach_target, grasp_impulse  # noqa: E402
from spacearm.control import MPC  # noqa: E402

OUT = Path(__file__).resolve().parent / "mpc_tracking_spatial6.png"
DT, TRACK, DETUMBLE = 0.05, 3.0, 3.0


def main() -> None:
    robot = spacearm.presets.spatial6()
    x0 = robot.neutral_configuration()
    body, offset = robot.resolve_point(None)
    target = spacearm.Target(50.0, [3.0, 4.0, 5.0], grasp_points={"handle": (0.3, 0.0, 0.0)})
    s0 = target.state(position=robot.point_position(x0) + [0.01, -0.01, 0.005] - [0.3, 0.0, 0.0], angular_velocity=(0.0, 0.0, 0.1))
    grasp = target.free_body(s0, "handle")
    track = mpc.Problem(
        horizon=8, dt=DT,
        running=[mpc.PointCost(body, grasp, weight=1e4, offset=offset), mpc.BaseAttitudeCost(10.0, rate_weight=1.0),
                 mpc.JointCost(0.0, robot.initial_q, weight_qd=1.0), mpc.ControlCost(1e-3)],
        terminal=[mpc.PointCost(body, grasp, weight=1e3, offset=offset)], control_limit=5.0)
    a = spacearm.simulate(robot, TRACK, dt=DT, controller=MPC(track, max_iterations=3))
    err = np.linalg.norm(np.array([robot.point_position(x) for x in a.x]) - grasp.evaluate(a.t)[0], axis=1)
    q = a.x[:, 3:7]
    angle = 2 * np.arccos(np.clip(np.abs(q @ q[0]), 0.0, 1.0))

    x, u = a.x[-1], a.u[-1]
    s = grasp.states(a.t[-1])
    hit = grasp_impulse(robot, x, u, target, s, grasp="handle")
    cap = attach_target(robot, x, hit.u_after, target, hit.target_state_after)
    n = cap.robot.n_dof
    calm = mpc.Problem(
        horizon=8, dt=DT, mode="rotation-flying",
        running=[mpc.BaseAttitudeCost(0.0, rate_weight=1e6), mpc.JointCost(0.0, x[7:], weight_qd=1e4), mpc.ControlCost(1e-2)],
        terminal=[mpc.BaseAttitudeCost(0.0, rate_weight=1e6), mpc.JointCost(0.0, x[7:], weight_qd=1e4)],
        control_limit=[5.0] * n + [2.0] * 3)
    b = spacearm.simulate(cap.robot, DETUMBLE, x0=x, u0=hit.u_after, dt=DT, mode="rotation-flying", controller=MPC(calm, max_iterations=3))
    tb = a.t[-1] + b.t
    rate = np.linalg.norm(b.u[:, 3:6], axis=1)

    fig, ax = plt.subplots(4, 1, figsize=(7, 9), sharex=True)
    ax[0].semilogy(a.t, err * 1e3)
    ax[0].axhline(1.0, color="0.6", lw=0.8, ls="--")
    ax[0].set_ylabel("grasp point error (mm)")
    ax[1].plot(a.t, np.degrees(angle))
    ax[1].set_ylabel("base rotation (deg)")
    ax[2].semilogy(tb, np.degrees(rate), label="|ω0| (deg/s)")
    ax[2].semilogy(tb, np.linalg.norm(b["L_com"], axis=1), label="|L| (N·m·s)")
    ax[2].set_ylabel("detumbling")
    ax[2].legend(fontsize=8)
    ax[3].plot(a.t[:-1], a["solve_time"][:-1] * 1e3, ".", ms=3, label="tracking")
    ax[3].plot(tb[:-1], b["solve_time"][:-1] * 1e3, ".", ms=3, label="detumbling")
    ax[3].set_ylabel("solve time (ms)")
    ax[3].set_ylim(bottom=0)
    ax[3].legend(fontsize=8)
    ax[3].set_xlabel("t (s)")
    for axis in ax:
        axis.axvline(a.t[-1], color="0.6", lw=0.8)
    ax[0].set_title("MPC on spatial6: tracking a tumbling grasp point, then detumbling")
    fig.tight_layout()
    fig.savefig(OUT, dpi=110)
    settled = a.t >= 1.0
    print(OUT, f"max error after 1 s {err[settled].max() * 1e3:.3f} mm, base rotation {np.degrees(angle.max()):.3f} deg, "
               f"|L| {np.linalg.norm(b['L_com'][0]):.3f} -> {np.linalg.norm(b['L_com'][-1]):.2e} N m s, "
               f"median solve {np.median(a['solve_time'][1:-1]) * 1e3:.1f} / {np.median(b['solve_time'][1:-1]) * 1e3:.1f} ms")


if __name__ == "__main__":
    main()
