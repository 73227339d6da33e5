"""carl-bench's `carl.envs.dmc.wrappers`: `MujocoToGymWrapper`, a dm_control environment as a
Gymnasium one (needs dm_control; carl-spec's own dm_control family needs no wrapper)."""

from __future__ import annotations

from typing import Any

import gymnasium
import numpy as np
from gymnasium import spaces

from .dmc_tasks import _dm_control


def get_shape(shape: tuple[int, ...]) -> tuple[int, ...]:
    """carl-bench's: a scalar's shape `()` as `(1,)`, others unchanged."""
    return shape if shape else (1,)


class MujocoToGymWrapper(gymnasium.Env[Any, Any]):
    """carl-bench's wrapper: a dm_control environment built with `flat_observation=True`
    (observations under "observations") as a Gymnasium environment with a flat Box observation.

    As carl-bench's: `step` returns `(obs, reward, False, last, info)` (an episode's end is
    reported as truncation), `reset(seed=...)` does not reseed dm_control's task, and `render`
    renders with dm_control's `physics.render` (`mode="rgb_array"`)."""

    def __init__(self, env: Any) -> None:
        _dm_control.require(
            "carl.envs.dmc.wrappers.MujocoToGymWrapper", "carl-spec's CARLDmc<Domain>Env classes (carl_spec.compat.envs.dmc)"
        )
        self.env = env
        action_spec = env.action_spec()
        self.action_space = spaces.Box(action_spec.minimum, action_spec.maximum, dtype=action_spec.dtype)
        obs_spec = env.observation_spec()
        size = int(np.sum([get_shape(v.shape) for v in obs_spec.values()]))
        dtype = np.unique([[v.dtype for v in obs_spec.values()]])[0]
        self.observation_space = spaces.Box(low=-np.inf, high=np.inf, shape=(size,), dtype=dtype)

    def step(self, action: Any) -> tuple[Any, Any, bool, bool, dict[str, Any]]:
        from dm_env import StepType

        timestep = self.env.step(action=action)
        info = {"step_type": timestep.step_type, "discount": timestep.discount}
        return timestep.observation["observations"], timestep.reward, False, timestep.step_type == StepType.LAST, info

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None, **_: Any) -> tuple[Any, dict[str, Any]]:
        super().reset(seed=seed, options=options)
        timestep = self.env.reset()
        return timestep.observation["observations"], {}

    def render(self, mode: str = "human", camera_id: int = 0, **kwargs: Any) -> Any:  # type: ignore[override, unused-ignore]
        if mode == "rgb_array":
            return self.env.physics.render(camera_id=camera_id, **kwargs)
        raise NotImplementedError(f"MujocoToGymWrapper renders mode='rgb_array' only, not {mode!r}")


__all__ = ["MujocoToGymWrapper", "get_shape"]
