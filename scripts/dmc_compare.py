#!/usr/bin/env python3
"""Compare carl-spec's dm_control family with dm_control 1.0.50, at each environment's `dm_control` instance set.

Both sides are driven the same way and measured from their observations (dm_control's flat
observation layout is carl-spec's): dm_control's suite task (`suite.load(domain, task)`, MuJoCo)
and `carl-spec rollout <env> --instance-set <env>/dm_control --actions -` (JSON Lines).

Metrics (dmc_walker): fall_height_<t>, fall_torso_zz_<t>: the torso's height and the xz entry of
its rotation (the sine of its pitch) <t> s after standing straight at rest (every joint at 0) under
zero action; medium_fall_height_1s: the same in the medium below; random_return as below.

Metrics (dmc_fish): coast_speed_<t>, coast_yaw_rate_<t>: the fish's forward speed and yaw rate <t> s
after a push (level, joints at 0, 0.4 m/s forward, 3 rad/s yaw) under zero action, slowed by the
medium alone; gravity_sink_speed_<t>: its sinking speed with gravity on (dm_control's disable flag
cleared, 9.81 down; carl-spec's gravity 9.81); <servo>_angle_<t>: a joint's angle under a constant
control (tail1 under tail 1, finright_roll under fins_flap 1, finleft_pitch under 0.6);
tail_yaw_rate_1s: the yaw rate the beating tail gives; random_return as below.

Metrics (dmc_finger, task spin): from the finger hanging at rest (proximal at its ref −90°, distal
at 0), under zero action the spinner started at 10 rad/s coasts down (damping 0.03 and frictionloss
0.1): coast_speed_<t> (its hinge rate, rad/s) and coast_turned_<t> (the angle it has turned, rad,
from the tip's unwrapped position), coast_stop_time (s, the first time |rate| < 0.05 rad/s); under
the constant action (1, 0.5) from rest the finger swings into the spinner and turns it:
push_proximal_<t> (rad), push_touch_<t> (the sum of the two touch observations) and push_turned_<t>;
random_return as below.

Metrics (dmc_quadruped), from the observation (hinges 0-15, their rates 16-31, activations 32-43,
torso velocity 44-46, torso zz 47, accelerometer 48-50, gyro 51-53, arcsinh of the toes' forces 54-65):
* drop_*: dropped at rest from dm_control's reset pose of seed 0 (its orientation and
  non-contacting height, joints at 0) under zero action: the torso's zz at 0.5 s and 3 s
  (final upright), the time to rest (the first time the hinges' rates and the torso's speed all
  stay below 0.05 to the end of the 3 s) and the toes' total force at rest (N, the part of the
  weight the toes carry);
* servo_*: from standing (identity orientation at the non-contacting height) under one constant
  action (lift 0.5, extend 0.3, yaw 0 on every leg): the front left knee's angle and the torso's
  zz after 1 s;
* random_return as below (dm_control's reset on both sides).

Metrics (dmc_point_mass):
* push_<axis>_<t>s: the ball's displacement <t> s after a constant control from rest at the
  centre (the passive response of the damped slides to one motor: terminal speed gear / damping);
* medium_push_x_1s: the same 1 s push in a medium (viscosity 2 Pa*s, wind 0.05 m/s along x, density
  1000 kg/m^3), MuJoCo's inertia-box fluid model on both sides;
* random_return: episode return under uniform random actions (dm_control's reset, carl-spec's
  `random_start` option), mean and standard deviation over `--episodes` seeds, and the two-sided
  p-value of a Mann-Whitney U test against dm_control's episodes.
Deterministic metrics pass within +-15 % of dm_control, random returns at p >= 0.05.

`--speed` also times single-environment steps per second: dm_control's `env.step` (its control
step) with uniform random actions against `carl-spec bench <env> --num-envs 1 --threads 1`,
interleaved over `--runs` rounds (compare ratios: the machine may be shared).

Usage (from the repository root, with dm_control 1.0.50 installed, which needs mujoco < 4):
    python3 scripts/dmc_compare.py --carl-spec target/release/carl-spec --episodes 30 --speed \\
        --json dmc_compare.json --markdown dmc_compare.md
`--carl-only` prints carl-spec's side only (to refresh the test pins).
"""
import argparse
import json
import os
import statistics
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from robot_mujoco_compare import CarlSide, mann_whitney_p  # noqa: E402
from robot_speed_compare import carl_steps_per_sec, count, write_report  # noqa: E402

# carl-spec env -> (dm_control domain, task, carl-spec options reproducing the task's reset)
ENVS = {
    "dmc_finger": ("finger", "spin", []),
    "dmc_point_mass": ("point_mass", "easy", ["random_start=true"]),
    "dmc_walker": ("walker", "walk", []),
    "dmc_fish": ("fish", "swim", []),
    "dmc_quadruped": ("quadruped", "walk", []),
}
MEDIUM = dict(viscosity=2.0, density=1000.0, wind_x=0.05)
#: the second side's context of an environment (default MEDIUM): fish.xml disables gravity, so its
#: second side turns gravity on (dm_control's disable flag cleared, gravity 9.81 down)
SECOND = {"dmc_fish": dict(gravity=9.81)}


def instance_context(env):
    with open(f"specs/instances/{env}/dm_control.json") as f:
        return json.load(f)["instances"][0]["context"]


class DmcSide:
    """dm_control's suite task; `physics` options overridden by `medium` if given."""

    def __init__(self, domain, task, medium=None):
        from dm_control import suite

        self.domain, self.task, self.medium = domain, task, medium
        self.suite = suite

    def env(self, seed):
        env = self.suite.load(self.domain, self.task, task_kwargs={"random": seed})
        if self.medium and "gravity" in self.medium:
            import mujoco

            opt = env.physics.model.opt
            opt.disableflags &= ~int(mujoco.mjtDisableBit.mjDSBL_GRAVITY)
            opt.gravity[:] = [0.0, 0.0, -self.medium["gravity"]]
        elif self.medium:
            opt = env.physics.model.opt
            opt.viscosity = self.medium.get("viscosity", 0.0)
            opt.density = self.medium.get("density", 0.0)
            opt.wind[:] = [self.medium.get("wind_x", 0.0), 0.0, 0.0]
        return env

    def run(self, seed, actions, init=None):
        """Observations (reset first) and rewards under the action list, from the state `init`
        (carl-spec's state, dm_control's (qpos, qvel)) if given."""
        import numpy as np

        env = self.env(seed)
        ts = env.reset()
        if init is not None:
            with env.physics.reset_context():
                env.physics.data.qpos[:] = init[1][0]
                env.physics.data.qvel[:] = init[1][1]
            ts = ts._replace(observation=env.task.get_observation(env.physics))
        flat = lambda o: np.concatenate([np.ravel(v) for v in o.values()]).tolist()  # noqa: E731
        obs, rewards = [flat(ts.observation)], []
        for a in actions:
            ts = env.step(np.asarray(a, dtype=float))
            obs.append(flat(ts.observation))
            rewards.append(ts.reward)
        return obs, rewards

    def random_episode(self, seed):
        import numpy as np

        env = self.env(seed)
        spec = env.action_spec()
        rng = np.random.RandomState(seed)
        env.reset()
        total, n = 0.0, 0
        while True:
            ts = env.step(rng.uniform(spec.minimum, spec.maximum))
            total += ts.reward
            n += 1
            if ts.last():
                return n, total


def point_mass_metrics(side, medium_side, episodes):
    out = {}
    # (carl-spec's state, dm_control's (qpos, qvel)), as robot_mujoco_compare's sides take it
    rest = ([0.0, 0.0, 0.0, 0.0], ([0.0, 0.0], [0.0, 0.0]))
    for axis, ctrl in (("x", [1.0, 0.0]), ("y", [0.3, -1.0])):
        obs, _ = side.run(0, [ctrl] * 50, init=rest)
        k = 0 if axis == "x" else 1
        out[f"push_{axis}_0.2s"] = obs[10][k]
        out[f"push_{axis}_1s"] = obs[50][k]
    obs, _ = medium_side.run(0, [[1.0, 0.0]] * 50, init=rest)
    out["medium_push_x_1s"] = obs[50][0]
    returns = [side.random_episode(seed)[1] for seed in range(episodes)]
    out["random_return"] = returns
    return out


def walker_metrics(side, medium_side, episodes):
    """The passive fall from standing straight (every joint at 0, at rest, zero action): the torso's
    height and pitch; the same in a medium; random-policy returns."""
    out = {}
    rest = ([0.0] * 18, ([0.0] * 9, [0.0] * 9))
    obs, _ = side.run(0, [[0.0] * 6] * 80, init=rest)
    for k, t in ((20, "0.5s"), (40, "1s"), (80, "2s")):
        out[f"fall_height_{t}"] = obs[k][14]
        out[f"fall_torso_zz_{t}"] = obs[k][1]  # torso xz entry: sine of its pitch
    obs, _ = medium_side.run(0, [[0.0] * 6] * 40, init=rest)
    out["medium_fall_height_1s"] = obs[40][14]
    out["random_return"] = [side.random_episode(seed)[1] for seed in range(episodes)]
    return out


def fish_metrics(side, gravity_side, episodes):
    """The fish coasting in its medium from a push (level, every joint at 0, forward speed 0.4 m/s
    along its body and a yaw rate of 3 rad/s, zero action): its forward speed and yaw rate; the
    same with gravity on (sinking speed); constant-control responses of the tail and the fins;
    random-policy returns."""
    out = {}
    q = [0.0, 0.0, 0.1, 1.0, 0.0, 0.0, 0.0] + [0.0] * 7
    v = [0.0, 0.4, 0.0, 0.0, 0.0, 3.0] + [0.0] * 7
    rest = (q + v + [0.0, 0.4, 0.1], (q, v))
    obs, _ = side.run(0, [[0.0] * 5] * 25, init=rest)
    for k, t in ((5, "0.2s"), (25, "1s")):
        out[f"coast_speed_{t}"] = obs[k][12]  # qvel[1]: forward (y) speed
        out[f"coast_yaw_rate_{t}"] = obs[k][16]  # qvel[5]: angular velocity about z (body frame)
    obs, _ = gravity_side.run(0, [[0.0] * 5] * 50, init=rest)
    out["gravity_sink_speed_1s"] = -obs[25][13]
    out["gravity_sink_speed_2s"] = -obs[50][13]
    for name, ctrl, k in (("tail", [1.0, 0.0, 0.0, 0.0, 0.0], 0), ("fins_flap", [0.0, 0.0, 1.0, 0.0, 0.0], 3),
                          ("finleft_pitch", [0.0, 0.0, 0.0, 0.6, 0.0], 6)):
        obs, _ = side.run(0, [ctrl] * 25, init=rest)
        out[f"{name}_angle_0.2s"] = obs[5][k]
        out[f"{name}_angle_1s"] = obs[25][k]
    obs, _ = side.run(0, [[1.0, 0.0, 0.0, 0.0, 0.0]] * 25, init=rest)
    out["tail_yaw_rate_1s"] = obs[25][16]
    out["random_return"] = [side.random_episode(seed)[1] for seed in range(episodes)]
    return out


def finger_metrics(side, medium_side, episodes):
    """The spinner's coast-down, the finger pushing it under a constant action, random returns."""
    import math

    out = {}
    hang = [-math.pi / 2, 0.0, 0.0]

    def turned(obs):
        """The spinner's turned angle at each observation (the tip's unwrapped angle)."""
        angles, total, prev = [0.0], 0.0, math.atan2(obs[0][2], obs[0][3])
        for o in obs[1:]:
            a = math.atan2(o[2], o[3])
            d = (a - prev + math.pi) % (2 * math.pi) - math.pi
            total += d
            prev = a
            angles.append(total)
        return angles

    start = (hang + [0.0, 0.0, 10.0], (hang, [0.0, 0.0, 10.0]))
    obs, _ = side.run(0, [[0.0, 0.0]] * 150, init=start)
    ang = turned(obs)
    for k, t in ((25, "0.5s"), (50, "1s"), (100, "2s")):
        out[f"coast_speed_{t}"] = obs[k][6]
        out[f"coast_turned_{t}"] = abs(ang[k])
    stop = next((k for k, o in enumerate(obs) if abs(o[6]) < 0.05), len(obs) - 1)
    out["coast_stop_time"] = 0.02 * stop
    rest = (hang + [0.0, 0.0, 0.0], (hang, [0.0, 0.0, 0.0]))
    obs, _ = side.run(0, [[1.0, 0.5]] * 100, init=rest)
    ang = turned(obs)
    for k, t in ((10, "0.2s"), (25, "0.5s"), (100, "2s")):
        out[f"push_proximal_{t}"] = obs[k][0]
        out[f"push_touch_{t}"] = obs[k][7] + obs[k][8]
        out[f"push_turned_{t}"] = abs(ang[k])
    out["random_return"] = [side.random_episode(seed)[1] for seed in range(episodes)]
    return out


def quadruped_start(upright):
    """dm_control's reset pose of seed 0 (or with the identity orientation): (carl-spec's state,
    dm_control's (qpos, qvel))."""
    import numpy as np
    from dm_control import suite
    from dm_control.suite import quadruped

    env = suite.load("quadruped", "walk", task_kwargs={"random": 0})
    env.reset()
    if upright:
        quadruped._find_non_contacting_height(env.physics, np.array([1.0, 0.0, 0.0, 0.0]))
    qpos = env.physics.data.qpos.tolist()
    nv, na = env.physics.model.nv, env.physics.model.na
    return qpos + [0.0] * (nv + na), (qpos, [0.0] * nv)


def quadruped_metrics(side, medium_side, episodes):
    import math

    out = {}
    obs, _ = side.run(0, [[0.0] * 12] * 150, init=quadruped_start(False))
    out["drop_upright_0.5s"] = obs[25][47]
    out["drop_upright_3s"] = obs[150][47]
    moving = [max(max(abs(v) for v in o[16:32]), math.hypot(*o[44:47])) >= 0.05 for o in obs]
    last = max((k for k, m in enumerate(moving) if m), default=0)
    out["drop_time_to_rest"] = 0.02 * (last + 1)
    out["drop_toe_force_3s"] = sum(math.sqrt(sum(math.sinh(x) ** 2 for x in obs[150][54 + 3 * k:57 + 3 * k]))
                                   for k in range(4))
    obs, _ = side.run(0, [[0.0, 0.5, 0.3] * 4] * 50, init=quadruped_start(True))
    out["servo_knee_1s"] = obs[50][2]
    out["servo_upright_1s"] = obs[50][47]
    out["random_return"] = [side.random_episode(seed)[1] for seed in range(episodes)]
    return out


METRICS = {
    "dmc_finger": finger_metrics, "dmc_fish": fish_metrics, "dmc_point_mass": point_mass_metrics,
    "dmc_quadruped": quadruped_metrics, "dmc_walker": walker_metrics,
}


def carl_sides(exe, env):
    ctx = instance_context(env)
    opts = ENVS[env][2]
    return CarlSide(exe, env, ctx, opts), CarlSide(exe, env, {**ctx, **SECOND.get(env, MEDIUM)}, opts)


def dmc_speed(env, steps):
    import numpy as np

    spec = env.action_spec()
    rng = np.random.RandomState(0)
    actions = [rng.uniform(spec.minimum, spec.maximum) for _ in range(4096)]
    env.reset()
    t0 = time.perf_counter()
    for k in range(steps):
        if env.step(actions[k % len(actions)]).last():
            env.reset()
    return steps / (time.perf_counter() - t0)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--carl-spec", default="target/release/carl-spec")
    ap.add_argument("--envs", default=",".join(ENVS))
    ap.add_argument("--episodes", type=count, default=30)
    ap.add_argument("--speed", action="store_true")
    ap.add_argument("--runs", type=count, default=5)
    ap.add_argument("--steps", type=count, default=5000)
    ap.add_argument("--carl-only", action="store_true")
    ap.add_argument("--json")
    ap.add_argument("--markdown")
    args = ap.parse_args()
    envs = [e.strip() for e in args.envs.split(",") if e.strip()]
    for e in envs:
        if e not in ENVS:
            sys.exit(f"unknown environment {e!r}; choose from {', '.join(ENVS)}")
    results, lines = {}, ["| environment | metric | dm_control | carl-spec | ratio / p | within |", "|---|---|---|---|---|---|"]
    for env in envs:
        domain, task, _ = ENVS[env]
        carl = METRICS[env](*carl_sides(args.carl_spec, env), args.episodes)
        if args.carl_only:
            print(json.dumps({env: carl}, indent=1))
            continue
        dmc = METRICS[env](DmcSide(domain, task), DmcSide(domain, task, SECOND.get(env, MEDIUM)), args.episodes)
        rows = {}
        for m, ref in dmc.items():
            ours = carl[m]
            if isinstance(ref, list):
                p = mann_whitney_p(ours, ref)
                rows[m] = dict(dmc=[statistics.mean(ref), statistics.stdev(ref)],
                               carl=[statistics.mean(ours), statistics.stdev(ours)], p=p, ok=p >= 0.05)
                lines.append(f"| {env} | {m} ({args.episodes} seeds) | {rows[m]['dmc'][0]:.1f} ± {rows[m]['dmc'][1]:.1f} | "
                             f"{rows[m]['carl'][0]:.1f} ± {rows[m]['carl'][1]:.1f} | p {p:.2f} | {'yes' if p >= 0.05 else 'NO'} |")
            else:
                r = ours / ref if ref else float("nan")
                rows[m] = dict(dmc=ref, carl=ours, ratio=r, ok=abs(r - 1) <= 0.15)
                lines.append(f"| {env} | {m} | {ref:.5g} | {ours:.5g} | {r:.3f} | {'yes' if rows[m]['ok'] else 'NO'} |")
        results[env] = rows
    if args.carl_only:
        return
    meta = {"generator": "scripts/dmc_compare.py", "episodes": args.episodes}
    if args.speed:
        lines += ["", "| environment | dm_control steps/s (median) | carl-spec steps/s (median) | carl-spec / dm_control |",
                  "|---|---|---|---|"]
        from dm_control import suite

        for env in envs:
            domain, task, _ = ENVS[env]
            denv = suite.load(domain, task, task_kwargs={"random": 0})
            runs = {"dm_control": [], "carl": []}
            for _ in range(args.runs):
                runs["dm_control"].append(dmc_speed(denv, args.steps))
                runs["carl"].append(carl_steps_per_sec(args.carl_spec, env, args.steps))
            med = {k: statistics.median(v) for k, v in runs.items()}
            results[env]["speed"] = {"runs": runs, "median": med, "ratio": med["carl"] / med["dm_control"]}
            lines.append(f"| {env} | {med['dm_control']:.0f} | {med['carl']:.0f} | {med['carl'] / med['dm_control']:.2f} |")
        lines += ["", f"{args.runs} interleaved runs of {args.steps} steps per side; load average "
                  f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs."]
    write_report(args, meta, results, "\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
