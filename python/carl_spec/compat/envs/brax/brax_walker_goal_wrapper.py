"""carl-bench's `carl.envs.brax.brax_walker_goal_wrapper`: the goal directions, and the goal and
language wrappers of its Brax walkers.

`directions` and `DIRECTION_NAMES` are carl-bench's. The wrappers need the goal features
(target_distance, target_direction, target_radius) of the goal option of issue 26, which carl-spec's
ant, half_cheetah and humanoid do not have yet: building one raises `PendingEnvironmentError`
naming it (carl-bench integrates the walker's velocity observation into a position, which
carl-spec will provide from the runtime's own state instead).
"""

from __future__ import annotations

from typing import Any, NoReturn

from ..._pending import GOAL, PendingEnvironmentError

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


def _refuse(name: str) -> NoReturn:
    raise PendingEnvironmentError(f"{name}: carl-spec's walkers have no goal features yet: it needs {GOAL}; see docs/guides/migration.md")


class BraxWalkerGoalWrapper:
    """carl-bench's positional goal for the Brax walkers (pending: issue 26's goal option)."""

    def __init__(self, env: Any = None, env_name: str = "", asset_path: str = "", *args: Any, **kwargs: Any) -> None:
        _refuse("BraxWalkerGoalWrapper")


class BraxLanguageWrapper:
    """carl-bench's goal description in words (pending: issue 26's goal option)."""

    def __init__(self, env: Any = None, *args: Any, **kwargs: Any) -> None:
        _refuse("BraxLanguageWrapper")


__all__ = ["DIRECTION_NAMES", "BraxLanguageWrapper", "BraxWalkerGoalWrapper", "directions"]
