#!/usr/bin/env python3
"""Generate bit-exact parity fixtures for carl-spec's classic-control environments from the
real Gymnasium implementation.

Usage (a venv of its own, `.venv-*` is gitignored):

    python3 -m venv .venv-gym
    .venv-gym/bin/pip install "gymnasium==1.4.*" numpy
    .venv-gym/bin/python scripts/gen_parity_fixtures.py [out_dir]

Writes crates/carl-envs-classic-control/tests/fixtures/parity/<env>.json, replayed by
crates/carl-envs-classic-control/tests/integration/parity.rs.

How a carl-spec context maps onto Gymnasium
-------------------------------------------
Each episode lists its context by carl-spec canonical feature name ("context"). The script
writes the corresponding attributes onto ``env.unwrapped`` as *Python floats* (NumPy 2 treats
Python floats as "weak" scalars; assigning np.float64 would change float32 arithmetic in
Pendulum and MountainCarContinuous) and recomputes every derived quantity:

* cartpole: gravity->gravity, masscart->masscart, masspole->masspole, pole_length->length,
  force_magnifier->force_mag, update_interval->tau; then
  total_mass = masspole + masscart and polemass_length = masspole * length
  (exactly Gymnasium's __init__ formulas; carl-bench 1.1.1 forgets this).
* pendulum: dt, g, l, m, max_speed, max_torque -> attributes of the same name; the
  action_space is rebuilt as Box(-max_torque, max_torque, (1,), float32) (only cosmetic:
  step() clips with self.max_torque).
* mountain_car: force, goal_position, goal_velocity, gravity, max_position, max_speed,
  min_position -> same-named attributes.
* mountain_car_continuous: min_position, max_position, max_speed, goal_position,
  goal_velocity, power -> same-named attributes.
* acrobot: link_length_1->LINK_LENGTH_1, link_length_2->LINK_LENGTH_2,
  link_mass_1->LINK_MASS_1, link_mass_2->LINK_MASS_2, link_com_1->LINK_COM_POS_1,
  link_com_2->LINK_COM_POS_2, link_moi->LINK_MOI, max_velocity_1->MAX_VEL_1,
  max_velocity_2->MAX_VEL_2 (set on the instance, shadowing the class attributes);
  torque_noise_max stays 0 (its noise comes from NumPy's generator, not reproducible from
  Rust); an episode may set option "dynamics": "nips" -> book_or_nips = "nips".
Initial-state features (start_*, initial_*) only affect reset(); the fixtures instead set an
explicit initial state: after env.reset(seed=...), ``env.unwrapped.state`` is overwritten
with a float64 array (CartPole/Acrobot/Pendulum/MountainCarContinuous: np.array(float64);
MountainCar: np.array([pos, vel]) float64, as its reset produces).

Each episode is stepped through the gym.make() wrapper stack (TimeLimit with the recorded
max_episode_steps) until terminated or truncated. Observations and float32 actions are stored
as the uint32 bit patterns of their float32 values; rewards as JSON numbers (Python's repr
round-trips float64 exactly); initial states and the float64 internal-state checkpoints
(every 10th step and the last) as JSON numbers.
"""

import json
import math
import os
import platform
import sys

import gymnasium as gym
import numpy as np


def f32_bits(values):
    return [int(x) for x in np.asarray(values, dtype=np.float32).view(np.uint32)]


CARTPOLE_ATTRS = {
    "gravity": "gravity",
    "masscart": "masscart",
    "masspole": "masspole",
    "pole_length": "length",
    "force_magnifier": "force_mag",
    "update_interval": "tau",
}
ACROBOT_ATTRS = {
    "link_length_1": "LINK_LENGTH_1",
    "link_length_2": "LINK_LENGTH_2",
    "link_mass_1": "LINK_MASS_1",
    "link_mass_2": "LINK_MASS_2",
    "link_com_1": "LINK_COM_POS_1",
    "link_com_2": "LINK_COM_POS_2",
    "link_moi": "LINK_MOI",
    "max_velocity_1": "MAX_VEL_1",
    "max_velocity_2": "MAX_VEL_2",
}


def apply_context(name, u, context, options):
    """Write a carl-spec context onto env.unwrapped; returns the attributes written."""
    written = {}

    def put(attr, value):
        setattr(u, attr, float(value))
        written[attr] = float(value)

    if name == "cartpole":
        for k, v in context.items():
            put(CARTPOLE_ATTRS[k], v)
        put("total_mass", u.masspole + u.masscart)
        put("polemass_length", u.masspole * u.length)
    elif name == "pendulum":
        for k, v in context.items():
            put(k, v)
        u.action_space = gym.spaces.Box(-u.max_torque, u.max_torque, (1,), np.float32)
    elif name in ("mountain_car", "mountain_car_continuous"):
        for k, v in context.items():
            put(k, v)
    elif name == "acrobot":
        for k, v in context.items():
            put(ACROBOT_ATTRS[k], v)
        if options.get("dynamics") == "nips":
            u.book_or_nips = "nips"
            written["book_or_nips"] = "nips"
    else:
        raise ValueError(name)
    return written


def current_obs(name, u):
    if name == "pendulum":
        return u._get_obs()
    if name == "acrobot":
        return u._get_ob()
    return np.array(u.state, dtype=np.float32)


# --- per-environment episode definitions -------------------------------------------------


def initial_state(name, rng):
    if name == "cartpole":
        return rng.uniform(-0.05, 0.05, size=4)
    if name == "pendulum":
        return np.array([rng.uniform(-np.pi, np.pi), rng.uniform(-1.0, 1.0)])
    if name in ("mountain_car", "mountain_car_continuous"):
        return np.array([rng.uniform(-0.6, -0.4), rng.uniform(-0.01, 0.01)])
    if name == "acrobot":
        return rng.uniform(-0.1, 0.1, size=4)
    raise ValueError(name)


def choose_action(name, u, rng, context, explore_p):
    """Seeded, mostly-sensible policies with random exploration (probability explore_p), so
    that episodes are long, reach goals/limits/terminations and exercise clipping."""
    explore = rng.random() < explore_p
    if name == "cartpole":
        x, x_dot, th, th_dot = u.state
        if explore:
            return int(rng.integers(2))
        return int(th + 0.3 * th_dot + 0.02 * x_dot > 0)
    if name == "pendulum":
        mt = context.get("max_torque", 2.0)
        return np.array([rng.uniform(-1.3 * mt, 1.3 * mt)], dtype=np.float32)
    if name == "mountain_car":
        if explore:
            return int(rng.integers(3))
        return 2 if u.state[1] >= 0 else 0
    if name == "mountain_car_continuous":
        if explore:
            return np.array([rng.uniform(-2.0, 2.0)], dtype=np.float32)
        sign = 1.0 if u.state[1] >= 0 else -1.0
        return np.array([sign * rng.uniform(0.3, 1.5)], dtype=np.float32)
    if name == "acrobot":
        if explore:
            return int(rng.integers(3))
        return 2 if u.state[3] >= 0 else 0
    raise ValueError(name)


ENVS = {
    "cartpole": ("CartPole-v1", 200, [
        ("default", {}, {}),
        ("heavy_cart_long_pole", {"masscart": 2.5, "masspole": 0.3, "pole_length": 0.8}, {}),
        ("light_cart_strong_push", {"masscart": 0.5, "gravity": 15.0, "force_magnifier": 20.0,
                                    "update_interval": 0.01}, {}),
        ("mars_heavy_cart", {"gravity": 3.7, "masscart": 5.0, "pole_length": 0.25,
                             "update_interval": 0.03, "masspole": 0.05}, {}),
    ]),
    "pendulum": ("Pendulum-v1", 200, [
        ("default", {}, {}),
        ("earth_heavy_short", {"g": 9.81, "m": 1.3, "l": 0.7}, {}),
        ("mars_fine_step", {"g": 3.7, "dt": 0.02, "max_speed": 12.0, "max_torque": 3.0}, {}),
        ("light_long_coarse", {"m": 0.4, "l": 1.6, "dt": 0.07, "max_torque": 1.2,
                               "max_speed": 6.5}, {}),
    ]),
    "mountain_car": ("MountainCar-v0", 200, [
        ("default", {}, {}),
        ("low_goal_strong", {"goal_position": 0.3, "force": 0.0015, "gravity": 0.002}, {}),
        ("steep_slow", {"gravity": 0.0035, "force": 0.0012, "max_speed": 0.05,
                        "min_position": -1.0}, {}),
        ("left_goal", {"goal_position": -0.2, "goal_velocity": -0.01, "max_position": 0.5,
                       "force": 0.0008}, {}),
    ]),
    "mountain_car_continuous": ("MountainCarContinuous-v0", 300, [
        ("default", {}, {}),
        ("strong_low_goal", {"power": 0.0025, "goal_position": 0.3, "max_speed": 0.06}, {}),
        ("weak_far_goal", {"power": 0.0011, "goal_position": 0.55, "goal_velocity": 0.01,
                           "min_position": -1.1}, {}),
        ("narrow", {"min_position": -0.9, "max_position": 0.5, "max_speed": 0.04,
                    "goal_position": 0.4, "power": 0.002}, {}),
    ]),
    "acrobot": ("Acrobot-v1", 200, [
        ("default", {}, {}),
        ("heavy_first_link", {"link_mass_1": 1.5, "link_mass_2": 0.7, "link_length_1": 1.3}, {}),
        ("shifted_com", {"link_length_1": 0.8, "link_com_1": 0.3, "link_com_2": 0.6,
                         "link_moi": 1.4, "link_length_2": 1.2}, {}),
        ("slow_joints", {"max_velocity_1": 2.0, "max_velocity_2": 4.0, "link_mass_2": 2.0}, {}),
        ("nips_dynamics", {"link_mass_1": 0.8}, {"dynamics": "nips"}),
    ]),
}

MIN_STEPS_PER_CONTEXT = 200
# The internal float64 state (env.unwrapped.state) after step t is recorded for t % 10 == 0
# and at the episode's end: float32 observations alone would hide 1-ulp float64 differences.
STATE_CHECKPOINT_EVERY = 10
# max_episode_steps above is Gymnasium's registered limit except MountainCarContinuous (999),
# shortened to 300 to keep the fixture small; CartPole and Acrobot use 200 (registered: 500)
# so that their heuristic-policy episodes end by truncation.


def run_episode(name, gym_id, max_steps, ep_name, context, options, seed, explore_p):
    rng = np.random.default_rng(seed)
    env = gym.make(gym_id, max_episode_steps=max_steps)
    u = env.unwrapped
    written = apply_context(name, u, context, options)
    env.reset(seed=seed)
    init = initial_state(name, rng)
    u.state = np.array(init, dtype=np.float64)
    init_obs = current_obs(name, u)
    actions, obs, rewards, terms, truncs, checkpoints = [], [], [], [], [], []
    while True:
        a = choose_action(name, u, rng, context, explore_p)
        o, r, term, trunc, _ = env.step(a)
        assert np.asarray(o).dtype == np.float32, (name, np.asarray(o).dtype)
        actions.append(f32_bits(a)[0] if isinstance(a, np.ndarray) else int(a))
        obs.append(f32_bits(o))
        rewards.append(float(r))
        terms.append(bool(term))
        truncs.append(bool(trunc))
        t = len(actions) - 1
        if t % STATE_CHECKPOINT_EVERY == 0 or term or trunc:
            checkpoints.append([t, [float(x) for x in np.asarray(u.state).ravel()]])
        if term or trunc:
            break
    env.close()
    return {
        "name": ep_name,
        "context": context,
        "options": options,
        "gymnasium_attributes": written,
        "max_episode_steps": max_steps,
        "initial_state": [float(x) for x in init],
        "initial_obs_bits": f32_bits(init_obs),
        "actions": actions,
        "obs_bits": obs,
        "rewards": rewards,
        "terminated": terms,
        "truncated": truncs,
        "state_checkpoints": checkpoints,
    }


def main():
    out_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", "crates", "carl-envs-classic-control", "tests", "fixtures", "parity")
    os.makedirs(out_dir, exist_ok=True)
    for name, (gym_id, max_steps, contexts) in ENVS.items():
        episodes = []
        for ci, (ep_name, context, options) in enumerate(contexts):
            steps, k = 0, 0
            # Episode 0 mostly follows the heuristic policy; later ones are uniformly random
            # (short, terminating CartPole episodes); at least two episodes per context.
            while steps < MIN_STEPS_PER_CONTEXT or k < (1 if name == "pendulum" else 2):
                seed = 1000 * ci + k
                explore_p = 0.25 if k == 0 else 1.0
                ep = run_episode(name, gym_id, max_steps, f"{ep_name}#{k}", context, options,
                                 seed, explore_p)
                episodes.append(ep)
                steps += len(ep["actions"])
                k += 1
        doc = {
            "env": name,
            "gymnasium_id": gym_id,
            "gymnasium_version": gym.__version__,
            "numpy_version": np.__version__,
            "python_version": platform.python_version(),
            "platform": platform.platform(),
            "action_encoding": ("float32 bit patterns (uint32)"
                                if name in ("pendulum", "mountain_car_continuous")
                                else "discrete integers"),
            "episodes": episodes,
        }
        path = os.path.join(out_dir, f"{name}.json")
        with open(path, "w") as f:
            json.dump(doc, f, separators=(",", ":"))
            f.write("\n")
        n = sum(len(e["actions"]) for e in episodes)
        print(f"{path}: {len(episodes)} episodes, {n} steps, "
              f"{sum(e['terminated'][-1] for e in episodes)} terminated, "
              f"{sum(e['truncated'][-1] for e in episodes)} truncated")


if __name__ == "__main__":
    main()
