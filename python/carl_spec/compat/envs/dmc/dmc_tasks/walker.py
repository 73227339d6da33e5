"""carl-bench's `carl.envs.dmc.dmc_tasks.walker`, over carl-spec's `dmc_walker`.

`get_model_and_assets` is dm_control's walker.xml and its common assets (shipped with carl-spec, no
dm_control needed). The task functions (`stand_context`, `walk_context`, `run_context`) return
dm_control environments, built as carl-bench's were (the XML, `adapt_context`, dm_control's
`PlanarWalker`); they need dm_control and without it raise `DmControlMissingError` naming
`CARLDmcWalkerEnv(task=...)`, carl-spec's own runtime.
"""

from __future__ import annotations

from typing import Any

from . import _dm_control
from ._common_xml import ASSETS
from ._walker_xml import WALKER_XML
from .utils import adapt_context

# dm_control's walker.py
_DEFAULT_TIME_LIMIT = 25
_CONTROL_TIMESTEP = 0.025
_WALK_SPEED = 1
_RUN_SPEED = 8


def get_model_and_assets() -> tuple[bytes, dict[str, bytes]]:
    """dm_control's walker.xml and its common assets (`common.ASSETS`), as dm_control's."""
    return WALKER_XML.encode(), dict(ASSETS)


def _task(name: str, move_speed: float) -> Any:
    def make(
        context: dict[str, Any] | None = None,
        time_limit: float = _DEFAULT_TIME_LIMIT,
        random: Any = None,
        environment_kwargs: dict[str, Any] | None = None,
    ) -> Any:
        _dm_control.require(f"carl.envs.dmc.dmc_tasks.walker.{name}", "CARLDmcWalkerEnv(task=...)")
        from dm_control.suite import walker

        xml, assets = get_model_and_assets()
        if context:
            xml = adapt_context(xml_string=xml, context=context)
        physics = walker.Physics.from_xml_string(xml, assets)
        task = walker.PlanarWalker(move_speed=move_speed, random=random)
        return _dm_control.environment(physics, task, time_limit, _CONTROL_TIMESTEP, environment_kwargs)

    make.__name__ = make.__qualname__ = name
    make.__doc__ = (
        f"carl-bench's {name}: dm_control's PlanarWalker (move_speed {move_speed}) on walker.xml adapted to "
        "`context` (needs dm_control)."
    )
    return make


stand_context = _task("stand_context", 0)
walk_context = _task("walk_context", _WALK_SPEED)
run_context = _task("run_context", _RUN_SPEED)

__all__ = ["get_model_and_assets", "stand_context", "walk_context", "run_context"]
