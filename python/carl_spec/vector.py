"""`carl_spec.make_vec`: a batch stepped in Rust as one `gymnasium.vector.VectorEnv`."""

from __future__ import annotations

import json
import os
from typing import Any

import gymnasium
import numpy as np
from gymnasium.error import ClosedEnvironmentError
from gymnasium.vector import AutoresetMode
from gymnasium.vector.utils import batch_space

from . import _core
from ._args import NoiseStd, check_int, check_name, check_seed, context_args, json_object, quote
from ._errors import curriculum_bounds_hint
from ._spaces import space_from_json
from .curriculum import check_selector
from .env import instance_index, os_entropy_seed

_MODES = {
    "next_step": AutoresetMode.NEXT_STEP,
    "same_step": AutoresetMode.SAME_STEP,
    "disabled": AutoresetMode.DISABLED,
}


def _mode_name(mode: str | AutoresetMode) -> str:
    if isinstance(mode, AutoresetMode):
        return {v: k for k, v in _MODES.items()}[mode]
    return str(mode)


class CarlVectorEnv(gymnasium.vector.VectorEnv[np.ndarray, np.ndarray, np.ndarray]):
    """`num_envs` environments stepped by one call into Rust (GIL released, `threads` threads).

    Each environment has its own context source state: with `instances` or `distribution`, every
    (auto)reset of environment `i` re-selects its context from its own streams, and
    `infos["instance_id"]` holds every environment's instance. `autoreset_mode` is Gymnasium's:
    "next_step" (default), "same_step" (`final_obs` / `final_info` in the infos) or "disabled"
    (reset with `options={"reset_mask": mask}`). `reset(seed=s)` seeds environment `i` with
    `s + i`, as Gymnasium's vector envs do; `reset(seed=[s0, s1, ...])` each with its own, in
    one native call. `options={"instance": [i0, i1, ...]}` plays instance `i_k` of the set in
    environment `k` (None or -1: its own selection). The observation space is the same for every
    context source (see `CarlEnv`). At the step that ends an episode, `infos["outcome"]` (with
    `_outcome`; in same-step mode inside `final_info`) says how it ended where the environment
    defines it (`landed`, `solved`, `timed_out`, ...). `context_noise`, `context_noise_redraw`, `options`,
    `allow_out_of_bounds`, `schedules` and `curriculum` are `carl_spec.make`'s (see `CarlEnv`; under
    a schedule `infos["context"]` holds every environment's current values at every step; a
    curriculum chooses each environment's next context when its episode ends, so it needs
    `autoreset_mode` "next_step" or "disabled", and `infos["curriculum"]` is its `describe()` at
    reset and at steps that end an episode); with noise,
    `infos["observed_context"]` holds what each environment observes (`{feature: (num_envs,)}`
    plus Gymnasium's `_feature` / `_observed_context` masks). In same-step mode
    `infos["final_info"]` is the finished episodes' step info (`context`, `instance_id`, ...) in
    the same vector layout, as Gymnasium's `SyncVectorEnv` over `carl_spec.make` envs gives it.
    The infos at reset and at every step are `SyncVectorEnv`'s over `cs.make` envs key for key
    (`context`, `instance_id` / `instance_name` from a set, `context_seed` from a distribution,
    masked to the envs that were reset); their context arrays are read-only. Actions, seeds and
    outputs are checked as `cs.make` checks them; `num_envs` is at most 65,536 (4,096 for physics
    and pixel envs) and `threads` at most 256, as `carl-spec bench`. `get_attr` / `call` give each
    environment's `context`, `context_info()`, `instance_id`, `state` and spaces.
    Episodes are truncated at the spec's limit (`max_episode_steps`, if given, must equal it).
    `close()` frees the batch; any later call raises Gymnasium's `ClosedEnvironmentError`.
    """

    def __init__(
        self,
        env: str,
        num_envs: int,
        *,
        context: dict[str, Any] | None = None,
        instances: str | None = None,
        distribution: str | None = None,
        selection: str = "round_robin",
        instance: int | None = None,
        obs_context: list[str] | bool | None = None,
        autoreset_mode: str | AutoresetMode = "next_step",
        threads: int = 1,
        specs_dir: str | os.PathLike[str] | None = None,
        render_mode: str | None = None,
        context_noise: dict[str, NoiseStd] | None = None,
        context_noise_redraw: str = "episode",
        options: dict[str, Any] | None = None,
        allow_out_of_bounds: bool = False,
        schedules: dict[str, dict[str, Any]] | None = None,
        curriculum: Any = None,
        max_episode_steps: int | None = None,
    ) -> None:
        if render_mode is not None:
            raise ValueError("make_vec does not render; use carl_spec.make(..., render_mode='rgb_array')")
        if max_episode_steps is not None:
            _check_episode_limit(env, max_episode_steps, specs_dir)
        mode = _mode_name(autoreset_mode)
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
        num_envs = check_int("num_envs", num_envs, 1)
        threads = check_int("threads", threads, 1)
        self._ctor: dict[str, Any] = dict(
            env=env, num_envs=num_envs, autoreset_mode=mode, threads=threads, specs_dir=specs_dir,
            curriculum=curriculum, **source
        )
        self._curriculum = None if curriculum is None else check_selector(curriculum)
        if self._curriculum is not None and _MODES[mode] == AutoresetMode.SAME_STEP:
            raise ValueError(
                "a curriculum chooses each episode's context when the previous one ends, before the reset: "
                "use autoreset_mode='next_step' (the default) or 'disabled', not 'same_step'"
            )
        self._core = _core.VecEnv(
            check_name("env", env),
            num_envs,
            context_args(**source, curriculum=self._curriculum is not None),
            autoreset_mode=check_name("autoreset_mode", mode),
            threads=threads,
            specs_dir=None if specs_dir is None else os.fspath(specs_dir),
        )
        self.num_envs = num_envs
        self.render_mode = None
        self.metadata = {"autoreset_mode": _MODES[mode], "render_modes": []}
        self.single_observation_space = space_from_json(json.loads(self._core.observation_space_json()))
        self.single_action_space = space_from_json(json.loads(self._core.action_space_json()))
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self.action_space = batch_space(self.single_action_space, num_envs)
        self._seeded = False
        self._mode = _MODES[mode]
        self._same_step = self._mode == AutoresetMode.SAME_STEP
        self._end_info = self._core.has_episode_end_info
        self._returns = np.zeros(num_envs)
        if not self._end_info and self._curriculum is None and type(self).step is CarlVectorEnv.step:
            # Nothing to add in Python: the batch step is the native call itself (one Python
            # frame less per batch step; a subclass that overrides `step` keeps its own).
            self.step = self._core.step  # type: ignore[method-assign]

    def reset(
        self, *, seed: int | list[int | None] | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        mask = None
        instances = None
        if options is not None:
            if not isinstance(options, dict):
                raise TypeError(f"reset options must be a dict or None, got {type(options).__name__}")
            unknown = sorted(str(k) for k in options if k not in ("reset_mask", "instance"))
            if unknown:
                raise ValueError(
                    f"reset options {', '.join(repr(k) for k in unknown)} are not known; valid keys: reset_mask, instance"
                )
        if options is not None and "reset_mask" in options:
            if self._mode != AutoresetMode.DISABLED:
                raise ValueError("options['reset_mask'] is for autoreset_mode='disabled'")
            mask = np.asarray(options["reset_mask"])
            if mask.dtype != np.bool_ or mask.shape != (self.num_envs,) or not mask.any():
                raise ValueError(f"options['reset_mask'] must be a bool array of shape ({self.num_envs},) with a True value")
        if options is not None and options.get("instance") is not None:
            instances = self._instances(options["instance"])
        if self._curriculum is not None:
            for i in range(self.num_envs) if mask is None else np.flatnonzero(mask):
                self._choose(int(i))
                self._returns[i] = 0.0
        if isinstance(seed, (list, tuple)) or instances is not None:
            if isinstance(seed, (list, tuple)):
                if len(seed) != self.num_envs:
                    raise ValueError(f"seed list must have num_envs={self.num_envs} entries, got {len(seed)}")
                seeds = list(seed)
                # The common case checked in one pass (ints and Nones in range); anything else
                # entry by entry, for the error naming the first bad one.
                ints = [s for s in seeds if s is not None]
                if not all(type(s) is int for s in ints) or (ints and not (0 <= min(ints) and max(ints) < 2**64)):
                    seeds = [check_seed(s, f"seed[{i}]") for i, s in enumerate(seeds)]
            else:
                s0 = check_seed(seed)
                if s0 is not None and s0 + self.num_envs - 1 >= 2**64:
                    raise ValueError(f"seed={s0}: environment i is seeded with seed + i, which must stay below 2**64")
                seeds = [None if s0 is None else s0 + i for i in range(self.num_envs)]
            if not self._seeded:
                entropy = os_entropy_seed()
                seeds = [(entropy + i) % 2**64 if s is None else s for i, s in enumerate(seeds)]
            self._seeded = True
            # One native call resets every chosen env with its own seed (and instance).
            obs = self._core.reset_each(seeds, instances, mask)
            return obs, self._with_curriculum(self._core.infos(mask))
        if isinstance(seed, int) and not isinstance(seed, bool):
            # Env i gets seed + i, as Gymnasium's vector envs seed it: each must be a seed.
            check_seed(seed)
            if seed + self.num_envs - 1 >= 2**64:
                raise ValueError(
                    f"seed={seed}: environment i is seeded with seed + i, and the last environment's seed "
                    f"({seed + self.num_envs - 1}) is not below 2**64"
                )
        else:
            check_seed(seed)
        if seed is None and not self._seeded:
            seed = os_entropy_seed() % (2**64 - self.num_envs)
        if seed is not None:
            self._seeded = True
        obs = self._core.reset(seed, mask)
        return obs, self._with_curriculum(self._core.infos(mask))

    def _choose(self, i: int) -> None:
        """The curriculum's context for environment `i`'s next episode."""
        assert self._curriculum is not None
        with curriculum_bounds_hint(self._curriculum):
            self._core.set_next_context(i, json_object("curriculum context", self._curriculum.select(i)))

    def _with_curriculum(self, infos: dict[str, Any]) -> dict[str, Any]:
        if self._curriculum is not None:
            infos["curriculum"] = self._curriculum.describe()
        return infos

    def _curriculum_step(self, rewards: np.ndarray, done: np.ndarray, infos: dict[str, Any]) -> None:
        """Returns summed; each finished episode's context and return to the curriculum, and (next-step
        autoreset) the context of the episode that starts at the next step chosen now."""
        assert self._curriculum is not None
        self._returns += rewards
        ended = [int(i) for i in np.flatnonzero(done)]
        for i in ended:
            info = self._core.context_info(i)
            self._curriculum.update(i, dict(info["context"]) if info else {}, float(self._returns[i]))
            self._returns[i] = 0.0
            if self._mode == AutoresetMode.NEXT_STEP:
                self._choose(i)
        if len(ended):
            infos["curriculum"] = self._curriculum.describe()

    def _instances(self, value: Any) -> list[int | None]:
        """`options["instance"]`: one instance index per env (None or -1: the selection's pick)."""
        if isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_)):
            raise TypeError(
                f"options['instance'] of a vector env is one instance per environment: a sequence of "
                f"{self.num_envs} ints (None or -1: the env's own selection), got {value!r}"
            )
        try:
            items = list(value)
        except TypeError:
            raise TypeError(f"options['instance'] must be a sequence of {self.num_envs} ints, got {type(value).__name__}") from None
        if len(items) != self.num_envs:
            raise ValueError(f"options['instance'] must have num_envs={self.num_envs} entries, got {len(items)}")
        return [
            None if (k is None or (not isinstance(k, (bool, np.bool_)) and isinstance(k, (int, np.integer)) and k == -1))
            else instance_index(k, f"options['instance'][{i}]")
            for i, k in enumerate(items)
        ]

    def step(self, actions: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        # One call: actions in, the GIL released around the native batch step, the arrays and
        # Gymnasium's vector infos (same-step `final_obs` / `final_info`, `instance_id`,
        # `observed_context`) built in Rust.
        out = self._core.step(actions)
        if self._end_info and out[2].any():
            self._add_episode_end_info(out[4], out[2])
        if self._curriculum is not None:
            self._curriculum_step(out[1], out[2] | out[3], out[4])
        return out

    def _add_episode_end_info(self, infos: dict[str, Any], terminated: np.ndarray) -> None:
        # rna_design's sequences: Gymnasium's own layout, env by env (only at episode ends).
        target = infos["final_info"] if self._same_step else infos
        for i in np.flatnonzero(terminated):
            end = self._core.episode_end_info(int(i))
            if end is not None:
                target = self._add_info(target, end, int(i))
        if self._same_step:
            infos["final_info"] = target
        else:
            infos.update(target)

    def close_extras(self, **kwargs: Any) -> None:
        """Frees the native batch: any later `reset`, `step` or query raises Gymnasium's
        `ClosedEnvironmentError` (as `AsyncVectorEnv` does), never steps a closed batch."""
        self.__dict__.pop("step", None)  # the native step bound in __init__
        # A batch whose construction failed part way has neither (Gymnasium's __del__ still closes it).
        ctor = self.__dict__.get("_ctor", {})
        self._core = _ClosedCore(f"make_vec({ctor.get('env')!r}, {ctor.get('num_envs')})")  # type: ignore[assignment]

    def context_info(self, i: int) -> dict[str, Any] | None:
        """Environment `i`'s current context info (contexts from a set or distribution)."""
        return self._core.context_info(check_int("i", i, 0, self.num_envs - 1))

    # -- Gymnasium's per-environment access (`SyncVectorEnv.get_attr` / `call` / `set_attr`) -----

    def call(self, name: str, *args: Any, **kwargs: Any) -> tuple[Any, ...]:
        """Each environment's attribute `name` (called with the arguments if it is a method), as
        `SyncVectorEnv.call` returns it for `cs.make` environments. The batch's environments are
        native, so these are available: `context`, `context_info()`, `instance_id`, `state`,
        `observation_space`, `action_space`, `render_mode`, `metadata`, `np_random_seed` is not."""
        name = check_name("name", name)
        out = []
        for i in range(self.num_envs):
            value = self._env_attr(i, name)
            out.append(value(*args, **kwargs) if callable(value) and not isinstance(value, gymnasium.spaces.Space) else value)
        return tuple(out)

    def get_attr(self, name: str) -> tuple[Any, ...]:
        """Each environment's attribute `name` (see `call`)."""
        return self.call(name)

    def set_attr(self, name: str, values: list[Any] | tuple[Any, ...] | Any) -> None:
        """Gymnasium's `set_attr`: the batch's environments are native and have no settable
        attribute, so this raises, naming what to do instead."""
        raise AttributeError(
            f"make_vec environments have no settable attribute {quote(str(name))}: contexts come from "
            "context=, instances= or distribution= (make a new batch to change them)"
        )

    def _env_attr(self, i: int, name: str) -> Any:
        core = self._core
        if name == "context":
            info = core.context_info(i)
            return dict(info["context"]) if info is not None else _plain_context(core.infos(), i)
        if name == "context_info":
            return lambda: _context_info(core, i)
        if name == "instance_id":
            info = _context_info(core, i)
            return info.get("instance_id")
        if name == "state":
            return core.state(i)
        if name == "observation_space":
            return self.single_observation_space
        if name == "action_space":
            return self.single_action_space
        if name in ("render_mode", "metadata", "spec"):
            return getattr(self, name)
        raise AttributeError(
            f"make_vec environments have no attribute {quote(name)} (get_attr/call support context, context_info, "
            "instance_id, state, observation_space, action_space, render_mode, metadata, spec)"
        )

    def __reduce__(self) -> tuple[Any, ...]:
        return (_rebuild_vec, (self._ctor,))


def _context_info(core: Any, i: int) -> dict[str, Any]:
    """Environment `i`'s info as `cs.make` reports it (`context`, and its set or draw labels)."""
    info = core.context_info(i)
    if info is not None:
        return dict(info)
    return {"context": _plain_context(core.infos(), i)}


def _plain_context(infos: dict[str, Any], i: int) -> dict[str, float]:
    ctx = infos["context"]
    return {k: float(v[i]) for k, v in ctx.items() if not k.startswith("_")}


def _check_episode_limit(env: str, max_episode_steps: int, specs_dir: str | os.PathLike[str] | None) -> None:
    """`max_episode_steps` (as `gymnasium.make_vec` passes it) must be the spec's episode limit:
    the batch truncates there in Rust, and no wrapper sits inside it to truncate earlier."""
    limit = json.loads(_core.spec_json(env, None if specs_dir is None else os.fspath(specs_dir)))["max_episode_steps"]
    if max_episode_steps != limit:
        raise ValueError(
            f"make_vec({env!r}) truncates episodes at the spec's limit ({limit} steps); max_episode_steps="
            f"{max_episode_steps} is not supported here: gymnasium.make_vec(..., vectorization_mode='sync') "
            "wraps each environment in a TimeLimit of that length"
        )


class _ClosedCore:
    """Stands for the native batch after `close()`: every use raises."""

    def __init__(self, what: str) -> None:
        self._what = what

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__"):
            raise AttributeError(name)  # copy/pickle protocol lookups
        raise ClosedEnvironmentError(f"{self._what} is closed (close() was called); make a new one")


def _rebuild_vec(ctor: dict[str, Any]) -> CarlVectorEnv:
    ctor = dict(ctor)
    return CarlVectorEnv(ctor.pop("env"), ctor.pop("num_envs"), **ctor)
