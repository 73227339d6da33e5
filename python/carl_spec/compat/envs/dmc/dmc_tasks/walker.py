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


def _model(context: dict[str, Any]) -> tuple[bytes, dict[str, bytes]]:
    xml, assets = get_model_and_assets()
    return (adapt_context(xml_string=xml, context=context) if context else xml), assets


def _task(name: str, move_speed: float) -> Any:
    return _dm_control.task_function(
        "walker",
        name,
        "CARLDmcWalkerEnv(task=...)",
        _model,
        lambda suite, random: suite.PlanarWalker(move_speed=move_speed, random=random),
        _DEFAULT_TIME_LIMIT,
        _CONTROL_TIMESTEP,
        f"carl-bench's {name}: dm_control's PlanarWalker (move_speed {move_speed}) on walker.xml adapted to "
        "`context` (needs dm_control).",
    )


stand_context = _task("stand_context", 0)
walk_context = _task("walk_context", _WALK_SPEED)
run_context = _task("run_context", _RUN_SPEED)

__all__ = ["get_model_and_assets", "stand_context", "walk_context", "run_context"]
