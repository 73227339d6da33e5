#!/usr/bin/env python3
"""Batched speed of carl-spec's robots beside envpool's MuJoCo tasks of the same name, in one run.

For each robot and each of `--runs` rounds (interleaved, so that both sides see the same machine
load), this times
* envpool `envpool.make_gymnasium("<Robot>-v5", num_envs=N, batch_size=N, num_threads=T)`:
  `--steps` environment steps (`--steps / N` batch steps) with actions from a pre-drawn table of
  uniform random actions; envpool resets finished environments itself (resets are part of the
  time), and
* `carl-spec bench <robot> --num-envs N --threads T --steps S`: its `vec_steps_per_sec`
  (random actions from a pre-drawn table, auto-reset),
and prints the median environment steps per second of each side, their ratio (carl-spec /
envpool) and the load average before and after (compare ratios, not absolute rates: the machine
may be shared). The robots are those of `robot_speed_compare.py` (its `GYM_IDS`) and the dm_control
family's environments (envpool's dm_control tasks of the same name, `ENVPOOL_IDS`).

Usage (from the repository root, in a venv with envpool from PyPI, e.g.
`python3 -m venv ~/venvs/envpool && ~/venvs/envpool/bin/pip install envpool==1.2.5`):
    ~/venvs/envpool/bin/python scripts/robot_envpool_compare.py --carl-spec target/release/carl-spec \\
        --num-envs 16 --threads 2 --runs 5 --json robot_envpool.json --markdown robot_envpool.md
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from robot_speed_compare import GYM_IDS, count, write_report  # noqa: E402

ACTION_TABLE = 256
# envpool's id of each environment: the MuJoCo robots' Gymnasium ids, and envpool's dm_control
# tasks (its `<Domain><Task>-v1`) for the dm_control family.
ENVPOOL_IDS = {**GYM_IDS, "dmc_point_mass": "PointMassEasy-v1", "dmc_walker": "WalkerWalk-v1",
               "dmc_fish": "FishSwim-v1", "dmc_quadruped": "QuadrupedWalk-v1",
               "dmc_finger": "FingerSpin-v1"}


def envpool_steps_per_sec(env, actions, batch_steps):
    env.reset()
    for k in range(min(batch_steps // 10, 100)):  # warm-up, as carl-spec bench does
        env.step(actions[k % len(actions)])
    t0 = time.perf_counter()
    for k in range(batch_steps):
        env.step(actions[k % len(actions)])
    return batch_steps * env.config["num_envs"] / (time.perf_counter() - t0)


def carl_steps_per_sec(exe, robot, num_envs, threads, steps):
    cmd = [exe, "bench", robot, "--num-envs", str(num_envs), "--threads", str(threads), "--steps", str(steps)]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"carl-spec failed: {' '.join(cmd)}\n{p.stderr}")
    return float(json.loads(p.stdout.strip().splitlines()[-1])["vec_steps_per_sec"])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--carl-spec", default="target/release/carl-spec")
    ap.add_argument("--robots", default=",".join(GYM_IDS))  # or any of ENVPOOL_IDS
    ap.add_argument("--num-envs", type=count, default=16)
    ap.add_argument("--threads", type=count, default=2)
    ap.add_argument("--runs", type=count, default=5)
    ap.add_argument("--steps", type=count, default=32000, help="environment steps timed per run and side")
    ap.add_argument("--json")
    ap.add_argument("--markdown")
    args = ap.parse_args()
    if min(args.runs, args.steps, args.num_envs, args.threads) < 1:
        sys.exit("--runs, --steps, --num-envs and --threads must be at least 1")
    robots = [r.strip() for r in args.robots.split(",") if r.strip()]
    for r in robots:
        if r not in ENVPOOL_IDS:
            sys.exit(f"unknown robot {r!r}; choose from {', '.join(ENVPOOL_IDS)}")
    import envpool
    import numpy as np

    batch_steps = max(1, args.steps // args.num_envs)
    load_before = os.getloadavg()
    results = {}
    for robot in robots:
        env = envpool.make_gymnasium(
            ENVPOOL_IDS[robot], num_envs=args.num_envs, batch_size=args.num_envs, num_threads=args.threads, seed=0
        )
        space = env.action_space
        rng = np.random.default_rng(0)
        actions = [
            rng.uniform(space.low, space.high, size=(args.num_envs, *space.shape)).astype(space.dtype)
            for _ in range(ACTION_TABLE)
        ]
        runs = {"envpool": [], "carl": []}
        for k in range(args.runs):
            runs["envpool"].append(envpool_steps_per_sec(env, actions, batch_steps))
            runs["carl"].append(carl_steps_per_sec(args.carl_spec, robot, args.num_envs, args.threads, args.steps))
            print(
                f"{robot} run {k + 1}: envpool {runs['envpool'][-1]:.0f}/s, carl-spec {runs['carl'][-1]:.0f}/s",
                file=sys.stderr,
                flush=True,
            )
        env.close()
        med = {side: statistics.median(v) for side, v in runs.items()}
        results[robot] = {"runs": runs, "median": med, "ratio": med["carl"] / med["envpool"]}
    load_after = os.getloadavg()
    meta = {
        "generator": "scripts/robot_envpool_compare.py",
        "envpool": envpool.__version__,
        "numpy": np.__version__,
        "num_envs": args.num_envs,
        "threads": args.threads,
        "runs": args.runs,
        "steps": args.steps,
        "cpus": os.cpu_count(),
        "load_before": [round(x, 2) for x in load_before],
        "load_after": [round(x, 2) for x in load_after],
    }
    lines = [
        f"| robot | envpool ×{args.num_envs} steps/s (median) | carl-spec ×{args.num_envs} steps/s (median) "
        "| carl-spec / envpool |",
        "|---|---|---|---|",
    ]
    for robot, r in results.items():
        lines.append(f"| {robot} | {r['median']['envpool']:.0f} | {r['median']['carl']:.0f} | {r['ratio']:.2f} |")
    lines.append("")
    lines.append(
        f"{args.runs} interleaved runs of {args.steps} environment steps per side on {args.threads} threads; "
        f"load average before {meta['load_before'][0]:.1f}, after {meta['load_after'][0]:.1f} on {meta['cpus']} CPUs."
    )
    md = "\n".join(lines) + "\n"
    write_report(args, meta, results, md)


if __name__ == "__main__":
    main()
