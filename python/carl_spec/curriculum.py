"""Curricula: the next contexts of an environment, chosen from outside while it trains.

A curriculum is any object with three methods (the `ContextSelector` protocol):

* `select(env_index) -> dict`: the context of environment `env_index`'s next episode;
* `update(env_index, context, episode_return)`: called with every finished episode's context
  and undiscounted return;
* `describe() -> dict`: the current training distribution, reported as `info["curriculum"]`.

`cs.make(env, curriculum=c)` and `cs.make_vec(env, n, curriculum=c)` call it: `select` before
every episode (in a batch, per environment), `update` when one ends. A context it selects is
checked like any context: a feature outside its bounds raises a ValueError naming it. Batches
need `autoreset_mode="next_step"` (the default) or `"disabled"`: the choice for an episode is made
when the previous one ends, before its reset.

Two built-ins work over the spec's bounds, seeded, deterministic for a seed and a sequence of
calls (a batch calls them in environment order):

* `AutomaticDomainRandomization` (ADR, OpenAI et al. 2019): each feature's range starts at an
  initial interval (by default its default value) and widens by `delta` on a side while the
  episodes played at that boundary reach `threshold` on average (narrowing below
  `threshold_low`), never beyond the feature's bounds.
* `SelfPacedCurriculum` (after Klink et al. 2020): a Gaussian per feature moves from an easy
  distribution towards the target one by `step` of the remaining way whenever the last
  `episodes_per_update` episodes' mean return reaches `threshold`.
"""

from __future__ import annotations

import math
from typing import Any, Mapping, Protocol, Sequence, runtime_checkable

import numpy as np

from ._errors import UnknownNameError


@runtime_checkable
class ContextSelector(Protocol):
    def select(self, env_index: int) -> dict[str, float]: ...

    def update(self, env_index: int, context: Mapping[str, float], episode_return: float) -> None: ...

    def describe(self) -> dict[str, Any]: ...


def check_selector(curriculum: Any) -> ContextSelector:
    missing = [m for m in ("select", "update", "describe") if not callable(getattr(curriculum, m, None))]
    if missing:
        raise TypeError(
            f"curriculum must have select(env_index), update(env_index, context, episode_return) and describe(); "
            f"{type(curriculum).__name__} lacks {', '.join(missing)}"
        )
    return curriculum  # type: ignore[no-any-return]


def _features(env: str, names: Sequence[str]) -> dict[str, tuple[float, float, float]]:
    """(default, low bound, high bound) of float features, by canonical name; unbounded sides
    are infinite."""
    from .specs import spec  # the spec tooling loads on first use, not with `cs.make`

    s = spec(env)
    out = {}
    for name in names:
        f = s.features.get(name)
        if f is None:
            raise UnknownNameError(f"{env} has no context feature {name!r}; features: {', '.join(s.features)}")
        if f.get("type") != "float":
            raise ValueError(f"{env}: a curriculum moves float features; {name!r} is {f.get('type')}")
        lo, hi = f.get("bounds", [None, None])
        out[name] = (float(f["default"]), -math.inf if lo is None else float(lo), math.inf if hi is None else float(hi))
    return out


def _finite(where: str, x: Any) -> float:
    try:
        v = float(x)
    except (TypeError, ValueError):
        raise ValueError(f"{where} must be a number, got {x!r}") from None
    if not math.isfinite(v):
        raise ValueError(f"{where} must be finite, got {x!r}")
    return v


class AutomaticDomainRandomization:
    """ADR over `features`: `{name: (low, high)}` initial ranges (a list of names starts each at
    its default), widened or narrowed by `delta` (`{name: step}` or one number for all, in the
    feature's unit) at one boundary at a time. With probability `boundary_probability` an episode
    tests a boundary: that feature at its current low or high, the others uniform in their
    ranges; after `buffer_size` such episodes at one boundary, a mean return ≥ `threshold` widens
    it (up to the feature's bounds), < `threshold_low` narrows it (not past the initial range)."""

    def __init__(
        self,
        env: str,
        features: Mapping[str, tuple[float, float]] | Sequence[str],
        *,
        delta: float | Mapping[str, float],
        threshold: float,
        threshold_low: float | None = None,
        buffer_size: int = 10,
        boundary_probability: float = 0.5,
        seed: int = 0,
    ) -> None:
        names = list(features)
        if not names:
            raise ValueError("ADR needs at least one feature")
        self._info = _features(env, names)
        initial = {n: (features[n] if isinstance(features, Mapping) else (self._info[n][0],) * 2) for n in names}
        self.ranges: dict[str, list[float]] = {}
        self.initial: dict[str, tuple[float, float]] = {}
        for n, r in initial.items():
            lo, hi = (_finite(f"features[{n!r}][{k}]", v) for k, v in enumerate(r))
            _, blo, bhi = self._info[n]
            if not (blo <= lo <= hi <= bhi):
                raise ValueError(f"ADR: the initial range [{lo}, {hi}] of {n!r} must be ordered and inside its bounds [{blo}, {bhi}]")
            self.ranges[n] = [lo, hi]
            self.initial[n] = (lo, hi)
        deltas = delta if isinstance(delta, Mapping) else {n: delta for n in names}
        self.delta = {n: _finite(f"delta[{n!r}]", deltas.get(n)) for n in names}
        if any(d <= 0 for d in self.delta.values()):
            raise ValueError(f"ADR: every delta must be > 0, got {self.delta}")
        self.threshold = _finite("threshold", threshold)
        self.threshold_low = -math.inf if threshold_low is None else _finite("threshold_low", threshold_low)
        if self.threshold_low > self.threshold:
            raise ValueError("ADR: threshold_low must not exceed threshold")
        if not (isinstance(buffer_size, int) and buffer_size >= 1):
            raise ValueError(f"ADR: buffer_size must be an int ≥ 1, got {buffer_size!r}")
        self.buffer_size = buffer_size
        p = _finite("boundary_probability", boundary_probability)
        if not 0.0 <= p <= 1.0:
            raise ValueError(f"ADR: boundary_probability must be in [0, 1], got {p}")
        self.boundary_probability = p
        self._rng = np.random.Generator(np.random.PCG64(seed))
        self._buffers: dict[tuple[str, int], list[float]] = {(n, s): [] for n in names for s in (0, 1)}
        self._testing: dict[int, tuple[str, int] | None] = {}

    def select(self, env_index: int) -> dict[str, float]:
        ctx = {n: float(self._rng.uniform(lo, hi)) if hi > lo else lo for n, (lo, hi) in self.ranges.items()}
        test = None
        if self._rng.random() < self.boundary_probability:
            names = list(self.ranges)
            n = names[int(self._rng.integers(len(names)))]
            side = int(self._rng.integers(2))
            ctx[n] = self.ranges[n][side]
            test = (n, side)
        self._testing[env_index] = test
        return ctx

    def update(self, env_index: int, context: Mapping[str, float], episode_return: float) -> None:
        test = self._testing.pop(env_index, None)
        if test is None:
            return
        buf = self._buffers[test]
        buf.append(float(episode_return))
        if len(buf) < self.buffer_size:
            return
        mean = sum(buf) / len(buf)
        buf.clear()
        n, side = test
        lo, hi = self.ranges[n]
        _, blo, bhi = self._info[n]
        d = self.delta[n]
        if mean >= self.threshold:
            self.ranges[n] = [max(blo, lo - d), hi] if side == 0 else [lo, min(bhi, hi + d)]
        elif mean < self.threshold_low:
            ilo, ihi = self.initial[n]
            self.ranges[n] = [min(ilo, lo + d), hi] if side == 0 else [lo, max(ihi, hi - d)]

    def describe(self) -> dict[str, Any]:
        return {"kind": "adr", "ranges": {n: tuple(r) for n, r in self.ranges.items()}}


class SelfPacedCurriculum:
    """A Gaussian per feature moving from `initial` (`{name: (mean, std)}`, the easy tasks) to
    `target` (`{name: (mean, std)}`): after every `episodes_per_update` finished episodes whose
    mean return reaches `threshold`, each mean and std moves `step` of the remaining way. Draws
    outside the feature's bounds are drawn again (up to 1000 times, then an error)."""

    def __init__(
        self,
        env: str,
        target: Mapping[str, tuple[float, float]],
        initial: Mapping[str, tuple[float, float]],
        *,
        threshold: float,
        step: float = 0.1,
        episodes_per_update: int = 10,
        seed: int = 0,
    ) -> None:
        if set(target) != set(initial) or not target:
            raise ValueError("SelfPacedCurriculum: target and initial must name the same features (at least one)")
        self._info = _features(env, list(target))
        self.target: dict[str, tuple[float, float]] = {}
        self.current: dict[str, list[float]] = {}
        for what, src, dst in (("target", target, self.target), ("initial", initial, None)):
            for n, ms in src.items():
                mean, std = (_finite(f"{what}[{n!r}][{k}]", v) for k, v in enumerate(ms))
                _, blo, bhi = self._info[n]
                if not (blo <= mean <= bhi) or std < 0:
                    raise ValueError(f"SelfPacedCurriculum: {what} mean {mean} of {n!r} must lie in its bounds [{blo}, {bhi}] with std ≥ 0")
                if dst is not None:
                    dst[n] = (mean, std)
                else:
                    self.current[n] = [mean, std]
        self.threshold = _finite("threshold", threshold)
        s = _finite("step", step)
        if not 0.0 < s <= 1.0:
            raise ValueError(f"SelfPacedCurriculum: step must be in (0, 1], got {s}")
        self.step = s
        if not (isinstance(episodes_per_update, int) and episodes_per_update >= 1):
            raise ValueError(f"SelfPacedCurriculum: episodes_per_update must be an int ≥ 1, got {episodes_per_update!r}")
        self.episodes_per_update = episodes_per_update
        self.updates = 0
        self._returns: list[float] = []
        self._rng = np.random.Generator(np.random.PCG64(seed))

    def select(self, env_index: int) -> dict[str, float]:
        ctx = {}
        for n, (mean, std) in self.current.items():
            _, blo, bhi = self._info[n]
            for _ in range(1000):
                x = float(self._rng.normal(mean, std)) if std > 0 else mean
                if blo <= x <= bhi:
                    break
            else:
                raise ValueError(f"SelfPacedCurriculum: N({mean}, {std}) of {n!r} gave no draw inside [{blo}, {bhi}] in 1000 tries")
            ctx[n] = x
        return ctx

    def update(self, env_index: int, context: Mapping[str, float], episode_return: float) -> None:
        self._returns.append(float(episode_return))
        if len(self._returns) < self.episodes_per_update:
            return
        mean_return = sum(self._returns) / len(self._returns)
        self._returns.clear()
        if mean_return >= self.threshold:
            self.updates += 1
            for n, cur in self.current.items():
                tm, ts = self.target[n]
                cur[0] += self.step * (tm - cur[0])
                cur[1] += self.step * (ts - cur[1])

    def describe(self) -> dict[str, Any]:
        return {
            "kind": "self_paced",
            "updates": self.updates,
            "distribution": {n: {"mean": m, "std": s} for n, (m, s) in self.current.items()},
        }


__all__ = ["AutomaticDomainRandomization", "ContextSelector", "SelfPacedCurriculum", "check_selector"]
