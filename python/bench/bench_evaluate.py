#!/usr/bin/env python3
"""`carl_spec.evaluate` against a hand-written `make_vec` loop on the same batch, in the same run.

    python python/bench/bench_evaluate.py [--rounds R] [--only NAME ...]

Each workload runs a trivial policy (a constant action) on one batch configuration (environment,
context source, num_envs). Per round, both sides run one after the other (the order alternates
between rounds, so both see the same machine load):

* `make_vec`: `cs.make_vec(...)` with the same source and num_envs, default autoreset, stepping
  `policy(obs)` for as many batch steps as evaluate needed;
* `evaluate`: `cs.evaluate(policy, ...)` end to end (make_vec construction, resets with each
  episode's seed, the bookkeeping, the result).

Rates are environment steps per second: batch steps x num_envs / time, batch steps counted as
calls of the policy (one per batch step on both sides), time the CPU time of this process
(`time.process_time`: both sides run on one thread, and a machine shared with other jobs slows
wall time far more than CPU time; `--wall` times wall-clock time instead). `useful` counts only the steps of
recorded episodes (evaluate's batch keeps stepping finished environments while the last episodes
run). Printed: one JSON line per workload with the median of each side, `ratio` =
evaluate / make_vec (the goal is >= 0.9) and `useful_ratio`.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import time
from typing import Any, Callable

import numpy as np

import carl_spec as cs


def constant(n_actions_shape: tuple[int, ...], dtype: Any) -> Callable[[np.ndarray], np.ndarray]:
    cache: dict[int, np.ndarray] = {}

    def policy(obs: np.ndarray) -> np.ndarray:
        n = len(obs)
        a = cache.get(n)
        if a is None:
            a = cache[n] = np.zeros((n, *n_actions_shape), dtype=dtype)
        return a

    return policy


WORKLOADS: dict[str, dict[str, Any]] = {
    # Landing in Space's test planets: 6 instances, 100 episodes each, 16 environments.
    "lunar_lander_planets": dict(
        env="lunar_lander", make=dict(instances="lunar_lander/landing_in_space_test_planets"),
        evaluate=dict(instances="lunar_lander/landing_in_space_test_planets", episodes=100),
        num_envs=16, action=((), np.int64),
    ),
    # Pendulum's Q1 set for g: 100 instances, 20 episodes each (200 steps), 64 environments.
    "pendulum_q1_g": dict(
        env="pendulum", make=dict(instances="pendulum/q1_g_sigma_0_5"),
        evaluate=dict(instances="pendulum/q1_g_sigma_0_5", episodes=20),
        num_envs=64, action=((1,), np.float32),
    ),
    # CartPole at its default context: the cheapest batch step there is (a structure-of-arrays
    # kernel, microseconds per batch) and episodes of ~10 steps: evaluate's per-episode reset is
    # most visible here.
    "cartpole_default": dict(
        env="cartpole", make=dict(), evaluate=dict(context={}, episodes=3000),
        num_envs=64, action=((), np.int64),
    ),
}


def run(name: str, w: dict[str, Any], rounds: int, clock: Callable[[], float]) -> dict[str, Any]:
    shape, dtype = w["action"]
    n = w["num_envs"]
    rates: dict[str, list[float]] = {"make_vec": [], "evaluate": [], "useful": []}
    for r in range(rounds):
        calls = [0]
        base = constant(shape, dtype)

        def counted(obs: np.ndarray) -> np.ndarray:
            calls[0] += 1
            return base(obs)

        def side_evaluate() -> int:
            calls[0] = 0
            t0 = clock()
            res = cs.evaluate(counted, w["env"], seed=r, num_envs=n, **w["evaluate"])
            dt = clock() - t0
            rates["evaluate"].append(calls[0] * n / dt)
            rates["useful"].append(sum(e.length for e in res.episodes) / dt)
            return calls[0]

        def side_make_vec(steps: int) -> None:
            t0 = clock()
            venv = cs.make_vec(w["env"], n, **w["make"])
            obs, _ = venv.reset(seed=r)
            step = venv.step
            for _ in range(steps):
                obs = step(counted(obs))[0]
            venv.close()
            rates["make_vec"].append(steps * n / (clock() - t0))

        if r % 2 == 0:
            steps = side_evaluate()
            side_make_vec(steps)
        else:
            side_make_vec(steps)  # noqa: F821 - set by round 0
            side_evaluate()
    med = {k: statistics.median(v) for k, v in rates.items()}
    return {
        "workload": name,
        "num_envs": n,
        "batch_steps": steps,
        "make_vec_steps_per_s": round(med["make_vec"]),
        "evaluate_steps_per_s": round(med["evaluate"]),
        "ratio": round(med["evaluate"] / med["make_vec"], 3),
        "useful_ratio": round(med["useful"] / med["make_vec"], 3),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--only", nargs="*", choices=sorted(WORKLOADS))
    ap.add_argument("--wall", action="store_true", help="time wall-clock time instead of this process's CPU time")
    args = ap.parse_args()
    clock = time.perf_counter if args.wall else time.process_time
    for name in args.only or WORKLOADS:
        out = run(name, WORKLOADS[name], args.rounds, clock)
        out["clock"] = "wall" if args.wall else "cpu"
        out["loadavg_1min"] = round(os.getloadavg()[0], 2)
        print(json.dumps(out), flush=True)


if __name__ == "__main__":
    main()
