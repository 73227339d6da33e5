"""Hostile input through the Python API (issue 31): each reproduction of the issue as a test.
Non-finite outputs and actions, sizes and seeds, messages that name what is wrong, Ctrl-C in long
native calls, and one vector env used by two threads."""

from __future__ import annotations

import math
import os
import signal
import threading
import time
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest

import carl_spec as cs

# -- item 3: no silent NaN/inf ------------------------------------------------------------------


@pytest.mark.parametrize("bad", [[math.nan], [math.inf], [-math.inf], np.array([np.nan], dtype=np.float32)])
def test_non_finite_action_refused(bad: Any) -> None:
    env = cs.make("pendulum")
    env.reset(seed=0)
    with pytest.raises(ValueError, match="component 0 is .*finite"):
        env.step(bad)
    # The env is not poisoned: a good action still steps with finite outputs.
    obs, reward, *_ = env.step([0.5])
    assert np.isfinite(obs).all() and math.isfinite(float(reward))


@pytest.mark.parametrize("bad", [None, [None], "0.5", ["a"], [True], object()])
def test_box_action_of_no_numbers_refused(bad: Any) -> None:
    env = cs.make("pendulum")
    env.reset(seed=0)
    with pytest.raises(cs.InvalidActionError, match="pendulum"):
        env.step(bad)


@pytest.mark.parametrize("env_id", ["mountain_car_continuous", "pendulum"])
def test_huge_finite_action_is_clipped_to_the_space(env_id: str) -> None:
    a, b = cs.make(env_id), cs.make(env_id)
    a.reset(seed=3)
    b.reset(seed=3)
    high = b.action_space.high
    for _ in range(5):
        oa, ra, *_ = a.step([1e300])
        ob, rb, *_ = b.step(high)
        assert math.isfinite(float(ra))
        np.testing.assert_array_equal(oa, ob)
        assert ra == rb


def test_non_finite_observation_is_an_error_naming_the_step() -> None:
    env = cs.make("cartpole", context={"gravity": 1e30})
    with pytest.raises(ValueError, match=r"cartpole step \d+: the environment produced a non-finite (observation component \d+|reward)"):
        env.reset(seed=0)
        for _ in range(500):
            if any(env.step(0)[2:4]):
                env.reset()


def test_non_finite_observation_in_a_batch_names_the_environment() -> None:
    venv = cs.make_vec("cartpole", 2, context={"gravity": 1e30})
    venv.reset(seed=0)
    with pytest.raises(ValueError, match=r"cartpole environment \d, step \d+: the environment produced a non-finite"):
        for _ in range(500):
            venv.step(np.zeros(2, dtype=np.int64))


@pytest.mark.parametrize("std", [1e308, math.inf, math.nan, -1.0, "1e308%"])
def test_overflowing_context_noise_refused_at_construction(std: Any) -> None:
    with pytest.raises(ValueError, match="context_noise"):
        cs.make("pendulum", obs_context=["g"], context_noise={"g": std})
    with pytest.raises(ValueError, match="context_noise"):
        cs.make_vec("pendulum", 2, obs_context=["g"], context_noise={"g": std})


def test_vector_non_finite_and_huge_actions() -> None:
    venv = cs.make_vec("mountain_car_continuous", 2)
    venv.reset(seed=0)
    for bad in ([[math.nan], [0.0]], [[0.0], [math.inf]]):
        with pytest.raises(ValueError, match="action of environment \\d component 0 is .*finite"):
            venv.step(np.array(bad))
    _, rewards, *_ = venv.step(np.array([[1e300], [-1e300]]))
    assert np.isfinite(rewards).all()


# -- item 5: sizes bounded as the CLI's bench bounds them ---------------------------------------


def test_make_vec_sizes_bounded_and_named() -> None:
    with pytest.raises(ValueError, match=r"num_envs=1000000000 is outside 1..=65536"):
        cs.make_vec("cartpole", 10**9)
    with pytest.raises(ValueError, match=r"num_envs=5000 is outside 1..=4096 for ant"):
        cs.make_vec("ant", 5000)
    with pytest.raises(ValueError, match=r"threads=1000000 is outside 1..=256"):
        cs.make_vec("cartpole", 2, threads=10**6)


@pytest.mark.parametrize("kwargs", [dict(num_envs=-1), dict(num_envs=2, threads=-1), dict(num_envs=2, threads=0), dict(num_envs=0)])
def test_negative_sizes_are_value_errors_naming_the_argument(kwargs: dict[str, int]) -> None:
    name = "threads" if "threads" in kwargs else "num_envs"
    with pytest.raises(ValueError, match=name) as e:
        cs.make_vec("cartpole", **kwargs)
    assert not isinstance(e.value, OverflowError)


def test_negative_instance_and_n_are_value_errors() -> None:
    with pytest.raises(ValueError, match="instance"):
        cs.make("pendulum", instances="q1_dt_sigma_0_1", selection="static", instance=-1)
    with pytest.raises(ValueError, match="n=-1"):
        cs.sample("pendulum", distribution="q1_dt_sigma_0_1", n=-1, seed=0)
    with pytest.raises(ValueError, match="seed"):
        cs.sample("pendulum", distribution="q1_dt_sigma_0_1", n=1, seed=-1)


# -- item 6: long native calls return to Ctrl-C -------------------------------------------------


@pytest.fixture
def sigint_raises() -> Iterator[None]:
    """SIGINT raising KeyboardInterrupt in the main thread for the test. Python installs that
    handler only where its parent left SIGINT at its default: a run started with SIGINT ignored
    (a background job of a shell without job control) would otherwise wait forever."""
    if threading.current_thread() is not threading.main_thread():
        pytest.skip("signals reach the main thread only")
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def test_native_steps_return_to_ctrl_c(sigint_raises: None) -> None:
    venv = cs.make_vec("cartpole", 64)
    venv.reset(seed=0)
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    t0 = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            venv._core.native_steps([np.zeros(64, dtype=np.int64)], 10**12)
    finally:
        timer.cancel()
    assert time.monotonic() - t0 < 5.0


def test_a_make_vec_step_returns_to_ctrl_c_on_every_thread(sigint_raises: None) -> None:
    """rna_design's last step of seed 6's episode (25 sites, actions from default_rng(6)) folds
    for seconds; both envs of a 2-thread batch do it, one on the worker thread: the worker must
    stop too (it used to finish its folds: 9.7 s instead of 0.3 s)."""
    rng = np.random.default_rng(6)
    actions = [int(rng.integers(0, 4)) for _ in range(25)]
    venv = cs.make_vec("rna_design", 2, threads=2, context={"mutation_threshold": 10})
    venv.reset(seed=[6, 6])
    for a in actions[:-1]:
        _, _, term, trunc, _ = venv.step(np.array([a, a]))
        assert not (term.any() or trunc.any())
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    t0 = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            venv.step(np.array([actions[-1]] * 2))
    finally:
        timer.cancel()
    assert time.monotonic() - t0 < 2.0
    with pytest.raises(RuntimeError, match="reset"):
        venv.step(np.array([0, 0]))
    venv.reset(seed=0)
    venv.step(np.array([0, 0]))


# -- item 9: make_vec refuses what cs.make refuses ----------------------------------------------


@pytest.mark.parametrize(
    "actions",
    [np.array([0.5, 0.5]), np.array([1.0, 0.0]), ["a", "b"], np.array([True, False]), np.zeros(3, dtype=np.int64), np.zeros((2, 1), dtype=np.int64), [None, None]],
)
def test_make_vec_discrete_actions_checked_as_make_does(actions: Any) -> None:
    venv = cs.make_vec("cartpole", 2)
    venv.reset(seed=0)
    with pytest.raises(cs.InvalidActionError, match="cartpole"):
        venv.step(actions)


@pytest.mark.parametrize("actions", [np.zeros((2, 2)), np.zeros(3), ["a", "b"], [[None], [None]]])
def test_make_vec_box_actions_checked_as_make_does(actions: Any) -> None:
    venv = cs.make_vec("pendulum", 2)
    venv.reset(seed=0)
    with pytest.raises(cs.InvalidActionError, match="pendulum"):
        venv.step(actions)


def test_make_vec_box_actions_of_right_shape_pass() -> None:
    venv = cs.make_vec("pendulum", 2)
    venv.reset(seed=0)
    venv.step(np.zeros((2, 1), dtype=np.float32))
    venv.step(np.zeros(2))  # one component: (num_envs,) as SyncVectorEnv takes it
    venv.step([[0], [1]])


@pytest.mark.parametrize("seed", [2**64, -1, 1.0, np.int64(3), "1"])
def test_seeds_follow_gymnasiums_rule(seed: Any) -> None:
    env = cs.make("cartpole")
    venv = cs.make_vec("cartpole", 2)
    for reset in (env.reset, venv.reset):
        with pytest.raises(ValueError, match="seed"):
            reset(seed=seed)


def test_largest_seed() -> None:
    cs.make("cartpole").reset(seed=2**64 - 1)
    cs.make_vec("cartpole", 1).reset(seed=2**64 - 1)
    # Environment i gets seed + i: the last one would wrap to 0.
    with pytest.raises(ValueError, match="last environment's seed"):
        cs.make_vec("cartpole", 2).reset(seed=2**64 - 1)


def test_seed_lists_follow_the_rule() -> None:
    venv = cs.make_vec("cartpole", 2)
    with pytest.raises(ValueError, match=r"seed\[1\]"):
        venv.reset(seed=[0, -1])
    venv.reset(seed=[0, None])


# -- item 13: messages name the feature, quote input escaped and cut ----------------------------


@pytest.mark.parametrize("value", [math.nan, math.inf, None, 10**400])
@pytest.mark.parametrize("make", [cs.make, lambda e, **k: cs.make_vec(e, 2, **k)])
def test_bad_context_values_name_the_feature(make: Any, value: Any) -> None:
    with pytest.raises(ValueError, match=r'context\["gravity"\]'):
        make("cartpole", context={"gravity": value})


def test_unknown_names_are_quoted_escaped_and_cut() -> None:
    for kwargs in (
        dict(context={"x" * 100_000: 1.0}),
        dict(instances="x" * 100_000),
        dict(distribution="\x1b[31mred"),
        dict(obs_context=["\x1b[31mred"]),
    ):
        with pytest.raises(cs.UnknownNameError) as e:
            cs.make("cartpole", **kwargs)
        text = str(e.value)
        assert len(text) < 2_000 and "\x1b" not in text, text[:200]
    with pytest.raises(ValueError) as e2:
        cs.make("pendulum", instances="q1_dt_sigma_0_1", selection="\x1b" + "s" * 10_000)
    assert len(str(e2.value)) < 2_000 and "\x1b" not in str(e2.value)


def test_two_threads_on_one_vector_env_get_a_clear_error() -> None:
    venv = cs.make_vec("cartpole", 64)
    venv.reset(seed=0)
    acts = np.zeros(64, dtype=np.int64)
    errors: list[BaseException] = []

    def busy() -> None:
        try:
            venv._core.native_steps([acts], 2_000_000)
        except BaseException as e:  # noqa: BLE001
            errors.append(e)

    t = threading.Thread(target=busy)
    t.start()
    time.sleep(0.2)
    try:
        with pytest.raises(RuntimeError, match="being used by another thread"):
            for _ in range(1000):
                venv.step(acts)
    finally:
        t.join()
    assert not errors


def test_spec_queries_quote_unknown_names() -> None:
    for call in (
        lambda: cs.spec("x" * 100_000),
        lambda: cs.instances.load("\x1b[2J" + "y" * 300),
        lambda: cs.sample("pendulum", distribution="\x1b[2J", n=1, seed=0),
        lambda: cs.make_vec("\x07" * 5, 2),
    ):
        with pytest.raises(cs.UnknownNameError) as e:
            call()
        assert len(str(e.value)) < 2_000 and "\x1b" not in str(e.value) and "\x07" not in str(e.value)
