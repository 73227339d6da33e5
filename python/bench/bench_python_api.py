#!/usr/bin/env python3
"""Steps per second through the Python API, each beside its anchor in the same run.

    python python/bench/bench_python_api.py [--seconds S]

Prints one JSON line per workload. Anchors: Gymnasium's NumPy CartPoleVectorEnv and Gymnasium's
CartPole through gymnasium.make. (envpool is not installed here; the Rust VecEnv anchor is
`carl-spec bench ENV`.)
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from typing import Any, Callable

import numpy as np


def rate(step: Callable[[], None], steps_per_call: int, seconds: float) -> float:
    """Best of 3 runs of ~`seconds` each, in environment steps per second."""
    best = 0.0
    for _ in range(3):
        n, t0 = 0, time.perf_counter()
        while (t := time.perf_counter() - t0) < seconds:
            for _ in range(50):
                step()
            n += 50
        best = max(best, n * steps_per_call / t)
    return best


def vec_cartpole(seconds: float) -> dict[str, Any]:
    import carl_spec as cs
    from gymnasium.envs.classic_control.cartpole import CartPoleVectorEnv

    n = 1024
    ours = cs.make_vec("cartpole", n, autoreset_mode="same_step", threads=1)
    ours.reset(seed=0)
    ref = CartPoleVectorEnv(num_envs=n)
    ref.reset(seed=0)
    rng = np.random.default_rng(0)
    acts = [rng.integers(0, 2, size=n) for _ in range(64)]
    i = [0]

    def step_ours() -> None:
        i[0] = (i[0] + 1) & 63
        ours.step(acts[i[0]])

    def step_ref() -> None:
        i[0] = (i[0] + 1) & 63
        ref.step(acts[i[0]])

    ours_next = cs.make_vec("cartpole", n, autoreset_mode="next_step", threads=1)
    ours_next.reset(seed=0)

    def step_next() -> None:
        i[0] = (i[0] + 1) & 63
        ours_next.step(acts[i[0]])

    a, b, c = rate(step_ours, n, seconds), rate(step_ref, n, seconds), rate(step_next, n, seconds)
    return {"workload": "make_vec cartpole x1024, 1 thread", "carl_spec_same_step": a, "carl_spec_next_step": c,
            "gymnasium_CartPoleVectorEnv": b, "ratio_same_step": a / b}


def single_cartpole(seconds: float) -> dict[str, Any]:
    import gymnasium
    import carl_spec  # noqa: F401  (registers carl_spec/*)

    out: dict[str, Any] = {"workload": "gymnasium.make cartpole, 1 env"}
    for name, gid in [("carl_spec", "carl_spec/cartpole-v0"), ("gymnasium", "CartPole-v1")]:
        env = gymnasium.make(gid)
        env.reset(seed=0)
        state = {"done": False}

        def step() -> None:
            _, _, t, u, _ = env.step(1 if np.random.random() < 0.5 else 0)
            if t or u:
                env.reset()

        out[name] = rate(step, 1, seconds)
    out["ratio"] = out["carl_spec"] / out["gymnasium"]
    return out


def vec_physics(env_id: str, n: int, threads: int, seconds: float) -> dict[str, Any]:
    import carl_spec as cs

    venv = cs.make_vec(env_id, n, autoreset_mode="same_step", threads=threads)
    venv.reset(seed=0)
    venv.action_space.seed(0)
    acts = [venv.action_space.sample() for _ in range(16)]
    i = [0]

    def step() -> None:
        i[0] = (i[0] + 1) & 15
        venv.step(acts[i[0]])

    return {"workload": f"make_vec {env_id} x{n}, {threads} threads", "carl_spec": rate(step, n, seconds)}


def import_and_make() -> dict[str, Any]:
    code = "import time; t=time.perf_counter(); import carl_spec as cs; cs.make('cartpole'); print(time.perf_counter()-t)"
    times = [float(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout) for _ in range(5)]
    return {"workload": "import carl_spec; cs.make('cartpole')", "seconds_median": sorted(times)[2], "seconds_all": times}


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("--seconds", type=float, default=1.0)
    args = p.parse_args()
    for row in [
        import_and_make(),
        vec_cartpole(args.seconds),
        single_cartpole(args.seconds),
        vec_physics("lunar_lander", 64, 2, args.seconds),
        vec_physics("bipedal_walker", 64, 2, args.seconds),
    ]:
        print(json.dumps(row), flush=True)


if __name__ == "__main__":
    main()
