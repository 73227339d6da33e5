"""What Gymnasium users rely on (issues 29 and 31): the episode limit in the env's spec with
truncation exactly once, the `module:id` form, environments shipped to worker processes
(AsyncVectorEnv under spawn and forkserver), action types, `close()`, episode statistics."""

from __future__ import annotations

import pickle
import subprocess
import sys
from typing import Any

import cloudpickle
import gymnasium
import numpy as np
import pytest
from gymnasium.error import ClosedEnvironmentError

import carl_spec as cs

# -- the episode limit -----------------------------------------------------------------------


@pytest.mark.parametrize("env_id", cs.RUNTIMES)
def test_gymnasium_make_states_the_spec_episode_limit(env_id: str) -> None:
    limit = cs.spec(env_id).max_episode_steps
    env = gymnasium.make(cs.gym_id(env_id))
    assert env.spec is not None and env.spec.max_episode_steps == limit
    assert env.unwrapped.spec is not None and env.unwrapped.spec.max_episode_steps == limit
    assert env.unwrapped._core.max_episode_steps == limit  # what the runtime truncates at
    # No TimeLimit on top: the runtime truncates itself (one wrapper layer less per step).
    layer: Any = env
    while isinstance(layer, gymnasium.Wrapper):
        assert not isinstance(layer, gymnasium.wrappers.TimeLimit)
        layer = layer.env
    env.close()


def pendulum_actions(n: int) -> list[np.ndarray]:
    return [np.array([((t * 7) % 5 - 2) * 0.9], dtype=np.float32) for t in range(n)]


def test_truncation_comes_once_at_the_limit_exactly_as_cs_make() -> None:
    # Pendulum never terminates: every episode ends by truncation at the spec's 200 steps, once
    # (the runtime truncates, no TimeLimit on top), exactly as cs.make's env, episode after episode.
    limit = cs.spec("pendulum").max_episode_steps
    assert limit == 200
    ours, ref = gymnasium.make("carl_spec/pendulum-v0"), cs.make("pendulum")
    for seed in (1, 2):
        a, _ = ours.reset(seed=seed)
        b, _ = ref.reset(seed=seed)
        np.testing.assert_array_equal(a, b)
        for t, action in enumerate(pendulum_actions(limit), start=1):
            o1, r1, term1, trunc1, _ = ours.step(action)
            o2, r2, term2, trunc2, _ = ref.step(action)
            np.testing.assert_array_equal(o1, o2)
            assert (r1, term1, trunc1) == (r2, term2, trunc2) == (r2, False, t == limit)


def test_a_shorter_limit_from_gymnasium_make_truncates_there() -> None:
    env = gymnasium.make("carl_spec/pendulum-v0", max_episode_steps=50)
    assert env.spec is not None and env.spec.max_episode_steps == 50
    for seed in (0, 1):
        env.reset(seed=seed)
        flags = [env.step(a)[3] for a in pendulum_actions(50)]
        assert flags == [False] * 49 + [True]


def test_vector_entry_point_truncates_at_the_limit_and_refuses_another() -> None:
    venv = gymnasium.make_vec("carl_spec/pendulum-v0", 2, vectorization_mode="vector_entry_point")
    assert isinstance(venv, cs.CarlVectorEnv)
    venv.reset(seed=0)
    for t in range(1, 201):
        _, _, term, trunc, _ = venv.step(np.zeros((2, 1), dtype=np.float32))
        assert not term.any() and trunc.all() == (t == 200) and trunc.any() == (t == 200)
    with pytest.raises(ValueError, match=r"limit \(200 steps\); max_episode_steps=50 is not supported.*'sync'"):
        gymnasium.make_vec("carl_spec/pendulum-v0", 2, vectorization_mode="vector_entry_point", max_episode_steps=50)
    assert cs.make_vec("pendulum", 2, max_episode_steps=200).num_envs == 2
    sync = gymnasium.make_vec("carl_spec/pendulum-v0", 2, vectorization_mode="sync", max_episode_steps=50)
    sync.reset(seed=0)
    flags = [sync.step(np.zeros((2, 1), dtype=np.float32))[3].all() for _ in range(50)]
    assert flags == [False] * 49 + [True]


def fresh(code: str) -> str:
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return r.stdout.strip().splitlines()[-1]


def test_module_prefixed_id_needs_no_import() -> None:
    # CleanRL-style scripts call gymnasium.make(env_id) and import nothing else.
    out = fresh(
        "import gymnasium, sys\n"
        "assert 'carl_spec' not in sys.modules\n"
        "env = gymnasium.make('carl_spec:carl_spec/cartpole-v0')\n"
        "obs, _ = env.reset(seed=0)\n"
        "venv = gymnasium.make_vec('carl_spec:carl_spec/cartpole-v0', 2, vectorization_mode='sync')\n"
        "vobs, _ = venv.reset(seed=0)\n"
        "print(type(env.unwrapped).__name__, env.spec.id, env.spec.max_episode_steps, obs.shape, vobs.shape)"
    )
    assert out == "CarlEnv carl_spec/cartpole-v0 500 (4,) (2, 4)"


# -- shipping environments to worker processes --------------------------------------------


def test_the_package_pickles_by_reference() -> None:
    # cloudpickle ships a lambda's globals; the package must be a plain module for that (a module
    # subclass fails with "cannot pickle '_Package' object", issue 31 item 4).
    fn = pickle.loads(cloudpickle.dumps(lambda: cs.make("cartpole", context={"masscart": 2.0})))
    assert fn().context["masscart"] == 2.0
    assert pickle.loads(cloudpickle.dumps(cs)) is cs


def test_an_env_pickles_as_a_fresh_env_of_the_same_arguments() -> None:
    # What holds for a CarlEnv instance: it pickles as its constructor arguments, so the copy is
    # a new environment (reset it); the episode in progress is not carried over.
    env = cs.make("cartpole", context={"masscart": 2.0})
    env.reset(seed=3)
    env.step(1)
    for dumps in (pickle.dumps, cloudpickle.dumps):
        clone = pickle.loads(dumps(env))
        assert clone.context["masscart"] == 2.0
        with pytest.raises(RuntimeError, match="before reset"):
            clone.step(0)
        np.testing.assert_array_equal(clone.reset(seed=3)[0], cs.make("cartpole", context={"masscart": 2.0}).reset(seed=3)[0])
    wrapped = gymnasium.make("carl_spec/cartpole-v0")
    assert pickle.loads(pickle.dumps(wrapped)).spec.max_episode_steps == 500
    assert pickle.loads(pickle.dumps(wrapped.unwrapped)).spec == wrapped.unwrapped.spec


def run(venv: Any, steps: int) -> list[tuple[Any, ...]]:
    obs, _ = venv.reset(seed=11)
    out: list[tuple[Any, ...]] = [(obs,)]
    for t in range(steps):
        o, r, term, trunc, _ = venv.step(np.array([t % 2, (t // 3) % 2]))
        out.append((o, r, term, trunc))
    return out


@pytest.mark.parametrize("context", ["spawn", "forkserver"])
def test_async_vector_env_ships_make_lambdas(context: str) -> None:
    venv = gymnasium.vector.AsyncVectorEnv([lambda: cs.make("cartpole") for _ in range(2)], context=context)
    try:
        ours = run(venv, 60)
    finally:
        venv.close()
    ref = run(gymnasium.vector.SyncVectorEnv([lambda: cs.make("cartpole") for _ in range(2)]), 60)
    for a, b in zip(ours, ref, strict=True):
        for x, y in zip(a, b, strict=True):
            np.testing.assert_array_equal(x, y)


# -- actions -----------------------------------------------------------------------------------


def test_discrete_actions_are_ints_never_bools_floats_or_arrays() -> None:
    env = cs.make("cartpole")
    env.reset(seed=0)
    for ok in (1, np.int64(1), np.uint8(0), np.array(1), np.array(0, dtype=np.int32)):
        env.step(ok)
    env.reset(seed=0)
    for bad, why in [
        (True, "bool True"),
        (np.True_, "bool True"),
        (1.0, "float 1.0"),
        (np.float32(1.0), "float32"),
        (np.array([1]), r"shape \(1,\)"),
        (np.array([[0]]), r"shape \(1, 1\)"),
        ("1", "str"),
        (None, "NoneType"),
    ]:
        with pytest.raises(cs.InvalidActionError, match=f"cartpole: a Discrete\\(2\\) action is an int.*{why}"):
            env.step(bad)
        # Both a ValueError and a TypeError: either `except` works.
        with pytest.raises(ValueError):
            env.step(bad)
        with pytest.raises(TypeError):
            env.step(bad)
    for out_of_range in (2, -1, 2**63, 2**70):
        with pytest.raises(ValueError, match="cartpole"):
            env.step(out_of_range)
    env.step(0)  # the refused actions changed nothing


def test_gymnasium_make_env_refuses_the_same_actions() -> None:
    env = gymnasium.make("carl_spec/cartpole-v0")
    env.reset(seed=0)
    with pytest.raises(cs.InvalidActionError):
        env.step(True)
    with pytest.raises(cs.InvalidActionError):
        env.step(np.array([1]))


# -- close -------------------------------------------------------------------------------------


@pytest.mark.parametrize("env_id", ["cartpole", "rna_design"])
def test_a_closed_vector_env_stops(env_id: str) -> None:
    # rna_design steps in Python (episode-end infos); cartpole binds the native step directly.
    venv = cs.make_vec(env_id, 2)
    venv.reset(seed=0)
    venv.step(venv.action_space.sample())
    venv.close()
    assert venv.closed
    with pytest.raises(ClosedEnvironmentError, match=f"make_vec\\('{env_id}', 2\\) is closed"):
        venv.step(venv.action_space.sample())
    with pytest.raises(ClosedEnvironmentError, match="is closed"):
        venv.reset(seed=0)
    with pytest.raises(ClosedEnvironmentError, match="is closed"):
        venv.context_info(0)
    venv.close()  # twice is fine
    # A pickled closed env is its constructor arguments: a new, open batch.
    again = pickle.loads(pickle.dumps(venv))
    again.reset(seed=0)
    again.close()


# -- episode statistics ----------------------------------------------------------------------


def test_no_episode_key_of_our_own_record_episode_statistics_adds_it() -> None:
    # carl-spec's infos never hold "episode": Gymnasium's RecordEpisodeStatistics (CleanRL's
    # source of episodic returns) owns that key and refuses an info that already has it.
    env = gymnasium.wrappers.RecordEpisodeStatistics(cs.make("cartpole"))
    env.reset(seed=0)
    total, steps = 0.0, 0
    while True:
        _, r, term, trunc, info = env.step(steps % 2)
        total, steps = total + float(r), steps + 1
        if term or trunc:
            break
        assert "episode" not in info
    assert info["episode"]["l"] == steps and info["episode"]["r"] == total
    venv = gymnasium.wrappers.vector.RecordEpisodeStatistics(cs.make_vec("cartpole", 3))
    venv.reset(seed=0)
    seen = False
    for t in range(200):
        _, _, term, trunc, infos = venv.step(np.array([t % 2] * 3))
        if "episode" in infos:
            seen = True
            done = term | trunc
            np.testing.assert_array_equal(infos["_episode"], done)
            assert (infos["episode"]["l"][done] > 0).all()
    assert seen


# -- set_state, duplicate feature names ----------------------------------------------------


def test_set_state_before_reset_steps_under_the_current_context() -> None:
    # Issue 31 item 13: stepping after set_state without a reset raised KeyError('context').
    state = [0.01, -0.02, 0.03, 0.04]
    env = cs.make("cartpole", context={"masscart": 2.0})
    env.set_state(state)
    ref = cs.make("cartpole", context={"masscart": 2.0})
    ref.reset(seed=0)
    ref.set_state(state)
    a, b = env.step(1), ref.step(1)
    np.testing.assert_array_equal(a[0], b[0])
    assert a[1:4] == b[1:4] and a[4] == b[4] and a[4]["context"]["masscart"] == 2.0
    sets = cs.make("pendulum", instances="pendulum/q1_l_sigma_0_5")
    sets.set_state([0.5, 0.0])
    assert sets.step([0.0])[4]["instance_id"] == 0
    with pytest.raises(ValueError, match="state"):
        cs.make("cartpole").set_state([0.0])


@pytest.mark.parametrize("make", [cs.make, lambda env, **kw: cs.make_vec(env, 2, **kw)])
def test_a_feature_given_by_alias_and_name_is_refused(make: Any) -> None:
    # Issue 31 item 13: {"length": 0.7, "pole_length": 0.9} silently took one of them.
    assert make("cartpole", context={"length": 0.7}) is not None
    with pytest.raises(ValueError, match='gives feature pole_length twice, as "length" and "pole_length"'):
        make("cartpole", context={"length": 0.7, "pole_length": 0.9})
    with pytest.raises(ValueError, match="gives feature pole_length twice"):
        make("cartpole", context={"pole_length": 0.9, "length": 0.9})
