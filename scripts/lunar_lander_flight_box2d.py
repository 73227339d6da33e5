#!/usr/bin/env python3
"""Box2D's lander in flight, for checking carl-spec's closed-form flight step by step: Gymnasium's
heuristic flies LunarLander-v3 (Box2D) for each planet and seed; every step's action and the
lander's state after it (origin x, y, angle, COM velocity, angular velocity) and the legs' angles
relative to the lander are recorded until the first leg contact or `--steps` steps.

Usage (Gymnasium 1.4 with box2d in a venv of its own, `.venv-*` is gitignored):
    .venv-peers/bin/python scripts/lunar_lander_flight_box2d.py \
        --out crates/carl-spec/tests/integration/fixtures/lunar_lander_flight_box2d.json

`crates/carl-spec/tests/integration/lunar_lander.rs` replays the same actions from the same seeds (the same terrain, push and
engine dispersion: NumPy's generator in Gymnasium's order) and compares every step.
"""
import argparse
import json

import gymnasium as gym
from gymnasium.envs.box2d.lunar_lander import heuristic

from lunar_lander_heuristic_check import PLANETS

EVERY = 5


def fly(gravity, seed, steps):
    env = gym.make("LunarLander-v3")
    env.unwrapped.gravity = gravity
    s, _ = env.reset(seed=seed)
    u = env.unwrapped
    actions, states = [], []
    for _ in range(steps):
        a = int(heuristic(u, s))
        s, _, term, _, _ = env.step(a)
        if term or u.legs[0].ground_contact or u.legs[1].ground_contact:
            break
        L = u.lander
        actions.append(a)
        states.append([len(actions)] + [float(f"{v:.7g}") for v in [L.position[0], L.position[1], L.angle, L.linearVelocity[0],
                                                   L.linearVelocity[1], L.angularVelocity,
                                                   u.legs[0].angle - L.angle, u.legs[1].angle - L.angle]])
    env.close()
    # Every `EVERY`-th step and the last one (keeps the fixture small).
    states = [st for st in states if st[0] % EVERY == 0 or st[0] == len(actions)]
    return {"seed": seed, "actions": actions, "states": states}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--out")
    args = ap.parse_args()
    doc = {
        "source": "gymnasium " + gym.__version__ + " LunarLander-v3 (Box2D), gymnasium.envs.box2d.lunar_lander.heuristic",
        "state": "[step count, then after that step: lander origin x, y, angle, COM vx, vy, angular velocity, leg 0 and leg 1 angle relative to the lander], every 5th step and the last",
        "planets": {name: {"gravity_y": g, "runs": [fly(g, seed, args.steps) for seed in range(args.seeds)]}
                    for name, g in PLANETS.items()},
    }
    text = json.dumps(doc, separators=(",", ":"))
    if args.out:
        with open(args.out, "w") as f:
            f.write(text + "\n")
    for name, p in doc["planets"].items():
        print(name, [len(r["actions"]) for r in p["runs"]])


if __name__ == "__main__":
    main()
