#!/usr/bin/env python3
"""Compare carl-spec's Ant, HalfCheetah, Humanoid, HumanoidStandup, Hopper, Walker2d, InvertedPendulum, InvertedDoublePendulum, Reacher and Pusher with Gymnasium's MuJoCo v5 versions.

Both sides are driven the same way and measured from their observations (the v5 layout is the
same on both): each metric below runs on Gymnasium 1.4 (`gymnasium.make("Ant-v5")`, MuJoCo) and on
`carl-spec rollout <robot> --actions -` (JSON Lines), with seeded resets.

Metrics (per robot):
* rest_height: root height (`qpos[2]`, HalfCheetah 0.7 + `qpos[1]`, Hopper and Walker2d
  `qpos[1]`) after `REST_STEPS` steps of zero action (Humanoid: after the initial drop, before
  it collapses; Hopper and Walker2d: 0.2 s, after the foot landed), mean over seeds;
* fall_time: seconds of zero action until the episode terminates (Humanoid, Hopper, Walker2d;
  Ant, HalfCheetah and HumanoidStandup do not fall, reported as the time limit; HumanoidStandup
  runs 200 steps: its rest height is the lying torso's);
* step_response: change of one joint's angle 0.1 s and 0.25 s after a full-scale constant
  control on its motor (towards the inside of its range), minus the same seed's zero-action run
  (so passive motion cancels); Hopper, Walker2d and HumanoidStandup: every actuated joint;
* gait_velocity: mean forward velocity (`qvel[0]`) under a fixed open-loop sinusoidal gait
  (`GAITS`), until termination or 1000 steps, mean over `--gait-seeds` seeds (default 3), with
  its standard deviation and, with more than 3 seeds, the Mann-Whitney p-value as below;
* random_length / random_return: episode length and return under uniform random actions,
  mean and standard deviation over `--episodes` seeds (default 20), and the two-sided p-value
  of a Mann-Whitney U test (normal approximation) of each carl-spec column against MuJoCo's
  episodes (the criterion where MuJoCo's spread exceeds its mean).

The control tasks (inverted_pendulum, inverted_double_pendulum, reacher, pusher: `CONTROL`) have
their own metrics, from explicit initial states set on both sides (`--initial-state`, `set_state`):
* fall_time_<tilt>: seconds of zero action from the pole (IDP: the lower pole) tilted by <tilt> rad,
  at rest, until the episode terminates;
* coast_<joint>_<t>s (Pusher, no gravity: its passive behaviour): a joint's angle <t> s after it
  starts at 1 rad/s with zero action (damping and armature slow it);
* step_<joint>_<t>s: change of a coordinate (the cart's x, the pole angle; Reacher's and Pusher's
  arm angles)
  <t> s after a constant control on one actuator from the rest state (the pendulums: a fraction of
  full scale small enough that the pole stays up past 0.25 s), minus the zero-action run's;
* random_length / random_return as above.

carl-spec runs twice: with its default context (CARL's Brax parameters: masses, actuator
strength, joint damping and friction differ from MuJoCo's XML) and with a context set to
MuJoCo's values where a context feature exists (`MUJOCO_CONTEXT`; Ant, Humanoid, Hopper and Walker2d:
their spec's frozen instance set `mujoco_v5`, which holds every model value): the first column shows
what a user of the benchmark gets, the second how much of the difference is the parameters.

Usage (from the repository root, with Gymnasium 1.4 and mujoco installed):
    python3 scripts/robot_mujoco_compare.py --carl-spec target/release/carl-spec \\
        --json robot_mujoco_compare.json --markdown robot_mujoco_compare.md
`--carl-only` skips Gymnasium (prints carl-spec's side only, e.g. to refresh the test pins);
`--carl-option rapier=true` runs HalfCheetah on its former rapier3d engine (the articulated engine
is its default).
"""
import argparse
import json
import math
import statistics
import subprocess
import sys

from robot_speed_compare import count

ROBOTS = {
    # gym id, action dim, ctrl max, qpos index of the height, obs index offset of qpos
    # (obs = qpos[skip:] ++ qvel ...), nq, physics dt of one env step
    "ant": dict(gym="Ant-v5", na=8, ctrl=1.0, z=2, skip=2, nq=15, dt=0.05, base_z=0.0),
    "half_cheetah": dict(gym="HalfCheetah-v5", na=6, ctrl=1.0, z=1, skip=1, nq=9, dt=0.05, base_z=0.7),
    "humanoid": dict(gym="Humanoid-v5", na=17, ctrl=0.4, z=2, skip=2, nq=24, dt=0.015, base_z=0.0),
    "hopper": dict(gym="Hopper-v5", na=3, ctrl=1.0, z=1, skip=1, nq=6, dt=0.008, base_z=0.0),
    "walker2d": dict(gym="Walker2d-v5", na=6, ctrl=1.0, z=1, skip=1, nq=9, dt=0.008, base_z=0.0),
    "humanoid_standup": dict(gym="HumanoidStandup-v5", na=17, ctrl=0.4, z=2, skip=2, nq=24, dt=0.015, base_z=0.0),
}
REST_STEPS = {"ant": 100, "half_cheetah": 100, "humanoid": 10, "hopper": 25, "walker2d": 25, "humanoid_standup": 20}
# Zero-action steps of the fall-time run (robots that never terminate: shorter than the limit).
FALL_STEPS = {"humanoid_standup": 200}
SEEDS_SHORT = [0, 1, 2, 3, 4]
# (actuator index, qpos index of its joint, name[, sign of the control]) of the joints whose
# torque-step response is measured (Hopper's and Walker2d's thighs and legs start at the upper
# end of their range [-150°, 0°]: their step pushes them down into it).
STEP_JOINTS = {
    "ant": [(2, 7, "hip_1"), (3, 8, "ankle_1")],
    "half_cheetah": [(0, 3, "bthigh"), (3, 6, "fthigh")],
    "humanoid": [(5, 12, "right_hip_y"), (6, 13, "right_knee")],
    "hopper": [(0, 3, "thigh", -1), (1, 4, "leg", -1), (2, 5, "foot", 1)],
    "walker2d": [
        (0, 3, "thigh", -1),
        (1, 4, "leg", -1),
        (2, 5, "foot", 1),
        (3, 6, "thigh_left", -1),
        (4, 7, "leg_left", -1),
        (5, 8, "foot_left", 1),
    ],
    # Every motor, towards the inside of its range from the lying pose (the knees' ranges end at -2°).
    "humanoid_standup": [
        (0, 8, "abdomen_y"), (1, 7, "abdomen_z"), (2, 9, "abdomen_x"), (3, 10, "right_hip_x", -1),
        (4, 11, "right_hip_z"), (5, 12, "right_hip_y"), (6, 13, "right_knee", -1), (7, 14, "left_hip_x", -1),
        (8, 15, "left_hip_z"), (9, 16, "left_hip_y"), (10, 17, "left_knee", -1), (11, 18, "right_shoulder1"),
        (12, 19, "right_shoulder2"), (13, 20, "right_elbow"), (14, 21, "left_shoulder1"),
        (15, 22, "left_shoulder2"), (16, 23, "left_elbow"),
    ],
}
# Robots whose step responses run with terminate_when_unhealthy=False (both sides).
NO_TERMINATION_STEP = ("hopper", "walker2d")
# Env steps after which the step response is read (about 0.1 s and 0.25 s).
STEP_TIMES = {
    "ant": [2, 5], "half_cheetah": [2, 5], "humanoid": [7, 17], "hopper": [12, 31], "walker2d": [12, 31],
    "humanoid_standup": [7, 17],
}

# MuJoCo's XML values expressed as carl-spec context features (where a feature exists).
MUJOCO_CONTEXT = {
    # half_cheetah.xml: torso 6.2502 kg (settotalmass 14), damping 6/4.5/3/4.5/3/1.5 (mean 3.75),
    # solreflimit (0.02, 1) (joint_stiffness 2500), friction 0.4.
    "half_cheetah": {"torso_mass": 6.2502, "joint_angular_damping": 3.75, "joint_stiffness": 2500.0, "friction": 0.4},
}
# Robots whose spec freezes MuJoCo's values as the instance set `mujoco_v5` (read from the spec).
INSTANCE_SET_ROBOTS = (
    "ant", "humanoid", "hopper", "walker2d", "inverted_pendulum", "inverted_double_pendulum", "reacher", "pusher",
    "humanoid_standup",
)


# The control tasks: gym id, action dim, env-step dt, rest state (qpos ++ qvel; Reacher: arm
# angles ++ target ++ arm rates, carl-spec's state layout; IDP's state ends with qfrc_constraint[0]),
# tilted coordinate, step responses (actuator, control, name, how to read it from the
# observation), env steps read.
CONTROL = {
    "inverted_pendulum": dict(
        gym="InvertedPendulum-v5", na=1, dt=0.04, nq=2, tilt=1, tilts=[0.02, 0.05],
        steps=[(0, 0.2, "cart_x", ("obs", 0)), (0, 0.2, "pole", ("obs", 1))], at=[3, 6],
    ),
    "inverted_double_pendulum": dict(
        gym="InvertedDoublePendulum-v5", na=1, dt=0.05, nq=3, tilt=1, tilts=[0.02, 0.05],
        steps=[(0, 0.1, "cart_x", ("obs", 0)), (0, 0.1, "pole", ("angle", 1, 3)), (0, 0.1, "pole2", ("angle", 2, 4))],
        at=[2, 5],
    ),
    "reacher": dict(
        gym="Reacher-v5", na=2, dt=0.02, nq=4, tilt=None, tilts=[],
        steps=[(0, 1.0, "joint0", ("angle", 2, 0)), (1, 1.0, "joint1", ("angle", 3, 1))], at=[5, 12],
    ),
    # Full-scale torque on each of the seven motors, towards the inside of its range (the elbow's
    # and the wrist flex's end at 0); the object parked out of the arm's way; no gravity.
    "pusher": dict(
        gym="Pusher-v5", na=7, dt=0.05, nq=9, tilt=None, tilts=[],
        steps=[(k, 2.0 * sgn, name, ("obs", k)) for k, (name, sgn) in enumerate(
            [("shoulder_pan", 1), ("shoulder_lift", 1), ("upper_arm_roll", 1), ("elbow_flex", -1),
             ("forearm_roll", 1), ("wrist_flex", -1), ("wrist_roll", 1)])],
        at=[2, 5], coast=[(0, "shoulder_pan"), (3, "elbow_flex")],
    ),
}
for _r in CONTROL:
    ROBOTS.setdefault(_r, dict(gym=CONTROL[_r]["gym"]))


def control_state(robot, tilt=0.0):
    """carl-spec's state and Gymnasium's (qpos, qvel) of the rest state with a tilt."""
    c = CONTROL[robot]
    if robot == "reacher":
        qpos = [0.0, 0.0, 0.1, 0.1]
        return qpos + [0.0, 0.0], (qpos, [0.0] * 4)
    if robot == "pusher":
        # The object's slides (y, x) at (-0.3, 0.2): behind the arm's reach at rest.
        qpos = [0.0] * 7 + [-0.3, 0.2]
        qvel = [0.0] * 9
        if tilt:
            qvel[int(tilt[0])] = tilt[1]
        return qpos + qvel, (qpos + [0.0, 0.0], qvel + [0.0, 0.0])
    qpos = [0.0] * c["nq"]
    if c["tilt"] is not None:
        qpos[c["tilt"]] = tilt
    extra = [0.0] if robot == "inverted_double_pendulum" else []
    return qpos + [0.0] * c["nq"] + extra, (qpos, [0.0] * c["nq"])


def read(obs, n, how):
    """The coordinate at observation n; an angle (atan2 of its sin and cos) unwrapped along the
    run (Reacher's upper arm turns past pi within 0.25 s)."""
    if how[0] == "obs":
        return obs[n][how[1]]
    total, prev = 0.0, None
    for o in obs[: n + 1]:
        a = math.atan2(o[how[1]], o[how[2]])
        if prev is not None:
            total += (a - prev + math.pi) % (2 * math.pi) - math.pi
        else:
            total = a
        prev = a
    return total


def measure_control(side, robot, episodes):
    c = CONTROL[robot]
    zero = [0.0] * c["na"]
    res = {}
    for tilt in c["tilts"]:
        _, rewards = side.run(0, [zero] * 1000, init=control_state(robot, tilt))
        res[f"fall_time_{tilt:g}"] = len(rewards) * c["dt"]
    horizon = max(c["at"])
    for j, name in c.get("coast", []):
        obs, _ = side.run(0, [zero] * horizon, init=control_state(robot, (j, 1.0)))
        for n in c["at"]:
            res[f"coast_{name}_{n * c['dt']:.3g}s"] = obs[n][j]
    base, _ = side.run(0, [zero] * horizon, init=control_state(robot))
    for act, u, name, how in c["steps"]:
        a = [0.0] * c["na"]
        a[act] = u
        obs, _ = side.run(0, [a] * horizon, init=control_state(robot))
        for n in c["at"]:
            if n < len(obs):
                res[f"step_{name}_{n * c['dt']:.3g}s"] = read(obs, n, how) - read(base, n, how)
    res.update(random_episodes(side, episodes))
    return res


def mujoco_context(robot):
    if robot in INSTANCE_SET_ROBOTS:
        with open(f"specs/{robot}.json") as f:
            sets = json.load(f)["instance_sets"]
        return dict(sets["mujoco_v5"]["explicit"][0]["context"])
    return MUJOCO_CONTEXT[robot]


def gait(robot, t):
    """Open-loop sinusoidal controls at time t (s): a fixed trot/bound, full-scale amplitude."""
    w = 2 * math.pi * 2.0  # 2 Hz
    if robot == "ant":
        # actuator order hip_4, ankle_4, hip_1, ankle_1, hip_2, ankle_2, hip_3, ankle_3;
        # diagonal pairs (1, 3) and (2, 4) in anti-phase, ankles a quarter period behind.
        phase = {4: 0.0, 1: math.pi, 2: 0.0, 3: math.pi}
        out = []
        for leg in (4, 1, 2, 3):
            out.append(math.sin(w * t + phase[leg]))
            out.append(math.sin(w * t + phase[leg] - math.pi / 2))
        return out
    if robot == "half_cheetah":
        # bthigh, bshin, bfoot, fthigh, fshin, ffoot: back and front legs in anti-phase.
        return [math.sin(w * t + p) for p in (0.0, -0.5, -1.0, math.pi, math.pi - 0.5, math.pi - 1.0)]
    if robot == "hopper":
        # thigh, leg, foot: a hop, half amplitude, the leg and foot a quarter period behind.
        return [0.5 * math.sin(w * t + p) for p in (0.0, -math.pi / 2, -math.pi)]
    if robot == "walker2d":
        # right thigh, leg, foot, then the left leg in anti-phase, half amplitude.
        right = [0.5 * math.sin(w * t + p) for p in (0.0, -math.pi / 2, -math.pi)]
        left = [0.5 * math.sin(w * t + math.pi + p) for p in (0.0, -math.pi / 2, -math.pi)]
        return right + left
    # humanoid: hips y and knees alternate (right 5, 6 / left 9, 10), rest zero.
    a = [0.0] * 17
    a[5] = 0.4 * math.sin(w * t)
    a[6] = 0.4 * math.sin(w * t - math.pi / 2)
    a[9] = 0.4 * math.sin(w * t + math.pi)
    a[10] = 0.4 * math.sin(w * t + math.pi / 2)
    return a


def root_height(robot, obs):
    r = ROBOTS[robot]
    return r["base_z"] + obs[r["z"] - r["skip"]]


def forward_velocity(robot, obs):
    r = ROBOTS[robot]
    return obs[r["nq"] - r["skip"]]


# ---------------------------------------------------------------- drivers


class CarlSide:
    """Runs carl-spec episodes through `carl-spec rollout` (JSON Lines on stdout)."""

    def __init__(self, exe, robot, context, options=()):
        self.exe, self.robot, self.context, self.options = exe, robot, context, list(options)

    def without_termination(self):
        """The same side with Gymnasium's terminate_when_unhealthy=False."""
        return CarlSide(self.exe, self.robot, self.context, self.options + ["terminate_when_unhealthy=false"])

    def _cmd(self, seed):
        cmd = [self.exe, "rollout", self.robot, "--seed", str(seed), "--allow-out-of-bounds"]
        for k, v in sorted(self.context.items()):
            cmd += ["--context", f"{k}={v}"]
        for o in self.options:
            cmd += ["--option", o]
        return cmd

    @staticmethod
    def _parse(text):
        obs, rewards, done = [], [], False
        for line in text.splitlines():
            d = json.loads(line)
            if "reset" in d:
                obs.append(d["reset"]["obs"])
                continue
            obs.append(d["obs"])
            rewards.append(d["reward"])
            done = d["terminated"] or d["truncated"]
        return obs, rewards, done

    def run(self, seed, actions, init=None):
        """Observations (reset first) and rewards of one episode under the action list, from the
        state `init` (carl-spec's state, Gymnasium's (qpos, qvel)) if given."""
        cmd = self._cmd(seed) + ["--actions", "-", "--steps", str(len(actions))]
        if init is not None:
            cmd += ["--initial-state", ",".join(repr(float(x)) for x in init[0])]
        stdin = "".join(json.dumps(a) + "\n" for a in actions)
        p = subprocess.run(cmd, input=stdin, capture_output=True, text=True)
        if p.returncode != 0:
            sys.exit(f"carl-spec failed: {' '.join(cmd)}\n{p.stderr}")
        return self._parse(p.stdout)[:2]

    def random_episode(self, seed):
        cmd = self._cmd(seed) + ["--policy", "random"]
        p = subprocess.run(cmd, capture_output=True, text=True)
        if p.returncode != 0:
            sys.exit(f"carl-spec failed: {' '.join(cmd)}\n{p.stderr}")
        _, rewards, _ = self._parse(p.stdout)
        return len(rewards), sum(rewards)


class GymSide:
    """Runs Gymnasium MuJoCo v5 episodes (1000-step time limit as registered)."""

    def __init__(self, robot, **kwargs):
        import gymnasium as gym

        self.robot = robot
        self.env = gym.make(ROBOTS[robot]["gym"], **kwargs)

    def without_termination(self):
        return GymSide(self.robot, terminate_when_unhealthy=False)

    def run(self, seed, actions, init=None):
        import numpy as np

        obs, _ = self.env.reset(seed=seed)
        if init is not None:
            u = self.env.unwrapped
            u.set_state(np.asarray(init[1][0], dtype=np.float64), np.asarray(init[1][1], dtype=np.float64))
            obs = u._get_obs()
        out, rewards = [obs.tolist()], []
        for a in actions:
            obs, r, term, trunc, _ = self.env.step(np.asarray(a, dtype=np.float64))
            out.append(obs.tolist())
            rewards.append(float(r))
            if term or trunc:
                break
        return out, rewards

    def random_episode(self, seed):
        self.env.action_space.seed(seed)
        self.env.reset(seed=seed)
        n, ret = 0, 0.0
        while True:
            _, r, term, trunc, _ = self.env.step(self.env.action_space.sample())
            n += 1
            ret += float(r)
            if term or trunc:
                return n, ret


# ---------------------------------------------------------------- metrics


def measure(side, robot, episodes, gait_seeds=3):
    r = ROBOTS[robot]
    na, dt = r["na"], r["dt"]
    zero = [0.0] * na
    res = {}

    heights = []
    for s in SEEDS_SHORT:
        obs, _ = side.run(s, [zero] * REST_STEPS[robot])
        heights.append(root_height(robot, obs[-1]))
    res["rest_height"] = statistics.mean(heights)

    falls = []
    for s in SEEDS_SHORT:
        _, rewards = side.run(s, [zero] * FALL_STEPS.get(robot, 1000))
        falls.append(len(rewards) * dt)
    res["fall_time"] = statistics.mean(falls)

    horizon = max(STEP_TIMES[robot])
    # Hopper and Walker2d tip over within the horizon: their step responses run on.
    step_side = side.without_termination() if robot in NO_TERMINATION_STEP else side
    base = {s: step_side.run(s, [zero] * horizon)[0] for s in SEEDS_SHORT[:3]}
    for act, qi, name, *sign in STEP_JOINTS[robot]:
        u = [0.0] * na
        u[act] = r["ctrl"] * (sign[0] if sign else 1)
        oi = qi - r["skip"]
        for n in STEP_TIMES[robot]:
            d = []
            for s in SEEDS_SHORT[:3]:
                obs, _ = step_side.run(s, [u] * horizon)
                d.append(obs[n][oi] - base[s][n][oi])
            res[f"step_{name}_{n * dt:.3g}s"] = statistics.mean(d)

    vel = []
    for s in range(gait_seeds):
        obs, _ = side.run(s, [gait(robot, k * dt) for k in range(1000)])
        vel.append(statistics.mean(forward_velocity(robot, o) for o in obs[1:]))
    res["gait_velocity"] = statistics.mean(vel)
    if gait_seeds > 3:
        res["gait_velocity_sd"] = statistics.pstdev(vel)
        res["gait_velocity_samples"] = vel

    res.update(random_episodes(side, episodes))
    return res


def random_episodes(side, episodes):
    """Random-policy episodes with seeds 0..episodes-1: their lengths and returns, means and spreads."""
    lens, rets = [], []
    for s in range(episodes):
        n, ret = side.random_episode(s)
        lens.append(n)
        rets.append(ret)
    return {
        "random_length": statistics.mean(lens),
        "random_length_sd": statistics.pstdev(lens),
        "random_return": statistics.mean(rets),
        "random_return_sd": statistics.pstdev(rets),
        "random_length_samples": lens,
        "random_return_samples": rets,
    }


def mann_whitney_p(a, b):
    """Two-sided p-value of the Mann-Whitney U test (normal approximation, tie-corrected)."""
    n1, n2 = len(a), len(b)
    pooled = sorted([(x, 0) for x in a] + [(x, 1) for x in b])
    ranks = [0.0] * len(pooled)
    i, ties = 0, 0.0
    while i < len(pooled):
        j = i
        while j + 1 < len(pooled) and pooled[j + 1][0] == pooled[i][0]:
            j += 1
        for k in range(i, j + 1):
            ranks[k] = (i + j) / 2 + 1
        t = j - i + 1
        ties += t**3 - t
        i = j + 1
    r1 = sum(r for r, (_, g) in zip(ranks, pooled) if g == 0)
    u = r1 - n1 * (n1 + 1) / 2
    n = n1 + n2
    var = n1 * n2 / 12 * ((n + 1) - ties / (n * (n - 1)))
    if var <= 0:
        return 1.0
    z = (u - n1 * n2 / 2) / math.sqrt(var)
    return math.erfc(abs(z) / math.sqrt(2))


def ratio(a, b):
    if b == 0 or a is None or b is None:
        return None
    return a / b


def num(x):
    """Three significant digits without exponents."""
    return f"{x:.0f}" if abs(x) >= 100 else f"{x:.3g}"


def markdown(table):
    lines = [
        "| robot | metric | MuJoCo (Gymnasium v5) | carl-spec (CARL context) | ratio | carl-spec (MuJoCo's values) | ratio |",
        "|---|---|---|---|---|---|---|",
    ]
    for robot, rows in table.items():
        for metric, v in rows.items():
            if metric.endswith("_sd") or metric.endswith("_samples") or metric.endswith("_p"):
                continue
            cells = []
            for key in ("mujoco", "carl", "carl_matched"):
                x = v.get(key)
                sd = rows.get(metric + "_sd", {}).get(key)
                cells.append("—" if x is None else (f"{num(x)} ± {num(sd)}" if sd is not None else num(x)))
            r1 = ratio(v.get("carl"), v.get("mujoco"))
            r2 = ratio(v.get("carl_matched"), v.get("mujoco"))
            f = lambda r: "—" if r is None else f"{r:.2f}"
            p = rows.get(metric + "_p", {})
            r1s = f(r1) + (f" (p {p['carl']:.2f})" if "carl" in p else "")
            r2s = f(r2) + (f" (p {p['carl_matched']:.2f})" if "carl_matched" in p else "")
            lines.append(f"| {robot} | {metric} | {cells[0]} | {cells[1]} | {r1s} | {cells[2]} | {r2s} |")
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--carl-spec", default="target/release/carl-spec")
    ap.add_argument("--robots", default="ant,half_cheetah,humanoid")
    ap.add_argument("--episodes", type=count, default=20)
    ap.add_argument("--gait-seeds", type=count, default=3, help="seeds of the open-loop gait (0, 1, ...)")
    ap.add_argument("--json")
    ap.add_argument("--markdown")
    ap.add_argument("--carl-only", action="store_true", help="skip Gymnasium (carl-spec's side only)")
    ap.add_argument(
        "--carl-option",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="an environment option for carl-spec's side, e.g. rapier=true (HalfCheetah's rapier3d engine); repeatable",
    )
    args = ap.parse_args()
    if args.episodes < 1:
        sys.exit("--episodes must be at least 1")
    robots = [r.strip() for r in args.robots.split(",") if r.strip()]
    for robot in robots:
        if robot not in ROBOTS:
            sys.exit(f"unknown robot {robot!r}; choose from {', '.join(ROBOTS)}")
    meta = {
        "generator": "scripts/robot_mujoco_compare.py",
        "episodes": args.episodes,
        "gait_seeds": args.gait_seeds,
        "carl_options": args.carl_option,
    }
    if not args.carl_only:
        import gymnasium
        import mujoco

        meta["gymnasium"] = gymnasium.__version__
        meta["mujoco"] = mujoco.__version__
    table = {}
    for robot in robots:
        sides = {
            "carl": CarlSide(args.carl_spec, robot, {}, args.carl_option),
            "carl_matched": CarlSide(args.carl_spec, robot, mujoco_context(robot), args.carl_option),
        }
        if not args.carl_only:
            sides["mujoco"] = GymSide(robot)
        rows = {}
        for key, side in sides.items():
            print(f"{robot}: {key} ...", file=sys.stderr, flush=True)
            if robot in CONTROL:
                measured = measure_control(side, robot, args.episodes)
            else:
                measured = measure(side, robot, args.episodes, args.gait_seeds)
            for metric, value in measured.items():
                rows.setdefault(metric, {})[key] = value
        for metric in ("random_length", "random_return", "gait_velocity"):
            if metric + "_samples" not in rows:
                continue
            samples = rows.pop(metric + "_samples")
            if "mujoco" in samples:
                for key in ("carl", "carl_matched"):
                    p = mann_whitney_p(samples[key], samples["mujoco"])
                    rows.setdefault(metric + "_p", {})[key] = p
        table[robot] = rows
    out = {"meta": meta, "mujoco_context": {r: mujoco_context(r) for r in robots}, "table": table}
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=1, sort_keys=True)
            f.write("\n")
    md = markdown(table)
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write(md)
    print(md)


if __name__ == "__main__":
    main()
