"""Parity: carl-spec equals Gymnasium 1.4 on the classic five (reset states for the same seed,
then every step), make_vec equals N make, and make equals `carl-spec rollout`."""

from __future__ import annotations

import json
from pathlib import Path

import gymnasium
import numpy as np
import pytest

import carl_spec as cs
from conftest import CLASSIC, cli

GYM_IDS = {
    "cartpole": "CartPole-v1",
    "pendulum": "Pendulum-v1",
    "mountain_car": "MountainCar-v0",
    "mountain_car_continuous": "MountainCarContinuous-v0",
    "acrobot": "Acrobot-v1",
}


@pytest.mark.parametrize("env_id", CLASSIC)
@pytest.mark.parametrize("seed", [0, 1, 42, 2**40 + 3])
def test_reset_state_equals_gymnasium(env_id: str, seed: int) -> None:
    ours, _ = cs.make(env_id).reset(seed=seed)
    theirs, _ = gymnasium.make(GYM_IDS[env_id]).reset(seed=seed)
    assert ours.dtype == theirs.dtype
    np.testing.assert_array_equal(ours, theirs)


@pytest.mark.parametrize("env_id", CLASSIC)
def test_episodes_equal_gymnasium_step_for_step(env_id: str) -> None:
    """Three episodes after one seeded reset (later resets unseeded, continuing the stream), with
    the same random actions: observations, rewards and flags identical."""
    ours = cs.make(env_id)
    theirs = gymnasium.make(GYM_IDS[env_id])
    space = theirs.action_space
    space.seed(5)
    a, _ = ours.reset(seed=123)
    b, _ = theirs.reset(seed=123)
    episodes, steps = 0, 0
    while episodes < 3 and steps < 3000:
        np.testing.assert_array_equal(a, b)
        action = space.sample()
        a, ra, ta, ua, _ = ours.step(action)
        b, rb, tb, ub, _ = theirs.step(action)
        steps += 1
        assert (float(ra), ta, ua) == (float(rb), tb, ub), f"step {steps}"
        if ta or ua:
            np.testing.assert_array_equal(a, b)
            a, _ = ours.reset()
            b, _ = theirs.reset()
            episodes += 1
    assert episodes >= 1


@pytest.mark.parametrize("env_id", ["cartpole", "pendulum", "lunar_lander", "acrobot"])
def test_make_vec_equals_n_make(env_id: str) -> None:
    n, seed = 4, 11
    venv = cs.make_vec(env_id, n, autoreset_mode="same_step")
    envs = [cs.make(env_id) for _ in range(n)]
    obs, _ = venv.reset(seed=seed)
    singles = [e.reset(seed=seed + i)[0] for i, e in enumerate(envs)]
    np.testing.assert_array_equal(obs, np.stack(singles))
    venv.action_space.seed(3)
    for _ in range(600):
        actions = venv.action_space.sample()
        obs, rew, term, trunc, infos = venv.step(actions)
        for i, e in enumerate(envs):
            o, r, t, u, _ = e.step(actions[i])
            assert (r, t, u) == (rew[i], term[i], trunc[i])
            if t or u:
                np.testing.assert_array_equal(infos["final_obs"][i], o)
                o, _ = e.reset()
            np.testing.assert_array_equal(obs[i], o)


@pytest.mark.parametrize("env_id", ["cartpole", "mountain_car_continuous", "lunar_lander"])
def test_make_equals_cli_rollout(env_id: str, tmp_path: Path) -> None:
    env = cs.make(env_id, context=None)
    env.action_space.seed(2)
    actions = [env.action_space.sample() for _ in range(150)]
    as_json = [int(a) if np.ndim(a) == 0 else [float(x) for x in a] for a in actions]
    (tmp_path / "actions.json").write_text(json.dumps(as_json))
    lines = [json.loads(l) for l in cli("rollout", env_id, "--seed", "8", "--actions", str(tmp_path / "actions.json")).splitlines()]
    obs, _ = env.reset(seed=8)
    np.testing.assert_array_equal(obs, np.array(lines[0]["reset"]["obs"], dtype=np.float32))
    for line, action in zip(lines[1:], as_json):
        obs, r, t, u, _ = env.step(action if isinstance(action, int) else np.array(action, dtype=np.float32))
        np.testing.assert_array_equal(obs, np.array(line["obs"], dtype=np.float32))
        assert (r, t, u) == (line["reward"], line["terminated"], line["truncated"])
