#!/usr/bin/env python3
"""Single-env speed of carl-spec's robots beside Gymnasium's MuJoCo v5 versions, in one run.

Both sides: one environment, uniform random actions, episodes with their resets included,
default frame skip (Ant/HalfCheetah/Humanoid: 5). carl-spec is timed by `carl-spec bench ENV
--num-envs 1 --threads 1 --steps N` (its `single_ns_per_step`), MuJoCo by a plain
`env.step` loop. The two alternate `--repeats` times; the medians and their ratio are printed
as a Markdown table, with the load average (the machine may be shared).

    python scripts/robot_speed_vs_mujoco.py --carl-spec target/release/carl-spec
(needs gymnasium 1.4 and mujoco in the running Python, e.g. /work/venvs/peers/bin/python).
"""
import argparse
import json
import os
import statistics
import subprocess
import time

import gymnasium as gym
import numpy as np

ROBOTS = [("ant", "Ant-v5"), ("half_cheetah", "HalfCheetah-v5"), ("humanoid", "Humanoid-v5")]


def mujoco_us_per_step(env_id: str, steps: int, seed: int) -> float:
    env = gym.make(env_id)
    env.action_space.seed(seed)
    actions = [env.action_space.sample() for _ in range(steps)]
    env.reset(seed=seed)
    t = time.perf_counter()
    for a in actions:
        _, _, term, trunc, _ = env.step(a)
        if term or trunc:
            env.reset()
    dt = time.perf_counter() - t
    env.close()
    return dt / steps * 1e6


def carl_us_per_step(binary: str, env: str, steps: int) -> float:
    out = subprocess.run(
        [binary, "bench", env, "--num-envs", "1", "--threads", "1", "--steps", str(steps)],
        check=True, capture_output=True, text=True,
    ).stdout
    return json.loads(out)["single_ns_per_step"] / 1e3


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--carl-spec", default="target/release/carl-spec")
    ap.add_argument("--steps", type=int, default=2000)
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args()
    print(f"load average at start: {os.getloadavg()[0]:.1f} ({os.cpu_count()} cores)")
    print("| robot | carl-spec µs/step | MuJoCo v5 µs/step | speed vs MuJoCo |")
    print("|---|---|---|---|")
    for env, gid in ROBOTS:
        ours, theirs = [], []
        for r in range(args.repeats):
            theirs.append(mujoco_us_per_step(gid, args.steps, r))
            ours.append(carl_us_per_step(args.carl_spec, env, args.steps))
        o, m = statistics.median(ours), statistics.median(theirs)
        print(f"| {env} | {o:.0f} | {m:.0f} | {m / o:.2f}x |", flush=True)
    print(f"load average at end: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    np.random.seed(0)
    main()
