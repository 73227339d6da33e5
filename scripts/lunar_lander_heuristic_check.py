#!/usr/bin/env python3
"""Gymnasium reference for the Rust lander's behaviour: landing / crash rates of Gymnasium's own
`heuristic` controller on LunarLander-v3 under each test planet's gravity.

Usage (Gymnasium in a venv of its own, `.venv-*` is gitignored):
    python3 -m venv .venv-peers && .venv-peers/bin/pip install swig \
        && .venv-peers/bin/pip install "gymnasium[box2d]==1.4.*"
    .venv-peers/bin/python scripts/lunar_lander_heuristic_check.py --episodes 50 \
        --out crates/carl-spec/tests/integration/fixtures/lunar_lander_heuristic_gymnasium.json

Gymnasium's constructor refuses gravity outside (-12, 0); like CARL we set the attribute the
world is built from at reset (`env.unwrapped.gravity`) after construction. Seeds are 0..N-1.
"""
import argparse
import json
import math

import gymnasium as gym
from gymnasium.envs.box2d.lunar_lander import heuristic

PLANETS = {
    "Jupiter": -23.143693999999996,
    "Neptune": -10.983448000000001,
    "Earth": -9.80665,
    "Mars": -3.6971070499999996,
    "Moon": -1.6279039,
    "Pluto": -0.6962721499999999,
}


def run(gravity, episodes, crash_penalty=100.0):
    env = gym.make("LunarLander-v3")
    env.unwrapped.gravity = gravity
    counts = {"landed": 0, "crashed": 0, "out_of_view": 0, "timeout": 0}
    returns, lengths = [], []
    for seed in range(episodes):
        s, _ = env.reset(seed=seed)
        total, steps = 0.0, 0
        while True:
            a = heuristic(env, s)
            s, r, term, trunc, _ = env.step(a)
            steps += 1
            u = env.unwrapped
            if term and u.game_over:
                r = -crash_penalty
            total += r
            if term or trunc:
                if term and not u.lander.awake:
                    counts["landed"] += 1
                elif term and u.game_over:
                    counts["crashed"] += 1
                elif term:
                    counts["out_of_view"] += 1
                else:
                    counts["timeout"] += 1
                break
        returns.append(total)
        lengths.append(steps)
    env.close()
    n = len(returns)
    mean = sum(returns) / n
    std = math.sqrt(sum((x - mean) ** 2 for x in returns) / n)
    return {
        "gravity_y": gravity,
        "episodes": n,
        **{f"{k}_rate": v / n for k, v in counts.items()},
        "mean_return": mean,
        "std_return": std,
        "mean_length": sum(lengths) / n,
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--episodes", type=int, default=50)
    ap.add_argument("--out")
    args = ap.parse_args()
    results = {}
    for name, g in PLANETS.items():
        results[name] = run(g, args.episodes)
        r = results[name]
        print(f"{name:8s} g={g:9.4f} landed={r['landed_rate']:.2f} crashed={r['crashed_rate']:.2f} "
              f"out={r['out_of_view_rate']:.2f} timeout={r['timeout_rate']:.2f} "
              f"return={r['mean_return']:8.1f}±{r['std_return']:.1f} len={r['mean_length']:.0f}")
    doc = {
        "source": "gymnasium " + gym.__version__ + " LunarLander-v3 (Box2D), gymnasium.envs.box2d.lunar_lander.heuristic",
        "seeds": f"0..{args.episodes - 1}",
        "note": "landed = terminated while the lander is not awake; crashed = game_over; timeout = 1000 steps",
        "planets": results,
    }
    if args.out:
        with open(args.out, "w") as f:
            json.dump(doc, f, indent=2)
            f.write("\n")


if __name__ == "__main__":
    main()
