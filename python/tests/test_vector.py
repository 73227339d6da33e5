"""make_vec is a conforming gymnasium VectorEnv in all three autoreset modes: step for step equal
to Gymnasium's own SyncVectorEnv over cs.make envs, plus the modes' defining behaviour."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from gymnasium.vector import AutoresetMode, SyncVectorEnv

import carl_spec as cs

MODES = {"next_step": AutoresetMode.NEXT_STEP, "same_step": AutoresetMode.SAME_STEP, "disabled": AutoresetMode.DISABLED}


def assert_infos_equal(ours: dict[str, Any], ref: dict[str, Any], path: str = "infos") -> None:
    """Same keys, and equal arrays (values and dtypes) or nested dicts, recursively."""
    assert sorted(ours) == sorted(ref), f"{path}: {sorted(ours)} != {sorted(ref)}"
    for k, v in ref.items():
        if isinstance(v, dict):
            assert_infos_equal(ours[k], v, f"{path}[{k!r}]")
        else:
            assert ours[k].dtype == v.dtype, f"{path}[{k!r}]: {ours[k].dtype} != {v.dtype}"
            np.testing.assert_array_equal(ours[k], v, err_msg=f"{path}[{k!r}]")


def _pair(env_id: str, n: int, mode: str, **kw: object) -> tuple[cs.CarlVectorEnv, SyncVectorEnv]:
    ours = cs.make_vec(env_id, n, autoreset_mode=mode, **kw)
    ref = SyncVectorEnv([lambda: cs.make(env_id, **kw) for _ in range(n)], autoreset_mode=MODES[mode])
    return ours, ref


@pytest.mark.parametrize("mode", list(MODES))
@pytest.mark.parametrize(
    "env_id,kw",
    [
        ("cartpole", {}),
        ("pendulum", {"distribution": "q1_g_sigma_0_5"}),
        ("pendulum", {"instances": "pendulum/q1_g_sigma_0_5", "selection": "random", "obs_context": True}),
        ("lunar_lander", {"instances": "lunar_lander/landing_in_space_train", "obs_context": ["GRAVITY_Y"]}),
        (
            "pendulum",
            {
                "instances": "pendulum/q1_g_sigma_0_5",
                "obs_context": ["g", "m"],
                "context_noise": {"g": "10%"},
                "context_noise_redraw": "step",
            },
        ),
    ],
    ids=["cartpole", "pendulum-dist", "pendulum-set", "lunar-set", "pendulum-noise"],
)
def test_equals_sync_vector_env(mode: str, env_id: str, kw: dict[str, object]) -> None:
    n = 5
    ours, ref = _pair(env_id, n, mode, **kw)
    assert ours.metadata["autoreset_mode"] == MODES[mode]
    assert ours.single_observation_space == ref.single_observation_space
    a, ia = ours.reset(seed=21)
    b, ib = ref.reset(seed=21)
    np.testing.assert_array_equal(a, b)
    noisy = "context_noise" in kw
    if noisy:
        assert_infos_equal(ia["observed_context"], ib["observed_context"])
    ours.action_space.seed(1)
    finished = 0
    for t in range(400):
        actions = ours.action_space.sample()
        a, ra, ta, ua, ia = ours.step(actions)
        b, rb, tb, ub, ib = ref.step(actions)
        np.testing.assert_array_equal(a, b, err_msg=f"step {t}")
        np.testing.assert_array_equal(ra, rb)
        np.testing.assert_array_equal(ta, tb)
        np.testing.assert_array_equal(ua, ub)
        assert a.dtype == b.dtype and ra.dtype == np.float64 and ta.dtype == np.bool_
        done = ta | ua
        finished += int(done.sum())
        if noisy:
            # What each env observes of its context, in Gymnasium's vector info layout.
            assert_infos_equal(ia["observed_context"], ib["observed_context"], f"step {t}")
            np.testing.assert_array_equal(ia["_observed_context"], ib["_observed_context"])
        if "instance_id" in ib:
            np.testing.assert_array_equal(ia["instance_id"], ib["instance_id"])
        if mode == "same_step" and done.any():
            np.testing.assert_array_equal(ia["_final_obs"], ib["_final_obs"])
            for i in np.flatnonzero(done):
                np.testing.assert_array_equal(ia["final_obs"][i], ib["final_obs"][i])
            # final_info: the finished episodes' infos (context, instance, draw seed, observed
            # context), laid out as SyncVectorEnv lays out cs.make's.
            np.testing.assert_array_equal(ia["_final_info"], ib["_final_info"])
            assert_infos_equal(ia["final_info"], ib["final_info"], f"step {t} final_info")
            # The features' masks are one shared array, so it is read-only: writing through one
            # feature's mask must not silently change another's.
            ctx = ia["final_info"]["context"]
            mask = ctx["_" + next(k for k in ctx if not k.startswith("_"))]
            with pytest.raises(ValueError, match="read-only"):
                mask[0] = not mask[0]
        elif mode == "same_step":
            assert "final_info" not in ia and "final_info" not in ib
        if mode == "disabled" and done.any():
            a, _ = ours.reset(options={"reset_mask": done})
            b, _ = ref.reset(options={"reset_mask": done})
            np.testing.assert_array_equal(a, b)
    assert finished > 0


def test_next_step_resets_on_the_following_step() -> None:
    venv = cs.make_vec("cartpole", 2, autoreset_mode="next_step")
    single = cs.make("cartpole")
    venv.reset(seed=0)
    single.reset(seed=0)
    for _ in range(500):
        obs, rew, term, trunc, _ = venv.step(np.array([1, 0]))
        o, r, t, u, _ = single.step(1)
        np.testing.assert_array_equal(obs[0], o)
        if t or u:
            break
    assert term[0]
    # The next step ignores env 0's action, returns the reset observation, reward 0, no flags.
    obs, rew, term, trunc, _ = venv.step(np.array([1, 0]))
    o, _ = single.reset()
    np.testing.assert_array_equal(obs[0], o)
    assert rew[0] == 0.0 and not term[0] and not trunc[0]


def test_disabled_refuses_to_step_a_finished_env() -> None:
    venv = cs.make_vec("cartpole", 2, autoreset_mode="disabled")
    venv.reset(seed=0)
    for _ in range(500):
        _, _, term, trunc, _ = venv.step(np.array([1, 1]))
        if (term | trunc).any():
            break
    with pytest.raises(RuntimeError, match="reset mask"):
        venv.step(np.array([1, 1]))
    venv.reset(options={"reset_mask": term | trunc})
    venv.step(np.array([1, 1]))
    with pytest.raises(ValueError, match="reset_mask"):
        cs.make_vec("cartpole", 2).reset(options={"reset_mask": np.array([True, False])})


def test_seed_list_and_threads_do_not_change_results() -> None:
    a = cs.make_vec("lunar_lander", 4, threads=1)
    b = cs.make_vec("lunar_lander", 4, threads=2)
    oa, _ = a.reset(seed=[3, 4, 5, 6])
    ob, _ = b.reset(seed=3)
    np.testing.assert_array_equal(oa, ob)
    a.action_space.seed(0)
    for _ in range(50):
        act = a.action_space.sample()
        np.testing.assert_array_equal(a.step(act)[0], b.step(act)[0])


def test_instance_ids_reported_and_reselected_at_autoreset() -> None:
    name = "pendulum/" + sorted(cs.spec("pendulum").instance_sets)[0]
    n_inst = len(cs.instances.load(name))
    venv = cs.make_vec("pendulum", 3, instances=name, selection="random", autoreset_mode="same_step")
    _, info = venv.reset(seed=0)
    ids = [info["instance_id"].copy()]
    assert info["instance_id"].dtype == np.int64 and ((0 <= ids[0]) & (ids[0] < n_inst)).all()
    for _ in range(3 * 200):
        _, _, _, trunc, info = venv.step(venv.action_space.sample())
        if trunc.any():
            ids.append(info["instance_id"].copy())
    assert len({tuple(x) for x in ids}) > 1, "instances must be re-selected at autoreset"
    ctx = venv.context_info(0)
    assert ctx is not None and ctx["instance_id"] == info["instance_id"][0]


def _arrays(x: Any) -> list[np.ndarray]:
    """Every NumPy array in a step's outputs (inside infos and object arrays too)."""
    if isinstance(x, dict):
        return [a for v in x.values() for a in _arrays(v)]
    if isinstance(x, (tuple, list)):
        return [a for v in x for a in _arrays(v)]
    if isinstance(x, np.ndarray):
        if x.dtype == object:
            return [x] + [a for v in x for a in _arrays(v)]
        return [x]
    return []


def _snapshot(x: Any) -> Any:
    if isinstance(x, dict):
        return {k: _snapshot(v) for k, v in x.items()}
    if isinstance(x, (tuple, list)):
        return [_snapshot(v) for v in x]
    if isinstance(x, np.ndarray):
        return [_snapshot(v) for v in x] if x.dtype == object else x.copy()
    return x


def _assert_same(a: Any, b: Any) -> None:
    if isinstance(b, dict):
        assert sorted(a) == sorted(b)
        for k in b:
            _assert_same(a[k], b[k])
    elif isinstance(b, list):
        assert len(a) == len(b)
        for x, y in zip(a, b):
            _assert_same(x, y)
    elif isinstance(b, np.ndarray):
        np.testing.assert_array_equal(a, b)
    else:
        assert a is b or a == b


@pytest.mark.parametrize("threads", [1, 2])
def test_step_outputs_are_fresh_and_never_change_later(threads: int) -> None:
    """The step makes its arrays and info dicts ahead (while the workers step) and releases a
    step's outputs two steps later: every step must still hand out objects of its own (no
    memory shared with another step's) that later steps never change, whether kept or dropped."""
    venv = cs.make_vec("lunar_lander", 8, autoreset_mode="same_step", threads=threads)
    venv.reset(seed=0)
    venv.action_space.seed(1)
    kept: list[tuple[Any, Any]] = []
    ends = 0
    for t in range(300):
        out = venv.step(venv.action_space.sample())
        ends += "final_obs" in out[4]
        # the outputs are the user's to change
        out[0][:] = -1.0
        if "final_info" in out[4]:
            context = out[4]["final_info"]["context"]
            context[next(iter(context))][:] = 123.0
        if t % 3 == 0:  # keep some, drop the others at once
            kept.append((out, _snapshot(out)))
    assert ends > 5
    for out, snap in kept:
        _assert_same(out, snap)
    # Within a step one read-only mask serves all features, and the read-only context arrays are
    # shared while no context changes; across steps no writeable array is shared.
    owners = [
        (k, a)
        for k, (out, _) in enumerate(kept)
        for a in {id(a): a for a in _arrays(out)}.values()
        if a.base is None and a.flags.writeable
    ]
    for i, (k, a) in enumerate(owners):
        for m, b in owners[i + 1 :]:
            assert a is not b or k == m
            assert a is b or not np.shares_memory(a, b)


@pytest.mark.parametrize("threads", [1, 2])
def test_native_steps_bench_anchor_steps_the_same_episodes_as_step(threads: int) -> None:
    # The bench's in-process anchor (`VecEnv.native_steps`) must time the very work `step` does.
    n, k = 8, 150
    a = cs.make_vec("lunar_lander", n, autoreset_mode="same_step", threads=threads)
    b = cs.make_vec("lunar_lander", n, autoreset_mode="same_step", threads=threads)
    rng = np.random.default_rng(3)
    acts = [rng.integers(0, 4, n) for _ in range(5)]
    a.reset(seed=11)
    b.reset(seed=11)
    for i in range(k):
        a.step(acts[i % len(acts)])
    b._core.native_steps(acts, k)
    for i in range(n):
        assert a._core.state(i) == b._core.state(i)
    with pytest.raises(ValueError, match="at least one action batch"):
        b._core.native_steps([], 1)


def _flags(x: Any) -> list[bool]:
    return [a.flags.writeable for a in _arrays(x)]


@pytest.mark.parametrize("threads", [1, 2])
@pytest.mark.parametrize(
    "env_id, kw",
    [
        ("lunar_lander", {}),
        ("pendulum", {"distribution": "q1_g_sigma_0_5"}),
        (
            "pendulum",
            {
                "instances": "pendulum/q1_g_sigma_0_5",
                "obs_context": ["g", "m"],
                "context_noise": {"g": "10%"},
                "context_noise_redraw": "step",
            },
        ),
    ],
    ids=["lunar", "pendulum-dist", "pendulum-noise"],
)
def test_released_outputs_are_reused_without_a_trace(threads: int, env_id: str, kw: dict[str, object]) -> None:
    """Arrays of a step that nobody holds any more are refilled by a later step (the stock
    reclaims them, and nested info dicts whole) instead of made anew. Whatever the user did to
    them before letting go (wrote into them, added keys), a later step must hand out exactly what
    a batch whose every output is kept (so nothing can be reused) hands out."""
    n = 8
    reused = cs.make_vec(env_id, n, autoreset_mode="same_step", threads=threads, **kw)
    fresh = cs.make_vec(env_id, n, autoreset_mode="same_step", threads=threads, **kw)
    reused.reset(seed=4)
    fresh.reset(seed=4)
    reused.action_space.seed(2)
    kept: list[Any] = []
    ends = 0
    for t in range(600):
        a = reused.action_space.sample()
        out = reused.step(a)
        ref = fresh.step(a)
        kept.append(ref)
        _assert_same(_snapshot(out), _snapshot(ref))
        assert _flags(out) == _flags(ref)
        ends += "final_info" in out[4]
        # Everything the user may do to outputs before dropping them.
        out[0][:] = np.nan
        out[1][:] = -7.0
        out[2][:] = True
        if "observed_context" in out[4]:  # a nested dict at every step
            for key, col in out[4]["observed_context"].items():
                if not key.startswith("_"):
                    col[:] = -3.0
        if "final_info" in out[4]:
            final = out[4]["final_info"]
            for key, col in final["context"].items():
                if not key.startswith("_"):
                    col[:] = 123.0
            if t % 4 == 0:
                final["context"]["extra"] = np.zeros(n)
            if t % 4 == 1:
                del final["context"][next(iter(final["context"]))]
            for row in out[4]["final_obs"]:
                if row is not None:
                    row[:] = 5.0
        del out
    assert ends >= 3  # pendulum: every 200 steps


def test_outputs_held_through_a_view_or_a_weak_reference_are_not_reused() -> None:
    # A view holds its base; a weak reference must see its array die, not come back refilled.
    import weakref

    venv = cs.make_vec("lunar_lander", 4, autoreset_mode="same_step", threads=1)
    venv.reset(seed=0)
    out = venv.step(np.zeros(4, dtype=np.int64))
    view, before = out[0][1:], out[0][1:].copy()
    rewards = weakref.ref(out[1])
    del out
    for _ in range(6):
        venv.step(np.ones(4, dtype=np.int64))
    np.testing.assert_array_equal(view, before)
    assert rewards() is None
