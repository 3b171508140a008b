"""Environment steps per second: spacearm's vectorized Reach (one native batch call per step,
``spacearm.gym.ReachVectorEnv``) at 1, 2, 4, … threads, against a MuJoCo Gymnasium environment
of the same robot built from the exported MJCF (``spacearm.interop.mujoco.to_mjcf``: RK4, the
same ``dt``, ``frame_skip`` ``mj_step``s per env step as gymnasium's ``MujocoEnv.do_simulation``,
the same observation and reward), vectorized by gymnasium's ``SyncVectorEnv``.

Both run the same number of copies with the same random actions (episodes of
``max_episode_steps`` with autoreset); rounds are interleaved (every configuration once per
round), and the table gives the median env steps per second (copies × steps / time) and the
ratio to MuJoCo. The check column is the largest end-effector difference (m) between spacearm
and MuJoCo after 20 env steps of the same torques from the same state.

    python benchmarks/gym.py                    # 64 copies, threads 1, 2, 4, … up to the cores
    python benchmarks/gym.py --copies 16 --rounds 5 --steps 50

Needs ``spacearm[rl]`` and ``mujoco``.
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import numpy as np

import gymnasium
import mujoco
import spacearm
import spacearm.gym as sgym
from gymnasium.vector import AutoresetMode, SyncVectorEnv
from spacearm.interop import mujoco as mj


class MujocoReach(gymnasium.Env):
    """The Reach task of ``task`` (a spacearm.gym.ReachTask) on MuJoCo: same observation,
    reward, action scaling and goals; MuJoCo steps the dynamics."""

    metadata = {"render_modes": []}

    def __init__(self, task, xml: str):
        self.task = task
        self.model = mujoco.MjModel.from_xml_string(xml)
        self.model.opt.timestep = task.dt
        self.data = mujoco.MjData(self.model)
        robot = task.robot
        self.ctrl_of_tau = np.column_stack([mj.actuator_controls(robot, e) for e in np.eye(robot.n_dof)])
        self.site = self.model.site(robot.end_effector).id
        self.order = mj.engine_dof_order(robot)
        self.observation_space = task.observation_space
        self.action_space = task.action_space
        self.qpos0, self.qvel0 = mj.to_mujoco_state(robot, task.x0, task.u0)

    def _obs(self):
        d = self.data
        n = self.task.robot.n_dof
        q = np.empty(n)
        qd = np.empty(n)
        q[self.order] = d.qpos[7:]
        qd[self.order] = d.qvel[6:]
        p = d.site_xpos[self.site].copy()
        w0 = d.xmat[1].reshape(3, 3) @ d.qvel[3:6]
        return np.concatenate([q, qd, p, self.goal - p, w0])

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        mujoco.mj_resetData(self.model, self.data)
        self.data.qpos[:] = self.qpos0
        self.data.qvel[:] = self.qvel0
        self.goal = self.task.sample_goal(self.np_random)
        self.steps = 0
        mujoco.mj_forward(self.model, self.data)
        return self._obs(), {}

    def step(self, action):
        a = np.asarray(action, dtype=float)
        self.data.ctrl[:] = self.ctrl_of_tau @ self.task.torque(a[None])[0]
        mujoco.mj_step(self.model, self.data, nstep=self.task.frame_skip)
        self.steps += 1
        obs = self._obs()
        reward, _, success, runaway = self.task.reward(obs[None], a[None])
        return obs, float(reward[0]), bool(success[0] or runaway[0]), self.steps >= self.task.max_episode_steps, {}


def time_env(env, actions) -> float:
    """Seconds for len(actions) vector steps."""
    t0 = time.perf_counter()
    for a in actions:
        env.step(a)
    return time.perf_counter() - t0


def check(task, xml, steps=20) -> float:
    """Largest end-effector difference (m) after ``steps`` env steps of the same torques."""
    rng = np.random.default_rng(0)
    ours = sgym.ReachEnv(dt=task.dt, frame_skip=task.frame_skip)
    theirs = MujocoReach(task, xml)
    o1, _ = ours.reset(seed=0)
    o2, _ = theirs.reset(seed=0)
    n = task.robot.n_dof
    worst = 0.0
    for _ in range(steps):
        a = rng.uniform(-1, 1, n).astype(np.float32)
        o1 = ours.step(a)[0]
        o2 = theirs.step(a)[0]
        worst = max(worst, float(np.max(np.abs(o1[2 * n : 2 * n + 3] - o2[2 * n : 2 * n + 3]))))
    return worst


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--copies", type=int, default=64)
    ap.add_argument("--steps", type=int, default=100, help="vector steps per timed batch")
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--threads", type=str, default=None, help="comma-separated thread counts (default 1, 2, 4, … up to the cores)")
    ap.add_argument("--dt", type=float, default=0.01)
    ap.add_argument("--frame-skip", type=int, default=5)
    args = ap.parse_args(argv)
    cores = os.cpu_count() or 1
    if args.threads:
        threads = [int(t) for t in args.threads.split(",")]
    else:
        threads, t = [], 1
        while t <= cores:
            threads.append(t)
            t *= 2
        if threads[-1] != cores:
            threads.append(cores)
    robot = spacearm.presets.spatial6()
    task = sgym.ReachTask(robot, dt=args.dt, frame_skip=args.frame_skip, max_episode_steps=50)
    xml = mj.to_mjcf(robot)
    b = args.copies
    envs = {f"spacearm {t} thr": sgym.ReachVectorEnv(b, robot, threads=t, dt=args.dt, frame_skip=args.frame_skip, max_episode_steps=50)
            for t in threads}
    envs["mujoco Sync"] = SyncVectorEnv([lambda: MujocoReach(task, xml) for _ in range(b)], autoreset_mode=AutoresetMode.NEXT_STEP)
    rng = np.random.default_rng(1)
    actions = rng.uniform(-1, 1, (args.steps, b, robot.n_dof)).astype(np.float32)
    for env in envs.values():
        env.reset(seed=0)
        time_env(env, actions[:5])  # warm-up
    times = {name: [] for name in envs}
    for _ in range(args.rounds):
        for name, env in envs.items():  # interleaved: every configuration once per round
            times[name].append(time_env(env, actions))
    rate = {name: b * args.steps / statistics.median(ts) for name, ts in times.items()}
    ref = rate["mujoco Sync"]
    print(f"spatial6 (N = {robot.n_dof}), {b} copies, dt = {args.dt} s, frame_skip = {args.frame_skip} "
          f"(RK4 steps per env step), {args.rounds} interleaved rounds of {args.steps} vector steps; {cores} cores")
    print(f"{'environment':<18}{'env steps/s':>14}{'vs mujoco':>11}")
    for name, r in rate.items():
        print(f"{name:<18}{r:>14,.0f}{r / ref:>11.2f}")
    print(f"check: largest end-effector difference after 20 env steps, spacearm vs MuJoCo: {check(task, xml):.2e} m")
    print(f"versions: spacearm {spacearm.__version__}, mujoco {mujoco.__version__}, gymnasium {gymnasium.__version__}")


if __name__ == "__main__":
    main()
