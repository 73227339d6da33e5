"""Options from Python: context noise, the runtimes' variant options, out-of-bounds permission,
float64 observations and pixel observations with visible context; in make and make_vec, pickled."""

from __future__ import annotations

import pickle

import gymnasium
import numpy as np
import pytest

import carl_spec as cs


def _episode_observed(env: cs.CarlEnv, seed: int, steps: int) -> tuple[list[float], list[float]]:
    """Observed `g` (last component) and info's observed_context over one reset and `steps` steps."""
    obs, info = env.reset(seed=seed)
    seen, reported = [float(obs[-1])], [info["observed_context"]["g"]]
    for _ in range(steps):
        obs, _, _, _, info = env.step(np.zeros(1, dtype=np.float32))
        seen.append(float(obs[-1]))
        reported.append(info["observed_context"]["g"])
    return seen, reported


def test_noise_per_episode_is_constant_within_an_episode_and_seeded() -> None:
    env = cs.make("pendulum", obs_context=["g"], context_noise={"g": 0.5})
    seen, reported = _episode_observed(env, seed=3, steps=5)
    assert seen == reported, "info['observed_context'] is what the observation shows"
    assert len(set(seen)) == 1 and seen[0] != 10.0, seen
    again, _ = _episode_observed(cs.make("pendulum", obs_context=["g"], context_noise={"g": 0.5}), seed=3, steps=5)
    assert again == seen, "reset(seed) determines the noise"
    other, _ = _episode_observed(env, seed=4, steps=0)
    assert other[0] != seen[0]
    _, info = env.reset(seed=3)
    assert info["context"]["g"] == 10.0, "the dynamics keep the true value"
    # Many episodes: the noise has about the requested spread around the true value.
    draws = [env.reset(seed=s)[0][-1] for s in range(400)]
    assert abs(np.mean(draws) - 10.0) < 0.1 and 0.4 < np.std(draws) < 0.6


def test_noise_per_step_and_relative_std() -> None:
    env = cs.make("pendulum", obs_context=["g"], context_noise={"g": "10%"}, context_noise_redraw="step")
    seen, reported = _episode_observed(env, seed=1, steps=50)
    assert seen == reported
    assert len(set(seen)) == len(seen), "a fresh draw every step"
    assert 0.6 < np.std(seen) < 1.5, "10 % of |default| = 1.0"


def test_noise_in_make_vec_and_its_space() -> None:
    venv = cs.make_vec("pendulum", 4, obs_context=["g"], context_noise={"g": 0.5})
    assert venv.single_observation_space.high[-1] == np.inf, "a noisy feature is unbounded"
    obs, _ = venv.reset(seed=0)
    assert len(set(obs[:, -1].tolist())) == 4 and not np.any(obs[:, -1] == 10.0)
    single = cs.make("pendulum", obs_context=["g"], context_noise={"g": 0.5})
    for i in range(4):
        np.testing.assert_array_equal(single.reset(seed=i)[0], obs[i])


def test_bad_noise_is_refused_with_its_reason() -> None:
    with pytest.raises(ValueError, match="obs_context"):
        cs.make("pendulum", context_noise={"g": 0.5})
    with pytest.raises(ValueError, match="not observed"):
        cs.make("pendulum", obs_context=["m"], context_noise={"g": 0.5})
    with pytest.raises(ValueError, match="percentage"):
        cs.make("pendulum", obs_context=["g"], context_noise={"g": "ten"})
    with pytest.raises(ValueError, match=">= 0"):
        cs.make("pendulum", obs_context=["g"], context_noise={"g": -1.0})
    with pytest.raises(ValueError, match="did you mean"):
        cs.make("pendulum", obs_context=["g"], context_noise={"gg": 1.0})
    with pytest.raises(ValueError, match="redraw"):
        cs.make("pendulum", obs_context=["g"], context_noise={"g": 1.0}, context_noise_redraw="sometimes")


def test_variant_options() -> None:
    discrete = cs.make("lunar_lander")
    cont = cs.make("lunar_lander", options={"continuous": True})
    assert isinstance(discrete.action_space, gymnasium.spaces.Discrete)
    assert isinstance(cont.action_space, gymnasium.spaces.Box) and cont.action_space.shape == (2,)
    cont.reset(seed=0)
    cont.step(np.array([0.5, -0.5], dtype=np.float32))
    venv = cs.make_vec("lunar_lander", 2, options={"continuous": True})
    assert venv.single_action_space.shape == (2,)
    venv.reset(seed=0)
    venv.step(np.zeros((2, 2), dtype=np.float32))
    walker = cs.make("bipedal_walker", options={"hardcore": True})
    walker.reset(seed=0)
    walker.step(np.zeros(4, dtype=np.float32))
    with pytest.raises(ValueError, match="hardcore needs true or false"):
        cs.make("bipedal_walker", options={"hardcore": 2})


def test_bad_options_are_refused_with_the_valid_ones() -> None:
    with pytest.raises(cs.UnknownNameError, match="valid options: continuous, crash_penalty"):
        cs.make("lunar_lander", options={"continous": True})
    with pytest.raises(cs.UnknownNameError, match="takes no options"):
        cs.make_vec("cartpole", 2, options={"continuous": True})
    # The removed rapier2d walker engine's option is refused like any unknown one.
    with pytest.raises(cs.UnknownNameError, match='no option "rapier"; valid options: hardcore'):
        cs.make("bipedal_walker", options={"rapier": True})
    with pytest.raises(ValueError, match="true or false"):
        cs.make("lunar_lander", options={"continuous": 3})
    with pytest.raises(ValueError, match="options must be a dict"):
        cs.make("lunar_lander", options=["continuous"])  # type: ignore[arg-type]


def test_out_of_bounds_needs_explicit_permission() -> None:
    for build in (lambda **kw: cs.make("cartpole", **kw), lambda **kw: cs.make_vec("cartpole", 3, **kw)):
        with pytest.raises(ValueError) as err:
            build(context={"masscart": 1e6})
        message = str(err.value)
        assert "masscart" in message and "outside its bounds [" in message and "allow_out_of_bounds=True" in message
        env = build(context={"masscart": 1e6}, allow_out_of_bounds=True)
        env.reset(seed=0)
    env = cs.make("cartpole", context={"masscart": 1e6}, allow_out_of_bounds=True)
    env.reset(seed=0)
    assert env.context["masscart"] == 1e6
    with pytest.raises(ValueError, match="True or False"):
        cs.make("cartpole", allow_out_of_bounds="yes")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="fixed context"):
        cs.make("pendulum", distribution="q1_g_sigma_0_5", allow_out_of_bounds=True)


def test_new_arguments_pickle_with_the_constructor() -> None:
    env = cs.make(
        "lunar_lander",
        context={"GRAVITY_Y": -20.0},
        allow_out_of_bounds=True,
        obs_context=["GRAVITY_Y"],
        context_noise={"GRAVITY_Y": "5%"},
        context_noise_redraw="step",
        options={"continuous": True},
    )
    clone = pickle.loads(pickle.dumps(env))
    a, ia = env.reset(seed=2)
    b, ib = clone.reset(seed=2)
    np.testing.assert_array_equal(a, b)
    assert ia == ib and ia["context"]["GRAVITY_Y"] == -20.0
    act = np.array([0.2, 0.1], dtype=np.float32)
    np.testing.assert_array_equal(env.step(act)[0], clone.step(act)[0])
    venv = cs.make_vec("lunar_lander", 2, options={"continuous": True}, obs_context=["GRAVITY_Y"], context_noise={"GRAVITY_Y": 1.0})
    vclone = pickle.loads(pickle.dumps(venv))
    np.testing.assert_array_equal(venv.reset(seed=5)[0], vclone.reset(seed=5)[0])
    assert vclone.single_action_space.shape == (2,)


def test_float64_observations_carry_float64_values() -> None:
    """Humanoid's centre-of-mass terms are computed in float64 (its positions and velocities come
    from rapier's float32 world, so they are float32 values in a float64 array)."""
    env_id = "humanoid"
    env = cs.make(env_id)
    assert env.observation_space.dtype == np.float64
    venv = cs.make_vec(env_id, 2, autoreset_mode="same_step")
    obs, _ = env.reset(seed=7)
    vobs, _ = venv.reset(seed=7)
    np.testing.assert_array_equal(vobs[0], obs)
    env.action_space.seed(0)
    finer = 0
    for _ in range(3):
        a = env.action_space.sample()
        obs, *_ = env.step(a)
        vobs, *_ = venv.step(np.stack([a, a]))
        assert obs.dtype == np.float64 and vobs.dtype == np.float64
        np.testing.assert_array_equal(vobs[0], obs)
        finer += int(np.sum(obs.astype(np.float32).astype(np.float64) != obs))
    assert finer > 0, "values finer than float32 reach Python"


def test_pixels_with_visible_context_are_a_dict() -> None:
    env = cs.make("vehicle_racing", obs_context=True)
    space = env.observation_space
    assert isinstance(space, gymnasium.spaces.Dict)
    assert space["obs"].dtype == np.uint8 and space["obs"].shape == (96, 96, 3)
    assert space["context"].dtype == np.float32
    obs, info = env.reset(seed=0)
    assert obs in space
    names = env.unwrapped._core.visible_features
    np.testing.assert_array_equal(obs["context"], np.array([info["context"][n] for n in names], dtype=np.float32))
    venv = cs.make_vec("vehicle_racing", 2, obs_context=True, autoreset_mode="same_step")
    vobs, _ = venv.reset(seed=0)
    assert vobs["obs"].shape == (2, 96, 96, 3) and vobs["obs"].dtype == np.uint8
    assert vobs["context"].shape == (2, len(venv.single_observation_space["context"].low))


def test_goal_option_of_the_walkers() -> None:
    # Without the option the goal features are refused away from their defaults, naming it.
    with pytest.raises(ValueError, match="acts only with option goal"):
        cs.make("hopper", context={"target_radius": 1.0})
    cs.make("hopper", context={"target_radius": 5.0})  # the default is no change
    env = cs.make("half_cheetah", options={"goal": True}, context={"target_distance": 2.0, "target_direction": 2})
    obs, info = env.reset(seed=0)
    assert info["goal_direction"] == "east" and info["success"] == 0
    assert abs(info["goal_distance"] - 2.0) < 1e-12 and info["goal_position"] == [2.0, 0.0]
    plain = cs.make("half_cheetah")
    plain_obs, plain_info = plain.reset(seed=0)
    assert np.array_equal(obs, plain_obs) and "goal_distance" not in plain_info
    before = info["goal_distance"]
    for _ in range(50):
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        assert reward == pytest.approx(max(0.0, before - info["goal_distance"]), abs=1e-12)
        before = info["goal_distance"]
        assert info["success"] == int(terminated)
        if terminated:
            break
    with pytest.raises(ValueError, match="target_direction = 5 is outside its bounds choices"):
        cs.make("ant", options={"goal": True}, context={"target_direction": 5})
