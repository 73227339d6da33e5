"""`make_vec`'s infos equal Gymnasium's `SyncVectorEnv` over `cs.make` key for key, mask for mask
and value for value (issue 31, item 14), in each autoreset mode and for each context source; and
Gymnasium's per-environment access (`get_attr`, `call`, `set_attr`)."""

from __future__ import annotations

from typing import Any

import gymnasium
import numpy as np
import pytest
from gymnasium.vector import AutoresetMode, SyncVectorEnv

import carl_spec as cs

N = 3
SOURCES: dict[str, dict[str, Any]] = {
    "fixed": dict(context={"g": 9.0}),
    "instances": dict(instances="q1_dt_sigma_0_1", selection="random"),
    "distribution": dict(distribution="q1_dt_sigma_0_1"),
}
MODES = {"next_step": AutoresetMode.NEXT_STEP, "same_step": AutoresetMode.SAME_STEP, "disabled": AutoresetMode.DISABLED}


def same(a: Any, b: Any, path: str = "infos") -> None:
    """`a` (make_vec) equals `b` (SyncVectorEnv): the same keys, dtypes and values."""
    if isinstance(b, dict):
        assert isinstance(a, dict), path
        assert sorted(a) == sorted(b), f"{path}: keys {sorted(a)} != {sorted(b)}"
        for k in b:
            same(a[k], b[k], f"{path}[{k!r}]")
    elif isinstance(b, np.ndarray) and b.dtype == object:
        assert isinstance(a, np.ndarray) and a.dtype == object and a.shape == b.shape, path
        for i, (x, y) in enumerate(zip(a, b)):
            same(x, y, f"{path}[{i}]")
    elif isinstance(b, np.ndarray):
        assert isinstance(a, np.ndarray), path
        assert a.dtype == b.dtype, f"{path}: dtype {a.dtype} != {b.dtype}"
        np.testing.assert_array_equal(a, b, err_msg=path)
    else:
        assert a == b, f"{path}: {a!r} != {b!r}"


@pytest.mark.parametrize("source", list(SOURCES))
@pytest.mark.parametrize("mode", list(MODES))
def test_infos_equal_sync_vector_env(mode: str, source: str) -> None:
    kwargs = SOURCES[source]
    ours = cs.make_vec("pendulum", N, autoreset_mode=mode, **kwargs)
    theirs = SyncVectorEnv([lambda: cs.make("pendulum", **kwargs) for _ in range(N)], autoreset_mode=MODES[mode])
    oa, ia = ours.reset(seed=7)
    ob, ib = theirs.reset(seed=7)
    np.testing.assert_array_equal(oa, ob)
    same(ia, ib, "reset")
    rng = np.random.default_rng(0)
    resets = 0
    # Pendulum truncates at 200 steps: 2 episodes each, with autoresets in between.
    for t in range(410):
        actions = rng.uniform(-2, 2, size=(N, 1)).astype(np.float32)
        sa = ours.step(actions)
        sb = theirs.step(actions)
        for x, y in zip(sa[:4], sb[:4]):
            np.testing.assert_array_equal(x, y)
        same(sa[4], sb[4], f"step {t}")
        done = sb[2] | sb[3]
        if mode == "disabled" and done.any():
            # Reset some of the finished envs only: masks for those alone.
            mask = done.copy()
            mask[np.flatnonzero(done)[1:]] = False
            ra, ria = ours.reset(options={"reset_mask": mask})
            rb, rib = theirs.reset(options={"reset_mask": mask})
            np.testing.assert_array_equal(ra, rb)
            same(ria, rib, f"masked reset at step {t}")
            resets += 1
            if (done & ~mask).any():
                ra, ria = ours.reset(options={"reset_mask": done & ~mask})
                rb, rib = theirs.reset(options={"reset_mask": done & ~mask})
                same(ria, rib, f"second masked reset at step {t}")
    if mode == "disabled":
        assert resets >= 1
    ours.close()
    theirs.close()


def test_distribution_infos_have_context_seed_and_no_instance_id() -> None:
    venv = cs.make_vec("pendulum", 2, distribution="q1_dt_sigma_0_1")
    _, info = venv.reset(seed=0)
    assert "instance_id" not in info
    assert info["context_seed"].dtype == np.uint64 and info["_context_seed"].all()
    _, _, _, _, info = venv.step(np.zeros((2, 1), dtype=np.float32))
    assert "context" in info and info["_context"].all()


def test_get_attr_and_call_as_gymnasium_vector_envs() -> None:
    venv = cs.make_vec("pendulum", N, instances="q1_dt_sigma_0_1")
    sync = SyncVectorEnv([lambda: cs.make("pendulum", instances="q1_dt_sigma_0_1") for _ in range(N)])
    venv.reset(seed=1)
    sync.reset(seed=1)
    assert venv.get_attr("context") == sync.get_attr("context")
    assert venv.get_attr("action_space") == sync.get_attr("action_space")
    assert venv.get_attr("render_mode") == (None,) * N
    infos = venv.call("context_info")
    assert [i["instance_id"] for i in infos] == list(venv.get_attr("instance_id"))
    with pytest.raises(AttributeError, match="no attribute"):
        venv.get_attr("nope")
    with pytest.raises(AttributeError, match="settable"):
        venv.set_attr("context", [{}] * N)
    plain = cs.make_vec("cartpole", 2, context={"gravity": 5.0})
    plain.reset(seed=0)
    assert [c["gravity"] for c in plain.get_attr("context")] == [5.0, 5.0]
    assert isinstance(plain.get_attr("observation_space")[0], gymnasium.spaces.Box)
