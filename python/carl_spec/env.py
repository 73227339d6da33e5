"""`carl_spec.make`: one contextual environment as a `gymnasium.Env` (the Rust `ContextualEnv`)."""

from __future__ import annotations

import dataclasses
import json
import os
from typing import Any, SupportsFloat

import gymnasium
import numpy as np
from gymnasium.envs.registration import EnvSpec

from . import _core
from ._args import NoiseStd, check_name, check_seed, context_args, json_object
from ._errors import InvalidActionError, curriculum_bounds_hint
from ._spaces import space_from_json
from .curriculum import check_selector


def os_entropy_seed() -> int:
    """A 64-bit seed from the OS (what an env never seeded uses, so parallel workers differ)."""
    return int.from_bytes(os.urandom(8), "little")


def discrete_action(env_id: str, space: gymnasium.spaces.Space[Any], action: Any) -> int:
    """A Discrete action as an int: a Python int, a NumPy integer scalar or a 0-d integer array.
    Bools (Python's and NumPy's), floats (even 1.0), strings and arrays of any other shape are
    refused, naming the space; `Discrete.contains`' rule, with bools refused as well."""
    if isinstance(action, (bool, np.bool_)):
        raise InvalidActionError(
            f"{env_id}: a {space} action is an int, got the bool {bool(action)} (pass int(action) if you mean {int(action)})"
        )
    if isinstance(action, int):
        return action
    if isinstance(action, (np.ndarray, np.generic)):
        if np.issubdtype(action.dtype, np.integer) and action.shape == ():
            return int(action)
        if action.shape != ():
            raise InvalidActionError(
                f"{env_id}: a {space} action is an int (or a NumPy integer scalar), got a NumPy array of "
                f"shape {action.shape}; pass one element (e.g. int(action[0]))"
            )
        raise InvalidActionError(
            f"{env_id}: a {space} action is an int (or a NumPy integer scalar), got a {action.dtype} value {action!r}"
        )
    raise InvalidActionError(
        f"{env_id}: a {space} action is an int (or a NumPy integer scalar), got {type(action).__name__} {action!r:.80}"
    )


def box_action(env_id: str, space: gymnasium.spaces.Space[Any], action: Any) -> np.ndarray:
    """A Box action as float64 components: numbers only (None, strings, objects and bools are
    refused, naming the space); the native step refuses non-finite components and clips finite
    ones to the space, as Gymnasium's own environments clip."""
    a = action if isinstance(action, np.ndarray) else np.asarray(action)
    if a.dtype.kind not in "iuf":
        raise InvalidActionError(
            f"{env_id}: a {space} action is numbers, got {type(action).__name__} {_short(action)}"
        )
    return np.ascontiguousarray(a, dtype=np.float64).reshape(-1)


#: The keys `reset(options=...)` takes.
RESET_OPTIONS = ("instance",)


def reset_instance(options: Any, valid: tuple[str, ...] = RESET_OPTIONS) -> int | None:
    """`options["instance"]` of a `reset` (None without it), checked: a dict whose keys are
    `valid`, the instance a non-negative int (Python or NumPy; not a bool). Whether the set has
    that instance is checked by the environment (a ValueError naming the set's size)."""
    if options is None:
        return None
    if not isinstance(options, dict):
        raise TypeError(f"reset options must be a dict or None, got {type(options).__name__}")
    unknown = sorted(str(k) for k in options if k not in valid)
    if unknown:
        raise ValueError(
            f"reset options {', '.join(repr(k) for k in unknown)} are not known; valid keys: {', '.join(valid)}"
        )
    if "instance" not in options or options["instance"] is None:
        return None
    return instance_index(options["instance"], "options['instance']")


def instance_index(i: Any, what: str) -> int:
    """An instance index: a non-negative int (a TypeError for anything else that is not an int)."""
    if isinstance(i, (bool, np.bool_)) or not isinstance(i, (int, np.integer)):
        raise TypeError(f"{what} must be an instance index (a non-negative int), got {type(i).__name__} {i!r}")
    if i < 0 or i >= 2**63:
        raise ValueError(f"{what}={int(i)} is not an instance index (0, 1, ..., the set's size - 1)")
    return int(i)


def _short(x: Any) -> str:
    text = repr(x)
    return text if len(text) <= 80 else text[:80] + "…"


def _with_numpy_seed(info: dict[str, Any]) -> dict[str, Any]:
    if "context_seed" in info:
        # A NumPy scalar, so Gymnasium's vector envs can batch it (it may exceed int64).
        info["context_seed"] = np.uint64(info["context_seed"])
    return info


def _fresh(info: dict[str, Any]) -> dict[str, Any]:
    """A copy users may keep and modify (the nested objects are dicts of floats)."""
    out = dict(info)
    out["context"] = dict(info["context"])
    if "observed_context" in info:
        out["observed_context"] = dict(info["observed_context"])
    return out


class CarlEnv(gymnasium.Env[np.ndarray, Any]):
    """A carl-spec environment under a context source.

    Exactly one of `context` (a fixed context: feature -> value, missing features at their
    defaults), `instances` (a frozen set `ENV/SET`, chosen per reset by `selection`:
    "round_robin", "random" or "static" with `instance=i`) or `distribution` (a named
    distribution of the spec, drawn afresh at every reset); none means the default context.
    `obs_context` appends features to the observation (a list of names, or True for all); for
    pixel observations (uint8) the observation becomes `{"obs": pixels, "context": float32}`.
    `context_noise` shows the agent visible features with Gaussian noise, `{name: std}` with std a
    number (the feature's unit) or a percentage of |default| ("10%"), drawn anew every episode
    (`context_noise_redraw="episode"`) or every step ("step"); the dynamics keep the true value and
    `info["observed_context"]` holds what the agent saw. `options` selects the runtime's variant
    (`{"continuous": True}` for LunarLanderContinuous, `{"hardcore": True}`, ...; unknown names are
    refused with the valid ones); for `rna_design`, `{"target_structure_ids": [1, 5]}` picks the
    targets (ids of the dataset's targets; unknown ids are refused with the valid range), and the
    info of an episode's last step holds `sequence`, `folded_structure`, `target_structure`,
    `target_id` and the Hamming distances. A fixed context outside the spec's bounds is refused (naming the
    feature and its bounds) unless `allow_out_of_bounds=True`.

    Schedules: `schedules={feature: {"kind": ...}}` changes dynamics features within every
    episode, from the episode's own value `b` at step `t` (0 at reset): `{"kind": "step", "at": t0,
    "to": x}`, `{"kind": "linear", "to": x, "over": n}` (reaches x after n steps), `{"kind": "sine",
    "amplitude": a, "period": p, "phase": 0}`, `{"kind": "random_walk", "std": s, "low": lo, "high":
    hi}` (seeded by `reset(seed=...)`, reflected into [lo, hi]). `info["context"]` holds the current
    values at every step. A schedule that can leave a feature's bounds, a feature that does not act
    on the dynamics, or an environment whose runtime cannot change its context mid-episode (the
    classic-control five can) raises a ValueError naming the problem.

    Curricula: `curriculum=` an object with `select(env_index)`, `update(env_index, context,
    episode_return)` and `describe()` (`carl_spec.curriculum`: `AutomaticDomainRandomization`,
    `SelfPacedCurriculum`, or your own) chooses each episode's context at reset and hears every
    finished episode's context and return; `info["curriculum"]` holds `describe()`. It needs a
    fixed `context=` or a `distribution=` as the source (not `instances=`).

    Seeding: `reset(seed=s)` determines everything that follows (instance choice, draws, initial
    states); the classic five start from the state Gymnasium's env starts from with seed `s`.
    An env never seeded draws its first seed from the OS. `reset(options={"instance": i})` plays
    instance `i` of the set (round-robin selection goes on from `i + 1`); an index outside the
    set, a source that is no set, a non-integer index or another option key raise an error.

    The observation space depends on the environment, its version, `options`, `obs_context` and
    `context_noise` only, never on the context source: train on one set or distribution, test on
    another (Stable-Baselines3's `model.set_env(test_env)`, `DQN.load(path, env=test_env)`). A
    visible feature's bounds are the spec's declared bounds, so a set that deliberately goes out
    of bounds (Landing in Space's Jupiter) shows a value outside them.

    Outcome: at the step that ends an episode, `info["outcome"]` says how it ended where the
    environment defines it (LunarLander `landed` / `crashed` / `out_of_view`, CartPole `failed`,
    MountainCar and Acrobot `solved`, BipedalWalker `fell` / `solved`), and `timed_out` at the
    time limit.

    Actions: a Discrete action is an int, a NumPy integer scalar or a 0-d integer array; bools,
    floats and arrays of other shapes raise `carl_spec.InvalidActionError` (a ValueError and a
    TypeError), an int outside the space a ValueError. A Box action is numbers NumPy turns into
    the space's components (None, strings and bools raise `InvalidActionError`); NaN and ±inf
    raise a ValueError naming the component, and finite values outside the space are clipped to
    it, as Gymnasium's own environments clip. A non-finite observation or reward (a context that
    drives the dynamics outside their meaningful range) raises a ValueError naming the step and
    the component, as `carl-spec rollout` does. Seeds follow Gymnasium's rule (None or a
    non-negative int), below 2**64.

    Episodes truncate at the spec's `max_episode_steps` (`env.spec.max_episode_steps` under
    `gymnasium.make`). Pickling (what `AsyncVectorEnv`, SB3's `SubprocVecEnv` and Ray do with
    env functions and envs) keeps the constructor arguments and Gymnasium's spec: the copy is a
    new environment to reset, without the episode in progress or the random streams' position.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 50}

    def __init__(
        self,
        env: str,
        *,
        context: dict[str, Any] | None = None,
        instances: str | None = None,
        distribution: str | None = None,
        selection: str = "round_robin",
        instance: int | None = None,
        obs_context: list[str] | bool | None = None,
        render_mode: str | None = None,
        specs_dir: str | os.PathLike[str] | None = None,
        context_noise: dict[str, NoiseStd] | None = None,
        context_noise_redraw: str = "episode",
        options: dict[str, Any] | None = None,
        allow_out_of_bounds: bool = False,
        schedules: dict[str, dict[str, Any]] | None = None,
        curriculum: Any = None,
    ) -> None:
        source: dict[str, Any] = dict(
            context=context,
            instances=instances,
            distribution=distribution,
            selection=selection,
            instance=instance,
            obs_context=obs_context,
            context_noise=context_noise,
            context_noise_redraw=context_noise_redraw,
            options=options,
            allow_out_of_bounds=allow_out_of_bounds,
            schedules=schedules,
        )
        self._ctor: dict[str, Any] = dict(
            env=env, render_mode=render_mode, specs_dir=specs_dir, curriculum=curriculum, **source
        )
        self._curriculum = None if curriculum is None else check_selector(curriculum)
        self._return = 0.0
        self._spec: EnvSpec | None = None
        self._core = _core.Env(
            check_name("env", env),
            context_args(**source),
            specs_dir=None if specs_dir is None else os.fspath(specs_dir),
        )
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode must be one of {self.metadata['render_modes']} or None, got {render_mode!r}")
        if render_mode is not None and not self._core.has_renderer():
            raise ValueError(f"{self._core.id} has no renderer; use render_mode=None")
        self.render_mode = render_mode
        self.env_id: str = self._core.id
        self.observation_space = space_from_json(json.loads(self._core.observation_space_json()))
        self.action_space = space_from_json(json.loads(self._core.action_space_json()))
        self._discrete = isinstance(self.action_space, gymnasium.spaces.Discrete)
        self._seeded = False
        self._info: dict[str, Any] = {}
        self._noise_per_step = self._core.noise_redraw() == "step"
        self._scheduled = schedules is not None and len(schedules) > 0
        self._goal = False

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[np.ndarray, dict[str, Any]]:
        check_seed(seed)
        instance = reset_instance(options)
        super().reset(seed=seed)
        if seed is None and not self._seeded:
            seed = os_entropy_seed()
        if seed is not None:
            self._seeded = True
        if self._curriculum is not None:
            with curriculum_bounds_hint(self._curriculum):
                self._core.set_next_context(json_object("curriculum context", self._curriculum.select(0)))
            self._return = 0.0
        obs, info = self._core.reset(seed, instance)
        self._info = _with_numpy_seed(info)
        if self._curriculum is not None:
            self._info["curriculum"] = self._curriculum.describe()
        self._goal = self._core.goal_info() is not None
        out = _fresh(info)
        if self._goal:
            out.update(self._core.goal_info() or {})
        return obs, out

    def step(self, action: Any) -> tuple[np.ndarray, SupportsFloat, bool, bool, dict[str, Any]]:
        if not self._discrete:
            action = box_action(self.env_id, self.action_space, action)
        elif type(action) is not int:
            action = discrete_action(self.env_id, self.action_space, action)
        try:
            obs, reward, terminated, truncated = self._core.step(action)
        except OverflowError:
            raise ValueError(f"{self.env_id}: action {action} is not in {self.action_space}") from None
        if self._noise_per_step:
            self._info["observed_context"] = self._core.observed_context()
        if self._scheduled:
            self._info["context"].update(self._core.scheduled_context())
        if self._curriculum is not None:
            self._return += reward
            if terminated or truncated:
                self._curriculum.update(0, dict(self._info["context"]), self._return)
                self._info["curriculum"] = self._curriculum.describe()
        info = _fresh(self._info)
        if self._goal:
            info.update(self._core.goal_info() or {})
        if terminated or truncated:
            outcome = self._core.outcome()
            if outcome is not None:
                info["outcome"] = outcome
        if terminated:
            end = self._core.episode_end_info()
            if end is not None:
                info.update(end)
        return obs, reward, terminated, truncated, info

    def render(self) -> np.ndarray | None:
        if self.render_mode == "rgb_array":
            return self._core.render()
        return None

    @property
    def context(self) -> dict[str, float]:
        """The current episode's context (every feature, canonical names)."""
        return dict(self._info.get("context", self._core.info()["context"]))

    @property
    def state(self) -> list[float]:
        """The runtime's internal float64 state."""
        return self._core.state()

    def set_state(self, state: list[float]) -> None:
        """Set the runtime's internal state (a list as `state` returns it). Like `reset`, it
        makes `step` valid; before the first reset the episode runs under the current context
        (the fixed context, or the source's first before any draw), reported in `info`."""
        self._core.set_state(list(state))
        if not self._info:
            info = self._core.info()
            if self._core.noise_redraw() is not None:
                info["observed_context"] = self._core.observed_context()
            self._info = _with_numpy_seed(info)

    @property
    def spec(self) -> EnvSpec | None:
        """Gymnasium's spec of the env, as `gymnasium.make` sets it, with `max_episode_steps`
        the episode limit the runtime truncates at (the spec's). The runtime truncates itself,
        so `gymnasium.make` adds no `TimeLimit` (one with `max_episode_steps=n` shortens the
        episodes to `n` steps; a longer limit than the spec's cannot take effect)."""
        return self._spec

    @spec.setter
    def spec(self, value: EnvSpec | None) -> None:
        limit = self._core.max_episode_steps
        if value is not None and value.max_episode_steps is None and limit is not None:
            value = dataclasses.replace(value, max_episode_steps=int(limit))
        self._spec = value

    def __reduce__(self) -> tuple[Any, ...]:
        # Pickles as its constructor arguments (AsyncVectorEnv, SubprocVecEnv, Ray ship envs
        # so), and Gymnasium's spec: the copy is a new environment (reset it before stepping);
        # the episode in progress, the seed and the random streams are not carried over.
        return (_rebuild_env, (self._ctor,), {"_spec": self._spec})


def _rebuild_env(ctor: dict[str, Any]) -> CarlEnv:
    return CarlEnv(**ctor)
