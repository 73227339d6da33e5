#!/usr/bin/env python3
"""Box2D's touchdowns, for comparing the rapier lander's contact dynamics with Gymnasium's on the
*same* states: Gymnasium's heuristic flies each seed on LunarLander-v3 (Box2D) with a planet's
gravity; the full physical state `LEAD` steps before the first leg contact (terrain, lander and
legs, shaping) is written in the layout of carl-spec's `LunarLander::state()`, together with the
episode's outcome in Box2D and the touchdown's measurements (speed at first leg contact, the largest
leg joint deflection past its rest angle).

Usage (Gymnasium 1.4 with box2d in a venv of its own, `.venv-*` is gitignored):
    .venv-peers/bin/python scripts/lunar_lander_touchdown_box2d.py --episodes 50 \
        --out crates/carl-spec/tests/integration/fixtures/lunar_lander_touchdowns_box2d.json

`crates/carl-spec/tests/integration/lunar_lander.rs` loads every recorded state into carl-spec's lander, lets the same heuristic
finish the episode and compares outcomes seed by seed (the flight before touchdown is taken out of
the comparison, the terrain is Gymnasium's own).
"""
import argparse
import json

import gymnasium as gym
from gymnasium.envs.box2d.lunar_lander import heuristic

from lunar_lander_heuristic_check import PLANETS

LEAD = 10


def body_state(b):
    # carl-spec: body origin (x, y), angle, COM velocity (vx, vy), angular velocity.
    return [b.position[0], b.position[1], b.angle, b.linearVelocity[0], b.linearVelocity[1], b.angularVelocity]


def snapshot(u):
    terrain = [p[0][1] for p in u.sky_polys] + [u.sky_polys[-1][1][1]]
    s = list(terrain)
    for b in [u.lander] + u.legs:
        s += body_state(b)
    s += [float(u.legs[0].ground_contact), float(u.legs[1].ground_contact), float(u.game_over), 0.0]
    s += [0.0, 0.0] if u.prev_shaping is None else [1.0, float(u.prev_shaping)]
    return s


def outcome(u, term):
    if term and not u.lander.awake:
        return "landed"
    if term and u.game_over:
        return "crashed"
    if term:
        return "out_of_view"
    return "timeout"


def run(gravity, seed):
    env = gym.make("LunarLander-v3")
    env.unwrapped.gravity = gravity
    s, _ = env.reset(seed=seed)
    u = env.unwrapped
    history = [snapshot(u)]
    touchdown = None
    max_deflection = 0.0
    steps = 0
    while True:
        s, r, term, trunc, _ = env.step(heuristic(env, s))
        steps += 1
        history.append(snapshot(u))
        if touchdown is None and (s[6] or s[7]):
            touchdown = {"step": steps, "vx": float(u.lander.linearVelocity[0]),
                         "vy": float(u.lander.linearVelocity[1]), "angle": float(u.lander.angle)}
        if touchdown is not None:
            for leg, sign in zip(u.legs, (1.0, -1.0)):
                max_deflection = max(max_deflection, sign * leg.joint.angle - 0.4)
        if term or trunc:
            break
    env.close()
    out = {"seed": seed, "outcome": outcome(u, term), "steps": steps}
    if touchdown is not None and touchdown["step"] > LEAD:
        out["state"] = history[touchdown["step"] - LEAD]
        out["state_step"] = touchdown["step"] - LEAD
        out["touchdown"] = touchdown
        out["max_leg_deflection"] = max_deflection
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--episodes", type=int, default=50)
    ap.add_argument("--planets", default=",".join(PLANETS))
    ap.add_argument("--out")
    args = ap.parse_args()
    doc = {
        "source": "gymnasium " + gym.__version__ + " LunarLander-v3 (Box2D), gymnasium.envs.box2d.lunar_lander.heuristic",
        "generator": "scripts/lunar_lander_touchdown_box2d.py",
        "lead_steps": LEAD,
        "state_layout": "carl-spec LunarLander::state(): 11 terrain heights; lander, leg 0, leg 1 as "
        "(x, y, angle, vx, vy, w); leg contacts; game over; rest time; has-previous-shaping; previous shaping",
        "planets": {},
    }
    for name in args.planets.split(","):
        g = PLANETS[name]
        runs = [run(g, seed) for seed in range(args.episodes)]
        doc["planets"][name] = {"gravity_y": g, "runs": runs}
        counts = {}
        for r in runs:
            counts[r["outcome"]] = counts.get(r["outcome"], 0) + 1
        td = [r["touchdown"]["vy"] for r in runs if "touchdown" in r]
        print(f"{name:8s} {counts} touchdown vy mean {sum(td) / max(len(td), 1):.2f} "
              f"max deflection {max([r.get('max_leg_deflection', 0) for r in runs]):.3f}")
    if args.out:
        with open(args.out, "w") as f:
            json.dump(doc, f)
            f.write("\n")


if __name__ == "__main__":
    main()
