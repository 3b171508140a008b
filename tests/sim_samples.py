"""Synthetic simulation results in the layout of ``_core.simulate`` (docs/simulation.md), for
testing the Trajectory, its files and its figures without running a simulation."""

import numpy as np

import spacearm
from spacearm.rotations import quat_from_axis_angle


def synthetic(robot=None, k=41, seed=0):
    """A run in the layout of _core.simulate: base drifting and turning about a fixed axis,
    joints swinging; momenta, energy, CM and end effector from the robot's own functions."""
    robot = robot or spacearm.presets.spatial6()
    rng = np.random.default_rng(seed)
    n = robot.n_dof
    t = np.linspace(0.0, 2.0, k)
    axis = np.array([1.0, 2.0, 2.0]) / 3.0
    x = np.zeros((k, 7 + n))
    u = np.zeros((k, 6 + n))
    amp = rng.uniform(0.1, 0.5, n)
    for i, ti in enumerate(t):
        x[i, :3] = [0.1 * ti, -0.05 * ti, 0.02]
        x[i, 3:7] = quat_from_axis_angle(axis, 0.3 * ti)
        x[i, 7:] = robot.initial_q + amp * np.sin(ti)
        u[i, :3] = [0.1, -0.05, 0.0]
        u[i, 3:6] = 0.3 * axis
        u[i, 6:] = amp * np.cos(ti)
    data = {"t": t, "x": x, "u": u, "du": np.zeros_like(u), "tau": rng.normal(size=(k, n)),
            "tau_cmd": rng.normal(size=(k, n)), "base_wrench": np.zeros((k, 6))}
    mom = [robot.momentum(x[i], u[i]) for i in range(k)]
    data["P"] = np.array([m.P for m in mom])
    data["L_origin"] = np.array([m.L_origin for m in mom])
    data["L_com"] = np.array([m.L_com for m in mom])
    data["energy"] = np.array([robot.kinetic_energy(x[i], u[i]) for i in range(k)])
    data["com"] = np.array([robot.center_of_mass(x[i]) for i in range(k)])
    data["ee_position"] = np.array([robot.point_position(x[i]) for i in range(k)])
    data["ee_quat"] = np.tile([0.0, 0.0, 0.0, 1.0], (k, 1))
    data["reference"] = np.tile(robot.initial_q, (k, 1))
    data["tracking_error"] = np.linalg.norm(x[:, 7:] - robot.initial_q, axis=1)
    data["saturation_t"] = np.array([0.5, 0.55, 1.0])
    data["saturation_actuator"] = np.array([1, 1, 6])
    data["saturation_kind"] = np.array([0, 0, 2])
    meta = {"mode": "floating", "integrator": "rk4", "dt": 1e-3, "rtol": 1e-9, "atol": 1e-12,
            "controller": "JointPD", "conserved": ["P", "L_origin"], "drift": {"P": 0.0, "L_origin": 0.0},
            "n_steps": 2000, "n_rejected": 0, "n_rhs_evals": 8000,
            "actuator_names": [f"joint{i + 1}" for i in range(n)] + ["thruster_force"],
            "wheel_dofs": [], "tracking_error_kind": "joint"}
    return robot, data, meta
