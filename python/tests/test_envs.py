"""Every runtime passes Gymnasium's env checker and keeps its observations in the declared space."""

from __future__ import annotations

import pickle
import re
import warnings

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import carl_spec as cs

RUNTIMES = list(cs.RUNTIMES)

# Advice check_env also gives Gymnasium's own CartPole and Pendulum (same spaces); anything else fails.
ADVISORY = re.compile(
    r"A Box observation space (minimum|maximum) value is (-)?infinity|"
    r"we recommend using a symmetric and normalized space"
)


def checked(env: gymnasium.Env) -> None:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_env(env, skip_render_check=True)
    unexpected = [str(w.message) for w in caught if not ADVISORY.search(str(w.message))]
    assert not unexpected, unexpected


def _a_set(env: str) -> str | None:
    """A set whose instances lie inside the spec's bounds: a visible feature's space is the
    declared bounds, which a deliberately out-of-bounds set (Landing in Space's test grid) leaves."""
    sets = cs.spec(env).instance_sets
    inside = [k for k in sorted(sets) if not dict(sets[k]).get("allow_out_of_bounds", False)]
    return f"{env}/{inside[0]}" if inside else None


@pytest.mark.parametrize("env_id", RUNTIMES)
def test_check_env_default_context(env_id: str) -> None:
    checked(cs.make(env_id))


@pytest.mark.parametrize("env_id", RUNTIMES)
def test_check_env_frozen_set_with_visible_context(env_id: str) -> None:
    """A frozen set where the spec has one, else a named distribution, else the default context;
    always with every feature visible in the observation (pixel observations become
    `{"obs": pixels, "context": features}`)."""
    iset = _a_set(env_id)
    dists = sorted(cs.spec(env_id).distributions)
    if iset is not None:
        env = cs.make(env_id, instances=iset, selection="random", obs_context=True)
    elif dists:
        env = cs.make(env_id, distribution=dists[0], obs_context=True)
    else:
        env = cs.make(env_id, obs_context=True)
    base = cs.make(env_id).observation_space
    space = env.observation_space
    if isinstance(space, gymnasium.spaces.Dict):
        assert base.dtype == np.uint8 and space["obs"] == base and space["context"].shape[0] > 0
    else:
        assert space.shape[0] > base.shape[0]
    checked(env)


# Every runtime stays in its space. Neither Box2D runtime leaves it in random-action runs any more:
# on the former rapier2d engine, LunarLander rolled on the ground spinning past ±2π (19 of 185 episodes) and
# BipedalWalker's hull flipped past ±π in the air in rare episodes (rapier's contact warm start
# threw hard landings up). On the Box2D-semantics engine (src/physics2d) a lander body contact ends
# the episode first, as in Gymnasium, and the walker stays in the space here
# (examples/bipedal_walker_flips.rs: 1 of 300 episodes reaches |angle| 3.21, against 8 of 300 up to
# 10.0 on rapier2d).
@pytest.mark.parametrize("env_id", RUNTIMES)
def test_observations_stay_in_space_and_dtypes_as_declared(env_id: str) -> None:
    env = cs.make(env_id)
    space = env.observation_space
    declared = cs.spec(env_id).runtime_spaces["observation"]["dtype"]
    assert space.dtype == np.dtype(declared)
    env.action_space.seed(0)
    obs, _ = env.reset(seed=0)
    for _ in range(1000):
        assert obs.dtype == space.dtype and obs.shape == space.shape
        assert obs in space, f"{env_id}: {obs} outside {space}"
        obs, r, term, trunc, _ = env.step(env.action_space.sample())
        assert isinstance(r, float) and isinstance(term, bool) and isinstance(trunc, bool)
        if term or trunc:
            obs, _ = env.reset()


def test_vehicle_racing_pixels_are_uint8() -> None:
    env = cs.make("vehicle_racing")
    assert env.observation_space.dtype == np.uint8
    assert env.observation_space.shape == (96, 96, 3)
    obs, _ = env.reset(seed=1)
    assert obs.dtype == np.uint8 and obs.shape == (96, 96, 3)


def test_render_rgb_array() -> None:
    env = cs.make("lunar_lander", render_mode="rgb_array")
    env.reset(seed=0)
    frame = env.render()
    assert frame is not None and frame.dtype == np.uint8 and frame.ndim == 3 and frame.shape[2] == 3
    assert frame.std() > 0
    with pytest.raises(ValueError, match="render_mode"):
        cs.make("lunar_lander", render_mode="human")
    with pytest.raises(ValueError, match="no renderer"):
        cs.make("cartpole", render_mode="rgb_array")


def test_pickle_as_constructor_arguments() -> None:
    env = cs.make("pendulum", context={"g": 9.0}, obs_context=["g"])
    clone = pickle.loads(pickle.dumps(env))
    a, _ = env.reset(seed=4)
    b, _ = clone.reset(seed=4)
    np.testing.assert_array_equal(a, b)
    assert clone.context["g"] == 9.0
    venv = cs.make_vec("cartpole", 3)
    vclone = pickle.loads(pickle.dumps(venv))
    np.testing.assert_array_equal(venv.reset(seed=1)[0], vclone.reset(seed=1)[0])


def test_gymnasium_registration() -> None:
    env = gymnasium.make("carl_spec/cartpole-v0", context={"masscart": 2.0})
    obs, _ = env.reset(seed=0)
    assert obs.shape == (4,)
    assert env.unwrapped.context["masscart"] == 2.0
    venv = gymnasium.make_vec("carl_spec/cartpole-v0", 8)
    assert isinstance(venv, cs.CarlVectorEnv)
    obs, _ = venv.reset(seed=0)
    assert obs.shape == (8, 4)


def test_unseeded_envs_differ_seeded_ones_repeat() -> None:
    a, _ = cs.make("cartpole").reset()
    b, _ = cs.make("cartpole").reset()
    assert not np.array_equal(a, b)
    c, _ = cs.make("cartpole").reset(seed=9)
    d, _ = cs.make("cartpole").reset(seed=9)
    np.testing.assert_array_equal(c, d)


def test_bad_actions_raise_value_error() -> None:
    env = cs.make("cartpole")
    env.reset(seed=0)
    with pytest.raises(ValueError, match="outside 0..2"):
        env.step(5)
    cont = cs.make("pendulum")
    cont.reset(seed=0)
    with pytest.raises(ValueError, match="component"):
        cont.step(np.zeros(3, dtype=np.float32))
    with pytest.raises(RuntimeError, match="before reset"):
        cs.make("cartpole").step(0)
