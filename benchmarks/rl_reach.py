#!/usr/bin/env python
"""A learning curve on ``spacearm/Reach-v0`` without PyTorch: augmented random search (ARS,
Mania, Guy & Recht 2018, the antithetic random-search estimator of the evolution strategies of
Salimans et al. 2017) or the noisy cross-entropy method (Rubinstein 1999; Szita & Lőrincz 2006) on
a linear policy, with the vectorized environment.

Policy: ``a = clip(W f(obs), -1, 1)`` with the features ``f`` (``--features``, default
``qd,error,omega``) the observation's ``q̇`` (/1 rad/s), ``p_goal - p_ee`` (/0.3 m) and ``ω_0``
(/0.05 rad/s), fixed scales (``q - q_0`` and a bias can be added; ``p_ee`` is a function of ``q``).
For ``spatial6``: 6 × 12 = 72 parameters. At the goal at rest every default feature is zero, so
is the action.

The mean policy starts as the joint damper ``a_i = -q̇_i / (1 rad/s)`` (``--damping``; 0 gives
the zero policy): at rest it *is* the zero policy (same return), but its perturbations do not run
the wrist away. Started from the zero policy itself, ARS and CEM both fall into policies that
end every episode in a runaway: linear policies near zero are mostly unstable here (parameters
of standard deviation 0.003, actions below 0.01, ran away in 30 % of 64 episodes, 0.01 in 91 %;
mostly the wrist joints 4 and 6 counter-rotating past 3 rad/s after several seconds), measured
and reported in docs/rl.md.

ARS (``--method ars``, the default; V1 without state normalization: the features have fixed
scales): per iteration, ``--population / 2`` directions ``δ ~ N(0, I)``, each policy
``μ ± ν δ`` run on the same ``--goals`` goals (one episode per goal; every run of the iteration in
one ``ReachVectorEnv``, ``population × goals`` copies stepped in one native call per step);
with the ``--elite`` fraction of directions of the highest ``max(r+, r-)``,
``μ ← μ + α / (b σ_R) Σ (r+ - r-) δ`` (``α`` ``--step``, ``σ_R`` the standard deviation of the
``2b`` returns used). CEM (``--method cem``): ``--population`` candidates from
``N(μ, diag σ²)``, ``μ, σ²`` refitted to the elite fraction plus the extra variance
``Z_t = noise × max(0, 1 - t / iterations)``. The goals of every iteration are new (seeds drawn
from ``--seed``).

The curve: after every iteration, the mean policy ``μ`` on ``--eval-goals`` fixed evaluation
goals (seeds 1,000,000 + i, never used in training): mean return, success rate
(``info["is_success"]``: the end effector within 0.02 m of the goal), runaway rate and mean
final distance. On the same evaluation goals: the zero policy and a scripted resolved-motion-rate
controller (the core's DLS law through ``J*``, ``spacearm.analysis.rmrc_rates``, strategies
``naive`` and ``minimum_disturbance``, followed by a joint-rate loop through ``H*`` and ``c*``:
the law of ``spacearm.control.ResolvedMotionRate``; gain 1/s and velocity gain 5/s, the best of
gain ∈ {1, 2, 4} × velocity gain ∈ {5, 10} on these goals), which reads the simulator's full
state (the base attitude too: more than the observation gives).

    python benchmarks/rl_reach.py                          # the run of docs/rl.md (a few minutes)
    python benchmarks/rl_reach.py --iterations 3 --population 8 --goals 2 --eval-goals 4 --json '' --no-figure

Writes the curve as JSON (``--json``, default docs/figures/rl_reach_learning_curve.json; '' for
none) and the figure (``--figure``, default docs/figures/rl_reach_learning_curve.png). Needs
``spacearm[rl,plot]``. Not run in CI.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time

import numpy as np

import spacearm
import spacearm.gym as sgym
from spacearm.analysis import rmrc_rates

HERE = os.path.dirname(os.path.abspath(__file__))
FIGURES = os.path.join(os.path.dirname(HERE), "docs", "figures")
EVAL_SEED = 1_000_000


FEATURES = ("q", "qd", "error", "omega", "bias")


class LinearPolicy:
    """``a = clip(W f(obs), -1, 1)`` for a batch of parameter vectors (one per copy); ``f`` the
    chosen ``features`` of the observation, each over a fixed scale: ``q`` (``q - q_0``, /0.5 rad),
    ``qd`` (``q̇``, /1 rad/s), ``error`` (``p_goal - p_ee``, /0.3 m), ``omega`` (``ω_0``, /0.05 rad/s),
    ``bias`` (1)."""

    def __init__(self, task, features=("qd", "error", "omega")):
        n = task.robot.n_dof
        self.n = n
        self.q0 = task.x0[7:].copy()
        unknown = set(features) - set(FEATURES)
        if unknown:
            raise ValueError(f"unknown features {sorted(unknown)}: choose among {FEATURES}")
        self.features_used = tuple(f for f in FEATURES if f in features)
        self.n_features = sum({"q": n, "qd": n, "error": 3, "omega": 3, "bias": 1}[f] for f in self.features_used)
        self.n_params = n * self.n_features

    def features(self, obs):
        n = self.n
        parts = {"q": lambda: (obs[:, :n] - self.q0) / 0.5, "qd": lambda: obs[:, n : 2 * n] / 1.0,
                 "error": lambda: obs[:, 2 * n + 3 : 2 * n + 6] / 0.3, "omega": lambda: obs[:, 2 * n + 6 : 2 * n + 9] / 0.05,
                 "bias": lambda: np.ones((len(obs), 1))}
        return np.concatenate([parts[f]() for f in self.features_used], axis=1)

    def damper(self, gain):
        """Parameters of the joint damper ``a_i = -gain q̇_i / (1 rad/s)`` (zero without the ``qd``
        feature): at rest it is the zero policy."""
        w = np.zeros((self.n, self.n_features))
        if "qd" in self.features_used:
            start = sum(self.n if f == "q" else 0 for f in self.features_used[: self.features_used.index("qd")])
            w[:, start : start + self.n] = -gain * np.eye(self.n)
        return w.ravel()

    def act(self, params, obs):
        """``params`` (B, n_params), ``obs`` (B, 2N+9) -> actions (B, N)."""
        w = params.reshape(len(params), self.n, self.n_features)
        return np.clip(np.einsum("bij,bj->bi", w, self.features(obs)), -1.0, 1.0)


def run_episodes(env, seeds, policy):
    """One episode per copy from ``seeds`` (one per copy); ``policy(obs, env) -> actions``.
    Returns per copy: return, success, runaway, final distance, steps (rewards after a copy's
    episode ends, its autoreset, are not counted)."""
    obs, _ = env.reset(seed=list(seeds))
    b = env.num_envs
    total = np.zeros(b)
    live = np.ones(b, dtype=bool)
    success = np.zeros(b, dtype=bool)
    runaway = np.zeros(b, dtype=bool)
    distance = np.zeros(b)
    steps = np.zeros(b, dtype=int)
    while live.any():
        obs, reward, terminated, truncated, info = env.step(policy(obs, env).astype(np.float32))
        total += np.where(live, reward, 0.0)
        success |= live & info["is_success"]
        runaway |= live & info["runaway"]
        distance = np.where(live, info["distance"], distance)
        steps += live
        live &= ~(terminated | truncated)
    return total, success, runaway, distance, steps


def summary(result):
    total, success, runaway, distance, steps = result
    return {"mean_return": float(total.mean()), "success_rate": float(success.mean()), "runaway_rate": float(runaway.mean()),
            "mean_final_distance": float(distance.mean()), "mean_steps": float(steps.mean())}


def scripted_policy(task, strategy, gain=1.0, velocity_gain=5.0, max_rate=1.0):
    """Resolved-motion-rate control of the end effector toward the goal: ``q̇_cmd`` from the core's
    DLS law through ``J*`` (``rmrc_rates``, position rows, the point velocity ``gain (p_goal - p)``),
    scaled so no joint exceeds ``max_rate``; then ``τ = H* velocity_gain (q̇_cmd - q̇) + c*`` as an
    action (``τ / τ_max``). Reads the vector env's full states (the base attitude too)."""
    robot = task.robot
    n, nx = robot.n_dof, robot.nx

    def policy(obs, env):
        states = env._states  # the simulator's full states: privileged, the observation lacks the base attitude
        actions = np.zeros((len(obs), n))
        for i, s in enumerate(states):
            x, u = s[:nx], s[nx:]
            error = obs[i, 2 * n + 3 : 2 * n + 6]
            qd_cmd = np.asarray(rmrc_rates(robot, x, np.concatenate([gain * error, np.zeros(3)]), task="position", strategy=strategy).qd)
            peak = np.max(np.abs(qd_cmd))
            if peak > max_rate:
                qd_cmd *= max_rate / peak
            tau = robot.generalized_inertia(x) @ (velocity_gain * (qd_cmd - u[6:])) + robot.generalized_bias(x, u)
            actions[i] = tau / task.torque_scale
        return np.clip(actions, -1.0, 1.0)

    return policy


def figure(curve, baselines, path, meta):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    it = np.array([c["iteration"] for c in curve])
    steps = np.array([c["env_steps"] for c in curve]) / 1e6
    fig = Figure(figsize=(9.0, 3.6))
    FigureCanvasAgg(fig)
    ax1, ax2 = fig.subplots(1, 2)
    ax1.plot(steps, [c["eval"]["mean_return"] for c in curve], "C0-", lw=2, label=f"{meta['method']} mean policy (evaluation goals)")
    ax1.plot(steps, [c["population_mean_return"] for c in curve], "C0:", lw=1, label=f"{meta['method']} runs (training goals)")
    ax1.plot(steps, [c["elite_mean_return"] for c in curve], "C0--", lw=1, label=f"{meta['method']} elites (training goals)")
    styles = {"zero": ("C7", "zero policy"), "rmrc_naive": ("C3", "scripted RMRC, naive (DLS)"),
              "rmrc_minimum_disturbance": ("C2", "scripted RMRC, minimum disturbance (DLS)")}
    for key, b in baselines.items():
        color, label = styles[key]
        ax1.axhline(b["mean_return"], color=color, ls="-.", lw=1, label=label)
        ax2.axhline(b["success_rate"], color=color, ls="-.", lw=1)
    lo = min(min(c["eval"]["mean_return"] for c in curve), min(b["mean_return"] for b in baselines.values()))
    ax1.set_ylim(lo - 10, 0)
    ax1.set_xlabel("environment steps (millions)")
    ax1.set_ylabel("mean episode return")
    ax1.legend(fontsize=7, loc="lower right")
    ax1.grid(alpha=0.3)
    ax2.plot(steps, [c["eval"]["success_rate"] for c in curve], "C0-", lw=2, label="success rate")
    ax2.plot(steps, [c["eval"]["mean_final_distance"] for c in curve], "C1-", lw=1.5, label="final distance (m)")
    ax2.plot(steps, [c["eval"]["runaway_rate"] for c in curve], "C4:", lw=1.5, label="runaway rate")
    ax2.set_xlabel("environment steps (millions)")
    ax2.set_ylim(0, 1.05)
    ax2.legend(fontsize=7, loc="center right")
    ax2.grid(alpha=0.3)
    ax2.set_title("mean policy, evaluation goals", fontsize=9)
    fig.suptitle(f"spacearm/Reach-v0 (spatial6, floating): {meta['method']}, linear policy, {meta['population']} runs × "
                 f"{meta['goals']} goals, {meta['eval_goals']} evaluation goals, seed {meta['seed']}", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--method", choices=("ars", "cem"), default="ars")
    ap.add_argument("--iterations", type=int, default=80)
    ap.add_argument("--population", type=int, default=48)
    ap.add_argument("--goals", type=int, default=4, help="training goals per candidate and iteration")
    ap.add_argument("--elite", type=float, default=None, help="elite fraction (CEM: of the candidates, default 0.2; ARS: of the directions, default 0.5)")
    ap.add_argument("--sigma0", type=float, default=0.3, help="initial standard deviation of every parameter")
    ap.add_argument("--nu", type=float, default=0.03, help="ARS: exploration noise of a direction")
    ap.add_argument("--step", type=float, default=0.02, help="ARS: step size")
    ap.add_argument("--noise", type=float, default=0.01, help="extra variance at the start (noisy CEM), decaying linearly to 0")
    ap.add_argument("--features", default="qd,error,omega", help=f"policy features, comma-separated, among {','.join(FEATURES)}")
    ap.add_argument("--damping", type=float, default=1.0, help="the initial mean policy: the joint damper of this gain (0: the zero policy)")
    ap.add_argument("--eval-goals", type=int, default=32)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--threads", type=int, default=None)
    ap.add_argument("--json", default=os.path.join(FIGURES, "rl_reach_learning_curve.json"))
    ap.add_argument("--figure", default=os.path.join(FIGURES, "rl_reach_learning_curve.png"))
    ap.add_argument("--no-figure", action="store_true")
    args = ap.parse_args(argv)

    rng = np.random.default_rng(args.seed)
    pop, goals = args.population, args.goals
    train = sgym.make_vec(pop * goals, threads=args.threads)
    evaluate = sgym.make_vec(args.eval_goals, threads=args.threads)
    task = train.task
    policy = LinearPolicy(task, args.features.split(","))
    eval_seeds = [EVAL_SEED + i for i in range(args.eval_goals)]
    if args.elite is None:
        args.elite = 0.2 if args.method == "cem" else 0.5
    n_elite = max(2, int(round(args.elite * (pop if args.method == "cem" else pop // 2))))

    t0 = time.perf_counter()
    baselines = {"zero": summary(run_episodes(evaluate, eval_seeds, lambda obs, env: np.zeros((len(obs), task.robot.n_dof))))}
    for strategy in ("naive", "minimum_disturbance"):
        baselines[f"rmrc_{strategy}"] = summary(run_episodes(evaluate, eval_seeds, scripted_policy(task, strategy)))
    for key, b in baselines.items():
        print(f"baseline {key:26s} return {b['mean_return']:8.2f}  success {b['success_rate']:.2f}  runaway {b['runaway_rate']:.2f}  "
              f"final distance {b['mean_final_distance']:.3f} m")

    mu = policy.damper(args.damping)
    var = np.full(policy.n_params, args.sigma0**2)

    def evaluate_mean():
        return summary(run_episodes(evaluate, eval_seeds, lambda obs, env: policy.act(np.tile(mu, (len(obs), 1)), obs)))

    curve = [{"iteration": 0, "env_steps": 0, "population_mean_return": None, "elite_mean_return": None, "eval": evaluate_mean()}]
    env_steps = 0
    print(f"iter {0:3d}  env steps {0:9d}  eval return {curve[0]['eval']['mean_return']:8.2f}  success {curve[0]['eval']['success_rate']:.2f}")
    for it in range(1, args.iterations + 1):
        seeds = [int(s) for s in rng.integers(0, 2**31 - 1, size=goals)]
        if args.method == "cem":
            candidates = mu + np.sqrt(var) * rng.standard_normal((pop, policy.n_params))
        else:  # ARS: pop // 2 directions, each tried as mu + nu delta and mu - nu delta
            directions = rng.standard_normal((pop // 2, policy.n_params))
            candidates = np.concatenate([mu + args.nu * directions, mu - args.nu * directions])
        params = np.repeat(candidates, goals, axis=0)  # copy c * goals + g: candidate c on goal g
        total, _, _, _, steps = run_episodes(train, seeds * len(candidates), lambda obs, env: policy.act(params, obs))
        env_steps += int(steps.sum())
        score = total.reshape(len(candidates), goals).mean(axis=1)
        if args.method == "cem":
            elite = np.argsort(score)[-n_elite:]
            mu = candidates[elite].mean(axis=0)
            var = candidates[elite].var(axis=0) + args.noise * max(0.0, 1.0 - it / args.iterations)
            elite_mean = float(score[elite].mean())
        else:
            plus, minus = score[: pop // 2], score[pop // 2 :]
            top = np.argsort(np.maximum(plus, minus))[-n_elite:]
            spread = np.concatenate([plus[top], minus[top]]).std() + 1e-8
            mu = mu + args.step / (n_elite * spread) * ((plus[top] - minus[top]) @ directions[top])
            elite_mean = float(np.maximum(plus, minus)[top].mean())
        ev = evaluate_mean()
        curve.append({"iteration": it, "env_steps": env_steps, "population_mean_return": float(score.mean()),
                      "elite_mean_return": elite_mean, "eval": ev})
        print(f"iter {it:3d}  env steps {env_steps:9d}  population {score.mean():8.2f}  elites {elite_mean:8.2f}  "
              f"eval return {ev['mean_return']:8.2f}  success {ev['success_rate']:.2f}  runaway {ev['runaway_rate']:.2f}  "
              f"final distance {ev['mean_final_distance']:.3f} m  ({time.perf_counter() - t0:.0f} s)", flush=True)
    wall = time.perf_counter() - t0

    meta = {"method": {"ars": "ARS", "cem": "noisy CEM"}[args.method], "population": pop, "goals": goals, "eval_goals": args.eval_goals, "seed": args.seed}
    out = {"env": "spacearm/Reach-v0", "robot": "spatial6", "method": {"ars": "augmented random search (V1), linear policy", "cem": "noisy cross-entropy method, linear policy"}[args.method],
           "args": vars(args), "n_params": policy.n_params, "n_elite": n_elite, "eval_seeds": [EVAL_SEED, EVAL_SEED + args.eval_goals - 1],
           "baselines": baselines, "curve": curve, "wall_s": wall, "spacearm": spacearm.__version__,
           "machine": {"cpus": os.cpu_count(), "platform": platform.platform(), "load_average": list(os.getloadavg())},
           "final_mean_policy": mu.tolist()}
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=1)
    if not args.no_figure:
        figure(curve, baselines, args.figure, meta)
    first, last = curve[0]["eval"], curve[-1]["eval"]
    print(f"eval return {first['mean_return']:.2f} -> {last['mean_return']:.2f}, success {first['success_rate']:.2f} -> "
          f"{last['success_rate']:.2f}, final distance {first['mean_final_distance']:.3f} -> {last['mean_final_distance']:.3f} m "
          f"({env_steps} env steps, {wall:.0f} s)")


if __name__ == "__main__":
    main()
