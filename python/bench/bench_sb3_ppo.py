#!/usr/bin/env python3
"""Wall time of SB3 PPO on CartPole, 100k steps, rl-zoo's CartPole-v1 hyperparameters, 8 envs:
carl-spec's CartPole through `CarlSB3VecEnv` (one Rust call per batch step) beside the same run on
Gymnasium's CartPole-v1 through SB3's `make_vec_env` (DummyVecEnv + Monitor, what rl-zoo uses).

    python python/bench/bench_sb3_ppo.py [--repeats 2] [--steps 100000]

Needs the training venv (torch, stable-baselines3). After a short warm-up of each, runs alternate
(Gymnasium, carl-spec, carl-spec, Gymnasium, ...) so first-run costs and machine load hit both alike; prints one JSON line per run (wall and process CPU seconds: on a
shared machine CPU time is the fairer of the two) and a summary line with medians.
"""

from __future__ import annotations

import argparse
import json
import statistics
import time
from typing import Any

import numpy as np
import torch
from stable_baselines3 import PPO
from stable_baselines3.common.env_util import make_vec_env
from stable_baselines3.common.evaluation import evaluate_policy
from stable_baselines3.common.vec_env import VecEnv, VecMonitor

from carl_spec.sb3 import CarlSB3VecEnv

RL_ZOO_CARTPOLE: dict[str, Any] = dict(
    n_steps=32,
    batch_size=256,
    gae_lambda=0.8,
    gamma=0.98,
    n_epochs=20,
    ent_coef=0.0,
    learning_rate=lambda p: p * 1e-3,
    clip_range=lambda p: p * 0.2,
)


def make(which: str, n: int) -> VecEnv:
    if which == "carl_spec":
        return VecMonitor(CarlSB3VecEnv("cartpole", n))
    return make_vec_env("CartPole-v1", n_envs=n)


def run(which: str, seed: int, steps: int) -> dict[str, Any]:
    venv = make(which, 8)
    t0, c0 = time.perf_counter(), time.process_time()
    model = PPO("MlpPolicy", venv, seed=seed, device="cpu", **RL_ZOO_CARTPOLE)
    model.learn(steps)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    eval_env = make(which, 1)
    eval_env.seed(10_000 + seed)
    returns, _ = evaluate_policy(model, eval_env, n_eval_episodes=20, deterministic=True, return_episode_rewards=True)
    return {"env": which, "seed": seed, "steps": steps, "wall_s": round(wall, 2), "cpu_s": round(cpu, 2), "greedy_mean_20": float(np.mean(returns))}


def step_only(steps: int) -> dict[str, Any]:
    """The environment side alone: `steps` env steps of 8 envs with random actions through each
    SB3 VecEnv (what PPO's rollout pays besides the policy), process CPU seconds."""
    out: dict[str, Any] = {"workload": f"SB3 VecEnv step only, {steps} steps, 8 envs"}
    rng = np.random.default_rng(0)
    actions = rng.integers(0, 2, size=(64, 8))
    for which in ("carl_spec", "gymnasium"):
        venv = make(which, 8)
        venv.seed(0)
        venv.reset()
        c0 = time.process_time()
        for k in range(steps // 8):
            venv.step(actions[k & 63])
        out[f"{which}_cpu_s"] = round(time.process_time() - c0, 3)
    out["ratio_carl_spec_over_gymnasium"] = round(out["carl_spec_cpu_s"] / out["gymnasium_cpu_s"], 3)
    return out


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("--repeats", type=int, default=2)
    p.add_argument("--steps", type=int, default=100_000)
    p.add_argument("--step-only", action="store_true", help="only the VecEnv stepping, no training")
    args = p.parse_args()
    torch.set_num_threads(1)
    print(json.dumps(step_only(args.steps)), flush=True)
    if args.step_only:
        return
    # Warm up torch and SB3 once for each, then alternate which goes first, so neither pays the
    # process's first-run costs.
    for which in ("carl_spec", "gymnasium"):
        run(which, 0, 4096)
    rows: dict[str, list[dict[str, Any]]] = {"carl_spec": [], "gymnasium": []}
    for r in range(args.repeats):
        for which in ("gymnasium", "carl_spec")[:: 1 if r % 2 == 0 else -1]:
            row = run(which, r, args.steps)
            rows[which].append(row)
            print(json.dumps(row), flush=True)
    summary: dict[str, Any] = {"workload": f"SB3 PPO CartPole {args.steps} steps, 8 envs"}
    for key in ("wall_s", "cpu_s"):
        med = {k: statistics.median(x[key] for x in v) for k, v in rows.items()}
        summary[f"median_{key}"] = med
        summary[f"ratio_{key}_carl_spec_over_gymnasium"] = round(med["carl_spec"] / med["gymnasium"], 3)
    print(json.dumps(summary))


if __name__ == "__main__":
    main()
