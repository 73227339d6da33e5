"""Bounded-but-extreme contexts and actions fed to every runtime through Python (issue 31): each
either runs with finite observations and rewards or raises a clear exception (a ValueError or
KeyError naming the problem), never a crash, a panic, a hang or a silent NaN. Values come from a
seeded generator, so a failure replays."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

import carl_spec as cs

#: Clear errors: bad input (ValueError, KeyError and their subclasses such as UnknownNameError).
CLEAR = (ValueError, KeyError)
#: Steps per probe: enough to cross a reset in the light environments.
STEPS = 8
#: Stand-in for an open side of a feature's bounds: huge but finite.
HUGE = 1e30


def runtime_or_skip(env: str) -> None:
    try:
        cs.make(env).close()
    except CLEAR as e:
        if env == "mario":
            pytest.skip(f"mario needs its data directory: {e}")
        raise


def extreme_values(feature: dict[str, Any], rng: np.random.Generator) -> list[float]:
    """Both bounds (an open side as ±1e30) and two random values inside them, one log-uniform
    towards the far side: all inside the feature's bounds."""
    lo, hi = (feature.get("bounds") or [None, None])[:2]
    lo = -HUGE if lo is None else float(lo)
    hi = HUGE if hi is None else float(hi)
    far = hi if abs(hi) >= abs(lo) else lo
    towards = math.copysign(10 ** rng.uniform(0, math.log10(max(abs(far), 1.0))), far)
    values = [lo, hi, float(np.clip(towards, lo, hi)), float(rng.uniform(max(lo, -1e6), min(hi, 1e6)))]
    if feature["type"] == "int":
        values = [float(round(v)) for v in values]
    return values


def check_episode(env: Any, rng: np.random.Generator, extreme_actions: bool) -> None:
    """Reset and a few steps: finite numbers or a clear error."""
    obs, _ = env.reset(seed=int(rng.integers(0, 2**31)))
    assert np.all(np.isfinite(np.asarray(obs, dtype=np.float64)))
    space = env.action_space
    for _ in range(STEPS):
        if extreme_actions and hasattr(space, "high"):
            action = np.where(rng.random(space.shape) < 0.5, -1e30, 1e30).astype(space.dtype)
        else:
            action = space.sample()
        obs, reward, terminated, truncated, _ = env.step(action)
        assert np.all(np.isfinite(np.asarray(obs, dtype=np.float64))), "a non-finite observation passed silently"
        assert math.isfinite(float(reward)), "a non-finite reward passed silently"
        if terminated or truncated:
            env.reset()


@pytest.mark.parametrize("env_id", cs.RUNTIMES)
def test_every_feature_at_extreme_values_gives_finite_output_or_a_clear_error(env_id: str) -> None:
    runtime_or_skip(env_id)
    rng = np.random.default_rng(31)
    spec = cs.spec(env_id)
    for name, feature in spec.features.items():
        if feature["type"] not in ("float", "int") or "default" not in feature:
            continue
        for value in extreme_values(feature, rng):
            try:
                env = cs.make(env_id, context={name: value})
            except CLEAR:
                continue
            try:
                check_episode(env, rng, extreme_actions=False)
            except CLEAR:
                pass
            finally:
                env.close()


@pytest.mark.parametrize("env_id", cs.RUNTIMES)
def test_extreme_actions_are_clipped_or_refused(env_id: str) -> None:
    runtime_or_skip(env_id)
    rng = np.random.default_rng(32)
    env = cs.make(env_id)
    try:
        check_episode(env, rng, extreme_actions=True)
    except CLEAR:
        pass
    finally:
        env.close()
