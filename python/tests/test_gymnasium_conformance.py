"""What Gymnasium users rely on (issues 29 and 31): environments shipped to worker processes
(AsyncVectorEnv under spawn and forkserver)."""

from __future__ import annotations

import pickle
from typing import Any

import cloudpickle
import gymnasium
import numpy as np
import pytest

import carl_spec as cs

# -- shipping environments to worker processes --------------------------------------------


def test_the_package_pickles_by_reference() -> None:
    # cloudpickle ships a lambda's globals; the package must be a plain module for that (a module
    # subclass fails with "cannot pickle '_Package' object", issue 31 item 4).
    fn = pickle.loads(cloudpickle.dumps(lambda: cs.make("cartpole", context={"masscart": 2.0})))
    assert fn().context["masscart"] == 2.0
    assert pickle.loads(cloudpickle.dumps(cs)) is cs


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
