#!/usr/bin/env python
"""A short PPO training on ``spacearm/Reach-v0`` with Stable-Baselines3, and its learning curve.

Eight copies of the environment (SB3's ``make_vec_env``, each under its ``Monitor``), PPO with
SB3's default MLP policy. The curve is the mean return and the mean final end-effector distance
of the last 20 finished episodes after each rollout, against the environment steps so far.

Writes ``rl_reach_ppo.png`` (and ``rl_reach_ppo.csv``, the curve's numbers) to --out-dir.
Needs ``stable-baselines3`` (PyTorch) and ``spacearm[rl,plot]``; not run in CI (minutes of CPU).

    python examples/rl_reach_ppo.py --timesteps 200000 --out-dir docs/figures
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--timesteps", type=int, default=200_000)
    ap.add_argument("--envs", type=int, default=8)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out-dir", default=".")
    args = ap.parse_args(argv)

    import gymnasium
    import torch
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from stable_baselines3 import PPO
    from stable_baselines3.common.callbacks import BaseCallback
    from stable_baselines3.common.env_util import make_vec_env

    import spacearm.gym  # noqa: F401  (registers the environments)

    torch.set_num_threads(1)
    env = make_vec_env(lambda: gymnasium.make("spacearm/Reach-v0"), n_envs=args.envs, seed=args.seed,
                       monitor_kwargs={"info_keywords": ("distance",)})
    curve = []

    class Curve(BaseCallback):
        def _on_rollout_end(self) -> None:
            eps = list(self.model.ep_info_buffer)[-20:]
            if eps:
                curve.append((self.num_timesteps, float(np.mean([e["r"] for e in eps])), float(np.mean([e["distance"] for e in eps]))))

        def _on_step(self) -> bool:
            return True

    model = PPO("MlpPolicy", env, n_steps=256, batch_size=256, seed=args.seed, verbose=0, device="cpu")
    t0 = time.perf_counter()
    model.learn(total_timesteps=args.timesteps, callback=Curve())
    wall = time.perf_counter() - t0
    data = np.array(curve)
    out = Path(args.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    np.savetxt(out / "rl_reach_ppo.csv", data, delimiter=",", header="timesteps,mean_return,mean_final_distance_m", comments="")

    fig = Figure(figsize=(7.5, 3.2), dpi=150)
    FigureCanvasAgg(fig)
    ax1, ax2 = fig.subplots(1, 2)
    ax1.plot(data[:, 0], data[:, 1], color="C0")
    ax1.set_xlabel("environment steps")
    ax1.set_ylabel("mean episode return (last 20)")
    ax2.plot(data[:, 0], data[:, 2], color="C3")
    ax2.set_xlabel("environment steps")
    ax2.set_ylabel("final end-effector distance [m]")
    fig.suptitle(f"PPO (Stable-Baselines3) on spacearm/Reach-v0, {args.envs} envs, {args.timesteps:,} steps, {wall / 60:.1f} min CPU",
                 fontsize=9)
    fig.tight_layout()
    fig.savefig(out / "rl_reach_ppo.png")
    print(f"trained {args.timesteps} steps in {wall:.0f} s; first/last mean return {data[0, 1]:.1f} / {data[-1, 1]:.1f}, "
          f"final distance {data[0, 2]:.3f} / {data[-1, 2]:.3f} m; wrote {out / 'rl_reach_ppo.png'}")


if __name__ == "__main__":
    main()
