#!/usr/bin/env python
"""The three flying modes of the paper's Table 1 on spatial6, with the same arm maneuver.

The arm follows a 4 s quintic joint maneuver under computed torque on the reduced EOM (which
compensates the base wrench it is combined with, docs/simulation-core.md); the base is actuated as each
mode allows, by a thruster law written as a Python ``control.Callback`` (base wrench only):

- rotation-flying: thruster torque couples hold the base attitude (PD on the attitude error
  quaternion); no external force, so the linear momentum P is conserved and the system CM stays
  put, while the angular momentum changes;
- translation-flying: a force through the system CM holds the base CM in place (PD on its
  position); no external torque about the CM, so L_com is conserved, while P changes (the CM
  moves as the arm moves);
- flying: the full wrench holds both the base position and attitude — the end effector then
  moves as on a fixed base; and ``control.CoordinatedFlying``, the native coordinated
  controller, drives the end effector along a straight line while holding the base pose.

Writes spatial6_<mode>.png and spatial6_<mode>_paths.png to --out-dir (a few seconds).

    python examples/flying_modes.py --out-dir out/examples
"""

import numpy as np

import spacearm
from spacearm import control

from _common import case_figure, out_dir


def attitude_error(quat, quat_ref):
    """Rotation vector (small-angle: 2 × vector part) of ``quat ⊗ quat_ref⁻¹``, in 𝒥."""
    x, y, z, w = quat
    rx, ry, rz, rw = -quat_ref[0], -quat_ref[1], -quat_ref[2], quat_ref[3]
    v = np.array([w * rx + x * rw + y * rz - z * ry, w * ry - x * rz + y * rw + z * rx, w * rz + x * ry - y * rx + z * rw])
    s = w * rw - x * rx - y * ry - z * rz
    return 2.0 * np.sign(s if s != 0 else 1.0) * v


def thruster_law(x0, n, force=True, torque=True, kp_f=5000.0, kd_f=3300.0, kp_t=2000.0, kd_t=1500.0):
    """A base wrench ``[F0, N0]`` (N, N m) holding the initial base pose: PD on the base CM
    position and on the attitude error, with joint torques left to the arm controller."""
    r_ref, q_ref = np.array(x0[:3]), np.array(x0[3:7])

    def fn(t, x, u):
        wrench = np.zeros(6)
        if force:
            wrench[:3] = -kp_f * (x[:3] - r_ref) - kd_f * u[:3]
        if torque:
            wrench[3:] = -kp_t * attitude_error(x[3:7], q_ref) - kd_t * u[3:6]
        return np.zeros(n), wrench

    return fn


def main():
    out = out_dir(__doc__.split("\n\n")[0])
    robot = spacearm.presets.spatial6()
    x0 = robot.neutral_configuration()
    q0 = robot.initial_q
    ref = control.QuinticJoint(q0, q0 + np.array([0.8, 0.5, 0.6, 0.5, 0.6, 0.5]), 0.0, 4.0)
    arm = control.ComputedTorque(kp=25.0, kd=10.0, reference=ref)
    modes = {
        "rotation-flying": thruster_law(x0, robot.n_dof, force=False),
        "translation-flying": thruster_law(x0, robot.n_dof, torque=False),
        "flying": thruster_law(x0, robot.n_dof),
    }
    runs = {mode: (mode, control.Combined(arm=arm, base=control.Callback(law))) for mode, law in modes.items()}
    if hasattr(control, "CoordinatedFlying"):
        # Native coordinated control: the end effector along a 0.4 m straight line while the
        # base wrench holds the base pose (acceleration-level, all in Rust).
        p0 = robot.point_position(x0)
        line = control.CartesianLine(p0, p0 + np.array([-0.2, 0.3, -0.1]), 0.0, 4.0)
        runs["flying_coordinated"] = ("flying", control.CoordinatedFlying(ee_reference=line))
    for name, (mode, ctrl) in runs.items():
        traj = spacearm.simulate(robot, 5.0, mode=mode, controller=ctrl, dt=1e-3, record_every=10)
        print(f"--- spatial6 / {name}\n{traj.summary()}\n  changed: "
              + ", ".join(f"{k} {v:.3g}" for k, v in traj.drift(["P", "L_origin", "L_com"]).items()) + "\n")
        traj.plot(out / f"spatial6_{name}.png")
        how = "coordinated control" if name == "flying_coordinated" else "computed torque + thrusters"
        case_figure(traj, out / f"spatial6_{name}_paths.png", f"spatial6, {mode}, {how}", plane=(0, 2))
    print(f"figures in {out}/")


if __name__ == "__main__":
    main()
