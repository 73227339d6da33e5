#!/usr/bin/env python3
"""Single-environment speed of carl-spec's robots beside Gymnasium's MuJoCo v5, in one run.

For each robot and each of `--runs` rounds (interleaved, so that both sides see the same machine
load), this times
* Gymnasium 1.4 `gymnasium.make("<Robot>-v5")` (MuJoCo, frame skip 5 (Hopper, Walker2d: 4), its 1000-step time limit):
  `--steps` steps with actions from a pre-drawn table of uniform random actions, resetting
  whenever an episode ends (resets are part of the time), and
* `carl-spec bench <robot> --num-envs 1 --threads 1 --steps N`: its `single_steps_per_sec`
  (one environment, random actions from a pre-drawn table, auto-reset; the same frame skip:
  5, Hopper and Walker2d 4, InvertedPendulum and Reacher 2; Pusher and HumanoidStandup 5),
and prints the median steps per second of each side, their ratio (carl-spec / MuJoCo) and the
load average before and after (the machine may be shared: compare ratios, not absolute rates).

Usage (from the repository root, with Gymnasium 1.4 and mujoco installed):
    python3 scripts/robot_speed_compare.py --carl-spec target/release/carl-spec \\
        --runs 5 --json robot_speed.json --markdown robot_speed.md
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import time



def count(text):
    """An argparse type: an integer of at least 1 (a count of runs, steps, episodes, seeds)."""
    n = int(text)
    if n < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, not {n}")
    return n


GYM_IDS = {
    "ant": "Ant-v5",
    "half_cheetah": "HalfCheetah-v5",
    "humanoid": "Humanoid-v5",
    "hopper": "Hopper-v5",
    "walker2d": "Walker2d-v5",
    "inverted_pendulum": "InvertedPendulum-v5",
    "inverted_double_pendulum": "InvertedDoublePendulum-v5",
    "reacher": "Reacher-v5",
    "pusher": "Pusher-v5",
    "humanoid_standup": "HumanoidStandup-v5",
}
ACTION_TABLE = 4096


def mujoco_steps_per_sec(env, actions, steps):
    env.reset(seed=0)
    for k in range(min(steps // 10, 1000)):  # warm-up, as carl-spec bench does
        _, _, term, trunc, _ = env.step(actions[k % len(actions)])
        if term or trunc:
            env.reset()
    t0 = time.perf_counter()
    for k in range(steps):
        _, _, term, trunc, _ = env.step(actions[k % len(actions)])
        if term or trunc:
            env.reset()
    return steps / (time.perf_counter() - t0)


def carl_steps_per_sec(exe, robot, steps):
    cmd = [exe, "bench", robot, "--num-envs", "1", "--threads", "1", "--steps", str(steps)]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"carl-spec failed: {' '.join(cmd)}\n{p.stderr}")
    return float(json.loads(p.stdout.strip().splitlines()[-1])["single_steps_per_sec"])


def write_report(args, meta, results, md):
    """The raw runs as JSON (`--json`), the table as markdown (`--markdown`), the table printed."""
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"meta": meta, "results": results}, f, indent=1)
            f.write("\n")
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write(md)
    print(md)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--carl-spec", default="target/release/carl-spec")
    ap.add_argument("--robots", default="ant,half_cheetah,humanoid")
    ap.add_argument("--runs", type=count, default=5)
    ap.add_argument("--steps", type=count, default=5000, help="environment steps timed per run and side")
    ap.add_argument("--json")
    ap.add_argument("--markdown")
    args = ap.parse_args()
    if args.runs < 1 or args.steps < 1:
        sys.exit("--runs and --steps must be at least 1")
    robots = [r.strip() for r in args.robots.split(",") if r.strip()]
    for r in robots:
        if r not in GYM_IDS:
            sys.exit(f"unknown robot {r!r}; choose from {', '.join(GYM_IDS)}")
    import gymnasium as gym
    import mujoco
    import numpy as np

    load_before = os.getloadavg()
    results = {}
    for robot in robots:
        env = gym.make(GYM_IDS[robot])
        env.action_space.seed(0)
        actions = [env.action_space.sample() for _ in range(ACTION_TABLE)]
        runs = {"mujoco": [], "carl": []}
        for k in range(args.runs):
            runs["mujoco"].append(mujoco_steps_per_sec(env, actions, args.steps))
            runs["carl"].append(carl_steps_per_sec(args.carl_spec, robot, args.steps))
            print(f"{robot} run {k + 1}: MuJoCo {runs['mujoco'][-1]:.0f}/s, carl-spec {runs['carl'][-1]:.0f}/s",
                  file=sys.stderr, flush=True)
        env.close()
        med = {side: statistics.median(v) for side, v in runs.items()}
        results[robot] = {"runs": runs, "median": med, "ratio": med["carl"] / med["mujoco"]}
    load_after = os.getloadavg()
    meta = {
        "generator": "scripts/robot_speed_compare.py",
        "gymnasium": gym.__version__,
        "mujoco": mujoco.__version__,
        "numpy": np.__version__,
        "runs": args.runs,
        "steps": args.steps,
        "cpus": os.cpu_count(),
        "load_before": [round(x, 2) for x in load_before],
        "load_after": [round(x, 2) for x in load_after],
    }
    lines = [
        "| robot | MuJoCo v5 steps/s (median) | carl-spec steps/s (median) | carl-spec / MuJoCo |",
        "|---|---|---|---|",
    ]
    for robot, r in results.items():
        lines.append(f"| {robot} | {r['median']['mujoco']:.0f} | {r['median']['carl']:.0f} | {r['ratio']:.2f} |")
    lines.append("")
    lines.append(
        f"{args.runs} interleaved runs of {args.steps} steps per side; load average before "
        f"{meta['load_before'][0]:.1f}, after {meta['load_after'][0]:.1f} on {meta['cpus']} CPUs."
    )
    md = "\n".join(lines) + "\n"
    write_report(args, meta, results, md)


if __name__ == "__main__":
    main()
