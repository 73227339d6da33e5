#!/usr/bin/env python3
"""Record Gymnasium 1.4's BipedalWalker (Box2D) under its scripted gait, step by step, for
`examples/bipedal_walker_replay.rs`: per step the state before and after (hull origin x, y,
angle, centre-of-mass velocity, angular velocity; joint angles and speeds; the two lower-leg
contact flags; every body's state), the action, and the course (terrain_x, terrain_y).

Protocol as `bipedal_walker_gait_check.py` (Gymnasium's `__main__`: reset, zero action, then
`BipedalWalkerHeuristics`).

    .venv-peers/bin/python scripts/bipedal_walker_record_box2d.py --seed 0 --steps 400 > rec.json
"""
import argparse
import json

import numpy as np


def snapshot(u):
    bodies = [u.hull] + list(u.legs)
    b = u.hull
    return {
        "hull": [b.position.x, b.position.y, b.angle, b.linearVelocity.x, b.linearVelocity.y, b.angularVelocity],
        "q": [j.angle for j in u.joints],
        "dq": [j.speed for j in u.joints],
        "contact": [float(u.legs[1].ground_contact), float(u.legs[3].ground_contact)],
        "bodies": [[x.position.x, x.position.y, x.angle, x.linearVelocity.x, x.linearVelocity.y, x.angularVelocity]
                   for x in bodies],
    }


def main():
    import gymnasium as gym
    from gymnasium.envs.box2d.bipedal_walker import BipedalWalkerHeuristics

    ap = argparse.ArgumentParser()
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--steps", type=int, default=400)
    args = ap.parse_args()
    env = gym.make("BipedalWalker-v3")
    u = env.unwrapped
    env.reset(seed=args.seed)
    h = BipedalWalkerHeuristics()
    a = np.zeros(4)
    rows = []
    for t in range(args.steps):
        before = snapshot(u)
        s, r, term, trunc, _ = env.step(a)
        rows.append({"t": t, "before": before, "action": [float(x) for x in a], "reward": float(r),
                     "after": snapshot(u), "terminated": bool(term)})
        if term or trunc:
            break
        a = h.step_heuristic(s)
    print(json.dumps({"source": f"gymnasium {gym.__version__} BipedalWalker-v3, seed {args.seed}",
                      "terrain_x": [float(x) for x in u.terrain_x],
                      "terrain_y": [float(y) for y in u.terrain_y], "steps": rows}))


if __name__ == "__main__":
    main()
