"""carl-bench's `carl.envs.brax.brax_walker_goal_wrapper`: the goal directions, and the goal and
language wrappers of its Brax walkers, over carl-spec's `goal` option (crates/carl-envs-brax/src/goal.rs).

`directions` and `DIRECTION_NAMES` are carl-bench's. The compat walker classes (CARLBraxAnt,
CARLBraxHalfcheetah, CARLBraxHopper, CARLBraxHumanoid, CARLBraxWalker2d) turn the goal on
themselves when a context names a goal feature (their `env` attribute is then a
`BraxWalkerGoalWrapper`, or a `BraxLanguageWrapper` with `use_language_goals=True`); wrapping one
of them in `BraxWalkerGoalWrapper(env, env_name, asset_path)` turns it on as well.

The reward is the decrease of the torso's distance to the goal and the episode ends with
`info["success"] = 1` within target_radius, as carl-bench's; unlike carl-bench, the position is the
torso's true x-y position (carl-bench integrates velocity observations with the physics timestep,
not the control step), and the 22.5-degree codes point where their names say (see
docs/guides/migration.md).
"""

from __future__ import annotations

import string
from typing import Any

import gymnasium
import numpy as np
from gymnasium import spaces

#: carl-bench's compass codes: 1 north, 2 east, 3 south, 4 west; two or three digits combine them.
DIRECTION_NAMES = {
    1: "north",
    3: "south",
    2: "east",
    4: "west",
    12: "north east",
    32: "south east",
    14: "north west",
    34: "south west",
    112: "north north east",
    332: "south south east",
    114: "north north west",
    334: "south south west",
    212: "east north east",
    232: "east south east",
    414: "west north west",
    434: "west south west",
}

directions = [1, 3, 2, 4, 12, 32, 14, 34, 112, 332, 114, 334, 212, 232, 414, 434]

#: The goal features of the walkers (carl-bench's names = carl-spec's).
GOAL_FEATURES = frozenset({"target_distance", "target_direction", "target_radius"})

#: The observation space of a language goal.
GOAL_TEXT = spaces.Text(max_length=256, charset=string.ascii_letters + string.digits + " .-+e")


def goal_description(context: dict[str, Any]) -> str:
    """carl-bench's goal in words (the radius in metres, where carl-bench says "steps")."""
    return (
        f"The distance to the goal is {context['target_distance']}m {DIRECTION_NAMES[int(context['target_direction'])]}. "
        f"Move within {context['target_radius']}m of the goal."
    )


def _walker(env: Any, who: str) -> Any:
    base = getattr(env, "unwrapped", env)
    if not hasattr(base, "_enable_goal"):
        raise TypeError(
            f"{who} wraps carl_spec.compat's Brax walkers (CARLBraxAnt, CARLBraxHalfcheetah, CARLBraxHopper, "
            f"CARLBraxHumanoid, CARLBraxWalker2d), got {type(base).__name__}; carl-spec's own envs take "
            "carl_spec.make(id, options={'goal': True})"
        )
    return base


class BraxWalkerGoalWrapper(gymnasium.Wrapper):
    """carl-bench's positional goal for the Brax walkers, over carl-spec's `goal` option.

    `position` and `goal_position` are relative to the torso's start (m, x east, y north),
    `goal_radius` is target_radius; all None before the first reset."""

    def __init__(self, env: gymnasium.Env, env_name: str = "", asset_path: str = "") -> None:
        walker = _walker(env, "BraxWalkerGoalWrapper")
        super().__init__(env)
        self.env_name = env_name or walker.env_id
        self.asset_path = asset_path
        self.context: dict[str, Any] | None = None
        self.position: tuple[float, float] | None = None
        self.goal_position: np.ndarray | None = None
        self.goal_radius: float | None = None
        walker._tracker = self
        if walker.env is None or not walker._goal:
            walker._enable_goal()
            walker.env = self

    def _track(self, goal: dict[str, Any], context: dict[str, Any]) -> None:
        self.context = dict(context)
        self.position = (float(goal["torso_position"][0]), float(goal["torso_position"][1]))
        self.goal_position = np.array(goal["goal_position"], dtype=np.float64)
        self.goal_radius = float(context.get("target_radius", np.nan))


class BraxLanguageWrapper(gymnasium.Wrapper):
    """carl-bench's goal in words: the observation's `obs` becomes `{"obs": ..., "goal": text}`."""

    def __init__(self, env: gymnasium.Env) -> None:
        walker = _walker(env, "BraxLanguageWrapper")
        super().__init__(env)
        self.context: dict[str, Any] | None = None
        if getattr(walker, "_tracker", None) is None:
            BraxWalkerGoalWrapper(walker)
        self._goal_wrapper: BraxWalkerGoalWrapper = walker._tracker
        if walker.env is None or not walker.use_language_goals:
            walker._enable_language()
            walker.env = self

    @property
    def position(self) -> Any:
        """The goal wrapper's `position`."""
        return self._goal_wrapper.position

    def get_goal_desc(self, context: dict[str, Any]) -> str:
        return goal_description(context)


__all__ = ["DIRECTION_NAMES", "BraxLanguageWrapper", "BraxWalkerGoalWrapper", "directions"]
