#!/usr/bin/env python3
"""64 LunarLanders on 2 threads: carl-spec's VecEnv (`carl-spec bench`) beside envpool's, in one run.

    .venv-peers/bin/python scripts/bench_lunar_lander_envpool.py \
        --carl-spec target/release/carl-spec [--rounds 5] [--seconds 2]

Both step 64 discrete LunarLanders with uniformly random actions and automatic resets on 2
threads. The two are measured alternately, `--rounds` times each, so that the load of a shared
machine hits both alike; the script prints every sample, the medians and their ratio as JSON lines.
Needs envpool (tested with envpool 1.2.5).
"""
import argparse
import json
import statistics
import subprocess
import time

import envpool
import numpy as np


def envpool_rate(num_envs, threads, seconds):
    env = envpool.make("LunarLander-v3", env_type="gymnasium", num_envs=num_envs, num_threads=threads,
                       batch_size=num_envs, seed=0)
    env.reset()
    rng = np.random.default_rng(0)
    actions = [rng.integers(0, 4, size=num_envs) for _ in range(256)]
    for k in range(50):  # warm-up
        env.step(actions[k % 256])
    n, t0 = 0, time.perf_counter()
    while (t := time.perf_counter() - t0) < seconds:
        for _ in range(20):
            env.step(actions[n % 256])
            n += 1
    env.close()
    return n * num_envs / t


def carl_spec_rate(binary, num_envs, threads, steps):
    out = subprocess.run([binary, "bench", "lunar_lander", "--num-envs", str(num_envs), "--threads", str(threads),
                          "--steps", str(steps)], check=True, capture_output=True, text=True).stdout
    return json.loads(out)["vec_steps_per_sec"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--carl-spec", default="target/release/carl-spec")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--seconds", type=float, default=2.0)
    ap.add_argument("--num-envs", type=int, default=64)
    ap.add_argument("--threads", type=int, default=2)
    args = ap.parse_args()
    ours, theirs = [], []
    for r in range(args.rounds):
        theirs.append(envpool_rate(args.num_envs, args.threads, args.seconds))
        # About the same wall time as envpool's sample.
        steps = int(max(theirs[-1], 50_000) * args.seconds * 2)
        ours.append(carl_spec_rate(args.carl_spec, args.num_envs, args.threads, steps))
        print(json.dumps({"round": r, "envpool": round(theirs[-1]), "carl_spec": round(ours[-1]),
                          "ratio": round(ours[-1] / theirs[-1], 2)}), flush=True)
    mo, mt = statistics.median(ours), statistics.median(theirs)
    print(json.dumps({"workload": f"LunarLander-v3 x{args.num_envs}, {args.threads} threads, random actions",
                      "envpool_version": envpool.__version__, "rounds": args.rounds,
                      "carl_spec_median": round(mo), "envpool_median": round(mt),
                      "ratio_of_medians": round(mo / mt, 2),
                      "median_of_ratios": round(statistics.median(o / t for o, t in zip(ours, theirs)), 2)}))


if __name__ == "__main__":
    main()
