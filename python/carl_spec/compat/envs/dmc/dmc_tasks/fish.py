"""carl-bench's `carl.envs.dmc.dmc_tasks.fish`, over carl-spec's `dmc_fish`.

`get_model_and_assets` is dm_control's fish.xml and its common assets (shipped with carl-spec, no
dm_control needed). The task functions (`upright_context`, `swim_context`) return dm_control
environments, built as carl-bench's were (the XML, `adapt_context`, dm_control's fish tasks); they
need dm_control and without it raise `DmControlMissingError` naming `CARLDmcFishEnv(task=...)`,
carl-spec's own runtime.
"""

from __future__ import annotations

from typing import Any

from . import _dm_control
from ._common_xml import ASSETS
from ._fish_xml import FISH_XML
from .utils import adapt_context

# dm_control's fish.py
_DEFAULT_TIME_LIMIT = 40
_CONTROL_TIMESTEP = 0.04


def get_model_and_assets() -> tuple[bytes, dict[str, bytes]]:
    """dm_control's fish.xml and its common assets (`common.ASSETS`), as dm_control's."""
    return FISH_XML.encode(), dict(ASSETS)


def _model(context: dict[str, Any]) -> tuple[bytes, dict[str, bytes]]:
    xml, assets = get_model_and_assets()
    return (adapt_context(xml_string=xml, context=context) if context else xml), assets


def _task(name: str, task_class: str) -> Any:
    return _dm_control.task_function(
        "fish",
        name,
        "CARLDmcFishEnv(task=...)",
        _model,
        lambda suite, random: getattr(suite, task_class)(random=random),
        _DEFAULT_TIME_LIMIT,
        _CONTROL_TIMESTEP,
        f"carl-bench's {name}: dm_control's fish {task_class} task on fish.xml adapted to `context` (needs dm_control).",
    )


upright_context = _task("upright_context", "Upright")
swim_context = _task("swim_context", "Swim")

__all__ = ["get_model_and_assets", "upright_context", "swim_context"]
