"""carl-bench's `carl.envs.dmc.carl_dmcontrol`: `CARLDmcEnv`, its base of dm_control environments.

carl-spec's five `CARLDmc<Domain>Env` classes run carl-spec's own engine and do not derive from
it. `CARLDmcEnv` is for code that subclasses carl-bench's base (setting `domain`, `task` and
`get_context_features`): it runs dm_control itself, as carl-bench's did (each context's XML
edited by `adapt_context`, the environment rebuilt by `load_dm_control_env` at every
`_update_context`, wrapped in `MujocoToGymWrapper`), so it needs dm_control; without it,
building one raises `DmControlMissingError`.

Its context handling is carl-bench's in short: `contexts` (missing features at their defaults),
round robin over them (or random, static, a custom selector's `select()`), `{"obs", "context"}`
observations (`obs_context_features`, `obs_context_as_dict`), `info["context_id"]`.
"""

from __future__ import annotations

from typing import Any

import gymnasium
import numpy as np
from gymnasium import spaces

from .dmc_tasks import _dm_control
from .loader import load_dm_control_env
from .wrappers import MujocoToGymWrapper


class CARLDmcEnv(gymnasium.Env[dict[str, Any], Any]):
    """carl-bench's base of the dm_control environments (needs dm_control): subclasses set
    `domain`, `task` and `get_context_features()`."""

    domain: str = ""
    task: str = ""
    metadata = {"render_modes": ["rgb_array"]}

    @staticmethod
    def get_context_features() -> dict[str, Any]:
        raise NotImplementedError("CARLDmcEnv subclasses define get_context_features()")

    @classmethod
    def get_default_context(cls) -> dict[str, Any]:
        return {n: f.default_value for n, f in cls.get_context_features().items()}

    def __init__(
        self,
        contexts: dict[Any, dict[str, Any]] | None = None,
        obs_context_features: list[str] | None = None,
        obs_context_as_dict: bool = True,
        context_selector: Any = None,
        context_selector_kwargs: dict[str, Any] | None = None,
        **kwargs: Any,
    ) -> None:
        _dm_control.require(
            f"carl.envs.dmc.carl_dmcontrol.CARLDmcEnv ({type(self).__name__})",
            "carl-spec's CARLDmc<Domain>Env classes (carl_spec.compat.envs.dmc)",
        )
        default = self.get_default_context()
        contexts = contexts or {0: default}
        self.contexts = {k: {**default, **c} for k, c in contexts.items()}
        self.obs_context_features = list(default) if obs_context_features is None else list(obs_context_features)
        self.obs_context_as_dict = obs_context_as_dict
        if isinstance(context_selector, type):
            context_selector = context_selector(contexts=self.contexts, **(context_selector_kwargs or {}))
        self.context_selector = context_selector
        self._keys = list(self.contexts)
        self.context_id: int | None = None
        self.context: dict[str, Any] = {}
        self._progress_instance()
        self._update_context()
        self.action_space = self.env.action_space
        base = self.env.observation_space
        assert isinstance(base, spaces.Box)
        self.base_observation_space = spaces.Box(low=base.low, high=base.high, dtype=base.dtype)  # type: ignore[arg-type, unused-ignore]
        feats = self.get_context_features()
        bounds = {n: (float(getattr(feats[n], "lower", -np.inf)), float(getattr(feats[n], "upper", np.inf))) for n in self.obs_context_features}
        ctx: spaces.Space[Any]
        if obs_context_as_dict:
            ctx = spaces.Dict({n: spaces.Box(low=lo, high=hi, shape=(1,)) for n, (lo, hi) in bounds.items()})
        else:
            ctx = spaces.Box(low=np.array([b[0] for b in bounds.values()]), high=np.array([b[1] for b in bounds.values()]))
        self.observation_space = spaces.Dict({"obs": self.base_observation_space, "context": ctx})

    def _progress_instance(self) -> None:
        """Select the next context: round robin (the default), random (`RandomSelector`, from
        the env's `np_random`), the first (`StaticSelector`) or a custom selector's `select()`."""
        selector = self.context_selector
        mode = "round_robin" if selector is None else getattr(selector, "mode", None)
        if mode is None:
            self.context = dict(selector.select())
            self.context_id = selector.context_id
            return
        if mode == "random":
            self.context_id = int(self.np_random.integers(len(self._keys)))
        elif mode == "static":
            self.context_id = 0 if self.context_id is None else self.context_id
        else:
            self.context_id = 0 if self.context_id is None else (self.context_id + 1) % len(self._keys)
        self.context = dict(self.contexts[self._keys[self.context_id]])

    def _update_context(self) -> None:
        """Rebuild dm_control's environment from the current context (carl-bench's)."""
        env = load_dm_control_env(
            domain_name=self.domain, task_name=self.task, context=self.context, environment_kwargs={"flat_observation": True}
        )
        self.env = MujocoToGymWrapper(env)

    def _observe(self, obs: Any) -> dict[str, Any]:
        values = [float(self.context[n]) for n in self.obs_context_features]
        if self.obs_context_as_dict:
            context: Any = {n: np.array([v], dtype=np.float32) for n, v in zip(self.obs_context_features, values)}
        else:
            context = np.array(values, dtype=np.float32)
        return {"obs": obs, "context": context}

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[dict[str, Any], dict[str, Any]]:
        super().reset(seed=seed)
        self._progress_instance()
        self._update_context()
        obs, info = self.env.reset(seed=seed, options=options)
        return self._observe(obs), {**info, "context_id": self.context_id}

    def step(self, action: Any) -> tuple[dict[str, Any], Any, bool, bool, dict[str, Any]]:
        obs, reward, terminated, truncated, info = self.env.step(action)
        return self._observe(obs), reward, terminated, truncated, {**info, "context_id": self.context_id}

    def render(self) -> Any:
        return self.env.render(mode="rgb_array")


__all__ = ["CARLDmcEnv"]
