"""Contexts: fixed, frozen sets (selection modes), distributions; refusals name the valid options;
environments with different contexts never interfere."""

from __future__ import annotations

import numpy as np
import pytest

import carl_spec as cs

SET = "pendulum/q1_g_sigma_0_5"


def _ids(env: cs.CarlEnv, n: int, seed: int | None = None) -> list[int]:
    out = [env.reset(seed=seed)[1]["instance_id"]]
    out += [env.reset()[1]["instance_id"] for _ in range(n - 1)]
    return out


def test_fixed_context_is_applied_and_reported() -> None:
    env = cs.make("cartpole", context={"masscart": 2.5}, obs_context=["masscart"])
    obs, info = env.reset(seed=0)
    assert info["context"]["masscart"] == 2.5 and env.context["masscart"] == 2.5
    assert obs[-1] == np.float32(2.5)
    # The dynamics change with the context.
    d = cs.make("cartpole")
    d.reset(seed=0)
    env.reset(seed=0)
    assert not np.array_equal(env.step(1)[0][:4], d.step(1)[0])


def test_round_robin_static_and_random_selection() -> None:
    n = len(cs.instances.load(SET))
    rr = cs.make("pendulum", instances=SET)
    assert _ids(rr, 5, seed=3) == [3, 4, 5, 6, 7]
    assert _ids(rr, 3, seed=n - 1) == [n - 1, 0, 1]
    st = cs.make("pendulum", instances=SET, selection="static", instance=7)
    assert _ids(st, 3, seed=1) == [7, 7, 7]
    r1 = _ids(cs.make("pendulum", instances=SET, selection="random"), 10, seed=5)
    r2 = _ids(cs.make("pendulum", instances=SET, selection="random"), 10, seed=5)
    r3 = _ids(cs.make("pendulum", instances=SET, selection="random"), 10, seed=6)
    assert r1 == r2 and r1 != r3 and len(set(r1)) > 1 and all(0 <= i < n for i in r1)


def test_set_contexts_equal_the_frozen_values() -> None:
    iset = cs.instances.load(SET)
    env = cs.make("pendulum", instances=SET, selection="static", instance=4)
    _, info = env.reset(seed=0)
    for k, v in iset.contexts[4].items():
        assert info["context"][k] == v


def test_reset_seed_determines_everything_after() -> None:
    env = cs.make("pendulum", distribution="q1_g_sigma_0_5")
    def run(seed: int) -> list[tuple[float, float]]:
        out = []
        obs, info = env.reset(seed=seed)
        for _ in range(4):
            out.append((info["context"]["g"], float(obs[0])))
            obs, info = env.reset()
        return out
    a = run(1)
    env.reset(seed=99)
    env.reset()
    assert run(1) == a
    assert len({g for g, _ in a}) > 1, "a distribution draws a fresh context per reset"
    assert run(2) != a


def test_refusals_name_the_valid_options() -> None:
    with pytest.raises(cs.UnknownNameError, match="valid names: .*masscart"):
        cs.make("cartpole", context={"mascart": 2.0})
    with pytest.raises(cs.UnknownNameError, match='did you mean "masscart"'):
        cs.make("cartpole", context={"mascart": 2.0})
    with pytest.raises(ValueError, match="outside its bounds"):
        cs.make("cartpole", context={"masscart": -5.0})
    with pytest.raises(cs.UnknownNameError, match="distribution"):
        cs.make("pendulum", distribution="nope")
    with pytest.raises(cs.UnknownNameError, match="valid names"):
        cs.make("pendulum", obs_context=["nope"])
    with pytest.raises(cs.UnknownNameError, match="known: acrobot"):
        cs.make("no_such_env")
    with pytest.raises(ValueError, match="at most one"):
        cs.make("pendulum", context={"g": 9.0}, distribution="q1_g_sigma_0_5")
    with pytest.raises(ValueError, match="selection"):
        cs.make("pendulum", instances=SET, selection="sorted")
    with pytest.raises(ValueError, match="out of range"):
        cs.make("pendulum", instances=SET, selection="static", instance=10**6)


def test_two_contexts_stepped_alternately_equal_each_alone() -> None:
    def alone(ctx: dict[str, float]) -> list[np.ndarray]:
        env = cs.make("cartpole", context=ctx)
        obs = [env.reset(seed=0)[0]]
        for t in range(40):
            obs.append(env.step(t % 2)[0])
        return obs
    a_ctx, b_ctx = {"masscart": 2.0}, {"pole_length": 0.8}
    a, b = cs.make("cartpole", context=a_ctx), cs.make("cartpole", context=b_ctx)
    oa, ob = [a.reset(seed=0)[0]], [b.reset(seed=0)[0]]
    for t in range(40):
        oa.append(a.step(t % 2)[0])
        ob.append(b.step(t % 2)[0])
    for x, y in zip(oa, alone(a_ctx)):
        np.testing.assert_array_equal(x, y)
    for x, y in zip(ob, alone(b_ctx)):
        np.testing.assert_array_equal(x, y)
    assert not np.array_equal(oa[-1], ob[-1])
