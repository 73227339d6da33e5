"""`carl_spec.wrap`: make any Gymnasium environment contextual from the user's own spec file.

A benchmark author writes a carl-spec JSON spec for an environment carl-spec does not ship (its
features: defaults, bounds, types, what each affects; named distributions; instance sets) and
wraps the environment:

    env = cs.wrap(MyEnv, spec="my-specs/my_env.json", distribution="wide")

The spec is validated by the same validator as the bundled specs; contexts are chosen per reset
with exactly the selection and seeding rules of `cs.make` (Rust's `ContextualEnv`); each
episode's context is applied before the user's env resets, either to attributes of
`env.unwrapped` (by feature name, or renamed with `attributes=`) or by a user function
`apply(env, context)`.
"""

from __future__ import annotations

import json
import os
from typing import Any, Callable, SupportsFloat

import gymnasium
import numpy as np
from gymnasium import spaces

from . import _core
from ._args import NoiseStd, context_args
from ._errors import UnknownNameError, out_of_bounds_hint
from .env import _fresh, os_entropy_seed

PathLike = str | os.PathLike[str]
EnvFactory = Callable[[], gymnasium.Env[Any, Any]]
ApplyFn = Callable[[gymnasium.Env[Any, Any], dict[str, Any]], None]


def load_user_spec(spec: PathLike, env_id: str | None = None) -> dict[str, Any]:
    """The resolved spec of a user's file or directory (validated; `ValueError` lists every
    diagnostic with its line and column)."""
    doc: dict[str, Any] = json.loads(_core.user_spec_json(os.fspath(spec), env_id))
    return doc


def _typed(feature: dict[str, Any], value: float) -> Any:
    """A context value as the feature's type: int features as int, bool as bool."""
    kind = feature.get("type")
    if kind == "int":
        return int(round(value))
    if kind == "bool":
        return bool(value)
    return float(value)


class ContextualWrapper(gymnasium.Wrapper[Any, Any, Any, Any]):
    """A user's environment under a carl-spec context source (see `carl_spec.wrap`)."""

    def __init__(
        self,
        env: gymnasium.Env[Any, Any],
        spec: PathLike,
        *,
        env_id: str | None = None,
        context: dict[str, Any] | None = None,
        instances: str | None = None,
        distribution: str | None = None,
        selection: str = "round_robin",
        instance: int | None = None,
        obs_context: list[str] | bool | None = None,
        context_noise: dict[str, NoiseStd] | None = None,
        context_noise_redraw: str = "episode",
        apply: ApplyFn | None = None,
        attributes: dict[str, str] | None = None,
        _factory: EnvFactory | None = None,
    ) -> None:
        super().__init__(env)
        if apply is not None and attributes is not None:
            raise ValueError("give attributes= (feature -> attribute names) or apply=fn(env, context), not both")
        self._ctor: dict[str, Any] = dict(
            spec=spec, env_id=env_id, context=context, instances=instances, distribution=distribution,
            selection=selection, instance=instance, obs_context=obs_context, context_noise=context_noise,
            context_noise_redraw=context_noise_redraw, apply=apply, attributes=attributes,
        )
        self._factory = _factory
        self._spec = load_user_spec(spec, env_id)
        self._features: dict[str, dict[str, Any]] = {f["name"]: f for f in self._spec["features"]}
        self._visible = self._visible_names(obs_context)
        if context is not None:
            self._check_names_once(context)
        # A user's spec states the bounds its env runs in: widening them is the way out.
        with out_of_bounds_hint(f"widen its bounds in {os.fspath(spec)} to run it"):
            self._chooser = _core.ContextChooser(
                os.fspath(spec),
                context_args(
                    context=context,
                    instances=instances,
                    distribution=distribution,
                    selection=selection,
                    instance=instance,
                    obs_context=self._visible,
                    context_noise=context_noise,
                    context_noise_redraw=context_noise_redraw,
                ),
                env=env_id,
            )
        self._noise_per_step = self._chooser.noise_redraw() == "step"
        self._apply = apply
        self._attributes = self._check_attributes(attributes or {}) if apply is None else {}
        # A Gaussian measurement can land anywhere: noisy features are unbounded (as in cs.make).
        noisy = {self._canonical(n) for n in context_noise or {}}
        if self._visible:
            self.observation_space = self._observation_space_with_context(noisy)
        self._seeded = False
        self._info: dict[str, Any] = self._chooser.info()

    @property
    def spec_id(self) -> str:
        """The id of the user's spec."""
        return str(self._spec["id"])

    def _check_attributes(self, attributes: dict[str, str]) -> dict[str, str]:
        unknown = sorted(set(attributes) - set(self._features))
        if unknown:
            raise UnknownNameError(
                f"attributes= names features {unknown} that {self._spec['id']}'s spec does not have; "
                f"features: {', '.join(self._features)}"
            )
        target = self.env.unwrapped
        mapping = {name: attributes.get(name, name) for name in self._features}
        missing = [f"{n} -> {a}" for n, a in mapping.items() if not hasattr(target, a)]
        if missing:
            raise ValueError(
                f"{type(target).__name__} has no attribute for feature(s) {', '.join(missing)}; "
                "map features to attributes with attributes={feature: attribute}, or pass apply=fn(env, context)"
            )
        return mapping

    def _visible_names(self, obs_context: list[str] | bool | None) -> list[str]:
        if obs_context is None or obs_context is False:
            return []
        if obs_context is True:
            return list(self._features)
        names = []
        for n in obs_context:
            canonical = self._canonical(n)
            if canonical in names:
                raise ValueError(f"obs_context lists {canonical} twice")
            names.append(canonical)
        return names

    def _check_names_once(self, context: dict[str, Any]) -> None:
        """An alias and its canonical name (or two aliases) of one feature are refused, naming
        both, rather than one silently winning."""
        given: dict[str, str] = {}
        for name in context:
            try:
                canon = self._canonical(name)
            except UnknownNameError:
                continue  # the chooser refuses it with the valid names
            if canon in given:
                raise ValueError(
                    f'{self._spec["id"]}: the context gives feature {canon} twice, as "{given[canon]}" and "{name}"; give it once'
                )
            given[canon] = name

    def _canonical(self, name: str) -> str:
        for f in self._features.values():
            if name == f["name"] or name in f.get("aliases", []):
                return str(f["name"])
        raise UnknownNameError(
            f"{self._spec['id']} has no context feature \"{name}\"; features: {', '.join(self._features)}"
        )

    def _observation_space_with_context(self, noisy: set[str]) -> spaces.Box:
        base = self.env.observation_space
        if not isinstance(base, spaces.Box):
            raise ValueError(f"obs_context needs a Box observation space, got {base}")
        lows, highs = [], []
        for n in self._visible:
            lo, hi = [None, None] if n in noisy else self._features[n].get("bounds") or [None, None]
            lows.append(-np.inf if lo is None else lo)
            highs.append(np.inf if hi is None else hi)
        dtype = base.dtype if np.issubdtype(base.dtype, np.floating) else np.float32
        low = np.concatenate([base.low.reshape(-1).astype(dtype), np.array(lows, dtype=dtype)])
        high = np.concatenate([base.high.reshape(-1).astype(dtype), np.array(highs, dtype=dtype)])
        return spaces.Box(low=low, high=high, dtype=dtype)

    def _observe(self, obs: Any) -> Any:
        if not self._visible:
            return obs
        # What the agent sees: the noisy measurement when there is noise, else the true values.
        ctx = self._info.get("observed_context", self._info["context"])
        dtype = self.observation_space.dtype
        extra = np.array([ctx[n] for n in self._visible], dtype=dtype)
        return np.concatenate([np.asarray(obs, dtype=dtype).reshape(-1), extra])

    def _apply_context(self, context: dict[str, float]) -> None:
        typed = {n: _typed(self._features[n], v) for n, v in context.items()}
        if self._apply is not None:
            self._apply(self.env, typed)
            return
        target = self.env.unwrapped
        for name, attr in self._attributes.items():
            if name in typed:
                setattr(target, attr, typed[name])

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[Any, dict[str, Any]]:
        if seed is None and not self._seeded:
            seed = os_entropy_seed()
        if seed is not None:
            self._seeded = True
        info, env_seed = self._chooser.reset(seed)
        if "context_seed" in info:
            info["context_seed"] = np.uint64(info["context_seed"])
        self._info = info
        self._apply_context(info["context"])
        obs, env_info = self.env.reset(seed=env_seed, options=options)
        return self._observe(obs), {**env_info, **self._fresh_info()}

    def step(self, action: Any) -> tuple[Any, SupportsFloat, bool, bool, dict[str, Any]]:
        obs, reward, terminated, truncated, env_info = self.env.step(action)
        if self._noise_per_step:
            self._info["observed_context"] = self._chooser.after_step()
        return self._observe(obs), reward, terminated, truncated, {**env_info, **self._fresh_info()}

    def _fresh_info(self) -> dict[str, Any]:
        return _fresh(self._info)

    @property
    def context(self) -> dict[str, Any]:
        """The current episode's context (every feature, canonical names, typed)."""
        return {n: _typed(self._features[n], v) for n, v in self._info["context"].items()}

    def __reduce__(self) -> tuple[Any, ...]:
        if self._factory is None:
            raise TypeError("a wrapped env instance does not pickle; pass a factory to cs.wrap to ship it")
        return (_rebuild, (self._factory, self._ctor))


def _rebuild(factory: EnvFactory, ctor: dict[str, Any]) -> ContextualWrapper:
    return wrap(factory, **ctor)


def wrap(
    env_or_factory: gymnasium.Env[Any, Any] | EnvFactory,
    spec: PathLike,
    **kwargs: Any,
) -> ContextualWrapper:
    """Make `env_or_factory` (a Gymnasium env, or a zero-argument callable returning one; only a
    factory pickles) contextual under the user's spec file `spec`.

    Context sources (at most one; none means the spec's defaults): `context={feature: value}`
    (a fixed context, missing features at their defaults), `instances="SET"` (a frozen set in
    `<spec dir>/instances/<id>/SET.json`, chosen per reset by `selection=` "round_robin",
    "random" or "static" with `instance=i`), `distribution="NAME"` (a named distribution of the
    spec, drawn afresh at every reset). Values outside the spec's bounds and unknown feature names
    are refused with the valid names.

    Applying a context: each feature is set as an attribute of `env.unwrapped` of the same name
    (`attributes={feature: attribute}` renames), or `apply=fn(env, context)` does it. Run
    `cs.audit` to check that every feature really does what the spec claims.

    `obs_context` (a list of names, or True) appends those features to a Box observation.
    `context_noise={feature: std}` (a number in the feature's unit, or "10%" of |default|) and
    `context_noise_redraw` ("episode" or "step") show the agent noisy values of visible features,
    as `cs.make` does: the env keeps the true context, `info["observed_context"]` holds what the
    agent saw, and the draws are `cs.make`'s for the same seed.
    Seeding is `cs.make`'s: `reset(seed=s)` determines the instance (or draw) and resets the env
    with `s`; an env never seeded draws its first seed from the OS.
    """
    if isinstance(env_or_factory, gymnasium.Env):
        return ContextualWrapper(env_or_factory, spec, **kwargs)
    if not callable(env_or_factory):
        raise TypeError(f"wrap needs a gymnasium.Env or a factory returning one, got {type(env_or_factory).__name__}")
    env = env_or_factory()
    if not isinstance(env, gymnasium.Env):
        raise TypeError(f"the factory returned {type(env).__name__}, not a gymnasium.Env")
    return ContextualWrapper(env, spec, _factory=env_or_factory, **kwargs)
