#!/usr/bin/env python3
"""Gymnasium's scripted BipedalWalker gait (`BipedalWalkerHeuristics`) on Gymnasium 1.4 (Box2D)
and on carl-spec's `bipedal_walker`, seed by seed, driven by the very same Python controller.

Protocol (Gymnasium's own `__main__` loop in `gymnasium/envs/box2d/bipedal_walker.py`): reset,
then step with `[0, 0, 0, 0]`, and from then on step with `step_heuristic(obs)`; a fresh
`BipedalWalkerHeuristics()` per episode; at most 1600 steps (BipedalWalker-v3's time limit, the
registry's `max_episode_steps` in carl-spec). carl-spec runs through
`carl-spec rollout bipedal_walker --seed S --actions -` (one JSON action per line on stdin, one JSON
line per step on stdout), so the Rust environment is driven exactly as a Python agent drives it.
Seeds do not give the same course in both (each library has its own random streams).

Per episode: return, length, and the hull's final x on the course (start 4.67 m, finish line
88.67 m). Gymnasium's x is read from the hull; carl-spec's is rebuilt from the rewards (each
non-final reward is `Δ(130·x/SCALE − 5·|angle|)` minus the torque cost, and the angle is
observation 0), the final step adding `vx·dt` (the final reward is −100 on a fall).

Usage (Gymnasium in a venv of its own, `.venv-*` is gitignored; carl-spec built):
    python3 -m venv .venv-peers && .venv-peers/bin/pip install swig \
        && .venv-peers/bin/pip install "gymnasium[box2d]==1.4.*"
    cargo build --release
    .venv-peers/bin/python scripts/bipedal_walker_gait_check.py --seeds 30 \
        --carl-spec target/release/carl-spec --out bipedal_walker_gait.json --markdown
"""
import argparse
import json
import math
import subprocess

import numpy as np

SCALE = 30.0
FPS = 50.0
VIEWPORT_W = 600.0
MOTORS_TORQUE = 80.0
INIT_X = 14.0 / 30.0 * 20 / 2  # TERRAIN_STEP · TERRAIN_STARTPAD / 2
MAX_STEPS = 1600


def heuristics():
    from gymnasium.envs.box2d.bipedal_walker import BipedalWalkerHeuristics

    return BipedalWalkerHeuristics()


def run_gymnasium(seed):
    import gymnasium as gym

    env = gym.make("BipedalWalker-v3")
    env.reset(seed=seed)
    h = heuristics()
    a = np.zeros(4)
    total, steps = 0.0, 0
    while True:
        s, r, term, trunc, _ = env.step(a)
        total += r
        steps += 1
        if term or trunc:
            break
        a = h.step_heuristic(s)
    x = float(env.unwrapped.hull.position.x)
    fell = bool(env.unwrapped.game_over)
    env.close()
    return {"return": total, "length": steps, "x": x, "fell": fell}


def run_carl_spec(exe, seed, options=()):
    extra = [arg for opt in options for arg in ("--option", opt)]
    proc = subprocess.Popen(
        [exe, "rollout", "bipedal_walker", "--seed", str(seed), "--actions", "-", *extra],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
        bufsize=1,
    )
    first = json.loads(proc.stdout.readline())
    obs = first["reset"]["obs"]
    shaping = 130.0 * INIT_X / SCALE - 5.0 * abs(obs[0])
    x = INIT_X
    h = heuristics()
    a = np.zeros(4)
    total, steps, fell = 0.0, 0, False
    while True:
        proc.stdin.write(json.dumps([float(v) for v in a]) + "\n")
        proc.stdin.flush()
        line = json.loads(proc.stdout.readline())
        s, r = np.array(line["obs"], dtype=np.float32), line["reward"]
        total += r
        steps += 1
        if line["terminated"] and r == -100.0:
            fell = True
            x += s[2] / (0.3 * (VIEWPORT_W / SCALE) / FPS) / FPS
        else:
            cost = sum(0.00035 * MOTORS_TORQUE * min(abs(float(v)), 1.0) for v in a)
            new_shaping = shaping + r + cost
            x = (new_shaping + 5.0 * abs(float(s[0]))) * SCALE / 130.0
            shaping = new_shaping
        if line["terminated"] or line["truncated"]:
            break
        a = h.step_heuristic(s)
    proc.stdin.close()
    proc.wait()
    return {"return": total, "length": steps, "x": float(x), "fell": fell}


def summary(rows):
    n = len(rows)
    rets = [r["return"] for r in rows]
    mean = sum(rets) / n
    return {
        "episodes": n,
        "mean_return": mean,
        "std_return": math.sqrt(sum((v - mean) ** 2 for v in rets) / n),
        "median_return": float(np.median(rets)),
        "positive_return_share": sum(v > 0 for v in rets) / n,
        "past_40m_share": sum(r["x"] > 40.0 for r in rows) / n,
        "fell_share": sum(r["fell"] for r in rows) / n,
        "mean_length": sum(r["length"] for r in rows) / n,
    }


def markdown(gym_rows, carl_rows, gs, cs):
    out = ["| seed | Gymnasium x (m) | return | length | carl-spec x (m) | return | length |",
           "|---:|---:|---:|---:|---:|---:|---:|"]
    for i, (g, c) in enumerate(zip(gym_rows, carl_rows)):
        out.append(f"| {i} | {g['x']:.1f} | {g['return']:.1f} | {g['length']} "
                   f"| {c['x']:.1f} | {c['return']:.1f} | {c['length']} |")
    out.append("")
    out.append("| | Gymnasium 1.4 (Box2D) | carl-spec |")
    out.append("|---|---:|---:|")
    for key, label, fmt in [
        ("mean_return", "mean return", "{:.1f}"),
        ("median_return", "median return", "{:.1f}"),
        ("positive_return_share", "positive return", "{:.0%}"),
        ("past_40m_share", "past x = 40 m", "{:.0%}"),
        ("fell_share", "fell", "{:.0%}"),
        ("mean_length", "mean length (steps)", "{:.0f}"),
    ]:
        out.append(f"| {label} | {fmt.format(gs[key])} | {fmt.format(cs[key])} |")
    return "\n".join(out)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", type=int, default=30)
    ap.add_argument("--carl-spec", default="target/release/carl-spec")
    ap.add_argument("--out")
    ap.add_argument("--markdown", action="store_true")
    ap.add_argument("--option", action="append", default=[], metavar="NAME=VALUE",
                    help="carl-spec environment option (repeatable; applied to the carl-spec side only)")
    args = ap.parse_args()
    import gymnasium as gym

    gym_rows = [run_gymnasium(s) for s in range(args.seeds)]
    carl_rows = [run_carl_spec(args.carl_spec, s, args.option) for s in range(args.seeds)]
    gs, cs = summary(gym_rows), summary(carl_rows)
    doc = {
        "source": f"gymnasium {gym.__version__} BipedalWalker-v3 (Box2D) vs carl-spec rollout bipedal_walker "
                  f"{' '.join('--option ' + o for o in args.option)}; "
                  "controller gymnasium.envs.box2d.bipedal_walker.BipedalWalkerHeuristics, first action zeros",
        "seeds": f"0..{args.seeds - 1}",
        "gymnasium": {"summary": gs, "episodes": gym_rows},
        "carl_spec": {"summary": cs, "episodes": carl_rows},
    }
    if args.out:
        with open(args.out, "w") as f:
            json.dump(doc, f, indent=2)
            f.write("\n")
    if args.markdown:
        print(markdown(gym_rows, carl_rows, gs, cs))
    else:
        print(json.dumps({"gymnasium": gs, "carl_spec": cs}, indent=2))


if __name__ == "__main__":
    main()
