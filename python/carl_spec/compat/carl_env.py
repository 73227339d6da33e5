"""`CARLEnv`: carl-bench 1.1.1's environment class shape over carl-spec's runtimes.

What carl-bench users rely on keeps working: `contexts={id: context}` (missing features at their
defaults), `obs_context_features`, `obs_context_as_dict`, `context_selector` /
`context_selector_kwargs`, the `{"obs", "context"}` Dict observation, `info["context_id"]`,
`env.contexts` (settable), `env.context`, `env.context_id`, `get_context_features()`,
`get_default_context()`, `_progress_instance()`, `_update_context()`; an unseeded round robin starts
at context 0 as carl-bench's. Features are named as carl-bench names them.

What deliberately differs (carl-bench's flaws are not reproduced):
* every context is checked when the env is built: unknown names, carl-bench features carl-spec does
  not have (named, with the reason) and values outside the bounds are refused;
* selection is seeded by `reset(seed=s)` (carl-bench's RandomSelector uses NumPy's global RNG);
* no module-level state: two envs with different contexts never interfere (carl-bench's
  LunarLander writes its context into Gymnasium's module globals);
* `env.context` is the full context (carl-bench's lacks the defaults it filled into `contexts`);
* context values in observations are float32 arrays, so observations lie in `observation_space`;
* defaults are carl-spec's (Gymnasium's for the classic five, e.g. MountainCar's goal 0.5);
* `env.contexts = {...}` replaces the set from the next reset (carl-bench's selector keeps the old
  one), and `_update_context()` refuses a context changed in place (carl-bench pushes it into the
  physics mid-episode); every difference is listed in docs/guides/migration.md.
"""

from __future__ import annotations

import functools
import inspect
import json
from typing import Any, SupportsFloat

import gymnasium
import numpy as np
from gymnasium import spaces

from .. import _core
from .._args import context_args
from .._errors import UnknownNameError, out_of_bounds_hint
from .._spaces import space_from_json
from ..env import discrete_action, os_entropy_seed
from ..specs import Spec
from ..specs import spec as _load_spec
from .context.context_space import (
    CategoricalContextFeature,
    ContextFeature,
    ContextSpace,
    UniformFloatContextFeature,
    UniformIntegerContextFeature,
)
from .context import selection
from .context.selection import AbstractSelector, RoundRobinSelector

Context = dict[str, Any]
Contexts = dict[Any, Context]
_BUILTIN = {"RoundRobinSelector": "round_robin", "RandomSelector": "random", "StaticSelector": "static"}


@functools.cache
def load_spec(env_id: str) -> Spec:
    """The bundled spec (read once per process; specs are read-only data)."""
    return _load_spec(env_id)


@functools.cache
def _name_maps(env_id: str, bench_names: tuple[str, ...]) -> tuple[dict[str, str], dict[str, str]]:
    """Cached per class (see `CARLEnv._name_maps`); callers must not modify the dicts."""
    spec = load_spec(env_id)
    lookup = {}
    for f in spec.features.values():
        for n in [f["name"], *f.get("aliases", [])]:
            lookup[n] = f["name"]
    to_canon = {n: lookup[n] for n in bench_names}
    for canon in spec.features:
        if canon not in to_canon.values():
            to_canon[canon] = canon
    return to_canon, {c: n for n, c in to_canon.items()}


def _bound(x: Any, inf: float) -> float:
    return inf if x is None else float(x)


class CARLEnv(gymnasium.Env[dict[str, Any], Any]):
    """Base of the `CARL<Name>` classes: set `env_id`, `bench_names` and `bench_only`."""

    #: carl-spec id of the runtime.
    env_id: str = ""
    #: carl-bench's names of the features carl-spec has (carl-bench's order).
    bench_names: tuple[str, ...] = ()
    #: carl-bench features carl-spec does not have -> why (and what to use instead).
    bench_only: dict[str, str] = {}
    metadata = {"render_modes": ["rgb_array"], "render_fps": 50}

    # -- the feature table in carl-bench's names -------------------------------------------

    @classmethod
    def _name_maps(cls) -> tuple[dict[str, str], dict[str, str]]:
        """(compat name -> canonical, canonical -> compat name), compat names in carl-bench's
        order then carl-spec's own extra features."""
        return _name_maps(cls.env_id, cls.bench_names)

    @classmethod
    def get_context_features(cls) -> dict[str, ContextFeature]:
        """Every feature by its carl-bench name (carl-spec's extra features by their own), with
        carl-spec's defaults and bounds."""
        spec = load_spec(cls.env_id)
        out: dict[str, ContextFeature] = {}
        for name, canon in cls._name_maps()[0].items():
            f = spec.features[canon]
            lo, hi = f.get("bounds") or [None, None]
            default = f.get("default")
            if f["type"] == "int" and isinstance(default, float) and default.is_integer():
                default = int(default)
            cf: ContextFeature
            if f["type"] == "categorical" and f.get("choices"):
                cf = CategoricalContextFeature(name, list(f["choices"]), default)
            elif f["type"] == "int":
                cf = UniformIntegerContextFeature(name, _bound(lo, -np.inf), _bound(hi, np.inf), default)  # type: ignore[arg-type]
            else:
                cf = UniformFloatContextFeature(name, _bound(lo, -np.inf), _bound(hi, np.inf), default)
                cf.type = f["type"]
            cf.default_value = default
            cf.lower, cf.upper = _bound(lo, -np.inf), _bound(hi, np.inf)
            cf.canonical_name, cf.unit, cf.description = canon, f.get("unit"), f.get("description", "")
            out[name] = cf
        return out

    @classmethod
    def get_context_space(cls) -> ContextSpace:
        return ContextSpace(cls.get_context_features())

    @classmethod
    def get_default_context(cls) -> Context:
        return {n: f.default_value for n, f in cls.get_context_features().items() if f.default_value is not None}

    @classmethod
    def _canonical(cls, name: str) -> str:
        to_canon = cls._name_maps()[0]
        if name in to_canon:
            return to_canon[name]
        valid = ", ".join(to_canon)
        if name in cls.bench_only:
            raise UnknownNameError(
                f"{cls.__name__}: carl-bench's feature \"{name}\" is not a feature of carl-spec's {cls.env_id}: "
                f"{cls.bench_only[name]}. Valid features: {valid}"
            )
        raise UnknownNameError(f"{cls.__name__} has no context feature \"{name}\"; valid features: {valid}")

    # -- construction ------------------------------------------------------------------------

    def __init__(
        self,
        env: Any = None,
        contexts: Contexts | None = None,
        obs_context_features: list[str] | None = None,
        obs_context_as_dict: bool = True,
        context_selector: AbstractSelector | type[AbstractSelector] | None = None,
        context_selector_kwargs: dict[str, Any] | None = None,
        render_mode: str | None = None,
        **kwargs: Any,
    ) -> None:
        if env is not None:
            raise ValueError(
                f"{type(self).__name__} runs carl-spec's own {self.env_id} runtime; env= is not supported "
                "(to make your own Gymnasium env contextual, use carl_spec.wrap)"
            )
        if kwargs:
            raise TypeError(f"{type(self).__name__} got unexpected keyword argument(s): {', '.join(sorted(kwargs))}")
        self._ctor: dict[str, Any] = dict(
            contexts=contexts,
            obs_context_features=obs_context_features,
            obs_context_as_dict=obs_context_as_dict,
            context_selector=context_selector,
            context_selector_kwargs=context_selector_kwargs,
            render_mode=render_mode,
        )
        # The selector's type is checked before the contexts (carl-bench's order of complaints).
        self._check_selector(context_selector)
        self._selector_spec = (context_selector, context_selector_kwargs)
        self._seeded = False
        self._set_contexts(contexts)
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode must be one of {self.metadata['render_modes']} or None, got {render_mode!r}")
        self.render_mode = render_mode

        first = next(iter(self._contexts.values()))
        if obs_context_features is None:
            obs_context_features = list(first)
        for n in obs_context_features:
            self._canonical(n)
            if n not in first:
                raise ValueError(f"{n} has no numeric value to observe")
        self.obs_context_features: list[str] = list(obs_context_features)
        self.obs_context_as_dict = obs_context_as_dict
        self.action_space = space_from_json(json.loads(self._envs[0].action_space_json()))
        self._discrete = isinstance(self.action_space, spaces.Discrete)
        self.observation_space = self.get_observation_space(self.obs_context_features)
        self._context_obs_cache: Any = None

    def _set_contexts(self, contexts: Contexts | None) -> None:
        """Check `contexts`, build one runtime per context and a fresh selector of the chosen kind
        (the constructor and the `contexts` setter)."""
        if contexts is None:
            contexts = {0: {}}
        if not isinstance(contexts, dict) or not contexts:
            raise ValueError("contexts must be a non-empty dict {context_id: {feature: value}}")
        self._to_compat = self._name_maps()[1]
        canonical_contexts = [{self._canonical(k): v for k, v in c.items()} for c in contexts.values()]
        selector = self._selector(contexts, *self._selector_spec)
        mode = selector.mode
        # The compat API has no out-of-bounds switch; carl-spec's own make has one.
        with out_of_bounds_hint(f"carl_spec.make({self.env_id!r}, context=..., allow_out_of_bounds=True) runs it"):
            if len(canonical_contexts) == 1:
                # One context: carl-spec's fixed context, so unseeded resets continue the runtime's
                # own stream (for the classic five: exactly Gymnasium's env, reset for reset).
                chooser = _core.ContextChooser(None, context_args(context=canonical_contexts[0]), env=self.env_id)
            else:
                chooser = _core.ContextChooser(
                    None,
                    context_args(selection=mode or "round_robin", instance=0 if mode == "static" else None),
                    env=self.env_id,
                    contexts_json=json.dumps(canonical_contexts),
                )
            # One runtime per context, each checked now (names, bounds) like a carl-spec set.
            options = self._env_options(canonical_contexts)
            envs = [_core.Env(self.env_id, context_args(context=c, options=options)) for c in canonical_contexts]
        # Everything is checked: replace the set (a selector instance the user passed follows it).
        selector.contexts, selector.contexts_keys = contexts, list(contexts.keys())
        selector.context_ids, selector.context_id = list(range(len(contexts))), None
        self.context_selector = selector
        self._custom = mode is None
        self._chooser, self._envs = chooser, envs
        self._keys = list(contexts.keys())
        resolved = [dict(c) for c in chooser.instance_contexts()]
        self._contexts = {k: self._compat(c) for k, c in zip(self._keys, resolved)}
        # What the agent observes: the numeric values (a string choice as its index).
        self._numeric = [{self._to_compat[c]: float(v) for c, v in r.items()} for r in resolved]
        self.base_observation_space = self._hull([space_from_json(json.loads(e.observation_space_json())) for e in envs])
        # A new set starts over: its first reset selects as a new env's would.
        self._chosen: int | None = None
        self._started = False
        self._running: Any = None
        self._continue_after: int | None = None
        # Its streams are seeded at its first reset: by that reset's seed, else by the OS (a new
        # env) or by the env's own `np_random` (a set replaced by the `contexts` setter, so a
        # seeded run stays reproducible).
        self._derive_seed = self._seeded
        self._seeded = False
        self._current = 0
        self.context: Context | None = None

    def _env_options(self, canonical_contexts: list[dict[str, Any]]) -> dict[str, Any] | None:
        """The runtime options of the set's runtimes (subclasses: e.g. the Brax walkers' goal)."""
        return None

    def _compat(self, canonical: dict[str, float]) -> Context:
        """A resolved context in carl-bench's names and order, typed (whole int and categorical
        values as int)."""
        feats = load_spec(self.env_id).features
        out: Context = {}
        for name, canon in self._name_maps()[0].items():
            if canon not in canonical:
                continue  # no numeric value (e.g. RNA's list of target ids)
            v = canonical[canon]
            choices = feats[canon].get("choices") or []
            if feats[canon]["type"] == "categorical" and float(v).is_integer() and 0 <= v < len(choices) and isinstance(choices[int(v)], str):
                out[name] = choices[int(v)]  # a string choice (RNA's dataset) by its name
            elif feats[canon]["type"] in ("int", "categorical") and float(v).is_integer():
                out[name] = int(v)
            else:
                out[name] = v
        return out

    @staticmethod
    def _selector(
        contexts: Contexts,
        selector: AbstractSelector | type[AbstractSelector] | None,
        kwargs: dict[str, Any] | None,
    ) -> AbstractSelector:
        if selector is None:
            return RoundRobinSelector(contexts)
        if inspect.isclass(selector):
            # carl-bench's own selector classes are accepted by name, so code that still imports
            # them from `carl.context.selection` works.
            cls = getattr(selection, selector.__name__, None) if selector.__name__ in _BUILTIN else selector
            if cls is None or not issubclass(cls, AbstractSelector):
                raise ValueError(f"context_selector must be a selector class or instance, got {selector!r}")
            return cls(contexts=contexts, **(kwargs or {}))
        if isinstance(selector, AbstractSelector):
            return selector
        if type(selector).__name__ in _BUILTIN:
            return getattr(selection, type(selector).__name__)(contexts)
        raise ValueError(f"context_selector must be None or a selector class or instance, got {type(selector).__name__}")

    @staticmethod
    def _check_selector(selector: Any) -> None:
        if selector is None or isinstance(selector, AbstractSelector) or inspect.isclass(selector):
            return
        if type(selector).__name__ in _BUILTIN:
            return
        raise ValueError(
            f"context_selector must be None or an AbstractSelector class or instance, got {type(selector).__name__}"
        )

    @staticmethod
    def _hull(spaces_: list[spaces.Space[Any]]) -> spaces.Space[Any]:
        first = spaces_[0]
        if not isinstance(first, spaces.Box) or len(spaces_) == 1:
            return first
        low = np.min([s.low for s in spaces_ if isinstance(s, spaces.Box)], axis=0)
        high = np.max([s.high for s in spaces_ if isinstance(s, spaces.Box)], axis=0)
        return spaces.Box(low=low, high=high, dtype=first.dtype)

    def get_observation_space(self, obs_context_feature_names: list[str] | None = None) -> spaces.Dict:
        """`Dict({"obs": base space, "context": Dict of Box(1,) per feature | Box(k,)})`."""
        names = self.obs_context_features if obs_context_feature_names is None else obs_context_feature_names
        feats = self.get_context_features()
        if self.obs_context_as_dict:
            ctx: spaces.Space[Any] = spaces.Dict(
                {n: spaces.Box(low=feats[n].lower, high=feats[n].upper, shape=(1,), dtype=np.float32) for n in names}
            )
        else:
            ctx = spaces.Box(
                low=np.array([feats[n].lower for n in names], dtype=np.float32),
                high=np.array([feats[n].upper for n in names], dtype=np.float32),
                dtype=np.float32,
            )
        return spaces.Dict({"obs": self.base_observation_space, "context": ctx})

    # -- carl-bench's properties ---------------------------------------------------------------

    @property
    def contexts(self) -> Contexts:
        """The context set by the user's keys, every feature filled in (carl-bench's names)."""
        return {k: dict(c) for k, c in self._contexts.items()}

    @contexts.setter
    def contexts(self, contexts: Contexts) -> None:
        """Replace the context set (curricula): checked like the constructor's `contexts`, filled
        with the defaults, selected by a fresh selector of the same kind from the next reset on
        (round robin starts again at the first context). The running episode keeps its context:
        carl-spec never changes a context during an episode."""
        running = (self._runtime(), self._current, self.context) if self._started else None
        self._set_contexts(contexts)
        self._ctor["contexts"] = contexts
        if running is not None:
            # Steps until the next reset continue the running episode (its runtime, its context
            # and its context_id in the infos).
            self._running, self._current, self.context = running

    @property
    def context_id(self) -> int | None:
        """Position of the current context in `contexts` (None before the first reset)."""
        return self.context_selector.context_id

    @context_id.setter
    def context_id(self, new_id: int) -> None:
        """Switch to context `new_id` from the next reset on (round robin continues after it,
        static stays on it). carl-bench switches in the middle of the episode; carl-spec never
        changes a context during an episode."""
        if new_id not in self.context_selector.context_ids:
            raise ValueError(f"context id {new_id} is not in the context set (ids 0..{len(self._keys) - 1})")
        if len(self._keys) > 1:
            self._chooser.set_instance(int(new_id))
            self._continue_after = int(new_id)
        self.context_selector.context_id = int(new_id)
        self._chosen = int(new_id)
        self.context = dict(self._contexts[self._keys[int(new_id)]])

    # -- the Gymnasium API -----------------------------------------------------------------

    def _context_obs(self, i: int) -> Any:
        """Instance `i`'s context as observed (float32), built once per episode (contexts never
        change within one); every observation gets its own copy (users keep observations)."""
        ctx = self._numeric[i]
        if self.obs_context_as_dict:
            return {n: np.array([ctx[n]], dtype=np.float32) for n in self.obs_context_features}
        return np.array([ctx[n] for n in self.obs_context_features], dtype=np.float32)

    def _observe(self, obs: np.ndarray) -> dict[str, Any]:
        c = self._context_obs_cache
        context = {n: a.copy() for n, a in c.items()} if isinstance(c, dict) else c.copy()
        return {"obs": obs, "context": context}

    def _select(self, seed: int | None) -> tuple[int, int | None]:
        """Choose the next context (carl-bench's `_progress_instance`): returns its position and
        the seed its runtime resets with. Round robin starts at the first context when the first
        selection is unseeded (as carl-bench's); a seed `s` starts it at `s mod n`."""
        first = not self._seeded
        seed_for_streams = seed
        if seed is None and first:
            seed_for_streams = int(self.np_random.integers(2**63)) if self._derive_seed else os_entropy_seed()
        self._seeded = True
        if self._custom:
            self.context_selector.select()
            i = int(self.context_selector.context_id or 0)
            env_seed = seed_for_streams if (seed is not None or first) else None
        else:
            info, env_seed = self._chooser.reset(seed_for_streams)
            n = len(self._keys)
            after = self._continue_after
            if seed is None and first and n > 1 and (self.context_selector.mode == "round_robin" or after is not None):
                # The streams are seeded from the OS; the instances start at 0 as carl-bench's
                # (or after the context `env.context_id = i` switched to).
                self._chooser.set_instance(n - 1 if after is None else after)
                info, env_seed = self._chooser.reset(None)
            i = int(info.get("instance_id", 0))
            self.context_selector.context_id = i
            self.context_selector.n_calls += 1
        self._chosen = i
        self.context = dict(self._contexts[self._keys[i]])
        return i, env_seed

    def _runtime(self) -> Any:
        """The runtime of the running episode (the replaced set's until the next reset)."""
        return self._envs[self._current] if self._running is None else self._running

    def _progress_instance(self) -> None:
        """carl-bench's: select the next context (`env.context`, `env.context_id`) as a reset
        does; the reset after it selects again. The runtime switches at the next reset."""
        self._select(None)

    def _update_context(self) -> None:
        """carl-bench's: make `env.context` the context the physics runs. In carl-spec every
        context of the set has its own runtime, bound when the set is built, so there is nothing to
        push; a context changed in place never reaches the physics and is refused, naming the fix."""
        if self.context is None or self._chosen is None:
            return
        bound = self._contexts[self._keys[self._chosen]]
        if self.context != bound:
            changed = sorted(k for k in set(self.context) | set(bound) if self.context.get(k) != bound.get(k))
            raise ValueError(
                f"{type(self).__name__}: env.context was changed in place ({', '.join(changed)}); carl-spec binds each "
                "context when the set is built and never changes the physics during an episode. Set "
                "`env.contexts = {id: context}` (checked, used from the next reset) instead"
            )

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[dict[str, Any], dict[str, Any]]:
        super().reset(seed=seed)
        i, env_seed = self._select(seed)
        self._current = i
        self._running = None
        self._started = True
        self._context_obs_cache = self._context_obs(i)
        obs, _ = self._envs[i].reset(env_seed)
        return self._observe(obs), {"context_id": i}

    def step(self, action: Any) -> tuple[dict[str, Any], SupportsFloat, bool, bool, dict[str, Any]]:
        if not self._discrete:
            action = np.asarray(action, dtype=np.float32).reshape(-1)
        elif type(action) is not int:
            action = discrete_action(type(self).__name__, self.action_space, action)
        runtime = self._runtime()
        try:
            obs, reward, terminated, truncated = runtime.step(action)
        except OverflowError:
            raise ValueError(f"{type(self).__name__}: action {action} is not in {self.action_space}") from None
        return self._observe(obs), reward, terminated, truncated, {"context_id": self._current}

    def render(self) -> np.ndarray | None:
        if self.render_mode == "rgb_array":
            frame: np.ndarray = self._runtime().render()
            return frame
        return None

    def __reduce__(self) -> tuple[Any, ...]:
        return (_rebuild, (type(self), self._ctor))


def _rebuild(cls: type[CARLEnv], ctor: dict[str, Any]) -> CARLEnv:
    return cls(**ctor)
